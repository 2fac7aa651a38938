!> The explicit time loop: central differences with a variable step, one
!> cycle as the list of its phases (xd_solver_phases: element forces, the
!> step, loads, contact, velocities, constraints and rigid bodies,
!> energies, the advance), and, here with the run's options and result,
!> the phases that use them: the energy checks that stop a run gone bad
!> (exit 2) with a diagnostic, output, restart dumps, and the batch control
!> (signals, sense switches, the wall-clock limit).
module xd_solver_time_loop
    use, intrinsic :: iso_fortran_env, only: output_unit
    use xd_kinds, only: wp, dp, i8
    use xd_core_memory, only: nbytes, release_free_memory
    use xd_core_strings, only: itoa, rtoa, ftoa
    use xd_core_errors, only: exit_normal, exit_run, exit_signal
    use xd_core_timers, only: timers_t, ph_elements, ph_integrate, ph_output, ph_search, ph_init, ph_comm
    use xd_model, only: model_t
    use xd_elements_solid_groups, only: solids_t
    use xd_solver_state, only: state_t, allocate_force_arrays
    use xd_solver_assembly, only: assembly_t
    use xd_solver_energies, only: energies_t, prepare_energies, energy_bytes, masses_fixed
    use xd_output_histories, only: histories_t, histories_due, database_due, s_nodout, s_rcforc, write_histories, &
                                   history_failure, &
                                   flush_histories
    use xd_output_states, only: states_t, states_due, write_state, states_marks, states_failure
    use xd_output_histories, only: history_marks, merge_rotations
    use xd_solver_restart, only: dump_meta_t, write_dump
    use xd_core_signals, only: stop_signal, status_signal, hold_for_signal
    use xd_solver_sense_switch, only: read_sense_switch, switch_name, sw_none, sw_stop, sw_status, sw_dump, sw_state, &
                                      sw_flush, sw_unknown
    use xd_output_d3hsp, only: log_t, log_line
    use xd_solver_loads, only: pressures_t
    use xd_contact_rigidwall, only: walls_t
    use xd_contact_enforcement, only: body_response_t
    use xd_elements_beam_bs, only: beams_t
    use xd_contact_tied, only: ties_t
    use xd_contact_contact, only: contacts_t, contact_search, contact_work_end, contact_resultants, &
                                  gather_contact_state, scatter_contact_state, gather_drift, search_due, &
                                  contact_slave_rows
    use xd_solver_prescribed, only: prescribed_nodes_t
    use xd_rigid_bodies, only: rigid_t
    use xd_elements_shell_bt, only: shells_t, shell_rows
    use xd_solver_domain, only: neighbour_count, domain_t, gather_element_state, owned_motion, gather_layout, gather_subset, &
                                ghost_base, contact_ghosts, search_exchange, surface_spans, &
                                release_element_view
    use xd_core_comm, only: comm_max, comm_sum_int, comm_gather_small, comm_sum_dp
    use xd_solver_step_control, only: step_stats_t, step_stats_init, step_stats_count, step_stats_report, &
                                      hourglass_bound_report
    use xd_solver_mass_scaling, only: mass_scaling_t, mass_scaling_begin, mass_scaling_targets, mass_scaling_step, &
                                      mass_scaling_summary
    use xd_solver_state_writer, only: states_by_ranks, write_state_by_ranks
    use xd_solver_local_nodes, only: node_view_t, cut_state, localize_nodes, open_view, close_view, global_node, held_nodes
    use xd_solver_phases, only: element_phase, exchange_phase, bad_element, beam_phase, erosion_phase, step_phase, &
                                load_phase, contact_phase, velocity_phase, constraint_phase, energy_phase, &
                                advance_phase, any_rank
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
        !> the bytes of the loop's own per-node arrays (v(n-1/2), which holds
        !> v(n) after the energies, and the walls' mask) and the energies'
        !> tables
        integer(i8) :: node_bytes = 0
    end type run_result_t

    !> What the time loop keeps between cycles for its output, checks and
    !> batch control.
    type :: loop_t
        integer :: cycle0 = 0                 !< the run's first cycle (a restart's)
        real(dp) :: t0_wall = 0               !< wall clock at the loop's start
        real(dp) :: t_dump = 0                !< wall seconds the last dump took
        real(dp) :: t_last_progress = 0
        real(dp) :: ratio_limit = 1.5_dp      !< energy ratio beyond which the run stops (ENDENG)
        logical :: state_asked = .false.      !< a state asked by sense switch sw4, at this cycle's end
        logical :: switch_gone = .true.       !< d3kil could be deleted (sense switches are read)
        logical :: dumped_end = .false.       !< the end-of-run dump is written
        character(len=:), allocatable :: switch_text
    end type loop_t

