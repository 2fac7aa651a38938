!> Nodal state of the run: positions, half-step velocities, forces, masses,
!> constraint masks, time and step. Passed down the call chain, never global.
module xd_solver_state
    use xd_kinds, only: wp, dp, i8
    use xd_core_memory, only: nbytes, alloc
    use, intrinsic :: iso_fortran_env, only: int8
    implicit none
    private
    public :: state_t, nodal_bytes, allocate_force_arrays

    type :: state_t
        integer :: nnode = 0
        real(wp), allocatable :: x(:, :)      !< (3, nnode) current coordinates
        real(wp), allocatable :: v(:, :)      !< (3, nnode) velocity at t - dt/2 (t at start)
        real(wp), allocatable :: a(:, :)      !< (3, nnode) acceleration
        real(wp), allocatable :: f(:, :)      !< (3, nnode) nodal force (internal, sign: on the node)
        real(wp), allocatable :: mass(:)      !< lumped nodal mass
        !> per node, its free directions (xd_core_dofs): bit j - 1 set where
        !> direction j (x, y, z, then the rotations about them) is free,
        !> clear where an SPC, a TC/RC code or a missing mass or inertia
        !> fixes it (one byte a node)
        integer(int8), allocatable :: dofs(:)
        ! rotational degrees of freedom: only when the deck has shells
        logical :: rot = .false.
        real(wp), allocatable :: vr(:, :)     !< (3, nnode) angular velocity at t - dt/2
        real(wp), allocatable :: mom(:, :)    !< (3, nnode) nodal moments
        real(wp), allocatable :: irot(:)      !< rotational inertia
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

    !> The accelerations, forces (and moments, with rotations) of the nodes
    !> the state holds, zero: allocated by the time loop at its set-up, once
    !> the nodes a rank holds are known (the set-up reads none of them, so
    !> a rank that numbers its nodes apart never holds them for every node).
    subroutine allocate_force_arrays(st)
        type(state_t), intent(inout) :: st
        call alloc(st%a, 3, st%nnode, 'accelerations')
        call alloc(st%f, 3, st%nnode, 'nodal forces')
        if (st%rot) call alloc(st%mom, 3, st%nnode, 'nodal moments')
    end subroutine allocate_force_arrays

    !> The bytes of the nodal arrays this rank holds (issue 32's measure:
    !> its own and halo nodes' where the nodes are numbered per rank,
    !> xd_solver_local_nodes; else every node's).
    integer(i8) function nodal_bytes(st) result(b)
        type(state_t), intent(in) :: st
        b = nbytes(st%x) + nbytes(st%v) + nbytes(st%a) + nbytes(st%f) + nbytes(st%mass) &
            + nbytes(st%dofs) + nbytes(st%vr) + nbytes(st%mom) + nbytes(st%irot) &
            + nbytes(st%jprev)
    end function nodal_bytes

end module xd_solver_state
