!> Step 3 of the automatic contact, the local search (section 5.1 of Whirley
!> & Engelmann 1993): for each slave node, the segment it was in contact
!> with last cycle first, then the segments at that segment's node closest to
!> the contact point; otherwise the master node list of the global search in
!> order of distance, each master node screened by the tetrahedron test
!> (Eqs. 1-3) and the bounding-box test, trackable nodes followed along
!> their opposite region, and every segment at a passing node checked
!> (section 5.2). Several contacts: the hierarchy (shell interior > shell
!> tube/pinball or solid interior > solid tube/pinball), ties by the closest
!> contact point (old-segment search) or by the comparison vector (Eq. 4).
module xd_contact_local_search
    use xd_kinds, only: wp
    use xd_core_vectors, only: cross
    use xd_contact_surface, only: surface_t, seg_shell, wanted_side, seg_nodes, seg_normal, seg_thicknesses
    use xd_contact_segment_check, only: hit_t, segment_check, contact_interior
    use xd_contact_global_search, only: master_lists_t, separating_axes, reach_factor, list_row
    implicit none
    private
    public :: local_search_t, find_contact, search_switches_t, clearance_t, reset_clearance, &
              fresh_clearance

    !> Switches for the accuracy and cost study.
    type :: search_switches_t
        logical :: tracking = .true.
        logical :: screens = .true.
    end type search_switches_t

    !> What one slave's search needs besides the surface.
    type :: local_search_t
        real(wp), allocatable :: xl(:, :)    !< surface coordinates now (3, nnode)
        real(wp), allocatable :: vl(:, :)    !< surface velocities now (3, nnode)
        real(wp), allocatable :: lc(:)       !< characteristic lengths, as the last global search took them
        !> the interface's odometer when lc(m) was taken: every point of a
        !> segment at m lies within lc(m) + 2 (odo - lcodo(m)) of m
        real(wp), allocatable :: lcodo(:)
        real(wp) :: grow = 0                 !< the reach t_c plus the lead
        real(wp) :: lead = 0                 !< Lagrangian projection: contacts found this far before they touch
        real(wp) :: dt = 0                   !< this cycle's step (how deep a new contact can be)
        real(wp) :: odo = 0                  !< the interface's motion bound since t = 0 (its odometer)
        !> the first active cycle: every contact found is an initial
        !> penetration (no depth is refused)
        logical :: first = .false.
        !> PENMAX: a contact deeper than penmax times its segment's thickness
        !> (beyond the allowance it holds) is none (0: the zone's own limit)
        real(wp) :: penmax = 0
    end type local_search_t

    !> Per slave, a lower bound of its clearance (as master_lists_t%gap:
    !> the least distance to a segment it can reach before the next search,
    !> less the distance at which that segment's check finds a contact),
    !> taken at the slave's search or refreshed since, with the slave's
    !> position and the interface's motion bound since t = 0 (its odometer)
    !> at that moment. Every point of a segment moves at most the odometer's
    !> growth after it, the slave |x - x_ref|: while their sum plus twice
    !> the lead stays below the bound, the slave has no contact.
    !>
    !> A bound taken afresh (fresh_clearance) may leave out the few
    !> segments nearest the slave, its near set: the bound is then that of
    !> the others, and while it holds only the near segments can hold a
    !> contact, which the local search checks alone (find_contact's near).
    !> Held for the slaves this rank searches alone (under MPI, issue 32:
    !> the rank's own; on one rank every slave), in rows of their own:
    !> slave k's is row(k) (0: another rank's).
    type :: clearance_t
        integer :: search = -1               !< the last global search whose bounds were taken in
        integer, allocatable :: row(:)       !< (nslave) each slave's row (0: not held here)
        real(wp), allocatable :: g(:)        !< (rows) the bound
        real(wp), allocatable :: x(:, :)     !< (3, rows) the slave's position when it was taken
        real(wp), allocatable :: u(:)        !< (rows) the odometer when it was taken
        integer, allocatable :: wait(:)      !< (rows) local searches before a refresh is tried again
        integer, allocatable :: nnear(:)     !< (rows) segments in the near set (0: none)
        integer, allocatable :: near(:, :)   !< (max_near, rows) the near set
    end type clearance_t

    !> The most segments a near set holds
    integer, parameter, public :: max_near = 8
    !> A fresh bound leaves out, as near, the segments within this many
    !> leads of the slave's reach (some five to eight cycles' closure at
    !> the present speeds), so that the bound of the others lasts that
    !> long. car6 whole: 4, 8, 16, 48 and 96 took the local search 2.34,
    !> 2.33, 2.22-2.27, 2.31-2.36 and 2.41 s, the same answers bit for bit
    real(wp), parameter :: near_leads = 16.0_wp

    integer, parameter :: max_tried = 64   !< segments remembered per slave (each checked once)

    integer, parameter :: max_track_steps = 64

contains

    !> The contact of slave number i (position in s%slave) this cycle, in
    !> `best` (best%found false: none). `oldseg` is last cycle's segment (0:
    !> none), `fprev` the contact force it carried (the comparison vector).
    !>
    !> A segment other than the old one that holds the slave deeper than
    !> it can have gone since last cycle (its depth then plus twice this
    !> step's approach) is a contact only if the slave came into its
    !> contact zone since the last global search: at the positions of that
    !> search (`xs`, surface numbering) it lay outside the zone. Such a
    !> missed contact (the slave was held by another segment, or came
    !> through an edge) is kept; one that lay inside the zone already is a
    !> face the slave never crossed. A solid face's is no contact (a node
    !> inside a body's corner under the far face); the deepest refused
    !> segment and its depth come back in `refused` and `refused_depth` (0:
    !> none). A shell's is held where it is found (best%within: the depth
    !> allowed, a force only deeper): a node in a shell's thickness band
    !> that goes on reaches the mid-surface and passes, and refusing it
    !> let the last nodes through the demo tube's folds and car6's.
    !>
    !> With PENMAX (ls%penmax > 0), a segment that holds the slave deeper than
    !> penmax times its thickness (less `allow`, the slave's allowance, on
    !> the old segment) holds no contact: the node is released and passes.
    subroutine find_contact(s, lists, ls, i, oldseg, fprev, aprev, sw, best, xs, refused, refused_depth, allow, &
                            beyond, held, near, near_effect)
        type(surface_t), intent(in) :: s
        type(master_lists_t), intent(in) :: lists
        type(local_search_t), intent(in) :: ls
        integer, intent(in) :: i, oldseg
        real(wp), intent(in) :: fprev(3)
        real(wp), intent(in) :: aprev          !< the slave's depth last cycle (0: not in contact)
        type(search_switches_t), intent(in) :: sw
        type(hit_t), intent(out) :: best
        real(wp), intent(in), optional :: xs(:, :)   !< surface coordinates at the last global search
        integer, intent(out), optional :: refused
        real(wp), intent(out), optional :: refused_depth
        real(wp), intent(in), optional :: allow      !< the slave's allowance on oldseg
        real(wp), intent(out), optional :: beyond    !< the depth of a contact dropped beyond PENMAX (0: none)
        !> the segment the slave held last (0: none): it was on that
        !> segment's contact side then, so being deep under it again is a
        !> contact, not a face it never crossed
        integer, intent(in), optional :: held
        !> a slave not in contact last cycle whose clearance leaves these
        !> segments alone within reach: only they are checked, and
        !> near_effect says whether any of them found a contact or refused
        !> one (for the caller to search in full: the general search's
        !> choice among several depends on its order); none, and the
        !> general search finds none either
        integer, intent(in), optional :: near(:)
        logical, intent(out), optional :: near_effect
        type(hit_t) :: hit
        integer :: sn, want, j, k, m, mn, cnode, nsolid_miss, ntried, rseg, held_seg
        integer :: tried(max_tried)
        real(wp) :: ts, cv(3), rdep
        logical :: have_v, interior
        real(wp) :: deep

        sn = s%slave(i)
        held_seg = 0
        if (present(held)) held_seg = held
        ts = 0.5_wp*s%node_t(sn)
        want = wanted_side(s, sn)
        best%found = .false.
        best%level = 4
        nsolid_miss = 0
        ntried = 0
        rseg = 0
        rdep = 0
        deep = 0

        if (oldseg > 0) then
            ! the old segment: done if the contact point is inside it (and, on
            ! a shell, not within a half-thickness of its border)
            call check(oldseg, hit)
            if (hit%found) then
                if (in_plane_own(oldseg, hit) .or. too_deep(hit)) hit%found = .false.
            end if
            interior = hit%found .and. hit%kind == contact_interior .and. .not. grazing(hit)
            if (interior .and. .not. (s%seg_kind(oldseg) == seg_shell .and. hit%near_border)) then
                best = hit
                call report_refused()
                return
            end if
            if (hit%found) best = hit
            ! then every segment at the old segment's node nearest the contact
            ! point, ties by the comparison vector as below (a node at an
            ! edge of two faces goes on being pushed by the face that pushed it)
            cnode = s%seg(hit%near_node, oldseg)
            cv = -fprev
            if (.not. any(fprev /= 0.0_wp)) cv = ls%vl(:, sn) - ls%vl(:, cnode)
            do k = s%seg_ptr(cnode), s%seg_ptr(cnode + 1) - 1
                m = s%seg_list(k)
                if (m == oldseg) cycle
                ! next to an interior contact only a neighbour that can hold
                ! the slave's projection in its interior can change it
                if (interior) then
                    if (.not. may_hold(m, hit)) cycle
                end if
                call try(m, .true.)
            end do
            if (acceptable()) then
                call report_refused()
                return
            end if
            best%found = .false.
            best%level = 4
            nsolid_miss = 0
            ntried = 0
        end if

        if (present(near)) then
            cv = -fprev
            do j = 1, size(near)
                call try(near(j), .true.)
            end do
            near_effect = best%found .or. rseg /= 0 .or. deep /= 0.0_wp
            best%found = .false.
            best%level = 4
            call report_refused()
            return
        end if

        ! the general search: master nodes closest first
        ! comparison vector (Eq. 4): the force the slave pressed with last
        ! cycle (minus the contact force on it), else the relative velocity;
        ! the segment it presses against or approaches has the most negative
        ! v . n
        have_v = any(fprev /= 0.0_wp)
        cv = -fprev
        do j = lists%ptr(list_row(lists, i)), lists%last(list_row(lists, i))
            mn = lists%node(j)
            if (.not. have_v) cv = ls%vl(:, sn) - ls%vl(:, mn)      ! Eq. (4)
            if (lists%trackable(j) .and. sw%tracking) mn = track(mn)
            ! every point of a segment at mn lies within L_m of it (grown by
            ! the motion since the search): a slave farther away than that
            ! plus the thicknesses cannot touch one (the test of Fig. 3)
            if (sum((ls%xl(:, mn) - ls%xl(:, sn))**2) > (ls%lc(mn) + 2.0_wp*(ls%odo - ls%lcodo(mn)) + ls%grow + ts)**2) cycle
            if (sw%screens) then
                if (.not. screened_in(mn)) cycle
            end if
            do k = s%seg_ptr(mn), s%seg_ptr(mn + 1) - 1
                call try(s%seg_list(k), .true.)
            end do
        end do
        if (.not. acceptable()) then
            best%found = .false.
            best%level = 4
        end if
        call report_refused()

    contains

        subroutine report_refused()
            if (present(refused)) refused = rseg
            if (present(refused_depth)) refused_depth = rdep
            if (present(beyond)) then
                beyond = 0
                if (.not. best%found) beyond = deep
            end if
        end subroutine report_refused

        !> Contact h with segment m is deeper than the slave can have gone
        !> since last cycle, in m's zone that it did not enter since the
        !> last search (not at the first cycle, nor on the segment it held
        !> or holds, nor a contact found ahead of touching). came_in, the
        !> dearer test, only where the others leave it open.
        logical function never_entered(m, h)
            integer, intent(in) :: m
            type(hit_t), intent(in) :: h
            never_entered = .false.
            if (ls%first .or. m == oldseg .or. m == held_seg .or. h%gap /= 0.0_wp) return
            if (reachable(h)) return
            never_entered = .not. came_in(m)
        end function never_entered

        !> At the last global search the slave lay outside segment m's
        !> contact zone (beyond a shell's half thicknesses on either side,
        !> or on the outer side of a solid face): it came in since.
        logical function came_in(m)
            integer, intent(in) :: m
            type(hit_t) :: h0
            real(wp) :: tn(4)
            came_in = .true.
            if (.not. present(xs)) return
            call seg_thicknesses(s, m, tn)
            call segment_check(xs(:, s%seg(:, m)), tn, s%seg_kind(m) == seg_shell, xs(:, sn), ts, h0, &
                               touching=s%seg_body(m) /= s%node_body(sn))
            ! (a node on the surface then, within 1% of the thickness or window,
            ! by round-off or a touch, counts as outside)
            if (s%seg_kind(m) == seg_shell) then
                came_in = abs(h0%d) >= ts + h0%tm - 0.01_wp*h0%tm
            else
                came_in = h0%d >= ts - 0.01_wp*h0%tm
            end if
        end function came_in

        subroutine check(m, h)
            integer, intent(in) :: m
            type(hit_t), intent(out) :: h
            real(wp) :: xm(3, 4), tn(4)
            xm = ls%xl(:, s%seg(:, m))
            call seg_thicknesses(s, m, tn)
            call segment_check(xm, tn, s%seg_kind(m) == seg_shell, ls%xl(:, sn), ts, h, &
                               touching=s%seg_body(m) /= s%node_body(sn), lead=ls%lead)
            h%seg = m
        end subroutine check

        !> Check segment m unless it holds the slave or lies on a side the
        !> slave does not look at; keep it if it beats the best so far.
        subroutine try(m, general)
            integer, intent(in) :: m
            logical, intent(in) :: general
            type(hit_t) :: h
            ! a segment at several master nodes is checked once
            if (any(tried(1:ntried) == m)) return
            if (ntried < max_tried) then
                ntried = ntried + 1
                tried(ntried) = m
            end if
            if (any(s%seg(:, m) == sn)) return
            if (size(s%seg_elem, 2) > 0) then
                if (any(s%seg_elem(:, m) == sn)) return
            end if
            if (iand(s%seg_side(m), want) == 0) return
            ! a shell segment finds contact only within the two half
            ! thicknesses (and the lead) of its surface: a slave outside its
            ! box grown by them has none. (Solid faces are checked even so:
            ! a miss there counts for acceptable().)
            if (s%seg_kind(m) == seg_shell) then
                if (outside_box(m)) return
            end if
            call check(m, h)
            if (h%found) then
                if (in_plane_own(m, h) .or. too_deep(h)) return
                ! deeper than the slave can have gone since last cycle, in a
                ! zone it did not enter since the search: a solid face's is
                ! not its contact (a node inside a body's corner under the
                ! far face); a shell's holds it at that depth (h%within:
                ! allowed, no force until it goes deeper), for a node inside
                ! a shell's thickness band that moves on reaches its
                ! mid-surface and passes (refused, the demo tube's and
                ! car6's last pass-throughs did)
                if (never_entered(m, h)) then
                    if (s%seg_kind(m) /= seg_shell) then
                        if (abs(h%a) > rdep) then
                            rdep = abs(h%a)
                            rseg = m
                        end if
                        return
                    end if
                    h%within = .true.
                end if
            end if
            if (.not. h%found) then
                ! a solid face missed by a hair (the slave on its plane, outside)
                ! does not make the slave an outside node: it lies on the edge
                if (s%seg_kind(m) /= seg_shell .and. .not. (h%d >= ts .and. h%d - ts <= 1.0e-5_wp*h%tm)) &
                    nsolid_miss = nsolid_miss + 1
                return
            end if
            if (better(h, best, general)) best = h
        end subroutine try

        !> The slave lies outside segment m's bounding box grown by the
        !> segment's reach (half a shell's thickness, a solid's window), the
        !> lead and its own half thickness ts. (Taken where needed: the
        !> slaves searched in a cycle meet few of the segments.)
        logical function outside_box(m)
            integer, intent(in) :: m
            integer :: d
            real(wp) :: r
            r = s%seg_r(m) + ls%lead + ts
            outside_box = .true.
            associate (p => ls%xl(:, sn), x => ls%xl, n => s%seg(:, m))
                do d = 1, 3
                    if (p(d) < min(x(d, n(1)), x(d, n(2)), x(d, n(3)), x(d, n(4))) - r) return
                    if (p(d) > max(x(d, n(1)), x(d, n(2)), x(d, n(3)), x(d, n(4))) + r) return
                end do
            end associate
            outside_box = .false.
        end function outside_box

        logical function better(h, b, general)
            type(hit_t), intent(in) :: h, b
            logical, intent(in) :: general
            real(wp) :: vh, vb
            if (.not. b%found) then
                better = .true.
            else if (h%level /= b%level) then
                better = h%level < b%level
            else if (squarer(h, b) /= 0) then
                ! two solid faces: the one the slave's own solid surface
                ! meets squarely (its outward normals against the push):
                ! the end faces of two aligned bars, not the side face the
                ! node lies in; for a node of a plate under a sliding
                ! block, the block's bottom face, not its front face
                ! moving away over it
                better = squarer(h, b) > 0
            else if (beyond_half(h) .neqv. beyond_half(b)) then
                ! a node deeper than half a solid's window below one face and
                ! less deep below another came through the other (the far face
                ! of a thin solid must not pull a node through it)
                better = beyond_half(b)
            else if (grazing(h) .neqv. grazing(b)) then
                ! a node on a face's plane that penetrates another face of the
                ! same level by no more than it can have gone since last cycle
                ! (its depth then plus twice this step's approach) lies at
                ! their common edge: the face it went through pushes it (two
                ! bodies with aligned edges, where the side face would
                ! otherwise win as the closer one, and carry nothing). Deeper
                ! than that, it did not come through the other face: it slid
                ! in the plane of the first (a node under a sliding block
                ! enters the window of the block's back face from its deep
                ! end), and the face it lies on keeps it
                if (grazing(b)) then
                    better = reachable(h)
                else
                    better = .not. reachable(b)
                end if
            else
                better = h%dist < b%dist
                if (general) then
                    ! the most negative v . n (Eq. 4); where v does not tell the
                    ! two apart (v along both surfaces), the closest contact point.
                    ! n is the normal on the slave's side (outside): a shell
                    ! segment's nhat is its own normal whichever side the slave
                    ! is on, so below it the outside is -nhat (issue 28: read
                    ! as nhat, the rule favoured the face the slave did not
                    ! press, and a node in a fold's corner under two faces
                    ! switched between them every cycle)
                    vh = dot_product(cv, outside(h))
                    vb = dot_product(cv, outside(b))
                    if (abs(vh - vb) > 1.0e-6_wp*norm2(cv)) better = vh < vb
                end if
            end if
        end function better

        !> Contact h's normal on the slave's side: nhat, reversed for a
        !> slave below a shell segment (d < 0) within its zone (a contact
        !> found ahead of touching already has nhat turned to the slave's
        !> side: segment_check).
        function outside(h) result(n)
            type(hit_t), intent(in) :: h
            real(wp) :: n(3)
            n = h%nhat
            if (s%seg_kind(h%seg) == seg_shell .and. h%d < 0.0_wp .and. abs(h%d) < ts + h%tm) n = -n
        end function outside

        !> +1 if h's push meets the slave's own solid faces more squarely
        !> than b's (by more than 0.1 in the cosine), -1 if less, 0 if
        !> neither is clearly so or either is not a solid face.
        integer function squarer(h, b)
            type(hit_t), intent(in) :: h, b
            real(wp) :: fh, fb
            squarer = 0
            if (s%seg_kind(h%seg) == seg_shell .or. s%seg_kind(b%seg) == seg_shell) return
            fh = facing(h)
            if (fh < -2.0_wp) return
            fb = facing(b)
            if (fh > fb + 0.1_wp) squarer = 1
            if (fb > fh + 0.1_wp) squarer = -1
        end function squarer

        !> A tube or pinball contact with a neighbouring shell segment of the
        !> slave's own body (a node within three rings of it), pushing the
        !> slave within 60 degrees of the segment's plane: the next segment
        !> in the same sheet (a flat plate of shells as thick as its elements
        !> reaches it edge-on), not a fold that has closed. Not a contact.
        logical function in_plane_own(m, h)
            integer, intent(in) :: m
            type(hit_t), intent(in) :: h
            real(wp) :: nv(3)
            in_plane_own = .false.
            if (s%seg_kind(m) /= seg_shell .or. h%kind == contact_interior) return
            if (s%seg_body(m) /= s%node_body(sn)) return
            ! a neighbour: the segment has a node within three rings of the
            ! slave along the sheet (a sheet up to about three elements thick
            ! reaches that far in its plane); a fold that closes from farther
            ! along the sheet is no neighbour: left out, it would be found
            ! late and deep
            ! (the angle first: it is cheaper than the walk over the rings)
            nv = seg_normal(s, ls%xl, m)
            if (abs(dot_product(nv, h%nhat)) >= 0.5_wp*norm2(nv)) return
            in_plane_own = within_rings(m, 3)
        end function in_plane_own

        !> Segment m has a node within `rings` steps of the slave along the
        !> surface's node-to-node adjacency.
        logical function within_rings(m, rings)
            integer, intent(in) :: m, rings
            integer :: front(64), next(64), nf, nx, r, a, q, b
            within_rings = .false.
            nf = 1
            front(1) = sn
            do r = 1, rings
                nx = 0
                do a = 1, nf
                    do q = s%nn_ptr(front(a)), s%nn_ptr(front(a) + 1) - 1
                        b = s%nn_list(q)
                        if (any(s%seg(:, m) == b)) then
                            within_rings = .true.
                            return
                        end if
                        ! (the last ring's nodes are not walked on: no
                        ! front to build, whose deduplication had been
                        ! most of this function's time)
                        if (r < rings .and. nx < size(next)) then
                            if (.not. any(next(1:nx) == b)) then
                                nx = nx + 1
                                next(nx) = b
                            end if
                        end if
                    end do
                end do
                front(1:nx) = next(1:nx)
                nf = nx
            end do
        end function within_rings

        !> How squarely the slave's own solid faces meet the push of
        !> contact h: the largest -n_s . push over the slave's solid
        !> segments (unit outward normals n_s); -3 if it has none.
        real(wp) function facing(h)
            type(hit_t), intent(in) :: h
            integer :: q, m2
            real(wp) :: nv(3), ln
            facing = -3.0_wp
            do q = s%seg_ptr(sn), s%seg_ptr(sn + 1) - 1
                m2 = s%seg_list(q)
                if (s%seg_kind(m2) == seg_shell) cycle
                nv = seg_normal(s, ls%xl, m2)
                ln = norm2(nv)
                if (ln <= 0.0_wp) cycle
                facing = max(facing, -dot_product(nv, h%nhat)/ln)
            end do
        end function facing

        !> The contact's depth is within the slave's depth last cycle plus
        !> twice this step's approach along the return direction.
        logical function reachable(h)
            type(hit_t), intent(in) :: h
            real(wp) :: vr(3)
            integer :: j
            vr = ls%vl(:, sn)
            do j = 1, 4
                vr = vr - h%nshape(j)*ls%vl(:, s%seg(j, h%seg))
            end do
            reachable = abs(h%a) <= aprev + 2.0_wp*ls%dt*abs(dot_product(vr, h%nhat)) + 1.0e-3_wp*h%tm
        end function reachable

        !> A contact that only grazes its segment: a penetration below 1e-5
        !> of the thickness (round-off on a face's plane).
        logical function grazing(h)
            type(hit_t), intent(in) :: h
            grazing = abs(h%a) <= 1.0e-5_wp*h%tm
        end function grazing

        !> Deeper than PENMAX times the segment's thickness, beyond the
        !> allowance the slave holds on its old segment.
        logical function too_deep(h)
            type(hit_t), intent(in) :: h
            real(wp) :: p0
            too_deep = .false.
            if (ls%penmax <= 0.0_wp) return
            p0 = 0
            if (h%seg == oldseg .and. present(allow)) p0 = allow
            too_deep = abs(h%a) - p0 > ls%penmax*s%seg_t(h%seg)
            if (too_deep) deep = max(deep, abs(h%a))
        end function too_deep

        !> A solid contact deeper than half its window.
        logical function beyond_half(h)
            type(hit_t), intent(in) :: h
            beyond_half = .false.
            if (s%seg_kind(h%seg) /= seg_shell) beyond_half = -h%a > 0.5_wp*h%tm
        end function beyond_half

        !> A lone solid tube/pinball contact among solid segments that are not
        !> in contact is no contact (a node outside a solid's convex edge),
        !> unless the slave was in contact with that very segment last cycle:
        !> a node pressed onto a face that slides a little beyond its border
        !> (two bodies with aligned edges) keeps being pushed back along the
        !> face normal, by its depth below the face's plane, until it leaves
        !> the 60 degree cone of segment_check. Dropping it there and catching
        !> it again at depth a moment later would add the spring energy
        !> k a^2 / 2 at each catch.
        logical function acceptable()
            acceptable = best%found
            if (.not. acceptable .or. nsolid_miss == 0 .or. best%kind == contact_interior) return
            if (s%seg_kind(best%seg) /= seg_shell) acceptable = best%seg == oldseg
        end function acceptable

        !> Interior contact h with the old segment near its border (a
        !> distance b = h%border inside it): can segment m, a neighbour at
        !> the node nearest the contact point, hold the slave's projection in
        !> its interior? In a section across the border, a neighbour rising
        !> from it at angle phi towards the slave (at height |d|) holds it
        !> only if b <= |d| tan(phi); a node of the neighbour at height z
        !> above the tangent plane at the contact point and a distance r
        !> from that point along the plane has tan(phi) = z / (r - b). With a
        !> factor 4 for a section taken obliquely (a node off the section is
        !> farther along the plane than across the border): not, where every
        !> node of m off the old segment has b (r - b) > 4 |d| z. A neighbour
        !> falling away (z <= 0, the surface convex towards the slave) never
        !> can: the normal prisms of a convex surface do not overlap on its
        !> outer side. Only an interior contact can beat an interior one (the
        !> hierarchy). Measured on the tube crushed by a rigid plate: of 1.13
        !> million such searches, the neighbours changed the contact in 1,158;
        !> the 392 of them this test leaves out were ties on the common
        !> border (contact point within 1e-3 of the thickness, normal within
        !> 1e-3: the same contact).
        logical function may_hold(m, h)
            integer, intent(in) :: m
            type(hit_t), intent(in) :: h
            integer :: j
            real(wp) :: w(3), z, r
            may_hold = .true.
            if (h%d == 0.0_wp) return
            do j = 1, 4
                if (any(s%seg(:, oldseg) == s%seg(j, m))) cycle
                w = ls%xl(:, s%seg(j, m)) - h%xc
                z = dot_product(h%nhat, w)
                if (z <= 0.0_wp) cycle
                r = sqrt(max(dot_product(w, w) - z*z, 0.0_wp))
                if (h%border*(r - h%border) <= 4.0_wp*abs(h%d)*z) return
            end do
            may_hold = .false.
        end function may_hold

        !> Tracking along an opposite region: from the master node, step to
        !> the neighbour closest to the slave while that gets closer.
        integer function track(start) result(c)
            integer, intent(in) :: start
            integer :: step, q, nb, bestn
            real(wp) :: dbest, dd
            c = start
            dbest = sum((ls%xl(:, c) - ls%xl(:, sn))**2)
            do step = 1, max_track_steps
                bestn = 0
                do q = s%nn_ptr(c), s%nn_ptr(c + 1) - 1
                    nb = s%nn_list(q)
                    if (nb == sn .or. iand(s%node_side(nb), want) == 0) cycle
                    dd = sum((ls%xl(:, nb) - ls%xl(:, sn))**2)
                    if (dd < dbest) then
                        dbest = dd
                        bestn = nb
                    end if
                end do
                if (bestn == 0) exit
                c = bestn
            end do
        end function track

        !> The tetrahedron test (Eqs. 1-3) and the bounding-box test, on the
        !> segments at master node mn: true if one of them admits contact.
        logical function screened_in(mn)
            integer, intent(in) :: mn
            integer :: q, m, a, p1, p2, p3, nnd
            real(wp) :: h, area2, tm, c(3), warp
            real(wp) :: xa(3), x1(3), x2(3), x3(3), xs(3)
            screened_in = .false.
            xs = ls%xl(:, sn)
            xa = ls%xl(:, mn)
            do q = s%seg_ptr(mn), s%seg_ptr(mn + 1) - 1
                m = s%seg_list(q)
                ! both tests must pass; the bounding box of the segment, grown
                ! by the thicknesses, is the cheaper one: first (the box of the
                ! three nodes at mn alone left out the part of the segment near
                ! its far corner, where a slave whose list holds mn alone went
                ! unseen until it was deep in a crushed tube's band)
                if (outside_box(m)) cycle
                nnd = seg_nodes(s%seg(:, m))
                a = findloc(s%seg(1:nnd, m), mn, 1)
                ! the nodes after and before mn, and the one after that (a
                ! triangle: its third node again)
                p1 = s%seg(merge(1, a + 1, a == nnd), m)
                p2 = s%seg(merge(nnd, a - 1, a == 1), m)
                p3 = a + 2
                if (p3 > nnd) p3 = p3 - nnd
                x1 = ls%xl(:, p1)
                x2 = ls%xl(:, p2)
                x3 = ls%xl(:, s%seg(p3, m))
                tm = s%seg_t(m)
                if (s%seg_kind(m) == seg_shell) tm = 0.5_wp*tm
                ! characteristic height h = 3 V / A of the tetrahedron slave,
                ! master node and its two neighbours on the segment (Eq. 1):
                ! the slave's distance along the normal c / |c| of the base
                c = cross(x1 - xa, x2 - xa)
                area2 = sqrt(c(1)**2 + c(2)**2 + c(3)**2)
                if (area2 <= 0.0_wp) cycle
                h = (c(1)*(xs(1) - xa(1)) + c(2)*(xs(2) - xa(2)) + c(3)*(xs(3) - xa(3)))/area2
                ! a warped segment leaves the base plane by up to the height of
                ! its fourth node: the bounds of Eqs. (2)-(3) grow by it
                warp = abs(dot_product(c, x3 - xa))/area2
                if (s%seg_kind(m) == seg_shell) then
                    if (h > tm + ts + warp + ls%lead .or. h < -tm - ts - warp - ls%lead) cycle     ! Eq. (2)
                else
                    if (h > ts + warp + ls%lead .or. h < ts - tm - warp) cycle                  ! Eq. (3)
                end if
                screened_in = .true.
                return
            end do
        end function screened_in
    end subroutine find_contact

    !> The clearances of the slaves searched since the bounds were last
    !> taken in (lists%at beyond cl%search; all at the first call):
    !> lists%gap at the slave's position then (lists%xg) and the odometer
    !> then (lists%og). Search number nsearch is the last.
    subroutine reset_clearance(s, lists, nsearch, cl, owned)
        type(surface_t), intent(in) :: s
        type(master_lists_t), intent(in) :: lists
        integer, intent(in) :: nsearch
        type(clearance_t), intent(inout) :: cl
        !> (per slave: this rank searches it; absent: every slave) the
        !> slaves whose bounds are held here, once, at the first call
        logical, intent(in), optional :: owned(:)
        integer :: k, r, n, o
        if (.not. allocated(cl%g)) then
            allocate (cl%row(s%nslave))
            n = 0
            do k = 1, s%nslave
                cl%row(k) = 0
                if (present(owned)) then
                    if (.not. owned(k)) cycle
                end if
                n = n + 1
                cl%row(k) = n
            end do
            allocate (cl%g(n), cl%x(3, n), cl%u(n), cl%wait(n), cl%nnear(n), cl%near(max_near, n))
            cl%search = -1
        end if
        do k = 1, s%nslave
            r = cl%row(k)
            if (r == 0) cycle
            o = list_row(lists, k)
            if (o == 0) cycle
            if (lists%at(o) <= cl%search) cycle
            cl%g(r) = lists%gap(o)
            cl%x(:, r) = lists%xg(:, o)
            cl%u(r) = lists%og(o)
            cl%wait(r) = 0
            cl%nnear(r) = 0
        end do
        cl%search = nsearch
    end subroutine reset_clearance

    !> Slave number i's clearance now (positions ls%xl): the bound of
    !> master_lists_t%gap over the segments at the nodes of its pool, which
    !> by the search's bound are the only ones it can reach before the next
    !> search. Its box and six separating axes bound the distance to each
    !> segment. The segments whose bound is within near_leads leads (at
    !> most max_near, the nearest) are left out of it into the near set
    !> near(1:nnear): the bound is that of the others. Where it comes out
    !> no more than twice the lead (no clearance now) it stops there and
    !> returns -1, no bound, with no near set.
    real(wp) function fresh_clearance(s, lists, ls, i, near, nnear) result(g)
        type(surface_t), intent(in) :: s
        type(master_lists_t), intent(in) :: lists
        type(local_search_t), intent(in) :: ls
        integer, intent(in) :: i
        integer, intent(out) :: near(max_near), nnear
        integer :: sn, want, j, m, q, sg, k, nseen, kmax
        integer :: seen(max_tried)
        real(wp) :: ts, xs(3), x4(3, 4), e(3), d2, c, sep, ax(4, 6), reach_max, tau, b, bn(max_near)
        sn = s%slave(i)
        ts = 0.5_wp*s%node_t(sn)
        xs = ls%xl(:, sn)
        want = wanted_side(s, sn)
        reach_max = 2.0_wp*ts + lists%cmax
        tau = near_leads*ls%lead
        g = huge(1.0_wp)
        nseen = 0
        nnear = 0
        do j = lists%pool_ptr(list_row(lists, i)), lists%pool_last(list_row(lists, i))
            m = lists%pool_node(j)
            ! every point of a segment at m lay within L_m of m at the
            ! search, and now within L_m + 2u (a near segment's bound is
            ! below g too: the test holds for both)
            if (norm2(ls%xl(:, m) - xs) - ls%lc(m) - 2.0_wp*(ls%odo - ls%lcodo(m)) - reach_max >= g) cycle
            do q = s%seg_ptr(m), s%seg_ptr(m + 1) - 1
                sg = s%seg_list(q)
                if (iand(s%seg_side(sg), want) == 0) cycle
                if (any(s%seg(:, sg) == sn)) cycle
                ! (a segment met again at another node passes the box test
                ! again at no harm; the axes are taken once)
                x4 = ls%xl(:, s%seg(:, sg))
                e = max(min(x4(:, 1), x4(:, 2), x4(:, 3), x4(:, 4)) - xs, &
                        xs - max(x4(:, 1), x4(:, 2), x4(:, 3), x4(:, 4)), 0.0_wp)
                d2 = sqrt(e(1)**2 + e(2)**2 + e(3)**2)
                c = reach_factor(s, sg)*(ts + s%seg_r(sg))
                if (d2 - c >= g) cycle
                if (any(seen(1:nseen) == sg)) cycle
                if (nseen < max_tried) then
                    nseen = nseen + 1
                    seen(nseen) = sg
                end if
                call separating_axes(x4, ax)
                sep = d2
                do k = 1, 6
                    sep = max(sep, ax(1, k)*xs(1) + ax(2, k)*xs(2) + ax(3, k)*xs(3) - ax(4, k))
                end do
                b = sep - c
                if (b <= tau .and. g > 2.0_wp*ls%lead) then
                    ! near: into the set; when it is full, the farthest of it
                    ! and this one goes to the bound instead
                    if (nnear < max_near) then
                        nnear = nnear + 1
                        near(nnear) = sg
                        bn(nnear) = b
                        cycle
                    end if
                    kmax = maxloc(bn, 1)
                    if (bn(kmax) > b) then
                        g = min(g, bn(kmax))
                        near(kmax) = sg
                        bn(kmax) = b
                        cycle
                    end if
                end if
                g = min(g, b)
            end do
            if (g <= 2.0_wp*ls%lead) then
                ! (the nodes not yet met may hold nearer segments: the value
                ! is no bound, and must not serve as one at a later cycle,
                ! whose lead may be shorter)
                g = -1
                nnear = 0
                return
            end if
        end do
    end function fresh_clearance

end module xd_contact_local_search
