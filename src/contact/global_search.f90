!> Step 2 of the automatic contact, the global search (section 4 of Whirley
!> & Engelmann 1993): nodal characteristic lengths, three nested 1-D bucket
!> sorts, the node pool from the slave's bucket and its neighbours, the
!> reduced pool, and the master node list by the paper's steps A-C with
!> trackable and nontrackable master nodes. Closest-1 and closest-3 lists
!> are there for the paper's comparison.
!>
!> The reduced pool of slave s keeps a node m when
!> |x_s - x_m| <= L_m + t_c + max(delta_s, delta_m): L_m the characteristic
!> length (Fig. 3), t_c the largest shell thickness on the surface (a
!> contact surface lies up to a half-thickness off each segment) and
!> delta_i the pool margin of node i, which lets the list stay valid while
!> nodes move between searches (see xd_contact_contact for the bound).
!> The margins follow the local size (a fixed fraction of each node's
!> L at t = 0), so a fine region's pools are as narrow as its own mesh
!> asks, whatever the rest of the surface.
!>
!> Mixed sizes (a coarse barrier or ground next to a fine crush zone, a
!> fine patch in a coarse panel): the master nodes are bucketed in levels
!> by their own radius L_m + t_c + delta_m, in classes a factor of two
!> apart from the smallest up (a class of at most 32 nodes joins the next
!> one up); each level gets its own grid of buckets half its largest
!> radius wide, and a level of at most 32 nodes is one bucket (checked
!> node by node). A slave scans, of each level whose box it can reach,
!> the buckets within its radius there: fine nodes are never scanned
!> through coarse buckets, nor one large segment widens every bucket. A
!> uniform mesh is one or two levels.
!>
!> Slave nodes are independent: the lists are built in blocks of slaves,
!> each block with its own work arrays, and concatenated in slave order, so
!> the result does not depend on the number of threads.
module xd_contact_global_search
    use, intrinsic :: iso_fortran_env, only: int8
    use xd_kinds, only: wp, i8
    use xd_core_memory, only: nbytes, fit
    use xd_contact_surface, only: surface_t, segment_diagonals, side_a, side_b, wanted_side, seg_shell, corners
    use xd_model, only: mnl_minimal, mnl_closest1, mnl_closest3
    use xd_core_sorting, only: where_true
    use xd_core_vectors, only: cross
    implicit none
    private
    public :: buckets_t, bucket_sort, bucket_radii, node_pool, levels_t, sort_levels, level_pool, typical_length
    public :: characteristic_lengths, master_lists_t, build_master_lists, lists_bytes, pool_reach
    public :: search_work_t, new_search_work, mark_none, mark_trackable, mark_nontrackable, search_counts_t
    public :: compact_lists, lists_rows, list_row, list_rows
    public :: separating_axes, reach_factor, pool_margins, margin_floor, margin_classes

    integer(int8), parameter :: mark_none = 0, mark_trackable = 1, mark_nontrackable = 2
    integer, parameter :: axes_cache = 1024

    !> Nodes sorted into a grid of buckets at least `w` wide in each direction.
    type :: buckets_t
        integer :: nb(3) = 1
        real(wp) :: lo(3) = 0, hi(3) = 0, w(3) = 1   !< the nodes' box and the buckets' widths
        real(wp) :: base = 0                !< the largest base radius (bucket_radii) of its nodes
        real(wp) :: dmax = 0                !< the largest margin of its nodes
        integer, allocatable :: start(:)    !< (ncell + 1) first position of each cell in item
        integer, allocatable :: item(:)     !< node numbers, cell by cell
        !> (5, n) x, y, z, base radius and margin of item(q), for a streaming scan
        real(wp), allocatable :: xr(:, :)
    end type buckets_t

    !> Bucket grids of the master nodes by size (see the module's notes).
    type :: levels_t
        integer :: n = 0
        type(buckets_t), allocatable :: lv(:)
    end type levels_t

    integer, parameter :: few_nodes = 32     !< a level this small is one bucket

    !> Master node lists of all slaves, closest first: slave k's in
    !> node(ptr(k):last(k)). A search of some slaves rewrites their lists in
    !> place where they fit, else at the end of the store, and compacts the
    !> store when half of it is dead, so it costs about what it searched.
    type :: master_lists_t
        integer, allocatable :: ptr(:)      !< (nslave) where each slave's list starts
        integer, allocatable :: last(:)     !< (nslave) and ends (ptr - 1: empty)
        integer, allocatable :: node(:)     !< local node numbers
        logical, allocatable :: trackable(:)
        integer :: nused = 0, ndead = 0     !< entries of node in use, and dead among them
        !> (nslave) the slave's clearance at the search: the least distance
        !> from it to the bounding box of any segment at a node of its pool
        !> (its own segments and sides it does not look at left out), less
        !> the distance at which that segment's check can find a contact
        !> (the two half thicknesses for a shell; twice the slave's half
        !> thickness and the window for a solid face: a node beside a face's
        !> border is found up to twice its depth away). Every point of a
        !> segment moves at most u and so does the slave: while 2u plus the
        !> lead stays below it, the local search finds nothing for a slave
        !> that had no contact last cycle (see contact_local_search). A value
        !> not above zero only says there is no clearance (the search of it
        !> stops there)
        real(wp), allocatable :: gap(:)
        !> the slave's node pool less itself, in pool_node(pool_ptr(k):
        !> pool_last(k)) (kept as the lists are): by the search's bound, the
        !> segments at these nodes are the only ones it can reach before its
        !> next search (the local search refreshes its clearance over them)
        integer, allocatable :: pool_ptr(:), pool_last(:), pool_node(:)
        integer :: pused = 0, pdead = 0
        !> the largest segment part of a clearance's reach (see one_slave)
        real(wp) :: cmax = 0
        !> (3, nslave) where the slave was at its search (its gap's origin)
        real(wp), allocatable :: xg(:, :)
        !> (nslave) the interface's motion bound (its odometer) at the slave's
        !> search, and the number of that search
        real(wp), allocatable :: og(:)
        integer, allocatable :: at(:)
        !> (nslave) the slave's row in the per-slave arrays above (ptr,
        !> last, gap, pool_ptr, pool_last, xg, og, at; 0: none held here),
        !> nrow rows (lists_rows: on a rank of several, its own slaves',
        !> issue 32). Unallocated: slave k's row is k, nslave rows
        integer, allocatable :: row(:)
        integer :: nrow = 0
    end type master_lists_t

    !> Sizes summed over the slaves of one search.
    type :: search_counts_t
        integer(i8) :: pool = 0, reduced = 0, masters = 0
    end type search_counts_t

    !> One thread's work arrays: marks per surface node and the pool. A mark
    !> or an exclusion holds only while its stamp is the current slave's
    !> number, so nothing is reset between slaves.
    type :: search_work_t
        integer(int8), allocatable :: mark(:)
        integer, allocatable :: stamp(:)     !< slave whose search set mark(i)
        integer, allocatable :: excluded(:)  !< slave that node i shares a segment with
        integer, allocatable :: seen(:)      !< slave whose clearance took segment m in already
        integer, allocatable :: pool(:)
        real(wp), allocatable :: dist(:)
        integer :: npool = 0
        !> the separating axes of the segments met last (a direct-mapped
        !> cache by segment number: neighbouring slaves meet the same
        !> segments, and a search takes the axes only where it needs them)
        integer :: ctag(0:axes_cache - 1) = 0
        real(wp) :: cax(4, 6, 0:axes_cache - 1) = 0
    end type search_work_t

    !> Growable output of one block of slaves.
    type :: block_out_t
        integer :: n = 0
        real(wp), allocatable :: gap(:)
        integer, allocatable :: cnt(:), node(:)
        logical, allocatable :: trk(:)
        integer :: npool = 0
        integer, allocatable :: pcnt(:), pool(:)   !< pool sizes and nodes (the slave itself left out)
    end type block_out_t

    integer, parameter :: block_size = 256

    !> No node's margin below this fraction of the typical one: a node whose
    !> segments are all that small (a collapsed or sliver shell) would have
    !> the whole surface searched at each step it moves. Larger pools there
    !> cost time only; the search's bound holds with any margin.
    real(wp), parameter :: margin_floor = 1.0_wp/32

