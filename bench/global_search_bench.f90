!> make bench, global search alone. (1) A crumpled sheet of shells (a
!> coiled sheet whose turns overlap, so every node has other layers nearby)
!> of about 1e4, 1e5 and 1e6 nodes with the same local geometry at every
!> size: the cost per slave must stay flat. (2) Mixed sizes against their
!> uniform twins: a flat plate of 10 mm shells alone and 5 mm above one
!> 20 m ground shell; a square tube of 5 mm shells under a plate of 5 mm
!> shells and under one of 10 mm; a 1 mm patch in an 8 mm plate against
!> the patch alone (what the patch adds per patch node and search, the
!> plate's and the patched plate's searches timed in turns so that the
!> machine's drift cancels in their difference). Prints nanoseconds per
!> slave node per search (median of the repeats), master nodes and pool
!> per slave.
!> Usage: search_bench [N ...]  (sizes of the crumpled sheet; "mixed" alone
!> runs the mixed cases only)
program global_search_bench
    use xd_kinds, only: wp, dp, i8
    use xd_model, only: model_t, part_t, material_t, mat_elastic, mnl_minimal
    use xd_contact_surface, only: faces_t, surface_t, build_faces, build_surface
    use xd_contact_global_search, only: master_lists_t, build_master_lists, characteristic_lengths, search_counts_t, &
                                        typical_length, pool_margins, margin_classes
    use xd_core_sorting, only: small_sort
    implicit none
    integer :: k, nargs
    character(len=32) :: arg
    integer, allocatable :: sizes(:)
    logical :: mixed_only
    real(dp) :: ns(4), ms(4)

    !> One prepared search: the surface of the shells, its coordinates,
    !> characteristic lengths and pool margins, the slaves' margin classes.
    type :: prepared_t
        type(surface_t) :: s
        real(wp), allocatable :: xl(:, :), lc(:), dl(:), cmin(:), lcodo(:)
        integer, allocatable :: cls(:)
        type(master_lists_t) :: l
        type(search_counts_t) :: cnt
    end type prepared_t

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
    call patch_cases()

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

    !> A 2.08 m square plate of 8 mm shells (260 x 260, 68,121 nodes); the
    !> same with its central 64 mm (8 x 8 shells) replaced by 64 x 64
    !> shells of 1 mm (4,225 nodes; the patch's border nodes apart from the
    !> coarse ones, as a non-conforming refinement); that patch alone. 1 mm
    !> thick. The three searched in turns, 31 times: the patch's added cost
    !> per patch node is the median over the turns of (patched plate -
    !> plate) / patch nodes, against the median of the patch alone. The
    !> search interval follows the smallest margins that move: the patch's
    !> nodes keep their own margins in the plate (printed), so what a run
    !> pays per unit of the patch's motion is in the same ratio.
    subroutine patch_cases()
        integer, parameter :: nrep = 31
        type(prepared_t) :: c(0:2)
        real(dp) :: t(nrep, 0:3), add(nrep), np, nm
        integer :: kind, r, fine
        do kind = 0, 2
            call patch_surface(kind, c(kind))
        end do
        do kind = 0, 2
            t(1, kind) = one_search(c(kind))    ! warm-up
        end do
        ! the patch's own margin class in the patched plate (timed after,
        ! in turns with the patch alone): what a run searches at the pace
        ! of the patch's motion
        fine = minloc(c(1)%cmin, 1)
        do r = 1, nrep
            do kind = 0, 2
                t(r, kind) = one_search(c(kind))
            end do
        end do
        np = real(c(2)%s%nslave, dp)
        add = (t(:, 1) - t(:, 0))/np
        call small_sort(add)
        do kind = 0, 2
            call small_sort(t(:, kind))
            write (*, '(2x,a28,i15,i11,f18.1,f16.2,f13.2)') label(kind), c(kind)%s%nnode, nrep, &
                1.0e9_dp*t((nrep + 1)/2, kind)/c(kind)%s%nslave, real(c(kind)%cnt%masters, dp)/c(kind)%s%nslave, &
                real(c(kind)%cnt%pool, dp)/c(kind)%s%nslave
        end do
        write (*, '(a,f8.1,a,f8.1,a,f6.2,a)') '  mixed sizes: 1 mm patch in an 8 mm plate adds ', &
            1.0e9_dp*add((nrep + 1)/2), ' ns per patch node and search, alone ', 1.0e9_dp*t((nrep + 1)/2, 2)/np, &
            ' (', add((nrep + 1)/2)/(t((nrep + 1)/2, 2)/np), 'x)'
        ! the master nodes the local search checks at every cycle
        nm = 0
        do r = 1, c(1)%s%nslave
            if (c(1)%s%node(c(1)%s%slave(r)) > (260 + 1)**2) nm = nm + c(1)%l%last(r) - c(1)%l%ptr(r) + 1
        end do
        write (*, '(a,f7.2,a,f7.2,a,f6.2,a)') '  mixed sizes: master nodes per patch slave in the plate ', nm/np, &
            ', alone ', c(2)%cnt%masters/np, ' (', nm/real(c(2)%cnt%masters, dp), 'x)'
        do r = 1, nrep
            t(r, 3) = one_search(c(1), fine)
            t(r, 2) = one_search(c(2))
        end do
        call small_sort(t(:, 2))
        call small_sort(t(:, 3))
        write (*, '(a,i0,a,f8.1,a,f8.1,a,f6.2,a)') '  mixed sizes: the patch''s margin class (', &
            count(c(1)%cls == fine), ' slaves) searched in the plate ', 1.0e9_dp*t((nrep + 1)/2, 3)/np, &
            ' ns per patch node, alone ', 1.0e9_dp*t((nrep + 1)/2, 2)/np, ' (', t((nrep + 1)/2, 3)/t((nrep + 1)/2, 2), 'x)'
        write (*, '(a,f6.3,a,f6.3,a,f6.3,a)') '  mixed sizes: the patch''s least pool margin in the plate ', &
            1000*minval(c(1)%dl), ' mm, alone ', 1000*minval(c(2)%dl), ' mm (the plate''s ', 1000*maxval(c(0)%dl), ' mm)'
    end subroutine patch_cases

    character(len=28) function label(k)
        integer, intent(in) :: k
        select case (k)
        case (0); label = '8 mm plate (260 x 260)'
        case (1); label = 'the same, a 1 mm patch in it'
        case default; label = 'the 1 mm patch alone'
        end select
    end function label

    !> kind 0: the plate; 1: the plate with the patch; 2: the patch alone.
    subroutine patch_surface(kind, pc)
        integer, intent(in) :: kind
        type(prepared_t), intent(out) :: pc
        integer, parameter :: nc = 260, nf = 64, i0 = 126
        real(wp), allocatable :: x(:, :)
        integer, allocatable :: conn(:, :)
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
                    conn(:, e) = [1 + i + (nc + 1)*j, 2 + i + (nc + 1)*j, 2 + i + (nc + 1)*(j + 1), &
                                  1 + i + (nc + 1)*(j + 1)]
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
        call prepare(x, conn(:, 1:e), 0.001_wp, pc)
    end subroutine patch_surface

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
    !> thickness th, prepared for the search as the run makes it (reach =
    !> thickness, margins 0.25 x the local characteristic length).
    subroutine prepare(x, conn, th, pc)
        real(wp), intent(in) :: x(:, :), th
        integer, intent(in) :: conn(:, :)
        type(prepared_t), intent(out) :: pc
        type(model_t) :: m
        type(faces_t) :: f
        real(wp), allocatable :: dmin(:)
        logical, allocatable :: in_a(:), in_b(:)
        integer :: i, nraised
        real(wp) :: typ

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
                           [0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp], [0.1_wp, 1.0_wp, 1.0_wp], pc%s)
        allocate (pc%xl(3, pc%s%nnode), pc%lc(pc%s%nnode))
        pc%xl = m%x0(:, pc%s%node)
        call characteristic_lengths(pc%s, pc%xl, pc%lc)
        typ = 0.25_wp*typical_length(pack(pc%lc, pc%lc > 0.0_wp), 0.5_wp)
        call pool_margins(pc%s, pc%lc, 0.25_wp, typ, pc%dl, dmin, nraised)
        call margin_classes(pc%s, pc%dl, pc%cls, pc%cmin)
        allocate (pc%lcodo(pc%s%nnode))
        pc%lcodo = 0
    end subroutine prepare

    !> Seconds of one search of pc (characteristic lengths included: a
    !> search takes them, of the nodes it buckets); with cls, of that margin
    !> class's slaves only (the others keep their lists), as a run makes it.
    real(dp) function one_search(pc, cls) result(t)
        type(prepared_t), intent(inout) :: pc
        integer, intent(in), optional :: cls
        integer(i8) :: c0, c1, rate
        call system_clock(c0, rate)
        if (present(cls)) then
            call build_master_lists(pc%s, pc%xl, pc%lc, pc%s%max_thick, pc%dl, mnl_minimal, pc%l, pc%cnt, pc%cls == cls, &
                                    1, 0.0_wp, pc%lcodo)
        else
            call build_master_lists(pc%s, pc%xl, pc%lc, pc%s%max_thick, pc%dl, mnl_minimal, pc%l, pc%cnt, &
                                    odo=0.0_wp, lcodo=pc%lcodo)
        end if
        call system_clock(c1)
        t = real(c1 - c0, dp)/real(rate, dp)
    end function one_search

    !> The search of the shells conn on the nodes x, thickness th
    !> (prepare), timed. Prints the row; t: ns per slave per search, mm:
    !> master nodes per slave.
    subroutine time_search(label, x, conn, th, t, mm)
        character(len=*), intent(in) :: label
        real(wp), intent(in) :: x(:, :), th
        integer, intent(in) :: conn(:, :)
        real(dp), intent(out) :: t, mm
        type(prepared_t) :: pc
        real(dp), allocatable :: tr(:)
        real(dp) :: t0
        integer :: nrep, r
        call prepare(x, conn, th, pc)
        nrep = max(3, min(50, 2000000/pc%s%nnode))
        allocate (tr(nrep))
        t0 = one_search(pc)      ! warm-up
        do r = 1, nrep
            tr(r) = one_search(pc)
        end do
        call small_sort(tr)
        t = 1.0e9_dp*tr((nrep + 1)/2)/pc%s%nslave
        mm = real(pc%cnt%masters, dp)/pc%s%nslave
        write (*, '(2x,a28,i15,i11,f18.1,f16.2,f13.2)') label, pc%s%nnode, nrep, t, mm, real(pc%cnt%pool, dp)/pc%s%nslave
    end subroutine time_search

end program global_search_bench
