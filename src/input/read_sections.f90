!> Reader for *SECTION_SOLID (shell sections arrive with the shell element).
module xd_input_read_sections
    use xd_kinds, only: wp
    use xd_core_errors, only: error_t, make_error
    use xd_input_field_reader, only: card_t, get_int, get_real, card_error
    use xd_input_keyword_table, only: keyword_t
    use xd_input_context, only: read_ctx_t, get_card, first_card, no_more_cards, ignored_fields
    use xd_model, only: model_t, section_solid_t, section_shell_t, section_beam_t
    use xd_core_strings, only: itoa
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
        if (kw%name == 'SECTION_BEAM') then
            call read_section_beam(ctx, kw, model, error)
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

    !> *SECTION_BEAM: card 1 SECID ELFORM SHRF QR/IRID CST SCOOR NSM; card 2
    !> for ELFORM 2 A ISS ITT J SA IST, for ELFORM 1 TS1 TS2 TT1 TT2 NSLOC
    !> NTLOC (CST 0 a rectangle TS1 x TT1, 1 a tube of outer diameter TS1 and
    !> inner TT1: A, ISS, ITT and J computed; the ends' second values must
    !> equal the first).
    subroutine read_section_beam(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(section_beam_t) :: s
        integer :: ic, k
        real(wp) :: v(6), a, b, pi
        pi = acos(-1.0_wp)
        ic = first_card(kw)
        if (ic + 1 > kw%ncard) then
            call make_error(error, ctx%src%where(kw%kw_line)//': *SECTION_BEAM needs cards 1 and 2')
            return
        end if
        call get_card(ctx, kw, ic, 'SECID ELFORM SHRF QR CST SCOOR NSM', 1, card, error)
        if (allocated(error)) return
        call ignored_fields(model, card, [6], 'the reference axis offset is not used; ignored')
        call get_int(card, 1, s%id, 0, error); if (allocated(error)) return
        call get_int(card, 2, s%elform, 1, error, zero_default=.true.); if (allocated(error)) return
        call get_real(card, 3, s%shrf, 1.0_wp, error, zero_default=.true.); if (allocated(error)) return
        call get_int(card, 5, s%cst, 0, error); if (allocated(error)) return
        call get_real(card, 7, s%nsm, 0.0_wp, error); if (allocated(error)) return
        call get_int(card, 4, s%qr, 2, error, zero_default=.true.); if (allocated(error)) return
        if (s%id <= 0) then
            call card_error(card, 1, 'section id must be a positive integer', error); return
        end if
        if (s%elform /= 1 .and. s%elform /= 2 .and. s%elform /= 9) then
            call card_error(card, 2, 'beam formulation '//trim(card%f(2))//' is not supported (1: Hughes-Liu '// &
                            'with an elastic material, 2: Belytschko-Schwer resultant, 9: spot weld)', error)
            return
        end if
        if (s%elform == 1 .and. (s%qr < 1 .or. s%qr > 5)) then
            call card_error(card, 4, 'QR '//trim(card%f(4))//' is not a rule xdyna has for ELFORM 1 (1 one point, 2 '// &
                            '2 x 2 Gauss, 3 3 x 3 Gauss, 4 3 x 3 Lobatto, 5 4 x 4 Gauss; user rules, negative, are '// &
                            'not in xdyna)', error)
            return
        end if
        if (s%elform /= 1 .and. s%qr /= 2) call ignored_fields(model, card, [4], 'the quadrature rule is used by '// &
                                                               'ELFORM 1 only; ignored')
        if (s%nsm < 0.0_wp) then
            call card_error(card, 7, 'NSM must not be negative', error); return
        end if
        s%src = kw%card_line(ic)
        if (s%elform == 2) then
            call get_card(ctx, kw, ic + 1, 'A ISS ITT J SA IST', 2, card, error)
            if (allocated(error)) return
            do k = 1, 6
                call get_real(card, k, v(k), 0.0_wp, error); if (allocated(error)) return
            end do
            s%a = v(1); s%iss = v(2); s%itt = v(3); s%j = v(4); s%sa = v(5)
            if (.not. (s%a > 0.0_wp .and. s%iss > 0.0_wp .and. s%itt > 0.0_wp)) then
                call card_error(card, 1, 'A, ISS and ITT must be positive', error); return
            end if
            if (s%j <= 0.0_wp) s%j = s%iss + s%itt
        else
            call get_card(ctx, kw, ic + 1, 'TS1 TS2 TT1 TT2 NSLOC NTLOC', 2, card, error)
            if (allocated(error)) return
            do k = 1, 4
                call get_real(card, k, v(k), 0.0_wp, error); if (allocated(error)) return
            end do
            if (v(2) == 0.0_wp) v(2) = v(1)
            if (v(4) == 0.0_wp) v(4) = v(3)
            if (v(2) /= v(1) .or. v(4) /= v(3)) then
                call card_error(card, 2, 'a tapered beam (TS2 /= TS1 or TT2 /= TT1) is not in xdyna', error); return
            end if
            call ignored_fields(model, card, [5, 6], 'the reference surface offsets are not used; ignored')
            if (s%elform == 9 .and. s%cst == 0) then
                ! a spot weld: a round bar of diameter TS1 (LS-DYNA's CST 0
                ! for ELFORM 9 means a circle too)
                s%cst = 1
                v(3) = 0
            end if
            s%ts = v(1)
            s%tt = v(3)
            if (s%cst == 0) then
                ! a rectangle TS1 wide along s and TT1 along t
                if (.not. (v(1) > 0.0_wp .and. v(3) > 0.0_wp)) then
                    call card_error(card, 1, 'TS1 and TT1 must be positive', error); return
                end if
                s%a = v(1)*v(3)
                s%iss = v(1)*v(3)**3/12
                s%itt = v(3)*v(1)**3/12
                a = max(v(1), v(3))
                b = min(v(1), v(3))
                s%j = a*b**3*(1.0_wp/3 - 0.21_wp*(b/a)*(1 - b**4/(12*a**4)))
                s%zs = v(1)*v(3)**2/4
                s%zt = v(3)*v(1)**2/4
                s%zj = b**2*(3*a - b)/6
            else if (s%cst == 1) then
                if (.not. (v(1) > 0.0_wp .and. v(3) >= 0.0_wp .and. v(3) < v(1))) then
                    call card_error(card, 1, 'a tube needs its outer diameter TS1 above its inner TT1', error); return
                end if
                s%a = pi/4*(v(1)**2 - v(3)**2)
                s%iss = pi/64*(v(1)**4 - v(3)**4)
                s%itt = s%iss
                s%j = 2*s%iss
                s%zs = (v(1)**3 - v(3)**3)/6
                s%zt = s%zs
                s%zj = pi/12*(v(1)**3 - v(3)**3)
            else
                call make_error(error, ctx%src%where(s%src)//': *SECTION_BEAM field CST: '//itoa(s%cst)// &
                                ' is not 0 (rectangle) or 1 (tube)')
                return
            end if
        end if
        if (.not. allocated(model%sec_beam)) allocate (model%sec_beam(4))
        if (model%nsec_beam == size(model%sec_beam)) model%sec_beam = [model%sec_beam, model%sec_beam]
        model%nsec_beam = model%nsec_beam + 1
        model%sec_beam(model%nsec_beam) = s
        call no_more_cards(ctx, kw, ic + 2, error)
    end subroutine read_section_beam

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
