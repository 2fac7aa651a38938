!> Step 3 of the automatic contact on its own (section 5.1): the hierarchy
!> (a shell interior contact beats a solid interior one), the comparison
!> vector of Eq. (4) between two faces of one level, the lone solid
!> tube/pinball rule (a node outside a block's convex edge is in no contact,
!> unless it was pressed on that face last cycle), and tracking along an
!> opposite region from a far trackable master node (found with tracking,
!> missed without), and the refusal of a deep contact in a zone the slave
!> did not enter since the last search.
program test_contact_local_search
    use xd_kinds, only: wp
    use xd_testing, only: check, test_summary
    use xd_model, only: model_t, mnl_minimal
    use xd_contact_surface, only: faces_t, surface_t, build_faces, build_surface, seg_shell
    use xd_contact_global_search, only: characteristic_lengths, master_lists_t, build_master_lists, search_counts_t
    use xd_contact_local_search, only: local_search_t, find_contact, search_switches_t
    use xd_contact_segment_check, only: hit_t, contact_interior
    use xd_test_fixtures, only: empty_model, add_block, add_shell, node_at
    implicit none

    call hierarchy()
    call comparison_vector()
    call lone_tube()
    call tracking()
    call refused_deep()
    call test_summary()

contains

    !> Surface, master node lists and search state of model m (single
    !> surface, everything), all nodes at rest.
    subroutine prepare(m, s, l, ls)
        type(model_t), intent(in) :: m
        type(surface_t), intent(out) :: s
        type(master_lists_t), intent(out) :: l
        type(local_search_t), intent(out) :: ls
        type(faces_t) :: f
        type(search_counts_t) :: cnt
        integer :: j
        call build_faces(m, m%x0, f)
        call build_surface(f, m%nnode, [(.true., j=1, f%n)], [(.false., j=1, f%n)], [integer ::], .false., &
                           [0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp], [0.1_wp, 1.0_wp, 1.0_wp], s, m%hex_conn(:, 1:m%nhex))
        allocate (ls%xl(3, s%nnode), ls%vl(3, s%nnode), ls%lc(s%nnode), ls%lcodo(s%nnode))
        ls%lcodo = 0
        ls%xl = m%x0(:, s%node)
        ls%vl = 0
        call characteristic_lengths(s, ls%xl, ls%lc)
        ls%grow = s%max_thick
        ls%dt = 1.0e-6_wp
        call build_master_lists(s, ls%xl, ls%lc, s%max_thick, spread(0.05_wp, 1, s%nnode), mnl_minimal, l, cnt)
    end subroutine prepare

    !> A shell plate (t 0.2, mid-surface z = 0.05) and a small shell (t 0.1)
    !> of another body whose node sits at z = 0.02: 0.12 deep in the
    !> plate's contact zone (half thicknesses 0.05 + 0.1), at rest, in no
    !> contact last cycle. Where the node lay there already at the last
    !> search it never crossed into the zone: a shell's zone is its
    !> thickness band, so the contact is held where it is found (found,
    !> flagged `within`: slave_force allows its whole depth), nothing
    !> refused; as the segment the node held last (a contact that slid off
    !> and came back) it is found unflagged. Where it lay outside at the
    !> search (z = 0.5) it came in since (a missed contact): found,
    !> unflagged. At the first cycle every contact is an initial
    !> penetration: found. The same node 0.12 below a block's top face
    !> (inside the face's window, the element's depth), lying there at the
    !> search, is refused: no contact, the face and the depth 0.17 (with
    !> its half thickness 0.05) named.
    subroutine refused_deep()
        type(model_t) :: m
        type(surface_t) :: s
        type(master_lists_t) :: l
        type(local_search_t) :: ls
        type(hit_t) :: h
        integer :: p(4), k, rseg, plate
        real(wp) :: rdep
        real(wp), allocatable :: xs(:, :)
        call empty_model(m, 2)
        p = [node_at(m, [0.0_wp, 0.0_wp, 0.05_wp], .false.), node_at(m, [1.0_wp, 0.0_wp, 0.05_wp], .false.), &
             node_at(m, [1.0_wp, 1.0_wp, 0.05_wp], .false.), node_at(m, [0.0_wp, 1.0_wp, 0.05_wp], .false.)]
        call add_shell(m, p, 0.2_wp, 1)
        call probe_at_rest(m, 0.02_wp, -0.2_wp, s, l, ls, k, xs, h, rseg, rdep)
        call check(h%found .and. h%within .and. rseg == 0 .and. abs(abs(h%a) - 0.12_wp) < 1.0e-9_wp, &
                   'local search: a node 0.12 deep in a shell''s zone it lay in at the last search is held there '// &
                   '(found, flagged within, nothing refused)')
        ! the node held that plate earlier (released when it slid off,
        ! back under it now): on its contact side then, so a contact again
        plate = h%seg
        call find_contact(s, l, ls, k, 0, [0.0_wp, 0.0_wp, 0.0_wp], 0.0_wp, search_switches_t(), h, xs, rseg, rdep, &
                          held=plate)
        call check(h%found .and. .not. h%within .and. rseg == 0 .and. abs(abs(h%a) - 0.12_wp) < 1.0e-9_wp, &
                   'local search: the same node deep under the segment it held last (released, back) is found')
        xs(3, s%slave(k)) = 0.5_wp
        call find_contact(s, l, ls, k, 0, [0.0_wp, 0.0_wp, 0.0_wp], 0.0_wp, search_switches_t(), h, xs, rseg, rdep)
        call check(h%found .and. .not. h%within .and. rseg == 0 .and. abs(abs(h%a) - 0.12_wp) < 1.0e-9_wp, &
                   'local search: the same node outside the zone at the last search came in since: a missed contact, found')
        xs = ls%xl
        ls%first = .true.
        call find_contact(s, l, ls, k, 0, [0.0_wp, 0.0_wp, 0.0_wp], 0.0_wp, search_switches_t(), h, xs, rseg, rdep)
        call check(h%found .and. rseg == 0, 'local search: at the first cycle the same node is an initial penetration, found')
        ! a block's top face instead of the plate: refused
        call empty_model(m, 2)
        call add_block(m, [2, 2, 1], [0.0_wp, 0.0_wp, -1.0_wp], [0.5_wp, 0.5_wp, 1.0_wp], 1, .false.)
        call probe_at_rest(m, -0.12_wp, 0.3_wp, s, l, ls, k, xs, h, rseg, rdep)
        call check(.not. h%found .and. rseg > 0 .and. abs(rdep - 0.17_wp) < 1.0e-9_wp, &
                   'local search: a node 0.12 under a block''s top face it lay under at the last search is refused '// &
                   '(no contact; the face and the depth 0.17 named)')
    end subroutine refused_deep

    !> A small shell (t 0.1, part 2) added to m, its first node (the slave
    !> k) at (0.4, 0.4, z), the others at height zo; the surface prepared
    !> and the slave's local search run at rest, not at the first cycle,
    !> with the positions now as the last search's (xs).
    subroutine probe_at_rest(m, z, zo, s, l, ls, k, xs, h, rseg, rdep)
        type(model_t), intent(inout) :: m
        real(wp), intent(in) :: z, zo
        type(surface_t), intent(out) :: s
        type(master_lists_t), intent(out) :: l
        type(local_search_t), intent(out) :: ls
        integer, intent(out) :: k, rseg
        real(wp), allocatable, intent(out) :: xs(:, :)
        type(hit_t), intent(out) :: h
        real(wp), intent(out) :: rdep
        integer :: q(4)
        q = [node_at(m, [0.4_wp, 0.4_wp, z], .false.), node_at(m, [0.3_wp, 0.4_wp, zo], .false.), &
             node_at(m, [0.3_wp, 0.3_wp, zo], .false.), node_at(m, [0.4_wp, 0.3_wp, zo], .false.)]
        call add_shell(m, q, 0.1_wp, 2)
        call prepare(m, s, l, ls)
        k = slave_of(s, q(1))
        xs = ls%xl
        ls%first = .false.
        call find_contact(s, l, ls, k, 0, [0.0_wp, 0.0_wp, 0.0_wp], 0.0_wp, search_switches_t(), h, xs, rseg, rdep)
    end subroutine probe_at_rest

    !> Position in s%slave of model node nd.
    integer function slave_of(s, nd)
        type(surface_t), intent(in) :: s
        integer, intent(in) :: nd
        slave_of = findloc(s%node(s%slave), nd, 1)
    end function slave_of

    !> A block with its top face at z = 0, a shell plate (t 0.2) at z =
    !> 0.05 above it, and a small shell (t 0.1) of a third body whose node
    !> sits at z = 0.02, between them: within the plate's thickness (shell
    !> interior, level 1) and 0.03 into the block's contact reach (solid
    !> interior, level 2). The hierarchy takes the shell.
    subroutine hierarchy()
        type(model_t) :: m
        type(surface_t) :: s
        type(master_lists_t) :: l
        type(local_search_t) :: ls
        type(hit_t) :: h
        integer :: p(4), q(4), k, sn
        call empty_model(m, 3)
        call add_block(m, [2, 2, 1], [0.0_wp, 0.0_wp, -1.0_wp], [0.5_wp, 0.5_wp, 1.0_wp], 1, .false.)
        p = [node_at(m, [0.0_wp, 0.0_wp, 0.05_wp], .false.), node_at(m, [1.0_wp, 0.0_wp, 0.05_wp], .false.), &
             node_at(m, [1.0_wp, 1.0_wp, 0.05_wp], .false.), node_at(m, [0.0_wp, 1.0_wp, 0.05_wp], .false.)]
        call add_shell(m, p, 0.2_wp, 2)
        q = [node_at(m, [0.4_wp, 0.4_wp, 0.02_wp], .false.), node_at(m, [0.3_wp, 0.4_wp, 0.02_wp], .false.), &
             node_at(m, [0.3_wp, 0.3_wp, 0.02_wp], .false.), node_at(m, [0.4_wp, 0.3_wp, 0.02_wp], .false.)]
        call add_shell(m, q, 0.1_wp, 3)
        call prepare(m, s, l, ls)
        k = slave_of(s, q(1))
        call find_contact(s, l, ls, k, 0, [0.0_wp, 0.0_wp, 0.0_wp], 0.0_wp, search_switches_t(), h)
        call check(h%found, 'local search hierarchy: the node between a shell and a solid face is in contact')
        if (.not. h%found) return
        sn = s%slave(k)
        call check(s%seg_kind(h%seg) == seg_shell .and. h%level == 1 .and. h%kind == contact_interior, &
                   'local search hierarchy: the shell interior contact (level 1) beats the solid interior one (level 2)')
    end subroutine hierarchy

    !> A shell node (t 0.1, no solid faces of its own) 0.03 inside a block's
    !> top and front faces near their common edge, at equal depth: the
    !> hierarchy and the closest point tie, and Eq. (4) decides by the
    !> relative velocity: moving down, the top face (v . n = -1); moving
    !> along -x, the front face.
    subroutine comparison_vector()
        type(model_t) :: m
        type(surface_t) :: s
        type(master_lists_t) :: l
        type(local_search_t) :: ls
        type(hit_t) :: h
        integer :: q(4), k, sn
        real(wp) :: nz(3), nx(3)
        call empty_model(m, 2)
        call add_block(m, [2, 2, 2], [0.0_wp, 0.0_wp, 0.0_wp], [0.5_wp, 0.5_wp, 0.5_wp], 1, .false.)
        ! top face z = 1, front face x = 1; the node at (1 - 0.02, 0.5, 1 - 0.02) with ts = 0.05:
        ! d = 0.02 - ... : 0.03 deep in both
        q = [node_at(m, [0.98_wp, 0.45_wp, 0.98_wp], .false.), node_at(m, [1.5_wp, 0.45_wp, 1.5_wp], .false.), &
             node_at(m, [1.5_wp, 0.55_wp, 1.5_wp], .false.), node_at(m, [0.98_wp, 0.55_wp, 0.98_wp], .false.)]
        call add_shell(m, q, 0.1_wp, 2)
        call prepare(m, s, l, ls)
        k = slave_of(s, q(1))
        sn = s%slave(k)
        nz = [0.0_wp, 0.0_wp, 1.0_wp]
        nx = [1.0_wp, 0.0_wp, 0.0_wp]
        ls%vl(:, sn) = [0.0_wp, 0.0_wp, -1.0_wp]
        call find_contact(s, l, ls, k, 0, [0.0_wp, 0.0_wp, 0.0_wp], 0.0_wp, search_switches_t(), h)
        call check(h%found .and. norm2(h%nhat - nz) < 1.0e-9_wp, &
                   'local search Eq. (4): moving down, the top face (most negative v . n)')
        ls%vl(:, sn) = [-1.0_wp, 0.0_wp, 0.0_wp]
        call find_contact(s, l, ls, k, 0, [0.0_wp, 0.0_wp, 0.0_wp], 0.0_wp, search_switches_t(), h)
        call check(h%found .and. norm2(h%nhat - nx) < 1.0e-9_wp, &
                   'local search Eq. (4): moving along -x, the front face')
        ! in contact last cycle: the comparison vector is minus the contact force
        ls%vl(:, sn) = 0
        call find_contact(s, l, ls, k, 0, [0.0_wp, 0.0_wp, 5.0_wp], 0.0_wp, search_switches_t(), h)
        call check(h%found .and. norm2(h%nhat - nz) < 1.0e-9_wp, &
                   'local search Eq. (4): pushed up last cycle (contact force +z), the top face')
    end subroutine comparison_vector

    !> A node of another block (no thickness) just beyond a block's convex
    !> edge, 0.02 below the top face's plane and 0.005 beyond the right
    !> face: the top face offers a contact beyond its border (pushed along
    !> its normal), the right face is missed. A lone solid tube contact among
    !> missed solid faces is no contact; but if the node was pressed on the
    !> top face last cycle, it goes on being pushed by it.
    subroutine lone_tube()
        type(model_t) :: m
        type(surface_t) :: s
        type(master_lists_t) :: l
        type(local_search_t) :: ls
        type(hit_t) :: h
        integer :: nd, k, top, q
        call empty_model(m, 2)
        call add_block(m, [2, 2, 1], [0.0_wp, 0.0_wp, 0.0_wp], [0.5_wp, 0.5_wp, 1.0_wp], 1, .false.)
        call add_block(m, [1, 1, 1], [1.005_wp, 0.45_wp, 0.98_wp], [0.3_wp, 0.1_wp, 0.3_wp], 2, .false.)
        nd = node_at(m, [1.005_wp, 0.45_wp, 0.98_wp], .true.)
        call prepare(m, s, l, ls)
        k = slave_of(s, nd)
        call find_contact(s, l, ls, k, 0, [0.0_wp, 0.0_wp, 0.0_wp], 0.0_wp, search_switches_t(), h)
        call check(.not. h%found, 'local search: a node just outside a block''s convex edge is in no contact '// &
                   '(the lone solid tube rule)')
        ! the top face segment at the edge: the one whose nodes include (1, 0.5, 1)
        top = 0
        do q = 1, s%nseg
            if (s%seg_kind(q) == seg_shell) cycle
            if (all(abs(ls%xl(3, s%seg(:, q)) - 1.0_wp) < 1.0e-12_wp) .and. &
                any(norm2(ls%xl(:, s%seg(:, q)) - spread([1.0_wp, 0.5_wp, 1.0_wp], 2, 4), 1) < 1.0e-12_wp)) then
                if (any(abs(ls%xl(2, s%seg(:, q)) - 0.0_wp) < 1.0e-12_wp)) top = q
            end if
        end do
        call check(top > 0, 'local search: found the top face segment at the edge')
        if (top == 0) return
        call find_contact(s, l, ls, k, top, [0.0_wp, 0.0_wp, 1.0_wp], 0.02_wp, search_switches_t(), h)
        call check(h%found .and. h%seg == top .and. abs(h%a + 0.02_wp) < 1.0e-9_wp, &
                   'local search: pressed on that face last cycle, the node is still pushed by it (a = -0.02)')
    end subroutine lone_tube

    !> A strip of shells along x (1 x 10 segments) and a node of another
    !> shell 0.015 above it at x = 7.3 (in reach: 0.01 + 0.01); its list holds one
    !> trackable node, the strip's node at x = 0 (as a search long ago
    !> left it). Tracking walks along the opposite region to x = 7 and
    !> finds the contact; without tracking it is missed.
    subroutine tracking()
        type(model_t) :: m
        type(surface_t) :: s
        type(master_lists_t) :: l, l1
        type(local_search_t) :: ls
        type(hit_t) :: h
        integer :: i, a(0:10), b(0:10), q(4), k, start, j
        call empty_model(m, 2)
        do i = 0, 10
            a(i) = node_at(m, [real(i, wp), 0.0_wp, 0.0_wp], .false.)
            b(i) = node_at(m, [real(i, wp), 1.0_wp, 0.0_wp], .false.)
        end do
        do i = 0, 9
            call add_shell(m, [a(i), a(i + 1), b(i + 1), b(i)], 0.02_wp, 1)
        end do
        q = [node_at(m, [7.3_wp, 0.5_wp, 0.015_wp], .false.), node_at(m, [7.3_wp, 0.5_wp, 1.0_wp], .false.), &
             node_at(m, [7.3_wp, 0.6_wp, 1.0_wp], .false.), node_at(m, [7.3_wp, 0.6_wp, 0.015_wp], .false.)]
        call add_shell(m, q, 0.02_wp, 2)
        call prepare(m, s, l, ls)
        k = slave_of(s, q(1))
        start = findloc(s%node, a(0), 1)
        ! the list of every slave as the search made it, slave k's replaced by
        ! the one far trackable node
        allocate (l1%ptr(s%nslave), l1%last(s%nslave))
        allocate (l1%node(0), l1%trackable(0))
        do j = 1, s%nslave
            l1%ptr(j) = size(l1%node) + 1
            if (j == k) then
                l1%node = [l1%node, start]
                l1%trackable = [l1%trackable, .true.]
            end if
            l1%last(j) = size(l1%node)
        end do
        ls%lc = 20.0_wp     ! the far node's reach covers the slave (the search's premise)
        call find_contact(s, l1, ls, k, 0, [0.0_wp, 0.0_wp, 0.0_wp], 0.0_wp, search_switches_t(), h)
        call check(h%found .and. h%kind == contact_interior .and. abs(h%xc(1) - 7.3_wp) < 1.0e-9_wp, &
                   'local search tracking: from the trackable node at x = 0 to the contact at x = 7.3')
        call find_contact(s, l1, ls, k, 0, [0.0_wp, 0.0_wp, 0.0_wp], 0.0_wp, &
                          search_switches_t(tracking=.false., screens=.true.), h)
        call check(.not. h%found, 'local search without tracking: the far master node alone misses the contact')
    end subroutine tracking

end program test_contact_local_search
