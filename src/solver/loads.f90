!> External loads: body (base) accelerations from *LOAD_BODY_X/Y/Z and
!> the work they do.
module xd_solver_loads
    use xd_kinds, only: wp, dp
    use xd_model, only: model_t, curve_value
    use xd_solver_state, only: state_t
    implicit none
    private
    public :: body_acceleration, add_body_forces, body_power

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
                g(b%dir) = g(b%dir) - b%sf*curve_value(model%curve(b%curve_ix), t)
            end associate
        end do
    end function body_acceleration

    !> f += m g on every node.
    subroutine add_body_forces(st, g)
        type(state_t), intent(inout) :: st
        real(wp), intent(in) :: g(3)
        integer :: nd
        !$omp parallel do schedule(static)
        do nd = 1, st%nnode
            st%f(:, nd) = st%f(:, nd) + st%mass(nd)*g
        end do
        !$omp end parallel do
    end subroutine add_body_forces

    !> g . sum m v over the free directions: the power of a body load g.
    real(dp) function body_power(st, g) result(p)
        type(state_t), intent(in) :: st
        real(wp), intent(in) :: g(3)
        real(dp) :: mom(3)
        integer :: nd
        mom = 0
        do nd = 1, st%nnode
            mom = mom + st%mass(nd)*real(st%v(:, nd)*st%free(:, nd), dp)
        end do
        p = dot_product(real(g, dp), mom)
    end function body_power

end module xd_solver_loads
