!> The MPI operations the solver uses, on MPI_COMM_WORLD, called by every
!> rank at the same point (outside OpenMP regions). Sums that must be exact
!> are sums where every entry has one contributing rank and the others give
!> zero (x + 0 = x), so their result does not depend on the order MPI
!> chooses: this is how the ranks share what their own elements and slave
!> nodes computed and still reproduce the serial run bit for bit. A run
!> started without a launcher does not start MPI (xd_core_parallel_env):
!> it is one rank, and each operation is then that of one rank.
module xd_core_comm
    use mpi_f08, only: MPI_Initialized, MPI_Allreduce, MPI_Allgather, MPI_Allgatherv, MPI_IN_PLACE, MPI_SUM, MPI_MAX, &
                       MPI_COMM_WORLD, MPI_DOUBLE_PRECISION, MPI_REAL, MPI_INTEGER, MPI_INTEGER8, MPI_Datatype, MPI_Request, &
                       MPI_Irecv, MPI_Isend, MPI_Waitall, MPI_STATUSES_IGNORE, MPI_Comm_size, MPI_Gatherv, MPI_MIN, MPI_CHARACTER, &
                       MPI_Alltoall, MPI_Alltoallv, MPI_Comm_rank, MPI_Bcast
    use xd_core_sorting, only: sort_index
    use xd_kinds, only: wp, dp, i8
    implicit none
    private
    public :: comm_gather_wp, comm_gather_root_wp, comm_gather_root_dp, &
              comm_sum_wp, comm_sum_int, comm_sum_i8, comm_sum_dp, comm_max, comm_min_int, comm_gather_text, &
              comm_gather_small, &
              comm_gather_records, comm_neighbours, comm_ordered_records, comm_send_records, comm_rank_size, &
              comm_bcast_text

contains

    !> MPI was started (else this process is the one rank).
    logical function up()
        call MPI_Initialized(up)
    end function up

    !> This process's rank (from 0) and the number of ranks (0 and 1 where
    !> MPI was not started).
    subroutine comm_rank_size(rank, nranks)
        integer, intent(out) :: rank, nranks
        rank = 0
        nranks = 1
        if (.not. up()) return
        call MPI_Comm_rank(MPI_COMM_WORLD, rank)
        call MPI_Comm_size(MPI_COMM_WORLD, nranks)
    end subroutine comm_rank_size

    type(MPI_Datatype) function wp_type()
#ifdef XD_SINGLE
        wp_type = MPI_REAL
#else
        wp_type = MPI_DOUBLE_PRECISION
