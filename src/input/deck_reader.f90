!> Reads a keyword deck into a model: loads the lines (with includes), cuts
!> them into keywords, applies *KEYWORD width options and *PARAMETER values,
!> and hands each keyword to the reader of its family.
module xd_input_deck_reader
    use xd_core_errors, only: error_t, make_error
    use xd_core_strings, only: to_upper, itoa
    use xd_input_deck_source, only: load_deck
    use xd_input_field_reader, only: card_t, width_standard, width_long, width_i10, get_text, card_blank, &
                                     card_where
    use xd_input_keyword_table, only: keyword_t, lookup_keyword, fam_unknown, fam_meta, fam_geometry, &
                                      fam_section, fam_material, fam_set, fam_condition, fam_control, &
                                      fam_database, fam_skip, fam_planned, fam_load, fam_contact
    use xd_input_context, only: read_ctx_t, get_card, add_warning
    use xd_input_read_geometry, only: read_geometry
    use xd_input_read_sections, only: read_section
    use xd_input_read_materials, only: read_material
    use xd_input_read_sets, only: read_set
    use xd_input_read_conditions, only: read_condition
    use xd_input_read_controls, only: read_control, read_database
    use xd_input_read_loads, only: read_load
    use xd_input_read_contacts, only: read_contact
    use xd_model, only: model_t, mesh_fit
    use xd_kinds, only: dp
    use xd_input_expression, only: evaluate
    implicit none
    private
    public :: read_deck, read_options_t

    type :: read_options_t
        logical :: warn_unsupported = .false.   !< unsupported=warn on the command line
    end type read_options_t

