!> Readers for *NODE, *ELEMENT_SOLID and *PART.
module xd_input_read_geometry
    use xd_kinds, only: wp, dp
    use xd_core_comm, only: comm_rank_size, comm_min_int, comm_gather_records
    use xd_core_errors, only: error_t, make_error
    use xd_core_memory, only: grow
    use xd_core_strings, only: itoa
    use xd_input_field_reader, only: card_t, card_format_t, card_format, get_real, get_int, get_text, field_blank, card_blank, &
                                     card_error
    use xd_input_keyword_table, only: keyword_t
    use xd_input_context, only: read_ctx_t, get_card, add_warning, ignored_fields
    use xd_model, only: model_t, part_t, point_mass_t, part_mass_t
    implicit none
    private
    public :: read_geometry

    abstract interface
        !> Card ic as a record, or skip (a blank card), or failed (an error
        !> the caller holds).
        subroutine card_record_t(ic, rec, skip, failed)
            import :: dp
            integer, intent(in) :: ic
            real(dp), intent(out) :: rec(:)
            logical, intent(out) :: skip, failed
        end subroutine card_record_t
        !> (rec: assumed size, the record's width known to each keyword: a
        !> column of the gathered records passed without a descriptor)
        subroutine add_record_t(rec)
            import :: dp
            real(dp), intent(in) :: rec(*)
        end subroutine add_record_t
    end interface

