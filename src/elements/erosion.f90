!> Failure and erosion of shells and solids: FAIL of *MAT_PLASTIC_KINEMATIC (FS) and
!> *MAT_PIECEWISE_LINEAR_PLASTICITY, and *MAT_ADD_EROSION's pressure,
!> stress and time criteria.
!>
!> After each element pass, each shell computed here is checked at each
!> through-thickness point. A point fails where its effective plastic strain
!> reaches FAIL, or where at least NCS of *MAT_ADD_EROSION's criteria hold
!> there: pressure -(sxx + syy)/3 at least MXPRES or at most MNPRES (a
!> negative value, tension), the largest principal stress at least SIGP1,
!> the von Mises stress at least SIGVM. The shell erodes when NUMFIP of its
!> points have failed (default 1 with *MAT_ADD_EROSION; with FAIL alone,
!> all of them: a crack through the thickness), or at FAILTM. With
!> *CONTROL_TIMESTEP ERODE 1, a shell whose step falls below TSMIN (DTMIN of
!> *CONTROL_TERMINATION times the first step) erodes too, and sets no step.
!>
!> An eroded shell is computed no more. Its forces and moments leave the
!> assembly, its mass stays on its nodes, and its internal energy at erosion
!> is booked as eroded internal energy (glstat, matsum). Its contact
!> segments leave the contact (contact_erode), and the d3plot's deletion
!> flag reads 0 from the next state.
!>
!> A solid (one point) fails on the same criteria with its full stress:
!> pressure -(sxx + syy + szz)/3, the largest principal stress, the von
!> Mises stress. An eroded solid is computed frozen (solid_groups: on its
!> coordinates at erosion, at rest), its forces and step not taken; its
!> internal energy is booked as eroded. The contact surfaces follow
!> (contact_erode, contact_erode_solids).
!>
!> The strain criteria (MNEPS, MXEPS, EFFEPS, VOLEPS, EPSSH) take the
!> principal logarithmic strains: a solid's from its deformation gradient
!> at the centre; a shell point's from its strain rates integrated in the
!> shell's co-rotational frame (sh%strain, kept where a shell's material
!> has one of them).
module xd_elements_erosion
    use xd_kinds, only: wp, dp
    use xd_elements_hex8, only: hex_volume_operator
    use xd_model, only: material_t
    use xd_elements_shell_bt, only: shells_t, shell_blocks
    use xd_elements_solid_groups, only: solids_t
    use xd_model, only: model_t, mat_plastic_kinematic, mat_piecewise_linear
    implicit none
    private
    public :: shell_failures, erode_shells, dead_model_shells, solid_failures, erode_solids, solid_fails, &
              dead_model_hexes, strain_criteria, principal_values

