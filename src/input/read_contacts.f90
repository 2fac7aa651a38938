!> Readers for the contact keywords: *CONTACT_... (cards 1-3, optional card
!> A; PENMAX of card B and IGNORE of card C; the other fields of cards B-G
!> are read and named as ignored), *CONTROL_CONTACT and xdyna's own
!> *CONTROL_XDYNA_CONTACT (the search and enforcement policies the paper
!> discusses).
module xd_input_read_contacts
    use xd_kinds, only: wp, dp
    use xd_core_errors, only: error_t, make_error
    use xd_core_strings, only: itoa, rtoa
    use xd_input_field_reader, only: card_t, get_int, get_real, get_text, card_error, card_blank
    use xd_input_keyword_table, only: keyword_t
    use xd_input_context, only: get_id_card, read_ctx_t, get_card, first_card, add_warning, ignored_fields
    use xd_model, only: model_t, contact_t, ct_single, ct_surface_to_surface, ct_general, ct_nodes_to_surface, &
                        styp_segment_set, styp_node_set, styp_all, styp_all_but, search_auto, search_fixed, search_adaptive, &
                        mnl_minimal, mnl_closest1, mnl_closest3, ct_tied_nodes, ct_tied_shell_edge, ct_tied_surface, ct_tiebreak
    implicit none
    private
    public :: read_contact