contains

    !> The bytes of an interface's master lists and pool.
    integer(i8) function lists_bytes(l) result(b)
        type(master_lists_t), intent(in) :: l
        b = nbytes(l%ptr) + nbytes(l%last) + nbytes(l%node) + nbytes(l%trackable) + nbytes(l%gap) &
            + nbytes(l%pool_ptr) + nbytes(l%pool_last) + nbytes(l%pool_node) + nbytes(l%xg) + nbytes(l%og) &
            + nbytes(l%at) + nbytes(l%row)
    end function lists_bytes

    !> Slave k's row in the lists' per-slave arrays (0: none held here).
    pure integer function list_row(l, k) result(r)
        type(master_lists_t), intent(in) :: l
        integer, intent(in) :: k
        r = k
        if (allocated(l%row)) r = l%row(k)
    end function list_row

    !> The number of rows the lists' per-slave arrays hold, of nslave slaves.
    pure integer function list_rows(l, nslave) result(n)
        type(master_lists_t), intent(in) :: l
        integer, intent(in) :: nslave
        n = nslave
        if (allocated(l%row)) n = l%nrow
    end function list_rows

    !> The lists' per-slave arrays re-laid in new rows: slave k's at row(k)
    !> (0: not held), nrow rows. A slave that had no row keeps no list and
    !> no pool and has no clearance taken (as a slave never searched); the
    !> stores are compacted, the entries of the slaves left out dropped.
    !> Each kept slave's list, pool, gap and search stamps are as they were.
    subroutine lists_rows(l, row, nrow)
        type(master_lists_t), intent(inout) :: l
        integer, intent(in) :: row(:), nrow
        integer, allocatable :: old(:)
        integer :: k, r
        ! (old(r): new row r's row before, 0 where its slave had none)
        allocate (old(nrow))
        old = 0
        do k = 1, size(row)
            if (row(k) > 0) old(row(k)) = list_row(l, k)
        end do
        ! (an empty list: ptr 1, last 0; no pool: pool_last = pool_ptr - 2;
        ! no clearance taken: gap -huge)
        call relay_int(l%ptr, 1)
        call relay_int(l%last, 0)
        call relay_int(l%pool_ptr, 1)
        call relay_int(l%pool_last, -1)
        call relay_int(l%at, 0)
        call relay_real(l%gap, -huge(1.0_wp))
        call relay_real(l%og, 0.0_wp)
        if (allocated(l%xg)) then
            block
                real(wp), allocatable :: xa(:, :)
                allocate (xa(3, nrow))
                do r = 1, nrow
                    xa(:, r) = 0
                    if (old(r) > 0) xa(:, r) = l%xg(:, old(r))
                end do
                call move_alloc(xa, l%xg)
            end block
        end if
        ! (every slave's rows in slave order: no map kept)
        r = 0
        if (nrow == size(row)) then
            do k = 1, size(row)
                if (row(k) /= k) exit
                r = k
            end do
        end if
        if (r == size(row)) then
            if (allocated(l%row)) deallocate (l%row)
        else
            l%row = row
        end if
        l%nrow = nrow
        ! (the stores cut to their entries and a quarter's room: those of
        ! every slave, a dump's gathering, do not stay with the rows)
        if (allocated(l%ptr) .and. allocated(l%node)) then
            call compact_lists(l)
            if (size(l%node) > l%nused + l%nused/4 + 64) then
                call fit(l%node, l%nused + l%nused/4 + 64)
                call fit(l%trackable, l%nused + l%nused/4 + 64)
            end if
        end if
        if (allocated(l%pool_ptr) .and. allocated(l%pool_node)) then
            call compact_pools(l)
            if (size(l%pool_node) > l%pused + l%pused/4 + 64) call fit(l%pool_node, l%pused + l%pused/4 + 64)
        end if
    contains
        !> a's entries in the new rows (dflt where a row had none before)
        subroutine relay_int(a, dflt)
            integer, allocatable, intent(inout) :: a(:)
            integer, intent(in) :: dflt
            integer, allocatable :: b(:)
            integer :: q
            if (.not. allocated(a)) return
            allocate (b(nrow))
            do q = 1, nrow
                b(q) = dflt
                if (old(q) > 0) b(q) = a(old(q))
            end do
            call move_alloc(b, a)
        end subroutine relay_int
        subroutine relay_real(a, dflt)
            real(wp), allocatable, intent(inout) :: a(:)
            real(wp), intent(in) :: dflt
            real(wp), allocatable :: b(:)
            integer :: q
            if (.not. allocated(a)) return
            allocate (b(nrow))
            do q = 1, nrow
                b(q) = dflt
                if (old(q) > 0) b(q) = a(old(q))
            end do
            call move_alloc(b, a)
        end subroutine relay_real
    end subroutine lists_rows

    subroutine new_search_work(nnode, w, nseg)
        integer, intent(in) :: nnode
        type(search_work_t), intent(out) :: w
        integer, intent(in), optional :: nseg
        allocate (w%mark(nnode), w%stamp(nnode), w%excluded(nnode), w%pool(64), w%dist(64))
        if (present(nseg)) then
            allocate (w%seen(nseg))
            w%seen = 0
        end if
        w%mark = mark_none
        w%stamp = 0
        w%excluded = 0
    end subroutine new_search_work

    !> The pool margins of the surface's nodes from their characteristic
    !> lengths lc: delta_i = pmarg L_i, at most typ (pmarg times the median
    !> L: a few large segments must not widen the pools around them); typ
    !> for a node without a segment and as the floor's unit (margin_floor;
    !> nraised: the nodes so raised). dmin(i): the least margin of i and the nodes
    !> sharing a segment with it, what i's motion may use up of the margins
    !> it bounds (xd_contact_contact).
    subroutine pool_margins(s, lc, pmarg, typ, dl, dmin, nraised)
        type(surface_t), intent(in) :: s
        real(wp), intent(in) :: lc(:), pmarg, typ
        real(wp), allocatable, intent(out) :: dl(:), dmin(:)
        integer, intent(out) :: nraised
        integer :: i, j
        real(wp) :: d
        allocate (dl(s%nnode), dmin(s%nnode))
        nraised = 0
        do i = 1, s%nnode
            if (lc(i) > 0.0_wp) then
                dl(i) = min(pmarg*lc(i), typ)
                if (dl(i) < margin_floor*typ) then
                    dl(i) = margin_floor*typ
                    nraised = nraised + 1
                end if
            else
                dl(i) = typ
            end if
        end do
        do i = 1, s%nnode
            d = dl(i)
            do j = s%nn_ptr(i), s%nn_ptr(i + 1) - 1
                d = min(d, dl(s%nn_list(j)))
            end do
            dmin(i) = d
        end do
    end subroutine pool_margins

    !> The slaves' classes by their own pool margin: the largest margin (the
    !> typical one, which most nodes have) a class of its own; below it
    !> bands a factor of two wide down to the least margin (wider bands, by
    !> whole factors of two, where that would make more than max_classes);
    !> numbered from 1 without gaps; cmin(c): the least margin in class c.
    !> Each class is searched at the pace its own margins ask
    !> (xd_contact_contact): the typical nodes as with one margin for all.
    subroutine margin_classes(s, dl, cls, cmin)
        type(surface_t), intent(in) :: s
        real(wp), intent(in) :: dl(:)
        integer, allocatable, intent(out) :: cls(:)
        real(wp), allocatable, intent(out) :: cmin(:)
        integer, parameter :: max_classes = 8
        integer, allocatable :: band(:), map(:)
        real(wp) :: d0
        integer :: k, nb, width, nc
        allocate (cls(s%nslave), band(s%nslave))
        if (s%nslave == 0) then
            allocate (cmin(0))
            return
        end if
        d0 = maxval(dl(s%slave))
        do k = 1, s%nslave
            band(k) = 0
            ! (within round-off of the largest: the same class)
            if (dl(s%slave(k)) < d0*(1 - 1.0e-9_wp)) band(k) = exponent(d0/max(dl(s%slave(k)), tiny(1.0_wp)))
        end do
        nb = maxval(band)
        width = max(1, (nb + max_classes - 2)/(max_classes - 1))
        where (band > 0) band = (band - 1)/width + 1
        band = band + 1
        allocate (map(maxval(band)))
        map = 0
        do k = 1, s%nslave
            map(band(k)) = 1
        end do
        nc = 0
        do k = 1, size(map)
            if (map(k) == 0) cycle
            nc = nc + 1
            map(k) = nc
        end do
        allocate (cmin(nc))
        cmin = huge(1.0_wp)
        do k = 1, s%nslave
            cls(k) = map(band(k))
            cmin(cls(k)) = min(cmin(cls(k)), dl(s%slave(k)))
        end do
    end subroutine margin_classes

    !> Nodal characteristic length (section 4): the largest diagonal of the
    !> segments at each node, in the coordinates xl (3, nnode) of the surface.
    subroutine characteristic_lengths(s, xl, lc)
        type(surface_t), intent(in) :: s
        real(wp), intent(in) :: xl(:, :)
        real(wp), intent(out) :: lc(:)
        integer :: m, i
        real(wp) :: dmin, xs(3, 4)
        real(wp), allocatable :: dmax(:)
        allocate (dmax(s%nseg))
        ! (each segment's, then each node's largest over its segments:
        ! threaded, a maximum is the same in any order)
        !$omp parallel do schedule(static) private(dmin, xs)
        do m = 1, s%nseg
            call corners(xl, s%seg(:, m), xs)
            call segment_diagonals(xs, dmin, dmax(m))
        end do
        !$omp end parallel do
        lc = 0
        !$omp parallel do schedule(static)
        do i = 1, s%nnode
            lc(i) = node_length(s, dmax, i)
        end do
        !$omp end parallel do
    end subroutine characteristic_lengths

    !> Node i's characteristic length: the largest dmax of its segments (0
    !> without one).
    pure real(wp) function node_length(s, dmax, i) result(l)
        type(surface_t), intent(in) :: s
        real(wp), intent(in) :: dmax(:)
        integer, intent(in) :: i
        integer :: k
        l = 0
        do k = s%seg_ptr(i), s%seg_ptr(i + 1) - 1
            l = max(l, dmax(s%seg_list(k)))
        end do
    end function node_length

    !> Three nested one-dimensional bucket sorts (Benson & Hallquist 1990):
    !> the nodes with active(i) by x slab, each slab by y column, each column
    !> by z cell. Buckets are about rmax/2 wide and a point's pool is scanned
    !> over the buckets within its radius, so every node within it is seen
    !> (half-width buckets scan 5^3 = 125 small buckets, 58% of the volume
    !> of 27 buckets rmax wide). Their number is kept below about twice the
    !> number of nodes so memory stays linear.
    subroutine bucket_sort(xl, active, rmax, bk, single)
        real(wp), intent(in) :: xl(:, :)
        logical, intent(in) :: active(:)
        real(wp), intent(in) :: rmax
        type(buckets_t), intent(out) :: bk
        logical, intent(in), optional :: single   !< one bucket: every node checked
        logical :: one
        one = .false.
        if (present(single)) one = single
        call bucket_items(xl, where_true(active), rmax, one, bk)
    end subroutine bucket_sort

    !> bucket_sort of the nodes `items`.
    subroutine bucket_items(xl, items, rmax, single, bk)
        real(wp), intent(in) :: xl(:, :)
        integer, intent(in) :: items(:)
        real(wp), intent(in) :: rmax
        logical, intent(in) :: single
        type(buckets_t), intent(out) :: bk
        integer :: nact, i, d, ncell, cap, c(3)
        integer, allocatable :: key(:), tmp(:)
        real(wp) :: hi(3), ext(3), f
        nact = size(items)
        bk%item = items
        if (nact == 0) then
            allocate (bk%start(2))
            bk%start = 1
            return
        end if
        do d = 1, 3
            bk%lo(d) = minval(xl(d, bk%item))
            hi(d) = maxval(xl(d, bk%item))
        end do
        bk%hi = hi
        ext = hi - bk%lo
        do d = 1, 3
            bk%nb(d) = max(1, int(min(ext(d)/max(0.5_wp*rmax, tiny(1.0_wp)), 1.0e6_wp)))
        end do
        if (single) bk%nb = 1
        cap = max(8, 2*nact)
        do while (product(real(bk%nb, wp)) > real(cap, wp))
            f = (product(real(bk%nb, wp))/cap)**(1.0_wp/3.0_wp)
            bk%nb = max(1, int(bk%nb/max(f, 1.01_wp)))
        end do
        bk%w = max(ext/bk%nb, 0.5_wp*rmax, tiny(1.0_wp))
        ncell = product(bk%nb)
        ! one stable counting sort by the cell's number, x slowest and z
        ! fastest: the order the three nested sorts give
        allocate (key(nact), tmp(nact), bk%start(ncell + 1))
        do i = 1, nact
            c = cell_of(bk, xl(:, bk%item(i)))
            key(i) = c(3) + bk%nb(3)*((c(2) - 1) + bk%nb(2)*(c(1) - 1))
        end do
        bk%start = 0
        do i = 1, nact
            bk%start(key(i) + 1) = bk%start(key(i) + 1) + 1
        end do
        bk%start(1) = 1
        do i = 2, ncell + 1
            bk%start(i) = bk%start(i) + bk%start(i - 1)
        end do
        do i = 1, nact
            tmp(bk%start(key(i))) = bk%item(i)
            bk%start(key(i)) = bk%start(key(i)) + 1
        end do
        ! (each start now points past its cell: shift back by one cell)
        bk%start(2:ncell + 1) = bk%start(1:ncell)
        bk%start(1) = 1
        bk%item = tmp
        allocate (bk%xr(5, nact))
        do i = 1, nact
            bk%xr(1:3, i) = xl(:, bk%item(i))
        end do
        bk%xr(4:5, :) = 0
    end subroutine bucket_items

    !> The radius of each bucketed node m, in bucket order: a point p with
    !> margin d_p has m in its pool when |p - x_m| <= base(m) + max(d_p,
    !> dl(m)) (base: L_m + t_c; dl: the node's pool margin).
    subroutine bucket_radii(bk, base, dl)
        type(buckets_t), intent(inout) :: bk
        real(wp), intent(in) :: base(:), dl(:)
        integer :: q
        do q = 1, size(bk%item)
            bk%xr(4, q) = base(bk%item(q))
            bk%xr(5, q) = dl(bk%item(q))
        end do
        bk%base = 0
        bk%dmax = 0
        if (size(bk%item) == 0) return
        bk%base = maxval(bk%xr(4, :))
        bk%dmax = maxval(bk%xr(5, :))
    end subroutine bucket_radii

    pure function cell_of(bk, p) result(c)
        type(buckets_t), intent(in) :: bk
        real(wp), intent(in) :: p(3)
        integer :: c(3)
        c = min(bk%nb, max(1, 1 + int((p - bk%lo)/bk%w)))
    end function cell_of

    !> Node pool of a point p with margin dlp: the nodes m of the grid that
    !> lie within base(m) + max(dlp, dl(m)) of it (bucket_radii).
    subroutine node_pool(bk, p, dlp, w)
        type(buckets_t), intent(in) :: bk
        real(wp), intent(in) :: p(3), dlp
        type(search_work_t), intent(inout) :: w
        w%npool = 0
        call scan_buckets(bk, p, dlp, w)
        w%dist(1:w%npool) = sqrt(w%dist(1:w%npool))
    end subroutine node_pool

    !> Node pool of a point p with margin dlp over every level of bucket grids.
    subroutine level_pool(lev, p, dlp, w)
        type(levels_t), intent(in) :: lev
        real(wp), intent(in) :: p(3), dlp
        type(search_work_t), intent(inout) :: w
        integer :: k
        w%npool = 0
        do k = 1, lev%n
            call scan_buckets(lev%lv(k), p, dlp, w)
        end do
        w%dist(1:w%npool) = sqrt(w%dist(1:w%npool))
    end subroutine level_pool

    !> Append to the pool the nodes of bk within their radius of p (squared
    !> distances): the buckets within the grid's largest radius for p, none
    !> if p lies that far outside the nodes' box. The cells along z of a
    !> column are contiguous, so each column is one streaming scan.
    subroutine scan_buckets(bk, p, dlp, w)
        type(buckets_t), intent(in) :: bk
        real(wp), intent(in) :: p(3), dlp
        type(search_work_t), intent(inout) :: w
        integer :: c0(3), c1(3), i, j, cell, q, q0, q1, n
        real(wp) :: d2, rq, rmax
        if (size(bk%item) == 0) return
        rmax = bk%base + max(dlp, bk%dmax)
        if (any(p + rmax < bk%lo) .or. any(p - rmax > bk%hi)) return
        c0 = max(1, 1 + int(max((p - rmax - bk%lo)/bk%w, 0.0_wp)))
        c1 = min(bk%nb, 1 + int(min((p + rmax - bk%lo)/bk%w, real(bk%nb, wp))))
        do i = c0(1), c1(1)
            do j = c0(2), c1(2)
                cell = bk%nb(3)*((j - 1) + bk%nb(2)*(i - 1))
                q0 = bk%start(cell + c0(3))
                q1 = bk%start(cell + c1(3) + 1) - 1
                if (w%npool + q1 - q0 + 1 > size(w%pool)) call grow_pool(w, w%npool + q1 - q0 + 1)
                ! branch-free compaction: write every candidate, keep those inside
                n = w%npool
                do q = q0, q1
                    d2 = (bk%xr(1, q) - p(1))**2 + (bk%xr(2, q) - p(2))**2 + (bk%xr(3, q) - p(3))**2
                    rq = bk%xr(4, q) + max(dlp, bk%xr(5, q))
                    w%pool(n + 1) = bk%item(q)
                    w%dist(n + 1) = d2
                    n = n + merge(1, 0, d2 <= rq*rq)
                end do
                w%npool = n
            end do
        end do
    end subroutine scan_buckets

    !> The levels of bucket grids of the nodes with active(i): base radius
    !> base(i) and margin dl(i) (bucket_radii), own radius base + dl. The
    !> nodes fall in classes of radius a factor of two apart from the
    !> smallest up; a level gathers classes from the smallest up to the
    !> first where it holds more than few_nodes nodes; what is left at the
    !> end (the few largest) is one level, one bucket if few enough.
    subroutine sort_levels(xl, active, base, dl, lev)
        real(wp), intent(in) :: xl(:, :), base(:), dl(:)
        logical, intent(in) :: active(:)
        type(levels_t), intent(inout) :: lev
        call sort_level_items(xl, where_true(active), base, dl, lev)
    end subroutine sort_levels

    !> sort_levels of the nodes `nodes`.
    subroutine sort_level_items(xl, nodes, base, dl, lev)
        real(wp), intent(in) :: xl(:, :), base(:), dl(:)
        integer, intent(in) :: nodes(:)
        type(levels_t), intent(inout) :: lev
        integer, allocatable :: cls(:), cnt(:), lvl(:), first(:), items(:)
        real(wp), allocatable :: rmax(:)
        real(wp) :: rmin
        integer :: i, j, k, kmax, nl, acc
        if (allocated(lev%lv)) deallocate (lev%lv)
        lev%n = 0
        if (size(nodes) == 0) then
            allocate (lev%lv(0))
            return
        end if
        rmin = huge(1.0_wp)
        do j = 1, size(nodes)
            rmin = min(rmin, base(nodes(j)) + dl(nodes(j)))
        end do
        rmin = max(rmin, tiny(1.0_wp))
        ! class k: radii in [2^(k-1), 2^k) rmin
        allocate (cls(size(nodes)))
        do j = 1, size(nodes)
            i = nodes(j)
            cls(j) = exponent(max(base(i) + dl(i), rmin)/rmin)
        end do
        kmax = maxval(cls)
        allocate (cnt(kmax), lvl(kmax))
        cnt = 0
        do j = 1, size(nodes)
            cnt(cls(j)) = cnt(cls(j)) + 1
        end do
        ! the classes' levels, from the smallest up
        nl = 1
        acc = 0
        do k = 1, kmax
            lvl(k) = nl
            acc = acc + cnt(k)
            if (acc > few_nodes .and. k < kmax) then
                nl = nl + 1
                acc = 0
            end if
        end do
        ! the nodes level by level (a counting sort), each level's largest radius
        allocate (first(nl + 1), rmax(nl), items(size(nodes)))
        first = 0
        rmax = 0
        do j = 1, size(nodes)
            k = lvl(cls(j))
            first(k + 1) = first(k + 1) + 1
            rmax(k) = max(rmax(k), base(nodes(j)) + dl(nodes(j)))
        end do
        first(1) = 1
        do k = 2, nl + 1
            first(k) = first(k) + first(k - 1)
        end do
        do j = 1, size(nodes)
            k = lvl(cls(j))
            items(first(k)) = nodes(j)
            first(k) = first(k) + 1
        end do
        first(2:nl + 1) = first(1:nl)
        first(1) = 1
        allocate (lev%lv(nl))
        do k = 1, nl
            if (first(k + 1) == first(k)) cycle
            lev%n = lev%n + 1
            call bucket_items(xl, items(first(k):first(k + 1) - 1), rmax(k), first(k + 1) - first(k) <= few_nodes, &
                              lev%lv(lev%n))
            call bucket_radii(lev%lv(lev%n), base, dl)
        end do
    end subroutine sort_level_items

    !> The value below which a fraction frac of a lies (the median for 0.5):
    !> a selection in O(n) on a copy.
    function typical_length(a, frac) result(v)
        real(wp), intent(in) :: a(:), frac
        real(wp) :: v
        real(wp), allocatable :: b(:)
        real(wp) :: piv, t
        integer :: k, lo, hi, i, j
        if (size(a) == 0) then
            v = 0
            return
        end if
        b = a
        k = min(size(b), max(1, 1 + int(frac*(size(b) - 1))))
        lo = 1
        hi = size(b)
        do while (lo < hi)
            piv = b((lo + hi)/2)
            i = lo
            j = hi
            do while (i <= j)
                do while (b(i) < piv)
                    i = i + 1
                end do
                do while (b(j) > piv)
                    j = j - 1
                end do
                if (i <= j) then
                    t = b(i)
                    b(i) = b(j)
                    b(j) = t
                    i = i + 1
                    j = j - 1
                end if
            end do
            if (k <= j) then
                hi = j
            else if (k >= i) then
                lo = i
            else
                exit
            end if
        end do
        v = b(k)
    end function typical_length

    subroutine grow_pool(w, need)
        type(search_work_t), intent(inout) :: w
        integer, intent(in) :: need
        integer, allocatable :: ip(:)
        real(wp), allocatable :: rd(:)
        integer :: n
        n = max(2*size(w%pool), need)
        allocate (ip(n), rd(n))
        ip(1:w%npool) = w%pool(1:w%npool)
        rd(1:w%npool) = w%dist(1:w%npool)
        call move_alloc(ip, w%pool)
        call move_alloc(rd, w%dist)
    end subroutine grow_pool

    !> Master node lists of the slave nodes (section 4). xl: surface
    !> coordinates; lc: characteristic lengths; reach: the contact reach t_c;
    !> dl: the pool margins delta of the surface nodes; mnl: the list policy.
    !> search: the slaves to search (all if absent); the others keep the
    !> lists they have (none if they have none). Where only some are
    !> searched, only the master nodes that can lie in their pools are
    !> bucketed (within the box of their positions grown by the largest
    !> radius), so a search of a small region costs about its own size.
    !> stamp and odo: the search's number and the interface's motion bound
    !> then, kept with the searched slaves' lists (at, og). With lcodo, the
    !> characteristic lengths lc are taken here, of every node or (where
    !> some slaves only are searched) of the bucketed ones, lcodo(m) = odo
    !> for those (a segment at m lies within lc(m) + 2 (odometer - lcodo(m))
    !> of m at any time after); without it lc is given.
    !> How far beyond the box of the slaves `todo` a master node can lie in
    !> one of their pools: their largest pool margin, the master nodes'
    !> largest characteristic length (with lcodo and odo, grown by the
    !> motion bound since it was taken) and margin, and the contact reach.
    !> build_master_lists buckets what lies within it; MPI's search
    !> exchange sends what lies within it of a rank's slaves.
    pure real(wp) function pool_reach(s, lc, dl, reach, todo, odo, lcodo) result(g)
        type(surface_t), intent(in) :: s
        real(wp), intent(in) :: lc(:), dl(:), reach
        logical, intent(in) :: todo(:)
        real(wp), intent(in), optional :: odo, lcodo(:)
        real(wp) :: grow, r
        integer :: i
        grow = 0
        do i = 1, s%nslave
            if (todo(i)) grow = max(grow, dl(s%slave(i)))
        end do
        r = 0
        do i = 1, s%nnode
            if (iand(s%node_side(i), ior(side_a, side_b)) == 0) cycle
            if (present(lcodo)) then
                r = max(r, lc(i) + 2*(odo - lcodo(i)) + dl(i))
            else
                r = max(r, lc(i) + dl(i))
            end if
        end do
        g = grow + r + reach
    end function pool_reach

    subroutine build_master_lists(s, xl, lc, reach, dl, mnl, lists, counts, search, stamp, odo, lcodo, fresh)
        type(surface_t), intent(in) :: s
        real(wp), intent(in) :: xl(:, :), reach, dl(:)
        real(wp), intent(inout) :: lc(:)
        real(wp), intent(inout), optional :: lcodo(:)
        integer, intent(in) :: mnl
        type(master_lists_t), intent(inout) :: lists
        type(search_counts_t), intent(out) :: counts
        logical, intent(in), optional :: search(:)
        integer, intent(in), optional :: stamp
        real(wp), intent(in), optional :: odo
        !> MPI with contact ghosts: per surface node, its position xl is
        !> current (else stale: never bucketed; every node in the grown box
        !> of the searched slaves is current, contact's search_box)
        logical, intent(in), optional :: fresh(:)
        type(levels_t) :: lev
        type(search_work_t) :: w
        type(block_out_t), allocatable :: blk(:)
        real(wp), allocatable :: base(:), box(:, :)
        real(wp) :: cmax, lo(3), hi(3), grow
        logical, allocatable :: master(:), todo(:)
        integer :: nblk, ib, i, first, last, q, k, m, nt
        integer, allocatable :: mnodes(:)
        real(wp), allocatable :: dmax(:)
        real(wp) :: r, dmin, xs(3, 4)
        integer(i8) :: npool, nred, nm

        allocate (base(s%nnode), master(s%nnode), todo(s%nslave), box(6, s%nseg))
        todo = .true.
        if (present(search)) todo = search
        master = iand(s%node_side, ior(side_a, side_b)) /= 0
        if (all(todo) .and. .not. present(fresh)) then
            if (present(lcodo)) then
                call characteristic_lengths(s, xl, lc)
                lcodo = odo
            end if
            mnodes = where_true(master)
            ! the bounding box of each segment (the slaves' clearances; their
            ! separating axes are taken where needed, one_slave)
            !$omp parallel do schedule(static)
            do i = 1, s%nseg
                call seg_box(i)
            end do
            !$omp end parallel do
        else
            ! only the master nodes that can lie in a searched slave's pool:
            ! those within the box of the searched slaves grown by the
            ! largest radius (each node's characteristic length bounded as
            ! local_search_t%lcodo says)
            lo = huge(1.0_wp)
            hi = -huge(1.0_wp)
            do i = 1, s%nslave
                if (.not. todo(i)) cycle
                lo = min(lo, xl(:, s%slave(i)))
                hi = max(hi, xl(:, s%slave(i)))
            end do
            grow = pool_reach(s, lc, dl, reach, todo, odo, lcodo)
            lo = lo - grow
            hi = hi + grow
            do i = 1, s%nnode
                if (master(i)) master(i) = all(xl(:, i) >= lo) .and. all(xl(:, i) <= hi)
            end do
            if (present(fresh)) master = master .and. fresh
            mnodes = where_true(master)
            ! the segments at those nodes: their boxes, and the nodes'
            ! characteristic lengths now
            allocate (dmax(s%nseg))
            dmax = -1
            do q = 1, size(mnodes)
                do k = s%seg_ptr(mnodes(q)), s%seg_ptr(mnodes(q) + 1) - 1
                    m = s%seg_list(k)
                    if (dmax(m) >= 0.0_wp) cycle
                    call seg_box(m)
                    call corners(xl, s%seg(:, m), xs)
                    call segment_diagonals(xs, dmin, dmax(m))
                end do
            end do
            if (present(lcodo)) then
                do q = 1, size(mnodes)
                    lc(mnodes(q)) = node_length(s, dmax, mnodes(q))
                    lcodo(mnodes(q)) = odo
                end do
            end if
        end if
        base = lc + reach
        call sort_level_items(xl, mnodes, base, dl, lev)
        cmax = 0
        !$omp parallel do schedule(static) reduction(max:cmax)
        do i = 1, s%nseg
            cmax = max(cmax, reach_factor(s, i)*s%seg_r(i))
        end do
        !$omp end parallel do
        nblk = (s%nslave + block_size - 1)/block_size
        allocate (blk(nblk))
        npool = 0
        nred = 0
        !$omp parallel private(w, i, first, last, nt) reduction(+:npool, nred)
        call new_search_work(s%nnode, w, s%nseg)
        !$omp do schedule(dynamic)
        do ib = 1, nblk
            first = (ib - 1)*block_size + 1
            last = min(s%nslave, ib*block_size)
            if (.not. any(todo(first:last))) then
                ! (nothing searched here: the merge passes the block by)
                allocate (blk(ib)%cnt(0), blk(ib)%pcnt(0), blk(ib)%gap(0))
                cycle
            end if
            ! (the lists' and pools' room for the block's searched slaves,
            ! grown where short: a rank's own slaves, with contact ghosts,
            ! are a few in each of many blocks)
            nt = count(todo(first:last))
            allocate (blk(ib)%cnt(last - first + 1), blk(ib)%node(8*nt), blk(ib)%trk(8*nt), &
                      blk(ib)%gap(last - first + 1), blk(ib)%pcnt(last - first + 1), blk(ib)%pool(32*nt))
            blk(ib)%gap = -huge(1.0_wp)
            blk(ib)%pcnt = 0
            blk(ib)%cnt = 0
            do i = first, last
                if (.not. todo(i)) cycle
                call one_slave(s, lev, xl, lc, dl, box, cmax, reach, mnl, s%slave(i), w, blk(ib), i - first + 1, &
                               npool, nred)
            end do
        end do
        !$omp end do
        !$omp end parallel
        counts%pool = npool
        counts%reduced = nred
        call merge_lists(s, todo, blk, lists)
        lists%cmax = cmax
        ! where and when each searched slave's gap was taken, and its list
        r = 0
        if (present(odo)) r = odo
        k = 0
        if (present(stamp)) k = stamp
        nm = 0
        !$omp parallel do schedule(static) private(q) reduction(+:nm)
        do i = 1, s%nslave
            if (.not. todo(i)) cycle
            q = list_row(lists, i)
            lists%xg(:, q) = xl(:, s%slave(i))
            lists%og(q) = r
            lists%at(q) = k
            nm = nm + (lists%last(q) - lists%ptr(q) + 1)
        end do
        !$omp end parallel do
        counts%masters = nm
    contains
        subroutine seg_box(m)
            integer, intent(in) :: m
            box(1:3, m) = min(xl(:, s%seg(1, m)), xl(:, s%seg(2, m)), xl(:, s%seg(3, m)), xl(:, s%seg(4, m)))
            box(4:6, m) = max(xl(:, s%seg(1, m)), xl(:, s%seg(2, m)), xl(:, s%seg(3, m)), xl(:, s%seg(4, m)))
        end subroutine seg_box
    end subroutine build_master_lists

    !> The lists of the searched slaves (todo) from the blocks' output, the
    !> others' as they were (none where there were none): in place where a
    !> new list fits its slave's old one, else at the end of the store;
    !> the store compacted in slave order when half of it is dead.
    subroutine merge_lists(s, todo, blk, lists)
        type(surface_t), intent(in) :: s
        logical, intent(in) :: todo(:)
        type(block_out_t), intent(in) :: blk(:)
        type(master_lists_t), intent(inout) :: lists
        integer :: ib, i, k, first, qb, pb, c, pc, nr
        ! (the rows: the slaves' own, or one a slave where no rows are set)
        nr = list_rows(lists, s%nslave)
        ! (another number of slaves: the lists start afresh)
        if (allocated(lists%ptr)) then
            if (size(lists%ptr) /= nr) then
                deallocate (lists%ptr)
                if (allocated(lists%pool_ptr)) deallocate (lists%pool_ptr, lists%pool_last)
                if (allocated(lists%gap)) deallocate (lists%gap)
                if (allocated(lists%xg)) deallocate (lists%xg, lists%og, lists%at)
            end if
        end if
        if (.not. allocated(lists%ptr)) then
            if (allocated(lists%last)) deallocate (lists%last)
            allocate (lists%ptr(nr), lists%last(nr))
            lists%ptr = 1
            lists%last = 0
            lists%nused = 0
            lists%ndead = 0
            if (.not. allocated(lists%node)) allocate (lists%node(0), lists%trackable(0))
        end if
        ! (lists read back from a restart dump come without pools: until its
        ! next search a slave has none, pool_last = pool_ptr - 2, and its
        ! clearance is not taken afresh)
        if (.not. allocated(lists%pool_ptr)) then
            allocate (lists%pool_ptr(nr), lists%pool_last(nr))
            lists%pool_ptr = 1
            lists%pool_last = -1
            lists%pused = 0
            lists%pdead = 0
        end if
        if (.not. allocated(lists%pool_node)) allocate (lists%pool_node(0))
        if (.not. allocated(lists%gap)) then
            allocate (lists%gap(nr))
            lists%gap = -huge(1.0_wp)
        end if
        if (.not. allocated(lists%xg)) then
            allocate (lists%xg(3, nr), lists%og(nr), lists%at(nr))
            lists%xg = 0
            lists%og = 0
            lists%at = 0
        end if
        ! where each searched slave's list and pool go, in slave order (the
        ! store's layout does not depend on the threads), then the copies, a
        ! block a thread
        do ib = 1, size(blk)
            first = (ib - 1)*block_size + 1
            do i = 1, size(blk(ib)%cnt)
                if (.not. todo(first + i - 1)) cycle
                k = list_row(lists, first + i - 1)
                lists%gap(k) = blk(ib)%gap(i)
                call slot(lists%ptr(k), lists%last(k), lists%nused, lists%ndead, blk(ib)%cnt(i))
                call slot(lists%pool_ptr(k), lists%pool_last(k), lists%pused, lists%pdead, blk(ib)%pcnt(i))
            end do
        end do
        call room(lists%node, lists%trackable, lists%nused)
        call room_int(lists%pool_node, lists%pused)
        !$omp parallel do schedule(dynamic) private(first, qb, pb, i, k, c, pc)
        do ib = 1, size(blk)
            first = (ib - 1)*block_size + 1
            qb = 0
            pb = 0
            do i = 1, size(blk(ib)%cnt)
                if (.not. todo(first + i - 1)) cycle
                k = list_row(lists, first + i - 1)
                c = blk(ib)%cnt(i)
                pc = blk(ib)%pcnt(i)
                lists%node(lists%ptr(k):lists%last(k)) = blk(ib)%node(qb + 1:qb + c)
                lists%trackable(lists%ptr(k):lists%last(k)) = blk(ib)%trk(qb + 1:qb + c)
                lists%pool_node(lists%pool_ptr(k):lists%pool_last(k)) = blk(ib)%pool(pb + 1:pb + pc)
                qb = qb + c
                pb = pb + pc
            end do
        end do
        !$omp end parallel do
        if (2*lists%ndead > lists%nused) call compact_lists(lists)
        if (2*lists%pdead > lists%pused) call compact_pools(lists)
    contains
        !> A list of c entries in place of the one in a(p:l) (none where
        !> l < p - 1): there if it fits, else at the end of the store's used
        !> entries (used); dead counts the entries left behind.
        subroutine slot(p, l, used, dead, c)
            integer, intent(inout) :: p, l, used, dead
            integer, intent(in) :: c
            integer :: old
            old = max(0, l - p + 1)
            if (c > old) then
                p = used + 1
                used = used + c
                dead = dead + old
            else
                dead = dead + old - c
            end if
            l = p + c - 1
        end subroutine slot

        !> node and trk with room for n entries (grown by half again).
        subroutine room(node, trk, n)
            integer, allocatable, intent(inout) :: node(:)
            logical, allocatable, intent(inout) :: trk(:)
            integer, intent(in) :: n
            integer, allocatable :: ni(:)
            logical, allocatable :: nt(:)
            if (n <= size(node)) return
            allocate (ni(max(n, size(node) + size(node)/2 + 64)), nt(max(n, size(node) + size(node)/2 + 64)))
            ni(1:size(node)) = node
            nt(1:size(trk)) = trk
            call move_alloc(ni, node)
            call move_alloc(nt, trk)
        end subroutine room

        subroutine room_int(a, n)
            integer, allocatable, intent(inout) :: a(:)
            integer, intent(in) :: n
            integer, allocatable :: ni(:)
            if (n <= size(a)) return
            allocate (ni(max(n, size(a) + size(a)/2 + 64)))
            ni(1:size(a)) = a
            call move_alloc(ni, a)
        end subroutine room_int
    end subroutine merge_lists

    !> The master node lists' store in slave order, nothing dead.
    subroutine compact_lists(lists)
        type(master_lists_t), intent(inout) :: lists
        integer, allocatable :: ni(:)
        logical, allocatable :: nt(:)
        integer :: k, n, c
        n = sum(max(0, lists%last - lists%ptr + 1))
        ! (the store keeps its size: the searches that follow append to it
        ! again, and grown anew it was copied, serially, each time)
        allocate (ni(max(n + n/4 + 64, size(lists%node))), nt(max(n + n/4 + 64, size(lists%node))))
        n = 0
        do k = 1, size(lists%ptr)
            c = lists%last(k) - lists%ptr(k) + 1
            ni(n + 1:n + c) = lists%node(lists%ptr(k):lists%last(k))
            nt(n + 1:n + c) = lists%trackable(lists%ptr(k):lists%last(k))
            lists%ptr(k) = n + 1
            lists%last(k) = n + c
            n = n + c
        end do
        call move_alloc(ni, lists%node)
        call move_alloc(nt, lists%trackable)
        lists%nused = n
        lists%ndead = 0
    end subroutine compact_lists

    !> The pools' store in slave order, nothing dead.
    subroutine compact_pools(lists)
        type(master_lists_t), intent(inout) :: lists
        integer, allocatable :: ni(:)
        integer :: k, n, c
        n = sum(max(0, lists%pool_last - lists%pool_ptr + 1))
        allocate (ni(max(n + n/4 + 64, size(lists%pool_node))))
        n = 0
        do k = 1, size(lists%pool_ptr)
            c = lists%pool_last(k) - lists%pool_ptr(k) + 1
            if (c < 0) then
                ! (no pool: kept so)
                lists%pool_ptr(k) = n + 1
                lists%pool_last(k) = n - 1
                cycle
            end if
            ni(n + 1:n + c) = lists%pool_node(lists%pool_ptr(k):lists%pool_last(k))
            lists%pool_ptr(k) = n + 1
            lists%pool_last(k) = n + c
            n = n + c
        end do
        call move_alloc(ni, lists%pool_node)
        lists%pused = n
        lists%pdead = 0
    end subroutine compact_pools

    !> One slave node: node pool, reduced pool, master node list.
    subroutine one_slave(s, lev, xl, lc, dl, box, cmax, reach, mnl, sn, w, out, iloc, npool, nred)
        type(surface_t), intent(in) :: s
        type(levels_t), intent(in) :: lev
        real(wp), intent(in) :: xl(:, :), lc(:), dl(:), box(:, :), reach
        real(wp), intent(in) :: cmax     !< the largest segment part of a clearance's c (below)
        integer, intent(in) :: mnl, sn, iloc
        type(search_work_t), intent(inout) :: w
        type(block_out_t), intent(inout) :: out
        integer(i8), intent(inout) :: npool, nred
        integer :: want, i, j, m, n0, nkeep, q, sg, k
        logical :: keep
        real(wp) :: ts, g, d2, e(3), c, sep, xs(3)

        ! which sides the slave looks at: single surface A against A; two
        ! surfaces each side against the other; nodes-to-surface against B
        want = wanted_side(s, sn)

        call level_pool(lev, xl(:, sn), dl(sn), w)
        npool = npool + w%npool
        ! closest first (the reduced pool below keeps this order); the pool
        ! is kept so for the local search's clearance, which then meets the
        ! near segments first
        call sort_pool(w%pool(1:w%npool), w%dist(1:w%npool))
        do i = 1, w%npool
            if (w%pool(i) == sn) cycle
            if (out%npool == size(out%pool)) out%pool = [out%pool, out%pool]
            out%npool = out%npool + 1
            out%pool(out%npool) = w%pool(i)
            out%pcnt(iloc) = out%pcnt(iloc) + 1
        end do

        ! the clearance (master_lists_t%gap) over the segments at the pool's nodes
        ts = 0.5_wp*s%node_t(sn)
        xs = xl(:, sn)
        g = huge(1.0_wp)
        do i = 1, w%npool
            m = w%pool(i)
            if (m == sn) cycle
            ! every point of a segment at m lies within L_m of m (the paper's
            ! bound): a node that far cannot lower the clearance
            if (w%dist(i) - lc(m) - (2.0_wp*ts + cmax) >= g) cycle
            do q = s%seg_ptr(m), s%seg_ptr(m + 1) - 1
                sg = s%seg_list(q)
                if (w%seen(sg) == sn) cycle
                w%seen(sg) = sn
                if (iand(s%seg_side(sg), want) == 0) cycle
                if (any(s%seg(:, sg) == sn)) cycle
                ! the distance to the segment is at least that to its box and
                ! its separation along each of its axes
                e = max(box(1:3, sg) - xs, xs - box(4:6, sg), 0.0_wp)
                d2 = sqrt(e(1)**2 + e(2)**2 + e(3)**2)
                c = reach_factor(s, sg)*(ts + s%seg_r(sg))
                if (d2 - c >= g) cycle      ! the box alone keeps it farther
                k = mod(sg, axes_cache)
                if (w%ctag(k) /= sg) then
                    call separating_axes(xl(:, s%seg(:, sg)), w%cax(:, :, k))
                    w%ctag(k) = sg
                end if
                sep = d2
                do j = 1, 6
                    sep = max(sep, w%cax(1, j, k)*xs(1) + w%cax(2, j, k)*xs(2) + w%cax(3, j, k)*xs(3) - w%cax(4, j, k))
                end do
                g = min(g, sep - c)
            end do
            ! no clearance at all: the slave is searched every cycle anyway
            if (g <= 0.0_wp) exit
        end do
        out%gap(iloc) = g

        ! step A: nodes of the segments around the slave's neighbours are
        ! nontrackable (tracking from them could find the slave itself)
        w%excluded(sn) = sn
        do i = s%nn_ptr(sn), s%nn_ptr(sn + 1) - 1
            w%excluded(s%nn_list(i)) = sn
        end do
        do i = s%nn_ptr(sn), s%nn_ptr(sn + 1) - 1
            call mark_around(s%nn_list(i), mark_nontrackable)
        end do

        ! reduced pool: not the slave, no node sharing a segment with it, on a
        ! side the slave looks at (the radius test was the pool's)
        nkeep = 0
        do i = 1, w%npool
            m = w%pool(i)
            keep = w%excluded(m) /= sn .and. iand(s%node_side(m), want) /= 0
            if (keep) then
                nkeep = nkeep + 1
                w%pool(nkeep) = m
                w%dist(nkeep) = w%dist(i)
            end if
        end do
        w%npool = nkeep
        nred = nred + nkeep

        n0 = out%n
        select case (mnl)
        case (mnl_closest1, mnl_closest3)
            do i = 1, min(nkeep, mnl)
                call emit(w%pool(i), mark_of(w%pool(i)) /= mark_nontrackable)
            end do
        case default
            ! step C, in order of increasing distance
            do i = 1, nkeep
                m = w%pool(i)
                select case (mark_of(m))
                case (mark_nontrackable)
                    ! C2/C3: an adjacent region; keep it only within L_m (here
                    ! always true: the pool test used the same radius)
                    if (w%dist(i) > lc(m) + reach + max(dl(sn), dl(m))) cycle
                    call emit(m, .false.)
                    call mark_around(m, mark_nontrackable)
                case (mark_trackable)
                    ! C4: a closer node of this opposite region is stored
                    call mark_around(m, mark_trackable)
                case default
                    ! C5: the closest node of a new opposite region
                    call emit(m, .true.)
                    call mark_around(m, mark_trackable)
                end select
            end do
        end select
        out%cnt(iloc) = out%n - n0
    contains
        integer(int8) function mark_of(nd)
            integer, intent(in) :: nd
            mark_of = mark_none
            if (w%stamp(nd) == sn) mark_of = w%mark(nd)
        end function mark_of

        !> Mark every node of every segment at node nd: nd and the nodes
        !> sharing a segment with it. Nontrackable marks override trackable
        !> ones; trackable marks only fill unmarked nodes (a node next to an
        !> adjacent region stays nontrackable).
        subroutine mark_around(nd, mk)
            integer, intent(in) :: nd
            integer(int8), intent(in) :: mk
            integer :: j
            call set_mark(nd, mk, mk == mark_nontrackable)
            do j = s%nn_ptr(nd), s%nn_ptr(nd + 1) - 1
                call set_mark(s%nn_list(j), mk, mk == mark_nontrackable)
            end do
        end subroutine mark_around

        subroutine set_mark(nd, mk, override)
            integer, intent(in) :: nd
            integer(int8), intent(in) :: mk
            logical, intent(in) :: override
            if (w%stamp(nd) /= sn) then
                w%stamp(nd) = sn
                w%mark(nd) = mk
            else if (override) then
                w%mark(nd) = mk
            end if
        end subroutine set_mark

        subroutine emit(m, trk)
            integer, intent(in) :: m
            logical, intent(in) :: trk
            if (out%n == size(out%node)) then
                out%node = [out%node, out%node]
                out%trk = [out%trk, out%trk]
            end if
            out%n = out%n + 1
            out%node(out%n) = m
            out%trk(out%n) = trk
        end subroutine emit
    end subroutine one_slave

    !> How far beyond the two thicknesses (slave's half and the segment's
    !> reach) its check can find a contact: 1 for a shell; 2 for a solid
    !> face, whose node beside the border is found up to twice its depth away.
    pure real(wp) function reach_factor(s, m)
        type(surface_t), intent(in) :: s
        integer, intent(in) :: m
        reach_factor = merge(1.0_wp, 2.0_wp, s%seg_kind(m) == seg_shell)
    end function reach_factor

    !> Six unit axes of a segment (nodes x(3, 4); a triangle repeats its
    !> third node) with its support along each, max_j a . x_j: the normal
    !> both ways and the outward normal in its plane of each edge. A bilinear
    !> segment lies in the convex hull of its nodes, so a point's distance to
    !> it is at least a . p - support on every axis (zero axes: no bound).
    pure subroutine separating_axes(x, ax)
        real(wp), intent(in) :: x(3, 4)
        real(wp), intent(out) :: ax(4, 6)
        real(wp) :: n(3), e(3), a(3), len, ctr(3), sup, p
        integer :: k, j
        if (x(1, 3) == x(1, 4) .and. x(2, 3) == x(2, 4) .and. x(3, 3) == x(3, 4)) then
            n = cross(x(:, 2) - x(:, 1), x(:, 3) - x(:, 1))
        else
            n = cross(x(:, 3) - x(:, 1), x(:, 4) - x(:, 2))
        end if
        len = sqrt(n(1)**2 + n(2)**2 + n(3)**2)
        ax = 0
        if (len <= 0.0_wp) return
        n = n/len
        ctr = 0.25_wp*(x(:, 1) + x(:, 2) + x(:, 3) + x(:, 4))
        do k = 1, 6
            if (k <= 2) then
                a = n
                if (k == 2) a = -n
            else
                j = k - 2
                e = x(:, mod(j, 4) + 1) - x(:, j)
                a = cross(e, n)
                len = sqrt(a(1)**2 + a(2)**2 + a(3)**2)
                if (len <= 1.0e-12_wp*sqrt(e(1)**2 + e(2)**2 + e(3)**2) .or. len <= 0.0_wp) cycle
                a = a/len
                ! outward: away from the centre
                if (a(1)*(ctr(1) - x(1, j)) + a(2)*(ctr(2) - x(2, j)) + a(3)*(ctr(3) - x(3, j)) > 0.0_wp) a = -a
            end if
            sup = a(1)*x(1, 1) + a(2)*x(2, 1) + a(3)*x(3, 1)
            do j = 2, 4
                p = a(1)*x(1, j) + a(2)*x(2, j) + a(3)*x(3, j)
                sup = max(sup, p)
            end do
            ax(1:3, k) = a
            ax(4, k) = sup
        end do
    end subroutine separating_axes

    !> Sort the pool by distance, ties by node number (a total order, so the
    !> result is deterministic): insertion for short pools, heapsort (O(k log k))
    !> beyond 96 (car6's pools hold 28 nodes on average, many past 32: the
    !> heap's calls cost more there than insertion's moves).
    subroutine sort_pool(p, d)
        integer, intent(inout) :: p(:)
        real(wp), intent(inout) :: d(:)
        integer :: i, j, tp, n
        real(wp) :: td
        n = size(p)
        if (n <= 96) then
            do i = 2, n
                tp = p(i)
                td = d(i)
                j = i - 1
                do while (j >= 1)
                    if (d(j) < td .or. (d(j) == td .and. p(j) < tp)) exit
                    p(j + 1) = p(j)
                    d(j + 1) = d(j)
                    j = j - 1
                end do
                p(j + 1) = tp
                d(j + 1) = td
            end do
            return
        end if
        do i = n/2, 1, -1
            call sift(i, n)
        end do
        do i = n, 2, -1
            tp = p(1)
            p(1) = p(i)
            p(i) = tp
            td = d(1)
            d(1) = d(i)
            d(i) = td
            call sift(1, i - 1)
        end do
    contains
        logical function before(a, b)
            integer, intent(in) :: a, b
            before = d(a) < d(b) .or. (d(a) == d(b) .and. p(a) < p(b))
        end function before

        subroutine sift(first, last)
            integer, intent(in) :: first, last
            integer :: root, child, t
            real(wp) :: u
            root = first
            do while (2*root <= last)
                child = 2*root
                if (child < last) then
                    if (before(child, child + 1)) child = child + 1
                end if
                if (.not. before(root, child)) return
                t = p(root)
                p(root) = p(child)
                p(child) = t
                u = d(root)
                d(root) = d(child)
                d(child) = u
                root = child
            end do
        end subroutine sift
    end subroutine sort_pool

end module xd_contact_global_search
