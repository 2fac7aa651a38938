!> Set-up errors: a message that already names file, line, keyword and field.
!> Fallible set-up routines return `type(error_t), allocatable, intent(out)`;
!> callers test `allocated(error)` and return.
module xd_core_errors
    implicit none
    private
    public :: error_t, make_error, printable
    public :: exit_normal, exit_input, exit_run, exit_signal

    integer, parameter :: exit_normal = 0   !< normal termination
    integer, parameter :: exit_input = 1    !< input or model-check error
    integer, parameter :: exit_run = 2      !< error termination during the run
    integer, parameter :: exit_signal = 3   !< stopped by a signal or wall-clock limit

    type :: error_t
        character(len=:), allocatable :: message
        integer :: code = exit_input
    end type error_t

contains

    !> Build an error whose message is `file:line: text` (file and line optional).
    subroutine make_error(error, text, file, line, code)
        type(error_t), allocatable, intent(out) :: error
        character(len=*), intent(in) :: text
        character(len=*), intent(in), optional :: file
        integer, intent(in), optional :: line
        integer, intent(in), optional :: code
        character(len=16) :: buf
        allocate (error)
        error%message = ''
        if (present(file)) then
            error%message = trim(file)//':'
            if (present(line)) then
                write (buf, '(i0)') line
                error%message = error%message//trim(buf)//':'
            end if
            error%message = error%message//' '
        end if
        error%message = error%message//printable(text)
        if (present(code)) error%code = code
    end subroutine make_error

    !> text with its control characters (bytes 0-31 and 127: a terminal's
    !> escape sequences, a stray carriage return) written as \xNN, so that
    !> a deck's bytes echoed in a message cannot drive the terminal; the line
    !> feeds and tabs of a message's own layout are kept.
    pure function printable(text) result(t)
        character(len=*), intent(in) :: text
        character(len=:), allocatable :: t
        character(len=*), parameter :: hex = '0123456789ABCDEF'
        integer :: i, c
        t = ''
        do i = 1, len(text)
            c = iachar(text(i:i))
            if ((c < 32 .and. c /= 9 .and. c /= 10) .or. c == 127) then
                t = t//'\x'//hex(c/16 + 1:c/16 + 1)//hex(mod(c, 16) + 1:mod(c, 16) + 1)
            else
                t = t//text(i:i)
            end if
        end do
    end function printable

end module xd_core_errors
