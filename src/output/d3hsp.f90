!> The d3hsp log: banner, model summary with the subsystems in use, warnings,
!> energy ratio at intervals, the termination message and the timing table.
module xd_output_d3hsp
    use xd_kinds, only: wp, dp
    use xd_core_strings, only: itoa, join_path, out_path
    use xd_core_timers, only: timers_t, nphase, phase_name, ph_elements, ph_assembly, ph_integrate, &
                              ph_contact, ph_rigid, ph_output, ph_search, ph_local, ph_enforce, ph_comm, ph_ghost, ph_wait
    use xd_model, only: model_t, part_ihq, hg_bounded, hg_boundable, any_erosion
    use xd_elements_solid_groups, only: solids_t, hg_stiffness
    use xd_output_histories, only: version_line
    implicit none
    private
    public :: log_t, log_open, log_line, log_close, model_summary, timing_table

    type :: log_t
        integer :: unit = 0
        logical :: open = .false.
    end type log_t

contains

    !> Create the log, or (append: a restart) go on after the first run's.
    !> Open the printed output at `path` (out_path(stem, 'd3hsp'), or o=).
    subroutine log_open(path, lg, ok, append)
        character(len=*), intent(in) :: path
        type(log_t), intent(out) :: lg
        logical, intent(out) :: ok
        logical, intent(in), optional :: append
        integer :: st
        logical :: more
        more = .false.
        if (present(append)) more = append
        if (more) then
            open (newunit=lg%unit, file=path, status='unknown', position='append', &
                  action='write', iostat=st)
        else
            open (newunit=lg%unit, file=path, status='replace', action='write', iostat=st)
        end if
        ok = st == 0
        lg%open = ok
        if (.not. ok) return
        write (lg%unit, '(a)') ' xdyna: explicit finite elements with automatic contact', version_line(), ''
    end subroutine log_open

    subroutine log_line(lg, text)
        type(log_t), intent(in) :: lg
        character(len=*), intent(in) :: text
        integer :: ios
        if (.not. lg%open) return
        ! the log is the one file a failed write does not stop the run for:
        ! the run's own outputs name the failure (and a full disk fails them)
        write (lg%unit, '(a)', iostat=ios) text
        flush (lg%unit, iostat=ios)
    end subroutine log_line

    subroutine log_close(lg)
        type(log_t), intent(inout) :: lg
        if (lg%open) close (lg%unit)
        lg%open = .false.
    end subroutine log_close

    !> A real as d3hsp writes it (es12.4, left-adjusted).
    function fmt(x) result(t)
        real(wp), intent(in) :: x
        character(len=16) :: t
        write (t, '(es12.4)') x
        t = adjustl(t)
    end function fmt

    !> One line per part with shells: its hourglass form and coefficients
    !> (IHQ 1-3 viscous, 4-5 stiffness; QB and QW default to QM).
    function shell_hourglass_lines(model) result(s)
        type(model_t), intent(in) :: model
        character(len=:), allocatable :: s
        character(len=1), parameter :: nl = new_line('a')
        integer :: p, k, ihq
        real(wp) :: qm, qb, qw
        s = ''
        do p = 1, model%npart
            if (count(model%shell_part(1:model%nshell) == p) == 0) cycle
            ihq = part_ihq(model, p)
            qm = model%ctl%qh; qb = qm; qw = qm
            k = model%part(p)%hg_ix
            if (k > 0) then
                qm = model%hg(k)%qm; qb = model%hg(k)%qb; qw = model%hg(k)%qw
            end if
            if (ihq <= 3) then
                s = s//'     part '//itoa(model%part(p)%id)//' shell hourglass: viscous (IHQ '//itoa(ihq)// &
                    '), fractions of critical damping'
            else
                s = s//'     part '//itoa(model%part(p)%id)//' shell hourglass: stiffness (IHQ '//itoa(ihq)//')'
            end if
            s = s//' QM '//trim(fmt(qm))//' QB '//trim(fmt(qb))//' QW '//trim(fmt(qw))
            if (hg_bounded(model, p)) then
                s = s//', each mode bounded at its coefficient times its plastic capacity (flow stress; '// &
                    '*CONTROL_XDYNA_SHELL HGBOUND 1, the default)'
            else if (hg_boundable(model, p)) then
                s = s//', elastic springs without bound (*CONTROL_XDYNA_SHELL HGBOUND 0)'
            end if
            s = s//nl
        end do
    end function shell_hourglass_lines

    !> Model summary as text (for d3hsp and for --check on stdout).
    function model_summary(model, solids, nrigid) result(s)
        type(model_t), intent(in) :: model
        type(solids_t), intent(in) :: solids
        integer, intent(in) :: nrigid
        character(len=:), allocatable :: s
        character(len=160) :: buf
        character(len=1), parameter :: nl = new_line('a')
        integer :: p, ne, m, k
        s = ' input deck: '//model%deck_path//nl
        if (len_trim(model%title) > 0) s = s//' title: '//trim(model%title)//nl
        s = s//nl//' m o d e l   s u m m a r y'//nl
        write (buf, '(a,i12)') '   nodes ............................', model%nnode
        s = s//trim(buf)//nl
        write (buf, '(a,i12)') '   solid elements (hexahedra) .......', model%nhex
        s = s//trim(buf)//nl
        write (buf, '(a,i12)') '   shell elements ...................', model%nshell
        s = s//trim(buf)//nl
        if (model%nbeam > 0) then
            write (buf, '(a,i12)') '   beam elements ....................', model%nbeam
            s = s//trim(buf)//nl
        end if
        write (buf, '(a,i12)') '   solid element groups .............', solids%ngroup
        s = s//trim(buf)//nl
        write (buf, '(a,i12)') '   parts ............................', model%npart
        s = s//trim(buf)//nl
        write (buf, '(a,i12)') '   materials ........................', model%nmat
        s = s//trim(buf)//nl
        s = s//nl//'   part      material   type          elements  heading'//nl
        do p = 1, model%npart
            ne = count(model%hex_part(1:model%nhex) == p)
            if (model%nshell > 0) ne = ne + count(model%shell_part(1:model%nshell) == p)
            if (model%nbeam > 0) ne = ne + count(model%beam_part(1:model%nbeam) == p)
            m = model%part(p)%mat_ix
            write (buf, '(i7,i14,3x,a12,i10,2x,a)') model%part(p)%id, model%mat(m)%id, &
                model%mat(m)%keyword(5:16), ne, trim(model%part(p)%heading)
            s = s//trim(buf)//nl
        end do
        s = s//nl//' subsystems in use (a deck pays only for these)'//nl
        if (solids%n > 0) then
            s = s//'   solid elements ............ on  (one-point hexahedron, Flanagan-Belytschko)'//nl
        else if (model%nhex > 0) then
            s = s//'   solid elements ............ off (only rigid parts)'//nl
        else
            s = s//'   solid elements ............ off (none in the deck)'//nl
        end if
        if (solids%ngroup > 0) then
            if (any(solids%group%hg_form == hg_stiffness)) then
                s = s//'   hourglass control ......... on  (stiffness form in some parts)'//nl
            else
                s = s//'   hourglass control ......... on  (viscous form)'//nl
            end if
        end if
        s = s//'   bulk viscosity ............ on  (Q1 '//trim(fmt(model%ctl%q1))//', Q2 '// &
            trim(fmt(model%ctl%q2))//')'//nl
        if (model%nshell > 0) then
            s = s//'   shell elements ............ on  (Belytschko-Tsay, '//itoa(model%nshell)//')'//nl
            s = s//shell_hourglass_lines(model)
        else
            s = s//'   shell elements ............ off (none in the deck)'//nl
        end if
        if (model%nbeam > 0) then
            s = s//'   beam elements ............. on  ('//itoa(model%nbeam)//': '//itoa(beams_of(1))// &
                ' Hughes-Liu (ELFORM 1, section points), '//itoa(beams_of(2))//' Belytschko-Schwer resultant, '// &
                itoa(beams_of(9))//' spot welds)'//nl
        else
            s = s//'   beam elements ............. off (none in the deck)'//nl
        end if
        if (nrigid > 0) then
            s = s//'   rigid bodies .............. on  ('//itoa(nrigid)//')'//nl
        else
            s = s//'   rigid bodies .............. off (none in the deck)'//nl
        end if
        if (model%ncontact > 0) then
            s = s//'   contact ................... on  ('//itoa(model%ncontact)//' interface(s); automatic, '// &
                'four steps: surface, global and local search, enforcement)'//nl
        else
            s = s//'   contact ................... off (no contact keyword)'//nl
        end if
        if (any_erosion(model)) then
            s = s//'   failure and erosion ....... on  (FAIL, FS, *MAT_ADD_EROSION or ERODE; the contact surfaces '// &
                'follow, the faces inside eroding solids joining as they are exposed)'//nl
        else
            s = s//'   failure and erosion ....... off (no FAIL, FS, *MAT_ADD_EROSION or ERODE)'//nl
        end if
        if (model%ntied > 0) then
            s = s//'   tied contacts ............. on  ('//itoa(model%ntied)//' interface(s); slave nodes held on '// &
                'their segments, each named above)'//nl
        else
            s = s//'   tied contacts ............. off (no *CONTACT_TIED_...)'//nl
        end if
        if (model%nwall > 0) then
            s = s//'   rigid walls ............... on  ('//itoa(model%nwall)//' planar stonewall(s))'//nl
        else
            s = s//'   rigid walls ............... off (none in the deck)'//nl
        end if
        s = s//'   body loads ................ '//onoff(model%nbody > 0)//nl
        s = s//'   prescribed motion ......... '//onoff(model%npresc > 0)//nl
        s = s//'   segment pressures ......... '//onoff(model%npress > 0)//nl
        s = s//'   boundary constraints ...... '//onoff(model%nspc > 0 .or. any(model%node_tc(1:model%nnode) > 0))//nl
        s = s//'   initial velocities ........ '//onoff(model%nivel > 0)//nl
        if (model%npmass > 0) s = s//'   point masses (*ELEMENT_MASS) '//itoa(model%npmass)//', total '// &
                                    trim(fmt(sum(model%pmass(1:model%npmass)%mass)))//nl
        if (model%nxn > 0) s = s//'   extra nodes on rigid bodies '//itoa(sum([(size(model%xn(k)%node_ix), &
                                 k=1, model%nxn)]))//' (*CONSTRAINED_EXTRA_NODES)'//nl
        s = s//'   initial stresses .......... '//onoff(model%nistress > 0)//nl
        s = s//nl//' c o n t r o l s'//nl
        s = s//'   termination time .......... '//trim(fmt(model%ctl%endtim))//nl
        if (model%ctl%endcyc > 0) s = s//'   termination cycle ......... '//itoa(model%ctl%endcyc)//nl
        s = s//'   time step scale TSSFAC .... '//trim(fmt(model%ctl%tssfac))//nl
        if (model%nshell > 0) then
            select case (model%ctl%isdo)
            case (1)
                s = s//'   shell step length ISDO 1 .. area over the longest diagonal (triangles: the shortest '// &
                    'altitude), plate wave speed'//nl
            case (2)
                s = s//'   shell step length ISDO 2 .. the larger of the shortest side and area over the longest '// &
                    'side (triangles: the shortest side), bar wave speed'//nl
            case default
                s = s//'   shell step length ISDO 0 .. area over the longest side (triangles: the shortest '// &
                    'altitude), plate wave speed'//nl
            end select
        end if
        s = s//'   glstat / matsum / nodout .. '//trim(fmt(model%db%glstat%dt))//' / '// &
            trim(fmt(model%db%matsum%dt))//' / '//trim(fmt(model%db%nodout%dt))//nl
        ! where BINARY 2 leaves out an ASCII file (thist.h5 holds the series)
        if (any([model%db%glstat%binary, model%db%matsum%binary, model%db%nodout%binary, model%db%rwforc%binary, &
                 model%db%rcforc%binary] == 2)) s = s//'   thist.h5 alone (BINARY 2) . '//binout_only()//nl
        if (model%nwarn > 0) s = s//nl//model%warnings
    contains
        !> The databases whose ASCII file is not written.
        function binout_only() result(t)
            character(len=:), allocatable :: t
            t = ''
            if (model%db%glstat%binary == 2) t = t//' glstat'
            if (model%db%matsum%binary == 2) t = t//' matsum'
            if (model%db%nodout%binary == 2) t = t//' nodout'
            if (model%db%rwforc%binary == 2) t = t//' rwforc'
            if (model%db%rcforc%binary == 2) t = t//' rcforc'
            t = trim(adjustl(t))//' (no ASCII file)'
        end function binout_only
        function onoff(b) result(t)
            logical, intent(in) :: b
            character(len=:), allocatable :: t
            t = 'off'
            if (b) t = 'on'
        end function onoff
        !> the beams whose section has formulation elform
        integer function beams_of(elform) result(n)
            integer, intent(in) :: elform
            integer :: e
            n = 0
            do e = 1, model%nbeam
                if (model%beam_part(e) <= 0) cycle
                if (model%part(model%beam_part(e))%beam_sec_ix <= 0) cycle
                if (model%sec_beam(model%part(model%beam_part(e))%beam_sec_ix)%elform == elform) n = n + 1
            end do
        end function beams_of
    end function model_summary

    !> Wall seconds per phase, the run's processor seconds, contact share,
    !> time per zone cycle.
    subroutine timing_table(lg, tm, ncycle, nelem, total_wall)
        type(log_t), intent(in) :: lg
        type(timers_t), intent(in) :: tm
        integer, intent(in) :: ncycle, nelem
        real(dp), intent(in) :: total_wall
        integer :: k
        real(dp) :: loop_wall, ns
        character(len=160) :: buf
        call log_line(lg, '')
        call log_line(lg, ' t i m i n g   i n f o r m a t i o n')
        call log_line(lg, '')
        call log_line(lg, '   phase                        wall (s)    % wall')
        do k = 1, nphase
            write (buf, '(3x,a24,f13.3,f10.1)') phase_name(k), tm%wall(k), &
                100.0_dp*tm%wall(k)/max(total_wall, 1.0e-12_dp)
            call log_line(lg, trim(buf))
        end do
        write (buf, '(3x,a24,f13.3)') 'total', total_wall
        call log_line(lg, trim(buf))
        write (buf, '(a,f0.3,a,f4.2,a)') '   processor time, all threads ......... ', tm%cpu(), ' s (', &
            tm%cpu()/max(total_wall, 1.0e-12_dp), ' x the wall time)'
        call log_line(lg, trim(buf))
        loop_wall = tm%wall(ph_elements) + tm%wall(ph_assembly) + tm%wall(ph_integrate) + tm%wall(ph_rigid) + &
                    tm%wall(ph_contact) + tm%wall(ph_search) + tm%wall(ph_local) + tm%wall(ph_enforce) + &
                    tm%wall(ph_output) + tm%wall(ph_comm) + tm%wall(ph_ghost) + tm%wall(ph_wait)
        ns = 0
        if (ncycle > 0 .and. nelem > 0) ns = 1.0e9_dp*loop_wall/(real(ncycle, dp)*nelem)
        call log_line(lg, '')
        write (buf, '(a,f6.1,a)') '   contact share of the time loop ....... ', &
            100.0_dp*(tm%wall(ph_contact) + tm%wall(ph_search) + tm%wall(ph_local) + tm%wall(ph_enforce) + &
                      tm%wall(ph_ghost))/ &
            max(loop_wall, 1.0e-12_dp), ' %'
        call log_line(lg, trim(buf))
        write (buf, '(a,i12)') '   cycles ............................... ', ncycle
        call log_line(lg, trim(buf))
        write (buf, '(a,f12.1)') '   time per zone cycle (nanosec) ........ ', ns
        call log_line(lg, trim(buf))
    end subroutine timing_table

end module xd_output_d3hsp
