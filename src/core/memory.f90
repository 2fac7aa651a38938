!> Allocation wrappers: every large allocate goes through here so that a
!> failure names the array and its size instead of crashing.
module xd_core_memory
    use xd_kinds, only: wp, dp, i8
    use xd_core_parallel_env, only: terminate
    use xd_core_errors, only: exit_run
    use, intrinsic :: iso_fortran_env, only: error_unit, real32, real64, int8
    use, intrinsic :: iso_c_binding, only: c_int, c_size_t
    implicit none
    private
    public :: alloc, alloc_dp, grow, fit, take, untake, nbytes, peak_memory_kb, resident_memory_kb, release_free_memory

    interface alloc
        module procedure alloc_r1, alloc_r2, alloc_r3, alloc_i1, alloc_i2
    end interface alloc

    interface grow
        module procedure grow_r2, grow_i1, grow_i2
    end interface grow

    !> Cut a grown array to its first n entries (columns): the room grow
    !> doubled into is given back once the last entry is in.
    interface fit
        module procedure fit_r2, fit_i1, fit_i2, fit_l1
    end interface fit

    !> Keep an array's entries (columns) at idx alone, in idx's order: a(i)
    !> becomes a(idx(i)), the rest's room given back (a loop into an array
    !> of its own: no temporary of the array's size on the stack). Reals
    !> of either kind, whatever the working precision.
    interface take
        module procedure take_r32, take_r64, take_r2, take_i1, take_int8, take_log
    end interface take

    !> take undone: a(i) back to entry idx(i) of an array of n, the
    !> others zero.
    interface untake
        module procedure untake_r32, untake_r64, untake_r2, untake_i1
    end interface untake

    !> The bytes an allocatable array holds (0 unallocated), any rank.
    interface nbytes
        module procedure nbytes_r32, nbytes_r64, nbytes_int, nbytes_int8, nbytes_log
    end interface nbytes

