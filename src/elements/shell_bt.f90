!> Belytschko-Tsay shell (ELFORM 2): four nodes with six degrees of freedom,
!> one in-plane point, NIP Gauss points through the thickness, a corotational
!> frame from the element's diagonals, Belytschko-Tsay hourglass control;
!> triangles as quads with N3 = N4 (a third of the mass on each node).
!> Plane stress: elastic, or *MAT_003 / *MAT_024 with the 3-D radial return
!> and the thickness strain rate iterated so that s_zz = 0.
!> Stresses per point (local frame): xx yy xy yz zx.
module xd_elements_shell_bt
    use xd_kinds, only: wp, dp
    use xd_core_memory, only: alloc, alloc_dp
    use xd_model, only: model_t, mat_elastic, mat_plastic_kinematic, mat_piecewise_linear, mat_rigid
    use xd_materials_plasticity, only: plastic_params_t, plastic_update, yield_stress, rate_factor
    implicit none
    private
    public :: shells_t, build_shells, shell_forces, shell_masses, shell_frame, point_weight, point_z

    ! iteration tolerances: 1e-10 and 1e-12 relative in double precision,
    ! ten round-offs in single (where 1e-12 cannot be reached and every
    ! return ran to its iteration limit: the single build's shells took 2.6
    ! times as long)
    real(wp), parameter :: tol10 = max(1.0e-10_wp, 10*epsilon(1.0_wp)), tol12 = max(1.0e-12_wp, 10*epsilon(1.0_wp))

    type :: shells_t
        integer :: n = 0
        integer, allocatable :: conn(:, :)    !< (4, n)
        integer, allocatable :: eid(:), part(:)
        real(wp), allocatable :: h(:)         !< thickness (mean of the nodal values)
        real(wp), allocatable :: e(:), nu(:), ro(:), shrf(:), qm(:)
        integer, allocatable :: nip(:)
        real(wp), allocatable :: sig(:, :, :) !< (5, 10, n) stresses at the points
        real(wp), allocatable :: qhg(:, :)    !< (5, n) hourglass generalized forces
        logical, allocatable :: plastic(:)
        integer, allocatable :: pmat(:)       !< index into pp
        type(plastic_params_t), allocatable :: pp(:)  !< plastic laws of the shell materials
        real(wp), allocatable :: epsp(:, :)   !< (10, n) effective plastic strain per point
        real(wp), allocatable :: alpha(:, :, :)  !< (6, 10, n) back stress per point
        real(dp), allocatable :: eint(:), ehg(:), pend_int(:), pend_hg(:)
        real(wp), allocatable :: area0(:)
        real(wp), allocatable :: fslot(:, :), mslot(:, :)   !< (3, 4n) forces and moments
        real(wp) :: dtmin = 0
        integer :: crit = 0, bad = 0
        logical :: thickness_update = .false.   !< *CONTROL_SHELL ISTUPD
        integer, allocatable :: mine(:)       !< the elements computed here (MPI: this rank's)
        ! mass scaling (*CONTROL_TIMESTEP DT2MS), allocated only when it is on:
        ! an element's mass is msf times its own, so its step sqrt(msf) times
        real(wp), allocatable :: msf(:)       !< mass factor (1: the element's own mass)
        real(wp), allocatable :: msq(:)       !< sqrt(msf); 1 (allocated) without mass scaling
        real(wp), allocatable :: ms_need(:)   !< this cycle's wanted factor (0: none wanted)
        real(wp) :: ms_target = 0             !< element step to be kept (0: no scaling this cycle)
        logical :: ms_all = .false.           !< every element brought to ms_target (positive DT2MS, cycle 0)
    end type shells_t

    ! Gauss points and weights on [-1, 1], NIP 1..10 (rows: nip)
    real(dp), parameter :: gz(10, 10) = reshape([real(dp) :: &
        0.0_dp, 0, 0, 0, 0, 0, 0, 0, 0, 0, &
        -0.5773502691896258_dp, 0.5773502691896258_dp, 0, 0, 0, 0, 0, 0, 0, 0, &
        -0.7745966692414834_dp, 0.0_dp, 0.7745966692414834_dp, 0, 0, 0, 0, 0, 0, 0, &
        -0.8611363115940526_dp, -0.3399810435848563_dp, 0.3399810435848563_dp, 0.8611363115940526_dp, 0, 0, 0, 0, 0, 0, &
        -0.9061798459386640_dp, -0.5384693101056831_dp, 0.0_dp, 0.5384693101056831_dp, 0.9061798459386640_dp, &
        0, 0, 0, 0, 0, &
        -0.9324695142031521_dp, -0.6612093864662645_dp, -0.2386191860831969_dp, 0.2386191860831969_dp, &
        0.6612093864662645_dp, 0.9324695142031521_dp, 0, 0, 0, 0, &
        -0.9491079123427585_dp, -0.7415311855993945_dp, -0.4058451513773972_dp, 0.0_dp, 0.4058451513773972_dp, &
        0.7415311855993945_dp, 0.9491079123427585_dp, 0, 0, 0, &
        -0.9602898564975363_dp, -0.7966664774136267_dp, -0.5255324099163290_dp, -0.1834346424956498_dp, &
        0.1834346424956498_dp, 0.5255324099163290_dp, 0.7966664774136267_dp, 0.9602898564975363_dp, 0, 0, &
        -0.9681602395076261_dp, -0.8360311073266358_dp, -0.6133714327005904_dp, -0.3242534234038089_dp, 0.0_dp, &
        0.3242534234038089_dp, 0.6133714327005904_dp, 0.8360311073266358_dp, 0.9681602395076261_dp, 0, &
        -0.9739065285171717_dp, -0.8650633666889845_dp, -0.6794095682990244_dp, -0.4333953941292472_dp, &
        -0.1488743389816312_dp, 0.1488743389816312_dp, 0.4333953941292472_dp, 0.6794095682990244_dp, &
        0.8650633666889845_dp, 0.9739065285171717_dp], [10, 10])
    real(dp), parameter :: gw(10, 10) = reshape([real(dp) :: &
        2.0_dp, 0, 0, 0, 0, 0, 0, 0, 0, 0, &
        1.0_dp, 1.0_dp, 0, 0, 0, 0, 0, 0, 0, 0, &
        0.5555555555555556_dp, 0.8888888888888888_dp, 0.5555555555555556_dp, 0, 0, 0, 0, 0, 0, 0, &
        0.3478548451374538_dp, 0.6521451548625461_dp, 0.6521451548625461_dp, 0.3478548451374538_dp, 0, 0, 0, 0, 0, 0, &
        0.2369268850561891_dp, 0.4786286704993665_dp, 0.5688888888888889_dp, 0.4786286704993665_dp, &
        0.2369268850561891_dp, 0, 0, 0, 0, 0, &
        0.1713244923791704_dp, 0.3607615730481386_dp, 0.4679139345726910_dp, 0.4679139345726910_dp, &
        0.3607615730481386_dp, 0.1713244923791704_dp, 0, 0, 0, 0, &
        0.1294849661688697_dp, 0.2797053914892766_dp, 0.3818300505051189_dp, 0.4179591836734694_dp, &
        0.3818300505051189_dp, 0.2797053914892766_dp, 0.1294849661688697_dp, 0, 0, 0, &
        0.1012285362903763_dp, 0.2223810344533745_dp, 0.3137066458778873_dp, 0.3626837833783620_dp, &
        0.3626837833783620_dp, 0.3137066458778873_dp, 0.2223810344533745_dp, 0.1012285362903763_dp, 0, 0, &
        0.0812743883615744_dp, 0.1806481606948574_dp, 0.2606106964029354_dp, 0.3123470770400029_dp, &
        0.3302393550012598_dp, 0.3123470770400029_dp, 0.2606106964029354_dp, 0.1806481606948574_dp, &
        0.0812743883615744_dp, 0, &
        0.0666713443086881_dp, 0.1494513491505806_dp, 0.2190863625159820_dp, 0.2692667193099963_dp, &
        0.2955242247147529_dp, 0.2955242247147529_dp, 0.2692667193099963_dp, 0.2190863625159820_dp, &
        0.1494513491505806_dp, 0.0666713443086881_dp], [10, 10])

contains

    subroutine build_shells(model, sh, plastic_law)
        type(model_t), intent(in) :: model
        type(shells_t), intent(out) :: sh
        interface
            subroutine plastic_law(model, mix, pp)
                import :: model_t, plastic_params_t
                type(model_t), intent(in) :: model
                integer, intent(in) :: mix
                type(plastic_params_t), intent(out) :: pp
            end subroutine plastic_law
        end interface
        integer :: e, p, k, mix, ee
        integer, allocatable :: keep(:)
        ! rigid shells are not deformable elements (the rigid bodies take them)
        keep = pack([(e, e=1, model%nshell)], &
                    [(model%mat(model%part(model%shell_part(e))%mat_ix)%mtype /= mat_rigid, e=1, model%nshell)])
        sh%n = size(keep)
        sh%mine = [(e, e=1, sh%n)]
        if (sh%n == 0) return
        sh%thickness_update = model%ctl%istupd /= 0
        allocate (sh%conn(4, sh%n), sh%eid(sh%n), sh%part(sh%n), sh%h(sh%n), sh%e(sh%n), sh%nu(sh%n), &
                  sh%ro(sh%n), sh%shrf(sh%n), sh%qm(sh%n), sh%nip(sh%n), sh%area0(sh%n), sh%msq(sh%n))
        sh%msq = 1
        call alloc(sh%fslot, 3, 4*sh%n, 'shell force slots')
        call alloc(sh%mslot, 3, 4*sh%n, 'shell moment slots')
        call alloc(sh%qhg, 5, sh%n, 'shell hourglass forces')
        call alloc_dp(sh%eint, sh%n, 'shell energies')
        call alloc_dp(sh%ehg, sh%n, 'shell energies')
        call alloc_dp(sh%pend_int, sh%n, 'shell energies')
        call alloc_dp(sh%pend_hg, sh%n, 'shell energies')
        allocate (sh%sig(5, 10, sh%n), sh%plastic(sh%n), sh%pmat(sh%n), sh%pp(model%nmat), &
                  sh%epsp(10, sh%n), sh%alpha(6, 10, sh%n))
        sh%sig = 0
        sh%epsp = 0
        sh%alpha = 0
        do mix = 1, model%nmat
            if (model%mat(mix)%mtype == mat_plastic_kinematic .or. model%mat(mix)%mtype == mat_piecewise_linear) &
                call plastic_law(model, mix, sh%pp(mix))
        end do
        do e = 1, sh%n
            ee = keep(e)
            p = model%shell_part(ee)
            sh%conn(:, e) = model%shell_conn(:, ee)
            sh%eid(e) = model%shell_id(ee)
            sh%part(e) = p
            sh%h(e) = sum(model%shell_t(:, ee))/4
            associate (m => model%mat(model%part(p)%mat_ix), sec => model%sec_shell(model%part(p)%shell_sec_ix))
                sh%e(e) = m%e
                sh%nu(e) = m%pr
                sh%ro(e) = m%ro
                sh%shrf(e) = sec%shrf
                sh%nip(e) = sec%nip
                sh%plastic(e) = m%mtype == mat_plastic_kinematic .or. m%mtype == mat_piecewise_linear
                sh%pmat(e) = model%part(p)%mat_ix
            end associate
            sh%qm(e) = model%ctl%qh
            k = model%part(p)%hg_ix
            if (k > 0) sh%qm(e) = model%hg(k)%qm
        end do
    end subroutine build_shells

    !> Lumped masses: a quarter of rho h A on each node (a third for
    !> triangles); rotational inertia m (h^2 + 3A)/12 about every axis. With
    !> m (h^2 + A)/12 the transverse-shear-rotation coupling of a node,
    !> omega^2 ~ 12 k G / (rho A), lies above the translational limit
    !> (2c/L)^2 and the step from the element size is unstable; scaled to
    !> about m A/4 it lies well below, and rotary inertia hardly matters for
    !> thin shells.
    subroutine shell_masses(sh, x, mass, irot)
        type(shells_t), intent(inout) :: sh
        real(wp), intent(in) :: x(:, :)
        real(wp), intent(inout) :: mass(:), irot(:)
        integer :: e, k, nn
        real(wp) :: a, m
        do e = 1, sh%n
            a = area(x(:, sh%conn(:, e)), sh%conn(:, e))
            sh%area0(e) = a
            nn = 4
            if (sh%conn(3, e) == sh%conn(4, e)) nn = 3
            m = sh%ro(e)*sh%h(e)*a/nn
            do k = 1, nn
                mass(sh%conn(k, e)) = mass(sh%conn(k, e)) + m
                irot(sh%conn(k, e)) = irot(sh%conn(k, e)) + m*(sh%h(e)**2 + 3.0_wp*a)/12.0_wp
            end do
        end do
    end subroutine shell_masses

    pure real(wp) function area(xe, c)
        real(wp), intent(in) :: xe(3, 4)
        integer, intent(in) :: c(4)
        real(wp) :: d1(3), d2(3)
        d1 = xe(:, 3) - xe(:, 1)
        d2 = xe(:, 4) - xe(:, 2)
        if (c(3) == c(4)) d2 = xe(:, 3) - xe(:, 2)
        area = 0.5_wp*norm2([d1(2)*d2(3) - d1(3)*d2(2), d1(3)*d2(1) - d1(1)*d2(3), d1(1)*d2(2) - d1(2)*d2(1)])
    end function area

    !> Forces and moments of every shell at x(n) with v(n-1/2), w(n-1/2).
    !> Threaded over elements: each writes only its own slots and state; the
    !> smallest step and the first bad element are combined by element
    !> number, so the result does not depend on the threads.
    subroutine shell_forces(sh, x, v, w, dt, dt_avg_prev)
        type(shells_t), intent(inout) :: sh
        real(wp), intent(in) :: x(:, :), v(:, :), w(:, :), dt
        real(dp), intent(in) :: dt_avg_prev
        integer :: e, i, tcrit, tbad
        real(wp) :: dte, tmin
        sh%dtmin = huge(1.0_wp)
        sh%crit = 0
        sh%bad = 0
        !$omp parallel default(shared) private(e, i, dte, tmin, tcrit, tbad)
        tmin = huge(1.0_wp)
        tcrit = 0
        tbad = 0
        !$omp do schedule(static)
        do i = 1, size(sh%mine)
            e = sh%mine(i)
            call shell_element(sh, e, x, v, w, dt, dt_avg_prev, dte)
            if (.not. (dte > 0.0_wp)) then
                if (tbad == 0) tbad = e
                cycle
            end if
            ! mass scaling: the step of the element's scaled mass (msq 1
            ! without: the product is exact); one below the target asks for
            ! the factor that brings it there
            dte = dte*sh%msq(e)
            if (dte < sh%ms_target .or. sh%ms_all) call ask_mass(sh, e, dte)
            if (dte < tmin) then
                tmin = dte
                tcrit = e
            end if
        end do
        !$omp end do
        !$omp critical (shell_step)
        if (tbad > 0 .and. (sh%bad == 0 .or. tbad < sh%bad)) sh%bad = tbad
        if (tcrit > 0 .and. (tmin < sh%dtmin .or. (tmin == sh%dtmin .and. tcrit < sh%crit))) then
            sh%dtmin = tmin
            sh%crit = tcrit
        end if
        !$omp end critical (shell_step)
        !$omp end parallel
    end subroutine shell_forces

    !> Mass scaling: the factor that brings element e's step dte (of its
    !> present mass) to the target, which is its step now.
    subroutine ask_mass(sh, e, dte)
        type(shells_t), intent(inout) :: sh
        integer, intent(in) :: e
        real(wp), intent(inout) :: dte
        sh%ms_need(e) = sh%msf(e)*(sh%ms_target/dte)**2
        dte = sh%ms_target
    end subroutine ask_mass

    subroutine shell_element(sh, e, x, v, w, dt, dt_avg_prev, dte)
        type(shells_t), intent(inout) :: sh
        integer, intent(in) :: e
        real(wp), intent(in) :: x(:, :), v(:, :), w(:, :), dt
        real(dp), intent(in) :: dt_avg_prev
        real(wp), intent(out) :: dte
        real(wp), parameter :: hv(4) = [1.0_wp, -1.0_wp, 1.0_wp, -1.0_wp]
        real(wp) :: xe(3, 4), e1(3), e2(3), e3(3), xc(3), xl(4), yl(4), zl(4), a, b1(4), b2(4), vl(3, 4), wl(3, 4)
        real(wp) :: dx, dy, dxy, kx, ky, kxy, gxz, gyz, qe, ge, z, dd(5), s(5), sold(5)
        real(wp) :: nres(3), mres(3), qres(2), f(3, 4), m(3, 4), gam(4), qd(5), bb, c, ls, hh, wx, wy, gamz
        real(wp) :: dzz, dzz_mean, am, b1m(4), b2m(4)
        real(dp) :: pold, pnew
        integer :: k, ip, nip, nn
        logical :: ok
        real(wp), parameter :: quarter = 0.25_wp
        nn = 4
        if (sh%conn(3, e) == sh%conn(4, e)) nn = 3
        ! The rates v(n-1/2) are taken on the mid-step geometry x(n-1/2) =
        ! x(n) - dt/2 v(n-1/2), the forces on x(n). (Rates on x(n) see a
        ! rigid turn of theta per step as a membrane strain of order
        ! theta^2, always of one sign: a clamped elastic plate vibrating at a
        ! few degrees gained 22% energy in 200 us and one at ten degrees blew
        ! up; on the mid-step geometry 0.1%.)
        do k = 1, 4
            xe(:, k) = x(:, sh%conn(k, e)) - 0.5_wp*dt*v(:, sh%conn(k, e))
        end do
        call local_geometry(ok)
        if (.not. ok) then
            dte = -1
            return
        end if
        do k = 1, 4
            vl(:, k) = [dot_product(v(:, sh%conn(k, e)), e1), dot_product(v(:, sh%conn(k, e)), e2), &
                        dot_product(v(:, sh%conn(k, e)), e3)]
            wl(:, k) = [dot_product(w(:, sh%conn(k, e)), e1), dot_product(w(:, sh%conn(k, e)), e2), &
                        dot_product(w(:, sh%conn(k, e)), e3)]
        end do
        ! membrane, bending and transverse shear rates (BT 1984)
        dx = sum(b1*vl(1, :))
        dy = sum(b2*vl(2, :))
        dxy = sum(b2*vl(1, :) + b1*vl(2, :))
        kx = sum(b1*wl(2, :))
        ky = -sum(b2*wl(1, :))
        kxy = sum(b2*wl(2, :) - b1*wl(1, :))
        gxz = sum(b1*vl(3, :)) + quarter*sum(wl(2, :))
        gyz = sum(b2*vl(3, :)) - quarter*sum(wl(1, :))
        ! plane stress elastic update at the points, resultants
        hh = sh%h(e)
        qe = sh%e(e)/(1 - sh%nu(e)**2)
        ge = sh%e(e)/(2*(1 + sh%nu(e)))
        nip = sh%nip(e)
        nres = 0; mres = 0; qres = 0
        pold = 0; pnew = 0
        dzz_mean = 0
        do ip = 1, nip
            z = real(gz(ip, nip), wp)*hh/2
            dd = [dx + z*kx, dy + z*ky, dxy + z*kxy, gyz, gxz]     ! engineering shears
            sold = sh%sig(:, ip, e)
            s = sold
            if (sh%plastic(e)) then
                call plane_stress_plastic(sh, e, ip, dd, dt, s, dzz)
                dzz_mean = dzz_mean + real(gw(ip, nip), wp)/2*dzz
            else
                dzz_mean = dzz_mean - real(gw(ip, nip), wp)/2*sh%nu(e)/(1 - sh%nu(e))*(dd(1) + dd(2))
                s(1) = s(1) + dt*qe*(dd(1) + sh%nu(e)*dd(2))
                s(2) = s(2) + dt*qe*(dd(2) + sh%nu(e)*dd(1))
                s(3) = s(3) + dt*ge*dd(3)
                s(4) = s(4) + dt*sh%shrf(e)*ge*dd(4)
                s(5) = s(5) + dt*sh%shrf(e)*ge*dd(5)
            end if
            sh%sig(:, ip, e) = s
            ! powers per unit area with the old and the new stresses
            pold = pold + real(gw(ip, nip), dp)*hh/2*dot_product(real(sold, dp), real(dd, dp))
            pnew = pnew + real(gw(ip, nip), dp)*hh/2*dot_product(real(s, dp), real(dd, dp))
            nres = nres + real(gw(ip, nip), wp)*hh/2*s(1:3)
            mres = mres + real(gw(ip, nip), wp)*hh/2*z*s(1:3)
            qres = qres + real(gw(ip, nip), wp)*hh/2*[s(5), s(4)]
        end do
        ! thickness change (ISTUPD): the mean thickness strain rate of the points
        if (sh%thickness_update) sh%h(e) = sh%h(e)*exp(dt*dzz_mean)
        ! internal energy: the rule of the solids (work f(n).(v- + v+)/2 dt_avg)
        sh%eint(e) = sh%eint(e) + dt_avg_prev*(sh%pend_int(e) + 0.5_dp*pold*a)
        sh%pend_int(e) = 0.5_dp*pnew*a
        ! the hourglass rates on the mid-step geometry too
        gam = hourglass_gamma()
        wx = sum(b2*vl(3, :))
        wy = -sum(b1*vl(3, :))
        qd = [dot_product(gam, wl(1, :)), dot_product(gam, wl(2, :)), dot_product(gam, vl(3, :)), &
              dot_product(gam, vl(1, :) - wy*zl), dot_product(gam, vl(2, :) + wx*zl)]
        am = a
        b1m = b1
        b2m = b2
        ! the forces: on x(n)
        do k = 1, 4
            xe(:, k) = x(:, sh%conn(k, e))
        end do
        call local_geometry(ok)
        if (.not. ok) then
            dte = -1
            return
        end if
        ! nodal forces and moments (local): minus the derivatives of the power
        do k = 1, 4
            f(1, k) = -a*(b1(k)*nres(1) + b2(k)*nres(3))
            f(2, k) = -a*(b2(k)*nres(2) + b1(k)*nres(3))
            f(3, k) = -a*(b1(k)*qres(1) + b2(k)*qres(2))
            m(1, k) = -a*(-b2(k)*mres(2) - b1(k)*mres(3) - quarter*qres(2))
            m(2, k) = -a*(b1(k)*mres(1) + b2(k)*mres(3) + quarter*qres(1))
            m(3, k) = 0
        end do
        ! Belytschko-Tsay hourglass: gamma = h - (h.x) b1 - (h.y) b2; stiffness
        ! form on the out-of-plane rotations and displacement and the membrane
        ! membrane rates of a warped element (nodes zl off its mean plane) less
        ! the rigid spin about the in-plane axes (wx = dvz/dy, wy = -dvz/dx):
        ! that spin moves the warped nodes in-plane by (wy zl, -wx zl), an
        ! hourglass pattern, and without this correction a warped element
        ! turning as a rigid body strained its membrane hourglass springs (a
        ! warped patch spinning free stored 1.4% of its kinetic energy in
        ! them; the tube crush's mean force was 49.1 kN, now 41.5 kN)
        bb = sum(b1m**2 + b2m**2)
        c = sh%qm(e)
        pold = dot_product(real(sh%qhg(:, e), dp), real(qd, dp))
        sh%qhg(1:2, e) = sh%qhg(1:2, e) + dt*c*sh%e(e)*hh**3*am/192*bb*qd(1:2)
        sh%qhg(3, e) = sh%qhg(3, e) + dt*c*sh%shrf(e)*ge*hh**3/12*bb*qd(3)
        sh%qhg(4:5, e) = sh%qhg(4:5, e) + dt*c*sh%e(e)*hh*am/8*bb*qd(4:5)
        pnew = dot_product(real(sh%qhg(:, e), dp), real(qd, dp))
        sh%ehg(e) = sh%ehg(e) + dt_avg_prev*(sh%pend_hg(e) + 0.5_dp*pold)
        sh%pend_hg(e) = 0.5_dp*pnew
        gam = hourglass_gamma()
        gamz = dot_product(gam, zl)
        do k = 1, 4
            m(1, k) = m(1, k) - gam(k)*sh%qhg(1, e)
            m(2, k) = m(2, k) - gam(k)*sh%qhg(2, e)
            f(3, k) = f(3, k) - gam(k)*sh%qhg(3, e)
            f(1, k) = f(1, k) - gam(k)*sh%qhg(4, e)
            f(2, k) = f(2, k) - gam(k)*sh%qhg(5, e)
            ! the warping correction's share (the rates' dependence on vz
            ! through the spin): the forces stay work-conjugate to the rates
            ! and in equilibrium
            f(3, k) = f(3, k) - gamz*(b1(k)*sh%qhg(4, e) + b2(k)*sh%qhg(5, e))
        end do
        ! to global, into the element's slots (a triangle's fourth node is its third)
        do k = 1, 4
            sh%fslot(:, 4*(e - 1) + k) = f(1, k)*e1 + f(2, k)*e2 + f(3, k)*e3
            sh%mslot(:, 4*(e - 1) + k) = m(1, k)*e1 + m(2, k)*e2 + m(3, k)*e3
        end do
        ! time step: area over the longest side, plate wave speed
        ls = 0
        do k = 1, 4
            ls = max(ls, norm2(xe(:, mod(k, 4) + 1) - xe(:, k)))
        end do
        dte = a/ls/sqrt(sh%e(e)/(sh%ro(e)*(1 - sh%nu(e)**2)))
    contains
        !> The element's frame, local coordinates, area and derivatives on xe.
        subroutine local_geometry(good)
            logical, intent(out) :: good
            call shell_frame(xe, nn == 3, e1, e2, e3, good)
            if (.not. good) return
            xc = sum(xe, 2)/4
            do k = 1, 4
                xl(k) = dot_product(xe(:, k) - xc, e1)
                yl(k) = dot_product(xe(:, k) - xc, e2)
                zl(k) = dot_product(xe(:, k) - xc, e3)
            end do
            a = 0.5_wp*((xl(3) - xl(1))*(yl(4) - yl(2)) + (xl(2) - xl(4))*(yl(3) - yl(1)))
            good = a > 0.0_wp
            if (.not. good) return
            b1 = [yl(2) - yl(4), yl(3) - yl(1), yl(4) - yl(2), yl(1) - yl(3)]/(2*a)
            b2 = [xl(4) - xl(2), xl(1) - xl(3), xl(2) - xl(4), xl(3) - xl(1)]/(2*a)
        end subroutine local_geometry

        !> The hourglass shape vector gamma = h - (h.x) b1 - (h.y) b2 of the
        !> geometry local_geometry last took.
        function hourglass_gamma() result(g)
            real(wp) :: g(4)
            g = hv - dot_product(hv, xl)*b1 - dot_product(hv, yl)*b2
        end function hourglass_gamma
    end subroutine shell_element

    !> Plane stress plasticity at one point: the 3-D radial return with the
    !> thickness strain rate d_zz found by secant iteration so that s_zz = 0
    !> (starting from the elastic and the incompressible guesses). dd holds
    !> the in-plane rates and the engineering shears (xx yy xy yz zx).
    subroutine plane_stress_plastic(sh, e, ip, dd, dt, s, dzz)
        type(shells_t), intent(inout) :: sh
        integer, intent(in) :: e, ip
        real(wp), intent(in) :: dd(5), dt
        real(wp), intent(inout) :: s(5)
        real(wp), intent(out) :: dzz               !< the thickness strain rate found
        real(wp) :: lam, mu, d(1, 6), sg(1, 6), ep(1), al(1, 6), z0, z1, f0, f1, z2
        real(wp) :: qe, st(6), xeq, sy, h, t1, t2, t4, t5, t6, pm
        integer :: it
        dzz = -sh%nu(e)/(1 - sh%nu(e))*(dd(1) + dd(2))
        if (dt <= 0.0_wp) return
        mu = sh%e(e)/(2*(1 + sh%nu(e)))
        lam = sh%e(e)*sh%nu(e)/((1 + sh%nu(e))*(1 - 2*sh%nu(e)))
        z0 = -sh%nu(e)/(1 - sh%nu(e))*(dd(1) + dd(2))
        ! the elastic plane-stress trial (s_zz stays 0 with d_zz = z0): inside
        ! the yield surface, the 3-D return below would change nothing, so
        ! the point is done (most points of a crash model, most of the time)
        qe = sh%e(e)/(1 - sh%nu(e)**2)
        t1 = s(1) + dt*qe*(dd(1) + sh%nu(e)*dd(2))
        t2 = s(2) + dt*qe*(dd(2) + sh%nu(e)*dd(1))
        t4 = s(3) + dt*mu*dd(3)
        t5 = s(4) + dt*mu*dd(4)
        t6 = s(5) + dt*mu*dd(5)
        ! the von Mises value of dev(trial) - alpha, from scalars (an array
        ! built here and read back as a vector stalled the store forwarding)
        pm = (t1 + t2)/3.0_wp
        xeq = sqrt(1.5_wp*((t1 - pm - sh%alpha(1, ip, e))**2 + (t2 - pm - sh%alpha(2, ip, e))**2 + &
                           (pm + sh%alpha(3, ip, e))**2 + 2.0_wp*((t4 - sh%alpha(4, ip, e))**2 + &
                           (t5 - sh%alpha(5, ip, e))**2 + (t6 - sh%alpha(6, ip, e))**2)))
        st = [t1, t2, 0.0_wp, t4, t5, t6]
        call yield_stress(sh%pp(sh%pmat(e)), sh%epsp(ip, e), sy, h)
        if (xeq <= rate_factor(sh%pp(sh%pmat(e)), [dd(1), dd(2), z0, 0.5_wp*dd(3), 0.5_wp*dd(4), 0.5_wp*dd(5)])*sy) then
            s = [st(1), st(2), st(4), st(5), st(6)]
            return
        end if
        if (sh%pp(sh%pmat(e))%ncurve > 0 .or. sh%pp(sh%pmat(e))%beta >= 1.0_wp) then
            ! isotropic hardening: the plane-stress return in closed form
            call plane_stress_return(sh%e(e), sh%nu(e), sh%pp(sh%pmat(e)), &
                                     rate_factor(sh%pp(sh%pmat(e)), [dd(1), dd(2), z0, 0.5_wp*dd(3), 0.5_wp*dd(4), &
                                                                     0.5_wp*dd(5)]), &
                                     [st(1), st(2), st(4), st(5), st(6)], s, sh%epsp(ip, e), dzz)
            dzz = dzz/dt
            return
        end if
        ! mixed hardening: the 3-D radial return, d_zz iterated so that s_zz = 0
        z1 = -(dd(1) + dd(2))
        f0 = szz(z0)
        if (abs(f0) <= tol10*max(maxval(abs(s)), 1.0_wp)) then
            call commit(z0)
            return
        end if
        f1 = szz(z1)
        do it = 1, 20
            if (abs(f1 - f0) <= tiny(1.0_wp)) exit
            z2 = z1 - f1*(z1 - z0)/(f1 - f0)
            z0 = z1; f0 = f1
            z1 = z2
            f1 = szz(z1)
            if (abs(f1) <= tol10*max(maxval(abs(sg)), 1.0_wp)) exit
        end do
        call commit(z1)
    contains
        real(wp) function szz(dz)
            real(wp), intent(in) :: dz
            call trial(dz)
            szz = sg(1, 3)
        end function szz
        subroutine trial(dz)
            real(wp), intent(in) :: dz
            d(1, :) = [dd(1), dd(2), dz, 0.5_wp*dd(3), 0.5_wp*dd(4), 0.5_wp*dd(5)]
            sg(1, :) = [s(1), s(2), 0.0_wp, s(3), s(4), s(5)]
            ep(1) = sh%epsp(ip, e)
            al(1, :) = sh%alpha(:, ip, e)
            call plastic_update(1, lam, mu, sh%pp(sh%pmat(e)), d, dt, sg, ep, al)
        end subroutine trial
        subroutine commit(dz)
            real(wp), intent(in) :: dz
            dzz = dz
            call trial(dz)
            s = [sg(1, 1), sg(1, 2), sg(1, 4), sg(1, 5), sg(1, 6)]
            sh%epsp(ip, e) = ep(1)
            sh%alpha(:, ip, e) = al(1, :)
        end subroutine commit
    end subroutine plane_stress_plastic

    !> Plane-stress J2 return with isotropic hardening (Simo & Taylor 1986):
    !> from the elastic trial st (xx yy xy yz zx) to the stress s on the yield
    !> surface fac x sy(epsp). In the eigenbasis of the plane-stress
    !> projection P the backward-Euler return scales each mode by a closed
    !> form of the plastic multiplier dg: the equal-biaxial mode by
    !> 1/(1 + E dg/(3(1 - nu))), the shear modes (in-plane and transverse) by
    !> 1/(1 + 2 G dg); dg solves 1/2 phi^2 = 1/3 (fac sy(epsp + de))^2 with
    !> phi^2 = xi.P.xi and de = sqrt(2/3) dg phi (Newton on one scalar). The
    !> same state as the 3-D radial return with s_zz = 0 imposed, at a
    !> fraction of the cost. dezz: the thickness strain increment (elastic
    !> and plastic). s on entry: the stress before the step.
    pure subroutine plane_stress_return(ym, nu, pp, fac, st, s, epsp, dezz)
        real(wp), intent(in) :: ym, nu, fac, st(5)
        type(plastic_params_t), intent(in) :: pp
        real(wp), intent(inout) :: s(5), epsp
        real(wp), intent(out) :: dezz
        real(wp), parameter :: r2 = sqrt(2.0_wp), c23 = sqrt(2.0_wp/3.0_wp)
        real(wp) :: a1, a2, c1, c2, q1, rr, dg, u1, u2, phi2, phi, dphi2, dphi, de, sy, h, f, fp, sold
        integer :: it
        c1 = ym/(3.0_wp*(1.0_wp - nu))
        c2 = ym/(1.0_wp + nu)
        a1 = (st(1) + st(2))/r2
        a2 = (st(2) - st(1))/r2
        q1 = a1*a1/3.0_wp
        rr = a2*a2 + 2.0_wp*(st(3)**2 + st(4)**2 + st(5)**2)
        sold = s(1) + s(2)
        dg = 0
        do it = 1, 40
            u1 = 1.0_wp/(1.0_wp + c1*dg)
            u2 = 1.0_wp/(1.0_wp + c2*dg)
            phi2 = q1*u1*u1 + rr*u2*u2
            phi = sqrt(phi2)
            de = c23*dg*phi
            call yield_stress(pp, epsp + de, sy, h)
            f = 0.5_wp*phi2 - (fac*sy)**2/3.0_wp
            if (abs(f) <= tol12*phi2) exit
            dphi2 = -2.0_wp*(q1*c1*u1**3 + rr*c2*u2**3)
            dphi = dphi2/(2.0_wp*phi)
            fp = 0.5_wp*dphi2 - 2.0_wp/3.0_wp*fac*sy*fac*h*c23*(phi + dg*dphi)
            if (fp >= 0.0_wp) exit
            dg = max(dg - f/fp, 0.5_wp*dg)
        end do
        a1 = a1*u1
        a2 = a2*u2
        s(1) = (a1 - a2)/r2
        s(2) = (a1 + a2)/r2
        s(3:5) = st(3:5)*u2
        epsp = epsp + de
        ! thickness: elastic -nu/E (the in-plane stress sum's change) and
        ! plastic -(de_xx + de_yy) = -dg (s_xx + s_yy)/3 (incompressible)
        dezz = -nu/ym*(s(1) + s(2) - sold) - dg*(s(1) + s(2))/3.0_wp
    end subroutine plane_stress_return

    !> The corotational frame of a shell with nodes xe (triangle: N4 = N3):
    !> normal from the diagonals (a triangle's sides), x along side 1-2.
    !> ok false for a collapsed element.
    pure subroutine shell_frame(xe, tri, e1, e2, e3, ok)
        real(wp), intent(in) :: xe(3, 4)
        logical, intent(in) :: tri
        real(wp), intent(out) :: e1(3), e2(3), e3(3)
        logical, intent(out) :: ok
        real(wp) :: n3
        if (tri) then
            e3 = cross(xe(:, 2) - xe(:, 1), xe(:, 3) - xe(:, 1))
        else
            e3 = cross(xe(:, 3) - xe(:, 1), xe(:, 4) - xe(:, 2))
        end if
        ! lengths as sqrt(x.x): norm2's overflow-safe scaling costs much
        ! more, and coordinates are far from overflow
        n3 = sqrt(e3(1)**2 + e3(2)**2 + e3(3)**2)
        ok = n3 > 0.0_wp
        e1 = 0
        e2 = 0
        if (.not. ok) return
        e3 = e3/n3
        e1 = xe(:, 2) - xe(:, 1)
        e1 = e1 - (e1(1)*e3(1) + e1(2)*e3(2) + e1(3)*e3(3))*e3
        e1 = e1/sqrt(e1(1)**2 + e1(2)**2 + e1(3)**2)
        e2 = cross(e3, e1)
    end subroutine shell_frame

    !> (The shell keeps its own copy of the cross product: the same formula
    !> as xd_core_vectors's, but taking that one changes the compiled
    !> arithmetic of the frame in round-off, which car6's chaotic crush
    !> amplifies: node 605 ended at -520.2 mm instead of -519.9.)
    pure function cross(a, b) result(c)
        real(wp), intent(in) :: a(3), b(3)
        real(wp) :: c(3)
        c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
    end function cross

    !> Weight of integration point ip of nip through the thickness (the
    !> weights sum to 1).
    pure real(wp) function point_weight(ip, nip) result(w)
        integer, intent(in) :: ip, nip
        w = real(gw(ip, nip), wp)/2
    end function point_weight

    !> Position of integration point ip of nip through the thickness, from -1
    !> (the bottom surface) to 1 (the top).
    pure real(wp) function point_z(ip, nip) result(z)
        integer, intent(in) :: ip, nip
        z = real(gz(ip, nip), wp)
    end function point_z


end module xd_elements_shell_bt
