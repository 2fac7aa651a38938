!> The states as LS-DYNA's binary d3plot family, in the layout of LSTC's
!> "LS-DYNA Database Binary Output Files": 32-bit words in the machine's
!> byte order; the first member (`d3plot`) holds the 64 control words, the
!> geometry (initial coordinates, hexahedra and shells with their material
!> numbers) and the user ids (NARBS: the deck's node, element and part
!> ids), then, after an end-of-file marker, the part titles (entity type
!> 90001: the number of parts, then each part's id and its 72-character
!> title) and the run's title (90000), as LS-DYNA writes them: readers
!> (VTK's, lasso-python's) label the parts with them. The states follow in
!> the members after it; a state is the time, the global variables, current
!> coordinates and velocities of every node, 7 words per hexahedron (stress
!> xx yy zz xy yz zx, effective plastic strain), 6 per beam (axial force,
!> shears along s and t, moments about s and t at mid-length, torque), NV2D
!> words per shell and
!> one deletion flag per element (1: in the model; solids, shells, beams). The first state opens
!> `d3plot01`; `d3plot02`, ... follow when a state would take a member past its size
!> (a state is never split); a member followed by another ends with the
!> end-of-file marker -999999.0, the last one after its last state (VTK's
!> reader, 9.1, loses its file handle when the family's last word is the
!> marker). Each state is flushed when written, so that a run stopped at
!> any moment leaves every finished state readable.
!>
!> Choices where the description leaves one (the manual, "States"):
!> - the materials of the geometry are the parts that have elements,
!>   numbered hexahedron parts first and shell parts after, in the deck's
!>   order (readers such as VTK's take the counts NUMMAT8, NUMMAT4 in that
!>   order); NARBS maps them to the deck's part ids;
!> - MAXINT is 3 when no shell has more than three points through the
!>   thickness (then the three layers are mid-surface, inner, outer, as
!>   LS-DYNA writes them), else the largest number of points, written in
!>   their order from the bottom surface up (an element with fewer points
!>   writes zeros in the layers it lacks);
!> - shell stresses are in global axes (LS-DYNA's default, CMPFLG 0); the
!>   resultants (Mxx Myy Mxy Qyz Qxz Nxx Nyy Nxy, per unit width) in the
!>   element's local frame; the four words after them are the thickness,
!>   two zeros and the internal energy per unit initial volume;
!> - the global variables are NGLBV = 6 + 7 NMMAT: kinetic, internal and
!>   total energy, the velocity of the centre of mass, then per material
!>   the internal energy, kinetic energy, velocity (x y z of each), mass
!>   and hourglass energy; no rigid-wall words;
!> - the run-time word is 0, so that two equal runs write equal files.
module xd_output_d3plot
    use, intrinsic :: iso_fortran_env, only: int32, real32, int64
    use xd_kinds, only: i8
    use xd_core_files, only: delete_file, truncate_file
    implicit none
    private
    public :: d3plot_t, d3plot_mesh_t, d3plot_open, d3plot_close, d3plot_member_name, member_unit
    public :: d3plot_begin_state, d3plot_put, d3plot_end_state

    integer, parameter :: nhead = 64
    real(real32), parameter :: eof_marker = -999999.0_real32
    !> The unit of member sizes, 512 x 512 words: LS-DYNA's x=N gives N of
    !> them (7 by default)
    integer(int64), parameter :: member_unit = 512_int64*512

    !> The mesh as the d3plot holds it.
    type :: d3plot_mesh_t
        character(len=80) :: title = ''
        real(real32), allocatable :: x0(:, :)         !< (3, nnode) initial coordinates
        integer, allocatable :: node_id(:)
        integer, allocatable :: solid_conn(:, :)      !< (8, nsolid) node indices, 1-based
        integer, allocatable :: solid_mat(:), solid_id(:)
        integer, allocatable :: shell_conn(:, :)      !< (4, nshell)
        integer, allocatable :: shell_mat(:), shell_id(:)
        integer, allocatable :: beam_conn(:, :)       !< (3, nbeam) N1 N2 and the orientation node (N2 if none)
        integer, allocatable :: beam_mat(:), beam_id(:)
        integer :: nmat_solid = 0, nmat_shell = 0     !< NUMMAT8, NUMMAT4
        integer :: nmat_beam = 0                      !< NUMMAT2
        integer, allocatable :: part_id(:)            !< the deck's id of each material (NMMAT)
        character(len=70), allocatable :: part_title(:) !< the deck's heading of each (*PART's first card)
        integer :: maxint = 3
        integer :: nrigid = 0                         !< rigid bodies (NUMRBS)
    end type d3plot_mesh_t

    type :: d3plot_t
        logical :: on = .false.
        character(len=:), allocatable :: base         !< path of the first member
        integer :: u = -1
        integer :: member = 0                         !< the open member (0: d3plot, which holds no state)
        integer(int64) :: words = 0                   !< words of the open member (before the marker)
        integer :: in_member = 0                      !< states in the open member
        integer(int64) :: limit = 7*member_unit
        integer(int64) :: head_words = 0              !< control, geometry, ids and titles
        integer(int64) :: state_words = 0
        integer :: nnode = 0, nsolid = 0, nshell = 0, nmmat = 0, maxint = 3, nv2d = 0, nglbv = 0
        integer :: nbeam = 0
        logical :: failed = .false.
        character(len=:), allocatable :: failed_file
        !> a state written in parts (d3plot_begin_state, d3plot_put,
        !> d3plot_end_state): the words put so far
        integer(int64) :: put_words = 0
    end type d3plot_t

