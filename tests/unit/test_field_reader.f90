!> The field reader against every format rule of KEYWORDS.md: fixed widths,
!> touching fields, values anywhere in the field, E-less and D exponents,
!> free format, LONG and I10 widths, parameters, defaults, and errors that
!> name the place and the text.
program test_field_reader
    use xd_kinds, only: wp, dp
    use xd_core_errors, only: error_t
    use xd_testing, only: check, check_close, test_summary
    use xd_input_field_reader, only: card_format_t, card_format, card_t, param_table_t, split_card, &
                                     get_real, get_int, get_text, field_blank, parse_real, parse_int, &
                                     width_standard, width_long, width_i10
    use, intrinsic :: iso_c_binding, only: c_char, c_double, c_ptr, c_null_ptr, c_null_char
    use, intrinsic :: iso_fortran_env, only: int64
    use xd_core_strings, only: itoa
    implicit none
    type(param_table_t) :: params
    type(card_t) :: card
    type(card_format_t) :: fmt
    type(error_t), allocatable :: error
    real(wp) :: x
    integer :: n
    integer(int64) :: seed   !< same_as_strtod's sequence

    ! numbers
    call real_ok('1.5', 1.5_dp)
    call real_ok('.01', 0.01_dp)
    call real_ok('5.', 5.0_dp)
    call real_ok('1.0e+20', 1.0e20_dp)
    call real_ok('1.0D0', 1.0_dp)
    call real_ok('2.00000-3', 2.0e-3_dp)
    call real_ok('-1.5+2', -150.0_dp)
    call real_ok('7', 7.0_dp)
    call real_ok('+3.25E-1', 0.325_dp)
    call real_bad('O.002')
    call real_bad('1.2.3')
    call real_bad('e5')
    call real_bad('1-')
    call real_bad('--1')
    call real_bad('1 2')
    call real_bad('.')
    call real_bad('1e')
    call int_ok('12', 12)
    call int_ok('-3', -3)
    call int_ok('1.', 1)
    call int_ok('2.0E1', 20)
    call int_bad('1.5')
    call int_bad('abc')
    call int_bad('2147483648')
    call int_ok('-2147483647', -2147483647)
    call int_ok('+000000042', 42)
    call int_ok('-0', 0)

    ! the conversion bit for bit C's strtod (parse_real's own path for up to
    ! 18 significant digits within 10^+-22, strtod's beyond), over texts
    ! made to cross each of the fast path's bounds: 1 to 20 digits, the
    ! point anywhere, exponents -40 to 40, leading zeros, both signs
    call same_as_strtod()

    ! fixed fields that touch, values anywhere in their field
    fmt = card_format('A B')
    call split('       0.01.00000E20', fmt, card)
    call get_real(card, 1, x, -1.0_wp, error)
    call check(.not. allocated(error) .and. x == 0.0_wp, 'touching fields: first is 0.0')
    call get_real(card, 2, x, -1.0_wp, error)
    call check(.not. allocated(error) .and. x == 1.0e20_wp, 'touching fields: second is 1e20')
    call split('         1-15640.000', fmt, card)
    call get_int(card, 1, n, -1, error)
    call check(n == 1, 'touching integer and negative real: 1')
    call get_real(card, 2, x, -1.0_wp, error)
    call check(x == -15640.0_wp, 'touching integer and negative real: -15640')
    fmt = card_format('ID HEADING:70')
    call split('1         title', fmt, card)
    call get_int(card, 1, n, -1, error)
    call check(n == 1 .and. get_text(card, 2) == 'title', 'left-justified id then a heading')

    ! blank = default, 0 = default where asked, short line = trailing defaults
    fmt = card_format('A B C D')
    call split('       2.5          ', fmt, card)
    call get_real(card, 2, x, 9.0_wp, error)
    call check(x == 9.0_wp, 'blank field takes the default')
    call get_real(card, 4, x, 7.0_wp, error)
    call check(x == 7.0_wp, 'field past the end of a short line takes the default')
    call split('         0', fmt, card)
    call get_real(card, 1, x, 0.9_wp, error, zero_default=.true.)
    call check(x == 0.9_wp, 'zero means default where the manual says so')

    ! *NODE widths, LONG=Y and I10
    fmt = card_format('NID:8 X:16 Y:16 Z:16 TC:8 RC:8')
    call split('      12'//'1.5000000000e+00'//'            -2.5'//'             3.0'//'       7'//'       0', fmt, card)
    call get_int(card, 1, n, 0, error)
    call check(n == 12, '*NODE I8 id')
    call get_real(card, 3, x, 0.0_wp, error)
    call check(x == -2.5_wp, '*NODE E16 coordinate')
    call get_int(card, 5, n, 0, error)
    call check(n == 7, '*NODE I8 constraint code')
    fmt = card_format('NID:8 X:16 Y:16 Z:16 TC:8 RC:8', width_long)
    call check(all(fmt%width(1:6) == 20), 'LONG=Y widens every field to 20')
    call split(repeat(' ', 18)//'42'//repeat(' ', 17)//'1.5', fmt, card)
    call get_int(card, 1, n, 0, error)
    call get_real(card, 2, x, 0.0_wp, error)
    call check(n == 42 .and. x == 1.5_wp, 'long-format node card read')
    fmt = card_format('NID:8 X:16 Y:16 Z:16 TC:8 RC:8', width_i10)
    call check(fmt%width(1) == 10 .and. fmt%width(2) == 16, 'I10=Y widens I8 fields to 10 only')

    ! free format
    fmt = card_format('A B C D E')
    call split(' 1, 2.5 ,, 4', fmt, card)
    call get_int(card, 1, n, 0, error)
    call check(n == 1, 'free format: first field')
    call get_real(card, 2, x, 0.0_wp, error)
    call check(x == 2.5_wp, 'free format: spaces around a value')
    call get_real(card, 3, x, 8.0_wp, error)
    call check(x == 8.0_wp, 'free format: empty slot takes the default')
    call get_real(card, 4, x, 0.0_wp, error)
    call check(x == 4.0_wp, 'free format: fourth field')
    call check(field_blank(card, 5), 'free format: fewer fields than the card has')
    call split_card('1,2,3,4,5,6', 'deck.k', 9, '*X', 1, fmt, params, card, error)
    call check(allocated(error), 'free format: more fields than the card has is an error')

    ! parameters
    call params%add('VEL', 'R', '12.5')
    call params%add('nel', 'I', '40')
    fmt = card_format('A B C')
    call split('      &VEL    -&vel      &NEL', fmt, card)
    call get_real(card, 1, x, 0.0_wp, error)
    call check(x == 12.5_wp, 'parameter &name substituted')
    call get_real(card, 2, x, 0.0_wp, error)
    call check(x == -12.5_wp, 'parameter -&name negated, names case-insensitive')
    call get_int(card, 3, n, 0, error)
    call check(n == 40, 'integer parameter substituted')
    call split_card('    &UNDEF', 'deck.k', 3, '*MAT_ELASTIC', 1, card_format('MID RO'), params, card, error)
    call check(allocated(error), 'undefined parameter is an error')
    if (allocated(error)) call check(index(error%message, 'UNDEF') > 0 .and. index(error%message, 'deck.k:3') > 0, &
                                     'undefined parameter error names it and the line')

    ! errors name file, line, keyword, card, field and text
    fmt = card_format('T1 T2 T3 T4')
    call split_card('     O.002', 'deck.k', 1204, '*SECTION_SHELL', 2, fmt, params, card, error)
    call get_real(card, 1, x, 0.0_wp, error)
    call check(allocated(error), 'bad number is an error')
    if (allocated(error)) then
        call check(index(error%message, "deck.k:1204: *SECTION_SHELL card 2 field T1: 'O.002' is not a number") == 1, &
                   'error message names file:line, keyword, card, field, text', error%message)
        call check(index(error%message, '^') > 0, 'error message shows a caret under the field')
    end if
    fmt = card_format('NID X Y')
    call split_card('       1.5', 'a.k', 7, '*NODE', 1, fmt, params, card, error)
    call get_int(card, 1, n, 0, error)
    call check(allocated(error), 'non-integral value in an integer field is an error')
    if (allocated(error)) call check(index(error%message, "field NID: '1.5' is not an integer") > 0, &
                                     'integer error names the field', error%message)
    call test_summary()

contains

    subroutine same_as_strtod()
        interface
            function c_strtod(str, endptr) bind(c, name='strtod') result(d)
                import :: c_char, c_double, c_ptr
                character(kind=c_char), intent(in) :: str(*)
                type(c_ptr), value :: endptr
                real(c_double) :: d
            end function c_strtod
        end interface
        character(len=40) :: t
        character(kind=c_char) :: cs(41)
        integer :: k, nd, pt, ex, j, nbad, nfast, nlz
        real(dp) :: v, w
        logical :: ok
        character(len=*), parameter :: fixed(12) = [character(len=24) :: '9007199254740992', &
            '9007199254740993', '1e22', '1e23', '0.1', '123456789012345678', '1234567890123456789', &
            '-0.0', '4.9e-324', '2.2250738585072014e-308', '0.000000000000000000001', '1797693134862315.7e293']
        seed = 12345_int64
        nbad = 0
        nfast = 0
        do k = 1, 200000 + size(fixed)
            if (k <= size(fixed)) then
                t = fixed(k)
            else
                nd = 1 + next(20)
                pt = next(nd + 1)
                nlz = next(3)
                t = ''
                if (next(2) == 1) t = '-'
                do j = 1, nlz
                    t = trim(t)//'0'
                end do
                do j = 1, nd
                    if (j == pt + 1) t = trim(t)//'.'
                    t = trim(t)//achar(iachar('0') + next(10))
                end do
                if (next(3) > 0) then
                    ex = next(81) - 40
                    write (t(len_trim(t) + 1:), '(a,i0)') 'e', ex
                end if
            end if
            call parse_real(trim(t), v, ok)
            if (.not. ok) cycle
            cs = c_null_char
            do j = 1, len_trim(t)
                cs(j) = t(j:j)
            end do
            w = c_strtod(cs, c_null_ptr)
            if (transfer(v, 1_int64) /= transfer(w, 1_int64)) then
                nbad = nbad + 1
                if (nbad <= 5) print '(a,a,a,es25.17,a,es25.17)', ' parse_real ', trim(t), ': ', v, ' strtod ', w
            end if
            nfast = nfast + 1
        end do
        call check(nbad == 0 .and. nfast > 190000, 'parse_real bit for bit strtod on '//itoa(nfast)//' texts')
        call parse_real('-0.0', v, ok)
        call check(ok .and. v == 0.0_dp .and. sign(1.0_dp, v) < 0.0_dp, '-0.0 keeps its sign')
    end subroutine same_as_strtod

    !> 0 .. n-1 from a 64-bit linear congruential sequence
    integer function next(n)
        integer, intent(in) :: n
        seed = seed*6364136223846793005_int64 + 1442695040888963407_int64
        next = int(modulo(ishft(seed, -33), int(n, int64)))
    end function next

    subroutine split(text, f, c)
        character(len=*), intent(in) :: text
        type(card_format_t), intent(in) :: f
        type(card_t), intent(out) :: c
        type(error_t), allocatable :: e
        call split_card(text, 'test.k', 1, '*TEST', 1, f, params, c, e)
        call check(.not. allocated(e), 'split '''//text//'''')
    end subroutine split

    subroutine real_ok(s, want)
        character(len=*), intent(in) :: s
        real(dp), intent(in) :: want
        real(dp) :: v
        logical :: ok
        call parse_real(s, v, ok)
        call check(ok .and. abs(v - want) <= 1.0e-14_dp*abs(want), 'number '''//s//''' reads')
    end subroutine real_ok

    subroutine real_bad(s)
        character(len=*), intent(in) :: s
        real(dp) :: v
        logical :: ok
        call parse_real(s, v, ok)
        call check(.not. ok, 'number '''//s//''' rejected')
    end subroutine real_bad

    subroutine int_ok(s, want)
        character(len=*), intent(in) :: s
        integer, intent(in) :: want
        integer :: v
        logical :: ok
        call parse_int(s, v, ok)
        call check(ok .and. v == want, 'integer '''//s//''' reads')
    end subroutine int_ok

    subroutine int_bad(s)
        character(len=*), intent(in) :: s
        integer :: v
        logical :: ok
        call parse_int(s, v, ok)
        call check(.not. ok, 'integer '''//s//''' rejected')
    end subroutine int_bad

end program test_field_reader
