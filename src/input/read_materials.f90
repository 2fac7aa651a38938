!> Readers for the material keywords and *HOURGLASS.
module xd_input_read_materials
    use xd_kinds, only: wp
    use xd_core_errors, only: error_t
    use xd_input_field_reader, only: card_t, get_int, get_real, card_error, card_blank
    use xd_input_keyword_table, only: keyword_t
    use xd_input_context, only: read_ctx_t, get_card, first_card, no_more_cards, add_warning
    use xd_model, only: model_t, material_t, hourglass_t, mat_elastic
    implicit none
    private
    public :: read_material

contains

    subroutine read_material(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        select case (kw%name)
        case ('MAT_ELASTIC')
            call read_mat_elastic(ctx, kw, model, error)
        case ('HOURGLASS')
            call read_hourglass(ctx, kw, model, error)
        end select
    end subroutine read_material

    subroutine read_mat_elastic(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(material_t) :: m
        real(wp) :: da, db, k
        integer :: ic
        ic = first_card(kw)
        if (ic > kw%ncard) return
        call get_card(ctx, kw, ic, 'MID RO E PR DA DB K', 1, card, error)
        if (allocated(error)) return
        call get_int(card, 1, m%id, 0, error); if (allocated(error)) return
        call get_real(card, 2, m%ro, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 3, m%e, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 4, m%pr, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 5, da, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 6, db, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 7, k, 0.0_wp, error); if (allocated(error)) return
        if (m%id <= 0) then
            call card_error(card, 1, 'material id must be a positive integer', error); return
        end if
        if (.not. (m%ro > 0.0_wp)) then
            call card_error(card, 2, 'density must be positive', error); return
        end if
        if (.not. (m%e > 0.0_wp)) then
            call card_error(card, 3, 'Young''s modulus must be positive', error); return
        end if
        if (.not. (m%pr > -1.0_wp .and. m%pr < 0.5_wp)) then
            call card_error(card, 4, 'Poisson''s ratio must lie in (-1, 0.5)', error); return
        end if
        if (k /= 0.0_wp) then
            call card_error(card, 7, 'the fluid option (K) is not supported', error); return
        end if
        if (da /= 0.0_wp .or. db /= 0.0_wp) call add_warning(model, ctx%src%where(kw%card_line(ic))// &
            ': *MAT_ELASTIC fields DA/DB apply to beams only and are ignored')
        m%mtype = mat_elastic
        m%keyword = 'MAT_ELASTIC'
        m%src = kw%card_line(ic)
        call push_material(model, m)
        call no_more_cards(ctx, kw, ic + 1, error)
    end subroutine read_mat_elastic

    !> HGID IHQ QM IBQ Q1 Q2 QB QW; 0 means "take the *CONTROL default".
    subroutine read_hourglass(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(hourglass_t) :: h
        integer :: ic
        ic = first_card(kw)
        if (ic > kw%ncard) return
        call get_card(ctx, kw, ic, 'HGID IHQ QM IBQ Q1 Q2 QB QW', 1, card, error)
        if (allocated(error)) return
        call get_int(card, 1, h%id, 0, error); if (allocated(error)) return
        call get_int(card, 2, h%ihq, 0, error); if (allocated(error)) return
        call get_real(card, 3, h%qm, 0.1_wp, error, zero_default=.true.); if (allocated(error)) return
        call get_real(card, 5, h%q1, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 6, h%q2, 0.0_wp, error); if (allocated(error)) return
        if (h%id <= 0) then
            call card_error(card, 1, 'hourglass id must be a positive integer', error); return
        end if
        if (h%ihq < 0 .or. h%ihq > 5) then
            call card_error(card, 2, 'IHQ '//trim(card%f(2))//' is not supported (1-5)', error); return
        end if
        if (h%qm < 0.0_wp) then
            call card_error(card, 3, 'QM must not be negative', error); return
        end if
        h%src = kw%card_line(ic)
        if (.not. allocated(model%hg)) allocate (model%hg(8))
        if (model%nhg == size(model%hg)) model%hg = [model%hg, model%hg]
        model%nhg = model%nhg + 1
        model%hg(model%nhg) = h
        call no_more_cards(ctx, kw, ic + 1, error)
    end subroutine read_hourglass

    subroutine push_material(model, m)
        type(model_t), intent(inout) :: model
        type(material_t), intent(in) :: m
        if (.not. allocated(model%mat)) allocate (model%mat(8))
        if (model%nmat == size(model%mat)) model%mat = [model%mat, model%mat]
        model%nmat = model%nmat + 1
        model%mat(model%nmat) = m
    end subroutine push_material


end module xd_input_read_materials
