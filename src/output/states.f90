!> States (*DATABASE_BINARY_D3PLOT): LS-DYNA's binary d3plot family (module
!> xd_output_d3plot), and where *CONTROL_XDYNA_OUTPUT asks for it
!> `d3plot.h5` through HDF5's Fortran API with `d3plot.xdmf` beside it,
!> which ParaView and VisIt open as a time series. The HDF5 mesh is written once (group `mesh`: node ids, hexahedra and
!> shells as 0-based indices into the node arrays, element ids and part
!> ids); each state is a group `states/NNNNNN` (attribute `time`) with the
!> coordinates, displacement, velocity and contact force per node, and per
!> element the stress tensor (global xx yy zz xy yz zx; shells: the mean
!> through the thickness), the von Mises stress (shells: the largest of
!> the integration points), the effective plastic strain (shells: the
!> largest) and the shell thickness. Rigid parts' elements follow the
!> deformable ones in the mesh (LS-DYNA writes them too) with zero stress
!> and strain and their section's thickness. The dataset `states/time` lists the
!> times. After each state the file is flushed and the XDMF rewritten
!> (to a temporary file, then renamed), so a killed run leaves every
!> finished state readable.
module xd_output_states
    use hdf5
    use xd_kinds, only: wp, dp, i8
    use xd_core_strings, only: join_path, out_path
    use xd_core_files, only: rename_file, delete_file, written_bytes
    use xd_model, only: model_t, mat_rigid, shell_thickness
    use xd_solver_state, only: state_t
    use xd_elements_solid_groups, only: solids_t
    use xd_elements_beam_bs, only: beams_t
    use xd_elements_shell_bt, only: shells_t, shell_axes, point_weight
    use xd_output_shell_words, only: shell_state_words, to_global
    use xd_solver_energies, only: energies_t
    use xd_output_d3plot, only: d3plot_t, d3plot_mesh_t, d3plot_open, d3plot_close, member_unit, d3plot_begin_state, &
                                d3plot_put, d3plot_end_state
    implicit none
    private
    public :: states_t, open_states, states_due, write_state, close_states, states_marks_t, states_marks, states_failure, &
              states_summary
    ! (a state whose shells' words the ranks make, each for its own shells:
    ! xd_solver_state_writer)
    public :: take_state, binary_head, binary_put, binary_tail, state_nv2d

    type :: states_t
        logical :: on = .false.
        real(dp) :: dt = 0, next = 0
        integer(hid_t) :: file = -1
        integer :: n = 0                      !< states written
        logical :: writer = .true.            !< this process writes the file (MPI: rank 0)
        integer :: nnode = 0, nsolid = 0, nshell = 0   !< all elements, rigid ones included
        integer :: nbeam = 0                             !< beams (spot-weld beams among them)
        logical :: weld = .false.                        !< some beam is a weld that can fail
        integer :: nrhex = 0, nrshell = 0                !< rigid elements (after the deformable ones)
        real(wp), allocatable :: rshell_t(:)             !< rigid shells' thickness
        logical :: contact = .false.          !< the model has contact: states carry the contact force
        character(len=:), allocatable :: dir
        real(dp), allocatable :: times(:)
        logical :: failed = .false.           !< a write failed (a full disk, a quota): no more states
        character(len=:), allocatable :: failed_file
        logical :: h5 = .false.               !< d3plot.h5 + d3plot.xdmf (*CONTROL_XDYNA_OUTPUT)
        logical :: binary = .false.           !< the binary d3plot family is written (every rank knows)
        integer :: maxint = 3                 !< the binary family's layers a shell (every rank knows)
        type(d3plot_t) :: bin                 !< the binary d3plot family
        integer, allocatable :: dmat_part(:)  !< the part of each d3plot material
    end type states_t

    integer, parameter :: sp = kind(1.0e0)
    !> the nodes' and shells' words are made and written a chunk at a time
    !> (d3plot_put), not held for the whole model
    integer, parameter :: chunk = 4096

    !> Where the states stand: enough to go on from a restart dump.
    type :: states_marks_t
        integer :: n = 0
        real(dp) :: next = 0
        real(dp), allocatable :: times(:)
    end type states_marks_t

