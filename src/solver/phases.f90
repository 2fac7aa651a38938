!> The phases of one explicit cycle (issue 32, deliverable 5), each a
!> routine with what it reads and writes in its argument list, so that a
!> phase can be read, timed and tested alone and the time loop
!> (xd_solver_time_loop) reads as the list of them: element forces, their
!> exchange and assembly (where the MPI distribution of the elements
!> lives), beams, erosion, the step, applied loads, contact forces,
!> velocities, constraints and rigid bodies, energies, and the advance to
!> the next cycle. A phase that finds
!> the run gone bad returns the reason in `failure` (empty: none); the
!> time loop ends the run with it. Output, restart dumps and batch control
!> stay with the time loop, which holds the run's options and result.
module xd_solver_phases
    use xd_kinds, only: wp, dp
    use xd_core_strings, only: itoa, rtoa, ftoa
    use xd_core_threads, only: threaded
    use xd_core_timers, only: timers_t, ph_elements, ph_assembly, ph_integrate, ph_output, ph_contact, ph_rigid, &
                              ph_local, ph_enforce, ph_comm, ph_ghost, ph_wait
    use xd_core_comm, only: comm_gather_small, comm_max, comm_ordered_records
    use xd_model, only: model_t
    use xd_elements_solid_groups, only: solids_t, solid_forces, solid_name
    use xd_elements_shell_bt, only: shells_t, shell_forces, shell_name
    use xd_elements_beam_bs, only: beams_t, beam_forces
    use xd_elements_erosion, only: shell_failures, erode_shells, dead_model_shells, solid_failures, erode_solids, &
                                   dead_model_hexes
    use xd_solver_state, only: state_t
    use xd_solver_assembly, only: assembly_t, assemble
    use xd_solver_domain, only: domain_t, gather_energy_state, swap_slots, swap_velocities, gather_subset
    use xd_solver_energies, only: energies_t, compute_energies
    use xd_solver_loads, only: body_acceleration, add_body_forces, body_power, pressures_t, apply_pressures, &
                               pressure_power
    use xd_solver_prescribed, only: prescribed_nodes_t, apply_prescribed
    use xd_solver_mass_scaling, only: mass_scaling_t
    use xd_solver_step_control, only: by_element, by_contact, by_floor, by_other, by_growth, dt_growth
    use xd_output_d3hsp, only: log_t, log_line
    use xd_output_histories, only: histories_t, track_rotations
    use xd_contact_contact, only: contacts_t, contact_local_search, contact_enforce, contact_thickness, contact_erode, &
                                  contact_erode_solids, &
                                  contact_events, contact_energy, contact_drift
    use xd_contact_enforcement, only: body_response_t
    use xd_contact_rigidwall, only: walls_t, apply_walls
    use xd_contact_tied, only: ties_t, tie_forces, tie_accelerations, tie_velocities, tie_kinetic, tie_break
    use xd_rigid_bodies, only: rigid_t, rigid_step, rigid_response
    implicit none
    private
    public :: element_phase, exchange_phase, bad_element, beam_phase, erosion_phase, step_phase, load_phase, &
              contact_phase, velocity_phase, constraint_phase, energy_phase, advance_phase, step_element_name, any_rank