contains

    !> The name of member k (0: the base name; then base01 .. base99, base100, ...).
    function d3plot_member_name(base, k) result(name)
        character(len=*), intent(in) :: base
        integer, intent(in) :: k
        character(len=:), allocatable :: name
        character(len=16) :: b
        if (k == 0) then
            name = base
            return
        end if
        write (b, '(i2.2)') k
        if (k >= 100) write (b, '(i0)') k
        name = base//trim(b)
    end function d3plot_member_name

    !> Create the family's first member with the control words, the geometry
    !> and the user ids. With keep >= 0 (a restart), the family is cut back
    !> to its first `keep` states instead and opened for more.
    subroutine d3plot_open(d, base, mesh, limit, keep, ok)
        type(d3plot_t), intent(out) :: d
        character(len=*), intent(in) :: base
        type(d3plot_mesh_t), intent(in) :: mesh
        integer(int64), intent(in) :: limit       !< member size in words
        integer, intent(in) :: keep
        logical, intent(out) :: ok
        integer(int32), allocatable :: head(:)
        integer :: ios
        d%on = .true.
        d%base = base
        d%limit = max(limit, int(nhead, int64))
        d%nnode = size(mesh%node_id)
        d%nsolid = size(mesh%solid_id)
        d%nshell = size(mesh%shell_id)
        d%nbeam = 0
        if (allocated(mesh%beam_id)) d%nbeam = size(mesh%beam_id)
        d%nmmat = size(mesh%part_id)
        d%maxint = mesh%maxint
        d%nv2d = 7*d%maxint + 12
        d%nglbv = 6 + 7*d%nmmat
        call static_words(d, mesh, head)
        d%head_words = size(head, kind=int64)
        d%state_words = 1 + d%nglbv + 6_int64*d%nnode + 7_int64*d%nsolid + 6_int64*d%nbeam + &
                        int(d%nv2d, int64)*d%nshell + d%nsolid + d%nshell + d%nbeam
        if (keep >= 0) then
            call cut_back(d, keep, ok)
            return
        end if
        call delete_members(d, 1)
        d%member = 0
        d%words = d%head_words
        d%in_member = 0
        open (newunit=d%u, file=base, access='stream', form='unformatted', status='replace', action='readwrite', &
              iostat=ios)
        if (ios == 0) write (d%u, iostat=ios) head
        if (ios == 0) flush (d%u, iostat=ios)
        ok = ios == 0
        if (.not. ok) call fail_member(d)
    end subroutine d3plot_open

    !> Control words, geometry and user ids of the first member.
    subroutine static_words(d, mesh, w)
        type(d3plot_t), intent(in) :: d
        type(d3plot_mesh_t), intent(in) :: mesh
        integer(int32), allocatable, intent(out) :: w(:)
        integer(int32) :: c(nhead)
        integer :: narbs, k, ngeo, p0, i
        character(len=40) :: title
        narbs = 16 + d%nnode + d%nsolid + d%nbeam + d%nshell + 3*d%nmmat
        c = 0
        title = mesh%title(1:40)
        do k = 1, 10
            c(k) = transfer(title(4*k - 3:4*k), c(k))
        end do
        c(11) = 0                      ! run time: none (equal runs, equal files)
        c(12) = 1                      ! file type: d3plot
        c(13) = 0                      ! source version
        c(14) = transfer('xdyn', c(14))   ! release
        c(15) = transfer(971.0_real32, c(15))   ! version (readers look for 900 to 1000)
        c(16) = 4                      ! NDIM: 3-D, connectivity unpacked
        c(17) = d%nnode                ! NUMNP
        c(18) = 6                      ! ICODE: LS-DYNA 3-D
        c(19) = d%nglbv                ! NGLBV
        c(20) = 0                      ! IT: no temperatures
        c(21) = 1                      ! IU: coordinates
        c(22) = 1                      ! IV: velocities
        c(23) = 0                      ! IA: no accelerations
        c(24) = d%nsolid               ! NEL8
        c(25) = mesh%nmat_solid        ! NUMMAT8
        c(28) = 7                      ! NV3D: six stresses and the plastic strain
        c(29) = d%nbeam                ! NEL2: beams
        c(30) = mesh%nmat_beam         ! NUMMAT2
        c(31) = 6                      ! NV1D
        c(32) = d%nshell               ! NEL4
        c(33) = mesh%nmat_shell        ! NUMMAT4
        c(34) = d%nv2d                 ! NV2D
        c(35) = 0                      ! NEIPH
        c(36) = 0                      ! NEIPS
        c(37) = -(10000 + d%maxint)    ! MAXINT, with element deletion flags (MDLOPT 2)
        c(40) = narbs                  ! NARBS
        c(41) = 0                      ! NELT: no thick shells
        c(44:47) = 1000                ! IOSHL: stresses, plastic strain, resultants, thickness
        c(52) = d%nmmat                ! NMMAT
        ! geometry: coordinates, hexahedra (8 nodes, material), shells (4, material)
        ngeo = 3*d%nnode + 9*d%nsolid + 6*d%nbeam + 5*d%nshell
        allocate (w(nhead + ngeo + narbs + 3 + 19*d%nmmat + 19))
        w(1:nhead) = c
        k = nhead
        w(k + 1:k + 3*d%nnode) = transfer(reshape(mesh%x0, [3*d%nnode]), w(1:1), 3*d%nnode)
        k = k + 3*d%nnode
        do i = 1, d%nsolid
            w(k + 1:k + 8) = mesh%solid_conn(:, i)
            w(k + 9) = mesh%solid_mat(i)
            k = k + 9
        end do
        ! beams: N1 N2, the orientation node, two unused words, material
        do i = 1, d%nbeam
            w(k + 1:k + 3) = mesh%beam_conn(:, i)
            w(k + 4:k + 5) = 0
            w(k + 6) = mesh%beam_mat(i)
            k = k + 6
        end do
        do i = 1, d%nshell
            w(k + 1:k + 4) = mesh%shell_conn(:, i)
            w(k + 5) = mesh%shell_mat(i)
            k = k + 5
        end do
        ! user ids: ten words of pointers (1-based word addresses in the
        ! member) and counts, six more for the materials, then the ids
        p0 = k + 16 + 1
        w(k + 1) = -p0                             ! NSORT (< 0: material ids follow)
        w(k + 2) = p0 + d%nnode                    ! NSRH
        w(k + 3) = p0 + d%nnode + d%nsolid         ! NSRB
        w(k + 4) = w(k + 3) + d%nbeam              ! NSRS
        w(k + 5) = w(k + 4) + d%nshell             ! NSRT
        w(k + 6) = d%nnode                         ! NSORTD
        w(k + 7) = d%nsolid                        ! NSRHD
        w(k + 8) = d%nbeam                         ! NSRBD
        w(k + 9) = d%nshell                        ! NSRSD
        w(k + 10) = 0                              ! NSRTD
        w(k + 11) = w(k + 5)                       ! NSRMA
        w(k + 12) = w(k + 11) + d%nmmat            ! NSRMU
        w(k + 13) = w(k + 12) + d%nmmat            ! NSRMP
        w(k + 14) = d%nmmat                        ! NSRTM
        w(k + 15) = mesh%nrigid                    ! NUMRBS
        w(k + 16) = d%nmmat                        ! NMMAT
        k = k + 16
        w(k + 1:k + d%nnode) = mesh%node_id
        k = k + d%nnode
        w(k + 1:k + d%nsolid) = mesh%solid_id
        k = k + d%nsolid
        if (d%nbeam > 0) w(k + 1:k + d%nbeam) = mesh%beam_id
        k = k + d%nbeam
        w(k + 1:k + d%nshell) = mesh%shell_id
        k = k + d%nshell
        w(k + 1:k + d%nmmat) = mesh%part_id          ! sorted as numbered
        k = k + d%nmmat
        w(k + 1:k + d%nmmat) = mesh%part_id          ! in the deck's order (the same)
        k = k + d%nmmat
        w(k + 1:k + d%nmmat) = [(i, i=1, d%nmmat)]   ! the order: identity
        k = k + d%nmmat
        ! the end of the geometry, then the titles: parts (90001), run (90000)
        w(k + 1) = transfer(eof_marker, w(1))
        w(k + 2) = 90001
        w(k + 3) = d%nmmat
        k = k + 3
        do i = 1, d%nmmat
            w(k + 1) = mesh%part_id(i)
            w(k + 2:k + 19) = chars72(mesh%part_title(i))
            k = k + 19
        end do
        w(k + 1) = 90000
        w(k + 2:k + 19) = chars72(mesh%title)
    contains
        !> 72 characters (blank-filled) as 18 words.
        function chars72(text) result(c18)
            character(len=*), intent(in) :: text
            integer(int32) :: c18(18)
            character(len=72) :: t
            integer :: j
            t = text
            do j = 1, 18
                c18(j) = transfer(t(4*j - 3:4*j), c18(j))
            end do
        end function chars72
    end subroutine static_words

    !> One state, written in parts in the state's order: its time, the
    !> NGLBV global variables, the nodes' coordinates and velocities, the
    !> solids' (7 words each), beams' (6), shells' (NV2D) and the elements'
    !> deletion flags (hexahedra first). In parts, so
    !> that no writer holds a whole state's record (issue 32: the shells'
    !> words of a 250,000-shell plate at NIP 5 are 47 MB, which rank 0 and
    !> the serial run held at once): d3plot_begin_state, then d3plot_put of
    !> each part, then d3plot_end_state, which checks that the parts made a
    !> whole state and that the member holds it.
    subroutine d3plot_begin_state(d, time)
        type(d3plot_t), intent(inout) :: d
        real(kind(1.0d0)), intent(in) :: time
        d%put_words = 0
        if (.not. d%on .or. d%failed) return
        call next_member(d)
        call d3plot_put(d, [real(time, real32)], 1)
    end subroutine d3plot_begin_state

    !> The next part of a state (d3plot_begin_state).
    subroutine d3plot_put(d, w, n)
        type(d3plot_t), intent(inout) :: d
        !> n words (an array of any shape, in its order: no copy)
        real(real32), intent(in) :: w(*)
        integer, intent(in) :: n
        integer :: ios
        if (.not. d%on .or. d%failed) return
        if (n == 0) return
        write (d%u, pos=4*(d%words + d%put_words) + 1, iostat=ios) w(1:n)
        if (ios /= 0) then
            call fail_member(d)
            return
        end if
        d%put_words = d%put_words + n
    end subroutine d3plot_put

    !> The state's parts all put (d3plot_begin_state): flushed and counted.
    subroutine d3plot_end_state(d)
        type(d3plot_t), intent(inout) :: d
        integer :: ios
        integer(int64) :: sz
        if (.not. d%on .or. d%failed) return
        if (d%put_words /= d%state_words) error stop 'd3plot_end_state: the parts put are not a whole state'
        flush (d%u, iostat=ios)
        ! (and the file as long as the words put: a write cut short by a
        ! file-size limit or a full disk had passed unseen, a state counted
        ! that the member held only in part)
        if (ios == 0) inquire (unit=d%u, size=sz, iostat=ios)
        if (ios == 0 .and. sz < 4*(d%words + d%state_words)) ios = -1
        if (ios /= 0) then
            call fail_member(d)
            return
        end if
        d%words = d%words + d%state_words
        d%in_member = d%in_member + 1
    end subroutine d3plot_end_state

    !> Where the next state goes: a new member where the open one is full
    !> (member_full), the last ending with the marker.
    subroutine next_member(d)
        type(d3plot_t), intent(inout) :: d
        integer :: ios
        if (member_full(d)) then
            ! the next member; this one ends with the marker (the first
            ! has it before its titles)
            ios = 0
            if (d%member > 0) write (d%u, pos=4*d%words + 1, iostat=ios) eof_marker
            if (ios == 0) close (d%u, iostat=ios)
            if (ios /= 0) then
                call fail_member(d)
                return
            end if
            d%member = d%member + 1
            d%words = 0
            d%in_member = 0
            open (newunit=d%u, file=d3plot_member_name(d%base, d%member), access='stream', form='unformatted', &
                  status='replace', action='readwrite', iostat=ios)
            if (ios /= 0) then
                call fail_member(d)
                return
            end if
        end if
    end subroutine next_member

    subroutine d3plot_close(d)
        type(d3plot_t), intent(inout) :: d
        integer :: ios
        if (d%u /= -1) close (d%u, iostat=ios)
        d%u = -1
    end subroutine d3plot_close

    !> The next state opens a new member: the open one is the first (the
    !> geometry and titles alone), or the state would take it, which holds
    !> states already, past the limit (a member holds one state at least).
    pure logical function member_full(d)
        type(d3plot_t), intent(in) :: d
        member_full = d%member == 0 .or. (d%in_member > 0 .and. d%words + d%state_words > d%limit)
    end function member_full

    !> A write to the open member failed: no more states, the member named
    !> and cut back to its complete states (a state cut short by a full
    !> disk is not left at its end).
    subroutine fail_member(d)
        type(d3plot_t), intent(inout) :: d
        integer :: ios
        logical :: ok
        d%failed = .true.
        d%failed_file = d3plot_member_name(d%base, d%member)
        if (d%u /= -1) then
            close (d%u, iostat=ios)
            d%u = -1
            call truncate_file(d%failed_file, 4*int(d%words, i8), ok)
        end if
    end subroutine fail_member

    !> A restart: the members as the first `keep` states left them (the
    !> writer's rule replayed: a state opens a new member when it would take
    !> a member holding states past the limit), the states after them
    !> dropped, the last member reopened for more.
    subroutine cut_back(d, keep, ok)
        type(d3plot_t), intent(inout) :: d
        integer, intent(in) :: keep
        logical, intent(out) :: ok
        integer :: k, ios
        d%member = 0
        d%words = d%head_words
        d%in_member = 0
        do k = 1, keep
            if (member_full(d)) then
                d%member = d%member + 1
                d%words = 0
                d%in_member = 0
            end if
            d%words = d%words + d%state_words
            d%in_member = d%in_member + 1
        end do
        call delete_members(d, d%member + 1)
        call truncate_file(d3plot_member_name(d%base, d%member), 4*int(d%words, i8), ok)
        if (ok) then
            open (newunit=d%u, file=d3plot_member_name(d%base, d%member), access='stream', form='unformatted', &
                  status='old', action='readwrite', iostat=ios)
            ok = ios == 0
        end if
        if (.not. ok) call fail_member(d)
    end subroutine cut_back

    !> Delete members from `first` on (those of an earlier run in the same place).
    subroutine delete_members(d, first)
        type(d3plot_t), intent(in) :: d
        integer, intent(in) :: first
        integer :: k
        logical :: there
        k = max(first, 1)
        do
            inquire (file=d3plot_member_name(d%base, k), exist=there)
            if (.not. there) exit
            call delete_file(d3plot_member_name(d%base, k))
            k = k + 1
        end do
    end subroutine delete_members

end module xd_output_d3plot
