!> Solid elements in groups of one part (so one material, one formulation),
!> at most `group_size` elements each; element state as structure of arrays.
!> `solid_forces` runs every group (OpenMP over groups) and writes each
!> element's nodal forces into its own slots; the nodal sum is done later in
!> a fixed order, so results do not depend on the thread count.
module xd_elements_solid_groups
    use xd_kinds, only: wp, dp
    use xd_core_memory, only: alloc, alloc_dp
    use xd_core_sorting, only: sort_index
    use xd_model, only: model_t, mat_elastic
    use xd_elements_hex8, only: hex_b_matrix, hex_velocity_gradient, hex_stress_forces, &
                                hex_hourglass_shape, hex_hourglass_rates, hex_char_length
    use xd_materials_elastic, only: elastic_update, jaumann_rotate
    implicit none
    private
    public :: solids_t, solid_group_t, build_solids, solid_forces, group_size, hg_viscous, hg_stiffness

    integer, parameter :: group_size = 64
    integer, parameter :: hg_viscous = 1, hg_stiffness = 2

    type :: solid_group_t
        integer :: first = 0, last = 0    !< element range (solids order)
        integer :: part = 0               !< part index
        integer :: mtype = 0              !< material type
        real(wp) :: ro = 0, lam = 0, mu = 0
        integer :: hg_form = hg_viscous
        real(wp) :: qm = 0.1_wp
        real(wp) :: q1 = 1.5_wp, q2 = 0.06_wp
    end type solid_group_t

    type :: solids_t
        integer :: n = 0, ngroup = 0
        type(solid_group_t), allocatable :: group(:)
        integer, allocatable :: conn(:, :)     !< (8, n) node indices
        integer, allocatable :: eid(:)         !< user id
        integer, allocatable :: part(:)        !< part index
        integer, allocatable :: model_ix(:)    !< index in the model's element list
        real(wp), allocatable :: sig(:, :)     !< (6, n) Cauchy stress, xx yy zz xy yz zx
        real(wp), allocatable :: vol0(:)       !< initial volume
        real(wp), allocatable :: vol(:)        !< current volume
        real(wp), allocatable :: qhg(:, :, :)  !< (3, 4, n) hourglass generalized forces (stiffness:
                                               !< the state; viscous: last step's, for the energy)
        real(wp), allocatable :: qbv(:)        !< bulk viscosity pressure of the last step
        real(dp), allocatable :: eint(:)       !< internal energy (incl. bulk viscosity work)
        real(dp), allocatable :: ehg(:)        !< hourglass energy
        real(wp), allocatable :: fslot(:, :)   !< (3, 8n) force on each element-node incidence
        real(wp), allocatable :: gdt(:)        !< per group: smallest element time step
        integer, allocatable :: gcrit(:)       !< per group: element that sets it
        integer, allocatable :: gbad(:)        !< per group: first element with volume <= 0
    end type solids_t

contains

    !> Order elements by part (stable), cut into groups, set material constants.
    subroutine build_solids(model, s)
        type(model_t), intent(in) :: model
        type(solids_t), intent(out) :: s
        integer, allocatable :: perm(:)
        integer :: e, k, g, first, p, ihq
        real(wp) :: e_mod, nu
        s%n = model%nhex
        if (s%n == 0) return
        call sort_index(model%hex_part(1:s%n), perm)
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
        call alloc(s%sig, 6, s%n, 'solid stresses')
        call alloc(s%vol0, s%n, 'solid volumes')
        call alloc(s%vol, s%n, 'solid volumes')
        call alloc_dp(s%eint, s%n, 'solid internal energies')
        call alloc_dp(s%ehg, s%n, 'solid hourglass energies')
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
        if (any(s%group%qm > 0.0_wp)) call alloc(s%qhg, 3, 4, s%n, 'hourglass forces')
        call alloc(s%qbv, s%n, 'bulk viscosity')
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

    !> Internal forces of every solid for positions x and velocities v (the
    !> half-step velocity that acted over the last step dt). Updates stresses,
    !> energies, volumes; writes force slots, group time steps and flags.
    subroutine solid_forces(s, x, v, dt)
        type(solids_t), intent(inout) :: s
        real(wp), contiguous, intent(in) :: x(:, :), v(:, :)
        real(wp), intent(in) :: dt
        integer :: g
        !$omp parallel do schedule(dynamic, 4) default(shared) private(g)
        do g = 1, s%ngroup
            call group_kernel(s, g, x, v, dt)
        end do
        !$omp end parallel do
    end subroutine solid_forces

    subroutine group_kernel(s, g, x, v, dt)
        type(solids_t), intent(inout) :: s
        integer, intent(in) :: g
        real(wp), contiguous, intent(in) :: x(:, :), v(:, :)
        real(wp), intent(in) :: dt
        integer :: n, a, b, i, j, k, e, nd
        real(wp), dimension(s%group(g)%last - s%group(g)%first + 1, 8) :: xl, yl, zl, vx, vy, vz, &
                                                                          bx, by, bz, fx, fy, fz, &
                                                                          gx, gy, gz
        real(wp) :: vol(s%group(g)%last - s%group(g)%first + 1), volh(size(vol))
        real(wp) :: d(size(vol), 6), w(size(vol), 3), sold(6, size(vol))
        real(wp) :: q(size(vol)), rho(size(vol)), c(size(vol)), le(size(vol)), dte(size(vol))
        real(wp) :: gam(size(vol), 8, 4), h(size(vol), 3, 4), fh(size(vol), 3, 4)
        real(wp) :: tr, pw
        type(solid_group_t) :: gr

        gr = s%group(g)
        a = gr%first
        b = gr%last
        n = b - a + 1
        do k = 1, 8
            do i = 1, n
                nd = s%conn(k, a + i - 1)
                xl(i, k) = x(1, nd); yl(i, k) = x(2, nd); zl(i, k) = x(3, nd)
                vx(i, k) = v(1, nd); vy(i, k) = v(2, nd); vz(i, k) = v(3, nd)
            end do
        end do
        call hex_b_matrix(n, xl, yl, zl, bx, by, bz, vol)
        s%gbad(g) = 0
        do i = n, 1, -1
            if (.not. (vol(i) > 0.0_wp)) s%gbad(g) = a + i - 1
        end do
        if (s%gbad(g) /= 0) then
            s%gdt(g) = huge(1.0_wp)
            s%gcrit(g) = a
            return
        end if
        s%vol(a:b) = vol
        ! strain rate and spin on the mid-step geometry x - dt/2 v, where the
        ! half-step velocity belongs: a rigid rotation then gives no strain
        fx = xl - 0.5_wp*dt*vx
        fy = yl - 0.5_wp*dt*vy
        fz = zl - 0.5_wp*dt*vz
        call hex_b_matrix(n, fx, fy, fz, gx, gy, gz, volh)
        call hex_velocity_gradient(n, vx, vy, vz, gx, gy, gz, volh, d, w)

        ! constitutive update (one material per group)
        sold = s%sig(:, a:b)
        select case (gr%mtype)
        case (mat_elastic)
            call jaumann_rotate(n, w, dt, s%sig(:, a:b))
            call elastic_update(n, gr%lam, gr%mu, d, dt, s%sig(:, a:b))
        end select

        ! bulk viscosity and internal energy: the work of the stress and of the
        ! bulk viscosity over the step, trapezoidal in time (old and new values),
        ! which is exactly the work their nodal forces do in central differences
        do i = 1, n
            rho(i) = gr%ro*s%vol0(a + i - 1)/vol(i)
            c(i) = sqrt((gr%lam + 2.0_wp*gr%mu)/rho(i))
        end do
        call hex_char_length(n, xl, yl, zl, vol, le)
        do i = 1, n
            e = a + i - 1
            tr = d(i, 1) + d(i, 2) + d(i, 3)
            q(i) = 0.0_wp
            if (tr < 0.0_wp) q(i) = rho(i)*le(i)*(gr%q1*le(i)*tr*tr - gr%q2*c(i)*tr)
            pw = 0.5_wp*((sold(1, i) + s%sig(1, e))*d(i, 1) + (sold(2, i) + s%sig(2, e))*d(i, 2) &
                         + (sold(3, i) + s%sig(3, e))*d(i, 3)) &
                 + (sold(4, i) + s%sig(4, e))*d(i, 4) + (sold(5, i) + s%sig(5, e))*d(i, 5) &
                 + (sold(6, i) + s%sig(6, e))*d(i, 6) - 0.5_wp*(s%qbv(e) + q(i))*tr
            s%qbv(e) = q(i)
            s%eint(e) = s%eint(e) + real(pw*volh(i)*dt, dp)
            ! element time step with the bulk viscosity's reduction
            if (tr < 0.0_wp) then
                tr = gr%q1*le(i)*abs(tr) + gr%q2*c(i)
            else
                tr = 0.0_wp
            end if
            dte(i) = le(i)/(tr + sqrt(tr*tr + c(i)*c(i)))
        end do
        call hex_stress_forces(n, s%sig(:, a:b), q, bx, by, bz, fx, fy, fz)

        ! Flanagan-Belytschko hourglass control
        if (gr%qm > 0.0_wp) then
            call hex_hourglass_shape(n, xl, yl, zl, bx, by, bz, vol, gam)
            call hex_hourglass_rates(n, vx, vy, vz, gam, h)
            if (gr%hg_form == hg_viscous) then
                ! viscous form: force ah h, ah = QM rho c V^(2/3) / 4
                do i = 1, n
                    c(i) = gr%qm*rho(i)*c(i)*vol(i)**(2.0_wp/3.0_wp)/4.0_wp
                end do
                do k = 1, 4
                    do j = 1, 3
                        fh(:, j, k) = c*h(:, j, k)
                    end do
                end do
            else
                ! stiffness form: rotate the stored forces with the element,
                ! then add the increment k h dt, k = QM (lambda + 2 mu) B.B / (12 V)
                do i = 1, n
                    c(i) = dt*gr%qm*(gr%lam + 2.0_wp*gr%mu)*(sum(bx(i, :)**2) + sum(by(i, :)**2) &
                                                             + sum(bz(i, :)**2))/(12.0_wp*vol(i))
                end do
                do k = 1, 4
                    fh(:, 1, k) = s%qhg(1, k, a:b) + dt*(w(:, 1)*s%qhg(2, k, a:b) - w(:, 3)*s%qhg(3, k, a:b)) &
                                  + c*h(:, 1, k)
                    fh(:, 2, k) = s%qhg(2, k, a:b) + dt*(w(:, 2)*s%qhg(3, k, a:b) - w(:, 1)*s%qhg(1, k, a:b)) &
                                  + c*h(:, 2, k)
                    fh(:, 3, k) = s%qhg(3, k, a:b) + dt*(w(:, 3)*s%qhg(1, k, a:b) - w(:, 2)*s%qhg(2, k, a:b)) &
                                  + c*h(:, 3, k)
                end do
            end if
            ! hourglass work over the step, trapezoidal in the old and new forces
            do i = 1, n
                e = a + i - 1
                s%ehg(e) = s%ehg(e) + real(0.5_wp*dt*sum((s%qhg(:, :, e) + fh(i, :, :))*h(i, :, :)), dp)
                s%qhg(:, :, e) = fh(i, :, :)
            end do
            do k = 1, 8
                do i = 1, n
                    fx(i, k) = fx(i, k) - (fh(i, 1, 1)*gam(i, k, 1) + fh(i, 1, 2)*gam(i, k, 2) &
                                           + fh(i, 1, 3)*gam(i, k, 3) + fh(i, 1, 4)*gam(i, k, 4))
                    fy(i, k) = fy(i, k) - (fh(i, 2, 1)*gam(i, k, 1) + fh(i, 2, 2)*gam(i, k, 2) &
                                           + fh(i, 2, 3)*gam(i, k, 3) + fh(i, 2, 4)*gam(i, k, 4))
                    fz(i, k) = fz(i, k) - (fh(i, 3, 1)*gam(i, k, 1) + fh(i, 3, 2)*gam(i, k, 2) &
                                           + fh(i, 3, 3)*gam(i, k, 3) + fh(i, 3, 4)*gam(i, k, 4))
                end do
            end do
        end if

        do i = 1, n
            e = a + i - 1
            do k = 1, 8
                s%fslot(1, 8*(e - 1) + k) = fx(i, k)
                s%fslot(2, 8*(e - 1) + k) = fy(i, k)
                s%fslot(3, 8*(e - 1) + k) = fz(i, k)
            end do
        end do
        k = minloc(dte, 1)
        s%gdt(g) = dte(k)
        s%gcrit(g) = a + k - 1
        ! a NaN anywhere (a velocity gone bad) is flagged as a negative step
        do i = 1, n
            if (.not. (dte(i) == dte(i))) then
                s%gdt(g) = -1.0_wp
                s%gcrit(g) = a + i - 1
                exit
            end if
        end do
    end subroutine group_kernel

end module xd_elements_solid_groups
