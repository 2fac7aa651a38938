!> Eight-node hexahedron, one-point (uniform strain) integration after
!> Flanagan & Belytschko (1981), with their hourglass control.
!> Kernels work on a group of `n` elements, element index innermost, so
!> the loops vectorize; nodal data are gathered into (n,8) arrays first.
module xd_elements_hex8
    use xd_kinds, only: wp, dp
    implicit none
    private
    public :: hex_volume_operator, hex_corner_jacobians, hex_shape_kind
    public :: hex_regular, hex_wedge, hex_tet, hex_bad
    public :: hex_b_matrix, hex_velocity_gradient, hex_stress_forces
    public :: hex_hourglass_shape, hex_hourglass_rates, hex_hourglass_modes, hex_hourglass_forces, &
              hex_char_length, gamma_hg

    integer, parameter :: hex_regular = 0, hex_wedge = 1, hex_tet = 2, hex_bad = -1

    !> Hourglass base vectors Gamma (4 x 8), FB 1981 Eq. (16).
    real(wp), parameter :: gamma_hg(8, 4) = reshape([ &
        1.0_wp, 1.0_wp, -1.0_wp, -1.0_wp, -1.0_wp, -1.0_wp, 1.0_wp, 1.0_wp, &
        1.0_wp, -1.0_wp, -1.0_wp, 1.0_wp, -1.0_wp, 1.0_wp, 1.0_wp, -1.0_wp, &
        1.0_wp, -1.0_wp, 1.0_wp, -1.0_wp, 1.0_wp, -1.0_wp, 1.0_wp, -1.0_wp, &
        -1.0_wp, 1.0_wp, -1.0_wp, 1.0_wp, 1.0_wp, -1.0_wp, 1.0_wp, -1.0_wp], [8, 4])

    !> Node permutations that turn the node-1 formula of B into node I's.
    integer, parameter :: perm(8, 8) = reshape([ &
        1, 2, 3, 4, 5, 6, 7, 8, &
        2, 3, 4, 1, 6, 7, 8, 5, &
        3, 4, 1, 2, 7, 8, 5, 6, &
        4, 1, 2, 3, 8, 5, 6, 7, &
        5, 8, 7, 6, 1, 4, 3, 2, &
        6, 5, 8, 7, 2, 1, 4, 3, &
        7, 6, 5, 8, 3, 2, 1, 4, &
        8, 7, 6, 5, 4, 3, 2, 1], [8, 8])

    !> Faces, counter-clockwise seen from outside, for the characteristic length.
    integer, parameter :: face(4, 6) = reshape([1, 2, 3, 4, 5, 8, 7, 6, 1, 5, 6, 2, &
                                                2, 6, 7, 3, 3, 7, 8, 4, 4, 8, 5, 1], [4, 6])

