!> Recursive coordinate bisection: the domain decomposition of the MPI runs
!> (issue 8). Elements, given as centroids with a cost each (the time an
!> element-cycle takes: a shell with five points costs about twice a
!> one-point hexahedron), are split into parts of nearly equal cost whose
!> boundaries are planes across the longest side of each box, so a part is
!> compact and its halo small.
module xd_core_partition
    use xd_kinds, only: wp, dp
    use xd_core_sorting, only: sort_index
    implicit none
    private
    public :: rcb_partition, rcb_partition_by, centre_of

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
    !> side is cut again. Equal coordinates keep the order of the elements,
    !> so the partition depends on the model alone (and not on the ranks or
    !> threads that compute it).
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
            integer, allocatable :: perm(:), sub(:)
            real(dp), allocatable :: key(:)
            real(dp) :: total, target, cum
            real(wp) :: lo(3), hi(3), c(3)
            integer :: nl, k, ax, n, i
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
            allocate (key(n))
            do i = 1, n
                call centre(set(i), c)
                key(i) = real(c(ax), dp)
            end do
            call sort_index(key, perm)
            deallocate (key)
            target = total*nl/np
            ! the cut after k elements: the first k whose cumulative cost
            ! reaches the target, or the one before if that is nearer
            cum = 0
            do k = 1, n - 1
                cum = cum + w(set(perm(k)))
                if (cum >= target) exit
            end do
            k = min(k, n - 1)
            if (k > 1) then
                if (target - (cum - w(set(perm(k)))) < cum - target) k = k - 1
            end if
            ! (with `only`, the side whose parts hold it alone)
            if (want(first, nl)) then
                allocate (sub(k))
                sub = set(perm(1:k))
                call bisect(sub, first, nl)
                deallocate (sub)
            end if
            if (want(first + nl, np - nl)) then
                allocate (sub(n - k))
                sub = set(perm(k + 1:n))
                call bisect(sub, first + nl, np - nl)
            end if
        end subroutine bisect

        !> Parts first .. first + np - 1 are cut further: every one, or
        !> with `only` those that hold it.
        logical function want(first, np)
            integer, intent(in) :: first, np
            want = .true.
            if (present(only)) want = only >= first .and. only < first + np
        end function want
    end subroutine rcb_partition_by

end module xd_core_partition
