!> Solid elements in groups of one part (so one material, one formulation),
!> at most `group_size` elements each; element state as structure of arrays.
!> `solid_forces` runs every group (OpenMP over groups) and writes each
!> element's nodal forces into its own slots; the nodal sum is done later in
!> a fixed order, so results do not depend on the thread count.
module xd_elements_solid_groups
    use xd_kinds, only: wp, dp, i8
    use xd_core_memory, only: alloc, alloc_dp, nbytes
    use xd_core_sorting, only: sort_index
    use xd_core_strings, only: itoa
    use xd_model, only: model_t, material_t, mat_elastic, mat_plastic_kinematic, mat_piecewise_linear, mat_rigid, can_erode
    use xd_elements_hex8, only: hex_b_matrix, hex_velocity_gradient, hex_stress_forces, &
                                hex_hourglass_modes, hex_hourglass_forces, hex_char_length
    use xd_materials_elastic, only: elastic_update, jaumann_rotate
    use xd_materials_plasticity, only: plastic_params_t, plastic_update
    implicit none
    private
    public :: solids_t, solid_group_t, build_solids, solid_localize, solid_state_bytes, solid_bytes, solid_forces, group_size, &
              hg_viscous, hg_stiffness
    public :: material_plastic_law, stiff_volume_parts, solid_name

    integer, parameter :: group_size = 128
    integer, parameter :: hg_viscous = 1, hg_stiffness = 2

    type :: solid_group_t
        integer :: first = 0, last = 0    !< element range (solids order)
        integer :: part = 0               !< part index
        integer :: mtype = 0              !< material type
        real(wp) :: ro = 0, lam = 0, mu = 0
        integer :: hg_form = hg_viscous
        real(wp) :: qm = 0.1_wp
        real(wp) :: q1 = 1.5_wp, q2 = 0.06_wp
        real(wp) :: dt_scale = 1.0_wp       !< element steps scaled down (free corners of nearly incompressible parts)
        type(plastic_params_t) :: pp        !< plastic materials
    end type solid_group_t

    type :: solids_t
        integer :: n = 0, ngroup = 0
        type(solid_group_t), allocatable :: group(:)
        integer, allocatable :: conn(:, :)     !< (8, n) node indices
        integer, allocatable :: eid(:)         !< user id
        integer, allocatable :: part(:)        !< part index
        integer, allocatable :: model_ix(:)    !< index in the model's element list
        ! element state is blocked by group: group g holds the (m, 6) block of its
        ! m elements at offset 6*(first-1), so kernels see contiguous arrays
        !> The state (sig, vol, qhg, qbv, epsp, alpha) is held for this
        !> rank's groups alone (issue 32): group g's rows are goff(g) + 1 ..
        !> goff(g) + m, its blocks at goff(g) times their width, its groups in
        !> order (solid_localize); one rank, every group's, goff(g) = first -
        !> 1. nl rows in all; `local` once localized (MPI). Rank 0 takes
        !> every group's, gathered, for the time of an output.
        integer :: nl = 0
        integer, allocatable :: goff(:)
        logical :: local = .false.
        logical :: plastic_state = .false.    !< epsp and alpha are kept (some group is plastic)
        logical :: viewing = .false.
        real(wp), allocatable :: own_sig(:), own_vol(:), own_qhg(:), own_qbv(:), own_epsp(:), own_alpha(:)
        integer, allocatable :: own_goff(:)
        real(wp), allocatable :: sig(:)        !< Cauchy stress, xx yy zz xy yz zx
        real(wp), allocatable :: vol0(:)       !< initial volume
        real(wp), allocatable :: vol(:)        !< current volume
        real(wp), allocatable :: qhg(:)        !< (m, 3, 4) blocks: hourglass generalized forces (stiffness:
                                               !< the state; viscous: last step's, for the energy)
        real(wp), allocatable :: qbv(:)        !< bulk viscosity pressure of the last step
        real(wp), allocatable :: epsp(:)       !< effective plastic strain (size 0 without plastic parts)
        real(wp), allocatable :: alpha(:)      !< back stress, (m, 6) blocks like sig (size 0 without)
        real(dp), allocatable :: eint(:)       !< internal energy (incl. bulk viscosity work)
        real(dp), allocatable :: ehg(:)        !< hourglass energy
        ! the power of the current forces with v(n-1/2): half their work over
        ! the coming velocity update, weighted by its step once it is known
        real(dp), allocatable :: pend_int(:), pend_hg(:)
        !> (3, 8n) force on each element-node incidence; with the state held
        !> locally (MPI), (3, 8 nl + nhalo): the rank's rows' slots, then the
        !> halo's received from the other ranks (domain's local_slots)
        real(wp), allocatable :: fslot(:, :)
        real(wp), allocatable :: gdt(:)        !< per group: smallest element time step
        integer, allocatable :: gcrit(:)       !< per group: element that sets it
        integer, allocatable :: gbad(:)        !< per group: first element with volume <= 0
        integer, allocatable :: group_of(:)    !< group of each element
        logical, allocatable :: active(:)      !< per group: computed here (MPI: this rank's)
        ! mass scaling (*CONTROL_TIMESTEP DT2MS), allocated only when it is on:
        ! an element's mass is msf times its own, so its step sqrt(msf) times
        real(wp), allocatable :: msf(:)       !< mass factor (1: the element's own mass)
        real(wp), allocatable :: ms_need(:)   !< this cycle's wanted factor (0: none wanted)
        real(wp) :: ms_target = 0             !< element step to be kept (0: no scaling this cycle)
        logical :: ms_all = .false.           !< every element brought to ms_target (positive DT2MS, cycle 0)
        ! erosion (a part's material with FAIL, FS or *MAT_ADD_EROSION):
        ! an eroded element is computed frozen, on the coordinates it
        ! had when it eroded and at rest (no strain rate, no spin: its
        ! state stays as it was), its forces and step not taken
        logical :: erodible = .false.          !< some solid can erode
        logical, allocatable :: dead(:)        !< eroded (size n where erodible, else 0)
        !> ERODE: the minimum step (0: none yet), and the elements whose step
        !> fell below it this cycle (size n where erodible)
        real(wp) :: tsmin = 0
        logical, allocatable :: low(:)
        integer :: ndead = 0
        integer, allocatable :: gdead(:)       !< per group: eroded elements in it
        real(wp), allocatable :: xfrozen(:, :, :)  !< (3, 8, n) an eroded element's nodes at erosion
    contains
        procedure :: stress => solid_stress
        procedure :: set_stress => solid_set_stress
        procedure :: row => solid_row
    end type solids_t

contains

    !> Order elements by part (stable), cut into groups, set material constants.
    subroutine build_solids(model, s)
        type(model_t), intent(in) :: model
        type(solids_t), intent(out) :: s
        integer, allocatable :: perm(:), key(:)
        integer :: e, k, g, first, p, ihq
        real(wp) :: e_mod, nu
        ! rigid parts are not deformable elements: they go last and are cut off
        allocate (key(model%nhex))
        do e = 1, model%nhex
            key(e) = model%hex_part(e)
            if (model%mat(model%part(key(e))%mat_ix)%mtype == mat_rigid) key(e) = huge(1)
        end do
        s%n = count(key /= huge(1))
        call sort_index(key, perm)
        if (s%n == 0) then
            allocate (s%group(0), s%conn(8, 0), s%part(0), s%eid(0), s%model_ix(0), s%vol0(0), s%vol(0), &
                      s%gdt(0), s%gcrit(0), s%gbad(0), s%fslot(3, 0), s%eint(0), s%ehg(0), s%pend_int(0), &
                      s%pend_hg(0), s%sig(0), s%qhg(0), s%qbv(0), s%epsp(0), s%alpha(0), s%group_of(0), &
                      s%active(0), s%gdead(0), s%dead(0), s%xfrozen(3, 8, 0), s%low(0), s%goff(0))
            return
        end if
        call alloc(s%conn, 8, s%n, 'solid connectivity')
        call alloc(s%eid, s%n, 'solid ids')
        call alloc(s%part, s%n, 'solid parts')
        call alloc(s%model_ix, s%n, 'solid order')
        do e = 1, s%n
            s%model_ix(e) = perm(e)
            s%conn(:, e) = model%hex_conn(:, perm(e))
            s%eid(e) = model%hex_id(perm(e))
            s%part(e) = model%hex_part(perm(e))
        end do
        call alloc(s%sig, 6*s%n, 'solid stresses')
        call alloc(s%vol0, s%n, 'solid volumes')
        call alloc(s%vol, s%n, 'solid volumes')
        call alloc_dp(s%eint, s%n, 'solid internal energies')
        call alloc_dp(s%ehg, s%n, 'solid hourglass energies')
        call alloc_dp(s%pend_int, s%n, 'solid energy rates')
        call alloc_dp(s%pend_hg, s%n, 'solid energy rates')
        call alloc(s%fslot, 3, 8*s%n, 'solid force slots')

        ! count groups, then fill them
        allocate (s%group(s%n/group_size + model%npart + 1))
        s%ngroup = 0
        first = 1
        do e = 1, s%n
            if (e == s%n) then
                call close_group(first, e)
            else if (s%part(e + 1) /= s%part(e) .or. e - first + 1 == group_size) then
                call close_group(first, e)
                first = e + 1
            end if
        end do
        s%group = s%group(1:s%ngroup)
        call alloc(s%gdt, s%ngroup, 'group time steps')
        call alloc(s%gcrit, s%ngroup, 'group time steps')
        call alloc(s%gbad, s%ngroup, 'group flags')
        call alloc(s%qhg, 12*s%n, 'hourglass forces')
        call alloc(s%group_of, s%n, 'element groups')
        allocate (s%active(s%ngroup))
        s%active = .true.
        do g = 1, s%ngroup
            s%group_of(s%group(g)%first:s%group(g)%last) = g
        end do
        s%nl = s%n
        s%goff = s%group(:)%first - 1
        call alloc(s%qbv, s%n, 'bulk viscosity')
        allocate (s%gdead(s%ngroup))
        s%gdead = 0
        do g = 1, s%ngroup
            s%erodible = s%erodible .or. can_erode(model, model%part(s%group(g)%part)%mat_ix)
        end do
        if (s%erodible) then
            allocate (s%dead(s%n), s%low(s%n))
            call alloc(s%xfrozen, 3, 8, s%n, 'eroded solids'' coordinates')
            s%dead = .false.
            s%low = .false.
            s%xfrozen = 0
        else
            allocate (s%dead(0), s%xfrozen(3, 8, 0), s%low(0))
        end if
        if (any(s%group%mtype == mat_plastic_kinematic .or. s%group%mtype == mat_piecewise_linear)) then
            call alloc(s%epsp, s%n, 'plastic strains')
            call alloc(s%alpha, 6*s%n, 'back stresses')
            s%plastic_state = .true.
        else
            allocate (s%epsp(0), s%alpha(0))
        end if
    contains
        subroutine close_group(a, b)
            integer, intent(in) :: a, b
            s%ngroup = s%ngroup + 1
            g = s%ngroup
            p = s%part(a)
            s%group(g)%first = a
            s%group(g)%last = b
            s%group(g)%part = p
            associate (m => model%mat(model%part(p)%mat_ix))
                s%group(g)%mtype = m%mtype
                s%group(g)%ro = m%ro
                e_mod = m%e
                nu = m%pr
            end associate
            call plastic_params(model, model%mat(model%part(p)%mat_ix), s%group(g)%pp)
            s%group(g)%lam = e_mod*nu/((1.0_wp + nu)*(1.0_wp - 2.0_wp*nu))
            s%group(g)%mu = e_mod/(2.0_wp*(1.0_wp + nu))
            ihq = model%ctl%ihq
            s%group(g)%qm = model%ctl%qh
            s%group(g)%q1 = model%ctl%q1
            s%group(g)%q2 = model%ctl%q2
            k = model%part(p)%hg_ix
            if (k > 0) then
                if (model%hg(k)%ihq > 0) ihq = model%hg(k)%ihq
                s%group(g)%qm = model%hg(k)%qm
                if (model%hg(k)%q1 > 0.0_wp) s%group(g)%q1 = model%hg(k)%q1
                if (model%hg(k)%q2 > 0.0_wp) s%group(g)%q2 = model%hg(k)%q2
            end if
            s%group(g)%hg_form = hg_viscous
            if (ihq >= 4) s%group(g)%hg_form = hg_stiffness
        end subroutine close_group
    end subroutine build_solids

    !> Yield law of a plastic material: LCSS curve, else the EPS/ES table, else
    !> the bilinear SIGY, ETAN (plastic modulus E Et / (E - Et)).
    subroutine plastic_params(model, m, pp)
        type(model_t), intent(in) :: model
        type(material_t), intent(in) :: m
        type(plastic_params_t), intent(out) :: pp
        pp%sigy = m%sigy
        pp%ep = m%e*m%etan/(m%e - m%etan)
        pp%beta = m%beta
        pp%c = m%c
        pp%p = m%p
        if (m%mtype == mat_piecewise_linear) then
            pp%beta = 1.0_wp
            if (m%lcss_ix > 0) then
                pp%ncurve = model%curve(m%lcss_ix)%n
                pp%eps = model%curve(m%lcss_ix)%a
                pp%sy = model%curve(m%lcss_ix)%o
            else if (m%ntab > 0) then
                pp%ncurve = m%ntab
                pp%eps = m%eps(1:m%ntab)
                pp%sy = m%es(1:m%ntab)
            end if
        end if
    end subroutine plastic_params

    !> The plastic law of material mix (for the shells).
    subroutine material_plastic_law(model, mix, pp)
        type(model_t), intent(in) :: model
        integer, intent(in) :: mix
        type(plastic_params_t), intent(out) :: pp
        call plastic_params(model, model%mat(mix), pp)
    end subroutine material_plastic_law

    !> Parts whose material is nearly incompressible (lambda > 50 mu, nu
    !> above 0.49) under viscous hourglass control with QM above 0.01: their
    !> hourglass damping grows with the dilatational wave speed (a nu 0.4999
    !> block bouncing off a rigid wall for 3 ms put 25% of its energy into
    !> hourglass work at QM 0.1, 1% under IHQ 4). Returns the part indices
    !> (each once).
    function stiff_volume_parts(s) result(parts)
        type(solids_t), intent(in) :: s
        integer, allocatable :: parts(:)
        integer :: g
        allocate (parts(0))
        do g = 1, s%ngroup
            associate (gr => s%group(g))
                if (gr%hg_form /= hg_viscous .or. gr%qm <= 0.01_wp .or. gr%lam <= 50.0_wp*gr%mu) cycle
                if (any(parts == gr%part)) cycle
                parts = [parts, gr%part]
            end associate
        end do
    end function stiff_volume_parts

    !> Stress (xx yy zz xy yz zx) of element e.
    pure function solid_stress(s, e) result(sg)
        class(solids_t), intent(in) :: s
        integer, intent(in) :: e
        real(wp) :: sg(6)
        integer :: g, m, a
        g = s%group_of(e)
        a = s%group(g)%first
        m = s%group(g)%last - a + 1
        sg = s%sig(6*s%goff(g) + (e - a + 1) + m*[0, 1, 2, 3, 4, 5])
    end function solid_stress

    !> Element e's row of the state held here (vol, qbv, epsp; its group's).
    pure integer function solid_row(s, e) result(i)
        class(solids_t), intent(in) :: s
        integer, intent(in) :: e
        integer :: g
        g = s%group_of(e)
        i = s%goff(g) + e - s%group(g)%first + 1
    end function solid_row

    subroutine solid_set_stress(s, e, sg)
        class(solids_t), intent(inout) :: s
        integer, intent(in) :: e
        real(wp), intent(in) :: sg(6)
        integer :: g, m, a
        g = s%group_of(e)
        a = s%group(g)%first
        m = s%group(g)%last - a + 1
        s%sig(6*s%goff(g) + (e - a + 1) + m*[0, 1, 2, 3, 4, 5]) = sg
    end subroutine solid_set_stress

    !> The state (sig, vol, qhg, qbv, epsp, alpha) kept for this rank's
    !> groups (active) alone, in group order (issue 32): the rest of the
    !> arrays' memory goes. Values as they were (set up, or read from a
    !> dump).
    subroutine solid_localize(s)
        type(solids_t), intent(inout) :: s
        integer :: g, k
        if (s%local) error stop 'solid_localize: the state is local already'
        s%local = .true.
        k = 0
        do g = 1, s%ngroup
            if (.not. s%active(g)) then
                s%goff(g) = -1
                cycle
            end if
            s%goff(g) = k
            k = k + s%group(g)%last - s%group(g)%first + 1
        end do
        s%nl = k
        call keep(s%sig, 6)
        call keep(s%vol, 1)
        call keep(s%qhg, 12)
        call keep(s%qbv, 1)
        if (s%plastic_state) then
            call keep(s%epsp, 1)
            call keep(s%alpha, 6)
        end if
    contains
        !> a's blocks of the active groups (w values an element) in order
        subroutine keep(a, w)
            real(wp), allocatable, intent(inout) :: a(:)
            integer, intent(in) :: w
            real(wp), allocatable :: b(:)
            integer :: g, f, l
            allocate (b(w*s%nl))
            do g = 1, s%ngroup
                if (s%goff(g) < 0) cycle
                f = s%group(g)%first
                l = s%group(g)%last
                b(w*s%goff(g) + 1:w*(s%goff(g) + l - f + 1)) = a(w*(f - 1) + 1:w*l)
            end do
            call move_alloc(b, a)
        end subroutine keep
    end subroutine solid_localize

    !> The bytes of the state (sig, vol, qhg, qbv, epsp, alpha) and the
    !> force slots this rank holds: every solid's on one rank, its own
    !> groups' (and its halo's slots) on more.
    !> The bytes of every array of the solids this rank holds (the group
    !> records counted by their own size alone), outside an output's
    !> gathered view.
    integer(i8) function solid_bytes(s) result(b)
        type(solids_t), intent(in) :: s
        b = 0
        if (allocated(s%group)) b = b + size(s%group, kind=i8)*(storage_size(s%group, i8)/8)
        b = b + nbytes(s%conn) + nbytes(s%eid) + nbytes(s%part) + nbytes(s%model_ix) + nbytes(s%goff) &
            + nbytes(s%sig) + nbytes(s%vol0) + nbytes(s%vol) + nbytes(s%qhg) + nbytes(s%qbv) + nbytes(s%epsp) &
            + nbytes(s%alpha) + nbytes(s%eint) + nbytes(s%ehg) + nbytes(s%pend_int) + nbytes(s%pend_hg) &
            + nbytes(s%fslot) + nbytes(s%gdt) + nbytes(s%gcrit) + nbytes(s%gbad) + nbytes(s%group_of) &
            + nbytes(s%active) + nbytes(s%msf) + nbytes(s%ms_need) + nbytes(s%dead) + nbytes(s%low) &
            + nbytes(s%gdead) + nbytes(s%xfrozen)
    end function solid_bytes

    integer(i8) function solid_state_bytes(s, every) result(b)
        type(solids_t), intent(in) :: s
        !> every solid's, as one rank holds them
        logical, intent(in), optional :: every
        integer(i8) :: w
        b = 0
        if (s%n == 0) return
        ! (every array real(wp), allocated by build_solids)
        if (present(every)) then
            if (every) then
                ! an element's values: sig, vol, qhg, qbv, and epsp, alpha
                w = 6 + 1 + 12 + 1 + 3*8
                if (s%plastic_state) w = w + 1 + 6
                b = w*s%n*(storage_size(1.0_wp, i8)/8)
                return
            end if
        end if
        b = (size(s%sig, kind=i8) + size(s%vol, kind=i8) + size(s%qhg, kind=i8) + size(s%qbv, kind=i8) + &
             size(s%epsp, kind=i8) + size(s%alpha, kind=i8) + size(s%fslot, kind=i8))*(storage_size(1.0_wp, i8)/8)
    end function solid_state_bytes

    !> Internal forces of every solid for positions x and velocities v (the
    !> half-step velocity that acted over the last step dt). Updates stresses,
    !> energies, volumes; writes force slots, group time steps and flags.
    subroutine solid_forces(s, x, v, dt, dt_avg_prev)
        type(solids_t), intent(inout) :: s
        real(wp), contiguous, intent(in) :: x(:, :), v(:, :)
        real(wp), intent(in) :: dt            !< step just taken (the strain increment's)
        real(dp), intent(in) :: dt_avg_prev   !< step of the last velocity update
        integer :: g
        !$omp parallel do schedule(dynamic, 4) default(shared) private(g)
        do g = 1, s%ngroup
            if (s%active(g)) call group_kernel(s, g, x, v, dt, dt_avg_prev)
        end do
        !$omp end parallel do
    end subroutine solid_forces

    subroutine group_kernel(s, g, x, v, dt, dt_avg_prev)
        type(solids_t), intent(inout) :: s
        integer, intent(in) :: g
        real(wp), contiguous, intent(in) :: x(:, :), v(:, :)
        real(wp), intent(in) :: dt
        real(dp), intent(in) :: dt_avg_prev
        integer :: la, m
        ! (the group's rows of the state held here)
        la = s%goff(g)
        m = s%group(g)%last - s%group(g)%first + 1
        if (size(s%epsp) > 0) then
            call group_block(s, g, x, v, dt, dt_avg_prev, m, s%sig(6*la + 1:6*(la + m)), &
                             s%qhg(12*la + 1:12*(la + m)), s%alpha(6*la + 1:6*(la + m)), s%epsp(la + 1:la + m))
        else
            call group_block(s, g, x, v, dt, dt_avg_prev, m, s%sig(6*la + 1:6*(la + m)), &
                             s%qhg(12*la + 1:12*(la + m)), s%alpha, s%epsp)
        end if
    end subroutine group_kernel

    !> One group: sig and qhg are its contiguous blocks of element state.
    subroutine group_block(s, g, x, v, dt, dt_avg_prev, n, sig, qhg, alpha, epsp)
        type(solids_t), intent(inout) :: s
        integer, intent(in) :: g, n
        real(wp), contiguous, intent(in) :: x(:, :), v(:, :)
        real(wp), intent(in) :: dt
        real(dp), intent(in) :: dt_avg_prev
        real(wp), intent(inout) :: sig(n, 6), qhg(n, 3, 4)
        real(wp), contiguous, intent(inout) :: alpha(:), epsp(:)   !< size 0 for non-plastic models
        integer :: a, b, i, j, k, e, nd
        real(wp), dimension(n, 8) :: xl, yl, zl, vx, vy, vz, bx, by, bz, fx, fy, fz
        real(wp), dimension(n) :: vol, volh, q, rho, c, le, dte, tr, pw, qd
        real(wp) :: d(size(vol), 6), w(size(vol), 3), sold(size(vol), 6)
        real(wp) :: hx(size(vol), 3, 4), h(size(vol), 3, 4), fh(size(vol), 3, 4)
        type(solid_group_t) :: gr
        logical :: frozen
        real(wp) :: epold(n), alold(6*n)

        gr = s%group(g)
        a = gr%first
        b = gr%last
        do k = 1, 8
            do i = 1, n
                nd = s%conn(k, a + i - 1)
                xl(i, k) = x(1, nd); yl(i, k) = x(2, nd); zl(i, k) = x(3, nd)
                vx(i, k) = v(1, nd); vy(i, k) = v(2, nd); vz(i, k) = v(3, nd)
            end do
        end do
        ! an eroded element: on its coordinates at erosion, at rest
        frozen = s%gdead(g) > 0
        if (frozen) then
            do i = 1, n
                if (.not. s%dead(a + i - 1)) cycle
                xl(i, :) = s%xfrozen(1, :, a + i - 1)
                yl(i, :) = s%xfrozen(2, :, a + i - 1)
                zl(i, :) = s%xfrozen(3, :, a + i - 1)
                vx(i, :) = 0; vy(i, :) = 0; vz(i, :) = 0
            end do
            if (size(epsp) > 0) then
                epold = epsp(1:n)
                alold = alpha(1:6*n)
            end if
        end if

        ! strain rate and spin on the mid-step geometry x - dt/2 v, where the
        ! half-step velocity belongs: a rigid rotation then gives no strain
        fx = xl - (0.5_wp*dt)*vx
        fy = yl - (0.5_wp*dt)*vy
        fz = zl - (0.5_wp*dt)*vz
        call hex_b_matrix(n, fx, fy, fz, bx, by, bz, volh)
        call hex_velocity_gradient(n, vx, vy, vz, bx, by, bz, volh, d, w)
        ! forces, hourglass shapes and the time step on the end-of-step geometry
        call hex_b_matrix(n, xl, yl, zl, bx, by, bz, vol)
        s%gbad(g) = 0
        do i = n, 1, -1
            if (.not. (vol(i) > 0.0_wp .and. volh(i) > 0.0_wp)) s%gbad(g) = a + i - 1
        end do
        if (s%gbad(g) /= 0) then
            s%gdt(g) = huge(1.0_wp)
            s%gcrit(g) = a
            s%vol(s%goff(g) + 1:s%goff(g) + n) = vol
            return
        end if
        s%vol(s%goff(g) + 1:s%goff(g) + n) = vol

        ! constitutive update (one material per group)
        sold = sig
        select case (gr%mtype)
        case (mat_elastic)
            call jaumann_rotate(n, w, dt, sig)
            call elastic_update(n, gr%lam, gr%mu, d, dt, sig)
        case (mat_plastic_kinematic, mat_piecewise_linear)
            call jaumann_rotate(n, w, dt, sig)
            if (gr%pp%beta < 1.0_wp) call jaumann_rotate(n, w, dt, alpha)
            call plastic_update(n, gr%lam, gr%mu, gr%pp, d, dt, sig, epsp, alpha)
        end select

        ! bulk viscosity, and the internal energy: the nodal forces f(n) of an
        ! element do the work f(n) . (v(n-1/2) + v(n+1/2))/2 dt_avg(n), with
        ! dt_avg(n) the step of the velocity update at t(n); this is the work
        ! that central differences turn into kinetic energy, for constant and
        ! variable steps alike. Here, with D from v(n-1/2): the old forces'
        ! second half is completed with dt_avg(n-1), the new forces' first half
        ! waits for dt_avg(n).
        rho = gr%ro*s%vol0(a:b)/vol
        c = sqrt((gr%lam + 2.0_wp*gr%mu)/rho)
        call hex_char_length(n, xl, yl, zl, vol, le)
        tr = d(:, 1) + d(:, 2) + d(:, 3)
        q = merge(rho*le*(gr%q1*le*tr*tr - gr%q2*c*tr), 0.0_wp, tr < 0.0_wp)
        pw = 0.5_wp*(sold(:, 1)*d(:, 1) + sold(:, 2)*d(:, 2) + sold(:, 3)*d(:, 3) - s%qbv(s%goff(g) + 1:s%goff(g) + n)*tr) &
             + sold(:, 4)*d(:, 4) + sold(:, 5)*d(:, 5) + sold(:, 6)*d(:, 6)
        s%eint(a:b) = s%eint(a:b) + dt_avg_prev*(s%pend_int(a:b) + real(pw*volh, dp))
        pw = 0.5_wp*(sig(:, 1)*d(:, 1) + sig(:, 2)*d(:, 2) + sig(:, 3)*d(:, 3) - q*tr) &
             + sig(:, 4)*d(:, 4) + sig(:, 5)*d(:, 5) + sig(:, 6)*d(:, 6)
        s%pend_int(a:b) = real(pw*volh, dp)
        s%qbv(s%goff(g) + 1:s%goff(g) + n) = q
        ! element time step, reduced by the bulk viscosity in compression
        qd = merge(gr%q1*le*abs(tr) + gr%q2*c, 0.0_wp, tr < 0.0_wp)
        dte = gr%dt_scale*le/(qd + sqrt(qd*qd + c*c))
        call hex_stress_forces(n, sig, q, bx, by, bz, fx, fy, fz)

        ! Flanagan-Belytschko hourglass control
        if (gr%qm > 0.0_wp) then
            call hex_hourglass_modes(n, xl, yl, zl, vx, vy, vz, bx, by, bz, vol, hx, h)
            if (gr%hg_form == hg_viscous) then
                ! viscous form: force ah h, ah = QM rho c V^(2/3) / 4
                qd = gr%qm*0.25_wp*rho*c*vol**(2.0_wp/3.0_wp)
                do k = 1, 4
                    do j = 1, 3
                        fh(:, j, k) = qd*h(:, j, k)
                    end do
                end do
            else
                ! stiffness form: rotate the stored forces with the element,
                ! then add k h dt, k = QM (lambda + 2 mu) B.B / (12 V)
                qd = 0
                do k = 1, 8
                    qd = qd + bx(:, k)**2 + by(:, k)**2 + bz(:, k)**2
                end do
                qd = dt*gr%qm*(gr%lam + 2.0_wp*gr%mu)*qd/(12.0_wp*vol)
                do k = 1, 4
                    fh(:, 1, k) = qhg(:, 1, k) + dt*(w(:, 1)*qhg(:, 2, k) - w(:, 3)*qhg(:, 3, k)) &
                                  + qd*h(:, 1, k)
                    fh(:, 2, k) = qhg(:, 2, k) + dt*(w(:, 2)*qhg(:, 3, k) - w(:, 1)*qhg(:, 1, k)) &
                                  + qd*h(:, 2, k)
                    fh(:, 3, k) = qhg(:, 3, k) + dt*(w(:, 3)*qhg(:, 1, k) - w(:, 2)*qhg(:, 2, k)) &
                                  + qd*h(:, 3, k)
                end do
            end if
            ! hourglass work, booked as the internal energy above
            pw = 0
            q = 0
            do k = 1, 4
                do j = 1, 3
                    pw = pw + qhg(:, j, k)*h(:, j, k)
                    q = q + fh(:, j, k)*h(:, j, k)
                end do
            end do
            s%ehg(a:b) = s%ehg(a:b) + dt_avg_prev*(s%pend_hg(a:b) + real(0.5_wp*pw, dp))
            s%pend_hg(a:b) = real(0.5_wp*q, dp)
            qhg = fh
            call hex_hourglass_forces(n, fh, hx, bx, by, bz, vol, fx, fy, fz)
        end if

        if (frozen) then
            ! (at rest its strain rate and spin are 0 and its stress comes
            ! out as it was; one left on its yield surface could still take
            ! a return of round-off size, so its stress, plastic strain and
            ! back stress are put back as they were before the pass)
            do i = 1, n
                if (.not. s%dead(a + i - 1)) cycle
                fx(i, :) = 0; fy(i, :) = 0; fz(i, :) = 0
                sig(i, :) = sold(i, :)
                if (size(epsp) > 0) then
                    epsp(i) = epold(i)
                    do k = 0, 5
                        alpha(k*n + i) = alold(k*n + i)
                    end do
                end if
                dte(i) = huge(1.0_wp)
            end do
        end if
        do i = 1, n
            ! (the slots of the group's rows held here)
            e = 8*(s%goff(g) + i - 1)
            do k = 1, 8
                s%fslot(1, e + k) = fx(i, k)
                s%fslot(2, e + k) = fy(i, k)
                s%fslot(3, e + k) = fz(i, k)
            end do
        end do
        if (allocated(s%msf)) then
            ! mass scaling: the step of the element's scaled mass; one below
            ! the target asks for the factor that brings it there
            dte = dte*sqrt(s%msf(a:b))
            if (s%ms_target > 0.0_wp) then
                do i = 1, n
                    if (dte(i) > 0.0_wp .and. (dte(i) < s%ms_target .or. s%ms_all)) then
                        s%ms_need(a + i - 1) = s%msf(a + i - 1)*(s%ms_target/dte(i))**2
                        dte(i) = s%ms_target
                    end if
                end do
            end if
        end if
        if (s%tsmin > 0.0_wp) then
            ! ERODE: an element whose step fell below the minimum sets no
            ! step; it erodes after this pass (one already eroded is frozen,
            ! its step huge)
            do i = 1, n
                if (s%dead(a + i - 1)) cycle
                if (dte(i) < s%tsmin) then
                    s%low(a + i - 1) = .true.
                    dte(i) = huge(1.0_wp)
                end if
            end do
        end if
        k = minloc(dte, 1)
        s%gdt(g) = dte(k)
        s%gcrit(g) = a + k - 1
        ! a NaN anywhere (a velocity gone bad) is flagged as a negative step
        if (any(dte /= dte)) then
            s%gdt(g) = -1.0_wp
            s%gcrit(g) = a + findloc(dte /= dte, .true., 1) - 1
        end if
    end subroutine group_block

    !> 'solid 12 of part 3': solid e as the deck names it.
    function solid_name(model, solids, e) result(txt)
        type(model_t), intent(in) :: model
        type(solids_t), intent(in) :: solids
        integer, intent(in) :: e
        character(len=:), allocatable :: txt
        txt = 'solid '//itoa(solids%eid(e))//' of part '//itoa(model%part(solids%part(e))%id)
    end function solid_name

end module xd_elements_solid_groups
