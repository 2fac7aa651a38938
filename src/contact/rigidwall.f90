!> Planar rigid walls (LS-DYNA's stonewalls): a node that would pass the wall
!> in the coming step is stopped on it by removing its normal velocity
!> towards the wall; FRIC 1 also stops its sliding, 0 < FRIC < 1 removes at
!> most FRIC times the normal velocity change from the sliding velocity.
!> The impulse gives the wall force; the kinetic energy removed is the
!> stonewall energy.
module xd_contact_rigidwall
    use xd_kinds, only: wp, dp
    use xd_core_dofs, only: free3
    use xd_core_memory, only: alloc
    use xd_model, only: model_t, rigidwall_t, find_set, set_node, find_box, in_box
    use xd_core_strings, only: itoa
    use xd_core_threads, only: threaded
    use xd_solver_state, only: state_t
    use xd_core_sorting, only: where_true
    use xd_core_comm, only: comm_ordered_records
    implicit none
    private
    public :: walls_t, wall_nodes_t, build_walls, apply_walls, walls_kinetic, wall_distance, wall_normal_force

    type :: wall_nodes_t
        integer, allocatable :: node(:)     !< nodes the wall stops
        logical, allocatable :: on(:)       !< per model node: in node(:)
        !> nodes numbered per rank (xd_solver_local_nodes): node(:) holds
        !> this rank's own nodes alone, by their local numbers, and key(:)
        !> each one's place in the model's list (the order the wall's sums
        !> take); unallocated otherwise
        integer, allocatable :: key(:)
        real(dp) :: shift = 0               !< moving wall: distance moved along the normal
        real(dp) :: vel = 0, vel_old = 0    !< moving wall: velocity along the normal
        real(dp) :: energy = 0              !< kinetic energy removed so far
        !> force of the wall on its nodes this cycle (LS-DYNA's rwforc: a car
        !> striking a post in -x reads +x; the ground under a car, +z)
        real(wp) :: force(3) = 0
        !> its component along the wall normal (positive: pressing); a
        !> cylinder's, its size across the axis
        real(wp) :: normal_force = 0
    end type wall_nodes_t

    type :: walls_t
        integer :: n = 0
        type(wall_nodes_t), allocatable :: w(:)
    end type walls_t

contains

    !> Node lists, as LS-DYNA chooses a wall's nodes: NSID (0: every node),
    !> within box BOXID if given, less NSIDEX; with OFFSET > 0 only those
    !> within OFFSET of the wall at t = 0. A node behind the wall (or inside
    !> the cylinder) at t = 0 by more than round-off is not held by it: it
    !> would be thrown out in one step. Such nodes are listed in `notes`
    !> (for d3hsp) with the wall and their depth; nodes on the wall are held.
    subroutine build_walls(model, x0, walls, notes)
        type(model_t), intent(in) :: model
        real(wp), intent(in) :: x0(:, :)
        type(walls_t), intent(out) :: walls
        character(len=:), allocatable, intent(out) :: notes
        logical, allocatable :: on(:)
        integer :: i, s, b, nd, nbehind
        real(wp) :: d, nrm(3), tol, deepest
        character(len=16) :: buf
        notes = ''
        walls%n = model%nwall
        if (walls%n == 0) return
        allocate (walls%w(walls%n), on(model%nnode))
        tol = 1.0e-6_wp*max(norm2(maxval(x0, dim=2) - minval(x0, dim=2)), tiny(1.0_wp))
        do i = 1, walls%n
            associate (w => model%wall(i))
                if (w%nsid == 0) then
                    on = .true.
                else
                    on = .false.
                    s = find_set(model, set_node, w%nsid)
                    on(model%set(s)%member_ix) = .true.
                end if
                if (w%boxid /= 0) then
                    b = find_box(model, w%boxid)
                    do nd = 1, model%nnode
                        if (.not. in_box(model%box(b), x0(:, nd))) on(nd) = .false.
                    end do
                end if
                if (w%nsidex /= 0) then
                    s = find_set(model, set_node, w%nsidex)
                    on(model%set(s)%member_ix) = .false.
                end if
                walls%w(i)%vel = real(w%v0, dp)
                walls%w(i)%vel_old = walls%w(i)%vel
                nbehind = 0
                deepest = 0
                do nd = 1, model%nnode
                    if (.not. on(nd)) cycle
                    call wall_distance(w, walls%w(i), x0(:, nd), 0.0_wp, d, nrm)
                    if (w%offset > 0.0_wp .and. d > w%offset) then
                        on(nd) = .false.
                    else if (d < -tol) then
                        on(nd) = .false.
                        nbehind = nbehind + 1
                        deepest = max(deepest, -d)
                        if (nbehind <= 20) then
                            write (buf, '(es10.3)') -d
                            notes = notes//'rigid wall '//itoa(w%id)//': node '//itoa(model%node_id(nd))// &
                                    ' lies '//trim(adjustl(buf))//' behind the wall at t = 0; the wall does not hold it'// &
                                    new_line('a')
                        end if
                    end if
                end do
                if (nbehind > 20) then
                    write (buf, '(es10.3)') deepest
                    notes = notes//'rigid wall '//itoa(w%id)//': '//itoa(nbehind - 20)// &
                            ' more nodes behind the wall at t = 0 (deepest '//trim(adjustl(buf))//'), not held'// &
                            new_line('a')
                end if
                walls%w(i)%node = where_true(on)
                walls%w(i)%on = on
            end associate
        end do
    end subroutine build_walls

    !> Correct the half-step velocities v(n+1/2) so that no node of a wall's
    !> list ends the step behind it; dt is the coming step, dt_avg the one the
    !> velocity update used (for the force).
    !> The walls on the nodes of deformable bodies; `body_node` marks the
    !> nodes of rigid bodies, which take the walls' impulses as bodies
    !> (xd_rigid_bodies).
    !> (mine: under MPI with owned nodes, the nodes this rank integrates:
    !> it acts on those alone, and the sums over a wall's nodes, its mass
    !> and impulse, its force and energy, take every rank's terms in the
    !> order of the wall's node list, as one rank adds them)
    subroutine apply_walls(model, walls, st, dt, dt_avg, body_node, mine)
        type(model_t), intent(in) :: model
        type(walls_t), intent(inout) :: walls
        type(state_t), intent(inout) :: st
        real(wp), intent(in) :: dt, dt_avg
        logical, intent(in) :: body_node(:)
        logical, intent(in), optional :: mine(:)
        integer :: i
        do i = 1, walls%n
            call apply_wall(model%wall(i), walls%w(i), st, dt, dt_avg, body_node, mine)
        end do
    end subroutine apply_walls

    !> Each wall node's distance behind the wall at the step's end (0 where
    !> it is not behind, massless or a rigid body's) and the wall normal
    !> there, as a worksharing loop.
    subroutine wall_distances(w, wn, st, dt, body_node, dall, hn, mine)
        type(rigidwall_t), intent(in) :: w
        type(wall_nodes_t), intent(in) :: wn
        type(state_t), intent(in) :: st
        real(wp), intent(in) :: dt
        logical, intent(in) :: body_node(:)
        real(wp), intent(inout) :: dall(:), hn(:, :)
        logical, intent(in), optional :: mine(:)
        integer :: k, nd
        real(wp) :: xn(3)
        !$omp do schedule(static)
        do k = 1, size(wn%node)
            nd = wn%node(k)
            dall(k) = 0
            if (st%mass(nd) <= 0.0_wp .or. body_node(nd)) cycle
            if (present(mine)) then
                if (.not. mine(nd)) cycle
            end if
            xn = st%x(:, nd) + dt*st%v(:, nd)
            call wall_distance(w, wn, xn, real(dt*wn%vel, wp), dall(k), hn(:, k))
        end do
        !$omp end do
    end subroutine wall_distances

    subroutine apply_wall(w, wn, st, dt, dt_avg, body_node, mine)
        type(rigidwall_t), intent(in) :: w
        type(wall_nodes_t), intent(inout) :: wn
        type(state_t), intent(inout) :: st
        real(wp), intent(in) :: dt, dt_avg
        logical, intent(in) :: body_node(:)
        logical, intent(in), optional :: mine(:)
        integer :: k, nd, nc, q
        real(wp) :: dvn, vold(3), vprev(3), vt(3), vtn, cut, fk(3)
        real(dp) :: de, sum_m, sum_j, vw, ek
        integer, allocatable :: hit(:), at(:)
        real(wp), allocatable :: gap(:), hn(:, :), dall(:)
        !> (owned nodes) this rank's hits' terms: key (the place in the
        !> wall's node list) and the values the sums take
        real(dp), allocatable :: rec(:, :), all(:, :)
        wn%force = 0
        wn%normal_force = 0
        wn%vel_old = wn%vel
        if (st%time < w%birth .or. st%time > w%death) then
            wn%shift = wn%shift + dt*wn%vel
            return
        end if
        ! nodes that would end the step behind the wall (the wall at its
        ! present speed), with their distance and the wall normal there: the
        ! distances threaded, the list in node order
        allocate (hit(size(wn%node)), gap(size(wn%node)), hn(3, size(wn%node)), dall(size(wn%node)), &
                  at(size(wn%node)))
        ! (a parallel region only where more than one thread runs it:
        ! xd_core_threads)
        if (threaded(size(wn%node))) then
            !$omp parallel
            call wall_distances(w, wn, st, dt, body_node, dall, hn, mine)
            !$omp end parallel
        else
            call wall_distances(w, wn, st, dt, body_node, dall, hn, mine)
        end if
        nc = 0
        do k = 1, size(wn%node)
            if (dall(k) >= 0.0_wp) cycle
            nc = nc + 1
            hit(nc) = wn%node(k)
            gap(nc) = dall(k)
            hn(:, nc) = hn(:, k)
            at(nc) = k
            if (allocated(wn%key)) at(nc) = wn%key(k)
        end do
        ! the hits' sums (a moving wall's mass and impulse, then, the nodes
        ! moved, the force and energy), each taken over the hits' records in
        ! the wall's node order; under owned nodes every rank's records: the
        ! same sums as one rank takes
        vw = 0
        if (w%moving) then
            allocate (rec(3, nc))
            do k = 1, nc
                rec(:, k) = [real(at(k), dp), real(st%mass(hit(k)), dp), real(gap(k), dp)]
            end do
            call comm_ordered_records(rec, all, present(mine))
            if (size(all, 2) > 0) then
                sum_m = 0
                sum_j = 0
                do q = 1, size(all, 2)
                    sum_m = sum_m + real(all(2, q), wp)
                    sum_j = sum_j - real(all(2, q), wp)*real(all(3, q), wp)/dt
                end do
                sum_j = sum_j/(1.0_dp + sum_m/w%mass)
                vw = -sum_j/w%mass
                wn%vel = wn%vel + vw
            end if
            deallocate (rec)
        end if
        allocate (rec(5, nc))
        do k = 1, nc
            nd = hit(k)
            vold = st%v(:, nd)
            dvn = -gap(k)/dt + real(vw, wp)
            st%v(:, nd) = st%v(:, nd) + dvn*hn(:, k)
            if (w%fric > 0.0_wp) then
                vt = st%v(:, nd) - dot_product(st%v(:, nd), hn(:, k))*hn(:, k)
                vtn = norm2(vt)
                if (vtn > 0.0_wp) then
                    cut = vtn
                    if (w%fric < 1.0_wp) cut = min(vtn, w%fric*abs(dvn))
                    st%v(:, nd) = st%v(:, nd) - (cut/vtn)*vt
                end if
            end if
            st%v(:, nd) = st%v(:, nd)*free3(st%dofs(nd))
            fk = st%mass(nd)*(st%v(:, nd) - vold)/dt_avg
            vprev = vold - dt_avg*st%a(:, nd)
            ek = st%mass(nd)*dot_product(real(st%v(:, nd) - vold, dp), 0.5_dp*real(vprev + st%v(:, nd), dp))
            rec(:, k) = [real(at(k), dp), real(fk, dp), ek]
        end do
        call comm_ordered_records(rec, all, present(mine))
        de = 0
        do q = 1, size(all, 2)
            wn%force = wn%force + real(all(2:4, q), wp)
            de = de - all(5, q)
        end do
        if (w%moving) de = de - 0.5_dp*w%mass*(wn%vel**2 - wn%vel_old**2)
        wn%shift = wn%shift + dt*wn%vel
        call wall_normal_force(w, wn)
        wn%energy = wn%energy + de
    end subroutine apply_wall

    !> The normal force of a wall from its force on the nodes: along its
    !> normal, or for a cylinder (whose normal is its axis) across the axis.
    pure subroutine wall_normal_force(w, wn)
        type(rigidwall_t), intent(in) :: w
        type(wall_nodes_t), intent(inout) :: wn
        wn%normal_force = dot_product(wn%force, w%normal)
        if (w%cylinder) wn%normal_force = norm2(wn%force - wn%normal_force*w%normal)
    end subroutine wall_normal_force

    !> Signed distance of the point x from the wall after it moves by `ahead`
    !> along its normal (negative: behind or inside), and the wall normal
    !> there; huge when x is beyond a finite wall's edges or the cylinder's ends.
    pure subroutine wall_distance(w, wn, x, ahead, d, nrm)
        type(rigidwall_t), intent(in) :: w
        type(wall_nodes_t), intent(in) :: wn
        real(wp), intent(in) :: x(3), ahead
        real(wp), intent(out) :: d, nrm(3)
        real(wp) :: r(3), s, radial(3), rr
        r = x - w%tail
        if (w%cylinder) then
            s = dot_product(r, w%normal)
            radial = r - s*w%normal
            rr = norm2(radial)
            d = huge(1.0_wp)
            nrm = w%normal
            if (rr <= 0.0_wp) return
            if (w%length > 0.0_wp .and. (s < 0.0_wp .or. s > w%length)) return
            d = rr - w%radius
            nrm = radial/rr
            return
        end if
        r = r - real(wn%shift, wp)*w%normal - ahead*w%normal
        nrm = w%normal
        d = dot_product(r, w%normal)
        if (w%finite) then
            if (dot_product(r, w%l) < 0.0_wp .or. dot_product(r, w%l) > w%lenl .or. &
                dot_product(r, w%m) < 0.0_wp .or. dot_product(r, w%m) > w%lenm) d = huge(1.0_wp)
        end if
    end subroutine wall_distance

    !> Kinetic energy of the moving walls (part of the system's).
    pure real(dp) function walls_kinetic(model, walls) result(ke)
        type(model_t), intent(in) :: model
        type(walls_t), intent(in) :: walls
        integer :: i
        ke = 0
        do i = 1, walls%n
            if (model%wall(i)%moving) ke = ke + 0.5_dp*model%wall(i)%mass*walls%w(i)%vel_old*walls%w(i)%vel
        end do
    end function walls_kinetic

end module xd_contact_rigidwall
