!> Whether a loop over nodes or slaves is worth a parallel region.
!>
!> libgomp starts a team for every parallel region, one thread or many; with
!> one thread it allocates the team and frees it again each time: 1.3 us a
!> region here (gfortran 12), against 32 ns for the same loop as an
!> orphaned worksharing loop called outside any region. car6 enters about
!> twenty regions a cycle over 38,000 cycles, 0.9 s of its run on one
!> thread. The cycle's short loops therefore sit in routines with an
!> orphaned `!$omp do`, called from a parallel region where threaded() is
!> true and directly where it is not: the same loop, the same order.
module xd_core_threads
    !$ use omp_lib, only: omp_get_max_threads, omp_in_parallel
    implicit none
    private
    public :: threaded

contains

    !> A parallel region is to be opened here: more than one thread would
    !> run it, or the caller is itself in a region (there the loop needs a
    !> region of its own, as with `!$omp parallel do`, or its orphaned
    !> worksharing would bind to the caller's team, which a single thread
    !> of it reaching the loop would deadlock).
    logical function threaded()
        threaded = .false.
        !$ threaded = omp_get_max_threads() > 1 .or. omp_in_parallel()
    end function threaded

end module xd_core_threads
