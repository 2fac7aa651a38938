!> The contact interfaces of a run: their surfaces (step 1), when each one
!> searches (step 2), and the diagnostics the log reports. Steps 3 and 4
!> (local search and enforcement) work from the master node lists kept here.
!>
!> Search interval. Each surface node i keeps U_i, a bound on how far it
!> has moved since t = 0 relative to a motion common to the whole surface
!> (the sum over cycles of dt x its speed relative to the surface's mean
!> velocity: the pools rest on relative positions alone). The slaves fall
!> in classes by their own pool margin (margin_classes: bands a factor of
!> two wide), Delta_c the least margin of class c, t_c its last search.
!> Class c is searched again at the start of any cycle where, at some
!> node i, 4 (U_i - U_i(t_c)) > max(Delta_c, delta_min,i), delta_min,i the
!> least margin of i and the nodes sharing a segment with it. Fixed
!> interval: every class at most N cycles apart (BSORT, else NSRCH of
!> *CONTROL_XDYNA_CONTACT, else NSBCS, else 100), and sooner as above.
!>
!> The bound this guarantees: at every cycle, every slave node s of class
!> c that lies within contact reach t_c of a segment at master node m had
!> m in its reduced pool at its last search, when the pool's radius was
!> L_m + t_c + max(delta_s, delta_m) (xd_contact_global_search). Since t_c
!> s moved at most max(Delta_c, delta_min,s) / 4 <= delta_s / 4, m at most
!> max(Delta_c, delta_min,m) / 4 <= max(delta_s, delta_m) / 4, and a point
!> of a segment at m moved relative to m at most twice that of its nodes,
!> each sharing a segment with m, so at most max(delta_s, delta_m) / 4:
!> in all at most max(delta_s, delta_m). A fine region's slaves are thus
!> searched at the pace their own small margins ask, and the rest at
!> theirs: a fine minority costs its own size. The interface also keeps
!> its odometer, the sum of dt x the largest speed of any of its nodes,
!> which bounds any node's displacement over any time: the local search's
!> clearances use it.
module xd_contact_contact
    use xd_kinds, only: wp, dp, i8
    use, intrinsic :: iso_fortran_env, only: int8
    use xd_core_errors, only: error_t, make_error
    use xd_core_strings, only: itoa
    use xd_core_threads, only: threaded
    use xd_core_memory, only: grow, nbytes, take, untake
    use xd_model, only: model_t, contact_t, find_set, set_node, ct_single, ct_general, ct_surface_to_surface, mat_rigid, &
                        can_erode, ct_nodes_to_surface, styp_segment_set, styp_shell_set, styp_part_set, styp_part, &
                        styp_node_set, styp_all, styp_all_but, search_auto, search_adaptive, find_box, in_box, box_t
    use xd_contact_surface, only: faces_t, surface_t, build_faces, build_surface, face_key, seg_thicknesses, seg_nodes, seg_shell, &
                                  release_faces, release_activation, &
                                  surface_activate, &
                                  follow_thickness, faces_bytes, surface_bytes
    use xd_core_vectors, only: cross
    use xd_contact_global_search, only: master_lists_t, build_master_lists, characteristic_lengths, search_counts_t, &
                                        lists_rows, list_row, list_rows, &
                                        typical_length, pool_margins, margin_floor, margin_classes, lists_bytes, &
                                        pool_reach
    use xd_contact_segment_check, only: hit_t, pair_hit_t, kept, contact_interior, segment_check
    use xd_contact_local_search, only: local_search_t, find_contact, search_switches_t, clearance_t, &
                                       reset_clearance, fresh_clearance
    use xd_contact_enforcement, only: friction_t, penalty_force, lagrange_projection, slave_stiffness, pdir, &
                                      body_response_t
    use xd_contact_edge_contact, only: edges_t, build_edges, edge_search, edge_forces, edge_unknown, edge_initial
    !$ use omp_lib, only: omp_get_wtime
    use xd_core_sorting, only: where_true, sort_index
    use xd_core_comm, only: comm_gather_records, comm_send_records, comm_sum_wp, comm_sum_int, comm_sum_i8, comm_sum_dp, &
                            comm_max
    implicit none
    private
    public :: contact_bytes, search_box
    public :: contacts_t, interface_t, build_contacts, faces_of, contact_erode, contact_search, contact_drift, gather_drift, &
              search_due, &
              contact_report, &
              contact_erode_solids, &
              interface_summary, contact_masses, contact_local_search, contact_enforce, contact_work_end, &
              contact_energy, contact_resultants, gather_contact_state, scatter_contact_state, contact_events, &
              contact_thickness, contact_release_setup, contact_slave_rows

    type :: interface_t
        integer :: id = 0
        character(len=48) :: keyword = ''
        type(surface_t) :: surf
        type(master_lists_t) :: lists
        type(edges_t) :: ed                   !< exterior shell edges and their pairs (AUTOMATIC_GENERAL)
        real(wp), allocatable :: xl(:, :)     !< surface coordinates at the last search
        real(wp) :: margin = 0                !< typical pool margin (pmarg x the median L at t = 0)
        real(wp), allocatable :: dl(:)        !< pool margin delta_i of each surface node (its local size)
        real(wp), allocatable :: dmin(:)      !< delta_min,i (xd_contact_global_search's pool_margins)
        real(wp), allocatable :: un(:)        !< U_i: each surface node's relative motion bound since t = 0
        !> owned nodes: the surface's nodes this rank integrates (their
        !> places in surf%node), whose motion bounds it keeps (contact_drift;
        !> made at its first call: the ranks' nodes do not change)
        integer, allocatable :: drift_own(:)
        integer, allocatable :: cls(:)        !< per slave: its class by margin (margin_classes)
        real(wp), allocatable :: cmin(:)      !< per class: the least margin Delta_c of its slaves
        real(wp), allocatable :: uc(:, :)     !< (nnode, class): U_i at the class's last search
        real(wp), allocatable :: cbud(:, :)   !< (nnode, class): 4 / max(Delta_c, delta_min,i)
        real(wp), allocatable :: cused(:)     !< per class: max over the nodes of 4 (U_i - U_i,c) / max(Delta_c, delta_min,i)
        real(wp) :: odo = 0                   !< the sum over cycles of dt x the largest speed since t = 0
        integer :: nraised = 0                !< nodes whose margin was raised to the floor
        integer :: npartial = 0               !< searches of some classes only
        integer(i8) :: nsearched = 0          !< slaves searched, summed over the searches
        !> slave-cycles whose near set alone was checked (clearance_t), and
        !> of them those searched in full after (the near set found or
        !> refused a contact)
        integer(i8) :: nnear = 0, nnear_full = 0
        real(wp) :: reach = 0                 !< contact reach t_c (largest shell thickness)
        integer :: interval = 10
        logical :: adaptive = .false.
        real(wp) :: bt = 0, dt = 1.0e20_wp
        real(wp) :: worst = 0                 !< largest part of a margin used on a cycle with old lists
        integer :: last_cycle = -huge(1)
        integer :: nsearch = 0
        type(search_counts_t) :: total        !< summed over searches
        real(dp) :: wall = 0                  !< seconds in the global search
        integer, allocatable :: dump(:)       !< slave positions whose lists are dumped
        ! steps 3-4
        type(local_search_t) :: ls
        type(clearance_t) :: cl               !< per slave: clearance bounds (what the local search may skip)
        type(friction_t) :: fr
        real(wp), allocatable :: ms(:)        !< nodal masses of the surface nodes
        integer, allocatable :: cseg(:)       !< per slave: segment in contact last cycle (0: none)
        real(wp), allocatable :: fprev(:, :)  !< per slave: contact force last cycle (comparison vector)
        real(wp), allocatable :: ft(:, :)     !< per slave: friction force carried over
        real(wp), allocatable :: p0(:)        !< per slave: initial penetration still allowed
        real(wp), allocatable :: kp(:)        !< per slave: the penalty stiffness of its current contact
        real(wp), allocatable :: fk(:, :)     !< per slave (row hrow): this cycle's contact force on it
        real(wp), allocatable :: aeff(:)      !< per slave: its penetration last cycle, less the allowance p0
        logical :: started = .false.          !< the first active cycle has been seen
        integer :: ninit = 0                  !< initial penetrations found (allowed as IGNORE = 1)
        integer :: nlate = 0                  !< contacts deeper than one step's approach (excess allowed)
        real(wp) :: plate = 0                 !< the deepest of them
        integer :: nback = 0                  !< of those, back under the segment the node held last
        real(wp) :: pback = 0                 !< the deepest of them
        integer :: nwithin = 0                !< deep in a shell's zone the node lay in at the search: held there
        real(wp) :: pwithin = 0               !< the deepest of them
        integer :: nhand = 0                  !< moved to a segment deeper than the old one's spring there: excess allowed
        real(wp) :: phand = 0                 !< the largest excess
        real(wp) :: pinit = 0                 !< the deepest initial penetration
        integer :: nrel = 0                   !< contacts lost while deeper than one step can undo
        real(wp) :: prel = 0                  !< the deepest of them
        integer :: nref = 0                   !< deep contacts refused: zones the slave never entered
        real(wp) :: pref = 0                  !< the deepest of them
        !> per slave: the segment it held last (kept after the contact ends;
        !> 0: none yet): a slave back under it, deep, is in contact again
        integer, allocatable :: held(:)
        !> per slave: its row in the arrays of the slaves' contact state that
        !> only the slave's rank reads (cseg, held, fprev, ft, p0, kp, aeff,
        !> rdep, deep, rlast: with own_work on more than one rank, the rank's
        !> own slaves' rows alone; 0 for another rank's slave); k itself
        !> where they hold every slave (contact_slave_rows)
        integer, allocatable :: orow(:)
        logical :: own_rows = .false.
        integer, allocatable :: rseg(:)       !< per slave: this cycle's deepest refused segment (0: none)
        real(wp), allocatable :: rdep(:)      !< per slave: its depth
        real(wp), allocatable :: deep(:)      !< per slave: the depth of a contact dropped beyond PENMAX (0: none)
        integer, allocatable :: rlast(:)      !< per slave: the refused segment already named (0: none)
        integer, allocatable :: evk(:)        !< per slave: this cycle's event (ev_none, ev_initial, ...)
        real(wp), allocatable :: evd(:)       !< per slave: the depth of that event
        integer :: nev = 0                    !< events not yet written to the log
        type(contact_event_t), allocatable :: ev(:)
        integer :: npair = 0                  !< slaves in contact this cycle
        !> their contacts, in rows: hrow(k) is slave k's (hit and fk)
        type(pair_hit_t), allocatable :: hit(:)
        !> per slave: its row in hit and fk. Every slave's own (k) where the
        !> slaves' state is held whole; with the rank's own slaves' rows
        !> (own_rows) their rows (orow), and after them rows for the other
        !> ranks' slaves whose contacts the last exchange brought (0: none)
        integer, allocatable :: hrow(:)
        !> per slave: hit(k)%found, kept alongside in a compact array (the
        !> loops over every slave each cycle read this, not the records)
        logical, allocatable :: found(:)
        integer, allocatable :: pair(:)       !< their slave positions
        real(wp), allocatable :: fpair(:, :)  !< forces on those slaves
        real(dp) :: pminus = 0                !< power of this cycle's forces with v(n-1/2)
        real(dp) :: energy = 0                !< sliding interface energy (minus the contact forces' work)
        real(dp) :: fslave(3) = 0, fmaster(3) = 0, mslave = 0, mmaster = 0   !< rcforc: resultants, masses in contact
        real(dp) :: wall_local = 0, wall_enforce = 0
        ! where the contact acts, by part pair (the log's table at the end):
        ! the interface's parts (deck ids; a slave node on no segment of the
        ! surface counts under 0), each segment's and each slave's local part
        integer, allocatable :: part_id(:)
        integer, allocatable :: seg_lp(:), slave_lp(:)
        !> (slave part, master part, 1 without / 2 with an allowance): the
        !> normal impulse |f| dt and the work f . v_rel dt of the forces on
        !> the slaves (negative: the contact resisted the approach)
        real(dp), allocatable :: pair_imp(:, :, :), pair_work(:, :, :)
        integer(i8) :: ncontact_total = 0     !< slave-cycles in contact
        !> cycles whose pairs list_pairs listed from the rank's own and the
        !> received slaves alone (pair_candidates), not every slave
        integer(i8) :: ncand = 0
        logical :: active = .false.           !< between birth and death this cycle
        logical, allocatable :: owned(:)      !< per slave: searched and enforced here (MPI: this rank's)
        !> MPI: the other ranks' slaves the last gathering set (the next
        !> one sets them back to no contact first; unallocated before the
        !> first, which clears every other rank's slave)
        integer, allocatable :: got(:)
        integer, allocatable :: mine(:)       !< those slaves' positions (owned and live)
        !> per slave: on the surface now (a node inside a part that can
        !> erode is not, until erosion exposes it; one whose elements are all
        !> gone stays, as debris); every slave without such parts
        logical, allocatable :: live(:)
        logical :: listed = .false.           !< the slaves are a node set's (always live)
        !> per slave: erosion changed the surface within its reach, or the
        !> slave is inside a part (asked at set-up): searched the next cycle
        !> it is live
        logical, allocatable :: resl(:)
        !> some slave's resl may be set (a deck whose surfaces erosion
        !> changes): else the cycles do not look for one (a scan of every
        !> slave, twice a cycle on every rank)
        logical :: resl_on = .false.
        !> MPI with contact ghosts: the surface's nodes this rank moves (its
        !> own, its halo, the ghosts it receives), by their place in
        !> surf%node (the domain's contact_ghosts lists them at each choice
        !> of the ghosts). Between two searches no other surface node's position
        !> or velocity changes on this rank, so the local search gathers
        !> only these; every node where regather is set (a search's
        !> gathered positions, the first active cycle). Unallocated: every
        !> node, each cycle.
        integer, allocatable :: fresh(:)
        logical :: regather = .true.
    end type interface_t

    !> Named in d3hsp as they happen: an initial penetration (allowed and
    !> shrinking, as LS-DYNA's IGNORE = 1); a missed contact, found or
    !> moved deeper than one step's approach in a zone the slave entered
    !> since the last search (the excess allowed the same way); a contact
    !> released while deep; a deep contact refused, in a solid's zone the
    !> slave was already in at the last search (a face it never crossed: no
    !> contact; named once per slave and segment while it lasts); the same
    !> in a shell's zone, held at the depth found (its depth allowed); a
    !> contact released beyond PENMAX times the segment's thickness (counted
    !> with the deep releases).
    integer, parameter :: ev_none = 0, ev_initial = 1, ev_late = 2, ev_released = 3, ev_refused = 4, ev_penmax = 5, &
                          ev_back = 6, ev_within = 7, ev_handover = 8
    integer, parameter :: max_named = 200   !< late and released events named per interface (all counted)
    integer, parameter :: default_interval = 100   !< SEARCH 1: longest cycles between global searches when none is given
    !> contact_drift sums the surface's velocities in chunks of this many
    !> nodes, the chunks' sums then in order: the same sum for any number
    !> of threads
    !> list_pairs counts and lists the pairs in chunks of this many slaves
    integer, parameter :: pair_chunk = 4096
    real(wp), parameter, public :: contact_step_scale = 0.35_wp   !< contact step sqrt(m / k) times this (omega dt <= 0.5)

    type :: contact_event_t
        integer :: kind = ev_none
        integer :: slave = 0                  !< surface-local node
        integer :: seg = 0                    !< segment
        real(dp) :: time = 0
        real(wp) :: depth = 0
    end type contact_event_t

    type :: contacts_t
        integer :: n = 0
        type(faces_t) :: faces
        type(interface_t), allocatable :: ifc(:)
        integer :: mnl = 0
        integer :: dump_unit = 0
        type(search_switches_t) :: sw
        !> (faces) the segment is on the surface now: latent faces exposed,
        !> faces of eroded elements gone (size 0 without latent faces)
        logical, allocatable :: face_on(:)
        logical :: lagrange = .false.         !< Lagrangian projection instead of penalty
        !> (3, model nodes) contact force on each node this cycle, on the
        !> cycles whose outputs read it (a state, nodout): unallocated until
        !> the first (contact_enforce's outputs), stale between them
        real(wp), allocatable :: fnode(:, :)
        !> the nodes fnode holds a force at (nftouch of them, with repeats):
        !> the next cycle zeroes those alone, not every node of the model
        integer, allocatable :: ftouch(:)
        integer :: nftouch = 0
        !> MPI with contact ghosts: the model's nodes this rank moves (the
        !> domain's contact_ghosts). A pair of another rank's slave that
        !> touches none of them adds nothing this rank reads: its forces
        !> are applied only where the outputs read the contact forces
        !> (contact_enforce's `outputs`), its sums (rcforc's) always
        logical, allocatable :: moves(:)
        integer(i8) :: npair_all = 0, npair_applied = 0   !< this rank's pairs, all and applied
        real(wp) :: dt_limit = huge(1.0_wp)   !< stable step of the stiffest contact spring
        integer :: dt_node = 0                !< the node that sets it
        logical :: distributed = .false.      !< slaves split over MPI ranks: contacts are gathered
        !> owned nodes (unless XDYNA_CONTACT_OWN=0): each rank books the contacts' work
        !> (sliding energy, part pairs' impulse and work) of its own slaves'
        !> pairs alone, with their own nodes' velocities; the ranks' sums are
        !> added where an energy, a dump or the report reads them
        logical :: own_work = .false.
        !> THKCHG with ISTUPD: some interface's shell contact thickness
        !> follows the shells'; each model node's largest initial thickness of
        !> a deformable shell at it (0: none)
        logical :: thkchg = .false.
        real(dp), allocatable :: node_h0(:)
        integer :: nranks = 1
        real(dp) :: wall_gather = 0           !< seconds gathering the ranks' contacts
        !> owned nodes with contact ghosts: every model node's integrating
        !> rank (the domain's arank). On a cycle where no output reads every
        !> pair, a contact found goes only to the ranks that integrate its
        !> slave or its segment's nodes (send_contacts); an event goes to
        !> every rank, which books every event alike. Unallocated: every
        !> contact to every rank, each cycle.
        integer, allocatable :: rank_of(:)
        integer :: rank = 0
        !> the contacts' exchange: records this rank sent to other ranks
        !> (a record to each rank it went to), on cycles sent to their
        !> nodes' ranks and on cycles gathered to every rank
        integer(i8) :: sent_p2p = 0, sent_all = 0
        integer(i8) :: ncyc_p2p = 0, ncyc_all = 0
    end type contacts_t

contains

    !> The slaves' contact state that only the slave's rank reads (cseg,
    !> held, fprev, ft, p0, kp, aeff, rdep, deep, rlast: 100 bytes a slave)
    !> and their contacts found (hit, fk: 128) in rows: with each rank's own
    !> slaves' work (`own`) the rank's own slaves' alone (orow; hit's and
    !> fk's other ranks' slaves' rows follow at each exchange, hrow), else
    !> every slave's, the other ranks' slaves' entries zero (a dump's
    !> gathering, which sums them from their ranks: gather_contact_state).
    !> Where the rows are not made yet (contact_masses' rows_later, and its
    !> every-slave's rows) they are made here, cleared.
    subroutine contact_slave_rows(ct, own)
        type(contacts_t), intent(inout) :: ct
        logical, intent(in) :: own
        integer, allocatable :: mine(:)
        integer :: i, k, n, ns
        do i = 1, ct%n
            associate (it => ct%ifc(i))
                if (.not. allocated(it%orow)) cycle
                if (allocated(it%cseg) .and. (own .eqv. it%own_rows)) cycle
                ns = size(it%orow)
                ! the rank's own slaves, ascending: the rows (the arrays go
                ! from every slave's to these and back)
                n = 0
                do k = 1, ns
                    if (it%owned(k)) n = n + 1
                end do
                allocate (mine(n))
                n = 0
                do k = 1, ns
                    if (.not. it%owned(k)) cycle
                    n = n + 1
                    mine(n) = k
                end do
                if (.not. allocated(it%cseg)) then
                    call slave_rows_alloc(it, merge(n, ns, own))
                else
                    ! (each array to the rank's own slaves' rows, or back to
                    ! every slave's, the others' entries zero)
                    call relay_i(it%cseg)
                    call relay_i(it%held)
                    call relay_i(it%rlast)
                    call relay_r(it%p0)
                    call relay_r(it%kp)
                    call relay_r(it%aeff)
                    call relay_r(it%rdep)
                    call relay_r(it%deep)
                    call relay_r2(it%fprev)
                    call relay_r2(it%ft)
                    call relay_r2(it%fk)
                    if (own) then
                        call take_hits(it%hit, mine)
                    else
                        call untake_hits(it%hit, mine, ns)
                    end if
                end if
                if (own) then
                    it%orow = 0
                    do k = 1, n
                        it%orow(mine(k)) = k
                    end do
                else
                    do k = 1, ns
                        it%orow(k) = k
                        ! (the other ranks' slaves' contacts the last
                        ! exchange brought: none, until the next)
                        if (.not. it%owned(k)) it%found(k) = .false.
                    end do
                end if
                it%hrow = it%orow
                ! (the search lists' per-slave arrays in the same rows)
                call lists_rows(it%lists, it%orow, merge(n, ns, own))
                deallocate (mine)
                it%own_rows = own
            end associate
        end do
    contains
        subroutine relay_i(a)
            integer, allocatable, intent(inout) :: a(:)
            if (own) then
                call take(a, mine)
            else
                call untake(a, mine, ns)
            end if
        end subroutine relay_i
        subroutine relay_r(a)
            real(wp), allocatable, intent(inout) :: a(:)
            if (own) then
                call take(a, mine)
            else
                call untake(a, mine, ns)
            end if
        end subroutine relay_r
        subroutine relay_r2(a)
            real(wp), allocatable, intent(inout) :: a(:, :)
            if (own) then
                call take(a, mine)
            else
                call untake(a, mine, ns)
            end if
        end subroutine relay_r2
    end subroutine contact_slave_rows

    !> The records of hit's rows 1 .. size(idx) back to the slaves idx (of
    !> n slaves), every other slave's none (contact_slave_rows undone).
    subroutine untake_hits(hit, idx, n)
        type(pair_hit_t), allocatable, intent(inout) :: hit(:)
        integer, intent(in) :: idx(:), n
        type(pair_hit_t), allocatable :: whole(:)
        integer :: i
        ! (loops: no temporary of the slaves' size on the stack)
        allocate (whole(n))
        do i = 1, size(idx)
            whole(idx(i)) = hit(i)
        end do
        call move_alloc(whole, hit)
    end subroutine untake_hits

    !> hit's records of the slaves idx alone, in rows 1 .. size(idx).
    subroutine take_hits(hit, idx)
        type(pair_hit_t), allocatable, intent(inout) :: hit(:)
        integer, intent(in) :: idx(:)
        type(pair_hit_t), allocatable :: rows(:)
        integer :: i
        allocate (rows(size(idx)))
        do i = 1, size(idx)
            rows(i) = hit(idx(i))
        end do
        call move_alloc(rows, hit)
    end subroutine take_hits

    !> hit's and fk's room for the rank's own slaves' rows and nrecv more
    !> (the contacts of other ranks' slaves the exchange brought), the own
    !> rows kept; grown by half again where short.
    subroutine hit_room(it, nrecv)
        type(interface_t), intent(inout) :: it
        integer, intent(in) :: nrecv
        type(pair_hit_t), allocatable :: h(:)
        real(wp), allocatable :: fk(:, :)
        integer :: n, nown
        ! (the own rows: as many as of the rest of their contact state)
        nown = size(it%cseg)
        if (size(it%hit) >= nown + nrecv) return
        n = max(nown + nrecv, size(it%hit) + size(it%hit)/2)
        allocate (h(n), fk(3, n))
        h(1:nown) = it%hit(1:nown)
        fk(:, 1:nown) = it%fk(:, 1:nown)
        fk(:, nown + 1:) = 0
        call move_alloc(h, it%hit)
        call move_alloc(fk, it%fk)
    end subroutine hit_room

    !> Once the contact is set up, where nothing rebuilds its surfaces (no
    !> erosion, no latent faces, no shell thickness followed: `rebuilt`
    !> false): the model's faces and the surfaces' set-up springs, areas and
    !> sides released (84 bytes a face, 20 a surface node; the 250,000-shell
    !> plate with whole-model contact: 25 MB a rank).
    subroutine contact_release_setup(ct, rebuilt)
        type(contacts_t), intent(inout) :: ct
        logical, intent(in) :: rebuilt   !< erosion can change the surfaces
        integer :: i
        if (ct%n == 0 .or. rebuilt .or. ct%thkchg .or. ct%faces%nlatent > 0) return
        call release_faces(ct%faces)
        do i = 1, ct%n
            call release_activation(ct%ifc(i)%surf)
        end do
    end subroutine contact_release_setup

    !> The bytes of the contact's arrays on this rank: the faces, each
    !> interface's surface (segments and nodes), its search's lists and
    !> working arrays, its per-slave records, its edges, and the per-node
    !> contact forces (issue 32: every slave's and every surface node's on
    !> every rank). `split`: the same bytes by kind, d3hsp's line under the
    !> figure: (1) the faces, surfaces and edges, (2) the slaves' records
    !> (their contacts, forces, events, clearances and flags), (3) the
    !> search's lists, (4) the surface nodes' masses, motion bounds and
    !> gathered coordinates and velocities, (5) the per-node contact forces
    !> and the part pairs' tables.
    integer(i8) function contact_bytes(ct, split) result(b)
        type(contacts_t), intent(in) :: ct
        integer(i8), intent(out), optional :: split(5)
        integer(i8) :: q(5)
        integer :: i
        q = 0
        q(1) = faces_bytes(ct%faces) + nbytes(ct%face_on)
        q(5) = nbytes(ct%fnode) + nbytes(ct%ftouch) + nbytes(ct%moves) + nbytes(ct%node_h0)
        if (allocated(ct%ifc)) then
            do i = 1, size(ct%ifc)
                call interface_bytes(ct%ifc(i))
            end do
        end if
        b = sum(q)
        if (present(split)) split = q
    contains
        subroutine interface_bytes(it)
            type(interface_t), intent(in) :: it
            q(1) = q(1) + surface_bytes(it%surf) + nbytes(it%ed%en) + nbytes(it%ed%eseg) &
                   + nbytes(it%ed%pa) + nbytes(it%ed%pb) &
                   + nbytes(it%ed%side) + nbytes(it%ed%named) + nbytes(it%ed%kp) + nbytes(it%ed%p0) &
                   + nbytes(it%ed%dlast) + nbytes(it%ed%ft) + nbytes(it%ed%act) + nbytes(it%ed%st) + nbytes(it%ed%fa)
            if (allocated(it%ed%ev)) q(1) = q(1) + size(it%ed%ev, kind=i8)*(storage_size(it%ed%ev, i8)/8)
            q(2) = q(2) + nbytes(it%cls) + nbytes(it%cl%row) + nbytes(it%cl%g) + nbytes(it%cl%x) &
                   + nbytes(it%cl%u) + nbytes(it%cl%wait) + nbytes(it%cl%nnear) + nbytes(it%cl%near) &
                   + nbytes(it%cseg) + nbytes(it%fprev) + nbytes(it%ft) + nbytes(it%p0) + nbytes(it%kp) + nbytes(it%fk) &
                   + nbytes(it%aeff) + nbytes(it%held) + nbytes(it%rseg) + nbytes(it%rdep) + nbytes(it%deep) &
                   + nbytes(it%rlast) + nbytes(it%evk) + nbytes(it%evd) + nbytes(it%found) + nbytes(it%pair) &
                   + nbytes(it%fpair) + nbytes(it%slave_lp) + nbytes(it%owned) + nbytes(it%got) + nbytes(it%mine) &
                   + nbytes(it%live) + nbytes(it%resl) + nbytes(it%dump)
            if (allocated(it%hit)) q(2) = q(2) + size(it%hit, kind=i8)*(storage_size(it%hit, i8)/8)
            if (allocated(it%ev)) q(2) = q(2) + size(it%ev, kind=i8)*(storage_size(it%ev, i8)/8)
            q(3) = q(3) + lists_bytes(it%lists)
            q(4) = q(4) + nbytes(it%ms) + nbytes(it%xl) + nbytes(it%dl) + nbytes(it%dmin) + nbytes(it%un) &
                   + nbytes(it%drift_own) + nbytes(it%cmin) + nbytes(it%uc) + nbytes(it%cbud) + nbytes(it%cused) &
                   + nbytes(it%ls%xl) + nbytes(it%ls%vl) + nbytes(it%ls%lc) + nbytes(it%ls%lcodo) + nbytes(it%fresh)
            q(5) = q(5) + nbytes(it%part_id) + nbytes(it%seg_lp) + nbytes(it%pair_imp) + nbytes(it%pair_work)
        end subroutine interface_bytes
    end function contact_bytes

    !> Step 1 for every interface, from the initial coordinates x0.
    subroutine build_contacts(model, x0, ct, error)
        type(model_t), intent(in) :: model
        real(wp), intent(in) :: x0(:, :)
        type(contacts_t), intent(out) :: ct
        type(error_t), allocatable, intent(out) :: error
        integer :: i, interval, sset, k, ic
        logical :: given
        logical, allocatable :: in_a(:), in_b(:), dumped(:)
        integer, allocatable :: slaves(:)
        real(wp), allocatable :: xl(:, :), lc(:)
        ct%n = model%ncontact
        if (ct%n == 0) return
        ! hexahedra that can erode: the faces inside their parts are latent
        ! segments, exposed as the elements erode
        call build_faces(model, x0, ct%faces, erodible_hexes(model))
        ct%mnl = model%ctl%contact%mnl
        ct%sw = search_switches_t(tracking=model%ctl%contact%tracking, screens=model%ctl%contact%screens)
        ct%lagrange = model%ctl%contact%lagrange
        allocate (ct%ifc(ct%n), in_a(ct%faces%n), in_b(ct%faces%n))
        do i = 1, ct%n
            associate (c => model%contact(i), it => ct%ifc(i))
                it%id = c%id
                it%keyword = c%keyword
                it%bt = c%bt
                it%dt = c%dt
                it%fr = friction_t(fs=c%fs, fd=c%fd, dc=c%dc, vdc=c%vdc)
                it%ls%penmax = c%penmax
                in_b = .false.
                allocate (slaves(0))
                select case (c%kind)
                case (ct_single, ct_general)
                    call select_faces(c%ssid, c%sstyp, c%sref, 'SSID', in_a); if (allocated(error)) return
                case (ct_surface_to_surface)
                    call select_faces(c%ssid, c%sstyp, c%sref, 'SSID', in_a); if (allocated(error)) return
                    call select_faces(c%msid, c%mstyp, c%mref, 'MSID', in_b); if (allocated(error)) return
                case (ct_nodes_to_surface)
                    if (c%sstyp == styp_node_set) then
                        slaves = model%set(c%sref)%member_ix
                        it%listed = .true.
                    else
                        call select_faces(c%ssid, c%sstyp, c%sref, 'SSID', in_a); if (allocated(error)) return
                        slaves = face_nodes(in_a)
                    end if
                    in_a = .false.
                    call select_faces(c%msid, c%mstyp, c%mref, 'MSID', in_b); if (allocated(error)) return
                end select
                ! SBOXID, MBOXID: only segments whose centre, and slave nodes
                ! that, lie in the box at t = 0
                if (c%sboxid > 0) then
                    call box_faces(model%box(find_box(model, c%sboxid)), in_a)
                    slaves = pack(slaves, [(in_box(model%box(find_box(model, c%sboxid)), x0(:, slaves(k))), &
                                            k=1, size(slaves))])
                end if
                if (c%mboxid > 0) call box_faces(model%box(find_box(model, c%mboxid)), in_b)
                call build_surface(ct%faces, model%nnode, in_a, in_b, slaves, c%kind == ct_surface_to_surface, &
                                   [c%sst, c%mst, c%sfst, c%sfmt], [model%ctl%contact%slsfac, c%sfs, c%sfm], it%surf, &
                                   model%hex_conn(:, 1:model%nhex), &
                                   cap=(c%kind == ct_single .or. c%kind == ct_general) .and. model%ctl%contact%ssthk == 0, &
                                   follow=(c%kind == ct_single .or. c%kind == ct_general) .and. &
                                   model%ctl%contact%thkchg == 1 .and. model%ctl%istupd /= 0)
                ct%thkchg = ct%thkchg .or. it%surf%follow
                deallocate (slaves)
                allocate (it%live(it%surf%nslave), it%resl(it%surf%nslave))
                it%live = .true.
                it%resl = .false.
                ! AUTOMATIC_GENERAL: shell edges against shell edges as well
                if (c%kind == ct_general) call build_edges(it%surf, it%ed)
                call pair_parts(it)
                ! pool margins from the local characteristic lengths at t = 0;
                ! the typical one from the median (a node without a segment
                ! takes it; none falls below a fraction of it)
                allocate (xl(3, it%surf%nnode), lc(it%surf%nnode))
                xl = x0(:, it%surf%node)
                call characteristic_lengths(it%surf, xl, lc)
                it%margin = model%ctl%contact%pmarg*typical_length(pack(lc, lc > 0.0_wp), 0.5_wp)
                call pool_margins(it%surf, lc, model%ctl%contact%pmarg, it%margin, it%dl, it%dmin, it%nraised)
                call margin_classes(it%surf, it%dl, it%cls, it%cmin)
                allocate (it%un(it%surf%nnode), it%uc(it%surf%nnode, size(it%cmin)), it%cused(size(it%cmin)), &
                          it%cbud(it%surf%nnode, size(it%cmin)))
                it%un = 0
                it%uc = 0
                it%cused = 0
                do ic = 1, size(it%cmin)
                    it%cbud(:, ic) = 4.0_wp/max(it%cmin(ic), it%dmin, tiny(1.0_wp))
                end do
                it%reach = it%surf%max_thick
                deallocate (xl, lc)
                ! no interval given (BSORT, NSRCH, NSBCS all 0): LS-DYNA then
                ! chooses the interval itself; here the search runs when the
                ! motion could have used up the pool margin (4u > delta), which
                ! keeps the search's bound (SEARCH 1 of *CONTROL_XDYNA_CONTACT
                ! also searches every 100 cycles, as before 2026-11-26: car6
                ! searched 332 times, 219 on the motion alone)
                interval = default_interval
                if (model%ctl%contact%nsbcs > 0) interval = model%ctl%contact%nsbcs
                if (model%ctl%contact%nsrch > 0) interval = model%ctl%contact%nsrch
                if (c%bsort > 0) interval = c%bsort
                it%interval = interval
                given = model%ctl%contact%nsbcs > 0 .or. model%ctl%contact%nsrch > 0 .or. c%bsort > 0
                it%adaptive = model%ctl%contact%search == search_adaptive .or. &
                              (model%ctl%contact%search == search_auto .and. .not. given)
                ! slaves whose master node lists go to the debug dump
                if (model%ctl%contact%dump_nsid > 0) then
                    sset = find_set(model, set_node, model%ctl%contact%dump_nsid)
                    allocate (dumped(model%nnode))
                    dumped = .false.
                    dumped(model%set(sset)%member_ix) = .true.
                    it%dump = where_true(dumped(it%surf%node(it%surf%slave)))
                    deallocate (dumped)
                else
                    allocate (it%dump(0))
                end if
            end associate
        end do
        if (ct%faces%nlatent > 0) then
            ct%face_on = ct%faces%across == 0
            call set_liveness(ct, model%hex_conn(:, 1:model%nhex), [(.false., k=1, model%nhex)])
            ! a slave inside a part is searched the first cycle erosion
            ! exposes it
            do k = 1, ct%n
                ct%ifc(k)%resl = .not. ct%ifc(k)%live
                ct%ifc(k)%resl_on = any(ct%ifc(k)%resl)
            end do
        end if
        if (ct%thkchg) then
            ! the initial thickness of the deformable shells (as the shells
            ! take it: the mean of the nodal values), largest at each node
            allocate (ct%node_h0(model%nnode))
            ct%node_h0 = 0
            do i = 1, model%nshell
                if (model%mat(model%part(model%shell_part(i))%mat_ix)%mtype == mat_rigid) cycle
                do k = 1, 4
                    ct%node_h0(model%shell_conn(k, i)) = max(ct%node_h0(model%shell_conn(k, i)), &
                                                             real(sum(model%shell_t(:, i))/4, dp))
                end do
            end do
        end if
    contains
        subroutine box_faces(bx, on)
            type(box_t), intent(in) :: bx
            logical, intent(inout) :: on(:)
            integer :: f
            do f = 1, ct%faces%n
                if (on(f)) on(f) = in_box(bx, sum(x0(:, ct%faces%node(:, f)), dim=2)/4)
            end do
        end subroutine box_faces

        !> Faces of the parts, sets or segments that (sid, styp) names.
        subroutine select_faces(sid, styp, ref, field, sel)
            integer, intent(in) :: sid, styp, ref
            character(len=*), intent(in) :: field
            logical, intent(out) :: sel(:)
            call faces_of(model, ct%faces, model%contact(i), sid, styp, ref, field, sel, error)
        end subroutine select_faces

        !> The interface's parts and each segment's and slave's local part.
        subroutine pair_parts(it)
            type(interface_t), intent(inout) :: it
            logical, allocatable :: used(:)
            integer, allocatable :: loc(:)
            integer :: m, k, sn, p
            associate (s => it%surf)
                allocate (used(model%npart), loc(model%npart))
                used = .false.
                do m = 1, s%nseg
                    used(ct%faces%part(s%seg_face(m))) = .true.
                end do
                loc = 0
                it%part_id = [0]
                do p = 1, model%npart
                    if (.not. used(p)) cycle
                    it%part_id = [it%part_id, model%part(p)%id]
                    loc(p) = size(it%part_id)
                end do
                allocate (it%seg_lp(s%nseg), it%slave_lp(s%nslave))
                do m = 1, s%nseg
                    it%seg_lp(m) = loc(ct%faces%part(s%seg_face(m)))
                end do
                do k = 1, s%nslave
                    sn = s%slave(k)
                    it%slave_lp(k) = 1
                    if (s%seg_ptr(sn + 1) > s%seg_ptr(sn)) it%slave_lp(k) = it%seg_lp(s%seg_list(s%seg_ptr(sn)))
                end do
                allocate (it%pair_imp(size(it%part_id), size(it%part_id), 2), &
                          it%pair_work(size(it%part_id), size(it%part_id), 2))
                it%pair_imp = 0
                it%pair_work = 0
            end associate
        end subroutine pair_parts

        function face_nodes(sel) result(nodes)
            logical, intent(in) :: sel(:)
            integer, allocatable :: nodes(:)
            logical, allocatable :: on(:)
            integer :: j
            allocate (on(model%nnode))
            on = .false.
            do j = 1, ct%faces%n
                if (sel(j)) on(ct%faces%node(:, j)) = .true.
            end do
            nodes = where_true(on)
        end function face_nodes
    end subroutine build_contacts

    !> Faces of the parts, sets or segments that (sid, styp) of contact c
    !> names (sel: over faces); a listed segment that is no exterior face is
    !> an error naming the contact's card.
    subroutine faces_of(model, f, c, sid, styp, ref, field, sel, error)
        type(model_t), intent(in) :: model
        type(faces_t), intent(in) :: f
        type(contact_t), intent(in) :: c
        integer, intent(in) :: sid, styp, ref
        character(len=*), intent(in) :: field
        logical, intent(out) :: sel(:)
        type(error_t), allocatable, intent(inout) :: error
        logical, allocatable :: inpart(:), inshell(:)
        integer :: j, q, key(4), nu
        integer, allocatable :: fkey(:, :)
        select case (styp)
        case (styp_all)
            sel = .true.
        case (styp_part)
            sel = f%part == ref
        case (styp_part_set, styp_all_but)
            allocate (inpart(model%npart))
            inpart = .false.
            inpart(model%set(ref)%member_ix) = .true.
            sel = inpart(f%part)
            if (styp == styp_all_but) sel = .not. sel
        case (styp_shell_set)
            allocate (inshell(0:model%nshell))
            inshell = .false.
            inshell(model%set(ref)%member_ix) = .true.
            sel = inshell(f%shell)
        case (styp_segment_set)
            ! each listed segment must be an exterior face (any node order)
            allocate (fkey(4, f%n))
            do j = 1, f%n
                call face_key(f%node(:, j), fkey(:, j), nu)
            end do
            sel = .false.
            do q = 1, model%segset(ref)%n
                call face_key(model%segset(ref)%seg(:, q), key, nu)
                do j = 1, f%n
                    if (all(fkey(:, j) == key) .and. f%across(j) == 0) exit
                end do
                if (j > f%n) then
                    call make_error(error, trim(c%at)//': *'//trim(c%keyword)// &
                                    ' '//itoa(c%id)//' field '//field//': segment '//itoa(q)// &
                                    ' of *SET_SEGMENT '//itoa(sid)//' (nodes '// &
                                    trim(ids(model%segset(ref)%seg(:, q)))//') is not an exterior element face')
                    return
                end if
                sel(j) = .true.
            end do
        case default
            sel = .false.
        end select
    contains
        function ids(nd) result(t)
            integer, intent(in) :: nd(4)
            character(len=60) :: t
            write (t, '(i0,3(1x,i0))') model%node_id(nd)
        end function ids
    end subroutine faces_of

    !> Erosion: the segments of eroded shells leave every interface's
    !> node-to-segment lists, through which the searches find segments (the
    !> surface rebuilt as the elements erode), and a slave in contact with
    !> one of them, or holding it, lets it go. `dead_shell` is over the
    !> model's shells (index 0, a solid face: never).
    subroutine contact_erode(ct, dead_shell)
        type(contacts_t), intent(inout) :: ct
        logical, intent(in) :: dead_shell(0:)
        logical, allocatable :: segdead(:)
        integer, allocatable :: ptr(:), list(:)
        integer :: i, nd, q, n
        do i = 1, ct%n
            associate (it => ct%ifc(i), s => ct%ifc(i)%surf)
                segdead = dead_shell(ct%faces%shell(s%seg_face))
                if (.not. any(segdead)) cycle
                ! (kept out of the lists when solids' erosion rebuilds them)
                s%seg_on = s%seg_on .and. .not. segdead
                allocate (ptr(s%nnode + 1), list(size(s%seg_list)))
                n = 0
                ptr(1) = 1
                do nd = 1, s%nnode
                    do q = s%seg_ptr(nd), s%seg_ptr(nd + 1) - 1
                        if (segdead(s%seg_list(q))) cycle
                        n = n + 1
                        list(n) = s%seg_list(q)
                    end do
                    ptr(nd + 1) = n + 1
                end do
                s%seg_ptr = ptr
                s%seg_list = list(1:n)
                deallocate (ptr, list)
                call let_go(it, segdead)
            end associate
        end do
    end subroutine contact_erode

    !> Interface it's slaves in contact with, or holding, a segment `gone`
    !> let it go.
    subroutine let_go(it, gone)
        type(interface_t), intent(inout) :: it
        logical, intent(in) :: gone(:)
        integer :: k
        do k = 1, size(it%cseg)
            if (it%cseg(k) > 0) then
                if (gone(it%cseg(k))) it%cseg(k) = 0
            end if
        end do
        if (allocated(it%held)) then
            do k = 1, size(it%held)
                if (it%held(k) > 0) then
                    if (gone(it%held(k))) it%held(k) = 0
                end if
            end do
        end if
    end subroutine let_go

    !> The model's hexahedra whose part's material can erode (FAIL, FS or
    !> *MAT_ADD_EROSION), or every one with ERODE (its step), as the solids
    !> take it.
    function erodible_hexes(model) result(er)
        type(model_t), intent(in) :: model
        logical :: er(model%nhex)
        integer :: e, k
        do e = 1, model%nhex
            k = model%part(model%hex_part(e))%mat_ix
            er(e) = can_erode(model, k) .and. model%mat(k)%mtype /= mat_rigid
        end do
    end function erodible_hexes

    !> Erosion of solids (dead_hex over the model's hexahedra): a segment
    !> of a hexahedron that can erode is on the surface while its
    !> hexahedron lives and the one across (if any) does not. Where that
    !> changes, each interface's searches take the new surface
    !> (surface_activate: the lists and the nodes' springs); a slave in
    !> contact with, or holding, a segment gone lets it go; the slaves the
    !> erosion exposed join (set_liveness); they and the slaves within
    !> reach of a segment that came or went (twice the largest pool margin
    !> and the contact's reach from one of its nodes, at x) are searched
    !> the next cycle (the new segments are in no list yet; a slave farther
    !> away cannot reach them before its next search, which the margins'
    !> bound keeps); a node's spring that stiffened may lower the
    !> contact's stable step (0.35 sqrt(m / k)). Nothing where no face
    !> changes (and nothing without latent faces).
    subroutine contact_erode_solids(ct, hex_conn, dead_hex, x, restart)
        type(contacts_t), intent(inout) :: ct
        integer, intent(in) :: hex_conn(:, :)
        logical, intent(in) :: dead_hex(:)
        real(wp), intent(in) :: x(:, :)     !< the model's nodes now
        !> from a restart dump: the surfaces alone (the searches asked and
        !> the stable step are the dump's)
        logical, intent(in), optional :: restart
        logical :: keep_state
        logical, allocatable :: on(:), gone(:), changed(:)
        integer :: i, j, h, k
        if (ct%faces%nlatent == 0) return
        keep_state = .false.
        if (present(restart)) keep_state = restart
        on = ct%face_on
        do j = 1, ct%faces%n
            h = ct%faces%hex(j)
            if (h == 0) cycle
            on(j) = .not. dead_hex(h)
            if (ct%faces%across(j) > 0) on(j) = on(j) .and. dead_hex(ct%faces%across(j))
        end do
        if (all(on .eqv. ct%face_on)) return
        ct%face_on = on
        do i = 1, ct%n
            associate (it => ct%ifc(i), s => ct%ifc(i)%surf)
                ! (the shells' erosion has already taken its segments out)
                on = s%seg_on
                do k = 1, s%nseg
                    if (ct%faces%hex(s%seg_face(k)) > 0) on(k) = ct%face_on(s%seg_face(k))
                end do
                if (all(on .eqv. s%seg_on)) cycle
                gone = s%seg_on .and. .not. on
                ! on a restart, the searches and the step as the dump has them
                if (.not. keep_state) call ask_near(it, on, x)
                call surface_activate(s, ct%faces, on, changed)
                call let_go(it, gone)
                if (.not. keep_state .and. (.not. ct%lagrange .or. it%ed%ne > 0)) call spring_step(ct, it, changed)
            end associate
        end do
        ! (the slaves that join keep the search asked at set-up)
        call set_liveness(ct, hex_conn, dead_hex)
    end subroutine contact_erode_solids

    !> The slaves of interface it within reach of a segment that comes or
    !> goes (on against it%surf%seg_on) are searched the next cycle: those
    !> within twice the largest pool margin and the contact's reach of one
    !> of its nodes at x (a box first).
    subroutine ask_near(it, on, x)
        type(interface_t), intent(inout) :: it
        logical, intent(in) :: on(:)
        real(wp), intent(in) :: x(:, :)
        logical, allocatable :: near(:)
        real(wp), allocatable :: pts(:, :)
        real(wp) :: r, lo(3), hi(3), p(3)
        integer :: k, m, q
        associate (s => it%surf)
            allocate (near(s%nnode))
            near = .false.
            do m = 1, s%nseg
                if (on(m) .neqv. s%seg_on(m)) near(s%seg(:, m)) = .true.
            end do
            pts = x(:, s%node(pack([(q, q=1, s%nnode)], near)))
            r = 2*maxval(it%dl) + it%reach
            lo = minval(pts, 2) - r
            hi = maxval(pts, 2) + r
            do k = 1, s%nslave
                p = x(:, s%node(s%slave(k)))
                if (any(p < lo) .or. any(p > hi)) cycle
                if (minval(sum((pts - spread(p, 2, size(pts, 2)))**2, 1)) <= r*r) then
                    it%resl(k) = .true.
                    it%resl_on = .true.
                end if
            end do
        end associate
    end subroutine ask_near

    !> Each interface's live slaves with latent faces in the model: a slave
    !> on an active face, or at no living hexahedron (a node of shells, or
    !> debris whose elements all eroded), or a node set's; the slaves each
    !> rank searches and enforces, its own live ones.
    subroutine set_liveness(ct, hex_conn, dead_hex)
        type(contacts_t), intent(inout) :: ct
        integer, intent(in) :: hex_conn(:, :)
        logical, intent(in) :: dead_hex(:)
        logical, allocatable :: exposed(:), inside(:)
        integer :: j, e, i, nn
        nn = 0
        if (size(hex_conn) > 0) nn = maxval(hex_conn)
        do j = 1, ct%faces%n
            nn = max(nn, maxval(ct%faces%node(:, j)))
        end do
        allocate (exposed(nn), inside(nn))
        exposed = .false.
        inside = .false.
        do j = 1, ct%faces%n
            if (ct%face_on(j)) exposed(ct%faces%node(:, j)) = .true.
        end do
        do e = 1, size(hex_conn, 2)
            if (.not. dead_hex(e)) inside(hex_conn(:, e)) = .true.
        end do
        do i = 1, ct%n
            associate (it => ct%ifc(i), s => ct%ifc(i)%surf)
                if (it%listed) cycle
                do j = 1, s%nslave
                    e = s%node(s%slave(j))
                    if (e > nn) cycle
                    it%live(j) = exposed(e) .or. .not. inside(e)
                end do
                if (allocated(it%owned)) it%mine = where_true(it%owned .and. it%live)
            end associate
        end do
    end subroutine set_liveness

    !> MPI with contact ghosts: the box around interface it's live slaves
    !> that this rank owns, grown by what build_master_lists grows the box
    !> of the slaves it searches by (pool_reach of these), plus `span`:
    !> every master node a search of these slaves buckets lies inside, and
    !> every node of a segment at one within span of it. lo > hi (huge
    !> values): no such slave, an empty box.
    function search_box(it, x, span, time) result(box)
        type(interface_t), intent(in) :: it
        real(wp), intent(in) :: x(:, :), span
        real(dp), intent(in) :: time
        real(wp) :: box(6)
        real(wp) :: lo(3), hi(3), g
        logical, allocatable :: mine(:)
        integer :: k
        box(1:3) = huge(1.0_wp)
        box(4:6) = -huge(1.0_wp)
        ! (contact_search's window)
        if (time < it%bt .or. time > it%dt) return
        associate (s => it%surf)
            allocate (mine(s%nslave))
            lo = huge(1.0_wp)
            hi = -huge(1.0_wp)
            do k = 1, s%nslave
                mine(k) = it%owned(k) .and. it%live(k)
                if (.not. mine(k)) cycle
                lo = min(lo, x(:, s%node(s%slave(k))))
                hi = max(hi, x(:, s%node(s%slave(k))))
            end do
            if (.not. any(mine)) return
            g = pool_reach(s, it%ls%lc, it%dl, it%reach, mine, it%odo, it%ls%lcodo)
            box(1:3) = lo - g - span
            box(4:6) = hi + g + span
        end associate
    end function search_box

    !> Step 2 where due: at cycle 0 every slave; then every `interval`
    !> cycles every slave (fixed), and the slaves of each class whose
    !> margins the motion could have used up (cused > 1). The master nodes
    !> are all bucketed at their positions now, whatever the slaves
    !> searched. Returns the seconds spent.
    subroutine contact_search(ct, x, node_id, cycle, time, cur)
        type(contacts_t), intent(inout) :: ct
        real(wp), intent(in) :: x(:, :)
        integer, intent(in) :: node_id(:), cycle
        real(dp), intent(in) :: time
        !> MPI with contact ghosts: per model node, its position is current
        !> on this rank (the nodes it moves and those the search's exchange
        !> brought, search_box); only those are bucketed (absent: every node)
        logical, intent(in), optional :: cur(:)
        integer :: i, c, k
        logical, allocatable :: due(:), todo(:), fresh(:)
        type(search_counts_t) :: cnt
        real(dp) :: t0
        do i = 1, ct%n
            associate (it => ct%ifc(i))
                if (time < it%bt .or. time > it%dt) cycle
                due = due_classes(it, cycle)
                ! (a slave whose surface erosion changed counts on every rank,
                ! owned or not: every rank then searches at the same cycles and
                ! keeps the same last_cycle, nsearch and margins, as search_due
                ! and the next due classes assume; a rank without such a slave
                ! of its own searches none)
                if (.not. any(due) .and. .not. resl_due(it)) then
                    ! the lists of the last searches serve this cycle: how much
                    ! of the margins has the motion used?
                    it%worst = max(it%worst, maxval(it%cused))
                    deallocate (due)
                    cycle
                end if
                t0 = wtime()
                if (.not. allocated(it%xl)) allocate (it%xl(3, it%surf%nnode))
                call gather_x(x, it%surf%node, it%xl)
                ! (and the slaves whose surface erosion changed)
                todo = it%owned .and. it%live .and. (due(it%cls) .or. it%resl)
                ! (every rank alike: the live ones are searched by their
                ! owners now)
                it%resl = it%resl .and. .not. it%live
                if (it%resl_on) it%resl_on = any(it%resl)
                ! (the characteristic lengths taken there, of the nodes bucketed)
                if (present(cur)) then
                    allocate (fresh(it%surf%nnode))
                    do k = 1, it%surf%nnode
                        fresh(k) = cur(it%surf%node(k))
                    end do
                    call build_master_lists(it%surf, it%xl, it%ls%lc, it%reach, it%dl, ct%mnl, it%lists, cnt, todo, &
                                            it%nsearch + 1, it%odo, it%ls%lcodo, fresh)
                    deallocate (fresh)
                else
                    call build_master_lists(it%surf, it%xl, it%ls%lc, it%reach, it%dl, ct%mnl, it%lists, cnt, todo, &
                                            it%nsearch + 1, it%odo, it%ls%lcodo)
                end if
                if (it%ed%ne > 0) call edge_search(it%ed, it%surf, it%xl, it%dl)
                it%nsearch = it%nsearch + 1
                if (.not. all(due)) it%npartial = it%npartial + 1
                it%nsearched = it%nsearched + count(todo)
                it%last_cycle = cycle
                do c = 1, size(due)
                    if (.not. due(c)) cycle
                    it%uc(:, c) = it%un
                    it%cused(c) = 0
                end do
                it%total%pool = it%total%pool + cnt%pool
                it%total%reduced = it%total%reduced + cnt%reduced
                it%total%masters = it%total%masters + cnt%masters
                it%wall = it%wall + (wtime() - t0)
                if (size(it%dump) > 0 .and. ct%dump_unit /= 0) call dump_lists(ct%dump_unit, it, node_id, cycle, time)
                deallocate (due)
            end associate
        end do
    end subroutine contact_search

    !> The margin classes of interface it due for a search at this cycle:
    !> all at its first search and, with a fixed interval, when the interval
    !> is up (the longest; a class is also searched as soon as the motion
    !> could have used up its margins), else those whose margins are used up.
    function due_classes(it, cycle) result(due)
        type(interface_t), intent(in) :: it
        integer, intent(in) :: cycle
        logical, allocatable :: due(:)
        allocate (due(size(it%cmin)))
        if (it%nsearch == 0) then
            due = .true.
        else if (.not. it%adaptive .and. cycle - it%last_cycle >= it%interval) then
            due = .true.
        else
            due = it%cused > 1.0_wp
        end if
    end function due_classes

    !> Will contact_search search some interface at this cycle? (Every rank
    !> answers alike where the margins used are the ranks' maxima: a slave
    !> whose surface erosion changed counts on every rank, owned or not, a
    !> superset of contact_search's own test.)
    logical function search_due(ct, cycle, time) result(due)
        type(contacts_t), intent(in) :: ct
        integer, intent(in) :: cycle
        real(dp), intent(in) :: time
        integer :: i
        due = .false.
        do i = 1, ct%n
            associate (it => ct%ifc(i))
                if (time < it%bt .or. time > it%dt) cycle
                due = any(due_classes(it, cycle)) .or. resl_due(it)
            end associate
            if (due) return
        end do
    end function search_due

    !> Some live slave of interface it is to be searched because erosion
    !> changed the surface near it (resl), or exposed it.
    logical function resl_due(it) result(due)
        type(interface_t), intent(in) :: it
        due = .false.
        if (it%resl_on) due = any(it%resl .and. it%live)
    end function resl_due

    !> THKCHG (with ISTUPD): the shell contact thicknesses of the interfaces
    !> that follow the shells, scaled at each node by the ratio of its
    !> largest deformable shell thickness now (the shells' h, of the elements
    !> `mine` computed here; the largest over the ranks) to its initial one,
    !> within the 40% limit where it applies; a segment's own thickness by
    !> the mean of its nodes' ratios. The contact reach (what the global
    !> search's margin covers) does not shrink: it is the largest thickness
    !> seen, so a thickening shell stays within the search's bound to the
    !> next search at most.
    subroutine contact_thickness(ct, conn, h, mine, row)
        type(contacts_t), intent(inout) :: ct
        integer, intent(in) :: conn(:, :), mine(:)
        real(wp), intent(in) :: h(:)
        !> (the thicknesses held by row: shell e's at row(e); shell_rows)
        integer, intent(in), optional :: row(:)
        real(dp), allocatable :: tn(:)
        real(wp), allocatable :: rho(:)
        integer :: i, k, e, nd, q
        allocate (tn(size(ct%node_h0)))
        tn = 0
        do i = 1, size(mine)
            e = mine(i)
            q = e
            if (present(row)) q = row(e)
            do k = 1, 4
                tn(conn(k, e)) = max(tn(conn(k, e)), real(h(q), dp))
            end do
        end do
        if (ct%distributed) call comm_max(tn)
        do i = 1, ct%n
            associate (it => ct%ifc(i), s => ct%ifc(i)%surf)
                if (.not. s%follow) cycle
                allocate (rho(s%nnode))
                do nd = 1, s%nnode
                    rho(nd) = 1
                    if (ct%node_h0(s%node(nd)) > 0.0_dp .and. tn(s%node(nd)) > 0.0_dp) &
                        rho(nd) = real(tn(s%node(nd))/ct%node_h0(s%node(nd)), wp)
                end do
                call follow_thickness(s, ct%faces%node_cap, rho)
                it%reach = max(it%reach, s%max_thick)
                deallocate (rho)
            end associate
        end do
    end subroutine contact_thickness

    !> After the position update: u_i += dt x the speed of each surface node
    !> relative to the surface's mean velocity, u += dt x the largest
    !> speed, and the part of the margins used. (The pools rest on the
    !> nodes' positions relative to each other, so a motion common to all
    !> of them, a vehicle's travel, uses up no margin.) The mean velocity is
    !> an exact fixed-point sum (64-bit integers at a scale set by the
    !> largest speed) and the rest are maxima, so the result does not depend
    !> on the order the nodes are taken in: with `own` (owned nodes under
    !> MPI: the model's nodes this rank integrates) each rank takes its own
    !> surface nodes alone, and the sums and maxima over the ranks are those
    !> of one rank taking them all, bit for bit. A node's u_i is then kept
    !> by its rank alone (the others' copies go stale; a dump gathers them,
    !> gather_drift).
    subroutine contact_drift(ct, v, dt, own)
        type(contacts_t), intent(inout) :: ct
        !> (explicit shape, as gather_nodes')
        real(wp), intent(in) :: v(3, *), dt
        logical, intent(in), optional :: own(:)
        logical :: every(0)
        integer :: i
        ! (mine: the model's nodes this rank takes; empty: every node)
        do i = 1, ct%n
            if (ct%ifc(i)%surf%nnode == 0) cycle
            if (present(own)) then
                call drift_one(ct%ifc(i), own)
            else
                call drift_one(ct%ifc(i), every)
            end if
        end do
    contains
        subroutine drift_one(it, mine)
            type(interface_t), intent(inout) :: it
            logical, intent(in) :: mine(:)
            real(wp) :: vmax, vbar(3)
            real(dp) :: red(1), sc
            real(dp), allocatable :: rc(:)
            integer(i8) :: isum(3)
            integer :: k, nw
            ! owned nodes: the passes over this rank's own surface nodes
            ! alone, by their places (each pass over every surface node
            ! with a mask did not shrink with the ranks: 3 passes and one a
            ! margin class, a cycle); the same maximum, exact sum and
            ! maxima as the masked passes
            if (size(mine) > 0 .and. .not. allocated(it%drift_own)) then
                ! (loops: no temporary of the surface's size on the stack)
                nw = 0
                do k = 1, it%surf%nnode
                    if (mine(it%surf%node(k))) nw = nw + 1
                end do
                allocate (it%drift_own(nw))
                nw = 0
                do k = 1, it%surf%nnode
                    if (.not. mine(it%surf%node(k))) cycle
                    nw = nw + 1
                    it%drift_own(nw) = k
                end do
            end if
            nw = it%surf%nnode
            if (size(mine) > 0) nw = size(it%drift_own)
            ! (a parallel region only where more than one thread runs it:
            ! xd_core_threads)
            vmax = 0
            if (threaded(nw)) then
                !$omp parallel
                call drift_max(it, v, vmax)
                !$omp end parallel
            else
                call drift_max(it, v, vmax)
            end if
            if (present(own)) then
                red = vmax
                call comm_max(red)
                vmax = real(red(1), wp)
            end if
            ! the fixed-point scale: the sum of nnode terms of at most
            ! sqrt(vmax) each stays below 2^61
            sc = 0
            if (vmax > 0.0_wp) sc = scale(1.0_dp, 61 - exponent(real(it%surf%nnode, dp)*sqrt(real(vmax, dp))))
            isum = 0
            if (threaded(nw)) then
                !$omp parallel
                call drift_sum(it, v, sc, isum)
                !$omp end parallel
            else
                call drift_sum(it, v, sc, isum)
            end if
            if (present(own)) call comm_sum_i8(isum)
            vbar = 0
            if (sc > 0.0_dp) vbar = real(real(isum, dp)/sc/it%surf%nnode, wp)
            it%cused = 0
            if (threaded(nw)) then
                !$omp parallel
                call drift_use(it, v, dt, vbar)
                !$omp end parallel
            else
                call drift_use(it, v, dt, vbar)
            end if
            if (present(own)) then
                rc = it%cused
                call comm_max(rc)
                it%cused = real(rc, wp)
            end if
            it%odo = it%odo + dt*sqrt(vmax)
        end subroutine drift_one
    end subroutine contact_drift

    !> contact_drift's passes on interface it, as worksharing loops (each
    !> thread of a region calls them; outside one, the loops run whole):
    !> the largest speed squared of the nodes taken (owned nodes: the
    !> rank's own surface nodes, it%drift_own; else every surface node), ...
    subroutine drift_max(it, v, vmax)
        type(interface_t), intent(in) :: it
        real(wp), intent(in) :: v(3, *)
        real(wp), intent(inout) :: vmax
        integer :: k, n, j
        if (allocated(it%drift_own)) then
            ! (this rank's own surface nodes: contact_drift's list)
            !$omp do schedule(static) reduction(max:vmax)
            do j = 1, size(it%drift_own)
                n = it%surf%node(it%drift_own(j))
                vmax = max(vmax, v(1, n)**2 + v(2, n)**2 + v(3, n)**2)
            end do
            !$omp end do
            return
        end if
        !$omp do schedule(static) reduction(max:vmax)
        do k = 1, it%surf%nnode
            n = it%surf%node(k)
            vmax = max(vmax, v(1, n)**2 + v(2, n)**2 + v(3, n)**2)
        end do
        !$omp end do
    end subroutine drift_max

    !> ... their velocities' fixed-point sum at scale sc (each term truncated
    !> toward zero, one instruction that vectorises; the sum exact: any
    !> order) ...
    subroutine drift_sum(it, v, sc, isum)
        type(interface_t), intent(in) :: it
        real(wp), intent(in) :: v(3, *)
        real(dp), intent(in) :: sc
        integer(i8), intent(inout) :: isum(3)
        integer(i8) :: s1, s2, s3
        integer :: k, n, j, nw
        logical :: all
        all = .not. allocated(it%drift_own)
        s1 = 0
        s2 = 0
        s3 = 0
        nw = it%surf%nnode
        if (.not. all) nw = size(it%drift_own)
        !$omp do schedule(static)
        do j = 1, nw
            k = j
            if (.not. all) k = it%drift_own(j)
            n = it%surf%node(k)
            s1 = s1 + int(real(v(1, n), dp)*sc, i8)
            s2 = s2 + int(real(v(2, n), dp)*sc, i8)
            s3 = s3 + int(real(v(3, n), dp)*sc, i8)
        end do
        !$omp end do nowait
        !$omp atomic
        isum(1) = isum(1) + s1
        !$omp atomic
        isum(2) = isum(2) + s2
        !$omp atomic
        isum(3) = isum(3) + s3
        !$omp barrier
    end subroutine drift_sum

    !> ... and u_i += dt |v_i - vbar| with each class's margin used (it%cused,
    !> zero on entry: a maximum, each thread's taken in); a loop for u, then
    !> one a class, each without a mask where every node is taken (they
    !> vectorise).
    subroutine drift_use(it, v, dt, vbar)
        type(interface_t), intent(inout) :: it
        real(wp), intent(in) :: v(3, *), dt, vbar(3)
        integer :: k, n, c, j
        real(wp) :: vk, used
        if (.not. allocated(it%drift_own)) then
            !$omp do schedule(static)
            do k = 1, it%surf%nnode
                n = it%surf%node(k)
                vk = sqrt((v(1, n) - vbar(1))**2 + (v(2, n) - vbar(2))**2 + (v(3, n) - vbar(3))**2)
                it%un(k) = it%un(k) + dt*vk
            end do
            !$omp end do
            do c = 1, size(it%cmin)
                used = 0
                !$omp do schedule(static)
                do k = 1, it%surf%nnode
                    used = max(used, (it%un(k) - it%uc(k, c))*it%cbud(k, c))
                end do
                !$omp end do nowait
                !$omp critical (drift_used)
                it%cused(c) = max(it%cused(c), used)
                !$omp end critical (drift_used)
            end do
        else
            ! (this rank's own surface nodes: contact_drift's list)
            !$omp do schedule(static)
            do j = 1, size(it%drift_own)
                k = it%drift_own(j)
                n = it%surf%node(k)
                vk = sqrt((v(1, n) - vbar(1))**2 + (v(2, n) - vbar(2))**2 + (v(3, n) - vbar(3))**2)
                it%un(k) = it%un(k) + dt*vk
            end do
            !$omp end do
            do c = 1, size(it%cmin)
                used = 0
                !$omp do schedule(static)
                do j = 1, size(it%drift_own)
                    k = it%drift_own(j)
                    used = max(used, (it%un(k) - it%uc(k, c))*it%cbud(k, c))
                end do
                !$omp end do nowait
                !$omp critical (drift_used)
                it%cused(c) = max(it%cused(c), used)
                !$omp end critical (drift_used)
            end do
        end if
        !$omp barrier
    end subroutine drift_use

    !> Owned nodes: each surface node's motion bound u_i and the classes'
    !> copies of it from the node's rank (own: the model's nodes this rank
    !> integrates) to every rank, before a dump writes them (each value has
    !> one contributing rank, the others add zero: exact).
    subroutine gather_drift(ct, own)
        type(contacts_t), intent(inout) :: ct
        logical, intent(in) :: own(:)
        integer :: i, c
        do i = 1, ct%n
            associate (it => ct%ifc(i))
                if (it%surf%nnode == 0) cycle
                where (.not. own(it%surf%node)) it%un = 0
                call comm_sum_wp(it%un, size(it%un))
                do c = 1, size(it%uc, 2)
                    where (.not. own(it%surf%node)) it%uc(:, c) = 0
                    call comm_sum_wp(it%uc(:, c), size(it%un))
                end do
            end associate
        end do
    end subroutine gather_drift

    !> One block per dumped slave: header line, then one line per master node.
    subroutine dump_lists(u, it, node_id, cycle, time)
        integer, intent(in) :: u, cycle
        type(interface_t), intent(in) :: it
        integer, intent(in) :: node_id(:)
        real(dp), intent(in) :: time
        integer :: k, j, sl, sn, m
        character(len=1) :: tag
        do k = 1, size(it%dump)
            sn = it%surf%slave(it%dump(k))
            ! (the lists of a slave searched here: another rank's are not held)
            sl = list_row(it%lists, it%dump(k))
            if (sl == 0) cycle
            write (u, '(a,i0,a,i0,a,i0,a,es16.8,a,i0,a,3es16.8,a,i0)') 'search ', it%nsearch, ' interface ', it%id, &
                ' cycle ', cycle, ' time ', time, ' slave ', node_id(it%surf%node(sn)), ' at ', it%xl(:, sn), &
                ' masters ', it%lists%last(sl) - it%lists%ptr(sl) + 1
            do j = it%lists%ptr(sl), it%lists%last(sl)
                m = it%lists%node(j)
                tag = 'N'
                if (it%lists%trackable(j)) tag = 'T'
                write (u, '(2x,i0,1x,a,es16.8)') node_id(it%surf%node(m)), tag, norm2(it%xl(:, m) - it%xl(:, sn))
            end do
        end do
        flush (u)
    end subroutine dump_lists

    !> Nodal masses of the surface nodes, the per-slave state, and the
    !> step of the contact springs: a node of mass m between equal masses
    !> on springs of total stiffness k_t is stable for dt < 2 sqrt(m /
    !> (2 k_t)); a surface node carries its own spring as a slave and the
    !> springs of the slaves on its segments as a master, k_t about 2 k:
    !> dt < sqrt(m / k). Stable is not enough: a contact resolved in two
    !> or three steps (omega dt = 1.3 at that bound) gains or loses up to
    !> the whole impact energy in the central difference's onset and
    !> release (a 1 mm shell plate at SLSFAC 1 left its impact with 135%
    !> more energy), so the step is held to omega dt <= 0.5, omega =
    !> sqrt(2 k / m): dt < 0.35 sqrt(m / k) (contact_step_scale). Under the
    !> Lagrangian projection there are no springs and no bound (issue 28),
    !> except on an interface with shell edge pairs (their penalty springs).
    !> The slaves' contact state that the slave's rank alone reads is
    !> allocated for every slave (contact_slave_rows), or with `rows_later`
    !> left to the caller's contact_slave_rows once the rank's slaves are
    !> chosen (the initial penetrations' passes: their block's rows, without
    !> every slave's arrays first).
    subroutine contact_masses(ct, mass, rows_later)
        type(contacts_t), intent(inout) :: ct
        real(wp), intent(in) :: mass(:)
        logical, intent(in), optional :: rows_later
        integer :: i, k, n
        logical :: later
        later = .false.
        if (present(rows_later)) later = rows_later
        do i = 1, ct%n
            associate (it => ct%ifc(i), s => ct%ifc(i)%surf)
                it%ms = mass(s%node)
                n = s%nslave
                ! (the pairs' list starts with room for 1,024 and grows with
                ! the count: list_loops)
                allocate (it%pair(min(n, 1024)), it%fpair(3, min(n, 1024)))
                allocate (it%owned(n), it%evk(n), it%evd(n), it%ev(16), it%found(n))
                allocate (it%rseg(n), it%orow(n), it%hrow(n))
                it%own_rows = .false.
                it%orow = 0
                it%hrow = 0
                it%rseg = 0
                it%found = .false.
                it%evk = ev_none
                it%evd = 0
                it%owned = .true.
                it%mine = where_true(it%live)
                allocate (it%ls%xl(3, s%nnode), it%ls%vl(3, s%nnode))
                ! (the characteristic lengths the searches take, none yet)
                allocate (it%ls%lc(s%nnode), it%ls%lcodo(s%nnode))
                it%ls%lc = 0
                it%ls%lcodo = 0
                ! the Lagrangian projection has no springs to bound (the edge
                ! pairs of AUTOMATIC_GENERAL keep theirs)
                if (ct%lagrange .and. it%ed%ne == 0) cycle
                call spring_step(ct, it, [(.true., k=1, s%nnode)])
            end associate
        end do
        if (.not. later) call contact_slave_rows(ct, .false.)
    end subroutine contact_masses

    !> The slaves' contact state that only the slave's rank reads (cseg,
    !> held, fprev, ft, p0, kp, aeff, rdep, deep, rlast) and their contacts
    !> found (hit, fk), in n rows, cleared.
    subroutine slave_rows_alloc(it, n)
        type(interface_t), intent(inout) :: it
        integer, intent(in) :: n
        allocate (it%cseg(n), it%fprev(3, n), it%ft(3, n), it%hit(n), it%p0(n), it%kp(n), it%aeff(n), it%fk(3, n))
        allocate (it%rdep(n), it%rlast(n), it%deep(n), it%held(n))
        it%cseg = 0
        it%held = 0
        it%deep = 0
        it%rdep = 0
        it%rlast = 0
        it%kp = 0
        it%aeff = 0
        it%fk = 0
        it%p0 = 0
        it%fprev = 0
        it%ft = 0
    end subroutine slave_rows_alloc

    !> The contact's stable step lowered to 0.35 sqrt(m / k) of the nodes
    !> `at` of interface it (their spring as slave and master, a node on
    !> rigid parts left out), and the node that sets it.
    subroutine spring_step(ct, it, at)
        type(contacts_t), intent(inout) :: ct
        type(interface_t), intent(in) :: it
        logical, intent(in) :: at(:)
        integer :: k
        real(wp) :: dtk
        associate (s => it%surf)
            do k = 1, s%nnode
                if (.not. at(k) .or. s%node_k(k) <= 0.0_wp .or. it%ms(k) <= 0.0_wp .or. s%node_rigid(k)) cycle
                dtk = contact_step_scale*sqrt(it%ms(k)/s%node_k(k))
                if (dtk < ct%dt_limit) then
                    ct%dt_limit = dtk
                    ct%dt_node = s%node(k)
                end if
            end do
        end associate
    end subroutine spring_step

    !> Step 3 on x(n) with v(n-1/2): each slave's contact this cycle
    !> (slaves are independent of each other).
    subroutine contact_local_search(ct, x, v, time, dt, own)
        type(contacts_t), intent(inout) :: ct
        real(wp), intent(in) :: x(:, :), v(:, :), dt
        real(dp), intent(in) :: time
        !> owned nodes under MPI: the model's nodes this rank integrates (the
        !> largest speed is then each rank's own surface nodes' maximum,
        !> taken over the ranks: what one rank taking them all finds)
        logical, intent(in), optional :: own(:)
        logical :: every(0)
        integer :: i
        real(wp) :: v2
        real(dp) :: red(1)
        do i = 1, ct%n
            associate (it => ct%ifc(i), s => ct%ifc(i)%surf)
                it%active = time >= it%bt .and. time <= it%dt
                if (.not. it%active) then
                    it%regather = .true.
                    cycle
                end if
                if (present(own)) then
                    if (allocated(it%fresh) .and. .not. it%regather) then
                        ! (the other surface nodes are as the last gather left
                        ! them: its max speed the same, taken over own nodes)
                        call gather_nodes(x, v, s%node, it%ls%xl, it%ls%vl, v2, own, it%fresh)
                    else
                        call gather_nodes(x, v, s%node, it%ls%xl, it%ls%vl, v2, own)
                        it%regather = .false.
                    end if
                    red = v2
                    call comm_max(red)
                    v2 = real(red(1), wp)
                else
                    call gather_nodes(x, v, s%node, it%ls%xl, it%ls%vl, v2, every)
                end if
                ! Lagrangian projection: pairs that one step's approach (two
                ! nodes at the largest speed) could close are found before
                ! they touch, so that none penetrates (section 6)
                ! Penalty: pairs within half a step's approach of touching
                ! (a node at the largest speed against a segment at it: dt
                ! v_max) are found too, so that the spring's onset is swept
                ! over the step (penalty_force)
                if (ct%lagrange) then
                    it%ls%lead = 2.0_wp*dt*sqrt(v2)
                else
                    it%ls%lead = dt*sqrt(v2)
                end if
                ! a master surface lies up to t_c off its segment (and the
                ! segments may have stretched since their lengths were taken:
                ! local_search_t%lcodo)
                it%ls%grow = it%reach + it%ls%lead
                it%ls%dt = dt
                it%ls%odo = it%odo
                it%ls%first = .not. it%started
                if (it%cl%search /= it%nsearch .and. allocated(it%lists%gap)) &
                    call reset_clearance(s, it%lists, it%nsearch, it%cl, it%owned)
                ! (the slaves' depths last cycle, aeff + p0, taken per slave in
                ! find_contacts: as an array expression here they were a
                ! temporary of every slave built serially each cycle)
                call find_contacts(s, it%lists, it%ls, it%cl, it%cseg, it%held, it%fprev, it%aeff, ct%sw, &
                                   it%mine, it%hit, it%found, it%xl, it%rseg, it%rdep, it%p0, it%deep, it%nnear, &
                                   it%nnear_full, it%orow)
            end associate
        end do
    end subroutine contact_local_search

    !> The surface's coordinates (nodes `node` of x), threaded.
    subroutine gather_x(x, node, xl)
        real(wp), intent(in) :: x(:, :)
        integer, intent(in) :: node(:)
        real(wp), intent(out) :: xl(:, :)
        ! (a parallel region only where more than one thread runs it:
        ! xd_core_threads)
        if (threaded(size(node))) then
            !$omp parallel
            call gather_x_loop(x, node, xl)
            !$omp end parallel
        else
            call gather_x_loop(x, node, xl)
        end if
    end subroutine gather_x

    subroutine gather_x_loop(x, node, xl)
        real(wp), intent(in) :: x(:, :)
        integer, intent(in) :: node(:)
        real(wp), intent(inout) :: xl(:, :)
        integer :: k
        !$omp do schedule(static)
        do k = 1, size(node)
            xl(:, k) = x(:, node(k))
        end do
        !$omp end do
    end subroutine gather_x_loop

    !> The surface's coordinates and velocities (nodes `node` of x and v),
    !> and the largest speed squared (threaded: a maximum is the same in
    !> any order) of the nodes n with mine(n) true (indexed by the model's
    !> nodes; empty: every node). With `only`: those places of node alone
    !> (the others' xl and vl left as they are).
    subroutine gather_nodes(x, v, node, xl, vl, v2, mine, only)
        !> (explicit shape: a node's address one multiply, no descriptor)
        real(wp), intent(in) :: x(3, *), v(3, *)
        integer, intent(in) :: node(:)
        real(wp), intent(inout) :: xl(3, *), vl(3, *)
        real(wp), intent(out) :: v2
        logical, intent(in) :: mine(:)
        integer, intent(in), optional :: only(:)
        integer :: nk
        v2 = 0
        nk = size(node)
        if (present(only)) nk = size(only)
        if (threaded(nk)) then
            !$omp parallel
            call gather_nodes_loop(x, v, node, xl, vl, v2, mine, nk, only)
            !$omp end parallel
        else
            call gather_nodes_loop(x, v, node, xl, vl, v2, mine, nk, only)
        end if
    end subroutine gather_nodes

    subroutine gather_nodes_loop(x, v, node, xl, vl, v2, mine, nk, only)
        real(wp), intent(in) :: x(3, *), v(3, *)
        integer, intent(in) :: node(:), nk
        real(wp), intent(inout) :: xl(3, *), vl(3, *), v2
        logical, intent(in) :: mine(:)
        integer, intent(in), optional :: only(:)
        integer :: i, k, n
        logical :: every
        every = size(mine) == 0
        !$omp do schedule(static) reduction(max:v2)
        do i = 1, nk
            k = i
            if (present(only)) k = only(i)
            n = node(k)
            xl(1, k) = x(1, n)
            xl(2, k) = x(2, n)
            xl(3, k) = x(3, n)
            vl(1, k) = v(1, n)
            vl(2, k) = v(2, n)
            vl(3, k) = v(3, n)
            if (every) then
                v2 = max(v2, v(1, n)**2 + v(2, n)**2 + v(3, n)**2)
            else if (mine(n)) then
                v2 = max(v2, v(1, n)**2 + v(2, n)**2 + v(3, n)**2)
            end if
        end do
        !$omp end do
    end subroutine gather_nodes_loop

    !> The local search of every slave, threaded: a slave's search reads the
    !> surface and writes only its own hit and clearance. A slave not in
    !> contact last cycle whose clearance bound (clearance_t) exceeds what
    !> the motion since can have closed has no contact: its search is
    !> skipped (the screens' switch turns this off too). The closure is at
    !> most the slave's own displacement since the bound was taken plus the
    !> growth of u since (any point of a segment) plus twice the lead. Where
    !> the bound does not suffice, it is taken afresh at this cycle's
    !> positions (fresh_clearance); only if that leaves no clearance does the
    !> slave's search run. A slave so found close is searched without a
    !> fresh bound for the next `back_off` cycles (its clearance would rarely
    !> have grown).
    subroutine find_contacts(s, lists, ls, cl, cseg, held, fprev, aeff, sw, mine, hit, found, xs, rseg, rdep, allow, &
                             deep, nnear, nnear_full, orow)
        type(surface_t), intent(in) :: s
        type(master_lists_t), intent(in) :: lists
        type(local_search_t), intent(in) :: ls
        type(clearance_t), intent(inout) :: cl
        integer, intent(in) :: cseg(:)
        integer, intent(in) :: held(:)       !< per slave: the segment it held last (0: none)
        real(wp), intent(in) :: fprev(:, :)
        !> per slave: its depth last cycle less its allowance (the depth is
        !> aeff + allow)
        real(wp), intent(in) :: aeff(:)
        type(search_switches_t), intent(in) :: sw
        integer, intent(in) :: mine(:)
        type(pair_hit_t), intent(inout) :: hit(:)
        logical, intent(inout) :: found(:)
        real(wp), intent(in) :: xs(:, :)     !< surface coordinates at the last search
        integer, intent(inout) :: rseg(:)    !< per slave: deepest refused segment (0: none)
        real(wp), intent(inout) :: rdep(:)
        real(wp), intent(in) :: allow(:)     !< per slave: its allowance (initial or missed penetration)
        real(wp), intent(inout) :: deep(:)   !< per slave: the depth of a contact dropped beyond PENMAX (0: none)
        !> slave-cycles checked by their near sets alone, and of them those
        !> searched in full after (added to)
        integer(i8), intent(inout) :: nnear, nnear_full
        !> per slave: its row in cseg, held, fprev, aeff, rdep, allow and
        !> deep (the rank's own slaves' rows, slave_rows; k itself where
        !> they are every slave's)
        integer, intent(in) :: orow(:)
        integer, parameter :: back_off = 8
        integer(i8) :: nn, nf
        integer :: nc
        logical :: clean
        integer :: i, k, r, o
        logical :: clear_skip, refresh
        type(hit_t) :: hk
        clear_skip = sw%screens .and. cl%search >= 0
        refresh = clear_skip .and. allocated(lists%pool_ptr)
        if (refresh) refresh = size(lists%pool_ptr) == list_rows(lists, s%nslave)
        nn = 0
        nf = 0
        ! (the counts in the loop's own text: a reduction's variable must
        ! not be reached through the host from a procedure it calls)
        !$omp parallel do schedule(dynamic, 64) default(shared) private(i, k, r, o, nc, clean, hk) reduction(+:nn, nf)
        do i = 1, size(mine)
            k = mine(i)
            o = orow(k)
            ! (the slave's clearance row: mine are this rank's own, which
            ! hold one, clearance_t)
            r = 0
            if (clear_skip) r = cl%row(k)
            if (clear_skip .and. cseg(o) == 0) then
                ! the common case in line: clear on the growth of u alone,
                ! no near set, and nothing to reset (as clear and no_contact)
                if (cl%nnear(r) == 0) then
                    if (cl%g(r) > 2.0_wp*(ls%odo - cl%u(r)) + 2.0_wp*ls%lead) then
                        if (found(k) .or. rseg(k) /= 0 .or. deep(o) /= 0.0_wp) call no_contact(k, o)
                        cycle
                    end if
                end if
                ! clear on the bound kept, or on one taken afresh: only the
                ! near set (if any) can then hold a contact
                clean = clear(k, r)
                ! (a slave without a pool, read back from a restart dump and
                ! not searched since, takes no fresh clearance)
                if (.not. clean .and. refresh .and. &
                    lists%pool_last(list_row(lists, k)) >= lists%pool_ptr(list_row(lists, k)) - 1) then
                    if (cl%wait(r) == 0) then
                        cl%g(r) = fresh_clearance(s, lists, ls, k, cl%near(:, r), cl%nnear(r))
                        cl%x(:, r) = ls%xl(:, s%slave(k))
                        cl%u(r) = ls%odo
                        clean = cl%g(r) > 2.0_wp*ls%lead
                        if (.not. clean) cl%wait(r) = back_off
                    else
                        cl%wait(r) = cl%wait(r) - 1
                    end if
                end if
                if (clean) then
                    clean = near_clear(k, r, o, nc)
                    nn = nn + nc
                    if (clean) then
                        call no_contact(k, o)
                        cycle
                    end if
                    nf = nf + nc
                end if
            end if
            call find_contact(s, lists, ls, k, cseg(o), fprev(:, o), aeff(o) + allow(o), sw, hk, xs, rseg(k), rdep(o), &
                              allow(o), deep(o), held(o))
            hit(o) = kept(hk)
            found(k) = hk%found
        end do
        !$omp end parallel do
        nnear = nnear + nn
        nnear_full = nnear_full + nf
    contains
        !> Slave k's clearance bound exceeds what the motion can have closed
        !> since it was taken. Its own displacement is at most the growth of
        !> u: most slaves are clear on that alone, without reading their
        !> positions.
        logical function clear(k, r)
            integer, intent(in) :: k, r   !< the slave, its clearance row
            real(wp) :: du
            du = ls%odo - cl%u(r)
            clear = cl%g(r) > 2.0_wp*du + 2.0_wp*ls%lead
            if (clear) return
            clear = cl%g(r) > norm2(ls%xl(:, s%slave(k)) - cl%x(:, r)) + du + 2.0_wp*ls%lead
        end function clear

        !> Slave k's near set (clearance_t) holds no contact: none, or the
        !> check of its segments alone finds none and refuses none.
        logical function near_clear(k, r, o, checked)
            integer, intent(in) :: k, r, o   !< the slave, its clearance row, its row (orow)
            integer, intent(out) :: checked   !< 1 if there was a near set to check, else 0
            type(hit_t) :: h
            integer :: rs
            real(wp) :: rd, dp_
            logical :: effect
            near_clear = .true.
            checked = 0
            if (cl%nnear(r) == 0) return
            checked = 1
            call find_contact(s, lists, ls, k, 0, fprev(:, o), aeff(o) + allow(o), sw, h, xs, rs, rd, allow(o), dp_, held(o), &
                              near=cl%near(1:cl%nnear(r), r), near_effect=effect)
            near_clear = .not. effect
        end function near_clear

        !> (A slave already without contact keeps its record untouched.)
        subroutine no_contact(k, o)
            integer, intent(in) :: k, o   !< the slave, its row (orow)
            if (rseg(k) /= 0) rseg(k) = 0
            if (deep(o) /= 0.0_wp) deep(o) = 0
            if (.not. found(k)) return
            hit(o)%found = .false.
            hit(o)%level = 4
            found(k) = .false.
        end subroutine no_contact
    end subroutine find_contacts

    !> Step 4: penalty forces of the contacts found, added to f on the slave
    !> and (by the shape functions) the master nodes in slave order, so the
    !> sums do not depend on threads; the first half of their work.
    subroutine contact_enforce(ct, f, dt, dt_avg, mass, dofs, time, outputs, sums, br)
        type(contacts_t), intent(inout) :: ct
        real(wp), intent(inout) :: f(:, :)
        real(wp), intent(in) :: dt, dt_avg
        real(wp), intent(in) :: mass(:)
        integer(int8), intent(in) :: dofs(:)   !< per node, its free directions (xd_core_dofs)
        real(dp), intent(in) :: time
        !> the outputs read this cycle's contact forces (ct%fnode): every
        !> pair's applied (else, with ct%moves, those of other ranks' slaves
        !> away from this rank's nodes are not)
        logical, intent(in) :: outputs
        !> rcforc reads this cycle's sums over every pair (it%fslave ...):
        !> every rank takes every contact found (else, with ct%rank_of, each
        !> contact only goes to its nodes' ranks)
        logical, intent(in) :: sums
        !> Lagrangian projection: how the rigid bodies answer an impulse
        !> (where the model has any)
        type(body_response_t), intent(in), optional :: br
        integer :: i, k, j, sn, m, q, o, h
        real(wp) :: vrel(3), fs(3)
        real(dp) :: t0
        logical :: first, some
        ! the contact forces per node (fnode) only on a cycle whose outputs
        ! read them: allocated at the first, where the deck writes any; every
        ! other column zero (the nodes written at the last such cycle zeroed)
        if (outputs) then
            if (.not. allocated(ct%fnode)) then
                allocate (ct%fnode(3, size(f, 2)))
                ct%fnode = 0
            end if
            do q = 1, ct%nftouch
                ct%fnode(:, ct%ftouch(q)) = 0
            end do
            ct%nftouch = 0
        end if
        do i = 1, ct%n
            associate (it => ct%ifc(i), s => ct%ifc(i)%surf)
                it%npair = 0
                it%pminus = 0
                it%fslave = 0
                it%fmaster = 0
                it%mslave = 0
                it%mmaster = 0
                if (.not. it%active) then
                    it%cseg = 0
                    it%fprev = 0
                    it%ft = 0
                    it%kp = 0
                    cycle
                end if
                ! penalty forces (Eq. 12) with damping and friction, per slave
                ! (threaded: each writes only its own entries), then listed as
                ! pairs in slave order
                first = .not. it%started
                if (threaded(size(it%mine))) then
                    !$omp parallel
                    call slave_forces(it, s, dt)
                    !$omp end parallel
                else
                    call slave_forces(it, s, dt)
                end if
                it%started = .true.
                ! MPI: the contacts the other ranks' slaves found
                if (ct%distributed) then
                    t0 = wtime()
                    call gather_contacts(it, ct, allocated(ct%rank_of) .and. .not. (outputs .or. sums))
                    ct%wall_gather = ct%wall_gather + (wtime() - t0)
                end if
                call list_pairs(it, s%nslave, time)
                if (ct%lagrange .and. it%npair > 0) call lagrange_projection(s, it%npair, it%pair, it%hit, it%fpair, &
                                                                      it%ls%xl, it%ls%vl, it%fr, f, mass, dofs, dt, &
                                                                      dt_avg, br)
                if (outputs) call grow(ct%ftouch, ct%nftouch + 5*it%npair + 4*it%ed%nact, 'contact force nodes')
                ! both sides, in slave order (a deterministic sum)
                ct%npair_all = ct%npair_all + it%npair
                do q = 1, it%npair
                    k = it%pair(q)
                    sn = s%slave(k)
                    h = it%hrow(k)
                    m = it%hit(h)%seg
                    fs = it%fpair(:, q)
                    ! (the slave's contact state where its rank's rows hold
                    ! it: every slave's, or this rank's own)
                    o = it%orow(k)
                    if (o > 0) then
                        it%cseg(o) = m
                        it%held(o) = m
                        it%fprev(:, o) = fs
                    end if
                    ! (rcforc's sums: every pair)
                    it%fslave = it%fslave + fs
                    it%fmaster = it%fmaster - fs
                    it%mslave = it%mslave + it%ms(sn)
                    it%mmaster = it%mmaster + dot_product(it%hit(h)%nshape, it%ms(s%seg(:, m)))
                    if (allocated(ct%moves) .and. .not. outputs .and. .not. it%owned(k)) then
                        ! another rank's slave: its forces only where they
                        ! reach a node this rank moves (every such node's
                        ! sum takes every pair, in the same order)
                        some = ct%moves(s%node(sn))
                        do j = 1, seg_nodes(s%seg(:, m))
                            some = some .or. ct%moves(s%node(s%seg(j, m)))
                        end do
                        if (.not. some) cycle
                    end if
                    ct%npair_applied = ct%npair_applied + 1
                    vrel = it%ls%vl(:, sn) - matmul(it%ls%vl(:, s%seg(:, m)), it%hit(h)%nshape)
                    f(:, s%node(sn)) = f(:, s%node(sn)) + fs
                    do j = 1, seg_nodes(s%seg(:, m))
                        f(:, s%node(s%seg(j, m))) = f(:, s%node(s%seg(j, m))) - it%hit(h)%nshape(j)*fs
                    end do
                    if (outputs) then
                        ct%fnode(:, s%node(sn)) = ct%fnode(:, s%node(sn)) + fs
                        ct%nftouch = ct%nftouch + 1
                        ct%ftouch(ct%nftouch) = s%node(sn)
                        do j = 1, seg_nodes(s%seg(:, m))
                            ct%fnode(:, s%node(s%seg(j, m))) = ct%fnode(:, s%node(s%seg(j, m))) - &
                                                               it%hit(h)%nshape(j)*fs
                            ct%nftouch = ct%nftouch + 1
                            ct%ftouch(ct%nftouch) = s%node(s%seg(j, m))
                        end do
                    end if
                    if (.not. ct%own_work .or. it%owned(k)) &
                        it%pminus = it%pminus + dot_product(real(fs, dp), real(vrel, dp))
                end do
                it%ncontact_total = it%ncontact_total + it%npair
                if (it%ed%np > 0) call edge_enforce(it, f, ct%fnode, dt, time, first, ct%ftouch, ct%nftouch, outputs)
            end associate
        end do
    end subroutine contact_enforce

    !> The penalty forces of interface it's own slaves (contact_enforce),
    !> as a worksharing loop: each slave writes only its own entries.
    subroutine slave_forces(it, s, dt)
        type(interface_t), intent(inout) :: it
        type(surface_t), intent(in) :: s
        real(wp), intent(in) :: dt
        integer :: i2, k, o
        !$omp do schedule(dynamic, 64)
        do i2 = 1, size(it%mine)
            k = it%mine(i2)
            o = it%orow(k)
            if (it%cseg(o) == 0 .and. .not. it%found(k)) then
                ! no contact then or now: its state is already clear
                if (it%evk(k) /= ev_none) it%evk(k) = ev_none
                if (it%rseg(k) /= it%rlast(o)) call refusal(it, k)
                cycle
            end if
            call slave_force(it, s, k, dt)
            if (it%evk(k) == ev_none .and. it%rseg(k) /= it%rlast(o)) call refusal(it, k)
        end do
        !$omp end do
    end subroutine slave_forces

    !> The cycle's events booked and its pairs listed, both in slave order:
    !> the slaves in chunks of a fixed size, each chunk's pairs counted and
    !> then written at its offset (threaded; the same list for any number
    !> of threads); the events (rare) one after the other. Under MPI, once
    !> a rank has exchanged contacts (it%got made), only its own live
    !> slaves and the other ranks' slaves the exchange brought can hold a
    !> contact or an event: those alone are scanned, in slave order (a scan
    !> of every slave each cycle was the same on every rank however many),
    !> where they are under a quarter of the slaves.
    subroutine list_pairs(it, nslave, time)
        type(interface_t), intent(inout) :: it
        integer, intent(in) :: nslave
        real(dp), intent(in) :: time
        integer :: nch, n
        integer, allocatable :: cnt(:), cand(:)
        logical, allocatable :: evc(:)
        logical :: some
        ! (where the rank's own slaves are a large share of them, a few
        ! ranks, the scan of every slave in order costs less than listing
        ! and reading the candidates: on 2 ranks of the 250,000-shell plate
        ! the candidates took 0.1 ms a cycle more)
        some = .false.
        if (allocated(it%got)) some = 4*(size(it%mine) + size(it%got)) < nslave
        n = nslave
        if (some) then
            call pair_candidates(it, cand)
            n = size(cand)
            it%ncand = it%ncand + 1
        else
            allocate (cand(0))
        end if
        nch = (n + pair_chunk - 1)/pair_chunk
        allocate (cnt(nch + 1), evc(nch))
        ! (a parallel region only where more than one thread runs it:
        ! xd_core_threads)
        if (threaded(n)) then
            !$omp parallel
            call list_loops(it, n, time, cnt, evc, some, cand)
            !$omp end parallel
        else
            call list_loops(it, n, time, cnt, evc, some, cand)
        end if
        it%npair = cnt(nch + 1)
    end subroutine list_pairs

    !> The slaves that can hold a contact or an event on this rank after an
    !> exchange, ascending: its own live slaves (mine, ascending) and the
    !> other ranks' slaves the exchange brought (got, in the order they came),
    !> merged.
    subroutine pair_candidates(it, cand)
        type(interface_t), intent(in) :: it
        integer, allocatable, intent(out) :: cand(:)
        integer, allocatable :: perm(:)
        integer :: i, j, c, ng, nm
        nm = size(it%mine)
        ng = size(it%got)
        allocate (cand(nm + ng))
        if (ng == 0) then
            cand = it%mine
            return
        end if
        call sort_index(it%got, perm)
        i = 1
        j = 1
        c = 0
        do while (i <= nm .or. j <= ng)
            c = c + 1
            if (j > ng) then
                cand(c) = it%mine(i)
                i = i + 1
            else if (i > nm) then
                cand(c) = it%got(perm(j))
                j = j + 1
            else if (it%mine(i) < it%got(perm(j))) then
                cand(c) = it%mine(i)
                i = i + 1
            else
                cand(c) = it%got(perm(j))
                j = j + 1
            end if
        end do
    end subroutine pair_candidates

    !> list_pairs' loops as worksharing loops (each thread of a region calls
    !> it; outside one they run whole), the events booked by one thread
    !> between them. cnt, evc: shared, per chunk of the n slaves scanned
    !> (every slave, or with `some` the slaves cand).
    subroutine list_loops(it, n, time, cnt, evc, some, cand)
        type(interface_t), intent(inout) :: it
        integer, intent(in) :: n
        real(dp), intent(in) :: time
        integer, intent(inout) :: cnt(:)
        logical, intent(inout) :: evc(:)
        logical, intent(in) :: some
        integer, intent(in) :: cand(:)
        integer :: nch, c, k, q, j
        nch = size(evc)
        !$omp do schedule(static)
        do c = 1, nch
            cnt(c + 1) = 0
            evc(c) = .false.
            ! (two loops: the scan of every slave in order stays a stream)
            if (some) then
                do j = (c - 1)*pair_chunk + 1, min(c*pair_chunk, n)
                    k = cand(j)
                    if (it%found(k)) cnt(c + 1) = cnt(c + 1) + 1
                    if (it%evk(k) /= ev_none) evc(c) = .true.
                end do
            else
                do k = (c - 1)*pair_chunk + 1, min(c*pair_chunk, n)
                    if (it%found(k)) cnt(c + 1) = cnt(c + 1) + 1
                    if (it%evk(k) /= ev_none) evc(c) = .true.
                end do
            end if
        end do
        !$omp end do
        !$omp single
        cnt(1) = 0
        do c = 1, nch
            cnt(c + 1) = cnt(c + 1) + cnt(c)
        end do
        ! (the pairs' room: grown to this cycle's count where short, by half
        ! again; their list is written whole each cycle)
        if (cnt(nch + 1) > size(it%pair)) then
            q = max(cnt(nch + 1), size(it%pair) + size(it%pair)/2)
            deallocate (it%pair, it%fpair)
            allocate (it%pair(q), it%fpair(3, q))
        end if
        do c = 1, nch
            if (.not. evc(c)) cycle
            do j = (c - 1)*pair_chunk + 1, min(c*pair_chunk, n)
                k = j
                if (some) k = cand(j)
                if (it%evk(k) /= ev_none) call add_event(it, k, time)
            end do
        end do
        !$omp end single
        !$omp do schedule(static)
        do c = 1, nch
            q = cnt(c)
            if (some) then
                do j = (c - 1)*pair_chunk + 1, min(c*pair_chunk, n)
                    k = cand(j)
                    if (.not. it%found(k)) cycle
                    q = q + 1
                    it%pair(q) = k
                    it%fpair(:, q) = it%fk(:, it%hrow(k))
                end do
            else
                do k = (c - 1)*pair_chunk + 1, min(c*pair_chunk, n)
                    if (.not. it%found(k)) cycle
                    q = q + 1
                    it%pair(q) = k
                    it%fpair(:, q) = it%fk(:, it%hrow(k))
                end do
            end if
        end do
        !$omp end do
    end subroutine list_loops

    !> Steps 3-4 for the pairs of exterior shell edges (AUTOMATIC_GENERAL):
    !> their penalty forces, spread linearly to each edge's two nodes (edge
    !> a, taken as the slave side, and edge b), added in pair order; every
    !> rank holds every pair (the edges are few), so the sums are the same
    !> on every rank. Penalty forces also under the Lagrangian projection,
    !> which is for slave nodes.
    subroutine edge_enforce(it, f, fnode, dt, time, first, touch, ntouch, outputs)
        type(interface_t), intent(inout) :: it
        real(wp), intent(inout) :: f(:, :)
        !> the contact forces per node, written where an output reads them
        !> (outputs; else not allocated, perhaps)
        real(wp), allocatable, intent(inout) :: fnode(:, :)
        !> the nodes fnode is written at (room made for 4 a pair)
        integer, allocatable, intent(inout) :: touch(:)
        integer, intent(inout) :: ntouch
        logical, intent(in) :: outputs
        real(wp), intent(in) :: dt
        real(dp), intent(in) :: time
        logical, intent(in) :: first      !< the interface's first active cycle
        integer :: j, q, nd(4)
        real(wp) :: w(4), fa(3), vrel(3), fw(3, 4)
        associate (ed => it%ed, s => it%surf)
            call edge_forces(ed, s, it%ls%xl, it%ls%vl, it%ms, it%fr, dt, time, first)
            do j = 1, ed%nact
                q = ed%act(j)
                call edge_weights(it, q, nd, w)
                fa = ed%fa(:, q)
                fw = spread(fa, 2, 4)*spread(w, 1, 3)
                f(:, s%node(nd)) = f(:, s%node(nd)) + fw
                if (outputs) then
                    fnode(:, s%node(nd)) = fnode(:, s%node(nd)) + fw
                    touch(ntouch + 1:ntouch + 4) = s%node(nd)
                    ntouch = ntouch + 4
                end if
                vrel = matmul(it%ls%vl(:, nd), w)
                it%pminus = it%pminus + dot_product(real(fa, dp), real(vrel, dp))
                it%fslave = it%fslave + fa
                it%fmaster = it%fmaster - fa
                it%mslave = it%mslave + dot_product(abs(w(1:2)), it%ms(nd(1:2)))
                it%mmaster = it%mmaster + dot_product(abs(w(3:4)), it%ms(nd(3:4)))
            end do
        end associate
    end subroutine edge_enforce

    !> Edge pair q's four nodes (edge a's two, edge b's two) and the signed
    !> weights of edge a's force on them: 1 - s, s, -(1 - t), -t.
    pure subroutine edge_weights(it, q, nd, w)
        type(interface_t), intent(in) :: it
        integer, intent(in) :: q
        integer, intent(out) :: nd(4)
        real(wp), intent(out) :: w(4)
        associate (ed => it%ed)
            nd = [ed%en(:, ed%pa(q)), ed%en(:, ed%pb(q))]
            w = [1.0_wp - ed%st(1, q), ed%st(1, q), -(1.0_wp - ed%st(2, q)), -ed%st(2, q)]
        end associate
    end subroutine edge_weights

    !> One slave's penalty force (Eq. 12) in it%fk(:, k), and its event.
    !>
    !> The spring (the softer of the master segment and the slave node,
    !> LS-DYNA's SOFT 0, per unit area, times the area the node covers
    !> facing the master) is set when a contact starts or moves to another
    !> segment, and kept while it stays (a stiffness that changed during a
    !> contact would not be conservative). A contact, new or moved, may be
    !> deeper than the slave's depth last cycle by twice this step's
    !> approach at most (the depth below a surface does not jump where a
    !> node crosses from one segment to the next); the excess of a deeper
    !> one, which did not come through that segment, is allowed and named
    !> in d3hsp, as the penetrations present at the first active cycle are
    !> (LS-DYNA's IGNORE = 1). An allowance shrinks as the node moves out.
    subroutine slave_force(it, s, k, dt)
        type(interface_t), intent(inout) :: it
        type(surface_t), intent(in) :: s
        integer, intent(in) :: k
        real(wp), intent(in) :: dt
        integer :: sn, m, o
        real(wp) :: kpen, vrel(3), mm, meff, reach
        sn = s%slave(k)
        ! (its row in the rank's slaves' contact state: orow)
        o = it%orow(k)
        it%evk(k) = ev_none
        if (.not. it%hit(o)%found) then
            if (it%cseg(o) /= 0) then
                ! lost: by separation, or released while deeper than the
                ! node's relative motion could undo in one step
                m = it%cseg(o)
                vrel = it%ls%vl(:, sn) - sum(it%ls%vl(:, s%seg(:, m)), 2)/4.0_wp
                if (it%deep(o) > 0.0_wp) then
                    ! beyond PENMAX times the thickness: released, passes
                    it%evk(k) = ev_penmax
                    it%evd(k) = it%deep(o)
                    it%hit(o)%seg = m
                else if (it%aeff(o) > 2.0_wp*dt*norm2(vrel) + 1.0e-3_wp*s%seg_t(m)) then
                    it%evk(k) = ev_released
                    it%evd(k) = it%aeff(o)
                    it%hit(o)%seg = m
                end if
            end if
            call forget_slave(it, k)
            return
        end if
        m = it%hit(o)%seg
        vrel = it%ls%vl(:, sn) - matmul(it%ls%vl(:, s%seg(:, m)), it%hit(o)%nshape)
        if (.not. it%started) then
            ! initial penetration: allowed, shrinking as the node moves out
            if (abs(it%hit(o)%a) > 0.0_wp) then
                it%p0(o) = abs(it%hit(o)%a)
                it%evk(k) = ev_initial
                it%evd(k) = it%p0(o)
            end if
        else if (it%cseg(o) /= m) then
            ! a new contact deeper than the node can have gone in one step,
            ! or a move to a segment where the depth jumps beyond the depth
            ! last cycle plus the step's approach: the node did not come
            ! through this segment (it slid in the plane of one face of a
            ! body into the window of the next face, or came through an
            ! edge where no node-to-segment check sees it). Pushing the
            ! whole depth out would add the spring energy k a^2 / 2; the
            ! excess is allowed like an initial penetration (shrinking as
            ! the node moves out) and named in d3hsp. Across a flat or
            ! convex surface the depth does not jump at a move, so a node
            ! handed between segments (aligned meshes) gets no allowance.
            ! The local search let such a contact through only where the
            ! slave came into the segment's zone since the last search (a
            ! missed contact). The allowance keeps the spring's compression
            ! where it was: the old allowance plus the excess (dropping the
            ! old allowance would push the node out by it at once, the
            ! spring energy k p0^2 / 2 created).
            ! A shell contact in a zone the node lay in at the search
            ! (within) is held where it is found: its compression stays
            ! last cycle's, without the step's approach (none to speak of:
            ! the node did not come in).
            reach = 2.0_wp*abs(dot_product(vrel, it%hit(o)%nhat))*dt + 1.0e-3_wp*it%hit(o)%tm
            if (it%hit(o)%within) reach = 0
            if (it%cseg(o) /= 0) reach = reach + it%aeff(o) + it%p0(o)
            if (abs(it%hit(o)%a) > reach) then
                ! (back under the segment it held last: named apart, the
                ! local search let it through without the came-in test)
                if (it%hit(o)%within) then
                    it%evk(k) = ev_within
                else
                    it%evk(k) = merge(ev_back, ev_late, m == it%held(o))
                end if
                it%evd(k) = abs(it%hit(o)%a) - reach
                it%p0(o) = it%p0(o) + it%evd(k)
            else if (it%cseg(o) /= 0 .and. .not. it%hit(o)%within) then
                call hand_over(it%cseg(o))
            end if
        end if
        if (it%cseg(o) /= m .or. it%kp(o) <= 0.0_wp) then
            kpen = slave_stiffness(s, it%ls%xl, sn, m, it%hit(o)%nhat*pdir(it%hit(o)%a))
            it%kp(o) = kpen
        else
            kpen = it%kp(o)
        end if
        if (it%p0(o) > 0.0_wp) then
            it%p0(o) = min(it%p0(o), abs(it%hit(o)%a))
            it%hit(o)%a = sign(abs(it%hit(o)%a) - it%p0(o), it%hit(o)%a)
        end if
        it%aeff(o) = abs(it%hit(o)%a)
        mm = dot_product(it%hit(o)%nshape, it%ms(s%seg(:, m)))
        meff = it%ms(sn)*mm/max(it%ms(sn) + mm, tiny(1.0_wp))
        ! the spring swept over the step where it starts at the surface; one
        ! under an allowance starts at the allowed depth, which follows the
        ! node out (no force there either side of it): taken at x(n)
        call penalty_force(it%hit(o), kpen, vrel, meff, it%fr, dt, it%ft(:, o), it%fk(:, o), &
                           swept=it%p0(o) <= 0.0_wp, start=.not. it%started)
    contains
        !> A move from segment mo to this one: the spring goes on from the
        !> depth the old segment's spring would have at the node's place now
        !> (its depth there less its allowance); where the new segment's
        !> depth exceeds it, the excess is allowed (shrinking as the node
        !> moves out) and named. Two segments measure depth differently where
        !> they meet (the tube of one edge, the interior of the next: 5.9 um
        !> against 3.4 um where the tube's path gave -0.4 um at a crossing of
        !> two edges), and a spring that jumps to the deeper measure pushes
        !> back more than the node's path brought in (0.19% of the impact
        !> energy created there, issue 28).
        subroutine hand_over(mo)
            integer, intent(in) :: mo
            type(hit_t) :: ho
            real(wp) :: pe, tn(4)
            call seg_thicknesses(s, mo, tn)
            call segment_check(it%ls%xl(:, s%seg(:, mo)), tn, s%seg_kind(mo) == seg_shell, &
                               it%ls%xl(:, sn), 0.5_wp*s%node_t(sn), ho)
            pe = 0
            if (ho%found) pe = max(0.0_wp, abs(ho%a) - it%p0(o))
            ! (round-off: a node handed to and fro between two segments at
            ! the same depth; within 1e-3 of the thickness, as the other
            ! rules take it, no allowance)
            if (abs(it%hit(o)%a) - it%p0(o) > pe + 1.0e-3_wp*it%hit(o)%tm) then
                it%evk(k) = ev_handover
                it%evd(k) = abs(it%hit(o)%a) - it%p0(o) - pe
                it%p0(o) = abs(it%hit(o)%a) - pe
            end if
        end subroutine hand_over
    end subroutine slave_force

    !> Slave k's deepest refused segment this cycle (rseg) differs from the
    !> one last named: named now (none: the record cleared).
    pure subroutine refusal(it, k)
        type(interface_t), intent(inout) :: it
        integer, intent(in) :: k
        integer :: o
        o = it%orow(k)
        it%rlast(o) = it%rseg(k)
        if (it%rseg(k) == 0) return
        it%evk(k) = ev_refused
        it%evd(k) = it%rdep(o)
    end subroutine refusal

    !> Slave k out of contact: its contact state cleared.
    pure subroutine forget_slave(it, k)
        type(interface_t), intent(inout) :: it
        integer, intent(in) :: k
        integer :: o
        o = it%orow(k)
        it%cseg(o) = 0
        it%fprev(:, o) = 0
        it%ft(:, o) = 0
        it%p0(o) = 0
        it%kp(o) = 0
        it%aeff(o) = 0
    end subroutine forget_slave

    !> Book slave k's event of this cycle: counted, the deepest kept, named
    !> in the list the log takes (initial penetrations all, the others up
    !> to max_named per interface).
    subroutine add_event(it, k, time)
        type(interface_t), intent(inout) :: it
        integer, intent(in) :: k
        real(dp), intent(in) :: time
        type(contact_event_t), allocatable :: tmp(:)
        logical :: named
        select case (it%evk(k))
        case (ev_initial)
            it%ninit = it%ninit + 1
            it%pinit = max(it%pinit, it%evd(k))
            named = .true.
        case (ev_late)
            call tally(it%nlate, it%plate)
        case (ev_back)
            call tally(it%nback, it%pback)
        case (ev_within)
            call tally(it%nwithin, it%pwithin)
        case (ev_handover)
            call tally(it%nhand, it%phand)
        case (ev_refused)
            call tally(it%nref, it%pref)
        case default
            call tally(it%nrel, it%prel)
        end select
        if (.not. named) return
        if (it%nev == size(it%ev)) then
            allocate (tmp(2*size(it%ev)))
            tmp(1:it%nev) = it%ev
            call move_alloc(tmp, it%ev)
        end if
        it%nev = it%nev + 1
        it%ev(it%nev) = contact_event_t(kind=it%evk(k), slave=it%surf%slave(k), &
                                        seg=merge(it%rseg(k), it%hit(it%hrow(k))%seg, it%evk(k) == ev_refused), &
                                        time=time, depth=it%evd(k))
    contains
        !> One more event of a kind counted (n), its depth kept if the
        !> deepest (p); named while the kind has max_named or fewer.
        subroutine tally(n, p)
            integer, intent(inout) :: n
            real(wp), intent(inout) :: p
            n = n + 1
            p = max(p, it%evd(k))
            named = n <= max_named
        end subroutine tally
    end subroutine add_event

    !> The events booked since the last call, one line each, for d3hsp (and
    !> the list emptied).
    function contact_events(ct, node_id) result(txt)
        type(contacts_t), intent(inout) :: ct
        integer, intent(in) :: node_id(:)
        character(len=:), allocatable :: txt
        character(len=240) :: buf
        character(len=80) :: what
        integer :: i, q, j, nd(4)
        txt = ''
        do i = 1, ct%n
            associate (it => ct%ifc(i), s => ct%ifc(i)%surf)
                do q = 1, it%nev
                    associate (e => it%ev(q))
                        select case (e%kind)
                        case (ev_initial); what = 'initial penetration (allowed)'
                        case (ev_late); what = 'missed contact (entered since the search) deeper than a step: excess allowed'
                        case (ev_refused); what = 'deep under a face it did not cross since the search: no contact'
                        case (ev_back); what = 'back under the segment it held last, deeper than a step: excess allowed'
                        case (ev_within); what = 'deep in a shell''s zone it lay in at the search: held at that depth'
                        case (ev_handover); what = 'moved to a segment deeper than the old one''s spring there: '// &
                                                   'excess allowed'
                        case (ev_penmax); what = 'contact released beyond PENMAX times the thickness'
                        case default; what = 'contact released deep'
                        end select
                        nd = 0
                        if (e%seg > 0) nd = node_id(s%node(s%seg(:, e%seg)))
                        write (buf, '(a,i0,a,es12.5,a,a,a,i0,a,4(1x,i0),a,es11.4)') '   interface ', it%id, ' t ', &
                            e%time, ': ', trim(what), ': node ', node_id(s%node(e%slave)), ', segment', &
                            (nd(j), j=1, 4), ', depth ', e%depth
                        if (len(txt) > 0) txt = txt//new_line('a')
                        txt = txt//trim(buf)
                    end associate
                end do
                it%nev = 0
                do q = 1, it%ed%nev
                    associate (e => it%ed%ev(q))
                        if (e%kind == edge_unknown) then
                            what = 'within reach with no side known: no edge contact until they part; distance'
                        else if (e%kind == edge_initial) then
                            what = 'initial edge penetration (allowed): depth'
                        else
                            what = 'edge contact found deeper than a step: excess allowed'
                        end if
                        write (buf, '(a,i0,a,es12.5,a,2(1x,i0),a,2(1x,i0),a,a,1x,es11.4)') '   interface ', it%id, &
                            ' t ', e%time, ': edges', node_id(s%node(e%node(1:2))), ' and', node_id(s%node(e%node(3:4))), &
                            ': ', trim(what), e%depth
                        if (len(txt) > 0) txt = txt//new_line('a')
                        txt = txt//trim(buf)
                    end associate
                end do
                it%ed%nev = 0
            end associate
        end do
    end function contact_events

    !> MPI: every rank's own slaves' contacts of this cycle (what the pair
    !> list, the nodal sums and the work need), so that every rank holds the
    !> hits and forces of all slaves; records in slave order per rank.
    subroutine gather_contacts(it, ct, p2p)
        type(interface_t), intent(inout) :: it
        type(contacts_t), intent(inout) :: ct
        !> each contact found only to the ranks that integrate its nodes
        !> (an event to every rank); else every contact to every rank
        logical, intent(in) :: p2p
        real(dp), allocatable :: mine(:, :), all(:, :)
        integer :: i, k, n, r
        ! (the compact found, not hit(k)%found: each slave's record is a
        ! cache line of its own, and these loops run every cycle)
        n = 0
        do i = 1, size(it%mine)
            k = it%mine(i)
            if (it%found(k) .or. it%evk(k) /= ev_none) n = n + 1
        end do
        ! (the Lagrangian projection reads the gap of a contact found ahead
        ! of touching: without it the other ranks' slaves were projected
        ! with a stale gap, and two ranks' Lagrangian runs parted from the
        ! serial one)
        allocate (mine(19, n))
        n = 0
        do i = 1, size(it%mine)
            k = it%mine(i)
            if (.not. (it%found(k) .or. it%evk(k) /= ev_none)) cycle
            n = n + 1
            associate (h => it%hit(it%orow(k)))
                mine(:, n) = [real(k, dp), real(h%seg, dp), real(h%kind, dp), real(h%a, dp), real(h%nshape, dp), &
                              real(h%nhat, dp), real(it%fk(:, it%orow(k)), dp), merge(1.0_dp, 0.0_dp, h%found), &
                              real(it%evk(k), dp), real(it%evd(k), dp), real(it%rseg(k), dp), real(h%gap, dp)]
            end associate
        end do
        if (p2p) then
            call send_contacts(it, ct, mine, all)
            ct%ncyc_p2p = ct%ncyc_p2p + 1
        else
            call comm_gather_records(mine, ct%nranks, all)
            ct%sent_all = ct%sent_all + int(size(mine, 2), i8)*(ct%nranks - 1)
            ct%ncyc_all = ct%ncyc_all + 1
        end if
        ! the other ranks' slaves back to no contact: those the last
        ! gathering set (only it sets them), every one the first time (a
        ! pass over every slave's record each cycle took about 0.3 s of
        ! the 0.46 s the 10 x 10 tubes array's 2-rank run spent in this
        ! exchange over 300 cycles, none of it moving data)
        if (allocated(it%got)) then
            do i = 1, size(it%got)
                call no_remote(it%got(i))
            end do
        else
            do k = 1, size(it%owned)
                if (.not. it%owned(k)) call no_remote(k)
            end do
        end if
        it%got = pack(nint(all(1, :)), .not. it%owned(nint(all(1, :))))
        ! (in the rank's own slaves' rows: a row each after the own ones)
        if (it%own_rows) call hit_room(it, size(it%got))
        ! (the own rows: as many as of the rest of their contact state)
        r = size(it%cseg)
        do i = 1, size(all, 2)
            k = nint(all(1, i))
            if (it%owned(k)) cycle
            it%evk(k) = nint(all(16, i))
            it%evd(k) = real(all(17, i), wp)
            it%rseg(k) = nint(all(18, i))
            if (it%own_rows) then
                r = r + 1
                it%hrow(k) = r
            end if
            it%hit(it%hrow(k)) = pair_hit_t()
            associate (h => it%hit(it%hrow(k)))
                h%found = all(15, i) > 0.5_dp
                it%found(k) = h%found
                h%seg = nint(all(2, i))
                h%kind = nint(all(3, i))
                h%a = real(all(4, i), wp)
                h%nshape = real(all(5:8, i), wp)
                h%nhat = real(all(9:11, i), wp)
                it%fk(:, it%hrow(k)) = real(all(12:14, i), wp)
                h%gap = real(all(19, i), wp)
            end associate
        end do
    contains
        subroutine no_remote(q)
            integer, intent(in) :: q
            if (it%own_rows) then
                it%hrow(q) = 0
            else
                it%hit(q)%found = .false.
            end if
            it%found(q) = .false.
            it%evk(q) = ev_none
        end subroutine no_remote
    end subroutine gather_contacts

    !> The records of this rank's slaves' contacts (gather_contacts' mine,
    !> a column each: slave, segment, ..., found, event) to the ranks that
    !> need them: a contact found to the ranks that integrate its slave or
    !> a node of its segment (ct%rank_of; they alone add its forces to a
    !> node whose velocity they update), a record with an event to every
    !> rank (each books every event, and counts them alike); what the
    !> other ranks sent this one in all. Each slave has one rank, so the
    !> records land in the slaves' places whatever the order they arrive
    !> in, and every node's sum still takes its pairs in slave order.
    subroutine send_contacts(it, ct, mine, all)
        type(interface_t), intent(in) :: it
        type(contacts_t), intent(inout) :: ct
        real(dp), intent(in) :: mine(:, :)
        real(dp), allocatable, intent(out) :: all(:, :)
        real(dp), allocatable :: send(:, :)
        integer, allocatable :: to(:, :), nto(:), scnt(:), at(:)
        integer :: i, j, r, m, k, nr
        nr = ct%nranks
        ! (each record's ranks: at most its five nodes', or every rank)
        allocate (to(max(5, nr), size(mine, 2)), nto(size(mine, 2)), scnt(nr), at(nr))
        scnt = 0
        do i = 1, size(mine, 2)
            nto(i) = 0
            if (nint(mine(16, i)) /= ev_none) then
                do r = 0, nr - 1
                    call add(r)
                end do
            else
                k = nint(mine(1, i))
                m = nint(mine(2, i))
                associate (s => it%surf)
                    call add(ct%rank_of(s%node(s%slave(k))))
                    do j = 1, seg_nodes(s%seg(:, m))
                        call add(ct%rank_of(s%node(s%seg(j, m))))
                    end do
                end associate
            end if
        end do
        at(1) = 0
        do r = 2, nr
            at(r) = at(r - 1) + scnt(r - 1)
        end do
        allocate (send(size(mine, 1), sum(scnt)))
        do i = 1, size(mine, 2)
            do j = 1, nto(i)
                r = to(j, i) + 1
                at(r) = at(r) + 1
                send(:, at(r)) = mine(:, i)
            end do
        end do
        ct%sent_p2p = ct%sent_p2p + sum(int(scnt, i8))
        call comm_send_records(send, scnt, all)
    contains
        !> rank rr (0-based) takes record i, once; not this rank
        subroutine add(rr)
            integer, intent(in) :: rr
            if (rr == ct%rank) return
            if (any(to(1:nto(i), i) == rr)) return
            nto(i) = nto(i) + 1
            to(nto(i), i) = rr
            scnt(rr + 1) = scnt(rr + 1) + 1
        end subroutine add
    end subroutine send_contacts

    !> MPI, before a restart dump: every slave's state and master node list
    !> from its rank, and the search counters summed, on every rank (the
    !> event counters are counted on every rank alike already); with
    !> `counters_only` (the end-of-run report, which reads nothing else),
    !> the counters alone (the lists' sums had taken 0.35 s at the end of
    !> the 124,000-node tubes array's 2-rank run).
    subroutine gather_contact_state(ct, counters_only)
        type(contacts_t), intent(inout) :: ct
        logical, intent(in), optional :: counters_only
        integer :: i
        logical :: whole
        whole = .true.
        if (present(counters_only)) whole = .not. counters_only
        ! (the slaves' contact state every slave's again, each from its
        ! rank, where the ranks held their own alone)
        if (whole) call contact_slave_rows(ct, .false.)
        do i = 1, ct%n
            associate (it => ct%ifc(i))
                if (whole) call slave_state(it)
                if (ct%own_work) then
                    ! (each rank's own pairs' work: the sums, on every rank
                    ! until scatter_contact_state)
                    call sum_dp(it%energy)
                    call sum_pairs(it%pair_imp)
                    call sum_pairs(it%pair_work)
                end if
                call sum_i8(it%total%pool)
                call sum_i8(it%total%reduced)
                call sum_i8(it%total%masters)
            end associate
        end do
    contains
        !> Every slave's state and master node list from its rank, on every
        !> rank (a dump's).
        subroutine slave_state(it)
            type(interface_t), intent(inout) :: it
            integer :: k, n, ns
            integer, allocatable :: cnt(:), ptr(:), ib(:), tb(:)
            ns = size(it%owned)
            do k = 1, ns
                if (.not. it%owned(k)) call forget_slave(it, k)
            end do
            call comm_sum_int(it%cseg, ns)
            ! (held from the slave's rank, as cseg: where every pair went to
            ! every rank each kept it alike; in rows each its own)
            where (.not. it%owned) it%held = 0
            call comm_sum_int(it%held, ns)
            where (.not. it%owned) it%rlast = 0
            call comm_sum_int(it%rlast, ns)
            call comm_sum_wp(it%fprev, 3*ns)
            call comm_sum_wp(it%ft, 3*ns)
            call comm_sum_wp(it%p0, ns)
            call comm_sum_wp(it%kp, ns)
            call comm_sum_wp(it%aeff, ns)
            if (allocated(it%lists%ptr)) then
                ! (a slave another rank owns may hold the lists of the last
                ! gathering here: they count on their owner alone)
                cnt = it%lists%last - it%lists%ptr + 1
                where (.not. it%owned) cnt = 0
                call comm_sum_int(cnt, ns)
                allocate (ptr(ns + 1))
                ptr(1) = 1
                do k = 1, ns
                    ptr(k + 1) = ptr(k) + cnt(k)
                end do
                allocate (ib(ptr(ns + 1) - 1), tb(ptr(ns + 1) - 1))
                ib = 0
                tb = 0
                do k = 1, ns
                    if (.not. it%owned(k)) cycle
                    n = cnt(k)
                    ib(ptr(k):ptr(k) + n - 1) = it%lists%node(it%lists%ptr(k):it%lists%ptr(k) + n - 1)
                    tb(ptr(k):ptr(k) + n - 1) = merge(1, 0, it%lists%trackable(it%lists%ptr(k):it%lists%ptr(k) + n - 1))
                end do
                call comm_sum_int(ib, size(ib))
                call comm_sum_int(tb, size(tb))
                it%lists%ptr = ptr(1:ns)
                it%lists%last = ptr(2:ns + 1) - 1
                it%lists%node = ib
                it%lists%trackable = tb /= 0
                it%lists%nused = size(ib)
                it%lists%ndead = 0
                deallocate (ptr, ib, tb)
                if (allocated(it%lists%gap)) then
                    where (.not. it%owned) it%lists%gap = 0
                    call comm_sum_wp(it%lists%gap, ns)
                    where (.not. it%owned) it%lists%og = 0
                    call comm_sum_wp(it%lists%og, ns)
                    where (.not. it%owned) it%lists%at = 0
                    call comm_sum_int(it%lists%at, ns)
                    do k = 1, ns
                        if (.not. it%owned(k)) it%lists%xg(:, k) = 0
                    end do
                    call comm_sum_wp(it%lists%xg, 3*ns)
                end if
            end if
        end subroutine slave_state

        subroutine sum_i8(c)
            integer(i8), intent(inout) :: c
            real(dp) :: b(1)
            b = real(c, dp)
            call comm_sum_dp(b)
            c = nint(b(1), i8)
        end subroutine sum_i8

        subroutine sum_dp(c)
            real(dp), intent(inout) :: c
            real(dp) :: b(1)
            b = c
            call comm_sum_dp(b)
            c = b(1)
        end subroutine sum_dp

        subroutine sum_pairs(a)
            real(dp), intent(inout) :: a(:, :, :)
            real(dp), allocatable :: b(:)
            b = reshape(a, [size(a)])
            call comm_sum_dp(b)
            a = reshape(b, shape(a))
        end subroutine sum_pairs
    end subroutine gather_contact_state

    !> After gather_contact_state: the summed counters stay on rank 0 only,
    !> so that the ranks' further counts add up to the totals again.
    subroutine scatter_contact_state(ct, rank)
        type(contacts_t), intent(inout) :: ct
        integer, intent(in) :: rank
        integer :: i
        ! (each rank's own slaves' work: their contact state in its rows
        ! again, contact_slave_rows)
        if (ct%own_work) call contact_slave_rows(ct, .true.)
        if (rank == 0) return
        do i = 1, ct%n
            associate (it => ct%ifc(i))
                it%total%pool = 0
                it%total%reduced = 0
                it%total%masters = 0
                if (ct%own_work) then
                    it%energy = 0
                    it%pair_imp = 0
                    it%pair_work = 0
                end if
            end associate
        end do
    end subroutine scatter_contact_state

    !> Second half of the contact forces' work, with v(n+1/2): the sliding
    !> energy is minus that work (springs store it, friction dissipates it).
    subroutine contact_work_end(ct, v, dt_avg)
        type(contacts_t), intent(inout) :: ct
        real(wp), intent(in) :: v(:, :)
        real(dp), intent(in) :: dt_avg
        integer :: i, q, k, m, a, b, al, nd(4), j, h
        real(wp) :: vrel(3), vrel0(3), w(4), fa(3)
        real(dp) :: pplus, fv
        do i = 1, ct%n
            associate (it => ct%ifc(i), s => ct%ifc(i)%surf)
                pplus = 0
                do q = 1, it%npair
                    k = it%pair(q)
                    if (ct%own_work) then
                        if (.not. it%owned(k)) cycle
                    end if
                    h = it%hrow(k)
                    m = it%hit(h)%seg
                    vrel = v(:, s%node(s%slave(k))) - matmul(v(:, s%node(s%seg(:, m))), it%hit(h)%nshape)
                    fv = dot_product(real(it%fpair(:, q), dp), real(vrel, dp))
                    pplus = pplus + fv
                    ! by part pair: the same rule, with the first half from
                    ! v(n-1/2) (the surface velocities the search gathered)
                    vrel0 = it%ls%vl(:, s%slave(k)) - matmul(it%ls%vl(:, s%seg(:, m)), it%hit(h)%nshape)
                    a = it%slave_lp(k)
                    b = it%seg_lp(m)
                    ! (an allowance: the slave's rank's rows hold it)
                    al = 1
                    if (it%orow(k) > 0) then
                        if (it%p0(it%orow(k)) > 0.0_wp) al = 2
                    end if
                    it%pair_imp(a, b, al) = it%pair_imp(a, b, al) + dt_avg*norm2(real(it%fpair(:, q), dp))
                    it%pair_work(a, b, al) = it%pair_work(a, b, al) + &
                        0.5_dp*dt_avg*(fv + dot_product(real(it%fpair(:, q), dp), real(vrel0, dp)))
                end do
                ! the edge pairs: edge a's part against edge b's
                do j = 1, it%ed%nact
                    q = it%ed%act(j)
                    call edge_weights(it, q, nd, w)
                    fa = it%ed%fa(:, q)
                    fv = dot_product(real(fa, dp), real(matmul(v(:, s%node(nd)), w), dp))
                    pplus = pplus + fv
                    a = it%seg_lp(it%ed%eseg(it%ed%pa(q)))
                    b = it%seg_lp(it%ed%eseg(it%ed%pb(q)))
                    al = merge(2, 1, it%ed%p0(q) > 0.0_wp)
                    it%pair_imp(a, b, al) = it%pair_imp(a, b, al) + dt_avg*norm2(real(fa, dp))
                    it%pair_work(a, b, al) = it%pair_work(a, b, al) + &
                        0.5_dp*dt_avg*(fv + dot_product(real(fa, dp), real(matmul(it%ls%vl(:, nd), w), dp)))
                end do
                it%energy = it%energy - 0.5_dp*dt_avg*(it%pminus + pplus)
            end associate
        end do
    end subroutine contact_work_end

    !> Sliding interface energy at t(n): the work booked for earlier cycles
    !> and the first half of this cycle's (the rule every force follows).
    real(dp) function contact_energy(ct, dt_avg) result(e)
        type(contacts_t), intent(in) :: ct
        real(dp), intent(in) :: dt_avg
        integer :: i
        real(dp) :: r(1)
        e = 0
        do i = 1, ct%n
            e = e + ct%ifc(i)%energy - 0.5_dp*dt_avg*ct%ifc(i)%pminus
        end do
        ! (each rank's own pairs' work: the ranks' sums added; every rank
        ! calls this at the same point)
        if (ct%own_work) then
            r = e
            call comm_sum_dp(r)
            e = r(1)
        end if
    end function contact_energy

    !> rcforc values of every interface: slave force, slave mass in contact,
    !> master force, master mass in contact (shape-function weighted).
    function contact_resultants(ct) result(rc)
        type(contacts_t), intent(in) :: ct
        real(dp), allocatable :: rc(:, :)
        integer :: i
        allocate (rc(8, ct%n))
        do i = 1, ct%n
            rc(:, i) = [ct%ifc(i)%fslave, ct%ifc(i)%mslave, ct%ifc(i)%fmaster, ct%ifc(i)%mmaster]
        end do
    end function contact_resultants

    !> Set-up lines for the log, one block per interface.
    function interface_summary(ct, model) result(txt)
        type(contacts_t), intent(in) :: ct
        type(model_t), intent(in) :: model
        character(len=:), allocatable :: txt
        character(len=200) :: buf
        character(len=1), parameter :: nl = new_line('a')
        integer :: i
        txt = ' c o n t a c t   i n t e r f a c e s   (the automatic contact of Whirley and Engelmann)'//nl
        write (buf, '(a,i0,a,i0,a,i0,a)') '   exterior faces of the model: ', ct%faces%n - ct%faces%nlatent, &
            ' segments on ', ct%faces%nbody, ' bodies; ', ct%faces%ninterior, ' interior faces left out'
        txt = txt//trim(buf)//nl
        if (ct%faces%nlatent > 0) then
            write (buf, '(a,i0,a)') '   solids that can erode: ', ct%faces%nlatent, ' latent segments (the interior '// &
                'faces beside them, as each neighbour gives them), active when erosion exposes them'
            txt = txt//trim(buf)//nl
        end if
        do i = 1, ct%n
            associate (it => ct%ifc(i), s => ct%ifc(i)%surf)
                write (buf, '(a,i0,a,a)') '   interface ', it%id, '  *', trim(it%keyword)
                txt = txt//trim(buf)//nl
                write (buf, '(a,i0,a,i0,a,i0,a,i0,a,i0)') '     segments ', s%nseg, ' (shell ', s%nshell_seg, &
                    ', solid ', s%nsolid_seg, ')   surface nodes ', s%nnode, '   slave nodes ', s%nslave
                txt = txt//trim(buf)//nl
                if (s%latent) then
                    write (buf, '(a,i0,a,i0,a)') '     of these, ', count(.not. s%seg_on), ' latent segments and ', &
                        count(.not. it%live), ' slave nodes inside parts that can erode (they join as erosion exposes them)'
                    txt = txt//trim(buf)//nl
                end if
                if (s%follow) txt = txt//'     THKCHG 1: the shell contact thickness follows the shells'' '// &
                                    '(*CONTROL_SHELL ISTUPD), within the 40% limit where it applies'//nl
                if (it%ed%ne > 0) then
                    write (buf, '(a,i0,a)') '     edge to edge: ', it%ed%ne, ' exterior shell edges, paired at each '// &
                        'search (within both half-thicknesses plus delta)'
                    txt = txt//trim(buf)//nl
                end if
                if (s%ncap > 0) then
                    write (buf, '(a,i0,a)') '     shell contact thickness limited to 40% of the shortest edge at ', &
                        s%ncap, ' nodes (single surface, *CONTROL_CONTACT SSTHK 0; SSTHK 1 or SST/MST lift it)'
                    txt = txt//trim(buf)//nl
                end if
                if (s%nseg > 0) then
                    write (buf, '(a,2es11.3,a,2es11.3)') '     segment thickness min/max', minval(s%seg_t), &
                        maxval(s%seg_t), '   penalty stiffness min/max', minval(s%seg_k), maxval(s%seg_k)
                    txt = txt//trim(buf)//nl
                end if
                if (it%ls%penmax > 0.0_wp) then
                    write (buf, '(a,es10.3,a)') '     PENMAX ', it%ls%penmax, ': a contact deeper than this times its '// &
                        'segment''s thickness (beyond any allowance) is released'
                    txt = txt//trim(buf)//nl
                end if
                if (it%adaptive) then
                    write (buf, '(a)') '     global search on the motion alone: the slaves of a margin class when '// &
                        'a node''s motion since could have used up their margins'
                else
                    write (buf, '(a,i0,a)') '     global search every ', it%interval, &
                        ' cycles at the longest, a margin class sooner when the motion could have used up its margins'
                end if
                txt = txt//trim(buf)//nl
                write (buf, '(a,3es11.3,a,es11.3,a,i0,a)') '     pool margins delta min/median/max', minval(it%dl), &
                    it%margin, maxval(it%dl), ' (', model%ctl%contact%pmarg, ' x the local characteristic length); ', &
                    size(it%cmin), ' margin classes'
                txt = txt//trim(buf)//nl
                write (buf, '(a,es11.3)') '     contact reach t_c', it%reach
                txt = txt//trim(buf)//nl
                if (it%nraised > 0) then
                    write (buf, '(a,i0,a,es11.3,a)') '     pool margin raised at ', it%nraised, ' nodes to ', &
                        margin_floor*it%margin, ' (their segments shorter than 1/32 of the median: '// &
                        'larger pools there, the same bound)'
                    txt = txt//trim(buf)//nl
                end if
            end associate
        end do
        select case (model%ctl%contact%mnl)
        case (1); txt = txt//'   master node list: closest node'//nl
        case (3); txt = txt//'   master node list: three closest nodes'//nl
        case default; txt = txt//'   master node list: minimal set (steps A-C, section 4)'//nl
        end select
    end function interface_summary

    !> End-of-run lines: searches, sizes and time per interface.
    function contact_report(ct, e_ref) result(txt)
        type(contacts_t), intent(in) :: ct
        real(dp), intent(in) :: e_ref          !< the run's energy scale, initial energy plus external work (of "created")
        character(len=:), allocatable :: txt
        character(len=220) :: buf
        character(len=64) :: scale
        character(len=1), parameter :: nl = new_line('a')
        integer :: i
        real(dp) :: per, avg_m, avg_p, avg_r
        txt = nl//' c o n t a c t   s e a r c h   s u m m a r y'//nl
        txt = txt//'   interface   slaves  searches  masters/slave  pool/slave  reduced/slave   search (s)'// &
              '   ns/slave/search   max 4u/delta'//nl
        do i = 1, ct%n
            associate (it => ct%ifc(i))
                ! (per slave searched: a search of some classes searches fewer)
                per = real(max(1_i8, it%nsearched), dp)
                avg_m = real(it%total%masters, dp)/per
                avg_p = real(it%total%pool, dp)/per
                avg_r = real(it%total%reduced, dp)/per
                write (buf, '(i12,i9,i10,f15.2,f12.2,f15.2,f13.4,f18.1,f15.3)') it%id, it%surf%nslave, it%nsearch, &
                    avg_m, avg_p, avg_r, it%wall, 1.0e9_dp*it%wall/per, it%worst
                txt = txt//trim(buf)//nl
                if (it%npartial > 0) then
                    write (buf, '(a,i0,a,i0,a,i0,a,i0,a,f8.1,a)') '   interface ', it%id, ': ', it%npartial, ' of the ', &
                        it%nsearch, ' searches of some margin classes only (', size(it%cmin), &
                        ' classes); slaves searched ', per/max(1, it%surf%nslave), ' times on average'
                    txt = txt//trim(buf)//nl
                end if
                if (it%nnear > 0) then
                    write (buf, '(a,i0,a,i0,a,i0,a)') '   interface ', it%id, ': ', it%nnear, &
                        ' slave-cycles checked by their near sets alone (the segments a fresh clearance left out), ', &
                        it%nnear_full, ' of them searched in full after (a near segment found or refused a contact)'
                    txt = txt//trim(buf)//nl
                end if
                if (it%ninit > 0) then
                    write (buf, '(a,i0,a,i0,a,es10.3,a)') '   interface ', it%id, ': ', it%ninit, &
                        ' initial penetrations (deepest ', it%pinit, &
                        ') allowed, shrinking as the nodes move out (as LS-DYNA''s IGNORE = 1), each named above'
                    txt = txt//trim(buf)//nl
                end if
                if (it%nlate > 0) txt = txt//count_line(it%id, it%nlate, ' missed contacts found (or moved) deeper '// &
                    'than one step''s approach (largest excess ', it%plate, ') allowed like initial penetrations')//nl
                if (it%nback > 0) txt = txt//count_line(it%id, it%nback, ' contacts back under the segment the '// &
                    'node held last, deeper than a step (largest excess ', it%pback, ') allowed')//nl
                if (it%nref > 0) txt = txt//count_line(it%id, it%nref, ' deep contacts refused, under solid faces '// &
                    'the node did not cross since the search (deepest ', it%pref, ')')//nl
                if (it%nwithin > 0) txt = txt//count_line(it%id, it%nwithin, ' contacts deep in a shell''s zone '// &
                    'the node lay in at the search, held at that depth (deepest ', it%pwithin, ' allowed)')//nl
                if (it%nhand > 0) txt = txt//count_line(it%id, it%nhand, ' contacts moved to a segment deeper '// &
                    'than the old one''s spring there (largest excess ', it%phand, ') allowed')//nl
                if (it%energy < -0.01_dp*abs(e_ref)) then
                    ! the ratio books this work as (negative) sliding energy, so
                    ! it stays at 1 while the contact creates energy
                    ! (no initial energy to compare with: the work alone)
                    scale = '(the run had no initial energy nor external work)'
                    if (e_ref /= 0.0_dp) write (scale, '(a,f6.1,a)') '(', -100.0_dp*it%energy/abs(e_ref), &
                        '% of the initial energy plus external work)'
                    write (buf, '(a,i0,a,es10.3,a)') '   *** Warning: interface ', it%id, &
                        ': its forces did net positive work ', -it%energy, ' '//trim(scale)// &
                        ': energy created, which the energy ratio does not show'
                    txt = txt//trim(buf)//nl
                    txt = txt//'       (springs too stiff for the step: SLSFAC, SFS, SFM; or depths pushed out at once)'//nl
                end if
                if (it%nrel > 0) txt = txt//count_line(it%id, it%nrel, ' contacts released deep (deeper than '// &
                    'one step can undo, or beyond PENMAX; deepest ', it%prel, ')')//nl
                if (it%ed%ne > 0) then
                    write (buf, '(a,i0,a,i0,a,i0,a)') '   interface ', it%id, ': edge to edge: ', it%ed%ne, &
                        ' exterior shell edges, ', it%ed%ncontact, ' edge pair-cycles in contact'
                    txt = txt//trim(buf)//nl
                    if (it%ed%nlate > 0) then
                        write (buf, '(a,i0,a,i0,a,es10.3,a,i0,a)') '   interface ', it%id, ': ', it%ed%nlate, &
                            ' edge contacts found deeper than a step (largest excess ', it%ed%plate, &
                            ') allowed, shrinking as the edges part; the first ', min(it%ed%nlate, max_named), ' named above'
                        txt = txt//trim(buf)//nl
                    end if
                    if (it%ed%ninit > 0) then
                        write (buf, '(a,i0,a,i0,a,es10.3,a,i0,a)') '   interface ', it%id, ': ', it%ed%ninit, &
                            ' initial edge penetrations (deepest ', it%ed%pinit, ') allowed, shrinking as the edges '// &
                            'part; the first ', min(it%ed%ninit, max_named), ' named above'
                        txt = txt//trim(buf)//nl
                    end if
                    if (it%ed%nunknown > 0) then
                        write (buf, '(a,i0,a,i0,a,i0,a)') '   interface ', it%id, ': ', it%ed%nunknown, &
                            ' edge pairs within reach with no side known (overlapping when first seen): no contact '// &
                            'until they parted; the first ', min(it%ed%nunknown, max_named), ' named above'
                        txt = txt//trim(buf)//nl
                    end if
                end if
                txt = txt//pair_table(it)
            end associate
        end do
    end function contact_report

    !> The interface's force and work by part pair (slave part, master
    !> part), largest impulse first: normal impulse, the work of the forces
    !> on the slaves relative to the master (negative: resisting), and the
    !> share of both under an allowance (initial or missed penetration).
    function pair_table(it) result(txt)
        type(interface_t), intent(in) :: it
        character(len=:), allocatable :: txt
        character(len=200) :: buf
        character(len=1), parameter :: nl = new_line('a')
        real(dp), allocatable :: imp(:)
        integer, allocatable :: a(:), b(:), order(:)
        integer :: i, j, n, q
        txt = ''
        if (.not. allocated(it%pair_imp)) return
        n = size(it%part_id)
        allocate (imp(0), a(0), b(0))
        do j = 1, n
            do i = 1, n
                if (sum(it%pair_imp(i, j, :)) <= 0.0_dp) cycle
                imp = [imp, sum(it%pair_imp(i, j, :))]
                a = [a, i]
                b = [b, j]
            end do
        end do
        if (size(imp) == 0) return
        call sort_index(-imp, order)   ! largest impulse first
        write (buf, '(a,i0,a)') '   interface ', it%id, ': contact by part pair (slave part, master part; impulse '// &
            'of the normal force, work of the forces on the slaves, negative where they resisted; under allowances)'
        txt = txt//trim(buf)//nl
        txt = txt//'        slave  master        impulse           work   impulse (allow.)   work (allow.)'//nl
        do q = 1, min(size(order), 20)
            i = a(order(q))
            j = b(order(q))
            write (buf, '(2i8,4es16.6)') it%part_id(i), it%part_id(j), sum(it%pair_imp(i, j, :)), &
                sum(it%pair_work(i, j, :)), it%pair_imp(i, j, 2), it%pair_work(i, j, 2)
            txt = txt//trim(buf)//nl
        end do
        if (size(order) > 20) then
            write (buf, '(a,i0,a)') '        (', size(order) - 20, ' more pairs with less impulse)'
            txt = txt//trim(buf)//nl
        end if
        ! the work of all pairs is minus the interface's sliding energy
        write (buf, '(a,4es16.6)') '           all pairs', sum(it%pair_imp), sum(it%pair_work), &
            sum(it%pair_imp(:, :, 2)), sum(it%pair_work(:, :, 2))
        txt = txt//trim(buf)//nl
    end function pair_table

    real(dp) function wtime()
        integer(i8) :: c, r
        call system_clock(c, r)
        wtime = real(c, dp)/real(r, dp)
    end function wtime

    !> d3hsp's count of one kind of contact event: 'interface id: n' what
    !> depth tail '; the first m named above'.
    function count_line(id, n, what, depth, tail) result(t)
        integer, intent(in) :: id, n
        character(len=*), intent(in) :: what, tail
        real(wp), intent(in) :: depth
        character(len=:), allocatable :: t
        character(len=24) :: d
        write (d, '(es10.3)') depth
        t = '   interface '//itoa(id)//': '//itoa(n)//what//trim(adjustl(d))//tail//'; the first '// &
            itoa(min(n, max_named))//' named above'
    end function count_line

end module xd_contact_contact
