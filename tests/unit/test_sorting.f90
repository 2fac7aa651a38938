!> Id maps and the stable sort against brute force on random ids.
program test_sorting
    use xd_testing, only: check, test_summary
    use xd_core_sorting, only: sort_index, id_map_t
    implicit none
    integer, parameter :: n = 2000
    integer :: ids(n), k, dup, probe, brute, i
    integer, allocatable :: perm(:)
    real :: r(n)
    type(id_map_t) :: dense, sparse
    logical :: ok
    integer, parameter :: sizes(14) = [1, 2, 15, 16, 17, 31, 33, 64, 65, 100, 257, 1000, 1999, 2000]

    call random_seed(put=[(777 + k, k=1, 64)])
    call random_number(r)
    ! sparse ids: distinct multiples of 9973 shuffled by the random keys
    call sort_index(int(r*1.0e6), perm)
    ids = perm*9973
    call check(all(int(r(perm(1:n - 1))*1.0e6) <= int(r(perm(2:n))*1.0e6)), 'sort_index orders the keys')
    call sparse%build(ids, dup)
    call check(dup == 0 .and. .not. sparse%direct, 'sparse ids use the sorted table, no duplicate')
    ok = .true.
    do k = 1, 3000
        probe = 9973*(k - 500)
        brute = 0
        do i = 1, n
            if (ids(i) == probe) brute = i
        end do
        ok = ok .and. sparse%find(probe) == brute
    end do
    call check(ok, 'sparse id map agrees with brute force (hits and misses)')
    ids = [(i + 100, i=1, n)]
    ids(n) = 150
    call dense%build(ids, dup)
    call check(dense%direct .and. dup == 150, 'dense ids use the direct table and report a duplicate')
    call check(dense%find(101) == 1 .and. dense%find(99) == 0 .and. dense%find(10**6) == 0, &
               'dense id map finds and misses')
    call sort_index([3, 1, 3, 2, 1], perm)
    call check(all(perm == [2, 5, 4, 1, 3]), 'sort_index is stable for equal keys')
    ! the stable order itself (a brute-force insertion's) for sizes around
    ! the sort's runs of 16 and their merges, with many equal keys, keys
    ! already in order (whose runs are left unmerged) and reversed
    ok = .true.
    do k = 1, 40
        i = sizes(mod(k - 1, 14) + 1)
        call random_number(r)
        if (k <= 14) then
            r(1:i) = real(int(r(1:i)*7.0))               ! seven values: ties everywhere
        else if (k <= 28) then
            r(1:i) = [(real(int(real(probe)/3.0)), probe=1, i)]   ! in order, in threes
        else if (k <= 40) then
            r(1:i) = [(real(i - probe), probe=1, i)]     ! reversed
        end if
        call sort_index(real(r(1:i), kind(1.0d0)), perm)
        ok = ok .and. all(perm == stable_order(r(1:i)))
    end do
    call check(ok, 'sort_index gives the stable order on 40 sets (ties, in order, reversed; 1 to 2000 keys)')
    call test_summary()
contains
    !> The stable order of a by insertion (an element moves past those
    !> strictly greater only).
    function stable_order(a) result(p)
        real, intent(in) :: a(:)
        integer :: p(size(a))
        integer :: ii, jj, t
        p = [(ii, ii=1, size(a))]
        do ii = 2, size(a)
            t = p(ii)
            jj = ii - 1
            do while (jj >= 1)
                if (.not. a(t) < a(p(jj))) exit
                p(jj + 1) = p(jj)
                jj = jj - 1
            end do
            p(jj + 1) = t
        end do
    end function stable_order
end program test_sorting
