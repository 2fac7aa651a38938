!> Reads the fields of one card: fixed columns (10 wide unless the keyword says
!> otherwise; LONG and I10 widening), free format on commas, `&name` parameters,
!> Fortran-style numbers (touching fields, E-less exponents, D exponents).
!> Every error names file, line, keyword, card, field and the offending text,
!> and echoes the line with a caret under the field.
module xd_input_field_reader
    use, intrinsic :: iso_c_binding, only: c_char, c_double, c_ptr, c_null_ptr, c_null_char
    use xd_kinds, only: wp, dp, i8
    use xd_core_errors, only: error_t, make_error
    use xd_core_strings, only: to_upper, itoa
    implicit none
    private
    public :: card_format_t, card_format, card_t, param_table_t
    public :: width_standard, width_long, width_i10
    public :: split_card, get_real, get_int, get_text, field_blank, card_blank
    public :: parse_real, parse_int, card_error, card_where, max_card

    integer, parameter :: maxf = 16
    integer, parameter :: max_card = 400   !< longest card kept (LONG cards are 200)
    integer, parameter :: width_standard = 0, width_long = 1, width_i10 = 2
    !> 2^53, and the powers of ten exact in double precision (parse_real)
    integer(i8), parameter :: two53 = 9007199254740992_i8
    real(dp), parameter :: pow10(0:22) = [1.0e0_dp, 1.0e1_dp, 1.0e2_dp, 1.0e3_dp, 1.0e4_dp, 1.0e5_dp, 1.0e6_dp, &
                                          1.0e7_dp, 1.0e8_dp, 1.0e9_dp, 1.0e10_dp, 1.0e11_dp, 1.0e12_dp, 1.0e13_dp, &
                                          1.0e14_dp, 1.0e15_dp, 1.0e16_dp, 1.0e17_dp, 1.0e18_dp, 1.0e19_dp, 1.0e20_dp, &
                                          1.0e21_dp, 1.0e22_dp]

    interface
        !> C's correctly rounded decimal conversion; the text is validated first.
        pure function c_strtod(str, endptr) bind(c, name='strtod') result(d)
            import :: c_char, c_double, c_ptr
            character(kind=c_char), intent(in) :: str(64)
            type(c_ptr), value :: endptr
            real(c_double) :: d
        end function c_strtod
    end interface

    !> Field names and widths of one card layout.
    type :: card_format_t
        integer :: nfield = 0
        integer :: width(maxf) = 10
        character(len=8) :: name(maxf) = ''
    end type card_format_t

    !> `*PARAMETER` values: name (upper case), type letter, value text.
    type :: param_table_t
        integer :: n = 0
        character(len=32), allocatable :: name(:)
        character(len=1), allocatable :: ptype(:)
        character(len=80), allocatable :: value(:)
        character(len=256), allocatable :: scope(:)   !< '' global; else the file of a *PARAMETER_LOCAL
    contains
        procedure :: add => param_add
        procedure :: find => param_find
        procedure :: find_scoped => param_find_scoped
    end type param_table_t

    !> One card split into field texts, with what is needed to report on it.
    !> Fixed-length components: a deck has millions of cards, and allocating
    !> strings for each would dominate the reading time.
    type :: card_t
        integer :: nf = 0
        character(len=80) :: f(maxf) = ''
        integer :: col(maxf) = 1
        !> each field's length without its trailing blanks, and the card's:
        !> set with them (split_card, substitute), so that a blank test or a
        !> number's conversion does not scan 80 (400) padded characters
        integer :: flen(maxf) = 0
        integer :: tlen = 0
        character(len=8) :: name(maxf) = ''
        character(len=max_card) :: text = ''
        character(len=256) :: file = ''
        integer :: line = 0
        character(len=48) :: keyword = ''
        integer :: cardno = 0
    end type card_t

