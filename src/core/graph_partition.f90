!> Graph partitioning by METIS (Debian's libmetis, 32-bit indices): the
!> MPI decomposition's alternative to recursive coordinate bisection
!> (issue 32, `decomp=metis`). The work items (solid groups, shells) are
!> the vertices, weighted by their cost; two items that share nodes are
!> joined by an edge weighted by the number of nodes they share, so the
!> k-way partition's edge cut is the halo the ranks exchange. METIS's
!> random choices start from a fixed seed: every rank computes the same
!> partition from the same graph, and a run's partition depends on the
!> model alone.
module xd_core_graph_partition
    use, intrinsic :: iso_c_binding, only: c_int, c_ptr, c_null_ptr
    use xd_core_sorting, only: small_sort
    implicit none
    private
    public :: graph_partition, item_graph

    integer, parameter :: metis_noptions = 40
    !> (positions in METIS's options array, moptions_et of metis.h, + 1)
    integer, parameter :: opt_seed = 9, opt_ufactor = 17, opt_numbering = 18
    integer(c_int), parameter :: metis_ok = 1

    interface
        integer(c_int) function metis_set_default_options(options) bind(C, name='METIS_SetDefaultOptions')
            import :: c_int
            integer(c_int), intent(inout) :: options(*)
        end function metis_set_default_options

        integer(c_int) function metis_part_graph_kway(nvtxs, ncon, xadj, adjncy, vwgt, vsize, adjwgt, nparts, &
                                                      tpwgts, ubvec, options, edgecut, part) &
            bind(C, name='METIS_PartGraphKway')
            import :: c_int, c_ptr
            integer(c_int), intent(in) :: nvtxs, ncon, nparts
            integer(c_int), intent(in) :: xadj(*), adjncy(*), vwgt(*), adjwgt(*), options(*)
            type(c_ptr), value :: vsize, tpwgts, ubvec
            integer(c_int), intent(out) :: edgecut, part(*)
        end function metis_part_graph_kway
    end interface

contains

    !> The graph of n work items whose nodes are item_node(item_ptr(i) ..
    !> item_ptr(i + 1) - 1) (a node may repeat within an item): adjacency
    !> lists xadj/adjncy (1-based, METIS's CSR form) in ascending item
    !> order, and adjwgt, the nodes each pair shares.
    subroutine item_graph(n, nnode, item_ptr, item_node, xadj, adjncy, adjwgt)
        integer, intent(in) :: n, nnode, item_ptr(:), item_node(:)
        integer, allocatable, intent(out) :: xadj(:), adjncy(:), adjwgt(:)
        integer, allocatable :: node_ptr(:), node_item(:), fill(:), mark(:), wgt(:), nb(:), seen(:)
        integer :: i, j, k, nd, q, cnt, m, pass
        ! the items of each node (CSR), each item once per node: counted on
        ! the first pass, placed on the second
        allocate (node_ptr(nnode + 2), mark(nnode), fill(nnode), node_item(0))
        node_ptr = 0
        fill = 0
        do pass = 1, 2
            mark = 0
            do i = 1, n
                do j = item_ptr(i), item_ptr(i + 1) - 1
                    nd = item_node(j)
                    if (mark(nd) == i) cycle
                    mark(nd) = i
                    if (pass == 1) then
                        node_ptr(nd + 2) = node_ptr(nd + 2) + 1
                    else
                        node_item(node_ptr(nd + 1) + fill(nd)) = i
                        fill(nd) = fill(nd) + 1
                    end if
                end do
            end do
            if (pass == 2) exit
            node_ptr(1:2) = 1
            do nd = 2, nnode + 1
                node_ptr(nd + 1) = node_ptr(nd + 1) + node_ptr(nd)
            end do
            deallocate (node_item)
            allocate (node_item(node_ptr(nnode + 2) - 1))
        end do
        ! each item's neighbours: the other items at its nodes, with the
        ! count of nodes shared (in ascending order: the items of a node are)
        allocate (xadj(n + 1), wgt(n), nb(n), seen(n))
        seen = 0
        ! (mark: per node, the item whose nodes were taken last; seen: per
        ! item, the item whose neighbour it was found last)
        mark = 0
        wgt = 0
        xadj(1) = 1
        allocate (adjncy(16*n), adjwgt(16*n))
        do i = 1, n
            cnt = 0
            do j = item_ptr(i), item_ptr(i + 1) - 1
                nd = item_node(j)
                if (mark(nd) == i) cycle
                mark(nd) = i
                do q = node_ptr(nd + 1), node_ptr(nd + 2) - 1
                    k = node_item(q)
                    if (k == i) cycle
                    if (seen(k) /= i) then
                        seen(k) = i
                        cnt = cnt + 1
                        nb(cnt) = k
                        wgt(k) = 0
                    end if
                    wgt(k) = wgt(k) + 1
                end do
            end do
            call small_sort(nb(1:cnt))
            m = xadj(i)
            if (m + cnt - 1 > size(adjncy)) call grow(m + cnt)
            do q = 1, cnt
                adjncy(m + q - 1) = nb(q)
                adjwgt(m + q - 1) = wgt(nb(q))
            end do
            xadj(i + 1) = m + cnt
        end do
        adjncy = adjncy(1:xadj(n + 1) - 1)
        adjwgt = adjwgt(1:xadj(n + 1) - 1)
    contains
        subroutine grow(need)
            integer, intent(in) :: need
            integer, allocatable :: t(:)
            integer :: cap
            cap = max(2*size(adjncy), need)
            allocate (t(cap))
            t(1:size(adjncy)) = adjncy
            call move_alloc(t, adjncy)
            allocate (t(cap))
            t(1:size(adjwgt)) = adjwgt
            call move_alloc(t, adjwgt)
        end subroutine grow
    end subroutine item_graph

    !> part(i) in 1..nparts for the graph's n = size(vwgt) vertices (k-way,
    !> imbalance at most 3%, METIS's default; contiguous parts where the
    !> graph allows); edgecut: the weight of the edges cut; ok false if
    !> METIS fails (its status in `status`).
    subroutine graph_partition(xadj, adjncy, vwgt, adjwgt, nparts, part, edgecut, ok, status)
        integer, intent(in) :: xadj(:), adjncy(:), vwgt(:), adjwgt(:), nparts
        integer, intent(out) :: part(:), edgecut, status
        logical, intent(out) :: ok
        integer(c_int) :: options(metis_noptions), nv, ncon, np, cut, rc
        integer(c_int), allocatable :: cpart(:)
        nv = size(vwgt)
        part = 1
        edgecut = 0
        status = metis_ok
        ok = .true.
        if (nparts <= 1 .or. nv <= 1) return
        rc = metis_set_default_options(options)
        options(opt_numbering) = 1
        options(opt_seed) = 1
        options(opt_ufactor) = 30
        ncon = 1
        np = nparts
        allocate (cpart(nv))
        rc = metis_part_graph_kway(nv, ncon, xadj, adjncy, vwgt, c_null_ptr, adjwgt, np, c_null_ptr, c_null_ptr, &
                                   options, cut, cpart)
        status = rc
        ok = rc == metis_ok
        if (.not. ok) return
        part = cpart
        edgecut = cut
    end subroutine graph_partition

end module xd_core_graph_partition