contains

    subroutine run_time_loop(model, dom, st, solids, asm, sh, asm_sh, bm, walls, ct, pn, rg, pl, td, hist, states, lg, tm, &
                             opts, res)
        type(model_t), intent(in) :: model
        !> (its `owned` set here, before the loop)
        type(domain_t), intent(inout) :: dom
        type(state_t), intent(inout) :: st
        type(solids_t), intent(inout) :: solids
        !> (asm, asm_sh: their node lists renumbered where the nodes are
        !> numbered per rank)
        type(assembly_t), intent(inout) :: asm
        type(shells_t), intent(inout) :: sh
        type(assembly_t), intent(inout) :: asm_sh
        type(beams_t), intent(inout) :: bm
        type(walls_t), intent(inout) :: walls
        type(contacts_t), intent(inout) :: ct
        !> (its nodes' local numbers set where the nodes are numbered per rank)
        type(prescribed_nodes_t), intent(inout) :: pn
        type(rigid_t), intent(inout) :: rg
        type(pressures_t), intent(inout) :: pl
        type(ties_t), intent(inout) :: td       !< tied contacts
        type(histories_t), intent(inout) :: hist
        type(states_t), intent(inout) :: states
        type(log_t), intent(in) :: lg
        type(timers_t), intent(inout) :: tm
        type(run_options_t), intent(in) :: opts
        type(run_result_t), intent(out) :: res
        type(loop_t) :: lp
        type(energies_t) :: en
        type(mass_scaling_t) :: ms
        type(step_stats_t) :: ss
        integer :: set_by
        character(len=:), allocatable :: ms_stop
        !> v(n-1/2) saved before the velocity update where the energies are
        !> due, and after them v(n), the outputs' (energy_phase)
        real(wp), allocatable :: vminus(:, :), vrminus(:, :)
        real(dp), allocatable :: ke_fix(:)     !< tied contacts' kinetic energy by part
        type(body_response_t) :: br            !< Lagrangian contact: how the rigid bodies answer an impulse
        logical, allocatable :: no_body(:)   !< no node is a rigid body's (models without rigid bodies)
        !> contact ghosts: per model node, its position is current on this rank
        !> at a search (search_exchange)
        logical, allocatable :: cur(:)
        real(dp) :: spans(2)   !< the search's surface_spans, which the ghosts' choice after it reads
        real(wp) :: dtc, g_new(3)
        real(dp) :: dt_avg
        real(wp) :: dt_ref
        logical :: done
        logical :: energy_now                  !< this cycle computes the energies (and so may write output)
        logical :: output_now                  !< this cycle writes histories or a state
        integer :: bad_kind, bad                !< the first bad element (element_phase)
        character(len=:), allocatable :: failure
        integer :: beam_crit                   !< the beam that set the step (0: none)
        !> the shells add their forces to the nodes each thread's part holds
        !> alone (and no other rank's element touches) directly, in the
        !> order the assembly sums their slots (the same sums, without
        !> writing and reading the slots); the nodes the parts or the ranks
        !> share are summed from the slots after the pass
        logical :: shells_direct, refresh
        !> nodes numbered per rank: rank 0's whole view of the nodes for an
        !> output (held for the output's time)
        type(node_view_t) :: vw
        character(len=:), allocatable :: whole
        logical, allocatable :: keep(:)      !< (the model's nodes a rank keeps where they are numbered per rank)

        allocate (ke_fix(model%npart))
        shells_direct = sh%n > 0
        ke_fix = 0
        beam_crit = 0
        if (model%ctl%endeng > 0.0_wp) lp%ratio_limit = 1.0_dp + model%ctl%endeng/100.0_dp
        lp%t0_wall = tm%elapsed()
        lp%cycle0 = st%cycle
        lp%t_last_progress = lp%t0_wall
        call mass_scaling_begin(ms, model%ctl, lg)
        call step_stats_init(ss, solids%n, sh%n)
        if (dom%on) call choose_owned(dom, ct, rg, td, bm, pl, sh, hist, lg)
        if (allocated(dom%own_contact) .and. ct%n > 0) then
            ! each rank books its own slaves' contacts' work; a restart's
            ! sums (every rank read them) stay on rank 0 alone; the slaves'
            ! contact state in the rows of the rank's own slaves (made here,
            ! at their size, where the set-up left them for later)
            ct%own_work = .true.
            call scatter_contact_state(ct, dom%rank)
        else if (ct%n > 0) then
            ! (every slave's rows, where the set-up left them for later)
            call contact_slave_rows(ct, .false.)
        end if
        ! (the ghosts from the lists there are: a restart's; they read the
        ! rank's own slaves' contacts, in the rows made above)
        if (dom%ghosts) call contact_ghosts(dom, ct, st%x, st%v, surface_spans(ct, st%x, block=[dom%rank, dom%nranks]))
        ! (the scale of the momenta glstat and matsum report)
        call log_line(lg, ' initial nodal mass (the nodes'' lumped masses) .......... '//rtoa(sum(real(st%mass, dp))))
        if (dom%owned) then
            ! nodes numbered per rank where nothing reads every node
            whole = whole_nodes_reason(solids, sh, bm, ct, rg, pl, td, ms)
            if (len(whole) == 0) then
                call tm%start(ph_init)
                ! (the nodal arrays cut first; then the energies' node table
                ! for the nodes the rank keeps alone, from the model's
                ! connectivity, which localize_nodes then renumbers)
                keep = held_nodes(dom, solids, sh)
                call cut_state(dom, keep, st, en)
                call prepare_energies(model, st, solids, sh, en, bm, keep)
                call localize_nodes(dom, st, solids, asm, sh, asm_sh, hist, walls, pn)
                deallocate (keep)
                call tm%stop(ph_init)
                call log_line(lg, ' nodal arrays: nodes numbered per rank: each rank holds its own nodes and those '// &
                              'its elements touch (rank 0: '//itoa(size(dom%l2g))//' of '//itoa(dom%nglobal)// &
                              '); rank 0 gathers every node for a state or a dump, the nodout nodes for the '// &
                              'histories, for the output''s time')
            else
                call log_line(lg, ' nodal arrays: every node on every rank, for '//whole//' (nodes numbered per '// &
                              'rank need none of these)')
            end if
        end if
        ! the energies' tables (where the nodes were not cut, every node's),
        ! built here, at set-up, not as the first cycle's work
        call tm%start(ph_init)
        call prepare_energies(model, st, solids, sh, en, bm)
        ! owned nodes on more than one rank: the shells' thickness, area and
        ! energies held for the rank's own shells alone (an output's view
        ! gathers them), where nothing reads another rank's: not with mass
        ! scaling (every rank scales every shell's mass) or shells that can
        ! erode (every rank books an eroded shell's energy)
        if (dom%on .and. dom%owned .and. sh%n > 0) then
            if (.not. (allocated(sh%msf) .or. sh%erodible .or. model%ctl%erode == 1)) call shell_rows(sh)
        end if
        call tm%stop(ph_init)
        ! (the accelerations, forces and moments and the velocities the
        ! energies save: allocated by the first cycle, after its contact
        ! search, node_work_arrays)
        ! (what the set-up freed, back to the system before the loop)
        call release_free_memory()

        ! cycle n: forces at t(n) on x(n) with v(n-1/2); v(n+1/2) with the
        ! constraints; output at t(n); then x(n+1)
        do
            ! the end-of-run restart dump: the state at the start of the last
            ! cycle (a restart with a later end time goes on from there as
            ! the longer run would have, writing the outputs of t(n) again)
            if (opts%dump_every >= 0 .and. .not. lp%dumped_end) then
                if (st%time >= opts%endtim*(1.0_dp - 1.0e-12_dp) .or. &
                    (model%ctl%endcyc > 0 .and. st%cycle >= model%ctl%endcyc)) then
                    call node_work_arrays(st, en, tm, vminus, vrminus, no_body, res)
                    call dump_now(lp, opts, model, dom, st, solids, sh, bm, walls, rg, ct, td, hist, states, lg, tm, &
                                  res, vw)
                    lp%dumped_end = .true.
                    if (res%status /= exit_normal) exit
                end if
            end if
            if (ct%n > 0) then
                ! contact ghosts: a search reads the surface nodes within reach
                ! of the rank's slaves, from their ranks (cur: the nodes held
                ! current), and chooses the ghosts anew after it
                refresh = .false.
                if (dom%ghosts) refresh = search_due(ct, st%cycle, st%time)
                if (refresh) then
                    call tm%start(ph_comm)
                    call search_exchange(dom, ct, st%x, st%v, st%time, cur, spans)
                    call tm%stop(ph_comm)
                end if
                ! step 2 where due, on x(n); steps 3-4 will follow here
                call tm%start(ph_search)
                if (refresh) then
                    call contact_search(ct, st%x, model%node_id, st%cycle, st%time, cur)
                else
                    call contact_search(ct, st%x, model%node_id, st%cycle, st%time)
                end if
                call tm%stop(ph_search)
                if (refresh) then
                    call tm%start(ph_comm)
                    call contact_ghosts(dom, ct, st%x, st%v, spans)
                    call tm%stop(ph_comm)
                end if
            end if
            if (ms%on) call mass_scaling_targets(ms, st%cycle, solids, sh)
            ! (the first cycle's, after its search: node_work_arrays)
            call node_work_arrays(st, en, tm, vminus, vrminus, no_body, res)
            call element_phase(dom, st, solids, asm, sh, tm, shells_direct, dtc, bad_kind, bad)
            call exchange_phase(dom, st, solids, asm, sh, asm_sh, tm, shells_direct, dtc, bad_kind, bad)
            if (bad_kind /= 0) then
                if (dom%owned) call refresh_nodes(dom, model, st, sh, hist, tm, .false., vw)
                call fail(res, st, lg, bad_element(model, st, solids, sh, bad_kind, bad, dom))
                exit
            end if
            if (bm%n > 0) call beam_phase(model, st, sh, bm, lg, tm, dtc, beam_crit)
            ! failure: shells and solids that fail erode (their forces already in this
            ! cycle's; from the next on they are gone)
            if (sh%erodible .or. solids%erodible) call erosion_phase(model, dom, st, solids, sh, ct, lg)
            if (ms%on) then
                ! the masses the element pass asked for, before anything
                ! divides by them
                call tm%start(ph_elements)
                call mass_scaling_step(ms, model, dom, solids, sh, st, rg, lg, ms_stop)
                call tm%stop(ph_elements)
                if (allocated(ms_stop)) then
                    call fail(res, st, lg, ms_stop)
                    exit
                end if
            end if
            call step_phase(model, ms, solids, sh, bm, ct, lg, lp%cycle0, beam_crit, dtc, st, dt_ref, set_by, failure)
            if (len(failure) > 0) then
                call fail(res, st, lg, failure)
                exit
            end if
            call step_stats_count(ss, set_by, st%crit_elem)

            dt_avg = 0.5_dp*(real(st%dt_old, dp) + st%dt)
            call tm%start(ph_integrate)
            call load_phase(model, dom, pl, st, dt_avg, g_new)
            call tm%stop(ph_integrate)
            done = st%time >= opts%endtim*(1.0_dp - 1.0e-12_dp)
            if (model%ctl%endcyc > 0) done = done .or. st%cycle >= model%ctl%endcyc
            ! output where histories or states are due, at the first and the
            ! last cycle, or where sense switch sw4 asked a state; energies
            ! then (the d3plot's global variables carry them), and every
            ! energy_check_every cycles
            output_now = histories_due(hist, st%time) .or. states_due(states, st%time) .or. done .or. &
                         st%cycle == 0 .or. lp%state_asked
            energy_now = output_now .or. mod(st%cycle, opts%energy_check_every) == 0
            ! steps 3-4 of the contact on x(n): contact forces join f(n)
            ! (every pair's contact forces per node where an output reads
            ! them: a state, nodout, or every database at once)
            if (ct%n > 0) call contact_phase(model, dom, ct, rg, sh, st, lg, tm, dt_avg, &
                                             database_due(hist, s_nodout, st%time, done .or. st%cycle == 0) .or. &
                                             state_now(lp, states, st%time, done .or. st%cycle == 0), &
                                             database_due(hist, s_rcforc, st%time, done .or. st%cycle == 0), br)
            call tm%start(ph_integrate)
            call velocity_phase(dom, st, td, dt_avg, energy_now, vminus, vrminus)
            call tm%stop(ph_integrate)
            call constraint_phase(model, dom, walls, pn, rg, td, pl, st, lg, tm, dt_avg, g_new, no_body)

            if (energy_now) then
                call energy_phase(model, dom, st, solids, sh, walls, rg, ct, td, bm, tm, vminus, vrminus, dt_avg, &
                                  ke_fix, en)
                ! (vminus now v(n)) owned nodes: every node to rank 0 for a
                ! state, the nodout nodes for the histories, v(n) as their
                ! ranks averaged it (the energies are summed by rank)
                if (dom%owned .and. output_now) then
                    if (state_now(lp, states, st%time, done .or. st%cycle == 0)) then
                        call refresh_nodes(dom, model, st, sh, hist, tm, .true., vw, vminus, vrminus, state=.true.)
                    else
                        call refresh_histories(dom, model, st, sh, hist, tm, vw, vminus, vrminus)
                    end if
                end if
                call energy_check(lp, model, dom, st, solids, sh, rg, ct, pn, en, vminus, res, lg)
                if (res%status /= exit_normal) exit
                if (output_now) then
                    if (vw%on) then
                        call output_phase(lp, done .or. st%cycle == 0, model, dom, vw%st, solids, sh, bm, walls, &
                                          rg, ct, hist, states, en, vw%vn, vw%wn, tm, res, lg)
                    else
                        call output_phase(lp, done .or. st%cycle == 0, model, dom, st, solids, sh, bm, walls, &
                                          rg, ct, hist, states, en, vminus, vrminus, tm, res, lg)
                    end if
                end if
                if (dom%local) call close_view(sh, vw)
                if (res%status /= exit_normal) exit
            end if
            ! the contact forces' work with v(n+1/2), after the energies at t(n)
            if (ct%n > 0) call contact_work_end(ct, st%v, dt_avg)
            if (opts%progress .and. (tm%elapsed() - lp%t_last_progress >= opts%progress_every .or. done &
                                     .or. st%cycle == 0)) then
                lp%t_last_progress = tm%elapsed()
                call progress_line(lp, model, st, opts, tm, en)
            end if
            if (done) exit

            call advance_phase(dom, st, ct, hist, tm, dt_avg)
            call batch_phase(lp, opts, model, dom, st, solids, sh, bm, walls, rg, ct, td, hist, states, en, lg, tm, res, vw)
            if (res%status /= exit_normal) exit
        end do
        ! (a view an energy check's failure left open)
        if (dom%local) call close_view(sh, vw)

        res%ncycle = st%cycle
        res%loop_wall = tm%elapsed() - lp%t0_wall
        ! the end reached in one step at most past ENDTIM
        if (res%status == exit_normal .and. opts%endtim < huge(1.0_dp)) then
            if (.not. (st%time <= opts%endtim + 1.000001_dp*real(st%dt_old, dp))) &
                call fail(res, st, lg, 'time '//rtoa(st%time)//' is past the end time '//rtoa(opts%endtim)// &
                          ' by more than a step')
        end if
        call step_stats_report(ss, model, solids, sh, lg, merge(ct%dt_node, 0, ct%n > 0))
        if (allocated(sh%ncap)) then
            ! (each rank counts its own shells' rows: every shell's count
            ! by shell number, added over the ranks)
            block
                integer, allocatable :: ncap(:)
                integer :: i
                allocate (ncap(sh%n))
                ncap = 0
                do i = 1, sh%nl
                    ncap(sh%gix(i)) = sh%ncap(i)
                end do
                if (dom%on) call comm_sum_int(ncap, sh%n)
                call hourglass_bound_report(ss, model, sh, ncap, lg)
            end block
        end if
        call mass_scaling_summary(ms, model, solids, sh, st, lg)
        if (res%status == exit_normal) then
            call log_line(lg, '')
            call log_line(lg, ' N o r m a l    t e r m i n a t i o n   at time '//rtoa(st%time)// &
                          ', cycle '//itoa(st%cycle))
        end if
    end subroutine run_time_loop

    !> The accelerations, forces and moments, at the size the rank holds,
    !> and the velocities the energies save (vminus, vrminus) and no_body,
    !> allocated once: by the first cycle after its contact search, or
    !> before a dump at the start. The search's work arrays (the surface's
    !> size), freed, are handed back to the system first: the allocator
    !> took these from fresh pages beside them, and the 250,000-shell
    !> plate's peak a rank on 16 ranks held both. Their first touch is the
    !> set-up's time (it took 12 ms of cycle 0's time integration on
    !> 100,000 shells).
    subroutine node_work_arrays(st, en, tm, vminus, vrminus, no_body, res)
        type(state_t), intent(inout) :: st
        type(energies_t), intent(in) :: en
        type(timers_t), intent(inout) :: tm
        real(wp), allocatable, intent(inout) :: vminus(:, :), vrminus(:, :)
        logical, allocatable, intent(inout) :: no_body(:)
        type(run_result_t), intent(inout) :: res
        if (allocated(st%f)) return
        call tm%start(ph_init)
        call release_free_memory()
        call allocate_force_arrays(st)
        allocate (vminus(3, st%nnode), no_body(st%nnode))
        no_body = .false.
        if (st%rot) allocate (vrminus(3, st%nnode))
        vminus = 0
        if (st%rot) vrminus = 0
        call tm%stop(ph_init)
        res%node_bytes = nbytes(vminus) + nbytes(vrminus) + nbytes(no_body) + energy_bytes(en)
    end subroutine node_work_arrays

    !> Batch control at the end of a cycle: a status line on SIGUSR2; the
    !> sense switches of d3kil; a dump every opts%dump_every cycles; on
    !> SIGTERM or SIGUSR1, or near the wall-clock limit, a dump and the run
    !> stopped (exit 3). The loop ends where res%status is no longer normal.
    subroutine batch_phase(lp, opts, model, dom, st, solids, sh, bm, walls, rg, ct, td, hist, states, en, lg, tm, res, vw)
        type(loop_t), intent(inout) :: lp
        type(run_options_t), intent(in) :: opts
        type(model_t), intent(in) :: model
        type(domain_t), intent(in) :: dom
        type(state_t), intent(inout) :: st
        type(solids_t), intent(inout) :: solids
        type(shells_t), intent(inout) :: sh
        type(beams_t), intent(in) :: bm
        type(walls_t), intent(in) :: walls
        type(rigid_t), intent(in) :: rg
        type(contacts_t), intent(inout) :: ct
        type(ties_t), intent(in) :: td
        type(histories_t), intent(inout) :: hist
        type(states_t), intent(inout) :: states
        type(energies_t), intent(in) :: en
        type(log_t), intent(in) :: lg
        type(timers_t), intent(inout) :: tm
        type(run_result_t), intent(inout) :: res
        type(node_view_t), intent(inout) :: vw   !< (nodes numbered per rank: rank 0's view for a dump)
        integer :: sig, sw
        logical :: limit, status
        if (allocated(opts%hold_cycles)) then
            if (any(opts%hold_cycles == st%cycle)) call flush_histories(hist)
            if (any(opts%hold_cycles == st%cycle)) call hold_for_signal(' held at cycle '//itoa(st%cycle)// &
                                                               ' (XDYNA_HOLD_AT): waiting for a signal', 120.0, opts%progress)
        end if
        call stop_flags(lp, opts, dom, st, lg, tm, sig, limit, status, sw)
        if (status) call progress_line(lp, model, st, opts, tm, en)
        ! what a sense switch asks, at the end of this cycle (every rank)
        select case (sw)
        case (sw_stop)
            call dump()
            if (res%status == exit_normal) &
                call end_run(res, st, lg, exit_signal, 'stopped', 'stopped by sense switch sw1 (d3kil); restart dump '// &
                             opts%dump_path)
        case (sw_status)
            call progress_line(lp, model, st, opts, tm, en)
        case (sw_dump)
            call dump()
        case (sw_state)
            ! the state at the next cycle's end, where its energies are computed
            if (states%on) then
                lp%state_asked = .true.
            else
                call log_line(lg, ' *** Warning: sense switch sw4: this run writes no states')
            end if
        case (sw_flush)
            call flush_histories(hist)
        end select
        if (res%status /= exit_normal) return
        if (opts%dump_every > 0) then
            if (mod(st%cycle, opts%dump_every) == 0) call dump()
            if (res%status /= exit_normal) return
        end if
        if (sig /= 0) then
            call dump()
            if (res%status == exit_normal) call end_run(res, st, lg, exit_signal, 'stopped', 'stopped by signal '// &
                                                        itoa(sig)//'; restart dump '//opts%dump_path)
        else if (limit) then
            call dump()
            if (res%status == exit_normal) call end_run(res, st, lg, exit_signal, 'stopped', 'wall-clock limit of '// &
                                                        ftoa(opts%wallclock)//' s near; restart dump '//opts%dump_path)
        end if
    contains
        subroutine dump()
            call dump_now(lp, opts, model, dom, st, solids, sh, bm, walls, rg, ct, td, hist, states, lg, tm, res, vw)
        end subroutine dump
    end subroutine batch_phase

    !> A restart dump of the state now: with owned nodes every node from its
    !> rank first (into rank 0's whole view where the nodes are numbered
    !> per rank, which it writes from and then releases).
    subroutine dump_now(lp, opts, model, dom, st, solids, sh, bm, walls, rg, ct, td, hist, states, lg, tm, res, vw)
        type(loop_t), intent(inout) :: lp
        type(run_options_t), intent(in) :: opts
        type(model_t), intent(in) :: model
        type(domain_t), intent(in) :: dom
        type(state_t), intent(inout) :: st
        type(solids_t), intent(inout) :: solids
        type(shells_t), intent(inout) :: sh
        type(beams_t), intent(in) :: bm
        type(walls_t), intent(in) :: walls
        type(rigid_t), intent(in) :: rg
        type(contacts_t), intent(inout) :: ct
        type(ties_t), intent(in) :: td
        type(histories_t), intent(inout) :: hist
        type(states_t), intent(in) :: states
        type(log_t), intent(in) :: lg
        type(timers_t), intent(inout) :: tm
        type(run_result_t), intent(inout) :: res
        type(node_view_t), intent(inout) :: vw
        if (dom%owned) call refresh_nodes(dom, model, st, sh, hist, tm, .true., vw)
        if (vw%on) then
            call dump_phase(lp, opts, dom, vw%st, solids, sh, bm, walls, rg, ct, td, hist, states, lg, tm, res)
        else
            call dump_phase(lp, opts, dom, st, solids, sh, bm, walls, rg, ct, td, hist, states, lg, tm, res)
        end if
        if (dom%local) call close_view(sh, vw)
    end subroutine dump_now

    !> Owned nodes (issue 32): each rank integrates the nodes it assembles
    !> and exchanges its halo with its neighbours alone; the nodes every
    !> rank takes alike (contact surfaces, pressure segments, beams, ties:
    !> their velocities; rigid bodies: their forces) go to every rank.
    !> XDYNA_REPLICATED=1 keeps the replicated nodal state instead, every
    !> rank integrating every node (comparisons); d3hsp says which.
    subroutine choose_owned(dom, ct, rg, td, bm, pl, sh, hist, lg)
        type(domain_t), intent(inout) :: dom
        type(contacts_t), intent(in) :: ct
        type(rigid_t), intent(in) :: rg
        type(ties_t), intent(in) :: td
        type(beams_t), intent(in) :: bm
        type(pressures_t), intent(in) :: pl
        type(shells_t), intent(in) :: sh
        type(histories_t), intent(in) :: hist   !< (its nodout nodes, gathered at a history output)
        type(log_t), intent(in) :: lg
        character(len=8) :: env
        integer :: n, stat, i
        integer, allocatable :: surf(:), body(:), tie(:), csurf(:)
        logical :: ghosts, own
        integer :: wv
        real(dp) :: byt(2)
        call get_environment_variable('XDYNA_REPLICATED', env, length=n, status=stat)
        dom%owned = .not. (stat == 0 .and. n > 0 .and. env(1:max(n, 1)) /= '0')
        if (dom%owned) then
            dom%own = dom%node_mine
            dom%own_solid = dom%solid_mine
            dom%own_shell = dom%shell_mine
            ! (the default where there is contact; XDYNA_CONTACT_OWN=0 turns
            ! it off, and the ghosts with it)
            call get_environment_variable('XDYNA_CONTACT_OWN', env, length=n, status=stat)
            own = ct%n > 0 .and. .not. (stat == 0 .and. n > 0 .and. env(1:max(n, 1)) == '0')
            ! (the Lagrangian projection and the shell edges' pairs read
            ! every surface node: not there)
            if (own .and. (ct%lagrange .or. any([(ct%ifc(i)%ed%ne > 0, i=1, ct%n)]))) then
                own = .false.
                call log_line(lg, ' contact: every rank bounds every surface node''s motion and takes the '// &
                              'whole surfaces (no contact ghosts): the Lagrangian projection and shell '// &
                              'edge pairs read every surface node')
            end if
            if (own) dom%own_contact = dom%node_mine
            if (own) call log_line(lg, ' contact: each rank bounds the motion of its own surface '// &
                                               'nodes alone and books its own slaves'' contacts'' work, '// &
                                               'reduced over the ranks (XDYNA_CONTACT_OWN=0: every rank all)')
            ! (the contact surfaces' nodes: their velocities go to every rank)
            ! (and the pressure segments' nodes: every rank takes every
            ! segment's force, as it takes every contact)
            allocate (surf(0), csurf(0))
            do i = 1, ct%n
                csurf = [csurf, ct%ifc(i)%surf%node]
            end do
            ! contact ghosts (the default with own_contact; XDYNA_GHOSTS=0
            ! turns them off): the contact surfaces' velocities only to the
            ! ranks whose slaves are near them, chosen at each search
            ! (contact_ghosts)
            call get_environment_variable('XDYNA_GHOSTS', env, length=n, status=stat)
            ghosts = own .and. .not. (stat == 0 .and. n > 0 .and. env(1:max(n, 1)) == '0')
            if (.not. ghosts) surf = csurf
            if (pl%n > 0) surf = [surf, pack(pl%seg, pl%seg > 0)]
            allocate (body(0))
            do i = 1, rg%n
                body = [body, rg%b(i)%node]
            end do
            ! (the beams' nodes: every rank takes every beam, with its
            ! nodes' angular velocities)
            ! (the ties' slaves and segments' nodes: every rank takes every tie)
            if (td%n > 0) then
                tie = [td%slave, pack(td%mnode, td%mnode > 0)]
            else
                allocate (tie(0))
            end if
            if (bm%n > 0) then
                call owned_motion(dom, surf, body, reshape(bm%conn(1:2, :), [2*bm%n]), tie)
            else
                call owned_motion(dom, surf, body, [integer ::], tie)
            end if
            if (ghosts) then
                call ghost_base(dom, csurf)
                ! (XDYNA_CHECK_GHOSTS=1: each search's exchange checked
                ! against every surface node from its rank)
                call get_environment_variable('XDYNA_CHECK_GHOSTS', env, length=n, status=stat)
                dom%check_search = stat == 0 .and. n > 0 .and. env(1:max(n, 1)) == '1'
                call log_line(lg, ' contact: ghosts by proximity (XDYNA_GHOSTS=0: none): at each search each '// &
                              'rank''s box of what a search of its slaves buckets goes to all and a rank sends its own '// &
                              'surface nodes inside another''s box to it (of the surfaces'' '// &
                              itoa(size(dom%csurf%node))//' nodes), then each '// &
                              'rank''s box of what its slaves read to all, and until the next search a rank''s own '// &
                              'surface nodes inside another''s box sent to it with the halo')
            end if
            if (allocated(hist%nodes)) then
                if (size(hist%nodes) > 0) call gather_layout(dom%arank, dom%nranks, hist%nodes, dom%hist)
            end if
            call log_line(lg, ' nodal state: owned nodes: each rank integrates the nodes it assembles (rank 0: '// &
                          itoa(size(dom%nodes))//' of '//itoa(size(dom%node_mine))//'), sends the halo''s force '// &
                          'slots to their nodes'' ranks and its nodes'' velocities to the ranks that touch them, '// &
                          'point-to-point (rank 0: '//itoa(neighbour_count(dom))//' neighbours), and the contact '// &
                          'surfaces'' '//itoa(size(dom%surf%node))//' nodes'' velocities and the rigid bodies'' '// &
                          itoa(size(dom%body%node))//' nodes'' forces to every rank (the beams'' '// &
                          itoa(size(dom%rotn%node))//' nodes'' velocities and angular velocities, the ties'' '// &
                          itoa(td%n)//' slaves'' and their segments'' nodes'' forces and velocities); energies are each '// &
                          'rank''s own nodes'' and elements'' sums added over the ranks (the serial run''s to '// &
                          'rounding); every node is gathered only for a state or a dump, the nodout nodes for '// &
                          'the histories')
            ! the bytes a cycle, over all ranks (velocities of 6 values where
            ! nodes turn: shells or beams)
            wv = 3
            if (sh%n > 0 .or. bm%n > 0) wv = 6
            ! (the contact surfaces' and pressure segments' nodes travel in
            ! the neighbour exchange: motion_to_all)
            byt = [8.0_dp*(3*size(dom%so_slot) + 6*size(dom%ho_slot) + 3*size(dom%mo_node) + &
                           (wv - 3)*count(dom%mo_rot)), &
                   8.0_dp*6*(size(dom%rotn%node) - dom%rotn%cnt(dom%rank + 1))]
            if (allocated(dom%tie%node)) byt(2) = byt(2) + 8.0_dp*wv*(size(dom%tie%node) - dom%tie%cnt(dom%rank + 1))
            call comm_sum_dp(byt)
            if (ghosts) then
                call log_line(lg, ' owned nodes'' exchange a cycle, all ranks: '//itoa(nint(byt(1)))//' bytes '// &
                              'point-to-point (halo slots and velocities, with the pressure segments'' to every '// &
                              'other rank; the contact ghosts'' come on top, counted at the end of the run), '// &
                              itoa(nint(byt(2)))//' bytes of beam and tie velocities gathered to every rank')
            else
                call log_line(lg, ' owned nodes'' exchange a cycle, all ranks: '//itoa(nint(byt(1)))//' bytes '// &
                              'point-to-point (halo slots and velocities, with the contact surfaces'' and pressure '// &
                              'segments'' to every other rank), '//itoa(nint(byt(2)))//' bytes of beam and tie '// &
                              'velocities gathered to every rank')
            end if
        else
            call log_line(lg, ' nodal state: replicated (XDYNA_REPLICATED set): every rank integrates every node and '// &
                          'the ranks share all nodal forces each cycle')
        end if
    end subroutine choose_owned

    !> Why this run keeps every node's arrays on every rank (owned nodes),
    !> or '' where its nodes can be numbered per rank: each feature named
    !> reads nodes that no element of the rank touches (a contact surface,
    !> a rigid body, a tie, a beam, a pressure segment taken by every rank
    !> alike), or changes the masses or the elements during the run (mass
    !> scaling, thickness updates, erosion), which the per-rank numbering
    !> does not follow yet. (Rigid walls, prescribed motions and body loads
    !> act on each rank's own nodes: they follow it.)
    function whole_nodes_reason(solids, sh, bm, ct, rg, pl, td, ms) result(why)
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        type(beams_t), intent(in) :: bm
        type(contacts_t), intent(in) :: ct
        type(rigid_t), intent(in) :: rg
        type(pressures_t), intent(in) :: pl
        type(ties_t), intent(in) :: td
        type(mass_scaling_t), intent(in) :: ms
        character(len=:), allocatable :: why
        character(len=8) :: env
        integer :: n, stat
        why = ''
        call get_environment_variable('XDYNA_LOCAL_NODES', env, length=n, status=stat)
        if (stat == 0 .and. n > 0 .and. env(1:max(n, 1)) == '0') call add('XDYNA_LOCAL_NODES=0''s asking')
        if (ct%n > 0) call add('contact')
        if (rg%n > 0) call add('rigid bodies')
        if (td%n > 0) call add('tied contacts')
        if (bm%n > 0) call add('beams')
        if (pl%n > 0) call add('pressure loads')
        if (sh%erodible .or. solids%erodible) call add('erosion')
        if (ms%on) call add('mass scaling')
        if (.not. masses_fixed(solids, sh)) call add('masses that change')
    contains
        subroutine add(t)
            character(len=*), intent(in) :: t
            if (len(why) > 0) why = why//', '
            why = why//t
        end subroutine add
    end function whole_nodes_reason

    !> Owned nodes: every node's coordinates and velocities (and angular
    !> velocities), v(n) where given (vminus after the energies), and with `outputs`
    !> the accelerations and forces (and moments: nodout, d3plot), and the
    !> histories' tracked rotations, from the ranks that integrate them: with
    !> `outputs` (a state, a dump) to rank 0, which writes them, else (a
    !> failure's message) to every rank.
    subroutine refresh_nodes(dom, model, st, sh, hist, tm, outputs, vw, vminus, vrminus, state)
        type(domain_t), intent(in) :: dom
        type(model_t), intent(in) :: model
        type(state_t), intent(inout) :: st
        type(shells_t), intent(inout) :: sh
        type(histories_t), intent(inout) :: hist
        type(timers_t), intent(inout) :: tm
        logical, intent(in) :: outputs
        !> nodes numbered per rank: with `outputs`, rank 0's whole view
        !> (every node), which the caller closes; a failure's message takes
        !> none (each rank names the nodes it holds)
        type(node_view_t), intent(inout) :: vw
        real(wp), intent(inout), optional :: vminus(:, :)
        real(wp), intent(inout), allocatable, optional :: vrminus(:, :)
        !> for a state and the histories due with it (not a dump): every
        !> node's coordinates and v(n), the other values of the nodout
        !> nodes alone (open_view's `rest`)
        logical, intent(in), optional :: state
        logical :: slim
        slim = .false.
        if (present(state)) slim = state
        if (dom%local) then
            if (.not. outputs) return
            call tm%start(ph_comm)
            if (slim) then
                call open_view(dom, dom%every, model, st, sh, vminus, vrminus, .true., vw, rest=dom%hist)
            else
                call open_view(dom, dom%every, model, st, sh, vminus, vrminus, .true., vw)
            end if
            call merge_rotations(hist, dom%node_mine)
            call tm%stop(ph_comm)
            return
        end if
        call tm%start(ph_comm)
        ! (an array not allocated, as st%vr without rotations, is passed
        ! as absent: gather_subset)
        ! (a collective a call, up to four arrays each)
        if (outputs) then
            ! (to rank 0 alone, which writes)
            call gather_subset(dom, dom%every, st%x, st%v, st%a, st%f, writer=.true.)
            ! (the prescribed motions' last velocity changes: a dump's)
            if (allocated(st%jprev)) then
                call gather_subset(dom, dom%every, st%jprev, st%vr, st%mom, writer=.true.)
            else if (st%rot) then
                call gather_subset(dom, dom%every, st%vr, st%mom, writer=.true.)
            end if
            if (present(vminus)) call gather_subset(dom, dom%every, vminus, vrminus, writer=.true.)
        else
            call gather_subset(dom, dom%every, st%x, st%v, st%vr)
            if (present(vminus)) call gather_subset(dom, dom%every, vminus, vrminus)
        end if
        if (outputs) call merge_rotations(hist, dom%node_mine)
        call tm%stop(ph_comm)
    end subroutine refresh_nodes

    !> Owned nodes, at a history output without a state: the nodout nodes'
    !> coordinates, velocities (v(n) too), accelerations and forces (and
    !> angular velocities and moments) from their ranks to rank 0, which
    !> writes them, and their tracked rotations (the energies are summed by
    !> rank).
    subroutine refresh_histories(dom, model, st, sh, hist, tm, vw, vminus, vrminus)
        type(domain_t), intent(in) :: dom
        type(model_t), intent(in) :: model
        type(state_t), intent(inout) :: st
        type(shells_t), intent(inout) :: sh
        type(histories_t), intent(inout) :: hist
        type(timers_t), intent(inout) :: tm
        !> nodes numbered per rank: rank 0's view of the nodout nodes, which
        !> the caller closes
        type(node_view_t), intent(inout) :: vw
        real(wp), intent(inout) :: vminus(:, :)
        real(wp), intent(inout), allocatable :: vrminus(:, :)
        if (.not. allocated(dom%hist%node)) return
        if (dom%local) then
            call tm%start(ph_comm)
            call open_view(dom, dom%hist, model, st, sh, vminus, vrminus, .false., vw)
            call merge_rotations(hist, dom%node_mine)
            call tm%stop(ph_comm)
            return
        end if
        call tm%start(ph_comm)
        ! (two collectives: four arrays a call at most)
        ! (to rank 0 alone, which writes)
        call gather_subset(dom, dom%hist, st%x, st%v, st%a, st%f, writer=.true.)
        call gather_subset(dom, dom%hist, vminus, vrminus, st%vr, st%mom, writer=.true.)
        call merge_rotations(hist, dom%node_mine)
        call tm%stop(ph_comm)
    end subroutine refresh_histories

    !> The signals and the wall-clock limit, the same on every rank (MPI:
    !> the largest over the ranks, so all stop at the same cycle). The
    !> wall-clock margin: 10 cycles, 5% of the allowance, twice the last
    !> dump's time, and 0.5 s for the dump, closing the files and the
    !> parallel shutdown. sw: a sense switch of d3kil (rank 0 reads it
    !> every opts%switch_every cycles; sw_none: none).
    subroutine stop_flags(lp, opts, dom, st, lg, tm, sig, limit, status, sw)
        type(loop_t), intent(inout) :: lp
        type(run_options_t), intent(in) :: opts
        type(domain_t), intent(in) :: dom
        type(state_t), intent(in) :: st
        type(log_t), intent(in) :: lg
        type(timers_t), intent(in) :: tm
        integer, intent(out) :: sig
        logical, intent(out) :: limit, status
        integer, intent(out) :: sw
        real(dp) :: fl(4)
        limit = .false.
        sw = sw_none
        if (dom%rank == 0 .and. lp%switch_gone .and. mod(st%cycle, opts%switch_every) == 0) then
            call read_sense_switch(opts%kill_path, 'd3kil', sw, lp%switch_text, lp%switch_gone)
            if (sw /= sw_none) call log_line(lg, ' sense switch "'//lp%switch_text//'" read from d3kil at time '// &
                                             rtoa(st%time)//', cycle '//itoa(st%cycle)//': '//switch_name(sw))
            if (.not. lp%switch_gone) call log_line(lg, ' *** Warning: d3kil could not be deleted; sense '// &
                                                    'switches are no longer read')
            if (sw == sw_unknown) sw = sw_none
        end if
        if (opts%wallclock > 0.0_dp) then
            limit = tm%elapsed() + max(10.0_dp*(tm%elapsed() - lp%t0_wall)/max(st%cycle - lp%cycle0, 1), &
                                       0.05_dp*opts%wallclock, 2.0_dp*lp%t_dump) + 0.5_dp >= opts%wallclock
        end if
        fl = [real(stop_signal(), dp), merge(1.0_dp, 0.0_dp, limit), merge(1.0_dp, 0.0_dp, status_signal()), &
              real(sw, dp)]
        if (dom%on) call comm_max(fl)
        sig = nint(fl(1))
        limit = fl(2) > 0
        status = fl(3) > 0
        sw = nint(fl(4))
    end subroutine stop_flags

    !> The checks that stop a run gone bad (exit 2), on the energies at
    !> t(n): a rigid body turning a radian or more in a step; NaN or
    !> infinite energy; energy lost or gained beyond the ratio's margin;
    !> velocities reversing within a step. Each names a node.
    subroutine energy_check(lp, model, dom, st, solids, sh, rg, ct, pn, en, vn, res, lg)
        type(loop_t), intent(in) :: lp
        type(model_t), intent(in) :: model
        !> (owned nodes: the node a failure names is found over every rank's
        !> own nodes; every rank fails alike, from the same energies)
        type(domain_t), intent(in) :: dom
        type(state_t), intent(in) :: st
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        type(rigid_t), intent(in) :: rg
        type(contacts_t), intent(in) :: ct
        type(prescribed_nodes_t), intent(in) :: pn
        type(energies_t), intent(in) :: en
        real(wp), intent(in) :: vn(:, :)
        type(run_result_t), intent(inout) :: res
        type(log_t), intent(in) :: lg
        integer :: i, k
        !> (no node bad: past every model's last)
        integer, parameter :: none_bad = huge(1) - 1
        ! a rigid body turning a radian or more in one step: no motion the
        ! step resolves (the rotation of a step is the Cayley transform of
        ! omega dt, good for small angles); a prescribed spin of 1e30 rad/s
        ! ran to "normal termination" with nodes at 1e28 m/s
        do k = 1, rg%n
            if (.not. rg%b(k)%active) cycle
            if (norm2(rg%b(k)%omega)*real(st%dt_old, dp) >= 1.0_dp) then
                call fail(res, st, lg, 'impossible state: rigid body '//rigid_name(k)//' turns '// &
                          rtoa(norm2(rg%b(k)%omega)*real(st%dt_old, dp))//' rad in one step (angular '// &
                          'velocity '//rtoa(norm2(rg%b(k)%omega))//'); node '// &
                          node_where(model, solids, sh, rg%b(k)%node(1))//'; a prescribed rotation far beyond its '// &
                          'curve''s intent?')
                return
            end if
        end do
        res%e_scale = max(res%e_scale, abs(st%e_initial + en%ext))
        if (en%total /= en%total .or. abs(en%total) > huge(1.0_wp)) then
            do i = 1, st%nnode
                if (dom%owned) then
                    if (.not. dom%node_mine(i)) cycle
                end if
                if (any(st%v(:, i) /= st%v(:, i)) .or. any(abs(st%v(:, i)) > huge(1.0_wp))) exit
            end do
            ! (the model's number: nodes numbered per rank; none bad: none_bad)
            if (i > st%nnode) then
                i = none_bad
            else
                i = global_node(dom, i)
            end if
            if (dom%owned) i = ranks_pick(real(none_bad - i, dp), i)
            if (i >= none_bad) i = 1
            call fail(res, st, lg, 'energy is NaN or infinite; first bad node '//node_where(model, solids, sh, i))
        else if ((en%ratio < 0.0_dp .or. (en%ratio < 1.0_dp/lp%ratio_limit .and. st%cycle - lp%cycle0 >= 10)) &
                 .and. abs(st%e_initial + en%ext) > 0.0_dp) then
            ! energy lost beyond the margin, or a negative total against a
            ! positive input: no physical state, since walls, contact,
            ! hourglass and damping work are all in the total. The lower
            ! margin holds from the tenth cycle: before, a run loaded from
            ! rest has energies of a few steps' work, whose ratio the
            ! first-order start (v(1/2) = v(0) + a(0) dt/2) sets to
            ! anything (0.50 at cycle 2 of a velocity ramp, 0 at cycle 1
            ! of the contact patch test)
            i = fastest()
            call fail(res, st, lg, 'energy lost: total energy ratio '//ftoa(en%ratio)//' is below '// &
                      ftoa(1.0_dp/lp%ratio_limit)//' (total '//ftoa(en%total)//' against initial energy plus '// &
                      'external work '//ftoa(st%e_initial + en%ext)//'); fastest node '//node_where(model, solids, sh, i))
        else if (en%ratio > lp%ratio_limit) then
            i = fastest()
            call fail(res, st, lg, 'energy blow-up: total energy ratio '//ftoa(en%ratio)//' exceeds '// &
                      ftoa(lp%ratio_limit)//'; fastest node '//node_where(model, solids, sh, i))
        else if (en%ke < -(lp%ratio_limit - 1.0_dp)*abs(st%e_initial + en%ext)) then
            ! 1/2 m v(n-1/2).v(n+1/2) strongly negative: velocities turn
            ! round within a step, by more than the energy ratio's margin
            ! (slightly negative values are normal where nodes turn round).
            ! No physical state: a step beyond the stable limit, a contact
            ! spring too stiff for the step, or a prescribed motion that
            ! reverses within a step at a speed beyond reason. (This was
            ! let pass twice in a row for a stiff block bouncing off a
            ! wall; that block was running beyond its stable step.)
            i = fastest()
            call fail(res, st, lg, 'impossible state: kinetic energy 1/2 m v(n-1/2).v(n+1/2) is '//ftoa(en%ke)// &
                      ', below minus '//ftoa(lp%ratio_limit - 1.0_dp)//' times the initial energy plus '// &
                      'external work ('//ftoa(st%e_initial + en%ext)//'): velocities reverse within a '// &
                      'step; fastest node '//node_where(model, solids, sh, i)//'; '//cause_hint())
        end if
    contains
        !> The node of the largest m v^2 (the first of equals); owned nodes:
        !> over every rank's own.
        integer function fastest() result(nd)
            real(dp), allocatable :: e2(:)
            ! (allocated, not automatic: a model's worth of nodes on the stack)
            allocate (e2(size(st%mass)))
            e2(:) = sum(real(vn, dp)**2, 1)*st%mass
            if (dom%owned) then
                where (.not. dom%node_mine) e2 = -1
                nd = maxloc(e2, 1)
                ! (the model's number: nodes numbered per rank)
                nd = ranks_pick(e2(nd), global_node(dom, nd))
            else
                nd = maxloc(e2, 1)
            end if
        end function fastest

        !> Owned nodes: of every rank's (key, node), the node of the largest
        !> key, the lowest node of equals (a collective).
        integer function ranks_pick(key, nd) result(best)
            real(dp), intent(in) :: key
            integer, intent(in) :: nd
            real(dp) :: all(2, dom%nranks)
            integer :: r, k
            call comm_gather_small([key, real(nd, dp)], all)
            k = 1
            do r = 2, dom%nranks
                if (all(1, r) > all(1, k) .or. (all(1, r) == all(1, k) .and. all(2, r) < all(2, k))) k = r
            end do
            best = nint(all(2, k))
        end function ranks_pick

        !> A rigid body as the deck names it: its part, or its node set's body.
        function rigid_name(kb) result(t)
            integer, intent(in) :: kb
            character(len=:), allocatable :: t
            if (rg%b(kb)%part > 0) then
                t = 'of part '//itoa(model%part(rg%b(kb)%part)%id)
            else
                t = itoa(kb)//' (a node set)'
            end if
        end function rigid_name

        !> What makes velocities reverse within a step, for the message.
        function cause_hint() result(t)
            character(len=:), allocatable :: t
            t = 'a time step beyond the stable limit (TSSFAC too high?)'
            if (ct%n > 0) t = 'a contact penalty scale (SLSFAC, SFS, SFM) too high for the time step, or '//t
            if (pn%n > 0 .or. rg%n > 0) t = t//', or a prescribed motion reversing within a step'
        end function cause_hint
    end subroutine energy_check

    !> The restart dump of the state at the end of this cycle (rank 0
    !> writes it, every rank learns whether it could); a dump that cannot
    !> be written stops the run, the last good one kept.
    subroutine dump_phase(lp, opts, dom, st, solids, sh, bm, walls, rg, ct, td, hist, states, lg, tm, res)
        type(loop_t), intent(inout) :: lp
        type(run_options_t), intent(in) :: opts
        type(domain_t), intent(in) :: dom
        type(state_t), intent(in) :: st
        type(solids_t), intent(inout) :: solids
        type(shells_t), intent(inout) :: sh
        type(beams_t), intent(in) :: bm
        type(walls_t), intent(in) :: walls
        type(rigid_t), intent(in) :: rg
        type(contacts_t), intent(inout) :: ct
        type(ties_t), intent(in) :: td
        type(histories_t), intent(inout) :: hist
        type(states_t), intent(in) :: states
        type(log_t), intent(in) :: lg
        type(timers_t), intent(inout) :: tm
        type(run_result_t), intent(inout) :: res
        logical :: ok
        real(dp) :: t1
        t1 = tm%elapsed()
        call tm%start(ph_output)
        call gather_element_state(dom, solids, sh, energies=.true.)
        ! the dump's history marks count the rows in thist.h5
        call flush_histories(hist)
        ok = .true.
        ! (each surface node's motion bound from its rank: owned nodes keep
        ! their own alone, contact_drift)
        if (allocated(dom%own_contact) .and. ct%n > 0) call gather_drift(ct, dom%own_contact)
        if (dom%on) call gather_contact_state(ct)
        if (dom%rank == 0) call write_dump(opts%dump_path, opts%meta, st, solids, sh, bm, walls, rg, ct, td, &
                                           history_marks(hist), states_marks(states), ok)
        call release_element_view(solids, sh)
        if (dom%on) call scatter_contact_state(ct, dom%rank)
        ! rank 0 wrote it: every rank learns whether it could
        ok = .not. any_rank(dom, .not. ok)
        call tm%stop(ph_output)
        lp%t_dump = tm%elapsed() - t1
        if (ok) then
            call log_line(lg, ' restart dump at cycle '//itoa(st%cycle)//', time '//rtoa(st%time)//': '// &
                          opts%dump_path)
        else
            ! a full disk or a quota: the last good dump stays, and the run
            ! stops rather than go on without a way back
            call fail(res, st, lg, 'cannot write the restart dump '//opts%dump_path//write_failed// &
                      '; the last good dump, if any, is kept')
        end if
    end subroutine dump_phase

    !> The histories due at t(n) and the state where due (or forced: the
    !> run's first and last cycle, or asked by sense switch sw4); a write
    !> that fails (a full disk, a quota, the directory gone) stops the run,
    !> every file keeping its complete records.
    subroutine output_phase(lp, force, model, dom, st, solids, sh, bm, walls, rg, ct, hist, states, en, vn, vrminus, tm, &
                            res, lg)
        type(loop_t), intent(inout) :: lp
        logical, intent(in) :: force
        type(model_t), intent(in) :: model
        type(domain_t), intent(in) :: dom
        type(state_t), intent(in) :: st
        type(solids_t), intent(inout) :: solids
        type(shells_t), intent(inout) :: sh
        type(beams_t), intent(in) :: bm
        type(walls_t), intent(in) :: walls
        type(rigid_t), intent(in) :: rg
        type(contacts_t), intent(in) :: ct
        type(histories_t), intent(inout) :: hist
        type(states_t), intent(inout) :: states
        type(energies_t), intent(in) :: en
        real(wp), intent(in) :: vn(:, :)
        real(wp), intent(in), allocatable :: vrminus(:, :)
        type(timers_t), intent(inout) :: tm
        type(run_result_t), intent(inout) :: res
        type(log_t), intent(in) :: lg
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
        if (st%cycle > 0) ns = 1.0e9_dp*(tm%elapsed() - lp%t0_wall)/(real(st%cycle, dp)*max(solids%n + sh%n, 1))
        ! (the contact forces per node, ct%fnode, absent where no output has
        ! read them yet: an unallocated actual is an absent optional)
        if (ct%n > 0) then
            call write_histories(hist, model, st, solids, walls, rg, en, vn, crit, ns, force, contact_resultants(ct), &
                                 ct%fnode, wminus=vrminus)
        else
            call write_histories(hist, model, st, solids, walls, rg, en, vn, crit, ns, force, wminus=vrminus)
        end if
        if (state_now(lp, states, st%time, force)) then
            ! (the energies and shell thicknesses were gathered with this
            ! cycle's energies, which every output follows)
            if (states_by_ranks(states, dom, sh)) then
                ! (the shells' words made by their ranks, not from a view)
                call gather_element_state(dom, solids, sh, energies=dom%owned, dump=.false., shells=.false.)
                call write_state_by_ranks(states, dom, st, solids, sh, vn, en=en, bm=bm)
            else
                call gather_element_state(dom, solids, sh, energies=dom%owned, dump=.false.)
                call write_state(states, st, model%x0, solids, sh, vn, ct%fnode, en=en, bm=bm)
            end if
            call release_element_view(solids, sh)
            lp%state_asked = .false.
        end if
        call tm%stop(ph_output)
        ! a failed write (a full disk, a quota, the directory gone) stops
        ! the run; every file keeps its complete records
        failed_file = history_failure(hist)
        if (len(failed_file) == 0) failed_file = states_failure(states)
        ! rank 0 writes the files: every rank stops with it
        if (any_rank(dom, len(failed_file) > 0) .and. len(failed_file) == 0) failed_file = 'an output file (on rank 0)'
        if (len(failed_file) > 0) call fail(res, st, lg, 'cannot write '//failed_file//write_failed// &
                                            '; the output files keep every complete record written before')
    end subroutine output_phase

    !> A state is written at t(n): due, forced (the run's first and last
    !> cycle, where states are written at all), or asked by sense switch sw4.
    logical function state_now(lp, states, time, force)
        type(loop_t), intent(in) :: lp
        type(states_t), intent(in) :: states
        real(dp), intent(in) :: time
        logical, intent(in) :: force
        state_now = states_due(states, time) .or. (force .and. states%on) .or. lp%state_asked
    end function state_now

    !> The progress line on standard output: cycle, time, step, share
    !> done, energy ratio, wall time spent and left.
    subroutine progress_line(lp, model, st, opts, tm, en)
        type(loop_t), intent(in) :: lp
        type(model_t), intent(in) :: model
        type(state_t), intent(in) :: st
        type(run_options_t), intent(in) :: opts
        type(timers_t), intent(in) :: tm
        type(energies_t), intent(in) :: en
        real(dp) :: frac, el, left
        character(len=200) :: buf
        el = tm%elapsed() - lp%t0_wall
        frac = min(1.0_dp, st%time/max(opts%endtim, tiny(1.0_dp)))
        if (model%ctl%endcyc > 0) frac = max(frac, min(1.0_dp, real(st%cycle, dp)/model%ctl%endcyc))
        left = 0
        if (frac > 0) left = el*(1.0_dp - frac)/frac
        write (buf, '(a,i9,a,es11.4,a,es10.3,a,f6.1,a,f8.5,a,f9.1,a,f9.1,a)') ' cycle', st%cycle, &
            '  t', st%time, '  dt', st%dt, '  ', 100*frac, '%  ratio', en%ratio, '  elapsed', el, &
            's  left', left, 's'
        write (output_unit, '(a)') trim(buf)
        flush (output_unit)
    end subroutine progress_line

    !> 'node 12 (part 3)': a node and the part of an element on it.
    function node_where(model, solids, sh, i) result(txt)
        type(model_t), intent(in) :: model
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        integer, intent(in) :: i
        character(len=:), allocatable :: txt
        integer :: e
        txt = itoa(model%node_id(i))
        ! (the model's connectivity: the elements' own may be numbered per
        ! rank, and i is the model's number)
        do e = 1, solids%n
            if (any(model%hex_conn(:, solids%model_ix(e)) == i)) then
                txt = txt//' (part '//itoa(model%part(solids%part(e))%id)//')'
                return
            end if
        end do
        do e = 1, sh%n
            if (any(model%shell_conn(:, sh%model_ix(e)) == i)) then
                txt = txt//' (part '//itoa(model%part(sh%part(e))%id)//')'
                return
            end if
        end do
    end function node_where

    !> The run stops in error (exit 2) with `text`.
    subroutine fail(res, st, lg, text)
        type(run_result_t), intent(inout) :: res
        type(state_t), intent(in) :: st
        type(log_t), intent(in) :: lg
        character(len=*), intent(in) :: text
        call end_run(res, st, lg, exit_run, 'error termination', text)
    end subroutine fail

    !> The run ends early with exit status `code`: the message, with the
    !> time and cycle, for the caller and the log.
    subroutine end_run(res, st, lg, code, what, text)
        type(run_result_t), intent(inout) :: res
        type(state_t), intent(in) :: st
        type(log_t), intent(in) :: lg
        integer, intent(in) :: code
        character(len=*), intent(in) :: what, text
        res%status = code
        res%message = what//' at time '//rtoa(st%time)//', cycle '//itoa(st%cycle)//': '//text
        call log_line(lg, '')
        call log_line(lg, ' *** '//res%message)
    end subroutine end_run

end module xd_solver_time_loop
