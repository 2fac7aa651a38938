!> Step 4 of the automatic contact, constraint enforcement (section 6 of
!> Whirley & Engelmann 1993), for one slave node in contact: the penalty
!> force (Eq. 12), viscous contact damping (VDC) and Coulomb friction
!> (FS, FD, DC, as LS-DYNA's contact cards define them). The master side
!> takes the opposite force spread by the segment's shape functions (the
!> caller assembles it).
module xd_contact_enforcement
    use xd_kinds, only: wp
    use xd_contact_segment_check, only: hit_t
    implicit none
    private
    public :: friction_t, penalty_force

    !> Card 2 of the contact keyword.
    type :: friction_t
        real(wp) :: fs = 0, fd = 0, dc = 0   !< static, dynamic coefficients; decay (time/length)
        real(wp) :: vdc = 0                  !< viscous damping, % of critical
    end type friction_t

contains

    !> Force on the slave node. k: penalty stiffness; vrel: slave velocity
    !> less the contact point's; meff: the pair's effective mass (for VDC);
    !> dt: the step; ft: the tangential (friction) force, carried from cycle
    !> to cycle (in: last cycle's, out: this cycle's).
    pure subroutine penalty_force(hit, k, vrel, meff, fr, dt, ft, f)
        type(hit_t), intent(in) :: hit
        real(wp), intent(in) :: k, vrel(3), meff, dt
        type(friction_t), intent(in) :: fr
        real(wp), intent(inout) :: ft(3)
        real(wp), intent(out) :: f(3)
        real(wp) :: fn(3), vn, vt(3), c, mu, fmax, fnorm, ftn
        ! Eq. (12): f = K a n, a < 0 in penetration (a positive multiple of
        ! the return direction pushes the slave back)
        fn = -k*hit%a*hit%nhat
        fnorm = abs(k*hit%a)
        vn = dot_product(vrel, hit%nhat)
        if (fr%vdc > 0.0_wp) then
            ! viscous damping VDC % of critical on the normal relative velocity;
            ! it may cancel the normal force but never pull the surfaces together
            c = 0.01_wp*fr%vdc*2.0_wp*sqrt(k*meff)
            fnorm = max(0.0_wp, fnorm - c*vn)
            fn = fnorm*hit%nhat
        end if
        if (fr%fs > 0.0_wp .or. fr%fd > 0.0_wp) then
            ! elastic trial: last cycle's tangential force, turned into the
            ! current tangent plane, plus k times this cycle's slip; then the
            ! Coulomb limit mu |fn| with mu = FD + (FS - FD) exp(-DC |v_t|)
            vt = vrel - vn*hit%nhat
            ftn = dot_product(ft, hit%nhat)
            ft = ft - ftn*hit%nhat
            ft = ft - k*dt*vt
            mu = fr%fd + (fr%fs - fr%fd)*exp(-fr%dc*norm2(vt))
            fmax = mu*fnorm
            if (norm2(ft) > fmax) ft = ft*(fmax/norm2(ft))
        else
            ft = 0
        end if
        f = fn + ft
    end subroutine penalty_force

end module xd_contact_enforcement