contains

    subroutine read_deck(path, opts, model, ctx, error)
        character(len=*), intent(in) :: path
        type(read_options_t), intent(in) :: opts
        type(model_t), intent(out) :: model
        type(read_ctx_t), intent(out) :: ctx
        type(error_t), allocatable, intent(out) :: error
        type(keyword_t), allocatable :: kws(:)
        integer :: nkw, i

        model%deck_path = path
        ctx%warn_unsupported = opts%warn_unsupported
        call load_deck(ctx%src, path, error)
        if (allocated(error)) return
        call cut_keywords(ctx, kws, nkw)
        ! parameters first, so that a field may use one defined further down
        do i = 1, nkw
            if (index(kws(i)%name, 'PARAMETER') == 1) then
                call read_parameter(ctx, kws(i), error)
                if (allocated(error)) return
            end if
        end do
        do i = 1, nkw
            call dispatch(ctx, kws(i), model, error)
            if (allocated(error)) return
        end do
        call mesh_fit(model)
    end subroutine read_deck

    !> Keyword lines and the non-comment lines under each. *KEYWORD options
    !> (LONG=Y/S, I10=Y) set the width of every keyword after it.
    subroutine cut_keywords(ctx, kws, nkw)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), allocatable, intent(out) :: kws(:)
        integer, intent(out) :: nkw
        integer :: i, width, nc
        integer, allocatable :: lines(:)
        character(len=:), allocatable :: text
        allocate (kws(64), lines(1024))
        nkw = 0
        width = width_standard
        nc = 0
        do i = 1, ctx%src%nline
            if (ctx%src%is_comment(i)) cycle
            if (ctx%src%is_keyword(i)) then
                call close_keyword()
                text = ctx%src%line(i)
                if (nkw == size(kws)) kws = [kws, kws]
                nkw = nkw + 1
                kws(nkw) = keyword_t()
                kws(nkw)%kw_line = i
                if (to_upper(text(1:min(8, len(text)))) == '*KEYWORD') then
                    if (index(to_upper(text), 'LONG=Y') > 0) width = width_long
                    if (index(to_upper(text), 'LONG=S') > 0) width = width_standard
                    if (index(to_upper(text), 'I10=Y') > 0) width = width_i10
                end if
                call lookup_keyword(text, width, kws(nkw))
            else if (nkw > 0) then
                if (nc == size(lines)) lines = [lines, lines]
                nc = nc + 1
                lines(nc) = i
            end if
        end do
        call close_keyword()
    contains
        subroutine close_keyword()
            if (nkw == 0) return
            ! blank lines at the very end of a keyword separate it from the next
            ! one; blank lines in between are cards of defaults
            kws(nkw)%ncard = nc
            kws(nkw)%card_line = lines(1:nc)
            nc = 0
        end subroutine close_keyword
    end subroutine cut_keywords

    subroutine dispatch(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable :: at
        at = ctx%src%where(kw%kw_line)
        select case (kw%family)
        case (fam_meta)
            if (kw%name == 'TITLE' .and. kw%ncard > 0) model%title = ctx%src%line(kw%card_line(1))
            ! LS-DYNA's job identification (PROJECT, NUM, STAGE): named, not
            ! used (xdyna's outputs are named by outdir= and jobid=)
            if (kw%name == 'KEYWORD_ID') then
                if (kw%ncard > 0) then
                    call add_warning(model, at//': '//trim(kw%written)//' job identification "'// &
                                     trim(ctx%src%line(kw%card_line(1)))//'" read; output names come from '// &
                                     'outdir= and jobid=, not from it')
                else
                    call add_warning(model, at//': '//trim(kw%written)//' without its card; read')
                end if
            end if
        case (fam_geometry)
            call read_geometry(ctx, kw, model, error)
        case (fam_section)
            call read_section(ctx, kw, model, error)
        case (fam_material)
            call read_material(ctx, kw, model, error)
        case (fam_set)
            call read_set(ctx, kw, model, error)
        case (fam_condition)
            call read_condition(ctx, kw, model, error)
        case (fam_control)
            call read_control(ctx, kw, model, error)
        case (fam_database)
            call read_database(ctx, kw, model, error)
        case (fam_load)
            call read_load(ctx, kw, model, error)
        case (fam_contact)
            call read_contact(ctx, kw, model, error)
        case (fam_skip)
            call add_warning(model, at//': '//trim(kw%written)//' is output-only or tuning for '// &
                             'another code; skipped')
        case (fam_planned)
            call unsupported(at//': '//trim(kw%written)//' is not implemented in this version of xdyna')
        case default
            call unsupported(at//': '//trim(kw%written)//' is not a supported keyword')
        end select
    contains
        subroutine unsupported(text)
            character(len=*), intent(in) :: text
            if (ctx%warn_unsupported) then
                call add_warning(model, text//' (unsupported=warn: skipped)')
            else
                call make_error(error, text//' (run with unsupported=warn to skip it)')
            end if
        end subroutine unsupported
    end subroutine dispatch

    !> *PARAMETER(_LOCAL): cards of four pairs, name (A10, first character
    !> the type R/I/C, then the name) and value (A10).
    !> *PARAMETER_EXPRESSION(_LOCAL): cards PRMR (A10) EXPRESSION (A70), an
    !> expression continued on cards whose first 10 columns are blank; it may
    !> use parameters defined before it. _LOCAL: seen only from its own file.
    subroutine read_parameter(ctx, kw, error)
        type(read_ctx_t), intent(inout) :: ctx
        type(keyword_t), intent(in) :: kw
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        integer :: ic, k
        character(len=:), allocatable :: nm, scope, line, ex, msg
        character(len=40) :: buf
        real(dp) :: v
        scope = ''
        if (index(kw%name, '_LOCAL') > 0) scope = ctx%src%file_of(kw%kw_line)
        if (index(kw%name, '_EXPRESSION') > 0) then
            ic = 1
            do while (ic <= kw%ncard)
                line = ctx%src%line(kw%card_line(ic))
                nm = trim(adjustl(line(1:min(10, len(line)))))
                ex = ''
                if (len(line) > 10) ex = line(11:)
                if (len(nm) == 0) then
                    if (len_trim(ex) == 0) then
                        ic = ic + 1
                        cycle
                    end if
                    call make_error(error, ctx%src%where(kw%card_line(ic))//': '//trim(kw%written)// &
                                    ' field PRMR: a continuation card with no expression before it')
                    return
                end if
                ! continuation cards: first 10 columns blank
                do while (ic < kw%ncard)
                    line = ctx%src%line(kw%card_line(ic + 1))
                    if (len_trim(line(1:min(10, len(line)))) > 0) exit
                    if (len(line) > 10) ex = ex//' '//line(11:)
                    ic = ic + 1
                end do
                if (scan(to_upper(nm(1:1)), 'RI') /= 1 .or. len(nm) < 2) then
                    call make_error(error, ctx%src%where(kw%card_line(ic))//': '//trim(kw%written)// &
                                    ' field PRMR: '''//nm//''' must start with its type R or I, then the name')
                    return
                end if
                call evaluate(ex, ctx%params, ctx%src%file_of(kw%card_line(ic)), v, msg)
                if (len(msg) > 0) then
                    call make_error(error, ctx%src%where(kw%card_line(ic))//': '//trim(kw%written)// &
                                    ' field EXPRESSION of '''//trim(adjustl(nm(2:)))//''': '//msg)
                    return
                end if
                if (to_upper(nm(1:1)) == 'I') then
                    ! an integer parameter: truncated as LS-DYNA's LS_INTEGER,
                    ! but a value within round-off of an integer is that integer
                    if (abs(v - anint(v)) <= 1.0e-9_dp*max(1.0_dp, abs(v))) then
                        write (buf, '(f0.0)') anint(v)
                    else
                        write (buf, '(f0.0)') aint(v)
                    end if
                    k = index(buf, '.')
                    if (k > 0) buf(k:) = ''
                    if (len_trim(buf) == 0 .or. buf == '-') buf = '0'
                else
                    write (buf, '(es23.16)') v
                end if
                if (len(scope) > 0) then
                    call ctx%params%add(adjustl(nm(2:)), nm(1:1), trim(adjustl(buf)), scope)
                else
                    call ctx%params%add(adjustl(nm(2:)), nm(1:1), trim(adjustl(buf)))
                end if
                ic = ic + 1
            end do
            return
        end if
        do ic = 1, kw%ncard
            call get_card(ctx, kw, ic, 'PRMR1 VAL1 PRMR2 VAL2 PRMR3 VAL3 PRMR4 VAL4', 1, card, error)
            if (allocated(error)) return
            if (card_blank(card)) cycle
            do k = 1, 7, 2
                nm = get_text(card, k)
                if (len(nm) == 0) cycle
                if (scan(to_upper(nm(1:1)), 'RIC') /= 1 .or. len(nm) < 2) then
                    call make_error(error, card_where(card)//': *PARAMETER card 1 field PRMR'//itoa((k + 1)/2)// &
                                    ': '''//nm//''' must start with its type R, I or C, then the name')
                    return
                end if
                if (len(scope) > 0) then
                    call ctx%params%add(adjustl(nm(2:)), nm(1:1), get_text(card, k + 1), scope)
                else
                    call ctx%params%add(adjustl(nm(2:)), nm(1:1), get_text(card, k + 1))
                end if
            end do
        end do
    end subroutine read_parameter

end module xd_input_deck_reader
