!> The time loop's phases taken alone (issue 32, deliverable 5), on states
!> small enough to know the answer: the central-difference velocity update
!> (a free node, a massless node, a fixed direction, the angular
!> velocities), the advance to the next cycle, and the step's choice (the
!> growth limit, DTINIT at the first cycle, the failure on a step that is
!> not a positive number). The values are powers of two, so the expected
!> results are exact.
program test_phases
    use xd_kinds, only: wp, dp
    use xd_testing, only: check, test_summary
    use xd_solver_state, only: state_t
    use xd_core_dofs, only: all_free
    use xd_solver_phases, only: velocity_phase, advance_phase, step_phase
    use xd_solver_step_control, only: by_element, by_growth, by_other, dt_growth
    use xd_solver_mass_scaling, only: mass_scaling_t
    use xd_contact_tied, only: ties_t
    use xd_contact_contact, only: contacts_t
    use xd_output_histories, only: histories_t
    use xd_core_timers, only: timers_t
    use xd_model, only: model_t
    use xd_elements_solid_groups, only: solids_t
    use xd_elements_shell_bt, only: shells_t
    use xd_elements_beam_bs, only: beams_t
    use xd_solver_domain, only: domain_t
    use xd_output_d3hsp, only: log_t
    implicit none

    call velocities()
    call advance()
    call step_choice()
    call test_summary()

