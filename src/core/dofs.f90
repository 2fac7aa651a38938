!> A node's free directions in one byte (its dofs code): bit j - 1 set where
!> direction j (x, y, z, then the rotations about them) is free, clear
!> where a constraint fixes it. The masks the loops multiply by are
!> real(ibits(code, j - 1, 1)): 1 free, 0 fixed, exactly.
module xd_core_dofs
    use xd_kinds, only: wp
    use, intrinsic :: iso_fortran_env, only: int8
    implicit none
    private
    public :: all_free, free3, free3r, free_dir

    !> every direction free
    integer(int8), parameter :: all_free = 63_int8
    !> the translations' and the rotations' directions
    integer, parameter :: translations(3) = [1, 2, 3], rotations(3) = [4, 5, 6]

contains

    !> Direction j's mask (1 .. 6): 1 free, 0 fixed.
    pure elemental real(wp) function free_dir(c, j) result(w)
        integer(int8), intent(in) :: c
        integer, intent(in) :: j
        w = real(ibits(c, j - 1, 1), wp)
    end function free_dir

    !> The translations' masks.
    pure function free3(c) result(w)
        integer(int8), intent(in) :: c
        real(wp) :: w(3)
        w = free_dir(c, translations)
    end function free3

    !> The rotations' masks.
    pure function free3r(c) result(w)
        integer(int8), intent(in) :: c
        real(wp) :: w(3)
        w = free_dir(c, rotations)
    end function free3r

end module xd_core_dofs
