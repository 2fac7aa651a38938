!> Energy bookkeeping, global and per part: kinetic, internal, hourglass,
!> stonewall, external work, total and energy ratio, momentum and mass per part.
module xd_solver_energies
    use xd_kinds, only: wp, dp, i8
    use xd_core_memory, only: nbytes
    use xd_model, only: model_t
    use xd_elements_solid_groups, only: solids_t
    use xd_elements_beam_bs, only: beams_t
    use xd_elements_shell_bt, only: shells_t, shell_row
    use xd_solver_state, only: state_t
    use xd_contact_rigidwall, only: walls_t, walls_kinetic
    use xd_rigid_bodies, only: rigid_t, rigid_energy
    use xd_solver_assembly, only: assembly_t, build_assembly
    use xd_core_comm, only: comm_sum_dp
    implicit none
    private
    public :: energies_t, compute_energies, prepare_energies, energy_bytes, set_model_mass, masses_fixed

    type :: energies_t
        real(dp) :: ke = 0, ie = 0, hg = 0, ext = 0, wall = 0, slide = 0, total = 0, ratio = 1
        !> internal energy of the eroded shells (at erosion), in the total
        !> and the ratio; ratio_live leaves it out
        real(dp) :: eroded_ie = 0, ratio_live = 1
        real(dp), allocatable :: part_eroded(:)
        real(dp) :: vel(3) = 0              !< velocity of the centre of mass
        real(dp) :: mass = 0
        real(dp) :: added = 0               !< mass scaling: mass added so far
        integer :: nshell_scaled = 0        !< shells that reached the DT2MS step
        real(dp), allocatable :: part_ie(:), part_ke(:), part_hg(:), part_mass(:)
        real(dp), allocatable :: part_added(:)   !< mass scaling: mass added per part
        real(dp), allocatable :: part_mom(:, :)   !< (3, npart)
        ! work arrays: per node 1/2 v(n-1/2).v(n+1/2) and v(n) (0 on a rigid
        ! body's nodes, whose motion is the body's)
        real(dp), allocatable, private :: kn(:), vn(:, :)
        ! while element masses stay as they started (no mass scaling, no
        ! shell thickness update): each node's mass by part, the elements'
        ! shares summed once (np_ptr(nnode + 1) into np_part, np_m), and
        ! each part's mass
        logical, private :: fixed_mass = .false.
        integer, allocatable, private :: np_ptr(:), np_part(:)
        real(dp), allocatable, private :: np_m(:), part_mass0(:)
        !> nodes numbered per rank: the model's nodal mass, summed before
        !> the cut (each rank holds a part of the nodes; -1 otherwise)
        real(dp), private :: mass_whole = -1
    end type energies_t

