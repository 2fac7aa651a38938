!> Planar rigid walls (LS-DYNA's stonewalls): a node that would pass the wall
!> in the coming step is stopped on it by removing its normal velocity
!> towards the wall; FRIC 1 also stops its sliding, 0 < FRIC < 1 removes at
!> most FRIC times the normal velocity change from the sliding velocity.
!> The impulse gives the wall force; the kinetic energy removed is the
!> stonewall energy.
module xd_contact_rigidwall
    use xd_kinds, only: wp, dp
    use xd_core_memory, only: alloc
    use xd_model, only: model_t, rigidwall_t, find_set, set_node
    use xd_solver_state, only: state_t
    implicit none
    private
    public :: walls_t, build_walls, apply_walls

    type :: wall_nodes_t
        integer, allocatable :: node(:)     !< nodes the wall stops
        real(dp) :: energy = 0              !< kinetic energy removed so far
        real(wp) :: force(3) = 0            !< force of the nodes on the wall, this cycle
        real(wp) :: normal_force = 0        !< its component along the wall normal (positive: pressing)
    end type wall_nodes_t

    type :: walls_t
        integer :: n = 0
        type(wall_nodes_t), allocatable :: w(:)
    end type walls_t

contains

    !> Node lists: NSID (0: every node) less NSIDEX.
    subroutine build_walls(model, walls)
        type(model_t), intent(in) :: model
        type(walls_t), intent(out) :: walls
        logical, allocatable :: on(:)
        integer :: i, s, k
        walls%n = model%nwall
        if (walls%n == 0) return
        allocate (walls%w(walls%n), on(model%nnode))
        do i = 1, walls%n
            associate (w => model%wall(i))
                if (w%nsid == 0) then
                    on = .true.
                else
                    on = .false.
                    s = find_set(model, set_node, w%nsid)
                    on(model%set(s)%member_ix) = .true.
                end if
                if (w%nsidex /= 0) then
                    s = find_set(model, set_node, w%nsidex)
                    on(model%set(s)%member_ix) = .false.
                end if
                walls%w(i)%node = pack([(k, k=1, model%nnode)], on)
            end associate
        end do
    end subroutine build_walls

    !> Correct the half-step velocities v(n+1/2) so that no node of a wall's
    !> list ends the step behind it; dt is the coming step, dt_avg the one the
    !> velocity update used (for the force).
    subroutine apply_walls(model, walls, st, dt, dt_avg)
        type(model_t), intent(in) :: model
        type(walls_t), intent(inout) :: walls
        type(state_t), intent(inout) :: st
        real(wp), intent(in) :: dt, dt_avg
        integer :: i
        do i = 1, walls%n
            call apply_wall(model%wall(i), walls%w(i), st, dt, dt_avg)
        end do
    end subroutine apply_walls

    subroutine apply_wall(w, wn, st, dt, dt_avg)
        type(rigidwall_t), intent(in) :: w
        type(wall_nodes_t), intent(inout) :: wn
        type(state_t), intent(inout) :: st
        real(wp), intent(in) :: dt, dt_avg
        integer :: k, nd
        real(wp) :: xn(3), d, dvn, vold(3), vprev(3), vt(3), vtn, cut, r(3)
        real(dp) :: de
        wn%force = 0
        wn%normal_force = 0
        if (st%time < w%birth .or. st%time > w%death) return
        de = 0
        do k = 1, size(wn%node)
            nd = wn%node(k)
            if (st%mass(nd) <= 0.0_wp) cycle
            ! where the node would be after the step, measured from the wall
            xn = st%x(:, nd) + dt*st%v(:, nd)
            r = xn - w%tail
            d = dot_product(r, w%normal) - w%offset
            if (d >= 0.0_wp) cycle
            if (w%finite) then
                if (dot_product(r, w%l) < 0.0_wp .or. dot_product(r, w%l) > w%lenl .or. &
                    dot_product(r, w%m) < 0.0_wp .or. dot_product(r, w%m) > w%lenm) cycle
            end if
            vold = st%v(:, nd)
            ! normal: end the step on the wall
            dvn = -d/dt
            st%v(:, nd) = st%v(:, nd) + dvn*w%normal
            ! tangential: stick, or Coulomb-limited slip reduction
            if (w%fric > 0.0_wp) then
                vt = st%v(:, nd) - dot_product(st%v(:, nd), w%normal)*w%normal
                vtn = norm2(vt)
                if (vtn > 0.0_wp) then
                    cut = vtn
                    if (w%fric < 1.0_wp) cut = min(vtn, w%fric*dvn)
                    st%v(:, nd) = st%v(:, nd) - (cut/vtn)*vt
                end if
            end if
            st%v(:, nd) = st%v(:, nd)*st%free(:, nd)
            wn%force = wn%force - st%mass(nd)*(st%v(:, nd) - vold)/dt_avg
            ! energy taken by the wall: minus the work of its force m dv/dt_avg
            ! over the step, with the mean of v(n-1/2) and v(n+1/2); zero for a
            ! node resting on the wall however hard it is pressed
            vprev = vold - dt_avg*st%a(:, nd)
            de = de - st%mass(nd)*dot_product(real(st%v(:, nd) - vold, dp), 0.5_dp*real(vprev + st%v(:, nd), dp))
        end do
        wn%normal_force = -dot_product(wn%force, w%normal)
        wn%energy = wn%energy + de
    end subroutine apply_wall

end module xd_contact_rigidwall