contains

    !> Element forces at x(n) with v(n-1/2) (the step before, st%dt_old, and
    !> its average): each rank's solids and shells into their slots, or,
    !> with `shells_direct`, the shells' straight into st%f and st%mom at
    !> the nodes their thread's part holds alone (and no other rank's
    !> element touches), in the assembly's order (after the solids' sums of
    !> this rank's nodes; the nodes the parts or the ranks share are summed
    !> from the slots in exchange_phase). dtcrit: this rank's smallest stable
    !> step, its element in st%crit_elem; bad_kind and bad: the first bad
    !> element (1: solid volume, 2: solid NaN, 3: shell collapsed; 0: none),
    !> in element order, solids first.
    subroutine element_phase(dom, st, solids, asm, sh, tm, shells_direct, dtcrit, bad_kind, bad)
        type(domain_t), intent(in) :: dom
        type(state_t), intent(inout) :: st
        type(solids_t), intent(inout) :: solids
        type(assembly_t), intent(in) :: asm
        type(shells_t), intent(inout) :: sh
        type(timers_t), intent(inout) :: tm
        logical, intent(in) :: shells_direct
        real(wp), intent(out) :: dtcrit
        integer, intent(out) :: bad_kind, bad
        integer :: g
        call tm%start(ph_elements)
        call solid_forces(solids, st%x, st%v, st%dt_old, st%dt_avg_prev)
        call tm%stop(ph_elements)
        dtcrit = huge(1.0_wp)
        bad_kind = 0
        bad = 0
        do g = 1, solids%ngroup
            if (.not. solids%active(g)) cycle
            if (solids%gbad(g) /= 0) then
                bad_kind = 1
                bad = solids%gbad(g)
                exit
            end if
            if (solids%gdt(g) < 0.0_wp) then
                bad_kind = 2
                bad = solids%gcrit(g)
                exit
            end if
            if (solids%gdt(g) < dtcrit) then
                dtcrit = solids%gdt(g)
                st%crit_elem = solids%gcrit(g)
            end if
        end do
        if (shells_direct) then
            ! the nodes' sums start from the solids' (as the assembly's
            ! add), then the shells' forces in slot order
            call tm%start(ph_assembly)
            if (solids%n > 0) then
                if (dom%on) then
                    call assemble(asm, solids%fslot, st%f, nodes=dom%nodes)
                else
                    call assemble(asm, solids%fslot, st%f)
                end if
                if (dom%owned) then
                    call zero_nodes(st%mom, lo=dom%mv_lo, hi=dom%mv_hi)
                else
                    call zero_nodes(st%mom)
                end if
            else if (dom%owned) then
                ! owned nodes: only the nodes this rank moves (its own, its
                ! halo, the surfaces' ghosts, the bodies'): no other node's
                ! force is read on this rank (a gather takes it from its
                ! rank, as exchange_phase's assembly of the solids leaves
                ! them), and a pass over every node of the model does not
                ! shrink with the ranks
                call zero_nodes(st%f, st%mom, dom%mv_lo, dom%mv_hi)
            else
                call zero_nodes(st%f, st%mom)
            end if
            call tm%stop(ph_assembly)
            call tm%start(ph_elements)
            call shell_forces(sh, st%x, st%v, st%vr, st%dt_old, st%dt_avg_prev, st%f, st%mom)
            call tm%stop(ph_elements)
        else if (sh%n > 0) then
            call tm%start(ph_elements)
            call shell_forces(sh, st%x, st%v, st%vr, st%dt_old, st%dt_avg_prev)
            call tm%stop(ph_elements)
        end if
        if (sh%n > 0) then
            if (sh%bad /= 0 .and. bad_kind == 0) then
                bad_kind = 3
                bad = sh%bad
            end if
            if (sh%dtmin < dtcrit) then
                dtcrit = sh%dtmin
                st%crit_elem = -sh%crit
            end if
        end if
    end subroutine element_phase

    !> The element forces' exchange and assembly: under MPI, the smallest
    !> step and the first bad element of all ranks (the cycle's first
    !> collective: its time is mostly the wait for the slowest rank), then
    !> (no bad element) the halo's slots, each rank's nodes summed from the
    !> slots in the serial order (with `shells_direct`, only the nodes the
    !> shells' parts or the ranks share, the solids' sums of the latter
    !> again, now whole), and, in the replicated state, the nodal forces and
    !> moments shared; on one rank, the slots summed into st%f (and
    !> st%mom), or, with `shells_direct`, only the nodes the shells' parts
    !> share. The distribution of the element forces lives here.
    subroutine exchange_phase(dom, st, solids, asm, sh, asm_sh, tm, shells_direct, dtcrit, bad_kind, bad)
        type(domain_t), intent(in) :: dom
        type(state_t), intent(inout) :: st
        type(solids_t), intent(inout) :: solids
        type(assembly_t), intent(in) :: asm, asm_sh
        type(shells_t), intent(inout) :: sh
        type(timers_t), intent(inout) :: tm
        logical, intent(in) :: shells_direct
        real(wp), intent(inout) :: dtcrit
        integer, intent(inout) :: bad_kind, bad
        if (.not. dom%on) then
            call tm%start(ph_assembly)
            if (shells_direct) then
                if (size(sh%shared) > 0) call assemble(asm_sh, sh%fslot, st%f, add=.true., nodes=sh%shared, &
                                                       mslot=sh%mslot, m=st%mom)
            else
                if (solids%n > 0 .or. sh%n == 0) call assemble(asm, solids%fslot, st%f)
                if (sh%n > 0) call assemble(asm_sh, sh%fslot, st%f, add=solids%n > 0, mslot=sh%mslot, m=st%mom)
            end if
            call tm%stop(ph_assembly)
            return
        end if
        call tm%start(ph_wait)
        call reduce_step(dom, st, dtcrit, bad_kind, bad)
        call tm%stop(ph_wait)
        if (bad_kind /= 0) return
        ! the halo: slots of other ranks' elements on this rank's nodes,
        ! from the neighbours that computed them, to this rank alone
        call tm%start(ph_comm)
        call swap_slots(dom, solids, sh)
        call tm%stop(ph_comm)
        call tm%start(ph_assembly)
        if (shells_direct) then
            if (solids%n > 0) call assemble(asm, solids%fslot, st%f, nodes=dom%split_mine)
            if (size(sh%shared) > 0) call assemble(asm_sh, sh%fslot, st%f, add=.true., nodes=sh%shared, &
                                                   mslot=sh%mslot, m=st%mom)
        else
            if (solids%n > 0 .or. sh%n == 0) call assemble(asm, solids%fslot, st%f, nodes=dom%nodes)
            if (sh%n > 0) call assemble(asm_sh, sh%fslot, st%f, add=solids%n > 0, nodes=dom%nodes, &
                                        mslot=sh%mslot, m=st%mom)
        end if
        call tm%stop(ph_assembly)
        ! (owned nodes: each rank integrates its own; the others' forces
        ! are not needed here)
        if (dom%owned) return
        call tm%start(ph_comm)
        if (sh%n > 0) then
            call gather_subset(dom, dom%every, st%f, st%mom)
        else
            call gather_subset(dom, dom%every, st%f)
        end if
        call tm%stop(ph_comm)
    end subroutine exchange_phase

    !> The bad element element_phase found (bad_kind, bad), named: NaN in
    !> its coordinates or velocities, a negative volume, a collapsed shell.
    function bad_element(model, st, solids, sh, bad_kind, bad, dom) result(txt)
        type(model_t), intent(in) :: model
        type(state_t), intent(in) :: st
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        integer, intent(in) :: bad_kind, bad
        !> (nodes numbered per rank: the element's rank looks, and every
        !> rank learns what it saw: a collective)
        type(domain_t), intent(in), optional :: dom
        character(len=:), allocatable :: txt
        logical :: nan_vol, nan_x
        select case (bad_kind)
        case (1)
            ! (its volume where its state is held here: on its rank)
            nan_vol = .false.
            if (solids%goff(solids%group_of(bad)) >= 0) nan_vol = solids%vol(solids%row(bad)) /= solids%vol(solids%row(bad))
            nan_x = .false.
            if (all(solids%conn(:, bad) > 0)) nan_x = any(st%x(:, solids%conn(:, bad)) /= st%x(:, solids%conn(:, bad)))
            if (present(dom)) then
                if (dom%local) nan_x = any_rank(dom, nan_x .or. nan_vol)
            end if
            if (nan_vol .or. nan_x) then
                txt = 'NaN in the coordinates of '//solid_name(model, solids, bad)
            else
                txt = 'negative volume in '//solid_name(model, solids, bad)
            end if
        case (2)
            txt = 'NaN in '//solid_name(model, solids, bad)//' (its nodes'' velocities)'
        case (3)
            txt = shell_name(model, sh, bad)//' has collapsed (zero or negative area)'
        case default
            txt = ''
        end select
    end function bad_element

    !> The beams, on every rank alike, added to the shared forces (each
    !> spot weld that fails named in d3hsp); a beam sets the step where it
    !> is shorter than dtcrit (st%crit_elem 0, beam_crit the beam; else
    !> beam_crit 0).
    subroutine beam_phase(model, st, sh, bm, lg, tm, dtcrit, beam_crit)
        type(model_t), intent(in) :: model
        type(state_t), intent(inout) :: st
        type(shells_t), intent(in) :: sh
        type(beams_t), intent(inout) :: bm
        type(log_t), intent(in) :: lg
        type(timers_t), intent(inout) :: tm
        real(wp), intent(inout) :: dtcrit
        integer, intent(inout) :: beam_crit
        integer :: k
        character(len=250) :: buf
        call tm%start(ph_elements)
        call beam_forces(bm, st%x, st%v, st%vr, st%dt_old, st%time, st%f, st%mom, sh%n == 0)
        call tm%stop(ph_elements)
        do k = 1, size(bm%newly)
            write (buf, '(a,i0,a,i0,a,es12.5,a,6es11.3,a,es10.3,a)') ' spot weld beam ', bm%eid(bm%newly(k)), &
                ' of part ', model%part(bm%part(bm%newly(k)))%id, ' failed at time ', st%time, &
                ' (N, T, M at the ends: ', bm%res(:, bm%newly(k)), '; plastic strain ', bm%epsp(bm%newly(k)), ')'
            call log_line(lg, trim(buf))
        end do
        if (bm%dtmin < dtcrit) then
            dtcrit = bm%dtmin
            st%crit_elem = 0
            beam_crit = bm%crit
        else
            beam_crit = 0
        end if
    end subroutine beam_phase

    !> Zeros in the nodes' a (and b), threaded.
    !> Zeros in the columns of a (and b): every column, or those of the runs
    !> lo(k) .. hi(k).
    subroutine zero_nodes(a, b, lo, hi)
        real(wp), intent(inout) :: a(:, :)
        real(wp), intent(inout), optional :: b(:, :)
        integer, intent(in), optional :: lo(:), hi(:)
        ! (a parallel region only where more than one thread runs it:
        ! xd_core_threads)
        if (threaded(size(a, 2))) then
            !$omp parallel
            call zero_loop(a, b, lo, hi)
            !$omp end parallel
        else
            call zero_loop(a, b, lo, hi)
        end if
    end subroutine zero_nodes

    subroutine zero_loop(a, b, lo, hi)
        real(wp), intent(inout) :: a(:, :)
        real(wp), intent(inout), optional :: b(:, :)
        integer, intent(in), optional :: lo(:), hi(:)
        integer :: i, k
        if (present(lo)) then
            !$omp do schedule(static)
            do k = 1, size(lo)
                do i = lo(k), hi(k)
                    a(:, i) = 0
                    if (present(b)) b(:, i) = 0
                end do
            end do
            !$omp end do
            return
        end if
        !$omp do schedule(static)
        do i = 1, size(a, 2)
            a(:, i) = 0
            if (present(b)) b(:, i) = 0
        end do
        !$omp end do
    end subroutine zero_loop

    !> MPI: the smallest step of all ranks (ties: solids before shells, then
    !> the lower element, as the serial scan finds it) and the first bad
    !> element (solids before shells, then the lower element).
    subroutine reduce_step(dom, st, dtcrit, bad_kind, bad)
        type(domain_t), intent(in) :: dom
        type(state_t), intent(inout) :: st
        real(wp), intent(inout) :: dtcrit
        integer, intent(inout) :: bad_kind, bad
        real(dp) :: rec(4), all(4, dom%nranks)
        integer :: r, best
        rec = [real(dtcrit, dp), real(st%crit_elem, dp), real(bad_kind, dp), real(bad, dp)]
        call comm_gather_small(rec, all)
        best = 0
        do r = 1, dom%nranks
            if (all(3, r) == 0) cycle
            if (best == 0) then
                best = r
            else if (all(3, r) < all(3, best) .or. (all(3, r) == all(3, best) .and. all(4, r) < all(4, best))) then
                best = r
            end if
        end do
        if (best > 0) then
            bad_kind = nint(all(3, best))
            bad = nint(all(4, best))
            return
        end if
        best = 1
        do r = 2, dom%nranks
            if (all(1, r) < all(1, best)) then
                best = r
            else if (all(1, r) == all(1, best) .and. before(all(2, r), all(2, best))) then
                best = r
            end if
        end do
        dtcrit = real(all(1, best), wp)
        st%crit_elem = nint(all(2, best))
    end subroutine reduce_step

    !> Is the step's element c1 before c2 in the serial scan (solids > 0
    !> before shells < 0; 0, none, last)?
    logical function before(c1, c2)
        real(dp), intent(in) :: c1, c2
        if (c2 == 0) then
            before = c1 /= 0
        else if (c1 > 0 .and. c2 > 0) then
            before = c1 < c2
        else if (c1 < 0 .and. c2 < 0) then
            before = c1 > c2
        else
            before = c1 > 0 .and. c2 < 0
        end if
    end function before

    !> 'solid 12 of part 3', 'shell 7 of part 2' or 'beam 4 of part 1': the
    !> element of the step (st%crit_elem; beam_crit for a beam).
    function step_element_name(model, st, solids, sh, bm, beam_crit) result(txt)
        type(model_t), intent(in) :: model
        type(state_t), intent(in) :: st
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        type(beams_t), intent(in) :: bm
        integer, intent(in) :: beam_crit
        character(len=:), allocatable :: txt
        txt = 'element unknown'
        if (st%crit_elem > 0) txt = solid_name(model, solids, st%crit_elem)
        if (st%crit_elem < 0) txt = shell_name(model, sh, -st%crit_elem)
        if (st%crit_elem == 0 .and. beam_crit > 0) txt = 'beam '//itoa(bm%eid(beam_crit))//' of part '// &
                                                         itoa(model%part(bm%part(beam_crit))%id)
    end function step_element_name

    !> Whether `flag` holds on any rank (the rank itself when not parallel).
    logical function any_rank(dom, flag)
        type(domain_t), intent(in) :: dom
        logical, intent(in) :: flag
        real(dp) :: fl(1)
        fl = merge(1.0_dp, 0.0_dp, flag)
        if (dom%on) call comm_max(fl)
        any_rank = fl(1) > 0.0_dp
    end function any_rank

    !> The shells and solids that fail at this state erode on every rank:
    !> they leave the element loops (shells) or are computed frozen
    !> (solids), and the contact's surfaces (shells), each named in d3hsp.
    subroutine erosion_phase(model, dom, st, solids, sh, ct, lg)
        type(model_t), intent(in) :: model
        type(domain_t), intent(in) :: dom
        !> (owned nodes: the eroded solids' nodes' coordinates from their
        !> elements' ranks, where every rank freezes them)
        type(state_t), intent(inout) :: st
        type(solids_t), intent(inout) :: solids
        type(shells_t), intent(inout) :: sh
        type(contacts_t), intent(inout) :: ct
        type(log_t), intent(in) :: lg
        integer, allocatable :: newly(:)
        integer :: k
        if (sh%erodible) then
            call shell_failures(sh, model%mat, st%time, newly)
            newly = on_every_rank(dom, newly, sh%dead)
            if (size(newly) > 0) then
                if (dom%owned) call from_element_ranks(newly, dom%shell_mine, sh%eint)
                call erode_shells(sh, newly)
                do k = 1, min(size(newly), 2000 - (sh%ndead - size(newly)))
                    call log_eroded(lg, 'shell', sh%eid(newly(k)), model%part(sh%part(newly(k)))%id, st%time, &
                                    sh%eint(newly(k)))
                end do
                if (ct%n > 0) call contact_erode(ct, dead_model_shells(sh, model%nshell))
            end if
        end if
        if (solids%erodible) then
            call solid_failures(solids, model, st%time, st%x, newly)
            newly = on_every_rank(dom, newly, solids%dead)
            if (size(newly) > 0) then
                if (dom%owned) then
                    call from_element_ranks(newly, dom%solid_mine, solids%eint)
                    call solid_nodes_from_ranks(newly)
                end if
                call erode_solids(solids, newly, st%x)
                do k = 1, min(size(newly), 2000 - (solids%ndead - size(newly)))
                    call log_eroded(lg, 'solid', solids%eid(newly(k)), model%part(solids%part(newly(k)))%id, &
                                    st%time, solids%eint(newly(k)))
                end do
                ! the faces they exposed join the contact surfaces, theirs leave
                if (ct%n > 0) call contact_erode_solids(ct, model%hex_conn(:, 1:model%nhex), &
                                                        dead_model_hexes(solids, model%nhex), st%x)
            end if
        end if
    contains
        !> Owned nodes: the eroded elements' internal energy (logged, every
        !> rank alike) from their own ranks, which hold it current.
        subroutine from_element_ranks(gone, mine, eint)
            integer, intent(in) :: gone(:)
            logical, intent(in) :: mine(:)
            real(dp), intent(inout) :: eint(:)
            real(dp), allocatable :: rec(:, :), all(:, :)
            integer :: k, n
            allocate (rec(2, size(gone)))
            n = 0
            do k = 1, size(gone)
                if (.not. mine(gone(k))) cycle
                n = n + 1
                rec(:, n) = [real(gone(k), dp), eint(gone(k))]
            end do
            call comm_ordered_records(rec(:, 1:n), all, .true.)
            do k = 1, size(all, 2)
                eint(nint(all(1, k))) = all(2, k)
            end do
        end subroutine from_element_ranks

        !> Owned nodes: the eroded solids' nodes' coordinates from the
        !> solids' own ranks (every rank freezes the element's shape; where
        !> a rank moves a node too it holds the same bits already).
        subroutine solid_nodes_from_ranks(gone)
            integer, intent(in) :: gone(:)
            real(dp), allocatable :: rec(:, :), all(:, :)
            integer :: k, n, j
            allocate (rec(25, size(gone)))
            n = 0
            do k = 1, size(gone)
                if (.not. dom%solid_mine(gone(k))) cycle
                n = n + 1
                rec(1, n) = real(gone(k), dp)
                rec(2:25, n) = real(reshape(st%x(:, solids%conn(:, gone(k))), [24]), dp)
            end do
            call comm_ordered_records(rec(:, 1:n), all, .true.)
            do k = 1, size(all, 2)
                do j = 1, 8
                    st%x(:, solids%conn(j, nint(all(1, k)))) = real(all(3*j - 1:3*j + 1, k), wp)
                end do
            end do
        end subroutine solid_nodes_from_ranks
    end subroutine erosion_phase

    !> The elements that fail now on any rank (each rank's list `newly`
    !> shared), less those already eroded; on one rank, newly itself.
    function on_every_rank(dom, newly, dead) result(all_new)
        type(domain_t), intent(in) :: dom
        integer, intent(in) :: newly(:)
        logical, intent(in) :: dead(:)
        integer, allocatable :: all_new(:)
        real(dp), allocatable :: flag(:)
        integer :: k
        if (.not. dom%on) then
            all_new = newly
            return
        end if
        if (.not. any_rank(dom, size(newly) > 0)) then
            allocate (all_new(0))
            return
        end if
        allocate (flag(size(dead)))
        flag = 0
        flag(newly) = 1
        call comm_max(flag)
        all_new = pack([(k, k=1, size(dead))], flag > 0.0_dp .and. .not. dead)
    end function on_every_rank

    !> d3hsp's line for an eroded element (the first 2,000 of a kind).
    subroutine log_eroded(lg, kind, eid, pid, time, eint)
        type(log_t), intent(in) :: lg
        character(len=*), intent(in) :: kind
        integer, intent(in) :: eid, pid
        real(dp), intent(in) :: time, eint
        character(len=200) :: buf
        write (buf, '(a,i0,a,i0,a,es12.5,a,es11.4)') ' '//kind//' ', eid, ' of part ', pid, ' eroded at time ', time, &
            ', internal energy ', eint
        call log_line(lg, trim(buf))
    end subroutine log_eroded

    !> The step st%dt of this cycle from the elements' stable step dtc:
    !> TSSFAC times the shortest of the elements', the mass-scaling floor's,
    !> the contact springs' (where shorter), DTINIT's (rigid bodies alone, and
    !> the first step); falling at once, growing by dt_growth a cycle at
    !> most. set_by says what set it. A step that is not a finite positive
    !> number, grew a hundredfold over the run's first (dt_ref, taken at
    !> the run's first cycle cycle0) or fell below DTMIN is a failure naming
    !> the element that sets it.
    subroutine step_phase(model, ms, solids, sh, bm, ct, lg, cycle0, beam_crit, dtc, st, dt_ref, set_by, failure)
        type(model_t), intent(in) :: model
        type(mass_scaling_t), intent(in) :: ms
        type(solids_t), intent(inout) :: solids
        type(shells_t), intent(inout) :: sh
        type(beams_t), intent(in) :: bm
        type(contacts_t), intent(in) :: ct
        type(log_t), intent(in) :: lg
        integer, intent(in) :: cycle0, beam_crit
        real(wp), intent(inout) :: dtc
        type(state_t), intent(inout) :: st
        real(wp), intent(inout) :: dt_ref
        integer, intent(out) :: set_by
        character(len=:), allocatable, intent(out) :: failure
        failure = ''
        set_by = by_element
        if (ms%on) then
            if (dtc == ms%target) set_by = by_floor
        end if
        ! a model of rigid bodies alone has no element step: DTINIT sets it
        if (solids%ngroup == 0 .and. sh%n == 0 .and. bm%n == 0) then
            dtc = model%ctl%dtinit/model%ctl%tssfac
            set_by = by_other
        end if
        ! every deformable element eroded (none sets a step): the last
        ! step goes on
        if (solids%n + sh%n > 0 .and. bm%n == 0) then
            if (solids%ndead == solids%n .and. sh%ndead == sh%n .and. st%cycle > cycle0) then
                dtc = st%dt_old/model%ctl%tssfac
                set_by = by_other
            end if
        end if
        ! the stiffest contact spring's stable step, if it is shorter
        if (ct%n > 0) then
            if (ct%dt_limit < dtc) then
                if (st%cycle == cycle0) call log_line(lg, ' *** Warning: the stiffest contact spring''s stable '// &
                    'step '//rtoa(real(ct%dt_limit, dp))//' (node '//itoa(model%node_id(ct%dt_node))// &
                    ') is below the elements'' '//rtoa(real(dtc, dp))//': the contact sets the time step, '// &
                    'at '//ftoa(real(dtc/ct%dt_limit, dp))//' times the cycles (penalty scale SLSFAC, SFS, '// &
                    'SFM, or a cohesive tiebreak''s CN, too high?)')
                dtc = ct%dt_limit
                set_by = by_contact
            end if
        end if
        st%dt = real(model%ctl%tssfac, wp)*dtc
        ! falls at once, grows by 0.1% a cycle at most (dt_growth: a step
        ! that follows an element's ringing pumps it); from the step
        ! before the dump on a restart, as the uninterrupted run does
        if (st%cycle > 0 .and. st%dt_old > 0.0_wp) then
            if (st%dt > dt_growth*st%dt_old) then
                st%dt = dt_growth*st%dt_old
                set_by = by_growth
            end if
        end if
        ! the step of an intact mesh changes slowly: one that is not a
        ! finite positive number, or grew a hundredfold over this run's
        ! first, comes from elements turned inside out or a state gone
        ! bad (a curve of 1e30), not from physics
        if (st%cycle == cycle0) dt_ref = st%dt
        ! ERODE: from the first step on, shells whose step falls below
        ! DTMIN times it erode
        if (model%ctl%erode == 1 .and. model%ctl%dtmin > 0.0_wp .and. sh%n > 0 .and. sh%tsmin == 0.0_wp .and. &
            st%dt_first > 0.0_wp) sh%tsmin = model%ctl%dtmin*st%dt_first/real(model%ctl%tssfac, wp)
        ! and solids likewise (the elements' own steps, before TSSFAC, as the
        ! shells')
        if (model%ctl%erode == 1 .and. model%ctl%dtmin > 0.0_wp .and. solids%n > 0 .and. solids%tsmin == 0.0_wp &
            .and. st%dt_first > 0.0_wp) solids%tsmin = model%ctl%dtmin*st%dt_first/real(model%ctl%tssfac, wp)
        if (.not. (st%dt > 0.0_wp .and. st%dt <= huge(1.0_wp))) then
            failure = 'time step '//rtoa(real(st%dt, dp))//' is not a finite positive number; controlling '// &
                      step_element_name(model, st, solids, sh, bm, beam_crit)
            return
        else if (st%dt > 100.0_wp*dt_ref) then
            failure = 'time step '//rtoa(real(st%dt, dp))//' grew beyond 100 times the run''s first ('// &
                      rtoa(real(dt_ref, dp))//'): the state has gone bad; controlling '// &
                      step_element_name(model, st, solids, sh, bm, beam_crit)
            return
        end if
        if (st%cycle == 0) then
            if (model%ctl%dtinit > 0.0_wp) then
                if (model%ctl%dtinit < st%dt) set_by = by_other
                st%dt = min(st%dt, model%ctl%dtinit)
            end if
            st%dt_first = st%dt
        else if (model%ctl%dtmin > 0.0_wp .and. st%dt < model%ctl%dtmin*st%dt_first) then
            failure = 'time step '//rtoa(real(st%dt, dp))//' fell below DTMIN x first step; '// &
                      'controlling '//step_element_name(model, st, solids, sh, bm, beam_crit)
        end if
    end subroutine step_phase

    !> The applied loads at t(n) join f(n): body forces m g(n) and
    !> pressures, each doing f(n) . (v(n-1/2) + v(n+1/2))/2 dt_avg; the
    !> first half (with v(n-1/2)) here, the second in constraint_phase.
    !> g_new: the body acceleration, kept for the second half.
    subroutine load_phase(model, dom, pl, st, dt_avg, g_new)
        type(model_t), intent(in) :: model
        !> (owned nodes: the body load's power summed over every rank's own nodes)
        type(domain_t), intent(in) :: dom
        type(pressures_t), intent(inout) :: pl
        type(state_t), intent(inout) :: st
        real(dp), intent(in) :: dt_avg
        real(wp), intent(inout) :: g_new(3)
        if (model%nbody > 0) then
            g_new = body_acceleration(model, real(st%time, wp))
            st%ext_work = st%ext_work + 0.5_dp*dt_avg*body_power(st, g_new, dom%own)
            call add_body_forces(st, g_new)
        end if
        if (pl%n > 0) then
            ! pressure forces: the same work rule as every force at t(n)
            call apply_pressures(model, pl, st)
            st%ext_work = st%ext_work + 0.5_dp*dt_avg*pressure_power(pl, st)
        end if
    end subroutine load_phase

    !> Steps 3-4 of the automatic contact on x(n): each slave's contact
    !> (local search) and the penalty forces (or the Lagrangian projection,
    !> where a master on a rigid body answers as the body: br), added to
    !> st%f; the cycle's contact events logged.
    subroutine contact_phase(model, dom, ct, rg, sh, st, lg, tm, dt_avg, outputs, sums, br)
        type(model_t), intent(in) :: model
        type(domain_t), intent(in) :: dom
        type(contacts_t), intent(inout) :: ct
        type(rigid_t), intent(in) :: rg
        type(shells_t), intent(in) :: sh
        type(state_t), intent(inout) :: st
        type(log_t), intent(in) :: lg
        type(timers_t), intent(inout) :: tm
        real(dp), intent(in) :: dt_avg
        !> the outputs read this cycle's contact forces per node
        logical, intent(in) :: outputs
        !> rcforc reads this cycle's sums over every pair
        logical, intent(in) :: sums
        type(body_response_t), intent(inout) :: br
        real(dp) :: t_gather
        call tm%start(ph_local)
        ! THKCHG: the shells' thickness of this cycle's element pass
        if (ct%thkchg .and. sh%n > 0) then
            if (sh%by_row) then
                call contact_thickness(ct, sh%conn, sh%h, sh%mine, sh%lix)
            else
                call contact_thickness(ct, sh%conn, sh%h, sh%mine)
            end if
        end if
        ! (dom%own_contact unallocated, so absent, on one rank or under XDYNA_CONTACT_OWN=0)
        call contact_local_search(ct, st%x, st%v, st%time, st%dt, dom%own_contact)
        call tm%stop(ph_local)
        call tm%start(ph_enforce)
        t_gather = ct%wall_gather
        ! owned nodes: the Lagrangian projection reads the contact surfaces'
        ! nodes' forces, from their ranks (every rank then projects every
        ! pair alike)
        if (ct%lagrange .and. dom%owned) call gather_subset(dom, dom%surf, st%f)
        if (ct%lagrange .and. rg%n > 0) then
            ! a master on a rigid body answers as the body
            call rigid_response(rg, st%nnode, br)
            call contact_enforce(ct, st%f, st%dt, real(dt_avg, wp), st%mass, st%dofs, st%time, outputs, sums, br)
        else
            call contact_enforce(ct, st%f, st%dt, real(dt_avg, wp), st%mass, st%dofs, st%time, outputs, sums)
        end if
        call tm%stop(ph_enforce)
        if (dom%on) call tm%move(ph_enforce, ph_ghost, ct%wall_gather - t_gather)
        if (any(ct%ifc(:)%nev > 0) .or. any(ct%ifc(:)%ed%nev > 0)) call log_line(lg, contact_events(ct, model%node_id))
    end subroutine contact_phase

    !> Accelerations a(n) = f(n) / m (the tied contacts' slaves' forces
    !> carried by their segments first) and central differences: v(n+1/2) =
    !> v(n-1/2) + a(n) (dt(n-1/2) + dt(n+1/2))/2, the angular velocities
    !> likewise. With save_minus, v(n-1/2) (and the angular velocities) are
    !> kept in vminus (vrminus) for the energies.
    subroutine velocity_phase(dom, st, td, dt_avg, save_minus, vminus, vrminus)
        type(domain_t), intent(in) :: dom
        type(state_t), intent(inout) :: st
        type(ties_t), intent(inout) :: td
        real(dp), intent(in) :: dt_avg
        logical, intent(in) :: save_minus
        real(wp), intent(inout) :: vminus(:, :)
        real(wp), intent(inout), allocatable :: vrminus(:, :)
        ! tied contacts: the slaves' forces to their segments, and the
        ! segments' nodes accelerated with the slave masses they carry
        if (save_minus) vminus = st%v
        if (st%rot .and. save_minus) vrminus = st%vr
        if (td%n > 0) then
            ! owned nodes: the ties' nodes' forces from their ranks first;
            ! every rank then takes every tie, and updates the velocities of
            ! its own nodes and the ties' (kick_lo, kick_hi)
            ! (st%mom unallocated without rotations: absent)
            if (dom%owned) call gather_subset(dom, dom%tie, st%f, st%mom)
            call tie_forces(td, st%time, st%x, st%f, st%mom)
            call accelerations(st)
            call tie_accelerations(td, st%time, st%f, st%mass, st%dofs, st%a, st%mom, st%irot)
        end if
        ! (without ties the accelerations are taken in the kick's own loop:
        ! the same quotients, one pass over the nodes fewer)
        if (dom%owned) then
            if (threaded(size(dom%nodes))) then
                !$omp parallel
                call kick_runs(st, real(dt_avg, wp), dom%kick_lo, dom%kick_hi, td%n == 0)
                !$omp end parallel
            else
                call kick_runs(st, real(dt_avg, wp), dom%kick_lo, dom%kick_hi, td%n == 0)
            end if
        else if (threaded(st%nnode)) then
            !$omp parallel
            call kick(st, real(dt_avg, wp), td%n == 0)
            !$omp end parallel
        else
            call kick(st, real(dt_avg, wp), td%n == 0)
        end if
    end subroutine velocity_phase

    !> v += dt a, and vr likewise where the state has rotations; with
    !> from_forces, a = f / m in the free directions first, in the same loop
    !> (free_accel, as accelerations_loop). (Here and in kick_runs and
    !> accelerations_loop a direction's mask is xd_core_dofs' free_dir
    !> written out, real(ibits(dofs, j - 1, 1)): a call to another module's
    !> function is not inlined, and the loops would not vectorise.)
    subroutine kick(st, dt, from_forces)
        type(state_t), intent(inout) :: st
        real(wp), intent(in) :: dt
        logical, intent(in) :: from_forces
        integer :: nd
        real(wp) :: a1, a2, a3
        if (from_forces) then
            !$omp do schedule(static)
            do nd = 1, st%nnode
                a1 = free_accel(st%f(1, nd), st%mass(nd), real(ibits(st%dofs(nd), 0, 1), wp))
                a2 = free_accel(st%f(2, nd), st%mass(nd), real(ibits(st%dofs(nd), 1, 1), wp))
                a3 = free_accel(st%f(3, nd), st%mass(nd), real(ibits(st%dofs(nd), 2, 1), wp))
                st%a(1, nd) = a1
                st%a(2, nd) = a2
                st%a(3, nd) = a3
                st%v(1, nd) = st%v(1, nd) + dt*a1
                st%v(2, nd) = st%v(2, nd) + dt*a2
                st%v(3, nd) = st%v(3, nd) + dt*a3
            end do
            !$omp end do nowait
        else
            !$omp do schedule(static)
            do nd = 1, st%nnode
                st%v(:, nd) = st%v(:, nd) + dt*st%a(:, nd)
            end do
            !$omp end do nowait
        end if
        if (st%rot) then
            ! (a node without rotary inertia divides by 1 and adds 0 times
            ! that: no select, so that the loop vectorises)
            !$omp do schedule(static)
            do nd = 1, st%nnode
                st%vr(1, nd) = st%vr(1, nd) + free_spin(dt, st%mom(1, nd), st%irot(nd), real(ibits(st%dofs(nd), 3, 1), wp))
                st%vr(2, nd) = st%vr(2, nd) + free_spin(dt, st%mom(2, nd), st%irot(nd), real(ibits(st%dofs(nd), 4, 1), wp))
                st%vr(3, nd) = st%vr(3, nd) + free_spin(dt, st%mom(3, nd), st%irot(nd), real(ibits(st%dofs(nd), 5, 1), wp))
            end do
            !$omp end do
        end if
    end subroutine kick

    !> The kick of the nodes in the runs lo(k) .. hi(k) alone (owned
    !> nodes): the same operations as kick's node by node, each run's in a
    !> loop that vectorises; with from_forces the accelerations from the
    !> forces first (free_accel), else those in st%a (ties).
    subroutine kick_runs(st, dt, lo, hi, from_forces)
        type(state_t), intent(inout) :: st
        real(wp), intent(in) :: dt
        integer, intent(in) :: lo(:), hi(:)
        logical, intent(in) :: from_forces
        integer :: k, nd
        real(wp) :: a1, a2, a3
        !$omp do schedule(static)
        do k = 1, size(lo)
            if (from_forces) then
                ! (as kick's loop: the accelerations held in scalars, stored
                ! and added; written to st%a and read back from it, rank 0 of
                ! 16 on the 10 x 10 tubes took 8.6e7 instructions in 100
                ! cycles here, 5.8e7 now. The same lines as kick's, not a
                ! routine both call: a pure routine a node, called from both
                ! loops, made the serial kick 47% more instructions, 2.4e8 ->
                ! 3.6e8 on the 5 x 5 tubes in 30 cycles: tried)
                do nd = lo(k), hi(k)
                    a1 = free_accel(st%f(1, nd), st%mass(nd), real(ibits(st%dofs(nd), 0, 1), wp))
                    a2 = free_accel(st%f(2, nd), st%mass(nd), real(ibits(st%dofs(nd), 1, 1), wp))
                    a3 = free_accel(st%f(3, nd), st%mass(nd), real(ibits(st%dofs(nd), 2, 1), wp))
                    st%a(1, nd) = a1
                    st%a(2, nd) = a2
                    st%a(3, nd) = a3
                    st%v(1, nd) = st%v(1, nd) + dt*a1
                    st%v(2, nd) = st%v(2, nd) + dt*a2
                    st%v(3, nd) = st%v(3, nd) + dt*a3
                end do
            else
                do nd = lo(k), hi(k)
                    st%v(:, nd) = st%v(:, nd) + dt*st%a(:, nd)
                end do
            end if
            if (.not. st%rot) cycle
            do nd = lo(k), hi(k)
                st%vr(1, nd) = st%vr(1, nd) + free_spin(dt, st%mom(1, nd), st%irot(nd), real(ibits(st%dofs(nd), 3, 1), wp))
                st%vr(2, nd) = st%vr(2, nd) + free_spin(dt, st%mom(2, nd), st%irot(nd), real(ibits(st%dofs(nd), 4, 1), wp))
                st%vr(3, nd) = st%vr(3, nd) + free_spin(dt, st%mom(3, nd), st%irot(nd), real(ibits(st%dofs(nd), 5, 1), wp))
            end do
        end do
        !$omp end do
    end subroutine kick_runs

    !> a = f / m in the free directions.
    subroutine accelerations(st)
        type(state_t), intent(inout) :: st
        if (threaded(st%nnode)) then
            !$omp parallel
            call accelerations_loop(st)
            !$omp end parallel
        else
            call accelerations_loop(st)
        end if
    end subroutine accelerations

    subroutine accelerations_loop(st)
        type(state_t), intent(inout) :: st
        integer :: i
        !$omp do schedule(static)
        do i = 1, st%nnode
            st%a(1, i) = free_accel(st%f(1, i), st%mass(i), real(ibits(st%dofs(i), 0, 1), wp))
            st%a(2, i) = free_accel(st%f(2, i), st%mass(i), real(ibits(st%dofs(i), 1, 1), wp))
            st%a(3, i) = free_accel(st%f(3, i), st%mass(i), real(ibits(st%dofs(i), 2, 1), wp))
        end do
        !$omp end do
    end subroutine accelerations_loop

    !> A node's acceleration f / m in a direction (free 1) or 0 (free 0, or
    !> a massless node). (The quotient taken for every node, a massless
    !> one's over 1 and then times 0, without a select: the loops
    !> vectorise.)
    !> A node's angular velocity change dt M / I about a free axis (free_r
    !> 1) or 0 (free_r 0, or no rotary inertia: the quotient over 1 and
    !> then times 0, no select, so that the loops vectorise).
    pure elemental real(wp) function free_spin(dt, m, ri, free_r) result(dw)
        real(wp), intent(in) :: dt, m, ri, free_r
        real(wp) :: on
        on = merge(1.0_wp, 0.0_wp, ri > 0.0_wp)
        dw = dt*m/(ri + (1.0_wp - on))*free_r*on
    end function free_spin

    pure elemental real(wp) function free_accel(f, m, free) result(a)
        real(wp), intent(in) :: f, m, free
        real(wp) :: on
        on = merge(1.0_wp, 0.0_wp, m > 0.0_wp)
        a = f/(m + (1.0_wp - on))*free*on
    end function free_accel

    !> The constraints on v(n+1/2), in order: rigid walls, prescribed
    !> motion, rigid bodies, tied slaves (after every other update; the
    !> tiebreaks' failures logged); the work of the walls' and prescribed
    !> motions' forces, and the second half of the applied loads' (with the
    !> final v(n+1/2)), added to st%ext_work. no_body: per node, not a rigid
    !> body's (models without rigid bodies).
    subroutine constraint_phase(model, dom, walls, pn, rg, td, pl, st, lg, tm, dt_avg, g_new, no_body)
        type(model_t), intent(in) :: model
        !> (owned nodes: the walls and prescribed motions act on this rank's
        !> nodes, their sums over every rank's)
        type(domain_t), intent(in) :: dom
        type(walls_t), intent(inout) :: walls
        type(prescribed_nodes_t), intent(in) :: pn
        type(rigid_t), intent(inout) :: rg
        type(ties_t), intent(inout) :: td
        type(pressures_t), intent(inout) :: pl
        type(state_t), intent(inout) :: st
        type(log_t), intent(in) :: lg
        type(timers_t), intent(inout) :: tm
        real(dp), intent(in) :: dt_avg
        real(wp), intent(in) :: g_new(3)
        logical, intent(in) :: no_body(:)
        real(dp) :: wpm
        character(len=:), allocatable :: tie_events
        if (walls%n > 0) then
            call tm%start(ph_contact)
            ! (dom%own unallocated, so absent, but with owned nodes)
            if (rg%n > 0) then
                call apply_walls(model, walls, st, st%dt, real(dt_avg, wp), rg%member, dom%own)
            else
                call apply_walls(model, walls, st, st%dt, real(dt_avg, wp), no_body, dom%own)
            end if
            call tm%stop(ph_contact)
        end if
        if (pn%n > 0) then
            if (td%n > 0) then
                call apply_prescribed(model, pn, st, st%dt, real(dt_avg, wp), wpm, td%mnodal, dom%own)
            else
                call apply_prescribed(model, pn, st, st%dt, real(dt_avg, wp), wpm, mine=dom%own)
            end if
            st%ext_work = st%ext_work + wpm
        end if
        if (rg%n > 0) then
            call tm%start(ph_rigid)
            ! owned nodes: the bodies' nodes' forces (and moments) from their
            ! ranks, so that every rank moves every body alike
            if (dom%owned) call gather_subset(dom, dom%body, st%f, st%mom)
            call rigid_step(rg, model, st, st%dt, real(dt_avg, wp), wpm, walls)
            st%ext_work = st%ext_work + wpm
            call tm%stop(ph_rigid)
        end if
        ! owned nodes: the final v(n+1/2) of the nodes this rank holds but
        ! does not integrate, from their ranks (the ties and the pressures'
        ! power below read them; every rank then moves the tied slaves alike)
        if (dom%owned) call exchange_velocities(dom, st, tm)
        ! tied slaves move with their segments (after every other update)
        if (td%n > 0) then
            call tie_velocities(td, st%time, st%dt, st%x, st%v, st%vr)
            ! tiebreak: each held slave's interface force from its
            ! velocity change this step
            call tie_break(td, st%time, st%mass, real(dt_avg, wp), st%v, st%x, tie_events, model%node_id)
            if (len(tie_events) > 0) call log_line(lg, tie_events)
        end if
        ! second half of the load work, with the final v(n+1/2)
        if (model%nbody > 0) st%ext_work = st%ext_work + 0.5_dp*dt_avg*body_power(st, g_new, dom%own)
        if (pl%n > 0) st%ext_work = st%ext_work + 0.5_dp*dt_avg*pressure_power(pl, st)
    end subroutine constraint_phase

    !> The energies at t(n) in en (the element state gathered from the
    !> ranks first), from v(n-1/2) (vminus, vrminus) and v(n+1/2); then
    !> vminus becomes v(n), the mid-step velocities the outputs write (one
    !> nodal array for both: v(n-1/2) is read no more until the next
    !> energies save it again). At cycle 0 the kinetic energy
    !> is that of the initial velocities (the start v(1/2) = v(0) + a(0)
    !> dt/2 adds an O(dt^2) offset when a(0) /= 0), and it sets the initial
    !> energy. ke_fix: the tied contacts' kinetic energy by part.
    subroutine energy_phase(model, dom, st, solids, sh, walls, rg, ct, td, bm, tm, vminus, vrminus, dt_avg, ke_fix, en)
        type(model_t), intent(in) :: model
        type(domain_t), intent(in) :: dom
        type(state_t), intent(inout) :: st
        type(solids_t), intent(inout) :: solids
        type(shells_t), intent(inout) :: sh
        type(walls_t), intent(in) :: walls
        type(rigid_t), intent(in) :: rg
        type(contacts_t), intent(in) :: ct
        type(ties_t), intent(in) :: td
        type(beams_t), intent(in) :: bm
        type(timers_t), intent(inout) :: tm
        real(wp), intent(inout) :: vminus(:, :)
        real(wp), intent(in), allocatable :: vrminus(:, :)
        real(dp), intent(in) :: dt_avg
        real(dp), intent(inout) :: ke_fix(:)
        type(energies_t), intent(inout) :: en
        call tm%start(ph_output)
        ! (owned nodes: each rank sums its own nodes and elements, then the
        ! ranks' sums are added: no element state gathered)
        if (.not. dom%owned) call gather_energy_state(dom, solids, sh)
        if (st%cycle == 0) then
            ! (vrminus, like vminus, was taken before the update; v(n) is
            ! vminus as it is)
            if (td%n > 0) call tie_kinetic(td, st%mass, st%irot, vminus, vminus, vrminus, vrminus, ke_fix)
            ! (dom%own, own_solid, own_shell unallocated, so absent, but with
            ! owned nodes)
            call compute_energies(model, st, solids, sh, walls, rg, vminus, vminus, vrminus, vrminus, 0.0_dp, en, &
                                  contact_energy(ct, 0.0_dp), ke_fix, bm, dom%own, dom%own_solid, dom%own_shell)
            st%e_initial = en%total
            ! mass scaled at cycle 0 is in the initial energy
            st%ms_work = 0
            en%ratio = 1.0_dp
            ! no work is done by t = 0 (st%ext_work already holds the
            ! first half step's, the leapfrog's share of cycle 0, which
            ! the energies of t(1) count)
            en%ext = 0
        else
            if (td%n > 0) call tie_kinetic(td, st%mass, st%irot, vminus, st%v, vrminus, st%vr, ke_fix)
            call compute_energies(model, st, solids, sh, walls, rg, vminus, st%v, vrminus, st%vr, dt_avg, en, &
                                  contact_energy(ct, dt_avg) + td%ework, ke_fix, bm, dom%own, dom%own_solid, &
                                  dom%own_shell)
            vminus = 0.5_wp*(vminus + st%v)
        end if
        call tm%stop(ph_output)
    end subroutine energy_phase

    !> Owned nodes: the final v(n+1/2) of the nodes this rank holds but does
    !> not integrate, from their ranks (swap_velocities), before anything
    !> reads them (the contact's work, the advance).
    subroutine exchange_velocities(dom, st, tm)
        type(domain_t), intent(in) :: dom
        type(state_t), intent(inout) :: st
        type(timers_t), intent(inout) :: tm
        call tm%start(ph_comm)
        ! (st%vr unallocated without rotations: absent)
        call swap_velocities(dom, st%v, st%vr)
        call tm%stop(ph_comm)
    end subroutine exchange_velocities

    !> x(n+1) = x(n) + dt(n+1/2) v(n+1/2), the contact's motion bounds and
    !> the histories' rotations with it, and the clock to t(n+1).
    subroutine advance_phase(dom, st, ct, hist, tm, dt_avg)
        type(domain_t), intent(in) :: dom
        type(state_t), intent(inout) :: st
        type(contacts_t), intent(inout) :: ct
        type(histories_t), intent(inout) :: hist
        type(timers_t), intent(inout) :: tm
        real(dp), intent(in) :: dt_avg
        call tm%start(ph_integrate)
        if (dom%owned) then
            ! owned nodes: every node this rank holds a velocity for
            ! (exchange_velocities brought the others' v(n+1/2)), the same
            ! x += dt v as their own ranks take
            if (threaded(size(dom%nodes))) then
                !$omp parallel
                call drift_owned(st, dom%mv_lo, dom%mv_hi)
                !$omp end parallel
            else
                call drift_owned(st, dom%mv_lo, dom%mv_hi)
            end if
            call track_rotations(hist, st, dom%node_mine)
        else
            if (threaded(st%nnode)) then
                !$omp parallel
                call drift(st)
                !$omp end parallel
            else
                call drift(st)
            end if
            call track_rotations(hist, st)
        end if
        if (ct%n > 0) call contact_drift(ct, st%v, st%dt, dom%own_contact)
        st%time = st%time + real(st%dt, dp)
        st%cycle = st%cycle + 1
        st%dt_old = st%dt
        st%dt_avg_prev = dt_avg
        call tm%stop(ph_integrate)
    end subroutine advance_phase

    !> x += dt v on the nodes of the runs lo(k) .. hi(k).
    subroutine drift_owned(st, lo, hi)
        type(state_t), intent(inout) :: st
        integer, intent(in) :: lo(:), hi(:)
        integer :: k, nd
        !$omp do schedule(static)
        do k = 1, size(lo)
            do nd = lo(k), hi(k)
                st%x(:, nd) = st%x(:, nd) + st%dt*st%v(:, nd)
            end do
        end do
        !$omp end do
    end subroutine drift_owned

    !> x += dt v.
    subroutine drift(st)
        type(state_t), intent(inout) :: st
        integer :: nd
        !$omp do schedule(static)
        do nd = 1, st%nnode
            st%x(:, nd) = st%x(:, nd) + st%dt*st%v(:, nd)
        end do
        !$omp end do
    end subroutine drift

end module xd_solver_phases
