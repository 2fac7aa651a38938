!> A deformable shell's words in a binary d3plot state, in a module of its
!> own: rank 0 writing every shell's and each rank making its own shells'
!> (xd_solver_state_writer) call the same compiled code, which no caller
!> inlines (the compiler fuses multiplies and adds where it inlines: the
!> moment resultants had come out a unit in the last place apart), so the
!> words are the same bits whichever rank makes them.
module xd_output_shell_words
    use xd_kinds, only: wp
    use xd_elements_shell_bt, only: shells_t, shell_axes, point_weight, point_z
    implicit none
    private
    public :: shell_state_words, to_global

    integer, parameter :: sp = kind(1.0e0)

contains

    !> Deformable shell e's words of a binary state (7 mx + 12 of them):
    !> the layers (per layer six global stresses and the plastic strain),
    !> the resultants per unit width in the element's frame, the thickness
    !> and the internal energy density. Its points' state is in row js of
    !> sh%sig and sh%epsp, its thickness, area and energy in row jr (a view
    !> of every shell: e and e; a rank's own shells: their rows), its nodes'
    !> coordinates in x as its connectivity numbers them.
    subroutine shell_state_words(sh, x, e, js, jr, mx, w)
        type(shells_t), intent(in) :: sh
        real(wp), intent(in) :: x(:, :)
        integer, intent(in) :: e, js, jr
        integer, intent(in) :: mx   !< the layers a shell (the family's MAXINT)
        real(sp), intent(out) :: w(:)
        real(wp) :: r(3, 3), pt(5, 10), nr(5), mr(3), h, wt, z
        integer :: l, ip, ipx(3), nip
        w = 0
        nip = sh%pc%nip(sh%part(e))
        call shell_axes(sh, e, x, r)
        pt = 0
        pt(:, 1:nip) = sh%sig(js, :, 1:nip)
        if (mx == 3) then
            ! mid-surface, inner, outer
            select case (nip)
            case (1)
                ipx = [1, 1, 1]
            case (2)
                ipx = [0, 1, 2]
            case default
                ipx = [2, 1, 3]
            end select
            do l = 1, 3
                if (ipx(l) > 0) then
                    w(7*l - 6:7*l) = layer(pt(:, ipx(l)), sh%epsp(js, ipx(l)), r, sh%pc%plastic(sh%part(e)))
                else
                    w(7*l - 6:7*l) = layer(0.5_wp*(pt(:, 1) + pt(:, 2)), 0.5_wp*(sh%epsp(js, 1) + sh%epsp(js, 2)), r, &
                                           sh%pc%plastic(sh%part(e)))
                end if
            end do
        else
            do l = 1, nip
                w(7*l - 6:7*l) = layer(pt(:, l), sh%epsp(js, l), r, sh%pc%plastic(sh%part(e)))
            end do
        end if
        ! resultants per unit width in the element's frame
        h = sh%h(jr)
        nr = 0
        mr = 0
        do ip = 1, nip
            wt = point_weight(ip, nip)
            z = point_z(ip, nip)
            nr = nr + wt*pt(:, ip)
            mr = mr + wt*z*pt(1:3, ip)
        end do
        w(7*mx + 1:7*mx + 8) = real([0.5_wp*h*h*mr, h*nr(4), h*nr(5), h*nr(1:3)], sp)
        w(7*mx + 9) = real(h, sp)
        if (sh%area0(jr)*h > 0) w(7*mx + 12) = real(sh%eint(jr)/(sh%area0(jr)*h), sp)
    end subroutine shell_state_words

    !> A shell layer's seven d3plot words: the local stress p (xx yy xy yz
    !> zx, plane stress) in global axes from the frame r, the plastic strain.
    pure function layer(p, eps, r, plastic) result(w)
        real(wp), intent(in) :: p(5), eps, r(3, 3)
        logical, intent(in) :: plastic
        real(kind(1.0e0)) :: w(7)
        w(1:6) = real(to_global([p(1), p(2), 0.0_wp, p(3), p(4), p(5)], r), kind(1.0e0))
        w(7) = 0
        if (plastic) w(7) = real(eps, kind(1.0e0))
    end function layer

    !> A symmetric tensor (xx yy zz xy yz zx) in the frame r, to global axes.
    pure function to_global(sl, r) result(sg)
        real(wp), intent(in) :: sl(6), r(3, 3)
        real(wp) :: sg(6), t(3, 3), g(3, 3)
        integer :: i, j
        t(:, 1) = [sl(1), sl(4), sl(6)]
        t(:, 2) = [sl(4), sl(2), sl(5)]
        t(:, 3) = [sl(6), sl(5), sl(3)]
        ! g = r t r^T, written out (matmul on 3 x 3 goes through the library)
        do j = 1, 3
            do i = 1, 3
                g(i, j) = r(i, 1)*(t(1, 1)*r(j, 1) + t(1, 2)*r(j, 2) + t(1, 3)*r(j, 3)) &
                          + r(i, 2)*(t(2, 1)*r(j, 1) + t(2, 2)*r(j, 2) + t(2, 3)*r(j, 3)) &
                          + r(i, 3)*(t(3, 1)*r(j, 1) + t(3, 2)*r(j, 2) + t(3, 3)*r(j, 3))
            end do
        end do
        sg = [g(1, 1), g(2, 2), g(3, 3), g(1, 2), g(2, 3), g(3, 1)]
    end function to_global

end module xd_output_shell_words
