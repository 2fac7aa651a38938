!> The segment contact check (section 5.2 of Whirley & Engelmann 1993):
!> closest-point projection of a slave node on a master segment by Newton
!> iteration (Eqs. 5-6), clamping to an edge (line contact) or a corner
!> (point contact), the master thickness at the contact point from the
!> shape functions, the return direction from the segment normal inside and
!> from the edge tube or corner pinball outside, the signed distance and the
!> penetration (Eqs. 7-11), and the nearest-node / near-border flag.
module xd_contact_segment_check
    use xd_kinds, only: wp
    use xd_core_vectors, only: cross
    implicit none
    private
    public :: hit_t, pair_hit_t, kept, segment_check, shape4, contact_interior, contact_line, contact_point, &
              project_segment

    integer, parameter :: contact_interior = 0, contact_line = 1, contact_point = 2
    !> Newton's step in (xi, eta) that counts as converged: 1e-10, or what a
    !> 32-bit build can resolve (there 1e-10 was never met, and every
    !> projection went on as not converged)
    real(wp), parameter :: newton_tol = max(1.0e-10_wp, 64*epsilon(1.0_wp))

    !> Result of one segment contact check.
    type :: hit_t
        logical :: found = .false.        !< the slave is in contact with the segment
        integer :: seg = 0                !< segment (set by the caller)
        real(wp) :: xi = 0, eta = 0       !< contact point (isoparametric; triangles: area coordinates 2 and 3)
        real(wp) :: nshape(4) = 0         !< shape functions at the contact point
        real(wp) :: xc(3) = 0             !< contact point
        real(wp) :: dist = 0              !< |t|, slave to contact point
        real(wp) :: d = 0                 !< signed distance, Eq. (8)
        real(wp) :: a = 0                 !< penetration depth, Eqs. (10), (11)
        real(wp) :: nhat(3) = 0           !< return direction, Eq. (9)
        real(wp) :: tm = 0                !< master half-thickness (shell) or depth window (solid)
        integer :: kind = contact_interior   !< interior, line (tube) or point (pinball)
        integer :: level = 4              !< hierarchy: 1 shell interior, 2 shell tube/pinball or solid interior,
                                          !< 3 solid tube/pinball (4: no contact)
        integer :: near_node = 1          !< segment node (1-4) closest to the contact point
        logical :: near_border = .false.  !< contact point within tm of the segment border
        real(wp) :: border = 0            !< distance of the contact point to the segment border
        real(wp) :: gap = 0               !< found ahead of touching (Lagrangian lead): the open gap, a = 0
        logical :: converged = .true.     !< the Newton iteration of Eqs. (5)-(6) converged
        !> set by the local search: a shell contact deeper than a step in a
        !> zone the slave already lay in at the last search (it never
        !> crossed into it): held at the depth it is found
        logical :: within = .false.
    end type hit_t

    !> A slave's contact as the enforcement and the events read it: the
    !> fields of hit_t that outlive the local search (every slave holds one
    !> on every rank: 104 bytes, not hit_t's 184).
    type :: pair_hit_t
        logical :: found = .false.
        integer :: seg = 0
        integer :: kind = contact_interior
        integer :: level = 4
        real(wp) :: a = 0
        real(wp) :: nshape(4) = 0
        real(wp) :: nhat(3) = 0
        real(wp) :: tm = 0
        real(wp) :: gap = 0
        logical :: within = .false.
    end type pair_hit_t

contains

    !> The fields of a check's result a contact keeps.
    elemental function kept(h) result(p)
        type(hit_t), intent(in) :: h
        type(pair_hit_t) :: p
        p%found = h%found
        p%seg = h%seg
        p%kind = h%kind
        p%level = h%level
        p%a = h%a
        p%nshape = h%nshape
        p%nhat = h%nhat
        p%tm = h%tm
        p%gap = h%gap
        p%within = h%within
    end function kept

    !> Bilinear shape functions at (xi, eta).
    pure function shape4(xi, eta) result(n)
        real(wp), intent(in) :: xi, eta
        real(wp) :: n(4)
        n = 0.25_wp*[(1 - xi)*(1 - eta), (1 + xi)*(1 - eta), (1 + xi)*(1 + eta), (1 - xi)*(1 + eta)]
    end function shape4

    !> Closest point of segment xm (3, 4) to p: (xi, eta), shape functions and
    !> the kind (interior, line, point). Quadrilaterals: Newton on Eqs. (5)-(6)
    !> from the centre, then clamping; triangles (N4 = N3): the plane's
    !> projection in area coordinates, then clamping.
    pure subroutine project_segment(xm, p, xi, eta, nsh, kind, converged)
        real(wp), intent(in) :: xm(3, 4), p(3)
        real(wp), intent(out) :: xi, eta, nsh(4)
        integer, intent(out) :: kind
        logical, intent(out), optional :: converged
        logical :: conv
        conv = .true.
        if (all(xm(:, 3) == xm(:, 4))) then
            call project_triangle(xm, p, xi, eta, nsh, kind)
        else
            call project_quad(xm, p, xi, eta, nsh, kind, conv)
        end if
        if (present(converged)) converged = conv
    end subroutine project_segment

    pure subroutine project_quad(xm, p, xi, eta, nsh, kind, converged)
        real(wp), intent(in) :: xm(3, 4), p(3)
        real(wp), intent(out) :: xi, eta, nsh(4)
        integer, intent(out) :: kind
        logical, intent(out) :: converged
        real(wp) :: lx(3), le(3), lxe(3), r(3), j11, j12, j22, g1, g2, det, dxi, deta, xb, eb, db, dn, edge
        integer :: it
        logical :: out_xi, out_eta
        xi = 0
        eta = 0
        converged = .false.
        ! L_xi eta is constant on a bilinear patch
        lxe = 0.25_wp*(xm(:, 1) - xm(:, 2) + xm(:, 3) - xm(:, 4))
        do it = 1, 12
            call tangents(xm, xi, eta, lx, le)
            r = p - matmul(xm, shape4(xi, eta))
            g1 = dot_product(lx, r)
            g2 = dot_product(le, r)
            ! Jacobian of (g1, g2): L_xi xi = L_eta eta = 0
            j11 = -dot_product(lx, lx)
            j22 = -dot_product(le, le)
            j12 = dot_product(lxe, r) - dot_product(lx, le)
            det = j11*j22 - j12*j12
            if (abs(det) <= tiny(1.0_wp)) exit
            dxi = -(j22*g1 - j12*g2)/det
            deta = -(j11*g2 - j12*g1)/det
            ! far outside the patch the bilinear map is meaningless: stay near it
            xi = max(-2.0_wp, min(2.0_wp, xi + dxi))
            eta = max(-2.0_wp, min(2.0_wp, eta + deta))
            if (abs(dxi) + abs(deta) < newton_tol) then
                converged = .true.
                exit
            end if
        end do
        ! a slave right above an edge or corner (aligned meshes) is inside:
        ! round-off must not turn it into a tube or pinball contact
        ! (the round-off of the coordinates themselves, relative to the
        ! segment's size, counts: in a 32-bit build a node on a corner of
        ! bars 0.1 m from the origin sits 1e-5 of a 2.5 mm segment off it)
        edge = max(1.0e-8_wp, 16*epsilon(1.0_wp)*maxval(abs(xm))/ &
                   max(sqrt(min(dot_product(lx, lx), dot_product(le, le))), tiny(1.0_wp)))
        out_xi = abs(xi) > 1.0_wp + edge
        out_eta = abs(eta) > 1.0_wp + edge
        if (.not. out_xi) xi = max(-1.0_wp, min(1.0_wp, xi))
        if (.not. out_eta) eta = max(-1.0_wp, min(1.0_wp, eta))
        kind = contact_interior
        if (out_xi .or. out_eta .or. .not. converged) then
            ! outside (or Newton lost): the closest point of the border, over
            ! all four straight edges. With one coordinate out that is usually
            ! the edge it points to; with both out it may be either edge at
            ! the corner, or the corner itself (an obtuse corner's closest
            ! point lies on an edge, not at the corner); a Newton iteration
            ! that did not converge keeps its clamped point only where that
            ! is closer than the border
            dn = huge(1.0_wp)
            if (.not. (out_xi .or. out_eta)) dn = sum((p - matmul(xm, shape4(xi, eta)))**2)
            call border_point(xm, p, xb, eb, kind, db)
            if (db < dn) then
                xi = xb
                eta = eb
            else
                kind = contact_interior
            end if
        end if
        nsh = shape4(xi, eta)
    end subroutine project_quad

    !> The closest point to p of the four straight edges of quad xm: its
    !> (xi, eta), line or point contact, and its squared distance.
    pure subroutine border_point(xm, p, xi, eta, kind, dbest)
        real(wp), intent(in) :: xm(3, 4), p(3)
        real(wp), intent(out) :: xi, eta, dbest
        integer, intent(out) :: kind
        real(wp), parameter :: cx(4) = [-1.0_wp, 1.0_wp, 1.0_wp, -1.0_wp], ce(4) = [-1.0_wp, -1.0_wp, 1.0_wp, 1.0_wp]
        real(wp) :: e(3), u, q(3), dd
        integer :: k, k2
        dbest = huge(1.0_wp)
        xi = 0
        eta = 0
        kind = contact_point
        do k = 1, 4
            k2 = mod(k, 4) + 1
            e = xm(:, k2) - xm(:, k)
            u = dot_product(p - xm(:, k), e)/max(dot_product(e, e), tiny(1.0_wp))
            u = max(0.0_wp, min(1.0_wp, u))
            q = xm(:, k) + u*e
            dd = sum((p - q)**2)
            if (dd < dbest) then
                dbest = dd
                xi = cx(k) + u*(cx(k2) - cx(k))
                eta = ce(k) + u*(ce(k2) - ce(k))
                kind = contact_line
                if (u <= 0.0_wp .or. u >= 1.0_wp) kind = contact_point
            end if
        end do
    end subroutine border_point

    pure subroutine tangents(xm, xi, eta, lx, le)
        real(wp), intent(in) :: xm(3, 4), xi, eta
        real(wp), intent(out) :: lx(3), le(3)
        lx = 0.25_wp*((xm(:, 2) - xm(:, 1))*(1 - eta) + (xm(:, 3) - xm(:, 4))*(1 + eta))
        le = 0.25_wp*((xm(:, 4) - xm(:, 1))*(1 - xi) + (xm(:, 3) - xm(:, 2))*(1 + xi))
    end subroutine tangents

    !> Triangle: area coordinates of the projection on its plane; outside,
    !> the closest point of the closest edge (or a corner).
    pure subroutine project_triangle(xm, p, xi, eta, nsh, kind)
        real(wp), intent(in) :: xm(3, 4), p(3)
        real(wp), intent(out) :: xi, eta, nsh(4)
        integer, intent(out) :: kind
        real(wp) :: e1(3), e2(3), w(3), a11, a12, a22, b1, b2, det, l2, l3, best, q(3), u, dd
        integer :: k, ka, kb, kbest
        integer, parameter :: ea(3) = [1, 2, 3], eb(3) = [2, 3, 1]
        e1 = xm(:, 2) - xm(:, 1)
        e2 = xm(:, 3) - xm(:, 1)
        w = p - xm(:, 1)
        a11 = dot_product(e1, e1)
        a12 = dot_product(e1, e2)
        a22 = dot_product(e2, e2)
        b1 = dot_product(e1, w)
        b2 = dot_product(e2, w)
        det = a11*a22 - a12*a12
        l2 = (a22*b1 - a12*b2)/det
        l3 = (a11*b2 - a12*b1)/det
        kind = contact_interior
        if (l2 < 0.0_wp .or. l3 < 0.0_wp .or. l2 + l3 > 1.0_wp) then
            ! the closest point of the three edges
            best = huge(1.0_wp)
            kbest = 1
            do k = 1, 3
                ka = ea(k)
                kb = eb(k)
                u = dot_product(p - xm(:, ka), xm(:, kb) - xm(:, ka))/ &
                    max(dot_product(xm(:, kb) - xm(:, ka), xm(:, kb) - xm(:, ka)), tiny(1.0_wp))
                u = max(0.0_wp, min(1.0_wp, u))
                q = xm(:, ka) + u*(xm(:, kb) - xm(:, ka))
                dd = dot_product(p - q, p - q)
                if (dd < best) then
                    best = dd
                    kbest = k
                    ! area coordinates of q
                    select case (k)
                    case (1); l2 = u; l3 = 0
                    case (2); l2 = 1 - u; l3 = u
                    case default; l2 = 0; l3 = 1 - u
                    end select
                    kind = contact_line
                    if (u <= 0.0_wp .or. u >= 1.0_wp) kind = contact_point
                end if
            end do
        end if
        xi = l2
        eta = l3
        nsh = [1 - l2 - l3, l2, l3, 0.0_wp]
    end subroutine project_triangle

    !> Segment contact check of slave point xs (half-thickness ts) against
    !> master segment xm (3, 4) with nodal thicknesses tn (4) (shell: full
    !> thickness; solid: the representative thickness), `shell` telling which.
    !> `touching`: a slave exactly on a solid surface (d = ts) counts as in
    !> contact (another body's surface), or not (the slave's own body, where
    !> it would be a coplanar neighbour).
    pure subroutine segment_check(xm, tn, shell, xs, ts, hit, touching, lead)
        real(wp), intent(in) :: xm(3, 4), tn(4), xs(3), ts
        logical, intent(in) :: shell
        logical, intent(in), optional :: touching
        real(wp), intent(in), optional :: lead
        type(hit_t), intent(inout) :: hit
        real(wp) :: t(3), n(3), lx(3), le(3), nt, tlen, dn(4), e(3), u, q(3), db, ahead
        integer :: k, nnd
        logical :: on_seg, under
        ahead = 0
        under = .false.
        if (present(lead)) ahead = lead
        hit%gap = 0
        call project_segment(xm, xs, hit%xi, hit%eta, hit%nshape, hit%kind, hit%converged)
        hit%xc = matmul(xm, hit%nshape)
        ! thickness at the contact point from the shape functions: a half-
        ! thickness for shells, the depth window itself for solids
        hit%tm = dot_product(hit%nshape, tn)
        if (shell) hit%tm = 0.5_wp*hit%tm
        ! the segment normal, the reference direction of Eq. (8)
        if (all(xm(:, 3) == xm(:, 4))) then
            n = cross(xm(:, 2) - xm(:, 1), xm(:, 3) - xm(:, 1))
        else
            call tangents(xm, hit%xi, hit%eta, lx, le)
            n = cross(lx, le)
        end if
        n = n/max(norm2(n), tiny(1.0_wp))
        t = xs - hit%xc                                   ! Eq. (7)
        tlen = norm2(t)
        nt = dot_product(n, t)
        hit%dist = tlen
        on_seg = tlen <= 1.0e-12_wp*maxval(abs(xm))
        if (on_seg .or. (nt == 0.0_wp .and. hit%kind == contact_interior)) then
            ! the slave lies on the segment: the normal is the return direction
            hit%d = 0
            hit%nhat = n
        else if (nt == 0.0_wp) then
            ! in the segment's plane beyond an edge or corner: the tube or
            ! pinball's own direction, the distance |t| (Eqs. 8-9 with the
            ! sign that n . t cannot give)
            hit%d = tlen
            hit%nhat = t/tlen
        else
            hit%d = tlen*sign(1.0_wp, nt)                 ! Eq. (8)
            hit%nhat = t/tlen*sign(1.0_wp, nt)            ! Eq. (9), a unit vector
        end if
        if (shell) then
            hit%found = abs(hit%d) < ts + hit%tm
            if (hit%d /= 0.0_wp) then
                hit%a = hit%d - sign(1.0_wp, hit%d)*(ts + hit%tm)    ! Eq. (11)
            else
                hit%a = -(ts + hit%tm)
            end if
            if (.not. hit%found .and. abs(hit%d) < ts + hit%tm + ahead) then
                ! found ahead of touching: the push direction in nhat, a = 0
                hit%found = .true.
                hit%gap = abs(hit%d) - (ts + hit%tm)
                hit%nhat = hit%nhat*sign(1.0_wp, hit%d)
                hit%a = 0
            end if
            hit%level = 1
            if (hit%kind /= contact_interior) hit%level = 2
        else
            ! beyond the border of a solid face, a slave behind the face's plane
            ! is pushed back along the face normal by its depth below the plane
            ! (the radial tube direction would push a node inside the body
            ! sideways, and at aligned edges of two bodies that sideways push
            ! feeds the hourglass modes); a node beside the face, in or near
            ! its plane, is not inside the body: accepted only within 60
            ! degrees of the inward normal (a node inside a convex edge is
            ! about 45 degrees off each face)
            if (hit%kind /= contact_interior .and. nt < 0.0_wp .and. tlen > 0.0_wp) then
                if (-nt >= 0.5_wp*tlen) then
                    hit%d = nt
                    hit%nhat = n
                    ! within 25 degrees of the inward normal the node lies
                    ! under the face, a little beyond its border (aligned
                    ! edges of two bodies, the edge bulging by a hair): the
                    ! face's level, not a tube's, or the grazing side face
                    ! of the same body would win and carry nothing
                    under = -nt >= 0.9_wp*tlen
                else
                    hit%d = huge(1.0_wp)
                end if
            end if
            ! Eq. (3) window. Its deep end is open by a hair: a node exactly one
            ! window deep (the far node of an element under the face) is not in
            ! contact. Its shallow end is open too for the slave's own body: a
            ! node lying on the surface there is a coplanar neighbour, not a
            ! contact; on another body d = ts is touching (zero force)
            hit%found = hit%d < ts - 1.0e-9_wp*hit%tm .and. hit%d > ts - (1.0_wp - 1.0e-6_wp)*hit%tm
            if (present(touching)) then
                if (touching) hit%found = hit%d <= ts .and. hit%d > ts - (1.0_wp - 1.0e-6_wp)*hit%tm
            end if
            hit%a = hit%d - ts                                       ! Eq. (10)
            ! (on the slave's own body only strictly ahead: a coplanar
            ! neighbour at d = ts is no contact)
            if (.not. hit%found .and. ahead > 0.0_wp .and. hit%d >= ts .and. hit%d < ts + ahead .and. &
                (hit%d > ts .or. touching_ok())) then
                if (hit%kind == contact_interior .or. dot_product(n, hit%nhat) >= 0.5_wp) then
                    hit%found = .true.
                    hit%gap = hit%d - ts
                    hit%a = 0
                end if
            end if
            hit%level = 2
            if (hit%kind /= contact_interior .and. .not. under) hit%level = 3
        end if
        if (.not. hit%found) hit%level = 4
        ! nearest node, and whether the contact point is within tm of the border
        nnd = 4
        if (all(xm(:, 3) == xm(:, 4))) nnd = 3
        do k = 1, nnd
            dn(k) = dot_product(hit%xc - xm(:, k), hit%xc - xm(:, k))
        end do
        hit%near_node = minloc(dn(1:nnd), 1)
        db = huge(1.0_wp)
        do k = 1, nnd
            e = xm(:, mod(k, nnd) + 1) - xm(:, k)
            u = max(0.0_wp, min(1.0_wp, dot_product(hit%xc - xm(:, k), e)/max(dot_product(e, e), tiny(1.0_wp))))
            q = xm(:, k) + u*e
            db = min(db, norm2(hit%xc - q))
        end do
        hit%near_border = db <= hit%tm
        hit%border = db
    contains
        pure logical function touching_ok()
            touching_ok = .false.
            if (present(touching)) touching_ok = touching
        end function touching_ok
    end subroutine segment_check

end module xd_contact_segment_check
