!> Prescribed nodal motion (*BOUNDARY_PRESCRIBED_MOTION_NODE/_SET): after the
!> velocity update, the prescribed velocity component is imposed; the work of
!> the force that this takes is external work.
module xd_solver_prescribed
    use xd_kinds, only: wp, dp
    use xd_model, only: model_t, prescribed_t, curve_value, find_set, set_node
    use xd_solver_state, only: state_t
    use xd_core_comm, only: comm_sum_dp
    implicit none
    private
    public :: prescribed_nodes_t, build_prescribed, apply_prescribed

    !> Each prescription with its node list.
    type :: prescribed_nodes_t
        integer :: n = 0
        integer, allocatable :: first(:), node(:)   !< CSR: nodes of prescription i
        !> nodes numbered per rank (xd_solver_local_nodes): per entry of
        !> node(:), its number in this rank's nodal arrays where this rank
        !> integrates it, else 0 (node(:) keeps the model's numbers, which
        !> the initial coordinates take); unallocated otherwise
        integer, allocatable :: lnode(:)
    end type prescribed_nodes_t

contains

    subroutine build_prescribed(model, pn)
        type(model_t), intent(in) :: model
        type(prescribed_nodes_t), intent(out) :: pn
        integer :: i, s
        pn%n = model%npresc
        allocate (pn%first(pn%n + 1), pn%node(0))
        pn%first(1) = 1
        do i = 1, pn%n
            associate (pm => model%presc(i))
                if (pm%rigid) then
                    continue
                else if (pm%is_set) then
                    s = find_set(model, set_node, pm%id)
                    pn%node = [pn%node, model%set(s)%member_ix]
                else
                    pn%node = [pn%node, pm%ix]
                end if
            end associate
            pn%first(i + 1) = size(pn%node) + 1
        end do
    end subroutine build_prescribed

    !> v(n+1/2) of the prescribed components: velocity curve at t(n+1/2),
    !> acceleration curve at t(n) added to v(n-1/2), or the displacement at
    !> t(n+1) reached over the step. dt: the coming step; dt_avg: the step of
    !> the velocity update; a holds a(n) from the forces. Returns the work of
    !> the imposing forces, booked so that it sums to the change of the
    !> kinetic energy's product form 1/2 m v(n-1/2).v(n+1/2): half of this
    !> cycle's and of the last cycle's imposed velocity change, times m
    !> v(n-1/2). (The mean form, m dv . (v(n-1/2) + v(n+1/2))/2, left a
    !> residue of 1/2 m dv^2 at each step of a ramp: energy ratios of 0.5 in
    !> the first cycles of a run driven from rest.)
    !> (mine: under MPI with owned nodes, the nodes this rank integrates:
    !> it moves those alone, and the work is each rank's terms summed in
    !> the order of the prescriptions' node lists, the ranks' sums then
    !> added, as the other energies are: the serial run's to rounding. The
    !> terms gathered to every rank and sorted each cycle, the serial sum
    !> bitwise, cost rank 0 of 16 more than the serial run's whole phase
    !> on the 10 x 10 tubes: 7.4e7 instructions in 100 cycles.)
    subroutine apply_prescribed(model, pn, st, dt, dt_avg, work, mextra, mine)
        type(model_t), intent(in) :: model
        type(prescribed_nodes_t), intent(in) :: pn
        type(state_t), intent(inout) :: st
        real(wp), intent(in) :: dt, dt_avg
        real(dp), intent(out) :: work
        !> (nnode) mass a node carries beyond its own (tied slaves' on their
        !> segments' nodes): the prescribed motion moves it too
        real(wp), intent(in), optional :: mextra(:)
        logical, intent(in), optional :: mine(:)
        real(dp) :: m, ranks(1)
        integer :: i, k, nd, j, l, nr
        real(wp) :: t, target, vold, vprev, cv
        !> each node's term, kept and then summed in order (summed as it
        !> came, the sum was contracted with the term's last product: the
        !> serial external work moved in its last bit)
        real(dp), allocatable :: term(:)
        work = 0
        allocate (term(size(pn%node)))
        nr = 0
        t = real(st%time, wp)
        if (.not. allocated(st%jprev)) then
            allocate (st%jprev(3, st%nnode))
            st%jprev = 0
        end if
        do i = 1, pn%n
            associate (pm => model%presc(i), c => model%curve(model%presc(i)%curve_ix))
                if (pm%rigid .or. t < pm%birth .or. t > pm%death) cycle
                j = pm%dof
                ! (the curve's value: one for every node of the prescription)
                select case (pm%vad)
                case (0)
                    cv = curve_value(c, t + 0.5_wp*dt)
                case (1)
                    cv = curve_value(c, t)
                case default
                    cv = curve_value(c, t + dt)
                end select
                do k = pn%first(i), pn%first(i + 1) - 1
                    ! (nd: the model's number; l: the nodal arrays')
                    nd = pn%node(k)
                    l = nd
                    if (allocated(pn%lnode)) then
                        l = pn%lnode(k)
                        if (l == 0) cycle
                    end if
                    if (present(mine)) then
                        if (.not. mine(l)) cycle
                    end if
                    vold = st%v(j, l)
                    vprev = vold - dt_avg*st%a(j, l)
                    select case (pm%vad)
                    case (0)
                        target = pm%sf*cv
                    case (1)
                        target = vprev + dt_avg*pm%sf*cv
                    case default
                        target = (pm%sf*cv - (st%x(j, l) - model%x0(j, nd)))/dt
                    end select
                    st%v(j, l) = target
                    m = st%mass(l)
                    if (present(mextra)) m = m + mextra(l)
                    nr = nr + 1
                    term(nr) = 0.5_dp*m*(target - vold + st%jprev(j, l))*vprev
                    st%jprev(j, l) = target - vold
                end do
            end associate
        end do
        do k = 1, nr
            work = work + term(k)
        end do
        if (present(mine)) then
            ranks = work
            call comm_sum_dp(ranks)
            work = ranks(1)
        end if
    end subroutine apply_prescribed

end module xd_solver_prescribed
