!> Whole datasets in and out of an HDF5 group, for the restart dump: one
!> rank-1 dataset per array (arrays are passed flattened, [a], and put
!> back with reshape), in the array's own kind, so a dump holds the bits
!> of the run. Strings as attributes of the group. Every dataset carries
!> HDF5's Fletcher-32 checksum (chunked layout, the filter HDF5 checks on
!> each read), so a changed byte in a dump is found, not restarted from.
!> Writes count their failures in `nfail` (a full disk, a quota); reads
!> tell a missing dataset from one that fails its checksum.
module xd_output_h5io
    use hdf5
    use, intrinsic :: iso_fortran_env, only: real32, real64, int32, int64
    implicit none
    private
    public :: dput, dget, put_text, get_text, h5_no_exit_handler

    interface dput
        module procedure put_r4, put_r8, put_i4, put_i8
    end interface dput
    interface dget
        module procedure get_r4, get_r8, get_i4, get_i8
    end interface dget

contains

    subroutine put_any(g, name, t, n, buf_loc, nfail)
        use, intrinsic :: iso_c_binding, only: c_ptr
        integer(hid_t), intent(in) :: g, t
        character(len=*), intent(in) :: name
        integer, intent(in) :: n
        type(c_ptr), intent(in) :: buf_loc
        integer, intent(inout) :: nfail
        integer(hid_t) :: sp, ds, pl
        integer(hsize_t) :: d(1), c(1)
        integer :: err, e
        ! chunks of at most 2**24 values (a chunk is limited to 4 GiB)
        integer(hsize_t), parameter :: chunk_max = 16777216_hsize_t
        d = n
        e = 0
        call h5screate_simple_f(1, d, sp, err)
        e = e + min(err, 0)
        call h5pcreate_f(H5P_DATASET_CREATE_F, pl, err)
        if (n > 0) then
            c = min(d, chunk_max)
            call h5pset_chunk_f(pl, 1, c, err)
            e = e + min(err, 0)
            call h5pset_fletcher32_f(pl, err)
            e = e + min(err, 0)
        end if
        call h5dcreate_f(g, name, t, sp, ds, err, dcpl_id=pl)
        e = e + min(err, 0)
        if (n > 0 .and. err == 0) then
            call h5dwrite_f(ds, t, buf_loc, err)
            e = e + min(err, 0)
        end if
        call h5dclose_f(ds, err)
        e = e + min(err, 0)
        call h5pclose_f(pl, err)
        call h5sclose_f(sp, err)
        if (e /= 0) nfail = nfail + 1
    end subroutine put_any

    !> Size of dataset `name` (-1: absent) and, if present, its handle.
    subroutine open_any(g, name, n, ds)
        integer(hid_t), intent(in) :: g
        character(len=*), intent(in) :: name
        integer, intent(out) :: n
        integer(hid_t), intent(out) :: ds
        integer(hid_t) :: sp
        integer(hsize_t) :: d(1), mx(1)
        integer :: err
        logical :: there
        n = -1
        ds = -1
        call h5lexists_f(g, name, there, err)
        if (.not. there) return
        call h5dopen_f(g, name, ds, err)
        call h5dget_space_f(ds, sp, err)
        call h5sget_simple_extent_dims_f(sp, d, mx, err)
        call h5sclose_f(sp, err)
        n = int(d(1))
    end subroutine open_any

    subroutine put_r4(g, name, a, nfail)
        use, intrinsic :: iso_c_binding, only: c_loc
        integer(hid_t), intent(in) :: g
        character(len=*), intent(in) :: name
        integer, intent(inout) :: nfail
        real(real32), intent(in), target :: a(:)
        real(real32), allocatable, target :: b(:)
        if (size(a) == 0) then
            allocate (b(1))
        else
            b = a
        end if
        call put_any(g, name, h5kind_to_type(real32, H5_REAL_KIND), size(a), c_loc(b), nfail)
    end subroutine put_r4

    subroutine put_r8(g, name, a, nfail)
        use, intrinsic :: iso_c_binding, only: c_loc
        integer(hid_t), intent(in) :: g
        character(len=*), intent(in) :: name
        integer, intent(inout) :: nfail
        real(real64), intent(in) :: a(:)
        real(real64), allocatable, target :: b(:)
        if (size(a) == 0) then
            allocate (b(1))
        else
            b = a
        end if
        call put_any(g, name, h5kind_to_type(real64, H5_REAL_KIND), size(a), c_loc(b), nfail)
    end subroutine put_r8

    subroutine put_i4(g, name, a, nfail)
        use, intrinsic :: iso_c_binding, only: c_loc
        integer(hid_t), intent(in) :: g
        character(len=*), intent(in) :: name
        integer, intent(inout) :: nfail
        integer(int32), intent(in) :: a(:)
        integer(int32), allocatable, target :: b(:)
        if (size(a) == 0) then
            allocate (b(1))
        else
            b = a
        end if
        call put_any(g, name, h5kind_to_type(int32, H5_INTEGER_KIND), size(a), c_loc(b), nfail)
    end subroutine put_i4

    subroutine put_i8(g, name, a, nfail)
        use, intrinsic :: iso_c_binding, only: c_loc
        integer(hid_t), intent(in) :: g
        character(len=*), intent(in) :: name
        integer, intent(inout) :: nfail
        integer(int64), intent(in) :: a(:)
        integer(int64), allocatable, target :: b(:)
        if (size(a) == 0) then
            allocate (b(1))
        else
            b = a
        end if
        call put_any(g, name, h5kind_to_type(int64, H5_INTEGER_KIND), size(a), c_loc(b), nfail)
    end subroutine put_i8

    !> Read the n values of open dataset ds into the buffer at buf (type t,
    !> room for max(n, 1)) and close it.
    subroutine read_close(ds, t, n, buf, good)
        use, intrinsic :: iso_c_binding, only: c_ptr
        integer(hid_t), intent(in) :: ds, t
        integer, intent(in) :: n
        type(c_ptr), intent(in) :: buf
        logical, intent(out) :: good
        type(c_ptr) :: cp
        integer :: err
        good = .true.
        if (n > 0) then
            cp = buf
            call h5dread_f(ds, t, cp, err)
            good = err == 0
        end if
        call h5dclose_f(ds, err)
    end subroutine read_close

    !> Read dataset `name` whole into b (allocated to its size); ok false if
    !> it is absent (b empty) or fails its checksum; `why` says which.
    subroutine get_r4(g, name, b, ok, why)
        use, intrinsic :: iso_c_binding, only: c_loc
        integer(hid_t), intent(in) :: g
        character(len=*), intent(in) :: name
        real(real32), allocatable, target, intent(out) :: b(:)
        logical, intent(out) :: ok
        character(len=:), allocatable, intent(out), optional :: why
        logical :: good
        integer(hid_t) :: ds
        integer :: n
        if (present(why)) why = ''
        call open_any(g, name, n, ds)
        ok = n >= 0
        if (.not. ok) then
            allocate (b(0))
            if (present(why)) why = 'is missing'
            return
        end if
        allocate (b(max(n, 1)))
        call read_close(ds, h5kind_to_type(real32, H5_REAL_KIND), n, c_loc(b), good)
        b = b(1:n)
        if (.not. good) then
            ok = .false.
            if (present(why)) why = 'cannot be read: it fails its checksum (the dump is damaged)'
        end if
    end subroutine get_r4

    subroutine get_r8(g, name, b, ok, why)
        use, intrinsic :: iso_c_binding, only: c_loc
        integer(hid_t), intent(in) :: g
        character(len=*), intent(in) :: name
        real(real64), allocatable, target, intent(out) :: b(:)
        logical, intent(out) :: ok
        character(len=:), allocatable, intent(out), optional :: why
        logical :: good
        integer(hid_t) :: ds
        integer :: n
        if (present(why)) why = ''
        call open_any(g, name, n, ds)
        ok = n >= 0
        if (.not. ok) then
            allocate (b(0))
            if (present(why)) why = 'is missing'
            return
        end if
        allocate (b(max(n, 1)))
        call read_close(ds, h5kind_to_type(real64, H5_REAL_KIND), n, c_loc(b), good)
        b = b(1:n)
        if (.not. good) then
            ok = .false.
            if (present(why)) why = 'cannot be read: it fails its checksum (the dump is damaged)'
        end if
    end subroutine get_r8

    subroutine get_i4(g, name, b, ok, why)
        use, intrinsic :: iso_c_binding, only: c_loc
        integer(hid_t), intent(in) :: g
        character(len=*), intent(in) :: name
        integer(int32), allocatable, target, intent(out) :: b(:)
        logical, intent(out) :: ok
        character(len=:), allocatable, intent(out), optional :: why
        logical :: good
        integer(hid_t) :: ds
        integer :: n
        if (present(why)) why = ''
        call open_any(g, name, n, ds)
        ok = n >= 0
        if (.not. ok) then
            allocate (b(0))
            if (present(why)) why = 'is missing'
            return
        end if
        allocate (b(max(n, 1)))
        call read_close(ds, h5kind_to_type(int32, H5_INTEGER_KIND), n, c_loc(b), good)
        b = b(1:n)
        if (.not. good) then
            ok = .false.
            if (present(why)) why = 'cannot be read: it fails its checksum (the dump is damaged)'
        end if
    end subroutine get_i4

    subroutine get_i8(g, name, b, ok, why)
        use, intrinsic :: iso_c_binding, only: c_loc
        integer(hid_t), intent(in) :: g
        character(len=*), intent(in) :: name
        integer(int64), allocatable, target, intent(out) :: b(:)
        logical, intent(out) :: ok
        character(len=:), allocatable, intent(out), optional :: why
        logical :: good
        integer(hid_t) :: ds
        integer :: n
        if (present(why)) why = ''
        call open_any(g, name, n, ds)
        ok = n >= 0
        if (.not. ok) then
            allocate (b(0))
            if (present(why)) why = 'is missing'
            return
        end if
        allocate (b(max(n, 1)))
        call read_close(ds, h5kind_to_type(int64, H5_INTEGER_KIND), n, c_loc(b), good)
        b = b(1:n)
        if (.not. good) then
            ok = .false.
            if (present(why)) why = 'cannot be read: it fails its checksum (the dump is damaged)'
        end if
    end subroutine get_i8

    !> A string attribute of object g (an empty string is written as one
    !> blank: HDF5 strings have a size of at least 1).
    subroutine put_text(g, name, text)
        integer(hid_t), intent(in) :: g
        character(len=*), intent(in) :: name, text
        integer(hid_t) :: sp, at, t
        integer(hsize_t) :: d(1)
        integer :: err
        character(len=max(len(text), 1)) :: v
        v = text
        d = 1
        call h5screate_simple_f(1, d, sp, err)
        call h5tcopy_f(H5T_FORTRAN_S1, t, err)
        call h5tset_size_f(t, int(len(v), size_t), err)
        call h5acreate_f(g, name, t, sp, at, err)
        call h5awrite_f(at, t, [v], d, err)
        call h5aclose_f(at, err)
        call h5tclose_f(t, err)
        call h5sclose_f(sp, err)
    end subroutine put_text

    !> The string attribute `name` of g ('' if absent).
    function get_text(g, name) result(text)
        integer(hid_t), intent(in) :: g
        character(len=*), intent(in) :: name
        character(len=:), allocatable :: text
        integer(hid_t) :: at, t, mt
        integer(size_t) :: n
        integer(hsize_t) :: d(1)
        integer :: err
        logical :: there
        character(len=4096) :: buf(1)
        text = ''
        call h5aexists_f(g, name, there, err)
        if (.not. there) return
        call h5aopen_f(g, name, at, err)
        call h5aget_type_f(at, t, err)
        call h5tget_size_f(t, n, err)
        call h5tcopy_f(H5T_FORTRAN_S1, mt, err)
        call h5tset_size_f(mt, int(len(buf(1)), size_t), err)
        d = 1
        buf = ''
        call h5aread_f(at, mt, buf, d, err)
        call h5tclose_f(mt, err)
        call h5tclose_f(t, err)
        call h5aclose_f(at, err)
        text = buf(1)(1:min(int(n), len(buf(1))))
    end function get_text

    !> HDF5 registers a clean-up at exit that flushes and closes whatever
    !> is still open; after a write refused by a full disk that clean-up
    !> crashed (SIGSEGV inside it, after our error message). xdyna closes
    !> its files itself on every path that can still write them, so the
    !> handler is not registered: called before any other HDF5 call.
    subroutine h5_no_exit_handler()
        integer :: err
        call h5dont_atexit_f(err)
    end subroutine h5_no_exit_handler

end module xd_output_h5io
