!> Elastic update: uniaxial strain against Hooke's law; the Jaumann rate
!> carries a stress through a rigid rotation (90 degrees in small steps).
program test_elastic
    use xd_kinds, only: wp, dp
    use xd_testing, only: check, check_close, test_summary
    use xd_materials_elastic, only: elastic_update, jaumann_rotate
    implicit none
    real(wp) :: sig(6, 1), d(1, 6), w(1, 3), e, nu, lam, mu, dt, theta
    integer :: k, nstep
    e = 200.0e9_wp
    nu = 0.3_wp
    lam = e*nu/((1 + nu)*(1 - 2*nu))
    mu = e/(2*(1 + nu))
    ! uniaxial strain 1e-3 in x, applied in 100 increments
    sig = 0
    d = 0
    d(1, 1) = 1.0e-3_wp
    do k = 1, 100
        call elastic_update(1, lam, mu, d, 0.01_wp, sig)
    end do
    call check_close(real(sig(1, 1), dp), real((lam + 2*mu)*1.0e-3_wp, dp), 1.0e-6_dp*e*1.0e-3_dp, &
                     'elastic uniaxial strain: sigma_xx = (lambda + 2 mu) eps')
    call check_close(real(sig(2, 1), dp), real(lam*1.0e-3_wp, dp), 1.0e-6_dp*e*1.0e-3_dp, &
                     'elastic uniaxial strain: sigma_yy = lambda eps')
    ! rigid rotation about z by 90 degrees: sigma_xx = 100 becomes sigma_yy = 100
    sig = 0
    sig(1, 1) = 100.0_wp
    nstep = 20000
    theta = acos(-1.0_wp)/2
    dt = 1.0_wp/nstep
    w = 0
    w(1, 1) = -theta      ! W_xy = -omega_z for a counter-clockwise spin
    do k = 1, nstep
        call jaumann_rotate(1, w, dt, sig)
    end do
    ! first-order update: error O(theta^2/nstep), here about 1e-4 of the stress
    call check_close(real(sig(2, 1), dp), 100.0_dp, 0.02_dp, 'Jaumann: xx stress rotated into yy by a 90 deg spin')
    call check_close(real(sig(1, 1), dp), 0.0_dp, 0.02_dp, 'Jaumann: nothing left in xx')
    call check(abs(sig(1, 1) + sig(2, 1) + sig(3, 1) - 100.0_wp) < 1.0e-8_wp, 'Jaumann rotation keeps the trace')
    call test_summary()
end program test_elastic
