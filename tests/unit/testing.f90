!> Minimal test harness: each check prints PASS or FAIL with its name; the
!> runner counts them. A failed check also says what was expected.
module xd_testing
    use xd_kinds, only: wp, dp
    implicit none
    private
    public :: check, check_close, test_summary

    integer, save :: npass = 0, nfail = 0

contains

    subroutine check(cond, name, detail)
        logical, intent(in) :: cond
        character(len=*), intent(in) :: name
        character(len=*), intent(in), optional :: detail
        if (cond) then
            npass = npass + 1
            write (*, '(a)') 'PASS '//name
        else
            nfail = nfail + 1
            if (present(detail)) then
                write (*, '(a)') 'FAIL '//name//': '//detail
            else
                write (*, '(a)') 'FAIL '//name
            end if
        end if
    end subroutine check

    !> |got - want| <= tol (absolute).
    subroutine check_close(got, want, tol, name)
        real(dp), intent(in) :: got, want, tol
        character(len=*), intent(in) :: name
        character(len=120) :: buf
        write (buf, '(a,es15.7,a,es15.7,a,es9.2)') 'got', got, ' want', want, ' tol', tol
        call check(abs(got - want) <= tol, name, trim(buf))
    end subroutine check_close

    subroutine test_summary()
        write (*, '(a,i0,a,i0,a)') 'unit: ', npass, ' passed, ', nfail, ' failed'
    end subroutine test_summary

end module xd_testing
