!> *MAT_ELASTIC (001): hypoelastic, objective through the Jaumann rate.
module xd_materials_elastic
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
        real(wp), intent(inout) :: sig(6, n)
        real(wp) :: a, b, c, sxx, syy, szz, sxy, syz, szx
        integer :: i
        do i = 1, n
            a = w(i, 1)*dt; b = w(i, 2)*dt; c = w(i, 3)*dt
            sxx = sig(1, i); syy = sig(2, i); szz = sig(3, i)
            sxy = sig(4, i); syz = sig(5, i); szx = sig(6, i)
            sig(1, i) = sxx + 2.0_wp*(a*sxy - c*szx)
            sig(2, i) = syy + 2.0_wp*(b*syz - a*sxy)
            sig(3, i) = szz + 2.0_wp*(c*szx - b*syz)
            sig(4, i) = sxy + a*(syy - sxx) - c*syz + b*szx
            sig(5, i) = syz + b*(szz - syy) - a*szx + c*sxy
            sig(6, i) = szx + c*(sxx - szz) - b*sxy + a*syz
        end do
    end subroutine jaumann_rotate

    !> Isotropic elastic increment: dsigma = dt (lambda tr(d) I + 2 mu d).
    pure subroutine elastic_update(n, lam, mu, d, dt, sig)
        integer, intent(in) :: n
        real(wp), intent(in) :: lam, mu, d(n, 6), dt
        real(wp), intent(inout) :: sig(6, n)
        real(wp) :: tr
        integer :: i
        do i = 1, n
            tr = lam*(d(i, 1) + d(i, 2) + d(i, 3))*dt
            sig(1, i) = sig(1, i) + tr + 2.0_wp*mu*d(i, 1)*dt
            sig(2, i) = sig(2, i) + tr + 2.0_wp*mu*d(i, 2)*dt
            sig(3, i) = sig(3, i) + tr + 2.0_wp*mu*d(i, 3)*dt
            sig(4, i) = sig(4, i) + 2.0_wp*mu*d(i, 4)*dt
            sig(5, i) = sig(5, i) + 2.0_wp*mu*d(i, 5)*dt
            sig(6, i) = sig(6, i) + 2.0_wp*mu*d(i, 6)*dt
        end do
    end subroutine elastic_update

end module xd_materials_elastic
