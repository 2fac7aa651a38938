!> The sets built by rules: *SET_NODE_GENERAL, *SET_SHELL_GENERAL,
!> *SET_PART_GENERAL (OPTION E1..E7 cards applied in order, the D options
!> taking away what earlier cards gave) and *SET_NODE_ADD, *SET_PART_ADD,
!> *SET_SHELL_ADD (unions of sets of the same kind, which may themselves be
!> rule sets). Resolved into plain member lists once elements, parts and
!> boxes are known, before any set is used.
module xd_input_set_rules
    use xd_kinds, only: wp
    use xd_core_errors, only: error_t, make_error
    use xd_core_strings, only: itoa
    use xd_core_sorting, only: id_map_t, sort_index, small_sort
    use xd_input_context, only: read_ctx_t
    use xd_model, only: model_t, set_node, set_part, set_shell, find_set, find_box, in_box, mark_part_nodes
    implicit none
    private
    public :: resolve_set_rules, resolve_segment_rules

contains

    !> Shell connectivity and parts must be resolved (indices) already.
    subroutine resolve_set_rules(ctx, model, nodes, parts, error)
        type(read_ctx_t), intent(in) :: ctx
        type(model_t), intent(inout) :: model
        type(id_map_t), intent(in) :: nodes, parts
        type(error_t), allocatable, intent(out) :: error
        integer :: i, pass
        logical :: progress, pending
        logical, allocatable :: done(:)
        allocate (done(model%nset))
        done = [(model%set(i)%nrule == 0 .and. .not. model%set(i)%add, i=1, model%nset)]
        do i = 1, model%nset
            if (done(i) .or. model%set(i)%add) cycle
            call resolve_general(ctx, model, i, nodes, parts, error)
            if (allocated(error)) return
            done(i) = .true.
        end do
        ! unions, in as many passes as they nest
        do pass = 1, model%nset + 1
            progress = .false.
            pending = .false.
            do i = 1, model%nset
                if (done(i)) cycle
                call resolve_add(ctx, model, i, done, progress, error)
                if (allocated(error)) return
                if (.not. done(i)) pending = .true.
            end do
            if (.not. pending) exit
            if (.not. progress) then
                do i = 1, model%nset
                    if (.not. done(i)) exit
                end do
                call make_error(error, ctx%src%where(model%set(i)%src)//': set '//itoa(model%set(i)%id)// &
                                ' (_ADD) includes itself through other sets')
                return
            end if
        end do
    end subroutine resolve_set_rules

    subroutine resolve_add(ctx, model, i, done, progress, error)
        type(read_ctx_t), intent(in) :: ctx
        type(model_t), intent(inout) :: model
        integer, intent(in) :: i
        logical, intent(inout) :: done(:), progress
        type(error_t), allocatable, intent(out) :: error
        integer :: r, k, j, m, total
        integer, allocatable :: mem(:), perm(:)
        logical, allocatable :: dup(:)
        associate (s => model%set(i))
            ! the member sets must exist and be resolved; then their union
            total = 0
            do r = 1, s%nrule
                do k = 1, 8
                    if (s%rule_val(k, r) == 0) cycle
                    j = find_set(model, s%kind, s%rule_val(k, r))
                    if (j == 0) then
                        call make_error(error, ctx%src%where(s%rule_line(r))//': set '//itoa(s%id)// &
                                        ' (_ADD) field DSID'//itoa(k)//': set '//itoa(s%rule_val(k, r))// &
                                        ' of the same kind is not defined')
                        return
                    end if
                    if (.not. done(j)) return
                    total = total + model%set(j)%n
                end do
            end do
            ! heap arrays only (a set may hold millions of ids); duplicates
            ! dropped, first occurrence kept
            allocate (mem(total))
            m = 0
            do r = 1, s%nrule
                do k = 1, 8
                    if (s%rule_val(k, r) == 0) cycle
                    j = find_set(model, s%kind, s%rule_val(k, r))
                    mem(m + 1:m + model%set(j)%n) = model%set(j)%member(1:model%set(j)%n)
                    m = m + model%set(j)%n
                end do
            end do
            allocate (dup(total))
            dup = .false.
            if (total > 0) then
                call sort_index(mem, perm)
                do k = 2, total
                    ! equal ids sit together in perm; the stable sort keeps
                    ! the first occurrence first
                    if (mem(perm(k)) == mem(perm(k - 1))) dup(perm(k)) = .true.
                end do
            end if
            m = 0
            do k = 1, total
                if (dup(k)) cycle
                m = m + 1
                mem(m) = mem(k)
            end do
            call move_alloc(mem, s%member)
            s%n = m
        end associate
        done(i) = .true.
        progress = .true.
    end subroutine resolve_add

    subroutine resolve_general(ctx, model, i, nodes, parts, error)
        type(read_ctx_t), intent(in) :: ctx
        type(model_t), intent(inout) :: model
        integer, intent(in) :: i
        type(id_map_t), intent(in) :: nodes, parts
        type(error_t), allocatable, intent(out) :: error
        logical, allocatable :: on(:), pick(:)
        integer :: r, k, n, e, b, v, j
        logical :: del
        character(len=10) :: op
        character(len=:), allocatable :: at
        associate (s => model%set(i))
            select case (s%kind)
            case (set_node); n = model%nnode
            case (set_part); n = model%npart
            case default; n = model%nshell
            end select
            allocate (on(n), pick(n))
            on = .false.
            do r = 1, s%nrule
                call split_option(s%rule_op(r), op, del)
                at = ctx%src%where(s%rule_line(r))//': set '//itoa(s%id)//' (_GENERAL) option '//trim(s%rule_op(r))
                pick = .false.
                select case (trim(op))
                case ('ALL')
                    pick = .true.
                case ('NODE', 'PART', 'ELEM', 'SHELL', 'SOLID', 'BOX', 'SET_SHELL', 'SET_NODE', 'SET_PART')
                    do k = 1, 7
                        v = s%rule_val(k, r)
                        if (v == 0) cycle
                        call pick_one(trim(op), v, k)
                        if (allocated(error)) return
                    end do
                case default
                    call make_error(error, at//': not supported for this set (ALL, NODE, ELEM, SHELL, SOLID, '// &
                                    'PART, BOX, SET_SHELL, SET_NODE, SET_PART and their D forms are)')
                    return
                end select
                call apply_rule(on, pick, del)
            end do
            n = count(on)
            s%n = n
            select case (s%kind)
            case (set_node); s%member = pack(model%node_id(1:model%nnode), on)
            case (set_part); s%member = pack([(model%part(j)%id, j=1, model%npart)], on)
            case default; s%member = pack(model%shell_id(1:model%nshell), on)
            end select
        end associate
    contains
        subroutine pick_one(what, v, k)
            character(len=*), intent(in) :: what
            integer, intent(in) :: v, k
            integer :: p, j2, ix
            associate (s => model%set(i))
                select case (what)
                case ('NODE')
                    if (s%kind /= set_node) call wrong()
                    if (allocated(error)) return
                    ix = nodes%find(v)
                    if (ix == 0) call missing('node')
                    if (allocated(error)) return
                    pick(ix) = .true.
                case ('PART')
                    p = parts%find(v)
                    if (p == 0) call missing('part')
                    if (allocated(error)) return
                    select case (s%kind)
                    case (set_part)
                        pick(p) = .true.
                    case (set_node)
                        call mark_part_nodes(model, p, pick)
                    case default
                        where (model%shell_part(1:model%nshell) == p) pick = .true.
                    end select
                case ('ELEM', 'SHELL')
                    if (s%kind == set_part) call wrong()
                    if (allocated(error)) return
                    ix = findloc(model%shell_id(1:model%nshell), v, 1)
                    if (ix == 0) call missing('shell')
                    if (allocated(error)) return
                    if (s%kind == set_node) then
                        pick(model%shell_conn(:, ix)) = .true.
                    else
                        pick(ix) = .true.
                    end if
                case ('SOLID')
                    if (s%kind /= set_node) call wrong()
                    if (allocated(error)) return
                    ix = 0
                    if (model%nhex > 0) ix = findloc(model%hex_id(1:model%nhex), v, 1)
                    if (ix == 0) call missing('solid')
                    if (allocated(error)) return
                    pick(model%hex_conn(:, ix)) = .true.
                case ('BOX')
                    b = find_box(model, v)
                    if (b == 0) call missing('box')
                    if (allocated(error)) return
                    select case (s%kind)
                    case (set_node)
                        do j2 = 1, model%nnode
                            if (in_box(model%box(b), model%x0(:, j2))) pick(j2) = .true.
                        end do
                    case (set_shell)
                        ! a shell is in the box when its centre is
                        do e = 1, model%nshell
                            if (in_box(model%box(b), sum(model%x0(:, model%shell_conn(:, e)), dim=2)/4)) pick(e) = .true.
                        end do
                    case default
                        call wrong()
                    end select
                case ('SET_SHELL', 'SET_NODE', 'SET_PART')
                    select case (what)
                    case ('SET_SHELL'); j2 = find_set(model, set_shell, v)
                    case ('SET_NODE'); j2 = find_set(model, set_node, v)
                    case default; j2 = find_set(model, set_part, v)
                    end select
                    if (j2 == 0) call missing(what(5:)//' set')
                    if (allocated(error)) return
                    if (model%set(j2)%nrule > 0 .or. model%set(j2)%add) then
                        call make_error(error, at//' field E'//itoa(k)//': set '//itoa(v)// &
                                        ' is itself built by rules; list sets cannot nest here')
                        return
                    end if
                    call pick_from_set(model%set(j2)%kind, model%set(j2)%member(1:model%set(j2)%n))
                end select
            end associate
        end subroutine pick_one

        subroutine pick_from_set(kind, ids)
            integer, intent(in) :: kind, ids(:)
            integer :: q, ix, p
            associate (s => model%set(i))
                do q = 1, size(ids)
                    select case (kind)
                    case (set_node)
                        if (s%kind /= set_node) call wrong()
                        if (allocated(error)) return
                        ix = nodes%find(ids(q))
                        if (ix > 0) pick(ix) = .true.
                    case (set_shell)
                        ix = findloc(model%shell_id(1:model%nshell), ids(q), 1)
                        if (ix == 0) cycle
                        if (s%kind == set_node) then
                            pick(model%shell_conn(:, ix)) = .true.
                        else if (s%kind == set_shell) then
                            pick(ix) = .true.
                        end if
                    case default
                        p = parts%find(ids(q))
                        if (p == 0) cycle
                        if (s%kind == set_part) then
                            pick(p) = .true.
                        else if (s%kind == set_shell) then
                            where (model%shell_part(1:model%nshell) == p) pick = .true.
                        else
                            call mark_part_nodes(model, p, pick)
                        end if
                    end select
                end do
            end associate
        end subroutine pick_from_set

        subroutine missing(what)
            character(len=*), intent(in) :: what
            call make_error(error, at//': '//what//' '//itoa(v)//' is not defined')
        end subroutine missing

        subroutine wrong()
            call make_error(error, at//': this option does not apply to a set of this kind')
        end subroutine wrong
    end subroutine resolve_general

    !> *SET_SEGMENT_GENERAL: segments of shells (N1..N4 as the element) and
    !> exterior faces of hexahedra (outward; a face of a part's hexahedra is
    !> exterior when no other hexahedron of that part shares it), by the
    !> options ALL, PART, BOX (segments whose centre is inside), SHELL and
    !> SET_SHELL, each with a D form taking away what earlier cards gave.
    !> The members are written as node ids, as *SET_SEGMENT cards give them.
    subroutine resolve_segment_rules(ctx, model, parts, error)
        type(read_ctx_t), intent(in) :: ctx
        type(model_t), intent(inout) :: model
        type(id_map_t), intent(in) :: parts
        type(error_t), allocatable, intent(out) :: error
        integer, allocatable :: cand(:, :), cpart(:), cshell(:)
        logical, allocatable :: on(:), pick(:)
        integer :: i, r, k, v, p, b, j, nc
        logical :: del
        character(len=10) :: op
        character(len=:), allocatable :: at
        if (.not. any([(model%segset(i)%nrule > 0, i=1, model%nsegset)])) return
        call candidates(cand, cpart, cshell, nc)
        cand = cand(:, 1:nc)
        cpart = cpart(1:nc)
        cshell = cshell(1:nc)
        allocate (on(nc), pick(nc))
        do i = 1, model%nsegset
            associate (ss => model%segset(i))
                if (ss%nrule == 0) cycle
                on = .false.
                do r = 1, ss%nrule
                    call split_option(ss%rule_op(r), op, del)
                    at = ctx%src%where(ss%rule_line(r))//': *SET_SEGMENT_GENERAL '//itoa(ss%id)//' option '// &
                         trim(ss%rule_op(r))
                    pick = .false.
                    select case (trim(op))
                    case ('ALL')
                        pick = .true.
                    case ('PART', 'BOX', 'SHELL', 'SET_SHELL')
                        do k = 1, 7
                            v = ss%rule_val(k, r)
                            if (v == 0) cycle
                            select case (trim(op))
                            case ('PART')
                                p = parts%find(v)
                                if (p == 0) then
                                    call make_error(error, at//': part '//itoa(v)//' is not defined'); return
                                end if
                                where (cpart == p) pick = .true.
                            case ('BOX')
                                b = find_box(model, v)
                                if (b == 0) then
                                    call make_error(error, at//': box '//itoa(v)//' is not defined'); return
                                end if
                                do j = 1, nc
                                    if (in_box(model%box(b), centre(j))) pick(j) = .true.
                                end do
                            case ('SHELL')
                                j = findloc(model%shell_id(1:model%nshell), v, 1)
                                if (j == 0) then
                                    call make_error(error, at//': shell '//itoa(v)//' is not defined'); return
                                end if
                                where (cshell == j) pick = .true.
                            case default
                                b = find_set(model, set_shell, v)
                                if (b == 0) then
                                    call make_error(error, at//': shell set '//itoa(v)//' is not defined'); return
                                end if
                                do j = 1, model%set(b)%n
                                    p = findloc(model%shell_id(1:model%nshell), model%set(b)%member(j), 1)
                                    if (p > 0) where (cshell == p) pick = .true.
                                end do
                            end select
                        end do
                    case default
                        call make_error(error, at//': not supported (ALL, PART, BOX, SHELL, SET_SHELL and their '// &
                                        'D forms are)')
                        return
                    end select
                    call apply_rule(on, pick, del)
                end do
                ss%n = count(on)
                ss%seg = reshape(model%node_id(pack(cand, spread(on, 1, 4))), [4, ss%n])
            end associate
        end do
    contains
        !> Every shell, then every exterior hexahedron face (per part).
        subroutine candidates(c, cp, cs, n)
            integer, allocatable, intent(out) :: c(:, :), cp(:), cs(:)
            integer, intent(out) :: n
            integer, parameter :: face(4, 6) = reshape([1, 4, 3, 2, 5, 6, 7, 8, 1, 2, 6, 5, 2, 3, 7, 6, &
                                                        3, 4, 8, 7, 4, 1, 5, 8], [4, 6])
            integer, allocatable :: keys(:, :), perm(:)
            logical, allocatable :: inner(:)
            integer :: e, f, q, m, d(4), u(4), nu, g, i1, i2
            allocate (c(4, model%nshell + 6*model%nhex), cp(model%nshell + 6*model%nhex), &
                      cs(model%nshell + 6*model%nhex), keys(4, 6*model%nhex))
            n = 0
            do e = 1, model%nshell
                n = n + 1
                c(:, n) = model%shell_conn(:, e)
                cp(n) = model%shell_part(e)
                cs(n) = e
            end do
            ! faces shared by two hexahedra of one part: sorted by their
            ! smallest node, compared within the runs of equal smallest node
            m = 0
            do e = 1, model%nhex
                do f = 1, 6
                    m = m + 1
                    keys(:, m) = model%hex_conn(face(:, f), e)
                    call small_sort(keys(:, m))
                end do
            end do
            allocate (inner(m))
            inner = .false.
            if (m > 0) call sort_index(keys(1, :), perm)
            q = 1
            do while (q <= m)
                g = q
                do while (g < m)
                    if (keys(1, perm(g + 1)) /= keys(1, perm(q))) exit
                    g = g + 1
                end do
                do i1 = q, g
                    do i2 = i1 + 1, g
                        if (model%hex_part((perm(i1) - 1)/6 + 1) /= model%hex_part((perm(i2) - 1)/6 + 1)) cycle
                        if (all(keys(:, perm(i1)) == keys(:, perm(i2)))) then
                            inner(perm(i1)) = .true.
                            inner(perm(i2)) = .true.
                        end if
                    end do
                end do
                q = g + 1
            end do
            do e = 1, model%nhex
                do f = 1, 6
                    if (inner(6*(e - 1) + f)) cycle
                    d = model%hex_conn(face(:, f), e)
                    ! a face collapsed by a degenerate element: a triangle, or none
                    nu = 0
                    do q = 1, 4
                        if (.not. any(u(1:nu) == d(q))) then
                            nu = nu + 1
                            u(nu) = d(q)
                        end if
                    end do
                    if (nu < 3) cycle
                    if (nu == 3) d = [u(1), u(2), u(3), u(3)]
                    n = n + 1
                    c(:, n) = d
                    cp(n) = model%hex_part(e)
                    cs(n) = 0
                end do
            end do
        end subroutine candidates


        function centre(j) result(x)
            integer, intent(in) :: j
            real(wp) :: x(3)
            x = sum(model%x0(:, cand(:, j)), dim=2)/4
        end function centre
    end subroutine resolve_segment_rules

    !> An OPTION of a _GENERAL card: the option, and whether it is a D form
    !> (DPART, DBOX, ...: taking away what earlier cards gave).
    pure subroutine split_option(text, op, del)
        character(len=*), intent(in) :: text
        character(len=10), intent(out) :: op
        logical, intent(out) :: del
        op = text
        del = op(1:1) == 'D'
        if (del) op = op(2:)
    end subroutine split_option

    !> The cards of a _GENERAL set act in order: a card adds what it picks,
    !> a D card takes it away.
    pure subroutine apply_rule(on, pick, del)
        logical, intent(inout) :: on(:)
        logical, intent(in) :: pick(:)
        logical, intent(in) :: del
        if (del) then
            on = on .and. .not. pick
        else
            on = on .or. pick
        end if
    end subroutine apply_rule

end module xd_input_set_rules
