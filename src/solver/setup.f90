!> From a checked model to the initial state: element groups, volumes, lumped
!> masses, constraint masks, initial velocities and stresses.
module xd_solver_setup
    use xd_kinds, only: wp, dp
    use xd_core_memory, only: alloc
    use xd_model, only: model_t, find_set, constraint_dirs, set_node, set_part, iv_node_set, iv_node, iv_generation, &
                        mat_elastic, find_box, in_box, mark_part_nodes
    use xd_core_sorting, only: id_map_t
    use xd_elements_hex8, only: hex_b_matrix
    use xd_elements_solid_groups, only: solids_t, build_solids, material_plastic_law
    use xd_elements_solid_step_check, only: check_solid_steps
    use xd_solver_state, only: state_t
    use xd_core_dofs, only: free3, free3r, all_free
    use xd_core_vectors, only: cross
    use xd_solver_assembly, only: assembly_t, build_assembly
    use xd_rigid_bodies, only: rigid_t, rigid_lumped_mass, build_rigid
    use xd_elements_beam_bs, only: beams_t, build_beams, beam_masses
    use xd_elements_shell_bt, only: shells_t, build_shells, shell_masses
    use xd_solver_mass_scaling, only: mass_scaling_arrays
    use xd_core_errors, only: error_t, make_error
    use xd_core_strings, only: itoa, rtoa
    implicit none
    private
    public :: setup_run