contains

    subroutine failed(name, nbytes, msg)
        character(len=*), intent(in) :: name, msg
        integer(i8), intent(in) :: nbytes
        write (error_unit, '(a,a,a,i0,a,a)') 'xdyna: cannot allocate ', name, ' (', nbytes, &
            ' bytes): ', trim(msg)
        call terminate(exit_run)
    end subroutine failed

    subroutine alloc_r1(a, n, name)
        real(wp), allocatable, intent(inout) :: a(:)
        integer, intent(in) :: n
        character(len=*), intent(in) :: name
        integer :: st
        character(len=256) :: msg
        if (allocated(a)) deallocate (a)
        allocate (a(n), stat=st, errmsg=msg)
        if (st /= 0) call failed(name, int(n, i8)*storage_size(1.0_wp)/8, msg)
        a = 0.0_wp
    end subroutine alloc_r1

    subroutine alloc_r2(a, n1, n2, name)
        real(wp), allocatable, intent(inout) :: a(:, :)
        integer, intent(in) :: n1, n2
        character(len=*), intent(in) :: name
        integer :: st
        character(len=256) :: msg
        if (allocated(a)) deallocate (a)
        allocate (a(n1, n2), stat=st, errmsg=msg)
        if (st /= 0) call failed(name, int(n1, i8)*n2*storage_size(1.0_wp)/8, msg)
        a = 0.0_wp
    end subroutine alloc_r2

    subroutine alloc_r3(a, n1, n2, n3, name)
        real(wp), allocatable, intent(inout) :: a(:, :, :)
        integer, intent(in) :: n1, n2, n3
        character(len=*), intent(in) :: name
        integer :: st
        character(len=256) :: msg
        if (allocated(a)) deallocate (a)
        allocate (a(n1, n2, n3), stat=st, errmsg=msg)
        if (st /= 0) call failed(name, int(n1, i8)*n2*n3*storage_size(1.0_wp)/8, msg)
        a = 0.0_wp
    end subroutine alloc_r3

    subroutine alloc_i1(a, n, name)
        integer, allocatable, intent(inout) :: a(:)
        integer, intent(in) :: n
        character(len=*), intent(in) :: name
        integer :: st
        character(len=256) :: msg
        if (allocated(a)) deallocate (a)
        allocate (a(n), stat=st, errmsg=msg)
        if (st /= 0) call failed(name, int(n, i8)*4, msg)
        a = 0
    end subroutine alloc_i1

    subroutine alloc_i2(a, n1, n2, name)
        integer, allocatable, intent(inout) :: a(:, :)
        integer, intent(in) :: n1, n2
        character(len=*), intent(in) :: name
        integer :: st
        character(len=256) :: msg
        if (allocated(a)) deallocate (a)
        allocate (a(n1, n2), stat=st, errmsg=msg)
        if (st /= 0) call failed(name, int(n1, i8)*n2*4, msg)
        a = 0
    end subroutine alloc_i2

    subroutine alloc_dp(a, n, name)
        real(dp), allocatable, intent(inout) :: a(:)
        integer, intent(in) :: n
        character(len=*), intent(in) :: name
        integer :: st
        character(len=256) :: msg
        if (allocated(a)) deallocate (a)
        allocate (a(n), stat=st, errmsg=msg)
        if (st /= 0) call failed(name, int(n, i8)*8, msg)
        a = 0.0_dp
    end subroutine alloc_dp

    !> Make room for at least `need` columns, doubling, keeping the contents.
    subroutine grow_r2(a, n1, need, name)
        real(wp), allocatable, intent(inout) :: a(:, :)
        integer, intent(in) :: n1, need
        character(len=*), intent(in) :: name
        real(wp), allocatable :: tmp(:, :)
        integer :: n
        if (.not. allocated(a)) then
            call alloc_r2(a, n1, max(need, 1024), name)
            return
        end if
        if (size(a, 2) >= need) return
        n = max(need, 2*size(a, 2))
        call alloc_r2(tmp, n1, n, name)
        tmp(:, 1:size(a, 2)) = a
        call move_alloc(tmp, a)
    end subroutine grow_r2

    subroutine grow_i1(a, need, name)
        integer, allocatable, intent(inout) :: a(:)
        integer, intent(in) :: need
        character(len=*), intent(in) :: name
        integer, allocatable :: tmp(:)
        integer :: n
        if (.not. allocated(a)) then
            call alloc_i1(a, max(need, 1024), name)
            return
        end if
        if (size(a) >= need) return
        n = max(need, 2*size(a))
        call alloc_i1(tmp, n, name)
        tmp(1:size(a)) = a
        call move_alloc(tmp, a)
    end subroutine grow_i1

    subroutine grow_i2(a, n1, need, name)
        integer, allocatable, intent(inout) :: a(:, :)
        integer, intent(in) :: n1, need
        character(len=*), intent(in) :: name
        integer, allocatable :: tmp(:, :)
        integer :: n
        if (.not. allocated(a)) then
            call alloc_i2(a, n1, max(need, 1024), name)
            return
        end if
        if (size(a, 2) >= need) return
        n = max(need, 2*size(a, 2))
        call alloc_i2(tmp, n1, n, name)
        tmp(:, 1:size(a, 2)) = a
        call move_alloc(tmp, a)
    end subroutine grow_i2

    subroutine fit_r2(a, n)
        real(wp), allocatable, intent(inout) :: a(:, :)
        integer, intent(in) :: n
        real(wp), allocatable :: tmp(:, :)
        if (.not. allocated(a)) return
        if (size(a, 2) == n) return
        call alloc_r2(tmp, size(a, 1), n, 'an array cut to its size')
        tmp = a(:, 1:n)
        call move_alloc(tmp, a)
    end subroutine fit_r2

    subroutine fit_i1(a, n)
        integer, allocatable, intent(inout) :: a(:)
        integer, intent(in) :: n
        integer, allocatable :: tmp(:)
        if (.not. allocated(a)) return
        if (size(a) == n) return
        call alloc_i1(tmp, n, 'an array cut to its size')
        tmp = a(1:n)
        call move_alloc(tmp, a)
    end subroutine fit_i1

    subroutine fit_l1(a, n)
        logical, allocatable, intent(inout) :: a(:)
        integer, intent(in) :: n
        logical, allocatable :: tmp(:)
        if (.not. allocated(a)) return
        if (size(a) == n) return
        allocate (tmp(n))
        tmp = a(1:n)
        call move_alloc(tmp, a)
    end subroutine fit_l1

    subroutine fit_i2(a, n)
        integer, allocatable, intent(inout) :: a(:, :)
        integer, intent(in) :: n
        integer, allocatable :: tmp(:, :)
        if (.not. allocated(a)) return
        if (size(a, 2) == n) return
        call alloc_i2(tmp, size(a, 1), n, 'an array cut to its size')
        tmp = a(:, 1:n)
        call move_alloc(tmp, a)
    end subroutine fit_i2

    subroutine untake_r32(a, idx, n)
        real(real32), allocatable, intent(inout) :: a(:)
        integer, intent(in) :: idx(:), n
        real(real32), allocatable :: b(:)
        integer :: i
        allocate (b(n))
        b = 0
        do i = 1, size(idx)
            b(idx(i)) = a(i)
        end do
        call move_alloc(b, a)
    end subroutine untake_r32

    subroutine untake_r64(a, idx, n)
        real(real64), allocatable, intent(inout) :: a(:)
        integer, intent(in) :: idx(:), n
        real(real64), allocatable :: b(:)
        integer :: i
        allocate (b(n))
        b = 0
        do i = 1, size(idx)
            b(idx(i)) = a(i)
        end do
        call move_alloc(b, a)
    end subroutine untake_r64

    subroutine untake_r2(a, idx, n)
        real(wp), allocatable, intent(inout) :: a(:, :)
        integer, intent(in) :: idx(:), n
        real(wp), allocatable :: b(:, :)
        integer :: i
        allocate (b(size(a, 1), n))
        b = 0
        do i = 1, size(idx)
            b(:, idx(i)) = a(:, i)
        end do
        call move_alloc(b, a)
    end subroutine untake_r2

    subroutine untake_i1(a, idx, n)
        integer, allocatable, intent(inout) :: a(:)
        integer, intent(in) :: idx(:), n
        integer, allocatable :: b(:)
        integer :: i
        allocate (b(n))
        b = 0
        do i = 1, size(idx)
            b(idx(i)) = a(i)
        end do
        call move_alloc(b, a)
    end subroutine untake_i1

    subroutine take_r32(a, idx)
        real(real32), allocatable, intent(inout) :: a(:)
        integer, intent(in) :: idx(:)
        real(real32), allocatable :: b(:)
        integer :: i
        allocate (b(size(idx)))
        do i = 1, size(idx)
            b(i) = a(idx(i))
        end do
        call move_alloc(b, a)
    end subroutine take_r32

    subroutine take_r64(a, idx)
        real(real64), allocatable, intent(inout) :: a(:)
        integer, intent(in) :: idx(:)
        real(real64), allocatable :: b(:)
        integer :: i
        allocate (b(size(idx)))
        do i = 1, size(idx)
            b(i) = a(idx(i))
        end do
        call move_alloc(b, a)
    end subroutine take_r64

    subroutine take_r2(a, idx)
        real(wp), allocatable, intent(inout) :: a(:, :)
        integer, intent(in) :: idx(:)
        real(wp), allocatable :: b(:, :)
        integer :: i
        allocate (b(size(a, 1), size(idx)))
        do i = 1, size(idx)
            b(:, i) = a(:, idx(i))
        end do
        call move_alloc(b, a)
    end subroutine take_r2

    subroutine take_i1(a, idx)
        integer, allocatable, intent(inout) :: a(:)
        integer, intent(in) :: idx(:)
        integer, allocatable :: b(:)
        integer :: i
        allocate (b(size(idx)))
        do i = 1, size(idx)
            b(i) = a(idx(i))
        end do
        call move_alloc(b, a)
    end subroutine take_i1

    subroutine take_int8(a, idx)
        integer(int8), allocatable, intent(inout) :: a(:)
        integer, intent(in) :: idx(:)
        integer(int8), allocatable :: b(:)
        integer :: i
        allocate (b(size(idx)))
        do i = 1, size(idx)
            b(i) = a(idx(i))
        end do
        call move_alloc(b, a)
    end subroutine take_int8

    subroutine take_log(a, idx)
        logical, allocatable, intent(inout) :: a(:)
        integer, intent(in) :: idx(:)
        logical, allocatable :: b(:)
        integer :: i
        allocate (b(size(idx)))
        do i = 1, size(idx)
            b(i) = a(idx(i))
        end do
        call move_alloc(b, a)
    end subroutine take_log

    integer(i8) function nbytes_r32(a) result(b)
        real(real32), allocatable, intent(in) :: a(..)
        b = 0
        if (allocated(a)) b = size(a, kind=i8)*(storage_size(1.0_real32, i8)/8)
    end function nbytes_r32

    integer(i8) function nbytes_r64(a) result(b)
        real(real64), allocatable, intent(in) :: a(..)
        b = 0
        if (allocated(a)) b = size(a, kind=i8)*(storage_size(1.0_real64, i8)/8)
    end function nbytes_r64

    integer(i8) function nbytes_int(a) result(b)
        integer, allocatable, intent(in) :: a(..)
        b = 0
        if (allocated(a)) b = size(a, kind=i8)*(storage_size(1, i8)/8)
    end function nbytes_int

    integer(i8) function nbytes_int8(a) result(b)
        integer(int8), allocatable, intent(in) :: a(..)
        b = 0
        if (allocated(a)) b = size(a, kind=i8)
    end function nbytes_int8

    integer(i8) function nbytes_log(a) result(b)
        logical, allocatable, intent(in) :: a(..)
        b = 0
        if (allocated(a)) b = size(a, kind=i8)*(storage_size(.true., i8)/8)
    end function nbytes_log

    !> The heap's free memory handed back to the system (glibc's
    !> malloc_trim): the set-up's many small allocations (the deck's lines,
    !> the model's growing lists), freed, otherwise stay in the process's
    !> resident memory for the whole run.
    subroutine release_free_memory()
        interface
            integer(c_int) function malloc_trim(pad) bind(c, name='malloc_trim')
                import :: c_int, c_size_t
                integer(c_size_t), value :: pad
            end function malloc_trim
        end interface
        integer(c_int) :: r
        r = malloc_trim(0_c_size_t)
    end subroutine release_free_memory

    !> This process's peak resident memory in kB (VmHWM of /proc/self/status,
    !> Linux); -1 where it cannot be read.
    integer(i8) function peak_memory_kb() result(kb)
        kb = status_kb('VmHWM:')
    end function peak_memory_kb

    !> This process's resident memory now in kB (VmRSS); -1 where it cannot
    !> be read.
    integer(i8) function resident_memory_kb() result(kb)
        kb = status_kb('VmRSS:')
    end function resident_memory_kb

    !> A kB figure of /proc/self/status (Linux), by its 6-character key.
    integer(i8) function status_kb(key) result(kb)
        character(len=6), intent(in) :: key
        integer :: u, ios
        character(len=256) :: line
        kb = -1
        open (newunit=u, file='/proc/self/status', status='old', action='read', iostat=ios)
        if (ios /= 0) return
        do
            read (u, '(a)', iostat=ios) line
            if (ios /= 0) exit
            if (line(1:6) == key) then
                read (line(7:), *, iostat=ios) kb
                if (ios /= 0) kb = -1
                exit
            end if
        end do
        close (u)
    end function status_kb

end module xd_core_memory
