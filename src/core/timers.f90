!> Wall and CPU time per phase, for the d3hsp timing table.
module xd_core_timers
    use xd_kinds, only: dp, i8
    implicit none
    private
    public :: timers_t, nphase, phase_name
    public :: ph_input, ph_init, ph_elements, ph_assembly, ph_integrate, ph_contact, &
              ph_rigid, ph_output, ph_comm, ph_search, ph_local, ph_enforce, ph_ghost, ph_wait

    integer, parameter :: ph_input = 1, ph_init = 2, ph_elements = 3, ph_assembly = 4, &
                          ph_integrate = 5, ph_contact = 6, ph_rigid = 7, ph_output = 8, &
                          ph_comm = 9, ph_search = 10, ph_local = 11, ph_enforce = 12, &
                          ph_ghost = 13, ph_wait = 14, nphase = 14
    character(len=24), parameter :: phase_name(nphase) = [character(len=24) :: &
        'start-up and input', 'initialization', 'element processing', 'force assembly', &
        'time integration', 'rigid walls', 'rigid bodies', 'output', 'MPI halo exchange', &
        'contact global search', 'contact local search', 'contact enforcement', 'MPI contact exchange', &
        'MPI wait (imbalance)']

    !> Wall-clock seconds per phase (the monotonic clock, read without a
    !> system call); the processor time of all threads for the whole run
    !> only (a process's processor time is a system call: read at every
    !> phase's start and stop, some 24 times a cycle, it cost car6 3% of
    !> its run).
    type :: timers_t
        real(dp) :: wall(nphase) = 0.0_dp
        integer(i8) :: wall_start(nphase) = 0
        integer(i8) :: t0 = 0
        real(dp) :: cpu0 = 0.0_dp      !< processor time at begin
    contains
        procedure :: start => timer_start
        procedure :: stop => timer_stop
        procedure :: elapsed => timer_elapsed
        procedure :: cpu => timer_cpu
        procedure :: begin => timer_begin
        procedure :: move => timer_move
    end type timers_t

contains

    subroutine timer_start(self, ph)
        class(timers_t), intent(inout) :: self
        integer, intent(in) :: ph
        call system_clock(self%wall_start(ph))
        if (self%t0 == 0) self%t0 = self%wall_start(ph)
    end subroutine timer_start

    subroutine timer_stop(self, ph)
        class(timers_t), intent(inout) :: self
        integer, intent(in) :: ph
        integer(i8) :: now, rate
        call system_clock(now, rate)
        self%wall(ph) = self%wall(ph) + real(now - self%wall_start(ph), dp)/real(rate, dp)
    end subroutine timer_stop

    !> Book `seconds` of phase `from` (measured inside it) to phase `to`.
    subroutine timer_move(self, from, to, seconds)
        class(timers_t), intent(inout) :: self
        integer, intent(in) :: from, to
        real(dp), intent(in) :: seconds
        self%wall(from) = self%wall(from) - seconds
        self%wall(to) = self%wall(to) + seconds
    end subroutine timer_move

    !> Start the wall clock of elapsed() now (the program's first statement,
    !> so that it counts the parallel start-up too).
    subroutine timer_begin(self)
        class(timers_t), intent(inout) :: self
        real(dp) :: c
        call system_clock(self%t0)
        call cpu_time(c)
        self%cpu0 = c
    end subroutine timer_begin

    !> Processor seconds of all threads since begin.
    real(dp) function timer_cpu(self)
        class(timers_t), intent(in) :: self
        real(dp) :: c
        call cpu_time(c)
        timer_cpu = c - self%cpu0
    end function timer_cpu

    !> Wall seconds since begin() or the first timer started.
    real(dp) function timer_elapsed(self)
        class(timers_t), intent(in) :: self
        integer(i8) :: now, rate
        call system_clock(now, rate)
        timer_elapsed = real(now - self%t0, dp)/real(rate, dp)
    end function timer_elapsed

end module xd_core_timers
