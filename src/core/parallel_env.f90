!> MPI and OpenMP environment: start-up, rank and thread counts, and the one
!> routine that ends the program (MPI_Abort when more than one rank runs).
module xd_core_parallel_env
    use mpi_f08, only: MPI_Init_thread, MPI_Finalize, MPI_Initialized, MPI_Finalized, &
                       MPI_Abort, MPI_Comm_rank, MPI_Comm_size, MPI_COMM_WORLD, &
                       MPI_THREAD_FUNNELED
    use, intrinsic :: iso_fortran_env, only: output_unit, error_unit
    use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char
    !$ use omp_lib, only: omp_get_max_threads
    implicit none
    private
    public :: parallel_env_t, parallel_start, parallel_stop, terminate

    type :: parallel_env_t
        integer :: rank = 0
        integer :: nranks = 1
        integer :: nthreads = 1
    end type parallel_env_t

    interface
        integer(c_int) function c_setenv(name, value, overwrite) bind(c, name='setenv')
            import :: c_int, c_char
            character(kind=c_char), intent(in) :: name(*), value(*)
            integer(c_int), value :: overwrite
        end function c_setenv
    end interface

contains

    subroutine parallel_start(env)
        type(parallel_env_t), intent(out) :: env
        integer :: provided, st, n
        logical :: up
        call MPI_Initialized(up)
        if (.not. up) then
            ! started alone (no mpirun): Open MPI starts a PMIx server of its
            ! own, whose default store is a shared-memory file; under a
            ! file-size limit (ulimit -f below about 4.5 MB) that write
            ! failed and the run died before a word of ours. Its in-memory
            ! store needs no file (a value the user set is kept)
            call get_environment_variable('OMPI_COMM_WORLD_SIZE', length=n, status=st)
            if (st /= 0) then
                call get_environment_variable('PMIX_RANK', length=n, status=st)
                if (st /= 0) st = c_setenv('PMIX_MCA_gds'//c_null_char, 'hash'//c_null_char, 0_c_int)
            end if
            call MPI_Init_thread(MPI_THREAD_FUNNELED, provided)
        end if
        call MPI_Comm_rank(MPI_COMM_WORLD, env%rank)
        call MPI_Comm_size(MPI_COMM_WORLD, env%nranks)
        env%nthreads = 1
        !$ env%nthreads = omp_get_max_threads()
    end subroutine parallel_start

    subroutine parallel_stop()
        logical :: up, down
        call MPI_Initialized(up)
        call MPI_Finalized(down)
        if (up .and. .not. down) call MPI_Finalize()
    end subroutine parallel_stop

    !> End the program with exit status `code`. Flushes standard streams. When
    !> several ranks run and the code is not 0, aborts the whole MPI job so
    !> that no rank is left waiting, unless `collective` says that every rank
    !> ends here with this code (then they finish together, quietly).
    subroutine terminate(code, collective)
        integer, intent(in) :: code
        logical, intent(in), optional :: collective
        logical :: up, down, together
        integer :: nranks
        together = .false.
        if (present(collective)) together = collective
        flush (output_unit)
        flush (error_unit)
        call MPI_Initialized(up)
        call MPI_Finalized(down)
        if (up .and. .not. down) then
            call MPI_Comm_size(MPI_COMM_WORLD, nranks)
            if (nranks > 1 .and. code /= 0 .and. .not. together) call MPI_Abort(MPI_COMM_WORLD, code)
            call MPI_Finalize()
        end if
        stop code, quiet=.true.
    end subroutine terminate

end module xd_core_parallel_env
