!> Step 1 of the automatic contact, contact surface construction (section 3
!> of Whirley & Engelmann 1993). Every element face gets a number that does
!> not depend on the order of its nodes; faces with zero or one continuum
!> element attached are exterior; shells give their own two-sided segments.
!> Each exterior segment carries its thickness and the ingredients of its
!> penalty stiffness, and the body (connected surface region) it lies on.
!>
!> Two levels: `faces_t` is the exterior of the whole model, built once;
!> `surface_t` is one interface's contact surface, the faces its SSID/MSID
!> select, numbered locally with node-to-segment and node-to-node adjacency
!> for the global and local searches.
!>
!> Solids that can erode: erosion exposes the faces inside their parts. Each
!> interior face beside a hexahedron that can erode is a latent segment of
!> the hexahedron on its other side (as that one gives it, outward), and
!> each segment of a hexahedron that can erode is active while its
!> hexahedron lives and the one across (if any) does not. The surfaces
!> hold every segment; the searches see the active ones (surface_activate
!> rebuilds the node-to-segment lists and the nodes' springs from them).
module xd_contact_surface
    use xd_kinds, only: wp, i8
    use xd_core_memory, only: nbytes
    use xd_core_vectors, only: cross
    use xd_elements_hex8, only: hex_volume_operator
    use xd_model, only: model_t, mat_rigid
    use xd_core_sorting, only: where_true, small_sort
    implicit none
    private
    public :: faces_t, surface_t, build_faces, build_surface, seg_shell, seg_solid, follow_thickness, surface_activate
    public :: faces_bytes, surface_bytes, release_faces, release_activation, seg_thicknesses
    public :: side_a, side_b, side_slave, face_key, segment_diagonals, wanted_side, seg_nodes, seg_normal, corners

    integer, parameter :: seg_shell = 1, seg_solid = 2
    !> Bits of a node's or segment's side in an interface: on a segment of
    !> side A (the slave side, or the only side of a single surface), of
    !> side B (the master side of a two-surface contact), a slave node.
    integer, parameter :: side_a = 1, side_b = 2, side_slave = 4

    !> Outward faces of a hexahedron (N1..N4 bottom, N5..N8 top), each
    !> counter-clockwise seen from outside for a right-handed element.
    integer, parameter :: hex_face(4, 6) = reshape([1, 4, 3, 2, 5, 6, 7, 8, 1, 2, 6, 5, &
                                                    2, 3, 7, 6, 3, 4, 8, 7, 4, 1, 5, 8], [4, 6])

    !> The exterior segments of the whole model.
    type :: faces_t
        integer :: n = 0
        integer, allocatable :: node(:, :)     !< (4, n) model node indices; triangle: N4 = N3
        integer, allocatable :: kind(:)        !< seg_shell (two-sided) or seg_solid (outward normal)
        integer, allocatable :: part(:)        !< part index of the element that owns the face
        integer, allocatable :: shell(:)       !< model shell index of a shell on the face (0: none)
        integer, allocatable :: hex(:)         !< model hexahedron that owns a solid face (0: shell face)
        real(wp), allocatable :: thick(:)      !< segment thickness (section 3)
        real(wp), allocatable :: kgeo(:)       !< bulk modulus x A^2/V (solid) or x A/max diagonal (shell)
        real(wp), allocatable :: area(:)       !< initial area
        integer, allocatable :: body(:)        !< connected surface region
        logical, allocatable :: rigid(:)       !< on a *MAT_RIGID part
        integer :: nbody = 0
        integer :: ninterior = 0               !< faces between two continuum elements (not segments)
        !> (n) the hexahedron across a solid face (0: none, the face is the
        !> model's exterior); a latent segment has one, and starts inactive
        integer, allocatable :: across(:)
        integer :: nlatent = 0                 !< latent segments (faces inside parts that can erode)
        real(wp), allocatable :: node_thick(:) !< (model nodes) largest shell thickness at the node
        !> (model nodes) largest 40% of the shortest edge of a shell at the
        !> node (LS-DYNA's limit of a single-surface contact's shell
        !> thickness, SSTHK 0); huge at a node on no shell
        real(wp), allocatable :: node_cap(:)
    end type faces_t

    !> One interface's contact surface in local numbering.
    type :: surface_t
        integer :: nseg = 0, nnode = 0
        integer, allocatable :: seg(:, :)      !< (4, nseg) local node numbers
        integer, allocatable :: seg_face(:)    !< index in faces_t
        integer, allocatable :: seg_kind(:), seg_side(:), seg_body(:)
        !> (8, nseg) local numbers of the owning hexahedron's nodes (0: a
        !> shell's face); (8, 0) where no segment is a hexahedron's face
        integer, allocatable :: seg_elem(:, :)
                                               !< (0: not on this surface, or a shell segment)
        real(wp), allocatable :: seg_t(:)      !< segment thickness after SST/MST overrides
        real(wp), allocatable :: seg_tn(:, :)  !< (4, nseg) nodal thicknesses for the shape functions (5.2)
        !> (nseg) the segment's own share of the contact reach: half its
        !> largest thickness for a shell (its contact surface lies that far
        !> off the segment, on either side), its window for a solid face
        real(wp), allocatable :: seg_r(:)
        real(wp), allocatable :: seg_k(:)      !< master-side penalty stiffness (force/length)
        real(wp), allocatable :: seg_area(:)   !< initial segment area
        integer, allocatable :: node(:)        !< model node of each local node
        integer, allocatable :: node_side(:)   !< side bits
        integer, allocatable :: node_body(:)   !< body of the node's segments (0: a node without segments)
        real(wp), allocatable :: node_t(:)     !< slave shell thickness at the node (0: solids only)
        real(wp), allocatable :: node_k(:)     !< slave-side penalty stiffness, for the node's whole area
        real(wp), allocatable :: node_kpa(:)   !< slave-side penalty stiffness per unit area
        real(wp), allocatable :: node_area(:)  !< the node's share of its segments' initial areas (0: none)
        logical, allocatable :: node_rigid(:)  !< every segment at the node is on a rigid part (it moves with the body)
        integer, allocatable :: seg_ptr(:), seg_list(:)   !< node -> segments (CSR)
        integer, allocatable :: nn_ptr(:), nn_list(:)     !< node -> nodes sharing a segment (CSR)
        !> THKCHG: the thicknesses before the 40% limit (0: fixed by SST/MST,
        !> or a solid face), which the shells' thickness ratios scale (only
        !> where the surface follows the shells: `follow`)
        logical :: follow = .false., capped = .false.
        real(wp), allocatable :: seg_t_raw(:), seg_tn_raw(:, :), node_t_raw(:)
        integer :: nslave = 0
        integer :: ncap = 0                    !< surface nodes whose shell thickness the 40% edge limit lowered
        !> (nseg) the segment is in the searches' lists (latent ones, and
        !> eroded ones, not)
        logical, allocatable :: seg_on(:)
        logical :: latent = .false.            !< some segment is latent (a surface that erosion rebuilds)
        real(wp) :: stiff(3) = 0               !< SLSFAC, SFS, SFM (the nodes' springs, rebuilt)
        !> (nnode) the nodes' springs and areas at set-up, which a node
        !> without an active segment takes again
        real(wp), allocatable :: node_area0(:), node_kpa0(:)
        !> (nnode) sides from every segment (latent ones too): who can be a
        !> slave
        integer, allocatable :: node_side_all(:)
        integer, allocatable :: slave(:)       !< local numbers of the slave nodes
        integer :: nshell_seg = 0, nsolid_seg = 0
        logical :: single = .true.             !< one side: every slave against every segment
        logical :: two_way = .false.           !< two sides, each slave against the other side
        real(wp) :: max_thick = 0              !< largest slave or master thickness: the contact reach
    end type surface_t

contains

    !> The bytes of the faces' arrays.
    integer(i8) function faces_bytes(f) result(b)
        type(faces_t), intent(in) :: f
        b = nbytes(f%node) + nbytes(f%kind) + nbytes(f%part) + nbytes(f%shell) + nbytes(f%hex) + nbytes(f%thick) &
            + nbytes(f%kgeo) + nbytes(f%area) + nbytes(f%body) + nbytes(f%rigid) + nbytes(f%across) &
            + nbytes(f%node_thick) + nbytes(f%node_cap)
    end function faces_bytes

    !> The model's faces' arrays released once the surfaces are built, where
    !> nothing reads them again (no erosion, no latent faces, no shell
    !> thickness the contact follows): 84 bytes a face. The counts stay
    !> (d3hsp's summary reads them).
    subroutine release_faces(f)
        type(faces_t), intent(inout) :: f
        type(faces_t) :: counts
        counts%n = f%n
        counts%nbody = f%nbody
        counts%ninterior = f%ninterior
        counts%nlatent = f%nlatent
        ! (every array deallocated by the assignment)
        f = counts
    end subroutine release_faces

    !> A surface's set-up values that only surface_activate or erosion
    !> read again, where nothing rebuilds the surface: its nodes' springs
    !> and areas at set-up and their sides from every segment (20 bytes a
    !> node) and the segments' faces (4 bytes a segment); and where every
    !> segment's nodal thicknesses are its thickness (a uniform shell or a
    !> solid face, thickness not followed), the nodal thicknesses, 32
    !> bytes a segment (seg_thicknesses gives the same values from seg_t).
    subroutine release_activation(s)
        type(surface_t), intent(inout) :: s
        integer :: m
        logical :: uniform
        if (allocated(s%node_area0)) deallocate (s%node_area0)
        if (allocated(s%node_kpa0)) deallocate (s%node_kpa0)
        if (allocated(s%node_side_all)) deallocate (s%node_side_all)
        if (allocated(s%seg_face)) deallocate (s%seg_face)
        if (s%follow .or. .not. allocated(s%seg_tn)) return
        uniform = .true.
        do m = 1, s%nseg
            if (all(s%seg_tn(:, m) == s%seg_t(m))) cycle
            uniform = .false.
            exit
        end do
        if (.not. uniform) return
        deallocate (s%seg_tn)
        allocate (s%seg_tn(4, 0))
    end subroutine release_activation

    !> Segment m's nodal thicknesses (5.2): seg_tn's, or its thickness at
    !> each node where they were all its thickness (release_activation).
    !> (A subroutine: as a function returning the array, inlined into the
    !> slaves' force loop, it made car6's and the plate's enforcement
    !> phase a third slower, though the loop never called it.)
    pure subroutine seg_thicknesses(s, m, tn)
        type(surface_t), intent(in) :: s
        integer, intent(in) :: m
        real(wp), intent(out) :: tn(4)
        if (size(s%seg_tn, 2) > 0) then
            tn = s%seg_tn(:, m)
        else
            tn = s%seg_t(m)
        end if
    end subroutine seg_thicknesses

    !> The bytes of a surface's arrays (its segments, nodes and lists).
    integer(i8) function surface_bytes(s) result(b)
        type(surface_t), intent(in) :: s
        b = nbytes(s%seg) + nbytes(s%seg_face) + nbytes(s%seg_kind) + nbytes(s%seg_side) + nbytes(s%seg_body) &
            + nbytes(s%seg_elem) + nbytes(s%seg_t) + nbytes(s%seg_tn) + nbytes(s%seg_r) + nbytes(s%seg_k) &
            + nbytes(s%seg_area) + nbytes(s%node) + nbytes(s%node_side) + nbytes(s%node_body) + nbytes(s%node_t) &
            + nbytes(s%node_k) + nbytes(s%node_kpa) + nbytes(s%node_area) + nbytes(s%node_rigid) &
            + nbytes(s%seg_ptr) + nbytes(s%seg_list) + nbytes(s%nn_ptr) + nbytes(s%nn_list) + nbytes(s%seg_t_raw) &
            + nbytes(s%seg_tn_raw) + nbytes(s%node_t_raw) + nbytes(s%seg_on) + nbytes(s%node_area0) &
            + nbytes(s%node_kpa0) + nbytes(s%node_side_all) + nbytes(s%slave)
    end function surface_bytes

    !> Sorted unique nodes of a face, padded with 0: the face's number
    !> independent of node order (section 3). Returns the count of unique nodes.
    pure subroutine face_key(nd, key, nuniq)
        integer, intent(in) :: nd(4)
        integer, intent(out) :: key(4), nuniq
        integer :: i
        key = nd
        call small_sort(key)
        nuniq = 1
        do i = 2, 4
            if (key(i) /= key(nuniq)) then
                nuniq = nuniq + 1
                key(nuniq) = key(i)
            end if
        end do
        key(nuniq + 1:) = 0
    end subroutine face_key

    !> The corners xq of a segment or face with nodes nd, gathered from x (a
    !> section with a vector subscript passed on to a routine is packed into
    !> a temporary at each call).
    pure subroutine corners(x, nd, xq)
        real(wp), intent(in) :: x(:, :)
        integer, intent(in) :: nd(4)
        real(wp), intent(out) :: xq(3, 4)
        integer :: q
        do q = 1, 4
            xq(:, q) = x(:, nd(q))
        end do
    end subroutine corners

    !> The two diagonals of a quadrilateral segment; a triangle's "diagonals"
    !> are its shortest and longest edges.
    pure subroutine segment_diagonals(xs, dmin, dmax)
        real(wp), intent(in) :: xs(3, 4)
        real(wp), intent(out) :: dmin, dmax
        real(wp) :: e(3)
        if (all(xs(:, 3) == xs(:, 4))) then
            e = [norm2(xs(:, 2) - xs(:, 1)), norm2(xs(:, 3) - xs(:, 2)), norm2(xs(:, 1) - xs(:, 3))]
            dmin = minval(e)
            dmax = maxval(e)
        else
            ! (each diagonal's length once)
            e(1) = norm2(xs(:, 3) - xs(:, 1))
            e(2) = norm2(xs(:, 4) - xs(:, 2))
            dmin = min(e(1), e(2))
            dmax = max(e(1), e(2))
        end if
    end subroutine segment_diagonals

    pure real(wp) function segment_area(xs) result(a)
        real(wp), intent(in) :: xs(3, 4)
        a = 0.5_wp*norm2(cross(xs(:, 3) - xs(:, 1), xs(:, 4) - xs(:, 2)))
    end function segment_area

    !> One-point volume of hexahedron e at coordinates x.
    real(wp) function hex_vol(model, x, e)
        type(model_t), intent(in) :: model
        real(wp), intent(in) :: x(:, :)
        integer, intent(in) :: e
        real(wp) :: xe(8, 3), bm(8, 3)
        xe = transpose(x(:, model%hex_conn(:, e)))
        call hex_volume_operator(xe, bm, hex_vol)
    end function hex_vol

    !> Bulk modulus E / (3 (1 - 2 nu)) of a part's material (MAT_RIGID's E, PR
    !> set the contact stiffness of a rigid part).
    pure real(wp) function part_bulk(model, p) result(k)
        type(model_t), intent(in) :: model
        integer, intent(in) :: p
        associate (m => model%mat(model%part(p)%mat_ix))
            k = m%e/(3.0_wp*max(1.0_wp - 2.0_wp*m%pr, 1.0e-6_wp))
        end associate
    end function part_bulk

    !> The exterior of the whole model from the element connectivity and the
    !> initial coordinates x (3, nnode).
    subroutine build_faces(model, x, f, erodible)
        type(model_t), intent(in) :: model
        real(wp), intent(in) :: x(:, :)
        type(faces_t), intent(out) :: f
        !> (model hexahedra) can erode: latent segments inside their parts
        logical, intent(in), optional :: erodible(:)
        integer :: ncand, e, k, j, nu, c, n, a, b, i
        integer, allocatable :: cnode(:, :), ckey(:, :), chex(:), cshell(:), ptr(:), item(:), rep(:), ncont(:)
        integer, allocatable :: shell_on(:)
        real(wp), allocatable :: vol(:)
        real(wp) :: emin, xs(3, 4)
        logical :: same
        integer :: nd(4), key(4)

        ! candidate faces: six per hexahedron (collapsed ones dropped), one per shell
        ncand = 6*model%nhex + model%nshell
        allocate (cnode(4, ncand), ckey(4, ncand), chex(ncand), cshell(ncand), vol(model%nhex))
        c = 0
        do e = 1, model%nhex
            vol(e) = hex_vol(model, x, e)
            do k = 1, 6
                nd = model%hex_conn(hex_face(:, k), e)
                call face_key(nd, key, nu)
                if (nu < 3) cycle
                c = c + 1
                cnode(:, c) = tidy(nd, nu)
                ckey(:, c) = key
                chex(c) = e
                cshell(c) = 0
            end do
        end do
        do e = 1, model%nshell
            nd = model%shell_conn(:, e)
            call face_key(nd, key, nu)
            if (nu < 3) cycle
            c = c + 1
            cnode(:, c) = tidy(nd, nu)
            ckey(:, c) = key
            chex(c) = 0
            cshell(c) = e
        end do
        ncand = c

        ! group candidates by their smallest node, then compare keys in the group
        n = model%nnode
        allocate (ptr(n + 2), item(ncand), rep(ncand), ncont(ncand), shell_on(ncand))
        ptr = 0
        do c = 1, ncand
            ptr(ckey(1, c) + 2) = ptr(ckey(1, c) + 2) + 1
        end do
        ptr(1) = 1
        ptr(2) = 1
        do i = 3, n + 2
            ptr(i) = ptr(i) + ptr(i - 1)
        end do
        do c = 1, ncand
            item(ptr(ckey(1, c) + 1)) = c
            ptr(ckey(1, c) + 1) = ptr(ckey(1, c) + 1) + 1
        end do
        ! ptr(i) is now the start of group i; rep(c) = first candidate with c's key
        rep = 0
        ncont = 0
        shell_on = 0
        do i = 1, n
            a = ptr(i)
            b = ptr(i + 1) - 1
            do j = a, b
                c = item(j)
                do k = a, j - 1
                    same = all(ckey(:, item(k)) == ckey(:, c))
                    if (same) exit
                end do
                if (k < j) then
                    rep(c) = rep(item(k))
                else
                    rep(c) = c
                end if
                if (chex(c) > 0) ncont(rep(c)) = ncont(rep(c)) + 1
                if (cshell(c) > 0 .and. shell_on(rep(c)) == 0) shell_on(rep(c)) = cshell(c)
            end do
        end do

        ! exterior: zero or one continuum element on the face (Fig. 1)
        f%n = 0
        f%ninterior = 0
        do c = 1, ncand
            if (rep(c) /= c) cycle
            if (ncont(c) <= 1) then
                f%n = f%n + 1
            else
                f%ninterior = f%ninterior + 1
            end if
        end do
        ! latent: an interior face between two hexahedra, as each gives it,
        ! where the other can erode
        f%nlatent = 0
        if (present(erodible)) then
            if (any(erodible)) then
                do c = 1, ncand
                    if (chex(c) == 0 .or. ncont(rep(c)) /= 2) cycle
                    if (erodible(chex(partner(c)))) f%nlatent = f%nlatent + 1
                end do
            end if
        end if
        allocate (f%node(4, f%n + f%nlatent), f%kind(f%n + f%nlatent), f%part(f%n + f%nlatent), &
                  f%shell(f%n + f%nlatent), f%thick(f%n + f%nlatent), f%kgeo(f%n + f%nlatent), &
                  f%body(f%n + f%nlatent))
        allocate (f%area(f%n + f%nlatent))
        allocate (f%hex(f%n + f%nlatent), f%across(f%n + f%nlatent))
        f%hex = 0
        f%across = 0
        allocate (f%node_thick(n), f%node_cap(n))
        f%node_thick = 0
        f%node_cap = 0
        do e = 1, model%nshell
            call corners(x, model%shell_conn(:, e), xs)
            emin = shortest_edge(xs)
            do k = 1, 4
                f%node_thick(model%shell_conn(k, e)) = max(f%node_thick(model%shell_conn(k, e)), model%shell_t(k, e))
                f%node_cap(model%shell_conn(k, e)) = max(f%node_cap(model%shell_conn(k, e)), 0.4_wp*emin)
            end do
        end do
        where (f%node_cap == 0.0_wp) f%node_cap = huge(1.0_wp)
        j = 0
        do c = 1, ncand
            if (rep(c) /= c .or. ncont(c) > 1) cycle
            j = j + 1
            f%shell(j) = shell_on(c)
            if (ncont(c) == 1) then
                ! a solid face (with or without a shell on it): the face as the
                ! hexahedron gives it, outward
                e = solid_of(c)
                f%node(:, j) = cnode(:, e)
                f%kind(j) = seg_solid
                f%hex(j) = chex(e)
                call solid_segment(chex(e), f%node(:, j), f%part(j), f%thick(j), f%kgeo(j))
                call corners(x, f%node(:, j), xs)
                f%area(j) = segment_area(xs)
            else
                f%node(:, j) = cnode(:, c)
                f%kind(j) = seg_shell
                call shell_segment(cshell(c), f%node(:, j), f%part(j), f%thick(j), f%kgeo(j))
                call corners(x, f%node(:, j), xs)
                f%area(j) = segment_area(xs)
            end if
        end do
        if (f%nlatent > 0) then
            do c = 1, ncand
                if (chex(c) == 0 .or. ncont(rep(c)) /= 2) cycle
                if (.not. erodible(chex(partner(c)))) cycle
                j = j + 1
                f%shell(j) = 0
                f%node(:, j) = cnode(:, c)
                f%kind(j) = seg_solid
                f%hex(j) = chex(c)
                f%across(j) = chex(partner(c))
                call solid_segment(chex(c), f%node(:, j), f%part(j), f%thick(j), f%kgeo(j))
                call corners(x, f%node(:, j), xs)
                f%area(j) = segment_area(xs)
            end do
            f%n = f%n + f%nlatent
        end if
        allocate (f%rigid(f%n))
        do j = 1, f%n
            f%rigid(j) = model%mat(model%part(f%part(j))%mat_ix)%mtype == mat_rigid
        end do
        call find_bodies(n, f)
    contains
        !> The other hexahedron's candidate on interior face c (two hexahedra
        !> share its key)
        integer function partner(c) result(o)
            integer, intent(in) :: c
            integer :: jj
            o = 0
            do jj = ptr(ckey(1, c)), ptr(ckey(1, c) + 1) - 1
                if (item(jj) /= c .and. rep(item(jj)) == rep(c) .and. chex(item(jj)) > 0) then
                    o = item(jj)
                    return
                end if
            end do
        end function partner

        !> The shortest edge of a quadrilateral (a triangle's repeated node
        !> gives no edge).
        pure real(wp) function shortest_edge(xe) result(emin)
            real(wp), intent(in) :: xe(3, 4)
            integer :: q
            real(wp) :: le
            emin = huge(1.0_wp)
            do q = 1, 4
                le = norm2(xe(:, mod(q, 4) + 1) - xe(:, q))
                if (le > 0.0_wp) emin = min(emin, le)
            end do
        end function shortest_edge

        !> N4 = N3 for a triangle, whatever node was repeated.
        pure function tidy(nd, nu) result(t)
            integer, intent(in) :: nd(4), nu
            integer :: t(4), i, m
            t = nd
            if (nu == 4) return
            m = 1
            do i = 2, 4
                if (all(t(1:m) /= nd(i))) then
                    m = m + 1
                    t(m) = nd(i)
                end if
            end do
            t(4) = t(3)
        end function tidy

        !> The candidate with a hexahedron among those sharing rep c.
        integer function solid_of(c) result(s)
            integer, intent(in) :: c
            integer :: jj
            s = c
            if (chex(c) > 0) return
            do jj = ptr(ckey(1, c)), ptr(ckey(1, c) + 1) - 1
                if (rep(item(jj)) == c .and. chex(item(jj)) > 0) then
                    s = item(jj)
                    return
                end if
            end do
        end function solid_of


        !> Solid thickness min(0.6 x smallest diagonal, V / A); stiffness
        !> ingredient K A^2 / V (LS-DYNA's rule for solids).
        subroutine solid_segment(e, nd, p, t, kg)
            integer, intent(in) :: e
            integer, intent(inout) :: nd(4)
            integer, intent(out) :: p
            real(wp), intent(out) :: t, kg
            real(wp) :: xs(3, 4), area, dmin, dmax, cen(3), nrm(3)
            integer :: tmp
            p = model%hex_part(e)
            xs = x(:, nd)
            ! keep the normal pointing out of the element whatever its handedness
            cen = sum(x(:, model%hex_conn(:, e)), 2)/8.0_wp
            nrm = cross(xs(:, 3) - xs(:, 1), xs(:, 4) - xs(:, 2))
            if (dot_product(nrm, sum(xs, 2)/4.0_wp - cen) < 0.0_wp) then
                if (nd(3) == nd(4)) then
                    tmp = nd(2); nd(2) = nd(3); nd(3) = tmp; nd(4) = nd(3)
                else
                    tmp = nd(2); nd(2) = nd(4); nd(4) = tmp
                end if
                xs = x(:, nd)
            end if
            area = segment_area(xs)
            call segment_diagonals(xs, dmin, dmax)
            t = min(0.6_wp*dmin, vol(e)/max(area, tiny(1.0_wp)))
            kg = part_bulk(model, p)*area**2/max(vol(e), tiny(1.0_wp))
        end subroutine solid_segment

        !> Shell thickness: the largest nodal thickness of its nodes (section
        !> 3); stiffness ingredient K A / max diagonal (LS-DYNA's rule for shells).
        subroutine shell_segment(e, nd, p, t, kg)
            integer, intent(in) :: e
            integer, intent(in) :: nd(4)
            integer, intent(out) :: p
            real(wp), intent(out) :: t, kg
            real(wp) :: xs(3, 4), dmin, dmax
            p = model%shell_part(e)
            xs = x(:, nd)
            t = maxval(f%node_thick(nd))
            call segment_diagonals(xs, dmin, dmax)
            kg = part_bulk(model, p)*segment_area(xs)/max(dmax, tiny(1.0_wp))
        end subroutine shell_segment
    end subroutine build_faces

    !> Bodies: segments joined through shared nodes, by union-find on nodes.
    subroutine find_bodies(n, f)
        integer, intent(in) :: n
        type(faces_t), intent(inout) :: f
        integer, allocatable :: parent(:), label(:)
        integer :: j, k, r
        allocate (parent(n), label(n))
        do j = 1, n
            parent(j) = j
        end do
        do j = 1, f%n
            do k = 2, 4
                call unite(f%node(1, j), f%node(k, j))
            end do
        end do
        label = 0
        f%nbody = 0
        do j = 1, f%n
            r = root(f%node(1, j))
            if (label(r) == 0) then
                f%nbody = f%nbody + 1
                label(r) = f%nbody
            end if
            f%body(j) = label(r)
        end do
    contains
        integer function root(i)
            integer, intent(in) :: i
            root = i
            do while (parent(root) /= root)
                parent(root) = parent(parent(root))
                root = parent(root)
            end do
        end function root
        subroutine unite(a, b)
            integer, intent(in) :: a, b
            integer :: ra, rb
            ra = root(a)
            rb = root(b)
            if (ra /= rb) parent(max(ra, rb)) = min(ra, rb)
        end subroutine unite
    end subroutine find_bodies

    !> One interface's surface from the faces selected for side A (`in_a`),
    !> side B (`in_b`) and the extra slave nodes `slave_nodes` (model
    !> indices; nodes-to-surface). Single surface: everything on side A and
    !> every node a slave. Two-surface: nodes of both sides are slaves
    !> (the symmetric treatment of LS-DYNA's automatic surface-to-surface);
    !> nodes-to-surface: only `slave_nodes`.
    subroutine build_surface(f, nnode_model, in_a, in_b, slave_nodes, two_way, thick, stiff, s, hex_conn, cap, follow)
        type(faces_t), intent(in) :: f
        !> the contact thickness follows the shells' (THKCHG): keep the raw
        !> thicknesses
        logical, intent(in), optional :: follow
        !> limit shell thicknesses to 40% of the shortest edge (a single-surface
        !> contact with SSTHK 0), where SST / MST do not give them
        logical, intent(in), optional :: cap
        integer, intent(in), optional :: hex_conn(:, :)   !< the model's hexahedra, for seg_elem
        integer, intent(in) :: nnode_model
        logical, intent(in) :: in_a(:), in_b(:)
        integer, intent(in) :: slave_nodes(:)
        logical, intent(in) :: two_way
        real(wp), intent(in) :: thick(4)   !< SST, MST, SFST, SFMT
        real(wp), intent(in) :: stiff(3)   !< SLSFAC, SFS, SFM
        type(surface_t), intent(out) :: s
        integer, allocatable :: local(:)
        real(wp), allocatable :: kmin(:)
        integer :: j, k, m, nd, i, a, nnd, nhexseg
        logical :: in_any, capped

        capped = .false.
        if (present(cap)) capped = cap
        allocate (local(nnode_model))
        local = 0
        s%nseg = count(in_a .or. in_b)
        allocate (s%seg(4, s%nseg), s%seg_face(s%nseg), s%seg_kind(s%nseg), s%seg_side(s%nseg), s%seg_body(s%nseg))
        allocate (s%seg_t(s%nseg), s%seg_k(s%nseg), s%seg_tn(4, s%nseg), s%seg_area(s%nseg))
        s%nnode = 0
        m = 0
        do j = 1, f%n
            in_any = in_a(j) .or. in_b(j)
            if (.not. in_any) cycle
            m = m + 1
            s%seg_face(m) = j
            s%seg_side(m) = 0
            if (in_a(j)) s%seg_side(m) = side_a
            if (in_b(j)) s%seg_side(m) = ior(s%seg_side(m), side_b)
            s%seg_kind(m) = f%kind(j)
            s%seg_body(m) = f%body(j)
            do k = 1, 4
                nd = f%node(k, j)
                if (local(nd) == 0) then
                    s%nnode = s%nnode + 1
                    local(nd) = s%nnode
                end if
                s%seg(k, m) = local(nd)
            end do
        end do
        do i = 1, size(slave_nodes)
            if (local(slave_nodes(i)) == 0) then
                s%nnode = s%nnode + 1
                local(slave_nodes(i)) = s%nnode
            end if
        end do
        ! a slave never contacts a face of its own hexahedron (its opposite
        ! face lies exactly one depth window behind the face); a surface
        ! without a hexahedron's face holds none of these (8 integers a
        ! segment, 8 MB on a surface of 250,000 shells)
        nhexseg = 0
        if (present(hex_conn)) then
            do m = 1, s%nseg
                if (f%hex(s%seg_face(m)) > 0) nhexseg = nhexseg + 1
            end do
        end if
        allocate (s%seg_elem(8, merge(s%nseg, 0, nhexseg > 0)))
        s%seg_elem = 0
        if (nhexseg > 0) then
            do m = 1, s%nseg
                if (f%hex(s%seg_face(m)) > 0) s%seg_elem(:, m) = local(hex_conn(:, f%hex(s%seg_face(m))))
            end do
        end if
        allocate (s%node(s%nnode), s%node_side(s%nnode), s%node_t(s%nnode), s%node_k(s%nnode))
        do nd = 1, nnode_model
            if (local(nd) > 0) s%node(local(nd)) = nd
        end do
        s%node_side = 0
        do m = 1, s%nseg
            do k = 1, 4
                s%node_side(s%seg(k, m)) = ior(s%node_side(s%seg(k, m)), s%seg_side(m))
            end do
        end do
        if (size(slave_nodes) > 0) then
            ! nodes-to-surface: the listed nodes are the slaves, nothing else
            do i = 1, size(slave_nodes)
                a = local(slave_nodes(i))
                s%node_side(a) = ior(s%node_side(a), side_slave)
            end do
        else
            do nd = 1, s%nnode
                if (two_way .or. iand(s%node_side(nd), side_a) /= 0) &
                    s%node_side(nd) = ior(s%node_side(nd), side_slave)
            end do
        end if
        s%single = .not. any(in_b)
        s%two_way = two_way
        s%nslave = count(iand(s%node_side, side_slave) /= 0)
        allocate (s%slave(s%nslave))
        s%slave = where_true(iand(s%node_side, side_slave) /= 0)
        ! latent segments (inside parts that can erode) start inactive: the
        ! sides a node has in the searches come from its active ones (a
        ! node inside a part, none), its slave bit from all of them
        allocate (s%seg_on(s%nseg))
        s%seg_on = f%across(s%seg_face) == 0
        s%latent = .not. all(s%seg_on)
        s%node_side_all = s%node_side
        if (s%latent) call active_sides(s)
        s%stiff = stiff

        ! thickness (SST / MST override, SFST / SFMT scale) and penalty stiffness
        ! k = SLSFAC x SFM x (K A^2 / V or K A / max diagonal), LS-DYNA's rule,
        ! for a slave node that covers the segment's area. A slave's spring is
        ! scaled to the area the node covers (its share of its own segments),
        ! so that a uniform penetration carries a uniform pressure (the patch
        ! test): the stiffness per unit area k / A times the node's area
        allocate (kmin(s%nnode), s%node_area(s%nnode), s%node_kpa(s%nnode))
        kmin = huge(1.0_wp)
        s%node_area = 0
        s%nshell_seg = 0
        s%nsolid_seg = 0
        s%max_thick = 0
        s%capped = capped
        if (present(follow)) s%follow = follow
        ! (the thicknesses as the cards give them, which THKCHG scales:
        ! kept only where the surface follows the shells)
        if (s%follow) then
            allocate (s%seg_t_raw(s%nseg), s%seg_tn_raw(4, s%nseg))
            s%seg_t_raw = 0
            s%seg_tn_raw = 0
        end if
        do m = 1, s%nseg
            j = s%seg_face(m)
            if (s%seg_kind(m) == seg_shell) then
                s%nshell_seg = s%nshell_seg + 1
                s%seg_t(m) = thick(4)*f%thick(j)
                s%seg_tn(:, m) = thick(4)*f%node_thick(f%node(:, j))
                if (thick(2) <= 0.0_wp .and. s%follow) then
                    s%seg_t_raw(m) = s%seg_t(m)
                    s%seg_tn_raw(:, m) = s%seg_tn(:, m)
                end if
                if (capped) then
                    s%seg_tn(:, m) = min(s%seg_tn(:, m), f%node_cap(f%node(:, j)))
                    s%seg_t(m) = maxval(s%seg_tn(:, m))
                end if
                if (thick(2) > 0.0_wp) then
                    s%seg_t(m) = thick(2)
                    s%seg_tn(:, m) = thick(2)
                end if
                s%max_thick = max(s%max_thick, s%seg_t(m))
            else
                s%nsolid_seg = s%nsolid_seg + 1
                s%seg_t(m) = f%thick(j)
                s%seg_tn(:, m) = f%thick(j)
            end if
            s%seg_k(m) = stiff(1)*stiff(3)*f%kgeo(j)
            s%seg_area(m) = f%area(j)
            if (.not. s%seg_on(m)) cycle
            nnd = seg_nodes(s%seg(:, m))
            do k = 1, nnd
                kmin(s%seg(k, m)) = min(kmin(s%seg(k, m)), f%kgeo(j)/max(f%area(j), tiny(1.0_wp)))
                s%node_area(s%seg(k, m)) = s%node_area(s%seg(k, m)) + f%area(j)/nnd
            end do
        end do
        if (size(slave_nodes) > 0) call lone_slave_areas()
        allocate (s%seg_r(s%nseg))
        do m = 1, s%nseg
            s%seg_r(m) = max(s%seg_t(m), maxval(s%seg_tn(:, m)))
            if (s%seg_kind(m) == seg_shell) s%seg_r(m) = 0.5_wp*s%seg_r(m)
        end do
        if (s%follow) then
            allocate (s%node_t_raw(s%nnode))
            s%node_t_raw = 0
        end if
        do nd = 1, s%nnode
            s%node_t(nd) = thick(3)*f%node_thick(s%node(nd))
            if (thick(1) <= 0.0_wp .and. s%follow) s%node_t_raw(nd) = s%node_t(nd)
            if (capped .and. s%node_t(nd) > f%node_cap(s%node(nd))) then
                s%node_t(nd) = f%node_cap(s%node(nd))
                s%ncap = s%ncap + 1
            end if
            if (thick(1) > 0.0_wp .and. f%node_thick(s%node(nd)) > 0.0_wp) s%node_t(nd) = thick(1)
            s%max_thick = max(s%max_thick, s%node_t(nd))
            s%node_k(nd) = 0
            s%node_kpa(nd) = 0
            if (kmin(nd) < huge(1.0_wp)) then
                s%node_kpa(nd) = stiff(1)*stiff(2)*kmin(nd)
                s%node_k(nd) = s%node_kpa(nd)*s%node_area(nd)
            end if
        end do

        ! a node on rigid parts only moves with its body, whose mass, not the
        ! node's, meets the contact springs (the contact step leaves it out)
        allocate (s%node_rigid(s%nnode))
        s%node_rigid = .true.
        do m = 1, s%nseg
            if (.not. f%rigid(s%seg_face(m))) s%node_rigid(s%seg(:, m)) = .false.
        end do
        do i = 1, size(slave_nodes)
            s%node_rigid(local(slave_nodes(i))) = .false.
        end do
        allocate (s%node_body(s%nnode))
        s%node_body = 0
        do m = 1, s%nseg
            s%node_body(s%seg(:, m)) = s%seg_body(m)
        end do
        s%node_area0 = s%node_area
        s%node_kpa0 = s%node_kpa
        call segment_lists(s)
        call node_neighbours(s)
    contains
        !> Nodes-to-surface slaves on no segment of this surface (a node set,
        !> or the slave side's faces, which are not master segments): their
        !> area and stiffness per area from the model's exterior faces at
        !> them, as every other slave's, so their springs scale with the area
        !> they cover and enter the contact time-step bound. A node on no
        !> exterior face keeps none (it takes the segment's stiffness).
        subroutine lone_slave_areas()
            logical, allocatable :: onseg(:)
            integer :: jf, kk, n2, nn
            allocate (onseg(s%nnode))
            onseg = .false.
            do m = 1, s%nseg
                onseg(s%seg(:, m)) = .true.
            end do
            do jf = 1, f%n
                if (f%across(jf) > 0) cycle
                nn = seg_nodes(f%node(:, jf))
                do kk = 1, nn
                    n2 = local(f%node(kk, jf))
                    if (n2 == 0) cycle
                    if (onseg(n2)) cycle
                    kmin(n2) = min(kmin(n2), f%kgeo(jf)/max(f%area(jf), tiny(1.0_wp)))
                    s%node_area(n2) = s%node_area(n2) + f%area(jf)/nn
                end do
            end do
        end subroutine lone_slave_areas
    end subroutine build_surface

    !> THKCHG: the shell contact thicknesses that follow the shells (those
    !> SST/MST do not fix), the raw ones scaled by each node's thickness
    !> ratio rho (local nodes), then the 40% limit of build_surface where
    !> the surface has it (node_cap: the faces' per model node); a
    !> segment's own thickness by its nodes' mean ratio. max_thick only
    !> grows (the caller's contact reach).
    subroutine follow_thickness(s, node_cap, rho)
        type(surface_t), intent(inout) :: s
        real(wp), intent(in) :: node_cap(:), rho(:)
        integer :: nd, m
        do nd = 1, s%nnode
            if (s%node_t_raw(nd) <= 0.0_wp) cycle
            s%node_t(nd) = s%node_t_raw(nd)*rho(nd)
            if (s%capped) s%node_t(nd) = min(s%node_t(nd), node_cap(s%node(nd)))
            s%max_thick = max(s%max_thick, s%node_t(nd))
        end do
        do m = 1, s%nseg
            if (s%seg_t_raw(m) <= 0.0_wp) cycle
            s%seg_tn(:, m) = s%seg_tn_raw(:, m)*rho(s%seg(:, m))
            if (s%capped) then
                s%seg_tn(:, m) = min(s%seg_tn(:, m), node_cap(s%node(s%seg(:, m))))
                s%seg_t(m) = maxval(s%seg_tn(:, m))
            else
                s%seg_t(m) = s%seg_t_raw(m)*sum(rho(s%seg(:, m)))/4
            end if
            s%seg_r(m) = 0.5_wp*max(s%seg_t(m), maxval(s%seg_tn(:, m)))
            s%max_thick = max(s%max_thick, s%seg_t(m))
        end do
    end subroutine follow_thickness

    !> Sides a slave looks at: single surface everything, two surfaces the
    !> other side, nodes-to-surface the master side.
    pure integer function wanted_side(s, sn) result(want)
        type(surface_t), intent(in) :: s
        integer, intent(in) :: sn
        if (s%single) then
            want = side_a
        else
            want = 0
            if (iand(s%node_side(sn), side_a) /= 0) want = side_b
            if (iand(s%node_side(sn), side_b) /= 0 .and. s%two_way) want = ior(want, side_a)
            if (want == 0) want = side_b
        end if
    end function wanted_side

    !> 3 for a triangle (N4 = N3), else 4.
    !> Normal of segment m at coordinates xl, twice the area long, on the
    !> side its node order gives (outward for a solid face).
    pure function seg_normal(s, xl, m) result(nv)
        type(surface_t), intent(in) :: s
        real(wp), intent(in) :: xl(:, :)
        integer, intent(in) :: m
        real(wp) :: nv(3)
        if (seg_nodes(s%seg(:, m)) == 3) then
            nv = cross(xl(:, s%seg(2, m)) - xl(:, s%seg(1, m)), xl(:, s%seg(3, m)) - xl(:, s%seg(1, m)))
        else
            nv = cross(xl(:, s%seg(3, m)) - xl(:, s%seg(1, m)), xl(:, s%seg(4, m)) - xl(:, s%seg(2, m)))
        end if
    end function seg_normal

    pure integer function seg_nodes(sg)
        integer, intent(in) :: sg(4)
        seg_nodes = 4
        if (sg(4) == sg(3)) seg_nodes = 3
    end function seg_nodes

    !> node -> its active segments (CSR), in segment order
    subroutine segment_lists(s)
        type(surface_t), intent(inout) :: s
        integer, allocatable :: cnt(:)
        integer :: m, k, nd
        if (allocated(s%seg_ptr)) deallocate (s%seg_ptr, s%seg_list)
        allocate (cnt(s%nnode + 1), s%seg_ptr(s%nnode + 1))
        cnt = 0
        do m = 1, s%nseg
            if (.not. s%seg_on(m)) cycle
            do k = 1, seg_nodes(s%seg(:, m))
                cnt(s%seg(k, m)) = cnt(s%seg(k, m)) + 1
            end do
        end do
        s%seg_ptr(1) = 1
        do nd = 1, s%nnode
            s%seg_ptr(nd + 1) = s%seg_ptr(nd) + cnt(nd)
        end do
        allocate (s%seg_list(s%seg_ptr(s%nnode + 1) - 1))
        cnt(1:s%nnode) = s%seg_ptr(1:s%nnode)
        do m = 1, s%nseg
            if (.not. s%seg_on(m)) cycle
            do k = 1, seg_nodes(s%seg(:, m))
                s%seg_list(cnt(s%seg(k, m))) = m
                cnt(s%seg(k, m)) = cnt(s%seg(k, m)) + 1
            end do
        end do
    end subroutine segment_lists

    !> The side bits A and B of each node from its active segments (the
    !> slave bit kept)
    subroutine active_sides(s)
        type(surface_t), intent(inout) :: s
        integer :: m, k
        s%node_side = iand(s%node_side_all, side_slave)
        do m = 1, s%nseg
            if (.not. s%seg_on(m)) cycle
            do k = 1, 4
                s%node_side(s%seg(k, m)) = ior(s%node_side(s%seg(k, m)), s%seg_side(m))
            end do
        end do
    end subroutine active_sides

    !> The segments `on` active from now (erosion: latent faces exposed,
    !> eroded ones gone): the nodes' sides, their springs (a node's area
    !> its share of its active segments', its stiffness per area the
    !> softest of theirs, as build_surface takes them; a node without an
    !> active segment takes its set-up values again), the node-to-segment
    !> and node-to-node lists. Returns the nodes whose springs changed.
    subroutine surface_activate(s, f, on, changed)
        type(surface_t), intent(inout) :: s
        type(faces_t), intent(in) :: f
        logical, intent(in) :: on(:)
        logical, allocatable, intent(out) :: changed(:)
        real(wp), allocatable :: kmin(:), area(:)
        integer :: m, k, nnd, j, nd
        real(wp) :: kpa
        s%seg_on = on
        call active_sides(s)
        allocate (kmin(s%nnode), area(s%nnode), changed(s%nnode))
        kmin = huge(1.0_wp)
        area = 0
        do m = 1, s%nseg
            if (.not. s%seg_on(m)) cycle
            j = s%seg_face(m)
            nnd = seg_nodes(s%seg(:, m))
            do k = 1, nnd
                kmin(s%seg(k, m)) = min(kmin(s%seg(k, m)), f%kgeo(j)/max(f%area(j), tiny(1.0_wp)))
                area(s%seg(k, m)) = area(s%seg(k, m)) + f%area(j)/nnd
            end do
        end do
        do nd = 1, s%nnode
            if (kmin(nd) < huge(1.0_wp)) then
                kpa = s%stiff(1)*s%stiff(2)*kmin(nd)
            else
                area(nd) = s%node_area0(nd)
                kpa = s%node_kpa0(nd)
            end if
            changed(nd) = area(nd) /= s%node_area(nd) .or. kpa /= s%node_kpa(nd)
            s%node_area(nd) = area(nd)
            s%node_kpa(nd) = kpa
            s%node_k(nd) = kpa*area(nd)
        end do
        call segment_lists(s)
        deallocate (s%nn_ptr, s%nn_list)
        call node_neighbours(s)
    end subroutine surface_activate

    !> Nodes that share a segment with each node (itself excluded), ascending.
    subroutine node_neighbours(s)
        type(surface_t), intent(inout) :: s
        integer, allocatable :: mark(:), buf(:), tmp(:)
        integer :: nd, i, k, m, nb, total
        allocate (mark(s%nnode), buf(64))
        mark = 0
        ! at most three other nodes per node-segment incidence
        allocate (s%nn_ptr(s%nnode + 1), s%nn_list(3*size(s%seg_list)))
        s%nn_ptr(1) = 1
        total = 0
        do nd = 1, s%nnode
            nb = 0
            mark(nd) = nd
            do i = s%seg_ptr(nd), s%seg_ptr(nd + 1) - 1
                m = s%seg_list(i)
                do k = 1, 4
                    if (mark(s%seg(k, m)) == nd) cycle
                    mark(s%seg(k, m)) = nd
                    nb = nb + 1
                    if (nb > size(buf)) buf = [buf, buf]
                    buf(nb) = s%seg(k, m)
                end do
            end do
            call small_sort(buf(1:nb))
            s%nn_list(total + 1:total + nb) = buf(1:nb)
            total = total + nb
            s%nn_ptr(nd + 1) = total + 1
        end do
        allocate (tmp(total))
        tmp = s%nn_list(1:total)
        call move_alloc(tmp, s%nn_list)
    end subroutine node_neighbours

end module xd_contact_surface
