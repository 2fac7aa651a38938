!> A binary d3plot state whose deformable shells' words each rank makes for
!> its own shells and rank 0 writes, a chunk of the model's shells at a
!> time (issue 32). Rank 0 no longer gathers every shell's points' state
!> to make the words itself (shell_state_view: at NIP 5 the stresses and
!> plastic strains of a 250,000-shell plate, 60 MB). The words are the
!> same expressions of the same values (shell_state_words: the points'
!> state and the thickness, area and energy from the shell's rows, its
!> axes from its nodes' coordinates as the rank holds them), so the bytes
!> are the serial run's.
module xd_solver_state_writer
    use xd_kinds, only: wp
    use xd_solver_domain, only: domain_t, gather_to_root
    use xd_solver_state, only: state_t
    use xd_elements_shell_bt, only: shells_t, shell_row
    use xd_elements_solid_groups, only: solids_t
    use xd_elements_beam_bs, only: beams_t
    use xd_solver_energies, only: energies_t
    use xd_output_states, only: states_t, take_state, binary_head, binary_put, binary_tail, state_nv2d
    use xd_output_shell_words, only: shell_state_words
    implicit none
    private
    public :: states_by_ranks, write_state_by_ranks

    integer, parameter :: sp = kind(1.0e0)
    !> model shells a gather (rank 0 holds their words alone)
    integer, parameter :: chunk = 8192

contains

    !> The ranks make the shells' words of a state: more than one rank,
    !> the binary family and no d3plot.h5 (which takes every shell's
    !> state whole), deformable shells.
    logical function states_by_ranks(s, dom, sh) result(yes)
        type(states_t), intent(in) :: s
        type(domain_t), intent(in) :: dom
        type(shells_t), intent(in) :: sh
        yes = dom%on .and. s%on .and. s%binary .and. .not. s%h5 .and. sh%n > 0
    end function states_by_ranks

    !> One state at st%time (a collective: every rank calls it, rank 0
    !> writing or not). On rank 0 st and v are every node's (its view);
    !> on the others the rank's own, which its own shells' nodes are among.
    !> The solids' state is rank 0's view (gather_element_state).
    subroutine write_state_by_ranks(s, dom, st, solids, sh, v, en, bm)
        type(states_t), intent(inout) :: s
        type(domain_t), intent(in) :: dom
        type(state_t), intent(in) :: st
        type(solids_t), intent(in) :: solids
        type(shells_t), intent(in) :: sh
        real(wp), intent(in) :: v(:, :)
        type(energies_t), intent(in), optional :: en
        type(beams_t), intent(in), optional :: bm
        logical :: root, writes
        integer :: nw, a, b, e, r, k, n
        integer :: cnt(dom%nranks), at(dom%nranks)
        integer, allocatable :: disp(:)
        real(sp), allocatable :: words(:, :), one(:)
        real(wp), allocatable :: loc(:), buf(:)
        root = dom%rank == 0
        ! (the schedule on every rank; rank 0 writes unless a write failed
        ! before: it still takes the gathers, which every rank makes)
        writes = take_state(s, st%time) .and. root
        if (writes) writes = s%bin%on
        if (writes) call binary_head(s, st, solids, v, en, bm)
        nw = state_nv2d(s)
        allocate (one(nw))
        if (root) allocate (words(nw, min(chunk, sh%n)))
        do a = 1, sh%n, chunk
            b = min(a + chunk - 1, sh%n)
            cnt = 0
            do e = a, b
                r = dom%shell_rank(e) + 1
                cnt(r) = cnt(r) + 1
            end do
            n = cnt(dom%rank + 1)
            allocate (loc(max(nw*n, 1)))
            k = 0
            do e = a, b
                if (dom%shell_rank(e) /= dom%rank) cycle
                call shell_state_words(sh, st%x, e, sh%lix(e), shell_row(sh, e), s%maxint, one)
                loc(k*nw + 1:k*nw + nw) = real(one, wp)
                k = k + 1
            end do
            ! (single-precision words through real(wp): exact both ways)
            call gather_to_root(dom, loc, nw*n, nw*cnt, buf, disp)
            deallocate (loc)
            if (.not. root) cycle
            ! rank r - 1's words from disp(r) on, its shells ascending: in
            ! the model's order again
            at = disp
            do e = a, b
                r = dom%shell_rank(e) + 1
                words(:, e - a + 1) = real(buf(at(r) + 1:at(r) + nw), sp)
                at(r) = at(r) + nw
            end do
            if (writes) call binary_put(s, words, nw*(b - a + 1))
        end do
        if (writes) call binary_tail(s, sh, solids, bm)
    end subroutine write_state_by_ranks

end module xd_solver_state_writer
