!> Recursive coordinate bisection: the domain decomposition of the MPI runs
!> (issue 8). Elements, given as centroids with a cost each (the time an
!> element-cycle takes: a shell with five points costs about twice a
!> one-point hexahedron), are split into parts of nearly equal cost whose
!> boundaries are planes across the longest side of each box, so a part is
!> compact and its halo small.
module xd_core_partition
    use xd_kinds, only: wp, dp
    implicit none
    private
    public :: rcb_partition, rcb_partition_by, centre_of, weighted_cut

    abstract interface
        !> c: the centre of item i (exactly as the caller would store it)
        subroutine centre_of(i, c)
            import :: wp
            integer, intent(in) :: i
            real(wp), intent(out) :: c(3)
        end subroutine centre_of
    end interface

contains

    !> part(e) in 1..nparts for the centroids xc(3, n) with costs w(n) > 0.
    !> A set going to np parts is cut across the longest side of its box
    !> where the cost below the cut comes nearest to np/2 of np shares; each
    !> side is cut again. The items are ordered by the coordinate and, where
    !> it is equal, by their number (weighted_cut), so the partition
    !> depends on the model alone (and not on the ranks or threads that
    !> compute it).
    !> With `only`: that part's items alone (rcb_partition_by).
    subroutine rcb_partition(xc, w, nparts, part, only)
        real(wp), intent(in) :: xc(:, :), w(:)
        integer, intent(in) :: nparts
        integer, intent(out) :: part(:)
        integer, intent(in), optional :: only
        call rcb_partition_by(stored, w, nparts, part, only)
    contains
        subroutine stored(i, c)
            integer, intent(in) :: i
            real(wp), intent(out) :: c(3)
            c = xc(:, i)
        end subroutine stored
    end subroutine rcb_partition

    !> rcb_partition with each item's centre computed when the cut reads it
    !> (centre), not held for every item: the domain's set-up, whose peak
    !> held 24 bytes a work item of centres beside the whole model's state
    !> (issue 32). The same partition as rcb_partition's of the centres.
    !> With `only`: the cuts that lead to part `only` alone are made (the
    !> other side of each cut is not cut further), and only that part's
    !> items are given it, every other item 0: the part each of nparts
    !> callers needs is its own, at about half the sorting (n log n at
    !> the first cut, half that at the next, ...), and the callers' parts
    !> summed are the whole partition, the same as without `only`.
    subroutine rcb_partition_by(centre, w, nparts, part, only)
        procedure(centre_of) :: centre
        real(wp), intent(in) :: w(:)
        integer, intent(in) :: nparts
        integer, intent(out) :: part(:)
        integer, intent(in), optional :: only
        integer, allocatable :: all(:)
        integer :: e
        part = 1
        if (nparts <= 1 .or. size(w) == 0) return
        if (present(only)) part = 0
        ! (on the heap, as every set below: a model's worth of temporaries on
        ! the stack overflowed it at 1e6 shells)
        allocate (all(size(w)))
        do e = 1, size(w)
            all(e) = e
        end do
        call bisect(all, 1, nparts)
    contains
        recursive subroutine bisect(set, first, np)
            integer, intent(in) :: set(:), first, np
            integer, allocatable :: subl(:), subr(:)
            real(dp), allocatable :: key(:), cost(:)
            logical, allocatable :: left(:)
            real(dp) :: total, target
            real(wp) :: lo(3), hi(3), c(3)
            integer :: nl, k, ax, n, i, j
            n = size(set)
            if (np == 1 .or. n <= 1) then
                if (present(only)) then
                    ! (a set too small to cut goes whole to its first part)
                    if (only /= first) return
                end if
                part(set) = first
                return
            end if
            nl = np/2
            lo = huge(1.0_wp)
            hi = -huge(1.0_wp)
            total = 0
            do i = 1, n
                call centre(set(i), c)
                lo = min(lo, c)
                hi = max(hi, c)
                total = total + real(w(set(i)), dp)
            end do
            ax = maxloc(hi - lo, 1)
            allocate (key(n), cost(n), left(n))
            do i = 1, n
                call centre(set(i), c)
                key(i) = real(c(ax), dp)
                cost(i) = real(w(set(i)), dp)
            end do
            target = total*nl/np
            call weighted_cut(key, set, cost, target, left)
            deallocate (key, cost)
            ! (the two sides, in set's order)
            k = count(left)
            allocate (subl(k), subr(n - k))
            k = 0
            j = 0
            do i = 1, n
                if (left(i)) then
                    k = k + 1
                    subl(k) = set(i)
                else
                    j = j + 1
                    subr(j) = set(i)
                end if
            end do
            deallocate (left)
            ! (with `only`, the side whose parts hold it alone)
            if (want(first, nl)) call bisect(subl, first, nl)
            deallocate (subl)
            if (want(first + nl, np - nl)) call bisect(subr, first + nl, np - nl)
        end subroutine bisect

        !> Parts first .. first + np - 1 are cut further: every one, or
        !> with `only` those that hold it.
        logical function want(first, np)
            integer, intent(in) :: first, np
            want = .true.
            if (present(only)) want = only >= first .and. only < first + np
        end function want
    end subroutine rcb_partition_by

    !> The cut of n >= 2 items ordered by key and, where keys are equal, by
    !> id (distinct): left(i) for the first k of that order, k the first
    !> count whose summed cost reaches target, or one fewer where that sum
    !> is nearer target; at least one item on each side. Found by
    !> selection, not by sorting (expected time linear in n: the
    !> decomposition's every cut had sorted its items, 1.5e8 instructions
    !> on each rank of 16 for the 120,000-shell tubes' elements and slaves);
    !> the sums are taken in the selection's order, a deterministic one, so
    !> every rank finds the same cut.
    subroutine weighted_cut(key, id, cost, target, left)
        real(dp), intent(in) :: key(:), cost(:), target
        integer, intent(in) :: id(:)
        logical, intent(out) :: left(:)
        integer, allocatable :: p(:)
        integer :: n, lo, hi, i, j, t, piv, e, k1
        real(dp) :: wb, wl, clt, cle
        n = size(key)
        allocate (p(n))
        do i = 1, n
            p(i) = i
        end do
        ! p(1:lo-1) precede p(lo:hi) in the order, their cost summed in wb
        ! (below target), and the item sought is in p(lo:hi)
        lo = 1
        hi = n
        wb = 0
        do
            if (lo == hi) then
                e = p(lo)
                k1 = lo
                clt = wb
                exit
            end if
            ! (the pivot: the median of the range's first, middle and last
            ! items, moved to its end)
            call pivot_last(lo, (lo + hi)/2, hi)
            piv = p(hi)
            j = lo
            wl = 0
            do i = lo, hi - 1
                if (.not. before(p(i), piv)) cycle
                t = p(i)
                p(i) = p(j)
                p(j) = t
                wl = wl + cost(t)
                j = j + 1
            end do
            p(hi) = p(j)
            p(j) = piv
            ! p(lo:j-1) precede the pivot, now at j; p(j+1:hi) follow it
            if (wb + wl >= target .and. j > lo) then
                hi = j - 1
            else if (wb + wl + cost(piv) >= target .or. j == hi) then
                e = piv
                k1 = j
                clt = wb + wl
                exit
            else
                wb = wb + wl + cost(piv)
                lo = j + 1
            end if
        end do
        cle = clt + cost(e)
        if (k1 == n) then
            ! (every item but the last at most on the left: the cut after
            ! n - 1, the last of the others)
            e = p(1)
            do i = 2, n - 1
                if (before(e, p(i))) e = p(i)
            end do
            k1 = n - 1
            cle = clt
            clt = cle - cost(e)
        end if
        ! the first k1 items (through e), or k1 - 1 where that is nearer
        do i = 1, n
            left(i) = before(i, e)
        end do
        left(e) = .not. (k1 > 1 .and. target - clt < cle - target)
    contains
        logical function before(a, b)
            integer, intent(in) :: a, b
            before = key(a) < key(b) .or. (key(a) == key(b) .and. id(a) < id(b))
        end function before
        !> The median of p(a), p(b), p(c) to p(c).
        subroutine pivot_last(a, b, c)
            integer, intent(in) :: a, b, c
            integer :: m
            m = b
            if (before(p(a), p(b)) .neqv. before(p(a), p(c))) then
                m = a
            else if (before(p(b), p(a)) .neqv. before(p(b), p(c))) then
                m = b
            else
                m = c
            end if
            t = p(m)
            p(m) = p(c)
            p(c) = t
        end subroutine pivot_last
    end subroutine weighted_cut

end module xd_core_partition
