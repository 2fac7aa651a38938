!> Sorting and id look-up: user ids (any integers) to dense indices.
module xd_core_sorting
    use xd_kinds, only: dp
    implicit none
    private
    public :: sort_index, id_map_t, where_true, small_sort

    !> Stable merge sort of integer or real(dp) keys: perm such that
    !> keys(perm) is ascending, equal keys in their original order.
    interface sort_index
        module procedure sort_index_int, sort_index_dp
    end interface sort_index

    !> Maps user ids to indices 1..n. Dense ids use a direct table, sparse ones
    !> a sorted list and binary search.
    type :: id_map_t
        integer :: n = 0
        integer :: min_id = 0, max_id = -1
        logical :: direct = .false.
        integer, allocatable :: table(:)      !< direct: index of id (min_id-1+k), 0 if none
        integer, allocatable :: sorted_id(:)  !< sparse: ids ascending
        integer, allocatable :: sorted_ix(:)  !< sparse: their indices
    contains
        procedure :: build => id_map_build
        procedure :: find => id_map_find
    end type id_map_t

    !> In-place insertion sort, ascending: for the short lists of a node's
    !> neighbours or a handful of timings (quadratic: not for long arrays).
    interface small_sort
        module procedure small_sort_int, small_sort_dp
    end interface small_sort

contains

    pure subroutine small_sort_int(a)
        integer, intent(inout) :: a(:)
        integer :: i, j, t
        do i = 2, size(a)
            t = a(i)
            j = i - 1
            do while (j >= 1)
                if (a(j) <= t) exit
                a(j + 1) = a(j)
                j = j - 1
            end do
            a(j + 1) = t
        end do
    end subroutine small_sort_int

    pure subroutine small_sort_dp(a)
        real(dp), intent(inout) :: a(:)
        integer :: i, j
        real(dp) :: t
        do i = 2, size(a)
            t = a(i)
            j = i - 1
            do while (j >= 1)
                if (a(j) <= t) exit
                a(j + 1) = a(j)
                j = j - 1
            end do
            a(j + 1) = t
        end do
    end subroutine small_sort_dp

    !> Indices i where mask(i) is true, ascending. (A loop, not pack of an
    !> implied do: no stack temporary of the mask's size on large models.)
    function where_true(mask) result(ix)
        logical, intent(in) :: mask(:)
        integer, allocatable :: ix(:)
        integer :: i, n
        allocate (ix(count(mask)))
        n = 0
        do i = 1, size(mask)
            if (mask(i)) then
                n = n + 1
                ix(n) = i
            end if
        end do
    end function where_true

    !> Integer keys (up to 2^53 in size: exact as doubles).
    subroutine sort_index_int(keys, perm)
        integer, intent(in) :: keys(:)
        integer, allocatable, intent(out) :: perm(:)
        real(dp), allocatable :: k(:)
        k = real(keys, dp)
        call sort_index_dp(k, perm)
    end subroutine sort_index_int

    subroutine sort_index_dp(keys, perm)
        real(dp), intent(in) :: keys(:)
        integer, allocatable, intent(out) :: perm(:)
        integer, allocatable :: tmp(:)
        integer :: n, i, j, t, width, lo, mid, hi
        integer, parameter :: run = 16
        n = size(keys)
        allocate (perm(n), tmp(n))
        do i = 1, n
            perm(i) = i
        end do
        ! runs of `run` by a stable insertion (an element moves past those
        ! strictly greater alone), then merged in pairs; two runs already in
        ! order (the first's last no greater than the second's first: a mesh
        ! numbered along its axis) are left as they are. The result is the
        ! one stable order either way.
        do lo = 1, n, run
            hi = min(lo + run - 1, n)
            do i = lo + 1, hi
                t = perm(i)
                j = i - 1
                do while (j >= lo)
                    if (.not. keys(t) < keys(perm(j))) exit
                    perm(j + 1) = perm(j)
                    j = j - 1
                end do
                perm(j + 1) = t
            end do
        end do
        width = run
        do while (width < n)
            lo = 1
            do while (lo <= n)
                mid = min(lo + width - 1, n)
                hi = min(lo + 2*width - 1, n)
                if (mid < hi) then
                    if (keys(perm(mid + 1)) < keys(perm(mid))) call merge_runs(lo, mid, hi)
                end if
                lo = lo + 2*width
            end do
            width = 2*width
        end do
    contains
        subroutine merge_runs(l, m, h)
            integer, intent(in) :: l, m, h
            integer :: a, b, k
            a = l; b = m + 1; k = l
            do while (a <= m .and. b <= h)
                if (keys(perm(b)) < keys(perm(a))) then
                    tmp(k) = perm(b); b = b + 1
                else
                    tmp(k) = perm(a); a = a + 1
                end if
                k = k + 1
            end do
            do while (a <= m)
                tmp(k) = perm(a); a = a + 1; k = k + 1
            end do
            do while (b <= h)
                tmp(k) = perm(b); b = b + 1; k = k + 1
            end do
            perm(l:h) = tmp(l:h)
        end subroutine merge_runs
    end subroutine sort_index_dp

    !> Build the map from ids(1:n). `dup` returns the first id seen twice (0 if none).
    subroutine id_map_build(self, ids, dup)
        class(id_map_t), intent(inout) :: self
        integer, intent(in) :: ids(:)
        integer, intent(out) :: dup
        integer, allocatable :: perm(:)
        integer :: i, n
        dup = 0
        n = size(ids)
        self%n = n
        if (allocated(self%table)) deallocate (self%table)
        if (allocated(self%sorted_id)) deallocate (self%sorted_id)
        if (allocated(self%sorted_ix)) deallocate (self%sorted_ix)
        if (n == 0) return
        self%min_id = minval(ids)
        self%max_id = maxval(ids)
        self%direct = (int(self%max_id, 8) - self%min_id + 1) <= 4_8*n + 1024
        if (self%direct) then
            allocate (self%table(self%min_id:self%max_id))
            self%table = 0
            do i = 1, n
                if (self%table(ids(i)) /= 0 .and. dup == 0) dup = ids(i)
                self%table(ids(i)) = i
            end do
        else
            call sort_index(ids, perm)
            self%sorted_id = ids(perm)
            self%sorted_ix = perm
            do i = 2, n
                if (self%sorted_id(i) == self%sorted_id(i - 1)) then
                    dup = self%sorted_id(i)
                    exit
                end if
            end do
        end if
    end subroutine id_map_build

    !> Index of `id`, 0 if it is not in the map.
    pure integer function id_map_find(self, id) result(ix)
        class(id_map_t), intent(in) :: self
        integer, intent(in) :: id
        integer :: lo, hi, mid
        ix = 0
        if (self%n == 0) return
        if (id < self%min_id .or. id > self%max_id) return
        if (self%direct) then
            ix = self%table(id)
            return
        end if
        lo = 1; hi = self%n
        do while (lo <= hi)
            mid = (lo + hi)/2
            if (self%sorted_id(mid) == id) then
                ix = self%sorted_ix(mid)
                return
            else if (self%sorted_id(mid) < id) then
                lo = mid + 1
            else
                hi = mid - 1
            end if
        end do
    end function id_map_find

end module xd_core_sorting
