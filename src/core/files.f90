!> File operations Fortran lacks, from the C library: rename (atomic on one
!> file system: a reader sees the old file or the new one, never half of
!> one), truncate, mkdir (no shell ever sees a path) and the kind of a file.
module xd_core_files
    use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char, c_long
    use xd_kinds, only: i8
    implicit none
    private
    public :: rename_file, delete_file, written_bytes, truncate_file, make_dirs, file_kind, absolute_path
    public :: fk_missing, fk_regular, fk_directory, fk_other

    integer, parameter :: fk_missing = 0, fk_regular = 1, fk_directory = 2, fk_other = 3

    interface
        integer(c_int) function c_rename(a, b) bind(c, name='rename')
            import :: c_int, c_char
            character(kind=c_char), intent(in) :: a(*), b(*)
        end function c_rename
        integer(c_int) function c_truncate(p, n) bind(c, name='truncate')
            import :: c_int, c_char, c_long
            character(kind=c_char), intent(in) :: p(*)
            integer(c_long), value :: n
        end function c_truncate
        integer(c_long) function c_lseek(fd, off, whence) bind(c, name='lseek')
            import :: c_int, c_long
            integer(c_int), value :: fd
            integer(c_long), value :: off
            integer(c_int), value :: whence
        end function c_lseek
        integer(c_int) function c_unlink(p) bind(c, name='unlink')
            import :: c_int, c_char
            character(kind=c_char), intent(in) :: p(*)
        end function c_unlink
        integer(c_int) function c_mkdir(p, mode) bind(c, name='mkdir')
            import :: c_int, c_char
            character(kind=c_char), intent(in) :: p(*)
            integer(c_int), value :: mode
        end function c_mkdir
    end interface

contains

    !> Rename `from` to `to` (replacing it); ok false if that failed.
    subroutine rename_file(from, to, ok)
        character(len=*), intent(in) :: from, to
        logical, intent(out), optional :: ok
        integer(c_int) :: rc
        rc = c_rename(from//c_null_char, to//c_null_char)
        if (present(ok)) ok = rc == 0
    end subroutine rename_file

    !> The bytes the system holds of the file open on Fortran unit u (its
    !> offset, at the end of a sequential file): after a flush, fewer than
    !> the unit's own size means a write failed. gfortran's flush does not
    !> report a write the system refused (a full disk, EFBIG past a size
    !> limit), so this is how a failed write is seen.
    integer(i8) function written_bytes(u)
        integer, intent(in) :: u
        written_bytes = int(c_lseek(int(fnum(u), c_int), 0_c_long, 1_c_int), i8)
    end function written_bytes

    !> Remove a file if it is there (a temporary left by a failed write).
    subroutine delete_file(path)
        character(len=*), intent(in) :: path
        integer(c_int) :: rc
        rc = c_unlink(path//c_null_char)
    end subroutine delete_file

    !> Cut file `path` to `bytes` bytes.
    subroutine truncate_file(path, bytes, ok)
        character(len=*), intent(in) :: path
        integer(i8), intent(in) :: bytes
        logical, intent(out), optional :: ok
        integer(c_int) :: rc
        rc = c_truncate(path//c_null_char, int(bytes, c_long))
        if (present(ok)) ok = rc == 0
    end subroutine truncate_file

    !> Create directory `path` and its missing parents (mode 0777 less the
    !> umask), as `mkdir -p` would, with no shell; ok false if it is not a
    !> directory at the end.
    subroutine make_dirs(path, ok)
        character(len=*), intent(in) :: path
        logical, intent(out) :: ok
        integer :: k
        integer(c_int) :: rc
        do k = 2, len(path)
            if (path(k:k) == '/' .and. path(k - 1:k - 1) /= '/') then
                if (file_kind(path(1:k - 1)) == fk_missing) rc = c_mkdir(path(1:k - 1)//c_null_char, int(o'777', c_int))
            end if
        end do
        if (len(path) > 0) then
            if (file_kind(path) == fk_missing) rc = c_mkdir(path//c_null_char, int(o'777', c_int))
        end if
        ok = file_kind(path) == fk_directory
    end subroutine make_dirs

    !> What `path` is: missing, a regular file, a directory, or something
    !> else (a FIFO, a device, a socket), from stat(2) (the file itself, a
    !> link followed).
    integer function file_kind(path) result(k)
        character(len=*), intent(in) :: path
        integer :: values(13), st, mode
        call stat(path, values, st)
        k = fk_missing
        if (st /= 0) return
        mode = iand(values(3), int(o'170000'))
        if (mode == int(o'100000')) then
            k = fk_regular
        else if (mode == int(o'040000')) then
            k = fk_directory
        else
            k = fk_other
        end if
    end function file_kind

    !> `path` as an absolute path: itself if it starts with '/', else under
    !> the working directory (a restart from elsewhere finds the same files).
    function absolute_path(path) result(p)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: p
        character(len=4096) :: cwd
        integer :: st
        p = path
        if (len(path) == 0) return
        if (path(1:1) == '/') return
        call getcwd(cwd, st)
        if (st /= 0) return
        p = trim(cwd)//'/'//path
    end function absolute_path

end module xd_core_files
