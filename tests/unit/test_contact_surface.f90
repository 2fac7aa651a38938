!> Step 1 of the automatic contact (section 3) against hand counts: the
!> exterior faces of structured blocks, a hollow box, a shell coated on a
!> solid and two touching blocks; the solid and shell thickness rules and
!> the penalty stiffness against their closed forms; node adjacency.
program test_contact_surface
    use xd_kinds, only: wp, dp
    use xd_testing, only: check, check_close, test_summary
    use xd_model, only: model_t
    use xd_contact_surface, only: faces_t, surface_t, build_faces, build_surface, face_key, seg_shell, seg_solid
    use xd_test_fixtures, only: empty_model, add_block, add_shell, node_at
    use xd_core_vectors, only: cross
    implicit none
    type(model_t) :: m
    type(faces_t) :: f
    integer :: key(4), nu

    ! face numbering ignores node order
    call face_key([7, 3, 9, 5], key, nu)
    call check(all(key == [3, 5, 7, 9]) .and. nu == 4, 'surface: face number is the sorted node list')
    call face_key([4, 8, 2, 2], key, nu)
    call check(all(key == [2, 4, 8, 0]) .and. nu == 3, 'surface: a repeated node makes a triangle')

    ! a 3 x 2 x 4 block: exterior 2 (3x2 + 2x4 + 3x4) = 52; every face is
    ! shared by two elements or exterior: (6 x 24 - 52) / 2 = 46 interior
    call empty_model(m, 1)
    call add_block(m, [3, 2, 4], [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], 1, .true.)
    call build_faces(m, m%x0, f)
    call check(f%n == 52 .and. f%ninterior == 46 .and. f%nbody == 1, 'surface: 3x2x4 block has 52 exterior faces', &
               counts(f))
    call check(all(f%kind == seg_solid), 'surface: block faces are solid segments')
    call check(outward(m, f), 'surface: solid segment normals point out of the body')

    ! a 3 x 3 x 3 block with its middle element removed: 54 outer faces plus
    ! the 6 faces of the cavity; the cavity surface is a second body
    call empty_model(m, 1)
    call add_block(m, [3, 3, 3], [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], 1, .true., skip=[14])
    call build_faces(m, m%x0, f)
    call check(f%n == 60 .and. f%nbody == 2, 'surface: hollow box has 54 + 6 exterior faces on 2 bodies', counts(f))
    call check(outward(m, f), 'surface: cavity faces point into the cavity (out of the material)')

    ! two 2x2x1 blocks stacked with shared nodes: one 2x2x2 block, 24 faces
    ! outside, the 4 faces between them interior
    call empty_model(m, 2)
    call add_block(m, [2, 2, 1], [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], 1, .true.)
    call add_block(m, [2, 2, 1], [0.0_wp, 0.0_wp, 1.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], 2, .true.)
    call build_faces(m, m%x0, f)
    call check(f%n == 24 .and. f%ninterior == 12 .and. f%nbody == 1, &
               'surface: touching blocks sharing nodes: faces between them are interior', counts(f))
    ! the same blocks with their own nodes: 16 + 16 faces, two bodies
    call empty_model(m, 2)
    call add_block(m, [2, 2, 1], [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], 1, .false.)
    call add_block(m, [2, 2, 1], [0.0_wp, 0.0_wp, 1.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], 2, .false.)
    call build_faces(m, m%x0, f)
    call check(f%n == 32 .and. f%nbody == 2, 'surface: touching blocks with their own nodes: 2 x 16 faces, 2 bodies', &
               counts(f))

    call coated_block()
    call wedge_and_triangle()
    call rigid_stiffness()
    call thickness_rules()
    call shell_thickness_rule()
    call adjacency()
    call test_summary()