contains

    function states_marks(s) result(m)
        type(states_t), intent(in) :: s
        type(states_marks_t) :: m
        m%n = s%n
        m%next = s%next
        if (allocated(s%times)) then
            m%times = s%times
        else
            allocate (m%times(0))
        end if
    end function states_marks

    !> Create d3plot.h5 with the mesh, if the deck asks for states; with
    !> `resume` (a restart), open the run's file, drop the states written
    !> after the dump and go on.
    subroutine open_states(model, outdir, endtim, solids, sh, s, ok, resume, writer, bm)
        type(model_t), intent(in) :: model
        character(len=*), intent(in) :: outdir
        real(dp), intent(in) :: endtim
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        type(states_t), intent(out) :: s
        logical, intent(out) :: ok
        type(states_marks_t), intent(in), optional :: resume
        logical, intent(in), optional :: writer   !< .false.: keep the schedule only (MPI ranks > 0)
        type(beams_t), intent(in), optional :: bm   !< beams (the binary d3plot carries them)
        integer :: err, k, e
        integer(hid_t) :: g
        logical :: there
        character(len=16) :: name
        integer, allocatable :: rhex(:), rshell(:)
        ok = .true.
        s%dt = real(model%db%d3plot_dt, dp)
        if (model%db%d3plot_npltc > 0) s%dt = endtim/model%db%d3plot_npltc
        s%on = s%dt > 0.0_dp
        if (.not. s%on) return
        s%dir = outdir
        s%nnode = model%nnode
        rhex = pack([(e, e=1, model%nhex)], model%mat(model%part(model%hex_part(1:model%nhex))%mat_ix)%mtype == mat_rigid)
        rshell = pack([(e, e=1, model%nshell)], &
                      model%mat(model%part(model%shell_part(1:model%nshell))%mat_ix)%mtype == mat_rigid)
        s%nrhex = size(rhex)
        s%nrshell = size(rshell)
        s%nsolid = solids%n + s%nrhex
        s%nshell = sh%n + s%nrshell
        if (present(bm)) then
            s%nbeam = bm%n
            if (bm%n > 0) s%weld = any(bm%weld)
        end if
        s%rshell_t = [(shell_thickness(model, rshell(e)), e=1, s%nrshell)]
        s%contact = model%ncontact > 0
        allocate (s%times(0))
        if (present(writer)) s%writer = writer
        s%h5 = model%db%d3plot_h5
        s%binary = model%db%d3plot_binary
        if (sh%n > 0) s%maxint = max(3, sh%nipmax)
        if (present(resume)) then
            s%n = resume%n
            s%next = resume%next
            s%times = resume%times
        end if
        if (.not. s%writer) return
        if (model%db%d3plot_binary) then
            call open_binary(model, outdir, solids, sh, rhex, rshell, s, ok, resume, bm)
            if (.not. ok) return
        end if
        if (.not. s%h5) return
        call h5open_f(err)
        if (present(resume)) then
            call h5fopen_f(out_path(outdir, 'd3plot.h5'), H5F_ACC_RDWR_F, s%file, err)
            ok = err == 0
            if (.not. ok) return
            k = s%n
            do
                k = k + 1
                write (name, '(a,i6.6)') 'states/', k
                call h5lexists_f(s%file, trim(name), there, err)
                if (.not. there) exit
                call h5ldelete_f(s%file, trim(name), err)
            end do
            call set_times(s)
            call h5fflush_f(s%file, H5F_SCOPE_GLOBAL_F, err)
            call write_xdmf(s)
            return
        end if
        call h5fcreate_f(out_path(outdir, 'd3plot.h5'), H5F_ACC_TRUNC_F, s%file, err)
        ok = err == 0
        if (.not. ok) return
        call h5gcreate_f(s%file, 'mesh', g, err)
        call put_int1(g, 'node_ids', model%node_id(1:model%nnode))
        if (s%nsolid > 0) then
            call put_int2(g, 'solid_connectivity', reshape([solids%conn, model%hex_conn(:, rhex)], [8, s%nsolid]) - 1)
            call put_int1(g, 'solid_ids', [solids%eid, model%hex_id(rhex)])
            call put_int1(g, 'solid_part', model%part([solids%part, model%hex_part(rhex)])%id)
        end if
        if (s%nshell > 0) then
            call put_int2(g, 'shell_connectivity', reshape([sh%conn, model%shell_conn(:, rshell)], [4, s%nshell]) - 1)
            call put_int1(g, 'shell_ids', [sh%eid, model%shell_id(rshell)])
            call put_int1(g, 'shell_part', model%part([sh%part, model%shell_part(rshell)])%id)
        end if
        if (s%nbeam > 0) then
            call put_int2(g, 'beam_connectivity', bm%conn - 1)
            call put_int1(g, 'beam_ids', bm%eid)
            call put_int1(g, 'beam_part', model%part(bm%part)%id)
        end if
        call h5gclose_f(g, err)
        call h5gcreate_f(s%file, 'states', g, err)
        call h5gclose_f(g, err)
        call h5fflush_f(s%file, H5F_SCOPE_GLOBAL_F, err)
    end subroutine open_states

    !> The binary d3plot family's first member (or, on a restart, the family
    !> cut back to the dump's states).
    subroutine open_binary(model, outdir, solids, sh, rhex, rshell, s, ok, resume, bm)
        type(model_t), intent(in) :: model
        character(len=*), intent(in) :: outdir
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        integer, intent(in) :: rhex(:), rshell(:)
        type(states_t), intent(inout) :: s
        logical, intent(out) :: ok
        type(states_marks_t), intent(in), optional :: resume
        type(beams_t), intent(in), optional :: bm
        type(d3plot_mesh_t) :: m
        integer, allocatable :: spart(:), hpart(:), dmat(:)
        logical, allocatable :: with_solid(:), with_shell(:)
        integer :: p, k, keep, e
        integer, allocatable :: hconn(:, :), hid(:)
        ! the deformable elements (a model without shells has none allocated),
        ! then the rigid ones
        allocate (hpart(0), hconn(4, 0), hid(0))
        if (sh%n > 0) then
            hpart = sh%part(1:sh%n)
            hconn = sh%conn(:, 1:sh%n)
            hid = sh%eid(1:sh%n)
        end if
        hpart = [hpart, model%shell_part(rshell)]
        spart = [solids%part, model%hex_part(rhex)]
        ! the materials: parts with hexahedra, then parts with shells
        allocate (with_solid(model%npart), with_shell(model%npart), dmat(model%npart))
        with_solid = .false.
        with_shell = .false.
        with_solid(spart) = .true.
        with_shell(hpart) = .true.
        dmat = 0
        k = 0
        do p = 1, model%npart
            if (.not. with_solid(p)) cycle
            k = k + 1
            dmat(p) = k
        end do
        m%nmat_solid = k
        do p = 1, model%npart
            if (.not. with_shell(p) .or. dmat(p) > 0) cycle
            k = k + 1
            dmat(p) = k
        end do
        m%nmat_shell = k - m%nmat_solid
        ! then parts with beams
        if (present(bm)) then
            if (bm%n > 0) then
                do e = 1, bm%n
                    p = bm%part(e)
                    if (dmat(p) > 0) cycle
                    k = k + 1
                    dmat(p) = k
                end do
                m%nmat_beam = k - m%nmat_solid - m%nmat_shell
                m%beam_conn = reshape([(bm%conn(:, e), merge(model%beam_conn(3, e), bm%conn(2, e), &
                                        model%beam_conn(3, e) > 0), e=1, bm%n)], [3, bm%n])
                m%beam_mat = dmat(bm%part)
                m%beam_id = bm%eid
            end if
        end if
        allocate (s%dmat_part(k))
        do p = 1, model%npart
            if (dmat(p) > 0) s%dmat_part(dmat(p)) = p
        end do
        m%title = model%title
        m%x0 = real(model%x0(:, 1:model%nnode), kind(1.0e0))
        m%node_id = model%node_id(1:model%nnode)
        m%solid_conn = reshape([solids%conn, model%hex_conn(:, rhex)], [8, s%nsolid])
        m%solid_mat = dmat(spart)
        m%solid_id = [solids%eid, model%hex_id(rhex)]
        m%shell_conn = reshape([hconn, model%shell_conn(:, rshell)], [4, s%nshell])
        m%shell_mat = dmat(hpart)
        m%shell_id = [hid, model%shell_id(rshell)]
        m%part_id = model%part(s%dmat_part)%id
        m%part_title = model%part(s%dmat_part)%heading
        m%nrigid = count(model%mat(model%part(1:model%npart)%mat_ix)%mtype == mat_rigid)
        if (sh%n > 0) m%maxint = max(3, sh%nipmax)
        keep = -1
        if (present(resume)) keep = resume%n
        call d3plot_open(s%bin, out_path(outdir, 'd3plot'), m, model%db%d3plot_x*member_unit, keep, ok)
    end subroutine open_binary

    logical function states_due(s, time)
        type(states_t), intent(in) :: s
        real(dp), intent(in) :: time
        states_due = s%on .and. time >= s%next*(1.0_dp - 1.0e-12_dp)
    end function states_due

    !> One state at st%time: v is the velocity at that time, fc the contact
    !> force per node (absent: zero).
    subroutine write_state(s, st, x0, solids, sh, v, fc, en, bm)
        type(states_t), intent(inout) :: s
        type(state_t), intent(in) :: st
        real(wp), intent(in) :: x0(:, :)   !< the initial coordinates (the deck's)
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        real(wp), intent(in) :: v(:, :)
        real(wp), intent(in), optional :: fc(:, :)
        type(energies_t), intent(in), optional :: en   !< the energies at st%time (absent: zero in the d3plot)
        type(beams_t), intent(in), optional :: bm
        character(len=16) :: name
        integer(hid_t) :: g, sp, at
        integer(hsize_t) :: d1(1)
        integer :: err, e, ip
        real(wp), allocatable :: sig(:, :), vm(:), ep(:), th(:)
        real(wp) :: sg(6), r(3, 3), q2, w
        real(wp), allocatable :: bres(:, :)
        if (.not. s%on) return
        if (.not. take_state(s, st%time)) return
        if (s%bin%on) then
            call write_binary(s, st, solids, sh, v, en, bm)
            if (s%failed) return
        end if
        if (.not. s%h5) return
        write (name, '(a,i6.6)') 'states/', s%n
        call h5gcreate_f(s%file, trim(name), g, err)
        d1 = 1
        call h5screate_simple_f(1, d1, sp, err)
        call h5acreate_f(g, 'time', H5T_NATIVE_DOUBLE, sp, at, err)
        call h5awrite_f(at, H5T_NATIVE_DOUBLE, [st%time], d1, err)
        call h5aclose_f(at, err)
        call h5sclose_f(sp, err)
        call put_real2(g, 'coordinates', st%x)
        call put_real2(g, 'displacement', st%x - x0)
        call put_real2(g, 'velocity', v)
        if (s%contact .and. present(fc)) then
            call put_real2(g, 'contact_force', fc)
        else if (s%contact) then
            call put_real2(g, 'contact_force', 0.0_wp*st%x)
        end if
        if (s%nsolid > 0) then
            allocate (sig(6, s%nsolid), vm(s%nsolid), ep(s%nsolid))
            ep = 0
            sig = 0
            vm = 0
            !$omp parallel do schedule(static)
            do e = 1, solids%n
                sig(:, e) = solids%stress(e)
                vm(e) = von_mises(sig(:, e))
            end do
            !$omp end parallel do
            if (size(solids%epsp) > 0) ep(1:solids%n) = solids%epsp
            call put_real2(g, 'solid_stress', sig)
            call put_real1(g, 'solid_von_mises', vm)
            call put_real1(g, 'solid_plastic_strain', ep)
            ! with erosion possible: 1 for a solid in the model, 0 once eroded
            if (solids%erodible) then
                vm = 1
                where (solids%dead) vm(1:solids%n) = 0
                call put_real1(g, 'solid_alive', vm)
            end if
            deallocate (sig, vm, ep)
        end if
        if (s%nshell > 0) then
            allocate (sig(6, s%nshell), vm(s%nshell), ep(s%nshell), th(s%nshell))
            sig = 0
            vm = 0
            ep = 0
            th(sh%n + 1:) = s%rshell_t
            ! each element writes its own entries: threaded, the same result
            !$omp parallel do schedule(static) private(q2, sg, ip, w, r)
            do e = 1, sh%n
                q2 = 0
                ep(e) = 0
                sg = 0
                do ip = 1, sh%pc%nip(sh%part(e))
                    ! local (xx yy xy yz zx) at the point, plane stress: the
                    ! squared von Mises stress, the largest kept
                    associate (p => sh%sig(e, :, ip))
                        q2 = max(q2, p(1)**2 - p(1)*p(2) + p(2)**2 + 3.0_wp*(p(3)**2 + p(4)**2 + p(5)**2))
                        w = point_weight(ip, sh%pc%nip(sh%part(e)))
                        sg(1) = sg(1) + w*p(1)
                        sg(2) = sg(2) + w*p(2)
                        sg(4) = sg(4) + w*p(3)
                        sg(5) = sg(5) + w*p(4)
                        sg(6) = sg(6) + w*p(5)
                    end associate
                    if (sh%pc%plastic(sh%part(e))) ep(e) = max(ep(e), sh%epsp(e, ip))
                end do
                vm(e) = sqrt(q2)
                call shell_axes(sh, e, st%x, r)
                sig(:, e) = to_global(sg, r)
                th(e) = sh%h(e)
            end do
            !$omp end parallel do
            call put_real2(g, 'shell_stress', sig)
            call put_real1(g, 'shell_von_mises', vm)
            call put_real1(g, 'shell_plastic_strain', ep)
            call put_real1(g, 'shell_thickness', th)
            ! with erosion possible: 1 for a shell in the model, 0 once eroded
            ! (the d3plot's deletion flags; rigid shells last, always 1)
            if (sh%erodible) then
                th = 1
                where (sh%dead) th(1:sh%n) = 0
                call put_real1(g, 'shell_alive', th)
            end if
        end if
        if (s%nbeam > 0 .and. present(bm)) then
            ! the binary d3plot's six: axial force, shears along s and t,
            ! moments about s and t at mid-length, torque
            allocate (bres(6, s%nbeam))
            do e = 1, s%nbeam
                bres(:, e) = beam_record(bm, st%x, e)
            end do
            call put_real2(g, 'beam_resultants', bres)
            ! 1 for a beam in the model, 0 once a weld has failed
            if (s%weld) call put_real1(g, 'beam_alive', [(merge(0.0_wp, 1.0_wp, bm%dead(e)), e=1, s%nbeam)])
        end if
        call h5gclose_f(g, err)
        ! the list of times, rewritten whole (small)
        call set_times(s)
        call h5fflush_f(s%file, H5F_SCOPE_GLOBAL_F, err)
        if (err /= 0) then
            ! the XDMF keeps naming the states written before
            s%failed = .true.
            s%failed_file = out_path(s%dir, 'd3plot.h5')
            return
        end if
        call write_xdmf(s)
    end subroutine write_state

    !> A state at `time` taken into the schedule and counted (every rank
    !> alike); true where this process writes it (the writer, no write
    !> failed before).
    logical function take_state(s, time) result(writes)
        type(states_t), intent(inout) :: s
        real(dp), intent(in) :: time
        ! (a state asked off the schedule, sense switch sw4, leaves it as it is)
        if (states_due(s, time)) then
            s%next = s%next + s%dt
            if (time >= s%next) s%next = time + s%dt
        end if
        s%n = s%n + 1
        s%times = [s%times, time]
        writes = s%writer .and. .not. s%failed
    end function take_state

    !> The binary family's words a shell (every rank knows it).
    pure integer function state_nv2d(s) result(n)
        type(states_t), intent(in) :: s
        n = 7*s%maxint + 12
    end function state_nv2d

    !> One state of the binary d3plot family.
    subroutine write_binary(s, st, solids, sh, v, en, bm)
        type(states_t), intent(inout) :: s
        type(state_t), intent(in) :: st
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        real(wp), intent(in) :: v(:, :)
        type(energies_t), intent(in), optional :: en
        type(beams_t), intent(in), optional :: bm
        real(sp), allocatable :: shell(:, :)
        integer :: e, a, b
        call binary_head(s, st, solids, v, en, bm)
        ! the deformable shells, a chunk at a time (each element writes its
        ! own words: threaded, the same result)
        allocate (shell(state_nv2d(s), min(chunk, max(sh%n, 1))))
        do a = 1, sh%n, chunk
            b = min(a + chunk - 1, sh%n)
            !$omp parallel do schedule(static)
            do e = a, b
                call shell_state_words(sh, st%x, e, e, e, s%maxint, shell(:, e - a + 1))
            end do
            !$omp end parallel do
            call binary_put(s, shell, state_nv2d(s)*(b - a + 1))
        end do
        call binary_tail(s, sh, solids, bm)
    end subroutine write_binary

    !> A binary state's words up to the shells': the time and the global
    !> variables, the nodes' coordinates and velocities v, the solids' and
    !> the beams' words (the writer alone).
    subroutine binary_head(s, st, solids, v, en, bm)
        type(states_t), intent(inout) :: s
        type(state_t), intent(in) :: st
        type(solids_t), intent(in) :: solids
        real(wp), intent(in) :: v(:, :)
        type(energies_t), intent(in), optional :: en
        type(beams_t), intent(in), optional :: bm
        real(sp), allocatable :: beam(:, :)
        real(sp), allocatable :: glob(:), solid(:, :), xs(:, :)
        integer :: e, nm, k, j
        nm = size(s%dmat_part)
        allocate (glob(s%bin%nglbv), solid(7, s%nsolid))
        glob = 0
        if (present(en)) then
            glob(1:6) = real([en%ke, en%ie, en%total, en%vel], sp)
            if (allocated(en%part_ie)) then
                k = 6
                glob(k + 1:k + nm) = real(en%part_ie(s%dmat_part), sp)
                k = k + nm
                glob(k + 1:k + nm) = real(en%part_ke(s%dmat_part), sp)
                k = k + nm
                do j = 1, nm
                    associate (p => s%dmat_part(j))
                        if (en%part_mass(p) > 0) glob(k + 3*j - 2:k + 3*j) = real(en%part_mom(:, p)/en%part_mass(p), sp)
                    end associate
                end do
                k = k + 3*nm
                glob(k + 1:k + nm) = real(en%part_mass(s%dmat_part), sp)
                k = k + nm
                glob(k + 1:k + nm) = real(en%part_hg(s%dmat_part), sp)
            end if
        end if
        solid = 0
        !$omp parallel do schedule(static)
        do e = 1, solids%n
            solid(1:6, e) = real(solids%stress(e), sp)
        end do
        !$omp end parallel do
        if (size(solids%epsp) > 0) solid(7, 1:solids%n) = real(solids%epsp, sp)
        call d3plot_begin_state(s%bin, st%time)
        call d3plot_put(s%bin, glob, size(glob))
        ! the nodes' coordinates, then their velocities
        allocate (xs(3, min(chunk, s%nnode)))
        call put_nodes(st%x)
        call put_nodes(v)
        call d3plot_put(s%bin, solid, size(solid))
        ! beams: axial force, shears along s and t (the end moments' sum
        ! over the length), moments about s and t at mid-length, torque
        allocate (beam(6, s%bin%nbeam))
        beam = 0
        if (present(bm)) then
            do e = 1, min(bm%n, s%bin%nbeam)
                beam(:, e) = real(beam_record(bm, st%x, e), sp)
            end do
        end if
        call d3plot_put(s%bin, beam, size(beam))
    contains
        !> a(:, 1:nnode) in single precision, a chunk of nodes at a time
        subroutine put_nodes(a3)
            real(wp), intent(in) :: a3(:, :)
            integer :: a, b, i
            do a = 1, s%nnode, chunk
                b = min(a + chunk - 1, s%nnode)
                do i = a, b
                    xs(:, i - a + 1) = real(a3(:, i), sp)
                end do
                call d3plot_put(s%bin, xs, 3*(b - a + 1))
            end do
        end subroutine put_nodes
    end subroutine binary_head

    !> n words of the deformable shells (state_nv2d a shell, in the model's
    !> order), after binary_head (the writer alone).
    subroutine binary_put(s, w, n)
        type(states_t), intent(inout) :: s
        real(sp), intent(in) :: w(*)
        integer, intent(in) :: n
        call d3plot_put(s%bin, w, n)
    end subroutine binary_put

    !> A binary state's words after the deformable shells': the rigid
    !> shells' (their thickness alone) and every element's deletion flag;
    !> the state then ends (the writer alone; a write that failed marks s).
    subroutine binary_tail(s, sh, solids, bm)
        type(states_t), intent(inout) :: s
        type(shells_t), intent(in) :: sh
        type(solids_t), intent(in) :: solids
        type(beams_t), intent(in), optional :: bm
        real(sp), allocatable :: shell(:, :), alive(:)
        integer :: e, a, b
        allocate (shell(state_nv2d(s), min(chunk, max(s%nrshell, 1))))
        do a = 1, s%nrshell, chunk
            b = min(a + chunk - 1, s%nrshell)
            shell = 0
            do e = a, b
                shell(7*s%maxint + 9, e - a + 1) = real(s%rshell_t(e), sp)
            end do
            call d3plot_put(s%bin, shell, state_nv2d(s)*(b - a + 1))
        end do
        allocate (alive(s%nsolid + s%nshell + s%bin%nbeam))
        alive = 1
        if (present(bm)) then
            do e = 1, min(bm%n, s%bin%nbeam)
                if (bm%dead(e)) alive(s%nsolid + s%nshell + e) = 0
            end do
        end if
        ! eroded solids and shells: deletion flag 0 (the deformable ones come
        ! first in their kind)
        if (solids%ndead > 0) where (solids%dead) alive(1:solids%n) = 0
        if (sh%n > 0) then
            if (sh%ndead > 0) where (sh%dead) alive(s%nsolid + 1:s%nsolid + sh%n) = 0
        end if
        call d3plot_put(s%bin, alive, size(alive))
        call d3plot_end_state(s%bin)
        if (s%bin%failed) then
            s%failed = .true.
            s%failed_file = s%bin%failed_file
        end if
    end subroutine binary_tail



    !> The d3hsp line naming the states written and where.
    function states_summary(s) result(line)
        type(states_t), intent(in) :: s
        character(len=:), allocatable :: line
        character(len=120) :: b
        write (b, '(a,i0,a)') ' states: ', s%n, ' written'
        line = trim(b)
        if (s%bin%on) then
            write (b, '(a,i0,a,i0,a)') ', the d3plot family in ', s%bin%member + 1, ' member(s) of ', &
                s%bin%limit, ' words at most'
            line = line//trim(b)
        end if
        if (s%h5) line = line//', d3plot.h5 + d3plot.xdmf'
    end function states_summary

    !> The file a state's write failed on ('' if none).
    function states_failure(s) result(name)
        type(states_t), intent(in) :: s
        character(len=:), allocatable :: name
        name = ''
        if (s%failed) name = s%failed_file
    end function states_failure

    !> states/time: an extendible dataset set to s%times (grown in place, so
    !> that a run killed at any moment leaves it readable).
    subroutine set_times(s)
        type(states_t), intent(in) :: s
        integer(hid_t) :: ds, sp, pl
        integer(hsize_t) :: d(1), mx(1), ch(1)
        integer :: err
        logical :: there
        call h5lexists_f(s%file, 'states/time', there, err)
        if (.not. there) then
            d = 0
            mx = H5S_UNLIMITED_F
            ch = 64
            call h5screate_simple_f(1, d, sp, err, mx)
            call h5pcreate_f(H5P_DATASET_CREATE_F, pl, err)
            call h5pset_chunk_f(pl, 1, ch, err)
            call h5dcreate_f(s%file, 'states/time', H5T_NATIVE_DOUBLE, sp, ds, err, pl)
            call h5pclose_f(pl, err)
            call h5sclose_f(sp, err)
        else
            call h5dopen_f(s%file, 'states/time', ds, err)
        end if
        d = size(s%times)
        call h5dset_extent_f(ds, d, err)
        if (size(s%times) > 0) call h5dwrite_f(ds, H5T_NATIVE_DOUBLE, s%times, d, err)
        call h5dclose_f(ds, err)
    end subroutine set_times

    subroutine close_states(s)
        type(states_t), intent(inout) :: s
        integer :: err
        call d3plot_close(s%bin)
        if (.not. s%on .or. s%file < 0) return
        call h5fclose_f(s%file, err)
        s%file = -1
    end subroutine close_states

    !> The XDMF 3 description: a temporal collection of states, each a
    !> spatial collection of the solid and the shell grids on the same nodes.
    subroutine write_xdmf(s)
        type(states_t), intent(inout) :: s
        integer :: u, k, ios, nbad
        integer(i8) :: sz
        character(len=:), allocatable :: tmp, st
        character(len=32) :: nn, ns, nh, tv
        character(len=300) :: buf
        tmp = out_path(s%dir, 'd3plot.xdmf.tmp')
        write (nn, '(i0)') s%nnode
        write (ns, '(i0)') s%nsolid
        write (nh, '(i0)') s%nshell
        nbad = 0
        open (newunit=u, file=tmp, status='replace', action='write', iostat=ios)
        if (ios /= 0) then
            s%failed = .true.
            s%failed_file = tmp
            return
        end if
        write (u, '(a)', iostat=ios) '<?xml version="1.0" ?>', '<Xdmf Version="3.0">', ' <Domain>', &
            '  <Grid Name="states" GridType="Collection" CollectionType="Temporal">'
        if (ios /= 0) nbad = nbad + 1
        do k = 1, s%n
            write (buf, '(a,i6.6)') h5name(s)//':/states/', k
            st = trim(buf)
            write (tv, '(es24.16)') s%times(k)
            write (u, '(a)', iostat=ios) '   <Grid Name="state '//itoa0(k)//'" GridType="Collection" CollectionType="Spatial">', &
                '    <Time Value="'//trim(adjustl(tv))//'"/>'
            if (ios /= 0) nbad = nbad + 1
            if (s%nsolid > 0) call piece('solids', 'Hexahedron', ns, '8', 'solid')
            if (s%nshell > 0) call piece('shells', 'Quadrilateral', nh, '4', 'shell')
            if (s%nbeam > 0) call beam_piece()
            write (u, '(a)', iostat=ios) '   </Grid>'
            if (ios /= 0) nbad = nbad + 1
        end do
        write (u, '(a)', iostat=ios) '  </Grid>', ' </Domain>', '</Xdmf>'
        if (ios /= 0) nbad = nbad + 1
        flush (u, iostat=ios)
        inquire (unit=u, size=sz)
        if (ios /= 0 .or. written_bytes(u) /= sz) nbad = nbad + 1
        close (u, iostat=ios)
        if (ios /= 0) nbad = nbad + 1
        ! a failed write leaves the last complete description, no temporary
        if (nbad == 0) then
            call rename_file(tmp, out_path(s%dir, 'd3plot.xdmf'))
        else
            call delete_file(tmp)
            s%failed = .true.
            s%failed_file = out_path(s%dir, 'd3plot.xdmf')
        end if
    contains
        !> The beams as line cells with their resultants (no stress tensor).
        subroutine beam_piece()
            character(len=32) :: nb
            character(len=*), parameter :: names(6) = [character(len=14) :: 'axial_force', 'shear_s', 'shear_t', &
                                                       'moment_s', 'moment_t', 'torque']
            integer :: j
            write (nb, '(i0)') s%nbeam
            write (u, '(a)', iostat=ios) '    <Grid Name="beams" GridType="Uniform">', &
                '     <Topology TopologyType="Polyline" NodesPerElement="2" NumberOfElements="'//trim(nb)//'">', &
                '      <DataItem Dimensions="'//trim(nb)//' 2" NumberType="Int" Format="HDF">'// &
                h5name(s)//':/mesh/beam_connectivity</DataItem>', '     </Topology>', &
                '     <Geometry GeometryType="XYZ">', &
                '      <DataItem Dimensions="'//trim(nn)//' 3" NumberType="Float" Precision="4" Format="HDF">'// &
                st//'/coordinates</DataItem>', '     </Geometry>'
            if (ios /= 0) nbad = nbad + 1
            call attr('part', 'Scalar', 'Cell', trim(nb), 'Int', '4', h5name(s)//':/mesh/beam_part')
            call attr('node_id', 'Scalar', 'Node', trim(nn), 'Int', '4', h5name(s)//':/mesh/node_ids')
            call attr('element_id', 'Scalar', 'Cell', trim(nb), 'Int', '4', h5name(s)//':/mesh/beam_ids')
            call attr('displacement', 'Vector', 'Node', trim(nn)//' 3', 'Float', '4', st//'/displacement')
            call attr('velocity', 'Vector', 'Node', trim(nn)//' 3', 'Float', '4', st//'/velocity')
            ! each resultant a column of beam_resultants (a hyperslab)
            do j = 1, 6
                write (u, '(a)', iostat=ios) '     <Attribute Name="'//trim(names(j))// &
                    '" AttributeType="Scalar" Center="Cell">', &
                    '      <DataItem ItemType="HyperSlab" Dimensions="'//trim(nb)//' 1" Type="HyperSlab">', &
                    '       <DataItem Dimensions="3 2" Format="XML">0 '//itoa0(j - 1)//' 1 1 '//trim(nb)//' 1</DataItem>', &
                    '       <DataItem Dimensions="'//trim(nb)//' 6" NumberType="Float" Precision="4" Format="HDF">'// &
                    st//'/beam_resultants</DataItem>', '      </DataItem>', '     </Attribute>'
                if (ios /= 0) nbad = nbad + 1
            end do
            if (s%weld) call attr('alive', 'Scalar', 'Cell', trim(nb), 'Float', '4', st//'/beam_alive')
            write (u, '(a)', iostat=ios) '    </Grid>'
            if (ios /= 0) nbad = nbad + 1
        end subroutine beam_piece
        subroutine piece(gname, topo, ne, npe, pre)
            character(len=*), intent(in) :: gname, topo, ne, npe, pre
            write (u, '(a)', iostat=ios) '    <Grid Name="'//gname//'" GridType="Uniform">', &
                '     <Topology TopologyType="'//topo//'" NumberOfElements="'//trim(ne)//'">', &
                '      <DataItem Dimensions="'//trim(ne)//' '//npe//'" NumberType="Int" Format="HDF">'// &
                h5name(s)//':/mesh/'//pre//'_connectivity</DataItem>', '     </Topology>', &
                '     <Geometry GeometryType="XYZ">', &
                '      <DataItem Dimensions="'//trim(nn)//' 3" NumberType="Float" Precision="4" Format="HDF">'// &
                st//'/coordinates</DataItem>', '     </Geometry>'
            if (ios /= 0) nbad = nbad + 1
            call attr('part', 'Scalar', 'Cell', trim(ne), 'Int', '4', h5name(s)//':/mesh/'//pre//'_part')
            ! the deck's ids, so that an entity can be picked or found by them
            call attr('node_id', 'Scalar', 'Node', trim(nn), 'Int', '4', h5name(s)//':/mesh/node_ids')
            call attr('element_id', 'Scalar', 'Cell', trim(ne), 'Int', '4', h5name(s)//':/mesh/'//pre//'_ids')
            call attr('displacement', 'Vector', 'Node', trim(nn)//' 3', 'Float', '4', st//'/displacement')
            call attr('velocity', 'Vector', 'Node', trim(nn)//' 3', 'Float', '4', st//'/velocity')
            if (s%contact) call attr('contact_force', 'Vector', 'Node', trim(nn)//' 3', 'Float', '4', &
                                    st//'/contact_force')
            call attr('stress', 'Tensor6', 'Cell', trim(ne)//' 6', 'Float', '4', st//'/'//pre//'_stress')
            call attr('von_mises', 'Scalar', 'Cell', trim(ne), 'Float', '4', st//'/'//pre//'_von_mises')
            call attr('plastic_strain', 'Scalar', 'Cell', trim(ne), 'Float', '4', st//'/'//pre//'_plastic_strain')
            if (pre == 'shell') call attr('thickness', 'Scalar', 'Cell', trim(ne), 'Float', '4', st//'/shell_thickness')
            write (u, '(a)', iostat=ios) '    </Grid>'
            if (ios /= 0) nbad = nbad + 1
        end subroutine piece
        subroutine attr(aname, atype, centre, dims, ntype, prec, path)
            character(len=*), intent(in) :: aname, atype, centre, dims, ntype, prec, path
            write (u, '(a)', iostat=ios) '     <Attribute Name="'//aname//'" AttributeType="'//atype//'" Center="'//centre//'">', &
                '      <DataItem Dimensions="'//dims//'" NumberType="'//ntype//'" Precision="'//prec// &
                '" Format="HDF">'//path//'</DataItem>', '     </Attribute>'
            if (ios /= 0) nbad = nbad + 1
        end subroutine attr
    end subroutine write_xdmf

    !> Beam e's record for the states (the binary d3plot's and d3plot.h5's):
    !> axial force, shears along s and t (the end moments' sum over the
    !> present length), moments about s and t at mid-length, torque.
    pure function beam_record(bm, x, e) result(r)
        type(beams_t), intent(in) :: bm
        real(wp), intent(in) :: x(:, :)
        integer, intent(in) :: e
        real(wp) :: r(6), lb
        lb = norm2(x(:, bm%conn(2, e)) - x(:, bm%conn(1, e)))
        r = [bm%res(1, e), (bm%res(5, e) + bm%res(6, e))/lb, (bm%res(3, e) + bm%res(4, e))/lb, &
             0.5_wp*(bm%res(3, e) - bm%res(4, e)), 0.5_wp*(bm%res(5, e) - bm%res(6, e)), bm%res(2, e)]
    end function beam_record

    function itoa0(i) result(t)
        integer, intent(in) :: i
        character(len=:), allocatable :: t
        character(len=16) :: b
        write (b, '(i0)') i
        t = trim(b)
    end function itoa0

    pure real(wp) function von_mises(s) result(q)
        real(wp), intent(in) :: s(6)
        q = sqrt(0.5_wp*((s(1) - s(2))**2 + (s(2) - s(3))**2 + (s(3) - s(1))**2) + 3.0_wp*(s(4)**2 + s(5)**2 + s(6)**2))
    end function von_mises


    !> A dataset of the given dims (Fortran order; h5py sees them reversed)
    !> and type from the buffer at buf.
    subroutine put_dataset(g, name, dims, t, buf)
        use, intrinsic :: iso_c_binding, only: c_ptr
        integer(hid_t), intent(in) :: g, t
        character(len=*), intent(in) :: name
        integer, intent(in) :: dims(:)
        type(c_ptr), intent(in) :: buf
        integer(hid_t) :: sp, ds
        integer :: err
        call h5screate_simple_f(size(dims), int(dims, hsize_t), sp, err)
        call h5dcreate_f(g, name, t, sp, ds, err)
        if (product(dims) > 0) call h5dwrite_f(ds, t, buf, err)
        call h5dclose_f(ds, err)
        call h5sclose_f(sp, err)
    end subroutine put_dataset

    subroutine put_int1(g, name, a)
        use, intrinsic :: iso_c_binding, only: c_loc
        integer(hid_t), intent(in) :: g
        character(len=*), intent(in) :: name
        integer, intent(in) :: a(:)
        integer, allocatable, target :: b(:)
        allocate (b(max(size(a), 1)))
        b(1:size(a)) = a
        call put_dataset(g, name, [size(a)], H5T_NATIVE_INTEGER, c_loc(b))
    end subroutine put_int1

    subroutine put_int2(g, name, a)
        use, intrinsic :: iso_c_binding, only: c_loc
        integer(hid_t), intent(in) :: g
        character(len=*), intent(in) :: name
        integer, intent(in) :: a(:, :)
        integer, allocatable, target :: b(:, :)
        allocate (b(size(a, 1), max(size(a, 2), 1)))
        b(:, 1:size(a, 2)) = a
        call put_dataset(g, name, shape(a), H5T_NATIVE_INTEGER, c_loc(b))
    end subroutine put_int2

    !> Fields in single precision, like LS-DYNA's d3plot.
    subroutine put_real2(g, name, a)
        use, intrinsic :: iso_c_binding, only: c_loc
        integer(hid_t), intent(in) :: g
        character(len=*), intent(in) :: name
        real(wp), intent(in) :: a(:, :)
        real(kind(1.0e0)), allocatable, target :: b(:, :)
        allocate (b(size(a, 1), max(size(a, 2), 1)))
        b(:, 1:size(a, 2)) = real(a, kind(1.0e0))
        call put_dataset(g, name, shape(a), H5T_NATIVE_REAL, c_loc(b))
    end subroutine put_real2

    subroutine put_real1(g, name, a)
        use, intrinsic :: iso_c_binding, only: c_loc
        integer(hid_t), intent(in) :: g
        character(len=*), intent(in) :: name
        real(wp), intent(in) :: a(:)
        real(kind(1.0e0)), allocatable, target :: b(:)
        allocate (b(max(size(a), 1)))
        b(1:size(a)) = real(a, kind(1.0e0))
        call put_dataset(g, name, [size(a)], H5T_NATIVE_REAL, c_loc(b))
    end subroutine put_real1

    !> The name of the HDF5 file as the XDMF file beside it refers to it.
    function h5name(s) result(n)
        type(states_t), intent(in) :: s
        character(len=:), allocatable :: n
        integer :: k
        n = out_path(s%dir, 'd3plot.h5')
        k = index(n, '/', back=.true.)
        n = n(k + 1:)
    end function h5name

end module xd_output_states
