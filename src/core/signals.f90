!> Batch signals (POSIX, through the C library's signal()): SIGTERM and
!> SIGUSR1 ask the run to write a restart dump and stop (exit 3); SIGUSR2
!> asks for a status line (LS-DYNA's sw2). The handlers only set flags,
!> which the time loop reads once a cycle; nothing else happens inside a
!> handler. The flags are the one piece of state that changes behind the
!> run's back, which is what a signal is.
module xd_core_signals
    use, intrinsic :: iso_c_binding, only: c_int, c_funptr, c_funloc, c_intptr_t
    implicit none
    private
    public :: signals_install, stop_signal, status_signal, hold_for_signal

    integer(c_int), parameter :: sigusr1 = 10, sigusr2 = 12, sigterm = 15, sigxfsz = 25   ! Linux numbers

    integer(c_int), volatile, save :: pending_stop = 0     !< the signal that asked to stop (0: none)
    integer(c_int), volatile, save :: pending_status = 0

    interface
        integer(c_int) function c_usleep(us) bind(c, name='usleep')
            import :: c_int
            integer(c_int), value :: us
        end function c_usleep
        function c_signal(signum, handler) bind(c, name='signal') result(old)
            import :: c_int, c_funptr
            integer(c_int), value :: signum
            type(c_funptr), value :: handler
            type(c_funptr) :: old
        end function c_signal
    end interface

contains

    subroutine signals_install()
        type(c_funptr) :: old
        old = c_signal(sigterm, c_funloc(on_stop))
        old = c_signal(sigusr1, c_funloc(on_stop))
        old = c_signal(sigusr2, c_funloc(on_status))
        ! a file grown past the size limit (ulimit -f) fails its write with
        ! EFBIG, which the run reports naming the file, instead of the
        ! signal killing the run with nothing said
        old = c_signal(sigxfsz, transfer(1_c_intptr_t, old))
    end subroutine signals_install

    subroutine on_stop(signum) bind(c)
        integer(c_int), value :: signum
        pending_stop = signum
    end subroutine on_stop

    subroutine on_status(signum) bind(c)
        integer(c_int), value :: signum
        pending_status = signum
    end subroutine on_status

    !> The signal that asked the run to stop (SIGTERM 15 or SIGUSR1 10), 0 if none.
    integer function stop_signal()
        stop_signal = int(pending_stop)
    end function stop_signal

    !> Whether a status line was asked for since the last call (and clear it).
    logical function status_signal()
        status_signal = pending_status /= 0
        pending_status = 0
    end function status_signal

    !> For tests of the batch signals (XDYNA_HOLD_AT): say `text` on
    !> standard output and wait, polling every 10 ms, until a signal comes
    !> (a stop, or SIGUSR2 to go on; at most `limit` seconds). A test that signals after this line
    !> hits the run where it means to on any machine, however fast.
    subroutine hold_for_signal(text, limit, loud)
        use, intrinsic :: iso_fortran_env, only: output_unit
        character(len=*), intent(in) :: text
        real, intent(in) :: limit
        logical, intent(in) :: loud
        integer :: k, rc
        if (loud) then
            write (output_unit, '(a)') text
            flush (output_unit)
        end if
        do k = 1, nint(limit*100.0)
            if (pending_stop /= 0 .or. pending_status /= 0) exit
            rc = c_usleep(10000_c_int)
        end do
    end subroutine hold_for_signal

end module xd_core_signals
