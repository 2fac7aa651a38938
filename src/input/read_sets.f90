!> Readers for node and part sets (*SET_NODE_LIST, *SET_PART_LIST, _GENERATE).
module xd_input_read_sets
    use xd_kinds, only: i8
    use xd_core_errors, only: error_t
    use xd_core_strings, only: itoa
    use xd_input_field_reader, only: card_t, card_format_t, card_format, get_int, card_error, card_blank, get_text
    use xd_core_strings, only: to_upper
    use xd_input_keyword_table, only: keyword_t
    use xd_input_context, only: read_ctx_t, get_card, first_card, ignored_fields
    use xd_model, only: model_t, set_t, set_node, set_part, set_shell
    implicit none
    private
    public :: read_set

    !> the most ids a set may hold (200 MB of them): a _GENERATE range of
    !> two billion ids allocated gigabytes before it failed with no place named
    integer, parameter :: max_members = 50000000

contains

    subroutine read_set(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(set_t) :: s
        integer :: ic, k, v, b, e, j
        logical :: generate
        character(len=:), allocatable :: spec
        type(card_format_t) :: fmt

        ic = first_card(kw)
        if (ic > kw%ncard) return
        call get_card(ctx, kw, ic, 'SID DA1 DA2 DA3 DA4 SOLVER', 1, card, error)
        if (allocated(error)) return
        call ignored_fields(model, card, [2, 3, 4, 5, 6], 'set attributes (DA1-DA4) and solver names '// &
                            'are not used; ignored', keep='MECH')
        call get_int(card, 1, s%id, 0, error); if (allocated(error)) return
        if (s%id <= 0) then
            call card_error(card, 1, 'set id must be a positive integer', error); return
        end if
        s%kind = set_node
        if (kw%name(1:8) == 'SET_PART') s%kind = set_part
        if (kw%name(1:9) == 'SET_SHELL') s%kind = set_shell
        generate = index(kw%name, '_GENERATE') > 0
        s%src = kw%card_line(ic)
        allocate (s%member(64))
        if (index(kw%name, '_GENERAL') > 0 .or. index(kw%name, '_ADD') > 0) then
            call read_rules(ctx, kw, ic, s, error)
            if (allocated(error)) return
            call store(model, s)
            return
        end if
        if (generate) then
            spec = 'B1BEG B1END B2BEG B2END B3BEG B3END B4BEG B4END'
        else
            spec = 'ID1 ID2 ID3 ID4 ID5 ID6 ID7 ID8'
        end if
        fmt = card_format(spec, kw%width_mode)
        do ic = ic + 1, kw%ncard
            call get_card(ctx, kw, ic, fmt, ic, card, error)
            if (allocated(error)) return
            if (card_blank(card)) cycle
            if (generate) then
                do k = 1, 7, 2
                    call get_int(card, k, b, 0, error); if (allocated(error)) return
                    call get_int(card, k + 1, e, 0, error); if (allocated(error)) return
                    if (b == 0 .and. e == 0) cycle
                    if (b <= 0 .or. e < b) then
                        call card_error(card, k + 1, 'range '//itoa(b)//' to '//itoa(e)// &
                                        ' is empty or not positive', error)
                        return
                    end if
                    ! (counted in 64 bits: a range ending at the largest
                    ! integer wrapped its counter and never ended)
                    if (int(e, i8) - b + 1 + s%n > max_members) then
                        call card_error(card, k + 1, 'range '//itoa(b)//' to '//itoa(e)//' makes the set '// &
                                        'hold more than '//itoa(max_members)//' ids', error)
                        return
                    end if
                    do j = b, e - 1
                        call push(s, j)
                    end do
                    call push(s, e)
                end do
            else
                do k = 1, 8
                    call get_int(card, k, v, 0, error); if (allocated(error)) return
                    if (v < 0) then
                        call card_error(card, k, 'ids must be positive', error); return
                    end if
                    if (v > 0) call push(s, v)
                end do
            end if
        end do
        call shrink(s%member, s%n)
        call store(model, s)
    end subroutine read_set

    subroutine store(model, s)
        type(model_t), intent(inout) :: model
        type(set_t), intent(in) :: s
        if (.not. allocated(model%set)) allocate (model%set(8))
        if (model%nset == size(model%set)) model%set = [model%set, model%set]
        model%nset = model%nset + 1
        model%set(model%nset) = s
    end subroutine store

    !> _GENERAL cards OPTION E1..E7 (the options are checked when the set is
    !> resolved, with the model known); _ADD cards DSID1..DSID8 (sets of the
    !> same kind, united).
    subroutine read_rules(ctx, kw, ic0, s, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        integer, intent(in) :: ic0
        type(set_t), intent(inout) :: s
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        integer :: ic, k, n
        s%add = index(kw%name, '_ADD') > 0
        n = max(kw%ncard - ic0, 1)
        allocate (s%rule_op(n), s%rule_val(8, n), s%rule_line(n))
        s%rule_val = 0
        s%nrule = 0
        do ic = ic0 + 1, kw%ncard
            if (s%add) then
                call get_card(ctx, kw, ic, 'DSID1 DSID2 DSID3 DSID4 DSID5 DSID6 DSID7 DSID8', 2, card, error)
            else
                call get_card(ctx, kw, ic, 'OPTION E1 E2 E3 E4 E5 E6 E7', 2, card, error)
            end if
            if (allocated(error)) return
            if (card_blank(card)) cycle
            s%nrule = s%nrule + 1
            s%rule_line(s%nrule) = kw%card_line(ic)
            if (s%add) then
                s%rule_op(s%nrule) = 'ADD'
                do k = 1, 8
                    call get_int(card, k, s%rule_val(k, s%nrule), 0, error); if (allocated(error)) return
                    if (s%rule_val(k, s%nrule) < 0) then
                        call card_error(card, k, 'set ids must be positive', error); return
                    end if
                end do
            else
                s%rule_op(s%nrule) = to_upper(get_text(card, 1))
                do k = 1, 7
                    call get_int(card, k + 1, s%rule_val(k, s%nrule), 0, error); if (allocated(error)) return
                end do
            end if
        end do
    end subroutine read_rules

    !> Cut a to its first n entries through the heap (an array section
    !> assigned to itself would take a stack temporary as large as the set).
    subroutine shrink(a, n)
        integer, allocatable, intent(inout) :: a(:)
        integer, intent(in) :: n
        integer, allocatable :: tmp(:)
        allocate (tmp(n))
        tmp(1:n) = a(1:n)
        call move_alloc(tmp, a)
    end subroutine shrink

    subroutine push(s, v)
        type(set_t), intent(inout) :: s
        integer, intent(in) :: v
        integer, allocatable :: tmp(:)
        if (s%n == size(s%member)) then
            allocate (tmp(2*size(s%member)))
            tmp(1:s%n) = s%member(1:s%n)
            call move_alloc(tmp, s%member)
        end if
        s%n = s%n + 1
        s%member(s%n) = v
    end subroutine push

end module xd_input_read_sets
