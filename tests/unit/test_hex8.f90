!> Hexahedron operators against closed forms: volume of a general hexahedron
!> (sum of tetrahedra), gradient operator exact for linear fields, zero strain
!> rate and zero hourglass rate under rigid motion, element time step = L/c.
program test_hex8
    use xd_kinds, only: wp, dp
    use xd_testing, only: check, check_close, test_summary
    use xd_elements_hex8, only: hex_volume_operator, hex_b_matrix, hex_velocity_gradient, &
                                hex_hourglass_shape, hex_hourglass_rates, hex_hourglass_modes, &
                                hex_hourglass_forces, hex_char_length, &
                                hex_corner_jacobians, hex_shape_kind, hex_regular, hex_wedge, hex_tet, hex_bad
    implicit none
    real(wp), parameter :: ref(8, 3) = reshape([0, 1, 1, 0, 0, 1, 1, 0, 0, 0, 1, 1, 0, 0, 1, 1, &
                                                0, 0, 0, 0, 1, 1, 1, 1], [8, 3])*1.0_wp
    real(wp) :: xe(8, 3), b(8, 3), vol, vtet, q(3, 3), grad(3, 3), v(8, 3), d(1, 6), w(1, 3)
    real(wp) :: g(1, 8, 4), h(1, 3, 4), le(1), cj(8), omega(3)
    integer :: k, i, j
    real(dp) :: seed_vals(24)

    ! a distorted hexahedron: reference cube, stretched, sheared, nodes jittered
    call random_seed(put=[(12345 + k, k=1, 64)])
    call random_number(seed_vals)
    do k = 1, 8
        xe(k, :) = [2.0_wp*ref(k, 1) + 0.3_wp*ref(k, 2), 1.5_wp*ref(k, 2), 0.8_wp*ref(k, 3) + 0.2_wp*ref(k, 1)]
        xe(k, :) = xe(k, :) + 0.15_wp*(real(seed_vals(3*k - 2:3*k), wp) - 0.5_wp)
    end do
    call hex_volume_operator(xe, b, vol)

    ! volume: exact for a trilinear hexahedron equals the 24-tetrahedra split
    ! through face centres and the centroid (both are exact for ruled faces)
    vtet = volume_by_tets(xe)
    call check_close(real(vol, dp), real(vtet, dp), 1.0e-12_dp*abs(vtet), 'hex8 volume equals tetrahedral decomposition')
    call check_close(real(sum(xe(:, 2)*b(:, 2)), dp), real(vol, dp), 1.0e-12_dp, 'hex8 volume from y and x consistent')

    ! sum of B over nodes vanishes; B reproduces the gradient of a linear field
    call check(maxval(abs(sum(b, 1))) < 1.0e-13_wp, 'hex8 B sums to zero (constant field has no gradient)')
    q = reshape([0.3_wp, -1.2_wp, 0.7_wp, 2.0_wp, 0.1_wp, -0.4_wp, 0.5_wp, 0.9_wp, -2.2_wp], [3, 3])
    do k = 1, 8
        v(k, :) = matmul(q, xe(k, :)) + [1.0_wp, 2.0_wp, 3.0_wp]
    end do
    do i = 1, 3
        do j = 1, 3
            grad(i, j) = sum(v(:, i)*b(:, j))/vol
        end do
    end do
    call check(maxval(abs(grad - q)) < 1.0e-12_wp, 'hex8 gradient exact for a linear velocity field')

    ! rigid translation + rotation: zero strain rate and zero hourglass rate
    omega = [0.4_wp, -1.1_wp, 2.3_wp]
    do k = 1, 8
        v(k, :) = [3.0_wp, -1.0_wp, 0.5_wp] + cross(omega, xe(k, :))
    end do
    call hex_velocity_gradient(1, reshape(v(:, 1), [1, 8]), reshape(v(:, 2), [1, 8]), reshape(v(:, 3), [1, 8]), &
                               reshape(b(:, 1), [1, 8]), reshape(b(:, 2), [1, 8]), reshape(b(:, 3), [1, 8]), &
                               [vol], d, w)
    call check(maxval(abs(d)) < 1.0e-12_wp, 'hex8 rigid motion gives zero strain rate')
    call check(abs(w(1, 1) - (-omega(3))) + abs(w(1, 2) - (-omega(1))) + abs(w(1, 3) - (-omega(2))) < 1.0e-12_wp, &
               'hex8 spin of a rigid rotation is -omega (W_xy = -omega_z)')
    call hex_hourglass_shape(1, reshape(xe(:, 1), [1, 8]), reshape(xe(:, 2), [1, 8]), reshape(xe(:, 3), [1, 8]), &
                             reshape(b(:, 1), [1, 8]), reshape(b(:, 2), [1, 8]), reshape(b(:, 3), [1, 8]), [vol], g)
    call hex_hourglass_rates(1, reshape(v(:, 1), [1, 8]), reshape(v(:, 2), [1, 8]), reshape(v(:, 3), [1, 8]), g, h)
    call check(maxval(abs(h)) < 1.0e-12_wp, 'hex8 rigid motion gives zero hourglass rate (so zero force)')
    do k = 1, 8
        v(k, :) = matmul(q, xe(k, :))
    end do
    call hex_hourglass_rates(1, reshape(v(:, 1), [1, 8]), reshape(v(:, 2), [1, 8]), reshape(v(:, 3), [1, 8]), g, h)
    call check(maxval(abs(h)) < 1.0e-12_wp, 'hex8 uniform strain gives zero hourglass rate')
    ! an hourglass mode itself is seen
    do k = 1, 8
        v(k, :) = [0.0_wp, 0.0_wp, merge(1.0_wp, -1.0_wp, mod(k, 2) == 1)]
    end do
    call hex_hourglass_rates(1, reshape(v(:, 1), [1, 8]), reshape(v(:, 2), [1, 8]), reshape(v(:, 3), [1, 8]), g, h)
    call check(maxval(abs(h)) > 0.5_wp, 'hex8 hourglass mode gives a non-zero hourglass rate')

    ! the expanded form used by the kernel: same rates, and forces equal to
    ! -sum q gamma, on a distorted element with an arbitrary velocity field
    call check_modes_match_shapes()

    ! time step length of a cube is its side: dt = h / c (1-D formula, nu = 0)
    xe = 0.02_wp*ref
    call hex_volume_operator(xe, b, vol)
    call hex_char_length(1, reshape(xe(:, 1), [1, 8]), reshape(xe(:, 2), [1, 8]), reshape(xe(:, 3), [1, 8]), [vol], le)
    call check_close(real(le(1)/sqrt(200.0e9_wp/7850.0_wp), dp), 0.02_dp/sqrt(200.0e9_dp/7850.0_dp), 1.0e-12_dp, &
                     'hex8 element time step of a cube equals h/c')
    call check_close(real(vol, dp), 8.0e-6_dp, 1.0e-18_dp, 'hex8 cube volume h^3')

    ! corner Jacobians and shape classification
    call hex_corner_jacobians(ref, cj)
    call check(all(abs(cj - 1.0_wp) < 1.0e-14_wp), 'hex8 corner Jacobians of the unit cube are 1')
    xe = ref
    xe(7, :) = [0.2_wp, 0.2_wp, 0.2_wp]
    call hex_corner_jacobians(xe, cj)
    call check(cj(7) < 0.0_wp, 'hex8 a corner pushed through the element is detected')
    call check(hex_shape_kind([1, 2, 3, 4, 5, 6, 7, 8]) == hex_regular, 'hex8 regular connectivity')
    call check(hex_shape_kind([1, 2, 3, 4, 5, 5, 6, 6]) == hex_wedge, 'hex8 wedge N5=N6, N7=N8 accepted')
    call check(hex_shape_kind([1, 2, 3, 4, 4, 4, 4, 4]) == hex_tet, 'hex8 tetrahedron N4=..=N8 accepted')
    call check(hex_shape_kind([1, 1, 3, 4, 5, 6, 7, 8]) == hex_bad, 'hex8 other repeated nodes rejected')
    call test_summary()

