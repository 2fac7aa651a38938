!> What set the time step, cycle by cycle: an element (solid or shell), the
!> contact springs' stable-step bound, or the mass-scaling floor (DT2MS).
!> d3hsp gets the count of each at the end of the run, the elements that
!> set it most often by name, so that a user sees whether one crushed
!> element held the whole run back.
module xd_solver_step_control
    use xd_kinds, only: dp, wp
    use xd_core_strings, only: itoa
    use xd_core_sorting, only: sort_index
    use xd_model, only: model_t
    use xd_elements_solid_groups, only: solids_t, solid_name
    use xd_elements_shell_bt, only: shells_t, shell_name
    use xd_output_d3hsp, only: log_t, log_line
    implicit none
    private
    public :: step_stats_t, step_stats_init, step_stats_count, step_stats_report, hourglass_bound_report
    public :: by_element, by_contact, by_floor, by_other, by_growth, dt_growth

    integer, parameter :: by_element = 1, by_contact = 2, by_floor = 3, by_other = 4, by_growth = 5
    !> The step may fall at once but grows by at most this factor a cycle.
    !> An element's step is shorter while it compresses (the bulk
    !> viscosity's linear term enters it only then, 6% at Q2 0.06), so an
    !> element ringing in its highest mode compresses and expands on
    !> alternate cycles, and a step taken from it follows the mode's phase:
    !> shorter in one half of the swing, longer in the other. That feedback
    !> pumps the mode parametrically: one mode under the central difference
    !> at omega dt 1.6-1.8 (TSSFAC 0.9 reaches that) grows without bound
    !> (1e12 in 4,000 cycles at 1.6), where a fixed step, or one alternating
    !> without regard to the phase, stays bounded. Growth held to 1% a cycle
    !> still grows at 1.8 (130 times); 0.1% does not. (A cube dropped on its
    !> corner with the Lagrangian projection and no contact step bound went
    !> up this way in 480 cycles, issue 28.)
    real(wp), parameter :: dt_growth = 1.001_wp
    integer, parameter :: named = 5   !< elements named in the report

    type :: step_stats_t
        integer :: ncycle = 0
        integer :: nkind(5) = 0             !< cycles set by each of by_*
        integer, allocatable :: solid(:), shell(:)   !< cycles each element set the step
    end type step_stats_t

contains

    subroutine step_stats_init(ss, nsolid, nshell)
        type(step_stats_t), intent(out) :: ss
        integer, intent(in) :: nsolid, nshell
        allocate (ss%solid(nsolid), ss%shell(nshell))
        ss%solid = 0
        ss%shell = 0
    end subroutine step_stats_init

    !> One cycle: what set its step (by_*); crit: the element (solids > 0,
    !> minus the shell's index), for by_element and by_floor.
    subroutine step_stats_count(ss, kind, crit)
        type(step_stats_t), intent(inout) :: ss
        integer, intent(in) :: kind, crit
        ss%ncycle = ss%ncycle + 1
        ss%nkind(kind) = ss%nkind(kind) + 1
        if (kind /= by_element) return
        if (crit > 0) then
            ss%solid(crit) = ss%solid(crit) + 1
        else if (crit < 0) then
            ss%shell(-crit) = ss%shell(-crit) + 1
        end if
    end subroutine step_stats_count

    !> d3hsp's account of what set the step over the run: the share of
    !> cycles of each kind, the elements that set it longest, and the node
    !> whose contact spring sets the springs' bound (contact_node, a model
    !> node; 0: none).
    subroutine step_stats_report(ss, model, solids, sh, lg, contact_node)
        type(step_stats_t), intent(in) :: ss
        type(model_t), intent(in) :: model
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        type(log_t), intent(in) :: lg
        integer, intent(in) :: contact_node
        integer, allocatable :: perm(:), cnt(:)
        integer :: i, k, ns
        if (ss%ncycle == 0) return
        call log_line(lg, '')
        call log_line(lg, ' time step over the '//itoa(ss%ncycle)//' cycles of this run: set by an element in '// &
                      share(ss%nkind(by_element), ss%ncycle)//', by the contact springs'' bound in '// &
                      share(ss%nkind(by_contact), ss%ncycle)//', by the mass-scaling floor TSSFAC x |DT2MS| in '// &
                      share(ss%nkind(by_floor), ss%ncycle)//', otherwise (DTINIT, no element) in '// &
                      share(ss%nkind(by_other), ss%ncycle)//'; held to 0.1% growth a cycle in '// &
                      share(ss%nkind(by_growth), ss%ncycle))
        if (ss%nkind(by_contact) > 0 .and. contact_node > 0) &
            call log_line(lg, '   the contact springs'' bound: the stiffest spring, at node '// &
                          itoa(model%node_id(contact_node))//' (0.35 sqrt(m / k)): '// &
                          share(ss%nkind(by_contact), ss%ncycle))
        ns = size(ss%solid)
        cnt = [ss%solid, ss%shell]
        if (count(cnt > 0) == 0) return
        call sort_index(-real(cnt, dp), perm)
        do i = 1, min(named, count(cnt > 0))
            k = perm(i)
            if (k <= ns) then
                call log_line(lg, '   '//solid_name(model, solids, k)//': '//share(cnt(k), ss%ncycle))
            else
                call log_line(lg, '   '//shell_name(model, sh, k - ns)//': '//share(cnt(k), ss%ncycle))
            end if
        end do
        if (count(cnt > 0) > named) call log_line(lg, '   and '//itoa(count(cnt > 0) - named)// &
                                                  ' other elements: '//share(sum(cnt(perm(named + 1:))), ss%ncycle))
    end subroutine step_stats_report

    !> d3hsp's lines on the bounded shell hourglass (*CONTROL_XDYNA_SHELL
    !> HGBOUND 1) over the cycles of this run: how many shells the bound
    !> acted on (ncap, by shell number, summed over the ranks by the caller), and the
    !> ten it acted on longest; nothing where it never acted.
    subroutine hourglass_bound_report(ss, model, sh, ncap, lg)
        type(step_stats_t), intent(in) :: ss
        type(model_t), intent(in) :: model
        type(shells_t), intent(in) :: sh
        integer, intent(in) :: ncap(:)
        type(log_t), intent(in) :: lg
        integer, parameter :: longest = 10
        integer, allocatable :: perm(:)
        integer :: i, k, nact
        if (ss%ncycle == 0) return
        nact = count(ncap > 0)
        if (nact == 0) return
        call log_line(lg, '')
        call log_line(lg, ' stiffness-form hourglass of plastic shells bounded at its coefficient times the mode''s '// &
                      'plastic capacity: in '//itoa(nact)//' of '//itoa(sh%n)//' shells over the '//itoa(ss%ncycle)// &
                      ' cycles of this run (the cut-off work booked as hourglass energy); longest:')
        call sort_index(-real(ncap, dp), perm)
        do i = 1, min(longest, nact)
            k = perm(i)
            call log_line(lg, '   '//shell_name(model, sh, k)//': '//share(ncap(k), ss%ncycle))
        end do
        if (nact > longest) call log_line(lg, '   and '//itoa(nact - longest)//' other shells')
    end subroutine hourglass_bound_report

    !> n cycles of ncycle, as d3hsp's reports give them: "n cycles (x%)".
    function share(n, ncycle) result(s)
        integer, intent(in) :: n, ncycle
        character(len=:), allocatable :: s
        character(len=8) :: pc
        write (pc, '(f6.1)') 100.0_dp*n/ncycle
        s = itoa(n)//' cycles ('//trim(adjustl(pc))//'%)'
    end function share

end module xd_solver_step_control