contains

    subroutine read_contact(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        select case (kw%name)
        case ('CONTROL_CONTACT')
            call read_control_contact(ctx, kw, model, error)
        case ('CONTROL_XDYNA_CONTACT')
            call read_control_xdyna_contact(ctx, kw, model, error)
        case default
            call read_interface(ctx, kw, model, error)
        end select
    end subroutine read_contact

    !> *CONTACT_...: _ID card, card 1 SSID MSID SSTYP MSTYP SBOXID MBOXID SPR
    !> MPR; card 2 FS FD DC VC VDC PENCHK BT DT; card 3 SFS SFM SST MST SFST
    !> SFMT FSF VSF; optional card A SOFT SOFSCL LCIDAB MAXPAR SBOPT DEPTH
    !> BSORT FRCFRQ.
    subroutine read_interface(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(contact_t) :: c
        integer :: ic, k, ibox(2), ival
        real(wp) :: rval
        logical :: tied, tiebreak, eroding
        character(len=:), allocatable :: at

        c%keyword = kw%name
        tiebreak = .false.
        eroding = .false.
        select case (kw%name)
        case ('CONTACT_AUTOMATIC_SINGLE_SURFACE', 'CONTACT_SINGLE_SURFACE'); c%kind = ct_single
        ! the eroding contacts: the automatic ones, which follow erosion
        ! themselves (an eroded shell's segments leave the surface)
        case ('CONTACT_ERODING_SINGLE_SURFACE'); c%kind = ct_single; eroding = .true.
        case ('CONTACT_ERODING_SURFACE_TO_SURFACE'); c%kind = ct_surface_to_surface; eroding = .true.
        case ('CONTACT_ERODING_NODES_TO_SURFACE'); c%kind = ct_nodes_to_surface; eroding = .true.
        case ('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE'); c%kind = ct_surface_to_surface
        case ('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK'); c%kind = ct_surface_to_surface; tiebreak = .true.
        case ('CONTACT_AUTOMATIC_GENERAL'); c%kind = ct_general
        case ('CONTACT_AUTOMATIC_NODES_TO_SURFACE'); c%kind = ct_nodes_to_surface
        case ('CONTACT_TIED_NODES_TO_SURFACE'); c%kind = ct_tied_nodes
        case ('CONTACT_TIED_SHELL_EDGE_TO_SURFACE'); c%kind = ct_tied_shell_edge
        case ('CONTACT_TIED_SURFACE_TO_SURFACE'); c%kind = ct_tied_surface
        case ('CONTACT_TIED_NODES_TO_SURFACE_OFFSET'); c%kind = ct_tied_nodes; c%tied_offset = .true.
        case ('CONTACT_TIED_SHELL_EDGE_TO_SURFACE_OFFSET', 'CONTACT_TIED_SHELL_EDGE_TO_SURFACE_BEAM_OFFSET')
            c%kind = ct_tied_shell_edge; c%tied_offset = .true.
        case ('CONTACT_TIED_SURFACE_TO_SURFACE_OFFSET'); c%kind = ct_tied_surface; c%tied_offset = .true.
        ! spot welds: the beams' nodes (slave parts, or a node set) tied to
        ! the shells with their rotations, at their gaps
        case ('CONTACT_SPOTWELD'); c%kind = ct_tied_shell_edge; c%tied_offset = .true.
        end select
        tied = c%kind >= ct_tied_nodes
        if (kw%has_id) then
            call get_id_card(ctx, kw, c%id, c%heading, error)
            if (allocated(error)) return
        end if
        ic = first_card(kw)
        c%src = kw%kw_line
        c%at = ctx%src%where(c%src)
        at = ctx%src%where(kw%kw_line)//': '//trim(kw%written)

        ! card 1: which parts take part
        if (ic <= kw%ncard) then
            c%src = kw%card_line(ic)
            c%at = ctx%src%where(c%src)
            call get_card(ctx, kw, ic, 'SSID MSID SSTYP MSTYP SBOXID MBOXID SPR MPR', 1, card, error)
            if (allocated(error)) return
            call ignored_fields(model, card, [7, 8], 'interface force file output (SPR, MPR) is not written; ignored')
            call get_int(card, 1, c%ssid, 0, error); if (allocated(error)) return
            call get_int(card, 2, c%msid, 0, error); if (allocated(error)) return
            call get_int(card, 3, c%sstyp, 0, error); if (allocated(error)) return
            call get_int(card, 4, c%mstyp, 0, error); if (allocated(error)) return
            c%sboxid = 0
            c%mboxid = 0
            do k = 1, 2
                call get_int(card, 4 + k, ibox(k), 0, error); if (allocated(error)) return
                if (ibox(k) < 0) then
                    call card_error(card, 4 + k, 'a box id must not be negative (contact-box-following boxes '// &
                                    'are not supported)', error)
                    return
                end if
            end do
            c%sboxid = ibox(1)
            c%mboxid = ibox(2)
            if (c%sstyp < styp_segment_set .or. c%sstyp > styp_all_but) then
                call card_error(card, 3, 'SSTYP '//itoa(c%sstyp)//' is not 0-6 (segment set, shell set, part set, part, '// &
                                'node set, all, all but a part set)', error)
                return
            end if
            if (c%mstyp < styp_segment_set .or. c%mstyp > styp_all_but) then
                call card_error(card, 4, 'MSTYP '//itoa(c%mstyp)//' is not 0-6 (segment set, shell set, part set, part, '// &
                                'all, all but a part set)', error)
                return
            end if
            if (c%mstyp == styp_node_set .and. c%kind /= ct_single .and. c%kind /= ct_general) then
                call card_error(card, 4, 'the master side is made of segments: MSTYP 4 (node set) '// &
                                'is for the slave side only', error)
                return
            end if
            if (c%sstyp == styp_node_set .and. c%kind /= ct_nodes_to_surface .and. .not. tied) then
                call card_error(card, 3, 'SSTYP 4 (node set) gives slave nodes without segments: use '// &
                                '*CONTACT_AUTOMATIC_NODES_TO_SURFACE', error)
                return
            end if
            if (c%kind == ct_surface_to_surface .or. c%kind == ct_nodes_to_surface .or. tied) then
                if (c%ssid == 0 .and. c%sstyp /= styp_all) then
                    call card_error(card, 1, 'a two-surface contact needs a slave side (SSID > 0, or SSTYP 5)', &
                                    error)
                    return
                end if
                if (c%msid == 0 .and. c%mstyp /= styp_all) then
                    call card_error(card, 2, 'a two-surface contact needs a master side (MSID > 0, or MSTYP 5)', &
                                    error)
                    return
                end if
            end if
        end if

        ! card 2: friction, damping, birth and death
        if (ic + 1 <= kw%ncard) then
            call get_card(ctx, kw, ic + 1, 'FS FD DC VC VDC PENCHK BT DT', 2, card, error)
            if (allocated(error)) return
            call get_real(card, 1, c%fs, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 2, c%fd, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 3, c%dc, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 4, c%vc, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 5, c%vdc, 0.0_wp, error); if (allocated(error)) return
            call get_int(card, 6, ival, 0, error); if (allocated(error)) return
            call get_real(card, 7, c%bt, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 8, c%dt, 1.0e20_wp, error, zero_default=.true.); if (allocated(error)) return
            if (c%fs < 0.0_wp .or. c%fd < 0.0_wp .or. c%dc < 0.0_wp) then
                call card_error(card, 1, 'friction coefficients FS, FD and decay DC must not be negative', error)
                return
            end if
            if (c%vdc < 0.0_wp .or. c%vdc > 100.0_wp) then
                call card_error(card, 5, 'VDC is a percentage of critical damping: 0 to 100', error)
                return
            end if
            if (c%dt <= c%bt) then
                call card_error(card, 8, 'death time DT must be later than birth time BT', error)
                return
            end if
            if (ival /= 0) call add_warning(model, at//' card 2 field PENCHK: the automatic contact keeps '// &
                'a node in contact within its thickness window (section 5.2); PENCHK is ignored')
        end if

        ! card 3: penalty scales and thickness overrides
        if (ic + 2 <= kw%ncard) then
            call get_card(ctx, kw, ic + 2, 'SFS SFM SST MST SFST SFMT FSF VSF', 3, card, error)
            if (allocated(error)) return
            call get_real(card, 1, c%sfs, 1.0_wp, error, zero_default=.true.); if (allocated(error)) return
            call get_real(card, 2, c%sfm, 1.0_wp, error, zero_default=.true.); if (allocated(error)) return
            call get_real(card, 3, c%sst, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 4, c%mst, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 5, c%sfst, 1.0_wp, error, zero_default=.true.); if (allocated(error)) return
            call get_real(card, 6, c%sfmt, 1.0_wp, error, zero_default=.true.); if (allocated(error)) return
            do k = 1, 6
                call get_real(card, k, rval, 0.0_wp, error); if (allocated(error)) return
                if (rval < 0.0_wp) then
                    call card_error(card, k, 'penalty scales and thicknesses must not be negative', error)
                    return
                end if
            end do
            do k = 7, 8
                call get_real(card, k, rval, 1.0_wp, error, zero_default=.true.); if (allocated(error)) return
                if (rval /= 1.0_wp) call add_warning(model, at//' card 3 fields FSF/VSF: friction and viscous '// &
                                                     'scale factors are not implemented; ignored')
            end do
        end if

        ! the tiebreak's card 4: OPTION NFLS SFLS PARAM ERATEN ERATES CT2CN CN
        if (tiebreak) then
            if (ic + 3 > kw%ncard) then
                call make_error(error, at//': the tiebreak card (OPTION NFLS SFLS PARAM, after card 3) is missing')
                return
            end if
            call get_card(ctx, kw, ic + 3, 'OPTION NFLS SFLS PARAM ERATEN ERATES CT2CN CN', 4, card, error)
            if (allocated(error)) return
            call get_int(card, 1, c%tb_option, 1, error, zero_default=.true.); if (allocated(error)) return
            call get_real(card, 2, c%nfls, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 3, c%sfls, 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 4, c%tb_param, 0.0_wp, error); if (allocated(error)) return
            if (c%tb_option /= 1 .and. c%tb_option /= 2 .and. c%tb_option /= 9) then
                call card_error(card, 1, 'OPTION '//itoa(c%tb_option)//' is not 1 (tied until the stress '// &
                                'criterion, then contact), 2 (then the stress falls to zero over PARAM) or 9 (the '// &
                                'mixed-mode cohesive law); the other tiebreak options are not in xdyna', error)
                return
            end if
            if (c%nfls < 0.0_wp .or. c%sfls < 0.0_wp) then
                call card_error(card, 2, 'the failure stresses NFLS and SFLS must not be negative', error)
                return
            end if
            if (c%tb_option == 2 .and. c%tb_param <= 0.0_wp) then
                call card_error(card, 4, 'OPTION 2 needs PARAM > 0, the separation over which the stress falls '// &
                                'to zero', error)
                return
            end if
            if (c%tb_option == 9) then
                call get_real(card, 5, c%tb_gic, 0.0_wp, error); if (allocated(error)) return
                call get_real(card, 6, c%tb_giic, 0.0_wp, error); if (allocated(error)) return
                call get_real(card, 7, c%tb_ct2cn, 1.0_wp, error, zero_default=.true.); if (allocated(error)) return
                call get_real(card, 8, c%tb_cn, 0.0_wp, error); if (allocated(error)) return
                call cohesive_fields(card, c, error); if (allocated(error)) return
            else
                call ignored_fields(model, card, [5, 6, 7, 8], 'the tiebreak''s rate and cohesive fields are not '// &
                                    'used by OPTION 1 and 2; ignored')
            end if
            ic = ic + 1
        end if
        ! the eroding contacts' card 4: ISYM EROSOP IADJ
        if (eroding .and. ic + 3 <= kw%ncard) then
            call get_card(ctx, kw, ic + 3, 'ISYM EROSOP IADJ', 4, card, error)
            if (allocated(error)) return
            call get_int(card, 2, ival, 0, error); if (allocated(error)) return
            if (ival == 0) call add_warning(model, at//' card 4 field EROSOP 0: xdyna''s contacts always follow '// &
                                            'erosion (an eroded shell''s segments leave the surface)')
            call ignored_fields(model, card, [1, 3], 'symmetry planes (ISYM) and adjacent-material treatment '// &
                                '(IADJ) are not used; ignored')
            ic = ic + 1
        end if
        ! optional card A
        if (ic + 3 <= kw%ncard) then
            call get_card(ctx, kw, ic + 3, 'SOFT SOFSCL LCIDAB MAXPAR SBOPT DEPTH BSORT FRCFRQ', 4, card, error)
            if (allocated(error)) return
            call ignored_fields(model, card, [2, 4, 5, 6, 8], 'segment-based contact options are not in xdyna; ignored')
            call get_int(card, 1, ival, 0, error); if (allocated(error)) return
            if (ival /= 0) call add_warning(model, at//' card A field SOFT: the soft-constraint and segment-'// &
                'based options are not implemented; the penalty stiffness comes from the bulk modulus (SOFT 0)')
            call get_int(card, 3, ival, 0, error); if (allocated(error)) return
            if (ival /= 0) call add_warning(model, at//' card A field LCIDAB: airbag thickness curves are '// &
                                            'not implemented; ignored')
            call get_int(card, 7, c%bsort, 0, error); if (allocated(error)) return
            if (c%bsort < 0) then
                call card_error(card, 7, 'BSORT '//itoa(c%bsort)//' (cycles between global searches) must not be negative', error)
                return
            end if
        end if
        if (ic + 4 <= kw%ncard) then
            ! cards B-G: each field set to other than 0 is named (xdyna's
            ! thickness, penetration and initial-overlap rules are its own)
            do k = ic + 4, kw%ncard
                select case (k - ic - 3)
                case (1)
                    call get_card(ctx, kw, k, 'PENMAX THKOPT SHLTHK SNLOG ISYM I2D3D SLDTHK SLDSTF', 5, card, error)
                case (2)
                    call get_card(ctx, kw, k, 'IGAP IGNORE DPRFAC DTSTIF EDC EDGEK UNUSED FLANGL', 6, card, error)
                case (3)
                    call get_card(ctx, kw, k, 'Q2TRI DTPCHK SFNBR FNLSCL DNLSCL TCSO TIEDID SHLEDG', 7, card, error)
                case default
                    call get_card(ctx, kw, k, 'F1 F2 F3 F4 F5 F6 F7 F8', k - ic + 1, card, error)
                end select
                if (allocated(error)) return
                select case (k - ic - 3)
                case (1)
                    ! PENMAX: the release depth as a multiple of the segment's
                    ! thickness
                    call get_real(card, 1, c%penmax, 0.0_wp, error); if (allocated(error)) return
                    if (c%penmax < 0.0_wp) then
                        call card_error(card, 1, 'PENMAX (release depth over the segment thickness) must not be '// &
                                        'negative', error)
                        return
                    end if
                    call ignored_fields(model, card, [2, 3, 4, 5, 6, 7, 8], 'not used by xdyna''s automatic '// &
                                        'contact (its thickness and stiffness rules are SSTHK, SST/MST and SOFT 0); '// &
                                        'ignored')
                case (2)
                    call get_int(card, 2, c%ignore, 0, error); if (allocated(error)) return
                    if (c%ignore < 0 .or. c%ignore > 2) then
                        call card_error(card, 2, 'IGNORE '//itoa(c%ignore)//' is not 0 (*CONTROL_CONTACT''s), 1 '// &
                                        '(track initial penetrations) or 2 (track and name the coordinates that '// &
                                        'remove them); 3, 4 and negative values are for mortar contact', error)
                        return
                    end if
                    call ignored_fields(model, card, [1, 3, 4, 5, 6, 7, 8], 'not used by xdyna''s automatic '// &
                                        'contact; ignored')
                case default
                    call ignored_fields(model, card, [1, 2, 3, 4, 5, 6, 7, 8], 'optional cards D-G are not used by '// &
                                        'xdyna''s automatic contact; ignored')
                end select
            end do
        end if

        if (tied) then
            ! a tie is a constraint: no friction, damping, penalty or search
            if (c%fs > 0.0_wp .or. c%fd > 0.0_wp .or. c%dc > 0.0_wp .or. c%vc > 0.0_wp .or. c%vdc > 0.0_wp) &
                call add_warning(model, at//' card 2 fields FS-VDC: a tied contact holds its slave nodes on the '// &
                                 'surface (a constraint); friction and damping do not apply; ignored')
            if (c%bt > 0.0_wp) call add_warning(model, at//' card 2 field BT: the tie holds from t = 0 (the '// &
                                                'slave nodes are placed on the surface then); BT '// &
                                                'ignored')
            if (c%sfs /= 1.0_wp .or. c%sfm /= 1.0_wp) call add_warning(model, at//' card 3 fields SFS/SFM: a tied '// &
                                                'contact has no penalty springs; ignored')
            if (c%sboxid > 0 .or. c%mboxid > 0) then
                call make_error(error, at//': SBOXID/MBOXID are not read for a tied contact; give the slave '// &
                                'nodes as a node set instead')
                return
            end if
            if (.not. allocated(model%tied)) allocate (model%tied(4))
            if (model%ntied == size(model%tied)) model%tied = [model%tied, model%tied]
            model%ntied = model%ntied + 1
            if (c%id == 0) c%id = model%ncontact + model%ntied
            model%tied(model%ntied) = c
            return
        end if
        if (tiebreak) then
            ! the tie, held apart as the tied contacts are (the slaves keep
            ! their gaps), and the sliding contact for after it breaks
            if (c%id == 0) c%id = model%ncontact + 1
            block
                type(contact_t) :: t
                t = c
                t%kind = ct_tiebreak
                t%tied_offset = .true.
                if (.not. allocated(model%tied)) allocate (model%tied(4))
                if (model%ntied == size(model%tied)) model%tied = [model%tied, model%tied]
                model%ntied = model%ntied + 1
                model%tied(model%ntied) = t
            end block
            c%tb_option = 0
        end if
        if (.not. allocated(model%contact)) allocate (model%contact(4))
        if (model%ncontact == size(model%contact)) model%contact = [model%contact, model%contact]
        model%ncontact = model%ncontact + 1
        if (c%id == 0) c%id = model%ncontact
        model%contact(model%ncontact) = c
    end subroutine read_interface

    !> Card 1 SLSFAC RWPNAL ISLCHK SHLTHK PENOPT THKCHG ORIEN ENMASS; card 2
    !> USRSTR USRFRC NSBCS INTERM XPENE SSTHK ECDT TIEDPRJ; cards 3-7 ignored.
    subroutine read_control_contact(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        integer :: ival, k
        real(wp) :: rval
        character(len=:), allocatable :: at
        character(len=8), parameter :: ignored1(5) = [character(len=8) :: 'PENOPT', 'THKCHG', 'ORIEN', &
                                                      'ENMASS', '']
        at = ctx%src%where(kw%kw_line)//': '//trim(kw%written)
        associate (cc => model%ctl%contact)
            if (kw%ncard >= 1) then
                call get_card(ctx, kw, 1, 'SLSFAC RWPNAL ISLCHK SHLTHK PENOPT THKCHG ORIEN ENMASS', 1, card, error)
                if (allocated(error)) return
                call ignored_fields(model, card, [3, 4], 'the automatic contact always checks initial '// &
                    'penetrations and counts shell thickness; ignored', keep='1')
                call get_real(card, 1, cc%slsfac, 0.1_wp, error, zero_default=.true.); if (allocated(error)) return
                if (cc%slsfac < 0.0_wp) then
                    call card_error(card, 1, 'SLSFAC must not be negative', error); return
                end if
                call get_real(card, 2, rval, 0.0_wp, error); if (allocated(error)) return
                if (rval /= 0.0_wp) call add_warning(model, at//' field RWPNAL: rigid walls are stonewalls '// &
                                                     '(kinematic) in xdyna; ignored')
                call get_int(card, 6, cc%thkchg, 0, error); if (allocated(error)) return
                if (cc%thkchg /= 0 .and. cc%thkchg /= 1) then
                    call card_error(card, 6, 'THKCHG '//itoa(cc%thkchg)//' is not 0 (the initial shell thickness) '// &
                                    'or 1 (the shells'' thickness as it changes)', error)
                    return
                end if
                do k = 5, 8
                    if (k == 6) cycle
                    call get_int(card, k, ival, 0, error); if (allocated(error)) return
                    ! PENOPT 1 is the default stiffness rule (the one xdyna uses);
                    ! ORIEN 1 (LS-DYNA's default) orients segments, as the
                    ! automatic contact does anyway
                    if (ival /= 0 .and. .not. (k == 5 .and. ival == 1) .and. .not. (k == 7 .and. ival == 1)) &
                        call add_warning(model, at//' field '//trim(ignored1(k - 4))//': not implemented; ignored')
                end do
            end if
            if (kw%ncard >= 2) then
                call get_card(ctx, kw, 2, 'USRSTR USRFRC NSBCS INTERM XPENE SSTHK ECDT TIEDPRJ', 2, card, error)
                if (allocated(error)) return
                call ignored_fields(model, card, [1, 2, 4, 5, 7, 8], 'not used by xdyna; ignored', keep='4 4.0 4.')
                call get_int(card, 3, cc%nsbcs, 0, error); if (allocated(error)) return
                call get_int(card, 6, cc%ssthk, 0, error); if (allocated(error)) return
                if (cc%ssthk /= 0 .and. cc%ssthk /= 1) then
                    call card_error(card, 6, 'SSTHK '//itoa(cc%ssthk)//' is not 0 (single-surface shell thickness '// &
                                    'limited to 40% of the shortest edge) or 1 (the shell''s own)', error)
                    return
                end if
                if (cc%nsbcs < 0) then
                    call card_error(card, 3, 'NSBCS '//itoa(cc%nsbcs)//' (cycles between global searches) '// &
                                    'must not be negative', error)
                    return
                end if
            end if
            ! cards 3-7: every field set is named, but IGNORE (card 4)
            do k = 3, kw%ncard
                select case (k)
                case (3)
                    call get_card(ctx, kw, k, 'SFRIC DFRIC EDC VFC TH TH_SF PEN_SF PTSCL', k, card, error)
                case (4)
                    call get_card(ctx, kw, k, 'IGNORE FRCENG SKIPRWG OUTSEG SPOTSTP SPOTDEL SPOTHIN DIR_TIE', k, &
                                  card, error)
                case (5)
                    call get_card(ctx, kw, k, 'ISYM NSEROD RWGAPS RWGDTH RWKSF ICOV SWRADF ITHOFF', k, card, error)
                case (6)
                    call get_card(ctx, kw, k, 'SHLEDG PSTIFF ITHCNT TDCNOF FTALL UNUSED SHLTRW IGACTC', k, card, error)
                case default
                    call get_card(ctx, kw, k, 'F1 F2 F3 F4 F5 F6 F7 F8', k, card, error)
                end select
                if (allocated(error)) return
                if (k == 4) then
                    call get_int(card, 1, cc%ignore, 0, error); if (allocated(error)) return
                    if (cc%ignore < 0 .or. cc%ignore > 2) then
                        call card_error(card, 1, 'IGNORE '//itoa(cc%ignore)//' is not 0 (move slave nodes out of '// &
                                        'initial penetrations), 1 (track them) or 2 (track them and name the '// &
                                        'coordinates that remove them)', error)
                        return
                    end if
                    call ignored_fields(model, card, [2, 3, 4, 5, 6, 7, 8], 'not used by xdyna; ignored')
                else
                    call ignored_fields(model, card, [1, 2, 3, 4, 5, 6, 7, 8], 'not used by xdyna; ignored')
                end if
            end do
        end associate
    end subroutine read_control_contact

    !> xdyna's card: SEARCH NSRCH MNL TRACK SCREEN ENFORCE PMARG DUMPNS (see
    !> the manual, "*CONTROL_XDYNA_CONTACT").
    subroutine read_control_xdyna_contact(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        integer :: ival
        if (kw%ncard < 1) return
        if (kw%ncard > 1) then
            call make_error(error, ctx%src%where(kw%card_line(2))//': '//trim(kw%written)// &
                            ' has one card; unexpected card: '''//trim(ctx%src%line(kw%card_line(2)))//'''')
            return
        end if
        associate (cc => model%ctl%contact)
            call get_card(ctx, kw, 1, 'SEARCH NSRCH MNL TRACK SCREEN ENFORCE PMARG DUMPNS', 1, card, error)
            if (allocated(error)) return
            call get_int(card, 1, ival, 0, error); if (allocated(error)) return
            select case (ival)
            case (0); cc%search = search_auto
            case (1); cc%search = search_fixed
            case (2); cc%search = search_adaptive
            case default
                call card_error(card, 1, 'SEARCH '//itoa(ival)//' is not 0 (on the motion, at most NSRCH cycles apart if '// &
                                'given), 1 (also every 100 cycles when no interval is given) or 2 (on the motion alone)', &
                                error); return
            end select
            call get_int(card, 2, cc%nsrch, 0, error); if (allocated(error)) return
            if (cc%nsrch < 0) then
                call card_error(card, 2, 'NSRCH '//itoa(cc%nsrch)//' (cycles between global searches) must not be negative', error)
                return
            end if
            call get_int(card, 3, ival, 0, error); if (allocated(error)) return
            select case (ival)
            case (0); cc%mnl = mnl_minimal
            case (1); cc%mnl = mnl_closest1
            case (3); cc%mnl = mnl_closest3
            case default
                call card_error(card, 3, 'MNL '//itoa(ival)//' is not 0 (minimal set), 1 (closest node) or '// &
                                '3 (three closest)', error)
                return
            end select
            call on_off(4, cc%tracking); if (allocated(error)) return
            call on_off(5, cc%screens); if (allocated(error)) return
            call get_int(card, 6, ival, 0, error); if (allocated(error)) return
            select case (ival)
            case (0, 1); cc%lagrange = .false.
            case (2); cc%lagrange = .true.
            case default
                call card_error(card, 6, 'ENFORCE '//itoa(ival)//' is not 1 (penalty) or 2 (Lagrangian projection)', error); return
            end select
            call get_real(card, 7, cc%pmarg, 0.5_wp, error, zero_default=.true.); if (allocated(error)) return
            if (cc%pmarg < 0.0_wp) then
                call card_error(card, 7, 'PMARG must be positive', error); return
            end if
            call get_int(card, 8, cc%dump_nsid, 0, error); if (allocated(error)) return
        end associate
    contains
        subroutine on_off(k, flag)
            integer, intent(in) :: k
            logical, intent(out) :: flag
            call get_int(card, k, ival, 0, error); if (allocated(error)) return
            select case (ival)
            case (0, 1); flag = .true.
            case (2); flag = .false.
            case default
                call card_error(card, k, itoa(ival)//' is not 1 (on) or 2 (off)', error)
            end select
        end subroutine on_off
    end subroutine read_control_xdyna_contact

    !> OPTION 9's fields: the peak tractions T (NFLS) and S (SFLS), the
    !> energies GIC and GIIC, the stiffnesses CN and CT2CN CN positive, and
    !> each mode's energy more than its elastic share at the peak, T^2 /
    !> (2 CN) (else the traction would have to fall before it rose: no
    !> softening branch); PARAM the mixed-mode exponent (0: 1).
    subroutine cohesive_fields(card, c, error)
        type(card_t), intent(in) :: card
        type(contact_t), intent(inout) :: c
        type(error_t), allocatable, intent(out) :: error
        real(wp) :: ct
        if (.not. (c%nfls > 0.0_wp)) then
            call card_error(card, 2, 'OPTION 9 needs NFLS > 0, the peak normal traction T', error); return
        end if
        if (.not. (c%sfls > 0.0_wp)) then
            call card_error(card, 3, 'OPTION 9 needs SFLS > 0, the peak shear traction S', error); return
        end if
        if (.not. (c%tb_gic > 0.0_wp)) then
            call card_error(card, 5, 'OPTION 9 needs ERATEN > 0, the mode I energy release rate GIC', error); return
        end if
        if (.not. (c%tb_giic > 0.0_wp)) then
            call card_error(card, 6, 'OPTION 9 needs ERATES > 0, the mode II energy release rate GIIC', error); return
        end if
        if (.not. (c%tb_ct2cn > 0.0_wp)) then
            call card_error(card, 7, 'CT2CN, the tangential over the normal stiffness, must be positive', error); return
        end if
        if (.not. (c%tb_cn > 0.0_wp)) then
            call card_error(card, 8, 'OPTION 9 needs CN > 0, the normal stiffness (stress per length; xdyna '// &
                            'has no default for it)', error)
            return
        end if
        if (.not. (c%tb_gic > c%nfls**2/(2*c%tb_cn))) then
            call card_error(card, 5, 'GIC '//trim(card%f(5))//' is not above NFLS^2 / (2 CN) = '// &
                            rtoa(real(c%nfls**2/(2*c%tb_cn), dp))//', the energy stored at the peak (raise CN or GIC)', &
                            error)
            return
        end if
        ct = c%tb_ct2cn*c%tb_cn
        if (.not. (c%tb_giic > c%sfls**2/(2*ct))) then
            call card_error(card, 6, 'GIIC '//trim(card%f(6))//' is not above SFLS^2 / (2 CT2CN CN) = '// &
                            rtoa(real(c%sfls**2/(2*ct), dp))//', the energy stored at the peak (raise CN or GIIC)', &
                            error)
            return
        end if
        if (c%tb_param == 0.0_wp) c%tb_param = 1
    end subroutine cohesive_fields

end module xd_input_read_contacts
