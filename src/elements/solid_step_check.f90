!> The element time step L/c of a one-point hexahedron (LS-DYNA's: L the
!> volume over the largest face, c the dilatational wave speed) is the
!> stable step of a mesh without free surfaces, but not of a free corner:
!> the corner's volumetric mode is faster. For a free block of cubes the
!> highest frequency allows 0.97 of L/c at nu 0.3, 0.92 at 0.4, 0.85 at
!> 0.49-0.4999 (mesh sizes 2^3 to 6^3 alike: the mode is the corner's); a
!> lone cube's breathing mode, omega^2 = 12 K / (rho h^2), allows
!> sqrt((lambda + 2 mu) / 3K) of L/c: 0.734 at nu 0.3, 0.577 as nu -> 0.5
!> (Flanagan and Belytschko's element bound, 2 / sqrt(8 c^2 b.b) V, gives
!> 0.577 for any nu). A default TSSFAC 0.9 is then beyond the limit: a
!> nu 0.4999 block on a wall blew up at 0.9 and ran at 0.8, and a lone
!> steel cube translating freely blew up in 34 cycles.
!>
!> So at set-up the deformable solids are checked: the highest frequency of
!> their linear elastic stiffness (one-point B, lumped masses of the whole
!> model, the directions the constraints fix left out) is found by power
!> iteration, and where TSSFAC x the smallest element step L/c comes
!> within 5% of the stable step 2/omega_max or beyond it, their element
!> steps are scaled by 0.98 x 2/omega_max / (L/c) for the whole run (named
!> in d3hsp): the run then keeps TSSFAC's margin against the true limit, as
!> LS-DYNA's intends (its own step, L/c alone, has no such check). A mesh
!> whose corners allow 0.97 L/c keeps its step at TSSFAC 0.9. Hourglass
!> stiffness is left out (small beside the bulk stiffness here), and the
!> iteration approaches omega_max from below, so the ratio keeps a 2%
!> margin. The iteration costs about 5 us per element (0.5 s for 100,000
!> hexahedra), once.
module xd_elements_solid_step_check
    use xd_kinds, only: wp, dp
    use xd_elements_hex8, only: hex_b_matrix, hex_char_length
    use xd_elements_solid_groups, only: solids_t
    use xd_core_dofs, only: free3
    use, intrinsic :: iso_fortran_env, only: int8
    implicit none
    private
    public :: check_solid_steps

    integer, parameter :: max_iter = 200
    real(dp), parameter :: near = 0.95_dp        !< TSSFAC x L/c this close to the true limit is scaled

contains

    !> Scale the step of the checked groups (s%group%dt_scale) where the
    !> mesh's highest frequency asks for it; `note` says what was done ('' if
    !> nothing), with the parts named by the caller's ids in part_ids.
    subroutine check_solid_steps(s, x, mass, dofs, tssfac, part_ids, note)
        type(solids_t), intent(inout) :: s
        real(wp), intent(in) :: x(:, :), mass(:)
        integer(int8), intent(in) :: dofs(:)        !< per node, its free directions (xd_core_dofs)
        real(wp), intent(in) :: tssfac
        integer, intent(in) :: part_ids(:)
        character(len=:), allocatable, intent(out) :: note
        logical, allocatable :: on(:), touched(:)
        real(dp), allocatable :: u(:, :), f(:, :), w(:)
        real(dp) :: lam_max, lam_old, dt_true, dt_elem, scale, nrm
        integer :: g, it, k
        character(len=64) :: buf
        note = ''
        allocate (on(s%ngroup))
        do g = 1, s%ngroup
            associate (gr => s%group(g))
                on(g) = gr%mu > 0.0_wp
            end associate
        end do
        if (.not. any(on)) return
        ! the nodes the checked elements touch, and 1/sqrt(m) there
        allocate (touched(size(mass)), w(size(mass)))
        touched = .false.
        do g = 1, s%ngroup
            if (on(g)) touched(pack(s%conn(:, s%group(g)%first:s%group(g)%last), .true.)) = .true.
        end do
        w = 0
        where (touched .and. mass > 0.0_wp) w = 1.0_dp/sqrt(real(mass, dp))
        ! power iteration on M^-1/2 K M^-1/2, from a start with every mode in it
        allocate (u(3, size(mass)), f(3, size(mass)))
        do k = 1, size(mass)
            u(:, k) = w(k)*[sin(1.3_dp*k), cos(2.9_dp*k + 0.4_dp), sin(0.7_dp*k + 1.1_dp)]*free3(dofs(k))
        end do
        lam_max = 0
        do it = 1, max_iter
            nrm = sqrt(sum(u*u))
            if (nrm <= 0.0_dp) return
            u = u/nrm
            call stiffness_times(s, on, x, spread(w, 1, 3)*u, f)
            do k = 1, size(mass)
                f(:, k) = w(k)*f(:, k)*free3(dofs(k))
            end do
            lam_old = lam_max
            lam_max = sum(u*f)
            u = f
            if (it > 20 .and. abs(lam_max - lam_old) <= 1.0e-4_dp*lam_max) exit
        end do
        if (lam_max <= 0.0_dp) return
        dt_true = 2.0_dp/sqrt(lam_max)
        dt_elem = smallest_element_step(s, on, x)
        if (tssfac*dt_elem <= near*dt_true) return
        scale = 0.98_dp*dt_true/dt_elem
        if (scale >= 1.0_dp) return
        do g = 1, s%ngroup
            if (on(g)) s%group(g)%dt_scale = real(scale, wp)
        end do
        write (buf, '(f6.3)') scale
        note = 'the solids ('//part_list()//') have a highest frequency (a free corner, a lone element) '// &
               'beyond what TSSFAC x their element steps L/c keeps stable: their steps are scaled by '// &
               trim(adjustl(buf))//' (power iteration at t = 0, with a 2% margin)'
    contains
        function part_list() result(t)
            character(len=:), allocatable :: t
            integer :: gg
            character(len=16) :: b
            t = ''
            do gg = 1, s%ngroup
                if (.not. on(gg)) cycle
                write (b, '(i0)') part_ids(s%group(gg)%part)
                if (index(' '//t//' ', ' '//trim(b)//' ') == 0) t = trim(adjustl(t//' '//trim(b)))
            end do
            t = 'part '//t
        end function part_list
    end subroutine check_solid_steps

    !> f = K u over the checked groups: the one-point hexahedron's linear
    !> elastic force at the initial geometry.
    subroutine stiffness_times(s, on, x, u, f)
        type(solids_t), intent(in) :: s
        logical, intent(in) :: on(:)
        real(wp), intent(in) :: x(:, :)
        real(dp), intent(in) :: u(:, :)
        real(dp), intent(out) :: f(:, :)
        real(wp), allocatable :: xl(:, :), yl(:, :), zl(:, :), bx(:, :), by(:, :), bz(:, :), vol(:)
        real(dp) :: e(6), sg(6), tr
        integer :: g, a, n, i, k, nd
        f = 0
        do g = 1, s%ngroup
            if (.not. on(g)) cycle
            a = s%group(g)%first
            n = s%group(g)%last - a + 1
            call group_geometry(s, g, x, xl, yl, zl, bx, by, bz, vol)
            do i = 1, n
                if (vol(i) <= 0.0_wp) cycle
                e = 0
                do k = 1, 8
                    nd = s%conn(k, a + i - 1)
                    e(1) = e(1) + bx(i, k)*u(1, nd)
                    e(2) = e(2) + by(i, k)*u(2, nd)
                    e(3) = e(3) + bz(i, k)*u(3, nd)
                    e(4) = e(4) + by(i, k)*u(1, nd) + bx(i, k)*u(2, nd)
                    e(5) = e(5) + bz(i, k)*u(2, nd) + by(i, k)*u(3, nd)
                    e(6) = e(6) + bx(i, k)*u(3, nd) + bz(i, k)*u(1, nd)
                end do
                e = e/vol(i)
                tr = e(1) + e(2) + e(3)
                sg(1:3) = s%group(g)%lam*tr + 2.0_dp*s%group(g)%mu*e(1:3)
                sg(4:6) = s%group(g)%mu*e(4:6)
                do k = 1, 8
                    nd = s%conn(k, a + i - 1)
                    f(1, nd) = f(1, nd) + sg(1)*bx(i, k) + sg(4)*by(i, k) + sg(6)*bz(i, k)
                    f(2, nd) = f(2, nd) + sg(4)*bx(i, k) + sg(2)*by(i, k) + sg(5)*bz(i, k)
                    f(3, nd) = f(3, nd) + sg(6)*bx(i, k) + sg(5)*by(i, k) + sg(3)*bz(i, k)
                end do
            end do
        end do
    end subroutine stiffness_times

    !> The smallest L/c over the checked groups (no bulk viscosity, no TSSFAC).
    real(dp) function smallest_element_step(s, on, x) result(dtm)
        type(solids_t), intent(in) :: s
        logical, intent(in) :: on(:)
        real(wp), intent(in) :: x(:, :)
        real(wp), allocatable :: xl(:, :), yl(:, :), zl(:, :), bx(:, :), by(:, :), bz(:, :), vol(:), le(:)
        integer :: g, n
        real(wp) :: c
        dtm = huge(1.0_dp)
        do g = 1, s%ngroup
            if (.not. on(g)) cycle
            n = s%group(g)%last - s%group(g)%first + 1
            call group_geometry(s, g, x, xl, yl, zl, bx, by, bz, vol)
            allocate (le(n))
            call hex_char_length(n, xl, yl, zl, vol, le)
            c = sqrt((s%group(g)%lam + 2.0_wp*s%group(g)%mu)/s%group(g)%ro)
            dtm = min(dtm, real(minval(le/c), dp))
            deallocate (le)
        end do
    end function smallest_element_step

    !> Group g's corner coordinates at x, its B vectors and volumes.
    subroutine group_geometry(s, g, x, xl, yl, zl, bx, by, bz, vol)
        type(solids_t), intent(in) :: s
        integer, intent(in) :: g
        real(wp), intent(in) :: x(:, :)
        real(wp), allocatable, intent(out) :: xl(:, :), yl(:, :), zl(:, :), bx(:, :), by(:, :), bz(:, :), vol(:)
        integer :: a, b, n, k
        a = s%group(g)%first
        b = s%group(g)%last
        n = b - a + 1
        allocate (xl(n, 8), yl(n, 8), zl(n, 8), bx(n, 8), by(n, 8), bz(n, 8), vol(n))
        do k = 1, 8
            xl(:, k) = x(1, s%conn(k, a:b))
            yl(:, k) = x(2, s%conn(k, a:b))
            zl(:, k) = x(3, s%conn(k, a:b))
        end do
        call hex_b_matrix(n, xl, yl, zl, bx, by, bz, vol)
    end subroutine group_geometry

end module xd_elements_solid_step_check
