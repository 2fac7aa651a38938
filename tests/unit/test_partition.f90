!> Recursive coordinate bisection: cost balance, compact parts, determinism.
program test_partition
    use xd_kinds, only: wp
    use xd_testing, only: check, test_summary
    use xd_kinds, only: dp
    use xd_core_partition, only: rcb_partition, weighted_cut
    implicit none
    integer, parameter :: nx = 20, ny = 10, nz = 5, n = nx*ny*nz
    real(wp) :: xc(3, n), w(n), cost(8), vol
    integer :: part(n), again(n), one(n), i, j, k, e, np, p
    real(wp) :: lo(3), hi(3)
    logical :: balanced, compact, weighted, alone, same_cut
    character(len=120) :: msg

    e = 0
    do k = 1, nz
        do j = 1, ny
            do i = 1, nx
                e = e + 1
                xc(:, e) = [i - 0.5_wp, j - 0.5_wp, k - 0.5_wp]
            end do
        end do
    end do
    ! unit costs: every part within 3% of the mean (three levels of cuts,
    ! each off by at most half an element of 125)
    w = 1
    balanced = .true.
    compact = .true.
    do np = 1, 8
        call rcb_partition(xc, w, np, part)
        cost = 0
        do e = 1, n
            cost(part(e)) = cost(part(e)) + w(e)
        end do
        balanced = balanced .and. all(part >= 1 .and. part <= np) .and. &
                   maxval(cost(1:np)) <= 1.03_wp*n/np .and. minval(cost(1:np)) >= 0.97_wp*n/np
        ! compact: each part fills at least half of its bounding box
        do p = 1, np
            lo = minval(xc(:, pack([(e, e=1, n)], part == p)), 2) - 0.5_wp
            hi = maxval(xc(:, pack([(e, e=1, n)], part == p)), 2) + 0.5_wp
            vol = product(hi - lo)
            compact = compact .and. count(part == p) >= 0.5_wp*vol
        end do
    end do
    call check(balanced, 'unit costs, 1 to 8 parts: every part within 3% of the mean')
    call check(compact, 'every part fills at least half of its bounding box')
    ! costs 3 on the half x < 10 (shells next to solids, say): balance by cost
    where (xc(1, :) < 10.0_wp)
        w = 3
    elsewhere
        w = 1
    end where
    call rcb_partition(xc, w, 6, part)
    cost = 0
    do e = 1, n
        cost(part(e)) = cost(part(e)) + w(e)
    end do
    weighted = maxval(cost(1:6)) <= 1.03_wp*sum(w)/6 .and. minval(cost(1:6)) >= 0.97_wp*sum(w)/6
    write (msg, '(a,2f8.1,a,f8.1)') 'weighted costs, 6 parts: within 3% of the mean (', minval(cost(1:6)), &
        maxval(cost(1:6)), ' against', sum(w)/6
    call check(weighted, trim(msg))
    ! cost 3 against 1: the parts in the costly half hold a third as many
    ! elements (111 against 333)
    write (msg, '(a,2i5,a)') 'by cost, not by count: the parts hold ', minval([(count(part == p), p=1, 6)]), &
        maxval([(count(part == p), p=1, 6)]), ' elements (expected about 111 and 333)'
    call check(maxval([(count(part == p), p=1, 6)]) >= 2.8*minval([(count(part == p), p=1, 6)]), trim(msg))
    call rcb_partition(xc, w, 6, again)
    call check(all(again == part), 'the same model gives the same partition')
    ! each rank's cuts alone (`only`): its own part's items and no other's,
    ! and the ranks' parts summed (as build_domain sums them over the ranks)
    ! are the whole partition, for 1 to 8 parts and both cost fields, ties
    ! in the coordinates included (the grid's equal centres)
    alone = .true.
    do k = 1, 2
        ! (the weighted costs, then unit ones)
        if (k == 2) w = 1
        do np = 1, 8
            call rcb_partition(xc, w, np, part)
            again = 0
            do p = 1, np
                call rcb_partition(xc, w, np, one, only=p)
                alone = alone .and. all(pack(one, one /= 0) == p) .and. count(one == p) == count(part == p)
                again = again + one
            end do
            alone = alone .and. all(again == part)
        end do
    end do
    ! (and 3 items for 8 parts: sets too small to cut go whole to their
    ! first part, on that part's caller alone)
    call rcb_partition(xc(:, 1:3), w(1:3), 8, part(1:3))
    again(1:3) = 0
    do p = 1, 8
        call rcb_partition(xc(:, 1:3), w(1:3), 8, one(1:3), only=p)
        alone = alone .and. all(pack(one(1:3), one(1:3) /= 0) == p)
        again(1:3) = again(1:3) + one(1:3)
    end do
    alone = alone .and. all(again(1:3) == part(1:3))
    call check(alone, 'each part''s cuts alone (only): its items alone, and the parts summed are the whole '// &
               'partition, 1 to 8 parts, weighted and unit costs, and 3 items in 8 parts')
    ! the cut by selection (weighted_cut) against the definition taken by a
    ! plain stable sort: 2 to 60 items, keys from 4 values (many equal, the
    ! ids breaking the ties) or all different, whole-number costs 1 to 5 (so
    ! every sum is exact in either order) and targets across the total:
    ! the same side for every item. A cut one item off, or ties broken
    ! another way, fails it.
    same_cut = .true.
    call random_seed(size=k)
    call random_seed(put=[(7919*i, i=1, k)])
    do k = 1, 400
        call one_cut(2 + mod(k*37, 59), mod(k, 2) == 0, mod(k, 7)/7.0_dp + 0.03_dp)
    end do
    call check(same_cut, 'the cut by selection puts every item on the side the sorted order puts it '// &
               '(400 sets of 2 to 60 items, equal keys and costs 1 to 5)')
    call test_summary()
contains
    subroutine one_cut(m, ties, frac)
        integer, intent(in) :: m
        logical, intent(in) :: ties
        real(dp), intent(in) :: frac
        real(dp) :: key(m), cost(m), r(m), target, cum
        integer :: id(m), ord(m), a, b, t, kk
        logical :: left(m), want(m)
        call random_number(r)
        key = r
        if (ties) key = real(int(4*r), dp)
        call random_number(r)
        cost = real(1 + int(5*r), dp)
        ! (ids: a permutation, not the positions)
        do a = 1, m
            id(a) = 1000 - 3*a
        end do
        target = frac*sum(cost)
        call weighted_cut(key, id, cost, target, left)
        ! the definition: a stable insertion sort by (key, id), the first
        ! count whose sum reaches target (at most m - 1), one fewer where nearer
        do a = 1, m
            ord(a) = a
        end do
        do a = 2, m
            t = ord(a)
            b = a - 1
            do while (b >= 1)
                if (.not. (key(t) < key(ord(b)) .or. (key(t) == key(ord(b)) .and. id(t) < id(ord(b))))) exit
                ord(b + 1) = ord(b)
                b = b - 1
            end do
            ord(b + 1) = t
        end do
        cum = 0
        do kk = 1, m - 1
            cum = cum + cost(ord(kk))
            if (cum >= target) exit
        end do
        kk = min(kk, m - 1)
        if (kk > 1) then
            if (target - (cum - cost(ord(kk))) < cum - target) kk = kk - 1
        end if
        want = .false.
        want(ord(1:kk)) = .true.
        same_cut = same_cut .and. all(left .eqv. want)
    end subroutine one_cut
end program test_partition
