!> Initial penetrations, before the run is set up (LS-DYNA's IGNORE, of
!> *CONTROL_CONTACT card 4 and, per interface, of *CONTACT optional card
!> C, which wins where it is not 0):
!>
!> - IGNORE 0 (the default): slave nodes found inside a segment's contact
!>   zone at t = 0 are moved out along the contact's return direction, by
!>   their depth, so that the run starts with no penetration and no
!>   allowance. The four steps run on the initial coordinates as they will
!>   at cycle 0; the moves are made, and the search repeated, until none is
!>   left (at most max_pass passes; what is left then is tracked as under
!>   IGNORE 1, and named). Where a node of the segment moves the other way
!>   in the same pass (two sheets that overlap, each the other's master in
!>   a single-surface contact), each side moves half its depth. A node of a rigid body is not
!>   moved (the body's shape is its own): its penetration is tracked.
!> - IGNORE 1: nothing is moved; the first cycle allows each penetration
!>   found and the allowance shrinks as the node moves out.
!> - IGNORE 2: as 1, and each penetrating node is named with its
!>   coordinates and the coordinates that would remove the penetration.
!>
!> Every node moved or named is written to d3hsp with its interface, the
!> segment, the depth and both coordinates. The coordinates changed are
!> the model's initial ones: the mesh, the states and the masses all start
!> from them (a stress-free start, as LS-DYNA's).
!>
!> Under MPI the ranks share the searches (issue 32): each rank searches
!> and checks its own block of each interface's slaves (global step on
!> them alone, so its master lists are a rank's share), and the ranks
!> agree on each pass's moves through reductions in which each value has
!> one contributing rank: a node's deepest penetration (the lowest
!> interface where two are as deep, as one rank's pass over the interfaces
!> in order picks), its return direction and its move. The coordinates and
!> the lines named are the serial run's, bit for bit and in its order.
module xd_contact_initial_penetration
    use xd_kinds, only: wp, dp, i8
    use xd_core_errors, only: error_t
    use xd_core_strings, only: itoa
    use xd_model, only: model_t
    use xd_contact_contact, only: contacts_t, build_contacts, contact_masses, contact_search, contact_local_search, &
                                  contact_slave_rows, contact_release_setup
    use xd_contact_enforcement, only: pdir
    use xd_core_comm, only: comm_max, comm_min_int, comm_sum_wp, comm_sum_int, comm_gather_text
    implicit none
    private
    public :: initial_penetrations

    !> text lines, each ended by new_line('a')
    type :: lines_t
        character(len=:), allocatable :: s
    end type lines_t

    integer, parameter :: max_pass = 30   !< searches and moves at most
    integer, parameter :: max_named = 2000   !< nodes named per interface (all counted)

contains

    !> The IGNORE rule of each interface applied to model%x0; `txt` is what
    !> d3hsp takes (empty when no interface has a penetration to move or
    !> name). Every rank calls it alike and ends with the same x0 and txt.
    subroutine initial_penetrations(model, v, mass, rank, nranks, txt, nmoved_all, error)
        type(model_t), intent(inout) :: model
        !> the initial velocities and nodal masses (the local search picks a
        !> node's segment as cycle 0 will, by the velocity where several
        !> hold it)
        real(wp), intent(in) :: v(:, :), mass(:)
        !> this rank (from 0) of nranks: it searches its block of each
        !> interface's slaves
        integer, intent(in) :: rank, nranks
        character(len=:), allocatable, intent(out) :: txt
        integer, intent(out) :: nmoved_all   !< nodes moved (their coordinates changed)
        type(error_t), allocatable, intent(out) :: error
        type(contacts_t) :: ct
        real(wp), allocatable :: x(:, :), dx(:, :), xm(:, :), depth(:), depth1(:)
        real(dp), allocatable :: red(:)
        integer, allocatable :: rule(:), by(:), by1(:), seg_of(:, :), nnamed(:), nlisted(:), won(:)
        !> MPI: this pass's moving nodes (the same list on every rank) and
        !> each node's place in it (0: not moving)
        integer, allocatable :: mv(:), pos(:)
        real(wp), allocatable :: deepest(:)
        logical, allocatable :: moving(:)
        !> per interface: the lines this rank names at the first pass (its
        !> block's, in slave order)
        type(lines_t), allocatable :: named(:)
        integer :: i, k, pass, n, nd, m, j, sn
        real(wp) :: f, a
        character(len=300) :: buf
        txt = ''
        nmoved_all = 0
        if (model%ncontact == 0) return
        allocate (rule(model%ncontact))
        do i = 1, model%ncontact
            rule(i) = model%contact(i)%ignore
            if (rule(i) == 0) rule(i) = model%ctl%contact%ignore
        end do
        if (all(rule == 1)) return
        n = model%nnode
        x = model%x0(:, 1:n)
        allocate (dx(3, n), depth(n), depth1(n), by(n), by1(n), seg_of(4, n), moving(n))
        allocate (nnamed(model%ncontact), nlisted(model%ncontact), deepest(model%ncontact), named(model%ncontact))
        if (nranks > 1) allocate (red(n), won(n), pos(n))
        ! by1: the interface that first moved a node (0: never moved)
        by1 = 0
        do i = 1, size(named)
            named(i)%s = ''
        end do
        nnamed = 0
        deepest = 0
        do pass = 1, max_pass + 1
            call build_contacts(model, x, ct, error)
            if (allocated(error)) return
            ! (the model's faces and the surfaces' set-up values: this pass
            ! searches, it rebuilds nothing)
            call contact_release_setup(ct, .false.)
            ! (the slaves' contact state in rows of this rank's block, made
            ! once the block is chosen)
            call contact_masses(ct, mass, rows_later=.true.)
            if (nranks > 1) call own_block(ct, rank, nranks)
            call contact_slave_rows(ct, nranks > 1)
            call contact_search(ct, x, model%node_id, 0, 0.0_dp)
            call contact_local_search(ct, x, v, 0.0_dp, 0.0_wp)
            ! this pass's moves: each penetrating slave's depth and return
            ! direction (a node that is a slave of several interfaces: its
            ! deepest penetration)
            depth = 0
            by = 0
            do i = 1, ct%n
                associate (it => ct%ifc(i), s => ct%ifc(i)%surf)
                    if (.not. it%active .or. rule(i) == 1) cycle
                    do k = 1, s%nslave
                        if (.not. it%found(k)) cycle
                        ! the depth |a|; the slave goes out along nhat pdir(a)
                        a = -abs(it%hit(it%hrow(k))%a)
                        if (a >= 0.0_wp) cycle
                        sn = s%slave(k)
                        nd = s%node(sn)
                        m = it%hit(it%hrow(k))%seg
                        if (pass == 1) then
                            deepest(i) = max(deepest(i), -a)
                            if (rule(i) == 2 .or. s%node_rigid(sn)) then
                                ! named, not moved
                                nnamed(i) = nnamed(i) + 1
                                if (nnamed(i) <= max_named) then
                                    write (buf, '(a,i0,a,i0,a,4(1x,i0),a,es11.4,a,3es14.6,a,a,3es14.6)') &
                                        '   interface ', it%id, ': node ', model%node_id(nd), ' initially inside segment', &
                                        model%node_id(s%node(s%seg(:, m))), ' by ', -a, ': at', x(:, nd), &
                                        trim(merge(' (a rigid body''s node, not moved)', &
                                                   ' (IGNORE 2, tracked)             ', s%node_rigid(sn))), &
                                        '; out at', x(:, nd) - a*pdir(it%hit(it%hrow(k))%a)*it%hit(it%hrow(k))%nhat
                                    named(i)%s = named(i)%s//trim(buf)//new_line('a')
                                end if
                                cycle
                            end if
                        end if
                        if (rule(i) == 2 .or. s%node_rigid(sn)) cycle
                        if (-a > depth(nd)) then
                            depth(nd) = -a
                            dx(:, nd) = pdir(it%hit(it%hrow(k))%a)*it%hit(it%hrow(k))%nhat
                            by(nd) = i
                            if (by1(nd) == 0) seg_of(:, nd) = model%node_id(s%node(s%seg(:, m)))
                        end if
                    end do
                end associate
            end do
            if (pass == 1) call name_first(named, nnamed, deepest)
            if (nranks > 1) call agree_moves()
            moving = depth > 0.0_wp
            if (.not. any(moving)) exit
            if (pass > max_pass) then
                ! (the last search only counts what is left)
                write (buf, '(a,i0,a,i0,a,es11.4,a)') '   initial penetrations: ', count(moving), ' nodes still '// &
                    'inside a segment after ', max_pass, ' passes of moves (deepest ', maxval(depth), '): tracked from '// &
                    'the first cycle as under IGNORE 1 (each named there)'
                call add_line(trim(buf))
                exit
            end if
            ! the moves: half the depth where the segment moves too (each
            ! node by the rank whose slave it is; the others' coordinates
            ! taken from it after)
            if (nranks > 1) then
                allocate (xm(3, max(size(mv), 1)))
                xm = 0
            end if
            do i = 1, ct%n
                associate (it => ct%ifc(i), s => ct%ifc(i)%surf)
                    do k = 1, s%nslave
                        nd = s%node(s%slave(k))
                        if (by(nd) /= i .or. .not. moving(nd)) cycle
                        if (.not. it%found(k)) cycle
                        m = it%hit(it%hrow(k))%seg
                        f = 1.0_wp
                        do j = 1, 4
                            if (.not. moving(s%node(s%seg(j, m)))) cycle
                            if (dot_product(dx(:, s%node(s%seg(j, m))), dx(:, nd)) < 0.0_wp) f = 0.5_wp
                        end do
                        ! (a hair beyond the surface: round-off leaves none)
                        if (nranks > 1) then
                            xm(:, pos(nd)) = x(:, nd) + (f*depth(nd) + 1.0e-6_wp*it%hit(it%hrow(k))%tm)*dx(:, nd)
                        else
                            x(:, nd) = x(:, nd) + (f*depth(nd) + 1.0e-6_wp*it%hit(it%hrow(k))%tm)*dx(:, nd)
                        end if
                    end do
                end associate
            end do
            if (nranks > 1) then
                ! (one rank gives each moved node's place, the others zero)
                call comm_sum_wp(xm, 3*size(mv))
                do j = 1, size(mv)
                    x(:, mv(j)) = xm(:, j)
                end do
                deallocate (xm)
            end if
            ! (every moving node was moved: its deepest contact's slave)
            do nd = 1, n
                if (.not. moving(nd) .or. by1(nd) /= 0) cycle
                depth1(nd) = depth(nd)
                by1(nd) = by(nd)
            end do
        end do
        ! each node moved: named with its first penetration and the total move
        nlisted = 0
        do nd = 1, n
            i = by1(nd)
            if (i == 0) cycle
            nlisted(i) = nlisted(i) + 1
            if (nlisted(i) > max_named) cycle
            write (buf, '(a,i0,a,i0,a,4(1x,i0),a,es11.4,a,es11.4,a,3es14.6,a,3es14.6)') '   interface ', &
                model%contact(i)%id, ': node ', model%node_id(nd), ' initially inside segment', seg_of(:, nd), ' by ', &
                depth1(nd), ', moved out (IGNORE 0) by ', norm2(x(:, nd) - model%x0(:, nd)), ': from', &
                model%x0(:, nd), ' to', x(:, nd)
            call add_line(trim(buf))
        end do
        do i = 1, model%ncontact
            if (count(by1 == i) + nnamed(i) == 0) cycle
            write (buf, '(a,i0,a,i0,a,i0,a,es11.4,a)') '   interface ', model%contact(i)%id, ': ', count(by1 == i), &
                ' slave nodes moved out of initial penetrations (IGNORE 0), ', nnamed(i), &
                ' named and tracked (IGNORE 2 or rigid); deepest ', deepest(i), ' (every node is listed above up to '// &
                itoa(max_named)//')'
            call add_line(trim(buf))
        end do
        if (len(txt) > 0) txt = ' I n i t i a l   p e n e t r a t i o n s'//new_line('a')//txt
        model%x0(:, 1:n) = x
        nmoved_all = count(by1 > 0)
    contains
        subroutine add_line(line)
            character(len=*), intent(in) :: line
            if (len(txt) > 0) txt = txt//new_line('a')
            txt = txt//line
        end subroutine add_line

        !> The first pass's lines named (IGNORE 2, rigid bodies' nodes), in
        !> interface and slave order, and each interface's deepest, over
        !> the ranks.
        subroutine name_first(named, nnamed, deepest)
            type(lines_t), intent(inout) :: named(:)
            integer, intent(inout) :: nnamed(:)
            real(wp), intent(inout) :: deepest(:)
            character(len=:), allocatable :: all
            real(dp) :: dm(size(deepest))
            integer :: i, p, q, c
            if (nranks > 1) then
                dm = real(deepest, dp)
                call comm_max(dm)
                deepest = real(dm, wp)
                call comm_sum_int(nnamed, size(nnamed))
            end if
            do i = 1, size(named)
                if (nranks > 1) then
                    all = comm_gather_text(named(i)%s)
                else
                    all = named(i)%s
                end if
                ! (the first max_named lines)
                p = 1
                c = 0
                do while (p <= len(all) .and. c < max_named)
                    q = index(all(p:), new_line('a')) + p - 1
                    call add_line(all(p:q - 1))
                    c = c + 1
                    p = q + 1
                end do
                named(i)%s = ''
            end do
        end subroutine name_first

        !> This pass's moves, agreed over the ranks: each node's deepest
        !> penetration over the interfaces (the lowest interface of those
        !> as deep), with that slave's return direction and segment.
        subroutine agree_moves()
            integer :: nd, j, nm
            real(wp), allocatable :: pd(:, :)
            integer, allocatable :: ps(:, :)
            red = real(depth, dp)
            call comm_max(red)
            do nd = 1, n
                won(nd) = huge(1)
                if (by(nd) > 0 .and. real(depth(nd), dp) == red(nd)) won(nd) = by(nd)
            end do
            call comm_min_int(won)
            ! the nodes this pass moves, alike on every rank; their return
            ! directions and first segments from the rank whose slave each
            ! is (the others give zero), packed
            nm = 0
            do nd = 1, n
                pos(nd) = 0
                if (won(nd) == huge(1)) cycle
                nm = nm + 1
                pos(nd) = nm
            end do
            if (allocated(mv)) deallocate (mv)
            allocate (mv(nm), pd(3, max(nm, 1)), ps(4, max(nm, 1)))
            pd = 0
            ps = 0
            do nd = 1, n
                j = pos(nd)
                if (j == 0) cycle
                mv(j) = nd
                ! (a node is one slave of an interface, in one rank's block)
                if (by(nd) > 0 .and. by(nd) == won(nd)) then
                    pd(:, j) = dx(:, nd)
                    if (by1(nd) == 0) ps(:, j) = seg_of(:, nd)
                end if
            end do
            do nd = 1, n
                if (won(nd) == huge(1)) then
                    by(nd) = 0
                    depth(nd) = 0
                else
                    by(nd) = won(nd)
                    depth(nd) = real(red(nd), wp)
                end if
            end do
            call comm_sum_wp(pd, 3*nm)
            call comm_sum_int(ps, 4*nm)
            do j = 1, nm
                nd = mv(j)
                dx(:, nd) = pd(:, j)
                if (by1(nd) == 0) seg_of(:, nd) = ps(:, j)
            end do
        end subroutine agree_moves
    end subroutine initial_penetrations

    !> MPI: this rank searches and checks its block of each interface's
    !> slaves alone (the blocks in slave order, one a rank).
    subroutine own_block(ct, rank, nranks)
        type(contacts_t), intent(inout) :: ct
        integer, intent(in) :: rank, nranks
        integer :: i, k, lo, hi, c
        do i = 1, ct%n
            associate (it => ct%ifc(i))
                lo = int(int(it%surf%nslave, i8)*rank/nranks) + 1
                hi = int(int(it%surf%nslave, i8)*(rank + 1)/nranks)
                it%owned = .false.
                it%owned(lo:hi) = .true.
                c = count(it%live(lo:hi))
                deallocate (it%mine)
                allocate (it%mine(c))
                c = 0
                do k = lo, hi
                    if (.not. it%live(k)) cycle
                    c = c + 1
                    it%mine(c) = k
                end do
            end associate
        end do
    end subroutine own_block

end module xd_contact_initial_penetration
