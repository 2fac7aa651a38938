!> Step 2 of the automatic contact, the global search (section 4 of Whirley
!> & Engelmann 1993): nodal characteristic lengths, three nested 1-D bucket
!> sorts, the node pool from the slave's bucket and its neighbours, the
!> reduced pool, and the master node list by the paper's steps A-C with
!> trackable and nontrackable master nodes. Closest-1 and closest-3 lists
!> are there for the paper's comparison.
!>
!> The reduced pool keeps a node m when |x_s - x_m| <= L_m + t_c + delta:
!> L_m the characteristic length (Fig. 3), t_c the largest shell thickness
!> on the surface (a contact surface lies up to a half-thickness off each
!> segment) and delta the pool margin that lets the list stay valid while
!> nodes move between searches (see xd_contact_contact for the bound).
!>
!> Mixed sizes (a coarse barrier or ground next to a fine crush zone): the
!> master nodes are bucketed in levels by their radius. A level takes the
!> nodes up to 1.5 times the median radius of the nodes not yet placed and
!> gets its own grid of buckets half its largest radius wide; what is left
!> goes to the next level; a level of at most 32 nodes is one bucket
!> (checked node by node). Each level holds at least half of what is left,
!> so there are at most log2(n) of them, and a slave scans 125 buckets of
!> each: the search stays linear whatever the sizes (one large segment no
!> longer widens every bucket). A uniform mesh is one level, as before.
!>
!> Slave nodes are independent: the lists are built in blocks of slaves,
!> each block with its own work arrays, and concatenated in slave order, so
!> the result does not depend on the number of threads.
module xd_contact_global_search
    use, intrinsic :: iso_fortran_env, only: int8
    use xd_kinds, only: wp, i8
    use xd_contact_surface, only: surface_t, segment_diagonals, side_a, side_b, wanted_side, seg_shell
    use xd_model, only: mnl_minimal, mnl_closest1, mnl_closest3
    use xd_core_sorting, only: where_true
    use xd_core_vectors, only: cross
    implicit none
    private
    public :: buckets_t, bucket_sort, bucket_radii, node_pool, levels_t, sort_levels, level_pool, typical_length
    public :: characteristic_lengths, master_lists_t, build_master_lists
    public :: search_work_t, new_search_work, mark_none, mark_trackable, mark_nontrackable, search_counts_t
    public :: separating_axes, reach_factor

    integer(int8), parameter :: mark_none = 0, mark_trackable = 1, mark_nontrackable = 2

    !> Nodes sorted into a grid of buckets at least `w` wide in each direction.
    type :: buckets_t
        integer :: nb(3) = 1
        integer :: reach(3) = 1             !< buckets to scan on each side: ceiling(rmax / w)
        real(wp) :: lo(3) = 0, w(3) = 1
        integer, allocatable :: start(:)    !< (ncell + 1) first position of each cell in item
        integer, allocatable :: item(:)     !< node numbers, cell by cell
        real(wp), allocatable :: xr(:, :)   !< (4, n) x, y, z and squared radius of item(q), for a streaming scan
    end type buckets_t

    !> Bucket grids of the master nodes by size (see the module's notes).
    type :: levels_t
        integer :: n = 0
        type(buckets_t), allocatable :: lv(:)
    end type levels_t

    integer, parameter :: few_nodes = 32     !< a level this small is one bucket
    real(wp), parameter :: level_ratio = 1.5_wp

    !> Master node lists of all slaves (CSR in slave order), closest first.
    type :: master_lists_t
        integer, allocatable :: ptr(:)      !< (nslave + 1)
        integer, allocatable :: node(:)     !< local node numbers
        logical, allocatable :: trackable(:)
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
        !> (CSR in slave order) the slave's node pool less itself: by the
        !> search's bound, the segments at these nodes are the only ones it
        !> can reach before the next search (the local search refreshes its
        !> clearance over them)
        integer, allocatable :: pool_ptr(:), pool_node(:)
        !> the largest segment part of a clearance's reach (see one_slave)
        real(wp) :: cmax = 0
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

contains

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

    !> Nodal characteristic length (section 4): the largest diagonal of the
    !> segments at each node, in the coordinates xl (3, nnode) of the surface.
    subroutine characteristic_lengths(s, xl, lc)
        type(surface_t), intent(in) :: s
        real(wp), intent(in) :: xl(:, :)
        real(wp), intent(out) :: lc(:)
        integer :: m, k
        real(wp) :: dmin, dmax
        lc = 0
        do m = 1, s%nseg
            call segment_diagonals(xl(:, s%seg(:, m)), dmin, dmax)
            do k = 1, 4
                lc(s%seg(k, m)) = max(lc(s%seg(k, m)), dmax)
            end do
        end do
    end subroutine characteristic_lengths

    !> Three nested one-dimensional bucket sorts (Benson & Hallquist 1990):
    !> the nodes with active(i) by x slab, each slab by y column, each column
    !> by z cell. Buckets are about rmax/2 wide and a point's pool is scanned
    !> over `reach` buckets on each side, so every node within rmax of it is
    !> seen (half-width buckets scan 5^3 = 125 small buckets, 58% of the
    !> volume of 27 buckets rmax wide). Their number is kept below about
    !> twice the number of nodes so memory stays linear.
    subroutine bucket_sort(xl, active, rmax, bk, single)
        real(wp), intent(in) :: xl(:, :)
        logical, intent(in) :: active(:)
        real(wp), intent(in) :: rmax
        type(buckets_t), intent(out) :: bk
        logical, intent(in), optional :: single   !< one bucket: every node checked
        integer :: n, nact, i, d, a, b, ncell, cap
        integer, allocatable :: key(:, :), xs(:), ys(:), zs(:)
        real(wp) :: hi(3), ext(3), f
        n = size(active)
        nact = count(active)
        allocate (bk%item(nact))
        bk%item = where_true(active)
        if (nact == 0) then
            allocate (bk%start(2))
            bk%start = 1
            return
        end if
        do d = 1, 3
            bk%lo(d) = minval(xl(d, bk%item))
            hi(d) = maxval(xl(d, bk%item))
        end do
        ext = hi - bk%lo
        do d = 1, 3
            bk%nb(d) = max(1, int(min(ext(d)/max(0.5_wp*rmax, tiny(1.0_wp)), 1.0e6_wp)))
        end do
        if (present(single)) then
            if (single) bk%nb = 1
        end if
        cap = max(8, 2*nact)
        do while (product(real(bk%nb, wp)) > real(cap, wp))
            f = (product(real(bk%nb, wp))/cap)**(1.0_wp/3.0_wp)
            bk%nb = max(1, int(bk%nb/max(f, 1.01_wp)))
        end do
        bk%w = max(ext/bk%nb, 0.5_wp*rmax, tiny(1.0_wp))
        bk%reach = ceiling(rmax/bk%w)
        ncell = product(bk%nb)
        allocate (key(3, n), xs(bk%nb(1) + 1), ys(bk%nb(2) + 1), zs(bk%nb(3) + 1), bk%start(ncell + 1))
        do i = 1, nact
            key(:, bk%item(i)) = cell_of(bk, xl(:, bk%item(i)))
        end do
        bk%start = 0
        call counting_sort(bk%item, key(1, :), bk%nb(1), xs)
        do a = 1, bk%nb(1)
            if (xs(a + 1) == xs(a)) cycle
            call counting_sort(bk%item(xs(a):xs(a + 1) - 1), key(2, :), bk%nb(2), ys)
            ys = ys + xs(a) - 1
            do b = 1, bk%nb(2)
                if (ys(b + 1) == ys(b)) cycle
                call counting_sort(bk%item(ys(b):ys(b + 1) - 1), key(3, :), bk%nb(3), zs)
                zs = zs + ys(b) - 1
                i = 1 + bk%nb(3)*((b - 1) + bk%nb(2)*(a - 1))
                bk%start(i:i + bk%nb(3) - 1) = zs(1:bk%nb(3))
            end do
        end do
        ! empty columns and slabs: a cell starts where the next non-empty one does
        bk%start(ncell + 1) = nact + 1
        do i = ncell, 1, -1
            if (bk%start(i) == 0) bk%start(i) = bk%start(i + 1)
        end do
        allocate (bk%xr(4, nact))
        do i = 1, nact
            bk%xr(1:3, i) = xl(:, bk%item(i))
        end do
        bk%xr(4, :) = 0
    end subroutine bucket_sort

    !> Squared search radius r(m)^2 of each bucketed node, in bucket order.
    subroutine bucket_radii(bk, r)
        type(buckets_t), intent(inout) :: bk
        real(wp), intent(in) :: r(:)
        integer :: q
        do q = 1, size(bk%item)
            bk%xr(4, q) = r(bk%item(q))**2
        end do
    end subroutine bucket_radii

    !> Stable counting sort of `items` by key(items) in 1..nkey; start(k) is
    !> the position of bucket k in items (start(nkey + 1) = size + 1).
    subroutine counting_sort(items, key, nkey, start)
        integer, intent(inout) :: items(:)
        integer, intent(in) :: key(:), nkey
        integer, intent(out) :: start(:)
        integer, allocatable :: tmp(:), pos(:)
        integer :: i, k
        allocate (tmp(size(items)), pos(nkey + 1))
        start = 0
        do i = 1, size(items)
            k = key(items(i))
            start(k + 1) = start(k + 1) + 1
        end do
        start(1) = 1
        do k = 2, nkey + 1
            start(k) = start(k) + start(k - 1)
        end do
        pos = start
        do i = 1, size(items)
            k = key(items(i))
            tmp(pos(k)) = items(i)
            pos(k) = pos(k) + 1
        end do
        items = tmp
    end subroutine counting_sort

    pure function cell_of(bk, p) result(c)
        type(buckets_t), intent(in) :: bk
        real(wp), intent(in) :: p(3)
        integer :: c(3)
        c = min(bk%nb, max(1, 1 + int((p - bk%lo)/bk%w)))
    end function cell_of

    !> Node pool of a point p: the nodes of its bucket and the neighbouring
    !> ones that lie within their own radius of p (bucket_radii sets them;
    !> they must not exceed reach times the bucket width).
    subroutine node_pool(bk, p, w)
        type(buckets_t), intent(in) :: bk
        real(wp), intent(in) :: p(3)
        type(search_work_t), intent(inout) :: w
        w%npool = 0
        call scan_buckets(bk, p, w)
        w%dist(1:w%npool) = sqrt(w%dist(1:w%npool))
    end subroutine node_pool

    !> Node pool of a point p over every level of bucket grids.
    subroutine level_pool(lev, p, w)
        type(levels_t), intent(in) :: lev
        real(wp), intent(in) :: p(3)
        type(search_work_t), intent(inout) :: w
        integer :: k
        w%npool = 0
        do k = 1, lev%n
            call scan_buckets(lev%lv(k), p, w)
        end do
        w%dist(1:w%npool) = sqrt(w%dist(1:w%npool))
    end subroutine level_pool

    !> Append to the pool the nodes of bk within their radius of p (squared
    !> distances). The cells along z of a column are contiguous, so each
    !> column is one streaming scan.
    subroutine scan_buckets(bk, p, w)
        type(buckets_t), intent(in) :: bk
        real(wp), intent(in) :: p(3)
        type(search_work_t), intent(inout) :: w
        integer :: c(3), i, j, cell, q, q0, q1, n
        real(wp) :: d2
        c = cell_of(bk, p)
        do i = max(1, c(1) - bk%reach(1)), min(bk%nb(1), c(1) + bk%reach(1))
            do j = max(1, c(2) - bk%reach(2)), min(bk%nb(2), c(2) + bk%reach(2))
                cell = bk%nb(3)*((j - 1) + bk%nb(2)*(i - 1))
                q0 = bk%start(cell + max(1, c(3) - bk%reach(3)))
                q1 = bk%start(cell + min(bk%nb(3), c(3) + bk%reach(3)) + 1) - 1
                if (w%npool + q1 - q0 + 1 > size(w%pool)) call grow_pool(w, w%npool + q1 - q0 + 1)
                ! branch-free compaction: write every candidate, keep those inside
                n = w%npool
                do q = q0, q1
                    d2 = (bk%xr(1, q) - p(1))**2 + (bk%xr(2, q) - p(2))**2 + (bk%xr(3, q) - p(3))**2
                    w%pool(n + 1) = bk%item(q)
                    w%dist(n + 1) = d2
                    n = n + merge(1, 0, d2 <= bk%xr(4, q))
                end do
                w%npool = n
            end do
        end do
    end subroutine scan_buckets

    !> The levels of bucket grids of the nodes with active(i), radius r(i).
    subroutine sort_levels(xl, active, r, lev)
        real(wp), intent(in) :: xl(:, :), r(:)
        logical, intent(in) :: active(:)
        type(levels_t), intent(inout) :: lev
        logical, allocatable :: left(:), sel(:)
        type(buckets_t), allocatable :: tmp(:)
        integer :: nleft
        real(wp) :: cut
        if (allocated(lev%lv)) deallocate (lev%lv)
        allocate (lev%lv(4))
        lev%n = 0
        left = active
        allocate (sel(size(active)))
        do
            nleft = count(left)
            if (nleft == 0) exit
            if (lev%n == size(lev%lv)) then
                allocate (tmp(2*lev%n))
                tmp(1:lev%n) = lev%lv
                call move_alloc(tmp, lev%lv)
            end if
            lev%n = lev%n + 1
            if (nleft <= few_nodes) then
                sel = left
                call bucket_sort(xl, sel, maxval(r, mask=sel), lev%lv(lev%n), single=.true.)
            else
                cut = level_ratio*typical_length(pack(r, left), 0.5_wp)
                sel = left .and. r <= cut
                call bucket_sort(xl, sel, maxval(r, mask=sel), lev%lv(lev%n))
            end if
            call bucket_radii(lev%lv(lev%n), r)
            left = left .and. .not. sel
        end do
    end subroutine sort_levels

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

    !> Master node lists of every slave node (section 4). xl: surface
    !> coordinates; lc: characteristic lengths; reach: the contact reach t_c;
    !> margin: the pool margin delta; mnl: the list policy.
    subroutine build_master_lists(s, xl, lc, reach, margin, mnl, lists, counts, owned)
        type(surface_t), intent(in) :: s
        real(wp), intent(in) :: xl(:, :), lc(:), reach, margin
        integer, intent(in) :: mnl
        type(master_lists_t), intent(inout) :: lists
        type(search_counts_t), intent(out) :: counts
        logical, intent(in), optional :: owned(:)   !< the slaves to search for (others get empty lists)
        type(levels_t) :: lev
        type(search_work_t) :: w
        type(block_out_t), allocatable :: blk(:)
        real(wp), allocatable :: r(:), box(:, :), axes(:, :, :)
        real(wp) :: cmax
        logical, allocatable :: master(:)
        integer :: nblk, ib, i, first, last, pos
        integer(i8) :: npool, nred

        allocate (r(s%nnode), master(s%nnode))
        master = iand(s%node_side, ior(side_a, side_b)) /= 0
        r = lc + reach + margin
        call sort_levels(xl, master, r, lev)
        ! every segment's bounding box and separating axes (for the slaves'
        ! clearances)
        allocate (box(6, s%nseg), axes(4, 6, s%nseg))
        do i = 1, s%nseg
            box(1:3, i) = min(xl(:, s%seg(1, i)), xl(:, s%seg(2, i)), xl(:, s%seg(3, i)), xl(:, s%seg(4, i)))
            box(4:6, i) = max(xl(:, s%seg(1, i)), xl(:, s%seg(2, i)), xl(:, s%seg(3, i)), xl(:, s%seg(4, i)))
            call separating_axes(xl(:, s%seg(:, i)), axes(:, :, i))
        end do
        cmax = 0
        do i = 1, s%nseg
            cmax = max(cmax, reach_factor(s, i)*s%seg_r(i))
        end do
        nblk = (s%nslave + block_size - 1)/block_size
        allocate (blk(nblk))
        npool = 0
        nred = 0
        !$omp parallel private(w, i, first, last) reduction(+:npool, nred)
        call new_search_work(s%nnode, w, s%nseg)
        !$omp do schedule(dynamic)
        do ib = 1, nblk
            first = (ib - 1)*block_size + 1
            last = min(s%nslave, ib*block_size)
            allocate (blk(ib)%cnt(last - first + 1), blk(ib)%node(8*(last - first + 1)), &
                      blk(ib)%trk(8*(last - first + 1)), blk(ib)%gap(last - first + 1), &
                      blk(ib)%pcnt(last - first + 1), blk(ib)%pool(32*(last - first + 1)))
            blk(ib)%gap = -huge(1.0_wp)
            blk(ib)%pcnt = 0
            do i = first, last
                if (present(owned)) then
                    if (.not. owned(i)) then
                        blk(ib)%cnt(i - first + 1) = 0
                        cycle
                    end if
                end if
                call one_slave(s, lev, xl, lc, box, axes, cmax, reach + margin, mnl, s%slave(i), w, blk(ib), i - first + 1, &
                               npool, nred)
            end do
        end do
        !$omp end do
        !$omp end parallel

        if (allocated(lists%ptr)) deallocate (lists%ptr, lists%node, lists%trackable)
        if (allocated(lists%gap)) deallocate (lists%gap)
        if (allocated(lists%pool_ptr)) deallocate (lists%pool_ptr, lists%pool_node)
        allocate (lists%ptr(s%nslave + 1), lists%gap(s%nslave), lists%pool_ptr(s%nslave + 1))
        lists%ptr(1) = 1
        lists%pool_ptr(1) = 1
        do ib = 1, nblk
            first = (ib - 1)*block_size + 1
            do i = 1, size(blk(ib)%cnt)
                lists%ptr(first + i) = lists%ptr(first + i - 1) + blk(ib)%cnt(i)
                lists%pool_ptr(first + i) = lists%pool_ptr(first + i - 1) + blk(ib)%pcnt(i)
                lists%gap(first + i - 1) = blk(ib)%gap(i)
            end do
        end do
        allocate (lists%pool_node(lists%pool_ptr(s%nslave + 1) - 1))
        do ib = 1, nblk
            pos = lists%pool_ptr((ib - 1)*block_size + 1)
            lists%pool_node(pos:pos + blk(ib)%npool - 1) = blk(ib)%pool(1:blk(ib)%npool)
        end do
        lists%cmax = cmax
        allocate (lists%node(lists%ptr(s%nslave + 1) - 1), lists%trackable(lists%ptr(s%nslave + 1) - 1))
        do ib = 1, nblk
            pos = lists%ptr((ib - 1)*block_size + 1)
            lists%node(pos:pos + blk(ib)%n - 1) = blk(ib)%node(1:blk(ib)%n)
            lists%trackable(pos:pos + blk(ib)%n - 1) = blk(ib)%trk(1:blk(ib)%n)
        end do
        counts%pool = npool
        counts%reduced = nred
        counts%masters = size(lists%node)
    end subroutine build_master_lists

    !> One slave node: node pool, reduced pool, master node list.
    subroutine one_slave(s, lev, xl, lc, box, axes, cmax, extra, mnl, sn, w, out, iloc, npool, nred)
        type(surface_t), intent(in) :: s
        type(levels_t), intent(in) :: lev
        real(wp), intent(in) :: xl(:, :), lc(:), box(:, :), axes(:, :, :), extra
        real(wp), intent(in) :: cmax     !< the largest segment part of a clearance's c (below)
        integer, intent(in) :: mnl, sn, iloc
        type(search_work_t), intent(inout) :: w
        type(block_out_t), intent(inout) :: out
        integer(i8), intent(inout) :: npool, nred
        integer :: want, i, m, n0, nkeep, q, sg, k
        logical :: keep
        real(wp) :: ts, g, d2, e(3), c, sep, xs(3)

        ! which sides the slave looks at: single surface A against A; two
        ! surfaces each side against the other; nodes-to-surface against B
        want = wanted_side(s, sn)

        call level_pool(lev, xl(:, sn), w)
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
                sep = d2
                do k = 1, 6
                    sep = max(sep, axes(1, k, sg)*xs(1) + axes(2, k, sg)*xs(2) + axes(3, k, sg)*xs(3) - axes(4, k, sg))
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
                    if (w%dist(i) > lc(m) + extra) cycle
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
    !> beyond 32.
    subroutine sort_pool(p, d)
        integer, intent(inout) :: p(:)
        real(wp), intent(inout) :: d(:)
        integer :: i, j, tp, n
        real(wp) :: td
        n = size(p)
        if (n <= 32) then
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
