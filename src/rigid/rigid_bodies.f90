!> Rigid bodies: the parts of *MAT_RIGID. Mass, centre and inertia come from
!> their elements (3x3x3 Gauss points, exact for trilinear hexahedra), the
!> principal axes from LAPACK. Each cycle the nodal forces on a body give its
!> force and torque; the centre moves by central differences and the
!> orientation by the midpoint rule on the spatial angular momentum with
!> Cayley rotations (orthogonal to rounding; torque-free motion keeps its
!> angular momentum exactly and its energy to O((omega dt)^2)). The body's
!> nodes follow it: their positions are placed on the body and their
!> velocities are the chords.
module xd_rigid_bodies
    use xd_kinds, only: wp, dp
    use xd_core_errors, only: error_t, make_error
    use xd_core_strings, only: itoa
    use xd_model, only: model_t, mat_rigid, find_set, set_node, curve_value, constraint_dirs, mark_part_nodes
    use xd_solver_state, only: state_t
    use xd_core_vectors, only: cross
    use xd_contact_rigidwall, only: walls_t, wall_distance, wall_normal_force
    use xd_contact_enforcement, only: body_response_t
    implicit none
    logical, parameter :: coords_64 = precision(1.0_wp) >= 15   !< 64-bit field data (the default build)
    private
    public :: rigid_t, rigid_body_t, rigid_lumped_mass, build_rigid, rigid_step, rigid_energy, is_rigid_part, &
              rigid_response

    type :: rigid_body_t
        integer :: part = 0                 !< *MAT_RIGID part, 0 for a node-set body
        logical :: from_part = .true.       !< mass properties from elements (else nodal masses)
        !> its mass and inertia its own (a part, or *CONSTRAINED_NODAL_RIGID_BODY
        !> _INERTIA): the energies take the body's, not its nodes'
        logical :: own = .true.
        logical :: v_given = .false.        !< _INERTIA: the initial velocities the deck gives
        real(dp) :: vt0(3) = 0, vr0(3) = 0
        logical :: active = .true.
        real(dp) :: tfail = 1.0e20_dp       !< spot weld: released at this time
        integer, allocatable :: pres(:)     !< its *BOUNDARY_PRESCRIBED_MOTION_RIGID entries
        real(dp) :: xc0(3) = 0
        integer, allocatable :: node(:)
        real(dp), allocatable :: r(:, :)    !< (3, nodes) node positions in the body frame, from the centre
        real(dp) :: mass = 0
        real(dp) :: xc(3) = 0, vc(3) = 0, vc_old(3) = 0
        real(dp) :: jprev(3) = 0            !< last cycle's prescribed impulse per unit mass (vc - predicted)
        real(dp) :: ib(3) = 0               !< principal moments of inertia
        real(dp) :: q(3, 3) = 0             !< orientation: columns are the body axes in global
        real(dp) :: pi(3) = 0               !< spatial angular momentum at n+1/2
        real(dp) :: omega(3) = 0, omega_old(3) = 0
        logical :: fix_t(3) = .false., fix_r(3) = .false.
        logical :: line(3) = .false.        !< principal axes without inertia (nodes on one line)
    end type rigid_body_t

    type :: rigid_t
        integer :: n = 0
        type(rigid_body_t), allocatable :: b(:)
        logical, allocatable :: on(:)       !< node's mass belongs to a part-based rigid body
        logical, allocatable :: member(:)   !< node of an active rigid body (it moves with it)
    end type rigid_t

