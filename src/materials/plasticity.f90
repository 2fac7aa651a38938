!> Isotropic elastic-plastic solids with von Mises yield, by radial return:
!> *MAT_PLASTIC_KINEMATIC (003: linear hardening mixed between isotropic and
!> kinematic by BETA, Cowper-Symonds rate scaling) and
!> *MAT_PIECEWISE_LINEAR_PLASTICITY (024: isotropic hardening on a yield
!> curve of effective plastic strain, Cowper-Symonds rate scaling).
!> Stresses are (element, component): xx yy zz xy yz zx.
module xd_materials_plasticity
    use xd_kinds, only: wp
    implicit none
    private
    public :: plastic_params_t, plastic_update, yield_stress, rate_factor, equivalent_stress

    ! Newton tolerance: 1e-12 relative in double precision, ten round-offs in
    ! single (1e-12 cannot be reached there)
    real(wp), parameter :: tol12 = max(1.0e-12_wp, 10*epsilon(1.0_wp))

    !> Parameters of one plastic material, as the kernel needs them.
    type :: plastic_params_t
        real(wp) :: sigy = 0          !< initial yield stress (bilinear)
        real(wp) :: ep = 0            !< plastic hardening modulus E Et / (E - Et) (bilinear)
        real(wp) :: beta = 1          !< 1 isotropic, 0 kinematic
        real(wp) :: c = 0, p = 0      !< Cowper-Symonds; c = 0: rate independent
        integer :: ncurve = 0         !< > 0: yield curve points (effective plastic strain, stress)
        real(wp), allocatable :: eps(:), sy(:)
    end type plastic_params_t

contains

    !> Yield stress and hardening slope at effective plastic strain e (no rate
    !> factor): the curve, linear between points and extrapolated from its
    !> last segment, or the bilinear law.
    pure subroutine yield_stress(pp, e, sy, h)
        type(plastic_params_t), intent(in) :: pp
        real(wp), intent(in) :: e
        real(wp), intent(out) :: sy, h
        integer :: k
        if (pp%ncurve == 0) then
            sy = pp%sigy + pp%beta*pp%ep*e
            h = pp%beta*pp%ep
            return
        end if
        if (pp%ncurve == 1) then
            sy = pp%sy(1)
            h = 0
            return
        end if
        k = 1
        do while (k < pp%ncurve - 1)
            if (e < pp%eps(k + 1)) exit
            k = k + 1
        end do
        h = (pp%sy(k + 1) - pp%sy(k))/(pp%eps(k + 1) - pp%eps(k))
        sy = pp%sy(k) + h*(e - pp%eps(k))
        if (e < pp%eps(1)) then
            sy = pp%sy(1)
            h = 0
        end if
    end subroutine yield_stress

    !> The relative stress xi = dev(sig) - alpha and its von Mises value.
    pure subroutine equivalent_stress(sig, alpha, xi, xeq)
        real(wp), intent(in) :: sig(6), alpha(6)
        real(wp), intent(out) :: xi(6), xeq
        real(wp) :: pm
        pm = (sig(1) + sig(2) + sig(3))/3.0_wp
        xi(1:3) = sig(1:3) - pm - alpha(1:3)
        xi(4:6) = sig(4:6) - alpha(4:6)
        xeq = sqrt(1.5_wp*(xi(1)**2 + xi(2)**2 + xi(3)**2 + 2.0_wp*(xi(4)**2 + xi(5)**2 + xi(6)**2)))
    end subroutine equivalent_stress

    !> Cowper-Symonds scaling of the yield stress, 1 + (edot / C)^(1/P), with
    !> the effective deviatoric strain rate sqrt(2/3 d':d') of the rate d
    !> (xx yy zz xy yz zx, tensor shears); 1 when rate independent.
    pure real(wp) function rate_factor(pp, d) result(fac)
        type(plastic_params_t), intent(in) :: pp
        real(wp), intent(in) :: d(6)
        real(wp) :: dm, edot, rate
        fac = 1.0_wp
        if (pp%c > 0.0_wp .and. pp%p > 0.0_wp) then
            dm = (d(1) + d(2) + d(3))/3.0_wp
            edot = sqrt(2.0_wp/3.0_wp*((d(1) - dm)**2 + (d(2) - dm)**2 + (d(3) - dm)**2 &
                                        + 2.0_wp*(d(4)**2 + d(5)**2 + d(6)**2)))
            rate = edot/pp%c
            if (rate > 0.0_wp) fac = 1.0_wp + rate**(1.0_wp/pp%p)
        end if
    end function rate_factor

    !> Jaumann rotation is done by the caller. Elastic trial, then return to
    !> the (rate-scaled) yield surface along the deviatoric direction; the
    !> kinematic share of the hardening moves the back stress alpha.
    pure subroutine plastic_update(n, lam, mu, pp, d, dt, sig, epsp, alpha)
        integer, intent(in) :: n
        real(wp), intent(in) :: lam, mu, d(n, 6), dt
        type(plastic_params_t), intent(in) :: pp
        real(wp), intent(inout) :: sig(n, 6), epsp(n), alpha(n, 6)
        real(wp) :: tr, xi(6), xeq, fac, sy, h, dl, g, hk, s6(6), a6(6), d6(6)
        integer :: i, it
        hk = (1.0_wp - pp%beta)*pp%ep
        if (pp%ncurve > 0) hk = 0
        do i = 1, n
            tr = lam*(d(i, 1) + d(i, 2) + d(i, 3))*dt
            sig(i, 1:3) = sig(i, 1:3) + tr + 2.0_wp*mu*dt*d(i, 1:3)
            sig(i, 4:6) = sig(i, 4:6) + 2.0_wp*mu*dt*d(i, 4:6)
            s6 = sig(i, :)
            a6 = alpha(i, :)
            d6 = d(i, :)
            call equivalent_stress(s6, a6, xi, xeq)
            fac = rate_factor(pp, d6)
            call yield_stress(pp, epsp(i), sy, h)
            if (xeq <= fac*sy) cycle
            ! consistency: xeq - (3 mu + hk) dl = fac sy(epsp + dl); Newton
            ! (one step for linear hardening, a segment at a time on a curve)
            dl = 0
            do it = 1, 30
                call yield_stress(pp, epsp(i) + dl, sy, h)
                g = xeq - (3.0_wp*mu + hk)*dl - fac*sy
                if (abs(g) <= tol12*xeq) exit
                dl = dl + g/(3.0_wp*mu + hk + fac*h)
                dl = max(dl, 0.0_wp)
            end do
            epsp(i) = epsp(i) + dl
            sig(i, 1:3) = sig(i, 1:3) - 3.0_wp*mu*dl*xi(1:3)/xeq
            sig(i, 4:6) = sig(i, 4:6) - 3.0_wp*mu*dl*xi(4:6)/xeq
            if (hk > 0.0_wp) alpha(i, :) = alpha(i, :) + hk*dl*xi/xeq
        end do
    end subroutine plastic_update

end module xd_materials_plasticity
