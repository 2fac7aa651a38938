!> Beams: the Belytschko-Schwer resultant beam (*SECTION_BEAM ELFORM 2, and
!> the spot welds of ELFORM 9), elastic; and the Hughes-Liu beam (ELFORM 1,
!> xd_elements_beam_hl: one stress point along the length and a quadrature
!> of the section, elastic or *MAT_003 / *MAT_024 plastic with their
!> hardening), which shares the frame, the masses and the nodal forces
!> below (its resultants as end moments). A spot weld (*MAT_SPOTWELD with SIGY > 0, ELFORM 9 or 1) returns to the
!> same surface at its present yield stress sigma_y = SIGY + EH eps_p and
!> hardens: the plastic work of the return, R . C^-1 (R_trial - R) with C
!> the elastic stiffness of the resultants, over sigma_y A L is the
!> increment of eps_p (a bar's plastic strain exactly in tension); the weld
!> fails where eps_p reaches EFAIL.
!>
!> Co-rotational: each cycle the local frame is e1 along the chord N1 -> N2,
!> e2 (the section's s axis, from the orientation node N3 at t = 0) kept
!> normal to e1 by the least rotation and turned about e1 by the nodes' mean
!> spin, e3 = e1 x e2. The resultants (axial force N, torque T, end moments
!> about s and t) are updated from the deformation rates in that frame:
!>
!>   N += E A (v2 - v1).e1 / L dt,  T += G J (w2 - w1).e1 / L dt,
!>   [M1; M2] += E I / L [4 2; 2 4] [r1; r2] dt   (about s with ISS, t with ITT)
!>
!> with r_i the node's rotation rate relative to the chord's, w_i - e1 x (v2 -
!> v1) / L (Euler-Bernoulli bending). The nodal forces and moments are the
!> virtual work's: f1 = N e1 - S, f2 = -N e1 + S with S = (M1 + M2) x e1 / L,
!> m1 = -M1 + T e1, m2 = -M2 - T e1.
!>
!> Masses: (rho A + NSM) L / 2 at each node; rotary inertia rho L max(A L^2/24
!> + I/2, 1.5 I) (I the larger of ISS and ITT): the element's rotations then
!> are no faster than its axial mode. Step: the smaller of L / c and 2 / w of
!> the transverse (shear) mode, w^2 = 48 E I / (rho A L^4), which governs short
!> beams.
!>
!> Every rank computes every beam (they are few beside shells) and adds
!> their forces after the element forces are shared: the sum is the serial
!> run's on every rank.
module xd_elements_beam_bs
    use xd_kinds, only: wp, dp
    use xd_model, only: model_t, mat_spotweld, mat_plastic_kinematic, mat_piecewise_linear
    use xd_core_vectors, only: cross
    use xd_materials_plasticity, only: plastic_params_t
    use xd_elements_beam_hl, only: hl_section, hl_update, hl_end_moments, max_points
    use xd_elements_solid_groups, only: material_plastic_law
    implicit none
    private
    public :: beams_t, build_beams, beam_masses, beam_forces

    type :: beams_t
        integer :: n = 0
        integer, allocatable :: conn(:, :)    !< (2, n)
        integer, allocatable :: eid(:), part(:)
        real(wp), allocatable :: e(:), g(:), ro(:), a(:), iss(:), itt(:), j(:), nsm(:)
        real(wp), allocatable :: e2(:, :)     !< (3, n) the section's s axis
        real(wp), allocatable :: res(:, :)    !< (6, n) N, T, M_s at N1 and N2, M_t at N1 and N2
        real(dp), allocatable :: eint(:)      !< internal energy
        ! node -> beam-end incidences (CSR), for the sums in node order
        integer, allocatable :: ptr(:), inc(:)
        real(wp), allocatable :: fe(:, :), me(:, :)   !< (3, 2n) forces and moments at the ends
        real(wp) :: dtmin = huge(1.0_wp)
        integer :: crit = 0
        ! spot welds (*MAT_SPOTWELD): failure by time or resultants
        logical, allocatable :: weld(:), dead(:)
        real(wp), allocatable :: tfail(:), rfail(:, :)   !< (n), (6, n): NRR NRS NRT MRR MSS MTT (0: unused)
        integer, allocatable :: newly(:)      !< the welds that failed this cycle
        ! plastic beams (ELFORM 1 with *MAT_003 / *MAT_024, spot welds with
        ! SIGY): the fully plastic resultants N_p, T_p, M_ps, M_pt per unit
        ! yield stress, the yield stress now (0: elastic), the plastic
        ! hardening modulus, the plastic strain and the one at failure (0:
        ! none)
        real(wp), allocatable :: rpu(:, :)    !< (4, n)
        real(wp), allocatable :: sy(:), eh(:), epsp(:), efail(:)
        ! Hughes-Liu (ELFORM 1): its section's points (y, z, weight), their
        ! stresses (sigma, tau12, tau13) and plastic strains, the shear
        ! modulus SHRF G, the twist's factor sqrt(J / Ip), the law (0:
        ! elastic) among pps
        logical, allocatable :: hl(:)
        integer, allocatable :: hln(:), hlaw(:)
        real(wp), allocatable :: hlpt(:, :, :), hlsig(:, :, :), hlep(:, :), hlgs(:), hlc(:)
        type(plastic_params_t), allocatable :: pps(:)
    end type beams_t

contains

    subroutine build_beams(model, bm)
        type(model_t), intent(in) :: model
        type(beams_t), intent(out) :: bm
        integer, allocatable :: law_of(:)
        real(wp) :: ip
        integer :: e, p, k, nd
        integer, allocatable :: fill(:)
        real(wp) :: e1(3), v(3), s(3)
        bm%n = model%nbeam
        if (bm%n == 0) return
        allocate (bm%conn(2, bm%n), bm%eid(bm%n), bm%part(bm%n), bm%e(bm%n), bm%g(bm%n), bm%ro(bm%n), &
                  bm%a(bm%n), bm%iss(bm%n), bm%itt(bm%n), bm%j(bm%n), bm%nsm(bm%n), bm%e2(3, bm%n), &
                  bm%res(6, bm%n), bm%eint(bm%n), bm%fe(3, 2*bm%n), bm%me(3, 2*bm%n), bm%weld(bm%n), &
                  bm%dead(bm%n), bm%tfail(bm%n), bm%rfail(6, bm%n), bm%newly(0), bm%rpu(4, bm%n), bm%sy(bm%n), &
                  bm%eh(bm%n), bm%epsp(bm%n), bm%efail(bm%n))
        bm%rpu = 0
        bm%sy = 0
        bm%eh = 0
        bm%epsp = 0
        bm%efail = 0
        allocate (bm%hl(bm%n), bm%hln(bm%n), bm%hlaw(bm%n), bm%hlpt(3, max_points, bm%n), &
                  bm%hlsig(3, max_points, bm%n), bm%hlep(max_points, bm%n), bm%hlgs(bm%n), bm%hlc(bm%n), &
                  law_of(model%nmat), bm%pps(0))
        bm%hl = .false.
        bm%hln = 0
        bm%hlaw = 0
        bm%hlpt = 0
        bm%hlsig = 0
        bm%hlep = 0
        bm%hlgs = 0
        bm%hlc = 1
        law_of = 0
        bm%dead = .false.
        bm%res = 0
        bm%eint = 0
        do e = 1, bm%n
            p = model%beam_part(e)
            bm%conn(:, e) = model%beam_conn(1:2, e)
            bm%eid(e) = model%beam_id(e)
            bm%part(e) = p
            associate (m => model%mat(model%part(p)%mat_ix), sc => model%sec_beam(model%part(p)%beam_sec_ix))
                bm%e(e) = m%e
                bm%g(e) = m%e/(2*(1 + m%pr))
                bm%ro(e) = m%ro
                bm%a(e) = sc%a
                bm%iss(e) = sc%iss
                bm%itt(e) = sc%itt
                bm%j(e) = sc%j
                bm%nsm(e) = sc%nsm
                bm%weld(e) = m%mtype == mat_spotweld
                ! Hughes-Liu: the section's points, and a plastic material's
                ! law (one per material)
                if (sc%elform == 1 .and. m%mtype /= mat_spotweld) then
                    bm%hl(e) = .true.
                    call hl_section(sc%cst, sc%qr, sc%ts, sc%tt, bm%hln(e), bm%hlpt(:, :, e))
                    bm%hlgs(e) = sc%shrf*bm%g(e)
                    ip = sum(bm%hlpt(3, 1:bm%hln(e), e)*(bm%hlpt(1, 1:bm%hln(e), e)**2 + &
                                                         bm%hlpt(2, 1:bm%hln(e), e)**2))
                    if (ip > 0.0_wp) bm%hlc(e) = sqrt(min(sc%j/ip, 1.0_wp))
                    if (m%mtype == mat_plastic_kinematic .or. m%mtype == mat_piecewise_linear) then
                        if (law_of(model%part(p)%mat_ix) == 0) then
                            bm%pps = [bm%pps, plastic_params_t()]
                            call material_plastic_law(model, model%part(p)%mat_ix, bm%pps(size(bm%pps)))
                            ! (isotropic hardening in the beams: BETA's
                            ! kinematic share and the rate factor are
                            ! warned at input)
                            bm%pps(size(bm%pps))%beta = 1
                            bm%pps(size(bm%pps))%c = 0
                            law_of(model%part(p)%mat_ix) = size(bm%pps)
                        end if
                        bm%hlaw(e) = law_of(model%part(p)%mat_ix)
                    end if
                end if
                ! a spot weld with SIGY, on a section with its dimensions
                ! (ELFORM 2's has none: it stays elastic, d3hsp says so)
                if (m%mtype == mat_spotweld .and. m%sigy > 0.0_wp .and. sc%elform /= 2) then
                    bm%sy(e) = m%sigy
                    bm%eh(e) = m%eh
                    bm%efail(e) = m%efail
                end if
                if (bm%sy(e) > 0.0_wp) bm%rpu(:, e) = [sc%a, sc%zj/sqrt(3.0_wp), sc%zs, sc%zt]
                bm%tfail(e) = m%tfail
                bm%rfail(:, e) = m%rfail
            end associate
            ! s: toward the orientation node, normal to the axis (without one,
            ! the normal to the axis nearest the global axis it is least along)
            e1 = model%x0(:, bm%conn(2, e)) - model%x0(:, bm%conn(1, e))
            e1 = e1/norm2(e1)
            if (model%beam_conn(3, e) > 0) then
                v = model%x0(:, model%beam_conn(3, e)) - model%x0(:, bm%conn(1, e))
            else
                v = 0
                v(minloc(abs(e1), 1)) = 1
            end if
            s = v - dot_product(v, e1)*e1
            bm%e2(:, e) = s/norm2(s)
        end do
        ! node -> ends
        allocate (bm%ptr(model%nnode + 1), fill(model%nnode))
        bm%ptr = 0
        do e = 1, bm%n
            do k = 1, 2
                bm%ptr(bm%conn(k, e) + 1) = bm%ptr(bm%conn(k, e) + 1) + 1
            end do
        end do
        bm%ptr(1) = 1
        do nd = 1, model%nnode
            bm%ptr(nd + 1) = bm%ptr(nd + 1) + bm%ptr(nd)
        end do
        allocate (bm%inc(2*bm%n))
        fill = bm%ptr(1:model%nnode)
        do e = 1, bm%n
            do k = 1, 2
                nd = bm%conn(k, e)
                bm%inc(fill(nd)) = 2*(e - 1) + k
                fill(nd) = fill(nd) + 1
            end do
        end do
    end subroutine build_beams

    !> Lumped masses and rotary inertia (see the module's note).
    subroutine beam_masses(bm, x, mass, irot)
        type(beams_t), intent(in) :: bm
        real(wp), intent(in) :: x(:, :)
        real(wp), intent(inout) :: mass(:), irot(:)
        integer :: e, k
        real(wp) :: l, m, j
        do e = 1, bm%n
            l = norm2(x(:, bm%conn(2, e)) - x(:, bm%conn(1, e)))
            call node_inertia(bm, e, l, m, j)
            do k = 1, 2
                mass(bm%conn(k, e)) = mass(bm%conn(k, e)) + m
                irot(bm%conn(k, e)) = irot(bm%conn(k, e)) + j
            end do
        end do
    end subroutine beam_masses

    !> Beam e's lumped mass and rotary inertia at each of its nodes at
    !> length l (see the module's note).
    pure subroutine node_inertia(bm, e, l, m, j)
        type(beams_t), intent(in) :: bm
        integer, intent(in) :: e
        real(wp), intent(in) :: l
        real(wp), intent(out) :: m, j
        real(wp) :: imax
        m = (bm%ro(e)*bm%a(e) + bm%nsm(e))*l/2
        imax = max(bm%iss(e), bm%itt(e))
        j = bm%ro(e)*l*max(bm%a(e)*l**2/24 + imax/2, 1.5_wp*imax)
    end subroutine node_inertia

    !> The beams' forces and moments at x(n) from v(n-1/2), w(n-1/2), added to
    !> f and mom in node order (mom set, not added, where `set_mom`: no
    !> shell wrote it this cycle); the smallest stable step.
    subroutine beam_forces(bm, x, v, w, dt, time, f, mom, set_mom)
        type(beams_t), intent(inout) :: bm
        real(wp), intent(in) :: x(:, :), v(:, :), w(:, :), dt
        real(dp), intent(in) :: time
        real(wp), intent(inout) :: f(:, :), mom(:, :)
        logical, intent(in) :: set_mom
        integer :: e, n1, n2, nd, q, k
        real(wp) :: l, e1(3), e2(3), e3(3), dv(3), wc(3), t1(3), t2(3), r(6), old(6), phi, c, s, ei, m1(3), m2(3), sh(3)
        real(wp) :: dte, ro, imax, wm(3), dwv(3), rh(6), dvl(3), dwl(3), wml(3)
        type(plastic_params_t) :: none
        bm%dtmin = huge(1.0_wp)
        bm%crit = 0
        if (size(bm%newly) > 0) deallocate (bm%newly)
        if (.not. allocated(bm%newly)) allocate (bm%newly(0))
        do e = 1, bm%n
            if (bm%dead(e)) then
                bm%fe(:, 2*e - 1:2*e) = 0
                bm%me(:, 2*e - 1:2*e) = 0
                cycle
            end if
            n1 = bm%conn(1, e)
            n2 = bm%conn(2, e)
            e1 = x(:, n2) - x(:, n1)
            l = norm2(e1)
            e1 = e1/l
            ! the s axis: kept normal to the chord, turned by the mean spin
            e2 = bm%e2(:, e) - dot_product(bm%e2(:, e), e1)*e1
            e2 = e2/norm2(e2)
            phi = 0.5_wp*dot_product(w(:, n1) + w(:, n2), e1)*dt
            c = cos(phi)
            s = sin(phi)
            e2 = c*e2 + s*cross(e1, e2)
            bm%e2(:, e) = e2
            e3 = cross(e1, e2)
            ! rates: elongation, twist, the ends' rotations against the chord's
            dv = v(:, n2) - v(:, n1)
            wc = cross(e1, dv)/l
            t1 = w(:, n1) - wc
            t2 = w(:, n2) - wc
            r = [dot_product(dv, e1), dot_product(w(:, n2) - w(:, n1), e1), &
                 dot_product(t1, e2), dot_product(t2, e2), dot_product(t1, e3), dot_product(t2, e3)]
            old = bm%res(:, e)
            if (bm%hl(e)) then
                ! Hughes-Liu: the section points' stresses, their resultants
                ! as end moments
                wm = 0.5_wp*(w(:, n1) + w(:, n2))
                dwv = w(:, n2) - w(:, n1)
                dvl = [dot_product(dv, e1), dot_product(dv, e2), dot_product(dv, e3)]
                dwl = [dot_product(dwv, e1), dot_product(dwv, e2), dot_product(dwv, e3)]
                wml = [dot_product(wm, e1), dot_product(wm, e2), dot_product(wm, e3)]
                if (bm%hlaw(e) > 0) then
                    call hl_update(bm%hln(e), bm%hlpt(:, :, e), l, dvl, dwl, wml, dt, bm%e(e), bm%hlgs(e), bm%hlc(e), &
                                   .true., bm%pps(bm%hlaw(e)), bm%hlsig(:, :, e), bm%hlep(:, e), rh)
                else
                    call hl_update(bm%hln(e), bm%hlpt(:, :, e), l, dvl, dwl, wml, dt, bm%e(e), bm%hlgs(e), bm%hlc(e), &
                                   .false., none, bm%hlsig(:, :, e), bm%hlep(:, e), rh)
                end if
                bm%res(:, e) = hl_end_moments(rh, l)
            else
                bm%res(1, e) = old(1) + bm%e(e)*bm%a(e)*r(1)/l*dt
                bm%res(2, e) = old(2) + bm%g(e)*bm%j(e)*r(2)/l*dt
                ei = bm%e(e)*bm%iss(e)/l
                bm%res(3, e) = old(3) + ei*(4*r(3) + 2*r(4))*dt
                bm%res(4, e) = old(4) + ei*(2*r(3) + 4*r(4))*dt
                ei = bm%e(e)*bm%itt(e)/l
                bm%res(5, e) = old(5) + ei*(4*r(5) + 2*r(6))*dt
                bm%res(6, e) = old(6) + ei*(2*r(5) + 4*r(6))*dt
            end if
            ! plastic: each end's (N, T, M_s, M_t) returned radially to the
            ! fully plastic surface (N/N_p)^2 + (T/T_p)^2 + (M_s/M_ps)^2 +
            ! (M_t/M_pt)^2 = 1; N and T, shared by the ends, take the larger
            ! reduction
            if (bm%sy(e) > 0.0_wp) call plastic_return(e)
            ! the work over the step, at the mean of the resultants before
            ! and after it
            bm%eint(e) = bm%eint(e) + 0.5_dp*dt*dot_product(real(old + bm%res(:, e), dp), real(r, dp))
            ! a spot weld fails at TFAIL, or on its resultants: sum (R_i /
            ! R_iF)^2 >= 1 over the axial force in tension, the shears along s
            ! and t (the end moments' sum over L), the torque and the larger
            ! end moments about s and t; it carries nothing from then on
            if (bm%weld(e)) then
                if (weld_fails(e, l)) then
                    bm%dead(e) = .true.
                    bm%newly = [bm%newly, e]
                    bm%fe(:, 2*e - 1:2*e) = 0
                    bm%me(:, 2*e - 1:2*e) = 0
                    cycle
                end if
            end if
            ! forces and moments on the nodes
            m1 = bm%res(3, e)*e2 + bm%res(5, e)*e3
            m2 = bm%res(4, e)*e2 + bm%res(6, e)*e3
            sh = cross(m1 + m2, e1)/l
            bm%fe(:, 2*e - 1) = bm%res(1, e)*e1 - sh
            bm%fe(:, 2*e) = -bm%res(1, e)*e1 + sh
            bm%me(:, 2*e - 1) = -m1 + bm%res(2, e)*e1
            bm%me(:, 2*e) = -m2 - bm%res(2, e)*e1
            ! the step: the axial mode, and the transverse one of a short beam
            ro = bm%ro(e) + bm%nsm(e)/bm%a(e)
            imax = max(bm%iss(e), bm%itt(e))
            dte = min(l/sqrt(bm%e(e)/ro), 2/sqrt(48*bm%e(e)*imax/(ro*bm%a(e)*l**4)))
            if (bm%hl(e)) dte = min(dte, hl_step(e, l))
            if (dte < bm%dtmin) then
                bm%dtmin = dte
                bm%crit = e
            end if
        end do
        ! the sums at the nodes, ends in element order
        do nd = 1, size(bm%ptr) - 1
            if (bm%ptr(nd + 1) == bm%ptr(nd)) cycle
            if (set_mom) mom(:, nd) = 0
            do q = bm%ptr(nd), bm%ptr(nd + 1) - 1
                k = bm%inc(q)
                f(:, nd) = f(:, nd) + bm%fe(:, k)
                mom(:, nd) = mom(:, nd) + bm%me(:, k)
            end do
        end do
    contains
        !> Hughes-Liu beam e's stable step, 2 / omega with omega^2 bounded
        !> by Gershgorin's rows of M^-1/2 K M^-1/2 over its modes in each
        !> plane (the nodes' lumped mass m and rotary inertia j, as
        !> beam_masses gives them): the transverse rows 2 G A_s / (L m) + G
        !> A_s / sqrt(m j), the rotation rows (E I / L + G A_s L / 4 + |G A_s
        !> L / 4 - E I / L|) / j + G A_s / sqrt(m j); the axial 2 E A / (L m)
        !> and the twist's 2 G J / (L j)
        real(wp) function hl_step(e, l) result(dts)
            integer, intent(in) :: e
            real(wp), intent(in) :: l
            real(wp) :: m, j, gas, om2, ii
            integer :: q
            call node_inertia(bm, e, l, m, j)
            gas = bm%hlgs(e)*bm%a(e)
            om2 = max(2*bm%e(e)*bm%a(e)/(l*m), 2*bm%g(e)*bm%j(e)/(l*j))
            do q = 1, 2
                ii = merge(bm%iss(e), bm%itt(e), q == 1)
                om2 = max(om2, 2*gas/(l*m) + gas/sqrt(m*j), &
                          (bm%e(e)*ii/l + gas*l/4 + abs(gas*l/4 - bm%e(e)*ii/l))/j + gas/sqrt(m*j))
            end do
            dts = 2/sqrt(om2)
        end function hl_step

        subroutine plastic_return(e)
            integer, intent(in) :: e
            real(wp) :: f1, f2, c1, c2, p(4), tr(6), dr(6), dq(6), ei, dep
            real(dp) :: wpl
            p = bm%sy(e)*bm%rpu(:, e)
            associate (r => bm%res(:, e))
                f1 = (r(1)/p(1))**2 + (r(2)/p(2))**2 + (r(3)/p(3))**2 + (r(5)/p(4))**2
                f2 = (r(1)/p(1))**2 + (r(2)/p(2))**2 + (r(4)/p(3))**2 + (r(6)/p(4))**2
                if (max(f1, f2) <= 1.0_wp) return
                tr = r
                c1 = 1/sqrt(max(f1, 1.0_wp))
                c2 = 1/sqrt(max(f2, 1.0_wp))
                r(1) = r(1)*min(c1, c2)
                r(2) = r(2)*min(c1, c2)
                r(3) = r(3)*c1
                r(5) = r(5)*c1
                r(4) = r(4)*c2
                r(6) = r(6)*c2
                if (.not. bm%weld(e)) return
                ! hardening (spot welds): the plastic deformations C^-1
                ! (trial - returned), the end moments' stiffness E I / L [4 2;
                ! 2 4] inverted as L / (12 E I) [4 -2; -2 4]; their work over
                ! sigma_y A L is eps_p's increment, and sigma_y = SIGY + EH
                ! eps_p for the next step
                dr = tr - r
                dq(1) = dr(1)*l/(bm%e(e)*bm%a(e))
                dq(2) = dr(2)*l/(bm%g(e)*bm%j(e))
                ei = bm%e(e)*bm%iss(e)
                dq(3:4) = l/(12*ei)*[4*dr(3) - 2*dr(4), 4*dr(4) - 2*dr(3)]
                ei = bm%e(e)*bm%itt(e)
                dq(5:6) = l/(12*ei)*[4*dr(5) - 2*dr(6), 4*dr(6) - 2*dr(5)]
                wpl = dot_product(real(r, dp), real(dq, dp))
            end associate
            dep = real(max(wpl, 0.0_dp)/(real(bm%sy(e), dp)*bm%a(e)*l), wp)
            bm%epsp(e) = bm%epsp(e) + dep
            bm%sy(e) = bm%sy(e) + bm%eh(e)*dep
        end subroutine plastic_return

        logical function weld_fails(e, l)
            integer, intent(in) :: e
            real(wp), intent(in) :: l
            real(wp) :: r(6), c
            integer :: k
            weld_fails = bm%tfail(e) > 0.0_wp .and. time >= bm%tfail(e)
            if (weld_fails) return
            weld_fails = bm%efail(e) > 0.0_wp .and. bm%epsp(e) >= bm%efail(e)
            if (weld_fails) return
            r = [max(bm%res(1, e), 0.0_wp), abs(bm%res(5, e) + bm%res(6, e))/l, abs(bm%res(3, e) + bm%res(4, e))/l, &
                 abs(bm%res(2, e)), max(abs(bm%res(3, e)), abs(bm%res(4, e))), max(abs(bm%res(5, e)), abs(bm%res(6, e)))]
            c = 0
            do k = 1, 6
                if (bm%rfail(k, e) > 0.0_wp) c = c + (r(k)/bm%rfail(k, e))**2
            end do
            weld_fails = c >= 1.0_wp .and. any(bm%rfail(:, e) > 0.0_wp)
        end function weld_fails
    end subroutine beam_forces

end module xd_elements_beam_bs
