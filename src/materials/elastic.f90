!> *MAT_ELASTIC (001): hypoelastic, objective through the Jaumann rate.
module xd_materials_elastic
    ! stresses are (element, component): xx yy zz xy yz zx, element index first
    use xd_kinds, only: wp
    implicit none
    private
    public :: elastic_update, jaumann_rotate

contains

    !> Rotate the stresses by the spin over dt (sigma += dt (W sigma - sigma W)),
    !> so that a rigid rotation carries the stress with the body.
    pure subroutine jaumann_rotate(n, w, dt, sig)
        integer, intent(in) :: n
        real(wp), intent(in) :: w(n, 3), dt
        real(wp), intent(inout) :: sig(n, 6)
        real(wp) :: a, b, c, sxx, syy, szz, sxy, syz, szx
        integer :: i
        do i = 1, n
            a = w(i, 1)*dt; b = w(i, 2)*dt; c = w(i, 3)*dt
            sxx = sig(i, 1); syy = sig(i, 2); szz = sig(i, 3)
            sxy = sig(i, 4); syz = sig(i, 5); szx = sig(i, 6)
            sig(i, 1) = sxx + 2.0_wp*(a*sxy - c*szx)
            sig(i, 2) = syy + 2.0_wp*(b*syz - a*sxy)
            sig(i, 3) = szz + 2.0_wp*(c*szx - b*syz)
            sig(i, 4) = sxy + a*(syy - sxx) - c*syz + b*szx
            sig(i, 5) = syz + b*(szz - syy) - a*szx + c*sxy
            sig(i, 6) = szx + c*(sxx - szz) - b*sxy + a*syz
        end do
    end subroutine jaumann_rotate

    !> Isotropic elastic increment: dsigma = dt (lambda tr(d) I + 2 mu d).
    pure subroutine elastic_update(n, lam, mu, d, dt, sig)
        integer, intent(in) :: n
        real(wp), intent(in) :: lam, mu, d(n, 6), dt
        real(wp), intent(inout) :: sig(n, 6)
        real(wp) :: tr
        integer :: i, k
        do i = 1, n
            tr = lam*(d(i, 1) + d(i, 2) + d(i, 3))*dt
            sig(i, 1) = sig(i, 1) + tr
            sig(i, 2) = sig(i, 2) + tr
            sig(i, 3) = sig(i, 3) + tr
        end do
        do k = 1, 6
            sig(:, k) = sig(:, k) + (2.0_wp*mu*dt)*d(:, k)
        end do
    end subroutine elastic_update

end module xd_materials_elastic
