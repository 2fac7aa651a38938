!> The penalty force of step 4 (Eq. 12) swept over the step (issue 28):
!> in depth deeper than half the step's approach it is K a; a pair found
!> ahead of touching farther than that has none; across the surface it is
!> K times the mean of the depth's positive part over the path; at the
!> start the half step's one-sided path. VDC pushes the slave out of a
!> shell on either side. And the point of it: one mass bouncing on the
!> spring under the central difference, from every phase of the step at
!> which it meets the surface, keeps its energy to the swept bound, where
!> the spring taken at x(n) alone gains or loses up to 1.5%.
program test_contact_enforcement
    use xd_kinds, only: wp
    use xd_testing, only: check, check_close, test_summary
    use xd_contact_segment_check, only: hit_t, kept
    use xd_contact_enforcement, only: friction_t, penalty_force
    implicit none
    type(hit_t) :: h
    type(friction_t) :: fr, fv
    real(wp) :: f(3), ft(3), k, dt, v, hh
    real(wp) :: gain_sw, loss_sw, gain_x, loss_x, r
    integer :: j
    real(wp), parameter :: tol = 1.0e-12_wp

    k = 1.0e6_wp
    dt = 1.0e-6_wp
    v = 2.0_wp                     ! approaching at 2: h = dt v / 2 = 1e-6
    hh = 0.5_wp*dt*v
    h%found = .true.
    h%nhat = [0.0_wp, 0.0_wp, 1.0_wp]
    ! deeper than h: K a, as Eq. 12 without the sweep
    h%a = -3.0e-6_wp
    ft = 0
    call penalty_force(kept(h), k, [0.0_wp, 0.0_wp, -v], 1.0_wp, fr, dt, ft, f, swept=.true.)
    call check_close(f(3), 3.0_wp, tol, 'penalty: deeper than half the step''s approach the force is K a')
    ! at the surface (a = 0, no gap): the path from -h to +h, mean K h / 4
    h%a = 0
    h%gap = 0
    call penalty_force(kept(h), k, [0.0_wp, 0.0_wp, -v], 1.0_wp, fr, dt, ft, f, swept=.true.)
    call check_close(f(3), k*hh/4.0_wp, tol, 'penalty: at the surface the swept force is K h / 4')
    call penalty_force(kept(h), k, [0.0_wp, 0.0_wp, -v], 1.0_wp, fr, dt, ft, f)
    call check(all(f == 0.0_wp), 'penalty: at the surface the spring taken at x(n) alone has no force')
    ! found ahead by half of h: the path reaches h/2 deep, (p + h)^2 / (4 h)
    h%gap = 0.5_wp*hh
    call penalty_force(kept(h), k, [0.0_wp, 0.0_wp, -v], 1.0_wp, fr, dt, ft, f, swept=.true.)
    call check_close(f(3), k*(0.5_wp*hh)**2/(4.0_wp*hh), tol, &
                     'penalty: found ahead by h/2, the force is K (p + h)^2 / (4 h) with p = -h/2')
    ! found ahead by more than h: none, whichever way it moves
    h%gap = 1.01_wp*hh
    call penalty_force(kept(h), k, [0.0_wp, 0.0_wp, -v], 1.0_wp, fr, dt, ft, f, swept=.true.)
    call check(all(f == 0.0_wp), 'penalty: found ahead by more than half the step''s approach, no force')
    ! the start: the half step from t = 0, one-sided. 0.5 h deep moving in:
    ! the path [p, p + h], mean p + h/2; moving out: [p - h, p], mean of the
    ! positive part p^2 / (2 h)
    h%a = -0.5_wp*hh
    h%gap = 0
    call penalty_force(kept(h), k, [0.0_wp, 0.0_wp, -v], 1.0_wp, fr, dt, ft, f, swept=.true., start=.true.)
    call check_close(f(3), k*hh, tol, 'penalty: at the start, moving in from h/2 deep, the force is K (p + h/2)')
    call penalty_force(kept(h), k, [0.0_wp, 0.0_wp, v], 1.0_wp, fr, dt, ft, f, swept=.true., start=.true.)
    call check_close(f(3), k*(0.5_wp*hh)**2/(2.0_wp*hh), tol, &
                     'penalty: at the start, moving out from h/2 deep, the force is K p^2 / (2 h)')
    ! a slave below a shell (a > 0): pushed along -nhat, and VDC damps its
    ! approach along the same push (it used to turn the force to +nhat)
    ! (VDC 0.05% of critical with m_eff 1: c = 1, c v = 2 against K a = 3)
    fv%vdc = 0.05_wp
    h%a = 3.0e-6_wp
    call penalty_force(kept(h), k, [0.0_wp, 0.0_wp, v], 1.0_wp, fv, dt, ft, f, swept=.true.)
    call check_close(f(3), -5.0_wp, 1.0e-9_wp, &
                     'penalty: VDC on a slave below a shell adds c v to the push out along -nhat (approaching)')
    call penalty_force(kept(h), k, [0.0_wp, 0.0_wp, -v], 1.0_wp, fv, dt, ft, f, swept=.true.)
    call check_close(f(3), -1.0_wp, 1.0e-9_wp, &
                     'penalty: VDC on a slave below a shell takes c v from the push while it separates')
    fv%vdc = 20
    call penalty_force(kept(h), k, [0.0_wp, 0.0_wp, -v], 1.0_wp, fv, dt, ft, f, swept=.true.)
    call check(all(f == 0.0_wp), 'penalty: VDC may cancel the push but never pulls the surfaces together')

    ! one mass on the spring, omega dt = 0.45, meeting the surface at 200
    ! phases of the step: the bounce's energy ratio out/in
    gain_sw = 0; loss_sw = 0; gain_x = 0; loss_x = 0
    do j = 0, 199
        r = bounce(0.45_wp, real(j, wp)/200.0_wp, .true.)
        gain_sw = max(gain_sw, r - 1.0_wp)
        loss_sw = max(loss_sw, 1.0_wp - r)
        r = bounce(0.45_wp, real(j, wp)/200.0_wp, .false.)
        gain_x = max(gain_x, r - 1.0_wp)
        loss_x = max(loss_x, 1.0_wp - r)
    end do
    ! bands: swept, the worst gain 1.25e-4 and loss 0.23% (as computed when
    ! written, to 1e-5); at x(n) alone 1.5% each way
    call check(gain_sw < 1.5e-4_wp .and. loss_sw < 2.5e-3_wp, &
               'penalty: a bounce at omega dt 0.45, swept, gains under 1.5e-4 and loses under 0.25% at any phase')
    call check(gain_x > 1.0e-2_wp .and. loss_x > 1.0e-2_wp, &
               'penalty: the same bounce with the spring at x(n) alone gains and loses over 1% (what the sweep removes)')
    call test_summary()

