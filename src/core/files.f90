!> File operations Fortran lacks, from the C library: rename (atomic on one
!> file system: a reader sees the old file or the new one, never half of
!> one) and truncate.
module xd_core_files
    use, intrinsic :: iso_c_binding, only: c_int, c_char, c_null_char, c_long
    use xd_kinds, only: i8
    implicit none
    private
    public :: rename_file, truncate_file

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

    !> Cut file `path` to `bytes` bytes.
    subroutine truncate_file(path, bytes, ok)
        character(len=*), intent(in) :: path
        integer(i8), intent(in) :: bytes
        logical, intent(out), optional :: ok
        integer(c_int) :: rc
        rc = c_truncate(path//c_null_char, int(bytes, c_long))
        if (present(ok)) ok = rc == 0
    end subroutine truncate_file

end module xd_core_files