contains

    subroutine check_modes_match_shapes()
        real(wp) :: xd(8, 3), bb(8, 3), vv, vel(8, 3), gg(1, 8, 4), hh(1, 3, 4), hm(1, 3, 4), hx(1, 3, 4)
        real(wp) :: q(1, 3, 4), fx(1, 8), fy(1, 8), fz(1, 8), fref(8, 3)
        real(dp) :: rv(24), rq(12)
        integer :: kk, a
        call random_number(rv)
        do kk = 1, 8
            xd(kk, :) = ref(kk, :) + 0.2_wp*(real(rv(3*kk - 2:3*kk), wp) - 0.5_wp)
        end do
        call random_number(rv)
        vel = reshape(real(rv, wp), [8, 3]) - 0.5_wp
        call hex_volume_operator(xd, bb, vv)
        call hex_hourglass_shape(1, reshape(xd(:, 1), [1, 8]), reshape(xd(:, 2), [1, 8]), reshape(xd(:, 3), [1, 8]), &
                                 reshape(bb(:, 1), [1, 8]), reshape(bb(:, 2), [1, 8]), reshape(bb(:, 3), [1, 8]), &
                                 [vv], gg)
        call hex_hourglass_rates(1, reshape(vel(:, 1), [1, 8]), reshape(vel(:, 2), [1, 8]), &
                                 reshape(vel(:, 3), [1, 8]), gg, hh)
        call hex_hourglass_modes(1, reshape(xd(:, 1), [1, 8]), reshape(xd(:, 2), [1, 8]), reshape(xd(:, 3), [1, 8]), &
                                 reshape(vel(:, 1), [1, 8]), reshape(vel(:, 2), [1, 8]), reshape(vel(:, 3), [1, 8]), &
                                 reshape(bb(:, 1), [1, 8]), reshape(bb(:, 2), [1, 8]), reshape(bb(:, 3), [1, 8]), &
                                 [vv], hx, hm)
        call check(maxval(abs(hm - hh)) < 1.0e-12_wp, 'hex8 expanded hourglass rates equal v . gamma')
        call random_number(rq)
        q = reshape(real(rq, wp), [1, 3, 4])
        fx = 0; fy = 0; fz = 0
        call hex_hourglass_forces(1, q, hx, reshape(bb(:, 1), [1, 8]), reshape(bb(:, 2), [1, 8]), &
                                  reshape(bb(:, 3), [1, 8]), [vv], fx, fy, fz)
        fref = 0
        do a = 1, 4
            do kk = 1, 8
                fref(kk, :) = fref(kk, :) - q(1, :, a)*gg(1, kk, a)
            end do
        end do
        call check(maxval(abs(fx(1, :) - fref(:, 1))) + maxval(abs(fy(1, :) - fref(:, 2))) + &
                   maxval(abs(fz(1, :) - fref(:, 3))) < 1.0e-12_wp, 'hex8 expanded hourglass forces equal -q . gamma')
    end subroutine check_modes_match_shapes

    pure function cross(a, c) result(r)
        real(wp), intent(in) :: a(3), c(3)
        real(wp) :: r(3)
        r = [a(2)*c(3) - a(3)*c(2), a(3)*c(1) - a(1)*c(3), a(1)*c(2) - a(2)*c(1)]
    end function cross

    !> Volume as 24 tetrahedra (centroid, face centre, edge): exact for the
    !> trilinear hexahedron because each face is a hyperbolic paraboloid whose
    !> cone volume from a point is given exactly by its four edge triangles
    !> around the face's bilinear centre.
    function volume_by_tets(x) result(vt)
        real(wp), intent(in) :: x(8, 3)
        real(wp) :: vt, c(3), fc(3)
        integer, parameter :: face(4, 6) = reshape([1, 4, 3, 2, 5, 6, 7, 8, 1, 2, 6, 5, &
                                                    2, 3, 7, 6, 3, 4, 8, 7, 4, 1, 5, 8], [4, 6])
        integer :: f, k
        c = sum(x, 1)/8
        vt = 0
        do f = 1, 6
            fc = 0
            do k = 1, 4
                fc = fc + x(face(k, f), :)/4
            end do
            do k = 1, 4
                vt = vt + tet(c, fc, x(face(k, f), :), x(face(mod(k, 4) + 1, f), :))
            end do
        end do
    end function volume_by_tets

    pure real(wp) function tet(a, bb, cc, dd)
        real(wp), intent(in) :: a(3), bb(3), cc(3), dd(3)
        tet = dot_product(bb - a, cross(cc - a, dd - a))/6
    end function tet

end program test_hex8
