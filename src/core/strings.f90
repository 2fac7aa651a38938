!> Small string helpers for the deck reader and the writers.
module xd_core_strings
    use xd_kinds, only: wp, dp
    implicit none
    private
    public :: to_upper, to_lower, itoa, rtoa, ftoa, dirname, join_path, starts_with, out_path

contains

    pure function to_upper(s) result(u)
        character(len=*), intent(in) :: s
        character(len=len(s)) :: u
        integer :: i, c
        u = s
        do i = 1, len(s)
            c = iachar(s(i:i))
            if (c >= iachar('a') .and. c <= iachar('z')) u(i:i) = achar(c - 32)
        end do
    end function to_upper

    pure function to_lower(s) result(u)
        character(len=*), intent(in) :: s
        character(len=len(s)) :: u
        integer :: i, c
        u = s
        do i = 1, len(s)
            c = iachar(s(i:i))
            if (c >= iachar('A') .and. c <= iachar('Z')) u(i:i) = achar(c + 32)
        end do
    end function to_lower

    pure function itoa(i) result(s)
        integer, intent(in) :: i
        character(len=:), allocatable :: s
        character(len=24) :: buf
        write (buf, '(i0)') i
        s = trim(buf)
    end function itoa

    !> Scientific notation, six significant digits: 1.50750E-04.
    pure function rtoa(x) result(s)
        real(dp), intent(in) :: x
        character(len=:), allocatable :: s
        character(len=32) :: buf
        ! (a three-digit exponent keeps its E: 1.00000E+300, not 1.00000+300)
        if (abs(x) >= 1.0e100_dp .or. (abs(x) < 1.0e-99_dp .and. x /= 0.0_dp)) then
            write (buf, '(es13.5e3)') x
        else
            write (buf, '(es12.5)') x
        end if
        s = trim(adjustl(buf))
    end function rtoa

    !> Fixed notation, four decimals: 1.0213.
    pure function ftoa(x) result(s)
        real(dp), intent(in) :: x
        character(len=:), allocatable :: s
        character(len=32) :: buf
        ! beyond what nine digits before the point hold: exponent notation
        ! (a blown-up energy printed as asterisks said nothing)
        if (abs(x) >= 1.0e100_dp) then
            write (buf, '(es13.5e3)') x
        else if (abs(x) >= 1.0e8_dp) then
            write (buf, '(es12.5)') x
        else
            write (buf, '(f14.4)') x
        end if
        s = trim(adjustl(buf))
    end function ftoa

    !> Directory part of a path, '.' when there is none.
    pure function dirname(path) result(d)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: d
        integer :: k
        k = index(path, '/', back=.true.)
        if (k == 0) then
            d = '.'
        else if (k == 1) then
            d = '/'
        else
            d = path(1:k - 1)
        end if
    end function dirname

    !> `name` relative to `dir` unless it is absolute.
    pure function join_path(dir, name) result(p)
        character(len=*), intent(in) :: dir, name
        character(len=:), allocatable :: p
        if (len(name) > 0) then
            if (name(1:1) == '/') then
                p = name
                return
            end if
        end if
        if (dir == '.' .or. len(dir) == 0) then
            p = name
        else
            p = dir//'/'//name
        end if
    end function join_path

    !> An output file of a run: `stem` is the output directory, or the
    !> directory and a job prefix ending in '.' (jobid=: 'dir/job.').
    pure function out_path(stem, name) result(p)
        character(len=*), intent(in) :: stem, name
        character(len=:), allocatable :: p
        integer :: n
        n = len(stem)
        p = join_path(stem, name)
        if (n == 0) return
        if (stem(n:n) /= '.' .or. stem == '.' .or. stem == '..') return
        if (n >= 2) then
            if (stem(n - 1:n) == '/.') return
        end if
        p = stem//name
    end function out_path

    pure logical function starts_with(s, prefix)
        character(len=*), intent(in) :: s, prefix
        starts_with = .false.
        if (len(s) >= len(prefix)) starts_with = s(1:len(prefix)) == prefix
    end function starts_with

end module xd_core_strings
