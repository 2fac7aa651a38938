!> Small vector helpers shared by set-up and constraint code.
module xd_core_vectors
    use xd_kinds, only: dp
    implicit none
    private
    public :: cross

contains

    !> Cross product a x b.
    pure function cross(a, b) result(c)
        real(dp), intent(in) :: a(3), b(3)
        real(dp) :: c(3)
        c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
    end function cross

end module xd_core_vectors
