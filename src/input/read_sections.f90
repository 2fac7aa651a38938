!> Reader for *SECTION_SOLID (shell sections arrive with the shell element).
module xd_input_read_sections
    use xd_kinds, only: wp
    use xd_core_errors, only: error_t, make_error
    use xd_input_field_reader, only: card_t, get_int, get_real, card_error
    use xd_input_keyword_table, only: keyword_t
    use xd_input_context, only: read_ctx_t, get_card, first_card, no_more_cards, ignored_fields
    use xd_model, only: model_t, section_solid_t, section_shell_t
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
        if (kw%name == 'SECTION_SHELL') then
            call read_section_shell(ctx, kw, model, error)
            return
        end if
        ic = first_card(kw)
        if (ic > kw%ncard) return
        call get_card(ctx, kw, ic, 'SECID ELFORM AET', 1, card, error)
        if (allocated(error)) return
        call ignored_fields(model, card, [3], 'ambient element types are not in xdyna; ignored')
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

    !> Card 1 SECID ELFORM SHRF NIP PROPT QR/IRID ICOMP SETYP; card 2 T1..T4 NLOC MAREA IDOF EDGSET.
    subroutine read_section_shell(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(section_shell_t) :: s
        integer :: ic, k, icomp
        ic = first_card(kw)
        if (ic + 1 > kw%ncard) then
            call make_error(error, ctx%src%where(kw%kw_line)//': *SECTION_SHELL needs cards 1 and 2')
            return
        end if
        call get_card(ctx, kw, ic, 'SECID ELFORM SHRF NIP PROPT QR ICOMP SETYP', 1, card, error)
        if (allocated(error)) return
        call ignored_fields(model, card, [5, 6, 8], 'printout, quadrature rule and 2D-solid type are not used (Gauss '// &
            'through the thickness); ignored', keep='1 1.0 1. 1.00')
        call get_int(card, 1, s%id, 0, error); if (allocated(error)) return
        call get_int(card, 2, s%elform, 2, error, zero_default=.true.); if (allocated(error)) return
        call get_real(card, 3, s%shrf, 1.0_wp, error, zero_default=.true.); if (allocated(error)) return
        call get_int(card, 4, s%nip, 2, error, zero_default=.true.); if (allocated(error)) return
        call get_int(card, 7, icomp, 0, error); if (allocated(error)) return
        if (s%id <= 0) then
            call card_error(card, 1, 'section id must be a positive integer', error); return
        end if
        if (s%elform /= 2) then
            call card_error(card, 2, 'shell formulation '//trim(card%f(2))//' is not supported (2: Belytschko-Tsay)', error)
            return
        end if
        if (s%nip < 1 .or. s%nip > 10) then
            call card_error(card, 4, 'NIP must lie in 1-10', error); return
        end if
        if (icomp /= 0) then
            call card_error(card, 7, 'composite layups (ICOMP) are not supported', error); return
        end if
        call get_card(ctx, kw, ic + 1, 'T1 T2 T3 T4 NLOC MAREA IDOF EDGSET', 2, card, error)
        if (allocated(error)) return
        call ignored_fields(model, card, [5, 6, 7, 8], 'reference surface, added mass, thickness field and edge set are not in '// &
            'xdyna; ignored')
        do k = 1, 4
            call get_real(card, k, s%t(k), 0.0_wp, error); if (allocated(error)) return
        end do
        if (s%t(2) == 0.0_wp) s%t(2:4) = s%t(1)
        if (any(s%t < 0.0_wp)) then
            call card_error(card, minloc(s%t, 1), 'shell thickness must not be negative', error); return
        end if
        ! zero: the elements give their own (*ELEMENT_SHELL_THICKNESS), or the
        ! part is rigid; checked per element once parts and materials are known
        s%src = kw%card_line(ic)
        if (.not. allocated(model%sec_shell)) allocate (model%sec_shell(8))
        if (model%nsec_shell == size(model%sec_shell)) model%sec_shell = [model%sec_shell, model%sec_shell]
        model%nsec_shell = model%nsec_shell + 1
        model%sec_shell(model%nsec_shell) = s
        call no_more_cards(ctx, kw, ic + 2, error)
    end subroutine read_section_shell

end module xd_input_read_sections
