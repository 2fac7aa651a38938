!> Nodes numbered per rank (issue 32, deliverable 1). With owned nodes
!> each rank integrates the nodes it assembles and moves those its
!> elements touch; until this step every rank still held every node's
!> arrays. Here, once the decomposition and its lists are made, each
!> rank's nodal arrays are cut to the nodes it moves (its own and the
!> halo its elements touch), numbered 1 .. n in the model's order, and
!> every list that indexes them (the elements' connectivity, the
!> assembly's node lists, the halo's motion lists, the runs, the shells'
!> shared nodes, the nodout nodes, the rigid walls' and prescribed
!> motions' nodes) takes those numbers; the energies' node-by-part table
!> is built for the kept nodes alone (held_nodes, before the cut). Every
!> sum keeps its order (the local numbers rise with the model's), so the
!> motion is the serial run's bit for bit.
!>
!> An output is written by rank 0 from a whole view (node_view_t): every
!> node's values (or the nodout nodes' alone) gathered from their ranks
!> into arrays of the model's size, held for the output's time only, with
!> the shells' connectivity in the model's numbers while it lasts.
!>
!> Models with features that read nodes no element of the rank touches
!> (contact surfaces, rigid bodies, ties, beams, pressure segments) or
!> change the masses or the elements during the run (erosion, mass
!> scaling, thickness updates) keep every node on every rank: the time
!> loop's whole_nodes_reason says which, and d3hsp names it.
module xd_solver_local_nodes
    use, intrinsic :: iso_fortran_env, only: int8
    use xd_kinds, only: wp, dp
    use xd_core_comm, only: comm_gather_root_wp
    use xd_core_sorting, only: where_true
    use xd_core_memory, only: take, fit, release_free_memory
    use xd_model, only: model_t
    use xd_solver_state, only: state_t
    use xd_solver_assembly, only: assembly_t
    use xd_solver_energies, only: energies_t, set_model_mass
    use xd_elements_solid_groups, only: solids_t
    use xd_elements_shell_bt, only: shells_t
    use xd_output_histories, only: histories_t
    use xd_contact_rigidwall, only: walls_t
    use xd_solver_prescribed, only: prescribed_nodes_t
    use xd_solver_domain, only: domain_t, node_gather_t, node_runs
    implicit none
    private
    public :: node_view_t, cut_state, localize_nodes, open_view, close_view, global_node, held_nodes

    !> Rank 0's whole view of the nodes for an output (nodes numbered per
    !> rank): the state's arrays at the model's size, v(n) and w(n-1/2)
    !> beside them; on the other ranks nothing is held (`on` false there).
    type :: node_view_t
        logical :: on = .false.
        type(state_t) :: st
        real(wp), allocatable :: vn(:, :), wn(:, :)
        !> the shells' connectivity in the local numbers, kept aside while
        !> the view lends them the model's (a state's shell axes read it)
        integer, allocatable :: sconn(:, :)
    end type node_view_t

