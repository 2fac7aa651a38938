!> Nodal state of the run: positions, half-step velocities, forces, masses,
!> constraint masks, time and step. Passed down the call chain, never global.
module xd_solver_state
    use xd_kinds, only: wp, dp, i8
    implicit none
    private
    public :: state_t, nodal_bytes

    type :: state_t
        integer :: nnode = 0
        real(wp), allocatable :: x(:, :)      !< (3, nnode) current coordinates
        real(wp), allocatable :: x0(:, :)     !< (3, nnode) initial coordinates
        real(wp), allocatable :: v(:, :)      !< (3, nnode) velocity at t - dt/2 (t at start)
        real(wp), allocatable :: a(:, :)      !< (3, nnode) acceleration
        real(wp), allocatable :: f(:, :)      !< (3, nnode) nodal force (internal, sign: on the node)
        real(wp), allocatable :: mass(:)      !< lumped nodal mass
        real(wp), allocatable :: free(:, :)   !< (3, nnode) 1 free, 0 fixed by an SPC
        ! rotational degrees of freedom: only when the deck has shells
        logical :: rot = .false.
        real(wp), allocatable :: vr(:, :)     !< (3, nnode) angular velocity at t - dt/2
        real(wp), allocatable :: mom(:, :)    !< (3, nnode) nodal moments
        real(wp), allocatable :: irot(:)      !< rotational inertia
        real(wp), allocatable :: free_r(:, :) !< (3, nnode) 1 free, 0 fixed
        ! prescribed nodal motion: last cycle's imposed velocity change per
        ! component (only when the deck prescribes nodal motion)
        real(wp), allocatable :: jprev(:, :)  !< (3, nnode)
        real(dp) :: time = 0.0_dp
        real(wp) :: dt = 0.0_wp               !< step about to be taken (t -> t + dt)
        real(wp) :: dt_old = 0.0_wp           !< step just taken
        real(dp) :: dt_avg_prev = 0.0_dp      !< (dt_old + the step before) / 2: the last velocity update's
        real(wp) :: dt_first = 0.0_wp         !< first step, for DTMIN
        integer :: cycle = 0
        integer :: crit_elem = 0              !< element that set the step: solids index, or minus the shell's
        real(dp) :: ext_work = 0.0_dp         !< external work so far
        real(dp) :: e_initial = 0.0_dp        !< total energy at t = 0
        real(dp) :: ms_work = 0.0_dp          !< mass scaling: kinetic energy the added mass entered with
    end type state_t

contains

    !> The bytes of the nodal arrays this rank holds (issue 32's measure:
    !> every node's on every rank until the nodes are numbered per rank).
    integer(i8) function nodal_bytes(st) result(b)
        type(state_t), intent(in) :: st
        b = 0
        if (allocated(st%x)) b = b + size(st%x, kind=i8)*(storage_size(st%x, i8)/8)
        if (allocated(st%x0)) b = b + size(st%x0, kind=i8)*(storage_size(st%x0, i8)/8)
        if (allocated(st%v)) b = b + size(st%v, kind=i8)*(storage_size(st%v, i8)/8)
        if (allocated(st%a)) b = b + size(st%a, kind=i8)*(storage_size(st%a, i8)/8)
        if (allocated(st%f)) b = b + size(st%f, kind=i8)*(storage_size(st%f, i8)/8)
        if (allocated(st%mass)) b = b + size(st%mass, kind=i8)*(storage_size(st%mass, i8)/8)
        if (allocated(st%free)) b = b + size(st%free, kind=i8)*(storage_size(st%free, i8)/8)
        if (allocated(st%vr)) b = b + size(st%vr, kind=i8)*(storage_size(st%vr, i8)/8)
        if (allocated(st%mom)) b = b + size(st%mom, kind=i8)*(storage_size(st%mom, i8)/8)
        if (allocated(st%irot)) b = b + size(st%irot, kind=i8)*(storage_size(st%irot, i8)/8)
        if (allocated(st%free_r)) b = b + size(st%free_r, kind=i8)*(storage_size(st%free_r, i8)/8)
        if (allocated(st%jprev)) b = b + size(st%jprev, kind=i8)*(storage_size(st%jprev, i8)/8)
    end function nodal_bytes

end module xd_solver_state
