!> LS-DYNA's sense switches: a user steers a running job by writing a word
!> into a file named d3kil in the run's directory. sw1: a restart dump,
!> then stop (exit 3); sw2: a status line; sw3: a restart dump, and go on;
!> sw4: a state (d3plot) now, and go on; swa: the histories flushed to
!> disk. An empty d3kil (`touch d3kil`) stops like sw1, as LS-DYNA's does.
!> The file is read once and deleted, so each word asks once. The batch
!> signals (SIGTERM, SIGUSR1, SIGUSR2) stay as they are.
module xd_solver_sense_switch
    use xd_core_strings, only: to_upper
    use xd_core_files, only: file_kind, fk_regular
    implicit none
    private
    public :: sw_none, sw_stop, sw_status, sw_dump, sw_state, sw_flush, sw_unknown, read_sense_switch, switch_name

    integer, parameter :: sw_none = 0, sw_stop = 1, sw_status = 2, sw_dump = 3, sw_state = 4, sw_flush = 5, &
                          sw_unknown = -1

contains

    !> The switch asked by the first of the files path1, path2 that exists,
    !> which is deleted. text: its first line as written (for the log);
    !> gone: false where the file could not be deleted (it would ask again).
    subroutine read_sense_switch(path1, path2, sw, text, gone)
        character(len=*), intent(in) :: path1, path2
        integer, intent(out) :: sw
        character(len=:), allocatable, intent(out) :: text
        logical, intent(out) :: gone
        logical :: there
        character(len=80) :: line
        character(len=:), allocatable :: path, word
        integer :: u, ios, k
        sw = sw_none
        text = ''
        gone = .true.
        ! (a regular file only: a FIFO named d3kil would block the open)
        path = path1
        there = file_kind(path1) == fk_regular
        if (.not. there .and. len(path2) > 0) then
            path = path2
            there = file_kind(path2) == fk_regular
        end if
        if (.not. there) return
        line = ''
        open (newunit=u, file=path, status='old', action='read', iostat=ios)
        if (ios /= 0) then
            ! there a moment ago and now unreadable: asked again next time
            return
        end if
        read (u, '(a)', iostat=ios) line
        close (u, status='delete', iostat=ios)
        gone = ios == 0
        text = trim(adjustl(line))
        word = to_upper(text)
        k = index(word, ' ')
        if (k > 0) word = word(1:k - 1)
        select case (word)
        case ('', 'SW1')
            sw = sw_stop
        case ('SW2')
            sw = sw_status
        case ('SW3')
            sw = sw_dump
        case ('SW4')
            sw = sw_state
        case ('SWA')
            sw = sw_flush
        case default
            sw = sw_unknown
        end select
    end subroutine read_sense_switch

    !> What a switch does, for the log.
    function switch_name(sw) result(t)
        integer, intent(in) :: sw
        character(len=:), allocatable :: t
        select case (sw)
        case (sw_stop); t = 'sw1 (restart dump and stop)'
        case (sw_status); t = 'sw2 (status line)'
        case (sw_dump); t = 'sw3 (restart dump, the run goes on)'
        case (sw_state); t = 'sw4 (a state now)'
        case (sw_flush); t = 'swa (histories flushed)'
        case default; t = 'not a sense switch (sw1, sw2, sw3, sw4, swa): ignored'
        end select
    end function switch_name

end module xd_solver_sense_switch
