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
    call test_summary()
end program test_sorting
