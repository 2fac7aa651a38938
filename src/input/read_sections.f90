!> Reader for *SECTION_SOLID (shell sections arrive with the shell element).
module xd_input_read_sections
    use xd_core_errors, only: error_t
    use xd_input_field_reader, only: card_t, get_int, card_error
    use xd_input_keyword_table, only: keyword_t
    use xd_input_context, only: read_ctx_t, get_card, first_card, no_more_cards
    use xd_model, only: model_t, section_solid_t
    implicit none
    private
    public :: read_section

contains

    subroutine read_section(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(section_solid_t) :: s
        integer :: ic
        ic = first_card(kw)
        if (ic > kw%ncard) return
        call get_card(ctx, kw, ic, 'SECID ELFORM AET', 1, card, error)
        if (allocated(error)) return
        call get_int(card, 1, s%id, 0, error); if (allocated(error)) return
        call get_int(card, 2, s%elform, 1, error, zero_default=.true.); if (allocated(error)) return
        if (s%id <= 0) then
            call card_error(card, 1, 'section id must be a positive integer', error)
            return
        end if
        if (s%elform /= 1) then
            call card_error(card, 2, 'solid formulation '//trim(card%f(2))// &
                            ' is not supported (1: constant stress hexahedron)', error)
            return
        end if
        s%src = kw%card_line(ic)
        if (.not. allocated(model%sec_solid)) allocate (model%sec_solid(8))
        if (model%nsec_solid == size(model%sec_solid)) model%sec_solid = [model%sec_solid, model%sec_solid]
        model%nsec_solid = model%nsec_solid + 1
        model%sec_solid(model%nsec_solid) = s
        call no_more_cards(ctx, kw, ic + 1, error)
    end subroutine read_section

end module xd_input_read_sections