contains

    subroutine read_geometry(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        select case (kw%name)
        case ('NODE')
            call read_node(ctx, kw, model, error)
        case ('ELEMENT_SOLID')
            call read_element_solid(ctx, kw, model, error)
        case ('PART', 'PART_INERTIA')
            call read_part(ctx, kw, model, error)
        case ('ELEMENT_SHELL', 'ELEMENT_SHELL_THICKNESS')
            call read_element_shell(ctx, kw, model, error)
        case ('ELEMENT_BEAM')
            call read_element_beam(ctx, kw, model, error)
        case ('ELEMENT_MASS', 'ELEMENT_MASS_NODE_SET')
            call read_element_mass(ctx, kw, model, error)
        case ('ELEMENT_MASS_PART', 'ELEMENT_MASS_PART_SET')
            call read_element_mass_part(ctx, kw, model, error)
        end select
    end subroutine read_geometry

    subroutine read_node(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(card_format_t) :: fmt
        integer :: ic, n, tc, rc
        real(wp) :: xyz(3)
        logical :: skip
        fmt = card_format('NID:8 X:16 Y:16 Z:16 TC:8 RC:8', kw%width_mode)
        ! (room for a node a card at once, not grown by doubling as they
        ! come: the arrays are cut to their size after the deck)
        call add_room(model%nnode + kw%ncard)
        ! (under MPI each rank its block of the cards: read_in_blocks)
        if (read_in_blocks(kw%ncard, 7, node_record, add_record)) return
        if (allocated(error)) deallocate (error)
        do ic = 1, kw%ncard
            call node_card(ic, skip)
            if (allocated(error)) return
            if (skip) cycle
            call add_node(n, xyz, tc, rc, kw%card_line(ic))
        end do
    contains
        !> Card ic's node (n, xyz, tc, rc), or skip (a blank card), or error.
        subroutine node_card(ic, skip)
            integer, intent(in) :: ic
            logical, intent(out) :: skip
            skip = .false.
            call get_card(ctx, kw, ic, fmt, 1, card, error)
            if (allocated(error)) return
            skip = card_blank(card)
            if (skip) return
            call get_int(card, 1, n, 0, error); if (allocated(error)) return
            if (n <= 0) then
                call card_error(card, 1, 'node id must be a positive integer', error)
                return
            end if
            call get_real(card, 2, xyz(1), 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 3, xyz(2), 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 4, xyz(3), 0.0_wp, error); if (allocated(error)) return
            call get_int(card, 5, tc, 0, error); if (allocated(error)) return
            call get_int(card, 6, rc, 0, error); if (allocated(error)) return
            if (tc < 0 .or. tc > 7) then
                call card_error(card, 5, 'constraint code '//itoa(tc)//' is not 0-7', error)
                return
            end if
            if (rc < 0 .or. rc > 7) then
                call card_error(card, 6, 'constraint code '//itoa(rc)//' is not 0-7', error)
                return
            end if
        end subroutine node_card

        !> Card ic's node as a record (id, x, y, z, tc, rc, line).
        subroutine node_record(ic, rec, skip, failed)
            integer, intent(in) :: ic
            real(dp), intent(out) :: rec(:)
            logical, intent(out) :: skip, failed
            call node_card(ic, skip)
            failed = allocated(error)
            if (failed .or. skip) return
            rec = [real(n, dp), real(xyz, dp), real(tc, dp), real(rc, dp), real(kw%card_line(ic), dp)]
        end subroutine node_record

        !> (the record's integers are whole numbers held exactly: int, not
        !> nint's rounding call)
        subroutine add_record(rec)
            real(dp), intent(in) :: rec(*)
            call add_node(int(rec(1)), real(rec(2:4), wp), int(rec(5)), int(rec(6)), int(rec(7)))
        end subroutine add_record

        subroutine add_node(id, x, t, r, line)
            integer, intent(in) :: id, t, r, line
            real(wp), intent(in) :: x(3)
            model%nnode = model%nnode + 1
            call add_room(model%nnode)
            model%node_id(model%nnode) = id
            model%x0(:, model%nnode) = x
            model%node_tc(model%nnode) = t
            model%node_rc(model%nnode) = r
            model%node_src(model%nnode) = line
        end subroutine add_node

        !> The nodes' arrays with room for n nodes.
        subroutine add_room(n)
            integer, intent(in) :: n
            call grow(model%node_id, n, 'node ids')
            call grow(model%x0, 3, n, 'node coordinates')
            call grow(model%node_tc, n, 'node constraints')
            call grow(model%node_rc, n, 'node constraints')
            call grow(model%node_src, n, 'node lines')
        end subroutine add_room
    end subroutine read_node

    !> An element card's id (field 1, a positive integer), part (field 2)
    !> and size(nodes) node ids (fields 3 on), or error (the shells' and
    !> the beams' first cards).
    subroutine element_ids(card, eid, pid, nodes, error)
        type(card_t), intent(in) :: card
        integer, intent(out) :: eid, pid, nodes(:)
        type(error_t), allocatable, intent(out) :: error
        integer :: k
        call get_int(card, 1, eid, 0, error); if (allocated(error)) return
        call get_int(card, 2, pid, 0, error); if (allocated(error)) return
        do k = 1, size(nodes)
            call get_int(card, 2 + k, nodes(k), 0, error); if (allocated(error)) return
        end do
        if (eid <= 0) call card_error(card, 1, 'element id must be a positive integer', error)
    end subroutine element_ids

    !> Under MPI, a keyword's cards read in blocks, one a rank (every rank
    !> reads the whole deck: the large blocks of *NODE and *ELEMENT_SHELL
    !> cards were a fifth of a rank's start on 16 ranks of a 120,000-shell
    !> model), where there are ranks and cards enough (at least min_block a
    !> rank): each rank turns its block's cards into records of `width`
    !> values (card_record; a blank card gives none) and every rank adds
    !> every rank's records in card order (add_record). True where that was
    !> done; false where the cards are to be read in order: too few of them,
    !> or a bad card on some rank (the first error is then the one reading
    !> alone gives, on every rank alike). A collective where there are
    !> ranks.
    logical function read_in_blocks(ncard, width, card_record, add_record) result(done)
        integer, intent(in) :: ncard, width
        procedure(card_record_t) :: card_record
        procedure(add_record_t) :: add_record
        integer, parameter :: min_block = 1000
        real(dp), allocatable :: mine(:, :), all(:, :)
        integer :: rank, nranks, lo, hi, ic, m, k, first(1)
        logical :: skip, failed
        done = .false.
        call comm_rank_size(rank, nranks)
        if (nranks <= 1 .or. ncard < min_block*nranks) return
        lo = int(int(ncard, dp)*rank/nranks) + 1
        hi = int(int(ncard, dp)*(rank + 1)/nranks)
        allocate (mine(width, hi - lo + 1))
        m = 0
        first = huge(1)
        do ic = lo, hi
            call card_record(ic, mine(:, m + 1), skip, failed)
            if (failed) then
                first = ic
                exit
            end if
            if (.not. skip) m = m + 1
        end do
        call comm_min_int(first)
        if (first(1) /= huge(1)) return
        call comm_gather_records(mine(:, 1:m), nranks, all)
        do k = 1, size(all, 2)
            call add_record(all(:, k))
        end do
        done = .true.
    end function read_in_blocks

    !> *ELEMENT_MASS: EID NID MASS PID (I8 I8 E16 I8), a point mass on a
    !> node. PID (a part for the mass's energy in matsum) is warned: the mass
    !> counts in glstat's kinetic energy and the model's mass, not in a part.
    subroutine read_element_mass(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(card_format_t) :: fmt
        integer :: ic, eid, nid, pid
        real(wp) :: m
        fmt = card_format('EID:8 NID:8 MASS:16 PID:8', kw%width_mode)
        do ic = 1, kw%ncard
            call get_card(ctx, kw, ic, fmt, 1, card, error)
            if (allocated(error)) return
            if (card_blank(card)) cycle
            call get_int(card, 1, eid, 0, error); if (allocated(error)) return
            call get_int(card, 2, nid, 0, error); if (allocated(error)) return
            call get_real(card, 3, m, 0.0_wp, error); if (allocated(error)) return
            call get_int(card, 4, pid, 0, error); if (allocated(error)) return
            if (eid <= 0) then
                call card_error(card, 1, 'element id must be a positive integer', error); return
            end if
            if (nid <= 0) then
                call card_error(card, 2, trim(merge('node set id', 'node id    ', kw%name == 'ELEMENT_MASS_NODE_SET'))// &
                                ' must be a positive integer', error); return
            end if
            if (.not. (m >= 0.0_wp .and. m <= huge(1.0_wp))) then
                call card_error(card, 3, 'MASS must be a finite value, not negative', error); return
            end if
            if (pid /= 0) call add_warning(model, ctx%src%where(kw%card_line(ic))//': *ELEMENT_MASS '//itoa(eid)// &
                                           ' field PID = '//itoa(pid)//': the mass is not booked to a part in matsum '// &
                                           '(it counts in glstat and the model''s mass); ignored')
            if (.not. allocated(model%pmass)) allocate (model%pmass(16))
            if (model%npmass == size(model%pmass)) model%pmass = [model%pmass, model%pmass]
            model%npmass = model%npmass + 1
            model%pmass(model%npmass) = point_mass_t(eid=eid, nid=nid, mass=m, src=kw%card_line(ic), &
                                                     set=kw%name == 'ELEMENT_MASS_NODE_SET')
        end do
    end subroutine read_element_mass

    !> *ELEMENT_MASS_PART / _PART_SET: PID (PSID) ADDMASS FINMASS LCID MWD
    !> (I8 E16 E16 I8 I8). FINMASS > 0 wins over ADDMASS (the mass added is
    !> what makes the part that heavy); LCID and MWD (time-varying mass)
    !> are refused.
    subroutine read_element_mass_part(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(card_format_t) :: fmt
        type(part_mass_t) :: pm
        integer :: ic, id, lcid, mwd
        real(wp) :: add, fin
        fmt = card_format('PID:8 ADDMASS:16 FINMASS:16 LCID:8 MWD:8', kw%width_mode)
        do ic = 1, kw%ncard
            call get_card(ctx, kw, ic, fmt, 1, card, error)
            if (allocated(error)) return
            if (card_blank(card)) cycle
            call get_int(card, 1, id, 0, error); if (allocated(error)) return
            call get_real(card, 2, add, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 3, fin, 0.0_wp, error); if (allocated(error)) return
            call get_int(card, 4, lcid, 0, error); if (allocated(error)) return
            call get_int(card, 5, mwd, 0, error); if (allocated(error)) return
            if (id <= 0) then
                call card_error(card, 1, 'a part (set) id must be a positive integer', error); return
            end if
            if (.not. (add >= 0.0_wp .and. add <= huge(1.0_wp))) then
                call card_error(card, 2, 'ADDMASS must be a finite value, not negative', error); return
            end if
            if (.not. (fin >= 0.0_wp .and. fin <= huge(1.0_wp))) then
                call card_error(card, 3, 'FINMASS must be a finite value, not negative', error); return
            end if
            if (lcid /= 0 .or. mwd /= 0) then
                call card_error(card, 4, 'a mass varying in time (LCID, MWD) is not in xdyna', error); return
            end if
            pm = part_mass_t(id=id, set=kw%name == 'ELEMENT_MASS_PART_SET', addmass=add, finmass=fin, &
                             src=kw%card_line(ic))
            if (.not. allocated(model%partmass)) then
                model%partmass = [pm]
            else
                model%partmass = [model%partmass, pm]
            end if
        end do
    end subroutine read_element_mass_part

    !> One-line form EID PID N1..N8, or two-line form (EID PID, then N1..N10),
    !> told apart by whether the third field of the first card holds a node.
    subroutine read_element_solid(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card, card2
        type(card_format_t) :: fmt1, fmt2
        integer :: ic, eid, pid, k, nodes(8), e
        fmt1 = card_format('EID:8 PID:8 N1:8 N2:8 N3:8 N4:8 N5:8 N6:8 N7:8 N8:8', kw%width_mode)
        fmt2 = card_format('N1:8 N2:8 N3:8 N4:8 N5:8 N6:8 N7:8 N8:8 N9:8 N10:8', kw%width_mode)
        ic = 0
        do while (ic < kw%ncard)
            ic = ic + 1
            call get_card(ctx, kw, ic, fmt1, 1, card, error)
            if (allocated(error)) return
            if (card_blank(card)) cycle
            call get_int(card, 1, eid, 0, error); if (allocated(error)) return
            call get_int(card, 2, pid, 0, error); if (allocated(error)) return
            if (eid <= 0) then
                call card_error(card, 1, 'element id must be a positive integer', error)
                return
            end if
            if (field_blank(card, 3)) then
                if (ic == kw%ncard) then
                    call card_error(card, 3, 'two-line form: the card of nodes N1..N10 is missing', error)
                    return
                end if
                ic = ic + 1
                call get_card(ctx, kw, ic, fmt2, 2, card2, error)
                if (allocated(error)) return
                do k = 1, 8
                    call get_int(card2, k, nodes(k), 0, error); if (allocated(error)) return
                end do
                if (any(nodes <= 0)) then
                    call card_error(card2, minloc(nodes, 1), 'node id must be a positive integer', error)
                    return
                end if
            else
                do k = 1, 8
                    call get_int(card, 2 + k, nodes(k), 0, error); if (allocated(error)) return
                end do
                if (any(nodes <= 0)) then
                    call card_error(card, 2 + minloc(nodes, 1), 'node id must be a positive integer', error)
                    return
                end if
            end if
            model%nhex = model%nhex + 1
            e = model%nhex
            call grow(model%hex_id, e, 'solid element ids')
            call grow(model%hex_pid, e, 'solid element parts')
            call grow(model%hex_conn, 8, e, 'solid connectivity')
            call grow(model%hex_src, e, 'solid element lines')
            model%hex_id(e) = eid
            model%hex_pid(e) = pid
            model%hex_conn(:, e) = nodes
            model%hex_src(e) = kw%card_line(ic)
        end do
    end subroutine read_element_solid

    !> EID PID N1 N2 N3 N4 (N3 = N4: triangle); _THICKNESS adds THIC1..4 BETA (E16).
    subroutine read_element_shell(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(card_format_t) :: fmt1, fmt2
        integer :: ic, eid, pid, k, nodes(4), e
        real(wp) :: th(4)
        logical :: thick
        fmt1 = card_format('EID:8 PID:8 N1:8 N2:8 N3:8 N4:8', kw%width_mode)
        fmt2 = card_format('THIC1:16 THIC2:16 THIC3:16 THIC4:16 BETA:16', kw%width_mode)
        thick = kw%name == 'ELEMENT_SHELL_THICKNESS'
        ! (one card a shell: each rank its block, every shell's record to all;
        ! with thicknesses, a shell's second card follows its first past any
        ! blank card, so those are read in order)
        th = 0
        ! (room for a shell a card at once: add_room)
        call add_room(model%nshell + kw%ncard)
        if (.not. thick) then
            if (read_in_blocks(kw%ncard, 7, shell_record, add_record)) return
            if (allocated(error)) deallocate (error)
        end if
        ic = 0
        do while (ic < kw%ncard)
            ic = ic + 1
            call get_card(ctx, kw, ic, fmt1, 1, card, error)
            if (allocated(error)) return
            if (card_blank(card)) cycle
            call first_card()
            if (allocated(error)) return
            th = 0
            if (thick) then
                if (ic == kw%ncard) then
                    call card_error(card, 1, 'the thickness card THIC1..THIC4 is missing', error); return
                end if
                ic = ic + 1
                call get_card(ctx, kw, ic, fmt2, 2, card, error)
                if (allocated(error)) return
                do k = 1, 4
                    call get_real(card, k, th(k), 0.0_wp, error); if (allocated(error)) return
                end do
            end if
            call add_shell(eid, pid, nodes, kw%card_line(ic))
        end do
    contains
        !> The first card's shell (eid, pid, nodes), or error.
        subroutine first_card()
            call element_ids(card, eid, pid, nodes, error); if (allocated(error)) return
            if (nodes(4) == 0) nodes(4) = nodes(3)
            if (any(nodes <= 0)) then
                call card_error(card, 2 + minloc(nodes, 1), 'node id must be a positive integer', error); return
            end if
        end subroutine first_card

        !> Card ic's shell as a record (id, part, four nodes, line).
        subroutine shell_record(ic, rec, skip, failed)
            integer, intent(in) :: ic
            real(dp), intent(out) :: rec(:)
            logical, intent(out) :: skip, failed
            skip = .false.
            call get_card(ctx, kw, ic, fmt1, 1, card, error)
            if (.not. allocated(error)) skip = card_blank(card)
            if (.not. (allocated(error) .or. skip)) call first_card()
            failed = allocated(error)
            if (failed .or. skip) return
            rec = real([eid, pid, nodes, kw%card_line(ic)], dp)
        end subroutine shell_record

        !> (the record's integers are whole numbers held exactly: int)
        subroutine add_record(rec)
            real(dp), intent(in) :: rec(*)
            call add_shell(int(rec(1)), int(rec(2)), int(rec(3:6)), int(rec(7)))
        end subroutine add_record

        !> A shell appended to the model (its thicknesses th).
        subroutine add_shell(id, part, nd, line)
            integer, intent(in) :: id, part, nd(4), line
            model%nshell = model%nshell + 1
            e = model%nshell
            call add_room(e)
            model%shell_id(e) = id
            model%shell_pid(e) = part
            model%shell_conn(:, e) = nd
            model%shell_t(:, e) = th
            model%shell_src(e) = line
        end subroutine add_shell

        !> The shells' arrays with room for n shells.
        subroutine add_room(n)
            integer, intent(in) :: n
            call grow(model%shell_id, n, 'shell ids')
            call grow(model%shell_pid, n, 'shell parts')
            call grow(model%shell_conn, 4, n, 'shell connectivity')
            call grow(model%shell_src, n, 'shell lines')
            call grow(model%shell_t, 4, n, 'shell thicknesses')
        end subroutine add_room
    end subroutine read_element_shell

    !> *ELEMENT_BEAM: EID PID N1 N2 N3 RT1 RR1 RT2 RR2 LOCAL (N3 the
    !> orientation node, 0: none; the release codes are refused).
    subroutine read_element_beam(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(card_format_t) :: fmt
        integer :: ic, eid, pid, k, nodes(3), rel, e
        fmt = card_format('EID:8 PID:8 N1:8 N2:8 N3:8 RT1:8 RR1:8 RT2:8 RR2:8 LOCAL:8', kw%width_mode)
        do ic = 1, kw%ncard
            call get_card(ctx, kw, ic, fmt, 1, card, error)
            if (allocated(error)) return
            if (card_blank(card)) cycle
            call element_ids(card, eid, pid, nodes, error); if (allocated(error)) return
            if (nodes(1) <= 0 .or. nodes(2) <= 0) then
                call card_error(card, merge(3, 4, nodes(1) <= 0), 'node id must be a positive integer', error); return
            end if
            if (nodes(3) < 0) then
                call card_error(card, 5, 'the orientation node N3 must not be negative', error); return
            end if
            do k = 6, 9
                call get_int(card, k, rel, 0, error); if (allocated(error)) return
                if (rel /= 0) then
                    call card_error(card, k, 'release conditions (RT1 RR1 RT2 RR2) are not in xdyna', error); return
                end if
            end do
            model%nbeam = model%nbeam + 1
            e = model%nbeam
            call grow(model%beam_id, e, 'beam ids')
            call grow(model%beam_pid, e, 'beam parts')
            call grow(model%beam_conn, 3, e, 'beam connectivity')
            call grow(model%beam_src, e, 'beam lines')
            model%beam_id(e) = eid
            model%beam_pid(e) = pid
            model%beam_conn(:, e) = nodes
            model%beam_src(e) = kw%card_line(ic)
        end do
    end subroutine read_element_beam

    !> Pairs of cards: HEADING, then PID SECID MID EOSID HGID GRAV ADPOPT TMID.
    subroutine read_part(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: head, card
        type(part_t) :: p
        integer :: ic, eosid, tmid, k, ircs, step
        ic = 1
        do while (ic <= kw%ncard)
            call get_card(ctx, kw, ic, 'HEADING:70', 1, head, error, raw=.true.)
            if (allocated(error)) return
            if (ic == kw%ncard) then
                if (card_blank(head)) exit
                call make_error(error, ctx%src%where(kw%card_line(ic))//': '//trim(kw%written)// &
                                ' card 2: missing (PID SECID MID ... after the heading)')
                return
            end if
            call get_card(ctx, kw, ic + 1, 'PID SECID MID EOSID HGID GRAV ADPOPT TMID', 2, card, error)
            if (allocated(error)) return
            call ignored_fields(model, card, [6, 7], 'gravity preload (GRAV) and adaptivity (ADPOPT) are not in xdyna; '// &
                'ignored')
            p = part_t()
            p%heading = get_text(head, 1)
            call get_int(card, 1, p%id, 0, error); if (allocated(error)) return
            call get_int(card, 2, p%secid, 0, error); if (allocated(error)) return
            call get_int(card, 3, p%mid, 0, error); if (allocated(error)) return
            call get_int(card, 4, eosid, 0, error); if (allocated(error)) return
            call get_int(card, 5, p%hgid, 0, error); if (allocated(error)) return
            call get_int(card, 8, tmid, 0, error); if (allocated(error)) return
            if (p%id <= 0) then
                call card_error(card, 1, 'part id must be a positive integer', error)
                return
            end if
            if (eosid /= 0) then
                call card_error(card, 4, 'equations of state are not supported (EOSID must be 0)', error)
                return
            end if
            if (tmid /= 0) call add_warning(model, ctx%src%where(kw%card_line(ic + 1))// &
                                            ': *PART field TMID: thermal material ignored')
            p%src = kw%card_line(ic + 1)
            step = 2
            if (kw%name == 'PART_INERTIA') then
                ! cards 3-5: XC YC ZC TM IRCS NODEID; IXX IXY IXZ IYY IYZ IZZ; VTX..VRZ
                if (ic + 4 > kw%ncard) then
                    call make_error(error, ctx%src%where(kw%card_line(ic))//': '//trim(kw%written)// &
                                    ' needs cards 3 to 5 (XC YC ZC TM IRCS NODEID; IXX..IZZ; VTX..VRZ)')
                    return
                end if
                p%inertia = .true.
                call get_card(ctx, kw, ic + 2, 'XC YC ZC TM IRCS NODEID', 3, card, error)
                if (allocated(error)) return
                do k = 1, 3
                    call get_real(card, k, p%xc(k), 0.0_wp, error); if (allocated(error)) return
                end do
                call get_real(card, 4, p%tm, 0.0_wp, error); if (allocated(error)) return
                call get_int(card, 5, ircs, 0, error); if (allocated(error)) return
                call get_int(card, 6, p%nodeid, 0, error); if (allocated(error)) return
                if (.not. (p%tm > 0.0_wp)) then
                    call card_error(card, 4, 'the translational mass TM must be positive', error); return
                end if
                if (ircs /= 0) then
                    call card_error(card, 5, 'IRCS 1 (principal moments with orientation vectors) is not '// &
                                    'supported; give the global tensor (IRCS 0)', error)
                    return
                end if
                call get_card(ctx, kw, ic + 3, 'IXX IXY IXZ IYY IYZ IZZ', 4, card, error)
                if (allocated(error)) return
                do k = 1, 6
                    call get_real(card, k, p%itens(k), 0.0_wp, error); if (allocated(error)) return
                end do
                if (.not. (p%itens(1) > 0.0_wp .and. p%itens(4) > 0.0_wp .and. p%itens(6) > 0.0_wp)) then
                    call card_error(card, 1, 'IXX, IYY and IZZ must be positive', error); return
                end if
                call get_card(ctx, kw, ic + 4, 'VTX VTY VTZ VRX VRY VRZ', 5, card, error)
                if (allocated(error)) return
                do k = 1, 3
                    call get_real(card, k, p%vt(k), 0.0_wp, error); if (allocated(error)) return
                    call get_real(card, 3 + k, p%vr(k), 0.0_wp, error); if (allocated(error)) return
                end do
                step = 5
            end if
            if (.not. allocated(model%part)) allocate (model%part(8))
            if (model%npart == size(model%part)) model%part = [model%part, model%part]
            model%npart = model%npart + 1
            model%part(model%npart) = p
            ic = ic + step
        end do
    end subroutine read_part

end module xd_input_read_geometry
