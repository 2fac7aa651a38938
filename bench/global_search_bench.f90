!> make bench, global search alone: a crumpled sheet of shells (a coiled
!> sheet whose turns overlap, so every node has other layers nearby) of
!> about 1e4, 1e5 and 1e6 nodes with the same local geometry at every size.
!> Prints nanoseconds per slave node per search (median of the repeats),
!> master nodes and pool per slave. Usage: search_bench [N ...]
program global_search_bench
    use xd_kinds, only: wp, dp, i8
    use xd_model, only: model_t, part_t, material_t, mat_elastic, mnl_minimal
    use xd_contact_surface, only: faces_t, surface_t, build_faces, build_surface
    use xd_contact_global_search, only: master_lists_t, build_master_lists, characteristic_lengths, search_counts_t
    use xd_core_sorting, only: small_sort
    implicit none
    integer :: k, nargs, target
    character(len=32) :: arg
    integer, allocatable :: sizes(:)

    nargs = command_argument_count()
    if (nargs == 0) then
        sizes = [10000, 100000, 1000000]
    else
        allocate (sizes(nargs))
        do k = 1, nargs
            call get_command_argument(k, arg)
            read (arg, *) sizes(k)
        end do
    end if
    write (*, '(a)') '  surface nodes   searches   ns/slave/search   masters/slave   pool/slave'
    do k = 1, size(sizes)
        target = sizes(k)
        call one_size(target)
    end do

contains

    subroutine one_size(target)
        integer, intent(in) :: target
        type(model_t) :: m
        type(faces_t) :: f
        type(surface_t) :: s
        type(master_lists_t) :: l
        type(search_counts_t) :: cnt
        real(wp), allocatable :: xl(:, :), lc(:)
        real(dp), allocatable :: t(:)
        logical, allocatable :: in_a(:), in_b(:)
        integer :: n, i, j, nrep, r
        integer(i8) :: c0, c1, rate
        real(wp) :: a, h

        ! an n x n sheet of unit squares, coiled about the y axis: radius 4,
        ! 0.15 advance per element, so turns lie about 3.6 apart
        n = nint(sqrt(real(target, wp))) - 1
        h = 1.0_wp
        m%nnode = (n + 1)**2
        allocate (m%x0(3, m%nnode), m%node_id(m%nnode), m%node_tc(m%nnode), m%node_rc(m%nnode))
        do j = 0, n
            do i = 0, n
                a = 2*acos(-1.0_wp)*i/24.0_wp
                m%x0(:, 1 + i + (n + 1)*j) = [0.15_wp*i*h + 4*h*sin(a), j*h + 0.3_wp*h*sin(0.37_wp*i), &
                                              4*h*cos(a) + 0.5_wp*h*sin(2*acos(-1.0_wp)*j/17.0_wp)]
            end do
        end do
        do i = 1, m%nnode
            m%node_id(i) = i
        end do
        m%node_tc = 0
        m%node_rc = 0
        m%nshell = n*n
        allocate (m%shell_conn(4, m%nshell), m%shell_part(m%nshell), m%shell_t(4, m%nshell), m%shell_id(m%nshell))
        do j = 0, n - 1
            do i = 0, n - 1
                m%shell_conn(:, 1 + i + n*j) = [1 + i + (n + 1)*j, 2 + i + (n + 1)*j, 2 + i + (n + 1)*(j + 1), &
                                                1 + i + (n + 1)*(j + 1)]
            end do
        end do
        m%shell_part = 1
        m%shell_t = 0.05_wp
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
        nrep = max(3, min(50, 2000000/s%nnode))
        allocate (t(nrep))
        ! one search to warm up, then the timed ones (characteristic lengths
        ! included: a search recomputes them)
        call characteristic_lengths(s, xl, lc)
        call build_master_lists(s, xl, lc, 0.05_wp, 0.25_wp*sqrt(2.0_wp), mnl_minimal, l, cnt)
        do r = 1, nrep
            call system_clock(c0, rate)
            call characteristic_lengths(s, xl, lc)
            call build_master_lists(s, xl, lc, 0.05_wp, 0.25_wp*sqrt(2.0_wp), mnl_minimal, l, cnt)
            call system_clock(c1)
            t(r) = real(c1 - c0, dp)/real(rate, dp)
        end do
        call small_sort(t)
        write (*, '(i15,i11,f18.1,f16.2,f13.2)') s%nnode, nrep, 1.0e9_dp*t((nrep + 1)/2)/s%nslave, &
            real(cnt%masters, dp)/s%nslave, real(cnt%pool, dp)/s%nslave
    end subroutine one_size

end program global_search_bench