contains

    !> dV/dx for node 1 in terms of the other nodes' y and z (FB 1981, Eq. 79);
    !> cyclic use (y,z) -> (z,x) -> (x,y) gives the y and z components.
    elemental real(wp) function bfun(y2, y3, y4, y5, y6, y8, z2, z3, z4, z5, z6, z8)
        real(wp), intent(in) :: y2, y3, y4, y5, y6, y8, z2, z3, z4, z5, z6, z8
        bfun = (y2*((z6 - z3) - (z4 - z5)) + y3*(z2 - z4) + y4*((z3 - z8) - (z5 - z2)) &
                + y5*((z8 - z6) - (z2 - z4)) + y6*(z5 - z2) + y8*(z4 - z5))/12.0_wp
    end function bfun

    !> Integrated gradient operator B_iI = integral of dN_I/dx_i over the
    !> element (= dV/dx_iI) and the exact volume V = sum_I x_I B_xI, for a group.
    pure subroutine hex_b_matrix(n, x, y, z, bx, by, bz, vol)
        integer, intent(in) :: n
        real(wp), intent(in) :: x(n, 8), y(n, 8), z(n, 8)
        real(wp), intent(out) :: bx(n, 8), by(n, 8), bz(n, 8), vol(n)
        integer :: k
        integer :: p2, p3, p4, p5, p6, p8
        do k = 1, 8
            p2 = perm(2, k); p3 = perm(3, k); p4 = perm(4, k)
            p5 = perm(5, k); p6 = perm(6, k); p8 = perm(8, k)
            bx(:, k) = bfun(y(:, p2), y(:, p3), y(:, p4), y(:, p5), y(:, p6), y(:, p8), &
                            z(:, p2), z(:, p3), z(:, p4), z(:, p5), z(:, p6), z(:, p8))
            by(:, k) = bfun(z(:, p2), z(:, p3), z(:, p4), z(:, p5), z(:, p6), z(:, p8), &
                            x(:, p2), x(:, p3), x(:, p4), x(:, p5), x(:, p6), x(:, p8))
            bz(:, k) = bfun(x(:, p2), x(:, p3), x(:, p4), x(:, p5), x(:, p6), x(:, p8), &
                            y(:, p2), y(:, p3), y(:, p4), y(:, p5), y(:, p6), y(:, p8))
        end do
        vol = 0.0_wp
        do k = 1, 8
            vol = vol + x(:, k)*bx(:, k)
        end do
    end subroutine hex_b_matrix

    !> Single-element form of hex_b_matrix: xe(8,3) node coordinates.
    pure subroutine hex_volume_operator(xe, b, vol)
        real(wp), intent(in) :: xe(8, 3)
        real(wp), intent(out) :: b(8, 3), vol
        real(wp) :: v1(1)
        call hex_b_matrix(1, xe(:, 1), xe(:, 2), xe(:, 3), b(:, 1), b(:, 2), b(:, 3), v1)
        vol = v1(1)
    end subroutine hex_volume_operator

    !> Velocity gradient L = (1/V) sum_I v_I (x) B_I, split into the strain
    !> rate d (xx yy zz xy yz zx, tensor shear) and the spin w (w_xy w_yz w_zx).
    pure subroutine hex_velocity_gradient(n, vx, vy, vz, bx, by, bz, vol, d, w)
        integer, intent(in) :: n
        real(wp), intent(in) :: vx(n, 8), vy(n, 8), vz(n, 8)
        real(wp), intent(in) :: bx(n, 8), by(n, 8), bz(n, 8), vol(n)
        real(wp), intent(out) :: d(n, 6), w(n, 3)
        real(wp), dimension(n) :: lxx, lyy, lzz, lxy, lyx, lyz, lzy, lzx, lxz, r
        integer :: k
        lxx = 0; lyy = 0; lzz = 0; lxy = 0; lyx = 0; lyz = 0; lzy = 0; lzx = 0; lxz = 0
        do k = 1, 8
            lxx = lxx + vx(:, k)*bx(:, k)
            lyy = lyy + vy(:, k)*by(:, k)
            lzz = lzz + vz(:, k)*bz(:, k)
            lxy = lxy + vx(:, k)*by(:, k)
            lyx = lyx + vy(:, k)*bx(:, k)
            lyz = lyz + vy(:, k)*bz(:, k)
            lzy = lzy + vz(:, k)*by(:, k)
            lzx = lzx + vz(:, k)*bx(:, k)
            lxz = lxz + vx(:, k)*bz(:, k)
        end do
        r = 1.0_wp/vol
        d(:, 1) = lxx*r
        d(:, 2) = lyy*r
        d(:, 3) = lzz*r
        d(:, 4) = 0.5_wp*(lxy + lyx)*r
        d(:, 5) = 0.5_wp*(lyz + lzy)*r
        d(:, 6) = 0.5_wp*(lzx + lxz)*r
        w(:, 1) = 0.5_wp*(lxy - lyx)*r
        w(:, 2) = 0.5_wp*(lyz - lzy)*r
        w(:, 3) = 0.5_wp*(lzx - lxz)*r
    end subroutine hex_velocity_gradient

    !> Nodal forces of the stress (less the bulk viscosity q): f_iI = -s_ij B_jI.
    pure subroutine hex_stress_forces(n, sig, q, bx, by, bz, fx, fy, fz)
        integer, intent(in) :: n
        real(wp), intent(in) :: sig(n, 6), q(n)
        real(wp), intent(in) :: bx(n, 8), by(n, 8), bz(n, 8)
        real(wp), intent(out) :: fx(n, 8), fy(n, 8), fz(n, 8)
        integer :: k
        real(wp) :: sxx(n), syy(n), szz(n)
        sxx = sig(:, 1) - q
        syy = sig(:, 2) - q
        szz = sig(:, 3) - q
        do k = 1, 8
            fx(:, k) = -(sxx*bx(:, k) + sig(:, 4)*by(:, k) + sig(:, 6)*bz(:, k))
            fy(:, k) = -(sig(:, 4)*bx(:, k) + syy*by(:, k) + sig(:, 5)*bz(:, k))
            fz(:, k) = -(sig(:, 6)*bx(:, k) + sig(:, 5)*by(:, k) + szz*bz(:, k))
        end do
    end subroutine hex_stress_forces

    !> Hourglass shape vectors gamma = Gamma - (1/V)(Gamma . x_j) B_j (FB 1981
    !> Eq. 60): orthogonal to every linear velocity field, so rigid motion and
    !> uniform strain produce no hourglass force.
    pure subroutine hex_hourglass_shape(n, x, y, z, bx, by, bz, vol, g)
        integer, intent(in) :: n
        real(wp), intent(in) :: x(n, 8), y(n, 8), z(n, 8)
        real(wp), intent(in) :: bx(n, 8), by(n, 8), bz(n, 8), vol(n)
        real(wp), intent(out) :: g(n, 8, 4)
        real(wp) :: hx(n), hy(n), hz(n), r(n)
        integer :: a, k
        r = 1.0_wp/vol
        do a = 1, 4
            hx = 0; hy = 0; hz = 0
            do k = 1, 8
                hx = hx + gamma_hg(k, a)*x(:, k)
                hy = hy + gamma_hg(k, a)*y(:, k)
                hz = hz + gamma_hg(k, a)*z(:, k)
            end do
            hx = hx*r; hy = hy*r; hz = hz*r
            do k = 1, 8
                g(:, k, a) = gamma_hg(k, a) - (hx*bx(:, k) + hy*by(:, k) + hz*bz(:, k))
            end do
        end do
    end subroutine hex_hourglass_shape

    !> Hourglass mode rates h(i, j, a) = sum_I v_jI gamma_aI.
    pure subroutine hex_hourglass_rates(n, vx, vy, vz, g, h)
        integer, intent(in) :: n
        real(wp), intent(in) :: vx(n, 8), vy(n, 8), vz(n, 8), g(n, 8, 4)
        real(wp), intent(out) :: h(n, 3, 4)
        integer :: a, k
        h = 0
        do a = 1, 4
            do k = 1, 8
                h(:, 1, a) = h(:, 1, a) + vx(:, k)*g(:, k, a)
                h(:, 2, a) = h(:, 2, a) + vy(:, k)*g(:, k, a)
                h(:, 3, a) = h(:, 3, a) + vz(:, k)*g(:, k, a)
            end do
        end do
    end subroutine hex_hourglass_rates

    !> Hourglass rates without forming the shape vectors: with
    !> gamma_aI = Gamma_aI - (1/V) hx_aj B_jI and hx_aj = sum_I Gamma_aI x_jI,
    !> h_ia = sum_I v_iI gamma_aI = (v_i . Gamma_a) - hx_aj L_ij, L the velocity
    !> gradient (1/V) sum_I v_iI B_jI on the same geometry. Returns hx for
    !> hex_hourglass_forces.
    pure subroutine hex_hourglass_modes(n, x, y, z, vx, vy, vz, bx, by, bz, vol, hx, h)
        integer, intent(in) :: n
        real(wp), intent(in) :: x(n, 8), y(n, 8), z(n, 8), vx(n, 8), vy(n, 8), vz(n, 8)
        real(wp), intent(in) :: bx(n, 8), by(n, 8), bz(n, 8), vol(n)
        real(wp), intent(out) :: hx(n, 3, 4), h(n, 3, 4)
        real(wp), dimension(n) :: lxx, lxy, lxz, lyx, lyy, lyz, lzx, lzy, lzz, r
        integer :: a, k
        lxx = 0; lxy = 0; lxz = 0; lyx = 0; lyy = 0; lyz = 0; lzx = 0; lzy = 0; lzz = 0
        do k = 1, 8
            lxx = lxx + vx(:, k)*bx(:, k); lxy = lxy + vx(:, k)*by(:, k); lxz = lxz + vx(:, k)*bz(:, k)
            lyx = lyx + vy(:, k)*bx(:, k); lyy = lyy + vy(:, k)*by(:, k); lyz = lyz + vy(:, k)*bz(:, k)
            lzx = lzx + vz(:, k)*bx(:, k); lzy = lzy + vz(:, k)*by(:, k); lzz = lzz + vz(:, k)*bz(:, k)
        end do
        r = 1.0_wp/vol
        do a = 1, 4
            hx(:, :, a) = 0
            h(:, :, a) = 0
            do k = 1, 8
                hx(:, 1, a) = hx(:, 1, a) + gamma_hg(k, a)*x(:, k)
                hx(:, 2, a) = hx(:, 2, a) + gamma_hg(k, a)*y(:, k)
                hx(:, 3, a) = hx(:, 3, a) + gamma_hg(k, a)*z(:, k)
                h(:, 1, a) = h(:, 1, a) + gamma_hg(k, a)*vx(:, k)
                h(:, 2, a) = h(:, 2, a) + gamma_hg(k, a)*vy(:, k)
                h(:, 3, a) = h(:, 3, a) + gamma_hg(k, a)*vz(:, k)
            end do
            h(:, 1, a) = h(:, 1, a) - r*(hx(:, 1, a)*lxx + hx(:, 2, a)*lxy + hx(:, 3, a)*lxz)
            h(:, 2, a) = h(:, 2, a) - r*(hx(:, 1, a)*lyx + hx(:, 2, a)*lyy + hx(:, 3, a)*lyz)
            h(:, 3, a) = h(:, 3, a) - r*(hx(:, 1, a)*lzx + hx(:, 2, a)*lzy + hx(:, 3, a)*lzz)
        end do
    end subroutine hex_hourglass_modes

    !> Subtract the nodal forces of the hourglass generalized forces q(n,3,4):
    !> f_iI -= sum_a q_ia gamma_aI = sum_a q_ia Gamma_aI - c_ij B_jI with
    !> c_ij = (1/V) sum_a q_ia hx_aj.
    pure subroutine hex_hourglass_forces(n, q, hx, bx, by, bz, vol, fx, fy, fz)
        integer, intent(in) :: n
        real(wp), intent(in) :: q(n, 3, 4), hx(n, 3, 4), bx(n, 8), by(n, 8), bz(n, 8), vol(n)
        real(wp), intent(inout) :: fx(n, 8), fy(n, 8), fz(n, 8)
        real(wp), dimension(n, 3, 3) :: c
        real(wp) :: r(n)
        integer :: i, j, k
        r = 1.0_wp/vol
        do j = 1, 3
            do i = 1, 3
                c(:, i, j) = r*(q(:, i, 1)*hx(:, j, 1) + q(:, i, 2)*hx(:, j, 2) + q(:, i, 3)*hx(:, j, 3) &
                                + q(:, i, 4)*hx(:, j, 4))
            end do
        end do
        do k = 1, 8
            fx(:, k) = fx(:, k) - (gamma_hg(k, 1)*q(:, 1, 1) + gamma_hg(k, 2)*q(:, 1, 2) + gamma_hg(k, 3)*q(:, 1, 3) &
                                   + gamma_hg(k, 4)*q(:, 1, 4)) + c(:, 1, 1)*bx(:, k) + c(:, 1, 2)*by(:, k) &
                       + c(:, 1, 3)*bz(:, k)
            fy(:, k) = fy(:, k) - (gamma_hg(k, 1)*q(:, 2, 1) + gamma_hg(k, 2)*q(:, 2, 2) + gamma_hg(k, 3)*q(:, 2, 3) &
                                   + gamma_hg(k, 4)*q(:, 2, 4)) + c(:, 2, 1)*bx(:, k) + c(:, 2, 2)*by(:, k) &
                       + c(:, 2, 3)*bz(:, k)
            fz(:, k) = fz(:, k) - (gamma_hg(k, 1)*q(:, 3, 1) + gamma_hg(k, 2)*q(:, 3, 2) + gamma_hg(k, 3)*q(:, 3, 3) &
                                   + gamma_hg(k, 4)*q(:, 3, 4)) + c(:, 3, 1)*bx(:, k) + c(:, 3, 2)*by(:, k) &
                       + c(:, 3, 3)*bz(:, k)
        end do
    end subroutine hex_hourglass_forces

    !> Characteristic length V / (largest face area), LS-DYNA's choice for solids.
    pure subroutine hex_char_length(n, x, y, z, vol, le)
        integer, intent(in) :: n
        real(wp), intent(in) :: x(n, 8), y(n, 8), z(n, 8), vol(n)
        real(wp), intent(out) :: le(n)
        real(wp) :: amax(n), ax, ay, az, d1x, d1y, d1z, d2x, d2y, d2z, a2
        integer :: f, i, k1, k2, k3, k4
        amax = 0
        do f = 1, 6
            k1 = face(1, f); k2 = face(2, f); k3 = face(3, f); k4 = face(4, f)
            do i = 1, n
                d1x = x(i, k3) - x(i, k1); d1y = y(i, k3) - y(i, k1); d1z = z(i, k3) - z(i, k1)
                d2x = x(i, k4) - x(i, k2); d2y = y(i, k4) - y(i, k2); d2z = z(i, k4) - z(i, k2)
                ax = d1y*d2z - d1z*d2y
                ay = d1z*d2x - d1x*d2z
                az = d1x*d2y - d1y*d2x
                a2 = ax*ax + ay*ay + az*az
                amax(i) = max(amax(i), a2)
            end do
        end do
        le = vol/(0.5_wp*sqrt(amax))
    end subroutine hex_char_length

    !> Jacobian determinant at each corner (the triple product of its three
    !> edges): non-positive means the corner is inverted.
    pure subroutine hex_corner_jacobians(xe, cj)
        real(wp), intent(in) :: xe(8, 3)
        real(wp), intent(out) :: cj(8)
        ! for each corner: the three neighbours in right-handed order
        integer, parameter :: nb(3, 8) = reshape([2, 4, 5, 3, 1, 6, 4, 2, 7, 1, 3, 8, &
                                                  8, 6, 1, 5, 7, 2, 6, 8, 3, 7, 5, 4], [3, 8])
        real(wp) :: a(3), b(3), c(3)
        integer :: k
        do k = 1, 8
            a = xe(nb(1, k), :) - xe(k, :)
            b = xe(nb(2, k), :) - xe(k, :)
            c = xe(nb(3, k), :) - xe(k, :)
            cj(k) = a(1)*(b(2)*c(3) - b(3)*c(2)) - a(2)*(b(1)*c(3) - b(3)*c(1)) + a(3)*(b(1)*c(2) - b(2)*c(1))
        end do
    end subroutine hex_corner_jacobians

    !> Regular hexahedron, accepted degenerate wedge or tetrahedron, or bad.
    pure integer function hex_shape_kind(c) result(kind)
        integer, intent(in) :: c(8)
        integer :: i, j, nrep
        nrep = 0
        do i = 1, 8
            do j = i + 1, 8
                if (c(i) == c(j)) nrep = nrep + 1
            end do
        end do
        kind = hex_regular
        if (nrep == 0) return
        kind = hex_bad
        if (all(c(4:8) == c(4)) .and. c(1) /= c(2) .and. c(1) /= c(3) .and. c(2) /= c(3) .and. &
            all(c(1:3) /= c(4))) then
            kind = hex_tet
        else if (nrep == 2 .and. c(5) == c(6) .and. c(7) == c(8)) then
            kind = hex_wedge
        end if
    end function hex_shape_kind

end module xd_elements_hex8