contains

    !> The bytes of the energies' tables (per node: the node-by-part masses,
    !> and with changing masses the nodes' kinetic energies and momenta).
    integer(i8) function energy_bytes(en) result(b)
        type(energies_t), intent(in) :: en
        b = nbytes(en%kn) + nbytes(en%vn) + nbytes(en%np_ptr) + nbytes(en%np_part) + nbytes(en%np_m)
    end function energy_bytes

    !> The energies' tables and arrays (the nodes' shares of the parts'
    !> masses, the parts' sums), built at set-up: in the first output they
    !> had been a one-time cost inside the time loop's timing (node_part_masses
    !> and the arrays' first touch, 8-19 ms on 100,000 shells).
    subroutine prepare_energies(model, st, solids, sh, en, bm, keep)
        type(model_t), intent(in) :: model
        type(state_t), intent(in) :: st
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        type(energies_t), intent(inout) :: en
        type(beams_t), intent(in), optional :: bm
        !> (nodes numbered per rank: the model's nodes the rank holds, in
        !> the model's numbering; the table holds theirs. The nodal arrays
        !> may be cut already, the elements' connectivity not yet)
        logical, intent(in), optional :: keep(:)
        if (.not. allocated(en%part_ie)) then
            allocate (en%part_ie(model%npart), en%part_ke(model%npart), en%part_hg(model%npart), &
                      en%part_mass(model%npart), en%part_mom(3, model%npart), en%part_added(model%npart))
        end if
        if (.not. allocated(en%np_ptr)) call node_part_masses(model, st, solids, sh, en, bm, keep)
        if (.not. en%fixed_mass .and. .not. allocated(en%kn)) then
            allocate (en%kn(st%nnode), en%vn(3, st%nnode))
            en%kn = 0
            en%vn = 0
        end if
    end subroutine prepare_energies

    !> The nodes' masses stay as set up for the whole run (no mass
    !> scaling, no thickness update): the node-by-part table holds them.
    logical function masses_fixed(solids, sh)
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        masses_fixed = .not. (allocated(solids%msf) .or. allocated(sh%msf) .or. sh%thickness_update)
    end function masses_fixed

    !> Nodes numbered per rank (xd_solver_local_nodes): the model's nodal
    !> mass, sum(real(st%mass, dp)) before the cut, as one rank sums it
    !> (glstat's mean velocities divide by it; each rank then holds a part
    !> of the nodes). The node-by-part table is built for the kept nodes
    !> alone (prepare_energies' keep).
    subroutine set_model_mass(en, mass)
        type(energies_t), intent(inout) :: en
        real(dp), intent(in) :: mass
        en%mass_whole = mass
    end subroutine set_model_mass

    !> Energies at time t(n). Kinetic energy is 1/2 m v(n-1/2).v(n+1/2), the
    !> form that central differences conserve exactly with the trapezoidal
    !> internal work (it differs from 1/2 m v(n)^2 by O(dt^2)); momentum and
    !> velocities use v(n) = (v(n-1/2) + v(n+1/2))/2. With shells, the
    !> angular velocities wminus, wplus give the rotational kinetic energy
    !> 1/2 I w(n-1/2).w(n+1/2).
    !> Owned nodes (under MPI, issue 32): node_on, solid_on and shell_on
    !> are the nodes and elements this rank's sums take (its own; the
    !> others' values here are not current), and the ranks' sums are then
    !> added (the rigid bodies, walls and other terms every rank holds
    !> alike after). The ranks' partial sums are added in another order
    !> than one rank's single sum: the energies agree with a serial run's
    !> to rounding (1e-12 relative is the tests' bound), not bit for bit.
    subroutine compute_energies(model, st, solids, sh, walls, rg, vminus, vplus, wminus, wplus, dt_avg, en, slide, ke_fix, &
                                bm, node_on, solid_on, shell_on)
        type(model_t), intent(in) :: model
        type(state_t), intent(in) :: st
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        type(walls_t), intent(in) :: walls
        type(rigid_t), intent(in) :: rg
        real(wp), intent(in) :: vminus(:, :), vplus(:, :)
        real(wp), intent(in), optional :: wminus(:, :), wplus(:, :)   !< present when st%rot
        real(dp), intent(in) :: dt_avg       !< step of the velocity update at this time (0 at t = 0)
        type(energies_t), intent(inout) :: en
        real(dp), intent(in), optional :: slide   !< sliding interface energy (contact)
        !> (npart) kinetic energy to add by part: the tied contacts' (their
        !> slaves' mass as the dynamics move it, on their segments' nodes,
        !> instead of at the slaves' own velocities)
        real(dp), intent(in), optional :: ke_fix(:)
        type(beams_t), intent(in), optional :: bm   !< beams (their internal energy and nodal masses)
        logical, intent(in), optional :: node_on(:), solid_on(:), shell_on(:)
        integer :: e, p, nd
        real(dp) :: mom(3), ke_b, mom_b(3), ker
        logical :: split
        real(dp), allocatable :: pie(:)
        split = present(node_on) .and. present(solid_on) .and. present(shell_on)
        ! (built at set-up by the time loop; here for any other caller)
        call prepare_energies(model, st, solids, sh, en, bm)
        en%part_ie = 0; en%part_ke = 0; en%part_hg = 0; en%part_mass = 0; en%part_mom = 0; en%part_added = 0
        en%nshell_scaled = 0
        if (en%fixed_mass) then
            ! one pass over the nodes: each node's share, the whole model's
            ! kinetic energy, momentum and spin, and the parts' by the node
            ! table (a run of one part summed in registers: nodes mostly come
            ! part by part); each sum in node order, as separate loops
            ! would take it
            call node_pass()
            en%part_mass = en%part_mass0
            ! (solid_on, shell_on absent on one rank: every element)
            if (solids%n > 0) call ie_by_part(solids%part, solids%eint, solids%pend_int, solids%ehg, solids%pend_hg, &
                                              solid_on)
            if (sh%n > 0) then
                if (sh%by_row) then
                    call ie_by_part(sh%part, sh%eint, sh%pend_int, sh%ehg, sh%pend_hg, shell_on, sh%lix)
                else
                    call ie_by_part(sh%part, sh%eint, sh%pend_int, sh%ehg, sh%pend_hg, shell_on)
                end if
            end if
            if (split) call add_ranks(.false.)
            en%ie = sum(en%part_ie)
            en%hg = sum(en%part_hg)
        else
            ! each node's share once; the elements' loops weigh it by their mass
            do nd = 1, st%nnode
                en%kn(nd) = 0.5_dp*sum(real(vminus(:, nd), dp)*vplus(:, nd))
                en%vn(:, nd) = 0.5_dp*real(vminus(:, nd) + vplus(:, nd), dp)
            end do
            if (rg%n > 0) then
                do nd = 1, st%nnode
                    if (.not. rg%on(nd)) cycle
                    en%kn(nd) = 0
                    en%vn(:, nd) = 0
                end do
            end if
            call by_elements()
            en%ke = 0
            mom = 0
            do nd = 1, st%nnode
                if (split) then
                    if (.not. node_on(nd)) cycle
                end if
                en%ke = en%ke + st%mass(nd)*en%kn(nd)
                mom = mom + st%mass(nd)*en%vn(:, nd)
            end do
            ker = 0
            if (st%rot) then
                do nd = 1, st%nnode
                    ! a rigid body's nodes spin with it: their inertia is in the body's
                    if (rg%n > 0) then
                        if (rg%on(nd)) cycle
                    end if
                    if (split) then
                        if (.not. node_on(nd)) cycle
                    end if
                    ker = ker + 0.5_dp*st%irot(nd)*dot_product(real(wminus(:, nd), dp), real(wplus(:, nd), dp))
                end do
            end if
            if (split) call add_ranks(.true.)
        end if
        ! beams: their internal energy by part (either path)
        if (present(bm)) then
            if (bm%n > 0) then
                do e = 1, bm%n
                    en%part_ie(bm%part(e)) = en%part_ie(bm%part(e)) + bm%eint(e)
                end do
                en%ie = sum(en%part_ie)
            end if
        end if
        ! rigid bodies: their own inertia, not the lumped nodal masses
        do e = 1, rg%n
            if (.not. (rg%b(e)%from_part .or. rg%b(e)%own)) cycle
            call rigid_energy(rg%b(e), ke_b, mom_b, dt_avg == 0.0_dp)
            p = rg%b(e)%part
            if (p > 0) then
                en%part_ke(p) = en%part_ke(p) + ke_b
                en%part_mom(:, p) = en%part_mom(:, p) + mom_b
                en%part_mass(p) = en%part_mass(p) + rg%b(e)%mass
            end if
            en%ke = en%ke + ke_b
            mom = mom + mom_b
        end do
        if (en%mass_whole >= 0) then
            en%mass = en%mass_whole
        else
            en%mass = sum(real(st%mass, dp))
        end if
        en%added = sum(en%part_added)
        en%vel = 0
        if (en%mass > 0) en%vel = mom/en%mass
        en%ext = st%ext_work
        en%ke = en%ke + walls_kinetic(model, walls)
        en%wall = 0
        do e = 1, walls%n
            en%wall = en%wall + walls%w(e)%energy
        end do
        if (st%rot) en%ke = en%ke + ker
        ! eroded shells: their internal energy leaves the parts' and is
        ! booked as eroded
        if (.not. allocated(en%part_eroded)) allocate (en%part_eroded(model%npart))
        en%part_eroded = 0
        ! (eroded solids likewise; owned nodes: each rank's own, the ranks'
        ! sums added)
        pie = en%part_ie
        ! (shells that can erode keep their energies every shell's: shell_rows)
        if (sh%n > 0 .and. sh%ndead > 0) call book_eroded(sh%part, sh%dead, sh%eint, shell_on)
        if (solids%ndead > 0) call book_eroded(solids%part, solids%dead, solids%eint, solid_on)
        if (split) then
            call comm_sum_dp(en%part_eroded)
            en%part_ie = pie - en%part_eroded
            en%ie = sum(en%part_ie)
        end if
        en%eroded_ie = sum(en%part_eroded)
        if (present(ke_fix)) then
            en%part_ke = en%part_ke + ke_fix
            en%ke = en%ke + sum(ke_fix)
        end if
        en%slide = 0
        if (present(slide)) en%slide = slide
        en%total = en%ke + en%ie + en%hg + en%wall + en%slide + en%eroded_ie
        ! the kinetic energy that mass scaling's added mass entered with
        ! counts as energy put in, beside the external work
        if (abs(st%e_initial + en%ext + st%ms_work) > tiny(1.0_dp)) then
            en%ratio = en%total/(st%e_initial + en%ext + st%ms_work)
            en%ratio_live = (en%total - en%eroded_ie)/(st%e_initial + en%ext + st%ms_work)
        else
            en%ratio = 1.0_dp
            en%ratio_live = 1.0_dp
        end if
    contains
        !> The eroded elements' internal energy out of their parts' and into
        !> their parts' eroded energy.
        subroutine book_eroded(part, dead, eint, mine)
            integer, intent(in) :: part(:)
            logical, intent(in) :: dead(:)
            real(dp), intent(in) :: eint(:)
            !> (owned nodes: the elements this rank books)
            logical, intent(in), optional :: mine(:)
            integer :: e
            do e = 1, size(dead)
                if (.not. dead(e)) cycle
                if (present(mine)) then
                    if (.not. mine(e)) cycle
                end if
                en%part_ie(part(e)) = en%part_ie(part(e)) - eint(e)
                en%part_eroded(part(e)) = en%part_eroded(part(e)) + eint(e)
            end do
            en%ie = sum(en%part_ie)
        end subroutine book_eroded

        !> Owned nodes: the ranks' sums added (the parts' energies, momenta
        !> and, with `masses`, masses and added masses; the whole model's
        !> kinetic energy, momentum and spin; the shells scaled).
        subroutine add_ranks(masses)
            logical, intent(in) :: masses
            real(dp), allocatable :: buf(:)
            integer :: np
            np = model%npart
            allocate (buf(merge(8*np + 6, 6*np + 6, masses)))
            buf(1:6*np + 6) = [en%part_ie, en%part_hg, en%part_ke, reshape(en%part_mom, [3*np]), en%ke, mom, ker, &
                               real(en%nshell_scaled, dp)]
            if (masses) buf(6*np + 7:) = [en%part_mass, en%part_added]
            call comm_sum_dp(buf)
            en%part_ie = buf(1:np)
            en%part_hg = buf(np + 1:2*np)
            en%part_ke = buf(2*np + 1:3*np)
            en%part_mom = reshape(buf(3*np + 1:6*np), [3, np])
            en%ke = buf(6*np + 1)
            mom = buf(6*np + 2:6*np + 4)
            ker = buf(6*np + 5)
            en%nshell_scaled = nint(buf(6*np + 6))
            if (masses) then
                en%part_mass = buf(6*np + 7:7*np + 6)
                en%part_added = buf(7*np + 7:8*np + 6)
            end if
            en%ie = sum(en%part_ie)
            en%hg = sum(en%part_hg)
        end subroutine add_ranks

        !> The fixed-mass path's pass over the nodes (en%ke, mom and ker of
        !> the whole model, the parts' kinetic energy and momentum).
        subroutine node_pass()
            logical, allocatable :: skip(:)
            ! (wminus, wplus present when st%rot; st%irot, rg%on absent where
            ! not allocated; owned nodes: the other ranks' nodes skipped as
            ! a rigid body's are, adding nothing)
            if (split) then
                skip = .not. node_on
                if (rg%n > 0) skip = skip .or. rg%on
                call node_sums(st%nnode, model%npart, st%mass, vminus, vplus, en%np_ptr, en%np_part, en%np_m, &
                               en%part_ke, en%part_mom, en%ke, mom, ker, on=skip, irot=st%irot, wminus=wminus, &
                               wplus=wplus)
            else if (rg%n > 0) then
                call node_sums(st%nnode, model%npart, st%mass, vminus, vplus, en%np_ptr, en%np_part, en%np_m, &
                               en%part_ke, en%part_mom, en%ke, mom, ker, on=rg%on, irot=st%irot, wminus=wminus, &
                               wplus=wplus)
            else
                call node_sums(st%nnode, model%npart, st%mass, vminus, vplus, en%np_ptr, en%np_part, en%np_m, &
                               en%part_ke, en%part_mom, en%ke, mom, ker, irot=st%irot, wminus=wminus, wplus=wplus)
            end if
        end subroutine node_pass

        !> Internal and hourglass energy by part: the work booked so far and
        !> the first half of the current forces', a run of one part's
        !> elements summed in registers.
        subroutine ie_by_part(part, eint, pend_int, ehg, pend_hg, mine, row)
            integer, intent(in) :: part(:)
            real(dp), intent(in) :: eint(:), pend_int(:), ehg(:), pend_hg(:)
            !> (owned nodes: the elements this rank sums)
            logical, intent(in), optional :: mine(:)
            !> (the energies held by row: element p's at row(p); shell_rows)
            integer, intent(in), optional :: row(:)
            integer :: e, p, pc, first, q
            real(dp) :: aie, ahg
            first = 1
            do e = 1, size(part) + 1
                if (e <= size(part)) then
                    if (part(e) == part(first)) cycle
                end if
                if (e > first) then
                    pc = part(first)
                    aie = 0; ahg = 0
                    do p = first, e - 1
                        if (present(mine)) then
                            if (.not. mine(p)) cycle
                        end if
                        q = p
                        if (present(row)) q = row(p)
                        aie = aie + (eint(q) + dt_avg*pend_int(q))
                        ahg = ahg + (ehg(q) + dt_avg*pend_hg(q))
                    end do
                    en%part_ie(pc) = en%part_ie(pc) + aie
                    en%part_hg(pc) = en%part_hg(pc) + ahg
                end if
                first = e
            end do
        end subroutine ie_by_part

        !> Kinetic energy, momentum and mass by part through each element's
        !> share of its nodes (mass scaling or a thickness update change the
        !> elements' masses during the run), internal and hourglass energy.
        subroutine by_elements()
            integer :: e, k, p, nd, nn, pc, q
            real(dp) :: mshare, ksum, msum(3), ake, amom(3), amass, aie, ahg
            do e = 1, solids%n
                if (split) then
                    if (.not. solid_on(e)) cycle
                end if
                p = solids%part(e)
                mshare = real(model%mat(model%part(p)%mat_ix)%ro, dp)*solids%vol0(e)/8.0_dp
                if (allocated(solids%msf)) then
                    ! mass scaling: the element's mass is msf times its own
                    en%part_added(p) = en%part_added(p) + 8.0_dp*mshare*(solids%msf(e) - 1.0_dp)
                    mshare = mshare*solids%msf(e)
                end if
                ! work booked so far, and the first half of the current forces'
                en%part_ie(p) = en%part_ie(p) + solids%eint(e) + dt_avg*solids%pend_int(e)
                en%part_hg(p) = en%part_hg(p) + solids%ehg(e) + dt_avg*solids%pend_hg(e)
                en%part_mass(p) = en%part_mass(p) + 8.0_dp*mshare
                ksum = 0
                msum = 0
                do k = 1, 8
                    nd = solids%conn(k, e)
                    ksum = ksum + en%kn(nd)
                    msum = msum + en%vn(:, nd)
                end do
                en%part_ke(p) = en%part_ke(p) + mshare*ksum
                en%part_mom(:, p) = en%part_mom(:, p) + mshare*msum
            end do
            en%ie = sum(en%part_ie)
            en%hg = sum(en%part_hg)
            ! the sums of a run of elements of one part in registers (elements
            ! come part by part), added to the part's where the part changes
            pc = 0
            ake = 0; amom = 0; amass = 0; aie = 0; ahg = 0
            do e = 1, sh%n + 1
                p = -1
                if (e <= sh%n) p = sh%part(e)
                if (p /= pc) then
                    if (pc > 0) then
                        en%part_ke(pc) = en%part_ke(pc) + ake
                        en%part_mom(:, pc) = en%part_mom(:, pc) + amom
                        en%part_mass(pc) = en%part_mass(pc) + amass
                        en%part_ie(pc) = en%part_ie(pc) + aie
                        en%part_hg(pc) = en%part_hg(pc) + ahg
                        en%ie = en%ie + aie
                        en%hg = en%hg + ahg
                    end if
                    pc = p
                    ake = 0; amom = 0; amass = 0; aie = 0; ahg = 0
                end if
                if (e > sh%n) exit
                if (split) then
                    if (.not. shell_on(e)) cycle
                end if
                ! the shell's share of its nodes' mass (a third each for triangles)
                nn = 4
                if (sh%conn(3, e) == sh%conn(4, e)) nn = 3
                q = shell_row(sh, e)
                mshare = real(sh%pc%ro(sh%part(e))*sh%h(q)*sh%area0(q), dp)/nn
                if (allocated(sh%msf)) then
                    en%part_added(p) = en%part_added(p) + nn*mshare*(sh%msf(e) - 1.0_dp)
                    mshare = mshare*sh%msf(e)
                    if (sh%msf(e) /= 1.0_wp) en%nshell_scaled = en%nshell_scaled + 1
                end if
                ksum = 0
                msum = 0
                do k = 1, nn
                    nd = sh%conn(k, e)
                    ksum = ksum + en%kn(nd)
                    msum = msum + en%vn(:, nd)
                end do
                ake = ake + mshare*ksum
                amom = amom + mshare*msum
                amass = amass + mshare*nn
                aie = aie + (sh%eint(q) + dt_avg*sh%pend_int(q))
                ahg = ahg + (sh%ehg(q) + dt_avg*sh%pend_hg(q))
            end do
        end subroutine by_elements
    end subroutine compute_energies

    !> The fixed-mass path's pass over the nodes: the whole model's kinetic
    !> energy ke (1/2 m v(n-1/2).v(n+1/2)), momentum mom and spin energy ker,
    !> and the parts' kinetic energy and momentum by the node table (a run
    !> of one part summed in registers: nodes mostly come part by part);
    !> each sum in node order. A node on a rigid body (on, where present)
    !> counts nothing here (its body does); the spin only where irot, wminus
    !> and wplus are present. (Its own procedure on plain arrays: inside
    !> compute_energies the sums were kept in memory for want of registers,
    !> 11 ns a node.)
    subroutine node_sums(n, npart, mass, vminus, vplus, np_ptr, np_part, np_m, part_ke, part_mom, ke, mom, ker, on, &
                         irot, wminus, wplus)
        integer, intent(in) :: n, npart
        real(wp), intent(in) :: mass(n), vminus(3, n), vplus(3, n)
        integer, intent(in) :: np_ptr(n + 1), np_part(*)
        real(dp), intent(in) :: np_m(*)
        real(dp), intent(inout) :: part_ke(npart), part_mom(3, npart)
        real(dp), intent(out) :: ke, mom(3), ker
        logical, intent(in), optional :: on(n)
        real(wp), intent(in), optional :: irot(n), wminus(3, n), wplus(3, n)
        logical :: body, rot
        integer :: nd, k, p, pc
        real(dp) :: kn, vn1, vn2, vn3, ake, am1, am2, am3, ke_s, m1, m2, m3, kr
        logical :: on_body
        body = present(on)
        rot = present(irot) .and. present(wminus) .and. present(wplus)
        ke_s = 0
        m1 = 0; m2 = 0; m3 = 0
        kr = 0
        pc = 0
        ake = 0; am1 = 0; am2 = 0; am3 = 0
        do nd = 1, n
            kn = 0.5_dp*(real(vminus(1, nd), dp)*vplus(1, nd) + real(vminus(2, nd), dp)*vplus(2, nd) + &
                         real(vminus(3, nd), dp)*vplus(3, nd))
            vn1 = 0.5_dp*real(vminus(1, nd) + vplus(1, nd), dp)
            vn2 = 0.5_dp*real(vminus(2, nd) + vplus(2, nd), dp)
            vn3 = 0.5_dp*real(vminus(3, nd) + vplus(3, nd), dp)
            on_body = .false.
            if (body) on_body = on(nd)
            if (on_body) then
                kn = 0
                vn1 = 0; vn2 = 0; vn3 = 0
            end if
            ke_s = ke_s + mass(nd)*kn
            m1 = m1 + mass(nd)*vn1
            m2 = m2 + mass(nd)*vn2
            m3 = m3 + mass(nd)*vn3
            ! a rigid body's nodes spin with it: their inertia is in the body's
            if (rot .and. .not. on_body) &
                kr = kr + 0.5_dp*irot(nd)*(real(wminus(1, nd), dp)*wplus(1, nd) + &
                                           real(wminus(2, nd), dp)*wplus(2, nd) + &
                                           real(wminus(3, nd), dp)*wplus(3, nd))
            do k = np_ptr(nd), np_ptr(nd + 1) - 1
                p = np_part(k)
                if (p /= pc) then
                    if (pc > 0) then
                        part_ke(pc) = part_ke(pc) + ake
                        part_mom(1, pc) = part_mom(1, pc) + am1
                        part_mom(2, pc) = part_mom(2, pc) + am2
                        part_mom(3, pc) = part_mom(3, pc) + am3
                    end if
                    pc = p
                    ake = 0; am1 = 0; am2 = 0; am3 = 0
                end if
                ake = ake + np_m(k)*kn
                am1 = am1 + np_m(k)*vn1
                am2 = am2 + np_m(k)*vn2
                am3 = am3 + np_m(k)*vn3
            end do
        end do
        if (pc > 0) then
            part_ke(pc) = part_ke(pc) + ake
            part_mom(1, pc) = part_mom(1, pc) + am1
            part_mom(2, pc) = part_mom(2, pc) + am2
            part_mom(3, pc) = part_mom(3, pc) + am3
        end if
        ke = ke_s
        mom = [m1, m2, m3]
        ker = kr
    end subroutine node_sums

    !> The node-by-part mass table (each element's share of its nodes, as
    !> compute_energies weighs them: an eighth of a hexahedron, a quarter of
    !> a quadrilateral, a third of a triangle), where element masses stay
    !> fixed for the run: each node's incidences (the assembly's slot lists,
    !> solids then shells) with the shares of one part summed (a node has
    !> few).
    subroutine node_part_masses(model, st, solids, sh, en, bm, keep)
        type(model_t), intent(in) :: model
        type(state_t), intent(in) :: st
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        type(energies_t), intent(inout) :: en
        type(beams_t), intent(in), optional :: bm
        !> the nodes whose entries the table holds (absent: every node):
        !> every node's shares still go into the parts' masses, in node order
        logical, intent(in), optional :: keep(:)
        type(assembly_t) :: as, ash
        integer, allocatable :: ip(:)
        real(dp), allocatable :: im(:), fp(:)
        real(dp) :: madd
        integer :: e, k, nd, n, j, nrow, n0, most, nnode
        logical :: held
        en%fixed_mass = masses_fixed(solids, sh)
        ! (the model's nodes: with keep, the nodal arrays may be cut already)
        nnode = st%nnode
        if (present(keep)) nnode = size(keep)
        nrow = nnode
        if (present(keep)) nrow = count(keep)
        allocate (en%np_ptr(nrow + 1), en%part_mass0(model%npart))
        en%np_ptr = 1
        en%part_mass0 = 0
        if (.not. en%fixed_mass) then
            allocate (en%np_part(0), en%np_m(0))
            return
        end if
        call build_assembly(nnode, solids%conn, as)
        if (sh%n > 0) then
            call build_assembly(nnode, sh%conn, ash)
        else
            allocate (ash%ptr(nnode + 1), ash%slot(0))
            ash%ptr = 1
        end if
        n = 0
        if (present(bm)) n = 2*bm%n
        if (present(keep)) then
            ! (room for the kept nodes' entries, and one other node's at a
            ! time while its shares go into the parts' masses)
            most = 0
            j = 0
            do nd = 1, nnode
                k = as%ptr(nd + 1) - as%ptr(nd) + ash%ptr(nd + 1) - ash%ptr(nd)
                most = max(most, k)
                if (keep(nd)) j = j + k
            end do
            n = n + j + most
        else
            n = n + size(as%slot) + size(ash%slot)
        end if
        allocate (ip(n), im(n))
        n = 0
        nrow = 0
        do nd = 1, nnode
            held = .true.
            if (present(keep)) held = keep(nd)
            n0 = n
            if (held) then
                nrow = nrow + 1
                en%np_ptr(nrow) = n + 1
            end if
            do j = as%ptr(nd), as%ptr(nd + 1) - 1
                e = (as%slot(j) - 1)/8 + 1
                call add(solids%part(e), real(model%mat(model%part(solids%part(e))%mat_ix)%ro, dp)*solids%vol0(e)/8.0_dp)
            end do
            do j = ash%ptr(nd), ash%ptr(nd + 1) - 1
                e = (ash%slot(j) - 1)/4 + 1
                k = ash%slot(j) - 4*(e - 1)
                ! a triangle's fourth node is its third: counted once
                if (k == 4 .and. sh%conn(3, e) == sh%conn(4, e)) cycle
                call add(sh%part(e), real(sh%pc%ro(sh%part(e))*sh%h(e)*sh%area0(e), dp)/merge(3, 4, sh%conn(3, e) == sh%conn(4, e)))
            end do
            if (present(bm)) then
                if (bm%n > 0) then
                    do j = bm%ptr(nd), bm%ptr(nd + 1) - 1
                        e = (bm%inc(j) - 1)/2 + 1
                        call add(bm%part(e), real((bm%ro(e)*bm%a(e) + bm%nsm(e))* &
                                                  norm2(model%x0(:, bm%conn(2, e)) - model%x0(:, bm%conn(1, e)))/2, dp))
                    end do
                end if
            end if
            ! the node's shares into the parts' masses (in node order, as
            ! the whole table's were summed); another rank's node's entries
            ! are not kept
            do j = n0 + 1, n
                en%part_mass0(ip(j)) = en%part_mass0(ip(j)) + im(j)
            end do
            if (.not. held) n = n0
        end do
        en%np_ptr(nrow + 1) = n + 1
        en%np_part = ip(1:n)
        en%np_m = im(1:n)
        ! *ELEMENT_MASS_PART: the mass added in proportion to the part's own
        ! nodal shares, so its shares scale by the part's new mass over its own
        if (allocated(model%partmass)) then
            allocate (fp(model%npart))
            fp = 1
            do j = 1, size(model%partmass)
                do k = 1, size(model%partmass(j)%part_ix)
                    e = model%partmass(j)%part_ix(k)
                    if (en%part_mass0(e) <= 0.0_dp) cycle
                    madd = model%partmass(j)%addmass
                    if (model%partmass(j)%finmass > 0.0_wp) madd = model%partmass(j)%finmass - en%part_mass0(e)
                    if (madd > 0.0_dp) fp(e) = fp(e)*(1 + madd/en%part_mass0(e))
                end do
            end do
            en%np_m = en%np_m*fp(en%np_part)
            en%part_mass0 = en%part_mass0*fp
        end if
    contains
        !> Node nd's share m of part p: onto its entry of that part, or a new one.
        subroutine add(p, m)
            integer, intent(in) :: p
            real(dp), intent(in) :: m
            integer :: q
            do q = n0 + 1, n
                if (ip(q) == p) then
                    im(q) = im(q) + m
                    return
                end if
            end do
            n = n + 1
            ip(n) = p
            im(n) = m
        end subroutine add
    end subroutine node_part_masses

end module xd_solver_energies
