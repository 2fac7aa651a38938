!> Set-up errors: a message that already names file, line, keyword and field.
!> Fallible set-up routines return `type(error_t), allocatable, intent(out)`;
!> callers test `allocated(error)` and return.
module xd_core_errors
    implicit none
    private
    public :: error_t, make_error
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
        error%message = error%message//text
        if (present(code)) error%code = code
    end subroutine make_error

end module xd_core_errors
