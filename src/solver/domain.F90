!> The MPI domain decomposition of a run (issue 8, issue 32). Every rank
!> reads the deck and holds the whole mesh, and the nodal arrays unless
!> they are numbered per rank (xd_solver_local_nodes: each rank's own
!> nodes and those its elements touch, where no contact or other feature
!> reads every node); the work is split:
!>
!> - elements: solid groups and deformable shells are cut into `nranks`
!>   parts by recursive coordinate bisection weighted by cost (a hexahedron
!>   1, a shell 0.4 NIP); a rank computes only its own elements' forces;
!> - nodes (owned nodes, the default): each node is assembled and
!>   integrated by one rank (the rank of its first element in slot order).
!>   The force slots of elements on other ranks that a node needs (the
!>   halo) are sent to it point-to-point (swap_slots), so every node's
!>   force is the sum of its slots in the serial order; once v(n+1/2) is
!>   final each rank sends its nodes' velocities to the neighbours whose
!>   elements touch them, and in the same messages its contact surfaces'
!>   and pressure segments' nodes' velocities to every other rank
!>   (swap_velocities, motion_to_all), the beams' and ties' by a gather
!>   (gather_subset); every rank that holds a node's
!>   velocity moves it by the same x += dt v (owned_motion). Rigid bodies,
!>   walls, prescribed motions and ties receive what they need from the
!>   nodes' ranks (gather_subset, xd_core_comm's comm_ordered_records).
!>   In the replicated nodal state (XDYNA_REPLICATED=1) every rank
!>   integrates every node from forces shared by an exact sum;
!> - contact: each interface's slave nodes are cut by coordinate bisection
!>   (with owned nodes, a slave is its node's rank's); a rank searches
!>   (global and local) and computes the penalty forces of its own slaves
!>   against every master segment, and the contacts found go to the ranks
!>   that integrate their nodes (every rank where an output reads every
!>   pair, or without contact ghosts), which add them to the nodal forces in
!>   slave order. With contact ghosts a rank holds current only the surface
!>   nodes near its slaves: those a search reads (search_exchange) and
!>   those its local search reads until the next (contact_ghosts).
!>
!> Element state (stresses for d3plot and the restart dump) lives with the
!> element's rank and is gathered, exactly, when an output needs it; the
!> energies are each rank's own sums, added. The elements' state (the
!> solids' stresses, volumes, hourglass forces, bulk viscosity, plastic
!> strains, back stresses; the shells' points' stresses, plastic strains,
!> strains, back stresses, hourglass forces) is held for the rank's own
!> elements alone, in rows of their own, and so are their force slots,
!> with the halo's received ones after them (the shells' allocated so once
!> the split is made, place_shell_state; the solids' cut to the rank's
!> groups once the set-up and a restart's dump have put every solid's
!> initial state in place, localize_element_state); rank 0 takes every
!> element's, gathered, for the time of a state
!> or a dump it writes (solid_state_view, shell_state_view,
!> release_element_view). The motion is bitwise that of the serial run for
!> any rank count (the energies agree to rounding). The price is memory:
!> the mesh is on every rank (the shells' energies, thickness and area by
!> row with owned nodes: shell_rows; the solids' energies whole), and so
!> are the nodal arrays of a model whose contact (or rigid bodies, ties,
!> beams, pressure segments) reads every node.
module xd_solver_domain
    use xd_kinds, only: wp, dp, i8
    use xd_core_partition, only: rcb_partition, rcb_partition_by
    use xd_core_graph_partition, only: graph_partition, item_graph
    use xd_core_threads, only: threaded
    use xd_core_comm, only: comm_sum_wp, comm_sum_dp, comm_gather_wp, comm_neighbours, comm_gather_small, &
                            comm_gather_root_wp, comm_gather_root_dp, comm_max, comm_send_records, &
                            comm_sum_i8, comm_sum_int
    use xd_elements_solid_groups, only: solids_t, solid_localize
    use xd_elements_shell_bt, only: shells_t, shell_state_init, some_backstress
    use xd_solver_assembly, only: assembly_t, keep_assembled
    use xd_contact_contact, only: contacts_t, search_box
    use xd_contact_surface, only: surface_t, seg_nodes, side_a, side_b
    use xd_contact_global_search, only: list_row, list_rows
    use xd_core_sorting, only: where_true, id_map_t
    use xd_core_memory, only: alloc, nbytes, release_free_memory, grow
    use xd_core_strings, only: itoa
    use xd_model, only: model_t
    implicit none
    private
    public :: decomp_rcb, decomp_metis
    public :: node_gather_t, node_runs
    public :: domain_t, build_domain, domain_summary, gather_energy_state, gather_element_state, &
              swap_slots, swap_velocities, owned_motion, gather_subset, gather_layout, neighbour_count, &
              ghost_base, contact_ghosts, search_exchange, surface_spans, place_shell_state, localize_element_state, &
              release_element_view, &
              domain_bytes, gather_to_root

    !> A set of nodes whose values go from their ranks to every rank (an
    !> all-gather): per rank r, its own in node(off(r) + 1 : off(r) +
    !> cnt(r)), in node order.
    !> With the nodes numbered per rank (xd_solver_local_nodes), `node`
    !> keeps the model's numbers (rank 0 puts the values there, in its
    !> whole view of an output) and `mine` holds this rank's own entries'
    !> local numbers, which it sends.
    type :: node_gather_t
        integer, allocatable :: node(:), cnt(:), off(:)
        integer, allocatable :: mine(:)
    end type node_gather_t

    type :: domain_t
        integer :: rank = 0, nranks = 1
        logical :: on = .false.               !< more than one rank
        !> how the elements were split (the summary's heading), and the METIS
        !> partition's edge cut (nodes shared across ranks, counted per pair
        !> of work items)
        character(len=:), allocatable :: method_text
        integer :: edgecut = -1
        integer, allocatable :: nodes(:)      !< nodes this rank assembles
        !> of them, those other ranks' elements touch too (their sums wait
        !> for the halo's slots)
        integer, allocatable :: split_mine(:)
        logical, allocatable :: node_mine(:)
        logical, allocatable :: solid_mine(:) !< per solid element: its group is this rank's
        integer, allocatable :: group_rank(:) !< per solid group: its rank (0-based)
        logical, allocatable :: shell_mine(:)
        integer, allocatable :: shell_rank(:)   !< per shell: its rank (0-based)
        integer, allocatable :: bslot(:)      !< halo: solid force slots assembled on another rank
        logical, allocatable :: bslot_mine(:)
        integer, allocatable :: bshell(:)     !< halo: shell slots likewise
        logical, allocatable :: bshell_mine(:)
        integer :: nhalo = 0                  !< nodes with elements on more than one rank
        integer :: width = 3                  !< values a node's force carries: 3, or 6 with shells' moments
        real(dp), allocatable :: cost(:)      !< element cost per rank
        integer, allocatable :: nslave(:)     !< slave nodes per rank (all interfaces)
        !> per rank, what an owned-node layout would hold (issue 32; on rank
        !> 0, which logs it, with more than one rank): its solids, shells, the nodes its
        !> elements touch, of which those another rank assembles (the halo),
        !> the ranks it shares a node with, and over the contact interfaces
        !> the ghosts: other ranks' segments within reach of its slaves'
        !> box grown by the pool margin, and their nodes it does not touch
        integer, allocatable :: psolid(:), pshell(:), ptouch(:), phalo(:), pnbr(:), pgseg(:), pgnode(:)
        character(len=:), allocatable :: parts_text(:)   !< per rank: the part ids of its elements
        !> Owned nodes (issue 32): each rank integrates only the nodes it
        !> assembles, sends the halo slots it computed to their nodes'
        !> assemblers alone and, after each step, its nodes' motion to the
        !> ranks whose elements touch them (point-to-point, xd_core_comm's
        !> comm_neighbours). Set by the time loop, unless XDYNA_REPLICATED
        !> asks that every rank integrate every node.
        logical :: owned = .false.
        !> owned nodes (unless XDYNA_CONTACT_OWN=0; unallocated otherwise, so
        !> passed as absent): own again, given to the contact: the contact's motion
        !> bounds and largest speeds taken by each rank over its own surface
        !> nodes and reduced over the ranks (contact_drift,
        !> contact_local_search), and the contacts' work booked by slave, as
        !> ghosts by proximity need (no rank then holds every surface
        !> velocity). Each cycle it adds three small collectives that wait
        !> for the slowest rank (car6 on 2 ranks: time integration 1.0 ->
        !> 1.8 s of 17), which the ghosts it allows repay from a few ranks on
        !> (doc/performance.md: on 16 cores, 8 and 16 ranks 1.4x and 1.47x
        !> faster, 2 x 8 and 4 x 4 1.21x and 1.28x), so it is the default
        logical, allocatable :: own_contact(:)
        !> with own_contact (XDYNA_GHOSTS=0: off): contact ghosts by proximity. The
        !> contact surfaces' velocities no longer go to every rank: at each
        !> global search each rank's box of what a search of its slaves
        !> buckets goes to all, and each rank sends its own surface nodes
        !> inside another's box to it (search_exchange; csurf, every surface
        !> node by rank, is what the sides and XDYNA_CHECK_GHOSTS read);
        !> after it each rank's box of the surface nodes its slaves read goes
        !> to all, and until the next search a rank sends its own surface
        !> nodes inside another's box to it with its halo's motion, their
        !> position and velocity first (contact_ghosts). bmo_*, bmi_*,
        !> mv_base: the lists and the moved nodes without the ghosts
        logical :: ghosts = .false.
        type(node_gather_t) :: csurf
        integer, allocatable :: bmo_ptr(:), bmo_node(:), bmi_ptr(:), bmi_node(:)
        logical, allocatable :: bmo_rot(:), bmi_rot(:), mv_base(:)
        integer :: nghost_out = 0                  !< ghost entries this rank sent, last list
        integer :: nrefresh = 0                    !< ghost lists made (searches and the start)
        integer(i8) :: ghost_out_sum = 0           !< ghost entries sent, summed over the lists made
        !> the searches' exchanges (search_exchange): how many, and the
        !> surface nodes this rank sent in them, summed
        integer :: nsearch_ex = 0
        integer(i8) :: search_sent = 0
        !> XDYNA_CHECK_GHOSTS=1: each search's exchange checked against every
        !> surface node gathered from its rank (check_search): the surface
        !> nodes checked, those held current whose position or velocity is
        !> not their rank's, and the master nodes inside the rank's search
        !> box not held current, summed over the ranks and searches
        logical :: check_search = .false.
        integer(i8) :: search_check(3) = 0
        !> with owned nodes, node_mine again; unallocated in the replicated
        !> state, so that a routine's optional `mine` argument given it is
        !> absent there (every rank takes every node)
        logical, allocatable :: own(:)
        logical, allocatable :: own_solid(:), own_shell(:)   !< likewise solid_mine, shell_mine
        integer, allocatable :: nbr(:)        !< every other rank (0-based, ascending), the lists' order
        !> per neighbour k, entries ptr(k) + 1 .. ptr(k + 1), in slot order:
        !> the solids' halo slots sent to k (computed here, k assembles the
        !> node) and received from k (k computed them, this rank assembles);
        !> the shells' likewise
        integer, allocatable :: so_ptr(:), so_slot(:), si_ptr(:), si_slot(:)
        integer, allocatable :: ho_ptr(:), ho_slot(:), hi_ptr(:), hi_slot(:)
        !> per neighbour k, in node order: this rank's nodes whose motion
        !> goes to k (k's elements touch them) and k's nodes whose motion
        !> comes from k (this rank's elements touch them)
        integer, allocatable :: mo_ptr(:), mo_node(:), mi_ptr(:), mi_node(:)
        !> per entry of mo_node and mi_node: the node's angular velocity
        !> travels too (a node whose elements the receiver computes; not a
        !> contact surface node that only the contact reads, motion_to_all)
        logical, allocatable :: mo_rot(:), mi_rot(:)
        integer, allocatable :: arank(:)      !< every node's assembling (owned nodes: integrating) rank
        !> owned nodes with contact: the contact surfaces' nodes, whose
        !> velocities every rank receives each cycle (the surfaces stay whole
        !> on every rank); with rigid bodies, their nodes, whose forces
        !> (and moments) every rank receives before the bodies move (every
        !> rank moves every body alike)
        type(node_gather_t) :: surf, body
        !> every node, by the rank that assembles it (the replicated state's
        !> nodal forces, a state's or a dump's nodal values)
        type(node_gather_t) :: every
        !> owned nodes with beams: their nodes, whose velocities and angular
        !> velocities every rank receives (every rank takes every beam)
        type(node_gather_t) :: rotn
        !> owned nodes with tied contacts: the ties' nodes (slaves and their
        !> segments'), whose forces (and moments) every rank receives before
        !> the ties move them and whose final velocities every rank receives
        !> before the slaves follow their segments (every rank takes every
        !> tie); kick_lo, kick_hi: the nodes this rank updates the velocities
        !> of (its own and the ties') as runs of consecutive numbers (at
        !> most run_max long, so that threads share them: the loops over
        !> them vectorise)
        type(node_gather_t) :: tie
        integer, allocatable :: kick_lo(:), kick_hi(:)
        !> owned nodes: the nodout nodes, gathered at a history output
        type(node_gather_t) :: hist
        !> Nodes numbered per rank (issue 32; xd_solver_local_nodes): the
        !> nodal arrays hold the rank's own nodes and those its elements
        !> touch alone, numbered 1 .. size(l2g) in the model's order; l2g:
        !> each one's number in the model, of nglobal
        logical :: local = .false.
        integer :: nglobal = 0
        integer, allocatable :: l2g(:)
        !> owned nodes: the nodes this rank moves (its own, those its
        !> elements touch, the contact surfaces' and the rigid bodies') as runs
        integer, allocatable :: mv_lo(:), mv_hi(:)
    end type domain_t

    integer, parameter :: run_max = 1024
    !> the element decomposition: recursive coordinate bisection (the
    !> default) or METIS's k-way partition of the elements' graph
    integer, parameter :: decomp_rcb = 1, decomp_metis = 2

contains

    !> The bytes of the decomposition's arrays on this rank: per node (whose
    !> it is, the rank that integrates it, the runs it moves), per element
    !> (whose it is) and per slot and list entry (the halo's and the
    !> gathers' lists).
    integer(i8) function domain_bytes(dom) result(b)
        type(domain_t), intent(in) :: dom
        b = nbytes(dom%nodes) + nbytes(dom%split_mine) + nbytes(dom%node_mine) + nbytes(dom%solid_mine) &
            + nbytes(dom%group_rank) + nbytes(dom%shell_mine) + nbytes(dom%shell_rank) + nbytes(dom%bslot) &
            + nbytes(dom%bslot_mine) + nbytes(dom%bshell) + nbytes(dom%bshell_mine) + nbytes(dom%cost) &
            + nbytes(dom%nslave) + nbytes(dom%own_contact) + nbytes(dom%bmo_ptr) + nbytes(dom%bmo_node) &
            + nbytes(dom%bmi_ptr) + nbytes(dom%bmi_node) + nbytes(dom%bmo_rot) + nbytes(dom%bmi_rot) &
            + nbytes(dom%mv_base) + nbytes(dom%own) + nbytes(dom%own_solid) + nbytes(dom%own_shell) &
            + nbytes(dom%nbr) + nbytes(dom%so_ptr) + nbytes(dom%so_slot) + nbytes(dom%si_ptr) + nbytes(dom%si_slot) &
            + nbytes(dom%ho_ptr) + nbytes(dom%ho_slot) + nbytes(dom%hi_ptr) + nbytes(dom%hi_slot) &
            + nbytes(dom%mo_ptr) + nbytes(dom%mo_node) + nbytes(dom%mi_ptr) + nbytes(dom%mi_node) &
            + nbytes(dom%mo_rot) + nbytes(dom%mi_rot) + nbytes(dom%arank) + nbytes(dom%kick_lo) &
            + nbytes(dom%kick_hi) + nbytes(dom%mv_lo) + nbytes(dom%mv_hi) + gathered(dom%csurf) &
            + gathered(dom%surf) + gathered(dom%body) + gathered(dom%every) + gathered(dom%rotn) &
            + gathered(dom%tie) + gathered(dom%hist) + nbytes(dom%l2g)
    contains
        integer(i8) function gathered(g)
            type(node_gather_t), intent(in) :: g
            gathered = nbytes(g%node) + nbytes(g%cnt) + nbytes(g%off) + nbytes(g%mine)
        end function gathered
    end function domain_bytes

    !> Split the work of the model over `nranks` ranks; this is rank `rank`.
    !> Sets the element groups' and shells' ownership and each interface's
    !> own slave nodes.
    subroutine build_domain(model, x0, solids, sh, asm, asm_sh, ct, rank, nranks, dom, method, alone)
        type(model_t), intent(in) :: model
        real(wp), intent(in) :: x0(:, :)
        type(solids_t), intent(inout) :: solids
        type(shells_t), intent(inout) :: sh
        type(assembly_t), intent(in) :: asm, asm_sh
        type(contacts_t), intent(inout) :: ct
        integer, intent(in) :: rank, nranks
        type(domain_t), intent(out) :: dom
        !> decomp_rcb (absent: the same) or decomp_metis
        integer, intent(in), optional :: method
        !> --check parts=N: one process makes every rank's row of the
        !> summary's table itself (absent: each rank makes its own, summed
        !> over the ranks, a collective)
        logical, intent(in), optional :: alone
        !> (with `alone`: the bisection's every cut made here, not each
        !> rank's to its own part)
        logical :: every_cut
        integer, allocatable :: rows(:)
        real(wp), allocatable :: xc(:, :), w(:)
        integer, allocatable :: part(:), arank(:), spart(:), grank(:), shrank(:), iota(:)
        logical, allocatable :: multi(:)
        !> (d3hsp's table) the nodes one rank's elements touch, made for
        !> each row in turn (touched): one rank's at a time, not every
        !> rank's at once (a (node, rank) table was 64 MB on 16 ranks of a
        !> 1,000,000-node plate, rank 0's peak)
        logical, allocatable :: touch(:)
        integer :: ni, g, e, k, nd, j, r, i, nnode
        dom%rank = rank
        dom%nranks = nranks
        dom%on = nranks > 1
        nnode = asm%nnode
        if (sh%n > 0) dom%width = 6

        ! work items: the solid groups (their centres held: a group is a
        ! run of elements), then the shells (each one's centre made when
        ! the cut reads it, item_centre: 24 bytes a shell not held beside
        ! the set-up's whole state)
        ni = solids%ngroup + sh%n
        allocate (xc(3, solids%ngroup), w(ni), part(ni))
        do g = 1, solids%ngroup
            associate (gr => solids%group(g))
                xc(:, g) = 0
                do e = gr%first, gr%last
                    xc(:, g) = xc(:, g) + sum(x0(:, solids%conn(:, e)), 2)/8
                end do
                xc(:, g) = xc(:, g)/(gr%last - gr%first + 1)
                w(g) = real(gr%last - gr%first + 1, wp)
            end associate
        end do
        do e = 1, sh%n
            w(solids%ngroup + e) = 0.4_wp*sh%pc%nip(sh%part(e))
        end do
        dom%method_text = 'recursive coordinate bisection'
        if (present(method)) then
            if (method == decomp_metis) call metis_items()
        end if
        ! (--check parts=N: one process makes every part)
        every_cut = .false.
        if (present(alone)) every_cut = alone
        if (dom%edgecut < 0) then
            if (every_cut) then
                call rcb_partition_by(item_centre, w, nranks, part)
            else
                call own_part()
            end if
        end if
        part = part - 1
        grank = part(1:solids%ngroup)
        shrank = part(solids%ngroup + 1:)
        allocate (dom%cost(nranks))
        dom%cost = 0
        do i = 1, ni
            dom%cost(part(i) + 1) = dom%cost(part(i) + 1) + w(i)
        end do
        ! (the items' centres and weights: no more use; the room, for what
        ! follows)
        deallocate (xc, w, part)
        solids%active = grank == rank
        dom%group_rank = grank
        call list_parts()
        allocate (dom%solid_mine(solids%n))
        do g = 1, solids%ngroup
            dom%solid_mine(solids%group(g)%first:solids%group(g)%last) = grank(g) == rank
        end do
        dom%shell_mine = shrank == rank
        dom%shell_rank = shrank
        sh%mine = where_true(dom%shell_mine)

        ! each node's assembling rank: that of its first slot; nodes of no
        ! deformable element (rigid bodies, free nodes) go to rank 0
        allocate (arank(nnode), multi(nnode))
        arank = -1
        multi = .false.
        do nd = 1, nnode
            do j = asm%ptr(nd), asm%ptr(nd + 1) - 1
                r = grank(solids%group_of((asm%slot(j) - 1)/8 + 1))
                call seen(nd, r)
            end do
            if (sh%n > 0) then
                do j = asm_sh%ptr(nd), asm_sh%ptr(nd + 1) - 1
                    r = shrank((asm_sh%slot(j) - 1)/4 + 1)
                    call seen(nd, r)
                end do
            end if
            if (arank(nd) < 0) arank(nd) = 0
        end do
        dom%nhalo = count(multi)
        dom%node_mine = arank == rank
        dom%nodes = where_true(dom%node_mine)
        dom%split_mine = where_true(multi .and. dom%node_mine)
        ! (the shells' parts: a node other ranks' elements touch takes its
        ! forces through the slots; on one rank none does)
        if (dom%on) then
            allocate (sh%split(nnode))
            sh%split = 0
            where (multi .and. dom%node_mine) sh%split = 1
            where (multi .and. .not. dom%node_mine) sh%split = 2
        end if
        ! (the shells' blocks and their direct nodes follow from mine and
        ! split once the rows are placed: place_shell_state)
        dom%arank = arank
        ! (every node: an iota of our own, not a constructor on the stack)
        allocate (iota(nnode))
        do nd = 1, nnode
            iota(nd) = nd
        end do
        call gather_layout(arank, nranks, iota, dom%every)
        deallocate (iota)
        ! the halo slots: those of elements on a node that another rank assembles
        call halo_slots(8, solids%conn, grank(solids%group_of), dom%bslot, dom%bslot_mine)
        if (sh%n > 0) then
            call halo_slots(4, sh%conn, shrank, dom%bshell, dom%bshell_mine)
        else
            allocate (dom%bshell(0), dom%bshell_mine(0))
        end if

        ! (the table's rows: each rank its own, or with `alone` every one:
        ! rank 0 making all of them, O(ranks x nodes), held every rank at the
        ! start until it was done)
        if (present(alone)) then
            if (alone) rows = [(r, r=1, nranks)]
        end if
        if (.not. allocated(rows)) rows = [rank + 1]
        if (nranks > 1) call part_sizes()
        call neighbour_lists()

        ! contact: each interface's slaves by coordinate bisection (slaves
        ! whose lists go to the debug dump stay on rank 0, which writes it)
        allocate (dom%nslave(nranks))
        dom%nslave = 0
        allocate (dom%pgseg(nranks), dom%pgnode(nranks))
        dom%pgseg = 0
        dom%pgnode = 0
        ct%distributed = dom%on
        ct%nranks = nranks
        do i = 1, ct%n
            associate (it => ct%ifc(i), s => ct%ifc(i)%surf)
                if (allocated(xc)) deallocate (xc, w)
                if (allocated(spart)) deallocate (spart)
                allocate (xc(3, s%nslave), w(s%nslave), spart(s%nslave))
                do k = 1, s%nslave
                    xc(:, k) = x0(:, s%node(s%slave(k)))
                end do
                w = 1
                if (nranks > 1 .and. .not. every_cut) then
                    ! (each rank the cuts to its own part, summed: own_part)
                    call rcb_partition(xc, w, nranks, spart, only=rank + 1)
                    call comm_sum_int(spart, s%nslave)
                else
                    call rcb_partition(xc, w, nranks, spart)
                end if
                spart = spart - 1
                if (allocated(it%dump)) spart(it%dump) = 0
                it%owned = spart == rank
                it%mine = where_true(it%owned .and. it%live)
                do r = 1, nranks
                    dom%nslave(r) = dom%nslave(r) + count(spart == r - 1)
                end do
                if (nranks > 1) call ghosts(it%surf, it%dl, it%reach, spart)
            end associate
        end do
        if (nranks > 1 .and. size(rows) == 1) then
            call comm_sum_int(dom%pgseg, nranks)
            call comm_sum_int(dom%pgnode, nranks)
        end if
        if (allocated(touch)) deallocate (touch)
    contains
        !> The bisection of the ranks: each rank makes the cuts that lead to
        !> its own part (about half the sorting every rank repeated when
        !> each made every cut: 0.36e9 instructions on each of 16 ranks for
        !> 120,000 shells) and the parts are summed over the ranks, each
        !> item's given by one rank alone (the same partition).
        subroutine own_part()
            call rcb_partition_by(item_centre, w, nranks, part, only=rank + 1)
            if (nranks > 1) call comm_sum_int(part, ni)
        end subroutine own_part

        !> work item i's centre: a solid group's (held), a shell's
        subroutine item_centre(i, c)
            integer, intent(in) :: i
            real(wp), intent(out) :: c(3)
            integer :: k
            if (i <= solids%ngroup) then
                c = xc(:, i)
            else
                ! (sum(x0(:, conn), 2)/4 in the same order, without the
                ! temporary the array expression made at each of the cut's
                ! reads: 1,500 instructions a shell)
                c = 0
                do k = 1, 4
                    c = c + x0(:, sh%conn(k, i - solids%ngroup))
                end do
                c = c/4
            end if
        end subroutine item_centre

        !> METIS's k-way partition of the work items (decomp=metis): the
        !> items' graph through their shared nodes, each item weighing its
        !> cost (in tenths); where METIS fails, the bisection, said in the
        !> heading.
        subroutine metis_items()
            integer, allocatable :: iptr(:), inode(:), xadj(:), adjncy(:), adjwgt(:), vwgt(:)
            integer :: status, q
            logical :: ok
            allocate (iptr(ni + 1), vwgt(ni))
            iptr(1) = 1
            do g = 1, solids%ngroup
                iptr(g + 1) = iptr(g) + 8*(solids%group(g)%last - solids%group(g)%first + 1)
            end do
            do e = 1, sh%n
                iptr(solids%ngroup + e + 1) = iptr(solids%ngroup + e) + 4
            end do
            allocate (inode(iptr(ni + 1) - 1))
            q = 0
            do g = 1, solids%ngroup
                do e = solids%group(g)%first, solids%group(g)%last
                    inode(q + 1:q + 8) = solids%conn(:, e)
                    q = q + 8
                end do
            end do
            do e = 1, sh%n
                inode(q + 1:q + 4) = sh%conn(:, e)
                q = q + 4
            end do
            vwgt = max(1, nint(10*w))
            call item_graph(ni, nnode, iptr, inode, xadj, adjncy, adjwgt)
            call graph_partition(xadj, adjncy, vwgt, adjwgt, nranks, part, dom%edgecut, ok, status)
            if (ok) then
                dom%method_text = 'METIS k-way on the elements'' graph, '//itoa(dom%edgecut)//' shared nodes cut'
            else
                dom%edgecut = -1
                dom%method_text = 'recursive coordinate bisection: METIS failed (status '//itoa(status)//')'
            end if
        end subroutine metis_items

        !> Per rank: its elements, the nodes they touch, the halo, and the
        !> ranks it shares a node with: those that assemble a node it
        !> touches or touch a node it assembles. The rows `rows` made here,
        !> the others' summed in from their ranks.
        subroutine part_sizes()
            logical, allocatable :: nbr(:, :)
            integer, allocatable :: inbr(:)
            integer :: q, a, iq
            allocate (touch(nnode), nbr(nranks, nranks))
            allocate (dom%psolid(nranks), dom%pshell(nranks), dom%ptouch(nranks), dom%phalo(nranks), dom%pnbr(nranks))
            dom%psolid = 0
            dom%pshell = 0
            do q = 1, solids%n
                a = grank(solids%group_of(q)) + 1
                dom%psolid(a) = dom%psolid(a) + 1
            end do
            do q = 1, sh%n
                a = shrank(q) + 1
                dom%pshell(a) = dom%pshell(a) + 1
            end do
            nbr = .false.
            dom%ptouch = 0
            dom%phalo = 0
            do iq = 1, size(rows)
                q = rows(iq)
                call touched(q)
                do nd = 1, nnode
                    if (.not. touch(nd)) cycle
                    dom%ptouch(q) = dom%ptouch(q) + 1
                    if (arank(nd) /= q - 1) then
                        dom%phalo(q) = dom%phalo(q) + 1
                        nbr(q, arank(nd) + 1) = .true.
                        nbr(arank(nd) + 1, q) = .true.
                    end if
                end do
            end do
            if (size(rows) == 1) then
                call comm_sum_int(dom%ptouch, nranks)
                call comm_sum_int(dom%phalo, nranks)
                allocate (inbr(nranks*nranks))
                inbr = merge(1, 0, reshape(nbr, [nranks*nranks]))
                call comm_sum_int(inbr, nranks*nranks)
                nbr = reshape(inbr > 0, [nranks, nranks])
            end if
            do q = 1, nranks
                dom%pnbr(q) = count(nbr(:, q))
            end do
        end subroutine part_sizes

        !> touch: the nodes rank q's (1-based) elements touch.
        subroutine touched(q)
            integer, intent(in) :: q
            integer :: e
            touch = .false.
            do e = 1, solids%n
                if (grank(solids%group_of(e)) == q - 1) touch(solids%conn(:, e)) = .true.
            end do
            do e = 1, sh%n
                if (shrank(e) == q - 1) touch(sh%conn(:, e)) = .true.
            end do
        end subroutine touched

        !> The ghosts of surface s for each rank: the segments whose box (at
        !> x0) meets the box of the rank's part of the surface (its slaves and
        !> the surface nodes its elements touch) grown by their largest pool
        !> margin dl and the reach, less those whose nodes the rank's
        !> elements all touch; their nodes it does not touch.
        subroutine ghosts(s, dl, reach, spart)
            type(surface_t), intent(in) :: s
            real(wp), intent(in) :: dl(:), reach
            integer, intent(in) :: spart(:)
            real(wp) :: lo(3), hi(3), g, blo(3), bhi(3)
            logical, allocatable :: gn(:)
            integer :: q, k, m, nn, c, iq
            allocate (gn(nnode))
            do iq = 1, size(rows)
                q = rows(iq)
                call touched(q)
                lo = huge(1.0_wp)
                hi = -huge(1.0_wp)
                g = 0
                do k = 1, s%nslave
                    if (spart(k) /= q - 1) cycle
                    lo = min(lo, x0(:, s%node(s%slave(k))))
                    hi = max(hi, x0(:, s%node(s%slave(k))))
                    g = max(g, dl(s%slave(k)))
                end do
                do k = 1, s%nnode
                    if (.not. touch(s%node(k))) cycle
                    lo = min(lo, x0(:, s%node(k)))
                    hi = max(hi, x0(:, s%node(k)))
                    g = max(g, dl(k))
                end do
                lo = lo - (g + reach)
                hi = hi + (g + reach)
                gn = .false.
                do m = 1, s%nseg
                    nn = seg_nodes(s%seg(:, m))
                    if (all(touch(s%node(s%seg(1:nn, m))))) cycle
                    blo = huge(1.0_wp)
                    bhi = -huge(1.0_wp)
                    do c = 1, nn
                        blo = min(blo, x0(:, s%node(s%seg(c, m))))
                        bhi = max(bhi, x0(:, s%node(s%seg(c, m))))
                    end do
                    if (any(blo > hi) .or. any(bhi < lo)) cycle
                    dom%pgseg(q) = dom%pgseg(q) + 1
                    do c = 1, nn
                        if (.not. touch(s%node(s%seg(c, m)))) gn(s%node(s%seg(c, m))) = .true.
                    end do
                end do
                dom%pgnode(q) = dom%pgnode(q) + count(gn)
            end do
        end subroutine ghosts

        !> The owned-node exchange lists (domain_t's nbr, so/si, ho/hi,
        !> mo/mi) from the halo slots: a slot of this rank's element on a
        !> node rank q assembles goes to q, and q sends that node's motion
        !> back; a slot of q's element on a node this rank assembles comes
        !> from q, and the node's motion goes to q. The lists are kept for
        !> every other rank (empty where nothing passes: comm_neighbours
        !> sends no empty message), so that motion_to_all only lengthens
        !> the motion lists.
        subroutine neighbour_lists()
            integer, allocatable :: sto(:), sfrom(:), hto(:), hfrom(:)
            logical, allocatable :: mark(:)
            integer :: q, k
            allocate (sto(size(dom%bslot)), sfrom(size(dom%bslot)), hto(size(dom%bshell)), hfrom(size(dom%bshell)))
            allocate (mark(nnode))
            do k = 1, size(dom%bslot)
                call ends(dom%bslot(k), 8, solids%conn, grank(solids%group_of((dom%bslot(k) - 1)/8 + 1)), &
                          sto(k), sfrom(k))
            end do
            do k = 1, size(dom%bshell)
                call ends(dom%bshell(k), 4, sh%conn, shrank((dom%bshell(k) - 1)/4 + 1), hto(k), hfrom(k))
            end do
            dom%nbr = pack([(q, q=0, nranks - 1)], [(q /= rank, q=0, nranks - 1)])
            allocate (dom%so_ptr(1), dom%si_ptr(1), dom%ho_ptr(1), dom%hi_ptr(1), dom%mo_ptr(1), dom%mi_ptr(1))
            dom%so_ptr = 0; dom%si_ptr = 0; dom%ho_ptr = 0; dom%hi_ptr = 0; dom%mo_ptr = 0; dom%mi_ptr = 0
            allocate (dom%so_slot(0), dom%si_slot(0), dom%ho_slot(0), dom%hi_slot(0), dom%mo_node(0), dom%mi_node(0))
            do k = 1, size(dom%nbr)
                q = dom%nbr(k)
                dom%so_slot = [dom%so_slot, pack(dom%bslot, sto == q)]
                dom%si_slot = [dom%si_slot, pack(dom%bslot, sfrom == q)]
                dom%ho_slot = [dom%ho_slot, pack(dom%bshell, hto == q)]
                dom%hi_slot = [dom%hi_slot, pack(dom%bshell, hfrom == q)]
                dom%so_ptr = [dom%so_ptr, size(dom%so_slot)]
                dom%si_ptr = [dom%si_ptr, size(dom%si_slot)]
                dom%ho_ptr = [dom%ho_ptr, size(dom%ho_slot)]
                dom%hi_ptr = [dom%hi_ptr, size(dom%hi_slot)]
                ! the motion: this rank's nodes q's slots come from, q's
                ! nodes this rank's slots go to
                mark = .false.
                call mark_nodes(pack(dom%bslot, sfrom == q), 8, solids%conn, mark)
                call mark_nodes(pack(dom%bshell, hfrom == q), 4, sh%conn, mark)
                dom%mo_node = [dom%mo_node, where_true(mark)]
                dom%mo_ptr = [dom%mo_ptr, size(dom%mo_node)]
                mark = .false.
                call mark_nodes(pack(dom%bslot, sto == q), 8, solids%conn, mark)
                call mark_nodes(pack(dom%bshell, hto == q), 4, sh%conn, mark)
                dom%mi_node = [dom%mi_node, where_true(mark)]
                dom%mi_ptr = [dom%mi_ptr, size(dom%mi_node)]
            end do
            allocate (dom%mo_rot(size(dom%mo_node)), dom%mi_rot(size(dom%mi_node)))
            dom%mo_rot = .true.
            dom%mi_rot = .true.
        end subroutine neighbour_lists

        !> Slot j (nen a element, its element on rank er): the rank it goes
        !> to from here (to) or comes from to here (from), -1 if none.
        subroutine ends(j, nen, conn, er, to, from)
            integer, intent(in) :: j, nen, conn(:, :), er
            integer, intent(out) :: to, from
            integer :: an
            an = arank(conn(mod(j - 1, nen) + 1, (j - 1)/nen + 1))
            to = -1
            from = -1
            if (er == rank .and. an /= rank) to = an
            if (an == rank .and. er /= rank) from = er
        end subroutine ends

        !> mark: the nodes of the slots (nen an element).
        subroutine mark_nodes(slots, nen, conn, mark)
            integer, intent(in) :: slots(:), nen, conn(:, :)
            logical, intent(inout) :: mark(:)
            integer :: i
            do i = 1, size(slots)
                mark(conn(mod(slots(i) - 1, nen) + 1, (slots(i) - 1)/nen + 1)) = .true.
            end do
        end subroutine mark_nodes

        !> Per rank, the ids of the parts it has elements of.
        subroutine list_parts()
            logical :: on(model%npart, nranks)
            character(len=12*model%npart + 8) :: t(nranks)
            integer :: p, q
            on = .false.
            do q = 1, solids%ngroup
                on(solids%group(q)%part, grank(q) + 1) = .true.
            end do
            do q = 1, sh%n
                on(sh%part(q), shrank(q) + 1) = .true.
            end do
            do q = 1, nranks
                t(q) = ''
                do p = 1, model%npart
                    if (on(p, q)) t(q) = trim(t(q))//' '//itoa(model%part(p)%id)
                end do
                if (len_trim(t(q)) == 0) t(q) = ' none'
            end do
            dom%parts_text = t
        end subroutine list_parts

        !> Slots (nen per element) whose element's rank is not its node's.
        subroutine halo_slots(nen, conn, erank, list, mine)
            integer, intent(in) :: nen, conn(:, :), erank(:)
            integer, allocatable, intent(out) :: list(:)
            logical, allocatable, intent(out) :: mine(:)
            logical, allocatable :: halo(:)
            integer :: e, k
            allocate (halo(nen*size(erank)))
            do e = 1, size(erank)
                do k = 1, nen
                    halo(nen*(e - 1) + k) = erank(e) /= arank(conn(k, e))
                end do
            end do
            list = where_true(halo)
            mine = erank((list - 1)/nen + 1) == rank
        end subroutine halo_slots

        subroutine seen(nd, r)
            integer, intent(in) :: nd, r
            if (arank(nd) < 0) then
                arank(nd) = r
            else if (arank(nd) /= r) then
                multi(nd) = .true.
            end if
        end subroutine seen
    end subroutine build_domain

    !> The ascending node numbers `nodes` as runs lo(k) .. hi(k) of
    !> consecutive numbers, none longer than run_max.
    subroutine node_runs(nodes, lo, hi)
        integer, intent(in) :: nodes(:)
        integer, allocatable, intent(out) :: lo(:), hi(:)
        integer, allocatable :: t(:), u(:)
        integer :: i, n
        allocate (t(size(nodes)), u(size(nodes)))
        n = 0
        do i = 1, size(nodes)
            if (n > 0) then
                if (nodes(i) == u(n) + 1 .and. nodes(i) - t(n) < run_max) then
                    u(n) = nodes(i)
                    cycle
                end if
            end if
            n = n + 1
            t(n) = nodes(i)
            u(n) = nodes(i)
        end do
        lo = t(1:n)
        hi = u(1:n)
    end subroutine node_runs

    !> Log lines: the ranks' shares of the work and the halo.
    function domain_summary(dom) result(txt)
        type(domain_t), intent(in) :: dom
        character(len=:), allocatable :: txt
        character(len=200) :: buf
        integer :: r
        txt = ' d o m a i n   d e c o m p o s i t i o n   ('//itoa(dom%nranks)// &
              ' MPI ranks, '//dom%method_text//')'//new_line('a')// &
              '   rank   element cost   cost / mean   slave nodes   parts'//new_line('a')
        do r = 1, dom%nranks
            write (buf, '(i7,f15.1,f14.3,i14,3x)') r - 1, dom%cost(r), dom%cost(r)/max(sum(dom%cost)/dom%nranks, &
                                                                                      tiny(1.0_dp)), dom%nslave(r)
            txt = txt//trim(buf)//'  '//trim(dom%parts_text(r)(1:min(len_trim(dom%parts_text(r)), 120)))//new_line('a')
        end do
        write (buf, '(a,f8.3,a,i0,a,i0,a)') '   largest cost / mean ', &
            maxval(dom%cost)/max(sum(dom%cost)/dom%nranks, tiny(1.0_dp)), '; nodes on rank boundaries ', &
            dom%nhalo, ' of ', size(dom%node_mine), ' (the halo)'
        txt = txt//trim(buf)//new_line('a')
        txt = txt//'   halo exchange a cycle: '//itoa(size(dom%bslot) + size(dom%bshell))//' force slots ('// &
              itoa(8*(3*size(dom%bslot) + 6*size(dom%bshell)))//' bytes in all, each to its node''s rank alone); '// &
              'only in the replicated nodal state (XDYNA_REPLICATED=1) every rank''s nodal forces to all too ('// &
              itoa(8*dom%width*size(dom%node_mine))//' bytes a rank)'
        if (.not. allocated(dom%ptouch)) return
        txt = txt//new_line('a')//new_line('a')// &
              '   what each rank would hold with its own nodes and a halo (issue 32): its elements; the nodes'// &
              new_line('a')//'   they touch, of which another rank assembles the halo; the ranks it exchanges with;'// &
              new_line('a')//'   the contact ghosts: other ranks'' segments within the box of its slaves and surface'// &
              new_line('a')//'   grown by the pool margin and the reach, and their nodes it does not touch; and the'// &
              new_line('a')//'   share of the model''s nodes its nodal arrays would hold (touched and ghost nodes);'// &
              new_line('a')//'   halo bytes: its halo nodes'' forces out and their motion back, a cycle'// &
              new_line('a')//'   rank   solids   shells    nodes     halo  neighbours  ghost segs  ghost nodes  nodal share'// &
              '  halo bytes'
        do r = 1, dom%nranks
            write (buf, '(i7,3i9,i9,i12,i12,i13,f13.3,i12)') r - 1, dom%psolid(r), dom%pshell(r), dom%ptouch(r), &
                dom%phalo(r), dom%pnbr(r), dom%pgseg(r), dom%pgnode(r), &
                real(dom%ptouch(r) + dom%pgnode(r), dp)/max(size(dom%node_mine), 1), 2*8*dom%width*dom%phalo(r)
            txt = txt//new_line('a')//trim(buf)
        end do
        write (buf, '(a,i0,a)') '   halo nodes over all ranks ', sum(dom%phalo), &
            ' (a node counts once for each rank beyond its assembler whose elements touch it)'
        txt = txt//new_line('a')//trim(buf)
    end function domain_summary

    !> Owned nodes' halo exchange: the slots this rank's elements computed
    !> for nodes a neighbour assembles go to that neighbour alone, and those
    !> the neighbours computed for this rank's nodes come in (each value
    !> from one rank: the assembly then sums every node's slots in the
    !> serial order, bit for bit).
    subroutine swap_slots(dom, solids, sh)
        type(domain_t), intent(in) :: dom
        type(solids_t), intent(inout) :: solids
        type(shells_t), intent(inout) :: sh
        real(wp), allocatable :: sb(:), rb(:)
        integer :: soff(size(dom%nbr) + 1), roff(size(dom%nbr) + 1), k, i, p
        soff(1) = 0
        roff(1) = 0
        do k = 1, size(dom%nbr)
            soff(k + 1) = soff(k) + 3*(dom%so_ptr(k + 1) - dom%so_ptr(k)) + 6*(dom%ho_ptr(k + 1) - dom%ho_ptr(k))
            roff(k + 1) = roff(k) + 3*(dom%si_ptr(k + 1) - dom%si_ptr(k)) + 6*(dom%hi_ptr(k + 1) - dom%hi_ptr(k))
        end do
        allocate (sb(max(soff(size(soff)), 1)), rb(max(roff(size(roff)), 1)))
        do k = 1, size(dom%nbr)
            p = soff(k)
            do i = dom%so_ptr(k) + 1, dom%so_ptr(k + 1)
                sb(p + 1:p + 3) = solids%fslot(:, dom%so_slot(i))
                p = p + 3
            end do
            do i = dom%ho_ptr(k) + 1, dom%ho_ptr(k + 1)
                sb(p + 1:p + 3) = sh%fslot(:, dom%ho_slot(i))
                sb(p + 4:p + 6) = sh%mslot(:, dom%ho_slot(i))
                p = p + 6
            end do
        end do
        call comm_neighbours(dom%nbr, sb, soff, rb, roff)
        do k = 1, size(dom%nbr)
            p = roff(k)
            do i = dom%si_ptr(k) + 1, dom%si_ptr(k + 1)
                solids%fslot(:, dom%si_slot(i)) = rb(p + 1:p + 3)
                p = p + 3
            end do
            do i = dom%hi_ptr(k) + 1, dom%hi_ptr(k + 1)
                sh%fslot(:, dom%hi_slot(i)) = rb(p + 1:p + 3)
                sh%mslot(:, dom%hi_slot(i)) = rb(p + 4:p + 6)
                p = p + 6
            end do
        end do
    end subroutine swap_slots

    !> Owned nodes, once the velocities v(n+1/2) are final: this rank's
    !> nodes' velocities (and angular velocities, vr) to the neighbours
    !> whose elements touch them and the neighbours' nodes this rank's
    !> elements touch from them; with contact, every contact surface node's
    !> velocity from its rank to all. Each rank then moves every node it
    !> holds a velocity for by the same x += dt v (positions are never sent:
    !> they stay the same bits on every rank that moves a node).
    subroutine swap_velocities(dom, v, vr)
        type(domain_t), intent(in) :: dom
        real(wp), intent(inout) :: v(:, :)
        real(wp), intent(inout), optional :: vr(:, :)
        real(wp), allocatable :: sb(:), rb(:)
        integer :: soff(size(dom%nbr) + 1), roff(size(dom%nbr) + 1), i, nd, p, k, cs, cr
        logical :: rot
        rot = present(vr)
        ! (3 values a node, 6 where its angular velocity travels too; the
        ! rotations counted neighbour by neighbour and summed: counted from
        ! the first entry for each neighbour, they took rank 0 of 16 on the
        ! 10 x 10 tubes 2.4e7 instructions in 100 cycles, half of this
        ! routine's)
        soff = 3*dom%mo_ptr
        roff = 3*dom%mi_ptr
        if (rot) then
            cs = 0
            cr = 0
            do k = 1, size(dom%nbr)
                cs = cs + count(dom%mo_rot(dom%mo_ptr(k) + 1:dom%mo_ptr(k + 1)))
                cr = cr + count(dom%mi_rot(dom%mi_ptr(k) + 1:dom%mi_ptr(k + 1)))
                soff(k + 1) = soff(k + 1) + 3*cs
                roff(k + 1) = roff(k + 1) + 3*cr
            end do
        end if
        allocate (sb(max(soff(size(soff)), 1)), rb(max(roff(size(roff)), 1)))
        p = 0
        do i = 1, size(dom%mo_node)
            nd = dom%mo_node(i)
            sb(p + 1) = v(1, nd)
            sb(p + 2) = v(2, nd)
            sb(p + 3) = v(3, nd)
            p = p + 3
            if (rot) then
                if (dom%mo_rot(i)) then
                    sb(p + 1) = vr(1, nd)
                    sb(p + 2) = vr(2, nd)
                    sb(p + 3) = vr(3, nd)
                    p = p + 3
                end if
            end if
        end do
        call comm_neighbours(dom%nbr, sb, soff, rb, roff)
        p = 0
        do i = 1, size(dom%mi_node)
            nd = dom%mi_node(i)
            v(1, nd) = rb(p + 1)
            v(2, nd) = rb(p + 2)
            v(3, nd) = rb(p + 3)
            p = p + 3
            if (rot) then
                if (dom%mi_rot(i)) then
                    vr(1, nd) = rb(p + 1)
                    vr(2, nd) = rb(p + 2)
                    vr(3, nd) = rb(p + 3)
                    p = p + 3
                end if
            end if
        end do
        if (allocated(dom%rotn%node)) call gather_subset(dom, dom%rotn, v, vr)
        if (allocated(dom%tie%node)) call gather_subset(dom, dom%tie, v, vr)
    end subroutine swap_velocities

    !> Owned nodes: the nodes this rank moves (its own, the halo its
    !> elements touch, the contact surfaces' nodes `surf`, whose velocities
    !> swap_velocities brings from every rank, and the rigid bodies' nodes
    !> `body`, which every rank moves alike) as runs, and the surfaces' and
    !> the bodies' nodes by rank for their gathers.
    subroutine owned_motion(dom, surf, body, rotn, tie)
        type(domain_t), intent(inout) :: dom
        integer, intent(in) :: surf(:), body(:), rotn(:), tie(:)
        logical, allocatable :: mv(:)
        allocate (mv(size(dom%node_mine)))
        mv = dom%node_mine
        mv(tie) = .true.
        call node_runs(where_true(mv), dom%kick_lo, dom%kick_hi)
        mv(dom%mi_node) = .true.
        mv(surf) = .true.
        mv(body) = .true.
        mv(rotn) = .true.
        call node_runs(where_true(mv), dom%mv_lo, dom%mv_hi)
        call gather_layout(dom%arank, dom%nranks, surf, dom%surf)
        call motion_to_all(dom, surf)
        call gather_layout(dom%arank, dom%nranks, body, dom%body)
        call gather_layout(dom%arank, dom%nranks, rotn, dom%rotn)
        if (size(tie) > 0) call gather_layout(dom%arank, dom%nranks, tie, dom%tie)
    end subroutine owned_motion

    !> Owned nodes: the nodes `nodes` (the contact surfaces' and pressure
    !> segments', repeats allowed) join the motion lists, so that each
    !> rank's own go to every other rank in the neighbour exchange (one
    !> round of messages a cycle with the halo's motion, not a gather after
    !> it: on car6's 2 ranks the gather took 1.2 s of 20, about 30 us a
    !> cycle). For each other rank q, the nodes sent to q are this rank's
    !> halo nodes q's elements touch and its own listed nodes, in node order;
    !> those received, q's likewise, so a pair's lists agree. Only the
    !> halo's entries carry angular velocities (mo_rot, mi_rot).
    subroutine motion_to_all(dom, nodes)
        type(domain_t), intent(inout) :: dom
        integer, intent(in) :: nodes(:)
        logical, allocatable :: on(:), rout(:), rin(:), mo_rot(:), mi_rot(:)
        integer, allocatable :: mo_ptr(:), mi_ptr(:), mo_node(:), mi_node(:)
        integer :: k, q, nn
        if (size(nodes) == 0) return
        nn = size(dom%node_mine)
        allocate (on(nn), rout(nn), rin(nn), mo_node(0), mi_node(0), mo_rot(0), mi_rot(0), mo_ptr(1), mi_ptr(1))
        on = .false.
        on(nodes) = .true.
        mo_ptr = 0
        mi_ptr = 0
        do k = 1, size(dom%nbr)
            q = dom%nbr(k)
            rout = .false.
            rin = .false.
            rout(dom%mo_node(dom%mo_ptr(k) + 1:dom%mo_ptr(k + 1))) = .true.
            rin(dom%mi_node(dom%mi_ptr(k) + 1:dom%mi_ptr(k + 1))) = .true.
            call append_entries(rout .or. (on .and. dom%arank == dom%rank), rout, mo_node, mo_rot, mo_ptr)
            call append_entries(rin .or. (on .and. dom%arank == q), rin, mi_node, mi_rot, mi_ptr)
        end do
        call set_motion_lists(dom, mo_ptr, mo_node, mo_rot, mi_ptr, mi_node, mi_rot)
    end subroutine motion_to_all

    !> One neighbour's entries appended to a motion list (node, rot, ptr):
    !> the nodes with `take` true, in node order, each with its angular
    !> velocity where rot_of is true.
    subroutine append_entries(take, rot_of, node, rot, ptr)
        logical, intent(in) :: take(:), rot_of(:)
        integer, allocatable, intent(inout) :: node(:), ptr(:)
        logical, allocatable, intent(inout) :: rot(:)
        node = [node, where_true(take)]
        rot = [rot, pack(rot_of, take)]
        ptr = [ptr, size(node)]
    end subroutine append_entries

    !> Motion lists made anew (ptr, node, rot) from a base list (bptr, bnode,
    !> brot: each neighbour's entries in node order) and, for each
    !> neighbour k in turn, cnt(nbr(k) + 1) more nodes from `extra` (in node
    !> order, none in the base's entries for k; no angular velocity): each
    !> neighbour's two lists merged in node order. What masks over every
    !> node, one per neighbour, gave (append_entries), in the lists' own
    !> length: at each search on 16 ranks those masks were 30 passes over
    !> the model's nodes.
    subroutine merged_lists(dom, bptr, bnode, brot, cnt, extra, ptr, node, rot)
        type(domain_t), intent(in) :: dom
        integer, intent(in) :: bptr(:), bnode(:), cnt(:), extra(:)
        logical, intent(in) :: brot(:)
        integer, allocatable, intent(out) :: ptr(:), node(:)
        logical, allocatable, intent(out) :: rot(:)
        integer :: k, a, ae, b, be, n
        allocate (ptr(size(dom%nbr) + 1))
        allocate (node(bptr(size(bptr)) + sum(cnt)), rot(bptr(size(bptr)) + sum(cnt)))
        ptr(1) = 0
        n = 0
        be = 0
        do k = 1, size(dom%nbr)
            a = bptr(k) + 1
            ae = bptr(k + 1)
            b = be + 1
            be = be + cnt(dom%nbr(k) + 1)
            do while (a <= ae .or. b <= be)
                n = n + 1
                if (b > be) then
                    call base_entry()
                else if (a > ae) then
                    call extra_entry()
                else if (bnode(a) < extra(b)) then
                    call base_entry()
                else
                    call extra_entry()
                end if
            end do
            ptr(k + 1) = n
        end do
    contains
        subroutine base_entry()
            node(n) = bnode(a)
            rot(n) = brot(a)
            a = a + 1
        end subroutine base_entry
        subroutine extra_entry()
            node(n) = extra(b)
            rot(n) = .false.
            b = b + 1
        end subroutine extra_entry
    end subroutine merged_lists

    !> The motion lists (to and from every neighbour) replaced by these.
    subroutine set_motion_lists(dom, mo_ptr, mo_node, mo_rot, mi_ptr, mi_node, mi_rot)
        type(domain_t), intent(inout) :: dom
        integer, allocatable, intent(inout) :: mo_ptr(:), mo_node(:), mi_ptr(:), mi_node(:)
        logical, allocatable, intent(inout) :: mo_rot(:), mi_rot(:)
        call move_alloc(mo_ptr, dom%mo_ptr)
        call move_alloc(mi_ptr, dom%mi_ptr)
        call move_alloc(mo_node, dom%mo_node)
        call move_alloc(mi_node, dom%mi_node)
        call move_alloc(mo_rot, dom%mo_rot)
        call move_alloc(mi_rot, dom%mi_rot)
    end subroutine set_motion_lists

    !> The ranks this rank exchanges anything with point-to-point (the
    !> lists hold every other rank, most of them empty on many ranks).
    integer function neighbour_count(dom) result(n)
        type(domain_t), intent(in) :: dom
        integer :: k
        n = 0
        do k = 1, size(dom%nbr)
            if (dom%so_ptr(k + 1) > dom%so_ptr(k) .or. dom%si_ptr(k + 1) > dom%si_ptr(k) .or. &
                dom%ho_ptr(k + 1) > dom%ho_ptr(k) .or. dom%hi_ptr(k + 1) > dom%hi_ptr(k) .or. &
                dom%mo_ptr(k + 1) > dom%mo_ptr(k) .or. dom%mi_ptr(k + 1) > dom%mi_ptr(k)) n = n + 1
        end do
    end function neighbour_count

    !> The layout of a gather of the nodes `nodes` (repeats allowed) over
    !> nranks ranks, each node from its rank arank.
    !> Contact ghosts: the lists and the moved nodes as owned_motion made
    !> them without the contact surfaces (the base every search's ghosts
    !> are added to), and the surfaces' nodes `csurf` by rank.
    subroutine ghost_base(dom, csurf)
        type(domain_t), intent(inout) :: dom
        integer, intent(in) :: csurf(:)
        integer :: k
        dom%ghosts = .true.
        dom%bmo_ptr = dom%mo_ptr
        dom%bmo_node = dom%mo_node
        dom%bmo_rot = dom%mo_rot
        dom%bmi_ptr = dom%mi_ptr
        dom%bmi_node = dom%mi_node
        dom%bmi_rot = dom%mi_rot
        allocate (dom%mv_base(size(dom%node_mine)))
        dom%mv_base = .false.
        do k = 1, size(dom%mv_lo)
            dom%mv_base(dom%mv_lo(k):dom%mv_hi(k)) = .true.
        end do
        call gather_layout(dom%arank, dom%nranks, csurf, dom%csurf)
    end subroutine ghost_base

    !> Contact ghosts at a search (every rank at once; the positions of
    !> the surface nodes its slaves read current on each rank: its own,
    !> those it moves, those search_exchange brought): this
    !> rank's box of what its slaves read (themselves, their pools' and
    !> lists' nodes, the segments at those and at them, the segments they
    !> hold), grown by the farthest of those nodes from its slave and by the
    !> longest diagonal of a segment (a local search's walk along the
    !> surface stays nearer the slave than where it began, and reads the
    !> segments at the nodes it passes; the diagonal over the ranks, each
    !> taking the segments whose nodes it holds current: surface_spans);
    !> the boxes to every rank; then the motion lists: to rank q, the
    !> base's entries and this rank's own surface nodes inside q's box;
    !> from q, the base's and the ghosts q names (their numbers, positions
    !> and velocities sent with them: only the owner holds a far node's
    !> position current), in node order.
    !> The moved nodes: the base's and those received; each interface's
    !> surface nodes among them (it%fresh, which its local search gathers
    !> until the next search).
    subroutine contact_ghosts(dom, ct, x, v, spans)
        type(domain_t), intent(inout) :: dom
        type(contacts_t), intent(inout) :: ct
        !> (a new ghost's position and velocity come with its number: the
        !> rank that takes it may hold an old one)
        real(wp), intent(inout) :: x(:, :), v(:, :)
        !> surface_spans now: the search's (search_exchange), or at the
        !> start every segment's
        real(dp), intent(in) :: spans(2)
        logical, allocatable :: rd(:), out(:), mv(:)
        integer, allocatable :: mo_ptr(:), mi_ptr(:), mo_node(:), mi_node(:), rid(:)
        logical, allocatable :: mo_rot(:), mi_rot(:)
        real(dp) :: box(6), boxes(6, dom%nranks), reach, step
        logical, allocatable :: pm(:)
        integer, allocatable :: gid(:), gcnt(:), gfrom(:)
        real(dp), allocatable :: gsend(:, :), gin(:, :)
        integer :: i, q, k, j, sn, nn, r, g, b, added, e, nd, ng, lr
        nn = size(dom%node_mine)
        allocate (rd(nn), out(nn), mv(nn))
        rd = .false.
        reach = 0
        step = 0
        do i = 1, ct%n
            associate (it => ct%ifc(i), s => ct%ifc(i)%surf)
                ! pm: the surface's nodes its slaves read (the slaves, their
                ! pools' and lists' nodes, the nodes of the segments they
                ! hold); then every segment at such a node is read whole
                allocate (pm(s%nnode))
                pm = .false.
                do q = 1, size(it%mine)
                    k = it%mine(q)
                    sn = s%slave(k)
                    pm(sn) = .true.
                    ! (the lists' row of the slave: lists_rows)
                    lr = list_row(it%lists, k)
                    if (allocated(it%lists%pool_ptr) .and. lr > 0) then
                        if (size(it%lists%pool_ptr) == list_rows(it%lists, s%nslave)) then
                            do j = it%lists%pool_ptr(lr), it%lists%pool_last(lr)
                                pm(it%lists%pool_node(j)) = .true.
                                reach = max(reach, real(norm2(x(:, s%node(it%lists%pool_node(j))) - &
                                                              x(:, s%node(sn))), dp))
                            end do
                        end if
                    end if
                    if (allocated(it%lists%ptr) .and. lr > 0) then
                        if (size(it%lists%ptr) == list_rows(it%lists, s%nslave)) then
                            do j = it%lists%ptr(lr), it%lists%last(lr)
                                if (pm(it%lists%node(j))) cycle
                                pm(it%lists%node(j)) = .true.
                                reach = max(reach, real(norm2(x(:, s%node(it%lists%node(j))) - x(:, s%node(sn))), dp))
                            end do
                        end if
                    end if
                    do j = 1, 2
                        g = it%held(it%orow(k))
                        if (j == 2) g = it%cseg(it%orow(k))
                        if (g <= 0) cycle
                        do b = 1, 4
                            pm(s%seg(b, g)) = .true.
                            reach = max(reach, real(norm2(x(:, s%node(s%seg(b, g))) - x(:, s%node(sn))), dp))
                        end do
                    end do
                end do
                ! (the segments at the marked nodes from the node-to-segment
                ! lists, not a scan of every segment of the surface at each
                ! search on every rank: those lists hold the active
                ! segments, the only ones a search or a local search reads)
                do k = 1, s%nnode
                    if (.not. pm(k)) cycle
                    do j = s%seg_ptr(k), s%seg_ptr(k + 1) - 1
                        g = s%seg_list(j)
                        do b = 1, 4
                            rd(s%node(s%seg(b, g))) = .true.
                        end do
                    end do
                    rd(s%node(k)) = .true.
                end do
                deallocate (pm)
            end associate
        end do
        ! (the step: the longest diagonal of a segment)
        step = spans(1)
        box(1:3) = huge(1.0_dp)
        box(4:6) = -huge(1.0_dp)
        do j = 1, nn
            if (.not. rd(j)) cycle
            box(1:3) = min(box(1:3), real(x(:, j), dp))
            box(4:6) = max(box(4:6), real(x(:, j), dp))
        end do
        if (box(1) <= box(4)) then
            box(1:3) = box(1:3) - (reach + step)
            box(4:6) = box(4:6) + (reach + step)
        end if
        call comm_gather_small(box, boxes)
        ! the ghosts' lists, neighbour by neighbour (every other rank)
        mv = dom%mv_base
        dom%nghost_out = 0
        ! to each other rank r: the base's entries and this rank's surface
        ! nodes in r's box; the ghosts' numbers then go to r (which holds
        ! another rank's surface nodes' positions current only near its
        ! own slaves, and so cannot tell them itself)
        allocate (gcnt(dom%nranks), gfrom(dom%nranks), gid(0))
        gcnt = 0
        ng = 0
        out = .false.
        do k = 1, size(dom%nbr)
            r = dom%nbr(k)
            call side(r, out, added)
            dom%nghost_out = dom%nghost_out + added
            gcnt(r + 1) = added
        end do
        ! (each neighbour's list: its base entries and its ghosts, both in
        ! node order, merged; gid holds the ghosts neighbour by neighbour)
        call merged_lists(dom, dom%bmo_ptr, dom%bmo_node, dom%bmo_rot, gcnt, gid, mo_ptr, mo_node, mo_rot)
        allocate (gsend(7, ng))
        do e = 1, ng
            gsend(:, e) = [real(gid(e), dp), real(x(:, gid(e)), dp), real(v(:, gid(e)), dp)]
        end do
        call comm_send_records(gsend, gcnt, gin, gfrom)
        ! from r: the base's entries and the ghosts r sent (in node order),
        ! which this rank then moves (r's records in gin in rank order, as
        ! nbr)
        allocate (rid(size(gin, 2)))
        do e = 1, size(gin, 2)
            nd = nint(gin(1, e))
            rid(e) = nd
            mv(nd) = .true.
            x(:, nd) = real(gin(2:4, e), wp)
            v(:, nd) = real(gin(5:7, e), wp)
        end do
        call merged_lists(dom, dom%bmi_ptr, dom%bmi_node, dom%bmi_rot, gfrom, rid, mi_ptr, mi_node, mi_rot)
        call set_motion_lists(dom, mo_ptr, mo_node, mo_rot, mi_ptr, mi_node, mi_rot)
        call node_runs(where_true(mv), dom%mv_lo, dom%mv_hi)
        dom%nrefresh = dom%nrefresh + 1
        dom%ghost_out_sum = dom%ghost_out_sum + dom%nghost_out
        ! the nodes this rank moves until the next search: the contact
        ! applies another rank's slave's pair only where it reaches one
        ! (ct%moves); each surface's among them: the local search gathers
        ! those alone (after one whole gather)
        if (.not. allocated(ct%moves)) allocate (ct%moves(nn))
        ! (and each contact found goes to its nodes' integrating ranks alone)
        if (.not. allocated(ct%rank_of)) then
            ct%rank_of = dom%arank
            ct%rank = dom%rank
        end if
        do k = 1, nn
            ct%moves(k) = mv(k)
        end do
        do i = 1, ct%n
            associate (it => ct%ifc(i), s => ct%ifc(i)%surf)
                ! (loops: no temporary of the surface's size on the stack)
                g = 0
                do k = 1, s%nnode
                    if (mv(s%node(k))) g = g + 1
                end do
                if (allocated(it%fresh)) deallocate (it%fresh)
                allocate (it%fresh(g))
                g = 0
                do k = 1, s%nnode
                    if (.not. mv(s%node(k))) cycle
                    g = g + 1
                    it%fresh(g) = k
                end do
                it%regather = .true.
            end associate
        end do
    contains
        !> The ghosts this rank sends neighbour k (rank `reader`): its own
        !> surface nodes inside reader's box that are not among the base
        !> list's entries for k (bmo_ptr(k)+1 .. bmo_ptr(k+1), marked in
        !> mark while they are read): `added` of them, appended to gid.
        subroutine side(reader, mark, added)
            integer, intent(in) :: reader
            logical, intent(inout) :: mark(:)
            integer, intent(out) :: added
            integer :: jj, nd, e
            ! (mark: false on entry and on return; set for the base's
            ! entries alone while they are read)
            do e = dom%bmo_ptr(k) + 1, dom%bmo_ptr(k + 1)
                mark(dom%bmo_node(e)) = .true.
            end do
            added = 0
            ! (this rank's own surface nodes: its block of csurf, in node
            ! order)
            do jj = dom%csurf%off(dom%rank + 1) + 1, dom%csurf%off(dom%rank + 1) + dom%csurf%cnt(dom%rank + 1)
                nd = dom%csurf%node(jj)
                if (mark(nd)) cycle
                if (.not. inside(nd, boxes(:, reader + 1))) cycle
                added = added + 1
                ng = ng + 1
                call grow(gid, ng, 'contact ghosts')
                gid(ng) = nd
            end do
            do e = dom%bmo_ptr(k) + 1, dom%bmo_ptr(k + 1)
                mark(dom%bmo_node(e)) = .false.
            end do
        end subroutine side
        logical function inside(nd, bx)
            integer, intent(in) :: nd
            real(dp), intent(in) :: bx(6)
            inside = all(real(x(:, nd), dp) >= bx(1:3)) .and. all(real(x(:, nd), dp) <= bx(4:6))
        end function inside
    end subroutine contact_ghosts

    !> Over the ranks, the largest (1) diagonal and (2) distance between
    !> any two nodes of a contact segment, each rank taking the segments
    !> whose nodes it holds current (cur; absent: every segment). Every
    !> segment is some rank's whole: its element's rank moves its nodes.
    !> block (this rank, the ranks), without cur: where every rank holds
    !> every node's position alike (the loop's start), each rank takes its
    !> block of each surface's segments (every rank had taken every
    !> segment: 0.07e9 instructions a rank on the 10 x 10 tubes).
    function surface_spans(ct, x, cur, block) result(sp)
        type(contacts_t), intent(in) :: ct
        real(wp), intent(in) :: x(:, :)
        logical, intent(in), optional :: cur(:)
        integer, intent(in), optional :: block(2)
        real(dp) :: sp(2)
        integer :: i, g, lo, hi, k, j
        integer :: nd(4)
        sp = 0
        do i = 1, ct%n
            associate (s => ct%ifc(i)%surf)
                lo = 1
                hi = s%nseg
                if (present(block) .and. .not. present(cur)) then
                    lo = int(int(s%nseg, i8)*block(1)/block(2)) + 1
                    hi = int(int(s%nseg, i8)*(block(1) + 1)/block(2))
                end if
                if (present(cur) .and. all(s%seg_on)) then
                    ! (every segment active: those whose nodes are all
                    ! current, each from its first node's segment list, not
                    ! a scan of every segment of the surface at each search
                    ! on every rank)
                    do k = 1, s%nnode
                        if (.not. cur(s%node(k))) cycle
                        do j = s%seg_ptr(k), s%seg_ptr(k + 1) - 1
                            g = s%seg_list(j)
                            if (s%seg(1, g) /= k) cycle
                            nd = s%node(s%seg(:, g))
                            if (.not. all(cur(nd))) cycle
                            call take(nd)
                        end do
                    end do
                else
                    do g = lo, hi
                        nd = s%node(s%seg(:, g))
                        if (present(cur)) then
                            if (.not. all(cur(nd))) cycle
                        end if
                        call take(nd)
                    end do
                end if
            end associate
        end do
        call comm_max(sp)
    contains
        !> The spans of the segment with model nodes nd.
        subroutine take(nd)
            integer, intent(in) :: nd(4)
            integer :: a, b
            sp(1) = max(sp(1), real(norm2(x(:, nd(1)) - x(:, nd(3))), dp), real(norm2(x(:, nd(2)) - x(:, nd(4))), dp))
            do a = 1, 3
                do b = a + 1, 4
                    sp(2) = max(sp(2), real(norm2(x(:, nd(a)) - x(:, nd(b))), dp))
                end do
            end do
        end subroutine take
    end function surface_spans

    !> MPI with contact ghosts, before a global search: the surface nodes'
    !> positions and velocities the search reads, from their ranks. Each
    !> rank's box of each interface (search_box: every master node a search
    !> of its slaves buckets, and every node of a segment at one) goes to
    !> every rank; each rank sends its own surface nodes inside another's
    !> box to it (point-to-point, instead of every surface node to every
    !> rank). cur: per model node, its position is current here after (the
    !> nodes this rank moves, and those received), which the search alone
    !> buckets.
    subroutine search_exchange(dom, ct, x, v, time, cur, sp)
        type(domain_t), intent(inout) :: dom
        type(contacts_t), intent(in) :: ct
        real(wp), intent(inout) :: x(:, :), v(:, :)
        real(dp), intent(in) :: time
        logical, allocatable, intent(inout) :: cur(:)
        !> surface_spans over the nodes held current before the exchange
        !> (their positions do not change in it: the ghosts' choice after
        !> the search takes them)
        real(dp), intent(out) :: sp(2)
        real(dp), allocatable :: bx(:), boxes(:, :), send(:, :), got(:, :)
        real(wp) :: b(6)
        integer, allocatable :: mine(:), last(:), scnt(:)
        integer :: i, k, r, nd, q, n
        if (.not. allocated(cur)) allocate (cur(size(x, 2)))
        cur = ct%moves
        sp = surface_spans(ct, x, cur)
        allocate (bx(6*ct%n), boxes(6*ct%n, dom%nranks))
        do i = 1, ct%n
            bx(6*i - 5:6*i) = real(search_box(ct%ifc(i), x, real(sp(2), wp), time), dp)
        end do
        call comm_gather_small(bx, boxes)
        ! this rank's own surface nodes (a node of several surfaces once a
        ! rank: last)
        allocate (last(size(x, 2)), scnt(dom%nranks))
        last = -1
        n = 0
        do i = 1, ct%n
            do k = 1, ct%ifc(i)%surf%nnode
                if (ct%rank_of(ct%ifc(i)%surf%node(k)) == dom%rank) n = n + 1
            end do
        end do
        allocate (mine(n))
        n = 0
        do i = 1, ct%n
            do k = 1, ct%ifc(i)%surf%nnode
                nd = ct%ifc(i)%surf%node(k)
                if (ct%rank_of(nd) /= dom%rank) cycle
                n = n + 1
                mine(n) = nd
            end do
        end do
        ! counted, then packed: per other rank, its nodes inside any of its boxes
        scnt = 0
        do q = 1, 2
            if (q == 2) allocate (send(7, sum(scnt)))
            n = 0
            last = -1
            do r = 0, dom%nranks - 1
                if (r == dom%rank) cycle
                do k = 1, size(mine)
                    nd = mine(k)
                    if (last(nd) == r) cycle
                    do i = 1, ct%n
                        b = real(boxes(6*i - 5:6*i, r + 1), wp)
                        if (all(x(:, nd) >= b(1:3)) .and. all(x(:, nd) <= b(4:6))) exit
                    end do
                    if (i > ct%n) cycle
                    last(nd) = r
                    if (q == 1) then
                        scnt(r + 1) = scnt(r + 1) + 1
                    else
                        n = n + 1
                        send(:, n) = [real(nd, dp), real(x(:, nd), dp), real(v(:, nd), dp)]
                    end if
                end do
            end do
        end do
        dom%nsearch_ex = dom%nsearch_ex + 1
        dom%search_sent = dom%search_sent + sum(int(scnt, i8))
        call comm_send_records(send, scnt, got)
        do k = 1, size(got, 2)
            nd = nint(got(1, k))
            x(:, nd) = real(got(2:4, k), wp)
            v(:, nd) = real(got(5:7, k), wp)
            cur(nd) = .true.
        end do
        if (dom%check_search) call check_search(dom, ct, x, v, cur, real(sp(2), wp), time)
    end subroutine search_exchange

    !> XDYNA_CHECK_GHOSTS=1: what search_exchange leaves held against every
    !> surface node's position and velocity gathered from its rank (as
    !> before the exchange, csurf): a node held current (cur) must hold its
    !> rank's values, and every master node inside this rank's search box
    !> (at its true position) must be held current (the search buckets
    !> those alone). Counts summed over the ranks into dom%search_check.
    subroutine check_search(dom, ct, x, v, cur, span, time)
        type(domain_t), intent(inout) :: dom
        type(contacts_t), intent(in) :: ct
        real(wp), intent(in) :: x(:, :), v(:, :), span
        logical, intent(in) :: cur(:)
        real(dp), intent(in) :: time
        real(wp), allocatable :: xc(:, :), vc(:, :)
        real(wp) :: b(6)
        integer(i8) :: c(3)
        integer :: i, k, nd
        allocate (xc(size(x, 1), size(x, 2)), vc(size(v, 1), size(v, 2)))
        xc = x
        vc = v
        call gather_subset(dom, dom%csurf, xc, vc)
        c = 0
        do i = 1, ct%n
            associate (s => ct%ifc(i)%surf)
                b = search_box(ct%ifc(i), x, span, time)
                do k = 1, s%nnode
                    nd = s%node(k)
                    c(1) = c(1) + 1
                    if (cur(nd) .and. (any(x(:, nd) /= xc(:, nd)) .or. any(v(:, nd) /= vc(:, nd)))) c(2) = c(2) + 1
                    if (iand(s%node_side(k), ior(side_a, side_b)) == 0 .or. cur(nd)) cycle
                    if (all(xc(:, nd) >= b(1:3)) .and. all(xc(:, nd) <= b(4:6))) c(3) = c(3) + 1
                end do
            end associate
        end do
        call comm_sum_i8(c)
        dom%search_check = dom%search_check + c
    end subroutine check_search

    subroutine gather_layout(arank, nranks, nodes, g)
        integer, intent(in) :: arank(:), nranks, nodes(:)
        type(node_gather_t), intent(out) :: g
        logical, allocatable :: on(:)
        integer, allocatable :: at(:)
        integer :: r, i, nd
        ! (counted, then placed: one pass each, no list grown rank by rank)
        allocate (on(size(arank)), g%cnt(nranks), g%off(nranks), at(nranks))
        on = .false.
        do i = 1, size(nodes)
            on(nodes(i)) = .true.
        end do
        g%cnt = 0
        do nd = 1, size(arank)
            if (on(nd)) g%cnt(arank(nd) + 1) = g%cnt(arank(nd) + 1) + 1
        end do
        g%off(1) = 0
        do r = 2, nranks
            g%off(r) = g%off(r - 1) + g%cnt(r - 1)
        end do
        allocate (g%node(sum(g%cnt)))
        at = g%off
        do nd = 1, size(arank)
            if (.not. on(nd)) cycle
            r = arank(nd) + 1
            at(r) = at(r) + 1
            g%node(at(r)) = nd
        end do
    end subroutine gather_layout

    !> a(:, node) (and b, c, d) of the gather's nodes from their ranks, on
    !> every rank: each rank packs its nodes' values, all ranks gather them
    !> in one collective; with `writer`, on rank 0 alone (an output's: the
    !> other ranks read no node they do not move, and hold no buffer of the
    !> gather's size). (b, c and d may be unallocated arrays, which
    !> Fortran 2008 passes as absent: the angular velocities and moments of
    !> a model without rotations.)
    subroutine gather_subset(dom, g, a, b, c, d, writer)
        type(domain_t), intent(in) :: dom
        type(node_gather_t), intent(in) :: g
        real(wp), intent(inout) :: a(:, :)
        real(wp), intent(inout), optional :: b(:, :), c(:, :), d(:, :)
        logical, intent(in), optional :: writer
        real(wp), allocatable :: mine(:, :), all(:, :)
        integer :: i, r, w, nd, lo, hi, jb, jc, jd
        logical :: to_root
        if (size(g%node) == 0) return
        ! (each present array's first row in a node's record; 0: absent)
        w = 3
        jb = 0
        jc = 0
        jd = 0
        if (present(b)) then
            jb = w + 1
            w = w + 3
        end if
        if (present(c)) then
            jc = w + 1
            w = w + 3
        end if
        if (present(d)) then
            jd = w + 1
            w = w + 3
        end if
        to_root = .false.
        if (present(writer)) to_root = writer
        r = dom%rank + 1
        lo = g%off(r) + 1
        hi = g%off(r) + g%cnt(r)
        if (to_root .and. dom%rank /= 0) then
            allocate (mine(w, max(g%cnt(r), 1)), all(w, 1))
        else
            allocate (mine(w, max(g%cnt(r), 1)), all(w, size(g%node)))
        end if
        !$omp parallel do schedule(static) private(nd) if (threaded(g%cnt(r)))
        do i = 1, g%cnt(r)
            nd = g%node(g%off(r) + i)
            mine(1:3, i) = a(:, nd)
            if (jb > 0) mine(jb:jb + 2, i) = b(:, nd)
            if (jc > 0) mine(jc:jc + 2, i) = c(:, nd)
            if (jd > 0) mine(jd:jd + 2, i) = d(:, nd)
        end do
        !$omp end parallel do
        if (to_root) then
            call comm_gather_root_wp(mine, w*g%cnt(r), all, w*g%cnt, w*g%off, dom%rank == 0)
            if (dom%rank /= 0) return
        else
            call comm_gather_wp(mine, w*g%cnt(r), all, w*g%cnt, w*g%off)
        end if
        ! (the other ranks' nodes: this rank's are in place)
        !$omp parallel do schedule(static) private(nd) if (threaded(size(g%node)))
        do i = 1, size(g%node)
            if (i >= lo .and. i <= hi) cycle
            nd = g%node(i)
            a(:, nd) = all(1:3, i)
            if (jb > 0) b(:, nd) = all(jb:jb + 2, i)
            if (jc > 0) c(:, nd) = all(jc:jc + 2, i)
            if (jd > 0) d(:, nd) = all(jd:jd + 2, i)
        end do
        !$omp end parallel do
    end subroutine gather_subset


    !> The element energies (and shell thicknesses) from their ranks, for
    !> glstat and matsum.
    subroutine gather_energy_state(dom, solids, sh)
        type(domain_t), intent(in) :: dom
        type(solids_t), intent(inout) :: solids
        type(shells_t), intent(inout) :: sh
        if (.not. dom%on) return
        call merge_dp(solids%eint, 1, dom%solid_mine)
        call merge_dp(solids%ehg, 1, dom%solid_mine)
        call merge_dp(solids%pend_int, 1, dom%solid_mine)
        call merge_dp(solids%pend_hg, 1, dom%solid_mine)
        ! (held by row: the ranks' own rows, gathered whole for an output
        ! by shell_state_view)
        if (sh%n == 0 .or. sh%by_row) return
        call merge_dp(sh%eint, 1, dom%shell_mine)
        call merge_dp(sh%ehg, 1, dom%shell_mine)
        call merge_dp(sh%pend_int, 1, dom%shell_mine)
        call merge_dp(sh%pend_hg, 1, dom%shell_mine)
        call merge_wp(sh%h, 1, dom%shell_mine)
    end subroutine gather_energy_state

    !> All element state from the elements' ranks: for d3plot and the dump.
    !> `energies`: also the energies (not when this cycle gathered them).
    !> `dump` false: what a state reads alone (not the shells' hourglass
    !> forces, strains and back stresses, which only a dump holds).
    subroutine gather_element_state(dom, solids, sh, energies, dump, shells)
        type(domain_t), intent(in) :: dom
        type(solids_t), intent(inout) :: solids
        type(shells_t), intent(inout) :: sh
        logical, intent(in) :: energies
        logical, intent(in), optional :: dump
        !> false: not the shells' view (a state whose shells' words the
        !> ranks make, xd_solver_state_writer)
        logical, intent(in), optional :: shells
        logical :: every, with_shells
        if (.not. dom%on) return
        every = .true.
        if (present(dump)) every = dump
        with_shells = .true.
        if (present(shells)) with_shells = shells
        if (energies) call gather_energy_state(dom, solids, sh)
        ! (the elements' state is each rank's own in the time loop, where
        ! the outputs take this: localize_element_state, place_shell_state)
        if (solids%n > 0) call solid_state_view(dom, solids, every)
        if (sh%n > 0 .and. with_shells) call shell_state_view(dom, sh, every)
    end subroutine gather_element_state

    !> The shells' points' state and slots allocated (issue 32): on one
    !> rank every shell's; on more, the rank's own shells' rows and then
    !> the halo's slots received from the other ranks, the assembly's and
    !> the halo's slot lists mapped to those places (local_slots). Once the
    !> split is made and before a restart's dump is read into the rows.
    subroutine place_shell_state(dom, sh, asm_sh)
        type(domain_t), intent(inout) :: dom
        type(shells_t), intent(inout) :: sh
        type(assembly_t), intent(inout) :: asm_sh
        integer, allocatable :: every(:)
        integer :: e
        if (sh%n == 0) return
        if (.not. dom%on) then
            allocate (every(sh%n))
            do e = 1, sh%n
                every(e) = e
            end do
            call shell_state_init(sh, every, 0)
            return
        end if
        ! (the lists of the nodes this rank assembles alone, before the
        ! rows are allocated and their slots take their places here)
        call keep_assembled(asm_sh, dom%node_mine)
        call shell_state_init(sh, where_true(dom%shell_mine), size(dom%hi_slot))
        call local_slots(sh%lix, 4, 4*sh%nl, dom%ho_slot, dom%hi_slot, asm_sh)
    end subroutine place_shell_state

    !> The solids' state and slots held for the rank's own groups alone
    !> (more than one rank; once the set-up, a restart's dump included, has
    !> put every solid's initial state in place): the rest of the arrays'
    !> memory goes (issue 32).
    subroutine localize_element_state(dom, solids, asm)
        type(domain_t), intent(inout) :: dom
        type(solids_t), intent(inout) :: solids
        !> (its slot lists: to the slots held here, local_slots)
        type(assembly_t), intent(inout) :: asm
        integer, allocatable :: row(:)
        integer :: e
        if (.not. dom%on .or. solids%n == 0) return
        call solid_localize(solids)
        ! (each solid's row here, 0 for another rank's)
        allocate (row(solids%n))
        do e = 1, solids%n
            row(e) = 0
            if (solids%goff(solids%group_of(e)) >= 0) row(e) = solids%row(e)
        end do
        call keep_assembled(asm, dom%node_mine)
        call local_slots(row, 8, 8*solids%nl, dom%so_slot, dom%si_slot, asm)
        deallocate (solids%fslot)
        call alloc(solids%fslot, 3, 8*solids%nl + size(dom%si_slot), 'solid force slots')
    end subroutine localize_element_state

    !> The force slots held here (issue 32): the rank's own elements' (w
    !> slots an element: element e's slot k at w (row(e) - 1) + k, row 0
    !> for another rank's element), nown of them, then the halo's received
    !> (`inn`, each once) in their list's order. The lists of the slots
    !> sent (`out`) and received and the assembly's node lists (the nodes
    !> this rank assembles alone: keep_assembled) take those places; a node
    !> this rank assembles has only such slots, still in the serial order,
    !> so its sum is the same, bit for bit. (By the rows and a map of the
    !> halo's slots: a table of every slot's place had been 4 bytes a slot
    !> of the model, the set-up's peak on 16 ranks of the plate.)
    subroutine local_slots(row, w, nown, out, inn, as)
        integer, intent(in) :: row(:), w, nown
        integer, intent(inout) :: out(:), inn(:)
        type(assembly_t), intent(inout) :: as
        type(id_map_t) :: halo
        integer :: i, dup
        ! (a received slot's place among the received: i for inn(i))
        call halo%build(inn, dup)
        ! (loops: no temporary of the lists' size on the stack)
        do i = 1, size(out)
            out(i) = place(out(i))
        end do
        do i = 1, size(as%slot)
            as%slot(i) = place(as%slot(i))
        end do
        do i = 1, size(inn)
            inn(i) = nown + i
        end do
    contains
        !> model slot j's place here (0: neither this rank's nor received)
        integer function place(j) result(q)
            integer, intent(in) :: j
            integer :: e, k
            e = (j - 1)/w + 1
            if (row(e) > 0) then
                q = w*(row(e) - 1) + j - w*(e - 1)
            else
                k = halo%find(j)
                q = merge(nown + k, 0, k > 0)
            end if
        end function place
    end subroutine local_slots

    !> Every solid's state on rank 0, for a state or a dump that rank 0
    !> writes: each rank sends its groups' blocks (in group order), rank 0
    !> puts them at their groups' places and keeps its own aside until
    !> release_element_view. Exact (copies); every rank calls it. `every`
    !> false (a state): the stresses and plastic strains alone (a state
    !> reads no more; the volumes, hourglass forces, bulk viscosity and back
    !> stresses are a dump's).
    subroutine solid_state_view(dom, s, every)
        type(domain_t), intent(in) :: dom
        type(solids_t), intent(inout) :: s
        logical, intent(in) :: every
        integer, allocatable :: cnt(:)
        integer :: r, g
        logical :: root
        real(wp) :: none(1)
        if (s%viewing) return
        root = dom%rank == 0
        allocate (cnt(dom%nranks))
        cnt = 0
        do g = 1, s%ngroup
            r = dom%group_rank(g) + 1
            cnt(r) = cnt(r) + s%group(g)%last - s%group(g)%first + 1
        end do
        if (root) then
            call move_alloc(s%sig, s%own_sig)
            call move_alloc(s%epsp, s%own_epsp)
            ! (every group's rows at their places: the groups' own order)
            call move_alloc(s%goff, s%own_goff)
            s%goff = s%group(:)%first - 1
            allocate (s%sig(6*s%n), s%epsp(merge(s%n, 0, s%plastic_state)))
            call blocks(s%own_sig, 6, s%sig)
            if (s%plastic_state) call blocks(s%own_epsp, 1, s%epsp)
            if (every) then
                call move_alloc(s%vol, s%own_vol)
                call move_alloc(s%qhg, s%own_qhg)
                call move_alloc(s%qbv, s%own_qbv)
                call move_alloc(s%alpha, s%own_alpha)
                allocate (s%vol(s%n), s%qhg(12*s%n), s%qbv(s%n), s%alpha(merge(6*s%n, 0, s%plastic_state)))
                call blocks(s%own_vol, 1, s%vol)
                call blocks(s%own_qhg, 12, s%qhg)
                call blocks(s%own_qbv, 1, s%qbv)
                if (s%plastic_state) call blocks(s%own_alpha, 6, s%alpha)
            end if
            s%viewing = .true.
        else
            call blocks(s%sig, 6, none)
            if (s%plastic_state) call blocks(s%epsp, 1, none)
            if (every) then
                call blocks(s%vol, 1, none)
                call blocks(s%qhg, 12, none)
                call blocks(s%qbv, 1, none)
                if (s%plastic_state) call blocks(s%alpha, 6, none)
            end if
        end if
    contains
        !> loc: this rank's groups' blocks of w values an element (a
        !> group's block its m elements' m w values), to rank 0's full
        !> (every group's at its place). A w-th of each block at a time (its
        !> values m (c - 1) + 1 .. m c): rank 0's buffer holds a w-th of
        !> the model's values, not all of them beside the view.
        subroutine blocks(loc, w, full)
            real(wp), intent(in) :: loc(*)
            integer, intent(in) :: w
            real(wp), intent(inout) :: full(*)
            real(wp), allocatable :: buf(:), col(:)
            integer, allocatable :: disp(:), pos(:)
            integer :: r, g, f, m, c, off, k
            allocate (col(max(s%nl, 1)))
            do c = 1, w
                ! this rank's groups, in order: their blocks' c-th part
                off = 0
                k = 0
                do g = 1, s%ngroup
                    if (dom%group_rank(g) /= dom%rank) cycle
                    m = s%group(g)%last - s%group(g)%first + 1
                    col(k + 1:k + m) = loc(off + m*(c - 1) + 1:off + m*c)
                    off = off + w*m
                    k = k + m
                end do
                call gather_to_root(dom, col, s%nl, cnt, buf, disp)
                if (.not. root) cycle
                pos = disp
                do g = 1, s%ngroup
                    r = dom%group_rank(g) + 1
                    f = s%group(g)%first
                    m = s%group(g)%last - f + 1
                    full(w*(f - 1) + m*(c - 1) + 1:w*(f - 1) + m*c) = buf(pos(r) + 1:pos(r) + m)
                    pos(r) = pos(r) + m
                end do
            end do
        end subroutine blocks
    end subroutine solid_state_view

    !> Every shell's points' state on rank 0, for a state or a dump that
    !> rank 0 writes: each rank sends its rows (in its shells' order), rank
    !> 0 puts them at their shells' places in arrays of every shell and
    !> keeps its own aside until release_element_view. Exact (copies); every
    !> rank calls it.
    subroutine shell_state_view(dom, sh, every)
        type(domain_t), intent(in) :: dom
        type(shells_t), intent(inout) :: sh
        !> a dump's: also the hourglass forces, strains and back stresses
        !> (a state reads none of them)
        logical, intent(in) :: every
        integer, allocatable :: cnt(:), order(:), at(:)
        integer :: r, nip, i
        logical :: root
        real(wp) :: none(1)
        real(dp) :: nonedp(1)
        logical :: back
        if (sh%viewing) return
        root = dom%rank == 0
        ! (what every rank holds, whatever its own count: each gather below
        ! is made by all or none)
        back = some_backstress(sh)
        ! every rank's shells, rank after rank, each's ascending
        ! (loops: no temporary of the model's size on the stack)
        allocate (cnt(dom%nranks), order(sh%n), at(dom%nranks))
        cnt = 0
        do i = 1, sh%n
            cnt(dom%shell_rank(i) + 1) = cnt(dom%shell_rank(i) + 1) + 1
        end do
        at(1) = 0
        do r = 2, dom%nranks
            at(r) = at(r - 1) + cnt(r - 1)
        end do
        do i = 1, sh%n
            r = dom%shell_rank(i) + 1
            at(r) = at(r) + 1
            order(at(r)) = i
        end do
        nip = size(sh%sig, 3)
        if (root) then
            call move_alloc(sh%sig, sh%own_sig)
            call move_alloc(sh%epsp, sh%own_epsp)
            allocate (sh%sig(sh%n, 5, nip), sh%epsp(sh%n, nip))
            call rows(sh%own_sig, 5*nip, sh%sig, .false.)
            call rows(sh%own_epsp, nip, sh%epsp, .false.)
            if (every) then
                call move_alloc(sh%qhg, sh%own_qhg)
                call move_alloc(sh%strain, sh%own_strain)
                call move_alloc(sh%alpha, sh%own_alpha)
                allocate (sh%qhg(sh%n, 5))
                allocate (sh%strain(merge(sh%n, 0, sh%track_strain), 6, nip))
                allocate (sh%alpha(6, nip, merge(sh%n, 0, back)))
                call rows(sh%own_qhg, 5, sh%qhg, .false.)
                if (sh%track_strain) call rows(sh%own_strain, 6*nip, sh%strain, .false.)
                if (back) call rows(sh%own_alpha, 6*nip, sh%alpha, .true.)
            end if
            if (sh%by_row) then
                ! the per-shell arrays held by row (shell_rows), every
                ! shell's in the model's order
                call move_alloc(sh%h, sh%own_h)
                call move_alloc(sh%area0, sh%own_area0)
                call move_alloc(sh%eint, sh%own_eint)
                call move_alloc(sh%ehg, sh%own_ehg)
                call move_alloc(sh%pend_int, sh%own_pend_int)
                call move_alloc(sh%pend_hg, sh%own_pend_hg)
                allocate (sh%h(sh%n), sh%area0(sh%n), sh%eint(sh%n), sh%ehg(sh%n), sh%pend_int(sh%n), sh%pend_hg(sh%n))
                call rows(sh%own_h, 1, sh%h, .false.)
                call rows(sh%own_area0, 1, sh%area0, .false.)
                call rows_dp(sh%own_eint, sh%eint)
                call rows_dp(sh%own_ehg, sh%ehg)
                call rows_dp(sh%own_pend_int, sh%pend_int)
                call rows_dp(sh%own_pend_hg, sh%pend_hg)
                sh%by_row = .false.
            end if
            sh%viewing = .true.
        else
            ! (only rank 0 receives)
            call rows(sh%sig, 5*nip, none, .false.)
            call rows(sh%epsp, nip, none, .false.)
            if (every) then
                call rows(sh%qhg, 5, none, .false.)
                if (sh%track_strain) call rows(sh%strain, 6*nip, none, .false.)
                if (back) call rows(sh%alpha, 6*nip, none, .true.)
            end if
            if (sh%by_row) then
                call rows(sh%h, 1, none, .false.)
                call rows(sh%area0, 1, none, .false.)
                call rows_dp(sh%eint, nonedp)
                call rows_dp(sh%ehg, nonedp)
                call rows_dp(sh%pend_int, nonedp)
                call rows_dp(sh%pend_hg, nonedp)
            end if
        end if
    contains
        !> rows for one value a shell in double precision (the energies)
        subroutine rows_dp(loc, full)
            real(dp), intent(in) :: loc(*)
            real(dp), intent(inout) :: full(*)
            real(dp), allocatable :: buf(:)
            integer :: disp(dom%nranks)
            integer :: r, i, o
            disp = root_displacements(cnt)
            allocate (buf(merge(sum(cnt), 1, root)))
            call comm_gather_root_dp(loc, sh%nl, buf, cnt, disp, root)
            if (.not. root) return
            o = 0
            do r = 1, dom%nranks
                do i = 1, cnt(r)
                    full(order(o + i)) = buf(disp(r) + i)
                end do
                o = o + cnt(r)
            end do
        end subroutine rows_dp

        !> loc: this rank's nl rows of ncol values (a column of nl after
        !> another; last: an element's ncol values together), to rank 0's
        !> full (every shell's, likewise). A column at a time: rank 0's
        !> buffer holds one value of every shell, not all of them beside the
        !> whole view (the sig view of a 250,000-shell plate at NIP 5 had
        !> taken 50 MB twice over on rank 0 of 16).
        subroutine rows(loc, ncol, full, last)
            real(wp), intent(in) :: loc(*)
            integer, intent(in) :: ncol
            real(wp), intent(inout) :: full(*)
            logical, intent(in) :: last
            real(wp), allocatable :: buf(:), col(:)
            integer, allocatable :: disp(:)
            integer :: r, c, i, o, nr
            allocate (col(max(sh%nl, 1)))
            do c = 1, ncol
                if (last) then
                    do i = 1, sh%nl
                        col(i) = loc((i - 1)*ncol + c)
                    end do
                else
                    do i = 1, sh%nl
                        col(i) = loc((c - 1)*sh%nl + i)
                    end do
                end if
                call gather_to_root(dom, col, sh%nl, cnt, buf, disp)
                if (.not. root) cycle
                o = 0
                do r = 1, dom%nranks
                    nr = cnt(r)
                    if (last) then
                        do i = 1, nr
                            full((order(o + i) - 1)*ncol + c) = buf(disp(r) + i)
                        end do
                    else
                        do i = 1, nr
                            full(order(o + i) + (c - 1)*sh%n) = buf(disp(r) + i)
                        end do
                    end if
                    o = o + nr
                end do
            end do
        end subroutine rows
    end subroutine shell_state_view

    !> Every rank's n values loc (rank r - 1 gives cnt(r)) to rank 0's buf,
    !> rank after rank, rank r - 1's from disp(r) on; buf of size 1 on the
    !> other ranks. (The element views' one gather.)
    subroutine gather_to_root(dom, loc, n, cnt, buf, disp)
        type(domain_t), intent(in) :: dom
        real(wp), intent(in) :: loc(*)
        integer, intent(in) :: n, cnt(:)
        real(wp), allocatable, intent(out) :: buf(:)
        integer, allocatable, intent(out) :: disp(:)
        allocate (disp(size(cnt)))
        disp = root_displacements(cnt)
        allocate (buf(merge(sum(cnt), 1, dom%rank == 0)))
        call comm_gather_root_wp(loc, n, buf, cnt, disp, dom%rank == 0)
    end subroutine gather_to_root

    !> Where each rank's values start in a gather to rank 0 (0-based),
    !> ranks in order, rank r - 1 giving cnt(r).
    pure function root_displacements(cnt) result(disp)
        integer, intent(in) :: cnt(:)
        integer :: disp(size(cnt))
        integer :: r
        disp(1) = 0
        do r = 2, size(cnt)
            disp(r) = disp(r - 1) + cnt(r - 1)
        end do
    end function root_displacements

    !> After the output that took it: rank 0's own rows of the solids' state
    !> and the shells' points' state back in place of the views
    !> (solid_state_view, shell_state_view).
    subroutine release_element_view(solids, sh)
        type(solids_t), intent(inout) :: solids
        type(shells_t), intent(inout) :: sh
        if (solids%viewing) then
            call move_alloc(solids%own_sig, solids%sig)
            call move_alloc(solids%own_epsp, solids%epsp)
            call move_alloc(solids%own_goff, solids%goff)
            ! (a dump's view alone took these: solid_state_view's every)
            if (allocated(solids%own_vol)) call move_alloc(solids%own_vol, solids%vol)
            if (allocated(solids%own_qhg)) call move_alloc(solids%own_qhg, solids%qhg)
            if (allocated(solids%own_qbv)) call move_alloc(solids%own_qbv, solids%qbv)
            if (allocated(solids%own_alpha)) call move_alloc(solids%own_alpha, solids%alpha)
            solids%viewing = .false.
            call release_free_memory()
        end if
        if (.not. sh%viewing) return
        call move_alloc(sh%own_sig, sh%sig)
        call move_alloc(sh%own_epsp, sh%epsp)
        ! (a dump's view alone took these: shell_state_view's every)
        if (allocated(sh%own_qhg)) call move_alloc(sh%own_qhg, sh%qhg)
        if (allocated(sh%own_strain)) call move_alloc(sh%own_strain, sh%strain)
        if (allocated(sh%own_alpha)) call move_alloc(sh%own_alpha, sh%alpha)
        if (allocated(sh%own_eint)) then
            ! (the per-shell arrays' own rows: shell_rows)
            call move_alloc(sh%own_h, sh%h)
            call move_alloc(sh%own_area0, sh%area0)
            call move_alloc(sh%own_eint, sh%eint)
            call move_alloc(sh%own_ehg, sh%ehg)
            call move_alloc(sh%own_pend_int, sh%pend_int)
            call move_alloc(sh%own_pend_hg, sh%pend_hg)
            sh%by_row = .true.
        end if
        sh%viewing = .false.
        ! (rank 0, after the output: the view's memory handed back to the
        ! system, not kept in the heap until the next output)
        call release_free_memory()
    end subroutine release_element_view

    !> a holds `stride` values per element: element e's are entries
    !> stride (e-1) + 1 .. stride e (the solids' group blocks hold the same
    !> entries, since a group is one rank's whole). Other ranks' elements are
    !> zeroed, then the ranks' arrays summed.
    subroutine merge_wp(a, stride, mine)
        real(wp), intent(inout) :: a(*)
        integer, intent(in) :: stride
        logical, intent(in) :: mine(:)
        integer :: e
        do e = 1, size(mine)
            if (.not. mine(e)) a(stride*(e - 1) + 1:stride*e) = 0
        end do
        call comm_sum_wp(a, stride*size(mine))
    end subroutine merge_wp


#ifdef XD_SINGLE
    subroutine merge_dp(a, stride, mine)
        real(dp), intent(inout) :: a(*)
        integer, intent(in) :: stride
        logical, intent(in) :: mine(:)
        integer :: e
        do e = 1, size(mine)
            if (.not. mine(e)) a(stride*(e - 1) + 1:stride*e) = 0
        end do
        call comm_sum_dp(a(1:stride*size(mine)))
    end subroutine merge_dp
#else
    subroutine merge_dp(a, stride, mine)
        real(dp), intent(inout) :: a(*)
        integer, intent(in) :: stride
        logical, intent(in) :: mine(:)
        call merge_wp(a, stride, mine)
    end subroutine merge_dp
#endif

end module xd_solver_domain
