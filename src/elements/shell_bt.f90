!> Belytschko-Tsay shell (ELFORM 2): four nodes with six degrees of freedom,
!> one in-plane point, NIP Gauss points through the thickness, a corotational
!> frame from the element's diagonals, Belytschko-Tsay hourglass control;
!> triangles as quads with N3 = N4 (a third of the mass on each node).
!> Plane stress: elastic, or *MAT_003 / *MAT_024 with the 3-D radial return
!> and the thickness strain rate iterated so that s_zz = 0.
!> Stresses per point (local frame): xx yy xy yz zx.
module xd_elements_shell_bt
    use xd_kinds, only: wp, dp, i8
    use xd_core_memory, only: alloc, alloc_dp, nbytes, take
    use xd_core_strings, only: itoa
    use xd_model, only: model_t, mat_elastic, mat_plastic_kinematic, mat_piecewise_linear, mat_rigid, hg_bounded, can_erode
    use xd_materials_plasticity, only: plastic_params_t, plastic_update, yield_stress, rate_factor
    !$ use omp_lib, only: omp_get_max_threads
    implicit none
    private
    public :: shells_t, build_shells, shell_state_init, shell_state_bytes, shell_bytes, &
              shell_forces, shell_masses, shell_axes, shell_blocks, shell_rows, shell_row, &
              point_weight, point_z
    public :: shell_name, some_backstress

    ! iteration tolerances: 1e-10 and 1e-12 relative in double precision,
    ! ten round-offs in single (where 1e-12 cannot be reached and every
    ! return ran to its iteration limit: the single build's shells took 2.6
    ! times as long)
    real(wp), parameter :: tol10 = max(1.0e-10_wp, 10*epsilon(1.0_wp)), tol12 = max(1.0e-12_wp, 10*epsilon(1.0_wp))
    !> the plane-stress returns' constants (as products: a quotient is a
    !> division instruction even by a constant)
    real(wp), parameter :: rr2 = 1.0_wp/sqrt(2.0_wp), c23 = sqrt(2.0_wp/3.0_wp), third = 1.0_wp/3.0_wp
    !> the yield stress of a shell that is not plastic (its yield never
    !> reached): large beyond any stress, with a square that is still a
    !> number (the elastic test compares the trial's von Mises value,
    !> squared, with it squared; huge(1.0) squared overflowed there, which
    !> a build trapping floating-point exceptions stopped on)
    real(wp), parameter :: no_yield = sqrt(huge(1.0_wp))/4

    !> The constants a shell takes from its part: one entry per part of the
    !> model (its part index, shells_t's part(e); the entries of parts
    !> without deformable shells unused). Every shell had held its own
    !> copy, 156 bytes a shell that each element-cycle read again (issue
    !> 32: memory; issue 29: the plate's loads).
    type :: shell_part_consts_t
        real(wp), allocatable :: e(:), nu(:), ro(:), shrf(:)
        !> the moduli's combinations: G = E / 2(1 + nu), E / (1 - nu^2),
        !> nu / (1 - nu), and the plate wave speed sqrt(E / rho (1 - nu^2))
        real(wp), allocatable :: ge(:), qe(:), nuf(:), wsp(:)
        !> the plane-stress return's: the equal-biaxial mode's modulus E /
        !> 3(1 - nu) (the shear modes' is 2 G), and -nu / E (its thickness
        !> strain)
        real(wp), allocatable :: cbi(:), nue(:)
        !> hourglass coefficients: membrane (QM), bending (QB), warping (QW);
        !> viscous form (IHQ 1-3) or stiffness form (IHQ 4-5)
        real(wp), allocatable :: qm(:), qb(:), qw(:)
        logical, allocatable :: hg_viscous(:)
        !> *CONTROL_XDYNA_SHELL HGBOUND 1 (the default): the stiffness form of
        !> a plastic shell bounded (block_forces)
        logical, allocatable :: hg_bound(:)
        integer, allocatable :: nip(:)
        integer, allocatable :: mix(:)        !< material index (into pp)
        logical, allocatable :: plastic(:)
        !> the plastic law for the points' loops (pp's fields one gather
        !> away): the bilinear law's sigy and beta ep (ycurve false), a
        !> curve's (true); no_yield and 0 where the part is not plastic (its
        !> yield never reached); rated: Cowper-Symonds scales the yield
        real(wp), allocatable :: sy0(:), hk(:)
        logical, allocatable :: ycurve(:), rated(:)
        !> the material can move a back stress (kinematic share of a
        !> hardening modulus not 0); otherwise alpha stays 0 and is not read
        logical, allocatable :: backstress(:)
    end type shell_part_consts_t

    type :: shells_t
        integer :: n = 0
        integer, allocatable :: conn(:, :)    !< (4, n)
        integer, allocatable :: eid(:), part(:)
        real(wp), allocatable :: h(:)         !< thickness (mean of the nodal values)
        !> the constants of the shells' parts (section, material, hourglass
        !> card), read through part(e)
        type(shell_part_consts_t) :: pc
        !> per row of this rank's shells (lix, below): the cycles the
        !> hourglass bound acted on the shell, this run
        integer, allocatable :: ncap(:)
        !> (n, 5, nip) stresses at the points (nip: the most of any shell);
        !> the element index first, as every per-point array here: a block's
        !> loads and stores of one component are runs of memory (vector
        !> moves), not gathers and scattered stores at a stride of 5 nip
        real(wp), allocatable :: sig(:, :, :)
        real(wp), allocatable :: qhg(:, :)    !< (nl, 5) hourglass generalized forces
        type(plastic_params_t), allocatable :: pp(:)  !< plastic laws of the shell materials
        real(wp), allocatable :: epsp(:, :)   !< (n, nip) effective plastic strain per point
        !> (n, 6, nip) the points' logarithmic strains (xx yy zz xy yz zx,
        !> tensor shears) in the shell's frame, their rates integrated: kept
        !> where a shell's material has a *MAT_ADD_EROSION strain criterion
        !> (else size 0)
        logical :: track_strain = .false.
        real(wp), allocatable :: strain(:, :, :)
        real(wp), allocatable :: alpha(:, :, :)  !< (6, nip, n) back stress per point (n 0: no shell has one)
        real(dp), allocatable :: eint(:), ehg(:), pend_int(:), pend_hg(:)
        real(wp), allocatable :: area0(:)
        !> (3, 4n) forces and moments, slot 4 (e - 1) + k of shell e's node k;
        !> with the state held locally (MPI), (3, 4 nl + nhalo): the rank's
        !> shells' slots in their rows' order, 4 (lix(e) - 1) + k, then the
        !> halo's received from the other ranks (domain's local_slots)
        real(wp), allocatable :: fslot(:, :), mslot(:, :)
        real(wp) :: dtmin = 0
        integer :: crit = 0, bad = 0
        logical :: thickness_update = .false.   !< *CONTROL_SHELL ISTUPD
        integer :: isdo = 0                     !< *CONTROL_TIMESTEP ISDO: the step's length
        integer, allocatable :: mine(:)       !< the elements computed here (MPI: this rank's; eroded ones left out)
        !> The points' state (sig, epsp, strain, alpha, qhg) is held for this
        !> rank's shells alone (issue 32), in their own numbering: nl of
        !> them, shell e's row lix(e) (0: another rank's), row i shell
        !> gix(i), in ascending order, so that a block of consecutive shells
        !> has consecutive rows (shell_state_init). One rank: every shell,
        !> lix(e) = e. A writer that needs every shell's state takes a
        !> gathered copy for the time of the output (the domain's
        !> shell_state_view).
        integer :: nl = 0
        integer :: nipmax = 1                 !< the points a row holds: the most any shell has
        !> the per-shell thickness, area and energies (h, area0, eint, ehg,
        !> pend_int, pend_hg) held by row too, for this rank's shells alone
        !> (shell_rows: with owned nodes on more than one rank, once the
        !> set-up is done); else by the model's number. The connectivity,
        !> ids, parts and flags stay every shell's
        logical :: by_row = .false.
        integer, allocatable :: lix(:), gix(:)
        !> during such a view (rank 0): the rank's own rows, kept aside
        logical :: viewing = .false.
        real(wp), allocatable :: own_sig(:, :, :), own_epsp(:, :), own_qhg(:, :), own_strain(:, :, :), &
                                 own_alpha(:, :, :)
        !> (and with by_row, the per-shell arrays' own rows)
        real(wp), allocatable :: own_h(:), own_area0(:)
        real(dp), allocatable :: own_eint(:), own_ehg(:), own_pend_int(:), own_pend_hg(:)
        !> the element loop's blocks: runs of consecutive elements of mine,
        !> at most nblk each (shell_blocks, whenever mine changes), so that
        !> a block's element data are read at unit stride
        integer, allocatable :: bfirst(:), bcount(:)
        !> per block: some shell moves a back stress, takes a yield curve,
        !> a rate factor; every shell is plastic (shell_blocks: tested once,
        !> not per block and cycle)
        logical, allocatable :: bback(:), bcurve(:), brated(:), bplastic(:)
        !> the blocks' parts, one a thread (shell_blocks): blocks pfirst(p)
        !> .. plast(p), runs of mine of nearly equal length. A node whose
        !> shells all lie in one part is that part's (direct(k, e): node k
        !> of shell e is), and its thread adds their forces to it directly;
        !> the others, `shared`, take theirs through the slots
        integer, allocatable :: pfirst(:), plast(:), shared(:)
        logical, allocatable :: direct(:, :)   !< (4, nl): by row (lix)
        !> MPI (set by the domain; unallocated on one rank): per node, 0
        !> when no other rank's element touches it, 1 when others do and
        !> this rank assembles it, 2 when another rank assembles it. Such a
        !> node takes its forces through the slots (the halo's slots go to
        !> its rank, and its sum waits for them); `shared` holds only the
        !> nodes this rank assembles, and all of those with split 1
        integer, allocatable :: split(:)
        ! failure and erosion
        integer, allocatable :: model_ix(:)   !< index in the model's shell list
        logical, allocatable :: dead(:)       !< eroded
        logical :: erodible = .false.         !< some shell's material has a failure criterion
        !> ERODE 1: an element step (before TSSFAC) below this marks the
        !> shell to erode (0: off, until the first step is known)
        real(wp) :: tsmin = 0
        logical, allocatable :: low(:)        !< (nl) by row: marked this cycle, step below tsmin, or inverted
        integer :: ndead = 0
        ! mass scaling (*CONTROL_TIMESTEP DT2MS), allocated only when it is on:
        ! an element's mass is msf times its own, so its step sqrt(msf) times
        real(wp), allocatable :: msf(:)       !< mass factor (1: the element's own mass)
        real(wp), allocatable :: msq(:)       !< sqrt(msf)
        real(wp), allocatable :: ms_need(:)   !< this cycle's wanted factor (0: none wanted)
        real(wp) :: ms_target = 0             !< element step to be kept (0: no scaling this cycle)
        logical :: ms_all = .false.           !< every element brought to ms_target (positive DT2MS, cycle 0)
    end type shells_t

    !> Shells per block of the element loop. The geometry of a whole block
    !> (frames, local coordinates, derivatives) is taken in loops over its
    !> elements before their forces: each element's frame is a chain of
    !> square roots and divisions that waits on itself, and the chains of a
    !> block's elements are independent, so the processor overlaps them
    !> (one element at a time, the frame alone took a fifth of car6's run).
    !> 64 a block (measured, whole runs, one thread: against 16, car6's
    !> first 60 ms 4% and the 100,000-shell plate 15% faster; 32 as 64 on
    !> car6, 128 1% slower there): the loops' vector bodies run longer
    !> between their set-ups, and the block's arrays still fit the caches.
    integer, parameter :: nblk = 64

    !> The geometry of a block of shells on one set of coordinates: the
    !> nodes, the corotational frame (e3 normal, e1 along side 1-2), the
    !> local coordinates about the centre, the area and the derivatives
    !> b1 = dN/dx, b2 = dN/dy; ok false for a collapsed or inverted element.
    type :: block_geom_t
        real(wp) :: xe(nblk, 3, 4)
        real(wp) :: e1(nblk, 3), e2(nblk, 3), e3(nblk, 3)
        real(wp) :: xl(nblk, 4), yl(nblk, 4), zl(nblk, 4)
        real(wp) :: a(nblk), b1(nblk, 4), b2(nblk, 4)
        real(wp) :: gam(nblk, 4)   !< hourglass shape vector h - (h.x) b1 - (h.y) b2
        !> 1 for a triangle (nodes 3 and 4 the same), 0 for a
        !> quadrilateral: the blocks' loops pick by it without a branch
        real(wp) :: tw(nblk)
        logical :: ok(nblk)
    end type block_geom_t

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
        integer :: e, p, mix, ee
        integer, allocatable :: keep(:)
        ! rigid shells are not deformable elements (the rigid bodies take them)
        keep = pack([(e, e=1, model%nshell)], &
                    [(model%mat(model%part(model%shell_part(e))%mat_ix)%mtype /= mat_rigid, e=1, model%nshell)])
        sh%n = size(keep)
        sh%mine = [(e, e=1, sh%n)]
        if (sh%n == 0) then
            ! (empty, so that the outputs of the rigid shells alone can
            ! concatenate them)
            allocate (sh%conn(4, 0), sh%eid(0), sh%part(0), sh%model_ix(0))
            call shell_blocks(sh)
            return
        end if
        sh%thickness_update = model%ctl%istupd /= 0
        sh%isdo = model%ctl%isdo
        allocate (sh%conn(4, sh%n), sh%eid(sh%n), sh%part(sh%n), sh%h(sh%n), sh%area0(sh%n), &
                  sh%model_ix(sh%n), sh%dead(sh%n))
        sh%dead = .false.
        call alloc_dp(sh%eint, sh%n, 'shell energies')
        call alloc_dp(sh%ehg, sh%n, 'shell energies')
        call alloc_dp(sh%pend_int, sh%n, 'shell energies')
        call alloc_dp(sh%pend_hg, sh%n, 'shell energies')
        allocate (sh%pp(model%nmat))
        do mix = 1, model%nmat
            if (model%mat(mix)%mtype == mat_plastic_kinematic .or. model%mat(mix)%mtype == mat_piecewise_linear) &
                call plastic_law(model, mix, sh%pp(mix))
        end do
        do e = 1, sh%n
            ee = keep(e)
            sh%conn(:, e) = model%shell_conn(:, ee)
            sh%eid(e) = model%shell_id(ee)
            sh%model_ix(e) = ee
            sh%part(e) = model%shell_part(ee)
            sh%h(e) = sum(model%shell_t(:, ee))/4
        end do
        call part_constants(model, sh)
        do e = 1, sh%n
            sh%erodible = sh%erodible .or. can_erode(model, sh%pc%mix(sh%part(e)))
        end do
        call shell_blocks(sh)
        ! the points' state, as many per shell as the most any shell has
        ! (NIP 2 in two columns, not five), and the slots: allocated for
        ! the shells of this rank alone once the run is split
        ! (shell_state_init); the strains where a criterion reads them
        sh%nipmax = 1
        do e = 1, sh%n
            p = sh%part(e)
            sh%nipmax = max(sh%nipmax, sh%pc%nip(p))
            associate (m => model%mat(sh%pc%mix(p)))
                sh%track_strain = sh%track_strain .or. (m%erosion .and. (m%mneps < 0.0_wp .or. m%mxeps > 0.0_wp .or. &
                                                       m%effeps > 0.0_wp .or. m%voleps /= 0.0_wp .or. m%epssh > 0.0_wp))
            end associate
        end do
    end subroutine build_shells

    !> The constants of the parts that have deformable shells (sh%pc, by
    !> part index): section, material and hourglass card; the other
    !> parts' entries 0 (false), never read.
    subroutine part_constants(model, sh)
        type(model_t), intent(in) :: model
        type(shells_t), intent(inout) :: sh
        integer :: np, p, e, k
        logical, allocatable :: has(:)
        np = size(model%part)
        allocate (has(np))
        has = .false.
        do e = 1, sh%n
            has(sh%part(e)) = .true.
        end do
        associate (c => sh%pc)
            allocate (c%e(np), c%nu(np), c%ro(np), c%shrf(np), c%ge(np), c%qe(np), c%nuf(np), c%wsp(np), &
                      c%cbi(np), c%nue(np), c%qm(np), c%qb(np), c%qw(np), c%hg_viscous(np), c%hg_bound(np), &
                      c%nip(np), c%mix(np), c%plastic(np), c%sy0(np), c%hk(np), c%ycurve(np), c%rated(np), &
                      c%backstress(np))
            c%e = 0; c%nu = 0; c%ro = 0; c%shrf = 0; c%ge = 0; c%qe = 0; c%nuf = 0; c%wsp = 0
            c%cbi = 0; c%nue = 0; c%qm = 0; c%qb = 0; c%qw = 0; c%hg_viscous = .false.; c%hg_bound = .false.
            c%nip = 0; c%mix = 0; c%plastic = .false.; c%sy0 = no_yield; c%hk = 0
            c%ycurve = .false.; c%rated = .false.; c%backstress = .false.
            do p = 1, np
                if (.not. has(p)) cycle
                c%mix(p) = model%part(p)%mat_ix
                associate (m => model%mat(model%part(p)%mat_ix), sec => model%sec_shell(model%part(p)%shell_sec_ix))
                    c%e(p) = m%e
                    c%nu(p) = m%pr
                    c%ro(p) = m%ro
                    c%shrf(p) = sec%shrf
                    c%nip(p) = sec%nip
                    c%plastic(p) = m%mtype == mat_plastic_kinematic .or. m%mtype == mat_piecewise_linear
                end associate
                if (c%plastic(p)) then
                    associate (pp => sh%pp(c%mix(p)))
                        c%sy0(p) = pp%sigy
                        c%hk(p) = pp%beta*pp%ep
                        c%ycurve(p) = pp%ncurve /= 0
                        c%rated(p) = pp%c > 0.0_wp .and. pp%p > 0.0_wp
                        c%backstress(p) = pp%ncurve == 0 .and. pp%beta < 1.0_wp .and. pp%ep /= 0.0_wp
                    end associate
                end if
                ! *CONTROL_HOURGLASS, then the part's *HOURGLASS (QB and QW
                ! default to its QM; QH stands for all three)
                c%qm(p) = model%ctl%qh
                c%qb(p) = model%ctl%qh
                c%qw(p) = model%ctl%qh
                c%hg_viscous(p) = model%ctl%ihq <= 3
                k = model%part(p)%hg_ix
                if (k > 0) then
                    c%qm(p) = model%hg(k)%qm
                    c%qb(p) = model%hg(k)%qb
                    c%qw(p) = model%hg(k)%qw
                    if (model%hg(k)%ihq > 0) c%hg_viscous(p) = model%hg(k)%ihq <= 3
                end if
                c%hg_bound(p) = hg_bounded(model, p)
                c%ge(p) = c%e(p)/(2*(1 + c%nu(p)))
                c%qe(p) = c%e(p)/(1 - c%nu(p)**2)
                c%nuf(p) = c%nu(p)/(1 - c%nu(p))
                c%wsp(p) = sqrt(c%e(p)/(c%ro(p)*(1 - c%nu(p)**2)))
                c%cbi(p) = c%e(p)/(3*(1 - c%nu(p)))
                c%nue(p) = -c%nu(p)/c%e(p)
            end do
        end associate
    end subroutine part_constants

    !> The points' state (sig, epsp, strain, alpha, qhg, zero) and the
    !> force and moment slots, allocated for the shells `own` (ascending;
    !> one rank: every shell) and `nhalo` slots received from other ranks
    !> after theirs: their rows in that order (issue 32: a rank holds its
    !> own shells' alone, from the start, so that the set-up's peak does
    !> not hold every shell's). Once, before a restart's dump is read into
    !> the rows.
    subroutine shell_state_init(sh, own, nhalo)
        type(shells_t), intent(inout) :: sh
        integer, intent(in) :: own(:), nhalo
        integer :: i, nip
        if (allocated(sh%sig)) error stop 'shell_state_init: the state is there already'
        do i = 2, size(own)
            if (own(i) <= own(i - 1)) error stop 'shell_state_init: own not ascending'
        end do
        sh%nl = size(own)
        sh%gix = own
        allocate (sh%lix(sh%n))
        sh%lix = 0
        do i = 1, sh%nl
            sh%lix(own(i)) = i
        end do
        nip = sh%nipmax
        allocate (sh%sig(sh%nl, 5, nip), sh%epsp(sh%nl, nip))
        sh%sig = 0
        sh%epsp = 0
        ! back stresses only where a material moves them
        allocate (sh%alpha(6, nip, merge(sh%nl, 0, some_backstress(sh))))
        sh%alpha = 0
        allocate (sh%strain(merge(sh%nl, 0, sh%track_strain), 6, nip))
        sh%strain = 0
        call alloc(sh%qhg, sh%nl, 5, 'shell hourglass forces')
        call alloc(sh%fslot, 3, 4*sh%nl + nhalo, 'shell force slots')
        call alloc(sh%mslot, 3, 4*sh%nl + nhalo, 'shell moment slots')
        ! the element loop's per-shell flags and counts, by row too
        allocate (sh%ncap(sh%nl), sh%low(sh%nl))
        sh%ncap = 0
        sh%low = .false.
        call shell_blocks(sh)
    end subroutine shell_state_init

    !> The per-shell thickness, area and energies cut to this rank's rows
    !> (issue 32: 48 of the 96 bytes a shell that every rank held for every
    !> shell), in the rows' order (ascending shells: a rank's sums over its
    !> rows take its shells in the model's order, as before). Once, after
    !> the set-up (restart dump included) and the energies' tables; an
    !> output's view (the domain's shell_state_view) gathers them whole.
    subroutine shell_rows(sh)
        type(shells_t), intent(inout) :: sh
        if (sh%by_row .or. sh%n == 0) return
        call take(sh%h, sh%gix)
        call take(sh%area0, sh%gix)
        call take(sh%eint, sh%gix)
        call take(sh%ehg, sh%gix)
        call take(sh%pend_int, sh%gix)
        call take(sh%pend_hg, sh%gix)
        sh%by_row = .true.
    end subroutine shell_rows

    !> Where shell e's thickness, area and energies are held: its row
    !> (shell_rows; 0 for another rank's shell), or e.
    pure integer function shell_row(sh, e) result(r)
        type(shells_t), intent(in) :: sh
        integer, intent(in) :: e
        r = e
        if (sh%by_row) r = sh%lix(e)
    end function shell_row

    !> The bytes of every array of the shells this rank holds (their
    !> state and slots, shell_state_bytes, and the rest: connectivity,
    !> energies, blocks, flags; the parts' constants), outside an output's
    !> gathered view.
    integer(i8) function shell_bytes(sh) result(b)
        type(shells_t), intent(in) :: sh
        b = nbytes(sh%conn) + nbytes(sh%eid) + nbytes(sh%part) + nbytes(sh%h) &
            + nbytes(sh%ncap) + nbytes(sh%sig) + nbytes(sh%qhg) + nbytes(sh%epsp) + nbytes(sh%strain) &
            + nbytes(sh%alpha) + nbytes(sh%eint) + nbytes(sh%ehg) + nbytes(sh%pend_int) + nbytes(sh%pend_hg) &
            + nbytes(sh%area0) + nbytes(sh%fslot) + nbytes(sh%mslot) + nbytes(sh%mine) + nbytes(sh%lix) &
            + nbytes(sh%gix) + nbytes(sh%bfirst) + nbytes(sh%bcount) + nbytes(sh%bback) + nbytes(sh%bcurve) &
            + nbytes(sh%brated) + nbytes(sh%bplastic) + nbytes(sh%pfirst) + nbytes(sh%plast) + nbytes(sh%shared) &
            + nbytes(sh%direct) + nbytes(sh%split) + nbytes(sh%model_ix) + nbytes(sh%dead) + nbytes(sh%low) &
            + nbytes(sh%msf) + nbytes(sh%msq) + nbytes(sh%ms_need) + nbytes(sh%pc%e) + nbytes(sh%pc%nu) &
            + nbytes(sh%pc%ro) + nbytes(sh%pc%shrf) + nbytes(sh%pc%ge) + nbytes(sh%pc%qe) + nbytes(sh%pc%nuf) &
            + nbytes(sh%pc%wsp) + nbytes(sh%pc%cbi) + nbytes(sh%pc%nue) + nbytes(sh%pc%qm) + nbytes(sh%pc%qb) &
            + nbytes(sh%pc%qw) + nbytes(sh%pc%hg_viscous) + nbytes(sh%pc%hg_bound) + nbytes(sh%pc%nip) &
            + nbytes(sh%pc%mix) + nbytes(sh%pc%plastic) + nbytes(sh%pc%sy0) + nbytes(sh%pc%hk) &
            + nbytes(sh%pc%ycurve) + nbytes(sh%pc%rated) + nbytes(sh%pc%backstress)
    end function shell_bytes

    !> The bytes of the points' state (sig, epsp, qhg, strain, alpha) and
    !> the force and moment slots this rank holds: every shell's on one
    !> rank, its own shells' (and its halo's slots) on more.
    integer(i8) function shell_state_bytes(sh, every) result(b)
        type(shells_t), intent(in) :: sh
        !> every shell's, as one rank holds them
        logical, intent(in), optional :: every
        integer(i8) :: w
        b = 0
        if (sh%n == 0 .or. .not. allocated(sh%sig)) return
        ! (every array real(wp); shell_state_init allocates them together)
        if (present(every)) then
            if (every) then
                ! a row's values: sig, epsp, qhg, the slots, and strain,
                ! alpha where kept
                w = size(sh%sig, 2)*size(sh%sig, 3) + size(sh%epsp, 2) + 5 + 2*3*4
                if (sh%track_strain) w = w + 6*size(sh%sig, 3)
                if (some_backstress(sh)) w = w + 6*size(sh%sig, 3)
                b = w*sh%n*(storage_size(1.0_wp, i8)/8)
                return
            end if
        end if
        b = (size(sh%sig, kind=i8) + size(sh%epsp, kind=i8) + size(sh%qhg, kind=i8) + size(sh%strain, kind=i8) + &
             size(sh%alpha, kind=i8) + size(sh%fslot, kind=i8) + size(sh%mslot, kind=i8))*(storage_size(1.0_wp, i8)/8)
    end function shell_state_bytes

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
            m = sh%pc%ro(sh%part(e))*sh%h(e)*a/nn
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

    !> Some shell's material moves a back stress (so the points keep one).
    pure logical function some_backstress(sh)
        type(shells_t), intent(in) :: sh
        some_backstress = .false.
        if (allocated(sh%pc%backstress)) some_backstress = any(sh%pc%backstress)
    end function some_backstress

    !> The flow stress sy and hardening slope h of shell e's material at
    !> effective plastic strain ep: the bilinear law in line (sy0 + hk ep:
    !> no_yield for a shell that is not plastic; a call cost as much as the
    !> rest of a return step), a curve's through yield_stress.
    pure subroutine flow_stress(sh, e, ep, sy, h)
        type(shells_t), intent(in) :: sh
        integer, intent(in) :: e
        real(wp), intent(in) :: ep
        real(wp), intent(out) :: sy, h
        integer :: p
        p = sh%part(e)
        if (sh%pc%ycurve(p)) then
            call yield_stress(sh%pp(sh%pc%mix(p)), ep, sy, h)
        else
            sy = sh%pc%sy0(p) + sh%pc%hk(p)*ep
            h = sh%pc%hk(p)
        end if
    end subroutine flow_stress

    !> The element loop's blocks from sh%mine (ascending): each a run of
    !> consecutive element numbers, at most nblk long, within one of the
    !> parts (one a thread: runs of mine of nearly equal length); then the
    !> nodes each part holds alone (direct) and those it shares (shared).
    subroutine shell_blocks(sh)
        type(shells_t), intent(inout) :: sh
        integer :: i, nbk, p, np, i0, i1, ib, l, k, e, nd, nnode
        integer, allocatable :: first(:), count(:), owner(:)
        allocate (first(size(sh%mine)), count(size(sh%mine)))
        np = 1
        !$ np = omp_get_max_threads()
        np = max(1, min(np, size(sh%mine)))
        if (allocated(sh%pfirst)) deallocate (sh%pfirst, sh%plast)
        allocate (sh%pfirst(np), sh%plast(np))
        nbk = 0
        do p = 1, np
            i0 = int((int(p - 1, 8)*size(sh%mine))/np) + 1
            i1 = int((int(p, 8)*size(sh%mine))/np)
            sh%pfirst(p) = nbk + 1
            do i = i0, i1
                if (nbk >= sh%pfirst(p)) then
                    if (sh%mine(i) == first(nbk) + count(nbk) .and. count(nbk) < nblk) then
                        count(nbk) = count(nbk) + 1
                        cycle
                    end if
                end if
                nbk = nbk + 1
                first(nbk) = sh%mine(i)
                count(nbk) = 1
            end do
            sh%plast(p) = nbk
        end do
        sh%bfirst = first(1:nbk)
        sh%bcount = count(1:nbk)
        if (allocated(sh%bback)) deallocate (sh%bback, sh%bcurve, sh%brated, sh%bplastic)
        allocate (sh%bback(nbk), sh%bcurve(nbk), sh%brated(nbk), sh%bplastic(nbk))
        sh%bback = .false.; sh%bcurve = .false.; sh%brated = .false.; sh%bplastic = .false.
        if (allocated(sh%pc%plastic)) then
            do ib = 1, nbk
                sh%bplastic(ib) = .true.
                do e = sh%bfirst(ib), sh%bfirst(ib) + sh%bcount(ib) - 1
                    k = sh%part(e)
                    sh%bback(ib) = sh%bback(ib) .or. sh%pc%backstress(k)
                    sh%bcurve(ib) = sh%bcurve(ib) .or. sh%pc%ycurve(k)
                    sh%brated(ib) = sh%brated(ib) .or. sh%pc%rated(k)
                    sh%bplastic(ib) = sh%bplastic(ib) .and. sh%pc%plastic(k)
                end do
            end do
        end if
        ! each node's part: 0 none yet, -1 shared by two or more
        nnode = 0
        if (sh%n > 0) nnode = maxval(sh%conn)
        allocate (owner(nnode))
        owner = 0
        do p = 1, np
            do ib = sh%pfirst(p), sh%plast(p)
                do l = 1, sh%bcount(ib)
                    e = sh%bfirst(ib) + l - 1
                    do k = 1, 4
                        nd = sh%conn(k, e)
                        if (allocated(sh%split)) then
                            if (sh%split(nd) /= 0) owner(nd) = -1
                        end if
                        if (owner(nd) == 0) then
                            owner(nd) = p
                        else if (owner(nd) /= p) then
                            owner(nd) = -1
                        end if
                    end do
                end do
            end do
        end do
        ! (by row: once the rows are placed, shell_state_init)
        if (allocated(sh%lix)) then
            if (.not. allocated(sh%direct)) allocate (sh%direct(4, sh%nl))
            sh%direct = .false.
            do p = 1, np
                do ib = sh%pfirst(p), sh%plast(p)
                    do l = 1, sh%bcount(ib)
                        e = sh%bfirst(ib) + l - 1
                        sh%direct(:, sh%lix(e)) = owner(sh%conn(:, e)) > 0
                    end do
                end do
            end do
        end if
        if (allocated(sh%split)) then
            ! (and every node this rank assembles that another rank's
            ! shells may touch, though none of its own does)
            sh%shared = pack([(nd, nd=1, nnode)], (owner < 0 .and. sh%split(1:nnode) /= 2) .or. sh%split(1:nnode) == 1)
        else
            sh%shared = pack([(nd, nd=1, nnode)], owner < 0)
        end if
    end subroutine shell_blocks

    !> Forces and moments of every shell at x(n) with v(n-1/2), w(n-1/2).
    !> Threaded over elements: each writes only its own slots and state; the
    !> smallest step and the first bad element are combined by element
    !> number, so the result does not depend on the threads. With f and m
    !> (one rank) the forces and moments on the nodes a thread's part holds
    !> alone are added to them directly, in the order the assembly sums the
    !> slots (element by element, node by node: the same sums bit for bit),
    !> and those on the shared nodes go to the slots, for the caller to sum
    !> (assemble over sh%shared, adding to f).
    subroutine shell_forces(sh, x, v, w, dt, dt_avg_prev, f, m)
        type(shells_t), intent(inout) :: sh
        real(wp), intent(in) :: dt
        real(wp), intent(in), contiguous :: x(:, :), v(:, :), w(:, :)
        real(dp), intent(in) :: dt_avg_prev
        real(wp), intent(inout), optional, contiguous :: f(:, :), m(:, :)
        integer :: e, ib, p, l, nb, e0, s0, tcrit, tbad
        real(wp) :: dte, dms, tmin, dtb(nblk), fs(nblk, 3, 4), ms(nblk, 3, 4)
        logical :: scaled
        real(wp) :: vg(nblk, 3, 4), wg(nblk, 3, 4)
        type(block_geom_t) :: gm, gn
        sh%dtmin = huge(1.0_wp)
        sh%crit = 0
        sh%bad = 0
        if (sh%tsmin > 0.0_wp) sh%low = .false.
        scaled = allocated(sh%msq)
        !$omp parallel default(shared) private(e, ib, p, l, nb, e0, s0, gm, gn, dte, dms, dtb, fs, ms, vg, wg, tmin, tcrit, &
        !$omp tbad)
        tmin = huge(1.0_wp)
        tcrit = 0
        tbad = 0
        ! a part a thread (with fewer threads, one takes several: each
        ! part's own nodes are still written by one thread alone)
        !$omp do schedule(static, 1)
        do p = 1, size(sh%pfirst)
        do ib = sh%pfirst(p), sh%plast(p)
            e0 = sh%bfirst(ib) - 1
            nb = sh%bcount(ib)
            ! (the block's rows of the points' state: consecutive too)
            s0 = sh%lix(e0 + 1) - 1
            ! the rates on the mid-step geometry, the forces on x(n)
            call block_gather(sh, e0, nb, x, v, w, gn%xe, vg, wg)
            gm%xe(1:nb, :, :) = gn%xe(1:nb, :, :) - 0.5_wp*dt*vg(1:nb, :, :)
            call block_geometry(sh, e0, nb, gm)
            call block_geometry(sh, e0, nb, gn)
            call block_forces(sh, ib, e0, s0, nb, gm, gn, vg, wg, dt, dt_avg_prev, dtb, fs, ms)
            if (present(f) .and. present(m)) then
                call block_add(sh, e0, s0, nb, dtb, fs, ms, f, m)
            else
                call block_slots(sh, s0, nb, dtb, fs, ms)
            end if
            do l = 1, nb
                e = e0 + l
                dte = dtb(l)
                ! mass scaling: the step of the element's scaled mass (msq,
                ! only where mass scaling is on)
                dms = dte
                if (scaled) dms = dte*sh%msq(e)
                if (sh%tsmin > 0.0_wp) then
                    ! ERODE: a shell whose step fell below the minimum (or that
                    ! turned inside out) sets no step: it erodes after this pass
                    if (.not. (dms >= sh%tsmin)) then
                        sh%low(s0 + l) = .true.
                        cycle
                    end if
                end if
                if (.not. (dte > 0.0_wp)) then
                    if (tbad == 0) tbad = e
                    cycle
                end if
                ! (mass scaling: a step below the target asks for the factor
                ! that brings it there)
                dte = dms
                if (dte < sh%ms_target .or. sh%ms_all) call ask_mass(sh, e, dte)
                if (dte < tmin) then
                    tmin = dte
                    tcrit = e
                end if
            end do
        end do
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

    !> Forces, moments, stresses and steps of the nb shells e0 + 1 .. e0 + nb of a
    !> block, gm their geometry at mid-step, gn at x(n): loops over the
    !> block's elements (structure of arrays, vectorised) for the rates, the
    !> hourglass and the forces; the points' stress update per element (a
    !> yielding point's return is its own iteration). dte(l) = -1 for an
    !> element collapsed or inverted (the mid-step one is not updated).
    subroutine block_forces(sh, ib, e0, s0, nb, gm, gn, vg, wg, dt, dt_avg_prev, dte, fs, ms)
        type(shells_t), intent(inout) :: sh
        integer, intent(in) :: ib       !< the block's number
        integer, intent(in) :: e0, nb   !< the block: shells e0 + 1 .. e0 + nb
        integer, intent(in) :: s0       !< their points' state: rows s0 + 1 .. s0 + nb
        type(block_geom_t), intent(in) :: gm, gn
        !> the nodes' velocities and angular velocities (block_gather)
        real(wp), intent(in) :: vg(nblk, 3, 4), wg(nblk, 3, 4)
        real(wp), intent(in) :: dt
        real(dp), intent(in) :: dt_avg_prev
        real(wp), intent(out) :: dte(:)
        !> the nodal forces and moments (global) of the block's elements
        real(wp), intent(out) :: fs(nblk, 3, 4), ms(nblk, 3, 4)
        real(wp), parameter :: quarter = 0.25_wp
        real(wp) :: vl(nblk, 3, 4), wl(nblk, 3, 4), r(nblk, 8)
        real(wp) :: nres(nblk, 3), mres(nblk, 3), qres(nblk, 2), qd(nblk, 5), hq(nblk, 5)
        real(wp) :: bb(nblk), gg(nblk), gamz(nblk), wsp(nblk)
        real(wp) :: hh(nblk), ym(nblk), nu(nblk), ro(nblk), ge(nblk), tf(nblk)
        real(wp) :: wx, wy, f1, f2, f3, m1, m2, b1k, b2k, gk, a, q1, q2, q3, q4, q5, b, g, s12, s23, s34, s41
        real(wp) :: cb, cw, cm, mn, jn, il, hs
        real(wp) :: qc(nblk, 3), sr(nblk), mf(nblk), sy(nblk)
        real(wp), parameter :: r3 = 1.7320508075688772_wp
        real(wp) :: vq(nblk, 5), sq(nblk, 5), bq(nblk, 5), kq(nblk, 3)
        real(wp) :: cap(nblk), bw(nblk)
        logical :: visc(nblk), bnd(nblk), capped(nblk), allok, anyvisc
        real(dp) :: pold(nblk), pnew(nblk)
        integer :: l, k, e, pk(nblk), d0
        ! (the per-shell arrays held by row here, or by the model's number:
        ! shell_rows)
        d0 = merge(s0, e0, sh%by_row)
        ! gather: the elements' data (their parts' constants)
        do l = 1, nb
            pk(l) = sh%part(e0 + l)
        end do
        do l = 1, nb
            e = e0 + l
            hh(l) = sh%h(d0 + l)
            ym(l) = sh%pc%e(pk(l))
            nu(l) = sh%pc%nu(pk(l))
            ro(l) = sh%pc%ro(pk(l))
            ge(l) = sh%pc%ge(pk(l))
            ! the step length's factor: a triangle's shortest altitude is
            ! twice its area over its longest side
            tf(l) = 1.0_wp + gn%tw(l)
        end do
        ! The rates v(n-1/2) are taken on the mid-step geometry x(n-1/2) =
        ! x(n) - dt/2 v(n-1/2), the forces on x(n). (Rates on x(n) see a
        ! rigid turn of theta per step as a membrane strain of order
        ! theta^2, always of one sign: a clamped elastic plate vibrating at a
        ! few degrees gained 22% energy in 200 us and one at ten degrees blew
        ! up; on the mid-step geometry 0.1%.)
        do k = 1, 4
            do l = 1, nb
                vl(l, 1, k) = vg(l, 1, k)*gm%e1(l, 1) + vg(l, 2, k)*gm%e1(l, 2) + vg(l, 3, k)*gm%e1(l, 3)
                vl(l, 2, k) = vg(l, 1, k)*gm%e2(l, 1) + vg(l, 2, k)*gm%e2(l, 2) + vg(l, 3, k)*gm%e2(l, 3)
                vl(l, 3, k) = vg(l, 1, k)*gm%e3(l, 1) + vg(l, 2, k)*gm%e3(l, 2) + vg(l, 3, k)*gm%e3(l, 3)
                wl(l, 1, k) = wg(l, 1, k)*gm%e1(l, 1) + wg(l, 2, k)*gm%e1(l, 2) + wg(l, 3, k)*gm%e1(l, 3)
                wl(l, 2, k) = wg(l, 1, k)*gm%e2(l, 1) + wg(l, 2, k)*gm%e2(l, 2) + wg(l, 3, k)*gm%e2(l, 3)
                wl(l, 3, k) = wg(l, 1, k)*gm%e3(l, 1) + wg(l, 2, k)*gm%e3(l, 2) + wg(l, 3, k)*gm%e3(l, 3)
            end do
        end do
        ! membrane, bending and transverse shear rates (BT 1984): dx dy dxy
        ! (engineering), kx ky kxy, gxz gyz
        ! (sums over the four nodes in registers, one element per lane: a
        ! block array zeroed and then added to stalled on its own stores)
        do l = 1, nb
            r(l, 1) = ((gm%b1(l, 1)*vl(l, 1, 1) + gm%b1(l, 2)*vl(l, 1, 2)) + gm%b1(l, 3)*vl(l, 1, 3)) + &
                      gm%b1(l, 4)*vl(l, 1, 4)
            r(l, 2) = ((gm%b2(l, 1)*vl(l, 2, 1) + gm%b2(l, 2)*vl(l, 2, 2)) + gm%b2(l, 3)*vl(l, 2, 3)) + &
                      gm%b2(l, 4)*vl(l, 2, 4)
            r(l, 3) = (((gm%b2(l, 1)*vl(l, 1, 1) + gm%b1(l, 1)*vl(l, 2, 1)) + &
                        (gm%b2(l, 2)*vl(l, 1, 2) + gm%b1(l, 2)*vl(l, 2, 2))) + &
                       (gm%b2(l, 3)*vl(l, 1, 3) + gm%b1(l, 3)*vl(l, 2, 3))) + &
                      (gm%b2(l, 4)*vl(l, 1, 4) + gm%b1(l, 4)*vl(l, 2, 4))
            r(l, 4) = ((gm%b1(l, 1)*wl(l, 2, 1) + gm%b1(l, 2)*wl(l, 2, 2)) + gm%b1(l, 3)*wl(l, 2, 3)) + &
                      gm%b1(l, 4)*wl(l, 2, 4)
            r(l, 5) = -(((gm%b2(l, 1)*wl(l, 1, 1) + gm%b2(l, 2)*wl(l, 1, 2)) + gm%b2(l, 3)*wl(l, 1, 3)) + &
                        gm%b2(l, 4)*wl(l, 1, 4))
            r(l, 6) = (((gm%b2(l, 1)*wl(l, 2, 1) - gm%b1(l, 1)*wl(l, 1, 1)) + &
                        (gm%b2(l, 2)*wl(l, 2, 2) - gm%b1(l, 2)*wl(l, 1, 2))) + &
                       (gm%b2(l, 3)*wl(l, 2, 3) - gm%b1(l, 3)*wl(l, 1, 3))) + &
                      (gm%b2(l, 4)*wl(l, 2, 4) - gm%b1(l, 4)*wl(l, 1, 4))
            r(l, 7) = (((gm%b1(l, 1)*vl(l, 3, 1) + gm%b1(l, 2)*vl(l, 3, 2)) + gm%b1(l, 3)*vl(l, 3, 3)) + &
                       gm%b1(l, 4)*vl(l, 3, 4)) + quarter*(((wl(l, 2, 1) + wl(l, 2, 2)) + wl(l, 2, 3)) + wl(l, 2, 4))
            r(l, 8) = (((gm%b2(l, 1)*vl(l, 3, 1) + gm%b2(l, 2)*vl(l, 3, 2)) + gm%b2(l, 3)*vl(l, 3, 3)) + &
                       gm%b2(l, 4)*vl(l, 3, 4)) - quarter*(((wl(l, 1, 1) + wl(l, 1, 2)) + wl(l, 1, 3)) + wl(l, 1, 4))
        end do
        ! the points' stresses, the resultants and the internal energy
        call block_points(sh, ib, e0, s0, nb, r, gm%a, gm%ok, hh, ym, nu, ge, dt, dt_avg_prev, nres, mres, qres)
        ! Belytschko-Tsay hourglass: gamma = h - (h.x) b1 - (h.y) b2; stiffness
        ! form on the out-of-plane rotations and displacement and the membrane
        ! rates of a warped element (nodes zl off its mean plane) less the
        ! rigid spin about the in-plane axes (wx = dvz/dy, wy = -dvz/dx): that
        ! spin moves the warped nodes in-plane by (wy zl, -wx zl), an
        ! hourglass pattern, and without this correction a warped element
        ! turning as a rigid body strained its membrane hourglass springs (a
        ! warped patch spinning free stored 1.4% of its kinetic energy in
        ! them; the tube crush's mean force was 49.1 kN, now 41.5 kN). The
        ! rates on the mid-step geometry too.
        do l = 1, nb
            wx = ((gm%b2(l, 1)*vl(l, 3, 1) + gm%b2(l, 2)*vl(l, 3, 2)) + gm%b2(l, 3)*vl(l, 3, 3)) + &
                 gm%b2(l, 4)*vl(l, 3, 4)
            wy = -(((gm%b1(l, 1)*vl(l, 3, 1) + gm%b1(l, 2)*vl(l, 3, 2)) + gm%b1(l, 3)*vl(l, 3, 3)) + &
                   gm%b1(l, 4)*vl(l, 3, 4))
            q1 = 0; q2 = 0; q3 = 0; q4 = 0; q5 = 0; b = 0; g = 0
            do k = 1, 4
                g = g + gm%gam(l, k)**2
                q1 = q1 + gm%gam(l, k)*wl(l, 1, k)
                q2 = q2 + gm%gam(l, k)*wl(l, 2, k)
                q3 = q3 + gm%gam(l, k)*vl(l, 3, k)
                q4 = q4 + gm%gam(l, k)*(vl(l, 1, k) - wy*gm%zl(l, k))
                q5 = q5 + gm%gam(l, k)*(vl(l, 2, k) + wx*gm%zl(l, k))
                b = b + (gm%b1(l, k)**2 + gm%b2(l, k)**2)
            end do
            qd(l, 1) = q1; qd(l, 2) = q2; qd(l, 3) = q3; qd(l, 4) = q4; qd(l, 5) = q5
            bb(l) = b
            gg(l) = g
        end do
        ! the generalized forces: stiffness form (IHQ 4-5), Q += dt k qdot
        ! with Belytschko and Tsay's k (bending QB E h^3 A/192 B.B, warping
        ! QW kappa G h^3/12 B.B, membrane QM E h A/8 B.B); viscous form
        ! (IHQ 1-3), Q = c qdot with c = 2 q sqrt(k1 m): each mode damped at
        ! the fraction q (QB, QW, QM) of critical against the stiffness k1
        ! the stiffness form has at coefficient 1 (the element's own), m the
        ! mode's mass, a node's share over gamma.gamma (rotary for bending)
        ! (in loops over the block, the element data gathered first: the
        ! update and the bound vectorise; one element at a time, the bound's
        ! chain of roots and divisions was 8% of car6's run)
        do k = 1, 5
            do l = 1, nb
                hq(l, k) = sh%qhg(s0 + l, k)
            end do
        end do
        do l = 1, nb
            e = e0 + l
            qc(l, 1) = sh%pc%qb(pk(l))
            qc(l, 2) = sh%pc%qw(pk(l))
            qc(l, 3) = sh%pc%qm(pk(l))
            sr(l) = sh%pc%shrf(pk(l))
            visc(l) = sh%pc%hg_viscous(pk(l))
            bnd(l) = sh%pc%hg_bound(pk(l))
            bw(l) = merge(1.0_wp, 0.0_wp, bnd(l))
        end do
        ! the modes' masses' factor: a node's share of the element mass
        ! (as shell_masses gives it: a third on a triangle's nodes; times
        ! the mass-scaling factor)
        do l = 1, nb
            mf(l) = 1.0_wp/(4.0_wp - gn%tw(l))
        end do
        if (allocated(sh%msf)) then
            do l = 1, nb
                mf(l) = mf(l)*sh%msf(e0 + l)
            end do
        end if
        ! the flow stress of the most strained point, where the bound acts:
        ! the strain and the bilinear law in loops over the block, a curve's
        ! law after (per element, with a call for each, it had been a tenth
        ! of this routine's time on car6)
        do l = 1, nb
            sy(l) = sh%epsp(s0 + l, 1)
        end do
        ! (the points beyond an element's nip weighed 0 against the
        ! strains, which are not negative; the elements where the bound
        ! does not act 0: no select, so that the loops vectorise)
        do k = 2, size(sh%epsp, 2)
            do l = 1, nb
                sy(l) = max(sy(l), sh%epsp(s0 + l, k)*real(min(max(sh%pc%nip(pk(l)) - k + 1, 0), 1), wp))
            end do
        end do
        do l = 1, nb
            e = e0 + l
            sy(l) = (sh%pc%sy0(pk(l)) + sh%pc%hk(pk(l))*sy(l))*bw(l)
        end do
        if (sh%bcurve(ib)) then
            do l = 1, nb
                e = e0 + l
                if (.not. (bnd(l) .and. sh%pc%ycurve(pk(l)))) cycle
                call flow_stress(sh, e, maxval(sh%epsp(s0 + l, 1:max(1, sh%pc%nip(pk(l))))), sy(l), hs)
            end do
        end if
        ! The stiffness form's hourglass on a plastic material, bounded as the
        ! material is (*CONTROL_XDYNA_SHELL HGBOUND 1, the default): each
        ! mode's generalized force at most its coefficient (QM, QB, QW) times
        ! that mode's fully plastic value in the fully integrated element (2 x
        ! 2 points, von Mises at the flow stress of the element's most strained
        ! point), so that the mode, elastic at q k1,
        ! yields near the material's yield strain (issue 28: without the bound
        ! the springs of folds pressed flat by the contact kept growing
        ! elastically and held the crush). Per unit flow stress sy, with A the
        ! area and L = sqrt(2/B.B) (the side of a square): membrane (in-plane
        ! u = a xi eta, strain and shear at the points) sy h A / (3 L) for the
        ! pair; bending (the rotations' pattern, curvatures as the membrane's
        ! strains, the plastic moment sy h^2/4 for the plastic force sy h)
        ! sy h^2 A / (12 L); warping (w = a xi eta: a constant twist 2 q / L^2,
        ! the plastic twisting moment sy h^2 / (4 sqrt 3)) sy h^2 A / (2 sqrt 3
        ! L^2). The part cut off is dissipated, as plastic work is, and booked
        ! with the hourglass energy; ncap counts the cycles it acted.
        ! Both forms and the bound are taken for every element in loops over
        ! the block and the element's own picked, so that the loops
        ! vectorise; the caps compared as squares.
        do l = 1, nb
            a = max(gm%a(l), 0.0_wp)
            kq(l, 1) = ym(l)*hh(l)**3*a/192*bb(l)
            kq(l, 2) = sr(l)*ge(l)*hh(l)**3/12*bb(l)
            kq(l, 3) = ym(l)*hh(l)*a/8*bb(l)
            pold(l) = (((real(hq(l, 1), dp)*qd(l, 1) + real(hq(l, 2), dp)*qd(l, 2)) + real(hq(l, 3), dp)*qd(l, 3)) + &
                       real(hq(l, 4), dp)*qd(l, 4)) + real(hq(l, 5), dp)*qd(l, 5)
        end do
        ! viscous: the modes' masses, a node's mass and rotary inertia over
        ! gamma.gamma (only in a block that has a viscous shell)
        if (any(visc(1:nb))) then
            do l = 1, nb
                a = max(gm%a(l), 0.0_wp)
                mn = ro(l)*hh(l)*a*mf(l)/gg(l)
                jn = mn*(hh(l)**2 + 3*a)/12
                cb = 2*qc(l, 1)*sqrt(kq(l, 1)*jn)
                cw = 2*qc(l, 2)*sqrt(kq(l, 2)*mn)
                cm = 2*qc(l, 3)*sqrt(kq(l, 3)*mn)
                vq(l, 1) = cb*qd(l, 1)
                vq(l, 2) = cb*qd(l, 2)
                vq(l, 3) = cw*qd(l, 3)
                vq(l, 4) = cm*qd(l, 4)
                vq(l, 5) = cm*qd(l, 5)
            end do
        end if
        ! stiffness
        do l = 1, nb
            sq(l, 1) = hq(l, 1) + dt*qc(l, 1)*kq(l, 1)*qd(l, 1)
            sq(l, 2) = hq(l, 2) + dt*qc(l, 1)*kq(l, 1)*qd(l, 2)
            sq(l, 3) = hq(l, 3) + dt*qc(l, 2)*kq(l, 2)*qd(l, 3)
            sq(l, 4) = hq(l, 4) + dt*qc(l, 3)*kq(l, 3)*qd(l, 4)
            sq(l, 5) = hq(l, 5) + dt*qc(l, 3)*kq(l, 3)*qd(l, 5)
        end do
        ! the bound (sy 0 where it does not act: caps of 0 scale to 0, so
        ! the caps' flags select); capped: it acted
        capped(1:nb) = .false.
        if (any(bnd(1:nb))) then
            do l = 1, nb
                a = max(gm%a(l), 0.0_wp)
                il = sqrt(bb(l)/2)
                cm = qc(l, 3)*sy(l)*hh(l)*a*il/3
                cb = qc(l, 1)*sy(l)*hh(l)*hh(l)*a*il/12
                cw = qc(l, 2)*sy(l)*hh(l)*hh(l)*a*il*il/(2*r3)
                q1 = sq(l, 1)**2 + sq(l, 2)**2
                q4 = sq(l, 4)**2 + sq(l, 5)**2
                ! (as min and max, not selects on comparisons: a comparison
                ! may trap, and the compiler keeps a select on one as a branch)
                f1 = min(1.0_wp, cm/sqrt(max(q4, tiny(1.0_wp))))
                f2 = min(1.0_wp, cb/sqrt(max(q1, tiny(1.0_wp))))
                f3 = abs(sq(l, 3))
                cap(l) = ((1.0_wp - f1) + (1.0_wp - f2)) + max(f3 - cw, 0.0_wp)
                bq(l, 1) = sq(l, 1)*f2
                bq(l, 2) = sq(l, 2)*f2
                bq(l, 3) = sign(min(f3, cw), sq(l, 3))
                bq(l, 4) = sq(l, 4)*f1
                bq(l, 5) = sq(l, 5)*f1
            end do
            capped(1:nb) = bnd(1:nb) .and. .not. visc(1:nb) .and. gm%ok(1:nb) .and. cap(1:nb) > 0.0_wp
        end if
        ! each element's own form (a block of one form, all its elements
        ! sound, the common case, in loops without a branch that vectorise:
        ! the same values)
        allok = all(gm%ok(1:nb))
        anyvisc = any(visc(1:nb))
        if (allok .and. .not. anyvisc .and. all(bnd(1:nb))) then
            hq(1:nb, :) = bq(1:nb, :)
        else if (allok .and. .not. anyvisc .and. .not. any(bnd(1:nb))) then
            hq(1:nb, :) = sq(1:nb, :)
        else
            do l = 1, nb
                if (visc(l)) then
                    hq(l, :) = vq(l, :)
                else if (bnd(l)) then
                    hq(l, :) = bq(l, :)
                else
                    hq(l, :) = sq(l, :)
                end if
                if (.not. gm%ok(l)) hq(l, :) = 0
            end do
        end if
        do l = 1, nb
            pnew(l) = (((real(hq(l, 1), dp)*qd(l, 1) + real(hq(l, 2), dp)*qd(l, 2)) + real(hq(l, 3), dp)*qd(l, 3)) + &
                       real(hq(l, 4), dp)*qd(l, 4)) + real(hq(l, 5), dp)*qd(l, 5)
        end do
        ! the work of each step's forces over the velocities before and
        ! after them, as the central difference moves the nodes
        if (allok) then
            do l = 1, nb
                e = e0 + l
                sh%ehg(d0 + l) = sh%ehg(d0 + l) + dt_avg_prev*(sh%pend_hg(d0 + l) + 0.5_dp*pold(l))
                sh%pend_hg(d0 + l) = 0.5_dp*pnew(l)
            end do
            do k = 1, 5
                do l = 1, nb
                    sh%qhg(s0 + l, k) = hq(l, k)
                end do
            end do
            if (any(capped(1:nb))) then
                do l = 1, nb
                    if (capped(l)) sh%ncap(s0 + l) = sh%ncap(s0 + l) + 1
                end do
            end if
        else
            do l = 1, nb
                if (.not. gm%ok(l)) cycle
                e = e0 + l
                sh%qhg(s0 + l, :) = hq(l, :)
                if (capped(l)) sh%ncap(s0 + l) = sh%ncap(s0 + l) + 1
                sh%ehg(d0 + l) = sh%ehg(d0 + l) + dt_avg_prev*(sh%pend_hg(d0 + l) + 0.5_dp*pold(l))
                sh%pend_hg(d0 + l) = 0.5_dp*pnew(l)
            end do
        end if
        ! the forces: on x(n); nodal forces and moments (local) are minus the
        ! derivatives of the power, the hourglass's and the warping
        ! correction's share (the rates' dependence on vz through the spin:
        ! the forces stay work-conjugate to the rates and in equilibrium)
        ! with them; then to global
        do l = 1, nb
            gamz(l) = ((gn%gam(l, 1)*gn%zl(l, 1) + gn%gam(l, 2)*gn%zl(l, 2)) + gn%gam(l, 3)*gn%zl(l, 3)) + &
                      gn%gam(l, 4)*gn%zl(l, 4)
        end do
        do k = 1, 4
            do l = 1, nb
                a = gn%a(l)
                b1k = gn%b1(l, k)
                b2k = gn%b2(l, k)
                gk = gn%gam(l, k)
                f1 = -a*(b1k*nres(l, 1) + b2k*nres(l, 3)) - gk*hq(l, 4)
                f2 = -a*(b2k*nres(l, 2) + b1k*nres(l, 3)) - gk*hq(l, 5)
                f3 = (-a*(b1k*qres(l, 1) + b2k*qres(l, 2)) - gk*hq(l, 3)) - gamz(l)*(b1k*hq(l, 4) + b2k*hq(l, 5))
                m1 = -a*(-b2k*mres(l, 2) - b1k*mres(l, 3) - quarter*qres(l, 2)) - gk*hq(l, 1)
                m2 = -a*(b1k*mres(l, 1) + b2k*mres(l, 3) + quarter*qres(l, 1)) - gk*hq(l, 2)
                fs(l, 1, k) = f1*gn%e1(l, 1) + f2*gn%e2(l, 1) + f3*gn%e3(l, 1)
                fs(l, 2, k) = f1*gn%e1(l, 2) + f2*gn%e2(l, 2) + f3*gn%e3(l, 2)
                fs(l, 3, k) = f1*gn%e1(l, 3) + f2*gn%e2(l, 3) + f3*gn%e3(l, 3)
                ms(l, 1, k) = m1*gn%e1(l, 1) + m2*gn%e2(l, 1)
                ms(l, 2, k) = m1*gn%e1(l, 2) + m2*gn%e2(l, 2)
                ms(l, 3, k) = m1*gn%e1(l, 3) + m2*gn%e2(l, 3)
            end do
        end do
        ! time step (ISDO, LS-DYNA's meaning): the plate wave speed and the
        ! area over the longest side; a triangle's shortest altitude, twice
        ! that (the longest side is the altitude's base)
        if (sh%isdo == 0) then
            ! (the longest side on x(n) here, not in block_geometry: the
            ! mid-step geometry needs none)
            do l = 1, nb
                s12 = (gn%xe(l, 1, 2) - gn%xe(l, 1, 1))**2 + (gn%xe(l, 2, 2) - gn%xe(l, 2, 1))**2 + &
                      (gn%xe(l, 3, 2) - gn%xe(l, 3, 1))**2
                s23 = (gn%xe(l, 1, 3) - gn%xe(l, 1, 2))**2 + (gn%xe(l, 2, 3) - gn%xe(l, 2, 2))**2 + &
                      (gn%xe(l, 3, 3) - gn%xe(l, 3, 2))**2
                s34 = (gn%xe(l, 1, 4) - gn%xe(l, 1, 3))**2 + (gn%xe(l, 2, 4) - gn%xe(l, 2, 3))**2 + &
                      (gn%xe(l, 3, 4) - gn%xe(l, 3, 3))**2
                s41 = (gn%xe(l, 1, 1) - gn%xe(l, 1, 4))**2 + (gn%xe(l, 2, 1) - gn%xe(l, 2, 4))**2 + &
                      (gn%xe(l, 3, 1) - gn%xe(l, 3, 4))**2
                wsp(l) = sh%pc%wsp(pk(l))
                dte(l) = tf(l)*gn%a(l)/sqrt(max(s12, s23, s34, s41))/wsp(l)
            end do
        else
            call step_options(sh, e0, nb, gn, ym, ro, nu, wsp, dte)
        end if
        do l = 1, nb
            if (.not. (gm%ok(l) .and. gn%ok(l))) dte(l) = -1
        end do
    end subroutine block_forces

    !> The block's forces and moments into the elements' slots (a
    !> triangle's fourth node is its third); zeros from an element collapsed
    !> or inverted (dte -1: the run stops, or ERODE removes it after this
    !> pass), as block_add adds none.
    subroutine block_slots(sh, s0, nb, dte, fs, ms)
        type(shells_t), intent(inout) :: sh
        integer, intent(in) :: s0, nb   !< the block's rows: s0 + 1 .. s0 + nb
        real(wp), intent(in) :: dte(:), fs(nblk, 3, 4), ms(nblk, 3, 4)
        integer :: l, k, e
        do l = 1, nb
            e = s0 + l
            if (.not. (dte(l) > 0.0_wp)) then
                sh%fslot(:, 4*e - 3:4*e) = 0
                sh%mslot(:, 4*e - 3:4*e) = 0
                cycle
            end if
            do k = 1, 4
                sh%fslot(:, 4*(e - 1) + k) = fs(l, :, k)
                sh%mslot(:, 4*(e - 1) + k) = ms(l, :, k)
            end do
        end do
    end subroutine block_slots

    !> The block's forces and moments added to the nodes' f and m where the
    !> block's part holds the node alone (direct), element by element and
    !> node by node: the order in which the assembly sums the slots; into
    !> the slots for the shared nodes, which the assembly sums after the
    !> pass (the same sums, bit for bit, for any number of threads).
    subroutine block_add(sh, e0, s0, nb, dte, fs, ms, f, m)
        type(shells_t), intent(inout) :: sh
        integer, intent(in) :: e0, nb   !< the block: shells e0 + 1 .. e0 + nb
        integer, intent(in) :: s0       !< their rows (the slots'): s0 + 1 .. s0 + nb
        real(wp), intent(in) :: dte(:), fs(nblk, 3, 4), ms(nblk, 3, 4)
        !> (explicit shape, as block_gather's)
        real(wp), intent(inout) :: f(3, *), m(3, *)
        integer :: l, k, nd, e, j
        logical :: ok
        do l = 1, nb
            e = e0 + l
            ! (an element collapsed or inverted adds nothing, and leaves
            ! zeros in its shared nodes' slots, as block_slots writes)
            ok = dte(l) > 0.0_wp
            do k = 1, 4
                nd = sh%conn(k, e)
                if (sh%direct(k, s0 + l)) then
                    if (.not. ok) cycle
                    f(1, nd) = f(1, nd) + fs(l, 1, k)
                    f(2, nd) = f(2, nd) + fs(l, 2, k)
                    f(3, nd) = f(3, nd) + fs(l, 3, k)
                    m(1, nd) = m(1, nd) + ms(l, 1, k)
                    m(2, nd) = m(2, nd) + ms(l, 2, k)
                    m(3, nd) = m(3, nd) + ms(l, 3, k)
                else
                    j = 4*(s0 + l - 1) + k
                    sh%fslot(:, j) = 0
                    sh%mslot(:, j) = 0
                    if (.not. ok) cycle
                    sh%fslot(:, j) = fs(l, :, k)
                    sh%mslot(:, j) = ms(l, :, k)
                end if
            end do
        end do
    end subroutine block_add

    !> ISDO 1: area over the longest diagonal (a triangle: its shortest
    !> altitude, as 0); 2: the bar wave speed and the larger of the shortest
    !> side and area over the longest side (a triangle: its shortest side).
    !> On the end-of-step geometry gn, as ISDO 0. (A module procedure, not
    !> one contained in block_forces: a contained one slowed the whole
    !> element loop by 4%.)
    subroutine step_options(sh, e0, nb, gn, ym, ro, nu, wsp, dte)
        type(shells_t), intent(in) :: sh
        integer, intent(in) :: e0, nb   !< the block: shells e0 + 1 .. e0 + nb
        type(block_geom_t), intent(in) :: gn
        real(wp), intent(in) :: ym(:), ro(:), nu(:)
        real(wp), intent(out) :: wsp(:)
        real(wp), intent(out) :: dte(:)
        integer :: l, k
        real(wp) :: sd(4), d13, d24, len
        logical :: tri
        do l = 1, nb
            tri = sh%conn(3, e0 + l) == sh%conn(4, e0 + l)
            do k = 1, 4
                sd(k) = norm2(gn%xe(l, :, mod(k, 4) + 1) - gn%xe(l, :, k))
            end do
            if (tri) sd(3) = sd(4)   ! the sides 1-2, 2-3 and 3-1 (4 = 3)
            if (sh%isdo == 1) then
                wsp(l) = sh%pc%wsp(sh%part(e0 + l))
                if (tri) then
                    len = 2*gn%a(l)/maxval(sd(1:3))
                else
                    d13 = norm2(gn%xe(l, :, 3) - gn%xe(l, :, 1))
                    d24 = norm2(gn%xe(l, :, 4) - gn%xe(l, :, 2))
                    len = gn%a(l)/max(d13, d24)
                end if
            else
                wsp(l) = sqrt(ym(l)/ro(l))
                if (tri) then
                    len = minval(sd(1:3))
                else
                    len = max(minval(sd), gn%a(l)/maxval(sd))
                end if
            end if
            dte(l) = len/wsp(l)
        end do
    end subroutine step_options


    !> The stresses at the points of the block's shells from their rates r
    !> (dx dy dxy kx ky kxy gxz gyz) on the mid-step areas a (elements not ok
    !> are left as they are): the plane-stress elastic trial of every point
    !> of a layer in one loop over the elements, then the return of those
    !> that yield (plane_stress_returns: the layer's together, packed, or
    !> dense_returns: the whole layer in place where most of it yields; with
    !> a back stress, mixed_return, each on its own); the resultants (membrane n, bending m,
    !> shear q per unit length), the thickness change (ISTUPD) and the
    !> internal energy.
    subroutine block_points(sh, ib, e0, s0, nb, r, a, ok, hh, ym, nu, ge, dt, dt_avg_prev, nres, mres, qres)
        type(shells_t), intent(inout) :: sh
        integer, intent(in) :: ib       !< the block's number
        integer, intent(in) :: e0, nb   !< the block: shells e0 + 1 .. e0 + nb
        integer, intent(in) :: s0       !< their points' state: rows s0 + 1 .. s0 + nb
        real(wp), intent(in) :: r(nblk, 8), a(nblk), dt
        !> the elements' thickness, Young's modulus, Poisson's ratio and shear modulus
        real(wp), intent(in) :: hh(nblk), ym(nblk), nu(nblk), ge(nblk)
        logical, intent(in) :: ok(nblk)
        real(dp), intent(in) :: dt_avg_prev
        real(wp), intent(out) :: nres(nblk, 3), mres(nblk, 3), qres(nblk, 2)
        real(wp) :: qe(nblk), sf(nblk), zf(nblk), wf(nblk), sy(nblk), al(nblk, 6)
        real(wp) :: dd(nblk, 5), so(nblk, 5), t(nblk, 5), dzz(nblk), dzm(nblk), xeq2(nblk), pm, fac, h, sl(5)
        real(dp) :: pold(nblk), pnew(nblk)
        real(wp) :: nuf(nblk)
        integer :: nip(nblk), pk(nblk), l, e, ip, mix, maxnip, k, d0
        real(wp) :: sy0(nblk), hk(nblk)
        !> every shell of the block has maxnip points; some moves a back
        !> stress; some takes a yield curve
        logical :: uniform, anyback, anycurve, anyrated
        !> uniform, every shell plastic, no back stress and no rate: the
        !> yielding points are those beyond sy
        logical :: simple
        !> the largest excess of a layer's trial over its yield, squared
        real(wp) :: over
        !> the layer's points that yield without a back stress (their
        !> elements' index in the block), and their rate factors
        integer :: ny, iy(nblk)
        real(wp) :: fy(nblk)
        !> 1 where a point of the layer yields, 0 elsewhere; the points'
        !> plastic strains before the step (the common block's)
        real(wp) :: yl(nblk), ep(nblk)
        d0 = merge(s0, e0, sh%by_row)
        ny = 0
        maxnip = 0
        do l = 1, nb
            e = e0 + l
            pk(l) = sh%part(e)
            qe(l) = sh%pc%qe(pk(l))
            nuf(l) = sh%pc%nuf(pk(l))
            ! the transverse shear factor of an elastic shell (the plastic
            ! return takes the full shear modulus)
            sf(l) = sh%pc%shrf(pk(l))
            if (sh%pc%plastic(pk(l))) sf(l) = 1
            sy0(l) = sh%pc%sy0(pk(l))
            hk(l) = sh%pc%hk(pk(l))
            nip(l) = sh%pc%nip(pk(l))
            if (.not. ok(l)) nip(l) = 0
            maxnip = max(maxnip, nip(l))
        end do
        nres(1:nb, :) = 0; mres(1:nb, :) = 0; qres(1:nb, :) = 0
        pold(1:nb) = 0; pnew(1:nb) = 0
        dzm(1:nb) = 0
        uniform = maxnip > 0 .and. all(nip(1:nb) == maxnip)
        anyback = sh%bback(ib)
        anycurve = sh%bcurve(ib)
        anyrated = sh%brated(ib)
        simple = uniform .and. .not. (anyback .or. anyrated) .and. dt > 0.0_wp .and. sh%bplastic(ib)
        do ip = 1, maxnip
            if (uniform) then
                ! (the common block: one section and law, no branch per
                ! element; a shell that is not plastic has sy0 no_yield and hk 0;
                ! the 3 x 3 tubes, NIP 5, 4% faster than by the general loop)
                do l = 1, nb
                    e = e0 + l
                    wf(l) = real(gw(ip, maxnip), wp)/2
                    zf(l) = real(gz(ip, maxnip), wp)*hh(l)/2
                    so(l, 1) = sh%sig(s0 + l, 1, ip)
                    so(l, 2) = sh%sig(s0 + l, 2, ip)
                    so(l, 3) = sh%sig(s0 + l, 3, ip)
                    so(l, 4) = sh%sig(s0 + l, 4, ip)
                    so(l, 5) = sh%sig(s0 + l, 5, ip)
                    ep(l) = sh%epsp(s0 + l, ip)
                    sy(l) = sy0(l) + hk(l)*ep(l)
                end do
                if (anyback) then
                    al(1:nb, :) = 0
                    do l = 1, nb
                        if (sh%pc%backstress(pk(l))) al(l, :) = sh%alpha(:, ip, s0 + l)
                    end do
                end if
                if (anycurve) then
                    do l = 1, nb
                        e = e0 + l
                        if (sh%pc%plastic(pk(l)) .and. sh%pc%ycurve(pk(l))) &
                            call flow_stress(sh, e, sh%epsp(s0 + l, ip), sy(l), h)
                    end do
                end if
            else
                do l = 1, nb
                    e = e0 + l
                    if (ip > nip(l)) then
                        wf(l) = 0; zf(l) = 0; so(l, :) = 0; al(l, :) = 0; sy(l) = no_yield
                        cycle
                    end if
                    wf(l) = real(gw(ip, nip(l)), wp)/2
                    zf(l) = real(gz(ip, nip(l)), wp)*hh(l)/2
                    so(l, :) = sh%sig(s0 + l, :, ip)
                    al(l, :) = 0
                    if (sh%pc%backstress(pk(l))) al(l, :) = sh%alpha(:, ip, s0 + l)
                    sy(l) = no_yield
                    if (sh%pc%plastic(pk(l))) call flow_stress(sh, e, sh%epsp(s0 + l, ip), sy(l), h)
                end do
            end if
            ! the elastic plane-stress trial (s_zz stays 0 with the elastic
            ! d_zz) and the von Mises value of its deviator less the back
            ! stress, squared (no root on the elastic path, the common one)
            do l = 1, nb
                dd(l, 1) = r(l, 1) + zf(l)*r(l, 4)
                dd(l, 2) = r(l, 2) + zf(l)*r(l, 5)
                dd(l, 3) = r(l, 3) + zf(l)*r(l, 6)
                dd(l, 4) = r(l, 8)     ! engineering shears
                dd(l, 5) = r(l, 7)
                dzz(l) = -nuf(l)*(dd(l, 1) + dd(l, 2))
                t(l, 1) = so(l, 1) + dt*qe(l)*(dd(l, 1) + nu(l)*dd(l, 2))
                t(l, 2) = so(l, 2) + dt*qe(l)*(dd(l, 2) + nu(l)*dd(l, 1))
                t(l, 3) = so(l, 3) + dt*ge(l)*dd(l, 3)
                t(l, 4) = so(l, 4) + dt*sf(l)*ge(l)*dd(l, 4)
                t(l, 5) = so(l, 5) + dt*sf(l)*ge(l)*dd(l, 5)
            end do
            if (anyback) then
                do l = 1, nb
                    pm = (t(l, 1) + t(l, 2))/3.0_wp
                    xeq2(l) = 1.5_wp*((t(l, 1) - pm - al(l, 1))**2 + (t(l, 2) - pm - al(l, 2))**2 + (pm + al(l, 3))**2 + &
                                      2.0_wp*((t(l, 3) - al(l, 4))**2 + (t(l, 4) - al(l, 5))**2 + (t(l, 5) - al(l, 6))**2))
                end do
            else
                ! (no back stress in the block: the same sums without it)
                do l = 1, nb
                    pm = (t(l, 1) + t(l, 2))/3.0_wp
                    xeq2(l) = 1.5_wp*((t(l, 1) - pm)**2 + (t(l, 2) - pm)**2 + pm**2 + &
                                      2.0_wp*(t(l, 3)**2 + t(l, 4)**2 + t(l, 5)**2))
                end do
            end if
            ! the points beyond the yield surface (Cowper-Symonds scales it
            ! by the rate); a layer with none, the common case outside a
            ! crush, is told by a loop that vectorises (the loop below
            ! branches per element: 3% of the shell plate's run)
            over = 1
            if (.not. anyrated) then
                over = -huge(1.0_wp)
                do l = 1, nb
                    over = max(over, xeq2(l) - sy(l)**2)
                end do
            end if
            if (over > 0.0_wp .and. simple) then
                ! (a block of plastic shells with the same points, without a
                ! back stress or a rate: where most of the layer yields,
                ! every point returned in place, the elastic ones at dg =
                ! 0; otherwise the yielding points listed alone, as the loop
                ! below lists them. A point's values are the same either
                ! way.)
                do l = 1, nb
                    yl(l) = merge(1.0_wp, 0.0_wp, xeq2(l) > sy(l)**2)
                end do
                ! (ny is 0 here: the layer before left it so)
                if (4*count(yl(1:nb) > 0.5_wp) >= 3*nb) then
                    call dense_returns(sh, e0, s0, nb, ip, yl, ep, anycurve, dt, so, t, dzz)
                else
                    do l = 1, nb
                        if (yl(l) < 0.5_wp) cycle
                        ny = ny + 1
                        iy(ny) = l
                        fy(ny) = 1
                    end do
                end if
                over = 0
            end if
            do l = 1, nb
                if (.not. (over > 0.0_wp)) exit
                if (ip > nip(l) .or. dt <= 0.0_wp) cycle
                e = e0 + l
                if (.not. sh%pc%plastic(pk(l))) cycle
                mix = sh%pc%mix(pk(l))
                fac = 1
                if (sh%pc%rated(pk(l))) &
                    fac = rate_factor(sh%pp(mix), [dd(l, 1), dd(l, 2), dzz(l), 0.5_wp*dd(l, 3), 0.5_wp*dd(l, 4), &
                                                   0.5_wp*dd(l, 5)])
                if (xeq2(l) <= (fac*sy(l))**2) cycle
                if (.not. sh%pc%backstress(pk(l))) then
                    ! isotropic hardening, or none (kinematic is then the
                    ! same law, its back stress stays 0): the layer's
                    ! returns taken together below
                    ny = ny + 1
                    iy(ny) = l
                    fy(ny) = fac
                    cycle
                end if
                sl = so(l, :)
                call mixed_return(sh, e, s0 + l, ip, dd(l, :), dt, sl, dzz(l))
                t(l, :) = sl
            end do
            if (ny > 0) then
                call plane_stress_returns(sh, e0, s0, ip, ny, iy, fy, anycurve, dt, so, t, dzz)
                ny = 0
            end if
            if (uniform) then
                do k = 1, 5
                    do l = 1, nb
                        sh%sig(s0 + l, k, ip) = t(l, k)
                    end do
                end do
            else
                do l = 1, nb
                    if (ip > nip(l)) cycle
                    sh%sig(s0 + l, :, ip) = t(l, :)
                end do
            end if
            ! the points' strains (where a criterion needs them): the rates
            ! over the step, in the shell's frame (tensor shears)
            if (sh%track_strain) then
                do l = 1, nb
                    if (ip > nip(l)) cycle
                    e = e0 + l
                    sh%strain(s0 + l, 1, ip) = sh%strain(s0 + l, 1, ip) + dt*dd(l, 1)
                    sh%strain(s0 + l, 2, ip) = sh%strain(s0 + l, 2, ip) + dt*dd(l, 2)
                    sh%strain(s0 + l, 3, ip) = sh%strain(s0 + l, 3, ip) + dt*dzz(l)
                    sh%strain(s0 + l, 4, ip) = sh%strain(s0 + l, 4, ip) + 0.5_wp*dt*dd(l, 3)
                    sh%strain(s0 + l, 5, ip) = sh%strain(s0 + l, 5, ip) + 0.5_wp*dt*dd(l, 4)
                    sh%strain(s0 + l, 6, ip) = sh%strain(s0 + l, 6, ip) + 0.5_wp*dt*dd(l, 5)
                end do
            end if
            ! powers per unit area with the old and the new stresses,
            ! resultants, the mean thickness strain rate
            do l = 1, nb
                pold(l) = pold(l) + real(wf(l)*hh(l), dp)*(((real(so(l, 1), dp)*dd(l, 1) + so(l, 2)*dd(l, 2)) + &
                                                            so(l, 3)*dd(l, 3)) + so(l, 4)*dd(l, 4) + so(l, 5)*dd(l, 5))
                pnew(l) = pnew(l) + real(wf(l)*hh(l), dp)*(((real(t(l, 1), dp)*dd(l, 1) + t(l, 2)*dd(l, 2)) + &
                                                            t(l, 3)*dd(l, 3)) + t(l, 4)*dd(l, 4) + t(l, 5)*dd(l, 5))
                nres(l, 1) = nres(l, 1) + wf(l)*hh(l)*t(l, 1)
                nres(l, 2) = nres(l, 2) + wf(l)*hh(l)*t(l, 2)
                nres(l, 3) = nres(l, 3) + wf(l)*hh(l)*t(l, 3)
                mres(l, 1) = mres(l, 1) + wf(l)*hh(l)*zf(l)*t(l, 1)
                mres(l, 2) = mres(l, 2) + wf(l)*hh(l)*zf(l)*t(l, 2)
                mres(l, 3) = mres(l, 3) + wf(l)*hh(l)*zf(l)*t(l, 3)
                qres(l, 1) = qres(l, 1) + wf(l)*hh(l)*t(l, 5)
                qres(l, 2) = qres(l, 2) + wf(l)*hh(l)*t(l, 4)
                dzm(l) = dzm(l) + wf(l)*dzz(l)
            end do
        end do
        ! (a block whose every shell is sound and has the same points, the
        ! common case, in loops without a branch: the same values)
        if (uniform) then
            if (sh%thickness_update) then
                ! (not vectorised: a vector exp (libmvec) rounds otherwise
                ! than the scalar one, and a shell's thickness would depend
                ! on its place in its block, which the ranks change)
                !GCC$ novector
                do l = 1, nb
                    sh%h(d0 + l) = sh%h(d0 + l)*exp(dt*dzm(l))
                end do
            end if
            do l = 1, nb
                e = e0 + l
                sh%eint(d0 + l) = sh%eint(d0 + l) + dt_avg_prev*(sh%pend_int(d0 + l) + 0.5_dp*pold(l)*a(l))
                sh%pend_int(d0 + l) = 0.5_dp*pnew(l)*a(l)
            end do
            return
        end if
        do l = 1, nb
            if (.not. ok(l)) cycle
            e = e0 + l
            ! thickness change (ISTUPD): the mean thickness strain rate of the points
            if (sh%thickness_update) sh%h(d0 + l) = sh%h(d0 + l)*exp(dt*dzm(l))
            ! internal energy: the rule of the solids (work f(n).(v- + v+)/2 dt_avg)
            sh%eint(d0 + l) = sh%eint(d0 + l) + dt_avg_prev*(sh%pend_int(d0 + l) + 0.5_dp*pold(l)*a(l))
            sh%pend_int(d0 + l) = 0.5_dp*pnew(l)*a(l)
        end do
    end subroutine block_points

    !> The nodes' coordinates, velocities and angular velocities of the
    !> block's shells, gathered once for the geometries and the rates (the
    !> coordinates into the end-of-step geometry's xe).
    subroutine block_gather(sh, e0, nb, x, v, w, xg, vg, wg)
        type(shells_t), intent(in) :: sh
        integer, intent(in) :: e0, nb   !< the block: shells e0 + 1 .. e0 + nb
        !> (explicit shape: the column stride known to be 3, a node's
        !> address is one multiply and no descriptor's strides)
        real(wp), intent(in) :: x(3, *), v(3, *), w(3, *)
        real(wp), intent(out) :: xg(nblk, 3, 4), vg(nblk, 3, 4), wg(nblk, 3, 4)
        integer :: l, k, nd
        do k = 1, 4
            do l = 1, nb
                nd = sh%conn(k, e0 + l)
                xg(l, :, k) = x(:, nd)
                vg(l, :, k) = v(:, nd)
                wg(l, :, k) = w(:, nd)
            end do
        end do
    end subroutine block_gather

    !> The geometry of the nb shells e0 + 1 .. e0 + nb on their nodes'
    !> coordinates g%xe (the element loop's: x(n) - dt/2 v(n-1/2), the
    !> mid-step's, and x(n)), in g: the frame and the local coordinates,
    !> written out per component so that the loops over the block's
    !> elements carry no calls.
    subroutine block_geometry(sh, e0, nb, g)
        type(shells_t), intent(in) :: sh
        integer, intent(in) :: e0, nb   !< the block: shells e0 + 1 .. e0 + nb
        type(block_geom_t), intent(inout) :: g   !< in: the nodes' coordinates xe
        real(wp) :: pd(nblk, 3), qd(nblk, 3), nlen(nblk)
        real(wp) :: p1, p2, p3, c1, c2, c3, n3, d, r1, r2, r3, aa, hx, hy
        integer :: l, k
        real(wp) :: a1, a2, a3
        ! the diagonals (a triangle's sides 1-2, 1-3), whose cross product
        ! is the normal: both taken, the element's picked by the weights tw
        ! of 1 and 0 (a x 1 + b x 0 is a exactly; a merge on the
        ! connectivity kept this loop scalar with a branch: a fifth of this
        ! routine's time on car6)
        ! (tw from the connectivity in a loop of its own: held per shell
        ! it was another stream of the element loop, 8 bytes a shell)
        do l = 1, nb
            g%tw(l) = merge(1.0_wp, 0.0_wp, sh%conn(3, e0 + l) == sh%conn(4, e0 + l))
        end do
        do k = 1, 3
            do l = 1, nb
                a1 = g%xe(l, k, 2) - g%xe(l, k, 1)
                a2 = g%xe(l, k, 3) - g%xe(l, k, 1)
                a3 = g%xe(l, k, 4) - g%xe(l, k, 2)
                pd(l, k) = a1*g%tw(l) + a2*(1.0_wp - g%tw(l))
                qd(l, k) = a2*g%tw(l) + a3*(1.0_wp - g%tw(l))
            end do
        end do
        do l = 1, nb
            ! the normal (straight-line code: the loop vectorises)
            c1 = pd(l, 2)*qd(l, 3) - pd(l, 3)*qd(l, 2)
            c2 = pd(l, 3)*qd(l, 1) - pd(l, 1)*qd(l, 3)
            c3 = pd(l, 1)*qd(l, 2) - pd(l, 2)*qd(l, 1)
            n3 = sqrt(c1**2 + c2**2 + c3**2)
            nlen(l) = n3
            ! (one division and products: a quotient is a division
            ! instruction each, several times a product's cost)
            n3 = 1.0_wp/max(n3, tiny(1.0_wp))
            c1 = c1*n3
            c2 = c2*n3
            c3 = c3*n3
            ! e1 along side 1-2, less its normal part
            p1 = g%xe(l, 1, 2) - g%xe(l, 1, 1)
            p2 = g%xe(l, 2, 2) - g%xe(l, 2, 1)
            p3 = g%xe(l, 3, 2) - g%xe(l, 3, 1)
            d = p1*c1 + p2*c2 + p3*c3
            p1 = p1 - d*c1
            p2 = p2 - d*c2
            p3 = p3 - d*c3
            d = sqrt(p1**2 + p2**2 + p3**2)
            d = 1.0_wp/max(d, tiny(1.0_wp))
            p1 = p1*d
            p2 = p2*d
            p3 = p3*d
            g%e3(l, 1) = c1
            g%e3(l, 2) = c2
            g%e3(l, 3) = c3
            g%e1(l, 1) = p1
            g%e1(l, 2) = p2
            g%e1(l, 3) = p3
            g%e2(l, 1) = c2*p3 - c3*p2
            g%e2(l, 2) = c3*p1 - c1*p3
            g%e2(l, 3) = c1*p2 - c2*p1
        end do
        do k = 1, 4
            do l = 1, nb
                ! local coordinates about the centre
                r1 = g%xe(l, 1, k) - (((g%xe(l, 1, 1) + g%xe(l, 1, 2)) + g%xe(l, 1, 3)) + g%xe(l, 1, 4))/4
                r2 = g%xe(l, 2, k) - (((g%xe(l, 2, 1) + g%xe(l, 2, 2)) + g%xe(l, 2, 3)) + g%xe(l, 2, 4))/4
                r3 = g%xe(l, 3, k) - (((g%xe(l, 3, 1) + g%xe(l, 3, 2)) + g%xe(l, 3, 3)) + g%xe(l, 3, 4))/4
                g%xl(l, k) = r1*g%e1(l, 1) + r2*g%e1(l, 2) + r3*g%e1(l, 3)
                g%yl(l, k) = r1*g%e2(l, 1) + r2*g%e2(l, 2) + r3*g%e2(l, 3)
                g%zl(l, k) = r1*g%e3(l, 1) + r2*g%e3(l, 2) + r3*g%e3(l, 3)
            end do
        end do
        do l = 1, nb
            g%a(l) = 0.5_wp*((g%xl(l, 3) - g%xl(l, 1))*(g%yl(l, 4) - g%yl(l, 2)) + &
                             (g%xl(l, 2) - g%xl(l, 4))*(g%yl(l, 3) - g%yl(l, 1)))
            ! (a collapsed or inverted element's derivatives are finite
            ! nonsense: ok below says so)
            aa = 1.0_wp/max(2*g%a(l), tiny(1.0_wp))
            g%b1(l, 1) = (g%yl(l, 2) - g%yl(l, 4))*aa
            g%b1(l, 2) = (g%yl(l, 3) - g%yl(l, 1))*aa
            g%b1(l, 3) = (g%yl(l, 4) - g%yl(l, 2))*aa
            g%b1(l, 4) = (g%yl(l, 1) - g%yl(l, 3))*aa
            g%b2(l, 1) = (g%xl(l, 4) - g%xl(l, 2))*aa
            g%b2(l, 2) = (g%xl(l, 1) - g%xl(l, 3))*aa
            g%b2(l, 3) = (g%xl(l, 2) - g%xl(l, 4))*aa
            g%b2(l, 4) = (g%xl(l, 3) - g%xl(l, 1))*aa
        end do
        do l = 1, nb
            ! the hourglass shape vector, h = (1, -1, 1, -1)
            hx = ((g%xl(l, 1) - g%xl(l, 2)) + g%xl(l, 3)) - g%xl(l, 4)
            hy = ((g%yl(l, 1) - g%yl(l, 2)) + g%yl(l, 3)) - g%yl(l, 4)
            g%gam(l, 1) = (1.0_wp - hx*g%b1(l, 1)) - hy*g%b2(l, 1)
            g%gam(l, 2) = (-1.0_wp - hx*g%b1(l, 2)) - hy*g%b2(l, 2)
            g%gam(l, 3) = (1.0_wp - hx*g%b1(l, 3)) - hy*g%b2(l, 3)
            g%gam(l, 4) = (-1.0_wp - hx*g%b1(l, 4)) - hy*g%b2(l, 4)
        end do
        do l = 1, nb
            g%ok(l) = nlen(l) > 0.0_wp .and. g%a(l) > 0.0_wp
        end do
    end subroutine block_geometry

    !> Mixed hardening beyond the yield surface: the 3-D radial return, d_zz
    !> found by secant iteration so that s_zz = 0 (starting from the elastic
    !> and the incompressible guesses).
    subroutine mixed_return(sh, e, is, ip, dd, dt, s, dzz)
        type(shells_t), intent(inout) :: sh
        integer, intent(in) :: e, ip
        integer, intent(in) :: is       !< its points' state's row
        real(wp), intent(in) :: dd(5), dt
        real(wp), intent(inout) :: s(5)
        real(wp), intent(out) :: dzz
        real(wp) :: lam, mu, d(1, 6), sg(1, 6), ep(1), al(1, 6), z0, z1, f0, f1, z2
        integer :: it, p
        p = sh%part(e)
        mu = sh%pc%ge(p)
        lam = sh%pc%e(p)*sh%pc%nu(p)/((1 + sh%pc%nu(p))*(1 - 2*sh%pc%nu(p)))
        z0 = -sh%pc%nu(p)/(1 - sh%pc%nu(p))*(dd(1) + dd(2))
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
            ep(1) = sh%epsp(is, ip)
            al(1, :) = sh%alpha(:, ip, is)
            call plastic_update(1, lam, mu, sh%pp(sh%pc%mix(p)), d, dt, sg, ep, al)
        end subroutine trial
        subroutine commit(dz)
            real(wp), intent(in) :: dz
            dzz = dz
            call trial(dz)
            s = [sg(1, 1), sg(1, 2), sg(1, 4), sg(1, 5), sg(1, 6)]
            sh%epsp(is, ip) = ep(1)
            sh%alpha(:, ip, is) = al(1, :)
        end subroutine commit
    end subroutine mixed_return

    !> Plane-stress J2 return with isotropic hardening (Simo & Taylor 1986)
    !> of the ny points iy(1:ny) of layer ip of a block (elements e0 + iy),
    !> rate factors fy: their values packed (gathered) for return_newton,
    !> the returned stresses put back. t: the trial stresses in, the
    !> returned ones out; so the stresses before the step; dzz the
    !> thickness strain rates; anycur: some shell of the block takes its
    !> yield from a curve.
    subroutine plane_stress_returns(sh, e0, s0, ip, ny, iy, fy, anycur, dt, so, t, dzz)
        type(shells_t), intent(inout) :: sh
        integer, intent(in) :: e0, ip, ny, iy(:)
        integer, intent(in) :: s0       !< the block's points' state: rows s0 + 1 ..
        real(wp), intent(in) :: fy(:), dt, so(nblk, 5)
        logical, intent(in) :: anycur
        real(wp), intent(inout) :: t(nblk, 5), dzz(nblk)
        real(wp) :: c1(nblk), c2(nblk), a1(nblk), a2(nblk), q1(nblk), rr(nblk), dg(nblk), u1(nblk), u2(nblk)
        real(wp) :: de(nblk), ep0(nblk), sy0(nblk), hk(nblk), act(nblk)
        real(wp) :: s1, s2, sold
        integer :: el(nblk), j, l, k
        do j = 1, ny
            l = iy(j)
            el(j) = e0 + l
            ep0(j) = sh%epsp(s0 + l, ip)
            ! the law's constants held per point for the iteration (read
            ! through sh at every step, the tubes' run took 3.6% longer)
            k = sh%part(e0 + l)
            sy0(j) = sh%pc%sy0(k)
            hk(j) = sh%pc%hk(k)
            c1(j) = sh%pc%cbi(k)
            c2(j) = 2*sh%pc%ge(k)     ! E / (1 + nu), exactly
            call split_modes(t(l, 1), t(l, 2), t(l, 3), t(l, 4), t(l, 5), a1(j), a2(j), q1(j), rr(j))
            act(j) = 1
        end do
        call return_newton(sh, ny, el, c1, c2, q1, rr, sy0, hk, ep0, fy, act, anycur, dg, u1, u2, de)
        do j = 1, ny
            l = iy(j)
            call join_modes(a1(j), a2(j), u1(j), u2(j), s1, s2)
            t(l, 1) = s1
            t(l, 2) = s2
            t(l, 3) = t(l, 3)*u2(j)
            t(l, 4) = t(l, 4)*u2(j)
            t(l, 5) = t(l, 5)*u2(j)
            sh%epsp(s0 + l, ip) = ep0(j) + de(j)
        end do
        ! the thickness strain rate, only where the thickness follows it
        ! (ISTUPD): otherwise no one reads it
        if (sh%thickness_update) then
            do j = 1, ny
                l = iy(j)
                s1 = t(l, 1)
                s2 = t(l, 2)
                sold = so(l, 1) + so(l, 2)
                dzz(l) = (sh%pc%nue(sh%part(e0 + l))*(s1 + s2 - sold) - dg(j)*(s1 + s2)*third)/dt
            end do
        end if
    end subroutine plane_stress_returns

    !> The same return on every point of layer ip of a block of nb plastic
    !> shells without a back stress or a rate, yl 1 where the point yields
    !> and 0 where it stays elastic: no gather and no scatter (the element
    !> values read and written in place), the elastic points carried
    !> through the iteration at dg = 0 and their trial stresses kept. Taken
    !> where most of a layer yields (in a crush): the 10 x 10 tubes' returns'
    !> packing and unpacking had been two fifths of their cost. ep: the
    !> points' plastic strains before the step.
    subroutine dense_returns(sh, e0, s0, nb, ip, yl, ep, anycur, dt, so, t, dzz)
        type(shells_t), intent(inout) :: sh
        integer, intent(in) :: e0, nb, ip
        integer, intent(in) :: s0       !< the block's points' state: rows s0 + 1 .. s0 + nb
        real(wp), intent(in) :: yl(nblk), ep(nblk), dt, so(nblk, 5)
        logical, intent(in) :: anycur
        real(wp), intent(inout) :: t(nblk, 5), dzz(nblk)
        real(wp) :: c2(nblk), a1(nblk), a2(nblk), q1(nblk), rr(nblk), dg(nblk), u1(nblk), u2(nblk)
        real(wp) :: de(nblk), fy(nblk), c1(nblk), sy0(nblk), hk(nblk)
        real(wp) :: s1, s2, sold
        integer :: el(nblk), l, k
        do l = 1, nb
            el(l) = e0 + l
            k = sh%part(e0 + l)
            c1(l) = sh%pc%cbi(k)
            c2(l) = 2*sh%pc%ge(k)
            sy0(l) = sh%pc%sy0(k)
            hk(l) = sh%pc%hk(k)
            call split_modes(t(l, 1), t(l, 2), t(l, 3), t(l, 4), t(l, 5), a1(l), a2(l), q1(l), rr(l))
            fy(l) = 1
        end do
        call return_newton(sh, nb, el, c1, c2, q1, rr, sy0, hk, ep, fy, yl, anycur, dg, u1, u2, de)
        ! (the same operations as plane_stress_returns' on a yielding
        ! point: the same values. An elastic point has dg = 0, u1 = u2 =
        ! 1 and de = 0 exactly: its shears and plastic strain come out as
        ! they were; its normal stresses are kept by the weights yl and 1
        ! - yl, 1 and 0, exact. (merge kept the loop scalar: a branch.)
        do l = 1, nb
            call join_modes(a1(l), a2(l), u1(l), u2(l), s1, s2)
            t(l, 1) = yl(l)*s1 + (1.0_wp - yl(l))*t(l, 1)
            t(l, 2) = yl(l)*s2 + (1.0_wp - yl(l))*t(l, 2)
            t(l, 3) = t(l, 3)*u2(l)
            t(l, 4) = t(l, 4)*u2(l)
            t(l, 5) = t(l, 5)*u2(l)
            sh%epsp(s0 + l, ip) = ep(l) + de(l)
        end do
        if (sh%thickness_update) then
            do l = 1, nb
                s1 = t(l, 1)
                s2 = t(l, 2)
                sold = so(l, 1) + so(l, 2)
                dzz(l) = yl(l)*((sh%pc%nue(sh%part(e0 + l))*(s1 + s2 - sold) - dg(l)*(s1 + s2)*third)/dt) + (1.0_wp - yl(l))*dzz(l)
            end do
        end if
    end subroutine dense_returns

    !> A plane-stress trial (xx yy xy and the transverse shears t1 .. t5)
    !> in the eigenmodes of the plane-stress projection: a1 = (t1 + t2) /
    !> sqrt 2 (equal biaxial), a2 = (t2 - t1) / sqrt 2, and the von Mises
    !> value's two parts q1 = a1^2 / 3 and rr = a2^2 + 2 (t3^2 + t4^2 +
    !> t5^2) (one copy for both returns: elemental, inlined in their loops).
    elemental subroutine split_modes(t1, t2, t3, t4, t5, a1, a2, q1, rr)
        real(wp), intent(in) :: t1, t2, t3, t4, t5
        real(wp), intent(out) :: a1, a2, q1, rr
        ! (constant divisions as products: a quotient is a division
        ! instruction even by a constant)
        a1 = (t1 + t2)*rr2
        a2 = (t2 - t1)*rr2
        q1 = a1*a1*third
        rr = a2*a2 + 2.0_wp*(t3**2 + t4**2 + t5**2)
    end subroutine split_modes

    !> The returned normal stresses s1 (xx), s2 (yy) from the modes a1, a2
    !> scaled by the return's factors u1, u2.
    elemental subroutine join_modes(a1, a2, u1, u2, s1, s2)
        real(wp), intent(in) :: a1, a2, u1, u2
        real(wp), intent(out) :: s1, s2
        s1 = (a1*u1 - a2*u2)*rr2
        s2 = (a1*u1 + a2*u2)*rr2
    end subroutine join_modes

    !> The plane-stress return's iteration on n points (elements el), from
    !> their elastic trials in the eigenbasis of the plane-stress projection
    !> P: q1 = a1^2 / 3 (the equal-biaxial mode, modulus c1 = E / 3(1 -
    !> nu)) and rr (the shear modes', in-plane and transverse, modulus c2
    !> = 2 G). The backward-Euler return scales the first by u1 = 1/(1 +
    !> c1 dg) and the others by u2 = 1/(1 + c2 dg); the plastic multiplier
    !> dg solves 1/2 phi^2 = 1/3 (fy sy(ep0 + de))^2 with phi^2 = q1 u1^2 +
    !> rr u2^2 and de = sqrt(2/3) dg phi. The same state as the 3-D radial
    !> return with s_zz = 0 imposed, at a fraction of the cost. act: 1
    !> where the point yields, 0 where it is carried at dg = 0. Out: dg,
    !> u1, u2 and the plastic strain increment de.
    !> Every Newton step of all the points in loops that vectorise (one
    !> return after the other, each waited on itself, had been half of the
    !> crushing tubes' run): no branch per point; a point that has
    !> converged takes go = 0 and keeps its dg.
    subroutine return_newton(sh, n, el, c1, c2, q1, rr, sy0, hk, ep0, fy, act, anycur, dg, u1, u2, de)
        type(shells_t), intent(in) :: sh
        integer, intent(in) :: n, el(n)
        real(wp), intent(in) :: c1(n), c2(n), q1(n), rr(n), sy0(n), hk(n), ep0(n), fy(n), act(n)
        logical, intent(in) :: anycur
        real(wp), intent(out) :: dg(n), u1(n), u2(n), de(n)
        real(wp) :: phi2(nblk), phi(nblk), sy(nblk), h(nblk)
        !> 1 while a point iterates, 0 once it has converged (or its
        !> Newton step would climb: f' >= 0)
        real(wp) :: go(nblk)
        !> |f| at the pass before (at dg = 0 before the first step)
        real(wp) :: fp(nblk)
        real(wp) :: f, fac, dphi2, dgn, p1, p2, pq, ys, gg, gp, fpr
        integer :: j, it
        ! the first step: from the trial (dg = 0)
        do j = 1, n
            phi2(j) = q1(j) + rr(j)
            phi(j) = sqrt(phi2(j))
            sy(j) = sy0(j) + hk(j)*ep0(j)
            h(j) = hk(j)
            de(j) = 0
        end do
        if (anycur) then
            do j = 1, n
                if (sh%pc%ycurve(sh%part(el(j)))) call flow_stress(sh, el(j), ep0(j), sy(j), h(j))
            end do
        end if
        do j = 1, n
            fac = fy(j)
            f = 0.5_wp*phi2(j) - (fac*sy(j))**2*third
            go(j) = act(j)*(0.5_wp + sign(0.5_wp, abs(f) - tol12*phi2(j)))
            fp(j) = abs(f)
            ! phi taken as phi_tr / (1 + ce dg), ce = (q1 c1 + rr c2) /
            ! phi_tr^2 the modes' moduli weighted by their shares of the
            ! trial (exact for one mode, to first order in dg for both):
            ! the yield condition is then linear in ce dg; numerator and
            ! denominator times phi_tr^2, one division. (The bound only
            ! keeps an elastic point carried at dg = 0 finite; it leaves a
            ! yielding point's value as it is.)
            ys = c23*fac*sy(j)
            dg(j) = go(j)*((phi(j) - ys)*phi2(j)/ &
                           max(ys*(q1(j)*c1(j) + rr(j)*c2(j)) + c23*c23*fac*h(j)*phi(j)*phi2(j), tiny(1.0_wp)))
        end do
        ! Newton on the root of f(dg) = phi^2/2 - (fy sy)^2/3, taken on G
        ! below, converged on f
        do it = 2, 40
            ! (any active point, scanned from the first: a sum over the
            ! batch, taken in order without -ffast-math, waited on each
            ! add in turn)
            if (.not. any(go(1:n) /= 0.0_wp)) exit
            do j = 1, n
                ! (both factors from one division)
                p1 = 1.0_wp + c1(j)*dg(j)
                p2 = 1.0_wp + c2(j)*dg(j)
                pq = 1.0_wp/(p1*p2)
                u1(j) = p2*pq
                u2(j) = p1*pq
                phi2(j) = q1(j)*u1(j)*u1(j) + rr(j)*u2(j)*u2(j)
                phi(j) = sqrt(phi2(j))
                de(j) = c23*dg(j)*phi(j)
                sy(j) = sy0(j) + hk(j)*(ep0(j) + de(j))
            end do
            if (anycur) then
                ! (h is hk but on a curve, whose points' slopes move)
                h(1:n) = hk(1:n)
                do j = 1, n
                    if (sh%pc%ycurve(sh%part(el(j)))) call flow_stress(sh, el(j), ep0(j) + de(j), sy(j), h(j))
                end do
            end if
            do j = 1, n
                fac = fy(j)
                f = 0.5_wp*phi2(j) - (fac*sy(j))**2*third
                dphi2 = -2.0_wp*(q1(j)*c1(j)*u1(j)**3 + rr(j)*c2(j)*u2(j)**3)
                ! Newton on G = 1/phi - 1/Y, Y = c23 fy sy, nearly linear in
                ! dg (1/phi is linear in it where one family of modes
                ! carries the stress): three steps where f's took four. G'
                ! > 0 where f' < 0. G and G' both times 2 phi^3 Y^2 > 0
                ! (with phi' = phi2' / (2 phi)), so that the step G / G' is
                ! one division, not four:
                !   G K = 2 phi^2 Y (Y - phi)
                !   G' K = (2/3) fy h phi^2 (2 phi^2 + dg phi2') - phi2' Y^2
                ys = c23*fac*sy(j)
                gg = 2.0_wp*phi2(j)*ys*(ys - phi(j))
                gp = c23*c23*fac*h(j)*phi2(j)*(2.0_wp*phi2(j) + dg(j)*dphi2) - dphi2*ys*ys
                ! go stays 1 while |f| > tol12 phi^2 and G' > 0 (the
                ! signs' factors: a comparison would be a branch; G' = +0
                ! stops too)
                go(j) = go(j)*(0.5_wp + sign(0.5_wp, abs(f) - tol12*phi2(j)))*(0.5_wp + sign(0.5_wp, gp - tiny(1.0_wp)))
                dgn = max(dg(j) - gg/max(gp, tiny(1.0_wp)), 0.5_wp*dg(j))
                dg(j) = go(j)*dgn + (1.0_wp - go(j))*dg(j)
                ! Newton's residuals fall quadratically, |f'| ~ |f|^2 /
                ! |f-|: where that forecast of the step just taken is
                ! below a hundredth of the tolerance, the point stops
                ! without a pass to check it (a pass of two divisions and
                ! a root; the 10 x 10 tubes' points converged at their
                ! third step, which the pass after each one checked); in
                ! products, not quotients: |f|^3 <= tol12 phi^2 f-^2 / 100
                fpr = abs(f)**3 - 0.01_wp*tol12*phi2(j)*fp(j)**2
                fp(j) = abs(f)
                go(j) = go(j)*(0.5_wp + sign(0.5_wp, fpr))
            end do
        end do
        ! u1, u2 and de at the last dg (the step of a point stopped by the
        ! forecast has not been evaluated)
        do j = 1, n
            p1 = 1.0_wp + c1(j)*dg(j)
            p2 = 1.0_wp + c2(j)*dg(j)
            pq = 1.0_wp/(p1*p2)
            u1(j) = p2*pq
            u2(j) = p1*pq
            de(j) = c23*dg(j)*sqrt(q1(j)*u1(j)*u1(j) + rr(j)*u2(j)*u2(j))
        end do
    end subroutine return_newton

    !> The corotational frame of shell e on coordinates x, as the element
    !> loop takes it (block_geometry): the columns of r are e1 (along side
    !> 1-2), e2 and e3 (the normal).
    subroutine shell_axes(sh, e, x, r)
        type(shells_t), intent(in) :: sh
        integer, intent(in) :: e
        real(wp), intent(in) :: x(:, :)
        real(wp), intent(out) :: r(3, 3)
        type(block_geom_t) :: g
        integer :: k
        do k = 1, 4
            g%xe(1, :, k) = x(:, sh%conn(k, e))
        end do
        call block_geometry(sh, e - 1, 1, g)
        r(:, 1) = g%e1(1, :)
        r(:, 2) = g%e2(1, :)
        r(:, 3) = g%e3(1, :)
    end subroutine shell_axes


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


    !> 'shell 7 of part 2': shell e as the deck names it.
    function shell_name(model, sh, e) result(txt)
        type(model_t), intent(in) :: model
        type(shells_t), intent(in) :: sh
        integer, intent(in) :: e
        character(len=:), allocatable :: txt
        txt = 'shell '//itoa(sh%eid(e))//' of part '//itoa(model%part(sh%part(e))%id)
    end function shell_name

end module xd_elements_shell_bt
