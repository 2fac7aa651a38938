!> Step 2 of the automatic contact (section 4): the bucket sort's node pool
!> is exactly the brute-force set on random clouds and on a crumpled sheet
!> of 1e4 nodes; the master node list of a configuration built like the
!> paper's Fig. 4 is the one the paper's walk-through gives; the closest-1
!> and closest-3 lists; the lists do not depend on the thread count. Mixed
!> sizes: the levels of bucket grids give the brute-force pools when radii
!> span four orders of magnitude and each node and query has its own
!> margin, one huge node does not widen the fine level, and a fine patch's
!> nodes are bucketed apart from a coarse majority. Local margins: after a
!> motion of each node up to the bound the search keeps (4 u_i <=
!> delta_min,i), every segment within reach of a slave has all its nodes in
!> the slave's pool from the search (a fine patch on a coarse plate). The
!> slaves' clearances are lower bounds of the distance to
!> every segment they can reach (a finely sampled distance, on the
!> crumpled sheet) and are not all trivial; so are the clearances the local
!> search takes afresh over the search's pools after the sheet has moved.
!> Lists in rows (a rank's own slaves', issue 32): a search of some slaves
!> into their rows gives each the list, pool, gap and stamps a search of
!> every slave gives it, and every slave's lists re-laid in those rows and
!> back keep them (the others then have none).
program test_contact_global_search
    use xd_kinds, only: wp
    use xd_testing, only: check, test_summary
    use xd_model, only: model_t, mnl_minimal, mnl_closest1, mnl_closest3
    use xd_contact_surface, only: faces_t, surface_t, build_faces, build_surface
    use xd_contact_global_search, only: buckets_t, bucket_sort, bucket_radii, node_pool, search_work_t, new_search_work, &
                                        characteristic_lengths, master_lists_t, build_master_lists, search_counts_t, &
                                        levels_t, sort_levels, level_pool, typical_length, pool_margins, margin_classes, &
                                        lists_rows, list_row
    use xd_contact_surface, only: wanted_side
    use xd_contact_local_search, only: local_search_t, fresh_clearance, max_near
    use xd_core_strings, only: ftoa
    use xd_test_fixtures, only: empty_model, add_shell, node_at, set_sheet, grid_quads
    !$ use omp_lib, only: omp_set_num_threads
    implicit none

    call random_cloud(2000, 0.01_wp, 0.08_wp, 'random cloud, 2000 points, radii 0.01-0.08')
    call random_cloud(10000, 0.001_wp, 0.03_wp, 'random cloud, 1e4 points, radii 0.001-0.03')
    call random_cloud(3000, 0.2_wp, 0.2_wp, 'random cloud, 3000 points, one bucket per axis')
    call mixed_cloud()
    call margins_cloud()
    call fine_patch_levels()
    call local_margin_bound()
    call class_search_bound()
    call lists_in_rows()
    call crumpled_sheet()
    call figure4()
    call figure4_paper()
    call test_summary()

