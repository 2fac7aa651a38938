!> Readers for boundary and initial conditions: *BOUNDARY_SPC_NODE/_SET,
!> *INITIAL_VELOCITY (+_NODE, _GENERATION), *INITIAL_STRESS_SOLID, nodal rigid
!> bodies and spot welds, *CONSTRAINED_EXTRA_NODES_NODE/_SET.
module xd_input_read_conditions
    use xd_kinds, only: wp
    use xd_core_errors, only: error_t, make_error
    use xd_core_strings, only: itoa
    use xd_input_field_reader, only: card_t, get_int, get_real, card_error, card_blank
    use xd_input_keyword_table, only: keyword_t
    use xd_input_context, only: get_id_card, read_ctx_t, get_card, first_card, no_more_cards, add_warning, ignored_fields
    use xd_model, only: model_t, spc_t, init_vel_t, init_stress_t, prescribed_t, nodal_rigid_t, extra_nodes_t, iv_node_set, &
                        iv_node, iv_generation
    implicit none
    private
    public :: read_condition

contains

    subroutine read_condition(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        select case (kw%name)
        case ('BOUNDARY_SPC_NODE', 'BOUNDARY_SPC_SET')
            call read_spc(ctx, kw, model, error)
        case ('BOUNDARY_PRESCRIBED_MOTION_NODE', 'BOUNDARY_PRESCRIBED_MOTION_SET', 'BOUNDARY_PRESCRIBED_MOTION_RIGID')
            call read_prescribed(ctx, kw, model, error)
        case ('CONSTRAINED_NODAL_RIGID_BODY', 'CONSTRAINED_NODAL_RIGID_BODY_INERTIA', 'CONSTRAINED_GENERALIZED_WELD_SPOT')
            call read_nodal_rigid(ctx, kw, model, error)
        case ('CONSTRAINED_EXTRA_NODES_NODE', 'CONSTRAINED_EXTRA_NODES_SET')
            call read_extra_nodes(ctx, kw, model, error)
        case ('INITIAL_VELOCITY')
            call read_initial_velocity(ctx, kw, model, error)
        case ('INITIAL_VELOCITY_NODE')
            call read_initial_velocity_node(ctx, kw, model, error)
        case ('INITIAL_VELOCITY_GENERATION')
            call read_initial_velocity_generation(ctx, kw, model, error)
        case ('INITIAL_STRESS_SOLID')
            call read_initial_stress_solid(ctx, kw, model, error)
        end select
    end subroutine read_condition

    subroutine read_spc(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(spc_t) :: c
        integer :: ic, k, cid
        character(len=:), allocatable :: spec
        if (kw%name == 'BOUNDARY_SPC_SET') then
            spec = 'NSID CID DOFX DOFY DOFZ DOFRX DOFRY DOFRZ'
        else
            spec = 'NID CID DOFX DOFY DOFZ DOFRX DOFRY DOFRZ'
        end if
        do ic = first_card(kw), kw%ncard
            call get_card(ctx, kw, ic, spec, 1, card, error)
            if (allocated(error)) return
            if (card_blank(card)) cycle
            c = spc_t()
            c%is_set = kw%name == 'BOUNDARY_SPC_SET'
            call get_int(card, 1, c%id, 0, error); if (allocated(error)) return
            call get_int(card, 2, cid, 0, error); if (allocated(error)) return
            if (c%id <= 0) then
                call card_error(card, 1, 'id must be a positive integer', error); return
            end if
            c%cid = cid
            do k = 1, 6
                call get_int(card, 2 + k, c%dof(k), 0, error); if (allocated(error)) return
                if (c%dof(k) /= 0 .and. c%dof(k) /= 1) then
                    call card_error(card, 2 + k, 'must be 0 (free) or 1 (fixed)', error); return
                end if
            end do
            c%src = kw%card_line(ic)
            if (.not. allocated(model%spc)) allocate (model%spc(16))
            if (model%nspc == size(model%spc)) model%spc = [model%spc, model%spc]
            model%nspc = model%nspc + 1
            model%spc(model%nspc) = c
        end do
    end subroutine read_spc

    !> Card 1 NSID NSIDEX BOXID IRIGID ICID; card 2 the velocity; card 3 (when
    !> NSIDEX is given) the velocity of the exempted nodes.
    subroutine read_initial_velocity(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(init_vel_t) :: iv, ex
        integer :: ic, boxid, icid, irigid
        ic = first_card(kw)
        if (ic > kw%ncard) return
        call get_card(ctx, kw, ic, 'NSID NSIDEX BOXID IRIGID ICID', 1, card, error)
        if (allocated(error)) return
        iv%kind = iv_node_set
        call get_int(card, 1, iv%id, 0, error); if (allocated(error)) return
        call get_int(card, 2, iv%exempt, 0, error); if (allocated(error)) return
        call get_int(card, 3, boxid, 0, error); if (allocated(error)) return
        ! IRIGID >= 1: the nodes' velocities override *PART_INERTIA's (for
        ! every rigid body: xdyna keeps one flag); rigid bodies without
        ! *PART_INERTIA always take their nodes' velocities (a momentum fit)
        call get_int(card, 4, irigid, 0, error); if (allocated(error)) return
        call get_int(card, 5, icid, 0, error); if (allocated(error)) return
        if (irigid >= 1) model%irigid = .true.
        iv%boxid = boxid
        iv%icid = icid
        iv%src = kw%card_line(ic)
        if (ic + 1 > kw%ncard) then
            call make_error(error, ctx%src%where(kw%kw_line)//': '//trim(kw%written)// &
                            ' card 2 (VX VY VZ VXR VYR VZR) is missing')
            return
        end if
        call read_velocity_card(ctx, kw, ic + 1, 2, iv, error); if (allocated(error)) return
        call push_ivel(model, iv)
        if (iv%exempt /= 0 .and. ic + 2 <= kw%ncard) then
            ex = init_vel_t(kind=iv_node_set, id=iv%exempt, src=kw%card_line(ic + 2), icid=iv%icid)
            call read_velocity_card(ctx, kw, ic + 2, 3, ex, error); if (allocated(error)) return
            call push_ivel(model, ex)
            call no_more_cards(ctx, kw, ic + 3, error)
        else
            call no_more_cards(ctx, kw, ic + 2, error)
        end if
    end subroutine read_initial_velocity

    subroutine read_velocity_card(ctx, kw, ic, cardno, iv, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        integer, intent(in) :: ic, cardno
        type(init_vel_t), intent(inout) :: iv
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        integer :: k
        call get_card(ctx, kw, ic, 'VX VY VZ VXR VYR VZR', cardno, card, error)
        if (allocated(error)) return
        do k = 1, 3
            call get_real(card, k, iv%v(k), 0.0_wp, error); if (allocated(error)) return
            call get_real(card, 3 + k, iv%vr(k), 0.0_wp, error); if (allocated(error)) return
        end do
    end subroutine read_velocity_card

    subroutine read_initial_velocity_node(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(init_vel_t) :: iv
        integer :: ic, k
        do ic = first_card(kw), kw%ncard
            call get_card(ctx, kw, ic, 'NID VX VY VZ VXR VYR VZR ICID', 1, card, error)
            if (allocated(error)) return
            if (card_blank(card)) cycle
            iv = init_vel_t(kind=iv_node, src=kw%card_line(ic))
            call get_int(card, 1, iv%id, 0, error); if (allocated(error)) return
            do k = 1, 3
                call get_real(card, 1 + k, iv%v(k), 0.0_wp, error); if (allocated(error)) return
                call get_real(card, 4 + k, iv%vr(k), 0.0_wp, error); if (allocated(error)) return
            end do
            call get_int(card, 8, iv%icid, 0, error); if (allocated(error)) return
            call push_ivel(model, iv)
        end do
    end subroutine read_initial_velocity_node

    !> Pairs: ID STYP OMEGA VX VY VZ IVATN ICID / XC YC ZC NX NY NZ PHASE IRIGID.
    !> Velocity = (VX,VY,VZ) + OMEGA n x (x - xc), n the unit axis.
    subroutine read_initial_velocity_generation(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card, card2
        type(init_vel_t) :: iv
        integer :: ic, k, icid, ivatn, phase, irigid
        ic = first_card(kw)
        do while (ic <= kw%ncard)
            call get_card(ctx, kw, ic, 'ID STYP OMEGA VX VY VZ IVATN ICID', 1, card, error)
            if (allocated(error)) return
            if (card_blank(card)) then
                ic = ic + 1
                cycle
            end if
            iv = init_vel_t(kind=iv_generation, src=kw%card_line(ic))
            call get_int(card, 1, iv%id, 0, error); if (allocated(error)) return
            call get_int(card, 2, iv%styp, 0, error); if (allocated(error)) return
            call get_real(card, 3, iv%omega, 0.0_wp, error); if (allocated(error)) return
            do k = 1, 3
                call get_real(card, 3 + k, iv%v(k), 0.0_wp, error); if (allocated(error)) return
            end do
            call get_int(card, 7, ivatn, 0, error); if (allocated(error)) return
            call get_int(card, 8, icid, 0, error); if (allocated(error)) return
            if (iv%styp < 1 .or. iv%styp > 3) then
                call card_error(card, 2, 'STYP must be 1 (part set), 2 (part) or 3 (node set)', error)
                return
            end if
            iv%icid = icid
            if (ic + 1 > kw%ncard) then
                call make_error(error, ctx%src%where(kw%card_line(ic))//': '//trim(kw%written)// &
                                ' card 2 (XC YC ZC NX NY NZ PHASE IRIGID) is missing')
                return
            end if
            call get_card(ctx, kw, ic + 1, 'XC YC ZC NX NY NZ PHASE IRIGID', 2, card2, error)
            if (allocated(error)) return
            do k = 1, 3
                call get_real(card2, k, iv%xc(k), 0.0_wp, error); if (allocated(error)) return
                call get_real(card2, 3 + k, iv%axis(k), 0.0_wp, error); if (allocated(error)) return
            end do
            call get_int(card2, 7, phase, 0, error); if (allocated(error)) return
            call get_int(card2, 8, irigid, 0, error); if (allocated(error)) return
            if (irigid >= 1) model%irigid = .true.
            if (iv%omega /= 0.0_wp .and. norm2(iv%axis) == 0.0_wp) then
                call card_error(card2, 4, 'OMEGA is given but the axis NX NY NZ is zero', error)
                return
            end if
            if (norm2(iv%axis) > 0.0_wp) iv%axis = iv%axis/norm2(iv%axis)
            if (ivatn /= 0 .or. phase /= 0) call add_warning(model, &
                ctx%src%where(kw%card_line(ic))//': *INITIAL_VELOCITY_GENERATION fields IVATN/PHASE ignored')
            call push_ivel(model, iv)
            ic = ic + 2
        end do
    end subroutine read_initial_velocity_generation

    !> Card 1 EID NINT NHISV LARGE ...; then NINT cards SIGXX SIGYY SIGZZ SIGXY
    !> SIGYZ SIGZX EPS, averaged onto the one-point element.
    subroutine read_initial_stress_solid(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(init_stress_t) :: is
        integer :: ic, nint, nhisv, large, k, ip
        real(wp) :: s
        ic = first_card(kw)
        do while (ic <= kw%ncard)
            call get_card(ctx, kw, ic, 'EID NINT NHISV LARGE IVEFLG IALEGP NTHINT NTHHSV', 1, card, error)
            if (allocated(error)) return
            call ignored_fields(model, card, [5, 6, 7, 8], 'not used; ignored')
            if (card_blank(card)) then
                ic = ic + 1
                cycle
            end if
            is = init_stress_t(src=kw%card_line(ic))
            call get_int(card, 1, is%eid, 0, error); if (allocated(error)) return
            call get_int(card, 2, nint, 1, error, zero_default=.true.); if (allocated(error)) return
            call get_int(card, 3, nhisv, 0, error); if (allocated(error)) return
            call get_int(card, 4, large, 0, error); if (allocated(error)) return
            if (nhisv /= 0) then
                call card_error(card, 3, 'history variables are not supported (NHISV must be 0)', error); return
            end if
            if (large /= 0) then
                call card_error(card, 4, 'the LARGE format is not supported', error); return
            end if
            if (nint < 1 .or. ic + nint > kw%ncard) then
                call card_error(card, 2, 'NINT stress cards are not all there', error); return
            end if
            do ip = 1, nint
                call get_card(ctx, kw, ic + ip, 'SIGXX SIGYY SIGZZ SIGXY SIGYZ SIGZX EPS', 2, card, error)
                if (allocated(error)) return
                call ignored_fields(model, card, [7], 'initial plastic strain is not used (elastic materials take '// &
                    'initial stress); ignored')
                do k = 1, 6
                    call get_real(card, k, s, 0.0_wp, error); if (allocated(error)) return
                    is%sig(k) = is%sig(k) + s/nint
                end do
            end do
            if (.not. allocated(model%istress)) allocate (model%istress(64))
            if (model%nistress == size(model%istress)) model%istress = [model%istress, model%istress]
            model%nistress = model%nistress + 1
            model%istress(model%nistress) = is
            ic = ic + 1 + nint
        end do
    end subroutine read_initial_stress_solid

    !> ID DOF VAD LCID SF VID DEATH BIRTH, repeated.
    subroutine read_prescribed(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(prescribed_t) :: pm
        integer :: ic, vid
        character(len=:), allocatable :: spec
        if (kw%name == 'BOUNDARY_PRESCRIBED_MOTION_SET') then
            spec = 'NSID DOF VAD LCID SF VID DEATH BIRTH'
        else if (kw%name == 'BOUNDARY_PRESCRIBED_MOTION_RIGID') then
            spec = 'PID DOF VAD LCID SF VID DEATH BIRTH'
        else
            spec = 'NID DOF VAD LCID SF VID DEATH BIRTH'
        end if
        do ic = first_card(kw), kw%ncard
            call get_card(ctx, kw, ic, spec, 1, card, error)
            if (allocated(error)) return
            if (card_blank(card)) cycle
            pm = prescribed_t(is_set=kw%name == 'BOUNDARY_PRESCRIBED_MOTION_SET', &
                              rigid=kw%name == 'BOUNDARY_PRESCRIBED_MOTION_RIGID', src=kw%card_line(ic))
            call get_int(card, 1, pm%id, 0, error); if (allocated(error)) return
            call get_int(card, 2, pm%dof, 0, error); if (allocated(error)) return
            call get_int(card, 3, pm%vad, 0, error); if (allocated(error)) return
            call get_int(card, 4, pm%lcid, 0, error); if (allocated(error)) return
            call get_real(card, 5, pm%sf, 1.0_wp, error, zero_default=.true.); if (allocated(error)) return
            call get_int(card, 6, vid, 0, error); if (allocated(error)) return
            call get_real(card, 7, pm%death, 1.0e28_wp, error, zero_default=.true.); if (allocated(error)) return
            call get_real(card, 8, pm%birth, 0.0_wp, error); if (allocated(error)) return
            if (pm%id <= 0) then
                call card_error(card, 1, 'id must be a positive integer', error); return
            end if
            if (pm%rigid) then
                if (.not. (pm%dof >= 1 .and. pm%dof <= 3) .and. .not. (pm%dof >= 5 .and. pm%dof <= 7)) then
                    call card_error(card, 2, 'DOF '//trim(card%f(2))//' is not supported on rigid bodies '// &
                                    '(1-3 translation, 5-7 rotation about x, y, z)', error)
                    return
                end if
                if (pm%dof >= 5 .and. pm%vad /= 0) then
                    call card_error(card, 3, 'rotations can be prescribed as angular velocity (VAD 0) only', error)
                    return
                end if
            else if (pm%dof < 1 .or. pm%dof > 3) then
                call card_error(card, 2, 'DOF '//trim(card%f(2))//' is not supported on nodes (1-3: x, y, z)', error)
                return
            end if
            if (pm%vad < 0 .or. pm%vad > 2) then
                call card_error(card, 3, 'VAD must be 0 (velocity), 1 (acceleration) or 2 (displacement)', error)
                return
            end if
            if (pm%lcid <= 0) then
                call card_error(card, 4, 'a load curve id is required', error); return
            end if
            if (pm%death <= pm%birth) then
                call card_error(card, 7, 'DEATH must be later than BIRTH', error); return
            end if
            if (.not. allocated(model%presc)) allocate (model%presc(8))
            if (model%npresc == size(model%presc)) model%presc = [model%presc, model%presc]
            model%npresc = model%npresc + 1
            model%presc(model%npresc) = pm
        end do
    end subroutine read_prescribed

    !> *CONSTRAINED_NODAL_RIGID_BODY: PID CID NSID PNODE IPRT DRFLAG RRFLAG.
    !> *CONSTRAINED_GENERALIZED_WELD_SPOT: NSID CID FILTER WINDOW NPR NPRT;
    !> TFAIL EPSF SN SS N M (failure at TFAIL; the force and strain criteria
    !> are refused until they are implemented).
    subroutine read_nodal_rigid(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(nodal_rigid_t) :: r
        integer :: ic, cid, k
        real(wp) :: v
        character(len=80) :: heading
        ic = first_card(kw)
        if (kw%has_id) then
            call get_id_card(ctx, kw, r%id, heading, error)
            if (allocated(error)) return
        end if
        do while (ic <= kw%ncard)
            r = nodal_rigid_t(id=r%id, src=kw%card_line(ic))
            if (kw%name == 'CONSTRAINED_NODAL_RIGID_BODY' .or. kw%name == 'CONSTRAINED_NODAL_RIGID_BODY_INERTIA') then
                call get_card(ctx, kw, ic, 'PID CID NSID PNODE IPRT DRFLAG RRFLAG', 1, card, error)
                if (allocated(error)) return
                call ignored_fields(model, card, [4, 5, 6, 7], 'PNODE, printing and release flags are not used; ignored')
                if (card_blank(card)) then
                    ic = ic + 1
                    cycle
                end if
                call get_int(card, 1, r%id, 0, error); if (allocated(error)) return
                call get_int(card, 2, cid, 0, error); if (allocated(error)) return
                call get_int(card, 3, r%nsid, 0, error); if (allocated(error)) return
                ic = ic + 1
                if (kw%name == 'CONSTRAINED_NODAL_RIGID_BODY_INERTIA') then
                    ! cards 2-4: XC YC ZC TM IRCS NODEID; IXX..IZZ; VTX..VRZ
                    if (ic + 2 > kw%ncard) then
                        call make_error(error, ctx%src%where(r%src)//': '//trim(kw%written)//' needs cards 2 to 4 '// &
                                        '(XC YC ZC TM IRCS NODEID; IXX IXY IXZ IYY IYZ IZZ; VTX..VRZ)')
                        return
                    end if
                    r%inertia = .true.
                    call get_card(ctx, kw, ic, 'XC YC ZC TM IRCS NODEID', 2, card, error)
                    if (allocated(error)) return
                    do k = 1, 3
                        call get_real(card, k, r%xc(k), 0.0_wp, error); if (allocated(error)) return
                    end do
                    call get_real(card, 4, r%tm, 0.0_wp, error); if (allocated(error)) return
                    call get_int(card, 5, k, 0, error); if (allocated(error)) return
                    if (k /= 0) then
                        call card_error(card, 5, 'IRCS 1 (principal moments with orientation vectors) is not '// &
                                        'supported; give the global tensor (IRCS 0)', error)
                        return
                    end if
                    call get_int(card, 6, r%nodeid, 0, error); if (allocated(error)) return
                    if (.not. (r%tm > 0.0_wp)) then
                        call card_error(card, 4, 'the translational mass TM must be positive', error); return
                    end if
                    call get_card(ctx, kw, ic + 1, 'IXX IXY IXZ IYY IYZ IZZ', 3, card, error)
                    if (allocated(error)) return
                    do k = 1, 6
                        call get_real(card, k, r%itens(k), 0.0_wp, error); if (allocated(error)) return
                    end do
                    if (.not. (r%itens(1) > 0.0_wp .and. r%itens(4) > 0.0_wp .and. r%itens(6) > 0.0_wp)) then
                        call card_error(card, 1, 'IXX, IYY and IZZ must be positive', error); return
                    end if
                    call get_card(ctx, kw, ic + 2, 'VTX VTY VTZ VRX VRY VRZ', 4, card, error)
                    if (allocated(error)) return
                    do k = 1, 3
                        call get_real(card, k, r%vt(k), 0.0_wp, error); if (allocated(error)) return
                        call get_real(card, 3 + k, r%vr(k), 0.0_wp, error); if (allocated(error)) return
                    end do
                    ic = ic + 3
                end if
            else
                r%weld = .true.
                call get_card(ctx, kw, ic, 'NSID CID FILTER WINDOW NPR NPRT', 1, card, error)
                if (allocated(error)) return
                call ignored_fields(model, card, [3, 4, 5, 6], 'force filtering and printing options are not used; ignored')
                call get_int(card, 1, r%nsid, 0, error); if (allocated(error)) return
                call get_int(card, 2, cid, 0, error); if (allocated(error)) return
                if (ic + 1 <= kw%ncard) then
                    call get_card(ctx, kw, ic + 1, 'TFAIL EPSF SN SS N M', 2, card, error)
                    if (allocated(error)) return
                    call ignored_fields(model, card, [5, 6], 'the exponents of the force criterion (refused) are not '// &
                        'used; ignored')
                    call get_real(card, 1, r%tfail, 1.0e20_wp, error, zero_default=.true.)
                    if (allocated(error)) return
                    do k = 2, 4
                        call get_real(card, k, v, 0.0_wp, error); if (allocated(error)) return
                        if (v > 0.0_wp) then
                            call card_error(card, k, 'only the failure time TFAIL is implemented; '// &
                                            'EPSF, SN and SS must be 0', error)
                            return
                        end if
                    end do
                end if
                ic = ic + 2
            end if
            ! CID: the system LS-DYNA writes the body's (weld's) output in
            if (cid /= 0) call add_warning(model, ctx%src%where(r%src)//': '//trim(kw%written)//' field CID = '// &
                                           itoa(cid)//': output in local axes is not written; ignored')
            if (r%nsid <= 0) then
                call make_error(error, ctx%src%where(r%src)//': '//trim(kw%written)//' field NSID: a node set is required')
                return
            end if
            if (.not. allocated(model%nrb)) allocate (model%nrb(8))
            if (model%nnrb == size(model%nrb)) model%nrb = [model%nrb, model%nrb]
            model%nnrb = model%nnrb + 1
            model%nrb(model%nnrb) = r
        end do
    end subroutine read_nodal_rigid

    !> *CONSTRAINED_EXTRA_NODES_NODE / _SET: PID NID (NSID) IFLAG, one card
    !> each; the part and the nodes are checked once the deck is read.
    subroutine read_extra_nodes(ctx, kw, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(keyword_t), intent(in) :: kw
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(card_t) :: card
        type(extra_nodes_t) :: r
        integer :: ic
        logical :: set
        set = kw%name == 'CONSTRAINED_EXTRA_NODES_SET'
        do ic = 1, kw%ncard
            if (set) then
                call get_card(ctx, kw, ic, 'PID NSID IFLAG', 1, card, error)
            else
                call get_card(ctx, kw, ic, 'PID NID IFLAG', 1, card, error)
            end if
            if (allocated(error)) return
            if (card_blank(card)) cycle
            r = extra_nodes_t(set=set, src=kw%card_line(ic))
            call get_int(card, 1, r%pid, 0, error); if (allocated(error)) return
            call get_int(card, 2, r%id, 0, error); if (allocated(error)) return
            call get_int(card, 3, r%iflag, 0, error); if (allocated(error)) return
            if (r%pid <= 0) then
                call card_error(card, 1, 'PID must name a rigid part', error); return
            end if
            if (r%id <= 0) then
                if (set) then
                    call card_error(card, 2, 'NSID must name a node set', error)
                else
                    call card_error(card, 2, 'NID must name a node', error)
                end if
                return
            end if
            if (r%iflag /= 0 .and. r%iflag /= 1) then
                call card_error(card, 3, 'IFLAG must be 0 or 1', error); return
            end if
            if (.not. allocated(model%xn)) allocate (model%xn(8))
            if (model%nxn == size(model%xn)) model%xn = [model%xn, model%xn]
            model%nxn = model%nxn + 1
            model%xn(model%nxn) = r
        end do
    end subroutine read_extra_nodes

    subroutine push_ivel(model, iv)
        type(model_t), intent(inout) :: model
        type(init_vel_t), intent(in) :: iv
        if (.not. allocated(model%ivel)) allocate (model%ivel(16))
        if (model%nivel == size(model%ivel)) model%ivel = [model%ivel, model%ivel]
        model%nivel = model%nivel + 1
        model%ivel(model%nivel) = iv
    end subroutine push_ivel

end module xd_input_read_conditions
