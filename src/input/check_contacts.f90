!> Checks of the contact keywords: the sets and parts that SSID and MSID
!> name exist and have the kind SSTYP / MSTYP says; shell sets used by an
!> interface are resolved to shell indices.
module xd_input_check_contacts
    use xd_core_errors, only: error_t, make_error
    use xd_core_strings, only: itoa
    use xd_core_sorting, only: id_map_t
    use xd_input_context, only: read_ctx_t, add_warning
    use xd_model, only: model_t, find_set, set_node, set_part, set_shell, styp_segment_set, styp_shell_set, &
                        styp_part_set, styp_part, styp_node_set, styp_all, styp_all_but, ct_single, ct_general, &
                        find_box, contact_t
    implicit none
    private
    public :: check_contacts

contains

    subroutine check_contacts(ctx, model, parts, error)
        type(read_ctx_t), intent(in) :: ctx
        type(model_t), intent(inout) :: model
        type(id_map_t), intent(in) :: parts
        type(error_t), allocatable, intent(out) :: error
        integer :: i
        type(contact_t) :: c
        ! the sliding contacts, then the tied ones (read alike, held apart)
        do i = 1, model%ncontact + model%ntied
            if (i <= model%ncontact) then
                c = model%contact(i)
            else
                c = model%tied(i - model%ncontact)
            end if
            block
                if (c%kind == ct_single .or. c%kind == ct_general) then
                    ! single surface: SSID 0 is the whole model; MSID is unused
                    if (c%ssid == 0) c%sstyp = styp_all
                    c%mstyp = c%sstyp
                    c%msid = c%ssid
                end if
                call resolve(c%ssid, c%sstyp, 'SSID', c%sref, c%src)
                if (allocated(error)) return
                call resolve(c%msid, c%mstyp, 'MSID', c%mref, c%src)
                if (allocated(error)) return
                if (c%kind == ct_single .or. c%kind == ct_general) c%mboxid = c%sboxid
                if (c%sboxid > 0 .and. find_box(model, c%sboxid) == 0) then
                    call make_error(error, ctx%src%where(c%src)//': *'//trim(c%keyword)//' field SBOXID: box '// &
                                    itoa(c%sboxid)//' is not defined (*DEFINE_BOX)')
                    return
                end if
                if (c%mboxid > 0 .and. find_box(model, c%mboxid) == 0) then
                    call make_error(error, ctx%src%where(c%src)//': *'//trim(c%keyword)//' field MBOXID: box '// &
                                    itoa(c%mboxid)//' is not defined (*DEFINE_BOX)')
                    return
                end if
            end block
            if (i <= model%ncontact) then
                model%contact(i) = c
            else
                model%tied(i - model%ncontact) = c
            end if
        end do
        ! THKCHG follows the shells' thickness, which changes only with ISTUPD
        if (model%ctl%contact%thkchg == 1 .and. model%ctl%istupd == 0) &
            call add_warning(model, model%deck_path//': *CONTROL_CONTACT field THKCHG 1: *CONTROL_SHELL ISTUPD is 0, '// &
                             'so shell thicknesses do not change; the contact thickness stays the initial one')
        if (model%ctl%contact%dump_nsid > 0) then
            if (find_set(model, set_node, model%ctl%contact%dump_nsid) == 0) then
                call make_error(error, model%deck_path//': *CONTROL_XDYNA_CONTACT field DUMPNS: node set '// &
                                itoa(model%ctl%contact%dump_nsid)//' is not defined')
                return
            end if
        end if
    contains
        subroutine resolve(sid, styp, field, ref, src)
            integer, intent(in) :: sid, styp, src
            character(len=*), intent(in) :: field
            integer, intent(out) :: ref
            type(id_map_t) :: shells
            integer :: k, dup
            character(len=:), allocatable :: at
            at = ctx%src%where(src)//': *'//trim(c%keyword)//' field '//field//': '
            ref = 0
            select case (styp)
            case (styp_all)
                return
            case (styp_segment_set)
                do k = 1, model%nsegset
                    if (model%segset(k)%id == sid) ref = k
                end do
                if (ref == 0) call make_error(error, at//'segment set '//itoa(sid)//' is not defined')
            case (styp_shell_set)
                ref = find_set(model, set_shell, sid)
                if (ref == 0) then
                    call make_error(error, at//'shell set '//itoa(sid)//' is not defined')
                    return
                end if
                if (model%set(ref)%n == 0) then
                    call make_error(error, at//'shell set '//itoa(sid)//' is empty: the contact would have no '// &
                                    'surface on that side')
                    return
                end if
                if (allocated(model%set(ref)%member_ix)) deallocate (model%set(ref)%member_ix)
                allocate (model%set(ref)%member_ix(model%set(ref)%n))
                call shells%build(model%shell_id(1:model%nshell), dup)
                do k = 1, model%set(ref)%n
                    model%set(ref)%member_ix(k) = shells%find(model%set(ref)%member(k))
                    if (model%set(ref)%member_ix(k) == 0) then
                        call make_error(error, at//'shell set '//itoa(sid)//': shell '// &
                                        itoa(model%set(ref)%member(k))//' is not defined')
                        return
                    end if
                end do
            case (styp_part_set, styp_all_but)
                ref = find_set(model, set_part, sid)
                if (ref == 0) then
                    call make_error(error, at//'part set '//itoa(sid)//' is not defined')
                else if (styp == styp_part_set .and. model%set(ref)%n == 0) then
                    ! (a set of parts to leave out may be empty)
                    call make_error(error, at//'part set '//itoa(sid)//' is empty: the contact would have no '// &
                                    'surface on that side')
                end if
            case (styp_part)
                ref = parts%find(sid)
                if (ref == 0) call make_error(error, at//'part '//itoa(sid)//' is not defined')
            case (styp_node_set)
                ref = find_set(model, set_node, sid)
                if (ref == 0) then
                    call make_error(error, at//'node set '//itoa(sid)//' is not defined')
                else if (model%set(ref)%n == 0) then
                    call make_error(error, at//'node set '//itoa(sid)//' is empty: the contact would have no '// &
                                    'slave nodes')
                end if
            end select
        end subroutine resolve
    end subroutine check_contacts

end module xd_input_check_contacts
