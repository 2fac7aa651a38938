!> Model checks before the run: every referenced id exists, no id is defined
!> twice, densities and moduli are positive, no hexahedron is inverted or
!> degenerate. Resolves ids to indices on the way.
module xd_input_model_check
    use xd_kinds, only: wp, dp
    use xd_core_errors, only: error_t, make_error
    use xd_core_strings, only: itoa
    use xd_core_sorting, only: id_map_t
    use xd_input_context, only: read_ctx_t, add_warning
    use xd_input_set_rules, only: resolve_set_rules, resolve_segment_rules
    use xd_input_check_contacts, only: check_contacts
    use xd_elements_hex8, only: hex_volume_operator, hex_corner_jacobians, hex_shape_kind, &
                                hex_regular, hex_wedge, hex_tet, hex_bad
    use xd_model, only: model_t, find_set, hg_bounded, mat_rigid, mat_elastic, mat_spotweld, mat_plastic_kinematic, &
        mat_piecewise_linear, set_node, set_shell, pressure_t, set_part, &
        iv_node_set, iv_node, &
        iv_generation, find_box, find_coord, point_mass_t
    implicit none
    private
    public :: check_model, id_maps_t

    type :: id_maps_t
        type(id_map_t) :: node, hex, part, sec, mat, hg
    end type id_maps_t