contains

    subroutine setup_run(model, hex_map, st, solids, asm, rg, sh, asm_sh, bm, nfree_nodes, error, step_note)
        type(model_t), intent(in) :: model
        type(id_map_t), intent(in) :: hex_map
        type(state_t), intent(out) :: st
        type(solids_t), intent(out) :: solids
        type(assembly_t), intent(out) :: asm
        type(rigid_t), intent(out) :: rg
        type(shells_t), intent(out) :: sh
        type(assembly_t), intent(out) :: asm_sh
        type(beams_t), intent(out) :: bm
        integer, intent(out) :: nfree_nodes
        type(error_t), allocatable, intent(out) :: error
        character(len=:), allocatable, intent(out) :: step_note   !< a scaled solid step, for d3hsp ('' if none)
        character(len=:), allocatable :: mass_note
        integer :: i
        st%nnode = model%nnode
        call alloc(st%x, 3, st%nnode, 'coordinates')
        call alloc(st%v, 3, st%nnode, 'velocities')
        ! (the accelerations, forces and moments, which no set-up reads, are
        ! allocated by the time loop, once it knows the nodes this rank
        ! holds: allocate_force_arrays)
        call alloc(st%mass, st%nnode, 'nodal masses')
        allocate (st%dofs(st%nnode))
        ! (the initial coordinates are the deck's: model%x0, held once)
        st%x = model%x0(:, 1:st%nnode)
        call build_solids(model, solids)
        call build_assembly(st%nnode, solids%conn, asm)
        call initial_volumes_and_mass(solids, st)
        call rigid_lumped_mass(model, st)
        call build_shells(model, sh, material_plastic_law)
        call mass_scaling_arrays(model%ctl, solids, sh)
        call build_beams(model, bm)
        if (sh%n > 0 .or. bm%n > 0) then
            st%rot = .true.
            call alloc(st%vr, 3, st%nnode, 'angular velocities')
            call alloc(st%irot, st%nnode, 'rotational inertia')
        end if
        if (sh%n > 0) then
            call shell_masses(sh, st%x, st%mass, st%irot)
            call build_assembly(st%nnode, sh%conn, asm_sh)
        end if
        if (bm%n > 0) call beam_masses(bm, st%x, st%mass, st%irot)
        ! *ELEMENT_MASS: point masses join their nodes' (and so a rigid
        ! body's, where the node is on one: the body takes a node's mass
        ! beyond its own elements' as a point mass)
        do i = 1, model%npmass
            st%mass(model%pmass(i)%ix) = st%mass(model%pmass(i)%ix) + model%pmass(i)%mass
        end do
        ! *ELEMENT_MASS_PART(_SET): to the parts' nodes
        mass_note = ''
        if (allocated(model%partmass)) call add_part_masses(model, solids, sh, st, mass_note)
        nfree_nodes = count(st%mass <= 0.0_wp)
        call constraint_masks(model, st)
        call initial_velocities(model, solids, st)
        do i = 1, st%nnode
            st%v(:, i) = st%v(:, i)*free3(st%dofs(i))
            if (st%rot) st%vr(:, i) = st%vr(:, i)*free3r(st%dofs(i))
        end do
        call check_speeds(model, st, error)
        if (allocated(error)) return
        call build_rigid(model, st, rg, error)
        if (allocated(error)) return
        call initial_stresses(model, hex_map, solids, st)
        call check_solid_steps(solids, model%x0, st%mass, st%dofs, model%ctl%tssfac, model%part(1:model%npart)%id, &
                               step_note)
        ! the part masses added, named with the step's notes in d3hsp
        if (len(mass_note) > 0) step_note = step_note//merge(new_line('a'), ' ', len(step_note) > 0)// &
                                            mass_note(1:len(mass_note) - 1)
    end subroutine setup_run

    subroutine initial_volumes_and_mass(s, st)
        type(solids_t), intent(inout) :: s
        type(state_t), intent(inout) :: st
        integer :: g, a, b, n, i, k
        real(wp), allocatable :: xl(:, :), yl(:, :), zl(:, :), bx(:, :), by(:, :), bz(:, :), vol(:)
        do g = 1, s%ngroup
            a = s%group(g)%first
            b = s%group(g)%last
            n = b - a + 1
            allocate (xl(n, 8), yl(n, 8), zl(n, 8), bx(n, 8), by(n, 8), bz(n, 8), vol(n))
            do k = 1, 8
                xl(:, k) = st%x(1, s%conn(k, a:b))
                yl(:, k) = st%x(2, s%conn(k, a:b))
                zl(:, k) = st%x(3, s%conn(k, a:b))
            end do
            call hex_b_matrix(n, xl, yl, zl, bx, by, bz, vol)
            s%vol0(a:b) = vol
            s%vol(a:b) = vol
            do i = 1, n
                do k = 1, 8
                    st%mass(s%conn(k, a + i - 1)) = st%mass(s%conn(k, a + i - 1)) + &
                                                    s%group(g)%ro*vol(i)/8.0_wp
                end do
            end do
            deallocate (xl, yl, zl, bx, by, bz, vol)
        end do
    end subroutine initial_volumes_and_mass

    !> *ELEMENT_MASS_PART(_SET): each part's added mass (ADDMASS, or FINMASS
    !> less the part's own mass) shared among its nodes in proportion to
    !> the part's own nodal masses (its elements' lumped shares), so that
    !> the part's mass distribution keeps its shape. `note` (d3hsp) names
    !> each part's mass before and after; a FINMASS below the part's own
    !> mass is named and nothing added.
    subroutine add_part_masses(model, solids, sh, st, note)
        type(model_t), intent(in) :: model
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        type(state_t), intent(inout) :: st
        character(len=:), allocatable, intent(inout) :: note
        real(wp), allocatable :: share(:)
        real(dp) :: mp, add
        integer :: i, q, e, k, p, nn, g
        character(len=200) :: buf
        allocate (share(st%nnode))
        do i = 1, size(model%partmass)
            associate (pm => model%partmass(i))
                do q = 1, size(pm%part_ix)
                    p = pm%part_ix(q)
                    share = 0
                    do g = 1, solids%ngroup
                        do e = solids%group(g)%first, solids%group(g)%last
                            if (solids%part(e) /= p) cycle
                            do k = 1, 8
                                share(solids%conn(k, e)) = share(solids%conn(k, e)) + &
                                                           solids%group(g)%ro*solids%vol0(e)/8
                            end do
                        end do
                    end do
                    do e = 1, sh%n
                        if (sh%part(e) /= p) cycle
                        nn = merge(3, 4, sh%conn(3, e) == sh%conn(4, e))
                        do k = 1, nn
                            share(sh%conn(k, e)) = share(sh%conn(k, e)) + sh%pc%ro(sh%part(e))*sh%h(e)*sh%area0(e)/nn
                        end do
                    end do
                    mp = sum(real(share, dp))
                    add = pm%addmass
                    if (pm%finmass > 0.0_wp) add = pm%finmass - mp
                    if (mp <= 0.0_dp .or. add < 0.0_dp) then
                        write (buf, '(a,i0,a,es12.5,a,es12.5,a)') '*ELEMENT_MASS_PART: part ', model%part(p)%id, &
                            ' has mass ', mp, '; FINMASS ', pm%finmass, ' is below it (or the part has no '// &
                            'elements): nothing added'
                        note = note//trim(buf)//new_line('a')
                        cycle
                    end if
                    st%mass = st%mass + real(add/mp, wp)*share
                    write (buf, '(a,i0,a,es12.5,a,es12.5)') ' *ELEMENT_MASS_PART: part ', model%part(p)%id, &
                        ': mass ', mp, ' -> ', mp + add
                    note = note//trim(buf)//new_line('a')
                end do
            end associate
        end do
    end subroutine add_part_masses

    !> *NODE TC/RC codes and *BOUNDARY_SPC: each fixed translation's
    !> (rotation's, with shells or beams) bit cleared in the node's dofs
    !> code; massless nodes and nodes without rotational inertia do not
    !> move in those directions.
    subroutine constraint_masks(model, st)
        type(model_t), intent(in) :: model
        type(state_t), intent(inout) :: st
        integer :: i, j, k, s
        logical :: fix(3)
        st%dofs = all_free
        do i = 1, st%nnode
            fix = constraint_dirs(model%node_tc(i)) .or. st%mass(i) <= 0.0_wp
            do j = 1, 3
                if (fix(j)) st%dofs(i) = ibclr(st%dofs(i), j - 1)
            end do
            if (.not. st%rot) cycle
            fix = constraint_dirs(model%node_rc(i)) .or. st%irot(i) <= 0.0_wp
            do j = 1, 3
                if (fix(j)) st%dofs(i) = ibclr(st%dofs(i), j + 2)
            end do
        end do
        do i = 1, model%nspc
            associate (c => model%spc(i))
                if (c%is_set) then
                    s = find_set(model, set_node, c%id)
                    do k = 1, model%set(s)%n
                        call apply_dofs(c%dof, model%set(s)%member_ix(k))
                    end do
                else
                    call apply_dofs(c%dof, c%ix)
                end if
            end associate
        end do
    contains
        subroutine apply_dofs(dof, nd)
            integer, intent(in) :: dof(6), nd
            integer :: j
            do j = 1, 3
                if (dof(j) == 1) st%dofs(nd) = ibclr(st%dofs(nd), j - 1)
                if (st%rot .and. dof(j + 3) == 1) st%dofs(nd) = ibclr(st%dofs(nd), j + 2)
            end do
        end subroutine apply_dofs
    end subroutine constraint_masks

    !> Node-set velocities first (NSID 0: every node), then generations,
    !> then single nodes, so the most specific definition wins.
    !> Initial velocities whose kinetic energy the run cannot hold: a node
    !> of mass m at speed |v| beyond sqrt(huge / m) / 1000 (the energies,
    !> summed over the model, would overflow; the arithmetic that found it
    !> trapped in the debug build). The speed is compared, never squared.
    subroutine check_speeds(model, st, error)
        type(model_t), intent(in) :: model
        type(state_t), intent(in) :: st
        type(error_t), allocatable, intent(out) :: error
        integer :: k
        real(wp) :: vmax, speed
        do k = 1, st%nnode
            vmax = sqrt(huge(1.0_wp)/max(st%mass(k), 1.0_wp))*1.0e-3_wp
            speed = maxval(abs(st%v(:, k)))
            if (st%rot) speed = max(speed, maxval(abs(st%vr(:, k))))
            if (speed > vmax) then
                call make_error(error, 'node '//itoa(model%node_id(k))//': its initial velocity ('// &
                                rtoa(real(speed, dp))// &
                                ') is beyond what the energies can hold (at most '//rtoa(real(vmax, dp))// &
                                ' for its mass): a *INITIAL_VELOCITY value far out of range?')
                return
            end if
        end do
    end subroutine check_speeds

    subroutine initial_velocities(model, solids, st)
        type(model_t), intent(in) :: model
        type(solids_t), intent(in) :: solids
        type(state_t), intent(inout) :: st
        integer :: i, k, s, pass
        logical, allocatable :: mark(:), exempt(:)
        allocate (mark(st%nnode), exempt(st%nnode))
        do pass = 1, 3
            do i = 1, model%nivel
                associate (iv => model%ivel(i))
                    if (pass == 1 .and. iv%kind == iv_node_set) then
                        exempt = .false.
                        if (iv%exempt /= 0) then
                            s = find_set(model, set_node, iv%exempt)
                            exempt(model%set(s)%member_ix) = .true.
                        end if
                        if (iv%id == 0) then
                            mark = .true.
                        else
                            mark = .false.
                            s = find_set(model, set_node, iv%id)
                            mark(model%set(s)%member_ix) = .true.
                        end if
                        mark = mark .and. .not. exempt
                        if (iv%boxid /= 0) then
                            s = find_box(model, iv%boxid)
                            do k = 1, st%nnode
                                if (.not. in_box(model%box(s), model%x0(:, k))) mark(k) = .false.
                            end do
                        end if
                        do k = 1, st%nnode
                            if (mark(k)) st%v(:, k) = iv%v
                            if (mark(k) .and. st%rot) st%vr(:, k) = iv%vr
                        end do
                    else if (pass == 2 .and. iv%kind == iv_generation) then
                        mark = .false.
                        select case (iv%styp)
                        case (1)
                            s = find_set(model, set_part, iv%id)
                            do k = 1, model%set(s)%n
                                call mark_part(model%set(s)%member_ix(k))
                            end do
                        case (2)
                            do k = 1, model%npart
                                if (model%part(k)%id == iv%id) call mark_part(k)
                            end do
                        case (3)
                            s = find_set(model, set_node, iv%id)
                            mark(model%set(s)%member_ix) = .true.
                        end select
                        do k = 1, st%nnode
                            if (mark(k)) st%v(:, k) = iv%v + iv%omega* &
                                                      real(cross(real(iv%axis, dp), real(st%x(:, k) - iv%xc, dp)), wp)
                            if (mark(k) .and. st%rot) st%vr(:, k) = iv%omega*iv%axis
                        end do
                    else if (pass == 3 .and. iv%kind == iv_node) then
                        st%v(:, iv%ix) = iv%v
                        if (st%rot) st%vr(:, iv%ix) = iv%vr
                    end if
                end associate
            end do
        end do
    contains
        subroutine mark_part(p)
            integer, intent(in) :: p
            call mark_part_nodes(model, p, mark)
        end subroutine mark_part
    end subroutine initial_velocities

    !> *INITIAL_STRESS_SOLID, and the strain energy it stores (linear elastic).
    subroutine initial_stresses(model, hex_map, s, st)
        type(model_t), intent(in) :: model
        type(id_map_t), intent(in) :: hex_map
        type(solids_t), intent(inout) :: s
        type(state_t), intent(inout) :: st
        integer :: i, e, m
        integer, allocatable :: where(:)
        real(wp) :: sg(6), em, nu
        if (model%nistress == 0) return
        allocate (where(model%nhex))
        where = 0
        where(s%model_ix) = [(e, e=1, s%n)]
        do i = 1, model%nistress
            e = hex_map%find(model%istress(i)%eid)
            if (model%mat(model%part(model%hex_part(e))%mat_ix)%mtype /= mat_elastic) cycle
            e = where(e)
            sg = model%istress(i)%sig
            call s%set_stress(e, sg)
            m = model%part(s%part(e))%mat_ix
            if (model%mat(m)%mtype == mat_elastic) then
                em = model%mat(m)%e
                nu = model%mat(m)%pr
                s%eint(e) = real(s%vol0(e), dp)/(2.0_dp*em)*((1.0_dp + nu)*(sum(real(sg(1:3), dp)**2) &
                            + 2.0_dp*sum(real(sg(4:6), dp)**2)) - nu*sum(real(sg(1:3), dp))**2)
            end if
        end do
    end subroutine initial_stresses

end module xd_solver_setup