contains

    !> The shells computed here that fail now (their indices in `newly`).
    subroutine shell_failures(sh, mat, time, newly)
        type(shells_t), intent(in) :: sh
        type(material_t), intent(in) :: mat(:)
        real(dp), intent(in) :: time
        integer, allocatable, intent(out) :: newly(:)
        integer :: i, e, ip, nfp, need, is
        logical :: gone
        allocate (newly(0))
        if (.not. sh%erodible) return
        do i = 1, size(sh%mine)
            e = sh%mine(i)
            ! ERODE: its step fell below the minimum
            if (sh%tsmin > 0.0_wp) then
                if (sh%low(sh%lix(e))) then
                    newly = [newly, e]
                    cycle
                end if
            end if
            associate (m => mat(sh%pc%mix(sh%part(e))))
                if (.not. (m%fail > 0.0_wp .or. m%erosion)) cycle
                gone = m%erosion .and. m%failtm > 0.0_wp .and. time >= m%failtm
                if (.not. gone) then
                    need = sh%pc%nip(sh%part(e))
                    if (m%erosion) need = min(max(m%numfip, 1), sh%pc%nip(sh%part(e)))
                    nfp = 0
                    is = sh%lix(e)      ! (the points' state's row)
                    do ip = 1, sh%pc%nip(sh%part(e))
                        if (strain_criteria(m)) then
                            if (point_fails(m, sh%sig(is, :, ip), sh%epsp(is, ip), sh%pc%plastic(sh%part(e)), &
                                            principal_values(sh%strain(is, :, ip)))) nfp = nfp + 1
                        else
                            if (point_fails(m, sh%sig(is, :, ip), sh%epsp(is, ip), sh%pc%plastic(sh%part(e)))) nfp = nfp + 1
                        end if
                    end do
                    gone = nfp >= need
                end if
                if (gone) newly = [newly, e]
            end associate
        end do
    end subroutine shell_failures

    !> One point: FAIL on the effective plastic strain, or NCS of the
    !> *MAT_ADD_EROSION criteria on its stress (plane stress, s = sxx syy
    !> sxy syz szx) and, where given, its principal strains ep.
    pure logical function point_fails(m, s, epsp, plastic, ep) result(f)
        type(material_t), intent(in) :: m
        real(wp), intent(in) :: s(5), epsp
        logical, intent(in) :: plastic
        real(wp), intent(in), optional :: ep(3)
        real(wp) :: p, s1, vm
        f = plastic .and. m%fail > 0.0_wp .and. epsp >= m%fail
        if (f .or. .not. m%erosion) return
        p = -(s(1) + s(2))/3
        s1 = max(0.5_wp*(s(1) + s(2)) + sqrt((0.5_wp*(s(1) - s(2)))**2 + s(3)**2), 0.0_wp)
        vm = sqrt(max(s(1)**2 - s(1)*s(2) + s(2)**2 + 3*(s(3)**2 + s(4)**2 + s(5)**2), 0.0_wp))
        f = stress_fails(m, p, s1, vm, ep)
    end function point_fails

    !> The material has a *MAT_ADD_EROSION strain criterion.
    pure logical function strain_criteria(m)
        type(material_t), intent(in) :: m
        strain_criteria = m%erosion .and. (m%mneps < 0.0_wp .or. m%mxeps > 0.0_wp .or. m%effeps > 0.0_wp .or. &
                                           m%voleps /= 0.0_wp .or. m%epssh > 0.0_wp)
    end function strain_criteria

    !> The eigenvalues of the symmetric tensor a (xx yy zz xy yz zx),
    !> descending: the deviator's invariants and Lode's angle (the closed
    !> form for a symmetric 3 x 3).
    pure function principal_values(a) result(e)
        real(wp), intent(in) :: a(6)
        real(wp) :: e(3)
        real(wp), parameter :: pi = 3.141592653589793_wp
        real(wp) :: pm, d1, d2, d3, j2, j3, r, th, c
        pm = (a(1) + a(2) + a(3))/3
        d1 = a(1) - pm
        d2 = a(2) - pm
        d3 = a(3) - pm
        j2 = 0.5_wp*(d1**2 + d2**2 + d3**2) + a(4)**2 + a(5)**2 + a(6)**2
        if (j2 <= 0.0_wp) then
            e = pm
            return
        end if
        j3 = d1*d2*d3 + 2*a(4)*a(5)*a(6) - d1*a(5)**2 - d2*a(6)**2 - d3*a(4)**2
        r = 1.5_wp*sqrt(3.0_wp)*j3/j2**1.5_wp
        th = acos(max(-1.0_wp, min(1.0_wp, r)))/3
        c = 2*sqrt(j2/3)
        e = pm + c*[cos(th), cos(th - 2*pi/3), cos(th + 2*pi/3)]
        ! (descending: th in [0, pi/3])
        e = [maxval(e), e(1) + e(2) + e(3) - maxval(e) - minval(e), minval(e)]
    end function principal_values

    !> The solids computed here (active groups) that fail now.
    subroutine solid_failures(s, model, time, x, newly)
        type(solids_t), intent(in) :: s
        type(model_t), intent(in) :: model
        real(dp), intent(in) :: time
        real(wp), intent(in) :: x(:, :)   !< the nodes now (the strain criteria)
        integer, allocatable, intent(out) :: newly(:)
        integer :: g, e
        real(wp) :: ep
        logical :: plastic
        allocate (newly(0))
        if (.not. s%erodible) return
        plastic = size(s%epsp) > 0
        do g = 1, s%ngroup
            if (.not. s%active(g)) cycle
            do e = s%group(g)%first, s%group(g)%last
                if (s%dead(e)) cycle
                ! ERODE: its step fell below the minimum
                if (s%tsmin > 0.0_wp) then
                    if (s%low(e)) then
                        newly = [newly, e]
                        cycle
                    end if
                end if
                associate (m => model%mat(model%part(s%part(e))%mat_ix))
                    if (.not. (m%fail > 0.0_wp .or. m%erosion)) cycle
                    ep = 0
                    if (plastic) ep = s%epsp(s%row(e))
                    if (m%erosion .and. m%failtm > 0.0_wp .and. time >= m%failtm) then
                        newly = [newly, e]
                    else if (strain_criteria(m)) then
                        if (solid_fails(m, s%stress(e), ep, plastic .and. &
                                        (s%group(g)%mtype == mat_plastic_kinematic .or. &
                                         s%group(g)%mtype == mat_piecewise_linear), &
                                        solid_strains(model%x0(:, s%conn(:, e)), x(:, s%conn(:, e))))) &
                            newly = [newly, e]
                    else if (solid_fails(m, s%stress(e), ep, plastic .and. &
                                         (s%group(g)%mtype == mat_plastic_kinematic .or. &
                                          s%group(g)%mtype == mat_piecewise_linear))) then
                        newly = [newly, e]
                    end if
                end associate
            end do
        end do
    end subroutine solid_failures

    !> NCS of *MAT_ADD_EROSION's stress criteria hold at a point of pressure
    !> p, largest principal stress s1 and von Mises stress vm (a shell's
    !> point or a solid's).
    pure logical function stress_fails(m, p, s1, vm, ep) result(f)
        type(material_t), intent(in) :: m
        real(wp), intent(in) :: p, s1, vm
        !> the principal strains, descending (the strain criteria count
        !> where given)
        real(wp), intent(in), optional :: ep(3)
        integer :: n
        real(wp) :: ev, em
        n = 0
        if (m%mxpres > 0.0_wp .and. p >= m%mxpres) n = n + 1
        if (m%mnpres < 0.0_wp .and. p <= m%mnpres) n = n + 1
        if (m%sigp1 > 0.0_wp .and. s1 >= m%sigp1) n = n + 1
        if (m%sigvm > 0.0_wp .and. vm >= m%sigvm) n = n + 1
        if (present(ep)) then
            ev = ep(1) + ep(2) + ep(3)
            em = ev/3
            if (m%mneps < 0.0_wp .and. ep(3) <= m%mneps) n = n + 1
            if (m%mxeps > 0.0_wp .and. ep(1) >= m%mxeps) n = n + 1
            if (m%effeps > 0.0_wp) then
                if (sqrt(2.0_wp/3*((ep(1) - em)**2 + (ep(2) - em)**2 + (ep(3) - em)**2)) >= m%effeps) n = n + 1
            end if
            if (m%voleps > 0.0_wp .and. ev >= m%voleps) n = n + 1
            if (m%voleps < 0.0_wp .and. ev <= m%voleps) n = n + 1
            if (m%epssh > 0.0_wp .and. 0.5_wp*(ep(1) - ep(3)) >= m%epssh) n = n + 1
        end if
        f = n >= m%ncs .and. n > 0
    end function stress_fails

    !> A solid's point (its one): FAIL on the effective plastic strain, or
    !> NCS of *MAT_ADD_EROSION's criteria on its stress s (xx yy zz xy yz
    !> zx): pressure, the largest principal stress, the von Mises stress.
    pure logical function solid_fails(m, s, epsp, plastic, ep) result(f)
        type(material_t), intent(in) :: m
        real(wp), intent(in) :: s(6), epsp
        logical, intent(in) :: plastic
        real(wp), intent(in), optional :: ep(3)   !< principal strains, descending
        real(wp) :: p, s1, vm, e3(3)
        f = plastic .and. m%fail > 0.0_wp .and. epsp >= m%fail
        if (f .or. .not. m%erosion) return
        p = -(s(1) + s(2) + s(3))/3
        e3 = principal_values(s)
        s1 = max(e3(1), 0.0_wp)
        vm = sqrt(max(0.5_wp*((s(1) - s(2))**2 + (s(2) - s(3))**2 + (s(3) - s(1))**2) + &
                      3*(s(4)**2 + s(5)**2 + s(6)**2), 0.0_wp))
        f = stress_fails(m, p, s1, vm, ep)
    end function solid_fails

    !> A solid's principal logarithmic strains, descending, from its
    !> deformation gradient at the centre, F = sum x_k (x) dN_k/dX (the
    !> initial geometry's uniform gradient, B / V0): half the logarithms of
    !> the eigenvalues of F^T F.
    function solid_strains(x0, x) result(ep)
        real(wp), intent(in) :: x0(3, 8), x(3, 8)
        real(wp) :: ep(3), b(8, 3), v0, f(3, 3), c(3, 3)
        integer :: k
        call hex_volume_operator(transpose(x0), b, v0)
        f = 0
        do k = 1, 8
            f = f + spread(x(:, k), 2, 3)*spread(b(k, :)/v0, 1, 3)
        end do
        c = matmul(transpose(f), f)
        ep = principal_values([c(1, 1), c(2, 2), c(3, 3), c(1, 2), c(2, 3), c(3, 1)])
        ep = 0.5_wp*log(max(ep, tiny(1.0_wp)))
    end function solid_strains

    !> Erode the solids `gone` (on every rank alike): frozen on their
    !> coordinates x now, their force slots zeroed. Their last forces are
    !> in this cycle's nodal sums: the frozen pass of the next cycle
    !> completes their work (pend_int, pend_hg) and adds none after it.
    subroutine erode_solids(s, gone, x)
        type(solids_t), intent(inout) :: s
        integer, intent(in) :: gone(:)
        real(wp), intent(in) :: x(:, :)
        integer :: k, e
        do k = 1, size(gone)
            e = gone(k)
            if (s%dead(e)) cycle
            s%dead(e) = .true.
            s%ndead = s%ndead + 1
            s%gdead(s%group_of(e)) = s%gdead(s%group_of(e)) + 1
            s%xfrozen(:, :, e) = x(:, s%conn(:, e))
            ! (its slots where they are held: its group's rank's rows)
            if (s%goff(s%group_of(e)) >= 0) s%fslot(:, 8*s%row(e) - 7:8*s%row(e)) = 0
        end do
    end subroutine erode_solids

    !> Erode the shells `gone` (on every rank alike): they leave the
    !> elements computed here, and their force and moment slots are zeroed
    !> for good.
    subroutine erode_shells(sh, gone)
        type(shells_t), intent(inout) :: sh
        integer, intent(in) :: gone(:)
        integer :: k, e
        if (size(gone) == 0) return
        do k = 1, size(gone)
            e = gone(k)
            if (sh%dead(e)) cycle
            sh%dead(e) = .true.
            sh%ndead = sh%ndead + 1
            ! (its slots where they are held: its rank's row)
            if (sh%lix(e) > 0) then
                sh%fslot(:, 4*sh%lix(e) - 3:4*sh%lix(e)) = 0
                sh%mslot(:, 4*sh%lix(e) - 3:4*sh%lix(e)) = 0
            end if
            ! the work of its last forces is not to come
            sh%pend_int(e) = 0
            sh%pend_hg(e) = 0
        end do
        sh%mine = pack(sh%mine, .not. sh%dead(sh%mine))
        call shell_blocks(sh)
    end subroutine erode_shells

    !> The eroded shells over the model's shell list (index 0, a solid face:
    !> never), as the contact's surfaces know them.
    function dead_model_shells(sh, nshell) result(dead)
        type(shells_t), intent(in) :: sh
        integer, intent(in) :: nshell
        logical :: dead(0:nshell)
        dead = .false.
        dead(sh%model_ix) = sh%dead
    end function dead_model_shells

    !> The eroded solids over the model's hexahedra.
    function dead_model_hexes(solids, nhex) result(dead)
        type(solids_t), intent(in) :: solids
        integer, intent(in) :: nhex
        logical :: dead(nhex)
        dead = .false.
        if (solids%erodible) dead(solids%model_ix) = solids%dead
    end function dead_model_hexes

end module xd_elements_erosion