contains

    subroutine check_model(ctx, model, maps, error)
        type(read_ctx_t), intent(in) :: ctx
        type(model_t), intent(inout) :: model
        type(id_maps_t), intent(out) :: maps
        type(error_t), allocatable, intent(out) :: error
        call build_maps(ctx, model, maps, error); if (allocated(error)) return
        call check_parts(ctx, model, maps, error); if (allocated(error)) return
        call check_hexes(ctx, model, maps, error); if (allocated(error)) return
        call check_shells(ctx, model, maps, error); if (allocated(error)) return
        call check_beams(ctx, model, maps, error); if (allocated(error)) return
        call check_rigid_mass(ctx, model, maps, error); if (allocated(error)) return
        call check_sets(ctx, model, maps, error); if (allocated(error)) return
        call apply_coordinate_systems(ctx, model, maps%node, error); if (allocated(error)) return
        call check_conditions(ctx, model, maps, error); if (allocated(error)) return
        call check_loads(ctx, model, maps%node, maps%part, error); if (allocated(error)) return
        call check_contacts(ctx, model, maps%part, error); if (allocated(error)) return
        call check_controls(model, error); if (allocated(error)) return
        ! (the cards' source lines, for the checks' messages: read no more)
        if (allocated(model%node_src)) deallocate (model%node_src)
        if (allocated(model%hex_src)) deallocate (model%hex_src)
        if (allocated(model%shell_src)) deallocate (model%shell_src)
        if (allocated(model%beam_src)) deallocate (model%beam_src)
    end subroutine check_model

    subroutine build_maps(ctx, model, maps, error)
        type(read_ctx_t), intent(in) :: ctx
        type(model_t), intent(inout) :: model
        type(id_maps_t), intent(out) :: maps
        type(error_t), allocatable, intent(out) :: error
        integer :: dup, k, j
        if (model%nnode == 0) then
            call make_error(error, model%deck_path//': the deck defines no nodes')
            return
        end if
        call maps%node%build(model%node_id(1:model%nnode), dup)
        if (dup /= 0) then
            call dup_error('*NODE', dup, model%node_id(1:model%nnode), model%node_src(1:model%nnode))
            return
        end if
        call maps%hex%build(model%hex_id(1:model%nhex), dup)
        if (dup /= 0) then
            call dup_error('*ELEMENT_SOLID', dup, model%hex_id(1:model%nhex), model%hex_src(1:model%nhex))
            return
        end if
        call maps%part%build(model%part(1:model%npart)%id, dup)
        if (dup /= 0) then
            call dup_error('*PART', dup, model%part(1:model%npart)%id, model%part(1:model%npart)%src)
            return
        end if
        call maps%sec%build(model%sec_solid(1:model%nsec_solid)%id, dup)
        if (dup /= 0) then
            call dup_error('*SECTION_SOLID', dup, model%sec_solid(1:model%nsec_solid)%id, &
                           model%sec_solid(1:model%nsec_solid)%src)
            return
        end if
        call maps%mat%build(model%mat(1:model%nmat)%id, dup)
        if (dup /= 0) then
            call dup_error('material', dup, model%mat(1:model%nmat)%id, model%mat(1:model%nmat)%src)
            return
        end if
        ! *MAT_ADD_EROSION: its criteria join the material it names
        if (allocated(model%erosion)) then
            do k = 1, size(model%erosion)
                associate (ad => model%erosion(k))
                    j = maps%mat%find(ad%id)
                    if (j == 0) then
                        call make_error(error, ctx%src%where(ad%add_src)//': *MAT_ADD_EROSION field MID: material '// &
                                        itoa(ad%id)//' is not defined')
                        return
                    end if
                    model%mat(j)%erosion = .true.
                    model%mat(j)%mxpres = ad%mxpres
                    model%mat(j)%mnpres = ad%mnpres
                    model%mat(j)%sigp1 = ad%sigp1
                    model%mat(j)%sigvm = ad%sigvm
                    model%mat(j)%failtm = ad%failtm
                    model%mat(j)%mneps = ad%mneps
                    model%mat(j)%mxeps = ad%mxeps
                    model%mat(j)%effeps = ad%effeps
                    model%mat(j)%voleps = ad%voleps
                    model%mat(j)%epssh = ad%epssh
                    model%mat(j)%numfip = ad%numfip
                    model%mat(j)%ncs = ad%ncs
                    model%mat(j)%add_src = ad%add_src
                end associate
            end do
        end if
        call maps%hg%build(model%hg(1:model%nhg)%id, dup)
        if (dup /= 0) then
            call dup_error('*HOURGLASS', dup, model%hg(1:model%nhg)%id, model%hg(1:model%nhg)%src)
            return
        end if
    contains
        subroutine dup_error(what, id, ids, src)
            character(len=*), intent(in) :: what
            integer, intent(in) :: id, ids(:), src(:)
            integer :: k
            do k = size(ids), 1, -1
                if (ids(k) == id) exit
            end do
            call make_error(error, ctx%src%where(src(k))//': '//what//' '//itoa(id)//' is defined twice')
        end subroutine dup_error
    end subroutine build_maps

    subroutine check_parts(ctx, model, maps, error)
        type(read_ctx_t), intent(in) :: ctx
        type(model_t), intent(inout) :: model
        type(id_maps_t), intent(in) :: maps
        type(error_t), allocatable, intent(out) :: error
        integer :: i
        do i = 1, model%npart
            associate (p => model%part(i))
                p%sec_ix = maps%sec%find(p%secid)
                p%shell_sec_ix = 0
                if (p%sec_ix == 0) p%shell_sec_ix = findloc(model%sec_shell(1:model%nsec_shell)%id, p%secid, 1)
                p%beam_sec_ix = 0
                if (p%sec_ix == 0 .and. p%shell_sec_ix == 0) &
                    p%beam_sec_ix = findloc(model%sec_beam(1:model%nsec_beam)%id, p%secid, 1)
                p%mat_ix = maps%mat%find(p%mid)
                p%hg_ix = 0
                if (p%hgid /= 0) p%hg_ix = maps%hg%find(p%hgid)
                if (p%sec_ix == 0 .and. p%shell_sec_ix == 0 .and. p%beam_sec_ix == 0) then
                    call make_error(error, ctx%src%where(p%src)//': *PART '//itoa(p%id)// &
                                    ' field SECID: section '//itoa(p%secid)//' is not defined')
                    return
                end if
                if (p%mat_ix == 0) then
                    call make_error(error, ctx%src%where(p%src)//': *PART '//itoa(p%id)// &
                                    ' field MID: material '//itoa(p%mid)//' is not defined')
                    return
                end if
                if (p%hgid /= 0 .and. p%hg_ix == 0) then
                    call make_error(error, ctx%src%where(p%src)//': *PART '//itoa(p%id)// &
                                    ' field HGID: *HOURGLASS '//itoa(p%hgid)//' is not defined')
                    return
                end if
            end associate
        end do
    end subroutine check_parts

    !> Where an element is, for a message: "deck.k:123: *ELEMENT_SHELL 456"
    !> (made only when a message needs it: one string per element had been
    !> a third of a 120,000-shell deck's input phase).
    function element_at(ctx, line, keyword, id) result(w)
        type(read_ctx_t), intent(in) :: ctx
        integer, intent(in) :: line, id
        character(len=*), intent(in) :: keyword
        character(len=:), allocatable :: w
        w = ctx%src%where(line)//': '//keyword//' '//itoa(id)
    end function element_at

    !> Resolve element nodes and parts; reject inverted and degenerate shapes.
    !> Wedges (N5=N6, N7=N8) and tetrahedra (N4=...=N8) are accepted.
    subroutine check_hexes(ctx, model, maps, error)
        type(read_ctx_t), intent(in) :: ctx
        type(model_t), intent(inout) :: model
        type(id_maps_t), intent(in) :: maps
        type(error_t), allocatable, intent(out) :: error
        integer :: e, k, nid, kind, nwedge, ntet
        real(wp) :: xe(8, 3), b(8, 3), vol, cj(8)
        allocate (model%hex_part(model%nhex))
        nwedge = 0
        ntet = 0
        do e = 1, model%nhex
            model%hex_part(e) = maps%part%find(model%hex_pid(e))
            if (model%hex_part(e) == 0) then
                call make_error(error, at()//' field PID: part '//itoa(model%hex_pid(e))//' is not defined')
                return
            end if
            if (model%part(model%hex_part(e))%sec_ix == 0) then
                call make_error(error, at()//' field PID: part '//itoa(model%hex_pid(e))//' has a shell section')
                return
            end if
            do k = 1, 8
                nid = model%hex_conn(k, e)
                model%hex_conn(k, e) = maps%node%find(nid)
                if (model%hex_conn(k, e) == 0) then
                    call make_error(error, at()//' field N'//itoa(k)//': node '//itoa(nid)//' is not defined')
                    return
                end if
            end do
            kind = hex_shape_kind(model%hex_conn(:, e))
            if (kind == hex_bad) then
                call make_error(error, at()//' is degenerate: repeated nodes other than the wedge '// &
                                '(N5=N6, N7=N8) or tetrahedron (N4=...=N8) patterns')
                return
            end if
            if (kind == hex_wedge) nwedge = nwedge + 1
            if (kind == hex_tet) ntet = ntet + 1
            do k = 1, 8
                xe(k, :) = model%x0(:, model%hex_conn(k, e))
            end do
            call hex_volume_operator(xe, b, vol)
            if (.not. (vol > 0.0_wp)) then
                call make_error(error, at()//' is inverted (volume '//trim(rtoa_short(vol))// &
                                '): number its nodes counter-clockwise seen from outside the N1-N4 face')
                return
            end if
            if (kind == hex_regular) then
                call hex_corner_jacobians(xe, cj)
                if (any(cj <= 0.0_wp)) then
                    call make_error(error, at()//' is distorted: its corner at node '// &
                                    itoa(model%node_id(model%hex_conn(minloc(cj, 1), e)))// &
                                    ' is inverted (non-positive corner Jacobian)')
                    return
                end if
            end if
        end do
        if (nwedge > 0) call add_warning(model, itoa(nwedge)//' solid elements are degenerate wedges '// &
                                         '(treated as one-point hexahedra)')
        if (ntet > 0) call add_warning(model, itoa(ntet)//' solid elements are degenerate tetrahedra '// &
                                       '(treated as one-point hexahedra)')
    contains
        function at() result(w)
            character(len=:), allocatable :: w
            w = element_at(ctx, model%hex_src(e), '*ELEMENT_SOLID', model%hex_id(e))
        end function at
    end subroutine check_hexes

    !> Shell elements: parts with shell sections, nodes, thickness, area.
    subroutine check_shells(ctx, model, maps, error)
        type(read_ctx_t), intent(in) :: ctx
        type(model_t), intent(inout) :: model
        type(id_maps_t), intent(in) :: maps
        type(error_t), allocatable, intent(out) :: error
        integer :: e, k, nid, p
        real(wp) :: an(3), d1(3), d2(3)
        if (model%nshell == 0) return
        allocate (model%shell_part(model%nshell))
        do e = 1, model%nshell
            p = maps%part%find(model%shell_pid(e))
            model%shell_part(e) = p
            if (p == 0) then
                call make_error(error, at()//' field PID: part '//itoa(model%shell_pid(e))//' is not defined')
                return
            end if
            if (model%part(p)%shell_sec_ix == 0) then
                call make_error(error, at()//' field PID: part '//itoa(model%shell_pid(e))//' has no shell section')
                return
            end if
            do k = 1, 4
                nid = model%shell_conn(k, e)
                model%shell_conn(k, e) = maps%node%find(nid)
                if (model%shell_conn(k, e) == 0) then
                    call make_error(error, at()//' field N'//itoa(k)//': node '//itoa(nid)//' is not defined')
                    return
                end if
            end do
            where (model%shell_t(:, e) <= 0.0_wp) model%shell_t(:, e) = model%sec_shell(model%part(p)%shell_sec_ix)%t
            if (any(model%shell_t(:, e) <= 0.0_wp) .and. model%mat(model%part(p)%mat_ix)%mtype /= mat_rigid) then
                call make_error(error, at()//': zero thickness at a node (neither the element nor section '// &
                                itoa(model%part(p)%secid)//' of part '//itoa(model%part(p)%id)// &
                                ' gives one); a deformable shell needs a positive thickness')
                return
            end if
            d1 = model%x0(:, model%shell_conn(3, e)) - model%x0(:, model%shell_conn(1, e))
            d2 = model%x0(:, model%shell_conn(4, e)) - model%x0(:, model%shell_conn(2, e))
            if (model%shell_conn(3, e) == model%shell_conn(4, e)) &
                d2 = model%x0(:, model%shell_conn(3, e)) - model%x0(:, model%shell_conn(2, e))
            an = [d1(2)*d2(3) - d1(3)*d2(2), d1(3)*d2(1) - d1(1)*d2(3), d1(1)*d2(2) - d1(2)*d2(1)]
            if (.not. (norm2(an) > 0.0_wp)) then
                call make_error(error, at()//' is degenerate (zero area)')
                return
            end if
        end do
    contains
        function at() result(w)
            character(len=:), allocatable :: w
            w = element_at(ctx, model%shell_src(e), '*ELEMENT_SHELL', model%shell_id(e))
        end function at
    end subroutine check_shells

    !> *ELEMENT_BEAM: parts with a beam section and an elastic material (the
    !> resultant beam's elastic response; plastic beams are not in xdyna),
    !> nodes defined, N1 /= N2, an orientation node off the beam's axis.
    subroutine check_beams(ctx, model, maps, error)
        type(read_ctx_t), intent(in) :: ctx
        type(model_t), intent(inout) :: model
        type(id_maps_t), intent(in) :: maps
        type(error_t), allocatable, intent(out) :: error
        integer :: e, k, p, nid
        real(wp) :: d1(3), d3(3)
        integer, allocatable :: warned(:)
        if (model%nbeam == 0) return
        allocate (warned(0))
        allocate (model%beam_part(model%nbeam))
        do e = 1, model%nbeam
            p = maps%part%find(model%beam_pid(e))
            model%beam_part(e) = p
            if (p == 0) then
                call make_error(error, at()//' field PID: part '//itoa(model%beam_pid(e))//' is not defined')
                return
            end if
            if (model%part(p)%beam_sec_ix == 0) then
                call make_error(error, at()//' field PID: part '//itoa(model%beam_pid(e))//' has no beam section')
                return
            end if
            select case (model%mat(model%part(p)%mat_ix)%mtype)
            case (mat_elastic)
            case (mat_spotweld)
                if (model%mat(model%part(p)%mat_ix)%sigy > 0.0_wp .and. &
                    model%sec_beam(model%part(p)%beam_sec_ix)%elform == 2 .and. .not. any(warned == p)) then
                    warned = [warned, p]
                    call add_warning(model, at()//': part '//itoa(model%beam_pid(e))//': a spot weld on an ELFORM 2 '// &
                                     'section (no dimensions for its plastic resultants) stays elastic: SIGY, EH and '// &
                                     'EFAIL are not used')
                end if
            case (mat_plastic_kinematic, mat_piecewise_linear)
                associate (m => model%mat(model%part(p)%mat_ix))
                    if ((m%beta < 1.0_wp .or. m%c > 0.0_wp) .and. .not. any(warned == p)) then
                        warned = [warned, p]
                        call add_warning(model, at()//': part '//itoa(model%beam_pid(e))//': the Hughes-Liu beam''s '// &
                                         'section points harden isotropically at the material''s rate-free flow '// &
                                         'stress (BETA''s kinematic share and the strain-rate factor are not used '// &
                                         'for beams)')
                    end if
                end associate
                if (model%sec_beam(model%part(p)%beam_sec_ix)%elform /= 1) then
                    call make_error(error, at()//' field PID: part '//itoa(model%beam_pid(e))//': a plastic beam needs '// &
                                    'the section''s dimensions (ELFORM 1, Hughes-Liu, integrates its stresses over '// &
                                    'them); ELFORM 2 and 9 take an elastic material in xdyna')
                    return
                end if
            case default
                call make_error(error, at()//' field PID: part '//itoa(model%beam_pid(e))//': beams take *MAT_ELASTIC, '// &
                                '*MAT_SPOTWELD, or (ELFORM 1) *MAT_003 / *MAT_024 in xdyna; rigid beams are not in xdyna')
                return
            end select
            do k = 1, 3
                nid = model%beam_conn(k, e)
                if (k == 3 .and. nid == 0) cycle
                model%beam_conn(k, e) = maps%node%find(nid)
                if (model%beam_conn(k, e) == 0) then
                    call make_error(error, at()//' field N'//itoa(k)//': node '//itoa(nid)//' is not defined')
                    return
                end if
            end do
            d1 = model%x0(:, model%beam_conn(2, e)) - model%x0(:, model%beam_conn(1, e))
            if (.not. (norm2(d1) > 0.0_wp)) then
                call make_error(error, at()//' has zero length (N1 and N2 coincide)')
                return
            end if
            if (model%beam_conn(3, e) > 0) then
                d3 = model%x0(:, model%beam_conn(3, e)) - model%x0(:, model%beam_conn(1, e))
                if (norm2([d1(2)*d3(3) - d1(3)*d3(2), d1(3)*d3(1) - d1(1)*d3(3), d1(1)*d3(2) - d1(2)*d3(1)]) <= &
                    1.0e-6_wp*norm2(d1)*norm2(d3)) then
                    call make_error(error, at()//' field N3: the orientation node '// &
                                    itoa(model%node_id(model%beam_conn(3, e)))//' lies on the beam''s axis')
                    return
                end if
            end if
        end do
    contains
        function at() result(w)
            character(len=:), allocatable :: w
            w = element_at(ctx, model%beam_src(e), '*ELEMENT_BEAM', model%beam_id(e))
        end function at
    end subroutine check_beams

    !> *DEFINE_COORDINATE_...: the axes (from the nodes' positions at t = 0
    !> for _NODES), then what is given in them turned global: initial
    !> velocities (ICID: velocities, angular velocities and the generation
    !> axis), body loads (CID: the load acts along the local axis), and
    !> constraints (CID: a local axis along a global one fixes that global
    !> direction; a skewed local axis is refused).
    subroutine apply_coordinate_systems(ctx, model, nodes, error)
        type(read_ctx_t), intent(in) :: ctx
        type(model_t), intent(inout) :: model
        type(id_map_t), intent(in) :: nodes
        type(error_t), allocatable, intent(out) :: error
        integer :: i, k, j, c, dof(6)
        real(wp) :: ex(3), ez(3)
        do i = 1, model%ncoord
            associate (cs => model%coord(i))
                if (cs%by_nodes) then
                    do k = 1, 3
                        j = nodes%find(cs%n(k))
                        if (j == 0) then
                            call make_error(error, ctx%src%where(cs%src)//': *DEFINE_COORDINATE_NODES field N'// &
                                            itoa(k)//': node '//itoa(cs%n(k))//' is not defined')
                            return
                        end if
                        cs%n(k) = j
                    end do
                    cs%o = model%x0(:, cs%n(1))
                    cs%l = model%x0(:, cs%n(2))
                    cs%p = model%x0(:, cs%n(3))
                end if
                ex = cs%l - cs%o
                ez = [ex(2)*(cs%p(3) - cs%o(3)) - ex(3)*(cs%p(2) - cs%o(2)), &
                      ex(3)*(cs%p(1) - cs%o(1)) - ex(1)*(cs%p(3) - cs%o(3)), &
                      ex(1)*(cs%p(2) - cs%o(2)) - ex(2)*(cs%p(1) - cs%o(1))]
                if (.not. (norm2(ex) > 0.0_wp .and. norm2(ez) > 1.0e-9_wp*norm2(ex)*norm2(cs%p - cs%o))) then
                    call make_error(error, ctx%src%where(cs%src)//': coordinate system '//itoa(cs%id)// &
                                    ': its three points are on one line (no axes)')
                    return
                end if
                cs%r(:, 1) = ex/norm2(ex)
                cs%r(:, 3) = ez/norm2(ez)
                cs%r(:, 2) = [cs%r(2, 3)*cs%r(3, 1) - cs%r(3, 3)*cs%r(2, 1), cs%r(3, 3)*cs%r(1, 1) - cs%r(1, 3)*cs%r(3, 1), &
                              cs%r(1, 3)*cs%r(2, 1) - cs%r(2, 3)*cs%r(1, 1)]
            end associate
        end do
        do i = 1, model%nivel
            associate (v => model%ivel(i))
                if (v%icid == 0) cycle
                c = find_coord(model, v%icid)
                if (c == 0) then
                    call make_error(error, ctx%src%where(v%src)//': field ICID: coordinate system '//itoa(v%icid)// &
                                    ' is not defined')
                    return
                end if
                v%v = matmul(model%coord(c)%r, v%v)
                v%vr = matmul(model%coord(c)%r, v%vr)
                v%axis = matmul(model%coord(c)%r, v%axis)
            end associate
        end do
        do i = 1, model%nbody
            associate (b => model%body(i))
                b%d = 0
                b%d(b%dir) = 1
                if (b%cid == 0) cycle
                c = find_coord(model, b%cid)
                if (c == 0) then
                    call make_error(error, ctx%src%where(b%src)//': *LOAD_BODY field CID: coordinate system '// &
                                    itoa(b%cid)//' is not defined')
                    return
                end if
                b%d = model%coord(c)%r(:, b%dir)
            end associate
        end do
        do i = 1, model%nspc
            associate (sp => model%spc(i))
                if (sp%cid == 0) cycle
                c = find_coord(model, sp%cid)
                if (c == 0) then
                    call make_error(error, ctx%src%where(sp%src)//': *BOUNDARY_SPC field CID: coordinate system '// &
                                    itoa(sp%cid)//' is not defined')
                    return
                end if
                dof = 0
                do k = 1, 3
                    j = maxloc(abs(model%coord(c)%r(:, k)), 1)
                    if (sp%dof(k) == 0 .and. sp%dof(k + 3) == 0) cycle
                    if (abs(model%coord(c)%r(j, k)) < 1.0_wp - 1.0e-9_wp) then
                        call make_error(error, ctx%src%where(sp%src)//': *BOUNDARY_SPC field CID: local axis '// &
                                        itoa(k)//' of system '//itoa(sp%cid)//' is not along a global axis; '// &
                                        'constraints along skewed axes are not implemented')
                        return
                    end if
                    dof(j) = max(dof(j), sp%dof(k))
                    dof(j + 3) = max(dof(j + 3), sp%dof(k + 3))
                end do
                sp%dof = dof
                sp%cid = 0
            end associate
        end do
    end subroutine apply_coordinate_systems

    !> A rigid part whose elements have no mass (zero density, or shells of
    !> zero thickness: mass is density x volume, as LS-DYNA computes it)
    !> needs *PART_INERTIA, unless it is fixed in every direction (CMO 1,
    !> CON1 = CON2 = 7), where its mass is never used: that is allowed and
    !> named. *PART_INERTIA is for rigid parts only; its NODEID must exist.
    subroutine check_rigid_mass(ctx, model, maps, error)
        type(read_ctx_t), intent(in) :: ctx
        type(model_t), intent(inout) :: model
        type(id_maps_t), intent(in) :: maps
        type(error_t), allocatable, intent(out) :: error
        integer :: p, e
        logical :: massless, fixed
        do p = 1, model%npart
            associate (pt => model%part(p), mat => model%mat(model%part(p)%mat_ix))
                if (mat%mtype /= mat_rigid) then
                    if (pt%inertia) then
                        call make_error(error, ctx%src%where(pt%src)//': *PART_INERTIA part '//itoa(pt%id)// &
                                        ': its material is not *MAT_RIGID (the inertia of a deformable part '// &
                                        'comes from its elements)')
                        return
                    end if
                    cycle
                end if
                if (pt%inertia) then
                    if (pt%nodeid /= 0 .and. maps%node%find(pt%nodeid) == 0) then
                        call make_error(error, ctx%src%where(pt%src)//': *PART_INERTIA part '//itoa(pt%id)// &
                                        ' field NODEID: node '//itoa(pt%nodeid)//' is not defined')
                        return
                    end if
                    cycle
                end if
                massless = .not. (mat%ro > 0.0_wp)
                if (.not. massless) then
                    massless = .true.
                    do e = 1, model%nshell
                        if (model%shell_part(e) == p .and. any(model%shell_t(:, e) > 0.0_wp)) massless = .false.
                    end do
                    if (model%nhex > 0) then
                        if (any(model%hex_part == p)) massless = .false.
                    end if
                end if
                if (.not. massless) cycle
                fixed = mat%cmo == 1 .and. mat%con1 == 7 .and. mat%con2 == 7
                if (.not. fixed) then
                    call make_error(error, ctx%src%where(pt%src)//': rigid part '//itoa(pt%id)// &
                                    ' has no mass (zero density or zero shell thickness) and is free to move: '// &
                                    'give it a thickness, a density or *PART_INERTIA')
                    return
                end if
                call add_warning(model, ctx%src%where(pt%src)//': rigid part '//itoa(pt%id)//' has no mass '// &
                                 '(zero density or shell thickness); it is fixed in all directions (CMO 1, '// &
                                 'CON1 7, CON2 7), so it runs as a fixed body without mass')
            end associate
        end do
    end subroutine check_rigid_mass

    function rtoa_short(x) result(s)
        real(wp), intent(in) :: x
        character(len=16) :: s
        ! (compared in double: the single build's reals end near 3e38 and
        ! 1e-38, where a three-digit exponent is never needed)
        if (abs(real(x, dp)) >= 1.0e100_dp .or. (abs(real(x, dp)) < 1.0e-99_dp .and. x /= 0.0_wp)) then
            write (s, '(es13.4e3)') x
        else
            write (s, '(es12.4)') x
        end if
        s = adjustl(s)
    end function rtoa_short

    subroutine check_sets(ctx, model, maps, error)
        type(read_ctx_t), intent(in) :: ctx
        type(model_t), intent(inout) :: model
        type(id_maps_t), intent(in) :: maps
        type(error_t), allocatable, intent(out) :: error
        integer :: i, j, k
        do i = 1, model%nset
            do j = 1, i - 1
                if (model%set(j)%id == model%set(i)%id .and. model%set(j)%kind == model%set(i)%kind) then
                    call make_error(error, ctx%src%where(model%set(i)%src)//': '//set_word(model%set(i)%kind)// &
                                    ' '//itoa(model%set(i)%id)//' is defined twice')
                    return
                end if
            end do
        end do
        call resolve_set_rules(ctx, model, maps%node, maps%part, error)
        if (allocated(error)) return
        do i = 1, model%nset
            associate (s => model%set(i))
                allocate (s%member_ix(s%n))
                if (s%kind == set_shell) cycle
                do k = 1, s%n
                    if (s%kind == set_node) then
                        s%member_ix(k) = maps%node%find(s%member(k))
                    else
                        s%member_ix(k) = maps%part%find(s%member(k))
                    end if
                    if (s%member_ix(k) == 0) then
                        call make_error(error, ctx%src%where(s%src)//': '//set_word(s%kind)//' '// &
                                        itoa(s%id)//': '//member_word(s%kind)//' '//itoa(s%member(k))// &
                                        ' is not defined')
                        return
                    end if
                end do
            end associate
        end do
    end subroutine check_sets

    pure function set_word(kind) result(w)
        integer, intent(in) :: kind
        character(len=:), allocatable :: w
        w = '*SET_NODE_LIST'
        if (kind == set_part) w = '*SET_PART_LIST'
    end function set_word

    pure function member_word(kind) result(w)
        integer, intent(in) :: kind
        character(len=:), allocatable :: w
        w = 'node'
        if (kind == set_part) w = 'part'
    end function member_word

    subroutine check_conditions(ctx, model, maps, error)
        type(read_ctx_t), intent(in) :: ctx
        type(model_t), intent(inout) :: model
        type(id_maps_t), intent(in) :: maps
        type(error_t), allocatable, intent(out) :: error
        integer :: i, k
        character(len=:), allocatable :: at
        do i = 1, model%nspc
            associate (c => model%spc(i))
                if (c%is_set) then
                    if (find_set(model, set_node, c%id) == 0) then
                        call make_error(error, ctx%src%where(c%src)//': *BOUNDARY_SPC_SET field NSID: '// &
                                        'node set '//itoa(c%id)//' is not defined')
                        return
                    end if
                else
                    c%ix = maps%node%find(c%id)
                end if
                if (.not. c%is_set .and. c%ix == 0) then
                    call make_error(error, ctx%src%where(c%src)//': *BOUNDARY_SPC_NODE field NID: node '// &
                                    itoa(c%id)//' is not defined')
                    return
                end if
            end associate
        end do
        do i = 1, model%nivel
            associate (v => model%ivel(i))
                select case (v%kind)
                case (iv_node)
                    v%ix = maps%node%find(v%id)
                    if (v%ix == 0) then
                        call make_error(error, ctx%src%where(v%src)//': *INITIAL_VELOCITY_NODE field NID: node '// &
                                        itoa(v%id)//' is not defined')
                        return
                    end if
                case (iv_node_set)
                    if (v%id /= 0 .and. find_set(model, set_node, v%id) == 0) then
                        call make_error(error, ctx%src%where(v%src)//': *INITIAL_VELOCITY field NSID: node set '// &
                                        itoa(v%id)//' is not defined')
                        return
                    end if
                    if (v%exempt /= 0 .and. find_set(model, set_node, v%exempt) == 0) then
                        call make_error(error, ctx%src%where(v%src)//': *INITIAL_VELOCITY field NSIDEX: node set '// &
                                        itoa(v%exempt)//' is not defined')
                        return
                    end if
                    if (v%boxid /= 0 .and. find_box(model, v%boxid) == 0) then
                        call make_error(error, ctx%src%where(v%src)//': *INITIAL_VELOCITY field BOXID: box '// &
                                        itoa(v%boxid)//' is not defined (*DEFINE_BOX)')
                        return
                    end if
                case (iv_generation)
                    select case (v%styp)
                    case (1); k = find_set(model, set_part, v%id)
                    case (2); k = maps%part%find(v%id)
                    case default; k = find_set(model, set_node, v%id)
                    end select
                    if (k == 0) then
                        call make_error(error, ctx%src%where(v%src)//': *INITIAL_VELOCITY_GENERATION field ID: '// &
                                        trim(styp_word(v%styp))//' '//itoa(v%id)//' is not defined')
                        return
                    end if
                end select
            end associate
        end do
        do i = 1, model%nistress
            if (maps%hex%find(model%istress(i)%eid) == 0) then
                call make_error(error, ctx%src%where(model%istress(i)%src)// &
                                ': *INITIAL_STRESS_SOLID field EID: solid element '// &
                                itoa(model%istress(i)%eid)//' is not defined')
                return
            end if
        end do
        ! *CONSTRAINED_EXTRA_NODES: a rigid part, and nodes that exist
        do i = 1, model%nxn
            associate (r => model%xn(i))
                at = ctx%src%where(r%src)//': *CONSTRAINED_EXTRA_NODES_'//trim(merge('SET ', 'NODE', r%set))
                r%part_ix = maps%part%find(r%pid)
                if (r%part_ix == 0) then
                    call make_error(error, at//' field PID: part '//itoa(r%pid)//' is not defined'); return
                end if
                if (model%mat(model%part(r%part_ix)%mat_ix)%mtype /= mat_rigid) then
                    call make_error(error, at//' field PID: part '//itoa(r%pid)//' is not rigid (*MAT_RIGID): '// &
                                    'extra nodes join a rigid body'); return
                end if
                if (r%iflag == 1 .and. model%part(r%part_ix)%inertia) then
                    call make_error(error, at//' field IFLAG: 1 (the nodes'' masses added to *PART_INERTIA''s '// &
                                    'properties) is not in xdyna; give the body''s properties with them, IFLAG 0')
                    return
                end if
                if (r%set) then
                    k = find_set(model, set_node, r%id)
                    if (k == 0) then
                        call make_error(error, at//' field NSID: node set '//itoa(r%id)//' is not defined'); return
                    end if
                    r%node_ix = model%set(k)%member_ix
                else
                    k = maps%node%find(r%id)
                    if (k == 0) then
                        call make_error(error, at//' field NID: node '//itoa(r%id)//' is not defined'); return
                    end if
                    r%node_ix = [k]
                end if
            end associate
        end do
        ! *ELEMENT_MASS_NODE_SET: each set's mass shared equally, one point
        ! mass a node
        if (any(model%pmass(1:model%npmass)%set)) then
            block
                type(point_mass_t), allocatable :: pms(:)
                integer :: ks, q
                allocate (pms(0))
                do i = 1, model%npmass
                    associate (pm => model%pmass(i))
                        if (.not. pm%set) then
                            pms = [pms, pm]
                            cycle
                        end if
                        ks = find_set(model, set_node, pm%nid)
                        if (ks == 0) then
                            call make_error(error, ctx%src%where(pm%src)//': *ELEMENT_MASS_NODE_SET '//itoa(pm%eid)// &
                                            ' field NSID: node set '//itoa(pm%nid)//' is not defined')
                            return
                        end if
                        if (model%set(ks)%n == 0) then
                            call make_error(error, ctx%src%where(pm%src)//': *ELEMENT_MASS_NODE_SET '//itoa(pm%eid)// &
                                            ' field NSID: node set '//itoa(pm%nid)//' is empty')
                            return
                        end if
                        do q = 1, model%set(ks)%n
                            pms = [pms, point_mass_t(eid=pm%eid, nid=model%set(ks)%member(q), &
                                                     mass=pm%mass/model%set(ks)%n, src=pm%src)]
                        end do
                    end associate
                end do
                model%pmass = pms
                model%npmass = size(pms)
            end block
        end if
        ! *ELEMENT_MASS_PART(_SET): the parts
        if (allocated(model%partmass)) then
            do i = 1, size(model%partmass)
                associate (pm => model%partmass(i))
                    if (pm%set) then
                        k = find_set(model, set_part, pm%id)
                        if (k == 0) then
                            call make_error(error, ctx%src%where(pm%src)//': *ELEMENT_MASS_PART_SET field PSID: '// &
                                            'part set '//itoa(pm%id)//' is not defined')
                            return
                        end if
                        pm%part_ix = model%set(k)%member_ix
                    else
                        k = maps%part%find(pm%id)
                        if (k == 0) then
                            call make_error(error, ctx%src%where(pm%src)//': *ELEMENT_MASS_PART field PID: part '// &
                                            itoa(pm%id)//' is not defined')
                            return
                        end if
                        pm%part_ix = [k]
                    end if
                end associate
            end do
        end if
        do i = 1, model%npmass
            associate (pm => model%pmass(i))
                pm%ix = maps%node%find(pm%nid)
                if (pm%ix == 0) then
                    call make_error(error, ctx%src%where(pm%src)//': *ELEMENT_MASS '//itoa(pm%eid)//' field NID: node '// &
                                    itoa(pm%nid)//' is not defined')
                    return
                end if
            end associate
        end do
        if (allocated(model%db%hist_node)) then
            allocate (model%db%hist_node_ix(size(model%db%hist_node)))
            do k = 1, size(model%db%hist_node)
                model%db%hist_node_ix(k) = maps%node%find(model%db%hist_node(k))
                if (model%db%hist_node_ix(k) == 0) then
                    call make_error(error, model%deck_path//': *DATABASE_HISTORY_NODE: node '// &
                                    itoa(model%db%hist_node(k))//' is not defined')
                    return
                end if
            end do
        end if
        if (allocated(model%db%hist_set)) then
            do k = 1, size(model%db%hist_set)
                if (find_set(model, set_node, model%db%hist_set(k)) == 0) then
                    call make_error(error, model%deck_path//': *DATABASE_HISTORY_NODE_SET: node set '// &
                                    itoa(model%db%hist_set(k))//' is not defined')
                    return
                end if
            end do
        end if
    end subroutine check_conditions

    !> Curves defined once; body loads name a curve; wall node sets exist.
    subroutine check_loads(ctx, model, nodes, parts, error)
        type(read_ctx_t), intent(in) :: ctx
        type(model_t), intent(inout) :: model
        type(id_map_t), intent(in) :: nodes, parts
        type(error_t), allocatable, intent(out) :: error
        type(id_map_t) :: curves
        integer :: dup, i, j, k, nid
        call curves%build(model%curve(1:model%ncurve)%id, dup)
        if (dup /= 0) then
            do i = model%ncurve, 1, -1
                if (model%curve(i)%id == dup) exit
            end do
            call make_error(error, ctx%src%where(model%curve(i)%src)//': *DEFINE_CURVE '//itoa(dup)// &
                            ' is defined twice')
            return
        end if
        do i = 1, model%nbody
            associate (b => model%body(i))
                b%curve_ix = curves%find(b%lcid)
                if (b%curve_ix == 0) then
                    call make_error(error, ctx%src%where(b%src)//': *LOAD_BODY_'//'XYZ'(b%dir:b%dir)// &
                                    ' field LCID: curve '//itoa(b%lcid)//' is not defined')
                    return
                end if
            end associate
        end do
        do i = 1, model%nmat
            associate (m => model%mat(i))
                if (m%lcss == 0) cycle
                m%lcss_ix = curves%find(m%lcss)
                if (m%lcss_ix == 0) then
                    call make_error(error, ctx%src%where(m%src)//': *MAT_PIECEWISE_LINEAR_PLASTICITY field LCSS: '// &
                                    'curve '//itoa(m%lcss)//' is not defined')
                    return
                end if
            end associate
        end do
        do i = 1, model%npresc
            associate (pm => model%presc(i))
                pm%curve_ix = curves%find(pm%lcid)
                if (pm%curve_ix == 0) then
                    call make_error(error, ctx%src%where(pm%src)//': *BOUNDARY_PRESCRIBED_MOTION field LCID: curve '// &
                                    itoa(pm%lcid)//' is not defined')
                    return
                end if
                if (pm%rigid) then
                    pm%ix = parts%find(pm%id)
                    if (pm%ix == 0) then
                        call make_error(error, ctx%src%where(pm%src)//': *BOUNDARY_PRESCRIBED_MOTION_RIGID field PID: '// &
                                        'part '//itoa(pm%id)//' is not defined')
                        return
                    end if
                    if (model%mat(model%part(pm%ix)%mat_ix)%mtype /= mat_rigid) then
                        call make_error(error, ctx%src%where(pm%src)//': *BOUNDARY_PRESCRIBED_MOTION_RIGID field PID: '// &
                                        'part '//itoa(pm%id)//' is not a *MAT_RIGID part')
                        return
                    end if
                else if (pm%is_set) then
                    if (find_set(model, set_node, pm%id) == 0) then
                        call make_error(error, ctx%src%where(pm%src)//': *BOUNDARY_PRESCRIBED_MOTION_SET field NSID: '// &
                                        'node set '//itoa(pm%id)//' is not defined')
                        return
                    end if
                else
                    pm%ix = nodes%find(pm%id)
                    if (pm%ix == 0) then
                        call make_error(error, ctx%src%where(pm%src)//': *BOUNDARY_PRESCRIBED_MOTION_NODE field NID: '// &
                                        'node '//itoa(pm%id)//' is not defined')
                        return
                    end if
                end if
            end associate
        end do
        call resolve_segment_rules(ctx, model, parts, error)
        if (allocated(error)) return
        do i = 1, model%nsegset
            associate (ss => model%segset(i))
                do k = 1, ss%n
                    do j = 1, 4
                        nid = ss%seg(j, k)
                        ss%seg(j, k) = nodes%find(nid)
                        if (ss%seg(j, k) == 0) then
                            call make_error(error, ctx%src%where(ss%src)//': *SET_SEGMENT '//itoa(ss%id)// &
                                            ': node '//itoa(nid)//' is not defined')
                            return
                        end if
                    end do
                end do
            end associate
        end do
        call expand_shell_pressures(ctx, model, error)
        if (allocated(error)) return
        do i = 1, model%npress
            associate (pr => model%press(i))
                pr%curve_ix = curves%find(pr%lcid)
                if (pr%curve_ix == 0) then
                    call make_error(error, ctx%src%where(pr%src)//': *LOAD_SEGMENT field LCID: curve '// &
                                    itoa(pr%lcid)//' is not defined')
                    return
                end if
                if (pr%shell_eid < 0) then
                    continue
                else if (pr%ssid > 0) then
                    if (.not. any(model%segset(1:model%nsegset)%id == pr%ssid)) then
                        call make_error(error, ctx%src%where(pr%src)//': *LOAD_SEGMENT_SET field SSID: '// &
                                        'segment set '//itoa(pr%ssid)//' is not defined')
                        return
                    end if
                else
                    do j = 1, 4
                        nid = pr%seg(j)
                        pr%seg(j) = nodes%find(nid)
                        if (pr%seg(j) == 0) then
                            call make_error(error, ctx%src%where(pr%src)//': *LOAD_SEGMENT field N'//itoa(j)// &
                                            ': node '//itoa(nid)//' is not defined')
                            return
                        end if
                    end do
                end if
            end associate
        end do
        do i = 1, model%nnrb
            if (find_set(model, set_node, model%nrb(i)%nsid) == 0) then
                call make_error(error, ctx%src%where(model%nrb(i)%src)//': field NSID: node set '// &
                                itoa(model%nrb(i)%nsid)//' is not defined')
                return
            end if
        end do
        do i = 1, model%nwall
            associate (w => model%wall(i))
                if (w%nsid /= 0 .and. find_set(model, set_node, w%nsid) == 0) then
                    call make_error(error, ctx%src%where(w%src)//': *RIGIDWALL_PLANAR field NSID: node set '// &
                                    itoa(w%nsid)//' is not defined')
                    return
                end if
                if (w%nsidex /= 0 .and. find_set(model, set_node, w%nsidex) == 0) then
                    call make_error(error, ctx%src%where(w%src)//': *RIGIDWALL_PLANAR field NSIDEX: node set '// &
                                    itoa(w%nsidex)//' is not defined')
                    return
                end if
                if (w%boxid /= 0 .and. find_box(model, w%boxid) == 0) then
                    call make_error(error, ctx%src%where(w%src)//': *RIGIDWALL field BOXID: box '// &
                                    itoa(w%boxid)//' is not defined (*DEFINE_BOX)')
                    return
                end if
            end associate
        end do
    end subroutine check_loads

    !> *LOAD_SHELL_ELEMENT and *LOAD_SHELL_SET become segment pressures on the
    !> shells' nodes (node indices; shell_eid = -1 marks them as resolved).
    subroutine expand_shell_pressures(ctx, model, error)
        type(read_ctx_t), intent(in) :: ctx
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        type(id_map_t) :: shells
        type(pressure_t), allocatable :: out(:)
        integer :: i, k, s, e, dup, n
        if (.not. any(model%press(1:model%npress)%shell_eid > 0 .or. model%press(1:model%npress)%shell_set > 0)) return
        call shells%build(model%shell_id(1:model%nshell), dup)
        allocate (out(0))
        do i = 1, model%npress
            associate (pr => model%press(i))
                if (pr%shell_eid > 0) then
                    e = shells%find(pr%shell_eid)
                    if (e == 0) then
                        call make_error(error, ctx%src%where(pr%src)//': *LOAD_SHELL_ELEMENT field EID: shell '// &
                                        itoa(pr%shell_eid)//' is not defined')
                        return
                    end if
                    out = [out, pressure_t(shell_eid=-1, seg=model%shell_conn(:, e), lcid=pr%lcid, sf=pr%sf, &
                                           at=pr%at, src=pr%src)]
                else if (pr%shell_set > 0) then
                    s = find_set(model, set_shell, pr%shell_set)
                    if (s == 0) then
                        call make_error(error, ctx%src%where(pr%src)//': *LOAD_SHELL_SET field ESID: shell set '// &
                                        itoa(pr%shell_set)//' is not defined')
                        return
                    end if
                    do k = 1, model%set(s)%n
                        e = shells%find(model%set(s)%member(k))
                        if (e == 0) then
                            call make_error(error, ctx%src%where(model%set(s)%src)//': *SET_SHELL_LIST '// &
                                            itoa(pr%shell_set)//': shell '//itoa(model%set(s)%member(k))//' is not defined')
                            return
                        end if
                        out = [out, pressure_t(shell_eid=-1, seg=model%shell_conn(:, e), lcid=pr%lcid, sf=pr%sf, &
                                               at=pr%at, src=pr%src)]
                    end do
                else
                    out = [out, pr]
                end if
            end associate
        end do
        n = size(out)
        model%npress = n
        model%press = out
    end subroutine expand_shell_pressures

    subroutine check_controls(model, error)
        type(model_t), intent(inout) :: model
        type(error_t), allocatable, intent(out) :: error
        integer :: e
        if (.not. model%ctl%termination_given .or. &
            (model%ctl%endtim <= 0.0_wp .and. model%ctl%endcyc <= 0)) then
            call make_error(error, model%deck_path//': *CONTROL_TERMINATION with ENDTIM > 0 '// &
                            '(or ENDCYC > 0) is required')
            return
        end if
        if (model%nhex + model%nshell + model%nbeam == 0) then
            call make_error(error, model%deck_path//': the deck defines no elements')
            return
        end if
        if (all(model%mat(model%part(model%hex_part(1:model%nhex))%mat_ix)%mtype == mat_rigid) .and. &
            all(model%mat(model%part(model%shell_part(1:model%nshell))%mat_ix)%mtype == mat_rigid) .and. &
            model%nbeam == 0 .and. .not. model%ctl%dtinit > 0.0_wp) then
            call make_error(error, model%deck_path//': *CONTROL_TIMESTEP field DTINIT: a model of rigid bodies '// &
                            'alone has no element time step; give DTINIT')
            return
        end if
        if (model%ctl%hgbound == 1 .and. model%ctl%hgbound_given) then
            if (.not. any([(hg_bounded(model, model%shell_part(e)), e=1, model%nshell)])) &
                call add_warning(model, model%deck_path//': *CONTROL_XDYNA_SHELL field HGBOUND 1: no shell has the '// &
                                 'stiffness-form hourglass (IHQ 4-5) on a plastic material (*MAT_003, *MAT_024); '// &
                                 'it acts nowhere')
        end if
    end subroutine check_controls

    pure function styp_word(styp) result(w)
        integer, intent(in) :: styp
        character(len=8) :: w
        select case (styp)
        case (1); w = 'part set'
        case (2); w = 'part'
        case default; w = 'node set'
        end select
    end function styp_word

end module xd_input_model_check
