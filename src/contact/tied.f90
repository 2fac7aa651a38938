!> Tied contacts (*CONTACT_TIED_NODES_TO_SURFACE, _SHELL_EDGE_TO_SURFACE,
!> _SURFACE_TO_SURFACE): slave nodes held on the master surface for the
!> whole run, a kinematic constraint (no springs, no search after t = 0).
!>
!> At t = 0 each slave node is projected on the nearest master segment
!> (closest point, project_segment of the segment check, edges and corners
!> included). It is tied if that point lies within the tie distance:
!>
!>   the slave's shell half thickness plus the segment's (SST, MST and
!>   SFST, SFMT as the sliding contacts take them; 0 on a solid), and at
!>   least 5% of the segment's shorter diagonal.
!>
!> A tied node is moved onto that point before the mesh is set up (a
!> stress-free start) and named in d3hsp with its segment and the distance
!> moved; a slave with no segment within reach is named as not tied.
!>
!> The search tries, for each slave, the segments of its cell in a uniform
!> grid of the segments' boxes grown by their tie distance (linear in the
!> model's size).
!>
!> Each cycle, with N_j the segment's shape functions at the tie point
!> (Hallquist's tied interface of DYNA3D):
!>
!> 1. the slave's force (and, for a shell edge, its moment) goes to the
!>    master nodes, N_j f_s, and the slave's own is zeroed;
!> 2. a master node's acceleration is its force over its mass plus the
!>    slave masses it carries, sum N_j m_s (its moment likewise over its
!>    rotary inertia plus N_j I_s);
!> 3. after every other velocity update (walls, prescribed motion, rigid
!>    bodies) the slave's velocity is the segment's there, v_s = sum N_j
!>    v_j (its angular velocity likewise, for a shell edge).
!>
!> Total force and linear momentum are kept exactly (sum of N_j = 1); the
!> slave keeps its own mass for the energies. The shell edge's rotations
!> are tied where the slave and every node of its segment have rotary
!> inertia (a shell surface); on a solid face only the translations are
!> tied, and d3hsp says so per interface. A slave on a rigid body, or a
!> slave that is also a node of another tie's segment (a chain), is a
!> set-up error naming the node. A master node on a rigid body passes the
!> slave's force to the body (the body's mass does not grow by it).
module xd_contact_tied
    use xd_kinds, only: wp, dp
    use xd_core_dofs, only: free3
    use, intrinsic :: iso_fortran_env, only: int8
    use xd_core_errors, only: error_t, make_error
    use xd_core_strings, only: itoa, rtoa
    use xd_core_sorting, only: where_true
    use xd_model, only: model_t, contact_t, styp_node_set, styp_part, styp_part_set, ct_tied_shell_edge, ct_tiebreak
    use xd_contact_surface, only: faces_t, build_faces, segment_diagonals, seg_shell
    use xd_contact_segment_check, only: project_segment
    use xd_core_vectors, only: cross
    use xd_contact_contact, only: faces_of, contact_step_scale
    implicit none
    private
    public :: ties_t, place_ties, start_ties, tie_forces, tie_accelerations, tie_velocities, tie_kinetic, tie_break, &
              cohesive_law

    integer, parameter :: max_named = 2000   !< nodes named per interface (all counted)
    integer, parameter :: tie_held = 0, tie_softening = 1, tie_broken = 2
    !> OPTION 9: held by the cohesive law's springs, undamaged or softening
    integer, parameter :: tie_cohesive = 3, tie_damaging = 4

    !> A uniform grid of the master segments for the set-up search.
    type :: seg_grid_t
        real(wp) :: lo(3) = 0, h = 1
        integer :: n(3) = 1
        integer, allocatable :: ptr(:), item(:)   !< cell -> segments (indices into the interface's list)
    end type seg_grid_t

    !> The ties of every tied interface, one entry per tied slave.
    type :: ties_t
        integer :: n = 0                      !< tied slave nodes
        integer, allocatable :: slave(:)      !< (n) model node
        integer, allocatable :: mnode(:, :)   !< (4, n) the segment's model nodes (triangle: N4 = N3)
        real(wp), allocatable :: phi(:, :)    !< (4, n) shape functions at the tie point
        integer, allocatable :: ifc(:)        !< (n) interface
        integer, allocatable :: spart(:)      !< (n) a part the slave node belongs to (0: none found)
        logical, allocatable :: rot(:)        !< (n) rotations tied as well
        logical, allocatable :: offset(:)     !< (n) _OFFSET: the slave kept at its gap
        real(wp), allocatable :: rloc(:, :)   !< (3, n) the gap in the segment's frame at t = 0
        !> (n) the mass each of the segment's nodes adds for the gap's rotary
        !> inertia, m_s |r|^2 / sum |y_j|^2
        real(wp), allocatable :: mrot(:)
        real(wp), allocatable :: death(:)     !< (tied interfaces) DT: the ties end then
        integer, allocatable :: master(:)     !< (nm) model nodes that carry a slave
        logical, allocatable :: m_rigid(:)    !< (nm) on a rigid body (the body takes the force)
        real(wp), allocatable :: madd(:)      !< (nm) slave mass carried (this cycle's ties)
        real(wp), allocatable :: jadd(:)      !< (nm) slave rotary inertia carried
        real(wp), allocatable :: mnodal(:)    !< (nnode) madd by model node (0 off the masters)
        real(wp), allocatable :: vold(:, :)   !< (3, n) the slave's velocity before this step's update
        integer, allocatable :: mpos(:, :)    !< (4, n) position of mnode in master
        ! tiebreak (*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK)
        integer, allocatable :: state(:)      !< (n) tie_held, tie_softening (OPTION 2), tie_broken
        real(wp), allocatable :: area(:)      !< (n) the slave's share of its side's face area
        real(wp), allocatable :: sgn(:)       !< (n) +1 or -1: the segment's normal turned from master to slave
        real(wp), allocatable :: fs0(:, :)    !< (3, n) the slave's own force this cycle (before the tie took it)
        real(wp), allocatable :: f0(:, :)     !< (3, n) OPTION 2: the interface force at failure, segment frame
        real(wp), allocatable :: dmg(:)       !< (n) OPTION 2: damage, the separation over PARAM (0-1)
        real(wp), allocatable :: urel(:, :)   !< (3, n) OPTION 2: the slave's separation from its tie place
        integer, allocatable :: opt(:)        !< (tied interfaces) tiebreak OPTION (0: a tied contact)
        logical :: tiebreak = .false.         !< some interface is a tiebreak
        real(wp), allocatable :: nfls(:), sfls(:), param(:)   !< (tied interfaces)
        !> (tied interfaces) OPTION 9: GIC, GIIC, the normal and tangential
        !> stiffnesses CN and CT2CN CN
        real(wp), allocatable :: gic(:), giic(:), kn(:), kt(:)
        real(wp), allocatable :: trac(:, :)   !< (2, n) OPTION 9: the normal and shear traction this cycle
        !> the stable step of the stiffest cohesive spring, 0.35 sqrt(m / k),
        !> and its node (huge, 0: none)
        real(wp) :: dt_limit = huge(1.0_wp)
        integer :: dt_node = 0
        real(dp) :: ework = 0                 !< work the softening interfaces took (dissipated)
        integer :: nbroken = 0
    end type ties_t

contains

    !> Projects the slaves of every *CONTACT_TIED_... on its master surface at
    !> t = 0 and moves the tied ones onto it (model%x0); `txt` is what d3hsp
    !> takes.
    subroutine place_ties(model, td, txt, error)
        type(model_t), intent(inout) :: model
        type(ties_t), intent(out) :: td
        character(len=:), allocatable, intent(out) :: txt
        type(error_t), allocatable, intent(out) :: error
        type(faces_t) :: faces
        logical, allocatable :: in_s(:), in_m(:), on(:)
        integer, allocatable :: slaves(:), segs(:), nd(:)
        integer :: i, k, j, s, best, kind, nnamed, nfree, ntied, q, k0, kc, qa, qb, qq
        real(wp) :: hs_max
        type(seg_grid_t) :: gr
        logical, allocatable :: tmark(:)
        real(wp) :: xm(3, 4), xi, eta, nsh(4), p(3), d, dbest, tol, dmin, dmax, moved, tbest, phib(4), en(3, 3), gp(3), sg
        real(wp), allocatable :: hnode(:), narea(:), nout(:, :)
        integer, allocatable :: npart_of(:)
        character(len=300) :: buf
        txt = ''
        if (model%ntied == 0) then
            allocate (td%slave(0), td%mnode(4, 0), td%phi(4, 0), td%ifc(0), td%rot(0), td%death(0), &
                      td%offset(0), td%rloc(3, 0), td%spart(0), td%area(0), td%opt(0), td%nfls(0), td%sfls(0), &
                      td%param(0), td%sgn(0), td%gic(0), td%giic(0), td%kn(0), td%kt(0))
            return
        end if
        call build_faces(model, model%x0, faces)
        allocate (in_s(faces%n), in_m(faces%n), on(model%nnode), td%death(model%ntied), td%opt(model%ntied), &
                  td%nfls(model%ntied), td%sfls(model%ntied), td%param(model%ntied), td%area(0), narea(model%nnode), &
                  nout(3, model%nnode), td%sgn(0), tmark(model%nnode), td%gic(model%ntied), td%giic(model%ntied), &
                  td%kn(model%ntied), td%kt(model%ntied))
        allocate (td%slave(0), td%mnode(4, 0), td%phi(4, 0), td%ifc(0), td%rot(0), td%offset(0), td%rloc(3, 0))
        ! a part of each node (its first face's), for the energies by part
        allocate (npart_of(model%nnode))
        npart_of = 0
        do j = faces%n, 1, -1
            npart_of(faces%node(:, j)) = faces%part(j)
        end do
        ! the shell thickness at each node (the slave's half goes into the
        ! tie distance)
        hnode = faces%node_thick
        do i = 1, model%ntied
            associate (c => model%tied(i))
                td%death(i) = c%dt
                td%opt(i) = merge(c%tb_option, 0, c%kind == ct_tiebreak)
                td%nfls(i) = c%nfls
                td%sfls(i) = c%sfls
                td%param(i) = c%tb_param
                td%gic(i) = c%tb_gic
                td%giic(i) = c%tb_giic
                td%kn(i) = c%tb_cn
                td%kt(i) = c%tb_ct2cn*c%tb_cn
                call faces_of(model, faces, c, c%msid, c%mstyp, c%mref, 'MSID', in_m, error)
                if (allocated(error)) return
                if (c%sstyp == styp_node_set) then
                    slaves = model%set(c%sref)%member_ix
                    on = .false.
                    on(slaves) = .true.
                else if (c%keyword == 'CONTACT_SPOTWELD' .and. model%nbeam > 0) then
                    ! the spot welds' beams of the slave parts: their nodes
                    on = .false.
                    do j = 1, model%nbeam
                        if (beam_in(model%beam_part(j))) on(model%beam_conn(1:2, j)) = .true.
                    end do
                    slaves = where_true(on)
                    in_s = .false.
                else
                    call faces_of(model, faces, c, c%ssid, c%sstyp, c%sref, 'SSID', in_s, error)
                    if (allocated(error)) return
                    on = .false.
                    do j = 1, faces%n
                        if (in_s(j)) on(faces%node(:, j)) = .true.
                    end do
                    slaves = where_true(on)
                end if
                ! the slave side's outward normals at its nodes (solids)
                narea = 0
                nout = 0
                do j = 1, faces%n
                    if (c%sstyp == styp_node_set) then
                        if (.not. any(on_set(faces%node(:, j)))) cycle
                    else if (.not. in_s(j)) then
                        cycle
                    end if
                    call add_area(faces%node(:, j), faces%kind(j) /= seg_shell)
                end do
                segs = where_true(in_m)
                if (size(segs) == 0) then
                    call make_error(error, trim(c%at)//': *'//trim(c%keyword)//' '//itoa(c%id)// &
                                    ': the master side (MSID) has no segments')
                    return
                end if
                txt = txt//' tied contact '//itoa(c%id)//' (*'//trim(c%keyword)//'): '
                k0 = size(td%slave) + 1
                hs_max = 0
                if (size(slaves) > 0) hs_max = maxval(hnode(slaves))
                call build_grid(segs, hs_max, c, gr)
                nnamed = 0
                nfree = 0
                ntied = 0
                do k = 1, size(slaves)
                    s = slaves(k)
                    p = model%x0(:, s)
                    best = 0
                    dbest = huge(1.0_wp)
                    tbest = 0
                    ! the candidates: the segments whose box, grown by their tie
                    ! distance, holds the slave's cell
                    kc = cell_of(gr, p)
                    if (kc == 0) then
                        qa = 1
                        qb = 0
                    else
                        qa = gr%ptr(kc)
                        qb = gr%ptr(kc + 1) - 1
                    end if
                    do qq = qa, qb
                        q = gr%item(qq)
                        j = segs(q)
                        nd = faces%node(:, j)
                        ! a node of the segment is not tied to it
                        if (any(nd == s)) cycle
                        xm = model%x0(:, nd)
                        ! a cheap reject: farther from every node than the
                        ! segment's longest diagonal and the tie distance
                        call segment_diagonals(xm, dmin, dmax)
                        tol = tie_distance(c, faces, j, hnode(s), dmin)
                        if (minval(norm2(xm - spread(p, 2, 4), 1)) > dmax + tol) cycle
                        call project_segment(xm, p, xi, eta, nsh, kind)
                        d = norm2(p - matmul(xm, nsh))
                        if (d <= tol .and. d < dbest) then
                            best = j
                            dbest = d
                            tbest = tol
                            phib = nsh
                        end if
                    end do
                    if (best == 0) then
                        nfree = nfree + 1
                        if (nnamed < max_named) then
                            nnamed = nnamed + 1
                            txt = txt//new_line('a')//'   node '//itoa(model%node_id(s))// &
                                  ' not tied: no master segment within the tie distance'
                        end if
                        cycle
                    end if
                    ntied = ntied + 1
                    nd = faces%node(:, best)
                    moved = dbest
                    phib = phibest(phib, nd)
                    td%offset = [td%offset, c%tied_offset]
                    if (c%tied_offset) then
                        ! the gap kept, in the segment's own frame
                        td%rloc = reshape([td%rloc, matmul(transpose(seg_frame(model%x0(:, nd))), &
                                                           model%x0(:, s) - matmul(model%x0(:, nd), phib))], &
                                          [3, size(td%offset)])
                        moved = 0
                    else
                        td%rloc = reshape([td%rloc, [0.0_wp, 0.0_wp, 0.0_wp]], [3, size(td%offset)])
                        model%x0(:, s) = matmul(model%x0(:, nd), phib)
                    end if
                    ! the normal's sense from the master to the slave side:
                    ! by the gap, or (touching) against the slave solid's
                    ! outward normal
                    en = seg_frame(model%x0(:, nd))
                    gp = model%x0(:, s) - matmul(model%x0(:, nd), phib)
                    if (norm2(gp) > 1.0e-6_wp*dmax_of(model%x0(:, nd))) then
                        sg = sign(1.0_wp, dot_product(gp, en(:, 3)))
                    else if (norm2(nout(:, s)) > 0.0_wp) then
                        sg = sign(1.0_wp, -dot_product(nout(:, s), en(:, 3)))
                    else
                        sg = 1
                    end if
                    td%sgn = [td%sgn, sg]
                    td%slave = [td%slave, s]
                    td%area = [td%area, 0.0_wp]   ! set once this interface's glued faces are known
                    td%ifc = [td%ifc, i]
                    td%rot = [td%rot, c%kind == ct_tied_shell_edge]
                    td%mnode = reshape([td%mnode, nd], [4, size(td%slave)])
                    td%phi = reshape([td%phi, phib], [4, size(td%slave)])
                    if (nnamed < max_named) then
                        nnamed = nnamed + 1
                        if (c%tied_offset) then
                            write (buf, '(a,i0,a,4(1x,i0),a,es10.3,a,es10.3,a)') '   node ', model%node_id(s), &
                                ' tied to segment', model%node_id(nd), ' (kept at its gap ', dbest, &
                                ' from it; tie distance ', tbest, ')'
                        else
                            write (buf, '(a,i0,a,4(1x,i0),a,es10.3,a,es10.3,a)') '   node ', model%node_id(s), &
                                ' tied to segment', model%node_id(nd), ' (moved ', moved, ' onto it; tie distance ', &
                                tbest, ')'
                        end if
                        txt = txt//new_line('a')//trim(buf)
                    end if
                end do
                ! each tied slave's share of the area of the slave side's
                ! faces whose nodes are all tied here (a tiebreak's stress is
                ! its interface force over it): a quarter of a
                ! quadrilateral, a third of a triangle
                tmark = .false.
                tmark(td%slave(k0:)) = .true.
                narea = 0
                do j = 1, faces%n
                    if (c%sstyp == styp_node_set) then
                        if (.not. all(tmark(faces%node(:, j)))) cycle
                    else if (.not. in_s(j) .or. .not. all(tmark(faces%node(:, j)))) then
                        cycle
                    end if
                    call add_area(faces%node(:, j), .false.)
                end do
                td%area(k0:) = narea(td%slave(k0:))
                txt = txt//new_line('a')//'   '//itoa(ntied)//' slave nodes tied, '//itoa(nfree)//' not tied'
                if (nnamed == max_named) txt = txt//' (the first '//itoa(max_named)//' named)'
                txt = txt//new_line('a')
            end associate
        end do
        td%n = size(td%slave)
        td%spart = npart_of(td%slave)
        td%tiebreak = any(td%opt > 0)
    contains
        !> A uniform grid over the segments' boxes, each grown by the segment's
        !> largest tie distance (its own half thickness and the thickest
        !> slave's): any segment within a slave's tie distance holds the
        !> slave's cell, so the search tries those alone (linear in the
        !> model instead of slaves x segments). Cells about a segment wide,
        !> at most 8 per segment.
        subroutine build_grid(segs, hs_max, c, gr)
            integer, intent(in) :: segs(:)
            real(wp), intent(in) :: hs_max
            type(contact_t), intent(in) :: c
            type(seg_grid_t), intent(out) :: gr
            real(wp), allocatable :: lo(:, :), hi(:, :)
            real(wp) :: xm(3, 4), d1, d2, r, top(3)
            integer :: q, n, i1(3), i2(3), a, b, cc, pass, kk
            integer, allocatable :: fill(:)
            n = size(segs)
            allocate (lo(3, n), hi(3, n))
            gr%h = 0
            do q = 1, n
                xm = model%x0(:, faces%node(:, segs(q)))
                call segment_diagonals(xm, d1, d2)
                r = tie_distance(c, faces, segs(q), hs_max, d1)
                lo(:, q) = minval(xm, 2) - r
                hi(:, q) = maxval(xm, 2) + r
                gr%h = gr%h + d2/n
            end do
            gr%lo = minval(lo, 2)
            top = maxval(hi, 2)
            gr%h = max(gr%h, maxval(top - gr%lo)*1.0e-6_wp, tiny(1.0_wp))
            do
                gr%n = max(1, ceiling((top - gr%lo)/gr%h))
                if (product(real(gr%n, dp)) <= 8.0_dp*n + 64) exit
                gr%h = 1.5_wp*gr%h
            end do
            allocate (gr%ptr(product(gr%n) + 1), fill(product(gr%n)))
            ! two passes: count, then fill
            do pass = 1, 2
                if (pass == 1) then
                    gr%ptr = 0
                else
                    gr%ptr(1) = 1
                    do cc = 1, product(gr%n)
                        gr%ptr(cc + 1) = gr%ptr(cc + 1) + gr%ptr(cc)
                    end do
                    allocate (gr%item(gr%ptr(product(gr%n) + 1) - 1))
                    fill = gr%ptr(1:product(gr%n))
                end if
                do q = 1, n
                    i1 = min(gr%n, 1 + int((lo(:, q) - gr%lo)/gr%h))
                    i2 = min(gr%n, 1 + int((hi(:, q) - gr%lo)/gr%h))
                    do b = i1(3), i2(3)
                        do a = i1(2), i2(2)
                            do cc = i1(1), i2(1)
                                kk = cc + gr%n(1)*((a - 1) + gr%n(2)*(b - 1))
                                if (pass == 1) then
                                    gr%ptr(kk + 1) = gr%ptr(kk + 1) + 1
                                else
                                    gr%item(fill(kk)) = q
                                    fill(kk) = fill(kk) + 1
                                end if
                            end do
                        end do
                    end do
                end do
            end do
        end subroutine build_grid

        !> part p on the slave side of the spot weld contact c (SSTYP 2 a part
        !> set, 3 a part)
        logical function beam_in(p)
            integer, intent(in) :: p
            associate (c => model%tied(i))
                select case (c%sstyp)
                case (styp_part)
                    beam_in = p == c%sref
                case (styp_part_set)
                    beam_in = any(model%set(c%sref)%member_ix == p)
                case default
                    beam_in = .false.
                end select
            end associate
        end function beam_in

        real(wp) function dmax_of(xq)
            real(wp), intent(in) :: xq(3, 4)
            real(wp) :: d1, d2
            call segment_diagonals(xq, d1, d2)
            dmax_of = d2
        end function dmax_of

        logical elemental function on_set(nd)
            integer, intent(in) :: nd
            on_set = on(nd)
        end function on_set

        subroutine add_area(nd, solid)
            integer, intent(in) :: nd(4)
            logical, intent(in) :: solid
            real(wp) :: a, an(3)
            integer :: q
            an = 0.5_wp*cross(model%x0(:, nd(3)) - model%x0(:, nd(1)), model%x0(:, nd(4)) - model%x0(:, nd(2)))
            a = norm2(an)
            ! a solid face's outward normal (its nodes run counter-clockwise
            ! seen from outside), summed at its nodes
            if (solid) then
                do q = 1, 4
                    nout(:, nd(q)) = nout(:, nd(q)) + an
                end do
            end if
            if (nd(4) == nd(3)) then
                do q = 1, 3
                    narea(nd(q)) = narea(nd(q)) + a/3
                end do
            else
                do q = 1, 4
                    narea(nd(q)) = narea(nd(q)) + a/4
                end do
            end if
        end subroutine add_area

        !> a triangle's fourth shape function on its repeated node is 0
        pure function phibest(ph, nn) result(r)
            real(wp), intent(in) :: ph(4)
            integer, intent(in) :: nn(4)
            real(wp) :: r(4)
            r = ph
            if (nn(4) == nn(3)) then
                r(3) = r(3) + r(4)
                r(4) = 0
            end if
        end function phibest
    end subroutine place_ties

    !> The cell of grid gr that holds point p (0: outside the grid).
    pure integer function cell_of(gr, p) result(k)
        type(seg_grid_t), intent(in) :: gr
        real(wp), intent(in) :: p(3)
        integer :: i(3)
        k = 0
        if (any(p < gr%lo)) return
        i = 1 + int((p - gr%lo)/gr%h)
        if (any(i > gr%n)) return
        k = i(1) + gr%n(1)*((i(2) - 1) + gr%n(2)*(i(3) - 1))
    end function cell_of

    !> The tie distance of slave (shell half thickness hs2*2 at the node)
    !> against face j: the half thicknesses (SST/MST, SFST/SFMT as the
    !> sliding contacts take them), at least 5% of the segment's shorter
    !> diagonal.
    pure real(wp) function tie_distance(c, faces, j, hs, dmin) result(tol)
        type(contact_t), intent(in) :: c
        type(faces_t), intent(in) :: faces
        integer, intent(in) :: j
        real(wp), intent(in) :: hs, dmin
        real(wp) :: ts, tm
        ts = hs*c%sfst
        if (c%sst > 0.0_wp) ts = c%sst
        tm = 0
        if (faces%kind(j) == seg_shell) tm = faces%thick(j)*c%sfmt
        if (c%mst > 0.0_wp) tm = c%mst
        tol = max(0.5_wp*(ts + tm), 0.05_wp*dmin)
    end function tie_distance

    !> After the mesh is set up: which ties hold rotations, the master list,
    !> the set-up checks (a slave on a rigid body, a chain), and the slaves'
    !> initial velocities made the segment's. `txt` adds to d3hsp.
    subroutine start_ties(model, td, member, x0, mass, v, vr, irot, txt, error)
        type(model_t), intent(in) :: model
        type(ties_t), intent(inout) :: td
        logical, intent(in) :: member(:)          !< node of a rigid body
        real(wp), intent(in) :: x0(:, :), mass(:)
        real(wp), intent(inout) :: v(:, :)
        real(wp), allocatable, intent(inout) :: vr(:, :)
        real(wp), allocatable, intent(in) :: irot(:)
        character(len=:), allocatable, intent(out) :: txt
        type(error_t), allocatable, intent(out) :: error
        integer, allocatable :: pos(:)
        logical, allocatable :: is_m(:)
        integer :: k, i, nrot, nlin, s, noff
        real(wp) :: dv, vmax, xm(3, 4), r(3), y(3, 4)
        real(dp) :: madded
        real(wp), allocatable :: vs(:, :)
        txt = ''
        if (td%n == 0) return
        allocate (pos(model%nnode), is_m(model%nnode))
        is_m = .false.
        do k = 1, td%n
            is_m(td%mnode(:, k)) = .true.
        end do
        ! (pos counts each node's ties here, before it holds positions)
        pos = 0
        do k = 1, td%n
            pos(td%slave(k)) = pos(td%slave(k)) + 1
        end do
        do k = 1, td%n
            s = td%slave(k)
            if (member(s)) then
                call make_error(error, tie_slave(k)//' is on a rigid body (use *CONSTRAINED_EXTRA_NODES to join a '// &
                                'node to a body)')
                return
            end if
            if (is_m(s)) then
                call make_error(error, tie_slave(k)//' is also a node of a tied segment (a chain of ties is not '// &
                                'supported)')
                return
            end if
            if (pos(s) > 1) then
                call make_error(error, 'slave node '//itoa(model%node_id(s))//' is tied by more than one '// &
                                '*CONTACT_TIED_... (tie it once)')
                return
            end if
        end do
        td%master = where_true(is_m)
        pos = 0
        pos(td%master) = [(i, i=1, size(td%master))]
        allocate (td%mpos(4, td%n), td%m_rigid(size(td%master)), td%madd(size(td%master)), td%jadd(size(td%master)))
        do k = 1, td%n
            td%mpos(:, k) = pos(td%mnode(:, k))
        end do
        td%m_rigid = member(td%master)
        td%madd = 0
        td%jadd = 0
        allocate (td%mnodal(model%nnode), td%vold(3, td%n))
        td%mnodal = 0
        td%vold = 0
        ! rotations where the slave and its segment's nodes have rotary inertia
        nrot = 0
        nlin = 0
        do k = 1, td%n
            if (.not. td%rot(k)) cycle
            if (.not. allocated(irot)) then
                td%rot(k) = .false.
            else
                td%rot(k) = irot(td%slave(k)) > 0.0_wp .and. all(irot(td%mnode(:, k)) > 0.0_wp .or. td%phi(:, k) == 0.0_wp)
            end if
            if (td%rot(k)) then
                nrot = nrot + 1
            else
                nlin = nlin + 1
            end if
        end do
        ! offset ties: the gap fixed in the segment's frame, its moment r x f_s
        ! passed as a couple of nodal forces, and m_s |r|^2 / sum |y|^2 added
        ! to each of the segment's nodes' mass: the gap's rotary inertia as
        ! the nodes' translations carry it (without it a gap long against
        ! its segment, seen through the couple, outruns the nodes' inertia:
        ! a lever of shells tied 5-35 mm beside a plate's edge blew up in 12
        ! cycles)
        allocate (td%mrot(td%n), td%state(td%n), td%fs0(3, td%n), td%f0(3, td%n), td%dmg(td%n), td%urel(3, td%n), &
                  td%trac(2, td%n))
        td%mrot = 0
        td%state = tie_held
        td%trac = 0
        ! OPTION 9: springs, not a constraint
        do k = 1, td%n
            if (td%opt(td%ifc(k)) == 9) td%state(k) = tie_cohesive
        end do
        call cohesive_start()
        td%fs0 = 0
        td%f0 = 0
        td%dmg = 0
        td%urel = 0
        noff = 0
        madded = 0
        do k = 1, td%n
            if (.not. td%offset(k) .or. td%state(k) == tie_cohesive) cycle
            xm = x0(:, td%mnode(:, k))
            r = x0(:, td%slave(k)) - matmul(xm, td%phi(:, k))
            y = xm - spread(sum(xm, 2)/4, 2, 4)
            td%mrot(k) = mass(td%slave(k))*dot_product(r, r)/sum(y**2)
            madded = madded + 4*td%mrot(k)
            noff = noff + 1
        end do
        if (noff > 0) txt = txt//' tied offsets: '//itoa(noff)//' slave nodes held at their gaps in their '// &
                            'segments'' frames; the segments'' nodes carry '//rtoa(madded)//' of added mass '// &
                            'for the gaps'' rotary inertia (in the kinetic energy, booked to the slaves'' parts)'// &
                            new_line('a')
        if (nrot + nlin > 0) txt = txt//' tied shell edges: '//itoa(nrot)//' slave nodes with rotations tied, '// &
                                   itoa(nlin)//' with translations only (a segment or slave without rotary inertia, '// &
                                   'such as a solid face)'//new_line('a')
        ! the slaves start with the segment's velocity
        vmax = 0
        dv = 0
        vs = v(:, td%slave)
        call tie_velocities(td, 0.0_dp, 0.0_wp, x0, v, vr)
        do k = 1, td%n
            vmax = max(vmax, norm2(vs(:, k)))
            dv = max(dv, norm2(v(:, td%slave(k)) - vs(:, k)))
        end do
        if (dv > 1.0e-12_wp*max(vmax, tiny(1.0_wp))) txt = txt//' tied slaves: initial velocities set to their '// &
            'segments'' (largest change '//rtoa(real(dv, dp))//')'//new_line('a')
    contains
        !> OPTION 9: each interface's law in d3hsp (the separations at the
        !> peak and at failure in modes I and II), and the springs' stable
        !> step, as the contact springs': each node's stiffness, its own
        !> spring as a slave and N_j of its slaves' as a master, k = A
        !> max(CN, CT); dt < 0.35 sqrt(m / k).
        subroutine cohesive_start()
            real(wp), allocatable :: knode(:)
            real(wp) :: kk, dtk
            integer :: i, q, j
            character(len=400) :: line
            if (.not. any(td%state == tie_cohesive)) return
            allocate (knode(model%nnode))
            knode = 0
            do k = 1, td%n
                if (td%state(k) /= tie_cohesive) cycle
                i = td%ifc(k)
                kk = td%area(k)*max(td%kn(i), td%kt(i))
                knode(td%slave(k)) = knode(td%slave(k)) + kk
                do q = 1, 4
                    knode(td%mnode(q, k)) = knode(td%mnode(q, k)) + td%phi(q, k)*kk
                end do
            end do
            do j = 1, model%nnode
                if (knode(j) <= 0.0_wp .or. mass(j) <= 0.0_wp .or. member(j)) cycle
                dtk = contact_step_scale*sqrt(mass(j)/knode(j))
                if (dtk < td%dt_limit) then
                    td%dt_limit = dtk
                    td%dt_node = j
                end if
            end do
            do i = 1, model%ntied
                if (td%opt(i) /= 9) cycle
                associate (c => model%tied(i))
                    write (line, '(a,i0,a,4(es10.3,a),es9.2,a,2(es10.3,a),es10.3,a,es10.3,a)') &
                        ' tiebreak ', c%id, ' OPTION 9 (cohesive): peak tractions T ', td%nfls(i), ', S ', td%sfls(i), &
                        '; GIC ', td%gic(i), ', GIIC ', td%giic(i), '; XMU ', td%param(i), &
                        '; stiffnesses CN ', td%kn(i), ', CT ', td%kt(i), '; mode I opens from ', &
                        td%nfls(i)/td%kn(i), ' to ', 2*td%gic(i)/td%nfls(i), ','
                    txt = txt//trim(line)
                    write (line, '(a,es10.3,a,es10.3,a)') ' mode II from ', td%sfls(i)/td%kt(i), ' to ', &
                        2*td%giic(i)/td%sfls(i), ' (compression is the sliding contact''s)'
                    txt = txt//trim(line)//new_line('a')
                end associate
            end do
            if (td%dt_node > 0) then
                write (line, '(a,es10.3,a,i0,a)') ' tiebreak cohesive springs: stable step 0.35 sqrt(m / k) ', &
                    td%dt_limit, ' (node ', model%node_id(td%dt_node), ')'
                txt = txt//trim(line)//new_line('a')
            end if
        end subroutine cohesive_start

        !> Tie k's place and slave, as the set-up errors name them.
        function tie_slave(k) result(t)
            integer, intent(in) :: k
            character(len=:), allocatable :: t
            associate (c => model%tied(td%ifc(k)))
                t = trim(c%at)//': *'//trim(c%keyword)//' '//itoa(c%id)//': slave node '//itoa(model%node_id(td%slave(k)))
            end associate
        end function tie_slave
    end subroutine start_ties

    !> Whether tie k holds its slave now (before its DT, not broken).
    pure logical function holds(td, k, time)
        type(ties_t), intent(in) :: td
        integer, intent(in) :: k
        real(dp), intent(in) :: time
        holds = time <= td%death(td%ifc(k)) .and. td%state(k) == tie_held
    end function holds

    !> The tied contacts' kinetic energy by part, to add to the nodes' own:
    !> the slave masses as the dynamics move them (N_j m_s and the gap's
    !> added mass on the segment's nodes, N_j I_s on their rotations) less
    !> the slaves' own, 1/2 m v(n-1/2).v(n+1/2) as the energies take it.
    !> With it the energy ratio holds the tie's dynamics to account: they
    !> conserve this energy, not the slaves' own.
    subroutine tie_kinetic(td, mass, irot, vm, vp, wm, wp_, ke)
        type(ties_t), intent(in) :: td
        real(wp), intent(in) :: mass(:), vm(:, :), vp(:, :)
        real(wp), allocatable, intent(in) :: irot(:), wm(:, :), wp_(:, :)
        real(dp), intent(inout) :: ke(:)
        integer :: k, q, s, j
        real(dp) :: c
        ke = 0
        do k = 1, td%n
            if (td%state(k) /= tie_held) cycle
            s = td%slave(k)
            c = -0.5_dp*mass(s)*dot_product(real(vm(:, s), dp), vp(:, s))
            do q = 1, 4
                j = td%mnode(q, k)
                c = c + 0.5_dp*(td%phi(q, k)*mass(s) + td%mrot(k))*dot_product(real(vm(:, j), dp), vp(:, j))
            end do
            if (td%rot(k)) then
                c = c - 0.5_dp*irot(s)*dot_product(real(wm(:, s), dp), wp_(:, s))
                do q = 1, 4
                    j = td%mnode(q, k)
                    c = c + 0.5_dp*td%phi(q, k)*irot(s)*dot_product(real(wm(:, j), dp), wp_(:, j))
                end do
            end if
            if (td%spart(k) > 0) ke(td%spart(k)) = ke(td%spart(k)) + c
        end do
    end subroutine tie_kinetic

    !> The segment's frame (columns e1, e2, e3): e3 its normal (the
    !> diagonals' cross product), e1 along its mid-line from the N1-N4 side
    !> to the N2-N3 side, e2 = e3 x e1. A triangle (N4 = N3) likewise.
    pure function seg_frame(xm) result(e)
        real(wp), intent(in) :: xm(3, 4)
        real(wp) :: e(3, 3)
        e(:, 3) = cross(xm(:, 3) - xm(:, 1), xm(:, 4) - xm(:, 2))
        e(:, 3) = e(:, 3)/norm2(e(:, 3))
        e(:, 1) = xm(:, 2) + xm(:, 3) - xm(:, 1) - xm(:, 4)
        e(:, 1) = e(:, 1) - dot_product(e(:, 1), e(:, 3))*e(:, 3)
        e(:, 1) = e(:, 1)/norm2(e(:, 1))
        e(:, 2) = cross(e(:, 3), e(:, 1))
    end function seg_frame

    !> The segment's nodes (4 entries, a triangle's N3 twice) from their
    !> centroid, y, and their second moment J = sum (|y|^2 1 - y y^T).
    pure subroutine seg_moment(xm, y, jm)
        real(wp), intent(in) :: xm(3, 4)
        real(wp), intent(out) :: y(3, 4), jm(3, 3)
        integer :: q, i
        y = xm - spread(sum(xm, 2)/4, 2, 4)
        jm = 0
        do q = 1, 4
            do i = 1, 3
                jm(i, i) = jm(i, i) + dot_product(y(:, q), y(:, q))
            end do
            jm = jm - spread(y(:, q), 2, 3)*spread(y(:, q), 1, 3)
        end do
    end subroutine seg_moment

    !> Forces on the segment's nodes whose sum is zero and whose moment
    !> about any point is m: (J^-1 m) x y_j. They are the forces of a moment
    !> on the segment's best-fit rigid rotation.
    pure function couple_forces(xm, m) result(fq)
        real(wp), intent(in) :: xm(3, 4), m(3)
        real(wp) :: fq(3, 4), y(3, 4), jm(3, 3), w(3)
        integer :: q
        call seg_moment(xm, y, jm)
        w = solve3(jm, m)
        do q = 1, 4
            fq(:, q) = cross(w, y(:, q))
        end do
    end function couple_forces

    !> The segment's best-fit rigid spin from its nodes' velocities: J w =
    !> sum y_j x (v_j - the mean velocity).
    pure function seg_spin(xm, vm) result(w)
        real(wp), intent(in) :: xm(3, 4), vm(3, 4)
        real(wp) :: w(3), y(3, 4), u(3, 4), jm(3, 3), h(3)
        integer :: q
        call seg_moment(xm, y, jm)
        u = vm - spread(sum(vm, 2)/4, 2, 4)
        h = 0
        do q = 1, 4
            h = h + cross(y(:, q), u(:, q))
        end do
        w = solve3(jm, h)
    end function seg_spin

    !> a 3 x 3 symmetric positive definite system by Cramer's rule
    pure function solve3(a, b) result(x)
        real(wp), intent(in) :: a(3, 3), b(3)
        real(wp) :: x(3), det
        det = dot_product(a(:, 1), cross(a(:, 2), a(:, 3)))
        x(1) = dot_product(b, cross(a(:, 2), a(:, 3)))/det
        x(2) = dot_product(a(:, 1), cross(b, a(:, 3)))/det
        x(3) = dot_product(a(:, 1), cross(a(:, 2), b))/det
    end function solve3

    !> Step 1: the slaves' forces (and tied moments) to their segments' nodes;
    !> an offset slave's force also as the couple of its gap, r x f_s.
    subroutine tie_forces(td, time, x, f, mom)
        type(ties_t), intent(inout) :: td
        real(dp), intent(in) :: time
        real(wp), intent(in) :: x(:, :)
        real(wp), intent(inout) :: f(:, :)
        real(wp), allocatable, intent(inout) :: mom(:, :)
        real(wp) :: fq(3, 4), xm(3, 4)
        integer :: k, q, s
        do k = 1, td%n
            if (td%state(k) == tie_softening) call soften(k)
            if (td%state(k) == tie_cohesive .or. td%state(k) == tie_damaging) then
                if (time <= td%death(td%ifc(k))) call cohesive(k)
                cycle
            end if
            if (.not. holds(td, k, time)) cycle
            s = td%slave(k)
            td%fs0(:, k) = f(:, s)
            if (td%offset(k)) then
                xm = x(:, td%mnode(:, k))
                fq = couple_forces(xm, cross(x(:, s) - matmul(xm, td%phi(:, k)), f(:, s)))
                do q = 1, 4
                    f(:, td%mnode(q, k)) = f(:, td%mnode(q, k)) + fq(:, q)
                end do
            end if
            do q = 1, 4
                f(:, td%mnode(q, k)) = f(:, td%mnode(q, k)) + td%phi(q, k)*f(:, s)
            end do
            f(:, s) = 0
            if (td%rot(k)) then
                do q = 1, 4
                    mom(:, td%mnode(q, k)) = mom(:, td%mnode(q, k)) + td%phi(q, k)*mom(:, s)
                end do
                mom(:, s) = 0
            end if
        end do
    contains
        !> OPTION 2 after failure: the interface force at failure, turned
        !> with the segment, times 1 - D, D the slave's separation from its
        !> tie place over PARAM (never healing); the work it takes is booked
        subroutine soften(k)
            integer, intent(in) :: k
            real(wp) :: e(3, 3), u(3), fc(3), xm(3, 4)
            integer :: s
            s = td%slave(k)
            xm = x(:, td%mnode(:, k))
            e = seg_frame(xm)
            u = x(:, s) - matmul(xm, td%phi(:, k)) - matmul(e, td%rloc(:, k))
            fc = (1 - td%dmg(k))*matmul(e, td%f0(:, k))
            ! the force of the last step over its separation's change
            td%ework = td%ework - dot_product(real(fc, dp), real(u - td%urel(:, k), dp))
            td%urel(:, k) = u
            td%dmg(k) = max(td%dmg(k), min(1.0_wp, norm2(u)/td%param(td%ifc(k))))
            if (td%dmg(k) >= 1.0_wp) then
                td%state(k) = tie_broken
                return
            end if
            call pair_force(k, xm, (1 - td%dmg(k))*matmul(e, td%f0(:, k)))
        end subroutine soften

        !> fc on slave k, its reaction on its segment's nodes (N_j), and the
        !> couple of its gap, r x (-fc), as forces that sum to zero
        subroutine pair_force(k, xm, fc)
            integer, intent(in) :: k
            real(wp), intent(in) :: xm(3, 4), fc(3)
            real(wp) :: fq(3, 4)
            integer :: q, s
            s = td%slave(k)
            f(:, s) = f(:, s) + fc
            do q = 1, 4
                f(:, td%mnode(q, k)) = f(:, td%mnode(q, k)) - td%phi(q, k)*fc
            end do
            fq = couple_forces(xm, cross(x(:, s) - matmul(xm, td%phi(:, k)), -fc))
            do q = 1, 4
                f(:, td%mnode(q, k)) = f(:, td%mnode(q, k)) + fq(:, q)
            end do
        end subroutine pair_force

        !> OPTION 9: the slave's separation from its tie place (its gap at
        !> t = 0 kept) in the segment's frame, the cohesive law's tractions
        !> on it times its area; the interface's work booked
        subroutine cohesive(k)
            integer, intent(in) :: k
            real(wp) :: e(3, 3), u(3), d(3), tr(3), fc(3), xm(3, 4)
            integer :: s, i
            s = td%slave(k)
            i = td%ifc(k)
            xm = x(:, td%mnode(:, k))
            e = seg_frame(xm)
            u = x(:, s) - matmul(xm, td%phi(:, k)) - matmul(e, td%rloc(:, k))
            d = [dot_product(u, e(:, 1)), dot_product(u, e(:, 2)), td%sgn(k)*dot_product(u, e(:, 3))]
            call cohesive_law(d, td%kn(i), td%kt(i), td%nfls(i), td%sfls(i), td%gic(i), td%giic(i), td%param(i), &
                              td%dmg(k), tr)
            td%trac(:, k) = [tr(3), norm2(tr(1:2))]
            fc = -td%area(k)*(tr(1)*e(:, 1) + tr(2)*e(:, 2) + td%sgn(k)*tr(3)*e(:, 3))
            ! the work over the step, with the forces at its two ends (as the
            ! central difference moves the nodes: the same sums as each
            ! step's force over the half steps before and after it)
            td%ework = td%ework - 0.5_dp*dot_product(real(td%f0(:, k) + fc, dp), real(u - td%urel(:, k), dp))
            td%urel(:, k) = u
            td%f0(:, k) = fc
            call pair_force(k, xm, fc)
        end subroutine cohesive
    end subroutine tie_forces

    !> The mixed-mode cohesive law of tiebreak OPTION 9 (bilinear, as
    !> Camanho and Davila's decohesion element): d(1:2) the shear
    !> separations, d(3) the normal one (opening positive); kn, kt the
    !> stiffnesses, t, s the peak tractions, gic, giic the energies, xmu
    !> the exponent (> 0 the power law (G_I/GIC)^xmu + (G_II/GIIC)^xmu =
    !> 1, < 0 Benzeggagh and Kenane's with |xmu|). With delta_I = max(d3,
    !> 0), delta_II = |d(1:2)|, beta = delta_II / delta_I and delta_m their
    !> length, the damage starts at
    !>
    !>   delta_0 = d10 d20 sqrt((1 + beta^2) / (d20^2 + (beta d10)^2))
    !>
    !> (d10 = t / kn, d20 = s / kt; d20 in shear alone) and is complete at
    !>
    !>   delta_F = 2 (1 + beta^2) / delta_0 ((kn / gic)^xmu + (kt beta^2 /
    !>             giic)^xmu)^(-1/xmu)
    !>
    !> (2 giic / s in shear alone), so that a mode alone releases its G_c;
    !> dmg = max(dmg, delta_F (delta_m - delta_0) / (delta_m (delta_F -
    !> delta_0))) in [0, 1], never healing. Tractions (1 - dmg) k d; none in
    !> compression (the sliding contact's).
    pure subroutine cohesive_law(d, kn, kt, t, s, gic, giic, xmu, dmg, tr)
        real(wp), intent(in) :: d(3), kn, kt, t, s, gic, giic, xmu
        real(wp), intent(inout) :: dmg
        real(wp), intent(out) :: tr(3)
        real(wp) :: di, dii, dm, b2, d10, d20, d0, df, w
        di = max(d(3), 0.0_wp)
        dii = norm2(d(1:2))
        dm = sqrt(di**2 + dii**2)
        d10 = t/kn
        d20 = s/kt
        if (dm > 0.0_wp) then
            if (di > 0.0_wp) then
                b2 = (dii/di)**2
                d0 = d10*d20*sqrt((1 + b2)/(d20**2 + b2*d10**2))
                if (xmu > 0.0_wp) then
                    df = 2*(1 + b2)/d0*((kn/gic)**xmu + (kt*b2/giic)**xmu)**(-1/xmu)
                else
                    w = (b2*kt/(kn + b2*kt))**abs(xmu)
                    df = 2*(1 + b2)/(d0*(kn + b2*kt))*(gic + (giic - gic)*w)
                end if
            else
                d0 = d20
                df = 2*giic/s
            end if
            if (dm > d0) dmg = max(dmg, min(1.0_wp, df*(dm - d0)/(dm*(df - d0))))
        end if
        tr(1:2) = (1 - dmg)*kt*d(1:2)
        tr(3) = (1 - dmg)*kn*di
    end subroutine cohesive_law

    !> Tiebreak failure, after every velocity update: each held tiebreak
    !> slave's interface force, what held it against its own force, F = m_s
    !> a_s - f_s with a_s its velocity change over the step (whatever moved
    !> its segment: forces, prescribed motion, a rigid body), over its area: the normal stress
    !> (tension positive, along the segment's normal from the master to the
    !> slave side) and the shear stress. Where (max(sn, 0)/NFLS)^2 + (ss/
    !> SFLS)^2 >= 1 the tie breaks: OPTION 1 releases the slave to the
    !> sliding contact; OPTION 2 keeps the force it had, falling to zero as
    !> the slave separates by PARAM. Each break is named in `txt`.
    subroutine tie_break(td, time, mass, dt_avg, v, x, txt, node_id)
        type(ties_t), intent(inout) :: td
        real(dp), intent(in) :: time
        real(wp), intent(in) :: mass(:), dt_avg, v(:, :), x(:, :)
        character(len=:), allocatable, intent(out) :: txt
        integer, intent(in) :: node_id(:)
        real(wp) :: fi(3), e(3, 3), sn, ss, crit, xm(3, 4)
        integer :: k, s, i
        character(len=200) :: buf
        txt = ''
        if (.not. td%tiebreak) return
        do k = 1, td%n
            i = td%ifc(k)
            if (td%state(k) == tie_cohesive .or. td%state(k) == tie_damaging) then
                call cohesive_events(k)
                cycle
            end if
            if (td%opt(i) == 0 .or. .not. holds(td, k, time)) cycle
            s = td%slave(k)
            if (td%area(k) <= 0.0_wp) cycle
            if (dt_avg <= 0.0_wp) cycle
            fi = mass(s)*(v(:, s) - td%vold(:, k))/dt_avg - td%fs0(:, k)
            xm = x(:, td%mnode(:, k))
            e = seg_frame(xm)
            sn = -dot_product(fi, e(:, 3))*td%sgn(k)/td%area(k)
            ss = norm2(fi - dot_product(fi, e(:, 3))*e(:, 3))/td%area(k)
            crit = 0
            if (td%nfls(i) > 0.0_wp) crit = crit + (max(sn, 0.0_wp)/td%nfls(i))**2
            if (td%sfls(i) > 0.0_wp) crit = crit + (ss/td%sfls(i))**2
            if (crit < 1.0_wp) cycle
            td%nbroken = td%nbroken + 1
            if (td%opt(i) == 2) then
                td%state(k) = tie_softening
                td%f0(:, k) = matmul(transpose(e), fi)
                td%urel(:, k) = 0
            else
                td%state(k) = tie_broken
            end if
            if (td%nbroken <= max_named) then
                write (buf, '(a,i0,a,i0,a,es12.5,a,es10.3,a,es10.3,a)') ' tiebreak ', i, ': node ', node_id(s), &
                    ' broke at time ', time, ' (normal stress ', sn, ', shear ', ss, ')'
                txt = txt//trim(buf)//new_line('a')
            end if
        end do
        if (len(txt) > 0) txt = txt(1:len(txt) - 1)
    contains
        !> OPTION 9: a slave whose damage began, and one whose damage is
        !> complete (released to the sliding contact), named
        subroutine cohesive_events(k)
            integer, intent(in) :: k
            if (time > td%death(td%ifc(k))) return
            s = td%slave(k)
            if (td%state(k) == tie_cohesive .and. td%dmg(k) > 0.0_wp) then
                td%state(k) = tie_damaging
                if (td%nbroken < max_named) then
                    write (buf, '(a,i0,a,i0,a,es12.5,a,es10.3,a,es10.3,a)') ' tiebreak ', td%ifc(k), ': node ', &
                        node_id(s), ' began to soften at time ', time, ' (normal traction ', td%trac(1, k), &
                        ', shear ', td%trac(2, k), ')'
                    txt = txt//trim(buf)//new_line('a')
                end if
            end if
            if (td%state(k) == tie_damaging .and. td%dmg(k) >= 1.0_wp) then
                td%state(k) = tie_broken
                td%nbroken = td%nbroken + 1
                if (td%nbroken <= max_named) then
                    write (buf, '(a,i0,a,i0,a,es12.5,a)') ' tiebreak ', td%ifc(k), ': node ', node_id(s), &
                        ' broke at time ', time, ' (fully damaged: released to the sliding contact)'
                    txt = txt//trim(buf)//new_line('a')
                end if
            end if
        end subroutine cohesive_events
    end subroutine tie_break

    !> Step 2, after the free accelerations: a master node's acceleration
    !> over its mass plus the slave mass it carries; its moment scaled so
    !> that the rotational update divides by its inertia plus the slaves'.
    subroutine tie_accelerations(td, time, f, mass, dofs, a, mom, irot)
        type(ties_t), intent(inout) :: td
        real(dp), intent(in) :: time
        real(wp), intent(in) :: f(:, :), mass(:)
        integer(int8), intent(in) :: dofs(:)   !< per node, its free directions (xd_core_dofs)
        real(wp), intent(inout) :: a(:, :)
        real(wp), allocatable, intent(inout) :: mom(:, :)
        real(wp), allocatable, intent(in) :: irot(:)
        integer :: k, q, i, j
        if (td%n == 0) return
        td%madd = 0
        td%jadd = 0
        do k = 1, td%n
            if (.not. holds(td, k, time)) cycle
            do q = 1, 4
                td%madd(td%mpos(q, k)) = td%madd(td%mpos(q, k)) + td%phi(q, k)*mass(td%slave(k))
                if (td%rot(k)) td%jadd(td%mpos(q, k)) = td%jadd(td%mpos(q, k)) + td%phi(q, k)*irot(td%slave(k))
                td%madd(td%mpos(q, k)) = td%madd(td%mpos(q, k)) + td%mrot(k)
            end do
        end do
        td%mnodal(td%master) = td%madd
        do i = 1, size(td%master)
            if (td%m_rigid(i)) cycle
            j = td%master(i)
            if (td%madd(i) > 0.0_wp) a(:, j) = f(:, j)/(mass(j) + td%madd(i))*free3(dofs(j))
            if (td%jadd(i) > 0.0_wp) mom(:, j) = mom(:, j)*(irot(j)/(irot(j) + td%jadd(i)))
        end do
    end subroutine tie_accelerations

    !> Step 3, after every other velocity update: each slave moves with its
    !> segment; an offset slave to its gap in the segment's frame at the
    !> step's end (positions x + dt v), so that the gap is kept exactly,
    !> not only to first order in the segment's turn.
    subroutine tie_velocities(td, time, dt, x, v, vr)
        type(ties_t), intent(inout) :: td
        real(dp), intent(in) :: time
        real(wp), intent(in) :: dt
        real(wp), intent(in) :: x(:, :)
        real(wp), intent(inout) :: v(:, :)
        real(wp), allocatable, intent(inout) :: vr(:, :)
        real(wp) :: ym(3, 4)
        integer :: k, s
        do k = 1, td%n
            if (.not. holds(td, k, time)) cycle
            s = td%slave(k)
            td%vold(:, k) = v(:, s)
            if (td%offset(k) .and. dt > 0.0_wp) then
                ym = x(:, td%mnode(:, k)) + dt*v(:, td%mnode(:, k))
                v(:, s) = (matmul(ym, td%phi(:, k)) + matmul(seg_frame(ym), td%rloc(:, k)) - x(:, s))/dt
            else if (td%offset(k)) then
                ! (at t = 0) the segment's velocity there and its best-fit
                ! spin times the gap
                ym = x(:, td%mnode(:, k))
                v(:, s) = matmul(v(:, td%mnode(:, k)), td%phi(:, k)) + &
                          cross(seg_spin(ym, v(:, td%mnode(:, k))), x(:, s) - matmul(ym, td%phi(:, k)))
            else
                v(:, s) = matmul(v(:, td%mnode(:, k)), td%phi(:, k))
            end if
            if (td%rot(k)) vr(:, s) = matmul(vr(:, td%mnode(:, k)), td%phi(:, k))
        end do
    end subroutine tie_velocities

end module xd_contact_tied
