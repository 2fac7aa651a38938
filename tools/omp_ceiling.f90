!> The machine's own thread scaling, as a ceiling for a code's: each thread
!> runs the same work alone (an arithmetic loop on data in its first-level
!> cache, and a triad over arrays in memory), on 1, 2, 4, ... threads; the
!> speed-up is the work done per second against one thread's.
!>   gfortran -O3 -march=x86-64-v3 -fopenmp tools/omp_ceiling.f90 -o omp_ceiling
!>   ./omp_ceiling 16
program omp_ceiling
    use omp_lib, only: omp_get_wtime, omp_set_num_threads, omp_get_thread_num
    implicit none
    integer, parameter :: dp = kind(1.0d0), nl1 = 2048, nmem = 2**25, reps = 400000
    real(dp), allocatable :: a(:), b(:), c(:)
    real(dp) :: t0, tc, tm, tc1, tm1, s
    integer :: nt, maxt, i, j
    character(len=16) :: arg
    maxt = 16
    if (command_argument_count() > 0) then
        call get_command_argument(1, arg)
        read (arg, *) maxt
    end if
    allocate (a(nmem), b(nmem), c(nmem))
    !$omp parallel do schedule(static)
    do i = 1, nmem
        a(i) = 0
        b(i) = 1.0_dp + 1.0e-9_dp*i
        c(i) = 2.0_dp - 1.0e-9_dp*i
    end do
    !$omp end parallel do
    write (*, '(a)') ' threads  arithmetic (s)  speed-up   triad (s)  speed-up'
    nt = 1
    do while (nt <= maxt)
        call omp_set_num_threads(nt)
        ! arithmetic: each thread the same amount (weak scaling)
        t0 = omp_get_wtime()
        s = 0
        !$omp parallel private(j, i) reduction(+:s)
        block
            real(dp) :: x(nl1)
            x = [(1.0_dp + 1.0e-6_dp*(i + omp_get_thread_num()), i=1, nl1)]
            do j = 1, reps*20
                do i = 1, nl1
                    x(i) = x(i)*0.999999_dp + 1.0e-7_dp
                end do
            end do
            s = s + sum(x)
        end block
        !$omp end parallel
        tc = omp_get_wtime() - t0
        ! triad over memory: the same arrays split among the threads (strong)
        t0 = omp_get_wtime()
        do j = 1, 10
            !$omp parallel do schedule(static)
            do i = 1, nmem
                a(i) = b(i) + 0.5_dp*c(i)
            end do
            !$omp end parallel do
        end do
        tm = omp_get_wtime() - t0
        if (nt == 1) then
            tc1 = tc
            tm1 = tm
        end if
        write (*, '(i8, f16.3, f10.2, f12.3, f10.2, es12.3)') nt, tc, nt*tc1/tc, tm, tm1/tm, s + a(nmem)
        nt = 2*nt
    end do
end program omp_ceiling
