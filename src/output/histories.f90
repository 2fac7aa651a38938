!> Time-history databases: glstat, matsum and nodout in LS-DYNA's ASCII
!> layout, and the same series in thist.h5. Written at the *DATABASE_*
!> intervals (the first cycle at or past each output time) and at the end.
module xd_output_histories
    use xd_kinds, only: wp, dp, i8
    use xd_core_dofs, only: free3, free3r
    use xd_core_strings, only: itoa, join_path, out_path
    use xd_core_files, only: truncate_file, written_bytes, delete_file
    use xd_core_comm, only: comm_sum_dp
    use xd_model, only: model_t, find_set, set_node, any_erosion
    use xd_elements_solid_groups, only: solids_t
    use xd_solver_state, only: state_t
    use xd_solver_energies, only: energies_t
    use xd_contact_rigidwall, only: walls_t
    use xd_rigid_bodies, only: rigid_t
    use xd_output_units, only: unit_name, unit_system_text
    use xd_output_thist_h5, only: h5_root_attributes
    use xd_output_thist_h5, only: h5file_t, h5series_t, h5_open, h5_reopen, h5_close, series_create, series_open, &
                                  series_append, series_flush
    implicit none
    private
    public :: merge_rotations
    public :: histories_t, open_histories, histories_due, database_due, s_nodout, s_rcforc, write_histories, &
              close_histories, version_line, &
              flush_histories, &
              history_marks_t, history_marks, history_failure, track_rotations

    character(len=*), parameter :: xdyna_version = '0.1.0'
    integer, parameter :: s_glstat = 1, s_matsum = 2, s_nodout = 3, s_rwforc = 4, s_rbdout = 5, s_rcforc = 6, &
                          ndb = 6

    type :: histories_t
        logical :: on(ndb) = .false.
        integer :: unit(ndb) = 0
        logical :: ascii(ndb) = .true.       !< the database has its ASCII file (BINARY not 2)
        logical :: dirty(ndb) = .false.      !< records written since its last check (settle_ascii)
        real(dp) :: dt(ndb) = 0, next(ndb) = 0
        type(h5file_t) :: h5
        type(h5series_t) :: ser(ndb)
        integer :: nwall = 0
        logical :: contact = .false.         !< glstat carries the sliding interface energy
        logical :: erosion = .false.         !< glstat carries the eroded internal energy
        logical :: scaling = .false.         !< glstat carries the added mass (DT2MS)
        integer(i8) :: flushed = -1          !< system clock at thist.h5's last flush (-1: never)
        integer, allocatable :: nodes(:)     !< node indices for nodout
        integer, allocatable :: node_ids(:)  !< and their user ids
        real(dp), allocatable :: rdisp(:, :) !< (3, nodout nodes) rotation so far (models with shells)
        !> nodes numbered per rank (MPI, issue 32): per nodout node, its
        !> number in this rank's nodal arrays where this rank integrates it,
        !> else 0 (unallocated otherwise: `nodes` index the nodal arrays)
        integer, allocatable :: lnodes(:)
        character(len=72) :: title = ''
        integer :: nwritten = 0
        logical :: writer = .true.           !< this process writes the files (MPI: rank 0)
        character(len=1024) :: path(ndb) = ''   !< each ASCII file
        character(len=1024) :: h5path = ''      !< thist.h5
        integer(i8) :: good(ndb) = 0         !< bytes of each ASCII file at its last complete record
        integer :: failed = 0                !< the file a write failed on (0 none, ndb + 1 thist.h5)
    end type histories_t

    !> Where the histories stand: enough to go on from a restart dump.
    type :: history_marks_t
        real(dp) :: next(ndb) = 0       !< next output time of each database
        integer :: nt(ndb) = 0          !< rows written to thist.h5
        integer(i8) :: bytes(ndb) = 0   !< size of each ASCII file
        integer :: nwritten = 0
        real(dp), allocatable :: rdisp(:)   !< the nodout nodes' rotations (3 per node; none without shells)
    end type history_marks_t

