!> Edge-to-edge contact of shell edges: what *CONTACT_AUTOMATIC_GENERAL
!> adds to the single-surface contact. The paper's contact (sections 3-6)
!> is node to segment: each slave node finds its master segment. Two shell
!> edges that cross away from any node (a plate's free edge across
!> another's) bring no node near a segment, and would pass through each
!> other.
!>
!> The exterior edges of the surface's shells (edges of one shell segment
!> only; LS-DYNA's AUTOMATIC_GENERAL checks those) are paired at each
!> global search: pairs whose edges lie within both half-thicknesses plus
!> the largest pool margin delta of their four nodes of each other, so
!> that the search's bound (4u <= delta at every node) holds for edges as
!> for nodes. Each cycle a pair whose closest
!> points lie inside both edges is in contact when the edges' distance
!> along their common normal m = e_a x e_b / |e_a x e_b| is below the sum
!> of the half-thicknesses; the spring pushes along m to the side edge a
!> was on when last clearly apart (sigma: the lines half the reach or more
!> apart, out of edge contact), so that edges that have crossed are pushed
!> back, not through. Closest points at an end of an
!> edge are a node against the other edge's segment, which the node to
!> segment contact treats (its tube and pinball): no force here, and no
!> double force there; so are edges crossing at an angle so small that a
!> node near the crossing lies within the other edge's reach. The force at the closest points is spread to the
!> edges' nodes linearly, so momentum and angular momentum are kept (the
!> force lies along the line joining the two points).
module xd_contact_edge_contact
    use xd_kinds, only: wp, dp, i8
    use xd_core_vectors, only: cross
    use xd_core_sorting, only: sort_index
    use xd_contact_surface, only: surface_t, seg_shell, seg_nodes
    use xd_contact_segment_check, only: hit_t, kept
    use xd_contact_enforcement, only: friction_t, penalty_force
    implicit none
    private
    public :: edges_t, edge_event_t, build_edges, edge_search, edge_forces, closest_on_lines, segment_distance, &
              edge_unknown, edge_late, edge_initial

    !> sin of the angle between two edges below which they count as
    !> parallel: their common normal is then not defined, and a crossing
    !> at so small an angle brings the nodes near the crossing within the
    !> other edge's tube (a node at most half an edge from the crossing is
    !> at most sin/2 of an edge from the other line), where the node to
    !> segment contact holds it
    real(wp), parameter :: parallel_sin = 0.01_wp
    !> A closest point within this fraction of an edge from its end is at
    !> the node (the node contact's): edges that cross at a node would
    !> otherwise switch the edge spring on and off with the round-off
    real(wp), parameter :: end_band = 1.0e-3_wp
    integer, parameter :: max_named = 200   !< edge events named per interface (all counted)
    !> Named in d3hsp: a pair within reach whose side is not known (no
    !> contact until the edges part); a contact found deeper than one
    !> step's approach (the excess allowed); a contact at the first cycle
    !> (the whole depth allowed, shrinking, as IGNORE = 1 for nodes).
    integer, parameter :: edge_unknown = 1, edge_late = 2, edge_initial = 3

    type :: edge_event_t
        integer :: kind = 0
        integer :: node(4) = 0               !< surface-local nodes: edge a's, then edge b's
        real(dp) :: time = 0
        real(wp) :: depth = 0
    end type edge_event_t

    type :: edges_t
        integer :: ne = 0
        integer, allocatable :: en(:, :)      !< (2, ne) surface-local nodes of each exterior shell edge
        integer, allocatable :: eseg(:)       !< the shell segment the edge bounds
        ! pairs of the last global search (edge a < edge b, in (a, b) order)
        integer :: np = 0
        integer, allocatable :: pa(:), pb(:)
        integer, allocatable :: side(:)       !< sigma: +1 or -1 (the side of b's line a was on when clearly apart), 0 unknown
        logical, allocatable :: named(:)      !< an unknown side within reach already named
        real(wp), allocatable :: kp(:)        !< the spring of a pair in contact (0: not in contact last cycle)
        real(wp), allocatable :: p0(:)        !< allowed depth (missed contact), shrinking as the edges part
        real(wp), allocatable :: dlast(:)     !< depth (allowance included) last cycle (0: not in contact)
        real(wp), allocatable :: ft(:, :)     !< friction force carried from cycle to cycle
        ! this cycle's contacts
        integer :: nact = 0
        integer, allocatable :: act(:)        !< pairs in contact, in pair order
        real(wp), allocatable :: st(:, :)     !< (2, np) closest points: parameters on edge a and edge b
        real(wp), allocatable :: fa(:, :)     !< (3, np) force on edge a's point (edge b takes minus it)
        ! counts for d3hsp
        integer(i8) :: ncontact = 0           !< pair-cycles in contact
        integer :: nlate = 0                  !< contacts found deeper than a step's approach (excess allowed)
        real(wp) :: plate = 0
        integer :: nunknown = 0               !< pairs found within reach with no side known (no contact)
        integer :: ninit = 0                  !< contacts at the first cycle (initial penetrations, allowed)
        real(wp) :: pinit = 0
        integer :: nev = 0                    !< events waiting for the log
        type(edge_event_t), allocatable :: ev(:)
    end type edges_t

contains

    !> The exterior edges of the surface's shell segments: those of one
    !> shell segment only (a triangle's repeated node gives three edges).
    subroutine build_edges(s, ed)
        type(surface_t), intent(in) :: s
        type(edges_t), intent(out) :: ed
        integer :: m, j, n, k, q
        integer, allocatable :: a(:), b(:), sg(:), perm(:)
        real(dp), allocatable :: key(:)
        allocate (a(4*s%nseg), b(4*s%nseg), sg(4*s%nseg))
        n = 0
        do m = 1, s%nseg
            if (s%seg_kind(m) /= seg_shell) cycle
            k = seg_nodes(s%seg(:, m))
            do j = 1, k
                n = n + 1
                a(n) = min(s%seg(j, m), s%seg(mod(j, k) + 1, m))
                b(n) = max(s%seg(j, m), s%seg(mod(j, k) + 1, m))
                sg(n) = m
            end do
        end do
        allocate (key(n))
        key = real(a(1:n), dp)*real(s%nnode + 1, dp) + real(b(1:n), dp)
        call sort_index(key, perm)
        allocate (ed%en(2, n), ed%eseg(n))
        k = 1
        do while (k <= n)
            q = k
            do while (q < n)
                if (key(perm(q + 1)) /= key(perm(k))) exit
                q = q + 1
            end do
            if (q == k) then
                ed%ne = ed%ne + 1
                ed%en(:, ed%ne) = [a(perm(k)), b(perm(k))]
                ed%eseg(ed%ne) = sg(perm(k))
            end if
            k = q + 1
        end do
        ed%en = ed%en(:, 1:ed%ne)
        ed%eseg = ed%eseg(1:ed%ne)
        allocate (ed%pa(0), ed%pb(0), ed%side(0), ed%named(0), ed%kp(0), ed%p0(0), ed%dlast(0), ed%ft(3, 0), ed%act(0), &
                  ed%st(2, 0), ed%fa(3, 0), ed%ev(8))
    end subroutine build_edges

    !> Step 2 for the edges, on the coordinates xl of the search: every pair
    !> of exterior edges (no node in common) within r_a + r_b + delta of each
    !> other, found by buckets of the edges' midpoints (a cell as wide as
    !> the longest edge plus both reaches and delta, so that such a pair
    !> lies in neighbouring cells). A pair that was already listed keeps
    !> its side and contact state.
    subroutine edge_search(ed, s, xl, dl)
        type(edges_t), intent(inout) :: ed
        type(surface_t), intent(in) :: s
        real(wp), intent(in) :: xl(:, :)
        real(wp), intent(in) :: dl(:)      !< the surface nodes' pool margins
        real(wp), allocatable :: mid(:, :)
        real(dp), allocatable :: ckey(:), ukey(:), pkey(:)
        integer, allocatable :: perm(:), ustart(:), na(:), nb(:), order(:)
        real(wp) :: lo(3), hc, rmax, lmax, margin
        integer :: e, f, n, nu, c(3), nc(3), dx, dy, dz, lo_i, hi_i, u, q, j, np
        if (ed%ne == 0) return
        allocate (mid(3, ed%ne))
        lmax = 0
        rmax = 0
        margin = 0
        do e = 1, ed%ne
            margin = max(margin, dl(ed%en(1, e)), dl(ed%en(2, e)))
            mid(:, e) = 0.5_wp*(xl(:, ed%en(1, e)) + xl(:, ed%en(2, e)))
            lmax = max(lmax, norm2(xl(:, ed%en(2, e)) - xl(:, ed%en(1, e))))
            rmax = max(rmax, s%seg_r(ed%eseg(e)))
        end do
        hc = max(lmax + 2.0_wp*rmax + margin, tiny(1.0_wp))
        lo = minval(mid, 2)
        nc = [(int((maxval(mid(j, :)) - lo(j))/hc) + 1, j=1, 3)]
        allocate (ckey(ed%ne))
        do e = 1, ed%ne
            c = int((mid(:, e) - lo)/hc)
            ckey(e) = cell_key(c)
        end do
        call sort_index(ckey, perm)
        ! the occupied cells, each with its first position in perm
        allocate (ukey(ed%ne), ustart(ed%ne + 1))
        nu = 0
        do j = 1, ed%ne
            if (nu > 0) then
                if (ckey(perm(j)) == ukey(nu)) cycle
            end if
            nu = nu + 1
            ukey(nu) = ckey(perm(j))
            ustart(nu) = j
        end do
        ustart(nu + 1) = ed%ne + 1
        allocate (na(64), nb(64))
        np = 0
        do e = 1, ed%ne
            c = int((mid(:, e) - lo)/hc)
            do dz = -1, 1
                do dy = -1, 1
                    do dx = -1, 1
                        if (any(c + [dx, dy, dz] < 0) .or. any(c + [dx, dy, dz] >= nc)) cycle
                        u = find_cell(cell_key(c + [dx, dy, dz]))
                        if (u == 0) cycle
                        do q = ustart(u), ustart(u + 1) - 1
                            f = perm(q)
                            if (f <= e) cycle
                            if (.not. candidate(e, f)) cycle
                            np = np + 1
                            if (np > size(na)) then
                                na = [na, na]
                                nb = [nb, nb]
                            end if
                            na(np) = e
                            nb(np) = f
                        end do
                    end do
                end do
            end do
        end do
        allocate (pkey(np))
        pkey = real(na(1:np), dp)*real(ed%ne + 1, dp) + real(nb(1:np), dp)
        call sort_index(pkey, order)
        call carry_state(ed, na(order), nb(order))
    contains
        real(dp) function cell_key(cc)
            integer, intent(in) :: cc(3)
            cell_key = real(cc(1), dp) + real(nc(1), dp)*(real(cc(2), dp) + real(nc(2), dp)*real(cc(3), dp))
        end function cell_key

        !> Position of cell key k among the occupied cells (0: empty).
        integer function find_cell(k)
            real(dp), intent(in) :: k
            lo_i = 1
            hi_i = nu
            find_cell = 0
            do while (lo_i <= hi_i)
                n = (lo_i + hi_i)/2
                if (ukey(n) == k) then
                    find_cell = n
                    return
                else if (ukey(n) < k) then
                    lo_i = n + 1
                else
                    hi_i = n - 1
                end if
            end do
        end function find_cell

        logical function candidate(e1, e2)
            integer, intent(in) :: e1, e2
            candidate = .false.
            if (any(ed%en(:, e1) == ed%en(1, e2)) .or. any(ed%en(:, e1) == ed%en(2, e2))) return
            if (ed%eseg(e1) == ed%eseg(e2)) return
            candidate = segment_distance(xl(:, ed%en(1, e1)), xl(:, ed%en(2, e1)), xl(:, ed%en(1, e2)), &
                                         xl(:, ed%en(2, e2))) <= s%seg_r(ed%eseg(e1)) + s%seg_r(ed%eseg(e2)) + &
                        max(dl(ed%en(1, e1)), dl(ed%en(2, e1)), dl(ed%en(1, e2)), dl(ed%en(2, e2)))
        end function candidate
    end subroutine edge_search

    !> The new pair list (a, b), sorted; each pair already listed keeps its
    !> side, spring, allowance and friction force (a pair dropped was apart:
    !> its state is not needed again).
    subroutine carry_state(ed, a, b)
        type(edges_t), intent(inout) :: ed
        integer, intent(in) :: a(:), b(:)
        integer, allocatable :: side(:)
        logical, allocatable :: named(:)
        real(wp), allocatable :: kp(:), p0(:), dlast(:), ft(:, :)
        integer :: q, o, np
        np = size(a)
        allocate (side(np), named(np), kp(np), p0(np), dlast(np), ft(3, np))
        side = 0
        named = .false.
        kp = 0
        p0 = 0
        dlast = 0
        ft = 0
        o = 1
        do q = 1, np
            do while (o <= ed%np)
                if (ed%pa(o) > a(q) .or. (ed%pa(o) == a(q) .and. ed%pb(o) >= b(q))) exit
                o = o + 1
            end do
            if (o > ed%np) cycle
            if (ed%pa(o) /= a(q) .or. ed%pb(o) /= b(q)) cycle
            side(q) = ed%side(o)
            named(q) = ed%named(o)
            kp(q) = ed%kp(o)
            p0(q) = ed%p0(o)
            dlast(q) = ed%dlast(o)
            ft(:, q) = ed%ft(:, o)
        end do
        ed%np = np
        ed%pa = a
        ed%pb = b
        call move_alloc(side, ed%side)
        call move_alloc(named, ed%named)
        call move_alloc(kp, ed%kp)
        call move_alloc(p0, ed%p0)
        call move_alloc(dlast, ed%dlast)
        call move_alloc(ft, ed%ft)
        deallocate (ed%act, ed%st, ed%fa)
        allocate (ed%act(np), ed%st(2, np), ed%fa(3, np))
        ! the pairs in contact last cycle (a new contact may take over from one)
        ed%nact = 0
        do q = 1, np
            if (ed%dlast(q) <= 0.0_wp) cycle
            ed%nact = ed%nact + 1
            ed%act(ed%nact) = q
        end do
    end subroutine carry_state

    !> Step 3 and 4 for the edges on x(n) (xl) with v(n-1/2) (vl): each pair's
    !> contact this cycle and its penalty force (the node contact's Eq. (12)
    !> with damping and friction, `penalty_force`). The spring (edge_spring)
    !> is set when a contact starts and kept while it lasts. A contact found deeper than the step's approach can explain
    !> (the edges crossed faster than a cycle's motion could show) has the
    !> excess allowed, shrinking as the edges part, and named, as a missed
    !> node contact is.
    subroutine edge_forces(ed, s, xl, vl, ms, fr, dt, time, first)
        type(edges_t), intent(inout) :: ed
        type(surface_t), intent(in) :: s
        real(wp), intent(in) :: xl(:, :), vl(:, :), ms(:), dt
        type(friction_t), intent(in) :: fr
        real(dp), intent(in) :: time
        logical, intent(in) :: first          !< the interface's first active cycle
        integer :: q, ea, eb, a1, a2, b1, b2
        real(wp) :: sp, tp, gl, m(3), r, depth, reach, vrel(3), n(3), mp, mq, meff, lever
        logical :: inside
        type(hit_t) :: hit
        integer, allocatable :: prev(:)
        real(wp), allocatable :: plast(:), dprev(:)
        integer :: nb
        ! last cycle's contacts, as they were (a new contact may take over
        ! from one of them)
        allocate (prev(ed%nact), plast(ed%nact), dprev(ed%nact))
        prev(:) = ed%act(1:ed%nact)
        plast(:) = ed%p0(prev)
        dprev(:) = ed%dlast(prev)
        ed%nact = 0
        do q = 1, ed%np
            ea = ed%pa(q)
            eb = ed%pb(q)
            a1 = ed%en(1, ea); a2 = ed%en(2, ea)
            b1 = ed%en(1, eb); b2 = ed%en(2, eb)
            r = s%seg_r(ed%eseg(ea)) + s%seg_r(ed%eseg(eb))
            call closest_on_lines(xl(:, a1), xl(:, a2), xl(:, b1), xl(:, b2), sp, tp, gl, m, inside, lever)
            ! edges crossing at so small an angle that the node of either edge
            ! nearest the crossing (half an edge from it at most) lies within
            ! half the reach of the other edge's line: the node contact's (its
            ! tube holds the node), and the common normal of nearly parallel
            ! edges (overlapping flanges) turns with every small rotation
            if (inside) inside = lever > 0.5_wp*r
            ! the side: followed while the pair is not in edge contact and the
            ! lines lie clearly apart (half the reach or more: an edge cannot
            ! get there from the other side within a step), kept while in
            ! contact, so that edges driven past each other are pushed back
            if (ed%kp(q) <= 0.0_wp .and. abs(gl) >= 0.5_wp*r .and. norm2(m) > 0.0_wp) &
                ed%side(q) = int(sign(1.0_wp, gl))
            if (.not. inside) then
                ! a node against the other edge's segment, or edges at a small
                ! angle: the node contact's
                call part(q)
                cycle
            end if
            if (ed%side(q) == 0) then
                if (.not. ed%named(q)) then
                    ! within half the reach with no side known (edges
                    ! overlapping when first seen): no contact until they part
                    ed%named(q) = .true.
                    ed%nunknown = ed%nunknown + 1
                    if (ed%nunknown <= max_named) call add_event(edge_unknown, abs(gl))
                end if
                call part(q)
                cycle
            end if
            depth = r - ed%side(q)*gl
            if (depth <= 0.0_wp) then
                call part(q)
                cycle
            end if
            n = ed%side(q)*m
            vrel = (1.0_wp - sp)*vl(:, a1) + sp*vl(:, a2) - (1.0_wp - tp)*vl(:, b1) - tp*vl(:, b2)
            if (ed%kp(q) <= 0.0_wp) then
                ! a new contact: deeper than twice the step's approach (the
                ! most a contact can grow in the cycle it starts) is missed
                reach = 2.0_wp*abs(dot_product(vrel, n))*dt + 1.0e-3_wp*r
                if (first) then
                    ! an initial penetration: allowed whole, shrinking
                    ed%p0(q) = depth
                    ed%ninit = ed%ninit + 1
                    ed%pinit = max(ed%pinit, depth)
                    if (ed%ninit <= max_named) call add_event(edge_initial, depth)
                else
                    ! the crossing handed on from a neighbouring pair (one edge in
                    ! common, the other edges at a node): the spring goes on from
                    ! that pair's depth and allowance, as a node moving to the
                    ! next segment keeps its own
                    nb = neighbour(q)
                    if (nb > 0) then
                        reach = reach + dprev(nb)
                        ed%p0(q) = plast(nb)
                    end if
                end if
                if (.not. first .and. depth > reach) then
                    ed%p0(q) = ed%p0(q) + depth - reach
                    ed%nlate = ed%nlate + 1
                    ed%plate = max(ed%plate, depth - reach)
                    if (ed%nlate <= max_named) call add_event(edge_late, depth - reach)
                end if
                ed%kp(q) = edge_spring(s, [a1, a2, b1, b2])
            end if
            ed%dlast(q) = depth
            if (ed%p0(q) > 0.0_wp) then
                ed%p0(q) = min(ed%p0(q), depth)
                depth = depth - ed%p0(q)
            end if
            hit%a = -depth
            hit%nhat = n
            mp = (1.0_wp - sp)*ms(a1) + sp*ms(a2)
            mq = (1.0_wp - tp)*ms(b1) + tp*ms(b2)
            meff = mp*mq/max(mp + mq, tiny(1.0_wp))
            call penalty_force(kept(hit), ed%kp(q), vrel, meff, fr, dt, ed%ft(:, q), ed%fa(:, q))
            ed%st(:, q) = [sp, tp]
            ed%nact = ed%nact + 1
            ed%act(ed%nact) = q
        end do
        ed%ncontact = ed%ncontact + ed%nact
    contains
        !> The pair in contact last cycle that pair p takes over from: one
        !> edge in common, the other two sharing a node; the deepest (0:
        !> none).
        integer function neighbour(p)
            integer, intent(in) :: p
            integer :: j, o
            real(wp) :: dbest
            neighbour = 0
            dbest = -1
            do j = 1, size(prev)
                o = prev(j)
                if (o == p) cycle
                if (.not. (hands_on(ed%pa(p), ed%pb(p), ed%pa(o), ed%pb(o)) .or. &
                           hands_on(ed%pa(p), ed%pb(p), ed%pb(o), ed%pa(o)))) cycle
                if (dprev(j) > dbest) then
                    dbest = dprev(j)
                    neighbour = j
                end if
            end do
        end function neighbour

        logical function hands_on(e1, e2, f1, f2)
            integer, intent(in) :: e1, e2, f1, f2
            hands_on = (e1 == f1 .and. adjacent(e2, f2)) .or. (e2 == f2 .and. adjacent(e1, f1))
        end function hands_on

        logical function adjacent(x, y)
            integer, intent(in) :: x, y
            adjacent = x /= y .and. (any(ed%en(:, x) == ed%en(1, y)) .or. any(ed%en(:, x) == ed%en(2, y)))
        end function adjacent

        subroutine part(p)
            integer, intent(in) :: p
            ed%kp(p) = 0
            ed%p0(p) = 0
            ed%dlast(p) = 0
            ed%ft(:, p) = 0
        end subroutine part

        subroutine add_event(kind, depth)
            integer, intent(in) :: kind
            real(wp), intent(in) :: depth
            type(edge_event_t), allocatable :: tmp(:)
            if (ed%nev == size(ed%ev)) then
                allocate (tmp(2*size(ed%ev)))
                tmp(1:ed%nev) = ed%ev(1:ed%nev)
                call move_alloc(tmp, ed%ev)
            end if
            ed%nev = ed%nev + 1
            ed%ev(ed%nev) = edge_event_t(kind=kind, node=[a1, a2, b1, b2], time=time, depth=depth)
        end subroutine add_event
    end subroutine edge_forces

    !> An edge pair's spring: the softest of its four nodes' slave springs
    !> (each the node's area times the softer stiffness per area, as a node
    !> contact's). The force at the closest points loads node i by a share
    !> w_i <= 1 of it, so a node's stable step under its own spring (the
    !> contact's time-step bound) holds under the edge spring as well: the
    !> edges add no shorter step. A node without area of its own (none on
    !> an exterior shell edge) would take its segment's spring.
    pure real(wp) function edge_spring(s, nd) result(k)
        type(surface_t), intent(in) :: s
        integer, intent(in) :: nd(4)
        integer :: j
        k = huge(1.0_wp)
        do j = 1, 4
            if (s%node_k(nd(j)) > 0.0_wp) k = min(k, s%node_k(nd(j)))
        end do
        if (k == huge(1.0_wp)) k = minval(s%seg_k(s%seg_list(s%seg_ptr(nd(1)):s%seg_ptr(nd(1) + 1) - 1)))
    end function edge_spring

    !> Closest points of the lines through a1-a2 and b1-b2: parameters s on
    !> a, t on b; inside when both lie inside their edges (end_band) and the
    !> edges are not parallel; m the unit common normal e_a x e_b / |e_a x
    !> e_b| (zero when parallel) and g = (a1 - b1) . m, the signed distance
    !> of the lines (the points' distance when inside); lever, half the
    !> longer edge times the sine of their angle (how far from the other
    !> line an edge's node nearest the crossing can lie).
    pure subroutine closest_on_lines(a1, a2, b1, b2, s, t, g, m, inside, lever)
        real(wp), intent(in) :: a1(3), a2(3), b1(3), b2(3)
        real(wp), intent(out) :: s, t, g, m(3)
        logical, intent(out) :: inside
        real(wp), intent(out), optional :: lever
        real(wp) :: u(3), w(3), r0(3), aa, bb, cc, dd, ee, den
        call line_terms(a1, a2, b1, b2, u, w, r0, aa, bb, cc, dd, ee, den)
        s = 0
        t = 0
        g = 0
        m = 0
        inside = .false.
        if (present(lever)) lever = 0
        ! den = |u|^2 |w|^2 sin^2
        if (den <= (parallel_sin**2)*aa*cc .or. den <= 0.0_wp) return
        s = (bb*ee - cc*dd)/den
        t = (aa*ee - bb*dd)/den
        m = cross(u, w)
        if (present(lever)) lever = 0.5_wp*sqrt(max(aa, cc))*norm2(m)/(sqrt(aa)*sqrt(cc))
        m = m/norm2(m)
        g = dot_product(r0, m)
        inside = min(s, 1.0_wp - s) > end_band .and. min(t, 1.0_wp - t) > end_band
    end subroutine closest_on_lines

    !> Shortest distance between the segments p1-p2 and q1-q2 (the closest
    !> points clamped to both segments; parallel segments included).
    pure real(wp) function segment_distance(p1, p2, q1, q2) result(d)
        real(wp), intent(in) :: p1(3), p2(3), q1(3), q2(3)
        real(wp) :: u(3), w(3), r0(3), aa, bb, cc, dd, ee, den, s, t
        call line_terms(p1, p2, q1, q2, u, w, r0, aa, bb, cc, dd, ee, den)
        ! s on the first segment for the lines' closest points (any s when
        ! parallel), then t for that s, each clamped, then s again for t
        if (den > 1.0e-12_wp*aa*cc) then
            s = min(1.0_wp, max(0.0_wp, (bb*ee - cc*dd)/den))
        else
            s = 0
        end if
        if (cc > 0.0_wp) then
            t = min(1.0_wp, max(0.0_wp, (bb*s + ee)/cc))
        else
            t = 0
        end if
        if (aa > 0.0_wp) then
            s = min(1.0_wp, max(0.0_wp, (bb*t - dd)/aa))
        else
            s = 0
        end if
        d = norm2(p1 + s*u - q1 - t*w)
    end function segment_distance

    !> The lines through a1-a2 and b1-b2: directions u, w, offset r0 = a1 -
    !> b1, their dot products and the determinant den = u.u w.w - (u.w)^2
    !> of the closest-point equations.
    pure subroutine line_terms(a1, a2, b1, b2, u, w, r0, aa, bb, cc, dd, ee, den)
        real(wp), intent(in) :: a1(3), a2(3), b1(3), b2(3)
        real(wp), intent(out) :: u(3), w(3), r0(3), aa, bb, cc, dd, ee, den
        u = a2 - a1
        w = b2 - b1
        r0 = a1 - b1
        aa = dot_product(u, u)
        bb = dot_product(u, w)
        cc = dot_product(w, w)
        dd = dot_product(u, r0)
        ee = dot_product(w, r0)
        den = aa*cc - bb*bb
    end subroutine line_terms

end module xd_contact_edge_contact