#endif
    end function wp_type

    !> In-place sums over the ranks of a(1:n).
    subroutine comm_sum_wp(a, n)
        integer, intent(in) :: n
        real(wp), intent(inout) :: a(*)
        if (n > 0 .and. up()) call MPI_Allreduce(MPI_IN_PLACE, a(1:n), n, wp_type(), MPI_SUM, MPI_COMM_WORLD)
    end subroutine comm_sum_wp


    subroutine comm_sum_int(a, n)
        integer, intent(in) :: n
        integer, intent(inout) :: a(*)
        if (n > 0 .and. up()) call MPI_Allreduce(MPI_IN_PLACE, a(1:n), n, MPI_INTEGER, MPI_SUM, MPI_COMM_WORLD)
    end subroutine comm_sum_int

    !> In-place sums over the ranks of 64-bit integers: exact, so the same
    !> in any order (fixed-point sums that must not depend on the ranks).
    subroutine comm_sum_i8(a)
        integer(i8), contiguous, intent(inout) :: a(:)
        if (up()) call MPI_Allreduce(MPI_IN_PLACE, a, size(a), MPI_INTEGER8, MPI_SUM, MPI_COMM_WORLD)
    end subroutine comm_sum_i8

    !> all = every rank's `mine`, rank after rank (rank r - 1 gives cnt(r)
    !> values at offset disp(r)).
    subroutine comm_gather_wp(mine, n, all, cnt, disp)
        integer, intent(in) :: n, cnt(:), disp(:)
        real(wp), intent(in) :: mine(*)
        real(wp), intent(inout) :: all(*)
        if (.not. up()) then
            all(disp(1) + 1:disp(1) + n) = mine(1:n)
            return
        end if
        call MPI_Allgatherv(mine(1:max(n, 1)), n, wp_type(), all(1:sum(cnt)), cnt, disp, wp_type(), MPI_COMM_WORLD)
    end subroutine comm_gather_wp

    !> On rank 0 alone: all = every rank's `mine` (n values), rank after
    !> rank (rank r - 1's cnt(r) values at offset disp(r)); the other ranks'
    !> `all` is not read or written (it may be of size 1).
    subroutine comm_gather_root_wp(mine, n, all, cnt, disp, root)
        integer, intent(in) :: n, cnt(:), disp(:)
        real(wp), intent(in) :: mine(*)
        real(wp), intent(inout) :: all(*)
        logical, intent(in) :: root     !< this is rank 0
        integer :: na
        if (.not. up()) then
            all(disp(1) + 1:disp(1) + n) = mine(1:n)
            return
        end if
        na = 1
        if (root) na = max(sum(cnt), 1)
        call MPI_Gatherv(mine(1:max(n, 1)), n, wp_type(), all(1:na), cnt, disp, wp_type(), 0, MPI_COMM_WORLD)
    end subroutine comm_gather_root_wp

    !> comm_gather_root_wp in double precision (values held so whatever
    !> the build's working precision: the elements' energies).
    subroutine comm_gather_root_dp(mine, n, all, cnt, disp, root)
        integer, intent(in) :: n, cnt(:), disp(:)
        real(dp), intent(in) :: mine(*)
        real(dp), intent(inout) :: all(*)
        logical, intent(in) :: root     !< this is rank 0
        integer :: na
        if (.not. up()) then
            all(disp(1) + 1:disp(1) + n) = mine(1:n)
            return
        end if
        na = 1
        if (root) na = max(sum(cnt), 1)
        call MPI_Gatherv(mine(1:max(n, 1)), n, MPI_DOUBLE_PRECISION, all(1:na), cnt, disp, MPI_DOUBLE_PRECISION, 0, &
                         MPI_COMM_WORLD)
    end subroutine comm_gather_root_dp

    !> In-place sum over the ranks of a(:) in double precision.
    subroutine comm_sum_dp(a)
        real(dp), contiguous, intent(inout) :: a(:)
        if (up()) call MPI_Allreduce(MPI_IN_PLACE, a, size(a), MPI_DOUBLE_PRECISION, MPI_SUM, MPI_COMM_WORLD)
    end subroutine comm_sum_dp

    !> In-place maximum over the ranks of a(:).
    subroutine comm_max(a)
        real(dp), contiguous, intent(inout) :: a(:)
        if (up()) call MPI_Allreduce(MPI_IN_PLACE, a, size(a), MPI_DOUBLE_PRECISION, MPI_MAX, MPI_COMM_WORLD)
    end subroutine comm_max

    !> In-place least value over the ranks of a(:).
    subroutine comm_min_int(a)
        integer, contiguous, intent(inout) :: a(:)
        if (up()) call MPI_Allreduce(MPI_IN_PLACE, a, size(a), MPI_INTEGER, MPI_MIN, MPI_COMM_WORLD)
    end subroutine comm_min_int

    !> Rank 0's text on every rank (its length first): what one rank read
    !> for all. Without MPI the text stays as it is.
    subroutine comm_bcast_text(text)
        character(len=:), allocatable, intent(inout) :: text
        integer :: n(1), rank
        if (.not. up()) return
        call MPI_Comm_rank(MPI_COMM_WORLD, rank)
        n = 0
        if (rank == 0) n = len(text)
        call MPI_Bcast(n, 1, MPI_INTEGER, 0, MPI_COMM_WORLD)
        if (rank /= 0) then
            if (allocated(text)) deallocate (text)
            allocate (character(len=n(1)) :: text)
        end if
        if (n(1) > 0) call MPI_Bcast(text, n(1), MPI_CHARACTER, 0, MPI_COMM_WORLD)
    end subroutine comm_bcast_text

    !> Every rank's text, rank after rank, on every rank.
    function comm_gather_text(mine) result(all)
        character(len=*), intent(in) :: mine
        character(len=:), allocatable :: all
        integer :: nranks, r
        integer, allocatable :: cnt(:), disp(:)
        if (.not. up()) then
            all = mine
            return
        end if
        call MPI_Comm_size(MPI_COMM_WORLD, nranks)
        allocate (cnt(nranks), disp(nranks))
        call MPI_Allgather(len(mine), 1, MPI_INTEGER, cnt, 1, MPI_INTEGER, MPI_COMM_WORLD)
        disp(1) = 0
        do r = 2, nranks
            disp(r) = disp(r - 1) + cnt(r - 1)
        end do
        allocate (character(len=sum(cnt)) :: all)
        call MPI_Allgatherv(mine, len(mine), MPI_CHARACTER, all, cnt, disp, MPI_CHARACTER, MPI_COMM_WORLD)
    end function comm_gather_text

    !> all(:, r) = rec from rank r - 1 (a few values per rank).
    subroutine comm_gather_small(rec, all)
        real(dp), contiguous, intent(in) :: rec(:)
        real(dp), contiguous, intent(out) :: all(:, :)
        if (.not. up()) then
            all(:, 1) = rec
            return
        end if
        call MPI_Allgather(rec, size(rec), MPI_DOUBLE_PRECISION, all, size(rec), MPI_DOUBLE_PRECISION, &
                           MPI_COMM_WORLD)
    end subroutine comm_gather_small

    !> Every rank's records (columns of width size(mine, 1)), rank by rank:
    !> all(:, 1:total), allocated here.
    subroutine comm_gather_records(mine, nranks, all)
        real(dp), contiguous, intent(in) :: mine(:, :)
        integer, intent(in) :: nranks
        real(dp), allocatable, intent(out) :: all(:, :)
        integer :: cnt(nranks), disp(nranks), r, w, n
        w = size(mine, 1)
        n = w*size(mine, 2)
        if (.not. up()) then
            all = mine
            return
        end if
        call MPI_Allgather(n, 1, MPI_INTEGER, cnt, 1, MPI_INTEGER, MPI_COMM_WORLD)
        disp(1) = 0
        do r = 2, nranks
            disp(r) = disp(r - 1) + cnt(r - 1)
        end do
        allocate (all(w, sum(cnt)/max(w, 1)))
        call MPI_Allgatherv(mine, n, MPI_DOUBLE_PRECISION, all, cnt, disp, MPI_DOUBLE_PRECISION, MPI_COMM_WORLD)
    end subroutine comm_gather_records

    !> Records to chosen ranks: columns scnt(1) of send go to rank 0,
    !> the next scnt(2) to rank 1, and so on (a rank sends itself none);
    !> got(:, 1:total), allocated here, holds what every other rank sent
    !> this one, rank by rank in rank order, each rank's in its order. The
    !> counts go first (one collective), then the records (one more).
    subroutine comm_send_records(send, scnt, got, from)
        real(dp), contiguous, intent(in) :: send(:, :)
        integer, contiguous, intent(in) :: scnt(:)
        real(dp), allocatable, intent(out) :: got(:, :)
        !> how many records came from each rank (rank r - 1's in from(r))
        integer, intent(out), optional :: from(:)
        integer :: rcnt(size(scnt)), sd(size(scnt)), rd(size(scnt)), sn(size(scnt)), rn(size(scnt)), r, w
        w = size(send, 1)
        if (.not. up()) then
            allocate (got(w, 0))
            if (present(from)) from = 0
            return
        end if
        call MPI_Alltoall(scnt, 1, MPI_INTEGER, rcnt, 1, MPI_INTEGER, MPI_COMM_WORLD)
        if (present(from)) from = rcnt
        sn = w*scnt
        rn = w*rcnt
        sd(1) = 0
        rd(1) = 0
        do r = 2, size(scnt)
            sd(r) = sd(r - 1) + sn(r - 1)
            rd(r) = rd(r - 1) + rn(r - 1)
        end do
        allocate (got(w, sum(rcnt)))
        call MPI_Alltoallv(send, sn, sd, MPI_DOUBLE_PRECISION, got, rn, rd, MPI_DOUBLE_PRECISION, MPI_COMM_WORLD)
    end subroutine comm_send_records

    !> Every rank's records (columns of mine, the first row each record's
    !> key, a whole number; no key on two ranks) in increasing key order:
    !> all(:, 1:total), allocated here. A sum a run reports, taken over
    !> these in order from zero, is the one the serial run takes when it
    !> adds them in key order, whichever rank holds which record. With
    !> gather false (every rank holds every record already: one rank, or
    !> the replicated nodal state) all is mine.
    subroutine comm_ordered_records(mine, all, gather)
        real(dp), contiguous, intent(in) :: mine(:, :)
        real(dp), allocatable, intent(out) :: all(:, :)
        logical, intent(in) :: gather
        real(dp), allocatable :: got(:, :)
        integer, allocatable :: perm(:)
        integer :: nranks
        if (.not. (gather .and. up())) then
            all = mine
            return
        end if
        call MPI_Comm_size(MPI_COMM_WORLD, nranks)
        call comm_gather_records(mine, nranks, got)
        call sort_index(got(1, :), perm)
        all = got(:, perm)
    end subroutine comm_ordered_records

    !> Point-to-point exchange with the neighbour ranks nbr(k) (0-based):
    !> sbuf(soff(k) + 1 : soff(k + 1)) goes to nbr(k), and what nbr(k) sends
    !> this rank lands in rbuf(roff(k) + 1 : roff(k + 1)). Every value has
    !> one sender and one place, so the result does not depend on the
    !> order the messages arrive in. Every rank calls it with its own
    !> neighbours (a pair's lists agree: they are built from the same
    !> decomposition on both sides).
    subroutine comm_neighbours(nbr, sbuf, soff, rbuf, roff)
        integer, intent(in) :: nbr(:), soff(:), roff(:)
        real(wp), intent(in), contiguous, target :: sbuf(:)
        real(wp), intent(inout), contiguous, target :: rbuf(:)
        type(MPI_Request) :: req(2*size(nbr))
        integer :: k, n, nr
        if (.not. up() .or. size(nbr) == 0) return
        nr = 0
        do k = 1, size(nbr)
            n = roff(k + 1) - roff(k)
            if (n == 0) cycle
            nr = nr + 1
            call MPI_Irecv(rbuf(roff(k) + 1:roff(k + 1)), n, wp_type(), nbr(k), 32, MPI_COMM_WORLD, req(nr))
        end do
        do k = 1, size(nbr)
            n = soff(k + 1) - soff(k)
            if (n == 0) cycle
            nr = nr + 1
            call MPI_Isend(sbuf(soff(k) + 1:soff(k + 1)), n, wp_type(), nbr(k), 32, MPI_COMM_WORLD, req(nr))
        end do
        call MPI_Waitall(nr, req(1:nr), MPI_STATUSES_IGNORE)
    end subroutine comm_neighbours

end module xd_core_comm
