!> External loads: body (base) accelerations from *LOAD_BODY_X/Y/Z and
!> the work they do.
module xd_solver_loads
    use xd_core_threads, only: threaded
    use xd_kinds, only: wp, dp
    use xd_core_dofs, only: free3
    use xd_model, only: model_t, curve_value
    use xd_solver_state, only: state_t
    use xd_core_vectors, only: cross
    use xd_core_comm, only: comm_sum_dp
    implicit none
    private
    public :: body_acceleration, add_body_forces, body_power
    public :: pressures_t, build_pressures, apply_pressures, pressure_power

    !> Loaded segments, flattened from *LOAD_SEGMENT and *LOAD_SEGMENT_SET.
    type :: pressures_t
        integer :: n = 0
        integer, allocatable :: seg(:, :)       !< (4, n) node indices (N3 = N4: triangle)
        integer, allocatable :: load(:)         !< its pressure entry
        real(wp), allocatable :: f(:, :, :)     !< (3, 4, n) nodal forces of this cycle
    end type pressures_t

contains

    !> Acceleration of the body loads at time t: a positive curve value loads
    !> in the negative axis direction (a base acceleration, as in LS-DYNA).
    pure function body_acceleration(model, t) result(g)
        type(model_t), intent(in) :: model
        real(wp), intent(in) :: t
        real(wp) :: g(3)
        integer :: i
        g = 0
        do i = 1, model%nbody
            associate (b => model%body(i))
                g = g - b%sf*curve_value(model%curve(b%curve_ix), t)*b%d
            end associate
        end do
    end function body_acceleration

    !> f += m g on every node.
    subroutine add_body_forces(st, g)
        type(state_t), intent(inout) :: st
        real(wp), intent(in) :: g(3)
        ! (a parallel region only where more than one thread runs it:
        ! xd_core_threads)
        if (threaded(st%nnode)) then
            !$omp parallel
            call body_force_loop(st, g)
            !$omp end parallel
        else
            call body_force_loop(st, g)
        end if
    end subroutine add_body_forces

    subroutine body_force_loop(st, g)
        type(state_t), intent(inout) :: st
        real(wp), intent(in) :: g(3)
        integer :: nd
        !$omp do schedule(static)
        do nd = 1, st%nnode
            st%f(:, nd) = st%f(:, nd) + st%mass(nd)*g
        end do
        !$omp end do
    end subroutine body_force_loop

    !> g . sum m v over the free directions: the power of a body load g.
    !> (mine: the nodes whose terms this rank sums, under owned nodes; the
    !> ranks' sums of mom are then added: comm_sum_dp)
    real(dp) function body_power(st, g, mine) result(p)
        type(state_t), intent(in) :: st
        real(wp), intent(in) :: g(3)
        logical, intent(in), optional :: mine(:)
        real(dp) :: mom(3)
        integer :: nd
        mom = 0
        do nd = 1, st%nnode
            if (present(mine)) then
                if (.not. mine(nd)) cycle
            end if
            mom = mom + st%mass(nd)*real(st%v(:, nd)*free3(st%dofs(nd)), dp)
        end do
        if (present(mine)) call comm_sum_dp(mom)
        p = dot_product(real(g, dp), mom)
    end function body_power

    subroutine build_pressures(model, pl)
        type(model_t), intent(in) :: model
        type(pressures_t), intent(out) :: pl
        integer :: i, k, m
        pl%n = 0
        do i = 1, model%npress
            if (model%press(i)%ssid == 0) then
                pl%n = pl%n + 1
            else
                do k = 1, model%nsegset
                    if (model%segset(k)%id == model%press(i)%ssid) pl%n = pl%n + model%segset(k)%n
                end do
            end if
        end do
        allocate (pl%seg(4, pl%n), pl%load(pl%n), pl%f(3, 4, pl%n))
        pl%f = 0
        m = 0
        do i = 1, model%npress
            if (model%press(i)%ssid == 0) then
                m = m + 1
                pl%seg(:, m) = model%press(i)%seg
                pl%load(m) = i
            else
                do k = 1, model%nsegset
                    if (model%segset(k)%id /= model%press(i)%ssid) cycle
                    pl%seg(:, m + 1:m + model%segset(k)%n) = model%segset(k)%seg
                    pl%load(m + 1:m + model%segset(k)%n) = i
                    m = m + model%segset(k)%n
                end do
            end if
        end do
    end subroutine build_pressures

    !> Pressure forces at t(n) on x(n), added to f: each node of a quad takes
    !> -p A n / 4 with A n = (x3 - x1) x (x4 - x2) / 2; a triangle's three nodes
    !> take a third each. Positive pressure pushes against the normal.
    subroutine apply_pressures(model, pl, st)
        type(model_t), intent(in) :: model
        type(pressures_t), intent(inout) :: pl
        type(state_t), intent(inout) :: st
        integer :: k, j
        real(wp) :: p, an(3), d1(3), d2(3), t
        t = real(st%time, wp)
        do k = 1, pl%n
            associate (pr => model%press(pl%load(k)), sg => pl%seg(:, k))
                pl%f(:, :, k) = 0
                if (t < pr%at) cycle
                p = pr%sf*curve_value(model%curve(pr%curve_ix), t - pr%at)
                if (sg(3) == sg(4)) then
                    d1 = st%x(:, sg(2)) - st%x(:, sg(1))
                    d2 = st%x(:, sg(3)) - st%x(:, sg(1))
                    an = real(0.5_dp*cross(real(d1, dp), real(d2, dp)), wp)
                    do j = 1, 3
                        pl%f(:, j, k) = -p*an/3.0_wp
                    end do
                else
                    d1 = st%x(:, sg(3)) - st%x(:, sg(1))
                    d2 = st%x(:, sg(4)) - st%x(:, sg(2))
                    an = real(0.5_dp*cross(real(d1, dp), real(d2, dp)), wp)
                    do j = 1, 4
                        pl%f(:, j, k) = -p*an/4.0_wp
                    end do
                end if
                do j = 1, 4
                    st%f(:, sg(j)) = st%f(:, sg(j)) + pl%f(:, j, k)
                end do
            end associate
        end do
    end subroutine apply_pressures

    !> Power of this cycle's pressure forces with the current velocities.
    real(dp) function pressure_power(pl, st) result(pw)
        type(pressures_t), intent(in) :: pl
        type(state_t), intent(in) :: st
        integer :: k, j
        pw = 0
        do k = 1, pl%n
            do j = 1, 4
                pw = pw + dot_product(real(pl%f(:, j, k), dp), real(st%v(:, pl%seg(j, k)), dp))
            end do
        end do
    end function pressure_power


end module xd_solver_loads
