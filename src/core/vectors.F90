!> Small vector helpers shared by set-up, contact and constraint code.
module xd_core_vectors
    use xd_kinds, only: wp, dp
    implicit none
    private
    public :: cross

    !> Cross product a x b, in double precision and in the field kind (the
    !> same kind in the double build).
    interface cross
        module procedure cross_dp
#ifdef XD_SINGLE
        module procedure cross_wp
#endif
    end interface cross

contains

    pure function cross_dp(a, b) result(c)
        real(dp), intent(in) :: a(3), b(3)
        real(dp) :: c(3)
        c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
    end function cross_dp

#ifdef XD_SINGLE
    pure function cross_wp(a, b) result(c)
        real(wp), intent(in) :: a(3), b(3)
        real(wp) :: c(3)
        c = [a(2)*b(3) - a(3)*b(2), a(3)*b(1) - a(1)*b(3), a(1)*b(2) - a(2)*b(1)]
    end function cross_wp
#endif

end module xd_core_vectors