contains

    !> Layout from a spec such as 'NID:8 X:16 Y:16 Z:16 TC:8 RC:8' (width 10 if
    !> omitted), widened by the LONG (20) or I10 (10) rule.
    function card_format(spec, mode) result(fmt)
        character(len=*), intent(in) :: spec
        integer, intent(in), optional :: mode
        type(card_format_t) :: fmt
        integer :: p, q, k, w
        character(len=:), allocatable :: tok
        p = 1
        do
            do while (p <= len(spec))
                if (spec(p:p) /= ' ') exit
                p = p + 1
            end do
            if (p > len(spec)) exit
            q = index(spec(p:), ' ')
            if (q == 0) then
                q = len(spec)
            else
                q = p + q - 2
            end if
            tok = spec(p:q)
            p = q + 2
            fmt%nfield = fmt%nfield + 1
            k = index(tok, ':')
            w = 10
            if (k > 0) then
                read (tok(k + 1:), *) w
                tok = tok(1:k - 1)
            end if
            fmt%name(fmt%nfield) = tok
            fmt%width(fmt%nfield) = w
        end do
        if (present(mode)) then
            select case (mode)
            case (width_long)
                where (fmt%width < 20) fmt%width = 20
            case (width_i10)
                where (fmt%width < 10) fmt%width = 10
            end select
        end if
    end function card_format

    !> Split `text` by `fmt` (or on commas when it has one) into `card`,
    !> substituting `&name` parameters. `raw` cards (titles, file names) are one
    !> field, the whole line.
    subroutine split_card(text, file, line, keyword, cardno, fmt, params, card, error, raw)
        character(len=*), intent(in) :: text, file, keyword
        integer, intent(in) :: line, cardno
        type(card_format_t), intent(in) :: fmt
        type(param_table_t), intent(in) :: params
        !> (inout, every component set here: as intent(out) its default
        !> initialization wrote all 2.3 kB of it for each card read, then
        !> most again)
        type(card_t), intent(inout) :: card
        type(error_t), allocatable, intent(out) :: error
        logical, intent(in), optional :: raw
        integer :: i, p, q, w, k
        logical :: is_raw

        card%text = text
        card%tlen = min(len_trim(text), max_card)
        card%file = file
        card%line = line
        card%keyword = keyword
        card%cardno = cardno
        card%nf = fmt%nfield
        card%name(1:fmt%nfield) = fmt%name(1:fmt%nfield)
        card%name(fmt%nfield + 1:) = ''
        card%f = ''
        card%flen = 0
        card%col = 1
        is_raw = .false.
        if (present(raw)) is_raw = raw
        if (is_raw) then
            card%nf = 1
            card%f(1) = text
            card%flen(1) = len_trim(card%f(1))
            return
        end if

        if (has_comma(text)) then
            p = 1
            do i = 1, maxf
                q = index(text(p:), ',')
                if (q == 0) then
                    q = len(text) + 1
                else
                    q = p + q - 1
                end if
                if (i <= fmt%nfield) then
                    call put_field(i, p, q - 1)
                    card%col(i) = p
                else if (len_trim(text(p:q - 1)) > 0) then
                    call card_error(card, i, 'more fields than the card has ('// &
                                    itoa(fmt%nfield)//')', error, use_name=.false.)
                    return
                end if
                p = q + 1
                if (p > len(text) + 1) exit
            end do
        else
            p = 1
            do i = 1, fmt%nfield
                w = fmt%width(i)
                card%col(i) = p
                if (p <= len(text)) then
                    q = min(len(text), p + w - 1)
                    call put_field(i, p, q)
                end if
                p = p + w
            end do
        end if

        do i = 1, card%nf
            k = 0
            if (card%f(i)(1:1) == '&') k = 2
            if (card%f(i)(1:2) == '-&') k = 3
            if (k > 0) then
                call substitute(card, i, k, params, error)
                if (allocated(error)) return
            end if
        end do
    contains
        !> Field i from text(a:b) without its leading blanks (adjustl's
        !> value, cut to the field's 80 characters as an assignment cuts
        !> it), its length without trailing blanks with it: two scans of
        !> the field's own characters, no temporary.
        subroutine put_field(i, a, b)
            integer, intent(in) :: i, a, b
            integer :: lo, hi
            lo = a
            do while (lo <= b)
                if (iachar(text(lo:lo)) /= 32) exit
                lo = lo + 1
            end do
            hi = b
            do while (hi >= lo)
                if (iachar(text(hi:hi)) /= 32) exit
                hi = hi - 1
            end do
            if (hi < lo) return
            card%f(i) = text(lo:hi)
            card%flen(i) = hi - lo + 1
            ! (cut: the kept part's own trailing blanks)
            if (card%flen(i) > len(card%f(i))) card%flen(i) = len_trim(card%f(i))
        end subroutine put_field
    end subroutine split_card

    !> Does the text hold a comma (a free-format card)? A loop over its
    !> characters: the library's index() took 680 instructions a card.
    pure logical function has_comma(text)
        character(len=*), intent(in) :: text
        integer :: i
        has_comma = .false.
        do i = 1, len(text)
            if (text(i:i) == ',') then
                has_comma = .true.
                return
            end if
        end do
    end function has_comma

    subroutine substitute(card, i, k, params, error)
        type(card_t), intent(inout) :: card
        integer, intent(in) :: i, k
        type(param_table_t), intent(in) :: params
        type(error_t), allocatable, intent(out) :: error
        integer :: ip
        character(len=80) :: v
        ip = params%find_scoped(card%f(i)(k:), card%file)
        if (ip == 0) then
            call card_error(card, i, 'parameter '''//trim(card%f(i)(k:))//''' is not defined', error)
            return
        end if
        v = adjustl(params%value(ip))
        if (k == 3) then
            if (v(1:1) == '-') then
                v = v(2:)
            else if (v(1:1) == '+') then
                v = '-'//v(2:)
            else
                v = '-'//v(1:len(v) - 1)
            end if
        end if
        card%f(i) = v
        card%flen(i) = len_trim(card%f(i))
    end subroutine substitute

    logical function field_blank(card, i)
        type(card_t), intent(in) :: card
        integer, intent(in) :: i
        field_blank = .true.
        if (i <= card%nf) field_blank = card%flen(i) == 0
    end function field_blank

    !> 'file:line' of the card.
    function card_where(card) result(w)
        type(card_t), intent(in) :: card
        character(len=:), allocatable :: w
        w = trim(card%file)//':'//itoa(card%line)
    end function card_where

    logical function card_blank(card)
        type(card_t), intent(in) :: card
        card_blank = card%tlen == 0
    end function card_blank

    !> Real field i; blank gives `default`; with `zero_default`, 0 does too.
    subroutine get_real(card, i, x, default, error, zero_default)
        type(card_t), intent(in) :: card
        integer, intent(in) :: i
        real(wp), intent(out) :: x
        real(wp), intent(in) :: default
        type(error_t), allocatable, intent(out) :: error
        logical, intent(in), optional :: zero_default
        real(dp) :: v
        logical :: ok, outside
        x = default
        if (field_blank(card, i)) return
        call parse_real(card%f(i)(1:card%flen(i)), v, ok, outside)
        if (outside) then
            call card_error(card, i, ''''//trim(card%f(i))//''' is out of range', error)
            return
        end if
        if (.not. ok) then
            call card_error(card, i, ''''//trim(card%f(i))//''' is not a number', error)
            return
        end if
        ! beyond the working precision's range, or below its smallest normal
        ! number (a subnormal density or modulus is no physical value)
        if (abs(v) > real(huge(x), dp) .or. (v /= 0.0_dp .and. abs(v) < real(tiny(x), dp))) then
            call card_error(card, i, ''''//trim(card%f(i))//''' is out of range', error)
            return
        end if
        x = real(v, wp)
        if (present(zero_default)) then
            if (zero_default .and. x == 0.0_wp) x = default
        end if
    end subroutine get_real

    !> Integer field i; blank gives `default`; with `zero_default`, 0 does too.
    subroutine get_int(card, i, n, default, error, zero_default)
        type(card_t), intent(in) :: card
        integer, intent(in) :: i
        integer, intent(out) :: n
        integer, intent(in) :: default
        type(error_t), allocatable, intent(out) :: error
        logical, intent(in), optional :: zero_default
        logical :: ok
        n = default
        if (field_blank(card, i)) return
        call parse_int(card%f(i)(1:card%flen(i)), n, ok)
        if (.not. ok) then
            call card_error(card, i, ''''//trim(card%f(i))//''' is not an integer', error)
            n = default
            return
        end if
        if (present(zero_default)) then
            if (zero_default .and. n == 0) n = default
        end if
    end subroutine get_int

    function get_text(card, i) result(s)
        type(card_t), intent(in) :: card
        integer, intent(in) :: i
        character(len=:), allocatable :: s
        s = ''
        if (i <= card%nf) s = trim(card%f(i))
    end function get_text

    !> Fortran-style real: [sign] digits [. digits] [exponent], the exponent
    !> being [EeDd][sign]digits or sign digits (E-less, as in 2.00000-3).
    !> A value whose decimal exponent lies beyond double precision's normal
    !> range (above 1e307 or below 1e-307 in size, not zero) is not
    !> converted (the conversion would overflow, a trap in a debug build):
    !> ok is false and `out_of_range` true.
    !>
    !> The conversion: where the significant digits (at most 18) make an
    !> integer M no larger than 2^53 and the value is M x 10^e with |e| <= 22,
    !> it is M times or divided by 10^|e|, both exact in double precision,
    !> so that the one rounding of that operation gives the correctly
    !> rounded value (Clinger's fast path), which is what C's strtod gives;
    !> any other text goes to strtod. A deck's coordinates and ids almost
    !> all take the first way (strtod took 500 instructions a field).
    pure subroutine parse_real(s, x, ok, out_of_range)
        character(len=*), intent(in) :: s
        real(dp), intent(out) :: x
        logical, intent(out) :: ok
        logical, intent(out), optional :: out_of_range
        integer :: i, n, ndig, m, nint_sig, nlead, ex, exsign, nsig, fdig, d, e10
        integer(i8) :: mant
        logical :: nonzero, seen_nonzero, neg, exact
        character(kind=c_char) :: buf(64)
        x = 0.0_dp
        ok = .false.
        if (present(out_of_range)) out_of_range = .false.
        n = len_trim(s)
        if (n == 0 .or. n > 60) return
        m = 0
        i = 1
        neg = s(1:1) == '-'
        if (s(i:i) == '+' .or. s(i:i) == '-') call put(buf, m, i, s(i:i))
        ndig = 0
        nint_sig = 0          ! significant digits before the point
        nlead = 0             ! zeros after the point before the first nonzero digit
        seen_nonzero = .false.
        ! (M: the significant digits, nsig of them; fdig: the digits after
        ! the point taken into M; exact: M holds every significant digit)
        mant = 0
        nsig = 0
        fdig = 0
        exact = .true.
        do while (i <= n)
            if (.not. is_digit(s(i:i))) exit
            ndig = ndig + 1
            if (s(i:i) /= '0') seen_nonzero = .true.
            if (seen_nonzero) nint_sig = nint_sig + 1
            if (seen_nonzero .and. exact) then
                ! (M takes the digit while it can hold it)
                d = ichar(s(i:i)) - ichar('0')
                nsig = nsig + 1
                exact = nsig <= 18
                if (exact) mant = 10*mant + d
            end if
            call put(buf, m, i, s(i:i))
        end do
        if (i <= n) then
            if (s(i:i) == '.') then
                call put(buf, m, i, '.')
                do while (i <= n)
                    if (.not. is_digit(s(i:i))) exit
                    ndig = ndig + 1
                    if (.not. seen_nonzero .and. s(i:i) == '0') nlead = nlead + 1
                    if (s(i:i) /= '0') seen_nonzero = .true.
                    if (exact) then
                        ! (after the point: the digit counts in fdig)
                        d = ichar(s(i:i)) - ichar('0')
                        if (mant > 0 .or. d > 0) nsig = nsig + 1
                        exact = nsig <= 18
                        if (exact) then
                            mant = 10*mant + d
                            fdig = fdig + 1
                        end if
                    end if
                    call put(buf, m, i, s(i:i))
                end do
            end if
        end if
        if (ndig == 0) return
        nonzero = seen_nonzero
        ex = 0
        if (i <= n) then
            select case (s(i:i))
            case ('e', 'E', 'd', 'D')
                i = i + 1
            case ('+', '-')
            case default
                return
            end select
            if (i > n) return
            m = m + 1
            buf(m) = 'e'
            exsign = 1
            if (s(i:i) == '-') exsign = -1
            if (s(i:i) == '+' .or. s(i:i) == '-') call put(buf, m, i, s(i:i))
            if (i > n) return
            do while (i <= n)
                if (.not. is_digit(s(i:i))) return
                if (ex < 100000) ex = 10*ex + (ichar(s(i:i)) - ichar('0'))
                call put(buf, m, i, s(i:i))
            end do
            ex = exsign*ex
        end if
        e10 = ex - fdig
        ! the decimal exponent of the leading significant digit
        if (nonzero) then
            if (nint_sig > 0) then
                ex = ex + nint_sig - 1
            else
                ex = ex - nlead - 1
            end if
            if (ex > 307 .or. ex < -307) then
                if (present(out_of_range)) out_of_range = .true.
                return
            end if
        end if
        if (exact .and. mant <= two53) then
            if (mant == 0) then
                x = 0.0_dp
            else if (e10 >= 0 .and. e10 <= 22) then
                x = real(mant, dp)*pow10(e10)
            else if (e10 < 0 .and. e10 >= -22) then
                x = real(mant, dp)/pow10(-e10)
            else
                exact = .false.
            end if
            if (exact) then
                if (neg) x = -x
                ok = x == x .and. abs(x) <= huge(x)
                return
            end if
        end if
        buf(m + 1) = c_null_char
        x = real(c_strtod(buf, c_null_ptr), dp)
        ok = x == x .and. abs(x) <= huge(x)
    end subroutine parse_real

    !> Append ch to the C buffer and step past it in the source text.
    pure subroutine put(buf, m, i, ch)
        character(kind=c_char), intent(inout) :: buf(64)
        integer, intent(inout) :: m, i
        character(len=1), intent(in) :: ch
        m = m + 1
        buf(m) = ch
        i = i + 1
    end subroutine put

    !> Integer: [sign] digits, or a real with an integral value (1. or 1.0E3).
    pure subroutine parse_int(s, n, ok)
        character(len=*), intent(in) :: s
        integer, intent(out) :: n
        logical, intent(out) :: ok
        real(dp) :: x
        integer :: i, k, nt
        integer(i8) :: v
        logical :: neg
        ! [sign] up to 9 digits: the value itself (what the conversion
        ! through a real gives, without it)
        n = 0
        nt = len_trim(s)
        k = 1
        neg = .false.
        if (nt > 0) then
            if (s(1:1) == '-' .or. s(1:1) == '+') then
                neg = s(1:1) == '-'
                k = 2
            end if
        end if
        if (nt >= k .and. nt - k < 9) then
            v = 0
            do i = k, nt
                if (.not. is_digit(s(i:i))) exit
                v = 10*v + (ichar(s(i:i)) - ichar('0'))
            end do
            if (i > nt) then
                if (neg) v = -v
                n = int(v)
                ok = .true.
                return
            end if
        end if
        call parse_real(s, x, ok)
        if (.not. ok) return
        ok = x == aint(x) .and. abs(x) <= real(huge(n), dp)
        if (ok) n = nint(x)
    end subroutine parse_int

    pure logical function is_digit(c)
        character(len=1), intent(in) :: c
        is_digit = c >= '0' .and. c <= '9'
    end function is_digit

    !> Error on field i of `card`: 'file:line: *KW card N field NAME: text',
    !> then the line with a caret under the field.
    subroutine card_error(card, i, text, error, use_name)
        type(card_t), intent(in) :: card
        integer, intent(in) :: i
        character(len=*), intent(in) :: text
        type(error_t), allocatable, intent(out) :: error
        logical, intent(in), optional :: use_name
        character(len=:), allocatable :: msg, fname
        integer :: c
        fname = 'field '//itoa(i)
        if (i <= maxf) then
            if (len_trim(card%name(i)) > 0) fname = 'field '//trim(card%name(i))
        end if
        if (present(use_name)) then
            if (.not. use_name) fname = 'field '//itoa(i)
        end if
        msg = card_where(card)//': '//trim(card%keyword)//' card '//itoa(card%cardno)//' '//fname//': '//text
        c = 1
        if (i <= maxf) c = card%col(i)
        ! caret under the first non-blank character of the field
        do while (c < len_trim(card%text))
            if (card%text(c:c) /= ' ') exit
            c = c + 1
        end do
        msg = msg//new_line('a')//'    | '//trim(card%text)//new_line('a')//'    | '//repeat(' ', max(c - 1, 0))//'^'
        call make_error(error, msg)
    end subroutine card_error

    !> Define or redefine a parameter; `scope` (a file name) makes it local
    !> to that file (*PARAMETER_LOCAL), none makes it global.
    subroutine param_add(self, name, ptype, value, scope)
        class(param_table_t), intent(inout) :: self
        character(len=*), intent(in) :: name, ptype, value
        character(len=*), intent(in), optional :: scope
        character(len=32), allocatable :: tn(:)
        character(len=1), allocatable :: tt(:)
        character(len=80), allocatable :: tv(:)
        character(len=256), allocatable :: ts(:)
        character(len=256) :: sc
        integer :: k
        sc = ''
        if (present(scope)) sc = scope
        if (.not. allocated(self%name)) then
            allocate (self%name(16), self%ptype(16), self%value(16), self%scope(16))
        end if
        do k = 1, self%n
            if (self%name(k) == to_upper(adjustl(name)) .and. self%scope(k) == sc) exit
        end do
        if (k > self%n) then
            if (self%n == size(self%name)) then
                allocate (tn(2*self%n), tt(2*self%n), tv(2*self%n), ts(2*self%n))
                tn(1:self%n) = self%name(1:self%n)
                tt(1:self%n) = self%ptype(1:self%n)
                tv(1:self%n) = self%value(1:self%n)
                ts(1:self%n) = self%scope(1:self%n)
                call move_alloc(tn, self%name)
                call move_alloc(tt, self%ptype)
                call move_alloc(tv, self%value)
                call move_alloc(ts, self%scope)
            end if
            self%n = self%n + 1
            k = self%n
        end if
        self%name(k) = to_upper(adjustl(name))
        self%ptype(k) = to_upper(ptype)
        self%value(k) = adjustl(value)
        self%scope(k) = sc
    end subroutine param_add

    !> A global parameter.
    integer function param_find(self, name) result(k)
        class(param_table_t), intent(in) :: self
        character(len=*), intent(in) :: name
        k = self%find_scoped(name, '')
    end function param_find

    !> The parameter seen from file `scope`: its local one if it has one,
    !> else the global one; 0 if neither.
    integer function param_find_scoped(self, name, scope) result(k)
        class(param_table_t), intent(in) :: self
        character(len=*), intent(in) :: name, scope
        character(len=32) :: key
        integer :: i
        key = to_upper(adjustl(name))
        k = 0
        do i = 1, self%n
            if (self%name(i) /= key) cycle
            if (len_trim(self%scope(i)) > 0) then
                if (self%scope(i) == scope) then
                    k = i
                    return
                end if
            else
                k = i
            end if
        end do
    end function param_find_scoped

end module xd_input_field_reader
