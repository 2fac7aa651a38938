!> Readers for the material keywords and *HOURGLASS.
module xd_input_read_materials
    use xd_kinds, only: wp
    use xd_core_strings, only: itoa
    use xd_core_errors, only: error_t, make_error
    use xd_input_field_reader, only: card_t, get_int, get_real, card_error, card_blank
    use xd_input_keyword_table, only: keyword_t
    use xd_input_context, only: read_ctx_t, get_card, first_card, no_more_cards, add_warning, ignored_fields
    use xd_model, only: mat_spotweld, model_t, material_t, hourglass_t, mat_elastic, mat_plastic_kinematic, mat_piecewise_linear, &
                        mat_rigid
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
        case ('MAT_PLASTIC_KINEMATIC')
            call read_mat_plastic_kinematic(ctx, kw, model, error)
        case ('MAT_PIECEWISE_LINEAR_PLASTICITY')
            call read_mat_piecewise(ctx, kw, model, error)
        case ('MAT_ADD_EROSION')
            call read_mat_add_erosion(ctx, kw, model, error)
        case ('MAT_RIGID')
            call read_mat_rigid(ctx, kw, model, error)
        case ('MAT_SPOTWELD')
            call read_mat_spotweld(ctx, kw, model, error)
        case ('HOURGLASS')
            call read_hourglass(ctx, kw, model, error)
        end select
    end subroutine read_material

    !> Card 1 MID RO E PR N COUPLE M ALIAS; card 2 CMO CON1 CON2; card 3 LCO A1..V3.
    !> E and PR give the contact stiffness; CMO 1: CON1, CON2 translation and
    !> rotation codes 0-7 in the global system.
    subroutine read_mat_rigid(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(material_t) :: m
        real(wp) :: cmo
        integer :: ic
        ic = first_card(kw)
        if (ic > kw%ncard) return
        call get_card(ctx, kw, ic, 'MID RO E PR N COUPLE M ALIAS', 1, card, error)
        if (allocated(error)) return
        call ignored_fields(model, card, [5, 6, 7, 8], 'MADYMO/CAL3D coupling fields are not used; ignored')
        ! a rigid part may have no density: its mass then comes from
        ! *PART_INERTIA, or it is fixed (checked with the parts)
        call read_elastic_constants(card, m, error, rigid=.true.); if (allocated(error)) return
        m%src = kw%card_line(ic)
        if (ic + 1 <= kw%ncard) then
            call get_card(ctx, kw, ic + 1, 'CMO CON1 CON2', 2, card, error)
            if (allocated(error)) return
            call get_real(card, 1, cmo, 0.0_wp, error); if (allocated(error)) return
            call get_int(card, 2, m%con1, 0, error); if (allocated(error)) return
            call get_int(card, 3, m%con2, 0, error); if (allocated(error)) return
            m%cmo = nint(cmo)
            if (m%cmo /= 0 .and. m%cmo /= 1) then
                call card_error(card, 1, 'only CMO 0 (free) or 1 (global constraints) is implemented', error)
                return
            end if
            if (m%cmo == 1 .and. (m%con1 < 0 .or. m%con1 > 7)) then
                call card_error(card, 2, 'translation code must be 0-7', error); return
            end if
            if (m%cmo == 1 .and. (m%con2 < 0 .or. m%con2 > 7)) then
                call card_error(card, 3, 'rotation code must be 0-7', error); return
            end if
            if (m%cmo == 0) then
                m%con1 = 0
                m%con2 = 0
            end if
        end if
        m%mtype = mat_rigid
        m%keyword = 'MAT_RIGID'
        call push_material(model, m)
    end subroutine read_mat_rigid

    !> MID RO E PR, common to the isotropic materials; checks them.
    subroutine read_elastic_constants(card, m, error, rigid)
        type(card_t), intent(in) :: card
        type(material_t), intent(inout) :: m
        type(error_t), allocatable, intent(out) :: error
        logical, intent(in), optional :: rigid
        logical :: zero_ok
        zero_ok = .false.
        if (present(rigid)) zero_ok = rigid
        call get_int(card, 1, m%id, 0, error); if (allocated(error)) return
        call get_real(card, 2, m%ro, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 3, m%e, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 4, m%pr, 0.0_wp, error); if (allocated(error)) return
        if (m%id <= 0) then
            call card_error(card, 1, 'material id must be a positive integer', error); return
        end if
        if (zero_ok) then
            if (.not. (m%ro >= 0.0_wp)) then
                call card_error(card, 2, 'density must not be negative', error); return
            end if
        else if (.not. (m%ro > 0.0_wp)) then
            call card_error(card, 2, 'density must be positive', error); return
        end if
        if (.not. (m%e > 0.0_wp)) then
            call card_error(card, 3, 'Young''s modulus must be positive', error); return
        end if
        if (.not. (m%pr > -1.0_wp .and. m%pr < 0.5_wp)) then
            call card_error(card, 4, 'Poisson''s ratio must lie in (-1, 0.5)', error); return
        end if
    end subroutine read_elastic_constants

    !> Card 1 MID RO E PR SIGY ETAN BETA; card 2 SRC SRP FS VP.
    subroutine read_mat_plastic_kinematic(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(material_t) :: m
        real(wp) :: fs, vp
        integer :: ic
        ic = first_card(kw)
        if (ic > kw%ncard) return
        call get_card(ctx, kw, ic, 'MID RO E PR SIGY ETAN BETA', 1, card, error)
        if (allocated(error)) return
        call read_elastic_constants(card, m, error); if (allocated(error)) return
        call get_real(card, 5, m%sigy, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 6, m%etan, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 7, m%beta, 0.0_wp, error); if (allocated(error)) return
        if (.not. (m%sigy > 0.0_wp)) then
            call card_error(card, 5, 'yield stress must be positive', error); return
        end if
        if (m%etan < 0.0_wp .or. m%etan >= m%e) then
            call card_error(card, 6, 'tangent modulus must lie in [0, E)', error); return
        end if
        if (m%beta < 0.0_wp .or. m%beta > 1.0_wp) then
            call card_error(card, 7, 'BETA must lie in [0, 1] (0 kinematic, 1 isotropic)', error); return
        end if
        m%src = kw%card_line(ic)
        if (ic + 1 <= kw%ncard) then
            call get_card(ctx, kw, ic + 1, 'SRC SRP FS VP', 2, card, error)
            if (allocated(error)) return
            call get_real(card, 1, m%c, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 2, m%p, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 3, fs, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 4, vp, 0.0_wp, error); if (allocated(error)) return
            if (m%c < 0.0_wp .or. m%p < 0.0_wp .or. (m%c > 0.0_wp .neqv. m%p > 0.0_wp)) then
                call card_error(card, 1, 'SRC and SRP must both be positive (or both 0: no rate effect)', error)
                return
            end if
            if (fs < 0.0_wp) then
                call card_error(card, 3, 'FS (the effective plastic strain at failure) must not be negative', error)
                return
            end if
            m%fail = fs
            if (vp /= 0.0_wp) then
                call card_error(card, 4, 'only VP 0 (the yield stress scaled by the strain rate) is implemented', error)
                return
            end if
        end if
        m%mtype = mat_plastic_kinematic
        m%keyword = 'MAT_PLASTIC_KINEMATIC'
        call push_material(model, m)
        call no_more_cards(ctx, kw, ic + 2, error)
    end subroutine read_mat_plastic_kinematic

    !> *MAT_ADD_EROSION: card 1 MID EXCL MXPRES MNEPS EFFEPS VOLEPS NUMFIP NCS;
    !> card 2 MNPRES SIGP1 SIGVM MXEPS EPSSH SIGTH IMPULSE FAILTM. The
    !> pressure, stress and time criteria, NUMFIP and NCS are used (shells);
    !> the strain and impulse criteria are refused where given (a field
    !> equal to EXCL is not given). The material must be defined (checked
    !> once the deck is read: the card is kept by MID).
    subroutine read_mat_add_erosion(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(material_t) :: m
        real(wp) :: excl, v(8)
        integer :: ic, k, mid
        ic = first_card(kw)
        if (ic > kw%ncard) return
        call get_card(ctx, kw, ic, 'MID EXCL MXPRES MNEPS EFFEPS VOLEPS NUMFIP NCS', 1, card, error)
        if (allocated(error)) return
        call get_int(card, 1, mid, 0, error); if (allocated(error)) return
        call get_real(card, 2, excl, 0.0_wp, error); if (allocated(error)) return
        call given(3, 6); if (allocated(error)) return
        m%mxpres = v(3)
        m%mneps = v(4)
        m%effeps = v(5)
        m%voleps = v(6)
        if (m%mneps > 0.0_wp) then
            call card_error(card, 4, 'MNEPS, the smallest principal strain at failure, must be negative (a '// &
                            'compression)', error)
            return
        end if
        if (m%effeps < 0.0_wp) then
            call card_error(card, 5, 'EFFEPS, the effective strain at failure, must not be negative', error); return
        end if
        call get_int(card, 7, m%numfip, 1, error, zero_default=.true.); if (allocated(error)) return
        call get_int(card, 8, m%ncs, 1, error, zero_default=.true.); if (allocated(error)) return
        if (m%numfip < 0) then
            call card_error(card, 7, 'NUMFIP < 0 (a percentage of the points) is not in xdyna; give a count', error)
            return
        end if
        if (m%ncs < 1) then
            call card_error(card, 8, 'NCS must be at least 1', error)
            return
        end if
        if (ic + 1 <= kw%ncard) then
            call get_card(ctx, kw, ic + 1, 'MNPRES SIGP1 SIGVM MXEPS EPSSH SIGTH IMPULSE FAILTM', 2, card, error)
            if (allocated(error)) return
            call given(1, 8); if (allocated(error)) return
            m%mnpres = v(1)
            m%sigp1 = v(2)
            m%sigvm = v(3)
            m%failtm = v(8)
            m%mxeps = v(4)
            m%epssh = v(5)
            if (m%mxeps < 0.0_wp .or. m%epssh < 0.0_wp) then
                call card_error(card, 4, 'MXEPS and EPSSH, the largest principal and shear strains at failure, '// &
                                'must not be negative', error)
                return
            end if
            call refuse(6, 7, 'the threshold and impulse criteria (SIGTH, IMPULSE)')
            if (allocated(error)) return
            if (m%sigp1 < 0.0_wp .or. m%sigvm < 0.0_wp .or. m%mxpres < 0.0_wp .or. m%failtm < 0.0_wp) then
                call card_error(card, 2, 'SIGP1, SIGVM, MXPRES and FAILTM must not be negative', error)
                return
            end if
        end if
        m%id = mid
        m%erosion = .true.
        m%add_src = kw%card_line(ic)
        if (.not. allocated(model%erosion)) then
            model%erosion = [m]
        else
            model%erosion = [model%erosion, m]
        end if
        call no_more_cards(ctx, kw, ic + 2, error)
    contains
        !> fields k1..k2 of the card into v, a field equal to EXCL read as 0
        subroutine given(k1, k2)
            integer, intent(in) :: k1, k2
            do k = k1, k2
                call get_real(card, k, v(k), 0.0_wp, error); if (allocated(error)) return
                if (v(k) == excl) v(k) = 0
            end do
        end subroutine given

        !> fields k1..k2 (read by given) must not be given
        subroutine refuse(k1, k2, what)
            integer, intent(in) :: k1, k2
            character(len=*), intent(in) :: what
            do k = k1, k2
                if (v(k) /= 0.0_wp) then
                    call card_error(card, k, what//' are not in xdyna; give 0 or EXCL', error)
                    return
                end if
            end do
        end subroutine refuse
    end subroutine read_mat_add_erosion

    !> Card 1 MID RO E PR SIGY ETAN FAIL TDEL; card 2 C P LCSS LCSR VP;
    !> cards 3-4 EPS1..8, ES1..8.
    subroutine read_mat_piecewise(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(material_t) :: m
        real(wp) :: fail, tdel, vp
        integer :: ic, k, lcsr
        ic = first_card(kw)
        if (ic > kw%ncard) return
        call get_card(ctx, kw, ic, 'MID RO E PR SIGY ETAN FAIL TDEL', 1, card, error)
        if (allocated(error)) return
        call read_elastic_constants(card, m, error); if (allocated(error)) return
        call get_real(card, 5, m%sigy, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 6, m%etan, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 7, fail, 1.0e21_wp, error, zero_default=.true.); if (allocated(error)) return
        call get_real(card, 8, tdel, 0.0_wp, error); if (allocated(error)) return
        if (m%etan < 0.0_wp .or. m%etan >= m%e) then
            call card_error(card, 6, 'tangent modulus must lie in [0, E)', error); return
        end if
        if (fail < 0.0_wp) then
            call card_error(card, 7, 'FAIL < 0 (a user failure subroutine) is not in xdyna', error)
            return
        end if
        if (fail < 1.0e20_wp) m%fail = fail
        if (tdel /= 0.0_wp) call add_warning(model, ctx%src%where(kw%card_line(ic))// &
            ': *MAT_PIECEWISE_LINEAR_PLASTICITY field TDEL: element deletion is not implemented; ignored')
        m%src = kw%card_line(ic)
        m%beta = 1.0_wp
        if (ic + 1 <= kw%ncard) then
            call get_card(ctx, kw, ic + 1, 'C P LCSS LCSR VP', 2, card, error)
            if (allocated(error)) return
            call get_real(card, 1, m%c, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 2, m%p, 0.0_wp, error); if (allocated(error)) return
            call get_int(card, 3, m%lcss, 0, error); if (allocated(error)) return
            call get_int(card, 4, lcsr, 0, error); if (allocated(error)) return
            call get_real(card, 5, vp, 0.0_wp, error); if (allocated(error)) return
            if (m%c < 0.0_wp .or. m%p < 0.0_wp .or. (m%c > 0.0_wp .neqv. m%p > 0.0_wp)) then
                call card_error(card, 1, 'C and P must both be positive (or both 0: no rate effect)', error)
                return
            end if
            if (lcsr /= 0) then
                call card_error(card, 4, 'a strain-rate scaling curve (LCSR) is not implemented', error); return
            end if
            if (vp /= 0.0_wp .and. vp /= -1.0_wp) then
                call card_error(card, 5, 'only VP 0 or -1 (the yield stress scaled by the strain rate) '// &
                                'is implemented', error)
                return
            end if
        end if
        if (ic + 3 <= kw%ncard) then
            call get_card(ctx, kw, ic + 2, 'EPS1 EPS2 EPS3 EPS4 EPS5 EPS6 EPS7 EPS8', 3, card, error)
            if (allocated(error)) return
            do k = 1, 8
                call get_real(card, k, m%eps(k), 0.0_wp, error); if (allocated(error)) return
            end do
            call get_card(ctx, kw, ic + 3, 'ES1 ES2 ES3 ES4 ES5 ES6 ES7 ES8', 4, card, error)
            if (allocated(error)) return
            do k = 1, 8
                call get_real(card, k, m%es(k), 0.0_wp, error); if (allocated(error)) return
            end do
            ! the table ends at the first zero strain after the first point
            m%ntab = 0
            do k = 1, 8
                if (k > 1 .and. m%eps(k) == 0.0_wp) exit
                if (m%es(k) == 0.0_wp .and. k > 1) exit
                m%ntab = k
            end do
            if (m%ntab == 1 .and. m%es(1) == 0.0_wp) m%ntab = 0
            do k = 2, m%ntab
                if (.not. (m%eps(k) > m%eps(k - 1))) then
                    call card_error(card, k, 'EPS values must increase', error); return
                end if
            end do
        end if
        if (m%lcss == 0 .and. m%ntab == 0 .and. .not. (m%sigy > 0.0_wp)) then
            call make_error(error, ctx%src%where(kw%card_line(ic))//': *MAT_PIECEWISE_LINEAR_PLASTICITY '// &
                            'card 1 field SIGY: a positive yield stress is needed without LCSS or EPS/ES')
            return
        end if
        m%mtype = mat_piecewise_linear
        m%keyword = 'MAT_PIECEWISE_LINEAR'
        call push_material(model, m)
        call no_more_cards(ctx, kw, ic + 4, error)
    end subroutine read_mat_piecewise

    !> *MAT_SPOTWELD: card 1 MID RO E PR SIGY EH DT TFAIL; card 2 EFAIL NRR NRS
    !> NRT MRR MSS MTT NF. With SIGY > 0 the weld is elastic-plastic in its
    !> resultants, hardening as SIGY + EH eps_p (a beam with its section's
    !> dimensions, ELFORM 1 or 9; see beam_bs); it fails at TFAIL, where
    !> sum (R_i / R_iF)^2 >= 1 over the given resultants (the axial force
    !> in tension only), or where eps_p reaches EFAIL.
    subroutine read_mat_spotweld(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(material_t) :: m
        integer :: ic, k
        ic = first_card(kw)
        if (ic > kw%ncard) return
        call get_card(ctx, kw, ic, 'MID RO E PR SIGY EH DT TFAIL', 1, card, error)
        if (allocated(error)) return
        call read_elastic_constants(card, m, error); if (allocated(error)) return
        call get_real(card, 5, m%sigy, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 6, m%eh, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 8, m%tfail, 0.0_wp, error); if (allocated(error)) return
        if (m%sigy < 0.0_wp) then
            call card_error(card, 5, 'SIGY must not be negative (0: an elastic weld)', error); return
        end if
        if (m%eh < 0.0_wp) then
            call card_error(card, 6, 'EH, the plastic hardening modulus, must not be negative', error); return
        end if
        call ignored_fields(model, card, [7], 'DT (a time step for the weld''s own scaling) is not used; ignored')
        m%src = kw%card_line(ic)
        if (ic + 1 <= kw%ncard) then
            call get_card(ctx, kw, ic + 1, 'EFAIL NRR NRS NRT MRR MSS MTT NF', 2, card, error)
            if (allocated(error)) return
            call get_real(card, 1, m%efail, 0.0_wp, error); if (allocated(error)) return
            if (m%efail < 0.0_wp) then
                call card_error(card, 1, 'EFAIL, the plastic strain at failure, must not be negative', error); return
            end if
            if (m%efail > 0.0_wp .and. .not. (m%sigy > 0.0_wp)) then
                call card_error(card, 1, 'EFAIL '//trim(card%f(1))//' needs SIGY > 0: an elastic weld has no '// &
                                'plastic strain', error)
                return
            end if
            do k = 1, 6
                call get_real(card, 1 + k, m%rfail(k), 0.0_wp, error); if (allocated(error)) return
                if (m%rfail(k) < 0.0_wp) then
                    call card_error(card, 1 + k, 'the resultants at failure must not be negative', error); return
                end if
            end do
            call ignored_fields(model, card, [8], 'NF (a filter on the resultants) is not used; ignored')
        end if
        m%mtype = mat_spotweld
        m%keyword = 'MAT_SPOTWELD'
        call push_material(model, m)
        call no_more_cards(ctx, kw, ic + 2, error)
    end subroutine read_mat_spotweld

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
        call ignored_fields(model, card, [5, 6], 'axial and bending damping are for beams (not in xdyna); ignored')
        call read_elastic_constants(card, m, error); if (allocated(error)) return
        call get_real(card, 5, da, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 6, db, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 7, k, 0.0_wp, error); if (allocated(error)) return
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
        call ignored_fields(model, card, [4], 'IBQ is not used by LS-DYNA either; ignored')
        call get_int(card, 1, h%id, 0, error); if (allocated(error)) return
        call get_int(card, 2, h%ihq, 0, error); if (allocated(error)) return
        call get_real(card, 3, h%qm, 0.1_wp, error, zero_default=.true.); if (allocated(error)) return
        call get_real(card, 5, h%q1, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 6, h%q2, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 7, h%qb, 0.0_wp, error); if (allocated(error)) return
        call get_real(card, 8, h%qw, 0.0_wp, error); if (allocated(error)) return
        if (h%id <= 0) then
            call card_error(card, 1, 'hourglass id must be a positive integer', error); return
        end if
        if (h%ihq < 0 .or. h%ihq > 5) then
            call card_error(card, 2, 'IHQ '//trim(card%f(2))//' is not supported (1-5)', error); return
        end if
        if (h%qm < 0.0_wp) then
            call card_error(card, 3, 'QM must not be negative', error); return
        end if
        if (h%qb < 0.0_wp) then
            call card_error(card, 7, 'QB must not be negative', error); return
        end if
        if (h%qw < 0.0_wp) then
            call card_error(card, 8, 'QW must not be negative', error); return
        end if
        if (h%qb == 0.0_wp) h%qb = h%qm
        if (h%qw == 0.0_wp) h%qw = h%qm
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