contains

    !> The marks of h now (the ASCII files flushed).
    function history_marks(h) result(m)
        type(histories_t), intent(in) :: h
        type(history_marks_t) :: m
        integer :: k, ios
        integer(i8) :: sz
        m%next = h%next
        m%nwritten = h%nwritten
        allocate (m%rdisp(0))
        if (allocated(h%rdisp)) m%rdisp = reshape(h%rdisp, [size(h%rdisp)])
        do k = 1, ndb
            m%nt(k) = h%ser(k)%nt
            if (h%on(k) .and. h%unit(k) /= 0) then
                ! after a failed write, the last complete record
                m%bytes(k) = h%good(k)
                if (h%failed == 0) then
                    flush (h%unit(k), iostat=ios)
                    inquire (unit=h%unit(k), size=sz)
                    if (ios == 0) m%bytes(k) = sz
                end if
            end if
        end do
    end function history_marks

    !> The second header line in LS-DYNA R14's columns: the code, its build
    !> (smp, d for 64-bit reals, s for 32-bit) and version in a field of 35
    !> characters from column 21, then `date` at column 57 and mm/dd/yyyy
    !> (readers find the date there).
    function version_line() result(s)
        character(len=:), allocatable :: s
        character(len=8) :: d
        character(len=35) :: code
        call date_and_time(date=d)
        code = 'xdyna smp '//merge('d', 's', wp == dp)//' '//xdyna_version
        s = repeat(' ', 20)//code//' date '//d(5:6)//'/'//d(7:8)//'/'//d(1:4)
    end function version_line

    !> The date and time now, ISO 8601 with the zone's offset.
    function iso_date() result(s)
        character(len=:), allocatable :: s
        character(len=8) :: d
        character(len=10) :: t
        character(len=5) :: z
        call date_and_time(date=d, time=t, zone=z)
        s = d(1:4)//'-'//d(5:6)//'-'//d(7:8)//'T'//t(1:2)//':'//t(3:4)//':'//t(5:6)//z(1:3)//':'//z(4:5)
    end function iso_date

    !> Create the history files; with `resume` (a restart), open the ones
    !> the run wrote instead, cut back to the marks of the dump, and go on.
    subroutine open_histories(model, outdir, rg, h, ok, resume, writer, rotating)
        type(model_t), intent(in) :: model
        type(rigid_t), intent(in) :: rg
        character(len=*), intent(in) :: outdir
        type(histories_t), intent(out) :: h
        logical, intent(out) :: ok
        type(history_marks_t), intent(in), optional :: resume
        logical, intent(in), optional :: writer   !< .false.: keep the schedule only (MPI ranks > 0)
        logical, intent(in), optional :: rotating !< the nodes have rotations (deformable shells)
        logical :: fresh
        character(len=32), allocatable :: cols(:), units(:)
        integer :: k, s, j
        integer, allocatable :: ids(:)

        h%title = model%title(1:72)
        h%dt = [real(model%db%glstat%dt, dp), real(model%db%matsum%dt, dp), real(model%db%nodout%dt, dp), &
                real(model%db%rwforc%dt, dp), real(model%db%glstat%dt, dp), real(model%db%rcforc%dt, dp)]
        h%on = h%dt > 0.0_dp
        ! BINARY 2 asks for LS-DYNA's binout alone, whose counterpart here is
        ! thist.h5: no ASCII file then (rbdout has none)
        h%ascii = [model%db%glstat%binary /= 2, model%db%matsum%binary /= 2, model%db%nodout%binary /= 2, &
                   model%db%rwforc%binary /= 2, .false., model%db%rcforc%binary /= 2]
        h%nwall = model%nwall
        if (h%nwall == 0) h%on(s_rwforc) = .false.
        if (rg%n == 0) h%on(s_rbdout) = .false.
        if (model%ncontact == 0) h%on(s_rcforc) = .false.
        h%contact = model%ncontact > 0
        h%erosion = any_erosion(model)
        h%scaling = model%ctl%dt2ms /= 0.0_wp
        ! nodout nodes: *DATABASE_HISTORY_NODE ids, then node sets
        allocate (h%nodes(0))
        if (allocated(model%db%hist_node_ix)) h%nodes = model%db%hist_node_ix
        if (allocated(model%db%hist_set)) then
            do k = 1, size(model%db%hist_set)
                s = find_set(model, set_node, model%db%hist_set(k))
                h%nodes = [h%nodes, model%set(s)%member_ix]
            end do
        end if
        if (size(h%nodes) == 0) h%on(s_nodout) = .false.

        fresh = .not. present(resume)
        if (present(writer)) h%writer = writer
        ! where nodes rotate: the nodout nodes' rotation so far, for nodout's
        ! rotation block (on every rank: under owned nodes each tracks its
        ! own nodes', merge_rotations gathers them for the writer)
        if (present(rotating)) then
            if (h%on(s_nodout) .and. rotating) then
                allocate (h%rdisp(3, size(h%nodes)))
                h%rdisp = 0
                if (.not. fresh) then
                    if (size(resume%rdisp) == size(h%rdisp)) h%rdisp = reshape(resume%rdisp, shape(h%rdisp))
                end if
            end if
        end if
        if (.not. h%writer) then
            if (.not. fresh) then
                h%next = resume%next
                h%nwritten = resume%nwritten
            end if
            ok = .true.
            return
        end if
        h%h5path = out_path(outdir, 'thist.h5')
        if (fresh) then
            call h5_open(out_path(outdir, 'thist.h5'), h%h5, ok)
            if (ok) call h5_root_attributes(h%h5, [character(len=16) :: 'title', 'code', 'date', 'unit_system'], &
                                            [character(len=160) :: model%title, 'xdyna '//xdyna_version// &
                                            merge(' (double precision)', ' (single precision)', wp == dp), &
                                            iso_date(), unit_system_text(model%ctl%unit_l, model%ctl%unit_t, &
                                            model%ctl%unit_m)])
        else
            call h5_reopen(out_path(outdir, 'thist.h5'), h%h5, ok)
            h%next = resume%next
            h%nwritten = resume%nwritten
        end if
        if (.not. ok) return
        if (h%on(s_glstat)) then
            call start_file(s_glstat, 'glstat')
            if (fresh) call header(h%unit(s_glstat))
            cols = [character(len=32) :: 'time_step', 'kinetic_energy', 'internal_energy', 'hourglass_energy', &
                    'external_work', 'total_energy', 'energy_ratio', 'x_velocity', 'y_velocity', 'z_velocity']
            units = [character(len=32) :: 'time', 'energy', 'energy', 'energy', 'energy', 'energy', '1', &
                     'length/time', 'length/time', 'length/time']
            if (h%nwall > 0) then
                cols = [cols, [character(len=32) :: 'stonewall_energy']]
                units = [units, [character(len=32) :: 'energy']]
            end if
            if (model%ncontact > 0) then
                cols = [cols, [character(len=32) :: 'sliding_interface_energy']]
                units = [units, [character(len=32) :: 'energy']]
            end if
            if (h%erosion) then
                cols = [cols, [character(len=32) :: 'eroded_internal_energy']]
                units = [units, [character(len=32) :: 'energy']]
            end if
            if (h%scaling) then
                cols = [cols, [character(len=32) :: 'added_mass']]
                units = [units, [character(len=32) :: 'mass']]
            end if
            call make_series('glstat', cols, units, 0, [0], s_glstat, '')
        end if
        if (h%on(s_matsum)) then
            call start_file(s_matsum, 'matsum')
            if (fresh) call header(h%unit(s_matsum))
            if (fresh .and. h%unit(s_matsum) /= 0) then
                call legend(h%unit(s_matsum), model%part(1:model%npart)%id, model%part(1:model%npart)%heading)
                write (h%unit(s_matsum), '(a)') '', '', ''
            end if
            cols = [character(len=32) :: 'internal_energy', 'kinetic_energy', 'hourglass_energy', 'x_momentum', &
                    'y_momentum', 'z_momentum', 'mass']
            units = [character(len=32) :: 'energy', 'energy', 'energy', 'mass*length/time', 'mass*length/time', &
                     'mass*length/time', 'mass']
            call make_series('matsum', cols, units, model%npart, model%part(1:model%npart)%id, s_matsum, 'part id')
        end if
        if (h%on(s_nodout)) then
            call start_file(s_nodout, 'nodout')
            if (fresh) call header(h%unit(s_nodout))
            ids = model%node_id(h%nodes)
            h%node_ids = ids
            if (fresh) call legend(h%unit(s_nodout), ids, [(repeat(' ', 70), j=1, size(ids))])
            cols = [character(len=32) :: 'x_displacement', 'y_displacement', 'z_displacement', 'x_velocity', &
                    'y_velocity', 'z_velocity', 'x_acceleration', 'y_acceleration', 'z_acceleration', &
                    'x_coordinate', 'y_coordinate', 'z_coordinate']
            units = [character(len=32) :: 'length', 'length', 'length', 'length/time', 'length/time', 'length/time', &
                     'length/time^2', 'length/time^2', 'length/time^2', 'length', 'length', 'length']
            ! HDF5 only (LS-DYNA's nodout has no such columns): the reaction
            ! of the node's single-point constraints (the force they apply in
            ! the directions they fix, -f there; 0 elsewhere), and the
            ! contact force on the node, the sum over its interfaces
            cols = [cols, [character(len=32) :: 'x_reaction_force', 'y_reaction_force', 'z_reaction_force']]
            units = [units, [character(len=32) :: 'force', 'force', 'force']]
            if (model%ncontact > 0) then
                cols = [cols, [character(len=32) :: 'x_contact_force', 'y_contact_force', 'z_contact_force']]
                units = [units, [character(len=32) :: 'force', 'force', 'force']]
            end if
            ! with shells, the rotations (LS-DYNA's second nodout block)
            if (allocated(h%rdisp)) then
                cols = [cols, [character(len=32) :: 'rx_displacement', 'ry_displacement', 'rz_displacement', &
                               'rx_velocity', 'ry_velocity', 'rz_velocity', 'rx_acceleration', 'ry_acceleration', &
                               'rz_acceleration']]
                units = [units, [character(len=32) :: 'radian', 'radian', 'radian', 'radian/time', 'radian/time', &
                                 'radian/time', 'radian/time^2', 'radian/time^2', 'radian/time^2']]
            end if
            call make_series('nodout', cols, units, size(ids), ids, s_nodout, 'node id')
        end if
        if (h%on(s_rwforc)) then
            call start_file(s_rwforc, 'rwforc')
            if (fresh) call header(h%unit(s_rwforc))
            ids = model%wall(1:model%nwall)%id
            if (fresh .and. h%unit(s_rwforc) /= 0) then
                call legend(h%unit(s_rwforc), ids, model%wall(1:model%nwall)%heading)
                write (h%unit(s_rwforc), '(a)') '', '', &
                    '    time       wall#   normal-force    x-force        y-force        z-force'
            end if
            cols = [character(len=32) :: 'normal_force', 'x_force', 'y_force', 'z_force']
            units = [character(len=32) :: 'force', 'force', 'force', 'force']
            call make_series('rwforc', cols, units, size(ids), ids, s_rwforc, 'rigid wall id (its _ID, else its '// &
                             'number in the deck)')
        end if
        if (h%on(s_rcforc)) then
            call start_file(s_rcforc, 'rcforc')
            if (fresh) call header(h%unit(s_rcforc))
            ids = model%contact(1:model%ncontact)%id
            if (fresh .and. h%unit(s_rcforc) /= 0) then
                call legend(h%unit(s_rcforc), ids, model%contact(1:model%ncontact)%heading)
                write (h%unit(s_rcforc), '(a)') ''
            end if
            cols = [character(len=32) :: 'slave_x_force', 'slave_y_force', 'slave_z_force', 'slave_mass', &
                    'master_x_force', 'master_y_force', 'master_z_force', 'master_mass']
            units = [character(len=32) :: 'force', 'force', 'force', 'mass', 'force', 'force', 'force', 'mass']
            call make_series('rcforc', cols, units, size(ids), ids, s_rcforc, 'contact interface id (its _ID, else '// &
                             'its number in the deck)')
        end if
        if (h%on(s_rbdout)) then
            ! rigid bodies, HDF5 only: part id, or minus the body's number for node-set bodies
            ids = [(merge(model%part(max(rg%b(j)%part, 1))%id, -j, rg%b(j)%part > 0), j=1, rg%n)]
            cols = [character(len=32) :: 'x_velocity', 'y_velocity', 'z_velocity', 'x_angular_velocity', &
                    'y_angular_velocity', 'z_angular_velocity', 'x_angular_momentum', 'y_angular_momentum', &
                    'z_angular_momentum']
            units = [character(len=32) :: 'length/time', 'length/time', 'length/time', '1/time', '1/time', &
                     '1/time', 'mass*length^2/time', 'mass*length^2/time', 'mass*length^2/time']
            call make_series('rbdout', cols, units, rg%n, ids, s_rbdout, 'rigid body: its part id, or minus its '// &
                             'number for a *CONSTRAINED_NODAL_RIGID_BODY')
        end if
        ! what the files hold now is complete (a restart's truncated files, or
        ! the headers)
        ! (gfortran places an appended file's offset at its first write, so
        ! the size is the unit's own here)
        do k = 1, ndb
            if (h%on(k) .and. h%unit(k) /= 0) then
                flush (h%unit(k))
                inquire (unit=h%unit(k), size=h%good(k))
            end if
        end do
    contains
        !> Create file `name` for database k, or (resuming) cut it back to
        !> the size it had at the dump and append.
        subroutine start_file(k, name)
            integer, intent(in) :: k
            character(len=*), intent(in) :: name
            if (.not. h%ascii(k)) then
                ! a fresh run leaves no older run's file of that name beside
                ! its thist.h5 (one would read as this run's)
                if (fresh) call delete_file(out_path(outdir, name))
                return
            end if
            h%path(k) = out_path(outdir, name)
            if (fresh) then
                open (newunit=h%unit(k), file=out_path(outdir, name), status='replace', action='write')
            else
                call truncate_file(out_path(outdir, name), resume%bytes(k))
                open (newunit=h%unit(k), file=out_path(outdir, name), status='old', action='write', &
                      position='append')
            end if
        end subroutine start_file
        !> units: the columns' dimensions; their units come from the deck's
        !> unit system (*CONTROL_UNITS)
        subroutine make_series(name, cols, units, nent, ids, k, entity)
            character(len=*), intent(in) :: name, cols(:), units(:), entity
            integer, intent(in) :: nent, ids(:), k
            logical :: good
            character(len=32) :: un(size(units))
            integer :: j
            if (fresh) then
                do j = 1, size(units)
                    un(j) = unit_name(trim(units(j)), model%ctl%unit_l, model%ctl%unit_t, model%ctl%unit_m)
                end do
                call series_create(h%h5, name, cols, units, un, &
                                   unit_name('time', model%ctl%unit_l, model%ctl%unit_t, model%ctl%unit_m), nent, &
                                   ids, entity, h%ser(k))
            else
                call series_open(h%h5, name, cols, nent, resume%nt(k), h%ser(k), good)
                ok = ok .and. good
            end if
        end subroutine make_series
        subroutine header(u)
            integer, intent(in) :: u
            if (u == 0) return
            write (u, '(a)') ' '//h%title
            write (u, '(a)') version_line()
        end subroutine header
        subroutine legend(u, ids, titles)
            integer, intent(in) :: u, ids(:)
            character(len=*), intent(in) :: titles(:)
            integer :: i
            if (u == 0) return
            write (u, '(a)') '', '{BEGIN LEGEND}', ' Entity #        Title'
            do i = 1, size(ids)
                write (u, '(i9,5x,a)') ids(i), titles(i)(1:min(70, len(titles(i))))
            end do
            write (u, '(a)') '{END LEGEND}'
        end subroutine legend
    end subroutine open_histories

    !> The databases due at time t (every one that is on, if `force`).
    pure function due_at(h, t, force) result(due)
        type(histories_t), intent(in) :: h
        real(dp), intent(in) :: t
        logical, intent(in) :: force
        logical :: due(ndb)
        due = h%on .and. (force .or. t >= h%next*(1.0_dp - 1.0e-9_dp))
    end function due_at

    !> Is any database due at time t?
    logical function histories_due(h, t)
        type(histories_t), intent(in) :: h
        real(dp), intent(in) :: t
        histories_due = any(due_at(h, t, .false.))
    end function histories_due

    !> Database db (s_nodout, s_rcforc, ...) is due at t (or forced). With
    !> contact, nodout's rows carry each node's contact force and rcforc's
    !> are sums over every contact pair of the cycle: the contact asks.
    logical function database_due(h, db, t, force)
        type(histories_t), intent(in) :: h
        integer, intent(in) :: db
        real(dp), intent(in) :: t
        logical, intent(in) :: force
        logical :: due(ndb)
        due = due_at(h, t, force)
        database_due = due(db)
    end function database_due

    !> Write the databases that are due at the state's time (all of them if
    !> `force`). vn: full-step velocities; a: accelerations.
    subroutine write_histories(h, model, st, solids, walls, rg, en, vn, crit, zone_ns, force, rc, fc, wminus)
        type(histories_t), intent(inout) :: h
        type(model_t), intent(in) :: model
        type(state_t), intent(in) :: st
        type(solids_t), intent(in) :: solids
        type(walls_t), intent(in) :: walls
        type(rigid_t), intent(in) :: rg
        type(energies_t), intent(in) :: en
        real(wp), intent(in) :: vn(:, :)
        integer, intent(in) :: crit(3)           !< controlling element: kind (1 solid, 2 shell), id, part id
        real(dp), intent(in) :: zone_ns
        logical, intent(in) :: force
        real(dp), intent(in), optional :: rc(:, :)   !< (8, interfaces): slave force, mass, master force, mass
        real(wp), intent(in), optional :: fc(:, :)   !< (3, nodes) contact force per node
        real(wp), intent(in), optional :: wminus(:, :)  !< (3, nodes) angular velocity at t - dt/2 (with shells)
        logical :: due(ndb)
        integer(i8) :: now, rate
        due = due_at(h, st%time, force)
        if (h%writer) then
            if (due(s_glstat)) call write_glstat(h, st, walls, en, crit, zone_ns)
            if (due(s_rwforc)) call write_rwforc(h, model, st, walls)
            if (due(s_rbdout)) call write_rbdout(h, st, rg)
            if (due(s_rcforc) .and. present(rc)) call write_rcforc(h, model, st, rc)
            if (due(s_matsum)) call write_matsum(h, model, st, en)
            if (due(s_nodout)) call write_nodout(h, st, model%x0, vn, fc, wminus)
        end if
        if (h%writer) then
            ! thist.h5's rows go out in blocks, the ASCII files' records with
            ! their units' buffers: at the first and the last output, and a
            ! second of wall time apart at most
            call system_clock(now, rate)
            if (force .or. h%flushed < 0 .or. real(now - h%flushed, dp) >= real(rate, dp)) call flush_histories(h)
        end if
        if (h%writer .and. h%failed == 0) then
            if (any(h%ser%bad)) h%failed = ndb + 1
        end if
        where (due)
            h%next = h%next + h%dt
        end where
        ! skip output times already passed (a step longer than the interval)
        where (h%on .and. h%next <= st%time)
            h%next = st%time + h%dt
        end where
        if (any(due)) h%nwritten = h%nwritten + 1
    end subroutine write_histories

    subroutine write_glstat(h, st, walls, en, crit, zone_ns)
        type(histories_t), intent(inout) :: h
        type(state_t), intent(in) :: st
        type(walls_t), intent(in) :: walls
        type(energies_t), intent(in) :: en
        integer, intent(in) :: crit(3)
        real(dp), intent(in) :: zone_ns
        integer :: u, k
        character(len=8) :: wl
        real(dp), allocatable :: vals(:)
        integer :: ios, nbad
        nbad = 0
        u = h%unit(s_glstat)
        if (u /= 0) then
            write (u, '(a)', iostat=ios) '', ''
            if (ios /= 0) nbad = nbad + 1
            ! (LS-DYNA counts the cycle about to be taken from 1); the columns
            ! that fixed-column readers slice: the cycle in 14-20, the element
            ! in 45-53, the part in 63-71
            write (u, '(a,i8,a,a6,i9,a,i10)', iostat=ios) ' dt of cycle', st%cycle + 1, ' is controlled by ', &
                merge('shell ', 'solid ', crit(1) == 2), crit(2), ' of part', crit(3)
            if (ios /= 0) nbad = nbad + 1
            write (u, '(a)', iostat=ios) ''
            if (ios /= 0) nbad = nbad + 1
            call row('time', st%time)
            call row('time step', real(st%dt, dp))
            call row('kinetic energy', en%ke)
            call row('internal energy', en%ie)
            if (walls%n > 0) then
                call row('stonewall energy', en%wall)
                do k = 1, walls%n
                    write (wl, '(a,i2)') ' wall#', k
                    call row('stonewall energy'//wl, walls%w(k)%energy)
                end do
            end if
            call row('spring and damper energy', 0.0_dp)
            call row('hourglass energy ', en%hg)
            call row('system damping energy', 0.0_dp)
            call row('sliding interface energy', en%slide)
            call row('external work', en%ext)
            ! no damping or drilling stiffness here: their lines read zero, as
            ! LS-DYNA's do for a model without them; an eroded shell's mass
            ! stays on its nodes, so no kinetic energy is eroded
            call row('eroded kinetic energy', 0.0_dp)
            call row('eroded internal energy', en%eroded_ie)
            call row('eroded hourglass energy', 0.0_dp)
            call row('total energy', en%total)
            call row('total energy / initial energy', en%ratio)
            call row('energy ratio w/o eroded energy', en%ratio_live)
            call row('global x velocity', en%vel(1))
            call row('global y velocity', en%vel(2))
            call row('global z velocity', en%vel(3))
            call row('dissipated kinetic energy', 0.0_dp)
            call row('dissipated internal energy', 0.0_dp)
            call row('drilling energy', 0.0_dp)
            write (u, '(a,i14)', iostat=ios) ' '//dots('time per zone cycle.(nanosec)'), nint(zone_ns)
            if (ios /= 0) nbad = nbad + 1
            write (u, '(a)', iostat=ios) '', '', ' number of shell elements that  ', &
                ' '//dots('reached the minimum time step')//'    '//itoa(en%nshell_scaled), '', ''
            if (ios /= 0) nbad = nbad + 1
            call row('added mass', en%added)
            if (en%mass - en%added > 0) then
                call row('percentage increase', 100*en%added/(en%mass - en%added))
            else
                call row('percentage increase', 0.0_dp)
            end if
            call settle(h, s_glstat, nbad)
        end if
        vals = [real(st%dt, dp), en%ke, en%ie, en%hg, en%ext, en%total, en%ratio, en%vel]
        if (walls%n > 0) vals = [vals, en%wall]
        if (h%contact) vals = [vals, en%slide]
        if (h%erosion) vals = [vals, en%eroded_ie]
        if (h%scaling) vals = [vals, en%added]
        call series_append(h%ser(s_glstat), st%time, reshape(vals, [1, size(vals)]))
    contains
        subroutine row(label, x)
            character(len=*), intent(in) :: label
            real(dp), intent(in) :: x
            write (u, '(a,es14.5)', iostat=ios) ' '//dots(label), x
            if (ios /= 0) nbad = nbad + 1
        end subroutine row
    end subroutine write_glstat

    !> A label padded with dots to 31 characters, as LS-DYNA prints them.
    pure function dots(label) result(s)
        character(len=*), intent(in) :: label
        character(len=31) :: s
        s = repeat('.', 31)
        s(1:min(31, len(label))) = label
    end function dots

    subroutine write_matsum(h, model, st, en)
        type(histories_t), intent(inout) :: h
        type(model_t), intent(in) :: model
        type(state_t), intent(in) :: st
        type(energies_t), intent(in) :: en
        integer :: u, p
        real(dp) :: rbv(3)
        real(dp), allocatable :: vals(:, :)
        integer :: ios, nbad
        nbad = 0
        u = h%unit(s_matsum)
        if (u /= 0) then
            write (u, '(a,es13.4)', iostat=ios) ' time =', st%time
            if (ios /= 0) nbad = nbad + 1
            do p = 1, model%npart
                rbv = 0
                if (en%part_mass(p) > 0) rbv = en%part_mom(:, p)/en%part_mass(p)
                write (u, '(a,i5,3x,a,es13.4,a,es13.4,a,es13.4,a,es13.4)', iostat=ios) ' mat.#=', model%part(p)%id, &
                    '          inten=', en%part_ie(p), '     kinen=', en%part_ke(p), '     eroded_ie=', en%part_eroded(p), &
                    '     eroded_ke=', 0.0_dp
                if (ios /= 0) nbad = nbad + 1
                write (u, '(a,es13.4,a,es13.4,a,es13.4)', iostat=ios) ' x-mom=', en%part_mom(1, p), '     y-mom=', &
                    en%part_mom(2, p), '     z-mom=', en%part_mom(3, p)
                if (ios /= 0) nbad = nbad + 1
                write (u, '(a,es13.4,a,es13.4,a,es13.4)', iostat=ios) ' x-rbv=', rbv(1), '     y-rbv=', rbv(2), &
                    '     z-rbv=', rbv(3)
                if (ios /= 0) nbad = nbad + 1
                write (u, '(a,es13.4,a,es13.4,a,es13.4)', iostat=ios) '                         hgeng=', en%part_hg(p), &
                    '     +mass=', en%part_added(p), '     eroded_he=', 0.0_dp
                if (ios /= 0) nbad = nbad + 1
                write (u, '(a)', iostat=ios) '', ''
                if (ios /= 0) nbad = nbad + 1
            end do
            call settle(h, s_matsum, nbad)
        end if
        allocate (vals(model%npart, 7))
        vals(:, 1) = en%part_ie
        vals(:, 2) = en%part_ke
        vals(:, 3) = en%part_hg
        vals(:, 4) = en%part_mom(1, :)
        vals(:, 5) = en%part_mom(2, :)
        vals(:, 6) = en%part_mom(3, :)
        vals(:, 7) = en%part_mass
        call series_append(h%ser(s_matsum), st%time, vals)
    end subroutine write_matsum

    !> nodout in LSTC's layout: each block after three blank lines, the step
    !> counted from 1 (as glstat's), the row '(i9, es13.4, 11es12.4)'; with
    !> shells a second block of the same step with the rotations, the
    !> angular velocities at st%time (the mean of wminus and st%vr) and
    !> accelerations (zero for nodes that do not rotate).
    subroutine write_nodout(h, st, x0, vn, fc, wminus)
        type(histories_t), intent(inout) :: h
        type(state_t), intent(in) :: st
        real(wp), intent(in) :: x0(:, :)   !< the initial coordinates (the deck's)
        real(wp), intent(in) :: vn(:, :)
        real(wp), intent(in), optional :: fc(:, :)
        real(wp), intent(in), optional :: wminus(:, :)
        integer :: u, k, nd, nc
        real(dp), allocatable :: vals(:, :), rot(:, :)
        integer :: ios, nbad
        nbad = 0
        u = h%unit(s_nodout)
        call block_head(' nodal point  x-disp     y-disp      z-disp      x-vel       y-vel       z-vel  '// &
                        '    x-accl      y-accl      z-accl      x-coor      y-coor      z-coor')
        allocate (vals(size(h%nodes), 12))
        do k = 1, size(h%nodes)
            nd = h%nodes(k)
            vals(k, 1:3) = st%x(:, nd) - x0(:, nd)
            vals(k, 4:6) = vn(:, nd)
            vals(k, 7:9) = st%a(:, nd)
            vals(k, 10:12) = st%x(:, nd)
            if (u == 0) cycle
            write (u, '(i9,es13.4,11es12.4)', iostat=ios) h%node_ids(k), vals(k, :)
            if (ios /= 0) nbad = nbad + 1
        end do
        if (allocated(h%rdisp) .and. st%rot) then
            ! rotation, angular velocity at st%time, angular acceleration
            ! (the moment over the rotational inertia, where free)
            allocate (rot(size(h%nodes), 9))
            rot = 0
            do k = 1, size(h%nodes)
                nd = h%nodes(k)
                rot(k, 1:3) = h%rdisp(:, k)
                if (present(wminus)) rot(k, 4:6) = 0.5_wp*(wminus(:, nd) + st%vr(:, nd))
                if (st%irot(nd) > 0.0_wp) rot(k, 7:9) = st%mom(:, nd)/st%irot(nd)*free3r(st%dofs(nd))
            end do
            call block_head(' nodal point  x-rot      y-rot       z-rot       x-rot vel   y-rot vel   '// &
                            'z-rot vel   x-rot acc   y-rot acc   z-rot acc')
            do k = 1, size(h%nodes)
                if (u == 0) exit
                write (u, '(i9,es13.4,8es12.4)', iostat=ios) h%node_ids(k), rot(k, :)
                if (ios /= 0) nbad = nbad + 1
            end do
        end if
        call settle(h, s_nodout, nbad)
        nc = 15
        if (h%contact) nc = 18
        vals = reshape([vals, [(0.0_dp, k=1, (nc - 12)*size(h%nodes))]], [size(h%nodes), nc])
        do k = 1, size(h%nodes)
            vals(k, 13:15) = -st%f(:, h%nodes(k))*(1.0_wp - free3(st%dofs(h%nodes(k))))
        end do
        if (h%contact .and. present(fc)) then
            do k = 1, size(h%nodes)
                vals(k, 16:18) = fc(:, h%nodes(k))
            end do
        end if
        if (allocated(rot)) vals = reshape([vals, rot], [size(h%nodes), nc + 9])
        call series_append(h%ser(s_nodout), st%time, vals)
    contains
        !> Three blank lines, the step line, a blank line and the column line.
        subroutine block_head(columns)
            character(len=*), intent(in) :: columns
            if (u == 0) return
            write (u, '(a)', iostat=ios) '', '', ''
            if (ios /= 0) nbad = nbad + 1
            write (u, '(a,i8,a,es14.7,a)', iostat=ios) ' n o d a l   p r i n t   o u t   f o r   t i m e  s t e p', &
                st%cycle + 1, '                              ( at time', st%time, ' )'
            if (ios /= 0) nbad = nbad + 1
            write (u, '(a)', iostat=ios) '', columns
            if (ios /= 0) nbad = nbad + 1
        end subroutine block_head
    end subroutine write_nodout

    !> The nodout nodes' rotations after a step: + dt w(n+1/2) (called as
    !> the coordinates are moved).
    !> (mine: under owned nodes, the nodes this rank integrates: only theirs
    !> are tracked here; merge_rotations gathers them for the output)
    subroutine track_rotations(h, st, mine)
        type(histories_t), intent(inout) :: h
        type(state_t), intent(in) :: st
        logical, intent(in), optional :: mine(:)
        integer :: k
        if (.not. allocated(h%rdisp) .or. .not. st%rot) return
        if (allocated(h%lnodes)) then
            ! (nodes numbered per rank: this rank's own nodout nodes)
            do k = 1, size(h%nodes)
                if (h%lnodes(k) > 0) h%rdisp(:, k) = h%rdisp(:, k) + real(st%dt, dp)*st%vr(:, h%lnodes(k))
            end do
            return
        end if
        do k = 1, size(h%nodes)
            if (present(mine)) then
                if (.not. mine(h%nodes(k))) cycle
            end if
            h%rdisp(:, k) = h%rdisp(:, k) + real(st%dt, dp)*st%vr(:, h%nodes(k))
        end do
    end subroutine track_rotations

    !> Owned nodes: the tracked rotations of every history node from the
    !> rank that integrates it (the others' copies, not tracked, zeroed and
    !> the ranks' values summed: exact).
    subroutine merge_rotations(h, mine)
        type(histories_t), intent(inout) :: h
        logical, intent(in) :: mine(:)
        integer :: k
        if (.not. allocated(h%rdisp)) return
        do k = 1, size(h%nodes)
            if (allocated(h%lnodes)) then
                if (h%lnodes(k) == 0) h%rdisp(:, k) = 0
            else if (.not. mine(h%nodes(k))) then
                h%rdisp(:, k) = 0
            end if
        end do
        call sum_ranks(h%rdisp)
    end subroutine merge_rotations

    subroutine sum_ranks(a)
        real(dp), intent(inout), target, contiguous :: a(:, :)
        real(dp), pointer, contiguous :: flat(:)
        flat(1:size(a)) => a
        call comm_sum_dp(flat)
    end subroutine sum_ranks

    !> Per interface, LS-DYNA's rcforc lines: the resultant of the contact
    !> forces on the slave nodes and on the master nodes, and the mass of
    !> the nodes in contact.
    subroutine write_rcforc(h, model, st, rc)
        type(histories_t), intent(inout) :: h
        type(model_t), intent(in) :: model
        type(state_t), intent(in) :: st
        real(dp), intent(in) :: rc(:, :)
        character(len=*), parameter :: fmt = '(a,i12,a,es12.5,7(a,es12.5))'
        integer :: k
        integer :: ios, nbad
        nbad = 0
        ! R14's columns: SURFA the slave side, SURFB the master side; the
        ! moments mx, my, mz are not computed here and read zero
        do k = 1, model%ncontact
            if (h%unit(s_rcforc) == 0) exit
            write (h%unit(s_rcforc), fmt, iostat=ios) '  SURFA', model%contact(k)%id, ' time', st%time, &
                '  x ', rc(1, k), '  y ', rc(2, k), '  z ', rc(3, k), ' mass ', rc(4, k), '  mx ', 0.0_dp, &
                '  my ', 0.0_dp, '  mz ', 0.0_dp
            if (ios /= 0) nbad = nbad + 1
            write (h%unit(s_rcforc), fmt, iostat=ios) '  SURFB', model%contact(k)%id, ' time', st%time, &
                '  x ', rc(5, k), '  y ', rc(6, k), '  z ', rc(7, k), ' mass ', rc(8, k), '  mx ', 0.0_dp, &
                '  my ', 0.0_dp, '  mz ', 0.0_dp
            if (ios /= 0) nbad = nbad + 1
        end do
        call settle(h, s_rcforc, nbad)
        call series_append(h%ser(s_rcforc), st%time, transpose(rc))
    end subroutine write_rcforc

    subroutine write_rwforc(h, model, st, walls)
        type(histories_t), intent(inout) :: h
        type(model_t), intent(in) :: model
        type(state_t), intent(in) :: st
        type(walls_t), intent(in) :: walls
        real(dp) :: vals(walls%n, 4)
        integer :: k
        integer :: ios, nbad
        nbad = 0
        do k = 1, walls%n
            vals(k, 1) = walls%w(k)%normal_force
            vals(k, 2:4) = walls%w(k)%force
            if (h%unit(s_rwforc) == 0) cycle
            write (h%unit(s_rwforc), '(es12.5,i8,4es15.6)', iostat=ios) st%time, model%wall(k)%id, vals(k, :)
            if (ios /= 0) nbad = nbad + 1
        end do
        call settle(h, s_rwforc, nbad)
        call series_append(h%ser(s_rwforc), st%time, vals)
    end subroutine write_rwforc

    !> Rigid bodies at t(n): centre velocity (mean of the half steps), angular
    !> velocity and spatial angular momentum at n+1/2.
    subroutine write_rbdout(h, st, rg)
        type(histories_t), intent(inout) :: h
        type(state_t), intent(in) :: st
        type(rigid_t), intent(in) :: rg
        real(dp) :: vals(rg%n, 9)
        integer :: k
        do k = 1, rg%n
            vals(k, 1:3) = 0.5_dp*(rg%b(k)%vc_old + rg%b(k)%vc)
            vals(k, 4:6) = rg%b(k)%omega
            vals(k, 7:9) = rg%b(k)%pi
        end do
        call series_append(h%ser(s_rbdout), st%time, vals)
    end subroutine write_rbdout

    !> After a record of database k with `nbad` failed writes: a failure is
    !> noted (the file is cut back to its last complete record when it is
    !> closed). The records themselves go out with the unit's buffer and are
    !> checked where the files are flushed (settle_ascii), not one by one: a
    !> flush and a size query per record cost car6 more than its elements'
    !> stresses.
    subroutine settle(h, k, nbad)
        type(histories_t), intent(inout) :: h
        integer, intent(in) :: k, nbad
        if (h%failed /= 0) return
        if (nbad > 0) h%failed = k
        h%dirty(k) = .true.
    end subroutine settle

    !> Each ASCII file flushed and its size kept as its last complete record
    !> (every record before the flush is whole), or the failure noted: a
    !> short write leaves the file smaller than what was written to it.
    subroutine settle_ascii(h)
        type(histories_t), intent(inout) :: h
        integer :: k, ios
        integer(i8) :: sz
        do k = 1, ndb
            if (h%failed /= 0) return
            ! (a unit appended to since a restart but not yet written has
            ! its offset at 0 until its first write: only those written)
            if (.not. h%on(k) .or. h%unit(k) == 0 .or. .not. h%dirty(k)) cycle
            h%dirty(k) = .false.
            flush (h%unit(k), iostat=ios)
            inquire (unit=h%unit(k), size=sz)
            if (ios /= 0 .or. written_bytes(h%unit(k)) /= sz) then
                h%failed = k
            else
                h%good(k) = sz
            end if
        end do
    end subroutine settle_ascii

    !> The file a write failed on ('' if none).
    function history_failure(h) result(name)
        type(histories_t), intent(in) :: h
        character(len=:), allocatable :: name
        name = ''
        if (h%failed >= 1 .and. h%failed <= ndb) name = trim(h%path(h%failed))
        if (h%failed == ndb + 1) name = trim(h%h5path)
    end function history_failure

    !> thist.h5's rows held in memory written out and the file flushed, the
    !> ASCII files flushed and checked (at the pace write_histories keeps,
    !> before a dump and at a hold); a failed write is the run's history
    !> failure.
    subroutine flush_histories(h)
        type(histories_t), intent(inout) :: h
        integer :: k
        integer(i8) :: rate
        if (.not. h%writer) return
        call settle_ascii(h)
        do k = 1, ndb
            if (h%ser(k)%gid >= 0) call series_flush(h%ser(k))
        end do
        call system_clock(h%flushed, rate)
        if (h%failed == 0) then
            if (any(h%ser%bad)) h%failed = ndb + 1
        end if
    end subroutine flush_histories

    subroutine close_histories(h)
        type(histories_t), intent(inout) :: h
        integer :: k, ios
        if (.not. h%writer) return
        ! the records still in the units' buffers written out and checked
        ! (a full disk met now, after another file's failure stopped the
        ! run, is a failed write too: its last record may be cut)
        call settle_ascii(h)
        do k = 1, ndb
            if (h%on(k) .and. h%unit(k) /= 0) close (h%unit(k), iostat=ios)
            h%unit(k) = 0
        end do
        ! after a failed write every ASCII file ends at its last complete
        ! record (those written after the failure are not kept either)
        if (h%failed /= 0) then
            do k = 1, ndb
                if (h%on(k) .and. len_trim(h%path(k)) > 0) call truncate_file(trim(h%path(k)), h%good(k))
            end do
        end if
        call h5_close(h%h5, h%ser)
    end subroutine close_histories

end module xd_output_histories