contains

    pure logical function is_rigid_part(model, p)
        type(model_t), intent(in) :: model
        integer, intent(in) :: p
        is_rigid_part = model%mat(model%part(p)%mat_ix)%mtype == mat_rigid
    end function is_rigid_part

    !> Lumped nodal masses of the rigid elements (for body loads and so that
    !> rigid nodes are not taken for massless ones).
    subroutine rigid_lumped_mass(model, st)
        type(model_t), intent(in) :: model
        type(state_t), intent(inout) :: st
        integer :: e, p, nn
        real(dp) :: xi(3), x(8, 3)
        real(dp), allocatable :: scale(:), mp(:), mh(:), ms(:)
        logical, allocatable :: mark(:)
        ! the rigid elements' masses once; *PART_INERTIA scales a part's to
        ! TM (or shares TM equally among the nodes of a part whose elements
        ! have no mass)
        allocate (scale(model%npart), mp(model%npart), mh(model%nhex), ms(model%nshell))
        scale = 1
        mp = 0
        mh = 0
        ms = 0
        do e = 1, model%nhex
            p = model%hex_part(e)
            if (.not. is_rigid_part(model, p)) cycle
            x = transpose(real(model%x0(:, model%hex_conn(:, e)), dp))
            call hex_mass_moments(x, real(model%mat(model%part(p)%mat_ix)%ro, dp), mh(e), xi)
            mp(p) = mp(p) + mh(e)
        end do
        do e = 1, model%nshell
            p = model%shell_part(e)
            if (.not. is_rigid_part(model, p)) cycle
            call shell_mass_moments(model, e, ms(e), xi)
            mp(p) = mp(p) + ms(e)
        end do
        do p = 1, model%npart
            if (model%part(p)%inertia .and. mp(p) > 0.0_dp) scale(p) = real(model%part(p)%tm, dp)/mp(p)
        end do
        do e = 1, model%nhex
            p = model%hex_part(e)
            st%mass(model%hex_conn(:, e)) = st%mass(model%hex_conn(:, e)) + real(scale(p)*mh(e)/8.0_dp, wp)
        end do
        do e = 1, model%nshell
            p = model%shell_part(e)
            st%mass(model%shell_conn(:, e)) = st%mass(model%shell_conn(:, e)) + real(scale(p)*ms(e)/4.0_dp, wp)
        end do
        allocate (mark(st%nnode))
        do p = 1, model%npart
            if (.not. (model%part(p)%inertia .and. mp(p) <= 0.0_dp)) cycle
            mark = .false.
            call mark_part_nodes(model, p, mark)
            nn = count(mark)
            if (nn > 0) where (mark) st%mass = st%mass + real(model%part(p)%tm/nn, wp)
        end do
    end subroutine rigid_lumped_mass

    !> Mass, first and second moments of a rigid shell: 2x2 Gauss points on
    !> the bilinear midsurface (exact for flat parallelograms), plus the
    !> thickness' own second moment m h^2/12 along the normal.
    subroutine shell_mass_moments(model, e, m, s1, j2)
        type(model_t), intent(in) :: model
        integer, intent(in) :: e
        real(dp), intent(out) :: m, s1(3)
        real(dp), intent(out), optional :: j2(3, 3)
        real(dp), parameter :: g = 1.0_dp/sqrt(3.0_dp)
        real(dp) :: x(3, 4), n(4), dxi(3), deta(3), nrm(3), xg(3), w, rho, h
        integer :: a, b, k
        real(dp), parameter :: xs(4) = [-1, 1, 1, -1], ys(4) = [-1, -1, 1, 1]
        x = real(model%x0(:, model%shell_conn(:, e)), dp)
        rho = real(model%mat(model%part(model%shell_part(e))%mat_ix)%ro, dp)
        h = real(sum(model%shell_t(:, e))/4, dp)
        m = 0
        s1 = 0
        if (present(j2)) j2 = 0
        do a = 1, 2
            do b = 1, 2
                n = (1 + xs*merge(-g, g, a == 1))*(1 + ys*merge(-g, g, b == 1))/4
                dxi = 0
                deta = 0
                do k = 1, 4
                    dxi = dxi + xs(k)*(1 + ys(k)*merge(-g, g, b == 1))/4*x(:, k)
                    deta = deta + ys(k)*(1 + xs(k)*merge(-g, g, a == 1))/4*x(:, k)
                end do
                nrm = cross(dxi, deta)
                w = rho*h*norm2(nrm)
                xg = matmul(x, n)
                m = m + w
                s1 = s1 + w*xg
                if (present(j2)) j2 = j2 + w*(spread(xg, 2, 3)*spread(xg, 1, 3) &
                                              + h**2/12*spread(nrm, 2, 3)*spread(nrm, 1, 3)/dot_product(nrm, nrm))
            end do
        end do
    end subroutine shell_mass_moments

    !> Mass (and first moment) of one hexahedron by 3x3x3 Gauss; with j2 the
    !> second moments sum rho x (x) x.
    subroutine hex_mass_moments(x, rho, m, s1, j2)
        real(dp), intent(in) :: x(8, 3), rho
        real(dp), intent(out) :: m, s1(3)
        real(dp), intent(out), optional :: j2(3, 3)
        real(dp), parameter :: gp(3) = [-sqrt(0.6_dp), 0.0_dp, sqrt(0.6_dp)], gw(3) = [5.0_dp, 8.0_dp, 5.0_dp]/9.0_dp
        real(dp), parameter :: xn(8, 3) = reshape([-1, 1, 1, -1, -1, 1, 1, -1, -1, -1, 1, 1, -1, -1, 1, 1, &
                                                   -1, -1, -1, -1, 1, 1, 1, 1], [8, 3])*1.0_dp
        real(dp) :: n(8), dn(8, 3), jac(3, 3), detj, xg(3), w
        integer :: a, b, c, k
        m = 0
        s1 = 0
        if (present(j2)) j2 = 0
        do a = 1, 3
            do b = 1, 3
                do c = 1, 3
                    do k = 1, 8
                        n(k) = (1 + xn(k, 1)*gp(a))*(1 + xn(k, 2)*gp(b))*(1 + xn(k, 3)*gp(c))/8
                        dn(k, 1) = xn(k, 1)*(1 + xn(k, 2)*gp(b))*(1 + xn(k, 3)*gp(c))/8
                        dn(k, 2) = xn(k, 2)*(1 + xn(k, 1)*gp(a))*(1 + xn(k, 3)*gp(c))/8
                        dn(k, 3) = xn(k, 3)*(1 + xn(k, 1)*gp(a))*(1 + xn(k, 2)*gp(b))/8
                    end do
                    jac = matmul(transpose(dn), x)
                    detj = jac(1, 1)*(jac(2, 2)*jac(3, 3) - jac(2, 3)*jac(3, 2)) &
                           - jac(1, 2)*(jac(2, 1)*jac(3, 3) - jac(2, 3)*jac(3, 1)) &
                           + jac(1, 3)*(jac(2, 1)*jac(3, 2) - jac(2, 2)*jac(3, 1))
                    w = rho*gw(a)*gw(b)*gw(c)*detj
                    xg = matmul(n, x)
                    m = m + w
                    s1 = s1 + w*xg
                    if (present(j2)) j2 = j2 + w*spread(xg, 2, 3)*spread(xg, 1, 3)
                end do
            end do
        end do
    end subroutine hex_mass_moments

    !> One rigid body per rigid part: mass properties, principal axes, node
    !> lists, constraints, and the initial motion fitted to the nodes' initial
    !> velocities (exact for a rigid velocity field).
    subroutine build_rigid(model, st, rg, error)
        type(model_t), intent(in) :: model
        type(state_t), intent(inout) :: st
        type(rigid_t), intent(out) :: rg
        type(error_t), allocatable, intent(out) :: error
        integer :: p, e, k, nb, s, i
        real(dp) :: m, s1(3), j2(3, 3), x(8, 3), jt(3, 3), rr(3)
        logical, allocatable :: mark(:), taken(:)
        allocate (rg%on(st%nnode), mark(st%nnode), taken(st%nnode))
        rg%on = .false.
        taken = .false.
        rg%n = count([(is_rigid_part(model, p), p=1, model%npart)]) + model%nnrb
        allocate (rg%b(rg%n))
        nb = 0
        do p = 1, model%npart
            if (.not. is_rigid_part(model, p)) cycle
            nb = nb + 1
            associate (b => rg%b(nb), mat => model%mat(model%part(p)%mat_ix))
                b%part = p
                mark = .false.
                jt = 0
                do e = 1, model%nhex
                    if (model%hex_part(e) /= p) cycle
                    x = transpose(real(model%x0(:, model%hex_conn(:, e)), dp))
                    call hex_mass_moments(x, real(mat%ro, dp), m, s1, j2)
                    b%mass = b%mass + m
                    b%xc = b%xc + s1
                    jt = jt + j2
                    mark(model%hex_conn(:, e)) = .true.
                end do
                do e = 1, model%nshell
                    if (model%shell_part(e) /= p) cycle
                    call shell_mass_moments(model, e, m, s1, j2)
                    b%mass = b%mass + m
                    b%xc = b%xc + s1
                    jt = jt + j2
                    mark(model%shell_conn(:, e)) = .true.
                end do
                ! *CONSTRAINED_EXTRA_NODES: more nodes of the body, whose
                ! mass (their elements' lumped share, point masses) it carries
                do i = 1, model%nxn
                    if (model%xn(i)%part_ix == p) mark(model%xn(i)%node_ix) = .true.
                end do
                call add_deformable_share(b, jt, mark)
                if (b%mass > 0.0_dp) then
                    b%xc = b%xc/b%mass
                    jt = jt - b%mass*spread(b%xc, 2, 3)*spread(b%xc, 1, 3)
                else
                    ! a massless body fixed in every direction (the input check
                    ! allows no other): unit mass and inertia about its nodes'
                    ! centroid keep the algebra finite; it never moves
                    b%mass = 1
                    b%xc = 0
                    do k = 1, st%nnode
                        if (mark(k)) b%xc = b%xc + real(model%x0(:, k), dp)
                    end do
                    b%xc = b%xc/max(count(mark), 1)
                    jt = 0.5_dp*identity()
                end if
                if (model%part(p)%inertia) then
                    ! *PART_INERTIA: the deck's mass, centre and global inertia
                    ! tensor I replace the elements'; J = tr(I)/2 1 - I
                    b%mass = real(model%part(p)%tm, dp)
                    b%xc = real(model%part(p)%xc, dp)
                    if (model%part(p)%nodeid /= 0) b%xc = real(model%x0(:, findloc(model%node_id, model%part(p)%nodeid, 1)), dp)
                    associate (it => real(model%part(p)%itens, dp))
                        jt = -reshape([it(1), it(2), it(3), it(2), it(4), it(5), it(3), it(5), it(6)], [3, 3])
                        jt = jt + 0.5_dp*(it(1) + it(4) + it(6))*identity()
                    end associate
                end if
                b%fix_t = constraint_dirs(mat%con1)
                b%fix_r = constraint_dirs(mat%con2)
                rg%on = rg%on .or. mark
            end associate
            call finish_body(rg%b(nb), jt, mark)
            if (allocated(error)) return
        end do
        do i = 1, model%nnrb
            nb = nb + 1
            associate (b => rg%b(nb), r => model%nrb(i))
                b%from_part = .false.
                b%part = 0
                if (r%weld) b%tfail = real(r%tfail, dp)
                s = find_set(model, set_node, r%nsid)
                mark = .false.
                mark(model%set(s)%member_ix) = .true.
                b%mass = sum(real(st%mass, dp), mask=mark)
                if (.not. (b%mass > 0.0_dp)) then
                    call make_error(error, 'nodal rigid body or spot weld on node set '//itoa(r%nsid)// &
                                    ': its nodes have no mass (they belong to no element)')
                    return
                end if
                b%xc = 0
                do k = 1, st%nnode
                    if (mark(k)) b%xc = b%xc + st%mass(k)*real(model%x0(:, k), dp)
                end do
                b%xc = b%xc/b%mass
                jt = 0
                do k = 1, st%nnode
                    if (.not. mark(k)) cycle
                    rr = real(model%x0(:, k), dp) - b%xc
                    jt = jt + st%mass(k)*spread(rr, 2, 3)*spread(rr, 1, 3)
                    ! a shell node's own rotational inertia: I += irot 1, i.e.
                    ! J += irot/2 1 in the second-moment form
                    if (st%rot) jt = jt + 0.5_dp*st%irot(k)*identity()
                end do
                b%own = r%inertia
                if (r%inertia) then
                    ! _INERTIA: the deck's mass, centre and global inertia tensor
                    ! I replace the nodes' (J = tr(I)/2 1 - I); the energies take
                    ! the body's
                    b%mass = real(r%tm, dp)
                    b%xc = real(r%xc, dp)
                    if (r%nodeid /= 0) b%xc = real(model%x0(:, findloc(model%node_id, r%nodeid, 1)), dp)
                    associate (it => real(r%itens, dp))
                        jt = -reshape([it(1), it(2), it(3), it(2), it(4), it(5), it(3), it(5), it(6)], [3, 3])
                        jt = jt + 0.5_dp*(it(1) + it(4) + it(6))*identity()
                    end associate
                    b%v_given = .true.
                    b%vt0 = real(r%vt, dp)
                    b%vr0 = real(r%vr, dp)
                    rg%on = rg%on .or. mark
                end if
            end associate
            call finish_body(rg%b(nb), jt, mark)
            if (allocated(error)) return
        end do
        allocate (rg%member(st%nnode))
        rg%member = .false.
        do nb = 1, rg%n
            rg%member(rg%b(nb)%node) = .true.
        end do
        ! prescribed motions of rigid parts
        do nb = 1, rg%n
            allocate (rg%b(nb)%pres(0))
            do i = 1, model%npresc
                if (model%presc(i)%rigid .and. model%presc(i)%ix == rg%b(nb)%part .and. rg%b(nb)%part > 0) &
                    rg%b(nb)%pres = [rg%b(nb)%pres, i]
            end do
        end do
    contains
        !> Deformable elements that share nodes with the rigid part put their
        !> lumped mass (and shells their rotational inertia) on those nodes:
        !> the body carries it, as point masses at the nodes. `jt` is the raw
        !> second moment, b%xc the first moment (not yet divided by the mass).
        subroutine add_deformable_share(b, jt, nodes)
            type(rigid_body_t), intent(inout) :: b
            real(dp), intent(inout) :: jt(3, 3)
            logical, intent(in) :: nodes(:)
            real(dp), allocatable :: rshare(:)
            real(dp) :: extra, xk(3), mm, d1(3), d2(3, 3)
            integer :: ee, kk
            allocate (rshare(st%nnode))
            rshare = 0
            ! the rigid elements' own lumped share, as rigid_lumped_mass gave it
            do ee = 1, model%nhex
                if (model%hex_part(ee) /= b%part) cycle
                x = transpose(real(model%x0(:, model%hex_conn(:, ee)), dp))
                call hex_mass_moments(x, real(model%mat(model%part(b%part)%mat_ix)%ro, dp), mm, d1, d2)
                rshare(model%hex_conn(:, ee)) = rshare(model%hex_conn(:, ee)) + mm/8.0_dp
            end do
            do ee = 1, model%nshell
                if (model%shell_part(ee) /= b%part) cycle
                call shell_mass_moments(model, ee, mm, d1, d2)
                rshare(model%shell_conn(:, ee)) = rshare(model%shell_conn(:, ee)) + mm/4.0_dp
            end do
            do kk = 1, st%nnode
                if (.not. nodes(kk)) cycle
                extra = real(st%mass(kk), dp) - rshare(kk)
                if (extra > 1.0e-6_dp*real(st%mass(kk), dp)) then
                    xk = real(model%x0(:, kk), dp)
                    b%mass = b%mass + extra
                    b%xc = b%xc + extra*xk
                    jt = jt + extra*spread(xk, 2, 3)*spread(xk, 1, 3)
                end if
                if (st%rot) jt = jt + 0.5_dp*st%irot(kk)*identity()
            end do
        end subroutine add_deformable_share

        !> Principal axes, body-frame node positions, initial motion from the
        !> nodes' initial velocities (exact for a rigid field).
        subroutine finish_body(b, jc, nodes)
            type(rigid_body_t), intent(inout) :: b
            real(dp), intent(in) :: jc(3, 3)
            logical, intent(in) :: nodes(:)
            real(dp) :: a(3, 3), w(3), work(64), il(3, 3), lm(3), r(3), mnodes
            integer :: kk, n, lapack_info
            if (any(nodes .and. taken)) then
                n = findloc(nodes .and. taken, .true., 1)
                call make_error(error, 'node '//itoa(model%node_id(n))//' belongs to two rigid bodies '// &
                                '(merging them is not implemented)')
                return
            end if
            taken = taken .or. nodes
            a = -jc
            do kk = 1, 3
                a(kk, kk) = a(kk, kk) + jc(1, 1) + jc(2, 2) + jc(3, 3)
            end do
            call dsyev('V', 'U', 3, a, 3, w, work, size(work), lapack_info)
            if (lapack_info /= 0) then
                call make_error(error, 'rigid body inertia: LAPACK dsyev failed ('//itoa(lapack_info)//')')
                return
            end if
            ! a body of nodes on one line (a two-node spot weld) has no inertia
            ! about that line; forces on the line have no torque about it, so
            ! a small floor keeps the inertia invertible without changing the motion
            if (maxval(w) > 0.0_dp) then
                b%line = w < 1.0e-9_dp*maxval(w)
                w = max(w, 1.0e-9_dp*maxval(w))
            else
                b%line = .true.
                w = 1.0_dp
            end if
            b%ib = w
            b%q = a
            b%xc0 = b%xc
            b%node = pack([(kk, kk=1, st%nnode)], nodes)
            allocate (b%r(3, size(b%node)))
            lm = 0
            il = 0
            b%vc = 0
            do kk = 1, size(b%node)
                n = b%node(kk)
                b%r(:, kk) = matmul(transpose(b%q), real(model%x0(:, n), dp) - b%xc)
                r = real(st%x(:, n), dp) - b%xc
                b%vc = b%vc + st%mass(n)*real(st%v(:, n), dp)
                lm = lm + st%mass(n)*cross(r, real(st%v(:, n), dp))
                il = il + st%mass(n)*(dot_product(r, r)*identity() - spread(r, 2, 3)*spread(r, 1, 3))
            end do
            mnodes = sum(real(st%mass(b%node), dp))
            if (mnodes > 0.0_dp) b%vc = b%vc/mnodes
            if (size(b%node) >= 3 .and. mnodes > 0.0_dp) then
                b%omega = solve3(il, lm)
            else
                b%omega = 0
            end if
            if (b%v_given .and. .not. model%irigid) then
                b%vc = b%vt0
                b%omega = b%vr0
            end if
            if (b%part > 0) then
                ! *PART_INERTIA gives the body's initial motion itself, unless
                ! an *INITIAL_VELOCITY card's IRIGID says the nodes' win
                if (model%part(b%part)%inertia .and. .not. model%irigid) then
                    b%vc = real(model%part(b%part)%vt, dp)
                    b%omega = real(model%part(b%part)%vr, dp)
                end if
            end if
            where (b%fix_t) b%vc = 0
            where (b%fix_r) b%omega = 0
            b%pi = matmul(inertia(b, b%q), b%omega)
            b%vc_old = b%vc
            b%omega_old = b%omega
            do kk = 1, size(b%node)
                n = b%node(kk)
                st%v(:, n) = real(b%vc + cross(b%omega, real(st%x(:, n), dp) - b%xc), wp)
            end do
        end subroutine finish_body
    end subroutine build_rigid

    !> After the velocity update: force and torque from the nodal forces f(n)
    !> at x(n), new velocities, new placement; the nodes get chord velocities
    !> that bring them to their places on the body at t(n+1).
    subroutine rigid_step(rg, model, st, dt, dt_avg, work, walls)
        type(rigid_t), intent(inout) :: rg
        type(model_t), intent(in) :: model
        type(state_t), intent(inout) :: st
        real(wp), intent(in) :: dt, dt_avg
        real(dp), intent(out) :: work            !< work of the prescribed motions this cycle
        type(walls_t), intent(inout) :: walls    !< rigid walls: they stop the bodies' nodes by impulses
        integer :: ib, k, i, it, j, ip
        real(dp) :: f(3), t(3), qm(3, 3), xn(3), h, ha, vpred(3), pipred(3), wfix(3), tt, qold(3, 3), xcold(3)
        logical :: fixr(3)
        h = real(dt, dp)
        ha = real(dt_avg, dp)
        tt = st%time
        work = 0
        do ib = 1, rg%n
            associate (b => rg%b(ib))
                if (.not. b%active) cycle
                if (tt >= b%tfail) then
                    ! a spot weld lets go: its nodes carry on with the velocities they have
                    b%active = .false.
                    rg%member(b%node) = .false.
                    cycle
                end if
                f = 0
                t = 0
                do k = 1, size(b%node)
                    i = b%node(k)
                    f = f + real(st%f(:, i), dp)
                    t = t + cross(real(st%x(:, i), dp) - b%xc, real(st%f(:, i), dp))
                end do
                ! moments of deformable shells at the body's nodes
                if (st%rot) then
                    do k = 1, size(b%node)
                        t = t + real(st%mom(:, b%node(k)), dp)
                    end do
                end if
                b%vc_old = b%vc
                b%omega_old = b%omega
                b%vc = b%vc + ha*f/b%mass
                where (b%fix_t) b%vc = 0
                b%pi = b%pi + ha*t
                vpred = b%vc
                pipred = b%pi
                fixr = b%fix_r
                wfix = 0
                do ip = 1, size(b%pres)
                    associate (pm => model%presc(b%pres(ip)), c => model%curve(model%presc(b%pres(ip))%curve_ix))
                        if (tt < pm%birth .or. tt > pm%death) cycle
                        if (pm%dof <= 3) then
                            j = pm%dof
                            select case (pm%vad)
                            case (0)
                                b%vc(j) = pm%sf*curve_value(c, real(tt + 0.5_dp*h, wp))
                            case (1)
                                b%vc(j) = b%vc_old(j) + ha*pm%sf*curve_value(c, real(tt, wp))
                            case default
                                b%vc(j) = (b%xc0(j) + pm%sf*curve_value(c, real(tt + h, wp)) - b%xc(j))/h
                            end select
                        else
                            j = pm%dof - 4
                            fixr(j) = .true.
                            wfix(j) = pm%sf*curve_value(c, real(tt + 0.5_dp*h, wp))
                        end if
                    end associate
                end do
                ! midpoint: omega = I(q_mid)^-1 pi, q_mid = cay(dt/2 omega) q
                do it = 1, 6
                    qm = matmul(cayley(0.5_dp*h*b%omega), b%q)
                    call constrained_omega(b, qm, fixr, wfix)
                end do
                ! the translation's kinetic energy is the product 1/2 M
                ! vc(n-1/2).vc(n+1/2); the prescription's work is booked so
                ! that it sums to that product's change exactly: half of this
                ! and of the last cycle's impulse, at vc(n-1/2) (the mean of
                ! the two half steps, the rule before, left 1/2 M |dv|^2 at
                ! each jump of a piecewise-linear displacement curve: ratios
                ! of 0.61 and 1.27 where the body slows down). The spin's
                ! energy is 1/2 pi.omega, whose change the mean form books.
                work = work + 0.5_dp*b%mass*dot_product(b%vc - vpred + b%jprev, b%vc_old) &
                       + dot_product(b%pi - pipred, 0.5_dp*(b%omega_old + b%omega))
                b%jprev = b%vc - vpred
                if (walls%n > 0) call wall_impulses(b, qm, fixr, wfix)
                ! a node's velocity: the move over the step that ends it on the
                ! body. With 64-bit coordinates, from its stored coordinate
                ! (which keeps it on the body: any drift is taken back at
                ! once). With 32-bit coordinates that coordinate's rounding, a
                ! hair of 1 m over a step of microseconds, is percent-level
                ! noise in the velocity (a rod's rigid end mass rang with a
                ! period 25% off): there, from the body's own 64-bit positions
                ! of the node before and after the step
                qold = b%q
                xcold = b%xc
                b%q = matmul(cayley(h*b%omega), b%q)
                b%xc = b%xc + h*b%vc
                do k = 1, size(b%node)
                    i = b%node(k)
                    xn = b%xc + matmul(b%q, b%r(:, k))
                    if (coords_64) then
                        st%v(:, i) = real((xn - real(st%x(:, i), dp))/h, wp)
                    else
                        st%v(:, i) = real((xn - (xcold + matmul(qold, b%r(:, k))))/h, wp)
                    end if
                    if (st%rot) st%vr(:, i) = real(b%omega, wp)
                end do
            end associate
        end do
    contains
        !> Rigid walls on the body: a node that would end the step behind a
        !> wall gets the normal impulse J >= 0 that brings it onto the wall,
        !> through the body's effective mass there, 1 / (1/M + (r x n).I^-1
        !> (r x n)) (and 1/M_wall for a moving wall); sequential sweeps over
        !> the nodes until the impulses settle. Minus their work is the
        !> wall's energy, J / dt_avg its force. Friction is not applied to
        !> rigid bodies.
        subroutine wall_impulses(b, qm, fixr, wfix)
            type(rigid_body_t), intent(inout) :: b
            real(dp), intent(in) :: qm(3, 3), wfix(3)
            logical, intent(in) :: fixr(3)
            integer :: iw, k, i, sweep
            real(dp) :: r(3), vn, rn(3), den, dj, jsum, is(3, 3), jt(3), lt(3), de, vw0
            real(wp) :: d, nrm(3), xp(3)
            real(dp), allocatable :: jn(:)
            allocate (jn(size(b%node)))
            is = inertia(b, qm)
            do iw = 1, walls%n
                associate (w => model%wall(iw), wn => walls%w(iw))
                    if (tt < w%birth .or. tt > w%death) cycle
                    jn = 0
                    jsum = 0
                    jt = 0
                    lt = 0
                    vw0 = wn%vel
                    do sweep = 1, 20
                        dj = 0
                        do k = 1, size(b%node)
                            i = b%node(k)
                            if (.not. wn%on(i)) cycle
                            r = real(st%x(:, i), dp) - b%xc
                            xp = real(real(st%x(:, i), dp) + h*(b%vc + cross(b%omega, r)), wp)
                            call wall_distance(w, wn, xp, real(h*wn%vel, wp), d, nrm)
                            if (d >= 0.0_wp .and. jn(k) == 0.0_dp) cycle
                            rn = cross(r, real(nrm, dp))
                            ! translation only in the body's free directions (the
                            ! sweeps settle what fixed rotations leave out)
                            den = sum(merge(real(nrm, dp)**2, 0.0_dp, .not. b%fix_t))/b%mass + &
                                  dot_product(rn, solve3(is, rn))
                            if (w%moving) den = den + 1.0_dp/w%mass
                            ! the change that ends the node on the wall, J kept >= 0
                            vn = -real(d, dp)/h
                            vn = max(-jn(k), vn/max(den, tiny(1.0_dp)))
                            if (vn == 0.0_dp) cycle
                            jn(k) = jn(k) + vn
                            jsum = jsum + vn
                            dj = max(dj, abs(vn))
                            b%vc = b%vc + vn*real(nrm, dp)/b%mass
                            where (b%fix_t) b%vc = 0
                            b%pi = b%pi + vn*rn
                            jt = jt + vn*real(nrm, dp)
                            lt = lt + vn*rn
                            call constrained_omega(b, qm, fixr, wfix)
                            if (w%moving) wn%vel = wn%vel - vn/w%mass
                            wn%force = wn%force + real(vn*real(nrm, dp)/ha, wp)
                        end do
                        if (dj <= 1.0e-12_dp*max(maxval(abs(jn)), tiny(1.0_dp))) exit
                    end do
                    if (jsum == 0.0_dp) cycle
                    ! the impulses' work by the rule every force follows: with
                    ! the mean of the velocities before and after the step
                    ! (v(n-1/2), v(n+1/2)); a moving wall gets what it gains
                    de = -dot_product(jt, 0.5_dp*(b%vc_old + b%vc)) - dot_product(lt, 0.5_dp*(b%omega_old + b%omega))
                    if (w%moving) de = de - 0.5_dp*w%mass*(wn%vel**2 - vw0**2)
                    wn%energy = wn%energy + de
                    call wall_normal_force(w, wn)
                end associate
            end do
        end subroutine wall_impulses
    end subroutine rigid_step

    !> omega from pi with the inertia at orientation q; fixed rotation
    !> directions have omega 0 and take the reaction into pi.
    subroutine constrained_omega(b, q, fixr, wfix)
        type(rigid_body_t), intent(inout) :: b
        real(dp), intent(in) :: q(3, 3)
        logical, intent(in) :: fixr(3)
        real(dp), intent(in) :: wfix(3)          !< values of the fixed components
        real(dp) :: is(3, 3), rhs(3)
        integer :: j
        is = inertia(b, q)
        if (.not. any(fixr)) then
            b%omega = solve3(is, b%pi)
            call drop_line_spin(b, q)
            return
        end if
        ! free components from pi less the fixed components' share
        rhs = b%pi - matmul(is, merge(wfix, 0.0_dp, fixr))
        do j = 1, 3
            if (fixr(j)) then
                is(j, :) = 0
                is(:, j) = 0
                is(j, j) = 1
                rhs(j) = wfix(j)
            end if
        end do
        b%omega = solve3(is, rhs)
        call drop_line_spin(b, q)
        b%pi = matmul(inertia(b, q), b%omega)
    end subroutine constrained_omega

    !> A body whose nodes lie on a line (a two-node spot weld) cannot spin
    !> about it: only round-off would drive that spin, so it is removed.
    subroutine drop_line_spin(b, q)
        type(rigid_body_t), intent(inout) :: b
        real(dp), intent(in) :: q(3, 3)
        integer :: k
        do k = 1, 3
            if (.not. b%line(k)) cycle
            b%omega = b%omega - dot_product(b%omega, q(:, k))*q(:, k)
            b%pi = b%pi - dot_product(b%pi, q(:, k))*q(:, k)
        end do
    end subroutine drop_line_spin

    !> Kinetic energy, 1/2 M vc(n-1/2).vc(n+1/2) + 1/2 pi(n+1/2).omega(n+1/2),
    !> and momentum of body ib.
    !> (node-set bodies keep their kinetic energy on their nodes)
    !> At the start (t = 0, after cycle 0's step) the spin is that of
    !> before the step, 1/2 pi(1/2).omega(-1/2), as the translation's
    !> product form has it: a spin that a prescribed motion gives in
    !> cycle 0 is that motion's work, not initial energy (it was counted
    !> twice, and the energy ratio of a body driven from rest read 0.61).
    !> The translation at the start is that of the initial velocity alone,
    !> 1/2 M vc(0).vc(0) and M vc(0), as the nodes' at t = 0 are: a force
    !> on the body in cycle 0 (a contact found ahead of touching) is not in
    !> the initial momentum (it made the total momentum of two free bodies
    !> differ between t = 0 and every later output, issue 28).
    pure subroutine rigid_energy(b, ke, mom, start)
        type(rigid_body_t), intent(in) :: b
        real(dp), intent(out) :: ke, mom(3)
        logical, intent(in) :: start
        if (start) then
            ke = 0.5_dp*b%mass*dot_product(b%vc_old, b%vc_old) + 0.5_dp*dot_product(b%pi, b%omega_old)
            mom = b%mass*b%vc_old
        else
            ke = 0.5_dp*b%mass*dot_product(b%vc_old, b%vc) + 0.5_dp*dot_product(b%pi, b%omega)
            mom = 0.5_dp*b%mass*(b%vc_old + b%vc)
        end if
    end subroutine rigid_energy

    pure function inertia(b, q) result(is)
        type(rigid_body_t), intent(in) :: b
        real(dp), intent(in) :: q(3, 3)
        real(dp) :: is(3, 3)
        integer :: k
        is = 0
        do k = 1, 3
            is = is + b%ib(k)*spread(q(:, k), 2, 3)*spread(q(:, k), 1, 3)
        end do
    end function inertia

    !> Cayley transform of the rotation vector w: (I - W/2)^-1 (I + W/2).
    pure function cayley(w) result(r)
        real(dp), intent(in) :: w(3)
        real(dp) :: r(3, 3), s(3, 3), d
        s = reshape([0.0_dp, w(3), -w(2), -w(3), 0.0_dp, w(1), w(2), -w(1), 0.0_dp], [3, 3])
        d = 1.0_dp + dot_product(w, w)/4.0_dp
        r = identity() + (s + matmul(s, s)/2.0_dp)/d
    end function cayley

    pure function identity() result(a)
        real(dp) :: a(3, 3)
        a = 0
        a(1, 1) = 1; a(2, 2) = 1; a(3, 3) = 1
    end function identity

    !> How each active rigid body answers an impulse, for the Lagrangian
    !> contact (a master on a rigid body is the body, not a point of its
    !> nodal mass): the body of each node, P_t / M, the world inverse
    !> inertia P_r Q diag(1/I) Q^T P_r (principal axes without inertia left
    !> out; P_t, P_r zero the constrained global directions) and the
    !> centre; a body under prescribed motion does not answer (zeros).
    subroutine rigid_response(rg, nnode, br)
        type(rigid_t), intent(in) :: rg
        integer, intent(in) :: nnode
        type(body_response_t), intent(inout) :: br
        integer :: ib, a
        real(dp) :: dinv(3), iinv(3, 3)
        if (.not. allocated(br%of)) allocate (br%of(nnode), br%wt(3, 3, rg%n), br%iinv(3, 3, rg%n), br%xc(3, rg%n))
        br%of = 0
        br%wt = 0
        br%iinv = 0
        do ib = 1, rg%n
            associate (b => rg%b(ib))
                br%xc(:, ib) = real(b%xc, wp)
                if (.not. b%active) cycle
                br%of(b%node) = ib
                if (size(b%pres) > 0) cycle
                do a = 1, 3
                    if (.not. b%fix_t(a) .and. b%mass > 0.0_dp) br%wt(a, a, ib) = real(1.0_dp/b%mass, wp)
                    dinv(a) = 0
                    if (.not. b%line(a) .and. b%ib(a) > 0.0_dp) dinv(a) = 1.0_dp/b%ib(a)
                end do
                iinv = matmul(b%q, matmul(reshape([dinv(1), 0.0_dp, 0.0_dp, 0.0_dp, dinv(2), 0.0_dp, 0.0_dp, 0.0_dp, &
                                                   dinv(3)], [3, 3]), transpose(b%q)))
                do a = 1, 3
                    if (b%fix_r(a)) then
                        iinv(a, :) = 0
                        iinv(:, a) = 0
                    end if
                end do
                br%iinv(:, :, ib) = real(iinv, wp)
            end associate
        end do
    end subroutine rigid_response

    !> x with a x = b for a 3x3 matrix (Cramer; a is symmetric positive here).
    pure function solve3(a, b) result(x)
        real(dp), intent(in) :: a(3, 3), b(3)
        real(dp) :: x(3), d
        integer :: j
        real(dp) :: m(3, 3)
        d = det3(a)
        do j = 1, 3
            m = a
            m(:, j) = b
            x(j) = det3(m)/d
        end do
    end function solve3

    pure real(dp) function det3(a)
        real(dp), intent(in) :: a(3, 3)
        det3 = a(1, 1)*(a(2, 2)*a(3, 3) - a(2, 3)*a(3, 2)) - a(1, 2)*(a(2, 1)*a(3, 3) - a(2, 3)*a(3, 1)) &
               + a(1, 3)*(a(2, 1)*a(3, 2) - a(2, 2)*a(3, 1))
    end function det3

end module xd_rigid_bodies
