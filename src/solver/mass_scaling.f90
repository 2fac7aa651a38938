!> Mass scaling (*CONTROL_TIMESTEP DT2MS and MS1ST, *CONTROL_TERMINATION
!> ENDMAS), as LS-DYNA's manual gives it. DT2MS < 0: an element whose step
!> would fall below |DT2MS| gets mass on its nodes, enough to bring its step
!> back to |DT2MS| (the step scales with the square root of the mass), so
!> the elements never set a step below TSSFAC |DT2MS|. DT2MS > 0: at the
!> first cycle every element's mass is set so that its step is DT2MS
!> exactly (mass added or taken away), and from then on as for DT2MS < 0.
!> MS1ST = 1: the masses are set at the first cycle only. ENDMAS: the run
!> stops once the added mass passes that percentage of the model's mass.
!>
!> An element's mass is its factor msf times its own; each scaling adds
!> its own mass times the change in msf, shared equally by its nodes (and
!> the shell's rotary inertia likewise). The node keeps its velocity, so
!> the added mass enters with kinetic energy 1/2 dm v^2; that energy is
!> booked (st%ms_work) beside the external work, so the energy ratio still
!> checks the physics. Every rank applies every rank's scalings in element
!> order: the masses are bitwise those of one rank.
module xd_solver_mass_scaling
    use xd_kinds, only: wp, dp
    use xd_core_strings, only: itoa, rtoa, ftoa
    use xd_core_sorting, only: sort_index
    use xd_core_comm, only: comm_gather_records
    use xd_model, only: model_t, controls_t
    use xd_elements_solid_groups, only: solids_t, solid_name
    use xd_elements_shell_bt, only: shells_t, shell_name
    use xd_solver_state, only: state_t
    use xd_solver_domain, only: domain_t
    use xd_rigid_bodies, only: rigid_t
    use xd_output_d3hsp, only: log_t, log_line
    implicit none
    private
    public :: mass_scaling_t, mass_scaling_arrays, mass_scaling_begin, mass_scaling_targets, mass_scaling_step, &
              mass_scaling_summary

    !> elements named in d3hsp when first scaled; the rest are counted
    integer, parameter :: max_named = 20

    type :: mass_scaling_t
        logical :: on = .false.
        real(wp) :: target = 0            !< |DT2MS|: the element step kept
        logical :: positive = .false.     !< DT2MS > 0: every element set at the first cycle
        logical :: first_only = .false.   !< MS1ST = 1
        integer :: named = 0              !< elements named so far (this run)
        integer :: first_scaled = 0       !< elements scaled for the first time (this run)
        real(dp) :: t_first = -1          !< time of the first scaling (this run)
    end type mass_scaling_t

contains

    !> At set-up, before a restart dump is read: the element factors, 1.
    subroutine mass_scaling_arrays(ctl, solids, sh)
        type(controls_t), intent(in) :: ctl
        type(solids_t), intent(inout) :: solids
        type(shells_t), intent(inout) :: sh
        if (ctl%dt2ms == 0.0_wp) return
        allocate (solids%msf(solids%n), solids%ms_need(solids%n), sh%msf(sh%n), sh%ms_need(sh%n), sh%msq(sh%n))
        solids%msf = 1
        solids%ms_need = 0
        sh%msf = 1
        sh%msq = 1
        sh%ms_need = 0
    end subroutine mass_scaling_arrays

    subroutine mass_scaling_begin(ms, ctl, lg)
        type(mass_scaling_t), intent(out) :: ms
        type(controls_t), intent(in) :: ctl
        type(log_t), intent(in) :: lg
        ms%on = ctl%dt2ms /= 0.0_wp
        if (.not. ms%on) return
        ms%target = abs(ctl%dt2ms)
        ms%positive = ctl%dt2ms > 0.0_wp
        ms%first_only = ctl%ms1st == 1
        if (ms%positive) then
            call log_line(lg, ' mass scaling (DT2MS '//rtoa(real(ctl%dt2ms, dp))//'): every element''s mass set at '// &
                          'the first cycle for a step of '//rtoa(real(ms%target, dp))//' s, then added where a step '// &
                          'would fall below it')
        else
            call log_line(lg, ' mass scaling (DT2MS '//rtoa(real(ctl%dt2ms, dp))//'): mass added to an element '// &
                          'whose step would fall below '//rtoa(real(ms%target, dp))//' s; the run''s step stays at '// &
                          'or above TSSFAC x |DT2MS| = '//rtoa(real(ctl%tssfac*ms%target, dp))//' s where the '// &
                          'elements set it')
        end if
        if (ms%first_only) call log_line(lg, ' mass scaling at the first cycle only (MS1ST 1)')
        if (ctl%endmas > 0.0_wp) call log_line(lg, ' the run stops when the added mass passes '// &
                                               ftoa(real(ctl%endmas, dp))//'% of the model''s (ENDMAS)')
    end subroutine mass_scaling_begin

    !> The step the element pass of this cycle must keep.
    subroutine mass_scaling_targets(ms, cycle, solids, sh)
        type(mass_scaling_t), intent(in) :: ms
        integer, intent(in) :: cycle
        type(solids_t), intent(inout) :: solids
        type(shells_t), intent(inout) :: sh
        real(wp) :: t
        t = ms%target
        if (ms%first_only .and. cycle > 0) t = 0
        solids%ms_target = t
        sh%ms_target = t
        solids%ms_all = ms%positive .and. cycle == 0
        sh%ms_all = solids%ms_all
    end subroutine mass_scaling_targets

    !> After the element pass: the factors it asked for, on every rank's
    !> nodes. stop_message: set when the added mass passes ENDMAS.
    subroutine mass_scaling_step(ms, model, dom, solids, sh, st, rg, lg, stop_message)
        type(mass_scaling_t), intent(inout) :: ms
        type(model_t), intent(in) :: model
        type(domain_t), intent(in) :: dom
        type(solids_t), intent(inout) :: solids
        type(shells_t), intent(inout) :: sh
        type(state_t), intent(inout) :: st
        type(rigid_t), intent(in) :: rg
        type(log_t), intent(in) :: lg
        character(len=:), allocatable, intent(out) :: stop_message
        real(dp), allocatable :: rec(:, :), all(:, :)
        integer, allocatable :: perm(:)
        integer :: i, n
        real(dp) :: added, pct
        n = count(solids%ms_need > 0.0_wp) + count(sh%ms_need > 0.0_wp)
        allocate (rec(11, n))
        n = 0
        call collect(1, solids%ms_need)
        call collect(2, sh%ms_need)
        if (dom%on) then
            ! every rank's, in element order (solids, then shells)
            call comm_gather_records(rec, dom%nranks, all)
            call sort_index(all(1, :)*(real(max(solids%n, sh%n), dp) + 1) + all(2, :), perm)
            all = all(:, perm)
        else
            call move_alloc(rec, all)
        end if
        if (size(all, 2) == 0) return
        do i = 1, size(all, 2)
            call scale_element(nint(all(1, i)), nint(all(2, i)), real(all(3, i), wp), all(4:11, i))
        end do
        if (model%ctl%endmas > 0.0_wp) then
            added = element_added_mass(model, solids, sh)
            pct = 100*added/(sum(real(st%mass, dp)) - added)
            if (pct > model%ctl%endmas) stop_message = 'the added mass '//rtoa(added)//' is '//ftoa(pct)// &
                '% of the model''s, past ENDMAS '//ftoa(real(model%ctl%endmas, dp))//'%; '// &
                heaviest(model, solids, sh, st%nnode, 1)
        end if

    contains

        !> This rank's asks of one kind (1 solids, 2 shells) as records, in
        !> element order, with the squared speeds of the element's nodes
        !> (the added mass's kinetic energy: the element's own rank holds
        !> them current, with owned nodes the others may not); the asks
        !> cleared.
        subroutine collect(kind, need)
            integer, intent(in) :: kind
            real(wp), intent(inout) :: need(:)
            integer :: e, k, nd
            real(dp) :: v2(8)
            do e = 1, size(need)
                if (need(e) > 0.0_wp) then
                    v2 = 0
                    do k = 1, merge(8, 4, kind == 1)
                        if (kind == 1) then
                            nd = solids%conn(k, e)
                        else
                            nd = sh%conn(k, e)
                        end if
                        v2(k) = sum(real(st%v(:, nd), dp)**2)
                    end do
                    n = n + 1
                    rec(:, n) = [real(kind, dp), real(e, dp), real(need(e), dp), v2]
                    need(e) = 0
                end if
            end do
        end subroutine collect

        subroutine scale_element(kind, e, f1, v2)
            integer, intent(in) :: kind, e
            real(wp), intent(in) :: f1
            real(dp), intent(in) :: v2(8)   !< the squared speeds of its nodes (collect)
            integer :: k, nn, nd
            real(wp) :: f0, me, dm, dj
            dj = 0
            if (kind == 1) then
                f0 = solids%msf(e)
                me = real(solid_mass(model, solids, e), wp)
                nn = 8
                solids%msf(e) = f1
            else
                f0 = sh%msf(e)
                nn = 4
                if (sh%conn(3, e) == sh%conn(4, e)) nn = 3
                me = real(shell_mass(sh, e), wp)
                ! the rotary inertia of shell_masses, scaled alike
                dj = (f1 - f0)*me/nn*(sh%h(e)**2 + 3.0_wp*sh%area0(e))/12.0_wp
                sh%msf(e) = f1
                sh%msq(e) = sqrt(f1)
            end if
            dm = (f1 - f0)*me/nn
            do k = 1, nn
                if (kind == 1) then
                    nd = solids%conn(k, e)
                else
                    nd = sh%conn(k, e)
                end if
                ! a rigid body's node moves with the body's own inertia
                if (rg%n > 0) then
                    if (rg%on(nd)) cycle
                end if
                st%ms_work = st%ms_work + 0.5_dp*dm*v2(k)
                st%mass(nd) = st%mass(nd) + dm
                if (kind == 2) st%irot(nd) = st%irot(nd) + dj
            end do
            if (f0 /= 1.0_wp) return
            ms%first_scaled = ms%first_scaled + 1
            if (ms%t_first < 0) ms%t_first = st%time
            if (ms%named >= max_named) return
            ms%named = ms%named + 1
            if (kind == 1) then
                call log_line(lg, ' mass scaling: '//solid_name(model, solids, e)//' at time '//rtoa(st%time)//', cycle '// &
                              itoa(st%cycle)//': its mass x '//rtoa(real(f1, dp))//' (+'//rtoa(real(nn*dm, dp))//')')
            else
                call log_line(lg, ' mass scaling: '//shell_name(model, sh, e)//' at time '//rtoa(st%time)//', cycle '// &
                              itoa(st%cycle)//': its mass x '//rtoa(real(f1, dp))//' (+'//rtoa(real(nn*dm, dp))//')')
            end if
            if (ms%named == max_named) call log_line(lg, ' mass scaling: further elements are counted, '// &
                                                     'not named (the summary at the end)')
        end subroutine scale_element
    end subroutine mass_scaling_step

    !> An element's own mass (unscaled): the solid's density times its
    !> initial volume; the shell's as shell_masses lumps it.
    real(dp) function solid_mass(model, solids, e)
        type(model_t), intent(in) :: model
        type(solids_t), intent(in) :: solids
        integer, intent(in) :: e
        solid_mass = real(model%mat(model%part(solids%part(e))%mat_ix)%ro, dp)*solids%vol0(e)
    end function solid_mass

    real(dp) function shell_mass(sh, e)
        type(shells_t), intent(in) :: sh
        integer, intent(in) :: e
        shell_mass = real(sh%pc%ro(sh%part(e)), dp)*sh%h(e)*sh%area0(e)
    end function shell_mass

    !> Mass added to the deformable elements so far (taken away: negative).
    real(dp) function element_added_mass(model, solids, sh) result(added)
        type(model_t), intent(in) :: model
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        integer :: e
        added = 0
        if (allocated(solids%msf)) then
            do e = 1, solids%n
                if (solids%msf(e) /= 1.0_wp) added = added + (solids%msf(e) - 1.0_dp)*solid_mass(model, solids, e)
            end do
        end if
        if (allocated(sh%msf)) then
            do e = 1, sh%n
                if (sh%msf(e) /= 1.0_wp) added = added + (sh%msf(e) - 1.0_dp)*shell_mass(sh, e)
            end do
        end if
    end function element_added_mass

    !> The nodes with the most added mass, as text (at most nmax).
    function heaviest(model, solids, sh, nnode, nmax) result(s)
        type(model_t), intent(in) :: model
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        integer, intent(in) :: nnode, nmax
        character(len=:), allocatable :: s
        real(dp), allocatable :: dm(:)
        integer, allocatable :: perm(:)
        integer :: e, k, nn, i
        allocate (dm(nnode))
        dm = 0
        do e = 1, solids%n
            if (solids%msf(e) == 1.0_wp) cycle
            do k = 1, 8
                dm(solids%conn(k, e)) = dm(solids%conn(k, e)) + (solids%msf(e) - 1.0_dp)*solid_mass(model, solids, e)/8
            end do
        end do
        do e = 1, sh%n
            if (sh%msf(e) == 1.0_wp) cycle
            nn = 4
            if (sh%conn(3, e) == sh%conn(4, e)) nn = 3
            do k = 1, nn
                dm(sh%conn(k, e)) = dm(sh%conn(k, e)) + (sh%msf(e) - 1.0_dp)*shell_mass(sh, e)/nn
            end do
        end do
        call sort_index(-dm, perm)
        s = 'the most added at node'
        if (nmax > 1) s = s//'s'
        do i = 1, min(nmax, nnode)
            if (dm(perm(i)) <= 0) exit
            if (i > 1) s = s//','
            s = s//' '//itoa(model%node_id(perm(i)))//' (+'//rtoa(dm(perm(i)))//')'
        end do
    end function heaviest

    !> The end-of-run lines for d3hsp.
    subroutine mass_scaling_summary(ms, model, solids, sh, st, lg)
        type(mass_scaling_t), intent(in) :: ms
        type(model_t), intent(in) :: model
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        type(state_t), intent(in) :: st
        type(log_t), intent(in) :: lg
        real(dp) :: added, total
        if (.not. ms%on) return
        added = element_added_mass(model, solids, sh)
        total = sum(real(st%mass, dp))
        call log_line(lg, '')
        call log_line(lg, ' mass scaling: '//itoa(count(solids%msf /= 1.0_wp))//' solids and '// &
                      itoa(count(sh%msf /= 1.0_wp))//' shells carry scaled mass; added '//rtoa(added)//', '// &
                      ftoa(100*added/(total - added))//'% of the model''s '//rtoa(total - added))
        if (ms%first_scaled > 0) call log_line(lg, '   this run scaled '//itoa(ms%first_scaled)// &
                                               ' elements for the first time, the first at time '//rtoa(ms%t_first))
        call log_line(lg, '   kinetic energy the added mass entered with: '//rtoa(st%ms_work)// &
                      ' (counted beside the external work in the energy ratio)')
        if (added /= 0) call log_line(lg, '   '//heaviest(model, solids, sh, st%nnode, 5))
    end subroutine mass_scaling_summary

end module xd_solver_mass_scaling
