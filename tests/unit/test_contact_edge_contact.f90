!> Edge-to-edge contact (AUTOMATIC_GENERAL): the closest points of two
!> lines against a closed form; the segment distance against a fine
!> sampling; the exterior edges of a sheet; the edge pairs of the bucket
!> search against a brute-force scan of every pair; and two plates whose
!> edges cross half an element from any node: no force while apart, a
!> force that pushes edge a back to its side when in reach and when it has
!> crossed, no force on a pair first seen overlapping (named instead), an
!> initial penetration allowed whole.
program test_contact_edge_contact
    use xd_kinds, only: wp, dp
    use xd_testing, only: check, check_close, test_summary
    use xd_model, only: model_t
    use xd_contact_surface, only: faces_t, surface_t, build_faces, build_surface
    use xd_contact_edge_contact, only: edges_t, build_edges, edge_search, edge_forces, closest_on_lines, &
                                       segment_distance
    use xd_contact_enforcement, only: friction_t
    use xd_test_fixtures, only: empty_model, add_shell, node_at, set_sheet, grid_quads
    implicit none

    call lines_closed_form()
    call distance_sampled()
    call sheet_edges()
    call pairs_brute_force()
    call crossing_plates()
    call test_summary()

contains

    !> Edge a along x at z = 0, edge b along y at z = h: they cross at their
    !> middles, h apart along the common normal e_x x e_y = e_z.
    subroutine lines_closed_form()
        real(wp) :: s, t, g, m(3)
        logical :: inside
        call closest_on_lines([-1.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 0.0_wp, 0.0_wp], [0.3_wp, -1.0_wp, 0.25_wp], &
                              [0.3_wp, 3.0_wp, 0.25_wp], s, t, g, m, inside)
        call check(inside, 'crossing edges: closest points inside both')
        call check_close(real(s, dp), 0.65_dp, 1.0e-14_dp, 'crossing edges: s = 0.65')
        call check_close(real(t, dp), 0.25_dp, 1.0e-14_dp, 'crossing edges: t = 0.25')
        call check_close(real(g, dp), -0.25_dp, 1.0e-14_dp, 'crossing edges: signed distance along e_z')
        call check(all(abs(m - [0.0_wp, 0.0_wp, 1.0_wp]) < 1.0e-14_wp), 'crossing edges: common normal e_z')
        call closest_on_lines([-1.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 0.0_wp, 0.0_wp], [1.5_wp, -1.0_wp, 0.25_wp], &
                              [1.5_wp, 1.0_wp, 0.25_wp], s, t, g, m, inside)
        call check(.not. inside .and. s > 1.0_wp, 'crossing beyond the end of edge a: not inside (a node''s)')
        call closest_on_lines([-1.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 0.0_wp, 0.0_wp], [-1.0_wp, 0.001_wp, 0.25_wp], &
                              [1.0_wp, -0.001_wp, 0.25_wp], s, t, g, m, inside)
        call check(.not. inside .and. all(m == 0.0_wp), 'edges at sin 0.001: parallel, no normal')
    end subroutine lines_closed_form

    !> The distance of random segment pairs is the minimum over a 201 x 201
    !> sampling of both, within the sampling's resolution (half a step of
    !> each segment), and never above it.
    subroutine distance_sampled()
        real(wp) :: p(3, 4), d, dmin, res, dd
        integer :: k, i, j, nbad
        call random_seed(put=[(4242 + k, k=1, 64)])
        nbad = 0
        do k = 1, 300
            call random_number(p)
            if (mod(k, 3) == 0) p(:, 4) = p(:, 3) + 0.7_wp*(p(:, 2) - p(:, 1))   ! parallel pairs too
            d = segment_distance(p(:, 1), p(:, 2), p(:, 3), p(:, 4))
            dmin = huge(1.0_wp)
            do i = 0, 200
                do j = 0, 200
                    dd = norm2(p(:, 1) + (i/200.0_wp)*(p(:, 2) - p(:, 1)) - p(:, 3) - (j/200.0_wp)*(p(:, 4) - p(:, 3)))
                    dmin = min(dmin, dd)
                end do
            end do
            res = 0.5_wp*(norm2(p(:, 2) - p(:, 1)) + norm2(p(:, 4) - p(:, 3)))/200.0_wp
            if (d > dmin + 1.0e-12_wp .or. d < dmin - res) nbad = nbad + 1
        end do
        call check(nbad == 0, 'segment distance = sampled minimum (300 random pairs, 100 parallel)')
    end subroutine distance_sampled

    !> An n x n sheet has 4 n exterior edges, each of one shell.
    subroutine sheet_edges()
        type(model_t) :: m
        type(faces_t) :: f
        type(surface_t) :: s
        type(edges_t) :: ed
        integer, parameter :: n = 7
        integer :: i, j
        real(wp), allocatable :: x(:, :)
        integer, allocatable :: conn(:, :)
        call empty_model(m, 1)
        allocate (x(3, (n + 1)**2), conn(4, n*n))
        do j = 0, n
            do i = 0, n
                x(:, 1 + i + (n + 1)*j) = [real(i, wp), real(j, wp), 0.0_wp]
            end do
        end do
        conn = grid_quads(n)
        call set_sheet(m, x, conn, 0.1_wp, 1)
        call surface_of(m, f, s)
        call build_edges(s, ed)
        call check(ed%ne == 4*n, 'a 7 x 7 sheet has 28 exterior edges')
        call check(all(abs(x(1, s%node(ed%en(1, :))) - 3.5_wp) > 3.4_wp .or. abs(x(2, s%node(ed%en(1, :))) - 3.5_wp) &
                       > 3.4_wp), 'every exterior edge lies on the border')
    end subroutine sheet_edges

    !> 400 unit-free quads of size 0.05 scattered in a unit cube: the pairs
    !> of the bucket search are those of a scan of every pair of edges
    !> within r_a + r_b + delta, no node in common.
    subroutine pairs_brute_force()
        type(model_t) :: m
        type(faces_t) :: f
        type(surface_t) :: s
        type(edges_t) :: ed
        real(wp) :: c(3), a(3), b(3), xl(3, 1600), r
        integer :: k, nd(4), e1, e2, nb, q
        logical :: same
        integer, allocatable :: bp(:, :)
        call empty_model(m, 1)
        call random_seed(put=[(99 + k, k=1, 64)])
        do k = 1, 400
            call random_number(c)
            call random_number(a)
            call random_number(b)
            a = 0.05_wp*(a - 0.5_wp)
            b = 0.05_wp*(b - 0.5_wp)
            nd = [node_at(m, c + a, .false.), node_at(m, c + b, .false.), node_at(m, c - a, .false.), &
                  node_at(m, c - b + 0.01_wp*a, .false.)]
            call add_shell(m, nd, 0.004_wp, 1)
        end do
        call surface_of(m, f, s)
        call build_edges(s, ed)
        call check(ed%ne == 1600, '400 lone quads: 1600 exterior edges')
        xl = m%x0(:, s%node)
        call edge_search(ed, s, xl, spread(0.02_wp, 1, s%nnode))
        allocate (bp(2, 0))
        do e1 = 1, ed%ne
            do e2 = e1 + 1, ed%ne
                if (any(ed%en(:, e1) == ed%en(1, e2)) .or. any(ed%en(:, e1) == ed%en(2, e2))) cycle
                if (ed%eseg(e1) == ed%eseg(e2)) cycle
                r = s%seg_r(ed%eseg(e1)) + s%seg_r(ed%eseg(e2)) + 0.02_wp
                if (segment_distance(xl(:, ed%en(1, e1)), xl(:, ed%en(2, e1)), xl(:, ed%en(1, e2)), &
                                     xl(:, ed%en(2, e2))) <= r) bp = reshape([bp, e1, e2], [2, size(bp, 2) + 1])
            end do
        end do
        nb = size(bp, 2)
        same = nb == ed%np
        if (same) then
            do q = 1, nb
                same = same .and. ed%pa(q) == bp(1, q) .and. ed%pb(q) == bp(2, q)
            end do
        end if
        call check(nb > 100 .and. same, 'edge pairs of the buckets = brute force (400 lone quads)')
    end subroutine pairs_brute_force

    !> Plate A (x from -1 to 0 at y = 0, edge at x = 0 along z, nodes at z =
    !> -0.5, 0.5) and plate B (x from h to 1 + h at z = 0, edge at x = h along y,
    !> nodes at y = -0.5, 0.5): the edges cross at their middles, h apart
    !> along x, no node near the other plate. Thickness 0.1 each: reach 0.1.
    subroutine crossing_plates()
        type(model_t) :: m
        type(faces_t) :: f
        type(surface_t) :: s
        type(edges_t) :: ed
        real(wp), allocatable :: xl(:, :), vl(:, :), ms(:)
        integer :: a(4), b(4), q, qa
        real(wp) :: fa(3)
        call empty_model(m, 2)
        a = [node_at(m, [-1.0_wp, 0.0_wp, -0.5_wp], .false.), node_at(m, [0.0_wp, 0.0_wp, -0.5_wp], .false.), &
             node_at(m, [0.0_wp, 0.0_wp, 0.5_wp], .false.), node_at(m, [-1.0_wp, 0.0_wp, 0.5_wp], .false.)]
        b = [node_at(m, [0.5_wp, -0.5_wp, 0.0_wp], .false.), node_at(m, [1.5_wp, -0.5_wp, 0.0_wp], .false.), &
             node_at(m, [1.5_wp, 0.5_wp, 0.0_wp], .false.), node_at(m, [0.5_wp, 0.5_wp, 0.0_wp], .false.)]
        call add_shell(m, a, 0.1_wp, 1)
        call add_shell(m, b, 0.1_wp, 2)
        call surface_of(m, f, s)
        call build_edges(s, ed)
        allocate (xl(3, s%nnode), vl(3, s%nnode), ms(s%nnode))
        xl = m%x0(:, s%node)
        vl = 0
        ms = 1
        call edge_search(ed, s, xl, spread(1.0_wp, 1, s%nnode))
        ! the pair of the two leading edges (x = 0 and x = 0.5 at the start)
        qa = 0
        do q = 1, ed%np
            if (all(abs(xl(1, ed%en(:, ed%pa(q)))) < 1.0e-12_wp) .and. all(abs(xl(1, ed%en(:, ed%pb(q))) - 0.5_wp) &
                                                                              < 1.0e-12_wp)) qa = q
        end do
        call check(qa > 0, 'crossing plates: the leading edges are paired')
        if (qa == 0) return
        call edge_forces(ed, s, xl, vl, ms, friction_t(), 1.0e-3_wp, 0.0_dp, .false.)
        call check(ed%nact == 0 .and. ed%side(qa) /= 0, 'crossing plates 0.5 apart: no contact, side known')
        ! B's edge moved to x = 0.06: in reach (0.1), 0.04 deep; a new
        ! contact deeper than the step's approach (v = 0 here) is allowed
        ! its excess: so step in from just outside first
        call move_b(s, m, b, xl, 0.1001_wp)
        call edge_forces(ed, s, xl, vl, ms, friction_t(), 1.0e-3_wp, 0.0_dp, .false.)
        call check(ed%nact == 0, 'crossing plates 0.1001 apart: still out of reach')
        do q = 1, 4
            vl(1, findloc(s%node, b(q), 1)) = -10.0_wp
        end do
        call move_b(s, m, b, xl, 0.09_wp)
        call edge_forces(ed, s, xl, vl, ms, friction_t(), 1.0e-3_wp, 0.0_dp, .false.)
        call check(ed%nact == 1 .and. ed%act(1) == qa .and. ed%nlate == 0, 'crossing plates 0.09 apart: in contact')
        fa = ed%fa(:, qa)
        call check(fa(1) < 0.0_wp .and. abs(fa(2)) + abs(fa(3)) < 1.0e-12_wp*abs(fa(1)), &
                   'in reach: edge a pushed back along -x (its side)')
        call check(all(abs(ed%st(:, qa) - 0.5_wp) < 1.0e-12_wp), 'in reach: closest points at the edges'' middles')
        call check_close(real(-fa(1)/ed%kp(qa), dp), 0.01_dp, 1.0e-12_dp, 'in reach: force = k x depth (0.01)')
        ! B's edge through A's, 0.03 beyond: pushed back, not through
        call move_b(s, m, b, xl, 0.06_wp)
        call edge_forces(ed, s, xl, vl, ms, friction_t(), 1.0e-3_wp, 0.0_dp, .false.)
        call move_b(s, m, b, xl, 0.02_wp)
        call edge_forces(ed, s, xl, vl, ms, friction_t(), 1.0e-3_wp, 0.0_dp, .false.)
        call move_b(s, m, b, xl, -0.03_wp)
        call edge_forces(ed, s, xl, vl, ms, friction_t(), 1.0e-3_wp, 0.0_dp, .false.)
        call check(ed%nact == 1 .and. ed%fa(1, qa) < 0.0_wp, 'crossed by 0.03: edge a still pushed to its side')
        call check_close(real(-ed%fa(1, qa)/ed%kp(qa), dp), 0.13_dp, 1.0e-12_dp, 'crossed: force = k x 0.13')
        ! a pair first seen crossed (a fresh list): no side, no force, named
        ed%np = 0
        call edge_search(ed, s, xl, spread(1.0_wp, 1, s%nnode))
        call edge_forces(ed, s, xl, vl, ms, friction_t(), 1.0e-3_wp, 0.0_dp, .false.)
        call check(ed%nact == 0 .and. ed%nunknown == 1 .and. ed%nev == 1, &
                   'a pair first seen within reach: no contact, named once')
        ! at the first cycle, 0.07 apart (0.03 deep, the side clear): an
        ! initial penetration, allowed whole (no force), named
        call move_b(s, m, b, xl, 0.07_wp)
        ed%np = 0
        call edge_search(ed, s, xl, spread(1.0_wp, 1, s%nnode))
        call edge_forces(ed, s, xl, vl, ms, friction_t(), 1.0e-3_wp, 0.0_dp, .true.)
        call check(ed%nact == 1 .and. ed%ninit == 1 .and. ed%nev == 2 .and. all(abs(ed%fa(:, ed%act(1))) < 1.0e-12_wp), &
                   'an edge pair in reach at the first cycle: allowed as an initial penetration, no force, named')
    end subroutine crossing_plates

    !> B's leading edge to x = xb (the whole plate moved along x).
    subroutine move_b(s, m, b, xl, xb)
        type(surface_t), intent(in) :: s
        type(model_t), intent(in) :: m
        integer, intent(in) :: b(4)
        real(wp), intent(inout) :: xl(:, :)
        real(wp), intent(in) :: xb
        integer :: j, k
        do j = 1, 4
            k = findloc(s%node, b(j), 1)
            xl(1, k) = m%x0(1, b(j)) - 0.5_wp + xb
        end do
    end subroutine move_b

    subroutine surface_of(m, f, s)
        type(model_t), intent(inout) :: m
        type(faces_t), intent(out) :: f
        type(surface_t), intent(out) :: s
        integer :: i
        call build_faces(m, m%x0, f)
        call build_surface(f, m%nnode, [(.true., i=1, f%n)], [(.false., i=1, f%n)], [integer ::], .false., &
                           [0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp], [0.1_wp, 1.0_wp, 1.0_wp], s)
    end subroutine surface_of

end program test_contact_edge_contact
