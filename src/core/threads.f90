!> Whether a loop over nodes or slaves is worth a parallel region.
!>
!> libgomp starts a team for every parallel region, one thread or many; with
!> one thread it allocates the team and frees it again each time: 1.3 us a
!> region here (gfortran 12), against 32 ns for the same loop as an
!> orphaned worksharing loop called outside any region. car6 enters about
!> twenty regions a cycle over 38,000 cycles, 0.9 s of its run on one
!> thread. The cycle's short loops therefore sit in routines with an
!> orphaned `!$omp do`, called from a parallel region where threaded() is
!> true (several threads and a long enough loop) and directly where it is
!> not: the same loop, the same order.
module xd_core_threads
    !$ use omp_lib, only: omp_get_max_threads, omp_in_parallel
    implicit none
    private
    public :: threaded

    !> The shortest loop given to a team. A region's start and barrier
    !> cost a few microseconds with two threads on a virtual machine here,
    !> about what 2,000-5,000 node updates take: car6 (2,378 nodes) on two
    !> threads took 23.6 s against 17.8 s on one, its time integration
    !> 3.66 against 0.97 s, while the 10 x 10 tubes (120,000 nodes) gained.
    !> A loop shorter than this runs on the thread that reaches it (the same
    !> values: each item is its own, and the loops' sums are kept in fixed
    !> chunks).
    integer, parameter :: min_items = 16384

contains

    !> A parallel region is to be opened here for a loop of n items: more
    !> than one thread would run it and the loop is long enough to pay for
    !> the team's start and barrier, or the caller is itself in a region
    !> (there the loop needs a region of its own, as with `!$omp parallel
    !> do`, or its orphaned worksharing would bind to the caller's team,
    !> which a single thread of it reaching the loop would deadlock).
    logical function threaded(n)
        integer, intent(in) :: n
        threaded = .false.
        !$ threaded = (omp_get_max_threads() > 1 .and. n >= min_items) .or. omp_in_parallel()
    end function threaded

end module xd_core_threads
