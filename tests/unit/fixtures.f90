!> Small models built in code for the unit tests: structured blocks of
!> hexahedra and sheets of shells, nodes merged by position when `share`
!> is asked for, one elastic steel material per part.
module xd_test_fixtures
    use xd_kinds, only: wp
    use xd_model, only: model_t, part_t, material_t, mat_elastic
    implicit none
    private
    public :: empty_model, add_block, add_shell, node_at, set_sheet, grid_quads

contains

    subroutine empty_model(model, npart)
        type(model_t), intent(out) :: model
        integer, intent(in) :: npart
        integer :: p
        model%nnode = 0
        allocate (model%x0(3, 0), model%node_id(0), model%node_tc(0), model%node_rc(0))
        allocate (model%hex_conn(8, 0), model%hex_part(0), model%hex_id(0))
        allocate (model%shell_conn(4, 0), model%shell_part(0), model%shell_t(4, 0), model%shell_id(0))
        model%npart = npart
        model%nmat = 1
        allocate (model%part(npart), model%mat(1))
        model%mat(1) = material_t(id=1, mtype=mat_elastic, ro=7850.0_wp, e=200.0e9_wp, pr=0.3_wp)
        do p = 1, npart
            model%part(p) = part_t(id=p, mid=1, mat_ix=1)
        end do
    end subroutine empty_model

    !> Index of the node at p: an existing one within 1e-9 when `share`,
    !> else a new one.
    integer function node_at(model, p, share) result(ix)
        type(model_t), intent(inout) :: model
        real(wp), intent(in) :: p(3)
        logical, intent(in) :: share
        if (share) then
            do ix = 1, model%nnode
                if (all(abs(model%x0(:, ix) - p) < 1.0e-9_wp)) return
            end do
        end if
        model%nnode = model%nnode + 1
        ix = model%nnode
        model%x0 = reshape([model%x0, p], [3, ix])
        model%node_id = [model%node_id, ix]
        model%node_tc = [model%node_tc, 0]
        model%node_rc = [model%node_rc, 0]
    end function node_at

    !> nx x ny x nz hexahedra of size h (3) from corner lo, in part pid;
    !> elements listed in `skip` (1-based, x fastest) are left out.
    subroutine add_block(model, n, lo, h, pid, share, skip)
        type(model_t), intent(inout) :: model
        integer, intent(in) :: n(3), pid
        real(wp), intent(in) :: lo(3), h(3)
        logical, intent(in) :: share
        integer, intent(in), optional :: skip(:)
        integer :: i, j, k, e, c(8), a, b, d
        integer, allocatable :: grid(:, :, :)
        allocate (grid(0:n(1), 0:n(2), 0:n(3)))
        do k = 0, n(3)
            do j = 0, n(2)
                do i = 0, n(1)
                    grid(i, j, k) = node_at(model, lo + h*[i, j, k], share)
                end do
            end do
        end do
        e = 0
        do k = 0, n(3) - 1
            do j = 0, n(2) - 1
                do i = 0, n(1) - 1
                    e = e + 1
                    if (present(skip)) then
                        if (any(skip == e)) cycle
                    end if
                    a = i; b = j; d = k
                    c = [grid(a, b, d), grid(a + 1, b, d), grid(a + 1, b + 1, d), grid(a, b + 1, d), &
                         grid(a, b, d + 1), grid(a + 1, b, d + 1), grid(a + 1, b + 1, d + 1), grid(a, b + 1, d + 1)]
                    model%nhex = model%nhex + 1
                    model%hex_conn = reshape([model%hex_conn, c], [8, model%nhex])
                    model%hex_part = [model%hex_part, pid]
                    model%hex_id = [model%hex_id, model%nhex]
                end do
            end do
        end do
    end subroutine add_block

    !> One shell on nodes nd (indices; nd(4) = nd(3) for a triangle) of
    !> thickness t in part pid.
    subroutine add_shell(model, nd, t, pid)
        type(model_t), intent(inout) :: model
        integer, intent(in) :: nd(4), pid
        real(wp), intent(in) :: t
        model%nshell = model%nshell + 1
        model%shell_conn = reshape([model%shell_conn, nd], [4, model%nshell])
        model%shell_t = reshape([model%shell_t, [t, t, t, t]], [4, model%nshell])
        model%shell_part = [model%shell_part, pid]
        model%shell_id = [model%shell_id, model%nshell]
    end subroutine add_shell

    !> Replace the model's nodes and shells by a sheet at once (for large
    !> meshes, where adding one at a time would cost n^2).
    subroutine set_sheet(model, x, conn, t, pid)
        type(model_t), intent(inout) :: model
        real(wp), intent(in) :: x(:, :), t
        integer, intent(in) :: conn(:, :), pid
        integer :: i
        model%nnode = size(x, 2)
        model%x0 = x
        model%node_id = [(i, i=1, model%nnode)]
        model%node_tc = [(0, i=1, model%nnode)]
        model%node_rc = model%node_tc
        model%nshell = size(conn, 2)
        model%shell_conn = conn
        model%shell_t = reshape([(t, i=1, 4*model%nshell)], [4, model%nshell])
        model%shell_part = [(pid, i=1, model%nshell)]
        model%shell_id = [(i, i=1, model%nshell)]
    end subroutine set_sheet

    !> Connectivity of an n x n grid of quads on (n + 1)^2 nodes numbered
    !> row by row (node 1 + i + (n + 1) j at column i, row j).
    function grid_quads(n) result(conn)
        integer, intent(in) :: n
        integer :: conn(4, n*n)
        integer :: i, j
        do j = 0, n - 1
            do i = 0, n - 1
                conn(:, 1 + i + n*j) = [1 + i + (n + 1)*j, 2 + i + (n + 1)*j, 2 + i + (n + 1)*(j + 1), 1 + i + (n + 1)*(j + 1)]
            end do
        end do
    end function grid_quads

end module xd_test_fixtures
