!> Readers for curves, loads and rigid walls: *DEFINE_CURVE, *LOAD_BODY_X/Y/Z,
!> *RIGIDWALL_PLANAR (_FINITE, _ID).
module xd_input_read_loads
    use xd_kinds, only: wp
    use xd_core_errors, only: error_t, make_error
    use xd_core_strings, only: itoa, to_upper
    use xd_input_field_reader, only: card_t, card_format_t, card_format, get_int, get_real, get_text, &
                                     card_error, card_blank
    use xd_input_keyword_table, only: keyword_t
    use xd_input_context, only: get_id_card, read_ctx_t, get_card, first_card, no_more_cards, add_warning, ignored_fields
    use xd_model, only: model_t, curve_t, body_load_t, rigidwall_t, segment_set_t, pressure_t, box_t, find_box, &
                        coord_t, find_coord
    implicit none
    private
    public :: read_load

contains

    subroutine read_load(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        select case (kw%name)
        case ('DEFINE_CURVE')
            call read_curve(ctx, kw, model, error)
        case ('LOAD_BODY_X', 'LOAD_BODY_Y', 'LOAD_BODY_Z')
            call read_body(ctx, kw, model, error)
        case ('RIGIDWALL_PLANAR', 'RIGIDWALL_PLANAR_FINITE', 'RIGIDWALL_PLANAR_MOVING', &
              'RIGIDWALL_PLANAR_FINITE_MOVING', 'RIGIDWALL_PLANAR_FORCES', 'RIGIDWALL_PLANAR_FINITE_FORCES', &
              'RIGIDWALL_PLANAR_MOVING_FORCES', 'RIGIDWALL_PLANAR_FINITE_MOVING_FORCES')
            call read_wall(ctx, kw, model, error)
        case ('DEFINE_BOX')
            call read_box(ctx, kw, model, error)
        case ('DEFINE_COORDINATE_SYSTEM', 'DEFINE_COORDINATE_NODES')
            call read_coord(ctx, kw, model, error)
        case ('RIGIDWALL_GEOMETRIC_CYLINDER')
            call read_cylinder(ctx, kw, model, error)
        case ('SET_SEGMENT', 'SET_SEGMENT_GENERAL')
            call read_segment_set(ctx, kw, model, error)
        case ('LOAD_SEGMENT', 'LOAD_SEGMENT_SET', 'LOAD_SHELL_ELEMENT', 'LOAD_SHELL_SET')
            call read_pressure(ctx, kw, model, error)
        end select
    end subroutine read_load

    !> Card 1 SID DA1..DA4; then N1 N2 N3 N4 A1..A4 per segment (N3 = N4: triangle).
    subroutine read_segment_set(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(card_format_t) :: fmt
        type(segment_set_t) :: ss
        integer :: ic, k, nd(4)
        ic = first_card(kw)
        if (ic > kw%ncard) return
        call get_card(ctx, kw, ic, 'SID DA1 DA2 DA3 DA4', 1, card, error)
        if (allocated(error)) return
        call ignored_fields(model, card, [2, 3, 4, 5], 'segment attributes are not used; ignored')
        call get_int(card, 1, ss%id, 0, error); if (allocated(error)) return
        if (ss%id <= 0) then
            call card_error(card, 1, 'set id must be a positive integer', error); return
        end if
        ss%src = kw%card_line(ic)
        allocate (ss%seg(4, max(kw%ncard - ic, 1)))
        if (kw%name == 'SET_SEGMENT_GENERAL') then
            ! OPTION E1..E7 cards, resolved once elements and parts are known
            allocate (ss%rule_op(max(kw%ncard - ic, 1)), ss%rule_val(8, max(kw%ncard - ic, 1)), &
                      ss%rule_line(max(kw%ncard - ic, 1)))
            ss%rule_val = 0
            do ic = ic + 1, kw%ncard
                call get_card(ctx, kw, ic, 'OPTION E1 E2 E3 E4 E5 E6 E7', 2, card, error)
                if (allocated(error)) return
                if (card_blank(card)) cycle
                ss%nrule = ss%nrule + 1
                ss%rule_op(ss%nrule) = to_upper(get_text(card, 1))
                ss%rule_line(ss%nrule) = kw%card_line(ic)
                do k = 1, 7
                    call get_int(card, k + 1, ss%rule_val(k, ss%nrule), 0, error); if (allocated(error)) return
                end do
            end do
            ss%n = 0
            if (.not. allocated(model%segset)) allocate (model%segset(4))
            if (model%nsegset == size(model%segset)) model%segset = [model%segset, model%segset]
            model%nsegset = model%nsegset + 1
            model%segset(model%nsegset) = ss
            return
        end if
        fmt = card_format('N1 N2 N3 N4 A1 A2 A3 A4', kw%width_mode)
        do ic = ic + 1, kw%ncard
            call get_card(ctx, kw, ic, fmt, 2, card, error)
            if (allocated(error)) return
            if (card_blank(card)) cycle
            call ignored_fields(model, card, [5, 6, 7, 8], 'segment attributes are not used; ignored')
            do k = 1, 4
                call get_int(card, k, nd(k), 0, error); if (allocated(error)) return
            end do
            if (nd(4) == 0) nd(4) = nd(3)
            if (any(nd <= 0)) then
                call card_error(card, minloc(nd, 1), 'segment nodes must be positive ids', error); return
            end if
            ss%n = ss%n + 1
            ss%seg(:, ss%n) = nd
        end do
        ss%seg = ss%seg(:, 1:ss%n)
        if (.not. allocated(model%segset)) allocate (model%segset(4))
        if (model%nsegset == size(model%segset)) model%segset = [model%segset, model%segset]
        model%nsegset = model%nsegset + 1
        model%segset(model%nsegset) = ss
    end subroutine read_segment_set

    !> *LOAD_SEGMENT: LCID SF AT N1 N2 N3 N4 (repeated); *LOAD_SEGMENT_SET: SSID LCID SF AT.
    subroutine read_pressure(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(pressure_t) :: pr
        integer :: ic, k, j
        do ic = first_card(kw), kw%ncard
            select case (kw%name)
            case ('LOAD_SEGMENT')
                call get_card(ctx, kw, ic, 'LCID SF AT N1 N2 N3 N4', 1, card, error)
            case ('LOAD_SEGMENT_SET')
                call get_card(ctx, kw, ic, 'SSID LCID SF AT', 1, card, error)
            case ('LOAD_SHELL_ELEMENT')
                call get_card(ctx, kw, ic, 'EID LCID SF AT', 1, card, error)
            case default
                call get_card(ctx, kw, ic, 'ESID LCID SF AT', 1, card, error)
            end select
            if (allocated(error)) return
            if (card_blank(card)) cycle
            pr = pressure_t(src=kw%card_line(ic))
            j = 0
            if (kw%name /= 'LOAD_SEGMENT') then
                call get_int(card, 1, k, 0, error); if (allocated(error)) return
                if (k <= 0) then
                    call card_error(card, 1, 'an id is required', error); return
                end if
                select case (kw%name)
                case ('LOAD_SEGMENT_SET'); pr%ssid = k
                case ('LOAD_SHELL_ELEMENT'); pr%shell_eid = k
                case default; pr%shell_set = k
                end select
                j = 1
            end if
            call get_int(card, j + 1, pr%lcid, 0, error); if (allocated(error)) return
            call get_real(card, j + 2, pr%sf, 1.0_wp, error, zero_default=.true.); if (allocated(error)) return
            call get_real(card, j + 3, pr%at, 0.0_wp, error); if (allocated(error)) return
            if (pr%lcid <= 0) then
                call card_error(card, j + 1, 'a load curve id is required', error); return
            end if
            if (kw%name == 'LOAD_SEGMENT') then
                do k = 1, 4
                    call get_int(card, 3 + k, pr%seg(k), 0, error); if (allocated(error)) return
                end do
                if (pr%seg(4) == 0) pr%seg(4) = pr%seg(3)
                if (any(pr%seg <= 0)) then
                    call card_error(card, 3 + minloc(pr%seg, 1), 'segment nodes must be positive ids', error)
                    return
                end if
            end if
            if (.not. allocated(model%press)) allocate (model%press(8))
            if (model%npress == size(model%press)) model%press = [model%press, model%press]
            model%npress = model%npress + 1
            model%press(model%npress) = pr
        end do
    end subroutine read_pressure

    !> Card 1 NSID NSIDEX BOXID BIRTH DEATH; card 2 XT YT ZT XH YH ZH FRIC;
    !> card 3 RADCYL LENCYL NSEGS. Nodes are kept outside the cylinder whose
    !> axis runs from the tail towards the head for LENCYL; LENCYL = 0 is a
    !> cylinder of infinite length both ways (LS-DYNA's meaning). _DISPLAY
    !> adds a card PID RO E PR for the wall's picture, which xdyna does not draw.
    subroutine read_cylinder(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(rigidwall_t) :: w
        integer :: ic, nsegs
        ic = first_card(kw)
        call read_wall_id(ctx, kw, w, error); if (allocated(error)) return
        if (ic + 2 > kw%ncard) then
            call make_error(error, ctx%src%where(kw%kw_line)//': '//trim(kw%written)//' needs cards 1 to 3')
            return
        end if
        call get_card(ctx, kw, ic, 'NSID NSIDEX BOXID BIRTH DEATH', 1, card, error)
        if (allocated(error)) return
        call get_int(card, 1, w%nsid, 0, error); if (allocated(error)) return
        call get_int(card, 2, w%nsidex, 0, error); if (allocated(error)) return
        call get_int(card, 3, w%boxid, 0, error); if (allocated(error)) return
        call get_real(card, 4, w%birth, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 5, w%death, 1.0e20_wp, error, zero_default=.true.); if (allocated(error)) return
        w%src = kw%card_line(ic)
        call read_wall_axis(ctx, kw, ic + 1, 'XT YT ZT XH YH ZH FRIC', w, card, error)
        if (allocated(error)) return
        call get_card(ctx, kw, ic + 2, 'RADCYL LENCYL NSEGS', 3, card, error)
        if (allocated(error)) return
        call get_real(card, 1, w%radius, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 2, w%length, 0.0_wp, error); if (allocated(error)) return
        call get_int(card, 3, nsegs, 0, error); if (allocated(error)) return
        if (.not. (w%radius > 0.0_wp)) then
            call card_error(card, 1, 'the radius must be positive', error); return
        end if
        if (w%length < 0.0_wp) then
            call card_error(card, 2, 'LENCYL must not be negative (0: infinite length)', error); return
        end if
        if (nsegs /= 0) then
            call card_error(card, 3, 'a cylinder of varying radius (NSEGS > 0) is not supported', error); return
        end if
        if (index(kw%written, '_DISPLAY') > 0 .and. ic + 3 <= kw%ncard) then
            call get_card(ctx, kw, ic + 3, 'PID RO E PR', 4, card, error)
            if (allocated(error)) return
            call ignored_fields(model, card, [1, 2, 3, 4], 'the wall''s picture (display part) is not drawn; ignored')
            ic = ic + 1
        end if
        w%cylinder = .true.
        if (.not. allocated(model%wall)) allocate (model%wall(4))
        if (model%nwall == size(model%wall)) model%wall = [model%wall, model%wall]
        model%nwall = model%nwall + 1
        if (w%id == 0) w%id = model%nwall
        model%wall(model%nwall) = w
        call no_more_cards(ctx, kw, ic + 3, error)
    end subroutine read_cylinder

    !> The ID/HEADING card of the _ID option.
    subroutine read_wall_id(ctx, kw, w, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(rigidwall_t), intent(inout) :: w
        type(error_t), allocatable, intent(out) :: error
        if (.not. kw%has_id) return
        call get_id_card(ctx, kw, w%id, w%heading, error)
    end subroutine read_wall_id

    !> Card 2 of the rigid walls: tail, head (the unit normal or axis from
    !> tail to head) and FRIC; returns the card for further fields.
    subroutine read_wall_axis(ctx, kw, ic, spec, w, card, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        integer, intent(in) :: ic
        character(len=*), intent(in) :: spec
        type(rigidwall_t), intent(inout) :: w
        type(card_t), intent(out) :: card
        type(error_t), allocatable, intent(out) :: error
        real(wp) :: head(3)
        integer :: k
        call get_card(ctx, kw, ic, spec, 2, card, error)
        if (allocated(error)) return
        do k = 1, 3
            call get_real(card, k, w%tail(k), 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 3 + k, head(k), 0.0_wp, error); if (allocated(error)) return
        end do
        call get_real(card, 7, w%fric, 0.0_wp, error); if (allocated(error)) return
        w%normal = head - w%tail
        if (norm2(w%normal) <= 0.0_wp) then
            call card_error(card, 4, 'the head point equals the tail: no normal or axis', error); return
        end if
        w%normal = w%normal/norm2(w%normal)
        if (w%fric < 0.0_wp .or. w%fric > 1.0_wp) then
            call card_error(card, 7, 'FRIC must lie in [0, 1] (welding, 2 and 3, is not implemented)', error); return
        end if
    end subroutine read_wall_axis

    !> *DEFINE_COORDINATE_SYSTEM: CID XO YO ZO XL YL ZL CIDL; XP YP ZP (local
    !> x from O to L, the x-y plane through P). *DEFINE_COORDINATE_NODES:
    !> CID N1 N2 N3 FLAG DIR (x from N1 to N2, the x-y plane through N3, at
    !> t = 0). Refused: CIDL (nested systems), FLAG 1 (axes moving with the
    !> nodes) and DIR other than X.
    subroutine read_coord(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(coord_t) :: c
        integer :: ic, k, cidl, flag
        character(len=:), allocatable :: dir
        ic = first_card(kw)
        if (ic > kw%ncard) then
            call make_error(error, ctx%src%where(kw%kw_line)//': '//trim(kw%written)//' needs its cards')
            return
        end if
        c%src = kw%card_line(ic)
        if (kw%name == 'DEFINE_COORDINATE_NODES') then
            call get_card(ctx, kw, ic, 'CID N1 N2 N3 FLAG DIR', 1, card, error)
            if (allocated(error)) return
            call get_int(card, 1, c%id, 0, error); if (allocated(error)) return
            do k = 1, 3
                call get_int(card, 1 + k, c%n(k), 0, error); if (allocated(error)) return
                if (c%n(k) <= 0) then
                    call card_error(card, 1 + k, 'node ids must be positive', error); return
                end if
            end do
            call get_int(card, 5, flag, 0, error); if (allocated(error)) return
            if (flag /= 0) then
                call card_error(card, 5, 'FLAG 1 (axes that follow the nodes) is not supported: the axes '// &
                                'are taken at t = 0 (FLAG 0)', error)
                return
            end if
            dir = get_text(card, 6)
            if (len(dir) > 0 .and. dir /= 'X' .and. dir /= 'x') then
                call card_error(card, 6, 'DIR '//dir//' is not supported (X: N1 to N2 is the local x axis)', error)
                return
            end if
            c%by_nodes = .true.
            ic = ic + 1
        else
            call get_card(ctx, kw, ic, 'CID XO YO ZO XL YL ZL CIDL', 1, card, error)
            if (allocated(error)) return
            call get_int(card, 1, c%id, 0, error); if (allocated(error)) return
            do k = 1, 3
                call get_real(card, 1 + k, c%o(k), 0.0_wp, error); if (allocated(error)) return
                call get_real(card, 4 + k, c%l(k), 0.0_wp, error); if (allocated(error)) return
            end do
            call get_int(card, 8, cidl, 0, error); if (allocated(error)) return
            if (cidl /= 0) then
                call card_error(card, 8, 'a system defined in another local system (CIDL) is not supported', error)
                return
            end if
            if (ic + 1 > kw%ncard) then
                call make_error(error, ctx%src%where(kw%kw_line)//': '//trim(kw%written)//' card 2 (XP YP ZP) is missing')
                return
            end if
            call get_card(ctx, kw, ic + 1, 'XP YP ZP', 2, card, error)
            if (allocated(error)) return
            do k = 1, 3
                call get_real(card, k, c%p(k), 0.0_wp, error); if (allocated(error)) return
            end do
            ic = ic + 2
        end if
        if (c%id <= 0) then
            call make_error(error, ctx%src%where(c%src)//': '//trim(kw%written)//' field CID: a positive id is needed')
            return
        end if
        if (find_coord(model, c%id) > 0) then
            call make_error(error, ctx%src%where(c%src)//': '//trim(kw%written)//' field CID: system '// &
                            itoa(c%id)//' is defined twice')
            return
        end if
        if (.not. allocated(model%coord)) allocate (model%coord(4))
        if (model%ncoord == size(model%coord)) model%coord = [model%coord, model%coord]
        model%ncoord = model%ncoord + 1
        model%coord(model%ncoord) = c
        call no_more_cards(ctx, kw, ic, error)
    end subroutine read_coord

    !> *DEFINE_BOX: BOXID XMN XMX YMN YMX ZMN ZMX.
    subroutine read_box(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(box_t) :: b
        integer :: ic, k
        ic = first_card(kw)
        if (ic > kw%ncard) then
            call make_error(error, ctx%src%where(kw%kw_line)//': '//trim(kw%written)//' needs its card')
            return
        end if
        call get_card(ctx, kw, ic, 'BOXID XMN XMX YMN YMX ZMN ZMX', 1, card, error)
        if (allocated(error)) return
        call get_int(card, 1, b%id, 0, error); if (allocated(error)) return
        if (b%id <= 0) then
            call card_error(card, 1, 'box id must be a positive integer', error); return
        end if
        if (find_box(model, b%id) > 0) then
            call card_error(card, 1, 'box '//trim(card%f(1))//' is defined twice', error); return
        end if
        do k = 1, 3
            call get_real(card, 2*k, b%lo(k), 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 2*k + 1, b%hi(k), 0.0_wp, error); if (allocated(error)) return
            if (b%hi(k) < b%lo(k)) then
                call card_error(card, 2*k + 1, 'the box''s upper bound is below its lower bound', error); return
            end if
        end do
        b%src = kw%card_line(ic)
        if (.not. allocated(model%box)) allocate (model%box(4))
        if (model%nbox == size(model%box)) model%box = [model%box, model%box]
        model%nbox = model%nbox + 1
        model%box(model%nbox) = b
        call no_more_cards(ctx, kw, ic + 1, error)
    end subroutine read_box

    !> Card 1 LCID SIDR SFA SFO OFFA OFFO DATTYP; then points A O (E20 each).
    !> Offsets first, then scales: a = SFA (A + OFFA), o = SFO (O + OFFO).
    subroutine read_curve(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(card_format_t) :: fmt
        type(curve_t) :: c
        real(wp) :: sfa, sfo, offa, offo, a, o
        integer :: ic, sidr, dattyp
        ic = first_card(kw)
        if (ic > kw%ncard) return
        call get_card(ctx, kw, ic, 'LCID SIDR SFA SFO OFFA OFFO DATTYP', 1, card, error)
        if (allocated(error)) return
        call get_int(card, 1, c%id, 0, error); if (allocated(error)) return
        call get_int(card, 2, sidr, 0, error); if (allocated(error)) return
        call get_real(card, 3, sfa, 1.0_wp, error, zero_default=.true.); if (allocated(error)) return
        call get_real(card, 4, sfo, 1.0_wp, error, zero_default=.true.); if (allocated(error)) return
        call get_real(card, 5, offa, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 6, offo, 0.0_wp, error); if (allocated(error)) return
        call get_int(card, 7, dattyp, 0, error); if (allocated(error)) return
        if (c%id <= 0) then
            call card_error(card, 1, 'curve id must be a positive integer', error); return
        end if
        if (sidr == 1) call add_warning(model, ctx%src%where(kw%card_line(ic))// &
            ': *DEFINE_CURVE field SIDR: dynamic relaxation is not implemented; the curve is used in the transient')
        if (dattyp /= 0) then
            call card_error(card, 7, 'DATTYP '//trim(card%f(7))//' is not supported (0 only)', error); return
        end if
        c%src = kw%card_line(ic)
        allocate (c%a(max(kw%ncard - ic, 1)), c%o(max(kw%ncard - ic, 1)))
        fmt = card_format('A:20 O:20', kw%width_mode)
        do ic = ic + 1, kw%ncard
            call get_card(ctx, kw, ic, fmt, 2, card, error)
            if (allocated(error)) return
            if (card_blank(card)) cycle
            call get_real(card, 1, a, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 2, o, 0.0_wp, error); if (allocated(error)) return
            c%n = c%n + 1
            c%a(c%n) = sfa*(a + offa)
            c%o(c%n) = sfo*(o + offo)
            if (c%n > 1) then
                if (.not. (c%a(c%n) > c%a(c%n - 1))) then
                    call card_error(card, 1, 'abscissae must increase (point '//trim(card%f(1))// &
                                    ' does not)', error)
                    return
                end if
            end if
        end do
        if (c%n < 1) then
            call make_error(error, ctx%src%where(kw%kw_line)//': *DEFINE_CURVE '//trim(get_text(card, 1))// &
                            ': the curve has no points')
            return
        end if
        c%a = c%a(1:c%n)
        c%o = c%o(1:c%n)
        if (.not. allocated(model%curve)) allocate (model%curve(8))
        if (model%ncurve == size(model%curve)) model%curve = [model%curve, model%curve]
        model%ncurve = model%ncurve + 1
        model%curve(model%ncurve) = c
    end subroutine read_curve

    !> LCID SF LCIDDR XC YC ZC CID.
    subroutine read_body(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(body_load_t) :: b
        integer :: ic, lciddr, cid
        ic = first_card(kw)
        if (ic > kw%ncard) return
        call get_card(ctx, kw, ic, 'LCID SF LCIDDR XC YC ZC CID', 1, card, error)
        if (allocated(error)) return
        call ignored_fields(model, card, [4, 5, 6], 'the centre of a rotational body load is not used; ignored')
        call get_int(card, 1, b%lcid, 0, error); if (allocated(error)) return
        call get_real(card, 2, b%sf, 1.0_wp, error, zero_default=.true.); if (allocated(error)) return
        call get_int(card, 3, lciddr, 0, error); if (allocated(error)) return
        call get_int(card, 7, cid, 0, error); if (allocated(error)) return
        if (b%lcid <= 0) then
            call card_error(card, 1, 'a load curve id is required', error); return
        end if
        b%cid = cid
        if (lciddr /= 0) call add_warning(model, ctx%src%where(kw%card_line(ic))//': '//trim(kw%written)// &
            ' field LCIDDR: dynamic relaxation is not implemented; ignored')
        b%dir = index('XYZ', kw%name(11:11))
        b%src = kw%card_line(ic)
        if (.not. allocated(model%body)) allocate (model%body(4))
        if (model%nbody == size(model%body)) model%body = [model%body, model%body]
        model%nbody = model%nbody + 1
        model%body(model%nbody) = b
        call no_more_cards(ctx, kw, ic + 1, error)
    end subroutine read_body

    !> Card 1 NSID NSIDEX BOXID OFFSET BIRTH DEATH RWKSF; card 2 XT YT ZT XH YH
    !> ZH FRIC WVEL; _FINITE adds XHEV YHEV ZHEV LENL LENM.
    subroutine read_wall(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(rigidwall_t) :: w
        real(wp) :: hev(3), rwksf, wvel
        integer :: ic, k, ssid
        ic = first_card(kw)
        call read_wall_id(ctx, kw, w, error); if (allocated(error)) return
        if (ic + 1 > kw%ncard) then
            call make_error(error, ctx%src%where(kw%kw_line)//': '//trim(kw%written)//' needs cards 1 and 2')
            return
        end if
        call get_card(ctx, kw, ic, 'NSID NSIDEX BOXID OFFSET BIRTH DEATH RWKSF', 1, card, error)
        if (allocated(error)) return
        call get_int(card, 1, w%nsid, 0, error); if (allocated(error)) return
        call get_int(card, 2, w%nsidex, 0, error); if (allocated(error)) return
        call get_int(card, 3, w%boxid, 0, error); if (allocated(error)) return
        call get_real(card, 4, w%offset, 0.0_wp, error); if (allocated(error)) return
        if (w%offset < 0.0_wp) then
            call card_error(card, 4, 'OFFSET must not be negative (0: every node of NSID/BOXID)', error); return
        end if
        call get_real(card, 5, w%birth, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 6, w%death, 1.0e20_wp, error, zero_default=.true.); if (allocated(error)) return
        call get_real(card, 7, rwksf, 1.0_wp, error, zero_default=.true.); if (allocated(error)) return
        if (rwksf /= 1.0_wp) call add_warning(model, ctx%src%where(kw%card_line(ic))//': '//trim(kw%written)// &
            ' field RWKSF: the wall is a stonewall (kinematic), not a penalty wall; the scale is ignored')
        w%src = kw%card_line(ic)
        call read_wall_axis(ctx, kw, ic + 1, 'XT YT ZT XH YH ZH FRIC WVEL', w, card, error)
        if (allocated(error)) return
        call get_real(card, 8, wvel, 0.0_wp, error); if (allocated(error)) return
        if (wvel /= 0.0_wp) call add_warning(model, ctx%src%where(kw%card_line(ic + 1))//': '// &
            trim(kw%written)//' field WVEL: the critical velocity for welding is not implemented; ignored')
        if (index(kw%name, '_FINITE') > 0) then
            if (ic + 2 > kw%ncard) then
                call make_error(error, ctx%src%where(kw%kw_line)//': '//trim(kw%written)// &
                                ' card 3 (XHEV YHEV ZHEV LENL LENM) is missing')
                return
            end if
            call get_card(ctx, kw, ic + 2, 'XHEV YHEV ZHEV LENL LENM', 3, card, error)
            if (allocated(error)) return
            do k = 1, 3
                call get_real(card, k, hev(k), 0.0_wp, error); if (allocated(error)) return
            end do
            call get_real(card, 4, w%lenl, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 5, w%lenm, 0.0_wp, error); if (allocated(error)) return
            w%l = hev - w%tail
            w%l = w%l - dot_product(w%l, w%normal)*w%normal
            if (norm2(w%l) <= 0.0_wp .or. w%lenl <= 0.0_wp .or. w%lenm <= 0.0_wp) then
                call card_error(card, 1, 'the edge vector must not be along the normal, and LENL, LENM '// &
                                'must be positive', error)
                return
            end if
            w%l = w%l/norm2(w%l)
            w%m = [w%normal(2)*w%l(3) - w%normal(3)*w%l(2), w%normal(3)*w%l(1) - w%normal(1)*w%l(3), &
                   w%normal(1)*w%l(2) - w%normal(2)*w%l(1)]
            w%finite = .true.
            ic = ic + 1
        end if
        if (index(kw%name, '_MOVING') > 0) then
            if (ic + 2 > kw%ncard) then
                call make_error(error, ctx%src%where(kw%kw_line)//': '//trim(kw%written)// &
                                ' card (MASS V0) is missing')
                return
            end if
            call get_card(ctx, kw, ic + 2, 'MASS V0', 3, card, error)
            if (allocated(error)) return
            call get_real(card, 1, w%mass, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 2, w%v0, 0.0_wp, error); if (allocated(error)) return
            if (.not. (w%mass > 0.0_wp)) then
                call card_error(card, 1, 'a moving wall needs a positive mass', error); return
            end if
            w%moving = .true.
            ic = ic + 1
        end if
        if (index(kw%name, '_FORCES') > 0) then
            ! SOFT SSID N1-N4: a segment set whose share of the wall force
            ! LS-DYNA writes to rwforc; the wall's total force is written
            if (ic + 2 <= kw%ncard) then
                call get_card(ctx, kw, ic + 2, 'SOFT SSID N1 N2 N3 N4', 3, card, error)
                if (allocated(error)) return
                call get_int(card, 2, ssid, 0, error); if (allocated(error)) return
                if (ssid /= 0 .or. .not. card_blank(card)) call add_warning(model, &
                    ctx%src%where(kw%card_line(ic + 2))//': '//trim(kw%written)//' fields SOFT SSID N1-N4: '// &
                    'the force on a segment set is not written; rwforc has the whole wall''s force')
                ic = ic + 1
            end if
            w%forces = .true.
        end if
        if (.not. allocated(model%wall)) allocate (model%wall(4))
        if (model%nwall == size(model%wall)) model%wall = [model%wall, model%wall]
        model%nwall = model%nwall + 1
        if (w%id == 0) w%id = model%nwall
        model%wall(model%nwall) = w
        call no_more_cards(ctx, kw, ic + 2, error)
    end subroutine read_wall

end module xd_input_read_loads
