!> Arithmetic of *PARAMETER_EXPRESSION: + - * / and ** (right-associative,
!> above unary minus as in Fortran), parentheses, numbers (Fortran and
!> E/D exponents), earlier parameters with or without a leading '&', and the
!> functions LS-DYNA's manual lists: sin cos tan csc sec ctn asin acos atan
!> atan2 sinh cosh tanh asinh acosh atanh min max sqrt mod abs sign int aint
!> nint anint real exp log log10 (plus the names ls_integer, ls_real).
!> Recursive descent; an error names the position and what was expected.
module xd_input_expression
    use, intrinsic :: ieee_exceptions, only: ieee_get_halting_mode, ieee_set_halting_mode, ieee_set_flag, &
                                             ieee_overflow, ieee_divide_by_zero, ieee_invalid, ieee_flag_type
    use xd_kinds, only: dp
    use xd_core_strings, only: to_upper, itoa
    use xd_input_field_reader, only: param_table_t
    implicit none
    private
    public :: evaluate

    type(ieee_flag_type), parameter :: traps(3) = [ieee_overflow, ieee_divide_by_zero, ieee_invalid]

    type :: parser_t
        character(len=:), allocatable :: s
        integer :: p = 1
        character(len=:), allocatable :: msg
    end type parser_t