contains

    !> Pools from the buckets against a brute-force scan of every pair.
    subroutine random_cloud(n, rmin, rmax, name)
        integer, intent(in) :: n
        real(wp), intent(in) :: rmin, rmax
        character(len=*), intent(in) :: name
        real(wp), allocatable :: x(:, :), r(:), q(:, :)
        integer :: k
        allocate (x(3, n), r(n), q(3, 200))
        call random_seed(put=[(977 + k, k=1, 64)])
        call random_number(x)
        x(3, :) = 0.3_wp*x(3, :)       ! a flattened cloud: unequal bucket counts per axis
        call random_number(r)
        r = rmin + (rmax - rmin)*r
        call random_number(q)
        q = 1.4_wp*q - 0.2_wp          ! query points inside and outside the cloud's box
        call compare_pools(x, r, 0*r, x, 'bucket search = brute force: '//name//' (queries at the points)')
        call compare_pools(x, r, 0*r, q, 'bucket search = brute force: '//name//' (queries in and around the box)')
    end subroutine random_cloud

    !> levels: the levels of bucket grids by size (sort_levels, level_pool)
    !> instead of one grid as wide as the largest radius. Node m is in the
    !> pool of query point i when |q_i - x_m| <= r_m + max(dq_i, dl_m)
    !> (dq: each query's margin, 0 without it).
    subroutine compare_pools(x, r, dl, q, name, levels, dq)
        real(wp), intent(in) :: x(:, :), r(:), dl(:), q(:, :)
        character(len=*), intent(in) :: name
        logical, intent(in), optional :: levels
        real(wp), intent(in), optional :: dq(:)
        type(buckets_t) :: bk
        type(levels_t) :: lev
        logical :: by_level
        type(search_work_t) :: w
        logical, allocatable :: active(:), hit(:), want(:)
        integer :: i, nbad, npairs
        real(wp) :: di
        call new_search_work(size(r), w)
        allocate (active(size(r)), hit(size(r)), want(size(r)))
        active = .true.
        by_level = .false.
        if (present(levels)) by_level = levels
        if (by_level) then
            call sort_levels(x, active, r, dl, lev)
        else
            call bucket_sort(x, active, maxval(r + dl), bk)
            call bucket_radii(bk, r, dl)
        end if
        nbad = 0
        npairs = 0
        do i = 1, size(q, 2)
            di = 0
            if (present(dq)) di = dq(i)
            if (by_level) then
                call level_pool(lev, q(:, i), di, w)
            else
                call node_pool(bk, q(:, i), di, w)
            end if
            hit = .false.
            hit(w%pool(1:w%npool)) = .true.
            want = (x(1, :) - q(1, i))**2 + (x(2, :) - q(2, i))**2 + (x(3, :) - q(3, i))**2 <= (r + max(di, dl))**2
            nbad = nbad + count(hit .neqv. want)
            if (count(hit) /= w%npool) nbad = nbad + 1      ! no node twice
            npairs = npairs + w%npool
        end do
        call check(nbad == 0 .and. npairs > 0, name, 'mismatches '//itoa(nbad)//' pairs '//itoa(npairs))
    end subroutine compare_pools

    !> Radii from 1e-3 to 1 (a few huge ones, like the nodes of a ground
    !> shell under a fine mesh): the pools of the levels equal brute force,
    !> and the finest level's buckets stay as narrow as its own radii.
    subroutine mixed_cloud()
        integer, parameter :: n = 4000
        real(wp), allocatable :: x(:, :), r(:), q(:, :)
        type(levels_t) :: lev
        logical, allocatable :: active(:)
        integer :: k
        allocate (x(3, n), r(n), q(3, 300), active(n))
        call random_seed(put=[(311 + k, k=1, 64)])
        call random_number(x)
        call random_number(r)
        r = 0.001_wp + 0.01_wp*r          ! a fine mesh ...
        r(1:4) = [0.9_wp, 1.0_wp, 0.7_wp, 0.95_wp]    ! ... a ground shell's corners
        r(5:200) = 0.05_wp + 0.05_wp*r(5:200)         ! ... and a coarse part
        call random_number(q)
        q = 1.4_wp*q - 0.2_wp
        call compare_pools(x, r, 0*r, q, 'levels of buckets = brute force: radii 1e-3 to 1 in one cloud', levels=.true.)
        active = .true.
        call sort_levels(x, active, r, 0*r, lev)
        ! one grid for all would scan 1.0 (the largest radius) around every
        ! point; the fine level scans what its own nodes and the cell cap need
        call check(lev%n >= 2 .and. lev%lv(1)%base + lev%lv(1)%dmax < 0.2_wp, &
                   'levels: the fine level''s scan is not widened by the huge radii', &
                   'levels '//itoa(lev%n)//' fine scan radius '//ftoa(lev%lv(1)%base + lev%lv(1)%dmax))
        call check(abs(typical_length([5.0_wp, 1.0_wp, 4.0_wp, 2.0_wp, 3.0_wp], 0.5_wp) - 3.0_wp) < 1.0e-12_wp, &
                   'typical_length: the median of 5 values')
    end subroutine mixed_cloud

    !> Each node and each query point with its own margin (0 to 0.02 on
    !> radii 0.005 to 0.03): the pools of one grid and of the levels equal
    !> brute force with the radius r_m + max(dq, dl_m).
    subroutine margins_cloud()
        integer, parameter :: n = 3000, nq = 300
        real(wp), allocatable :: x(:, :), r(:), dl(:), q(:, :), dq(:)
        integer :: k
        allocate (x(3, n), r(n), dl(n), q(3, nq), dq(nq))
        call random_seed(put=[(523 + k, k=1, 64)])
        call random_number(x)
        call random_number(r)
        r = 0.005_wp + 0.025_wp*r
        call random_number(dl)
        dl = 0.02_wp*dl
        call random_number(q)
        q = 1.4_wp*q - 0.2_wp
        call random_number(dq)
        dq = 0.02_wp*dq
        call compare_pools(x, r, dl, q, 'bucket search = brute force: own margins of nodes and queries (one grid)', &
                           dq=dq)
        call compare_pools(x, r, dl, q, 'bucket search = brute force: own margins of nodes and queries (levels)', &
                           levels=.true., dq=dq)
    end subroutine margins_cloud

    !> A fine patch (radii about 0.003, 10% of the nodes) in a coarse cloud
    !> (radii about 0.03): the levels keep the patch's nodes apart, in a
    !> level no wider than twice their own largest radius, so a fine
    !> query's scan is not that of the coarse buckets. (The median rule of
    !> before put every node in one level here.)
    subroutine fine_patch_levels()
        integer, parameter :: n = 6000, nf = 600
        real(wp), allocatable :: x(:, :), r(:), q(:, :)
        type(levels_t) :: lev
        logical, allocatable :: active(:)
        integer :: k, kf
        real(wp) :: rf
        allocate (x(3, n), r(n), q(3, 200), active(n))
        call random_seed(put=[(733 + k, k=1, 64)])
        call random_number(x)
        call random_number(r)
        r = 0.025_wp + 0.01_wp*r
        x(:, 1:nf) = 0.45_wp + 0.1_wp*x(:, 1:nf)
        r(1:nf) = 0.0025_wp + 0.001_wp*r(1:nf)/0.01_wp
        call random_number(q)
        q = 0.42_wp + 0.16_wp*q
        call compare_pools(x, r, 0*r, q, 'levels of buckets = brute force: a fine patch in a coarse cloud', &
                           levels=.true.)
        active = .true.
        call sort_levels(x, active, r, 0*r, lev)
        rf = maxval(r(1:nf))
        kf = 0
        do k = 1, lev%n
            if (any(lev%lv(k)%item <= nf)) kf = k
        end do
        call check(kf > 0 .and. lev%n >= 2, 'levels: a fine patch and a coarse majority are two levels or more', &
                   'levels '//itoa(lev%n))
        if (kf > 0) call check(all(lev%lv(kf)%item <= nf) .and. lev%lv(kf)%base + lev%lv(kf)%dmax <= 2*rf, &
                               'levels: the fine patch''s level holds no coarse node, its radius within 2x its own', &
                               'radius '//ftoa(lev%lv(kf)%base + lev%lv(kf)%dmax)//' fine '//ftoa(rf))
    end subroutine fine_patch_levels

    !> The search's bound with margins that follow the local size: a 1 mm
    !> patch (20 x 20 shells) 2 mm above a 10 mm plate (40 x 40 shells),
    !> 1 mm thick, margins pool_margins(0.25). Each node then moves by
    !> u_i = delta_min,i / 4 in a random direction (the most the adaptive
    !> search allows). Every segment that the slave can now be within
    !> reach t_c of (sampled distance) has all its nodes in the slave's pool
    !> from the search. Also: the patch's margins are its own (0.25 x its
    !> L), not the plate's. (Pools of radius L_m + t_c + delta_m alone, the
    !> slave's margin left out, fail here at coarse slaves.)
    subroutine local_margin_bound()
        type(surface_t) :: s
        type(master_lists_t) :: l
        type(search_counts_t) :: cnt
        real(wp), allocatable :: xl(:, :), lc(:), dl(:), dlmin(:), xn(:, :), rnd(:, :)
        integer :: i, nraised, nnear, nbad, nnc
        real(wp) :: typ, dir(3)
        call patch_on_plate(s, xl, nnc)
        allocate (lc(s%nnode), xn(3, s%nnode), rnd(3, s%nnode))
        call characteristic_lengths(s, xl, lc)
        typ = 0.25_wp*typical_length(pack(lc, lc > 0.0_wp), 0.5_wp)
        call pool_margins(s, lc, 0.25_wp, typ, dl, dlmin, nraised)
        call build_master_lists(s, xl, lc, s%max_thick, dl, mnl_minimal, l, cnt)
        call check(abs(minval(dl) - 0.25_wp*sqrt(2.0_wp)*0.001_wp) < 1.0e-9_wp .and. &
                   abs(maxval(dl) - 0.25_wp*sqrt(2.0_wp)*0.01_wp) < 1.0e-9_wp .and. nraised == 0, &
                   'pool margins: 0.25 x the local L, 1 mm patch and 10 mm plate each their own', &
                   'min '//ftoa(minval(dl))//' max '//ftoa(maxval(dl)))
        call random_seed(put=[(199 + i, i=1, 64)])
        call random_number(rnd)
        do i = 1, s%nnode
            dir = rnd(:, i) - 0.5_wp
            dir = dir/max(norm2(dir), 1.0e-12_wp)
            xn(:, i) = xl(:, i) + 0.25_wp*dlmin(i)*dir
        end do
        call count_misses(s, l, xn, nnear, nbad)
        call check(nbad == 0 .and. nnear > 500, 'local margins: every segment within reach after the largest '// &
                   'motion the search allows has its nodes in the slave''s pool', &
                   'segments within reach '//itoa(nnear)//', missed '//itoa(nbad))
    end subroutine local_margin_bound

    !> The searches by margin class (xd_contact_contact): the 1 mm patch 2
    !> mm above the 10 mm plate of local_margin_bound, all searched at t0.
    !> Then every node moves 0.9 of max(Delta_coarse, delta_min,i) / 4
    !> (the coarse class's budget, not due; the patch's class is) and the
    !> patch's class alone is searched; then each node moves again, by as
    !> much as both classes' budgets still allow. Every slave, with the
    !> lists of its own last search (the plate's from t0), has every segment
    !> now within reach in its pool; without the patch's search some patch
    !> slave misses one (the test can fail).
    subroutine class_search_bound()
        type(surface_t) :: s
        type(master_lists_t) :: l, l0
        type(search_counts_t) :: cnt
        real(wp), allocatable :: xl(:, :), lc(:), dl(:), dlmin(:), x1(:, :), x2(:, :), rnd(:, :), cmin(:)
        integer, allocatable :: cls(:)
        integer :: i, nnc, nraised, fine, coarse, nnear, nbad, nbad0
        real(wp) :: typ, dir(3), b1, bf, bc
        call patch_on_plate(s, xl, nnc)
        allocate (lc(s%nnode), x1(3, s%nnode), x2(3, s%nnode), rnd(3, s%nnode))
        call characteristic_lengths(s, xl, lc)
        typ = 0.25_wp*typical_length(pack(lc, lc > 0.0_wp), 0.5_wp)
        call pool_margins(s, lc, 0.25_wp, typ, dl, dlmin, nraised)
        call margin_classes(s, dl, cls, cmin)
        fine = minloc(cmin, 1)
        coarse = maxloc(cmin, 1)
        call check(size(cmin) == 2 .and. all(cls(pack([(i, i=1, s%nslave)], s%node(s%slave) > nnc)) == fine), &
                   'margin classes: the patch''s slaves one class, the plate''s another', 'classes '//itoa(size(cmin)))
        call build_master_lists(s, xl, lc, s%max_thick, dl, mnl_minimal, l, cnt)
        l0 = l
        call random_seed(put=[(421 + i, i=1, 64)])
        call random_number(rnd)
        do i = 1, s%nnode
            dir = rnd(:, i) - 0.5_wp
            dir = dir/max(norm2(dir), 1.0e-12_wp)
            x1(:, i) = xl(:, i) + 0.9_wp*0.25_wp*max(cmin(coarse), dlmin(i))*dir
        end do
        call characteristic_lengths(s, x1, lc)
        call build_master_lists(s, x1, lc, s%max_thick, dl, mnl_minimal, l, cnt, cls == fine, 2)
        call check(cnt%masters > 0 .and. all(l%at(pack([(i, i=1, s%nslave)], cls == coarse)) == 0) .and. &
                   all(l%at(pack([(i, i=1, s%nslave)], cls == fine)) == 2), &
                   'class search: the patch''s slaves searched again, the plate''s keep their lists')
        call random_number(rnd)
        do i = 1, s%nnode
            dir = rnd(:, i) - 0.5_wp
            dir = dir/max(norm2(dir), 1.0e-12_wp)
            b1 = 0.9_wp*0.25_wp*max(cmin(coarse), dlmin(i))
            bf = 0.25_wp*max(cmin(fine), dlmin(i))
            bc = 0.25_wp*max(cmin(coarse), dlmin(i)) - b1
            x2(:, i) = x1(:, i) + min(bf, bc)*dir
        end do
        call count_misses(s, l, x2, nnear, nbad)
        call count_misses(s, l0, x2, nnear, nbad0)
        call check(nbad == 0 .and. nnear > 500, 'class search: every segment within reach is in the pool of '// &
                   'each slave''s own last search', 'segments within reach '//itoa(nnear)//', missed '//itoa(nbad))
        call check(nbad0 > 0, 'class search: without the patch''s search some patch slave misses a segment', &
                   'missed '//itoa(nbad0))
    end subroutine class_search_bound

    !> The lists' per-slave arrays in rows: every other slave "own" (rows
    !> 1 .. n in slave order), searched alone into their rows, against
    !> every slave searched into its own; the whole lists re-laid in the
    !> rows (lists_rows) and back.
    subroutine lists_in_rows()
        type(surface_t) :: s
        type(master_lists_t) :: l, lr, lt
        type(search_counts_t) :: cnt
        real(wp), allocatable :: xl(:, :), lc(:), dl(:), dlmin(:)
        integer, allocatable :: row(:), ident(:)
        logical, allocatable :: own(:)
        integer :: i, k, nnc, nraised, n, nbad, nrow
        real(wp) :: typ
        call patch_on_plate(s, xl, nnc)
        allocate (lc(s%nnode))
        call characteristic_lengths(s, xl, lc)
        typ = 0.25_wp*typical_length(pack(lc, lc > 0.0_wp), 0.5_wp)
        call pool_margins(s, lc, 0.25_wp, typ, dl, dlmin, nraised)
        call build_master_lists(s, xl, lc, s%max_thick, dl, mnl_minimal, l, cnt, stamp=1)
        allocate (row(s%nslave), own(s%nslave), ident(s%nslave))
        n = 0
        do k = 1, s%nslave
            ident(k) = k
            own(k) = mod(k, 2) == 1
            row(k) = 0
            if (.not. own(k)) cycle
            n = n + 1
            row(k) = n
        end do
        nrow = n
        ! (the searched slaves' rows set before their first search)
        call lists_rows(lr, row, nrow)
        call build_master_lists(s, xl, lc, s%max_thick, dl, mnl_minimal, lr, cnt, own, stamp=1)
        call check(size(lr%ptr) == nrow .and. size(lr%gap) == nrow .and. size(lr%xg, 2) == nrow, &
                   'lists in rows: the per-slave arrays hold the rows alone', 'rows '//itoa(size(lr%ptr))//' of '// &
                   itoa(s%nslave)//' slaves')
        nbad = mismatches(lr, l, own)
        call check(nbad == 0, 'lists in rows: a search of the rows'' slaves gives each the list, pool, gap and '// &
                   'stamps of a search of every slave', 'slaves differing '//itoa(nbad))
        ! every slave's lists into the rows and back
        lt = l
        call lists_rows(lt, row, nrow)
        nbad = mismatches(lt, l, own)
        call lists_rows(lt, ident, s%nslave)
        nbad = nbad + mismatches(lt, l, own)
        n = 0
        do k = 1, s%nslave
            if (own(k)) cycle
            i = list_row(lt, k)
            if (lt%last(i) >= lt%ptr(i) .or. lt%pool_last(i) >= lt%pool_ptr(i) - 1 .or. lt%at(i) /= 0) n = n + 1
        end do
        call check(nbad == 0 .and. n == 0 .and. .not. allocated(lt%row) .and. size(lt%node) >= lt%nused, &
                   'lists in rows: every slave''s lists re-laid in the rows and back keep the rows'' slaves'' '// &
                   'lists, the others none', 'slaves differing '//itoa(nbad)//', others with a list '//itoa(n))
    end subroutine lists_in_rows

    !> The slaves of `which` whose list, pool, gap or stamps differ
    !> between a (in its rows) and b.
    integer function mismatches(a, b, which) result(nb)
        type(master_lists_t), intent(in) :: a, b
        logical, intent(in) :: which(:)
        integer :: k, ra, rb
        nb = 0
        do k = 1, size(which)
            if (.not. which(k)) cycle
            ra = list_row(a, k)
            rb = list_row(b, k)
            if (ra == 0) then
                nb = nb + 1
                cycle
            end if
            if (a%last(ra) - a%ptr(ra) /= b%last(rb) - b%ptr(rb) .or. &
                a%pool_last(ra) - a%pool_ptr(ra) /= b%pool_last(rb) - b%pool_ptr(rb)) then
                nb = nb + 1
                cycle
            end if
            if (any(a%node(a%ptr(ra):a%last(ra)) /= b%node(b%ptr(rb):b%last(rb))) .or. &
                any(a%trackable(a%ptr(ra):a%last(ra)) .neqv. b%trackable(b%ptr(rb):b%last(rb))) .or. &
                any(a%pool_node(a%pool_ptr(ra):a%pool_last(ra)) /= b%pool_node(b%pool_ptr(rb):b%pool_last(rb))) .or. &
                a%gap(ra) /= b%gap(rb) .or. any(a%xg(:, ra) /= b%xg(:, rb)) .or. a%og(ra) /= b%og(rb) .or. &
                a%at(ra) /= b%at(rb)) nb = nb + 1
        end do
    end function mismatches

    !> Slave-segment pairs within reach at xn (sampled distance) and
    !> those with a node outside the slave's pool in lists ll.
    subroutine count_misses(s, ll, xn, nnear, nbad)
        type(surface_t), intent(in) :: s
        type(master_lists_t), intent(in) :: ll
        real(wp), intent(in) :: xn(:, :)
        integer, intent(out) :: nnear, nbad
        logical, allocatable :: inpool(:)
        integer :: k, sn, sg, a, b
        real(wp) :: xm(3, 4), p(3), dmin
        allocate (inpool(s%nnode))
        nnear = 0
        nbad = 0
        do k = 1, s%nslave
            sn = s%slave(k)
            inpool = .false.
            inpool(ll%pool_node(ll%pool_ptr(k):ll%pool_last(k))) = .true.
            do sg = 1, s%nseg
                if (any(s%seg(:, sg) == sn)) cycle
                if (any(abs(xn(:, s%seg(1, sg)) - xn(:, sn)) > 0.03_wp)) cycle
                xm = xn(:, s%seg(:, sg))
                dmin = huge(1.0_wp)
                do a = 0, 10
                    do b = 0, 10
                        p = (1 - a/10.0_wp)*(1 - b/10.0_wp)*xm(:, 1) + a/10.0_wp*(1 - b/10.0_wp)*xm(:, 2) + &
                            a/10.0_wp*b/10.0_wp*xm(:, 3) + (1 - a/10.0_wp)*b/10.0_wp*xm(:, 4)
                        dmin = min(dmin, norm2(p - xn(:, sn)))
                    end do
                end do
                if (dmin > s%max_thick) cycle
                nnear = nnear + 1
                if (.not. all(inpool(s%seg(:, sg)))) nbad = nbad + 1
            end do
        end do
    end subroutine count_misses

    !> A 1 mm patch (20 x 20 shells) 2 mm above a 10 mm plate (40 x 40
    !> shells), 1 mm thick, one single surface: s, its coordinates xl, and
    !> nnc, the plate's nodes (numbered first).
    subroutine patch_on_plate(s, xl, nnc)
        type(surface_t), intent(out) :: s
        real(wp), allocatable, intent(out) :: xl(:, :)
        integer, intent(out) :: nnc
        integer, parameter :: nc = 40, nf = 20
        type(model_t) :: m
        type(faces_t) :: f
        real(wp), allocatable :: x(:, :)
        integer, allocatable :: conn(:, :)
        integer :: i, j
        nnc = (nc + 1)**2
        allocate (x(3, nnc + (nf + 1)**2), conn(4, nc*nc + nf*nf))
        do j = 0, nc
            do i = 0, nc
                x(:, 1 + i + (nc + 1)*j) = [0.01_wp*i, 0.01_wp*j, 0.0_wp]
            end do
        end do
        do j = 0, nf
            do i = 0, nf
                x(:, nnc + 1 + i + (nf + 1)*j) = [0.195_wp + 0.001_wp*i, 0.195_wp + 0.001_wp*j, 0.002_wp]
            end do
        end do
        conn(:, 1:nc*nc) = grid_quads(nc)
        conn(:, nc*nc + 1:) = nnc + grid_quads(nf)
        call empty_model(m, 1)
        call set_sheet(m, x, conn, 0.001_wp, 1)
        call build_faces(m, m%x0, f)
        call build_surface(f, m%nnode, [(.true., i=1, f%n)], [(.false., i=1, f%n)], [integer ::], .false., &
                           [0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp], [0.1_wp, 1.0_wp, 1.0_wp], s)
        xl = m%x0(:, s%node)
    end subroutine patch_on_plate

    !> The clearance of each slave of the surface s (coordinates xl) against a
    !> sampled distance to every segment it can reach before the next
    !> search: gap <= distance - reach of the segment's check, for every
    !> segment within half the margin of touching. True on a sampled
    !> distance (an upper bound of the true one) if true at all.
    subroutine check_clearances(s, xl, l, margin, name)
        type(surface_t), intent(in) :: s
        real(wp), intent(in) :: xl(:, :), margin
        type(master_lists_t), intent(in) :: l
        character(len=*), intent(in) :: name
        integer :: i, sn, m, a, b, nbad, npos, want
        real(wp) :: ts, c, dmin, p(3), xm(3, 4), u, v
        nbad = 0
        npos = 0
        do i = 1, s%nslave
            sn = s%slave(i)
            want = wanted_side(s, sn)
            ts = 0.5_wp*s%node_t(sn)
            if (l%gap(i) > 0.0_wp) npos = npos + 1
            do m = 1, s%nseg
                ! (first a scalar reject: a segment (under 0.05 across) whose
                ! first node lies 0.1 off along x has every node beyond 0.05;
                ! the same pairs skipped as by the test below, sooner)
                if (abs(xl(1, s%seg(1, m)) - xl(1, sn)) > 0.1_wp) cycle
                if (any(s%seg(:, m) == sn) .or. iand(s%seg_side(m), want) == 0) cycle
                xm = xl(:, s%seg(:, m))
                if (minval(norm2(xm - spread(xl(:, sn), 2, 4), 1)) > 0.05_wp) cycle    ! far: no need to sample
                c = ts + 0.5_wp*maxval(s%seg_tn(:, m))
                ! (no point of the segment is nearer than its nearest node
                ! less its diameter: beyond reach so, no need to sample)
                if (minval(norm2(xm - spread(xl(:, sn), 2, 4), 1)) - diameter(xm) - c > 0.5_wp*margin) cycle
                dmin = huge(1.0_wp)
                do a = 0, 20
                    do b = 0, 20
                        u = a/20.0_wp
                        v = b/20.0_wp
                        p = (1 - u)*(1 - v)*xm(:, 1) + u*(1 - v)*xm(:, 2) + u*v*xm(:, 3) + (1 - u)*v*xm(:, 4)
                        dmin = min(dmin, norm2(p - xl(:, sn)))
                    end do
                end do
                if (dmin - c > 0.5_wp*margin) cycle
                if (l%gap(i) > max(dmin - c, 0.0_wp) + 1.0e-9_wp) nbad = nbad + 1   ! (not positive: no clearance)
            end do
        end do
        call check(nbad == 0, 'clearance: a lower bound of the distance to every reachable segment: '//name, &
                   'violations '//itoa(nbad))
        call check(npos > s%nslave/4, 'clearance: positive for more than a quarter of the slaves: '//name, &
                   itoa(npos)//' of '//itoa(s%nslave))
    end subroutine check_clearances

    !> A 100 x 100 sheet of shells (1e4 nodes) crumpled by folds in two
    !> directions, pool radius L_m + margin as the global search uses it.
    subroutine crumpled_sheet()
        type(model_t) :: m
        type(faces_t) :: f
        type(surface_t) :: s
        type(master_lists_t) :: l1, l2
        type(search_counts_t) :: cnt
        real(wp), allocatable :: lc(:), r(:), xl(:, :)
        integer, parameter :: n = 99
        integer :: i, j
        real(wp), allocatable :: x(:, :)
        integer, allocatable :: conn(:, :)
        call empty_model(m, 1)
        allocate (x(3, (n + 1)**2), conn(4, n*n))
        do j = 0, n
            do i = 0, n
                x(:, 1 + i + (n + 1)*j) = crumple(real(i, wp)/n, real(j, wp)/n)
            end do
        end do
        conn = grid_quads(n)
        call set_sheet(m, x, conn, 0.001_wp, 1)
        call build_faces(m, m%x0, f)
        call build_surface(f, m%nnode, [(.true., i=1, f%n)], [(.false., i=1, f%n)], [integer ::], .false., &
                           [0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp], [0.1_wp, 1.0_wp, 1.0_wp], s)
        allocate (xl(3, s%nnode), lc(s%nnode), r(s%nnode))
        xl = m%x0(:, s%node)
        call characteristic_lengths(s, xl, lc)
        r = lc + 0.003_wp
        call check(s%nnode == 10000, 'crumpled sheet has 1e4 surface nodes')
        call compare_pools(xl, r, 0*r, xl, 'bucket search = brute force: crumpled sheet of 1e4 nodes')
        ! thread count does not change the lists (blocks of slaves, fixed order)
        !$ call omp_set_num_threads(1)
        call build_master_lists(s, xl, lc, 0.001_wp, spread(0.002_wp, 1, s%nnode), mnl_minimal, l1, cnt)
        !$ call omp_set_num_threads(2)
        call build_master_lists(s, xl, lc, 0.001_wp, spread(0.002_wp, 1, s%nnode), mnl_minimal, l2, cnt)
        call check(all(l1%ptr == l2%ptr) .and. all(l1%last == l2%last) .and. l1%nused == l2%nused .and. &
                   all(l1%node(1:l1%nused) == l2%node(1:l1%nused)) .and. &
                   all(l1%trackable(1:l1%nused) .eqv. l2%trackable(1:l1%nused)), &
                   'master node lists: identical with 1 and 2 threads')
        call check(cnt%masters > 0 .and. cnt%masters <= cnt%reduced .and. cnt%reduced <= cnt%pool, &
                   'master node lists: masters <= reduced pool <= pool')
        call check_clearances(s, xl, l1, 0.002_wp, 'crumpled sheet of 1e4 nodes')
        call check_fresh_clearances(s, xl, lc, l1, 0.002_wp)
    end subroutine crumpled_sheet

    !> The local search's fresh clearance (fresh_clearance, over the pools of
    !> the search lists l taken at xl) after the sheet has moved by a smooth
    !> field of up to u = 0.2 mm: a lower bound of the sampled distance, less
    !> the reach, to every segment that the search's bound still covers
    !> (within half the margin less 2u of touching), at the new positions;
    !> positive for many slaves. (Loosened by 1 mm, the bound fails here.)
    subroutine check_fresh_clearances(s, xl, lc, l, margin)
        type(surface_t), intent(in) :: s
        real(wp), intent(in) :: xl(:, :), lc(:), margin
        type(master_lists_t), intent(in) :: l
        type(local_search_t) :: ls
        real(wp), parameter :: u = 2.0e-4_wp
        integer :: i, sn, m, a, b, nbad, npos, want, nn, nwith, nnbad
        integer :: near(max_near)
        real(wp) :: ts, c, dmin, p(3), xm(3, 4), uu, vv, g
        ls%xl = xl
        do i = 1, size(xl, 2)
            ! a smooth motion of at most u (each component u / sqrt(3))
            ls%xl(:, i) = xl(:, i) + u/sqrt(3.0_wp)*[sin(40*xl(2, i)), cos(30*xl(1, i)), sin(50*xl(3, i) + 1)]
        end do
        ls%lc = lc
        ls%lcodo = 0*lc
        ls%odo = u
        ! (a lead of 1e-5: the near sets take the segments within 16 leads)
        ls%lead = 1.0e-5_wp
        nbad = 0
        npos = 0
        nwith = 0
        nnbad = 0
        do i = 1, s%nslave
            sn = s%slave(i)
            want = wanted_side(s, sn)
            ts = 0.5_wp*s%node_t(sn)
            g = fresh_clearance(s, l, ls, i, near, nn)
            if (g > 0.0_wp) npos = npos + 1
            if (nn > 0) nwith = nwith + 1
            ! a near set only with a bound (above twice the lead), of the
            ! slave's pool's segments, its own and those facing away left out
            if (nn > 0 .and. g <= 2*ls%lead) nnbad = nnbad + 1
            do a = 1, nn
                if (any(s%seg(:, near(a)) == sn) .or. iand(s%seg_side(near(a)), want) == 0) nnbad = nnbad + 1
            end do
            do m = 1, s%nseg
                ! (the scalar reject of check_clearances first)
                if (abs(ls%xl(1, s%seg(1, m)) - ls%xl(1, sn)) > 0.1_wp) cycle
                if (any(s%seg(:, m) == sn) .or. iand(s%seg_side(m), want) == 0) cycle
                ! (the bound is that of the segments outside the near set)
                if (any(near(1:nn) == m)) cycle
                xm = ls%xl(:, s%seg(:, m))
                if (minval(norm2(xm - spread(ls%xl(:, sn), 2, 4), 1)) > 0.05_wp) cycle    ! far: no need to sample
                c = ts + 0.5_wp*maxval(s%seg_tn(:, m))
                ! (beyond reach by the nearest node less the diameter)
                if (minval(norm2(xm - spread(ls%xl(:, sn), 2, 4), 1)) - diameter(xm) - c > 0.5_wp*margin - 2*u) cycle
                dmin = huge(1.0_wp)
                do a = 0, 20
                    do b = 0, 20
                        uu = a/20.0_wp
                        vv = b/20.0_wp
                        p = (1 - uu)*(1 - vv)*xm(:, 1) + uu*(1 - vv)*xm(:, 2) + uu*vv*xm(:, 3) + (1 - uu)*vv*xm(:, 4)
                        dmin = min(dmin, norm2(p - ls%xl(:, sn)))
                    end do
                end do
                if (dmin - c > 0.5_wp*margin - 2*u) cycle
                if (g > max(dmin - c, 0.0_wp) + 1.0e-9_wp) nbad = nbad + 1   ! (not positive: no clearance)
            end do
        end do
        call check(nbad == 0, 'fresh clearance after a motion of 0.2 mm: a lower bound of the distance to every '// &
                   'segment the search covers', 'violations '//itoa(nbad))
        call check(npos > s%nslave/4, 'fresh clearance: positive for more than a quarter of the slaves', &
                   itoa(npos)//' of '//itoa(s%nslave))
        ! the crumpled sheet's layers lie close: some slaves keep a bound
        ! only by leaving their nearest segments to the near set
        call check(nwith > 0 .and. nnbad == 0, 'fresh clearance: near sets taken (of segments the slave may meet, '// &
                   'with a bound above twice the lead)', itoa(nwith)//' slaves with one, '//itoa(nnbad)//' wrong')
    end subroutine check_fresh_clearances

    !> A sheet folded over itself twice across its length, so that layers
    !> lie close above each other: the pool meets the sheet's own far parts.
    pure function crumple(u, v) result(p)
        real(wp), intent(in) :: u, v
        real(wp) :: p(3), a
        a = 3.0_wp*acos(-1.0_wp)*u
        p = [0.15_wp*sin(a) + 0.01_wp*sin(17*v), v, 0.05_wp*cos(a)*(1 + 0.3_wp*sin(7*v)) + 0.1_wp*u]
    end function crumple

    !> The configuration of the paper's Fig. 4 in 3-D, strips one segment
    !> wide (nodes at y = 0 and 1), unit segments: a strip folded into a U
    !> (bottom z = 0 and top z = 1, x = 0..3, joined by a wall at x = 3)
    !> and a separate plate at z = -1. Node numbers: bottom 1 + x + 4y,
    !> top 9 + x + 4y, plate 17 + x + 4y. Slave: node 1 at the origin.
    !> Pool radius L + 1.1 = 2.51. Walk-through (ties by node number):
    !> top node 9 (d 1) unmarked: trackable master, its neighbours marked
    !> trackable; plate node 17 (d 1) likewise; nodes 10, 13, 18, 21 (d 1.41)
    !> and 14, 22 (d 1.73) marked trackable: not stored; bottom node 3 (d 2)
    !> nontrackable by step A (it shares a segment with the slave's neighbour
    !> 2): stored as nontrackable; 7 (d 2.24) the same; 11, 19, 15, 23
    !> trackable: not stored. Nodes 2, 5, 6 share a segment with the slave:
    !> not in the reduced pool. List: 9 T, 17 T, 3 N, 7 N.
    subroutine figure4()
        type(model_t) :: m
        type(faces_t) :: f
        type(surface_t) :: s
        type(master_lists_t) :: l
        type(search_counts_t) :: cnt
        real(wp), allocatable :: lc(:), xl(:, :)
        integer :: x, y, sl
        integer, allocatable :: got(:)
        call empty_model(m, 2)
        do y = 0, 1
            do x = 0, 3
                call assert_id(node_at(m, [real(x, wp), real(y, wp), 0.0_wp], .false.), 1 + x + 4*y)
            end do
        end do
        do y = 0, 1
            do x = 0, 3
                call assert_id(node_at(m, [real(x, wp), real(y, wp), 1.0_wp], .false.), 9 + x + 4*y)
            end do
        end do
        do y = 0, 1
            do x = 0, 3
                call assert_id(node_at(m, [real(x, wp), real(y, wp), -1.0_wp], .false.), 17 + x + 4*y)
            end do
        end do
        do x = 0, 2
            call add_shell(m, [1 + x, 2 + x, 6 + x, 5 + x], 0.001_wp, 1)
            call add_shell(m, [9 + x, 10 + x, 14 + x, 13 + x], 0.001_wp, 1)
            call add_shell(m, [17 + x, 18 + x, 22 + x, 21 + x], 0.001_wp, 2)
        end do
        call add_shell(m, [4, 12, 16, 8], 0.001_wp, 1)     ! the wall of the U
        call build_faces(m, m%x0, f)
        call check(f%nbody == 2, 'Fig. 4: the U and the plate are two bodies')
        call build_surface(f, m%nnode, [(.true., x=1, f%n)], [(.false., x=1, f%n)], [integer ::], .false., &
                           [0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp], [0.1_wp, 1.0_wp, 1.0_wp], s)
        allocate (xl(3, s%nnode), lc(s%nnode))
        xl = m%x0(:, s%node)
        call characteristic_lengths(s, xl, lc)
        sl = findloc(s%node(s%slave), 1, 1)

        call build_master_lists(s, xl, lc, 0.0_wp, spread(1.1_wp, 1, s%nnode), mnl_minimal, l, cnt)
        got = s%node(l%node(l%ptr(sl):l%last(sl)))
        call check(size(got) == 4, 'Fig. 4: four master nodes', 'got '//list(got))
        if (size(got) == 4) then
            call check(all(got == [9, 17, 3, 7]), 'Fig. 4: master nodes 9, 17, 3, 7 in order of distance', list(got))
            call check(all(l%trackable(l%ptr(sl):l%last(sl)) .eqv. [.true., .true., .false., .false.]), &
                       'Fig. 4: 9 and 17 trackable (closest on each opposite region), 3 and 7 nontrackable')
        end if
        call build_master_lists(s, xl, lc, 0.0_wp, spread(1.1_wp, 1, s%nnode), mnl_closest1, l, cnt)
        got = s%node(l%node(l%ptr(sl):l%last(sl)))
        call check(size(got) == 1, 'closest-1: one master node', list(got))
        if (size(got) == 1) call check(got(1) == 9, 'closest-1: node 9', list(got))
        call build_master_lists(s, xl, lc, 0.0_wp, spread(1.1_wp, 1, s%nnode), mnl_closest3, l, cnt)
        got = s%node(l%node(l%ptr(sl):l%last(sl)))
        call check(size(got) == 3, 'closest-3: three master nodes', list(got))
        if (size(got) == 3) call check(all(got == [9, 17, 10]), 'closest-3: nodes 9, 17, 10', list(got))
    end subroutine figure4

    !> The paper's own Fig. 4 walk-through (section 4, step C), m1..m8 as
    !> the text describes them, in the x-z plane, strips of width 0.1 in y
    !> (each node has a twin at y = 0.1). Slave s at the origin on body S:
    !> ... m6 - m1 - a - s - b - m5 ...; opposite region P: m2 - m8;
    !> opposite region Q: m7 - m3 - m4. Distances 0.58, 0.70, 1.12, 1.29,
    !> 1.40, 1.57, 1.86, 1.92 (m1..m8). Long tails to far nodes set the
    !> characteristic lengths so that every m is in the reduced pool.
    !> Expected (the paper): m1 nontrackable from step A, stored, and its
    !> neighbour m6 marked nontrackable (step C3, the propagation); m2
    !> unmarked: trackable, m8 marked trackable; m3 unmarked: trackable, m4
    !> and m7 marked trackable; m4 trackable: not stored; m5 nontrackable
    !> from step A: stored; m6 nontrackable (from m1): stored; m7, m8: not
    !> stored. Final list: m1 N, m2 T, m3 T, m5 N, m6 N (and the twins of
    !> the nontrackable ones, N).
    subroutine figure4_paper()
        type(model_t) :: m
        type(faces_t) :: f
        type(surface_t) :: s
        type(master_lists_t) :: l
        type(search_counts_t) :: cnt
        real(wp), allocatable :: lc(:), xl(:, :)
        real(wp), parameter :: w = 0.1_wp
        ! polyline nodes (x, z): S = T6 m6 m1 a s b m5 T5; P = T8 m8 m2; Q = T7 m7 m3 m4 T4
        real(wp), parameter :: ps(2, 8) = reshape([-0.6_wp, 4.5_wp, -0.6_wp, 1.45_wp, -0.3_wp, 0.5_wp, -0.3_wp, 0.0_wp, &
                                                   0.0_wp, 0.0_wp, 0.4_wp, 0.0_wp, 1.4_wp, 0.0_wp, 1.4_wp, -3.2_wp], [2, 8])
        real(wp), parameter :: pp(2, 3) = reshape([-4.7_wp, -0.9_wp, -1.7_wp, -0.9_wp, 0.0_wp, -0.7_wp], [2, 3])
        real(wp), parameter :: pq(2, 5) = reshape([0.85_wp, 5.0_wp, 0.85_wp, 1.65_wp, 1.0_wp, 0.5_wp, 1.25_wp, 0.3_wp, &
                                                   4.5_wp, 0.3_wp], [2, 5])
        integer :: is(8), ip(3), iq(5), js(8), jp(3), jq(5), sl, k
        integer, allocatable :: got(:), want(:)
        logical, allocatable :: trk(:)
        call empty_model(m, 3)
        call strip(m, ps, w, 1, is, js)
        call strip(m, pp, w, 2, ip, jp)
        call strip(m, pq, w, 3, iq, jq)
        call build_faces(m, m%x0, f)
        call check(f%nbody == 3, 'Fig. 4 (paper): the slave''s body and two opposite regions are three bodies')
        call build_surface(f, m%nnode, [(.true., k=1, f%n)], [(.false., k=1, f%n)], [integer ::], .false., &
                           [0.0_wp, 0.0_wp, 1.0_wp, 1.0_wp], [0.1_wp, 1.0_wp, 1.0_wp], s)
        allocate (xl(3, s%nnode), lc(s%nnode))
        xl = m%x0(:, s%node)
        call characteristic_lengths(s, xl, lc)
        sl = findloc(s%node(s%slave), is(5), 1)
        call build_master_lists(s, xl, lc, 0.0_wp, spread(0.05_wp, 1, s%nnode), mnl_minimal, l, cnt)
        got = s%node(l%node(l%ptr(sl):l%last(sl)))
        trk = l%trackable(l%ptr(sl):l%last(sl))
        ! m1, m1', m2, m3, m5, m5', m6, m6' in order of distance
        want = [is(3), js(3), ip(3), iq(3), is(7), js(7), is(2), js(2)]
        call check(size(got) == size(want), 'Fig. 4 (paper): eight master nodes (m1, m2, m3, m5, m6 and the twins '// &
                   'of m1, m5, m6)', 'got'//list(got)//' want'//list(want))
        if (size(got) == size(want)) then
            call check(all(got == want), 'Fig. 4 (paper): the list is m1, m2, m3, m5, m6 in order of distance', &
                       'got'//list(got)//' want'//list(want))
            call check(all(trk .eqv. [.false., .false., .true., .true., .false., .false., .false., .false.]), &
                       'Fig. 4 (paper): m2 and m3 trackable, m1, m5 and m6 nontrackable')
        end if
        call check(.not. any(got == iq(4)) .and. .not. any(got == iq(2)) .and. .not. any(got == ip(2)), &
                   'Fig. 4 (paper): m4, m7, m8 marked trackable by a closer node of their region: not stored')
        call check(any(got == is(2)), 'Fig. 4 (paper): m6 stored as nontrackable through m1 (step C3 propagation)')
    end subroutine figure4_paper

    !> Shells along polyline p (x, z) with width w in y, part pid; the
    !> node indices at y = 0 (i0) and y = w (i1).
    subroutine strip(m, p, w, pid, i0, i1)
        type(model_t), intent(inout) :: m
        real(wp), intent(in) :: p(:, :), w
        integer, intent(in) :: pid
        integer, intent(out) :: i0(:), i1(:)
        integer :: q
        do q = 1, size(p, 2)
            i0(q) = node_at(m, [p(1, q), 0.0_wp, p(2, q)], .false.)
            i1(q) = node_at(m, [p(1, q), w, p(2, q)], .false.)
        end do
        do q = 1, size(p, 2) - 1
            call add_shell(m, [i0(q), i0(q + 1), i1(q + 1), i1(q)], 0.001_wp, pid)
        end do
    end subroutine strip

    subroutine assert_id(got, want)
        integer, intent(in) :: got, want
        if (got /= want) error stop 'figure4: node numbering'
    end subroutine assert_id

    function list(a) result(t)
        integer, intent(in) :: a(:)
        character(len=:), allocatable :: t
        integer :: i
        t = ''
        do i = 1, size(a)
            t = t//' '//itoa(a(i))
        end do
    end function list

    function itoa(i) result(t)
        integer, intent(in) :: i
        character(len=:), allocatable :: t
        character(len=16) :: b
        write (b, '(i0)') i
        t = trim(b)
    end function itoa

    !> The largest distance between two of a segment's nodes.
    pure real(wp) function diameter(xm) result(d)
        real(wp), intent(in) :: xm(3, 4)
        integer :: i, j
        d = 0
        do i = 1, 3
            do j = i + 1, 4
                d = max(d, norm2(xm(:, i) - xm(:, j)))
            end do
        end do
    end function diameter

end program test_contact_global_search
