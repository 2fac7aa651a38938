!> Readers for *CONTROL_* and *DATABASE_* keywords.
module xd_input_read_controls
    use xd_kinds, only: wp
    use xd_core_errors, only: error_t
    use xd_core_strings, only: itoa, to_lower
    use xd_output_units, only: length_units, time_units, mass_units
    use xd_input_field_reader, only: card_t, get_int, get_real, card_error, card_blank
    use xd_input_keyword_table, only: keyword_t
    use xd_input_context, only: read_ctx_t, get_card, first_card, no_more_cards, add_warning, ignored_fields
    use xd_model, only: model_t, history_request_t
    implicit none
    private
    public :: read_control, read_database

contains

    subroutine read_control(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        integer :: ic, isdo, lctm, erode, btype, osu, inn, iacc
        character(len=:), allocatable :: at
        ic = first_card(kw)
        if (ic > kw%ncard) return
        at = ctx%src%where(kw%card_line(ic))//': '//trim(kw%written)
        associate (c => model%ctl)
            select case (kw%name)
            case ('CONTROL_TERMINATION')
                call get_card(ctx, kw, ic, 'ENDTIM ENDCYC DTMIN ENDENG ENDMAS', 1, card, error)
                if (allocated(error)) return
                call get_real(card, 1, c%endtim, 0.0_wp, error); if (allocated(error)) return
                call get_int(card, 2, c%endcyc, 0, error); if (allocated(error)) return
                call get_real(card, 3, c%dtmin, 0.0_wp, error); if (allocated(error)) return
                call get_real(card, 4, c%endeng, 0.0_wp, error); if (allocated(error)) return
                call get_real(card, 5, c%endmas, 0.0_wp, error); if (allocated(error)) return
                if (c%endtim < 0.0_wp) then
                    call card_error(card, 1, 'termination time must not be negative', error); return
                end if
                if (c%endmas < 0.0_wp) then
                    call card_error(card, 5, 'ENDMAS (a percentage of the mass) must not be negative', error); return
                end if
                c%termination_given = .true.
            case ('CONTROL_TIMESTEP')
                call get_card(ctx, kw, ic, 'DTINIT TSSFAC ISDO TSLIMT DT2MS LCTM ERODE MS1ST', 1, card, error)
                if (allocated(error)) return
                call ignored_fields(model, card, [4], 'TSLIMT (a shell step floor for *MAT_003 and *MAT_024) is not '// &
                                    'in xdyna; ignored')
                call get_real(card, 1, c%dtinit, 0.0_wp, error); if (allocated(error)) return
                call get_real(card, 2, c%tssfac, 0.9_wp, error, zero_default=.true.); if (allocated(error)) return
                call get_int(card, 3, isdo, 0, error); if (allocated(error)) return
                select case (isdo)
                case (0:2)
                    c%isdo = isdo
                case (3)
                    c%isdo = 0
                    call add_warning(model, at//' field ISDO: 3 (the step from the largest eigenvalue) is not in '// &
                                     'xdyna; ISDO 0 (area over the longest side) used')
                case default
                    call card_error(card, 3, 'ISDO '//trim(card%f(3))//' is not 0, 1, 2 or 3', error); return
                end select
                call get_real(card, 4, c%tslimt, 0.0_wp, error); if (allocated(error)) return
                call get_real(card, 5, c%dt2ms, 0.0_wp, error); if (allocated(error)) return
                call get_int(card, 6, lctm, 0, error); if (allocated(error)) return
                call get_int(card, 7, erode, 0, error); if (allocated(error)) return
                call get_int(card, 8, c%ms1st, 0, error); if (allocated(error)) return
                if (c%ms1st /= 0 .and. c%ms1st /= 1) then
                    call card_error(card, 8, 'MS1ST must be 0 or 1', error); return
                end if
                if (c%tssfac <= 0.0_wp .or. c%tssfac > 1.0_wp) then
                    call card_error(card, 2, 'TSSFAC must lie in (0, 1]', error); return
                end if
                if (lctm /= 0) call add_warning(model, at//' field LCTM: time step limit curve '// &
                                                'is not implemented; ignored')
                if (erode /= 0 .and. erode /= 1) then
                    call card_error(card, 7, 'ERODE must be 0 or 1', error); return
                end if
                c%erode = erode
            case ('CONTROL_HOURGLASS')
                call get_card(ctx, kw, ic, 'IHQ QH', 1, card, error)
                if (allocated(error)) return
                call get_int(card, 1, c%ihq, 1, error, zero_default=.true.); if (allocated(error)) return
                call get_real(card, 2, c%qh, 0.1_wp, error, zero_default=.true.); if (allocated(error)) return
                if (c%ihq < 1 .or. c%ihq > 5) then
                    call card_error(card, 1, 'IHQ '//trim(card%f(1))//' is not supported (1-5)', error); return
                end if
            case ('CONTROL_BULK_VISCOSITY')
                call get_card(ctx, kw, ic, 'Q1 Q2 TYPE', 1, card, error)
                if (allocated(error)) return
                call get_real(card, 1, c%q1, 1.5_wp, error, zero_default=.true.); if (allocated(error)) return
                call get_real(card, 2, c%q2, 0.06_wp, error, zero_default=.true.); if (allocated(error)) return
                call get_int(card, 3, btype, 1, error, zero_default=.true.); if (allocated(error)) return
                if (btype /= 1) call add_warning(model, at//' field TYPE: only the standard form (1) is implemented')
            case ('CONTROL_SHELL')
                call read_control_shell()
            case ('CONTROL_XDYNA_SHELL')
                ! xdyna's own: HGBOUND 1 (the default) bounds the
                ! stiffness-form hourglass of plastic shells by the modes'
                ! plastic capacity; 0 leaves the springs elastic
                call get_card(ctx, kw, ic, 'HGBOUND', 1, card, error)
                if (allocated(error)) return
                call get_int(card, 1, c%hgbound, 1, error); if (allocated(error)) return
                c%hgbound_given = .true.
                if (c%hgbound /= 0 .and. c%hgbound /= 1) then
                    call card_error(card, 1, 'HGBOUND '//trim(card%f(1))//' is not 0 or 1', error); return
                end if
            case ('CONTROL_ACCURACY')
                ! OSU (second-order objective stress update), INN (invariant
                ! node numbering), PIDOSU, IACC: xdyna has neither; the
                ! defaults (0, 1 or 0, -, 0) are what it does
                call get_card(ctx, kw, ic, 'OSU INN PIDOSU IACC', 1, card, error)
                if (allocated(error)) return
                call get_int(card, 1, osu, 0, error); if (allocated(error)) return
                call get_int(card, 2, inn, 1, error); if (allocated(error)) return
                call get_int(card, 4, iacc, 0, error); if (allocated(error)) return
                if (osu /= 0) call add_warning(model, at//' field OSU '//itoa(osu)//': the second-order '// &
                    'objective stress update is not implemented (the first-order update is used; answers with '// &
                    'large rotations per step differ); ignored')
                if (inn /= 0 .and. inn /= 1) call add_warning(model, at//' field INN '//itoa(inn)// &
                    ': invariant node numbering is not implemented (element axes follow the node order); ignored')
                if (iacc /= 0) call add_warning(model, at//' field IACC '//itoa(iacc)// &
                    ': the accuracy options of implicit and contact are not implemented; ignored')
            case ('CONTROL_UNITS')
                ! the unit system, for the outputs' labels only (the solver
                ! needs consistent units and converts nothing)
                call get_card(ctx, kw, ic, 'LENGTH TIME MASS TEMP', 1, card, error)
                if (allocated(error)) return
                c%unit_l = unit_index(1, length_units, 'm')
                if (allocated(error)) return
                c%unit_t = unit_index(2, time_units, 'sec')
                if (allocated(error)) return
                c%unit_m = unit_index(3, mass_units, 'kg')
                if (allocated(error)) return
                if (len_trim(card%f(4)) > 0) call add_warning(model, at//' field TEMP: xdyna has no temperatures; '// &
                                                              'ignored')
            case ('CONTROL_ENERGY')
                call get_card(ctx, kw, ic, 'HGEN RWEN SLNTEN RYLEN', 1, card, error)
                if (allocated(error)) return
                call get_int(card, 1, c%hgen, 1, error, zero_default=.true.); if (allocated(error)) return
                call get_int(card, 2, c%rwen, 2, error, zero_default=.true.); if (allocated(error)) return
                call get_int(card, 3, c%slnten, 1, error, zero_default=.true.); if (allocated(error)) return
                call get_int(card, 4, c%rylen, 1, error, zero_default=.true.); if (allocated(error)) return
            end select
        end associate
        if (kw%name == 'CONTROL_SHELL') return
        call no_more_cards(ctx, kw, ic + 1, error)
    contains
        !> The index of field k's unit in `names` (case ignored; blank: the
        !> default `dflt`, LS-DYNA's; 's' is 'sec').
        integer function unit_index(k, names, dflt) result(ix)
            integer, intent(in) :: k
            character(len=*), intent(in) :: names(:), dflt
            character(len=:), allocatable :: v
            integer :: j
            v = to_lower(trim(adjustl(card%f(k))))
            if (len(v) == 0) v = dflt
            if (v == 's') v = 'sec'
            ix = 0
            do j = 1, size(names)
                if (v == trim(names(j))) ix = j
            end do
            if (ix == 0) call card_error(card, k, 'unit "'//trim(adjustl(card%f(k)))//'" is not one of '// &
                                         join(names), error)
        end function unit_index

        function join(names) result(t)
            character(len=*), intent(in) :: names(:)
            character(len=:), allocatable :: t
            integer :: j
            t = trim(names(1))
            do j = 2, size(names)
                t = t//', '//trim(names(j))
            end do
        end function join

        !> Card 1 WRPANG ESORT IRNXX ISTUPD THEORY BWC MITER PROJ; card 2
        !> ROTASCL INTGRD LAMSHT CSTYP6 TSHELL. Fields that would change the
        !> physics and are not implemented get a warning naming them.
        subroutine read_control_shell()
            integer :: v, k, j
            character(len=8), parameter :: names1(8) = [character(len=8) :: 'WRPANG', 'ESORT', 'IRNXX', &
                'ISTUPD', 'THEORY', 'BWC', 'MITER', 'PROJ']
            character(len=8), parameter :: names2(5) = [character(len=8) :: 'ROTASCL', 'INTGRD', 'LAMSHT', &
                'CSTYP6', 'TSHELL']
            real(wp) :: r
            do j = ic, min(kw%ncard, ic + 1)
                if (j == ic) then
                    call get_card(ctx, kw, j, 'WRPANG ESORT IRNXX ISTUPD THEORY BWC MITER PROJ', 1, card, error)
                else
                    call get_card(ctx, kw, j, 'ROTASCL INTGRD LAMSHT CSTYP6 TSHELL', 2, card, error)
                end if
                if (allocated(error)) return
                do k = 1, merge(8, 5, j == ic)
                    call get_real(card, k, r, 0.0_wp, error); if (allocated(error)) return
                    v = nint(r)
                    if (j == ic .and. k == 4) then
                        model%ctl%istupd = v
                        cycle
                    end if
                    if (j == ic) then
                        ! WRPANG is a warning angle; ESORT 0 and THEORY 2 are what xdyna does
                        ! (ESORT 1, C0 triangles for degenerate shells, is not implemented)
                        if (k == 1 .or. (k == 2 .and. v == 0) .or. (k == 5 .and. (v == 2 .or. v == 0))) cycle
                        if (r /= 0.0_wp .and. .not. (k == 3 .and. v == -1)) call add_warning(model, at// &
                            ' field '//trim(names1(k))//': not implemented; ignored')
                    else
                        if (r /= 0.0_wp .and. .not. (k == 1 .and. r == 1.0_wp)) call add_warning(model, at// &
                            ' field '//trim(names2(k))//': not implemented; ignored')
                    end if
                end do
            end do
        end subroutine read_control_shell
    end subroutine read_control

    subroutine read_database(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(history_request_t) :: h
        integer :: ic, k, id, dump, flag
        real(wp) :: lcdt
        ic = first_card(kw)
        if (ic > kw%ncard) return
        select case (kw%name)
        case ('DATABASE_GLSTAT', 'DATABASE_MATSUM', 'DATABASE_NODOUT', 'DATABASE_RCFORC', 'DATABASE_RWFORC')
            call get_card(ctx, kw, ic, 'DT BINARY LCUR IOOPT', 1, card, error)
            if (allocated(error)) return
            call ignored_fields(model, card, [2, 3, 4], 'BINARY 1 or 3: the ASCII file and thist.h5 (the binout''s '// &
                'counterpart), 2: thist.h5 alone; no output curve; ignored', keep='1 2 3')
            call get_real(card, 1, h%dt, 0.0_wp, error); if (allocated(error)) return
            call get_int(card, 2, h%binary, 0, error); if (allocated(error)) return
            if (h%dt < 0.0_wp) then
                call card_error(card, 1, 'output interval must not be negative', error); return
            end if
            h%on = h%dt > 0.0_wp
            select case (kw%name)
            case ('DATABASE_GLSTAT'); model%db%glstat = h
            case ('DATABASE_MATSUM'); model%db%matsum = h
            case ('DATABASE_NODOUT'); model%db%nodout = h
            case ('DATABASE_RWFORC'); model%db%rwforc = h
            case ('DATABASE_RCFORC'); model%db%rcforc = h
            end select
            call no_more_cards(ctx, kw, ic + 1, error)
        case ('DATABASE_HISTORY_NODE', 'DATABASE_HISTORY_NODE_SET')
            do ic = first_card(kw), kw%ncard
                call get_card(ctx, kw, ic, 'ID1 ID2 ID3 ID4 ID5 ID6 ID7 ID8', 1, card, error)
                if (allocated(error)) return
                do k = 1, 8
                    call get_int(card, k, id, 0, error); if (allocated(error)) return
                    if (id < 0) then
                        call card_error(card, k, 'ids must be positive', error); return
                    end if
                    if (id == 0) cycle
                    if (kw%name == 'DATABASE_HISTORY_NODE') then
                        call push(model%db%hist_node, id)
                    else
                        call push(model%db%hist_set, id)
                    end if
                end do
            end do
        case ('DATABASE_HISTORY_NODE_ID')
            ! one node a card: ID, then a heading (for LS-DYNA's legend; not kept)
            do ic = first_card(kw), kw%ncard
                call get_card(ctx, kw, ic, 'ID HEADING', 1, card, error)
                if (allocated(error)) return
                call get_int(card, 1, id, 0, error); if (allocated(error)) return
                if (id <= 0) then
                    call card_error(card, 1, 'node id must be positive', error); return
                end if
                call push(model%db%hist_node, id)
            end do
        case ('DATABASE_BINARY_D3PLOT')
            call get_card(ctx, kw, ic, 'DT LCDT BEAM NPLTC PSETID', 1, card, error)
            if (allocated(error)) return
            call ignored_fields(model, card, [2, 3, 5], 'an output-interval curve, beam output and a part subset of the states '// &
                'are not in xdyna; every part is written at DT; ignored')
            call get_real(card, 1, model%db%d3plot_dt, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 2, lcdt, 0.0_wp, error); if (allocated(error)) return
            call get_int(card, 4, model%db%d3plot_npltc, 0, error); if (allocated(error)) return
        case ('CONTROL_XDYNA_OUTPUT')
            call get_card(ctx, kw, ic, 'BINARY HDF5 X', 1, card, error)
            if (allocated(error)) return
            call get_int(card, 1, flag, 1, error); if (allocated(error)) return
            if (flag /= 0 .and. flag /= 1) then
                call card_error(card, 1, 'BINARY must be 0 (no d3plot family) or 1 (the d3plot family)', error); return
            end if
            model%db%d3plot_binary = flag == 1
            call get_int(card, 2, flag, 0, error); if (allocated(error)) return
            if (flag /= 0 .and. flag /= 1) then
                call card_error(card, 2, 'HDF5 must be 0 (none) or 1 (d3plot.h5 and d3plot.xdmf)', error); return
            end if
            model%db%d3plot_h5 = flag == 1
            call get_int(card, 3, flag, 7, error); if (allocated(error)) return
            if (flag < 1 .or. flag > 8191) then
                call card_error(card, 3, 'X (d3plot member size in units of 262,144 words) must be 1 to 8191', error)
                return
            end if
            model%db%d3plot_x = flag
        case ('DATABASE_BINARY_D3DUMP')
            call get_card(ctx, kw, ic, 'CYCL', 1, card, error)
            if (allocated(error)) return
            call get_int(card, 1, dump, 0, error); if (allocated(error)) return
            model%db%d3dump = max(dump, 0)
        end select
    end subroutine read_database

    subroutine push(a, v)
        integer, allocatable, intent(inout) :: a(:)
        integer, intent(in) :: v
        if (.not. allocated(a)) allocate (a(0))
        a = [a, v]
    end subroutine push

end module xd_input_read_controls
