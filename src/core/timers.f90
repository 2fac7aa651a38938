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
        'input and checks', 'initialization', 'element processing', 'force assembly', &
        'time integration', 'rigid walls', 'rigid bodies', 'output', 'MPI halo exchange', &
        'contact global search', 'contact local search', 'contact enforcement', 'MPI contact exchange', &
        'MPI wait (imbalance)']

    type :: timers_t
        real(dp) :: wall(nphase) = 0.0_dp
        real(dp) :: cpu(nphase) = 0.0_dp
        integer(i8) :: wall_start(nphase) = 0
        real(dp) :: cpu_start(nphase) = 0.0_dp
        integer(i8) :: t0 = 0
    contains
        procedure :: start => timer_start
        procedure :: stop => timer_stop
        procedure :: elapsed => timer_elapsed
        procedure :: begin => timer_begin
        procedure :: move => timer_move
    end type timers_t

contains

    subroutine timer_start(self, ph)
        class(timers_t), intent(inout) :: self
        integer, intent(in) :: ph
        real :: c
        call system_clock(self%wall_start(ph))
        call cpu_time(c)
        self%cpu_start(ph) = real(c, dp)
        if (self%t0 == 0) self%t0 = self%wall_start(ph)
    end subroutine timer_start

    subroutine timer_stop(self, ph)
        class(timers_t), intent(inout) :: self
        integer, intent(in) :: ph
        integer(i8) :: now, rate
        real :: c
        call system_clock(now, rate)
        call cpu_time(c)
        self%wall(ph) = self%wall(ph) + real(now - self%wall_start(ph), dp)/real(rate, dp)
        self%cpu(ph) = self%cpu(ph) + real(c, dp) - self%cpu_start(ph)
    end subroutine timer_stop

    !> Book `seconds` of phase `from` (measured inside it) to phase `to`.
    subroutine timer_move(self, from, to, seconds)
        class(timers_t), intent(inout) :: self
        integer, intent(in) :: from, to
        real(dp), intent(in) :: seconds
        self%wall(from) = self%wall(from) - seconds
        self%wall(to) = self%wall(to) + seconds
        self%cpu(from) = self%cpu(from) - seconds
        self%cpu(to) = self%cpu(to) + seconds
    end subroutine timer_move

    !> Start the wall clock of elapsed() now (the program's first statement,
    !> so that it counts the parallel start-up too).
    subroutine timer_begin(self)
        class(timers_t), intent(inout) :: self
        call system_clock(self%t0)
    end subroutine timer_begin

    !> Wall seconds since begin() or the first timer started.
    real(dp) function timer_elapsed(self)
        class(timers_t), intent(in) :: self
        integer(i8) :: now, rate
        call system_clock(now, rate)
        timer_elapsed = real(now - self%t0, dp)/real(rate, dp)
    end function timer_elapsed

end module xd_core_timers