contains

    !> Three nodes: a free one of mass 2 under (4, -2, 6) N; a massless one
    !> under a force (no update: it has no inertia); one with y fixed.
    !> dt_avg 0.5: dv = a dt_avg.
    subroutine velocities()
        type(state_t) :: st
        type(ties_t) :: td
        type(domain_t) :: dom   !< one rank: every node integrated here
        real(wp) :: vminus(3, 3)
        real(wp), allocatable :: vrminus(:, :)
        call small_state(st)
        allocate (vrminus(3, 3))
        vminus = -1
        call velocity_phase(dom, st, td, 0.5_dp, .true., vminus, vrminus)
        call check(all(st%v(:, 1) == [1.25_wp, -0.25_wp, 1.75_wp]), 'phases: v(n+1/2) = v(n-1/2) + dt_avg f / m')
        call check(all(st%a(:, 1) == [2.0_wp, -1.0_wp, 3.0_wp]), 'phases: a = f / m')
        call check(all(st%v(:, 2) == [0.25_wp, 0.25_wp, 0.25_wp]), 'phases: a massless node keeps its velocity')
        call check(all(st%v(:, 3) == [0.75_wp, 0.25_wp, 0.75_wp]), 'phases: a fixed direction keeps its velocity')
        call check(all(vminus == 0.25_wp) .and. all(vrminus == 0.125_wp), 'phases: v(n-1/2) kept for the energies')
        call check(all(st%vr(:, 1) == [4.125_wp, 0.125_wp, 0.125_wp]), &
                   'phases: angular velocity from the moment over the rotary inertia')
        call check(all(st%vr(:, 2:3) == 0.125_wp), 'phases: no rotary inertia, no angular update')
    end subroutine velocities

    !> x(n+1) = x(n) + dt v(n+1/2); the clock and the steps move on.
    subroutine advance()
        type(state_t) :: st
        type(contacts_t) :: ct
        type(histories_t) :: hist
        type(timers_t) :: tm
        type(domain_t) :: dom   !< one rank: every node integrated here
        call small_state(st)
        st%dt = 0.25_wp
        st%time = 1
        st%cycle = 7
        call advance_phase(dom, st, ct, hist, tm, 0.375_dp)
        call check(all(st%x(:, 1) == [1.0_wp + 0.0625_wp, 0.0625_wp, 0.0625_wp]), 'phases: x(n+1) = x(n) + dt v')
        call check(st%time == 1.25_dp .and. st%cycle == 8, 'phases: the clock advances by the step')
        call check(st%dt_old == 0.25_wp .and. st%dt_avg_prev == 0.375_dp, 'phases: the step taken and its average kept')
    end subroutine advance

    !> The step from the elements' stable step dtc: TSSFAC 0.5 times it,
    !> held to dt_growth times the last one; DTINIT at cycle 0; a zero step
    !> (no element, no DTINIT) stops the run naming it.
    subroutine step_choice()
        type(model_t) :: model
        type(mass_scaling_t) :: ms
        type(solids_t) :: solids
        type(shells_t) :: sh
        type(beams_t) :: bm
        type(contacts_t) :: ct
        type(log_t) :: lg
        type(state_t) :: st
        real(wp) :: dtc, dt_ref
        integer :: set_by
        character(len=:), allocatable :: failure
        model%ctl%tssfac = 0.5_wp
        sh%n = 1
        ! growing: held to dt_growth x dt_old
        st%cycle = 5
        st%dt_old = 0.25_wp
        st%dt_first = 0.25_wp
        dtc = 1
        dt_ref = 0.25_wp
        call step_phase(model, ms, solids, sh, bm, ct, lg, 0, 0, dtc, st, dt_ref, set_by, failure)
        call check(len(failure) == 0 .and. st%dt == dt_growth*0.25_wp .and. set_by == by_growth, &
                   'phases: the step grows by dt_growth a cycle at most')
        ! falling: at once, set by the element
        dtc = 0.25_wp
        call step_phase(model, ms, solids, sh, bm, ct, lg, 0, 0, dtc, st, dt_ref, set_by, failure)
        call check(len(failure) == 0 .and. st%dt == 0.125_wp .and. set_by == by_element, &
                   'phases: the step falls at once to TSSFAC x the elements''')
        ! the first cycle: DTINIT if shorter
        st%cycle = 0
        model%ctl%dtinit = 0.0625_wp
        dtc = 0.25_wp
        call step_phase(model, ms, solids, sh, bm, ct, lg, 0, 0, dtc, st, dt_ref, set_by, failure)
        call check(st%dt == 0.0625_wp .and. st%dt_first == 0.0625_wp .and. set_by == by_other, &
                   'phases: DTINIT sets the first step where shorter')
        ! no element and no DTINIT: no step
        sh%n = 0
        model%ctl%dtinit = 0
        call step_phase(model, ms, solids, sh, bm, ct, lg, 0, 0, dtc, st, dt_ref, set_by, failure)
        call check(index(failure, 'is not a finite positive number') > 0, &
                   'phases: a step that is not a positive number is a failure', failure)
    end subroutine step_choice

    !> Three nodes at x = (1, 0, 0), (0, 1, 0), (0, 0, 1), v = 0.25 and
    !> angular velocity 0.125 everywhere; node 1 of mass 2 under (4, -2, 6)
    !> and moment (4, 0, 0) with rotary inertia 0.5; node 2 massless; node 3
    !> of mass 4 with y fixed, under (4, 4, 4).
    subroutine small_state(st)
        type(state_t), intent(out) :: st
        st%nnode = 3
        allocate (st%x(3, 3), st%v(3, 3), st%a(3, 3), st%f(3, 3), st%mass(3), st%dofs(3))
        allocate (st%vr(3, 3), st%mom(3, 3), st%irot(3))
        st%rot = .true.
        st%x = 0
        st%x(1, 1) = 1
        st%x(2, 2) = 1
        st%x(3, 3) = 1
        st%v = 0.25_wp
        st%vr = 0.125_wp
        st%a = 0
        st%f(:, 1) = [4.0_wp, -2.0_wp, 6.0_wp]
        st%f(:, 2) = [8.0_wp, 8.0_wp, 8.0_wp]
        st%f(:, 3) = [4.0_wp, 4.0_wp, 4.0_wp]
        st%mass = [2.0_wp, 0.0_wp, 4.0_wp]
        ! (every direction free but node 3's y: its dofs code's bit 1)
        st%dofs = all_free
        st%dofs(3) = ibclr(st%dofs(3), 1)
        st%mom = 0
        st%mom(1, 1) = 4
        st%irot = [0.5_wp, 0.0_wp, 0.0_wp]
    end subroutine small_state

end program test_phases
