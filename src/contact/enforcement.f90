!> Step 4 of the automatic contact, constraint enforcement (section 6 of
!> Whirley & Engelmann 1993): the penalty force of one slave node in
!> contact (Eq. 12), viscous contact damping (VDC) and Coulomb friction
!> (FS, FD, DC, as LS-DYNA's contact cards define them); the penalty
!> stiffness rule (from the bulk modulus and the element size, per unit
!> area, times the area the slave covers); and the Lagrangian projection
!> of the section's second method. The master side takes the opposite
!> force spread by the segment's shape functions (the caller assembles it).
module xd_contact_enforcement
    use xd_kinds, only: wp
    use xd_core_dofs, only: free_dir
    use, intrinsic :: iso_fortran_env, only: int8
    use xd_contact_segment_check, only: pair_hit_t, contact_interior
    use xd_contact_surface, only: surface_t, seg_shell, seg_nodes, seg_normal
    use xd_core_vectors, only: cross
    implicit none
    private
    public :: friction_t, penalty_force, lagrange_projection, slave_stiffness, facing_area, pdir, body_response_t

    !> Card 2 of the contact keyword.
    type :: friction_t
        real(wp) :: fs = 0, fd = 0, dc = 0   !< static, dynamic coefficients; decay (time/length)
        real(wp) :: vdc = 0                  !< viscous damping, % of critical
    end type friction_t

    !> How the rigid bodies answer an impulse (for the Lagrangian projection):
    !> each model node's body (0: none); per body the translational inverse
    !> mass P_t / M and the world inverse inertia (constrained directions
    !> and axes without inertia zero; a body under prescribed motion all
    !> zero), and its centre.
    type :: body_response_t
        integer, allocatable :: of(:)
        real(wp), allocatable :: wt(:, :, :), iinv(:, :, :), xc(:, :)
    end type body_response_t

contains

    !> Force on the slave node. k: penalty stiffness; vrel: slave velocity
    !> less the contact point's; meff: the pair's effective mass (for VDC);
    !> dt: the step; ft: the tangential (friction) force, carried from cycle
    !> to cycle (in: last cycle's, out: this cycle's).
    pure subroutine penalty_force(hit, k, vrel, meff, fr, dt, ft, f, swept, start)
        type(pair_hit_t), intent(in) :: hit
        real(wp), intent(in) :: k, vrel(3), meff, dt
        type(friction_t), intent(in) :: fr
        real(wp), intent(inout) :: ft(3)
        real(wp), intent(out) :: f(3)
        !> the spring swept over the step (the caller's search finds pairs
        !> up to half a step's approach before they touch)
        logical, intent(in), optional :: swept
        !> the first cycle: the force acts over the half step from t = 0
        !> (v(1/2) = v(0) + a(0) dt/2), the depth going from p to p + dt/2
        !> times its rate
        logical, intent(in), optional :: start
        real(wp) :: fn(3), e(3), vn, vt(3), c, mu, fmax, fnorm, ftn, p, q
        logical :: sw
        sw = .false.
        if (present(swept)) sw = swept
        ! Eq. (12): f = K a n, a < 0 in penetration (a positive multiple of
        ! the return direction pushes the slave back; a shell's slave below
        ! it has a > 0 and is pushed along -nhat): e the push direction
        e = pdir(hit%a)*hit%nhat
        vn = dot_product(vrel, hit%nhat)
        ! the depth (negative: the open gap of a pair found ahead)
        p = abs(hit%a)
        if (hit%a == 0.0_wp) p = -hit%gap
        if (sw .and. at_start()) then
            ! the half step's path: the depth's rate is -vrel . e
            q = -0.5_wp*dt*dot_product(vrel, e)
            fnorm = k*swept_depth(min(p, p + q), max(p, p + q))
        else if (sw) then
            q = 0.5_wp*dt*abs(vn)
            fnorm = k*swept_depth(p - q, p + q)
        else
            fnorm = k*max(p, 0.0_wp)
        end if
        fn = fnorm*e
        if (fr%vdc > 0.0_wp .and. p > 0.0_wp) then
            ! viscous damping VDC % of critical on the normal relative velocity
            ! (in penetration only: not ahead of touching); it may cancel the
            ! normal force but never pull the surfaces together
            c = 0.01_wp*fr%vdc*2.0_wp*sqrt(k*meff)
            fnorm = max(0.0_wp, fnorm - c*dot_product(vrel, e))
            fn = fnorm*e
        end if
        if (fr%fs > 0.0_wp .or. fr%fd > 0.0_wp) then
            ! elastic trial: last cycle's tangential force, turned into the
            ! current tangent plane, plus k times this cycle's slip; then the
            ! Coulomb limit mu |fn| with mu = FD + (FS - FD) exp(-DC |v_t|)
            vt = vrel - vn*hit%nhat
            ftn = dot_product(ft, hit%nhat)
            ft = ft - ftn*hit%nhat
            ft = ft - k*dt*vt
            mu = fr%fd + (fr%fs - fr%fd)*exp(-fr%dc*norm2(vt))
            fmax = mu*fnorm
            if (norm2(ft) > fmax) ft = ft*(fmax/norm2(ft))
        else
            ft = 0
        end if
        f = fn + ft
    contains
        pure logical function at_start()
            at_start = .false.
            if (present(start)) at_start = start
        end function at_start
    end subroutine penalty_force


    !> The penalty stiffness of slave sn against segment m (section 6, the
    !> rule after Eq. 12): the softer of the master segment and the slave
    !> node per unit area (LS-DYNA's SOFT 0), times the area the node covers
    !> facing the master's push; a node without area of its own takes the
    !> segment's stiffness.
    pure real(wp) function slave_stiffness(s, xl, sn, m, push) result(kpen)
        type(surface_t), intent(in) :: s
        real(wp), intent(in) :: xl(:, :), push(3)
        integer, intent(in) :: sn, m
        kpen = s%seg_k(m)
        if (s%node_area(sn) > 0.0_wp) kpen = min(kpen/s%seg_area(m), s%node_kpa(sn))*facing_area(s, xl, sn, push)
    end function slave_stiffness

    !> Lagrangian projection (forward increment Lagrange multipliers, after
    !> Carpenter, Taylor and Katona 1991): normal impulses J >= 0 such that
    !> no pair's gap closes further over the step to x(n+1) = x(n) + dt
    !> (v(n-1/2) + dt_avg (f + contact) / m). For pair q, the gap's rate
    !> changes by J n.(W_s + sum N_i^2 W_i) n, W the node's inverse mass
    !> matrix along the return direction: diag(free / m) for a node of its
    !> own; for a node of a rigid body (br given) the body's response, P_t /
    !> M + [r]^T I^-1 [r] (a fixed body's nodes do not move), and an impulse
    !> there moves the whole body, so every node of that body in another
    !> pair sees it. Pairs sharing nodes or bodies are solved by
    !> Gauss-Seidel sweeps in slave order; an isolated pair (node on node)
    !> is exact in one. Friction the same way: the tangential impulse that
    !> stops the pair's sliding, capped at mu times the normal impulse.
    !>
    !> pair(1:npair): the slave positions in contact, in slave order; hit:
    !> every slave's contact; fpair: their penalty forces in, the projected
    !> forces out; xl, vl: the surface nodes' positions x(n) and velocities
    !> v(n-1/2); f: the model's nodal forces without contact; mass, dofs:
    !> nodal masses and each node's free directions (xd_core_dofs).
    subroutine lagrange_projection(s, npair, pair, hit, fpair, xl, vl, fr, f, mass, dofs, dt, dt_avg, br)
        type(surface_t), intent(in) :: s
        integer, intent(in) :: npair, pair(:)
        type(pair_hit_t), intent(in) :: hit(:)
        real(wp), intent(inout) :: fpair(:, :)
        real(wp), intent(in) :: xl(:, :), vl(:, :)
        type(friction_t), intent(in) :: fr
        real(wp), intent(in) :: f(:, :), mass(:), dt, dt_avg
        integer(int8), intent(in) :: dofs(:)   !< per node, its free directions (xd_core_dofs)
        type(body_response_t), intent(in), optional :: br
        real(wp), allocatable :: pv(:, :), w(:, :, :), jn(:), jt(:, :), cap(:), r(:, :), dvb(:, :), dwb(:, :)
        integer, allocatable :: bod(:)
        integer :: q, k, sn, m, j, sweep, nd, a, b, nb
        real(wp) :: nh(3), g, den, dj, mu, change, scale, vrel(3), tdir(3), jnew(3), dj3(3), sk(3, 3)
        allocate (pv(3, s%nnode), w(3, 3, s%nnode), jn(npair), bod(s%nnode), r(3, s%nnode))
        nb = 0
        if (present(br)) nb = size(br%xc, 2)
        allocate (dvb(3, nb), dwb(3, nb))
        dvb = 0
        dwb = 0
        do nd = 1, s%nnode
            w(:, :, nd) = 0
            bod(nd) = 0
            if (nb > 0) bod(nd) = br%of(s%node(nd))
            b = bod(nd)
            if (b > 0) then
                ! a rigid body's node: its velocity is the body's (corrected
                ! through dvb, dwb as the sweeps go)
                r(:, nd) = xl(:, nd) - br%xc(:, b)
                sk = reshape([0.0_wp, r(3, nd), -r(2, nd), -r(3, nd), 0.0_wp, r(1, nd), r(2, nd), -r(1, nd), &
                              0.0_wp], [3, 3])
                w(:, :, nd) = br%wt(:, :, b) + matmul(transpose(sk), matmul(br%iinv(:, :, b), sk))
                pv(:, nd) = vl(:, nd)
                cycle
            end if
            if (mass(s%node(nd)) > 0.0_wp) then
                do a = 1, 3
                    w(a, a, nd) = free_dir(dofs(s%node(nd)), a)/mass(s%node(nd))
                end do
            end if
            pv(:, nd) = vl(:, nd) + dt_avg*matmul(w(:, :, nd), f(:, s%node(nd)))
        end do
        jn = 0
        scale = 0
        do sweep = 1, 20
            change = 0
            do q = 1, npair
                k = pair(q)
                sn = s%slave(k)
                m = hit(k)%seg
                nh = hit(k)%nhat
                ! a tube or pinball contact that only touches (a = 0: a node in
                ! the plane of a face beyond its edge) constrains nothing: a
                ! zero-gap constraint there would tie the node to the edge
                if (hit(k)%kind /= contact_interior .and. hit(k)%a == 0.0_wp .and. hit(k)%gap == 0.0_wp) cycle
                ! the change of the gap over the step along the return direction
                ! (negative: closing). The constraint stops the closing; the
                ! penetration already there is kept, not pushed out: pushing it
                ! out in one step would add the energy of that jump each time
                ! round-off leaves a trace of penetration (a resting contact)
                g = dt*dot_product(nh, rel_velocity(k, m))*pdir(hit(k)%a) + hit(k)%gap
                if (g >= 0.0_wp .and. jn(q) == 0.0_wp) cycle
                den = dot_product(nh, matmul(w(:, :, sn), nh))
                do j = 1, seg_nodes(s%seg(:, m))
                    den = den + hit(k)%nshape(j)**2*dot_product(nh, matmul(w(:, :, s%seg(j, m)), nh))
                end do
                if (den <= 0.0_wp) cycle
                dj = max(-jn(q), -g/(dt*den))
                if (dj == 0.0_wp) cycle
                jn(q) = jn(q) + dj
                change = max(change, abs(dj))
                scale = max(scale, jn(q))
                ! the impulse along +-n: the side -K a n would push the slave
                call push(sn, dj*pdir(hit(k)%a)*nh)
                do j = 1, seg_nodes(s%seg(:, m))
                    call push(s%seg(j, m), -dj*pdir(hit(k)%a)*hit(k)%nshape(j)*nh)
                end do
            end do
            if (change <= 1.0e-10_wp*max(scale, tiny(1.0_wp))) exit
        end do
        ! Coulomb friction on the projected velocities: the tangential
        ! impulse that stops the pair's sliding over the step (stick), capped
        ! at mu times the normal impulse (slip), mu = FD + (FS - FD)
        ! exp(-DC |v_t|) with v_t the sliding speed before the projection;
        ! Gauss-Seidel in slave order as the normal part
        allocate (jt(3, npair))
        jt = 0
        if (fr%fs > 0.0_wp .or. fr%fd > 0.0_wp) then
            ! each pair's limit mu J_n, from its sliding speed before the projection
            allocate (cap(npair))
            do q = 1, npair
                k = pair(q)
                nh = hit(k)%nhat
                vrel = vl(:, s%slave(k)) - matmul(vl(:, s%seg(:, hit(k)%seg)), hit(k)%nshape)
                vrel = vrel - dot_product(vrel, nh)*nh
                mu = fr%fd + (fr%fs - fr%fd)*exp(-fr%dc*norm2(vrel))
                cap(q) = max(mu, 0.0_wp)*jn(q)
            end do
            do sweep = 1, 20
                change = 0
                do q = 1, npair
                    if (jn(q) <= 0.0_wp) cycle
                    k = pair(q)
                    sn = s%slave(k)
                    m = hit(k)%seg
                    nh = hit(k)%nhat
                    vrel = rel_velocity(k, m)
                    vrel = vrel - dot_product(vrel, nh)*nh
                    ! impulse to stop the remaining slip, along it
                    if (norm2(vrel) > 0.0_wp) then
                        tdir = vrel/norm2(vrel)
                        den = dot_product(tdir, matmul(w(:, :, sn), tdir))
                        do j = 1, seg_nodes(s%seg(:, m))
                            den = den + hit(k)%nshape(j)**2*dot_product(tdir, matmul(w(:, :, s%seg(j, m)), tdir))
                        end do
                        if (den <= 0.0_wp) cycle
                        jnew = jt(:, q) - norm2(vrel)/den*tdir
                    else
                        jnew = jt(:, q)
                    end if
                    if (norm2(jnew) > cap(q)) jnew = jnew*(cap(q)/norm2(jnew))
                    dj3 = jnew - jt(:, q)
                    if (all(dj3 == 0.0_wp)) cycle
                    jt(:, q) = jnew
                    change = max(change, norm2(dj3))
                    call push(sn, dj3)
                    do j = 1, seg_nodes(s%seg(:, m))
                        call push(s%seg(j, m), -hit(k)%nshape(j)*dj3)
                    end do
                end do
                if (change <= 1.0e-10_wp*max(scale, tiny(1.0_wp))) exit
            end do
        end if
        do q = 1, npair
            k = pair(q)
            nh = hit(k)%nhat*pdir(hit(k)%a)
            fpair(:, q) = (jn(q)*nh + jt(:, q))/dt_avg
        end do
    contains
        !> Predicted velocity of surface node nd (a rigid body's node: the
        !> body's, with the impulses so far).
        function vel(nd) result(v)
            integer, intent(in) :: nd
            real(wp) :: v(3)
            v = pv(:, nd)
            if (bod(nd) > 0) v = v + dvb(:, bod(nd)) + cross(dwb(:, bod(nd)), r(:, nd))
        end function vel

        !> The slave's predicted velocity less the contact point's.
        function rel_velocity(k, m) result(v)
            integer, intent(in) :: k, m
            real(wp) :: v(3)
            integer :: i
            v = vel(s%slave(k))
            do i = 1, seg_nodes(s%seg(:, m))
                v = v - hit(k)%nshape(i)*vel(s%seg(i, m))
            end do
        end function rel_velocity

        !> Impulse imp at surface node nd.
        subroutine push(nd, imp)
            integer, intent(in) :: nd
            real(wp), intent(in) :: imp(3)
            integer :: bb
            bb = bod(nd)
            if (bb > 0) then
                dvb(:, bb) = dvb(:, bb) + matmul(br%wt(:, :, bb), imp)
                dwb(:, bb) = dwb(:, bb) + matmul(br%iinv(:, :, bb), cross(r(:, nd), imp))
            else
                pv(:, nd) = pv(:, nd) + matmul(w(:, :, nd), imp)
            end if
        end subroutine push
    end subroutine lagrange_projection

    !> The area slave node sn covers against a master that pushes it along
    !> `push`: its share of each of its own segments; of a solid face, the
    !> share projected on the plane normal to `push`, and only if the face
    !> is turned toward the master (a node on a block's edge covers the top
    !> face's area, not the side's); at least a quarter of its whole share.
    !> A shell counts whole, at its initial area, whatever its angle and
    !> stretch (a node on a fold line carries the fold).
    pure real(wp) function facing_area(s, xl, sn, push) result(a)
        type(surface_t), intent(in) :: s
        real(wp), intent(in) :: xl(:, :), push(3)
        integer, intent(in) :: sn
        integer :: q, m, nnd
        real(wp) :: nv(3), c
        a = 0
        do q = s%seg_ptr(sn), s%seg_ptr(sn + 1) - 1
            m = s%seg_list(q)
            nnd = seg_nodes(s%seg(:, m))
            nv = seg_normal(s, xl, m)      ! |nv| is twice the area
            c = dot_product(nv, push)
            if (s%seg_kind(m) == seg_shell) then
                a = a + s%seg_area(m)/nnd
            else if (c < 0.0_wp) then
                a = a - 0.5_wp*c/nnd
            end if
        end do
        ! a nodes-to-surface slave on no segment of the surface: its whole area
        if (s%seg_ptr(sn + 1) == s%seg_ptr(sn)) a = s%node_area(sn)
        a = max(a, 0.25_wp*s%node_area(sn))
    end function facing_area

    !> The side -K a n pushes the slave to: +1 along the return direction
    !> when a <= 0 (solids, shells from the normal side), -1 when a > 0
    !> (a shell approached from behind). Not sign(1, -a): a = -0.0 must give +1.
    !> The spring's depth averaged over the slave's path across the step:
    !> the central difference applies the force at x(n) over the step from
    !> t(n-1/2) to t(n+1/2), in which the depth goes from p - h to p + h
    !> (h half the step's approach; at the start, over the half step from t
    !> = 0, from p to p plus that half step's approach). The mean of max(0,
    !> s) over the interval [lo, hi] the depth sweeps, k times it, is the
    !> impulse the spring gives on that path: the mean depth where the path
    !> lies in contact, 0 where it lies outside, the positive part's share
    !> where it crosses the surface. Taken at x(n) alone, the spring's
    !> onset and release fall at whatever phase of the step the surface is
    !> crossed, and an impact leaves with up to (omega dt)^2 / 10 more or
    !> less energy than it brought (1.7% for a thin plate on a rigid block
    !> at the contact's step bound, issue 28); swept, a bounce at omega dt
    !> = 0.45 loses up to 0.2% and gains at most 1e-4.
    pure real(wp) function swept_depth(lo, hi) result(pe)
        real(wp), intent(in) :: lo, hi
        if (hi <= 0.0_wp) then
            pe = 0
        else if (lo >= 0.0_wp) then
            pe = 0.5_wp*(lo + hi)
        else
            pe = hi**2/(2.0_wp*(hi - lo))
        end if
    end function swept_depth

    pure real(wp) function pdir(a)
        real(wp), intent(in) :: a
        pdir = 1.0_wp
        if (a > 0.0_wp) pdir = -1.0_wp
    end function pdir

end module xd_contact_enforcement