contains

    !> Value of expression `text`; `msg` is empty on success.
    subroutine evaluate(text, params, scope, value, msg)
        character(len=*), intent(in) :: text
        type(param_table_t), intent(in) :: params
        character(len=*), intent(in) :: scope
        real(dp), intent(out) :: value
        character(len=:), allocatable, intent(out) :: msg
        type(parser_t) :: ps
        logical :: halt(3)
        ! a deck's arithmetic may overflow (1e300*1e300): it is evaluated
        ! with the floating-point traps off, so that the debug build, which
        ! traps them, reports it as the release build does (not finite)
        call ieee_get_halting_mode(traps, halt)
        call ieee_set_halting_mode(traps, .false.)
        ps%s = trim(text)
        ps%p = 1
        ps%msg = ''
        value = expr(ps, params, scope)
        if (len(ps%msg) == 0) then
            call skip_blanks(ps)
            if (ps%p <= len(ps%s)) call fail(ps, 'unexpected '''//ps%s(ps%p:)//'''')
        end if
        if (len(ps%msg) == 0 .and. .not. (abs(value) <= huge(1.0_dp))) call fail(ps, 'the value is not finite')
        call ieee_set_flag(traps, .false.)
        call ieee_set_halting_mode(traps, halt)
        msg = ps%msg
    end subroutine evaluate

    recursive real(dp) function expr(ps, params, scope) result(v)
        type(parser_t), intent(inout) :: ps
        type(param_table_t), intent(in) :: params
        character(len=*), intent(in) :: scope
        character :: op
        v = term(ps, params, scope)
        do while (len(ps%msg) == 0)
            call skip_blanks(ps)
            if (ps%p > len(ps%s)) exit
            op = ps%s(ps%p:ps%p)
            if (op /= '+' .and. op /= '-') exit
            ps%p = ps%p + 1
            if (op == '+') then
                v = v + term(ps, params, scope)
            else
                v = v - term(ps, params, scope)
            end if
        end do
    end function expr

    recursive real(dp) function term(ps, params, scope) result(v)
        type(parser_t), intent(inout) :: ps
        type(param_table_t), intent(in) :: params
        character(len=*), intent(in) :: scope
        character :: op
        real(dp) :: r
        v = unary(ps, params, scope)
        do while (len(ps%msg) == 0)
            call skip_blanks(ps)
            if (ps%p > len(ps%s)) exit
            op = ps%s(ps%p:ps%p)
            if (op /= '*' .and. op /= '/') exit
            if (ps%p < len(ps%s)) then
                if (ps%s(ps%p:ps%p + 1) == '**') exit
            end if
            ps%p = ps%p + 1
            r = unary(ps, params, scope)
            if (op == '*') then
                v = v*r
            else
                if (r == 0.0_dp) then
                    call fail(ps, 'division by zero')
                    return
                end if
                v = v/r
            end if
        end do
    end function term

    recursive real(dp) function unary(ps, params, scope) result(v)
        type(parser_t), intent(inout) :: ps
        type(param_table_t), intent(in) :: params
        character(len=*), intent(in) :: scope
        call skip_blanks(ps)
        if (ps%p <= len(ps%s)) then
            if (ps%s(ps%p:ps%p) == '-') then
                ps%p = ps%p + 1
                v = -unary(ps, params, scope)
                return
            else if (ps%s(ps%p:ps%p) == '+') then
                ps%p = ps%p + 1
                v = unary(ps, params, scope)
                return
            end if
        end if
        v = power(ps, params, scope)
    end function unary

    recursive real(dp) function power(ps, params, scope) result(v)
        type(parser_t), intent(inout) :: ps
        type(param_table_t), intent(in) :: params
        character(len=*), intent(in) :: scope
        real(dp) :: e
        v = primary(ps, params, scope)
        if (len(ps%msg) > 0) return
        call skip_blanks(ps)
        if (ps%p + 1 <= len(ps%s)) then
            if (ps%s(ps%p:ps%p + 1) == '**') then
                ps%p = ps%p + 2
                e = unary(ps, params, scope)
                if (len(ps%msg) > 0) return
                if (v < 0.0_dp .and. e /= aint(e)) then
                    call fail(ps, 'a negative number to a fractional power')
                    return
                end if
                if (e == aint(e) .and. abs(e) < 1.0e9_dp) then
                    v = v**nint(e)
                else
                    v = v**e
                end if
            end if
        end if
    end function power

    recursive real(dp) function primary(ps, params, scope) result(v)
        type(parser_t), intent(inout) :: ps
        type(param_table_t), intent(in) :: params
        character(len=*), intent(in) :: scope
        integer :: q, ip, st, na
        character(len=:), allocatable :: name
        real(dp) :: a(2)
        v = 0
        call skip_blanks(ps)
        if (ps%p > len(ps%s)) then
            call fail(ps, 'the expression ends where a value was expected')
            return
        end if
        q = ps%p
        select case (ps%s(q:q))
        case ('(')
            ps%p = q + 1
            v = expr(ps, params, scope)
            call expect(ps, ')')
        case ('0':'9', '.')
            do while (ps%p <= len(ps%s))
                if (scan(ps%s(ps%p:ps%p), '0123456789.') == 0) exit
                ps%p = ps%p + 1
            end do
            if (ps%p <= len(ps%s)) then
                if (scan(ps%s(ps%p:ps%p), 'eEdD') > 0) then
                    ps%p = ps%p + 1
                    if (ps%p <= len(ps%s)) then
                        if (scan(ps%s(ps%p:ps%p), '+-') > 0) ps%p = ps%p + 1
                    end if
                    do while (ps%p <= len(ps%s))
                        if (scan(ps%s(ps%p:ps%p), '0123456789') == 0) exit
                        ps%p = ps%p + 1
                    end do
                end if
            end if
            read (ps%s(q:ps%p - 1), *, iostat=st) v
            if (st /= 0) call fail(ps, 'bad number '''//ps%s(q:ps%p - 1)//'''')
        case ('&', 'A':'Z', 'a':'z', '_')
            if (ps%s(q:q) == '&') q = q + 1
            ps%p = q
            do while (ps%p <= len(ps%s))
                if (scan(to_upper(ps%s(ps%p:ps%p)), 'ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_') == 0) exit
                ps%p = ps%p + 1
            end do
            name = to_upper(ps%s(q:ps%p - 1))
            call skip_blanks(ps)
            if (ps%p <= len(ps%s)) then
                if (ps%s(ps%p:ps%p) == '(') then
                    ps%p = ps%p + 1
                    a = 0
                    na = 1
                    a(1) = expr(ps, params, scope)
                    call skip_blanks(ps)
                    if (len(ps%msg) == 0 .and. ps%p <= len(ps%s)) then
                        if (ps%s(ps%p:ps%p) == ',') then
                            ps%p = ps%p + 1
                            a(2) = expr(ps, params, scope)
                            na = 2
                        end if
                    end if
                    call expect(ps, ')')
                    if (len(ps%msg) > 0) return
                    v = apply(ps, name, a, na)
                    return
                end if
            end if
            if (name == 'PI') then
                v = acos(-1.0_dp)
                return
            end if
            ip = params%find_scoped(name, scope)
            if (ip == 0) then
                call fail(ps, 'parameter '''//name//''' is not defined before this expression')
                return
            end if
            read (params%value(ip), *, iostat=st) v
            if (st /= 0) call fail(ps, 'parameter '''//name//''' is not a number ('''// &
                                   trim(params%value(ip))//''')')
        case default
            call fail(ps, 'unexpected '''//ps%s(q:)//'''')
        end select
    end function primary

    real(dp) function apply(ps, name, a, na) result(v)
        type(parser_t), intent(inout) :: ps
        character(len=*), intent(in) :: name
        real(dp), intent(in) :: a(2)
        integer, intent(in) :: na
        integer :: want
        v = 0
        want = 1
        select case (name)
        case ('ATAN2', 'MIN', 'MAX', 'MOD', 'SIGN')
            want = 2
        end select
        if (na /= want) then
            call fail(ps, name//' takes '//itoa(want)//' argument(s)')
            return
        end if
        select case (name)
        case ('SIN'); v = sin(a(1))
        case ('COS'); v = cos(a(1))
        case ('TAN'); v = tan(a(1))
        case ('CSC'); v = 1.0_dp/sin(a(1))
        case ('SEC'); v = 1.0_dp/cos(a(1))
        case ('CTN'); v = 1.0_dp/tan(a(1))
        case ('ASIN'); v = asin(a(1))
        case ('ACOS'); v = acos(a(1))
        case ('ATAN'); v = atan(a(1))
        case ('ATAN2'); v = atan2(a(1), a(2))
        case ('SINH'); v = sinh(a(1))
        case ('COSH'); v = cosh(a(1))
        case ('TANH'); v = tanh(a(1))
        case ('ASINH'); v = asinh(a(1))
        case ('ACOSH'); v = acosh(a(1))
        case ('ATANH'); v = atanh(a(1))
        case ('MIN'); v = min(a(1), a(2))
        case ('MAX'); v = max(a(1), a(2))
        case ('MOD')
            if (a(2) == 0.0_dp) then
                call fail(ps, 'MOD by zero')
                return
            end if
            v = mod(a(1), a(2))
        case ('SIGN'); v = sign(a(1), a(2))
        case ('ABS'); v = abs(a(1))
        case ('SQRT')
            if (a(1) < 0.0_dp) then
                call fail(ps, 'SQRT of a negative number')
                return
            end if
            v = sqrt(a(1))
        case ('INT', 'AINT', 'LS_INTEGER'); v = aint(a(1))
        case ('NINT', 'ANINT'); v = anint(a(1))
        case ('REAL', 'LS_REAL'); v = a(1)
        case ('EXP'); v = exp(a(1))
        case ('LOG', 'LOG10')
            if (.not. (a(1) > 0.0_dp)) then
                call fail(ps, name//' of a number that is not positive')
                return
            end if
            if (name == 'LOG') then
                v = log(a(1))
            else
                v = log10(a(1))
            end if
        case default
            call fail(ps, 'unknown function '''//name//'''')
        end select
    end function apply

    subroutine expect(ps, c)
        type(parser_t), intent(inout) :: ps
        character, intent(in) :: c
        if (len(ps%msg) > 0) return
        call skip_blanks(ps)
        if (ps%p <= len(ps%s)) then
            if (ps%s(ps%p:ps%p) == c) then
                ps%p = ps%p + 1
                return
            end if
        end if
        call fail(ps, ''''//c//''' expected')
    end subroutine expect

    subroutine skip_blanks(ps)
        type(parser_t), intent(inout) :: ps
        do while (ps%p <= len(ps%s))
            if (ps%s(ps%p:ps%p) /= ' ') exit
            ps%p = ps%p + 1
        end do
    end subroutine skip_blanks

    subroutine fail(ps, what)
        type(parser_t), intent(inout) :: ps
        character(len=*), intent(in) :: what
        if (len(ps%msg) > 0) return
        ps%msg = what//' (at character '//itoa(min(ps%p, len(ps%s) + 1))//' of '''//ps%s//''')'
        ps%p = len(ps%s) + 1
    end subroutine fail

end module xd_input_expression
