!> The Hughes-Liu beam (*SECTION_BEAM ELFORM 1) as a kernel for the beams'
!> co-rotational frame (xd_elements_beam_bs): one stress point along the
!> length, at mid-span, and a quadrature of the cross-section (QR), each
!> section point carrying the axial stress and the two transverse shears in
!> the element's frame (e1 along the chord, e2 = s, e3 = t): a Timoshenko
!> beam, its curvature and shear constant over the element (no spurious
!> mode: two strain measures per plane against two deformation modes).
!>
!> At the section point (y, z) (y along s, z along t), with the nodes'
!> velocities v1, v2 and angular velocities w1, w2, dv = v2 - v1, dw = w2 -
!> w1, w_m = (w1 + w2) / 2 and L the present length (the velocity field v +
!> w x (y e2 + z e3), linear along the beam, differentiated):
!>
!>   d11 = dv.e1 / L - y dw.e3 / L + z dw.e2 / L
!>   g12 = dv.e2 / L - w_m.e3 - c z dw.e1 / L
!>   g13 = dv.e3 / L + w_m.e2 + c y dw.e1 / L
!>
!> (g the engineering shears; a rigid turn gives none). c = sqrt(J / Ip)
!> scales the twist's shear so that the elastic torque is G J dphi/dx with
!> J Saint-Venant's constant (the section's points alone would give the
!> polar moment Ip, which overstates a rectangle's torsional stiffness).
!> Stresses: sigma += E d11 dt, tau += SHRF G g dt, in the element's frame
!> (co-rotational: no objective rate needed); a plastic material returns
!> sqrt(sigma^2 + 3 tau12^2 + 3 tau13^2) to its flow stress (isotropic
!> hardening, the law's yield_stress) by a scalar Newton iteration on the
!> equivalent plastic strain's increment. The resultants N = sum w sigma,
!> M_s = sum w sigma z, M_t = -sum w sigma y, V_s = sum w tau12, V_t = sum w
!> tau13, T = c sum w (tau13 y - tau12 z) carry the virtual power N dv.e1 +
!> M_s dw.e2 + M_t dw.e3 + V_s (dv.e2 - L w_m.e3) + V_t (dv.e3 + L w_m.e2)
!> + T dw.e1, which beam_bs's end-moment form reproduces (hl_end_moments).
!>
!> Section rules (QR): a rectangle TS1 (along s) x TT1 (along t): 1 one
!> point, 2 (and 0) 2 x 2 Gauss, 3 3 x 3 Gauss, 4 3 x 3 Lobatto, 5 4 x 4
!> Gauss; a tube (or a round bar, TT1 = 0): 8 points around the
!> circumference times 2 Gauss points across the wall (integrating r dr):
!> exact for the elastic area, moments of inertia and polar moment.
module xd_elements_beam_hl
    use xd_kinds, only: wp, dp
    use xd_materials_plasticity, only: plastic_params_t, yield_stress
    implicit none
    private
    public :: hl_section, hl_update, hl_end_moments, max_points

    integer, parameter :: max_points = 16

contains

    !> The section's points: y (along s), z (along t) and the weights (areas),
    !> n of them, for the rule qr on a rectangle ts x tt (cst 0) or a tube of
    !> outer diameter ts and inner tt (cst 1).
    subroutine hl_section(cst, qr, ts, tt, n, pt)
        integer, intent(in) :: cst, qr
        real(wp), intent(in) :: ts, tt
        integer, intent(out) :: n
        real(wp), intent(out) :: pt(3, max_points)
        real(wp) :: g(4), w(4), ro, ri, r, th, pi
        integer :: m, i, j, k
        pt = 0
        if (cst == 1) then
            pi = acos(-1.0_wp)
            ro = ts/2
            ri = tt/2
            n = 0
            ! 2-point Gauss over r in [ri, ro] with the weight r dr, 8 angles
            do i = 1, 2
                r = 0.5_wp*(ro + ri) + (2*i - 3)*0.5_wp*(ro - ri)/sqrt(3.0_wp)
                do k = 1, 8
                    th = 2*pi*(k - 1)/8
                    n = n + 1
                    pt(1, n) = r*cos(th)
                    pt(2, n) = r*sin(th)
                    pt(3, n) = (2*pi/8)*r*0.5_wp*(ro - ri)
                end do
            end do
            return
        end if
        select case (qr)
        case (1)
            m = 1; g(1) = 0; w(1) = 2
        case (3)
            m = 3
            g(1:3) = [-sqrt(0.6_wp), 0.0_wp, sqrt(0.6_wp)]
            w(1:3) = [5.0_wp, 8.0_wp, 5.0_wp]/9
        case (4)
            m = 3
            g(1:3) = [-1.0_wp, 0.0_wp, 1.0_wp]
            w(1:3) = [1.0_wp, 4.0_wp, 1.0_wp]/3
        case (5)
            m = 4
            g(1:4) = [-0.8611363115940526_wp, -0.3399810435848563_wp, 0.3399810435848563_wp, 0.8611363115940526_wp]
            w(1:4) = [0.3478548451374538_wp, 0.6521451548625461_wp, 0.6521451548625461_wp, 0.3478548451374538_wp]
        case default
            m = 2
            g(1:2) = [-1.0_wp, 1.0_wp]/sqrt(3.0_wp)
            w(1:2) = 1
        end select
        n = 0
        do j = 1, m
            do i = 1, m
                n = n + 1
                pt(1, n) = 0.5_wp*ts*g(i)
                pt(2, n) = 0.5_wp*tt*g(j)
                pt(3, n) = 0.25_wp*ts*tt*w(i)*w(j)
            end do
        end do
    end subroutine hl_section

    !> One element's step: the section points' stresses sig (3, n: sigma,
    !> tau12, tau13) and plastic strains ep updated over dt from the rates
    !> (see the module's note), and the resultants r = (N, T, M_s, M_t, V_s,
    !> V_t). dv, dw, wm: the nodes' velocity and angular velocity
    !> differences and the mean angular velocity, in the element's frame
    !> (components along e1, e2, e3). plastic: the law pp applies.
    subroutine hl_update(n, pt, l, dv, dw, wm, dt, e, gs, c, plastic, pp, sig, ep, r)
        integer, intent(in) :: n
        real(wp), intent(in) :: pt(3, max_points), l, dv(3), dw(3), wm(3), dt, e, gs, c
        logical, intent(in) :: plastic
        type(plastic_params_t), intent(in) :: pp
        real(wp), intent(inout) :: sig(3, max_points), ep(max_points)
        real(wp), intent(out) :: r(6)
        real(wp) :: y, z, d11, g12, g13, s, t2, t3
        integer :: k
        r = 0
        do k = 1, n
            y = pt(1, k)
            z = pt(2, k)
            d11 = (dv(1) - y*dw(3) + z*dw(2))/l
            g12 = dv(2)/l - wm(3) - c*z*dw(1)/l
            g13 = dv(3)/l + wm(2) + c*y*dw(1)/l
            s = sig(1, k) + e*d11*dt
            t2 = sig(2, k) + gs*g12*dt
            t3 = sig(3, k) + gs*g13*dt
            if (plastic) call hl_return(pp, e, gs, s, t2, t3, ep(k))
            sig(:, k) = [s, t2, t3]
            r(1) = r(1) + pt(3, k)*s
            r(2) = r(2) + c*pt(3, k)*(t3*y - t2*z)
            r(3) = r(3) + pt(3, k)*s*z
            r(4) = r(4) - pt(3, k)*s*y
            r(5) = r(5) + pt(3, k)*t2
            r(6) = r(6) + pt(3, k)*t3
        end do
    end subroutine hl_update

    !> The trial (s, t2, t3) returned to the flow stress at ep + dep where
    !> sqrt(s^2 + 3 t2^2 + 3 t3^2) exceeds it: s = s_tr / (1 + E dep / sy),
    !> t = t_tr / (1 + 3 G dep / sy) with sy = sigma_y(ep + dep), the flow
    !> along the gradient of the equivalent stress in this stress space;
    !> the scalar equation in dep by Newton's method from below (the
    !> function falls monotonically in dep), bisection as its guard.
    subroutine hl_return(pp, e, gs, s, t2, t3, ep)
        type(plastic_params_t), intent(in) :: pp
        real(wp), intent(in) :: e, gs
        real(wp), intent(inout) :: s, t2, t3, ep
        real(wp) :: sy, h, q2, tt, a, b, f, df, dep, lo, hi, sy1, h1
        integer :: it
        call yield_stress(pp, ep, sy, h)
        tt = t2**2 + t3**2
        q2 = s**2 + 3*tt
        if (q2 <= sy**2) return
        lo = 0
        hi = sqrt(q2)/min(e, 3*gs)
        dep = 0
        do it = 1, 60
            call yield_stress(pp, ep + dep, sy1, h1)
            sy1 = max(sy1, tiny(1.0_wp))
            a = 1 + e*dep/sy1
            b = 1 + 3*gs*dep/sy1
            f = s**2/a**2 + 3*tt/b**2 - sy1**2
            if (f > 0.0_wp) then
                lo = dep
            else
                hi = dep
            end if
            if (abs(f) <= 1.0e-12_wp*sy1**2) exit
            ! d/d(dep) of f (sy1 and its slope h1 at the new strain)
            df = -2*s**2/a**3*(e/sy1 - e*dep*h1/sy1**2) - 6*tt/b**3*(3*gs/sy1 - 3*gs*dep*h1/sy1**2) - 2*sy1*h1
            if (df < 0.0_wp) then
                dep = dep - f/df
            else
                dep = 0.5_wp*(lo + hi)
            end if
            if (.not. (dep > lo .and. dep < hi)) dep = 0.5_wp*(lo + hi)
        end do
        call yield_stress(pp, ep + dep, sy1, h1)
        sy1 = max(sy1, tiny(1.0_wp))
        s = s/(1 + e*dep/sy1)
        t2 = t2/(1 + 3*gs*dep/sy1)
        t3 = t3/(1 + 3*gs*dep/sy1)
        ep = ep + dep
    end subroutine hl_return

    !> The resultants (N, T, M_s, M_t, V_s, V_t) as beam_bs's end moments
    !> (N, T, M_s1, M_s2, M_t1, M_t2), whose nodal forces and moments are
    !> the same: M_s1 = -M_s + L V_t / 2, M_s2 = M_s + L V_t / 2, M_t1 = -M_t
    !> - L V_s / 2, M_t2 = M_t - L V_s / 2.
    pure function hl_end_moments(r, l) result(res)
        real(wp), intent(in) :: r(6), l
        real(wp) :: res(6)
        res = [r(1), r(2), -r(3) + 0.5_wp*l*r(6), r(3) + 0.5_wp*l*r(6), -r(4) - 0.5_wp*l*r(5), r(4) - 0.5_wp*l*r(5)]
    end function hl_end_moments

end module xd_elements_beam_hl
