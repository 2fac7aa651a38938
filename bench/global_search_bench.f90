!> make bench, global search alone. (1) A crumpled sheet of shells (a
!> coiled sheet whose turns overlap, so every node has other layers nearby)
!> of about 1e4, 1e5 and 1e6 nodes with the same local geometry at every
!> size: the cost per slave must stay flat. (2) Mixed sizes against their
!> uniform twins: a flat plate of 10 mm shells alone and 5 mm above one
!> 20 m ground shell; a square tube of 5 mm shells under a plate of 5 mm
!> shells and under one of 10 mm; a 1 mm patch in an 8 mm plate against
!> the patch alone (what the patch adds per patch node and search). Prints
!> nanoseconds per slave node per
!> search (median of the repeats), master nodes and pool per slave.
!> Usage: search_bench [N ...]  (sizes of the crumpled sheet; "mixed" alone
!> runs the mixed cases only)
program global_search_bench
    use xd_kinds, only: wp, dp, i8
    use xd_model, only: model_t, part_t, material_t, mat_elastic, mnl_minimal
    use xd_contact_surface, only: faces_t, surface_t, build_faces, build_surface
    use xd_contact_global_search, only: master_lists_t, build_master_lists, characteristic_lengths, search_counts_t, &
                                        typical_length
    use xd_core_sorting, only: small_sort
    implicit none
    integer :: k, nargs
    character(len=32) :: arg
    integer, allocatable :: sizes(:)
    logical :: mixed_only
    real(dp) :: ns(4), ms(4), nsp(3), msp(3), nnp(3), dlp(3), add

    nargs = command_argument_count()
    mixed_only = .false.
    if (nargs == 0) then
        sizes = [10000, 100000, 1000000]
    else
        call get_command_argument(1, arg)
        mixed_only = trim(arg) == 'mixed'
        allocate (sizes(0))
        if (.not. mixed_only) then
            deallocate (sizes)
            allocate (sizes(nargs))
            do k = 1, nargs
                call get_command_argument(k, arg)
                read (arg, *) sizes(k)
            end do
        end if
    end if
    write (*, '(a)') '  case                         surface nodes   searches   ns/slave/search   masters/slave   pool/slave'
    do k = 1, size(sizes)
        call coiled_sheet(sizes(k))
    end do
    if (size(sizes) > 0 .and. .not. mixed_only) then
        if (nargs > 0) stop
    end if
    call plate_case(.false., ns(1), ms(1))
    call plate_case(.true., ns(2), ms(2))
    call tube_case(0.005_wp, ns(3), ms(3))
    call tube_case(0.010_wp, ns(4), ms(4))
    ! (the plate alone has no master nodes at all: its slaves see only their
    ! own flat sheet; on the ground each has the ground's nearest node)
    write (*, '(a,f6.2,a,f5.2,a,f5.2,a)') '  mixed sizes: plate on a ground shell ', ns(2)/ns(1), &
        'x the cost per slave; masters per slave ', ms(2), ' (plate alone ', ms(1), ')'
    write (*, '(a,f6.2,a,f6.2,a)') '  mixed sizes: tube under a coarse plate ', ns(4)/ns(3), 'x the cost per slave, ', &
        ms(4)/ms(3), 'x the masters per slave of the tube under a plate of its own size'
    ! a fine patch in a coarse plate: what the patch adds to a search, per
    ! patch node, against the patch searched alone
    call patch_case(0, nsp(1), msp(1), nnp(1), dlp(1))
    call patch_case(1, nsp(2), msp(2), nnp(2), dlp(2))
    call patch_case(2, nsp(3), msp(3), nnp(3), dlp(3))
    add = (nsp(2)*nnp(2) - nsp(1)*nnp(1))/nnp(3)
    write (*, '(a,f8.1,a,f8.1,a,f6.1,a)') '  mixed sizes: 1 mm patch in an 8 mm plate adds ', &
        add, ' ns per patch node and search, alone ', nsp(3), ' (', add/nsp(3), 'x)'
    ! the search runs when the motion could have used up the margin (4u >
    ! delta): what a run pays per unit of motion is the cost of a search
    ! over delta/4, and the patch alone, with its own smaller margin,
    ! searches as much more often
    write (*, '(a,f9.0,a,f9.0,a,f6.2,a,2(f6.3,a))') '  mixed sizes: per patch node and mm of motion, in the plate ', &
        add/(250*dlp(2)), ' ns, alone ', nsp(3)/(250*dlp(3)), ' (', add/dlp(2)/(nsp(3)/dlp(3)), &
        'x; margins delta ', 1000*dlp(2), ' and ', 1000*dlp(3), ' mm)'

contains

    subroutine coiled_sheet(target)
        integer, intent(in) :: target
        real(wp), allocatable :: x(:, :)
        integer, allocatable :: conn(:, :)
        integer :: n, i, j
        real(wp) :: a, h
        real(dp) :: t, mm
        ! an n x n sheet of unit squares, coiled about the y axis: radius 4,
        ! 0.15 advance per element, so turns lie about 3.6 apart
        n = nint(sqrt(real(target, wp))) - 1
        h = 1.0_wp
        allocate (x(3, (n + 1)**2), conn(4, n*n))
        do j = 0, n
            do i = 0, n
                a = 2*acos(-1.0_wp)*i/24.0_wp
                x(:, 1 + i + (n + 1)*j) = [0.15_wp*i*h + 4*h*sin(a), j*h + 0.3_wp*h*sin(0.37_wp*i), &
                                           4*h*cos(a) + 0.5_wp*h*sin(2*acos(-1.0_wp)*j/17.0_wp)]
            end do
        end do
        call grid_shells(n, conn)
        call time_search('crumpled sheet', x, conn, 0.05_wp, t, mm)
    end subroutine coiled_sheet

    !> A 119 x 119 plate of 10 mm shells (14,400 nodes), 1 mm thick; with
    !> `ground`, one 20 x 20 m shell 5 mm below it.
    subroutine plate_case(ground, t, mm)
        logical, intent(in) :: ground
        real(dp), intent(out) :: t, mm
        real(wp), allocatable :: x(:, :)
        integer, allocatable :: conn(:, :)
        integer :: n, i, j, nn, ne
        n = 119
        nn = (n + 1)**2
        ne = n*n
        if (ground) then
            allocate (x(3, nn + 4), conn(4, ne + 1))
        else
            allocate (x(3, nn), conn(4, ne))
        end if
        do j = 0, n
            do i = 0, n
                x(:, 1 + i + (n + 1)*j) = [0.01_wp*i, 0.01_wp*j, 0.0_wp]
            end do
        end do
        call grid_shells(n, conn)
        if (ground) then
            x(:, nn + 1:nn + 4) = reshape([-10.0_wp, -10.0_wp, -0.005_wp, 10.0_wp, -10.0_wp, -0.005_wp, &
                                           10.0_wp, 10.0_wp, -0.005_wp, -10.0_wp, 10.0_wp, -0.005_wp], [3, 4])
            conn(:, ne + 1) = [nn + 1, nn + 2, nn + 3, nn + 4]
            call time_search('plate on a 20 m ground shell', x, conn, 0.001_wp, t, mm)
        else
            call time_search('plate of 10 mm shells', x, conn, 0.001_wp, t, mm)
        end if
    end subroutine plate_case

    !> kind 0: a 2.08 m square plate of 8 mm shells (260 x 260, 68,121
    !> nodes); 1: the same with its central 64 mm (8 x 8 shells) replaced by
    !> 64 x 64 shells of 1 mm (4,225 nodes; the patch's border nodes apart
    !> from the coarse ones, as a non-conforming refinement); 2: that patch
    !> alone. 1 mm thick. t: ns per slave per search, mm: masters per slave,
    !> nn: nodes, dl: the pool margin delta (m).
    subroutine patch_case(kind, t, mm, nn, dl)
        integer, intent(in) :: kind
        real(dp), intent(out) :: t, mm, nn, dl
        real(wp), allocatable :: x(:, :)
        integer, allocatable :: conn(:, :)
        integer, parameter :: nc = 260, nf = 64, i0 = 126
        integer :: i, j, k, e, nnc, nnf
        logical :: hole
        nnc = 0
        if (kind /= 2) nnc = (nc + 1)**2
        nnf = 0
        if (kind /= 0) nnf = (nf + 1)**2
        allocate (x(3, nnc + nnf), conn(4, nc*nc + nf*nf))
        e = 0
        if (kind /= 2) then
            do j = 0, nc
                do i = 0, nc
                    x(:, 1 + i + (nc + 1)*j) = [0.008_wp*i, 0.008_wp*j, 0.0_wp]
                end do
            end do
            do j = 0, nc - 1
                do i = 0, nc - 1
                    hole = kind == 1 .and. i >= i0 .and. i < i0 + 8 .and. j >= i0 .and. j < i0 + 8
                    if (hole) cycle
                    e = e + 1
                    conn(:, e) = [1 + i + (nc + 1)*j, 2 + i + (nc + 1)*j, 2 + i + (nc + 1)*(j + 1), 1 + i + (nc + 1)*(j + 1)]
                end do
            end do
        end if
        if (kind /= 0) then
            do j = 0, nf
                do i = 0, nf
                    k = nnc + 1 + i + (nf + 1)*j
                    ! (a hair inside the hole's border, so no node coincides)
                    x(:, k) = [0.008_wp*i0 + 1.0e-5_wp + (0.064_wp - 2.0e-5_wp)*i/nf, &
                               0.008_wp*i0 + 1.0e-5_wp + (0.064_wp - 2.0e-5_wp)*j/nf, 0.0_wp]
                end do
            end do
            do j = 0, nf - 1
                do i = 0, nf - 1
                    e = e + 1
                    conn(:, e) = nnc + [1 + i + (nf + 1)*j, 2 + i + (nf + 1)*j, 2 + i + (nf + 1)*(j + 1), &
                                        1 + i + (nf + 1)*(j + 1)]
                end do
            end do
        end if
        select case (kind)
        case (0); call time_search('8 mm plate (260 x 260)', x, conn(:, 1:e), 0.001_wp, t, mm, nn, dl)
        case (1); call time_search('the same, a 1 mm patch in it', x, conn(:, 1:e), 0.001_wp, t, mm, nn, dl)
        case default; call time_search('the 1 mm patch alone', x, conn(:, 1:e), 0.001_wp, t, mm, nn, dl)
        end select
    end subroutine patch_case

    !> A square tube (50 mm side, 150 mm long, 5 mm shells, 1,200 shells)
    !> with a 220 mm square plate of shells of size hp 2 mm above its top.
    subroutine tube_case(hp, t, mm)
        real(wp), intent(in) :: hp
        real(dp), intent(out) :: t, mm
        real(wp), allocatable :: x(:, :)
        integer, allocatable :: conn(:, :)
        integer :: nside, nring, nz, np, i, j, k, side, nn, ne, nt, et
        real(wp) :: c, h, sv, around(2, 40)
        c = 0.05_wp
        h = 0.005_wp
        nside = 10
        nring = 4*nside
        nz = 30
        np = nint(0.22_wp/hp)
        nt = nring*(nz + 1)
        et = nring*nz
        nn = nt + (np + 1)**2
        ne = et + np*np
        allocate (x(3, nn), conn(4, ne))
        k = 0
        do side = 0, 3
            do i = 0, nside - 1
                sv = -c/2 + c*i/nside
                k = k + 1
                select case (side)
                case (0); around(:, k) = [sv, -c/2]
                case (1); around(:, k) = [c/2, sv]
                case (2); around(:, k) = [-sv, c/2]
                case default; around(:, k) = [-c/2, -sv]
                end select
            end do
        end do
        do j = 0, nz
            do i = 1, nring
                x(:, i + nring*j) = [around(1, i), around(2, i), h*j]
            end do
        end do
        do j = 0, nz - 1
            do i = 1, nring
                conn(:, i + nring*j) = [i + nring*j, mod(i, nring) + 1 + nring*j, mod(i, nring) + 1 + nring*(j + 1), &
                                        i + nring*(j + 1)]
            end do
        end do
        do j = 0, np
            do i = 0, np
                x(:, nt + 1 + i + (np + 1)*j) = [-0.11_wp + hp*i, -0.11_wp + hp*j, h*nz + 0.002_wp]
            end do
        end do
        do j = 0, np - 1
            do i = 0, np - 1
                conn(:, et + 1 + i + np*j) = nt + [1 + i + (np + 1)*j, 2 + i + (np + 1)*j, 2 + i + (np + 1)*(j + 1), &
                                                   1 + i + (np + 1)*(j + 1)]
            end do
        end do
        if (hp > 0.0075_wp) then
            call time_search('tube under a 10 mm plate', x, conn, 0.0015_wp, t, mm)
        else
            call time_search('tube under a 5 mm plate', x, conn, 0.0015_wp, t, mm)
        end if
    end subroutine tube_case

    !> The quadrilaterals of an n x n grid of (n + 1)^2 nodes numbered row by row.
    pure subroutine grid_shells(n, conn)
        integer, intent(in) :: n
        integer, intent(out) :: conn(:, :)
        integer :: i, j
        do j = 0, n - 1
            do i = 0, n - 1
                conn(:, 1 + i + n*j) = [1 + i + (n + 1)*j, 2 + i + (n + 1)*j, 2 + i + (n + 1)*(j + 1), &
                                        1 + i + (n + 1)*(j + 1)]
            end do
        end do
    end subroutine grid_shells

    !> One whole-model single surface of the shells conn on the nodes x,
    !> thickness th; the search as the run makes it (reach = thickness,
    !> margin 0.25 x the median characteristic length), timed. Prints the
    !> row; t: ns per slave per search, mm: master nodes per slave.
    subroutine time_search(label, x, conn, th, t, mm, nsl, dl)
        character(len=*), intent(in) :: label
        real(wp), intent(in) :: x(:, :), th
        integer, intent(in) :: conn(:, :)
        real(dp), intent(out) :: t, mm
        real(dp), intent(out), optional :: nsl   !< slave nodes
        real(dp), intent(out), optional :: dl    !< the pool margin delta
        type(model_t) :: m
        type(faces_t) :: f
        type(surface_t) :: s
        type(master_lists_t) :: l
        type(search_counts_t) :: cnt
        real(wp), allocatable :: xl(:, :), lc(:)
        real(dp), allocatable :: tr(:)
        logical, allocatable :: in_a(:), in_b(:)
        integer :: i, nrep, r
        integer(i8) :: c0, c1, rate
        real(wp) :: margin

        m%nnode = size(x, 2)
        m%x0 = x
        allocate (m%node_id(m%nnode), m%node_tc(m%nnode), m%node_rc(m%nnode))
        do i = 1, m%nnode
            m%node_id(i) = i
        end do
        m%node_tc = 0
        m%node_rc = 0
        m%nshell = size(conn, 2)
        m%shell_conn = conn
        allocate (m%shell_part(m%nshell), m%shell_t(4, m%nshell), m%shell_id(m%nshell))
        m%shell_part = 1
        m%shell_t = th
        do i = 1, m%nshell
            m%shell_id(i) = i
        end do
        allocate (m%hex_conn(8, 0), m%hex_part(0), m%hex_id(0))
        m%npart = 1
        m%nmat = 1
        allocate (m%part(1), m%mat(1))
        m%part(1) = part_t(id=1, mid=1, mat_ix=1)
        m%mat(1) = material_t(id=1, mtype=mat_elastic, ro=7850.0_wp, e=200.0e9_wp, pr=0.3_wp)

        call build_faces(m, m%x0, f)
        allocate (in_a(f%n), in_b(f%n))
        in_a = .true.
        in_b = .false.
        call build_surface(f, m%nnode, in_a, in_b, [integer ::], .false., &
                           [0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp], [0.1_wp, 1.0_wp, 1.0_wp], s)
        allocate (xl(3, s%nnode), lc(s%nnode))
        xl = m%x0(:, s%node)
        call characteristic_lengths(s, xl, lc)
        margin = 0.25_wp*typical_length(pack(lc, lc > 0.0_wp), 0.5_wp)
        nrep = max(3, min(50, 2000000/s%nnode))
        allocate (tr(nrep))
        ! one search to warm up, then the timed ones (characteristic lengths
        ! included: a search recomputes them)
        call build_master_lists(s, xl, lc, s%max_thick, margin, mnl_minimal, l, cnt)
        do r = 1, nrep
            call system_clock(c0, rate)
            call characteristic_lengths(s, xl, lc)
            call build_master_lists(s, xl, lc, s%max_thick, margin, mnl_minimal, l, cnt)
            call system_clock(c1)
            tr(r) = real(c1 - c0, dp)/real(rate, dp)
        end do
        call small_sort(tr)
        t = 1.0e9_dp*tr((nrep + 1)/2)/s%nslave
        mm = real(cnt%masters, dp)/s%nslave
        if (present(nsl)) nsl = real(s%nslave, dp)
        if (present(dl)) dl = real(margin, dp)
        write (*, '(2x,a28,i15,i11,f18.1,f16.2,f13.2)') label, s%nnode, nrep, t, mm, real(cnt%pool, dp)/s%nslave
    end subroutine time_search

end program global_search_bench
