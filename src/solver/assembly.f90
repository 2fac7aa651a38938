!> Deterministic force assembly: each element-node incidence has its own force
!> slot; a node's force is the sum of its slots in a fixed (element) order,
!> whatever the thread or rank count ("parith on").
module xd_solver_assembly
    use xd_kinds, only: wp
    use xd_core_memory, only: alloc, fit
    use xd_core_threads, only: threaded
    implicit none
    private
    public :: assembly_t, build_assembly, assemble, keep_assembled

    type :: assembly_t
        integer :: nnode = 0
        integer, allocatable :: ptr(:)    !< (nnode+1) start of each node's slot list
        integer, allocatable :: slot(:)   !< slot indices, ascending for each node
    end type assembly_t

contains

    !> Node -> slot lists for connectivity conn(nen, nel); slot 8(e-1)+k style.
    subroutine build_assembly(nnode, conn, asm)
        integer, intent(in) :: nnode
        integer, intent(in) :: conn(:, :)
        type(assembly_t), intent(out) :: asm
        integer :: nen, nel, e, k, nd
        integer, allocatable :: fill(:)
        nen = size(conn, 1)
        nel = size(conn, 2)
        asm%nnode = nnode
        call alloc(asm%ptr, nnode + 1, 'assembly pointers')
        call alloc(asm%slot, nen*nel, 'assembly slots')
        do e = 1, nel
            do k = 1, nen
                nd = conn(k, e)
                asm%ptr(nd + 1) = asm%ptr(nd + 1) + 1
            end do
        end do
        asm%ptr(1) = 1
        do nd = 1, nnode
            asm%ptr(nd + 1) = asm%ptr(nd + 1) + asm%ptr(nd)
        end do
        allocate (fill(nnode))
        fill = asm%ptr(1:nnode)
        do e = 1, nel
            do k = 1, nen
                nd = conn(k, e)
                asm%slot(fill(nd)) = nen*(e - 1) + k
                fill(nd) = fill(nd) + 1
            end do
        end do
    end subroutine build_assembly

    !> The slot lists of the nodes this rank assembles (mine) alone, the
    !> others' emptied and their room given back (issue 32: more than one
    !> rank assembles only its own nodes, exchange_phase, so another rank's
    !> node's list is never read; on 16 ranks of the 250,000-shell plate a
    !> rank's shell lists went from 4 MB to a sixteenth). The pointers keep
    !> their length (every node's, until the nodes are numbered per rank);
    !> a kept list is unchanged, in its order.
    subroutine keep_assembled(asm, mine)
        type(assembly_t), intent(inout) :: asm
        logical, intent(in) :: mine(:)
        integer :: nd, j, q, first
        if (.not. allocated(asm%ptr)) return
        q = 0
        first = asm%ptr(1)
        do nd = 1, asm%nnode
            ! (in place: a list only moves down)
            if (mine(nd)) then
                do j = first, asm%ptr(nd + 1) - 1
                    q = q + 1
                    asm%slot(q) = asm%slot(j)
                end do
            end if
            first = asm%ptr(nd + 1)
            asm%ptr(nd + 1) = q + 1
        end do
        call fit(asm%slot, q)
    end subroutine keep_assembled

    !> f(:, node) = sum of its slots, in slot order (added to f with `add`),
    !> for every node or the nodes listed in `nodes`; with mslot and m, also
    !> m(:, node) from mslot in the same pass over the slots (the shells'
    !> forces and moments: the same sums, bit for bit, as two passes).
    subroutine assemble(asm, fslot, f, add, nodes, mslot, m)
        type(assembly_t), intent(in) :: asm
        real(wp), contiguous, intent(in) :: fslot(:, :)
        real(wp), contiguous, intent(inout) :: f(:, :)
        logical, intent(in), optional :: add
        integer, intent(in), optional :: nodes(:)
        real(wp), contiguous, intent(in), optional :: mslot(:, :)
        real(wp), contiguous, intent(inout), optional :: m(:, :)
        logical :: acc, pair
        integer :: n
        acc = .false.
        if (present(add)) acc = add
        pair = present(mslot) .and. present(m)
        n = asm%nnode
        if (present(nodes)) n = size(nodes)
        ! (a region only where threads run and the list is long: car6's
        ! 2,378 nodes on two threads took 1.5-2.4 s in this phase with a
        ! region each call, against 0.23 s on one thread)
        if (threaded(n)) then
            !$omp parallel
            call assemble_loop(asm, fslot, f, acc, pair, n, nodes, mslot, m)
            !$omp end parallel
        else
            call assemble_loop(asm, fslot, f, acc, pair, n, nodes, mslot, m)
        end if
    end subroutine assemble

    !> assemble's loop over its n nodes (nodes(i), or i), an orphaned
    !> worksharing loop: the calling region's team shares it, or the thread
    !> that calls it outside one runs it whole.
    subroutine assemble_loop(asm, fslot, f, acc, pair, n, nodes, mslot, m)
        type(assembly_t), intent(in) :: asm
        real(wp), contiguous, intent(in) :: fslot(:, :)
        real(wp), contiguous, intent(inout) :: f(:, :)
        logical, intent(in) :: acc, pair
        integer, intent(in) :: n
        integer, intent(in), optional :: nodes(:)
        real(wp), contiguous, intent(in), optional :: mslot(:, :)
        real(wp), contiguous, intent(inout), optional :: m(:, :)
        integer :: i, nd, j, k
        real(wp) :: s1, s2, s3, r1, r2, r3
        !$omp do schedule(static)
        do i = 1, n
            nd = i
            if (present(nodes)) nd = nodes(i)
            s1 = 0; s2 = 0; s3 = 0
            if (acc) then
                s1 = f(1, nd); s2 = f(2, nd); s3 = f(3, nd)
            end if
            if (pair) then
                r1 = 0; r2 = 0; r3 = 0
                do j = asm%ptr(nd), asm%ptr(nd + 1) - 1
                    k = asm%slot(j)
                    s1 = s1 + fslot(1, k)
                    s2 = s2 + fslot(2, k)
                    s3 = s3 + fslot(3, k)
                    r1 = r1 + mslot(1, k)
                    r2 = r2 + mslot(2, k)
                    r3 = r3 + mslot(3, k)
                end do
                m(1, nd) = r1; m(2, nd) = r2; m(3, nd) = r3
            else
                do j = asm%ptr(nd), asm%ptr(nd + 1) - 1
                    k = asm%slot(j)
                    s1 = s1 + fslot(1, k)
                    s2 = s2 + fslot(2, k)
                    s3 = s3 + fslot(3, k)
                end do
            end if
            f(1, nd) = s1; f(2, nd) = s2; f(3, nd) = s3
        end do
        !$omp end do
    end subroutine assemble_loop

end module xd_solver_assembly
