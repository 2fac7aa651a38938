!> Kinds used everywhere: `wp` for field data (double by default, single with
!> `make PRECISION=single`), `dp` for accumulations that must stay double
!> (time, energies), `i8` for counters that may pass 2**31.
module xd_kinds
    use, intrinsic :: iso_fortran_env, only: real32, real64, int32, int64
    implicit none
    private
#ifdef XD_SINGLE
    integer, parameter, public :: wp = real32
#else
    integer, parameter, public :: wp = real64
#endif
    integer, parameter, public :: dp = real64
    integer, parameter, public :: ik = int32
    integer, parameter, public :: i8 = int64
end module xd_kinds
