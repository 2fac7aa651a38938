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
        logical :: mpi = .false.    !< MPI was started (a launcher's run, or XDYNA_MPI=1)
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
        env%nthreads = 1
        !$ env%nthreads = omp_get_max_threads()
        call MPI_Initialized(up)
        if (.not. up) then
            ! started alone (no launcher: none of its variables set) the run
            ! is one rank and MPI is not started at all: Open MPI's start of
            ! a lone process (its own PMIx server) and its finish took 0.4 s
            ! of every run, most of a small deck's wall time. XDYNA_MPI=1
            ! starts it anyway. The operations of xd_core_comm are then
            ! those of one rank
            if (.not. launched()) return
            ! a lone start that is asked for: Open MPI starts a PMIx server of
            ! its own, whose default store is a shared-memory file; under a
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
        env%mpi = .true.
        call MPI_Comm_rank(MPI_COMM_WORLD, env%rank)
        call MPI_Comm_size(MPI_COMM_WORLD, env%nranks)
    end subroutine parallel_start

    !> The process was started by an MPI launcher (mpirun, mpiexec, srun:
    !> one of the variables they give each rank is set), or XDYNA_MPI=1
    !> asks for MPI.
    logical function launched()
        character(len=*), parameter :: names(6) = [character(len=20) :: 'OMPI_COMM_WORLD_SIZE', 'PMIX_RANK', &
                                                    'PMI_RANK', 'PMI_SIZE', 'PMI_FD', 'SLURM_STEP_NUM_TASKS']
        character(len=8) :: v
        integer :: i, st
        launched = .false.
        do i = 1, size(names)
            call get_environment_variable(trim(names(i)), status=st)
            if (st == 0) launched = .true.
        end do
        call get_environment_variable('XDYNA_MPI', v, status=st)
        if (st == 0 .and. trim(v) == '1') launched = .true.
    end function launched

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
