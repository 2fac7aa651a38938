!> The cohesive law of tiebreak OPTION 9 against its definition: each mode
!> alone peaks at its traction and releases its energy (the area under the
!> traction, integrated in fine steps: 1e-4); proportional mixed-mode
!> openings release G_I and G_II on the criterion's curve, (G_I/GIC)^xmu +
!> (G_II/GIIC)^xmu = 1 for xmu 1 and 2, and Benzeggagh-Kenane's G_c for xmu
!> < 0 (1e-3: the steps' first-order error at the damage's onset); damage
!> never heals (unloading and reloading follow the secant); compression
!> carries no cohesive traction.
program test_contact_tied
    use xd_kinds, only: wp, dp
    use xd_testing, only: check, check_close, test_summary
    use xd_contact_tied, only: cohesive_law
    implicit none
    real(wp), parameter :: kn = 1.0e12_wp, kt = 0.5e12_wp, t = 1.0e6_wp, s = 0.6e6_wp, gic = 100.0_wp, giic = 250.0_wp
    real(dp) :: g1, g2, peak, gc, r
    real(wp) :: dmg, tr(3), dmg_mid, beta
    integer :: i
    ! mode I alone
    call open_along([0.0_wp, 0.0_wp, 1.0_wp], 1.0_wp, 4.0e-4_wp, g1, g2, peak, dmg)
    call check_close(peak, real(t, dp), 1.0e-3_dp*t, 'cohesive mode I: the traction peaks at T')
    call check_close(g1, real(gic, dp), 1.0e-4_dp*gic, 'cohesive mode I: the energy released is GIC')
    call check(abs(g2) < 1.0e-9_dp .and. dmg == 1.0_wp, 'cohesive mode I: no shear work, fully damaged')
    ! mode II alone (along an oblique in-plane direction)
    call open_along([0.6_wp, 0.8_wp, 0.0_wp], 1.0_wp, 1.0e-3_wp, g1, g2, peak, dmg)
    call check_close(peak, real(s, dp), 1.0e-3_dp*s, 'cohesive mode II: the traction peaks at S')
    call check_close(g2, real(giic, dp), 1.0e-4_dp*giic, 'cohesive mode II: the energy released is GIIC')
    ! proportional mixed modes on the power law's curve
    do i = 1, 3
        beta = 0.5_wp*2.0_wp**(i - 1)
        call open_along([beta, 0.0_wp, 1.0_wp], 1.0_wp, 1.0e-3_wp, g1, g2, peak, dmg)
        r = g1/gic + g2/giic
        call check_close(r, 1.0_dp, 1.0e-3_dp, 'cohesive mixed mode, beta '//trim(fmt(beta))// &
                         ', XMU 1: G_I/GIC + G_II/GIIC = 1')
        call open_along([beta, 0.0_wp, 1.0_wp], 2.0_wp, 1.0e-3_wp, g1, g2, peak, dmg)
        r = (g1/gic)**2 + (g2/giic)**2
        call check_close(r, 1.0_dp, 1.0e-3_dp, 'cohesive mixed mode, beta '//trim(fmt(beta))// &
                         ', XMU 2: (G_I/GIC)^2 + (G_II/GIIC)^2 = 1')
        call open_along([beta, 0.0_wp, 1.0_wp], -1.5_wp, 1.0e-3_wp, g1, g2, peak, dmg)
        gc = gic + (giic - gic)*(g2/(g1 + g2))**1.5_dp
        call check_close((g1 + g2)/gc, 1.0_dp, 1.0e-3_dp, 'cohesive mixed mode, beta '//trim(fmt(beta))// &
                         ', XMU -1.5: G_I + G_II = GIC + (GIIC - GIC) (G_II/G)^1.5 (Benzeggagh-Kenane)')
    end do
    ! unloading from the softening branch and reloading: the secant, the
    ! damage kept
    dmg = 0
    call cohesive_law([0.0_wp, 0.0_wp, 1.0e-4_wp], kn, kt, t, s, gic, giic, 1.0_wp, dmg, tr)
    dmg_mid = dmg
    call cohesive_law([0.0_wp, 0.0_wp, 0.5e-4_wp], kn, kt, t, s, gic, giic, 1.0_wp, dmg, tr)
    call check(dmg == dmg_mid .and. dmg > 0.0_wp .and. dmg < 1.0_wp, 'cohesive: unloading keeps the damage')
    call check_close(real(tr(3), dp), real((1 - dmg_mid)*kn*0.5e-4_wp, dp), 1.0e-9_dp*t, &
                     'cohesive: unloading follows the secant (1 - D) CN delta')
    call cohesive_law([0.0_wp, 0.0_wp, 0.0_wp], kn, kt, t, s, gic, giic, 1.0_wp, dmg, tr)
    call check(dmg == dmg_mid .and. all(tr == 0.0_wp), 'cohesive: closed again, no traction, the damage kept')
    ! compression: none (the sliding contact's), and no damage from it
    dmg = 0
    call cohesive_law([0.0_wp, 0.0_wp, -1.0e-3_wp], kn, kt, t, s, gic, giic, 1.0_wp, dmg, tr)
    call check(tr(3) == 0.0_wp .and. dmg == 0.0_wp, 'cohesive: compression carries no cohesive traction, no damage')
    call test_summary()
contains
    !> Opens the interface along dir (normalised) in 200,000 equal steps to
    !> dmax, integrating the work of each mode (trapezoids): g1 the normal,
    !> g2 the shear; peak the largest traction's length.
    subroutine open_along(dir, xmu, dmax, g1, g2, peak, dmg)
        real(wp), intent(in) :: dir(3), xmu, dmax
        real(dp), intent(out) :: g1, g2, peak
        real(wp), intent(out) :: dmg
        integer, parameter :: n = 200000
        real(wp) :: u(3), uo(3), tr(3), to(3), e(3)
        integer :: k
        e = dir/norm2(dir)
        dmg = 0
        g1 = 0
        g2 = 0
        peak = 0
        uo = 0
        to = 0
        do k = 1, n
            u = e*dmax*k/n
            call cohesive_law(u, kn, kt, t, s, gic, giic, xmu, dmg, tr)
            g1 = g1 + 0.5_dp*(tr(3) + to(3))*(u(3) - uo(3))
            g2 = g2 + 0.5_dp*dot_product(real(tr(1:2) + to(1:2), dp), real(u(1:2) - uo(1:2), dp))
            peak = max(peak, real(norm2(tr), dp))
            uo = u
            to = tr
        end do
    end subroutine open_along

    function fmt(x) result(c)
        real(wp), intent(in) :: x
        character(len=16) :: c
        write (c, '(f6.2)') x
        c = adjustl(c)
    end function fmt
end program test_contact_tied
