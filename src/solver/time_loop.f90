!> The explicit time loop: central differences with a variable step,
!> element forces, deterministic assembly, constraints, energies, output,
!> and the checks that stop a run gone bad (exit 2) with a diagnostic.
module xd_solver_time_loop
    use, intrinsic :: iso_fortran_env, only: output_unit
    use xd_kinds, only: wp, dp
    use xd_core_strings, only: itoa, rtoa, ftoa
    use xd_core_errors, only: exit_normal, exit_run, exit_signal
    use xd_core_timers, only: timers_t, ph_elements, ph_assembly, ph_integrate, ph_output, ph_contact, ph_rigid, &
                                  ph_search, ph_local, ph_enforce, ph_comm, ph_ghost, ph_wait
    use xd_model, only: model_t
    use xd_elements_solid_groups, only: solids_t, solid_forces
    use xd_solver_state, only: state_t
    use xd_solver_assembly, only: assembly_t, assemble
    use xd_solver_energies, only: energies_t, compute_energies
    use xd_output_histories, only: histories_t, histories_due, write_histories, history_failure, track_rotations, &
                                   flush_histories
    use xd_output_states, only: states_t, states_due, write_state, states_marks, states_failure
    use xd_output_histories, only: history_marks
    use xd_solver_restart, only: dump_meta_t, write_dump
    use xd_core_signals, only: stop_signal, status_signal, hold_for_signal
    use xd_solver_sense_switch, only: read_sense_switch, switch_name, sw_none, sw_stop, sw_status, sw_dump, sw_state, &
                                      sw_flush, sw_unknown
    use xd_output_d3hsp, only: log_t, log_line
    use xd_solver_loads, only: body_acceleration, add_body_forces, body_power, pressures_t, apply_pressures, &
                               pressure_power
    use xd_contact_rigidwall, only: walls_t, apply_walls
    use xd_contact_enforcement, only: body_response_t
    use xd_elements_erosion, only: shell_failures, erode_shells, dead_model_shells
    use xd_elements_beam_bs, only: beams_t, beam_forces
    use xd_contact_tied, only: ties_t, tie_forces, tie_accelerations, tie_velocities, tie_kinetic, tie_break
    use xd_contact_contact, only: contacts_t, contact_search, contact_drift, contact_local_search, contact_enforce, &
                                  contact_work_end, contact_energy, contact_resultants, gather_contact_state, &
                                  contact_thickness, contact_erode, &
                                  scatter_contact_state, contact_events
    use xd_solver_prescribed, only: prescribed_nodes_t, apply_prescribed
    use xd_rigid_bodies, only: rigid_t, rigid_step, rigid_response
    use xd_elements_shell_bt, only: shells_t, shell_forces
    use xd_solver_domain, only: domain_t, share_slots, share_nodes, gather_energy_state, gather_element_state
    use xd_core_comm, only: comm_gather_small, comm_max, comm_sum_int
    use xd_solver_step_control, only: step_stats_t, step_stats_init, step_stats_count, step_stats_report, by_element, &
                                      by_contact, by_floor, by_other, by_growth, dt_growth, &
                                      hourglass_bound_report
    use xd_solver_mass_scaling, only: mass_scaling_t, mass_scaling_begin, mass_scaling_targets, mass_scaling_step, &
                                      mass_scaling_summary
    implicit none
    private
    public :: run_options_t, run_result_t, run_time_loop

    type :: run_options_t
        real(dp) :: endtim = 0.0_dp          !< termination time (deck, or endtim= on the command line)
        logical :: progress = .true.
        real(dp) :: progress_every = 5.0_dp  !< wall seconds between progress lines
        integer :: energy_check_every = 100  !< cycles between energy checks
        integer :: dump_every = -1           !< cycles between restart dumps (0: at the end only; -1: none)
        real(dp) :: wallclock = 0.0_dp       !< wall seconds allowed (0: no limit): stop with a dump before
        character(len=:), allocatable :: dump_path
        !> the sense-switch file in the output directory (d3kil in the
        !> working directory is read too), looked for every `switch_every` cycles
        character(len=:), allocatable :: kill_path
        integer :: switch_every = 50
        type(dump_meta_t) :: meta            !< what a dump says about the run
        integer, allocatable :: hold_cycles(:) !< tests only (XDYNA_HOLD_AT): wait at these cycles for a signal
    end type run_options_t

    !> Why a write fails, as the messages say it.
    character(len=*), parameter :: write_failed = ' (the disk is full, a quota is reached, or the directory is gone)'

    type :: run_result_t
        integer :: status = exit_normal
        character(len=:), allocatable :: message
        integer :: ncycle = 0
        real(dp) :: loop_wall = 0.0_dp
        !> the run's energy scale: the largest |initial energy + external work|
        !> an energy check saw (the contact report's reference)
        real(dp) :: e_scale = 0.0_dp
    end type run_result_t

contains

    subroutine run_time_loop(model, dom, st, solids, asm, sh, asm_sh, bm, walls, ct, pn, rg, pl, td, hist, states, lg, tm, &
                             opts, res)
        type(model_t), intent(in) :: model
        type(domain_t), intent(in) :: dom
        type(state_t), intent(inout) :: st
        type(solids_t), intent(inout) :: solids
        type(assembly_t), intent(in) :: asm
        type(shells_t), intent(inout) :: sh
        type(assembly_t), intent(in) :: asm_sh
        type(beams_t), intent(inout) :: bm
        type(walls_t), intent(inout) :: walls
        type(contacts_t), intent(inout) :: ct
        type(prescribed_nodes_t), intent(in) :: pn
        type(rigid_t), intent(inout) :: rg
        type(pressures_t), intent(inout) :: pl
        type(ties_t), intent(inout) :: td       !< tied contacts
        type(histories_t), intent(inout) :: hist
        type(states_t), intent(inout) :: states
        type(log_t), intent(in) :: lg
        type(timers_t), intent(inout) :: tm
        type(run_options_t), intent(in) :: opts
        type(run_result_t), intent(out) :: res
        type(energies_t) :: en
        type(mass_scaling_t) :: ms
        type(step_stats_t) :: ss
        integer :: set_by
        character(len=:), allocatable :: ms_stop
        real(wp), allocatable :: vn(:, :), vminus(:, :), vrminus(:, :)
        real(dp), allocatable :: ke_fix(:)     !< tied contacts' kinetic energy by part
        type(body_response_t) :: br            !< Lagrangian contact: how the rigid bodies answer an impulse
        logical, allocatable :: no_body(:)   !< no node is a rigid body's (models without rigid bodies)
        real(wp) :: dtc, g_new(3)
        real(dp) :: dt_avg, wpm
        real(dp) :: t_last_progress, ratio_limit, t0_wall, t_dump, t_gather
        real(wp) :: dt_ref
        logical :: done, energy_now, dumped_end, near_limit, status_now, state_asked, switch_gone
        integer :: nd, cycle0, stop_sig, switch
        character(len=:), allocatable :: switch_text, tie_events
        integer :: beam_crit                   !< the beam that set the step (0: none)
        real(wp) :: dtc_pass                   !< the beams' step, combined after the element pass
        !> one rank: the shells add their forces to the nodes each thread's
        !> part holds alone directly, in the order the assembly sums their
        !> slots (the same sums, without writing and reading the slots); the
        !> nodes the parts share are summed from the slots after the pass
        logical :: shells_direct
        real(wp) :: ri, on                    !< the rotations' update, per node

        allocate (vn(3, st%nnode), vminus(3, st%nnode), no_body(st%nnode), ke_fix(model%npart))
        shells_direct = sh%n > 0 .and. .not. dom%on
        ke_fix = 0
        no_body = .false.
        if (st%rot) allocate (vrminus(3, st%nnode))
        ratio_limit = 1.5_dp
        beam_crit = 0
        state_asked = .false.
        switch_gone = .true.
        if (model%ctl%endeng > 0.0_wp) ratio_limit = 1.0_dp + model%ctl%endeng/100.0_dp
        t0_wall = tm%elapsed()
        cycle0 = st%cycle
        call mass_scaling_begin(ms, model%ctl, lg)
        call step_stats_init(ss, solids%n, sh%n)
        dumped_end = .false.
        t_dump = 0
        t_last_progress = t0_wall

        ! cycle n: forces at t(n) on x(n) with v(n-1/2); v(n+1/2) with the
        ! constraints; output at t(n); then x(n+1)
        do
            ! the end-of-run restart dump: the state at the start of the last
            ! cycle (a restart with a later end time goes on from there as
            ! the longer run would have, writing the outputs of t(n) again)
            if (opts%dump_every >= 0 .and. .not. dumped_end) then
                if (st%time >= opts%endtim*(1.0_dp - 1.0e-12_dp) .or. &
                    (model%ctl%endcyc > 0 .and. st%cycle >= model%ctl%endcyc)) then
                    call dump()
                    dumped_end = .true.
                    if (res%status /= exit_normal) exit
                end if
            end if
            if (ct%n > 0) then
                ! step 2 where due, on x(n); steps 3-4 will follow here
                call tm%start(ph_search)
                call contact_search(ct, st%x, model%node_id, st%cycle, st%time)
                call tm%stop(ph_search)
            end if
            if (ms%on) call mass_scaling_targets(ms, st%cycle, solids, sh)
            call element_pass(st%dt_old, st%dt_avg_prev, dtc)
            if (res%status /= exit_normal) exit
            if (bm%n > 0) then
                ! a beam sets the step where it is the shortest
                if (dtc_pass < dtc) then
                    dtc = dtc_pass
                    st%crit_elem = 0
                    beam_crit = bm%crit
                else
                    beam_crit = 0
                end if
            end if
            if (sh%n > 0) then
                ! failure: shells that fail erode (their forces already in
                ! this cycle's; from the next on they are gone)
                if (sh%erodible) call erosion()
            end if
            if (ms%on) then
                ! the masses the element pass asked for, before anything
                ! divides by them
                call tm%start(ph_elements)
                call mass_scaling_step(ms, model, dom, solids, sh, st, rg, lg, ms_stop)
                call tm%stop(ph_elements)
                if (allocated(ms_stop)) then
                    call fail(ms_stop)
                    exit
                end if
            end if
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
            if (solids%ngroup == 0 .and. sh%n > 0 .and. bm%n == 0) then
                if (sh%ndead == sh%n .and. st%cycle > cycle0) then
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
                        'SFM too high?)')
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
            if (.not. (st%dt > 0.0_wp .and. st%dt <= huge(1.0_wp))) then
                call fail('time step '//rtoa(real(st%dt, dp))//' is not a finite positive number; controlling '// &
                          controlling())
                exit
            else if (st%dt > 100.0_wp*dt_ref) then
                call fail('time step '//rtoa(real(st%dt, dp))//' grew beyond 100 times the run''s first ('// &
                          rtoa(real(dt_ref, dp))//'): the state has gone bad; controlling '//controlling())
                exit
            end if
            if (st%cycle == 0) then
                if (model%ctl%dtinit > 0.0_wp) then
                    if (model%ctl%dtinit < st%dt) set_by = by_other
                    st%dt = min(st%dt, model%ctl%dtinit)
                end if
                st%dt_first = st%dt
            else if (model%ctl%dtmin > 0.0_wp .and. st%dt < model%ctl%dtmin*st%dt_first) then
                call fail('time step '//rtoa(real(st%dt, dp))//' fell below DTMIN x first step; '// &
                          'controlling '//controlling())
                exit
            end if

            call step_stats_count(ss, set_by, st%crit_elem)

            call tm%start(ph_integrate)
            dt_avg = 0.5_dp*(real(st%dt_old, dp) + st%dt)
            if (model%nbody > 0) then
                ! body forces f(n) = m g(n) do f(n) . (v(n-1/2) + v(n+1/2))/2 dt_avg(n)
                g_new = body_acceleration(model, real(st%time, wp))
                st%ext_work = st%ext_work + 0.5_dp*dt_avg*body_power(st, g_new)
                call add_body_forces(st, g_new)
            end if
            if (pl%n > 0) then
                ! pressure forces: the same work rule as every force at t(n)
                call apply_pressures(model, pl, st)
                st%ext_work = st%ext_work + 0.5_dp*dt_avg*pressure_power(pl, st)
            end if
            if (ct%n > 0) then
                ! steps 3-4 on x(n): contact forces join f(n)
                call tm%stop(ph_integrate)
                call tm%start(ph_local)
                ! THKCHG: the shells' thickness of this cycle's element pass
                if (ct%thkchg .and. sh%n > 0) call contact_thickness(ct, sh%conn, sh%h, sh%mine)
                call contact_local_search(ct, st%x, st%v, st%time, st%dt)
                call tm%stop(ph_local)
                call tm%start(ph_enforce)
                t_gather = ct%wall_gather
                if (ct%lagrange .and. rg%n > 0) then
                    ! a master on a rigid body answers as the body
                    call rigid_response(rg, st%nnode, br)
                    call contact_enforce(ct, st%f, st%dt, real(dt_avg, wp), st%mass, st%free, st%time, br)
                else
                    call contact_enforce(ct, st%f, st%dt, real(dt_avg, wp), st%mass, st%free, st%time)
                end if
                call tm%stop(ph_enforce)
                if (dom%on) call tm%move(ph_enforce, ph_ghost, ct%wall_gather - t_gather)
                if (any(ct%ifc(:)%nev > 0) .or. any(ct%ifc(:)%ed%nev > 0)) call log_line(lg, contact_events(ct, model%node_id))
                call tm%start(ph_integrate)
            end if
            ! tied contacts: the slaves' forces to their segments, and the
            ! segments' nodes accelerated with the slave masses they carry
            if (td%n > 0) call tie_forces(td, st%time, st%x, st%f, st%mom)
            call accelerations()
            if (td%n > 0) then
                call tie_accelerations(td, st%time, st%f, st%mass, st%free, st%a, st%mom, st%irot)
            end if
            done = st%time >= opts%endtim*(1.0_dp - 1.0e-12_dp)
            if (model%ctl%endcyc > 0) done = done .or. st%cycle >= model%ctl%endcyc
            ! energies where histories or states are due (the d3plot's global
            ! variables carry them), or every energy_check_every cycles
            energy_now = histories_due(hist, st%time) .or. done .or. st%cycle == 0 .or. &
                         mod(st%cycle, opts%energy_check_every) == 0 .or. states_due(states, st%time) .or. &
                         state_asked
            if (energy_now) vminus = st%v
            ! central differences: v(n+1/2) = v(n-1/2) + a(n) (dt(n-1/2) + dt(n+1/2))/2
            !$omp parallel do schedule(static)
            do nd = 1, st%nnode
                st%v(:, nd) = st%v(:, nd) + real(dt_avg, wp)*st%a(:, nd)
            end do
            !$omp end parallel do
            if (st%rot) then
                if (energy_now) vrminus = st%vr
                ! (a node without rotary inertia divides by 1 and adds 0 times
                ! that: no select, so that the loop vectorises)
                !$omp parallel do schedule(static) private(ri, on)
                do nd = 1, st%nnode
                    on = merge(1.0_wp, 0.0_wp, st%irot(nd) > 0.0_wp)
                    ri = st%irot(nd) + (1.0_wp - on)
                    st%vr(1, nd) = st%vr(1, nd) + real(dt_avg, wp)*st%mom(1, nd)/ri*st%free_r(1, nd)*on
                    st%vr(2, nd) = st%vr(2, nd) + real(dt_avg, wp)*st%mom(2, nd)/ri*st%free_r(2, nd)*on
                    st%vr(3, nd) = st%vr(3, nd) + real(dt_avg, wp)*st%mom(3, nd)/ri*st%free_r(3, nd)*on
                end do
                !$omp end parallel do
            end if
            call tm%stop(ph_integrate)
            if (walls%n > 0) then
                call tm%start(ph_contact)
                if (rg%n > 0) then
                    call apply_walls(model, walls, st, st%dt, real(dt_avg, wp), rg%member)
                else
                    call apply_walls(model, walls, st, st%dt, real(dt_avg, wp), no_body)
                end if
                call tm%stop(ph_contact)
            end if
            if (pn%n > 0) then
                if (td%n > 0) then
                    call apply_prescribed(model, pn, st, st%dt, real(dt_avg, wp), wpm, td%mnodal)
                else
                    call apply_prescribed(model, pn, st, st%dt, real(dt_avg, wp), wpm)
                end if
                st%ext_work = st%ext_work + wpm
            end if
            if (rg%n > 0) then
                call tm%start(ph_rigid)
                call rigid_step(rg, model, st, st%dt, real(dt_avg, wp), wpm, walls)
                st%ext_work = st%ext_work + wpm
                call tm%stop(ph_rigid)
            end if
            ! tied slaves move with their segments (after every other update)
            if (td%n > 0) then
                call tie_velocities(td, st%time, st%dt, st%x, st%v, st%vr)
                ! tiebreak: each held slave's interface force from its
                ! velocity change this step
                call tie_break(td, st%time, st%mass, real(dt_avg, wp), st%v, st%x, tie_events, model%node_id)
                if (len(tie_events) > 0) call log_line(lg, tie_events)
            end if
            ! second half of the load work, with the final v(n+1/2)
            if (model%nbody > 0) st%ext_work = st%ext_work + 0.5_dp*dt_avg*body_power(st, g_new)
            if (pl%n > 0) st%ext_work = st%ext_work + 0.5_dp*dt_avg*pressure_power(pl, st)

            if (energy_now) then
                call tm%start(ph_output)
                call gather_energy_state(dom, solids, sh)
                if (st%cycle == 0) then
                    ! at t = 0 the kinetic energy is that of the initial velocities
                    ! (the start v(1/2) = v(0) + a(0) dt/2 adds an O(dt^2) offset
                    ! when a(0) /= 0)
                    ! (vrminus, like vminus, was taken before the update)
                    vn = vminus
                    if (td%n > 0) call tie_kinetic(td, st%mass, st%irot, vminus, vminus, vrminus, vrminus, ke_fix)
                    call compute_energies(model, st, solids, sh, walls, rg, vminus, vminus, vrminus, vrminus, 0.0_dp, en, &
                                          contact_energy(ct, 0.0_dp), ke_fix, bm)
                    st%e_initial = en%total
                    ! mass scaled at cycle 0 is in the initial energy
                    st%ms_work = 0
                    en%ratio = 1.0_dp
                    ! no work is done by t = 0 (st%ext_work already holds the
                    ! first half step's, the leapfrog's share of cycle 0, which
                    ! the energies of t(1) count)
                    en%ext = 0
                else
                    vn = 0.5_wp*(vminus + st%v)
                    if (td%n > 0) call tie_kinetic(td, st%mass, st%irot, vminus, st%v, vrminus, st%vr, ke_fix)
                    call compute_energies(model, st, solids, sh, walls, rg, vminus, st%v, vrminus, st%vr, dt_avg, en, &
                                          contact_energy(ct, dt_avg) + td%ework, ke_fix, bm)
                end if
                call tm%stop(ph_output)
                call check_energy()
                if (res%status /= exit_normal) exit
                if (histories_due(hist, st%time) .or. states_due(states, st%time) .or. done .or. st%cycle == 0 &
                    .or. state_asked) call output(force=done .or. st%cycle == 0)
                if (res%status /= exit_normal) exit
            end if
            ! the contact forces' work with v(n+1/2), after the energies at t(n)
            if (ct%n > 0) call contact_work_end(ct, st%v, dt_avg)
            if (opts%progress .and. (tm%elapsed() - t_last_progress >= opts%progress_every .or. done &
                                     .or. st%cycle == 0)) then
                t_last_progress = tm%elapsed()
                call progress()
            end if
            if (done) exit

            call tm%start(ph_integrate)
            !$omp parallel do schedule(static)
            do nd = 1, st%nnode
                st%x(:, nd) = st%x(:, nd) + st%dt*st%v(:, nd)
            end do
            !$omp end parallel do
            if (ct%n > 0) call contact_drift(ct, st%v, st%dt)
            call track_rotations(hist, st)
            st%time = st%time + real(st%dt, dp)
            st%cycle = st%cycle + 1
            st%dt_old = st%dt
            st%dt_avg_prev = dt_avg
            call tm%stop(ph_integrate)
            ! batch: a status line on SIGUSR2; a dump every N cycles; on SIGTERM
            ! or SIGUSR1, or near the wall-clock limit, a dump and exit 3
            if (allocated(opts%hold_cycles)) then
                if (any(opts%hold_cycles == st%cycle)) call flush_histories(hist)
                if (any(opts%hold_cycles == st%cycle)) call hold_for_signal(' held at cycle '//itoa(st%cycle)// &
                                                                   ' (XDYNA_HOLD_AT): waiting for a signal', 120.0, opts%progress)
            end if
            call stop_flags(stop_sig, near_limit, status_now, switch)
            if (status_now) call progress()
            if (switch /= sw_none) then
                call sense_switch(switch)
                if (res%status /= exit_normal) exit
            end if
            if (opts%dump_every > 0) then
                if (mod(st%cycle, opts%dump_every) == 0) call dump()
                if (res%status /= exit_normal) exit
            end if
            if (stop_sig /= 0) then
                call dump()
                if (res%status == exit_normal) &
                    call stop_run('stopped by signal '//itoa(stop_sig)//'; restart dump '//opts%dump_path)
                exit
            end if
            if (near_limit) then
                call dump()
                if (res%status == exit_normal) call stop_run('wall-clock limit of '//ftoa(opts%wallclock)// &
                                                             ' s near; restart dump '//opts%dump_path)
                exit
            end if
        end do

        res%ncycle = st%cycle
        res%loop_wall = tm%elapsed() - t0_wall
        ! the end reached in one step at most past ENDTIM
        if (res%status == exit_normal .and. opts%endtim < huge(1.0_dp)) then
            if (.not. (st%time <= opts%endtim + 1.000001_dp*real(st%dt_old, dp))) &
                call fail('time '//rtoa(st%time)//' is past the end time '//rtoa(opts%endtim)//' by more than a step')
        end if
        call step_stats_report(ss, model, solids, sh, lg)
        if (allocated(sh%ncap)) then
            if (dom%on) call comm_sum_int(sh%ncap, sh%n)
            call hourglass_bound_report(ss, model, sh, lg)
        end if
        call mass_scaling_summary(ms, model, solids, sh, st, lg)
        if (res%status == exit_normal) then
            call log_line(lg, '')
            call log_line(lg, ' N o r m a l    t e r m i n a t i o n   at time '//rtoa(st%time)// &
                          ', cycle '//itoa(st%cycle))
        end if

    contains

        !> Element forces and the stable step; stops on a bad element. Under
        !> MPI each rank computes its own elements; the step, the first bad
        !> element and the halo slots are shared, then the nodal forces.
        subroutine element_pass(dt, dt_avg_prev, dtcrit)
            real(wp), intent(in) :: dt
            real(dp), intent(in) :: dt_avg_prev
            real(wp), intent(out) :: dtcrit
            integer :: g, bad_kind, bad
            call tm%start(ph_elements)
            call solid_forces(solids, st%x, st%v, dt, dt_avg_prev)
            call tm%stop(ph_elements)
            ! the first bad element (1: solid volume, 2: solid NaN, 3: shell)
            ! and the smallest step, in element order (solids first)
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
                    call assemble(asm, solids%fslot, st%f)
                    call zero_nodes(st%mom)
                else
                    call zero_nodes(st%f, st%mom)
                end if
                call tm%stop(ph_assembly)
                call tm%start(ph_elements)
                call shell_forces(sh, st%x, st%v, st%vr, dt, dt_avg_prev, st%f, st%mom)
                call tm%stop(ph_elements)
                if (size(sh%shared) > 0) then
                    call tm%start(ph_assembly)
                    call assemble(asm_sh, sh%fslot, st%f, add=.true., nodes=sh%shared, mslot=sh%mslot, m=st%mom)
                    call tm%stop(ph_assembly)
                end if
            else if (sh%n > 0) then
                call tm%start(ph_elements)
                call shell_forces(sh, st%x, st%v, st%vr, dt, dt_avg_prev)
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
            if (dom%on) then
                ! the cycle's first collective: the time here is mostly the
                ! wait for the slowest rank's elements
                call tm%start(ph_wait)
                call reduce_step(dtcrit, bad_kind, bad)
                call tm%stop(ph_wait)
            end if
            select case (bad_kind)
            case (1)
                if (solids%vol(bad) /= solids%vol(bad) .or. any(st%x(:, solids%conn(:, bad)) /= &
                                                              st%x(:, solids%conn(:, bad)))) then
                    call fail('NaN in the coordinates of solid '//itoa(solids%eid(bad))//' of part '// &
                              itoa(model%part(solids%part(bad))%id))
                else
                    call fail('negative volume in solid '//itoa(solids%eid(bad))//' of part '// &
                              itoa(model%part(solids%part(bad))%id))
                end if
                return
            case (2)
                call fail('NaN in solid '//itoa(solids%eid(bad))//' of part '// &
                          itoa(model%part(solids%part(bad))%id)//' (its nodes'' velocities)')
                return
            case (3)
                call fail('shell '//itoa(sh%eid(bad))//' of part '//itoa(model%part(sh%part(bad))%id)// &
                          ' has collapsed (zero or negative area)')
                return
            end select
            if (dom%on) then
                ! the halo: slots of other ranks' elements on this rank's nodes
                call tm%start(ph_comm)
                call share_slots(dom, solids, sh)
                call tm%stop(ph_comm)
                call tm%start(ph_assembly)
                if (solids%n > 0 .or. sh%n == 0) call assemble(asm, solids%fslot, st%f, nodes=dom%nodes)
                if (sh%n > 0) call assemble(asm_sh, sh%fslot, st%f, add=solids%n > 0, nodes=dom%nodes, &
                                            mslot=sh%mslot, m=st%mom)
                call tm%stop(ph_assembly)
                call tm%start(ph_comm)
                if (sh%n > 0) then
                    call share_nodes(dom, st%f, st%mom)
                else
                    call share_nodes(dom, st%f)
                end if
                call tm%stop(ph_comm)
                call beams()
                return
            end if
            if (.not. shells_direct) then
                call tm%start(ph_assembly)
                if (solids%n > 0 .or. sh%n == 0) call assemble(asm, solids%fslot, st%f)
                if (sh%n > 0) call assemble(asm_sh, sh%fslot, st%f, add=solids%n > 0, mslot=sh%mslot, m=st%mom)
                call tm%stop(ph_assembly)
            end if
            call beams()
        end subroutine element_pass

        !> Zeros in the nodes' a (and b), threaded.
        subroutine zero_nodes(a, b)
            real(wp), intent(inout) :: a(:, :)
            real(wp), intent(inout), optional :: b(:, :)
            integer :: i
            !$omp parallel do schedule(static)
            do i = 1, size(a, 2)
                a(:, i) = 0
                if (present(b)) b(:, i) = 0
            end do
            !$omp end parallel do
        end subroutine zero_nodes

        !> The beams, on every rank alike, added to the shared forces; their
        !> step joins the elements'.
        subroutine beams()
            integer :: k
            character(len=250) :: buf
            dtc_pass = huge(1.0_wp)
            if (bm%n == 0) return
            call tm%start(ph_elements)
            call beam_forces(bm, st%x, st%v, st%vr, st%dt_old, st%time, st%f, st%mom, sh%n == 0)
            call tm%stop(ph_elements)
            dtc_pass = bm%dtmin
            do k = 1, size(bm%newly)
                write (buf, '(a,i0,a,i0,a,es12.5,a,6es11.3,a)') ' spot weld beam ', bm%eid(bm%newly(k)), ' of part ', &
                    model%part(bm%part(bm%newly(k)))%id, ' failed at time ', st%time, ' (N, T, M at the ends: ', &
                    bm%res(:, bm%newly(k)), ')'
                call log_line(lg, trim(buf))
            end do
        end subroutine beams

        !> MPI: the smallest step of all ranks (ties: solids before shells, then
        !> the lower element, as the serial scan finds it) and the first bad
        !> element (solids before shells, then the lower element).
        subroutine reduce_step(dtcrit, bad_kind, bad)
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

        !> 'solid 12 of part 3' or 'shell 7 of part 2': the element of the step.
        function controlling() result(txt)
            character(len=:), allocatable :: txt
            txt = 'element unknown'
            if (st%crit_elem > 0) txt = 'solid '//itoa(solids%eid(st%crit_elem))//' of part '// &
                                        itoa(model%part(solids%part(st%crit_elem))%id)
            if (st%crit_elem < 0) txt = 'shell '//itoa(sh%eid(-st%crit_elem))//' of part '// &
                                        itoa(model%part(sh%part(-st%crit_elem))%id)
            if (st%crit_elem == 0 .and. beam_crit > 0) txt = 'beam '//itoa(bm%eid(beam_crit))//' of part '// &
                                                             itoa(model%part(bm%part(beam_crit))%id)
        end function controlling
        !> The signals and the wall-clock limit, the same on every rank (MPI:
        !> the largest over the ranks, so all stop at the same cycle). The
        !> wall-clock margin: 10 cycles, 5% of the allowance, twice the last
        !> dump's time, and 0.5 s for the dump, closing the files and the
        !> parallel shutdown.
        subroutine stop_flags(sig, limit, status, sw)
            integer, intent(out) :: sig
            logical, intent(out) :: limit, status
            integer, intent(out) :: sw       !< a sense switch of d3kil (rank 0 reads it; sw_none: none)
            real(dp) :: fl(4)
            limit = .false.
            sw = sw_none
            if (dom%rank == 0 .and. switch_gone .and. mod(st%cycle, opts%switch_every) == 0) then
                call read_sense_switch(opts%kill_path, 'd3kil', sw, switch_text, switch_gone)
                if (sw /= sw_none) call log_line(lg, ' sense switch "'//switch_text//'" read from d3kil at time '// &
                                                 rtoa(st%time)//', cycle '//itoa(st%cycle)//': '//switch_name(sw))
                if (.not. switch_gone) call log_line(lg, ' *** Warning: d3kil could not be deleted; sense '// &
                                                     'switches are no longer read')
                if (sw == sw_unknown) sw = sw_none
            end if
            if (opts%wallclock > 0.0_dp) then
                limit = tm%elapsed() + max(10.0_dp*(tm%elapsed() - t0_wall)/max(st%cycle - cycle0, 1), &
                                           0.05_dp*opts%wallclock, 2.0_dp*t_dump) + 0.5_dp >= opts%wallclock
            end if
            fl = [real(stop_signal(), dp), merge(1.0_dp, 0.0_dp, limit), merge(1.0_dp, 0.0_dp, status_signal()), &
                  real(sw, dp)]
            if (dom%on) call comm_max(fl)
            sig = nint(fl(1))
            limit = fl(2) > 0
            status = fl(3) > 0
            sw = nint(fl(4))
        end subroutine stop_flags

        !> What a sense switch asks, at the end of this cycle (every rank).
        subroutine sense_switch(sw)
            integer, intent(in) :: sw
            select case (sw)
            case (sw_stop)
                call dump()
                if (res%status == exit_normal) &
                    call stop_run('stopped by sense switch sw1 (d3kil); restart dump '//opts%dump_path)
            case (sw_status)
                call progress()
            case (sw_dump)
                call dump()
            case (sw_state)
                ! the state at the next cycle's end, where its energies are computed
                if (states%on) then
                    state_asked = .true.
                else
                    call log_line(lg, ' *** Warning: sense switch sw4: this run writes no states')
                end if
            case (sw_flush)
                call flush_histories(hist)
            end select
        end subroutine sense_switch

        !> The shells that fail at this state erode on every rank: they leave
        !> the element loops and the contact's surfaces, each named in d3hsp.
        subroutine erosion()
            integer, allocatable :: newly(:)
            real(dp), allocatable :: flag(:)
            integer :: k
            character(len=200) :: buf
            call shell_failures(sh, model%mat, st%time, newly)
            if (dom%on) then
                if (.not. any_rank(size(newly) > 0)) return
                allocate (flag(sh%n))
                flag = 0
                flag(newly) = 1
                call comm_max(flag)
                newly = pack([(k, k=1, sh%n)], flag > 0.0_dp .and. .not. sh%dead)
            end if
            if (size(newly) == 0) return
            call erode_shells(sh, newly)
            do k = 1, size(newly)
                if (sh%ndead - size(newly) + k > 2000) exit
                write (buf, '(a,i0,a,i0,a,es12.5,a,es11.4)') ' shell ', sh%eid(newly(k)), ' of part ', &
                    model%part(sh%part(newly(k)))%id, ' eroded at time ', st%time, ', internal energy ', &
                    sh%eint(newly(k))
                call log_line(lg, trim(buf))
            end do
            if (ct%n > 0) call contact_erode(ct, dead_model_shells(sh, model%nshell))
        end subroutine erosion

        subroutine accelerations()
            integer :: i
            real(wp) :: on, mi
            ! (the quotients taken for every node, a massless one's over 1
            ! and then times 0, without a select: the loop vectorises; the
            ! same quotients)
            !$omp parallel do schedule(static) private(on, mi)
            do i = 1, st%nnode
                on = merge(1.0_wp, 0.0_wp, st%mass(i) > 0.0_wp)
                mi = st%mass(i) + (1.0_wp - on)
                st%a(1, i) = st%f(1, i)/mi*st%free(1, i)*on
                st%a(2, i) = st%f(2, i)/mi*st%free(2, i)*on
                st%a(3, i) = st%f(3, i)/mi*st%free(3, i)*on
            end do
            !$omp end parallel do
        end subroutine accelerations

        subroutine check_energy()
            integer :: i, k
            ! a rigid body turning a radian or more in one step: no motion the
            ! step resolves (the rotation of a step is the Cayley transform of
            ! omega dt, good for small angles); a prescribed spin of 1e30 rad/s
            ! ran to "normal termination" with nodes at 1e28 m/s
            do k = 1, rg%n
                if (.not. rg%b(k)%active) cycle
                if (norm2(rg%b(k)%omega)*real(st%dt_old, dp) >= 1.0_dp) then
                    call fail('impossible state: rigid body '//rigid_name(k)//' turns '// &
                              rtoa(norm2(rg%b(k)%omega)*real(st%dt_old, dp))//' rad in one step (angular '// &
                              'velocity '//rtoa(norm2(rg%b(k)%omega))//'); node '// &
                              node_where(rg%b(k)%node(1))//'; a prescribed rotation far beyond its curve''s intent?')
                    return
                end if
            end do
            res%e_scale = max(res%e_scale, abs(st%e_initial + en%ext))
            if (en%total /= en%total .or. abs(en%total) > huge(1.0_wp)) then
                do i = 1, st%nnode
                    if (any(st%v(:, i) /= st%v(:, i)) .or. any(abs(st%v(:, i)) > huge(1.0_wp))) exit
                end do
                if (i > st%nnode) i = 1
                call fail('energy is NaN or infinite; first bad node '//node_where(i))
            else if ((en%ratio < 0.0_dp .or. (en%ratio < 1.0_dp/ratio_limit .and. st%cycle - cycle0 >= 10)) &
                     .and. abs(st%e_initial + en%ext) > 0.0_dp) then
                ! energy lost beyond the margin, or a negative total against a
                ! positive input: no physical state, since walls, contact,
                ! hourglass and damping work are all in the total. The lower
                ! margin holds from the tenth cycle: before, a run loaded from
                ! rest has energies of a few steps' work, whose ratio the
                ! first-order start (v(1/2) = v(0) + a(0) dt/2) sets to
                ! anything (0.50 at cycle 2 of a velocity ramp, 0 at cycle 1
                ! of the contact patch test)
                i = maxloc(sum(real(vn, dp)**2, 1)*st%mass, 1)
                call fail('energy lost: total energy ratio '//ftoa(en%ratio)//' is below '// &
                          ftoa(1.0_dp/ratio_limit)//' (total '//ftoa(en%total)//' against initial energy plus '// &
                          'external work '//ftoa(st%e_initial + en%ext)//'); fastest node '//node_where(i))
            else if (en%ratio > ratio_limit) then
                i = maxloc(sum(real(vn, dp)**2, 1)*st%mass, 1)
                call fail('energy blow-up: total energy ratio '//ftoa(en%ratio)//' exceeds '// &
                          ftoa(ratio_limit)//'; fastest node '//node_where(i))
            else if (en%ke < -(ratio_limit - 1.0_dp)*abs(st%e_initial + en%ext)) then
                ! 1/2 m v(n-1/2).v(n+1/2) strongly negative: velocities turn
                ! round within a step, by more than the energy ratio's margin
                ! (slightly negative values are normal where nodes turn round).
                ! No physical state: a step beyond the stable limit, a contact
                ! spring too stiff for the step, or a prescribed motion that
                ! reverses within a step at a speed beyond reason. (This was
                ! let pass twice in a row for a stiff block bouncing off a
                ! wall; that block was running beyond its stable step.)
                i = maxloc(sum(real(vn, dp)**2, 1)*st%mass, 1)
                call fail('impossible state: kinetic energy 1/2 m v(n-1/2).v(n+1/2) is '//ftoa(en%ke)// &
                          ', below minus '//ftoa(ratio_limit - 1.0_dp)//' times the initial energy plus '// &
                          'external work ('//ftoa(st%e_initial + en%ext)//'): velocities reverse within a '// &
                          'step; fastest node '//node_where(i)//'; '//cause_hint())
            end if
        end subroutine check_energy

        !> Whether `flag` holds on any rank (the rank itself when not parallel).
        logical function any_rank(flag)
            logical, intent(in) :: flag
            real(dp) :: fl(1)
            fl = merge(1.0_dp, 0.0_dp, flag)
            if (dom%on) call comm_max(fl)
            any_rank = fl(1) > 0.0_dp
        end function any_rank

        !> A rigid body as the deck names it: its part, or its node set's body.
        function rigid_name(k) result(t)
            integer, intent(in) :: k
            character(len=:), allocatable :: t
            if (rg%b(k)%part > 0) then
                t = 'of part '//itoa(model%part(rg%b(k)%part)%id)
            else
                t = itoa(k)//' (a node set)'
            end if
        end function rigid_name

        !> What makes velocities reverse within a step, for the message.
        function cause_hint() result(t)
            character(len=:), allocatable :: t
            t = 'a time step beyond the stable limit (TSSFAC too high?)'
            if (ct%n > 0) t = 'a contact penalty scale (SLSFAC, SFS, SFM) too high for the time step, or '//t
            if (pn%n > 0 .or. rg%n > 0) t = t//', or a prescribed motion reversing within a step'
        end function cause_hint

        !> The restart dump of the state at the end of this cycle.
        subroutine dump()
            logical :: ok
            real(dp) :: t1
            t1 = tm%elapsed()
            call tm%start(ph_output)
            call gather_element_state(dom, solids, sh, energies=.true.)
            ! the dump's history marks count the rows in thist.h5
            call flush_histories(hist)
            ok = .true.
            if (dom%on) call gather_contact_state(ct)
            if (dom%rank == 0) call write_dump(opts%dump_path, opts%meta, st, solids, sh, bm, walls, rg, ct, td, &
                                               history_marks(hist), states_marks(states), ok)
            if (dom%on) call scatter_contact_state(ct, dom%rank)
            ! rank 0 wrote it: every rank learns whether it could
            ok = .not. any_rank(.not. ok)
            call tm%stop(ph_output)
            t_dump = tm%elapsed() - t1
            if (ok) then
                call log_line(lg, ' restart dump at cycle '//itoa(st%cycle)//', time '//rtoa(st%time)//': '// &
                              opts%dump_path)
            else
                ! a full disk or a quota: the last good dump stays, and the run
                ! stops rather than go on without a way back
                call fail('cannot write the restart dump '//opts%dump_path//write_failed// &
                          '; the last good dump, if any, is kept')
            end if
        end subroutine dump

        subroutine stop_run(text)
            character(len=*), intent(in) :: text
            call end_run(exit_signal, 'stopped', text)
        end subroutine stop_run

        !> 'node 12 (part 3)': a node and the part of an element on it.
        function node_where(i) result(txt)
            integer, intent(in) :: i
            character(len=:), allocatable :: txt
            integer :: e
            txt = itoa(model%node_id(i))
            do e = 1, solids%n
                if (any(solids%conn(:, e) == i)) then
                    txt = txt//' (part '//itoa(model%part(solids%part(e))%id)//')'
                    return
                end if
            end do
            do e = 1, sh%n
                if (any(sh%conn(:, e) == i)) then
                    txt = txt//' (part '//itoa(model%part(sh%part(e))%id)//')'
                    return
                end if
            end do
        end function node_where

        subroutine fail(text)
            character(len=*), intent(in) :: text
            call end_run(exit_run, 'error termination', text)
        end subroutine fail

        !> The run ends early with exit status `code`: the message, with the
        !> time and cycle, for the caller and the log.
        subroutine end_run(code, what, text)
            integer, intent(in) :: code
            character(len=*), intent(in) :: what, text
            res%status = code
            res%message = what//' at time '//rtoa(st%time)//', cycle '//itoa(st%cycle)//': '//text
            call log_line(lg, '')
            call log_line(lg, ' *** '//res%message)
        end subroutine end_run

        subroutine output(force)
            logical, intent(in) :: force
            integer :: crit(3)
            real(dp) :: ns
            character(len=:), allocatable :: failed_file
            call tm%start(ph_output)
            crit = 0
            if (st%crit_elem > 0) then
                crit = [1, solids%eid(st%crit_elem), model%part(solids%part(st%crit_elem))%id]
            else if (st%crit_elem < 0) then
                crit = [2, sh%eid(-st%crit_elem), model%part(sh%part(-st%crit_elem))%id]
            end if
            ns = 0
            if (st%cycle > 0) ns = 1.0e9_dp*(tm%elapsed() - t0_wall)/(real(st%cycle, dp)*max(solids%n + sh%n, 1))
            if (ct%n > 0) then
                call write_histories(hist, model, st, solids, walls, rg, en, vn, crit, ns, force, contact_resultants(ct), &
                                     ct%fnode, wminus=vrminus)
            else
                call write_histories(hist, model, st, solids, walls, rg, en, vn, crit, ns, force, wminus=vrminus)
            end if
            if (states_due(states, st%time) .or. (force .and. states%on) .or. state_asked) then
                ! the energies (and shell thicknesses) are gathered already
                ! where this cycle computed the energies
                call gather_element_state(dom, solids, sh, energies=.not. energy_now)
                if (ct%n > 0) then
                    call write_state(states, st, solids, sh, vn, ct%fnode, en=en, bm=bm)
                else
                    call write_state(states, st, solids, sh, vn, en=en, bm=bm)
                end if
                state_asked = .false.
            end if
            call tm%stop(ph_output)
            ! a failed write (a full disk, a quota, the directory gone) stops
            ! the run; every file keeps its complete records
            failed_file = history_failure(hist)
            if (len(failed_file) == 0) failed_file = states_failure(states)
            ! rank 0 writes the files: every rank stops with it
            if (any_rank(len(failed_file) > 0) .and. len(failed_file) == 0) failed_file = 'an output file (on rank 0)'
            if (len(failed_file) > 0) call fail('cannot write '//failed_file//write_failed// &
                '; the output files keep every complete record written before')
        end subroutine output

        subroutine progress()
            real(dp) :: frac, el, left
            character(len=200) :: buf
            el = tm%elapsed() - t0_wall
            frac = min(1.0_dp, st%time/max(opts%endtim, tiny(1.0_dp)))
            if (model%ctl%endcyc > 0) frac = max(frac, min(1.0_dp, real(st%cycle, dp)/model%ctl%endcyc))
            left = 0
            if (frac > 0) left = el*(1.0_dp - frac)/frac
            write (buf, '(a,i9,a,es11.4,a,es10.3,a,f6.1,a,f8.5,a,f9.1,a,f9.1,a)') ' cycle', st%cycle, &
                '  t', st%time, '  dt', st%dt, '  ', 100*frac, '%  ratio', en%ratio, '  elapsed', el, &
                's  left', left, 's'
            write (output_unit, '(a)') trim(buf)
            flush (output_unit)
        end subroutine progress

    end subroutine run_time_loop

end module xd_solver_time_loop
