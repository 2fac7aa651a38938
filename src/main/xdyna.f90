!> xdyna: read a keyword deck, check it, run the explicit time loop, write
!> the log and the time histories. Exit 0 normal, 1 input error, 2 error
!> termination during the run, 3 stopped by a signal (see the manual).
program xdyna
    use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
    use xd_kinds, only: wp, dp, i8
    use xd_core_errors, only: error_t, exit_normal, exit_input, exit_run, exit_signal, printable
    use xd_core_strings, only: to_lower, itoa, ftoa
    use xd_core_parallel_env, only: parallel_env_t, parallel_start, parallel_stop, terminate
    use xd_core_timers, only: timers_t, ph_input, ph_init
    use xd_input_deck_reader, only: read_deck, read_options_t
    use xd_input_context, only: read_ctx_t, add_warning
    use xd_input_field_reader, only: parse_real, parse_int
    use xd_input_model_check, only: check_model, id_maps_t
    use xd_input_keyword_table, only: skip_list_text
    use xd_model, only: model_t, mesh_bytes, release_setup_mesh, release_shell_thickness
    use xd_elements_solid_groups, only: solids_t, stiff_volume_parts
    use xd_solver_state, only: state_t, nodal_bytes
    use xd_solver_assembly, only: assembly_t
    use xd_solver_setup, only: setup_run
    use xd_solver_time_loop, only: run_options_t, run_result_t, run_time_loop
    use xd_contact_rigidwall, only: walls_t, build_walls
    use xd_elements_erosion, only: erode_shells, dead_model_shells, dead_model_hexes
    use xd_elements_beam_bs, only: beams_t
    use xd_contact_tied, only: ties_t, place_ties, start_ties
    use xd_contact_contact, only: contacts_t, build_contacts, interface_summary, contact_report, contact_masses, contact_erode, &
                                  contact_release_setup, &
                                  contact_erode_solids
    use xd_contact_initial_penetration, only: initial_penetrations
    use xd_core_strings, only: join_path, out_path
    use xd_core_files, only: make_dirs, file_kind, fk_missing, fk_regular, absolute_path
    use xd_output_d3plot, only: d3plot_member_name
    use xd_solver_prescribed, only: prescribed_nodes_t, build_prescribed
    use xd_rigid_bodies, only: rigid_t
    use xd_solver_loads, only: pressures_t, build_pressures
    use xd_elements_shell_bt, only: shells_t, shell_state_bytes, shell_bytes
    use xd_elements_solid_groups, only: solid_state_bytes, solid_bytes
    use xd_output_histories, only: histories_t, open_histories, close_histories, history_marks_t
    use xd_output_states, only: states_t, open_states, close_states, states_marks_t, states_summary
    use xd_solver_restart, only: dump_meta_t, read_dump_meta, read_dump, build_tag, dump_format
    use xd_output_h5io, only: h5_no_exit_handler
    use xd_core_signals, only: signals_install, stop_signal, hold_for_signal
    use xd_core_comm, only: comm_max, comm_gather_small, comm_sum_i8
    use xd_core_memory, only: peak_memory_kb, resident_memory_kb, release_free_memory
    use xd_output_d3hsp, only: log_t, log_open, log_line, log_close, model_summary, timing_table
    use xd_solver_domain, only: domain_t, build_domain, domain_summary, decomp_rcb, decomp_metis, localize_element_state, &
                                place_shell_state, domain_bytes
    use xd_contact_contact, only: gather_contact_state, scatter_contact_state, contact_bytes
    !$ use omp_lib, only: omp_set_num_threads, omp_get_num_procs
    implicit none

    type(parallel_env_t) :: env
    type(domain_t) :: dom
    type(read_options_t) :: ropts
    type(run_options_t) :: opts
    type(model_t) :: model
    type(read_ctx_t) :: ctx
    character(len=:), allocatable :: deck_digest
    type(id_maps_t) :: maps
    type(state_t) :: st
    type(solids_t) :: solids
    type(assembly_t) :: asm
    type(walls_t) :: walls
    type(contacts_t) :: ct
    type(prescribed_nodes_t) :: pn
    type(rigid_t) :: rg
    type(pressures_t) :: pl
    type(ties_t) :: td
    type(beams_t) :: bm
    integer, allocatable :: dead_now(:)
    type(shells_t) :: sh
    type(assembly_t) :: asm_sh
    type(histories_t) :: hist
    type(states_t) :: states
    type(log_t) :: lg
    type(timers_t) :: tm
    type(dump_meta_t) :: meta
    type(history_marks_t) :: hmarks
    type(states_marks_t) :: smarks
    character(len=:), allocatable :: dump_error, wall_notes, moved_note, tie_note
    logical :: outdir_given
    real(dp) :: wallclock
    type(run_result_t) :: res
    type(error_t), allocatable :: error
    character(len=:), allocatable :: deck, outdir, arg, restart, printed, jobid, stem
    logical :: check_only, ok
    character(len=:), allocatable :: memory_note, hold, step_note, why
    real(dp) :: endtim_cli
    !> the process's peak before the deck is read (libraries, MPI's
    !> buffers and shared segments): the floor under every rank's peak
    integer(i8) :: floor_kb
    integer :: i, k, ncpu, nfree, nparts, endcyc_cli, nmoved, nprocs, decomp
    character(len=:), allocatable :: bad_out
    !> the files a run writes in its output directory (besides d3hsp and
    !> the d3plot members)
    character(len=13), parameter :: out_names(11) = [character(len=13) :: 'glstat', 'matsum', 'nodout', &
        'rwforc', 'rcforc', 'thist.h5', 'd3plot', 'd3plot.h5', 'd3plot.xdmf', 'd3dump.h5', 'contact_debug']
    integer :: h5plot                !< h5plot= (or XDYNA_H5PLOT): 1 also d3plot.h5, 0 not, -1 the deck's
    integer :: xfactor               !< x=: d3plot member size in 262,144 words (0: the deck's)

    ! the batch signals count from the first instruction, before the
    ! parallel start-up: a SIGTERM during set-up stops the run cleanly
    ! (exit 3, no dump: there is no state yet)
    call signals_install()
    call h5_no_exit_handler()
    hold = get_env('XDYNA_HOLD_AT')
    if (hold == 'start') call hold_for_signal(' held at start (XDYNA_HOLD_AT): waiting for a signal', 120.0, .true.)
    call tm%begin()
    ! (MPI's start-up, about 0.3 s on two ranks here, counts with the
    ! input: the phases sum to the run's wall time)
    call tm%start(ph_input)
    call parallel_start(env)
    deck = ''
    outdir = '.'
    printed = ''
    memory_note = ''
    jobid = ''
    restart = ''
    check_only = .false.
    endtim_cli = -1.0_dp
    ncpu = 0
    nparts = 0
    decomp = decomp_rcb
    endcyc_cli = 0
    outdir_given = .false.
    wallclock = 0
    h5plot = -1
    xfactor = 0
    call wallclock_env()
    call h5plot_env()
    do i = 1, command_argument_count()
        arg = get_arg(i)
        select case (to_lower(arg))
        case ('--help', '-h')
            if (env%rank == 0) call usage()
            call finish(exit_normal)
        case ('--version')
            if (env%rank == 0) write (output_unit, '(a)') 'xdyna 0.1.0'
            call finish(exit_normal)
        case ('--check')
            check_only = .true.
        case default
            call keyword_arg(arg)
        end select
    end do
    if (len(restart) > 0) then
        ! a restart: the dump names its deck and output directory, and must
        ! come from this build
        call read_dump_meta(restart, meta, ok)
        why = ''
        if (len(meta%damage) > 0) then
            why = 'the dump '//meta%damage
        else if (.not. ok) then
            why = 'not a readable restart dump (not an HDF5 file, or damaged)'
        else if (meta%format == 0 .or. len(meta%build) == 0) then
            why = 'the dump is damaged or is not an xdyna dump (its format and build records cannot be read)'
        else if (meta%format /= dump_format .or. meta%build /= build_tag()) then
            why = 'the dump was written by another build ('//meta%build//', format '//itoa(meta%format)// &
                  '); this is '//build_tag()//', format '//itoa(dump_format)
        end if
        call stop_if_any('xdyna: r='//restart//': ', why)
        if (len(deck) == 0) deck = meta%deck
        if (.not. outdir_given) outdir = meta%outdir
    end if
    if (len(deck) == 0) then
        call say('xdyna: no input deck (i=deck.k); see xdyna --help')
        call finish(exit_input)
    end if
    !$ if (ncpu > 0) call omp_set_num_threads(ncpu)
    !$ if (ncpu > 0) env%nthreads = ncpu
    stem = outdir
    if (len(jobid) > 0) stem = join_path(outdir, jobid//'.')

    if (.not. check_only .and. env%rank == 0) then
        ! created by the C library: no shell ever sees the name
        call make_dirs(outdir, ok)
        if (.not. ok) then
            call say('xdyna: cannot create the output directory '''//outdir//'''')
            call finish_alone(exit_input)
        end if
        if (len(printed) == 0) printed = out_path(stem, 'd3hsp')
        ! an output that exists and is not a regular file (a FIFO, a device)
        ! would block the run at its open, beyond the reach of signals
        bad_out = not_a_file(printed)
        do k = 1, size(out_names)
            if (len(bad_out) == 0) bad_out = not_a_file(out_path(stem, trim(out_names(k))))
        end do
        do k = 1, 99
            if (len(bad_out) == 0) bad_out = not_a_file(d3plot_member_name(out_path(stem, 'd3plot'), k))
        end do
        if (len(bad_out) > 0) then
            call say('xdyna: the output '//bad_out//' exists and is not a regular file (a FIFO, a device, a '// &
                     'socket or a directory); remove it or choose another outdir=')
            call finish_alone(exit_input)
        end if
        call log_open(printed, lg, ok, append=len(restart) > 0)
        if (.not. ok) then
            call say('xdyna: cannot write the log in '//outdir)
            call finish_alone(exit_input)
        end if
        if (len(restart) > 0) then
            call log_line(lg, '')
            call log_line(lg, ' R e s t a r t   from '//restart//' at cycle '//itoa(meta%cycle))
        end if
        call log_line(lg, ' command line: xdyna i='//deck//' outdir='//outdir)
        if (len(jobid) > 0) call log_line(lg, ' jobid='//jobid//': every output file is named '//jobid//'.<file>')
        if (len(memory_note) > 0) call log_line(lg, memory_note)
        if (env%mpi) then
            call log_line(lg, ' ranks '//itoa(env%nranks)//', threads per rank '//itoa(env%nthreads))
        else
            call log_line(lg, ' ranks 1, threads per rank '//itoa(env%nthreads)// &
                          ' (no MPI launcher: MPI not started; XDYNA_MPI=1 starts it)')
        end if
    end if

    floor_kb = peak_memory_kb()
    call read_deck(deck, ropts, model, ctx, error)
    if (.not. allocated(error)) call check_model(ctx, model, maps, error)
    ! the command line's choices of state files over the deck's
    if (h5plot >= 0) model%db%d3plot_h5 = h5plot == 1
    if (xfactor > 0) model%db%d3plot_x = xfactor
    if (allocated(error)) then
        call say(error%message)
        call log_line(lg, ' *** Error: '//error%message)
        call log_line(lg, ' E r r o r   t e r m i n a t i o n   (input)')
        call finish(exit_input)
    end if
    call tm%stop(ph_input)
    call stop_before_run('reading the input')
    if (len(restart) > 0) then
        if (ctx%src%digest() /= meta%digest) then
            call say('xdyna: r='//restart//': the deck '//deck//' has changed since the dump '// &
                '(fingerprint '//ctx%src%digest()//', the dump''s '//meta%digest//'); a restart needs the same deck')
            call log_line(lg, ' *** Error: the deck has changed since the dump')
            call finish(exit_input)
        end if
    end if
    ! (the deck's fingerprint for the dumps; its text no longer needed)
    deck_digest = ctx%src%digest()
    call ctx%src%release()

    call tm%start(ph_init)
    ! tied contacts: slave nodes placed on their master surfaces (model%x0)
    ! before the mesh is set up
    call place_ties(model, td, tie_note, error)
    call stop_on_input_error()
    if (len(tie_note) > 0) call log_line(lg, tie_note)
    ! the mesh set up; then IGNORE 0: slave nodes moved out of initial
    ! penetrations (the moves named in d3hsp), and the mesh set up again
    ! from the moved nodes
    do i = 1, 2
        call setup_run(model, maps%hex, st, solids, asm, rg, sh, asm_sh, bm, nfree, error, step_note)
        if (allocated(error)) then
            call say(model%deck_path//': '//error%message)
            call log_line(lg, ' *** Error: '//model%deck_path//': '//error%message)
            call finish(exit_input)
        end if
        if (i == 2) exit
        call initial_penetrations(model, st%v, st%mass, env%rank, env%nranks, moved_note, nmoved, error)
        ! (the pass's whole contact, freed, back to the system: the
        ! allocator kept it, and the run's contact and decomposition came
        ! on top of it, the set-up's peak)
        call release_free_memory()
        call stop_on_input_error()
        if (len(moved_note) > 0) call log_line(lg, moved_note)
        if (nmoved == 0) exit
    end do
    ! (the ids' maps: the set-up's alone, released)
    maps = id_maps_t()
    if (len(step_note) > 0) call add_warning(model, step_note)
    call start_ties(model, td, rg%member, model%x0, st%mass, st%v, st%vr, st%irot, tie_note, error)
    call stop_on_input_error()
    if (len(tie_note) > 0) call log_line(lg, tie_note)
    call build_walls(model, model%x0, walls, wall_notes)
    do while (len(wall_notes) > 0)
        i = index(wall_notes, new_line('a'))
        call add_warning(model, wall_notes(1:i - 1))
        wall_notes = wall_notes(i + 1:)
    end do
    call build_contacts(model, model%x0, ct, error)
    call stop_on_input_error()
    ! (the model's faces and the surfaces' set-up springs: kept only where
    ! erosion or a followed shell thickness rebuilds the surfaces; released
    ! before the slaves' state is allocated, the set-up's peak)
    call contact_release_setup(ct, sh%erodible .or. solids%erodible)
    ! (the slaves' contact state: allocated by the time loop, in the rows of
    ! the rank's own slaves once the decomposition has chosen them, not
    ! every slave's here, the set-up's peak; a restart reads every slave's
    ! from the dump first)
    if (ct%n > 0) call contact_masses(ct, st%mass, rows_later=len(restart) == 0)
    ! a cohesive tiebreak's springs bound the step as the contact's do (its
    ! sliding contact is always there)
    if (ct%n > 0 .and. td%dt_limit < ct%dt_limit) then
        ct%dt_limit = td%dt_limit
        ct%dt_node = td%dt_node
    end if
    call build_prescribed(model, pn)
    call build_pressures(model, pl)
    ! (the shells' nodal thicknesses: the set-up's alone, their means kept)
    call release_shell_thickness(model)
    ! a pressure on a node without mass would push nothing (it is held
    ! fixed): a deck error, not a run
    do i = 1, pl%n
        if (any(st%mass(pl%seg(:, i)) <= 0.0_wp)) then
            k = pl%seg(minloc(st%mass(pl%seg(:, i)), 1), i)
            call say('xdyna: '//model%deck_path//': a pressure load (*LOAD_SEGMENT or *LOAD_SHELL) acts on node '// &
                     itoa(model%node_id(k))//', which belongs to no element (no mass)')
            call log_line(lg, ' *** Error: a pressure load acts on node '//itoa(model%node_id(k))//' without mass')
            call finish(exit_input)
        end if
    end do
    if (nfree > 0) call add_warning(model, itoa(nfree)//' nodes belong to no element (massless; held fixed)')
    do i = 1, size(stiff_volume_parts(solids))
        associate (p => model%part(stiff_volume_parts(solids)))
            call add_warning(model, 'part '//itoa(p(i)%id)//' is nearly incompressible (nu '// &
                             ftoa(real(model%mat(p(i)%mat_ix)%pr, dp))//') under viscous hourglass control: '// &
                             'its hourglass damping grows with the dilatational wave speed (a nu 0.4999 block '// &
                             'bouncing off a wall put 25% of its energy into hourglass work in 3 ms at QM 0.1, '// &
                             '1% under IHQ 4); a stiffness form (*CONTROL_HOURGLASS IHQ 4 to 6) keeps it small')
        end associate
    end do
    if (check_only) then
        if (env%rank == 0) then
            write (output_unit, '(a)') model_summary(model, solids, rg%n)
            if (nparts > 0) then
                ! the decomposition a run on nparts ranks makes
                call build_domain(model, model%x0, solids, sh, asm, asm_sh, ct, 0, nparts, dom, decomp, alone=.true.)
                write (output_unit, '(a)') domain_summary(dom)
            end if
            write (output_unit, '(a)') ' xdyna --check: input is valid; nothing was run'
        end if
        call finish(exit_normal)
    end if
    call stop_before_run('setting up the model')
    call build_domain(model, model%x0, solids, sh, asm, asm_sh, ct, env%rank, env%nranks, dom, decomp)
    ! the shells' points' state and slots: each rank's own shells' alone
    call place_shell_state(dom, sh, asm_sh)
    if (dom%on) call log_line(lg, domain_summary(dom))
    call log_line(lg, model_summary(model, solids, rg%n))
    if (ct%n > 0) then
        call log_line(lg, interface_summary(ct, model))
        if (model%ctl%contact%dump_nsid > 0 .and. env%rank == 0) then
            open (newunit=ct%dump_unit, file=out_path(stem, 'contact_debug'), status='replace', action='write')
        end if
    end if
    if (endcyc_cli > 0) model%ctl%endcyc = endcyc_cli
    opts%endtim = real(model%ctl%endtim, dp)
    if (endtim_cli > 0.0_dp) opts%endtim = endtim_cli
    if (opts%endtim <= 0.0_dp) opts%endtim = huge(1.0_dp)
    if (len(restart) > 0) then
        call read_dump(restart, st, solids, sh, bm, walls, rg, ct, td, hmarks, smarks, dump_error)
        why = ''
        if (allocated(dump_error)) why = 'cannot restart from this dump: '//dump_error
        call stop_if_any('xdyna: r='//restart//': ', why)
        if (dom%on) call scatter_contact_state(ct, env%rank)
        ! shells eroded before the dump: out of the element loops and the
        ! contact's surfaces again
        if (sh%n > 0) then
            if (any(sh%dead)) then
                dead_now = pack([(i, i=1, sh%n)], sh%dead)
                sh%dead = .false.
                sh%ndead = 0
                call erode_shells(sh, dead_now)
                if (ct%n > 0) call contact_erode(ct, dead_model_shells(sh, model%nshell))
            end if
        end if
        ! solids eroded before the dump: the faces they exposed on the contact
        ! surfaces again
        ! (the searches asked for and the stable step as the dump has them)
        if (solids%erodible .and. ct%n > 0) then
            if (any(solids%dead)) call contact_erode_solids(ct, model%hex_conn(:, 1:model%nhex), &
                                                            dead_model_hexes(solids, model%nhex), st%x, restart=.true.)
        end if
        call open_histories(model, stem, rg, hist, ok, resume=hmarks, writer=env%rank == 0, rotating=st%rot)
    else
        call open_histories(model, stem, rg, hist, ok, writer=env%rank == 0, rotating=st%rot)
    end if
    ! (the solids' state, whole as set up or read from the dump: from here
    ! each rank keeps its own groups')
    call localize_element_state(dom, solids, asm)
    if (.not. ok) then
        call say('xdyna: cannot create the time-history files in '//outdir)
        call finish_alone(exit_run)
    end if
    if (len(restart) > 0) then
        call open_states(model, stem, opts%endtim, solids, sh, states, ok, resume=smarks, writer=env%rank == 0, bm=bm)
    else
        call open_states(model, stem, opts%endtim, solids, sh, states, ok, writer=env%rank == 0, bm=bm)
    end if
    ! restart dumps: every N cycles and at the end if the deck asks, and
    ! always on a stop signal or the wall-clock limit
    if (len(hold) > 0 .and. hold /= 'start') then
        ! cycles, comma-separated
        allocate (opts%hold_cycles(0))
        do while (len(hold) > 0)
            i = index(hold//',', ',')
            call parse_int(hold(1:i - 1), k, ok)
            if (ok) opts%hold_cycles = [opts%hold_cycles, k]
            hold = hold(min(i + 1, len(hold) + 1):)
        end do
    end if
    opts%dump_every = model%db%d3dump
    opts%wallclock = wallclock
    opts%dump_path = out_path(stem, 'd3dump.h5')
    opts%kill_path = out_path(stem, 'd3kil')
    ! absolute: a restart started from another directory finds them
    opts%meta%deck = absolute_path(deck)
    opts%meta%digest = deck_digest
    opts%meta%outdir = absolute_path(outdir)
    if (.not. ok) then
        call say('xdyna: cannot create the states (d3plot'//trim(merge(', d3plot.h5', '           ', &
                 model%db%d3plot_h5))//') in '//outdir)
        call finish_alone(exit_run)
    end if
    ! (the nodes' constraint codes: the set-up's and the summary's alone)
    call release_setup_mesh(model)
    call tm%stop(ph_init)

    opts%progress = env%rank == 0
    call run_time_loop(model, dom, st, solids, asm, sh, asm_sh, bm, walls, ct, pn, rg, pl, td, hist, states, lg, tm, opts, res)
    if (env%rank == 0 .and. states%on) call log_line(lg, states_summary(states))
    call close_states(states)
    call close_histories(hist)
    if (dom%ghosts) call log_line(lg, ' contact ghosts (rank 0): lists made '//itoa(dom%nrefresh)// &
                                  ' times (each search and the start), '//itoa(nint(real(dom%ghost_out_sum, dp)/ &
                                  max(dom%nrefresh, 1)))//' surface nodes sent to the other ranks a list on '// &
                                  'average, '//itoa(dom%nghost_out)//' in the last (of '// &
                                  itoa(size(dom%csurf%node))//' surface nodes); at a search it sent '// &
                                  itoa(nint(real(dom%search_sent, dp)/max(dom%nsearch_ex, 1)))//' of its own '// &
                                  'surface nodes to the ranks whose slaves'' search reaches them, on average over '// &
                                  itoa(dom%nsearch_ex)//' searches; between searches its local '// &
                                  'search gathers '//itoa(sum([(size(ct%ifc(i)%fresh), i=1, ct%n)]))//' of its '// &
                                  'surfaces'' '//itoa(sum(ct%ifc(:)%surf%nnode))//' nodes a cycle (those it moves), '// &
                                  'and it applied '//ftoa(100*real(ct%npair_applied, dp)/real(max(ct%npair_all, 1_i8), dp))// &
                                  '% of the contact pairs its cycles listed (another rank''s slave''s pair only where it '// &
                                  'reaches a node this rank moves or an output reads the contact forces)')
    if (dom%check_search) call log_line(lg, ' contact ghosts checked (XDYNA_CHECK_GHOSTS=1) at '// &
                                        itoa(dom%nsearch_ex)//' searches against every surface node from its '// &
                                        'rank: '//itoa(int(dom%search_check(1)))//' surface nodes checked, '// &
                                        itoa(int(dom%search_check(2)))//' held current but not their rank''s, '// &
                                        itoa(int(dom%search_check(3)))//' master nodes within a rank''s search '// &
                                        'box not held current')
    if (dom%on .and. ct%n > 0) call exchange_line()
    if (dom%on .and. ct%n > 0) call gather_contact_state(ct, counters_only=.true.)
    if (ct%n > 0) call log_line(lg, contact_report(ct, max(abs(st%e_initial), res%e_scale)))
    if (ct%dump_unit /= 0) close (ct%dump_unit)
    call memory_line()
    call timing_table(lg, tm, res%ncycle, solids%n + sh%n, tm%elapsed())
    if (res%status == exit_signal) then
        call say('xdyna: '//res%message)
        call log_line(lg, ' S t o p p e d   (restart with xdyna r='//opts%dump_path//')')
        call finish(res%status)
    else if (res%status /= exit_normal) then
        call say('xdyna: '//res%message)
        call log_line(lg, ' E r r o r   t e r m i n a t i o n')
        call finish(res%status)
    end if
    if (env%rank == 0) write (output_unit, '(a)') ' normal termination: '//itoa(res%ncycle)//' cycles; output in '//outdir
    call finish(exit_normal)

contains

    !> d3hsp's line on the peak resident memory (VmHWM) of each rank: the
    !> smallest and the largest, with their ranks (a collective: every rank
    !> calls it).
    !> d3hsp: the contacts found, exchanged between the ranks each cycle
    !> (records of 19 numbers, 152 bytes), summed over the ranks: to the
    !> ranks that integrate a contact's nodes alone, or (where an output
    !> read every pair: a state, nodout, rcforc; the Lagrangian
    !> projection; no contact ghosts) to every other rank.
    subroutine exchange_line()
        integer(i8) :: t(5)
        t = [ct%sent_p2p, ct%sent_all, ct%ncyc_p2p, ct%ncyc_all, sum(ct%ifc(:)%ncand)]
        call comm_sum_i8(t)
        ! (each rank counts the same exchanges; the candidates' cycles: a
        ! rank's mean)
        t(3:5) = t(3:5)/env%nranks
        call log_line(lg, ' contacts exchanged between the ranks (each interface''s, a cycle): '// &
                      itoa(int(t(3)))//' times each contact found to its nodes'' ranks alone, '// &
                      itoa(nint(152*real(t(1), dp)/max(t(3), 1_i8)))//' bytes sent a time over all ranks; '// &
                      itoa(int(t(4)))//' times every contact to every rank (an output read every pair, or no '// &
                      'contact ghosts), '//itoa(nint(152*real(t(2), dp)/max(t(4), 1_i8)))//' bytes a time; '// &
                      'the pairs listed from a rank''s own and received slaves alone (not every slave) '// &
                      itoa(int(t(5)))//' times (a rank''s mean)')
    end subroutine exchange_line

    subroutine memory_line()
        real(dp) :: rec(13), all(13, env%nranks)
        integer(i8) :: csplit(5)
        rec(1) = real(peak_memory_kb(), dp)
        rec(8) = real(floor_kb, dp)
        rec(2) = real(shell_state_bytes(sh) + solid_state_bytes(solids), dp)
        ! (every element's, as one rank holds them)
        rec(3) = real(shell_state_bytes(sh, every=.true.) + solid_state_bytes(solids, every=.true.), dp)
        ! (at the end: what the run held, the set-up's peak past)
        rec(4) = real(resident_memory_kb(), dp)
        ! every nodal array and every array of the elements this rank holds
        ! (with the time loop's own per-node arrays, the energies' tables and
        ! the decomposition's per-node, per-element and per-slot lists)
        rec(5) = real(nodal_bytes(st) + shell_bytes(sh) + solid_bytes(solids) + res%node_bytes + domain_bytes(dom), dp)
        ! the deck's node and element arrays, whole on every rank
        rec(6) = real(mesh_bytes(model), dp)
        ! the contact's (its faces, surfaces, lists and per-slave records)
        rec(7) = real(contact_bytes(ct, csplit), dp)
        rec(9:13) = real(csplit, dp)
        if (env%nranks > 1) then
            call comm_gather_small(rec, all)
        else
            all(:, 1) = rec
        end if
        ! the elements' state (the solids' stresses, volumes, hourglass
        ! forces; the shells' points' stresses, plastic strains and
        ! hourglass forces) and force slots: most of an element's memory;
        ! each rank holds its own elements' and its halo's slots (issue 32)
        if (sh%n + solids%n > 0) then
            if (env%nranks == 1) then
                call log_line(lg, ' elements'' state and force slots (stresses, strains, hourglass and nodal forces) ... '// &
                              ftoa(all(2, 1)/1048576.0_dp)//' MB')
            else
                call log_line(lg, ' elements'' state and force slots per rank ... '//span(all(2, :), 1048576.0_dp)// &
                              ', each rank its own elements'' and its halo''s slots (all elements'': '// &
                              ftoa(maxval(all(3, :))/1048576.0_dp)//' MB)')
            end if
        end if
        ! the nodal arrays (the rank's own and halo nodes' where they are
        ! numbered per rank, else every node's) and the elements' (the state and slots above,
        ! the connectivity, energies, blocks and flags, the parts' constants)
        call figure(' nodal and element arrays ............ ', ' nodal and element arrays per rank ... ', all(5, :), &
                    1048576.0_dp, '')
        ! (not in the figure above: the deck's own arrays, which every rank
        ! holds whole)
        call figure(' the deck''s node and element arrays .. ', ' the deck''s node and element arrays per rank ', all(6, :), &
                    1048576.0_dp, ' (every rank holds them whole)')
        ! (the contact's arrays at the end of the run: its lists as the
        ! last search left them)
        if (ct%n > 0) then
            call figure(' contact arrays at the end ............ ', ' contact arrays at the end per rank ... ', &
                        all(7, :), 1048576.0_dp, '')
            ! (by kind, the largest rank's each)
            call log_line(lg, '   of them (MB'//trim(merge(', the largest rank''s', '                    ', &
                          env%nranks > 1))//'): surfaces and faces '//ftoa(maxval(all(9, :))/1048576.0_dp)// &
                          ', the slaves'' records '//ftoa(maxval(all(10, :))/1048576.0_dp)//', search lists '// &
                          ftoa(maxval(all(11, :))/1048576.0_dp)//', surface nodes'' masses, motion bounds and '// &
                          'gathers '//ftoa(maxval(all(12, :))/1048576.0_dp)//', contact forces per node and part '// &
                          'pairs '//ftoa(maxval(all(13, :))/1048576.0_dp))
        end if
        if (any(all(1, :) < 0.0_dp)) return
        call figure(' peak memory (VmHWM) ................. ', ' peak memory per rank (VmHWM) ........ ', all(1, :), 1024.0_dp, '')
        ! (what no split of the model can take away: the process as it was
        ! before the deck)
        if (minval(all(8, :)) >= 0.0_dp) &
            call figure('   of it, the process before the deck ', '   of it, the process before the deck ', all(8, :), &
                        1024.0_dp, '')
        if (any(all(4, :) < 0.0_dp)) return
        call figure(' resident memory at the end (VmRSS) .. ', ' resident memory at the end per rank (VmRSS) ', all(4, :), &
                    1024.0_dp, '')
    end subroutine memory_line

    !> d3hsp's memory line of a figure: on one rank its value, on more the
    !> ranks' smallest and largest (span), `tail` after them.
    subroutine figure(one, per_rank, per, unit, tail)
        character(len=*), intent(in) :: one, per_rank, tail
        real(dp), intent(in) :: per(:)   !< per rank
        real(dp), intent(in) :: unit
        if (env%nranks == 1) then
            call log_line(lg, one//ftoa(per(1)/unit)//' MB')
        else
            call log_line(lg, per_rank//span(per, unit)//tail)
        end if
    end subroutine figure

    !> A figure's smallest and largest over the ranks (per, in MB units of
    !> `unit`), with their ranks: 'a MB (rank i) to b MB (rank j)'.
    function span(per, unit) result(t)
        real(dp), intent(in) :: per(:), unit
        character(len=:), allocatable :: t
        integer :: lo, hi
        lo = minloc(per, 1)
        hi = maxloc(per, 1)
        t = ftoa(per(lo)/unit)//' MB (rank '//itoa(lo - 1)//') to '//ftoa(per(hi)/unit)//' MB (rank '//itoa(hi - 1)//')'
    end function span

    !> `path` when it exists and is not a regular file, else ''.
    function not_a_file(path) result(t)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: t
        integer :: kind
        kind = file_kind(path)
        t = ''
        if (kind /= fk_missing .and. kind /= fk_regular) t = path
    end function not_a_file

    function get_arg(k) result(a)
        integer, intent(in) :: k
        character(len=:), allocatable :: a
        integer :: n
        call get_command_argument(k, length=n)
        allocate (character(len=n) :: a)
        call get_command_argument(k, a)
    end function get_arg

    !> An environment variable's value ('' if unset).
    function get_env(name) result(v)
        character(len=*), intent(in) :: name
        character(len=:), allocatable :: v
        integer :: n, st
        call get_environment_variable(name, length=n, status=st)
        if (st /= 0 .or. n == 0) then
            v = ''
            return
        end if
        allocate (character(len=n) :: v)
        call get_environment_variable(name, v, status=st)
    end function get_env

    !> name=value arguments, LS-DYNA style.
    !> XDYNA_WALLCLOCK (seconds), as wallclock= (the command line wins).
    subroutine wallclock_env()
        character(len=64) :: v
        integer :: n, st
        logical :: good
        call get_environment_variable('XDYNA_WALLCLOCK', v, length=n, status=st)
        if (st /= 0 .or. n == 0) return
        call parse_real(trim(v), wallclock, good)
        if (.not. good .or. wallclock <= 0.0_dp) then
            call say('xdyna: XDYNA_WALLCLOCK='//trim(v)//' is not a positive number of seconds')
            call finish(exit_input)
        end if
    end subroutine wallclock_env

    !> XDYNA_H5PLOT (0 or 1), as h5plot= (the command line wins).
    subroutine h5plot_env()
        character(len=64) :: v
        integer :: n, st
        call get_environment_variable('XDYNA_H5PLOT', v, length=n, status=st)
        if (st /= 0 .or. n == 0) return
        call set_h5plot('XDYNA_H5PLOT', trim(v))
    end subroutine h5plot_env

    !> h5plot from a 0 or 1 (what: where it was given, for the message).
    subroutine set_h5plot(what, val)
        character(len=*), intent(in) :: what, val
        select case (val)
        case ('0'); h5plot = 0
        case ('1'); h5plot = 1
        case default
            call say('xdyna: '//what//'='//val//' must be 0 or 1')
            call finish(exit_input)
        end select
    end subroutine set_h5plot

    subroutine keyword_arg(a)
        character(len=*), intent(in) :: a
        integer :: k
        character(len=:), allocatable :: key, val
        logical :: good
        k = index(a, '=')
        if (k == 0) then
            call say('xdyna: unknown argument '''//a//'''; see xdyna --help')
            call finish(exit_input)
        end if
        key = to_lower(a(1:k - 1))
        val = a(k + 1:)
        select case (key)
        case ('i')
            deck = val
        case ('outdir')
            outdir = val
            outdir_given = .true.
        case ('o')
            ! LS-DYNA's o=: the printed-output file (our d3hsp)
            if (len(val) == 0) then
                call say('xdyna: o= needs a file name (the printed output, d3hsp)')
                call finish(exit_input)
            end if
            printed = val
        case ('jobid')
            if (len(val) == 0 .or. scan(val, '/ ') > 0) then
                call say('xdyna: jobid='//val//' must be a name without / or blanks (the output files'' prefix)')
                call finish(exit_input)
            end if
            jobid = val
        case ('memory', 'memory2')
            ! LS-DYNA's memory sizes (words, or with k/m/g): xdyna allocates
            ! what the model needs; the value is checked and noted in d3hsp
            if (.not. memory_size(val)) then
                call say('xdyna: '//key//'='//val//' is not a memory size (a number of words, or with k, m or g)')
                call finish(exit_input)
            end if
            memory_note = memory_note//' '//key//'='//val//' accepted and not needed: xdyna allocates what '// &
                          'the model needs'
        case ('ncpu')
            ! ncpu=-N: LS-DYNA's consistent-results mode on N threads;
            ! xdyna's results do not depend on the thread count anyway
            call parse_int(val, ncpu, good)
            if (.not. good .or. ncpu == 0) then
                call say('xdyna: ncpu='//val//' is not a non-zero integer (N threads; -N: the same, consistent)')
                call finish(exit_input)
            end if
            ncpu = abs(ncpu)
            ! a thread count far beyond the machine's processors only costs
            ! memory (a stack and work arrays each): 100,000 crashed the run
            nprocs = 1
            !$ nprocs = omp_get_num_procs()
            if (ncpu > max(64, 8*nprocs)) then
                call say('xdyna: ncpu='//val//' is more than 8 times the '//itoa(nprocs)//' processors here '// &
                         '(at most '//itoa(max(64, 8*nprocs))//' threads)')
                call finish(exit_input)
            end if
        case ('wallclock')
            call parse_real(val, wallclock, good)
            if (.not. good .or. wallclock <= 0.0_dp) then
                call say('xdyna: wallclock='//val//' is not a positive number of seconds')
                call finish(exit_input)
            end if
        case ('r')
            restart = val
        case ('h5plot')
            ! the states also (1) or not (0) in d3plot.h5 + d3plot.xdmf
            call set_h5plot('h5plot', val)
        case ('x')
            ! LS-DYNA's x=: the d3plot family's member size, in 262,144 words
            call parse_int(val, xfactor, good)
            if (.not. good .or. xfactor < 1 .or. xfactor > 8191) then
                call say('xdyna: x='//val//' is not an integer from 1 to 8191 (d3plot member size in 262,144 words)')
                call finish(exit_input)
            end if
        case ('endtim')
            call parse_real(val, endtim_cli, good)
            if (.not. good .or. endtim_cli <= 0.0_dp) then
                call say('xdyna: endtim='//val//' is not a positive number')
                call finish(exit_input)
            end if
        case ('endcyc')
            ! *CONTROL_TERMINATION's ENDCYC from the command line (the deck's
            ! is replaced): stop after this many cycles
            call parse_int(val, endcyc_cli, good)
            if (.not. good .or. endcyc_cli <= 0) then
                call say('xdyna: endcyc='//val//' is not a positive integer')
                call finish(exit_input)
            end if
        case ('parts')
            call parse_int(val, nparts, good)
            if (.not. good .or. nparts < 1) then
                call say('xdyna: parts='//val//' is not a positive integer')
                call finish(exit_input)
            end if
        case ('decomp')
            ! the MPI ranks' element decomposition
            select case (to_lower(val))
            case ('rcb'); decomp = decomp_rcb
            case ('metis'); decomp = decomp_metis
            case default
                call say('xdyna: decomp='//val//' must be rcb or metis')
                call finish(exit_input)
            end select
        case ('unsupported')
            select case (to_lower(val))
            case ('warn'); ropts%warn_unsupported = .true.
            case ('error'); ropts%warn_unsupported = .false.
            case default
                call say('xdyna: unsupported='//val//' must be error or warn')
                call finish(exit_input)
            end select
        case default
            call say('xdyna: unknown argument '''//a//'''; see xdyna --help')
            call finish(exit_input)
        end select
    end subroutine keyword_arg

    !> A memory size as LS-DYNA takes it: digits, optionally one of k m g.
    logical function memory_size(v)
        character(len=*), intent(in) :: v
        integer :: n
        n = len_trim(v)
        memory_size = n > 0
        if (.not. memory_size) return
        if (scan(to_lower(v(n:n)), 'kmg') > 0) n = n - 1
        memory_size = n > 0
        if (memory_size) memory_size = verify(v(1:n), '0123456789') == 0
    end function memory_size

    subroutine usage()
        write (output_unit, '(a)') &
            'usage: xdyna i=deck.k [outdir=DIR] [o=FILE] [jobid=NAME] [endtim=T] [endcyc=N] [ncpu=N|-N]', &
            '             [memory=SIZE] [memory2=SIZE] [wallclock=S] [r=DUMP] [unsupported=error|warn]', &
            '             [decomp=rcb|metis]', &
            '       xdyna --check i=deck.k [parts=N] [decomp=rcb|metis]   read and validate the deck,', &
            '                                   print the model summary', &
            '                                   (and the decomposition on N MPI ranks); run nothing', &
            '       xdyna --help | --version', &
            '       mpirun -np N xdyna i=deck.k', &
            '', &
            'Arguments (LS-DYNA''s names where LS-DYNA has them):', &
            '  i=deck.k        the keyword deck', &
            '  outdir=DIR      directory for every output file (default: the current one)', &
            '  o=FILE          the printed output file (default: d3hsp in outdir)', &
            '  jobid=NAME      prefix of the output files: NAME.d3hsp, NAME.glstat, ...', &
            '  endtim=T        end time, overriding *CONTROL_TERMINATION', &
            '  endcyc=N        end cycle, overriding *CONTROL_TERMINATION''s ENDCYC', &
            '  ncpu=N          OpenMP threads; ncpu=-N the same (results never depend on N)', &
            '  memory=SIZE, memory2=SIZE   accepted for LS-DYNA scripts; xdyna allocates as needed', &
            '  wallclock=S     stop with a restart dump after S seconds (also XDYNA_WALLCLOCK)', &
            '  x=N             d3plot family member size, N x 262,144 words (default 7, as LS-DYNA)', &
            '  h5plot=1|0      the states also in d3plot.h5 + d3plot.xdmf, or not (also XDYNA_H5PLOT;', &
            '                  default: *CONTROL_XDYNA_OUTPUT''s HDF5, else 0)', &
            '  r=DUMP          restart from a d3dump.h5 (give jobid= again if the run had one)', &
            '  unsupported=warn  skip keywords outside the subset with a warning (default: error)', &
            '  decomp=metis    MPI: split the elements by METIS''s k-way partition of their graph', &
            '                  (the halo smallest) instead of recursive coordinate bisection (rcb, the', &
            '                  default); the answers are the same either way', &
            '', &
            'Output files: d3hsp (log and every warning), glstat, matsum, nodout, rwforc,', &
            'rcforc (LS-DYNA ASCII layout, as the deck''s *DATABASE cards ask), thist.h5', &
            '(all histories), d3plot, d3plot01, ... (states, *DATABASE_BINARY_D3PLOT, in LS-DYNA''s', &
            'binary layout), d3plot.h5 + d3plot.xdmf (the states for ParaView, h5plot=1),', &
            'd3dump.h5 (restart dump), contact_debug (*CONTROL_XDYNA_CONTACT debug set).', &
            'Exit status: 0 normal, 1 input error, 2 error termination during the run,', &
            '3 stopped by a signal or wall-clock limit.', &
            '', &
            'Keywords skipped with a warning (output-only or tuning for another code):'
        write (output_unit, '(a)', advance='no') skip_list_text()
    end subroutine usage

    !> End: every rank comes here with the same code (all of them read the
    !> deck and run the same checks), so the ranks finish together.
    !> A set-up error: the message to the terminal and d3hsp, exit 1.
    subroutine stop_on_input_error()
        if (.not. allocated(error)) return
        call say(error%message)
        call log_line(lg, ' *** Error: '//error%message)
        call finish(exit_input)
    end subroutine stop_on_input_error

    subroutine finish(code)
        integer, intent(in) :: code
        call log_close(lg)
        call terminate(code, collective=.true.)
    end subroutine finish

    !> End where rank 0 alone failed (its files): the other ranks are
    !> stopped too (MPI_Abort).
    subroutine finish_alone(code)
        integer, intent(in) :: code
        call log_close(lg)
        call terminate(code)
    end subroutine finish_alone

    !> A stop signal that came before the time loop: exit 3 on every rank
    !> (the ranks agree first), no dump, since no state exists yet.
    subroutine stop_before_run(stage)
        character(len=*), intent(in) :: stage
        real(dp) :: fl(1)
        fl = real(stop_signal(), dp)
        if (env%nranks > 1) call comm_max(fl)
        if (fl(1) <= 0.0_dp) return
        call say('xdyna: stopped by signal '//itoa(nint(fl(1)))//' while '//stage// &
                 ', before the first cycle: no state yet, so no restart dump')
        call log_line(lg, ' S t o p p e d   by signal '//itoa(nint(fl(1)))//' while '//stage//', before the first cycle')
        call finish(exit_signal)
    end subroutine stop_before_run

    !> An input failure `why` (empty: none) of this rank, agreed over the
    !> ranks: where any rank failed every rank exits 1, rank 0 naming its
    !> own failure (prefix, then why), and a rank whose failure rank 0 did
    !> not share naming its own, with its rank (a file that only some ranks
    !> can read: a dump on a disk of one node). Before, a rank that failed
    !> alone stopped while the others waited for it in a collective: the
    !> run hung.
    subroutine stop_if_any(prefix, why)
        character(len=*), intent(in) :: prefix, why
        real(dp) :: fl(2)
        fl = 0
        if (len(why) > 0) fl(1) = 1
        if (env%rank == 0 .and. len(why) > 0) fl(2) = 1
        if (env%nranks > 1) call comm_max(fl)
        if (fl(1) == 0) return
        if (env%rank == 0 .and. len(why) > 0) then
            write (error_unit, '(a)') printable(prefix//why)
        else if (len(why) > 0 .and. fl(2) == 0) then
            write (error_unit, '(a)') printable(prefix//why//' (rank '//itoa(env%rank)//')')
        end if
        call finish(exit_input)
    end subroutine stop_if_any

    !> A message for standard error, from rank 0 alone.
    subroutine say(text)
        character(len=*), intent(in) :: text
        if (env%rank == 0) write (error_unit, '(a)') printable(text)
    end subroutine say

end program xdyna