contains

    !> The nodal arrays cut to the nodes this rank keeps (held_nodes), in
    !> the model's order, the model's nodal mass summed first as one rank
    !> sums it (glstat's mean velocities divide by it). First of the cut:
    !> the energies' node table is built after it (its transient whole
    !> lists no longer beside every node's state: the set-up's peak), and
    !> localize_nodes renumbers the lists after that.
    subroutine cut_state(dom, keep, st, en)
        type(domain_t), intent(inout) :: dom
        !> the model's nodes this rank keeps (held_nodes)
        logical, intent(in) :: keep(:)
        type(state_t), intent(inout) :: st
        type(energies_t), intent(inout) :: en
        integer :: k, nl
        call set_model_mass(en, sum(real(st%mass, dp)))
        ! (l2g: the kept nodes in the model's order)
        dom%nglobal = size(keep)
        allocate (dom%l2g(count(keep)))
        nl = 0
        do k = 1, size(keep)
            if (.not. keep(k)) cycle
            nl = nl + 1
            dom%l2g(nl) = k
        end do
        call take(st%x, dom%l2g)
        call take(st%v, dom%l2g)
        call take(st%mass, dom%l2g)
        call take(st%dofs, dom%l2g)
        if (allocated(st%vr)) call take(st%vr, dom%l2g)
        if (allocated(st%irot)) call take(st%irot, dom%l2g)
        if (allocated(st%jprev)) call take(st%jprev, dom%l2g)
        st%nnode = nl
    end subroutine cut_state

    !> Every list that indexes the nodal arrays renumbered to the nodes
    !> this rank keeps (see the module's head; dom%l2g), the arrays
    !> themselves cut by cut_state before. Once, after the owned nodes' lists are made
    !> (choose_owned) and the energies' node table is built for the kept
    !> nodes, before the time loop's own per-node arrays are allocated.
    subroutine localize_nodes(dom, st, solids, asm, sh, asm_sh, hist, walls, pn)
        type(domain_t), intent(inout) :: dom
        type(state_t), intent(inout) :: st
        type(solids_t), intent(inout) :: solids
        type(assembly_t), intent(inout) :: asm, asm_sh
        type(shells_t), intent(inout) :: sh
        type(histories_t), intent(inout) :: hist
        type(walls_t), intent(inout) :: walls
        type(prescribed_nodes_t), intent(inout) :: pn
        logical, allocatable :: moved(:)
        integer, allocatable :: g2l(:)
        integer :: n, k, e, nl
        if (.not. allocated(dom%l2g)) error stop 'localize_nodes: the nodal arrays are not cut (cut_state first)'
        n = dom%nglobal
        nl = size(dom%l2g)
        ! (g2l: the inverse of l2g, 0 for a node not kept)
        allocate (g2l(n))
        g2l = 0
        do k = 1, nl
            g2l(dom%l2g(k)) = k
        end do

        ! the elements' connectivity (another rank's element: 0, never read)
        do e = 1, solids%n
            if (dom%own_solid(e)) then
                solids%conn(:, e) = g2l(solids%conn(:, e))
            else
                solids%conn(:, e) = 0
            end if
        end do
        do e = 1, sh%n
            if (dom%own_shell(e)) then
                sh%conn(:, e) = g2l(sh%conn(:, e))
            else
                sh%conn(:, e) = 0
            end if
        end do
        if (allocated(sh%split)) call take(sh%split, dom%l2g)
        if (allocated(sh%shared)) call renumber(sh%shared)

        ! the assembly's node -> slot lists, each kept node's as it was
        call cut_assembly(asm)
        call cut_assembly(asm_sh)

        ! the decomposition's lists
        call renumber(dom%nodes)
        call renumber(dom%split_mine)
        call take(dom%node_mine, dom%l2g)
        dom%own = dom%node_mine
        call renumber(dom%mo_node)
        call renumber(dom%mi_node)
        call node_runs(where_true(dom%node_mine), dom%kick_lo, dom%kick_hi)
        ! (every node held is moved: one run after another)
        allocate (moved(nl))
        moved = .true.
        call node_runs(where_true(moved), dom%mv_lo, dom%mv_hi)
        call mine_of(dom%every)
        if (allocated(dom%hist%node)) call mine_of(dom%hist)
        ! (every node's list is rank 0's alone now: the others send their
        ! own entries, `mine`; no node's rank is looked up again)
        if (dom%rank /= 0) then
            deallocate (dom%every%node)
            allocate (dom%every%node(0))
        end if
        if (allocated(dom%arank)) deallocate (dom%arank)

        ! the rigid walls' nodes this rank integrates, by their local
        ! numbers, each with its place in the model's list (the sums' order)
        do k = 1, walls%n
            call own_entries(walls%w(k)%node, walls%w(k)%key)
            if (allocated(walls%w(k)%on)) deallocate (walls%w(k)%on)
        end do
        ! the prescribed motions' nodes likewise, in place (their model
        ! numbers kept for the initial coordinates)
        if (allocated(pn%node)) then
            allocate (pn%lnode(size(pn%node)))
            do k = 1, size(pn%node)
                pn%lnode(k) = own_number(pn%node(k))
            end do
        end if

        ! the nodout nodes this rank integrates, by their local numbers
        if (allocated(hist%nodes)) then
            allocate (hist%lnodes(size(hist%nodes)))
            do k = 1, size(hist%nodes)
                hist%lnodes(k) = own_number(hist%nodes(k))
            end do
        end if

        dom%local = .true.
    contains
        !> The local number of the model's node g where this rank integrates
        !> it, else 0.
        integer function own_number(g) result(l)
            integer, intent(in) :: g
            l = g2l(g)
            if (l == 0) return
            if (.not. dom%node_mine(l)) l = 0
        end function own_number

        !> A list of the model's node numbers, all held here, in local numbers
        !> (a loop: no temporary of the list's size on the stack).
        subroutine renumber(list)
            integer, intent(inout) :: list(:)
            integer :: i
            do i = 1, size(list)
                list(i) = g2l(list(i))
            end do
        end subroutine renumber

        subroutine cut_assembly(as)
            type(assembly_t), intent(inout) :: as
            integer, allocatable :: p(:), s(:)
            integer :: i, c
            if (.not. allocated(as%ptr)) return
            if (size(as%ptr) /= n + 1) return
            allocate (p(nl + 1))
            p(1) = 1
            do i = 1, nl
                p(i + 1) = p(i) + as%ptr(dom%l2g(i) + 1) - as%ptr(dom%l2g(i))
            end do
            allocate (s(p(nl + 1) - 1))
            do i = 1, nl
                c = as%ptr(dom%l2g(i) + 1) - as%ptr(dom%l2g(i))
                s(p(i):p(i) + c - 1) = as%slot(as%ptr(dom%l2g(i)):as%ptr(dom%l2g(i) + 1) - 1)
            end do
            call move_alloc(p, as%ptr)
            call move_alloc(s, as%slot)
            as%nnode = nl
        end subroutine cut_assembly

        !> A list of nodes (the model's numbers) cut to this rank's own, by
        !> their local numbers, with each one's place in the list.
        subroutine own_entries(list, key)
            integer, allocatable, intent(inout) :: list(:)
            integer, allocatable, intent(out) :: key(:)
            integer :: i, c, l
            ! (compacted in place: entry c is written once entry i >= c is read)
            allocate (key(size(list)))
            c = 0
            do i = 1, size(list)
                l = own_number(list(i))
                if (l == 0) cycle
                c = c + 1
                list(c) = l
                key(c) = i
            end do
            call fit(list, c)
            call fit(key, c)
        end subroutine own_entries

        !> A gather's own entries by their local numbers.
        subroutine mine_of(gt)
            type(node_gather_t), intent(inout) :: gt
            integer :: r, i
            r = dom%rank + 1
            allocate (gt%mine(gt%cnt(r)))
            do i = 1, gt%cnt(r)
                gt%mine(i) = g2l(gt%node(gt%off(r) + i))
            end do
        end subroutine mine_of
    end subroutine localize_nodes

    !> The model's nodes a rank keeps where its nodes are numbered apart:
    !> those it moves, its own and those its elements touch (the owned
    !> lists' runs hold both; the elements' are added, so that no
    !> connectivity entry is left without a number). Before the cut.
    function held_nodes(dom, solids, sh) result(keep)
        type(domain_t), intent(in) :: dom
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        logical, allocatable :: keep(:)
        integer :: k, e
        allocate (keep(size(dom%node_mine)))
        keep = .false.
        do k = 1, size(dom%mv_lo)
            keep(dom%mv_lo(k):dom%mv_hi(k)) = .true.
        end do
        do e = 1, solids%n
            if (dom%own_solid(e)) keep(solids%conn(:, e)) = .true.
        end do
        do e = 1, sh%n
            if (dom%own_shell(e)) keep(sh%conn(:, e)) = .true.
        end do
    end function held_nodes

    !> The model's number of this rank's node l (nodes numbered per rank),
    !> or l itself.
    integer function global_node(dom, l) result(g)
        type(domain_t), intent(in) :: dom
        integer, intent(in) :: l
        g = l
        if (.not. dom%local) return
        if (l >= 1 .and. l <= size(dom%l2g)) g = dom%l2g(l)
    end function global_node

    !> Rank 0's whole view for an output (a collective: every rank calls
    !> it): the gather g's nodes (every node for a state or a dump, the
    !> nodout nodes for the histories) with their coordinates, velocities,
    !> accelerations, forces, angular velocities, moments, rotary inertias
    !> and free directions, and vminus and vrminus as given, from their
    !> ranks. With `states`, the shells' connectivity in the model's
    !> numbers until close_view. With `rest` (a state: it writes every
    !> node's coordinates and v(n) = vminus alone), the other values are
    !> gathered for rest's nodes only (the nodout nodes, which the
    !> histories written with the state read; none where it has no nodes):
    !> rank 0 no longer holds every node's accelerations, forces, angular
    !> velocities and moments for a state. The view's arrays are the
    !> model's size either way; a node no gather reached is not read.
    subroutine open_view(dom, g, model, st, sh, vminus, vrminus, states, vw, rest)
        type(domain_t), intent(in) :: dom
        type(node_gather_t), intent(in) :: g
        type(model_t), intent(in) :: model
        type(state_t), intent(in) :: st
        type(shells_t), intent(inout) :: sh
        real(wp), intent(in), optional :: vminus(:, :)
        real(wp), intent(in), allocatable, optional :: vrminus(:, :)
        logical, intent(in) :: states
        type(node_view_t), intent(inout) :: vw
        type(node_gather_t), intent(in), optional :: rest
        logical :: root
        integer :: ng, e
        root = dom%rank == 0
        ng = dom%nglobal
        vw%on = root
        if (root) then
            vw%st%nnode = ng
            vw%st%rot = st%rot
            vw%st%time = st%time
            vw%st%dt = st%dt
            vw%st%dt_old = st%dt_old
            vw%st%dt_avg_prev = st%dt_avg_prev
            vw%st%dt_first = st%dt_first
            vw%st%cycle = st%cycle
            vw%st%crit_elem = st%crit_elem
            vw%st%ext_work = st%ext_work
            vw%st%e_initial = st%e_initial
            vw%st%ms_work = st%ms_work
            allocate (vw%st%x(3, ng), vw%st%v(3, ng), vw%st%a(3, ng), vw%st%f(3, ng), vw%st%dofs(ng))
            if (allocated(st%jprev)) allocate (vw%st%jprev(3, ng))
            if (st%rot) allocate (vw%st%vr(3, ng), vw%st%mom(3, ng), vw%st%irot(ng))
            if (present(vminus)) allocate (vw%vn(3, ng))
            if (present(vrminus)) then
                if (allocated(vrminus)) allocate (vw%wn(3, ng))
            end if
        end if
        call gather_rows(dom, g, st%x, vw%st%x)
        if (present(vminus)) call gather_rows(dom, g, vminus, vw%vn)
        if (present(rest)) then
            ! (every rank alike: the nodout layout is the same on all)
            if (allocated(rest%node)) then
                call other_values(rest)
            else if (root) then
                vw%st%dofs = 0
            end if
        else
            call other_values(g)
        end if
        if (root .and. states .and. sh%n > 0) then
            call move_alloc(sh%conn, vw%sconn)
            allocate (sh%conn(4, sh%n))
            do e = 1, sh%n
                sh%conn(:, e) = model%shell_conn(:, sh%model_ix(e))
            end do
        end if
    contains
        !> the values besides the coordinates and v(n), for gk's nodes
        subroutine other_values(gk)
            type(node_gather_t), intent(in) :: gk
            real(wp), allocatable :: one(:, :), row(:, :)
            integer :: i
            call gather_rows(dom, gk, st%v, vw%st%v)
            call gather_rows(dom, gk, st%a, vw%st%a)
            call gather_rows(dom, gk, st%f, vw%st%f)
            ! (the free directions' bits, exact as reals; through an array of
            ! our own, not a temporary on the stack)
            allocate (row(1, st%nnode))
            do i = 1, st%nnode
                row(1, i) = real(st%dofs(i), wp)
            end do
            call gather_rows(dom, gk, row, one, ng)
            if (root) then
                do i = 1, ng
                    vw%st%dofs(i) = int(one(1, i), int8)
                end do
            end if
            if (allocated(st%jprev)) then
                ! (the prescribed motions' last velocity changes: a dump's)
                call gather_rows(dom, gk, st%jprev, vw%st%jprev)
            end if
            if (st%rot) then
                call gather_rows(dom, gk, st%vr, vw%st%vr)
                call gather_rows(dom, gk, st%mom, vw%st%mom)
                row(1, :) = st%irot
                call gather_rows(dom, gk, row, one, ng)
                if (root) vw%st%irot(:) = one(1, :)
            end if
            if (present(vrminus)) then
                if (allocated(vrminus)) call gather_rows(dom, gk, vrminus, vw%wn)
            end if
        end subroutine other_values
    end subroutine open_view

    !> The view released (rank 0), the shells' local connectivity back.
    subroutine close_view(sh, vw)
        type(shells_t), intent(inout) :: sh
        type(node_view_t), intent(inout) :: vw
        type(state_t) :: none
        if (allocated(vw%sconn)) then
            deallocate (sh%conn)
            call move_alloc(vw%sconn, sh%conn)
        end if
        vw%st = none
        if (allocated(vw%vn)) deallocate (vw%vn)
        if (allocated(vw%wn)) deallocate (vw%wn)
        ! (rank 0, after an output: the view's memory handed back to the
        ! system, not kept in the heap until the next output)
        if (vw%on) call release_free_memory()
        vw%on = .false.
    end subroutine close_view

    !> src(:, node) of the gather's nodes from their ranks (each sends its
    !> own, by local number) into dst(:, node) on rank 0, by the model's
    !> numbers (dst allocated there; unallocated elsewhere, or with
    !> `alloc_n`, allocated (rows, alloc_n) on rank 0 here).
    subroutine gather_rows(dom, g, src, dst, alloc_n)
        type(domain_t), intent(in) :: dom
        type(node_gather_t), intent(in) :: g
        real(wp), intent(in) :: src(:, :)
        real(wp), allocatable, intent(inout) :: dst(:, :)
        integer, intent(in), optional :: alloc_n
        real(wp), allocatable :: mine(:, :), all(:, :)
        integer :: w, r, i
        logical :: root
        root = dom%rank == 0
        w = size(src, 1)
        r = dom%rank + 1
        if (present(alloc_n) .and. root) then
            if (allocated(dst)) deallocate (dst)
            ! (zero where the gather puts nothing: the nodes a history
            ! view leaves out, which its callers convert)
            allocate (dst(w, alloc_n))
            dst = 0
        end if
        allocate (mine(w, max(g%cnt(r), 1)))
        do i = 1, g%cnt(r)
            mine(:, i) = src(:, g%mine(i))
        end do
        if (root) then
            allocate (all(w, max(sum(g%cnt), 1)))
        else
            allocate (all(w, 1))
        end if
        call comm_gather_root_wp(mine, w*g%cnt(r), all, w*g%cnt, w*g%off, root)
        if (.not. root) return
        do i = 1, size(g%node)
            dst(:, g%node(i)) = all(:, i)
        end do
    end subroutine gather_rows

end module xd_solver_local_nodes