contains

    !> Kinetic energy after / before a unit mass at unit speed meets the
    !> surface z = 0 from above under the central difference (the contact
    !> found ahead by its open gap, as the local search does), first
    !> crossing the surface at `phase` of a step.
    real(wp) function bounce(wdt, phase, swept) result(ratio)
        real(wp), intent(in) :: wdt, phase
        logical, intent(in) :: swept
        type(hit_t) :: c
        type(friction_t) :: none
        real(wp) :: x, vz, kk, tstep, fo(3), tt(3)
        integer :: n
        kk = 1.0_wp
        tstep = wdt
        vz = -1.0_wp
        x = tstep*(1.0_wp - phase) + 1.0e-3_wp*tstep
        c%found = .true.
        c%nhat = [0.0_wp, 0.0_wp, 1.0_wp]
        tt = 0
        do n = 1, 100000
            c%a = min(x, 0.0_wp)
            c%gap = max(x, 0.0_wp)
            call penalty_force(kept(c), kk, [0.0_wp, 0.0_wp, vz], 1.0_wp, none, tstep, tt, fo, swept=swept)
            vz = vz + tstep*fo(3)
            x = x + tstep*vz
            if (x > 5.0_wp .and. vz > 0.0_wp) exit
        end do
        ratio = vz*vz
    end function bounce

end program test_contact_enforcement