contains

    function counts(f) result(t)
        type(faces_t), intent(in) :: f
        character(len=80) :: t
        write (t, '(a,i0,a,i0,a,i0)') 'exterior ', f%n, ' interior ', f%ninterior, ' bodies ', f%nbody
    end function counts

    !> Every solid segment's normal points away from its element's centre.
    logical function outward(m, f)
        type(model_t), intent(in) :: m
        type(faces_t), intent(in) :: f
        integer :: j, e, k
        real(wp) :: c(3), n(3), xs(3, 4)
        outward = .true.
        do j = 1, f%n
            if (f%kind(j) /= seg_solid) cycle
            xs = m%x0(:, f%node(:, j))
            n = cross(xs(:, 3) - xs(:, 1), xs(:, 4) - xs(:, 2))
            ! the element owning the face: the one with all four nodes
            do e = 1, m%nhex
                if (all([(any(m%hex_conn(:, e) == f%node(k, j)), k=1, 4)])) exit
            end do
            c = sum(m%x0(:, m%hex_conn(:, e)), 2)/8
            if (dot_product(n, sum(xs, 2)/4 - c) <= 0) outward = .false.
        end do
    end function outward

    !> A 2x2x2 block with four shells on its top face (same nodes) and two
    !> shells as a flap beyond it: the coated faces stay one solid segment
    !> each (24 in all) and the flap adds 2 shell segments, one body.
    subroutine coated_block()
        integer :: i, j, nd(4)
        real(wp) :: z
        call empty_model(m, 2)
        call add_block(m, [2, 2, 2], [0.0_wp, 0.0_wp, 0.0_wp], [0.5_wp, 0.5_wp, 0.5_wp], 1, .true.)
        z = 1.0_wp
        do j = 0, 1
            do i = 0, 1
                nd = [node_at(m, [0.5_wp*i, 0.5_wp*j, z], .true.), node_at(m, [0.5_wp*(i + 1), 0.5_wp*j, z], .true.), &
                      node_at(m, [0.5_wp*(i + 1), 0.5_wp*(j + 1), z], .true.), node_at(m, [0.5_wp*i, 0.5_wp*(j + 1), z], .true.)]
                call add_shell(m, nd, 0.002_wp, 2)
            end do
        end do
        do j = 0, 1
            nd = [node_at(m, [1.0_wp, 0.5_wp*j, z], .true.), node_at(m, [1.5_wp, 0.5_wp*j, z], .true.), &
                  node_at(m, [1.5_wp, 0.5_wp*(j + 1), z], .true.), node_at(m, [1.0_wp, 0.5_wp*(j + 1), z], .true.)]
            call add_shell(m, nd, 0.002_wp, 2)
        end do
        call build_faces(m, m%x0, f)
        call check(f%n == 26 .and. count(f%kind == seg_shell) == 2 .and. f%nbody == 1, &
                   'surface: shell coated on a solid: 24 solid segments (coated faces once) + 2 shell segments', &
                   counts(f))
        call check(count(f%shell > 0 .and. f%kind == seg_solid) == 4, &
                   'surface: the four coated faces know the shell on them')
    end subroutine coated_block

    !> A degenerate wedge (N5 = N6, N7 = N8) has 5 faces: 3 quadrilaterals
    !> and 2 triangles (the collapsed top face is no face); a triangular
    !> shell is a triangle segment whose stiffness uses its area.
    subroutine wedge_and_triangle()
        integer :: c(8), t(3)
        real(wp) :: kb
        call empty_model(m, 2)
        c = [node_at(m, [0.0_wp, 0.0_wp, 0.0_wp], .true.), node_at(m, [1.0_wp, 0.0_wp, 0.0_wp], .true.), &
             node_at(m, [1.0_wp, 1.0_wp, 0.0_wp], .true.), node_at(m, [0.0_wp, 1.0_wp, 0.0_wp], .true.), &
             0, 0, 0, 0]
        c(5) = node_at(m, [0.0_wp, 0.0_wp, 1.0_wp], .true.)
        c(6) = c(5)
        c(7) = node_at(m, [0.0_wp, 1.0_wp, 1.0_wp], .true.)
        c(8) = c(7)
        m%nhex = 1
        m%hex_conn = reshape(c, [8, 1])
        m%hex_part = [1]
        m%hex_id = [1]
        t = [node_at(m, [3.0_wp, 0.0_wp, 0.0_wp], .true.), node_at(m, [5.0_wp, 0.0_wp, 0.0_wp], .true.), &
             node_at(m, [3.0_wp, 1.0_wp, 0.0_wp], .true.)]
        call add_shell(m, [t(1), t(2), t(3), t(3)], 0.002_wp, 2)
        call build_faces(m, m%x0, f)
        call check(f%n == 6 .and. count(f%node(3, :) == f%node(4, :)) == 3, &
                   'surface: wedge gives 3 quadrilateral and 2 triangular faces; a triangular shell one triangle', &
                   counts(f))
        call check(outward(m, f), 'surface: wedge face normals point out')
        kb = 200.0e9_wp/(3*(1 - 2*0.3_wp))
        ! triangle: area 1, longest edge sqrt(5)
        call check_close(real(f%kgeo(f%n), dp), real(kb*1.0_wp/sqrt(5.0_wp), dp), 1.0e-9_dp*kb, &
                         'surface: triangle shell stiffness K A / longest edge')
    end subroutine wedge_and_triangle

    !> A *MAT_RIGID part takes part with the stiffness of its own E and PR.
    subroutine rigid_stiffness()
        real(wp) :: kb
        call empty_model(m, 1)
        m%mat(1)%mtype = 20
        m%mat(1)%e = 70.0e9_wp
        m%mat(1)%pr = 0.25_wp
        call add_block(m, [1, 1, 1], [0.0_wp, 0.0_wp, 0.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], 1, .true.)
        call build_faces(m, m%x0, f)
        kb = 70.0e9_wp/(3*(1 - 2*0.25_wp))
        call check(all(abs(f%kgeo - kb) < 1.0e-9_wp*kb), 'surface: a rigid part uses its MAT_RIGID E, PR '// &
                   '(K A^2/V = K for a unit cube)')
    end subroutine rigid_stiffness

    !> One 0.1 x 0.2 x 0.05 element: t = min(0.6 x smallest diagonal, V/A)
    !> on each face; k = SLSFAC K A^2 / V with K = E / (3 (1 - 2 nu)).
    subroutine thickness_rules()
        type(surface_t) :: s
        integer :: j, ax, q
        real(wp) :: h(3), area, diag, want, vol, xs(3, 4), n(3), kb
        logical :: ok_t, ok_k
        h = [0.1_wp, 0.2_wp, 0.05_wp]
        call empty_model(m, 1)
        call add_block(m, [1, 1, 1], [0.0_wp, 0.0_wp, 0.0_wp], h, 1, .true.)
        call build_faces(m, m%x0, f)
        vol = product(h)
        kb = 200.0e9_wp/(3*(1 - 2*0.3_wp))
        ok_t = f%n == 6
        ok_k = .true.
        do j = 1, f%n
            xs = m%x0(:, f%node(:, j))
            n = abs(cross(xs(:, 3) - xs(:, 1), xs(:, 4) - xs(:, 2)))
            ax = maxloc(n, 1)
            area = vol/h(ax)
            diag = norm2(pack(h, [(q /= ax, q=1, 3)]))
            want = min(0.6_wp*diag, vol/area)
            if (abs(f%thick(j) - want) > 1.0e-12_wp) ok_t = .false.
            if (abs(0.1_wp*f%kgeo(j) - 0.1_wp*kb*area**2/vol) > 1.0e-9_wp*kb) ok_k = .false.
        end do
        call check(ok_t, 'surface: solid thickness min(0.6 x smallest diagonal, V/A) on all six faces')
        call check(ok_k, 'surface: solid stiffness ingredient K A^2 / V on all six faces')
        call check_close(real(f%thick(1), dp), 0.05_dp, 1.0e-12_dp, 'surface: bottom face (0.1 x 0.2) t = V/A = 0.05')
        call build_surface(f, m%nnode, [(.true., j=1, 6)], [(.false., j=1, 6)], [integer ::], .false., &
                           [0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp], [0.1_wp, 1.0_wp, 2.0_wp], s)
        call check_close(real(s%seg_k(1), dp), real(0.1_wp*2.0_wp*kb*0.02_wp**2/vol, dp), 1.0e-6_dp*s%seg_k(1), &
                         'surface: penalty stiffness SLSFAC x SFM x K A^2 / V')
        call check(all(s%node_t == 0.0_wp), 'surface: a node on solids only has no shell thickness')
    end subroutine thickness_rules

    !> Shells of 1 mm and 3 mm sharing an edge, a 1 mm shell apart, and a
    !> solid under the thick one: segment thickness is the largest nodal
    !> thickness of its nodes (section 3); K A / max diagonal for shells.
    subroutine shell_thickness_rule()
        type(surface_t) :: s
        integer :: a(6), b(2), j
        real(wp) :: kb
        call empty_model(m, 3)
        call add_block(m, [1, 1, 1], [1.0_wp, 0.0_wp, -1.0_wp], [1.0_wp, 1.0_wp, 1.0_wp], 3, .true.)
        a = [node_at(m, [0.0_wp, 0.0_wp, 0.0_wp], .true.), node_at(m, [1.0_wp, 0.0_wp, 0.0_wp], .true.), &
             node_at(m, [1.0_wp, 1.0_wp, 0.0_wp], .true.), node_at(m, [0.0_wp, 1.0_wp, 0.0_wp], .true.), &
             node_at(m, [2.0_wp, 0.0_wp, 0.0_wp], .true.), node_at(m, [2.0_wp, 1.0_wp, 0.0_wp], .true.)]
        call add_shell(m, a([1, 2, 3, 4]), 0.001_wp, 1)
        call add_shell(m, a([2, 5, 6, 3]), 0.003_wp, 2)
        b = [node_at(m, [0.0_wp, 3.0_wp, 0.0_wp], .true.), node_at(m, [1.0_wp, 3.0_wp, 0.0_wp], .true.)]
        call add_shell(m, [b(1), b(2), node_at(m, [1.0_wp, 4.0_wp, 0.0_wp], .true.), node_at(m, [0.0_wp, 4.0_wp, 0.0_wp], &
                       .true.)], 0.001_wp, 1)
        call build_faces(m, m%x0, f)
        ! the thick shell lies on the solid's top face: one solid segment there
        call check(f%n == 6 + 2 .and. count(f%kind == seg_shell) == 2, 'surface: mixed mesh has 6 solid + 2 shell '// &
                   'segments', counts(f))
        kb = 200.0e9_wp/(3*(1 - 2*0.3_wp))
        do j = 1, f%n
            if (f%kind(j) /= seg_shell) cycle
            if (any(f%node(:, j) == a(2))) then
                call check_close(real(f%thick(j), dp), 0.003_dp, 1.0e-15_dp, &
                                 'surface: a 1 mm shell next to a 3 mm one takes 3 mm (largest nodal thickness)')
            else
                call check_close(real(f%thick(j), dp), 0.001_dp, 1.0e-15_dp, 'surface: a lone 1 mm shell keeps 1 mm')
            end if
            call check_close(real(f%kgeo(j), dp), real(kb*1.0_wp/sqrt(2.0_wp), dp), 1.0e-9_dp*kb, &
                             'surface: shell stiffness ingredient K A / max diagonal')
        end do
        call build_surface(f, m%nnode, [(.true., j=1, f%n)], [(.false., j=1, f%n)], [integer ::], .false., &
                           [0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp], [0.1_wp, 1.0_wp, 1.0_wp], s)
        call check_close(real(s%max_thick, dp), 0.003_dp, 1.0e-15_dp, 'surface: contact reach is the largest thickness')
        ! SST / MST overrides: every shell segment and shell node takes them
        call build_surface(f, m%nnode, [(.true., j=1, f%n)], [(.false., j=1, f%n)], [integer ::], .false., &
                           [0.005_wp, 0.004_wp, 1.0_wp, 1.0_wp], [0.1_wp, 1.0_wp, 1.0_wp], s)
        call check(all(pack(s%seg_t, s%seg_kind == seg_shell) == 0.004_wp) .and. &
                   all(pack(s%node_t, s%node_t > 0) == 0.005_wp), 'surface: MST and SST override the thicknesses')
    end subroutine shell_thickness_rule

    !> A 2 x 2 sheet of shells: the centre node touches 4 segments and 8
    !> nodes, a corner 1 segment and 3 nodes.
    subroutine adjacency()
        type(surface_t) :: s
        integer :: g(0:2, 0:2), i, j, c, k
        call empty_model(m, 1)
        do j = 0, 2
            do i = 0, 2
                g(i, j) = node_at(m, [real(i, wp), real(j, wp), 0.0_wp], .false.)
            end do
        end do
        do j = 0, 1
            do i = 0, 1
                call add_shell(m, [g(i, j), g(i + 1, j), g(i + 1, j + 1), g(i, j + 1)], 0.001_wp, 1)
            end do
        end do
        call build_faces(m, m%x0, f)
        call build_surface(f, m%nnode, [(.true., j=1, f%n)], [(.false., j=1, f%n)], [integer ::], .false., &
                           [0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp], [0.1_wp, 1.0_wp, 1.0_wp], s)
        do k = 1, s%nnode
            if (s%node(k) == g(1, 1)) c = k
        end do
        call check(s%seg_ptr(c + 1) - s%seg_ptr(c) == 4 .and. s%nn_ptr(c + 1) - s%nn_ptr(c) == 8, &
                   'surface: centre node has 4 segments and 8 neighbours')
        do k = 1, s%nnode
            if (s%node(k) == g(0, 0)) c = k
        end do
        call check(s%seg_ptr(c + 1) - s%seg_ptr(c) == 1 .and. s%nn_ptr(c + 1) - s%nn_ptr(c) == 3, &
                   'surface: corner node has 1 segment and 3 neighbours')
        call check(s%nslave == 9 .and. s%single, 'surface: single surface makes every node a slave')
    end subroutine adjacency

end program test_contact_surface
