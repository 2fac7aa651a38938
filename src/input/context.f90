!> What every keyword reader needs: the deck lines, the parameters, and the
!> helpers that turn card i of a keyword into fields.
module xd_input_context
    use xd_core_errors, only: error_t, make_error, printable
    use xd_core_strings, only: itoa
    use xd_input_deck_source, only: deck_source_t
    use xd_input_field_reader, only: card_format_t, card_t, param_table_t, split_card, card_format, card_blank, &
                                     width_long
    use xd_input_keyword_table, only: keyword_t
    use xd_model, only: model_t
    implicit none
    private
    public :: read_ctx_t, get_card, first_card, add_warning, extra_card_error, no_more_cards, ignored_fields, &
              get_id_card

    type :: read_ctx_t
        type(deck_source_t) :: src
        type(param_table_t) :: params
        logical :: warn_unsupported = .false.
    end type read_ctx_t

    !> Card `icard` (1-based among the keyword's cards) split by a layout given
    !> as a spec string ('NID:8 X:16 ...') or, in loops over many cards, as a
    !> card_format_t built once. `cardno` is the card's number in the manual.
    interface get_card
        module procedure get_card_spec, get_card_fmt
    end interface get_card

contains

    subroutine get_card_spec(ctx, kw, icard, spec, cardno, card, error, raw)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        integer, intent(in) :: icard, cardno
        character(len=*), intent(in) :: spec
        type(card_t), intent(inout) :: card
        type(error_t), allocatable, intent(out) :: error
        logical, intent(in), optional :: raw
        call get_card_fmt(ctx, kw, icard, card_format(spec, kw%width_mode), cardno, card, error, raw)
    end subroutine get_card_spec

    subroutine get_card_fmt(ctx, kw, icard, fmt, cardno, card, error, raw)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        integer, intent(in) :: icard, cardno
        type(card_format_t), intent(in) :: fmt
        type(card_t), intent(inout) :: card
        type(error_t), allocatable, intent(out) :: error
        logical, intent(in), optional :: raw
        integer :: ln, f
        ln = kw%card_line(icard)
        f = ctx%src%lfile(ln)
        call split_card(ctx%src%files(f)%text(ctx%src%lstart(ln):ctx%src%lstart(ln) + ctx%src%llen(ln) - 1), &
                        ctx%src%files(f)%name, ctx%src%lnum(ln), kw%written, cardno, fmt, ctx%params, card, &
                        error, raw)
    end subroutine get_card_fmt

    !> Index of the first data card: after the _TITLE or _ID card if present.
    integer function first_card(kw)
        type(keyword_t), intent(in) :: kw
        first_card = 1
        if (kw%title .or. kw%has_id) first_card = 2
    end function first_card

    subroutine add_warning(model, text)
        type(model_t), intent(inout) :: model
        character(len=*), intent(in) :: text
        model%nwarn = model%nwarn + 1
        if (.not. allocated(model%warnings)) model%warnings = ''
        model%warnings = model%warnings//' *** Warning: '//printable(text)//new_line('a')
    end subroutine add_warning

    !> The ID/heading card of an _ID option: ID (I10, I20 in long format),
    !> then the heading as text; a comma within the ID field makes the card
    !> free format (ID, heading). The heading may hold commas and blanks.
    subroutine get_id_card(ctx, kw, id, heading, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        integer, intent(out) :: id
        character(len=*), intent(out) :: heading
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: line, idt
        integer :: w, k, st
        id = 0
        heading = ''
        line = ctx%src%line(kw%card_line(1))
        w = 10
        if (kw%width_mode == width_long) w = 20
        k = index(line(1:min(len(line), w + 1)), ',')
        if (k > 0) then
            idt = line(1:k - 1)
            heading = adjustl(line(k + 1:))
        else
            idt = line(1:min(len(line), w))
            if (len(line) > w) heading = adjustl(line(w + 1:))
        end if
        if (len_trim(idt) == 0) return
        read (idt, *, iostat=st) id
        if (st /= 0) call make_error(error, ctx%src%where(kw%card_line(1))//': '//trim(kw%written)// &
                                     ' card 0 field ID: '''//trim(adjustl(idt))//''' is not an integer')
    end subroutine get_id_card

    !> Fields xdyna reads past: each one given a value other than blank, 0
    !> or one of `keep` (texts the field may hold to no effect, such as
    !> 'MECH') is named in d3hsp with its value and `why`.
    subroutine ignored_fields(model, card, idx, why, keep)
        type(model_t), intent(inout) :: model
        type(card_t), intent(in) :: card
        integer, intent(in) :: idx(:)
        character(len=*), intent(in) :: why
        character(len=*), intent(in), optional :: keep
        integer :: k, i, st
        real :: v
        character(len=80) :: t
        do k = 1, size(idx)
            i = idx(k)
            if (i > card%nf) cycle
            t = adjustl(card%f(i))
            if (len_trim(t) == 0) cycle
            read (t, *, iostat=st) v
            if (st == 0) then
                if (v == 0.0) cycle
            end if
            if (present(keep)) then
                if (index(' '//keep//' ', ' '//trim(t)//' ') > 0) cycle
            end if
            call add_warning(model, trim(card%file)//':'//itoa(card%line)//': '//trim(card%keyword)// &
                             ' field '//trim(card%name(i))//' = '//trim(t)//': '//why)
        end do
    end subroutine ignored_fields

    !> A non-blank card where the keyword has no more cards.
    subroutine extra_card_error(ctx, kw, icard, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        integer, intent(in) :: icard
        type(error_t), allocatable, intent(out) :: error
        integer :: ln
        ln = kw%card_line(icard)
        call make_error(error, ctx%src%where(ln)//': '//trim(kw%written)//' card '//itoa(icard)// &
                        ': unexpected card (the keyword has fewer cards): '''// &
                        trim(ctx%src%line(ln))//'''')
    end subroutine extra_card_error

    !> Cards from `from` on must be blank: the keyword has no more.
    subroutine no_more_cards(ctx, kw, from, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        integer, intent(in) :: from
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        integer :: ic
        do ic = from, kw%ncard
            call get_card(ctx, kw, ic, 'X', ic, card, error, raw=.true.)
            if (.not. card_blank(card)) then
                call extra_card_error(ctx, kw, ic, error)
                return
            end if
        end do
    end subroutine no_more_cards

end module xd_input_context
