!> The model as read from the deck: nodes, elements, parts, sections,
!> materials, sets, conditions, controls and output requests. Ids are the
!> user's until the model check resolves them to indices (`*_ix` fields).
module xd_model
    use xd_kinds, only: wp, dp, i8
    use xd_core_memory, only: fit, nbytes
    implicit none
    private
    public :: model_t, part_t, section_solid_t, section_shell_t, material_t, hourglass_t, set_t
    public :: spc_t, init_vel_t, init_stress_t, controls_t, database_t, history_request_t
    public :: curve_t, body_load_t, rigidwall_t, prescribed_t, nodal_rigid_t, segment_set_t, pressure_t, curve_value
    public :: box_t, find_box, in_box, coord_t, find_coord, mark_part_nodes
    public :: mat_elastic, mat_plastic_kinematic, mat_rigid, mat_piecewise_linear, mat_spotweld
    public :: set_node, set_part, set_shell, find_set, constraint_dirs, part_ihq, hg_bounded, hg_boundable
    public :: can_erode, any_erosion
    public :: iv_node_set, iv_node, iv_generation
    public :: mesh_fit, mesh_bytes, release_setup_mesh, release_shell_thickness, shell_thickness
    public :: contact_t, contact_controls_t, ct_single, ct_surface_to_surface, ct_general, ct_nodes_to_surface
    public :: ct_tied_nodes, ct_tied_shell_edge, ct_tied_surface, ct_tiebreak, section_beam_t
    public :: extra_nodes_t, point_mass_t, part_mass_t, search_auto, search_fixed, search_adaptive, mnl_minimal, &
              mnl_closest1, mnl_closest3
    public :: styp_segment_set, styp_shell_set, styp_part_set, styp_part, styp_node_set, styp_all, styp_all_but

    integer, parameter :: mat_elastic = 1, mat_plastic_kinematic = 3, mat_rigid = 20, &
                          mat_piecewise_linear = 24, mat_spotweld = 100
    integer, parameter :: set_node = 1, set_part = 2, set_shell = 3
    integer, parameter :: iv_node_set = 1, iv_node = 2, iv_generation = 3

    type :: part_t
        integer :: id = 0
        character(len=70) :: heading = ''
        integer :: secid = 0, mid = 0, hgid = 0
        integer :: sec_ix = 0, mat_ix = 0, hg_ix = 0
        integer :: shell_sec_ix = 0         !< the section is a *SECTION_SHELL
        integer :: beam_sec_ix = 0          !< the section is a *SECTION_BEAM
        integer :: src = 0                  !< deck line of its card
        !> *PART_INERTIA (rigid parts): mass, centre (or node), global inertia
        !> tensor about the centre, initial velocities of the body
        logical :: inertia = .false.
        real(wp) :: tm = 0, xc(3) = 0, itens(6) = 0, vt(3) = 0, vr(3) = 0
        integer :: nodeid = 0
    end type part_t

    type :: section_solid_t
        integer :: id = 0
        integer :: elform = 1
        integer :: src = 0
    end type section_solid_t

    type :: section_shell_t
        integer :: id = 0
        integer :: elform = 2
        real(wp) :: shrf = 1.0_wp           !< transverse shear factor
        integer :: nip = 2                  !< through-thickness points
        real(wp) :: t(4) = 0                !< nodal thicknesses
        integer :: src = 0
    end type section_shell_t

    !> *SECTION_BEAM: ELFORM 2 (Belytschko-Schwer resultant) with A, ISS,
    !> ITT, J, SA; ELFORM 1 (Hughes-Liu) with the section's dimensions, from
    !> which the same properties are computed (elastic only)
    type :: section_beam_t
        integer :: id = 0
        integer :: elform = 2
        real(wp) :: shrf = 1.0_wp
        integer :: cst = 0                  !< ELFORM 1: 0 rectangle, 1 tube
        integer :: qr = 2                   !< ELFORM 1: the section's quadrature rule (QR)
        real(wp) :: ts = 0, tt = 0          !< ELFORM 1 and 9: TS1 and TT1 (a tube's outer and inner diameters)
        real(wp) :: a = 0, iss = 0, itt = 0, j = 0, sa = 0
        real(wp) :: nsm = 0                 !< non-structural mass per length
        !> ELFORM 1: the plastic section moduli about s and t and the torque's
        !> (times the yield stress, resp. the shear yield: the fully plastic
        !> resultants)
        real(wp) :: zs = 0, zt = 0, zj = 0
        integer :: src = 0
    end type section_beam_t

    type :: material_t
        integer :: id = 0
        integer :: mtype = 0                !< LS-DYNA material number (1, 3, 20, 24)
        character(len=40) :: keyword = ''
        real(wp) :: ro = 0, e = 0, pr = 0
        ! plasticity (003, 024)
        real(wp) :: sigy = 0, etan = 0, beta = 1
        real(wp) :: c = 0, p = 0              !< Cowper-Symonds (003: SRC, SRP)
        integer :: lcss = 0, lcss_ix = 0      !< 024: yield curve
        integer :: cmo = 0, con1 = 0, con2 = 0   !< 020: rigid body constraints (CMO 1: global codes)
        integer :: ntab = 0                   !< 024: EPS/ES points given
        real(wp) :: eps(8) = 0, es(8) = 0
        integer :: src = 0
        ! failure and erosion (shells): FAIL of 003 (FS) and 024, and
        ! *MAT_ADD_EROSION's criteria (0: not used)
        real(wp) :: fail = 0                  !< effective plastic strain at failure
        real(wp) :: mxpres = 0, mnpres = 0    !< pressure above / (negative) below which a point fails
        real(wp) :: sigp1 = 0, sigvm = 0      !< maximum principal and von Mises stress
        !> the strain criteria (logarithmic strains; 0: not used): the
        !> smallest and the largest principal strain, the effective strain
        !> sqrt(2/3 e':e'), the volumetric strain (its sign the side), the
        !> largest tensorial shear strain (e1 - e3) / 2
        real(wp) :: mneps = 0, mxeps = 0, effeps = 0, voleps = 0, epssh = 0
        real(wp) :: failtm = 0                !< failure time
        integer :: numfip = 0                 !< failed points that erode a shell (0: all, FAIL alone)
        integer :: ncs = 1                    !< criteria a point must meet together
        logical :: erosion = .false.          !< *MAT_ADD_EROSION given
        integer :: add_src = 0
        !> *MAT_SPOTWELD: TFAIL and the resultants at failure NRR NRS NRT MRR
        !> MSS MTT (0: not in the criterion)
        real(wp) :: tfail = 0, rfail(6) = 0
        !> *MAT_SPOTWELD: the plastic hardening modulus EH (sigma_y = SIGY +
        !> EH eps_p) and the plastic strain at failure EFAIL (0: none)
        real(wp) :: eh = 0, efail = 0
    end type material_t

    type :: hourglass_t
        integer :: id = 0
        integer :: ihq = 0                  !< 0: take *CONTROL_HOURGLASS
        real(wp) :: qm = 0.1_wp
        real(wp) :: q1 = 1.5_wp, q2 = 0.06_wp
        !> shells: bending (QB) and warping (QW) coefficients; 0: QM
        real(wp) :: qb = 0, qw = 0
        integer :: src = 0
    end type hourglass_t

    !> Node or part set; `member` holds ids, `member_ix` indices once checked.
    type :: set_t
        integer :: id = 0
        integer :: kind = 0
        integer :: n = 0
        integer, allocatable :: member(:)
        integer, allocatable :: member_ix(:)
        integer :: src = 0
        !> _GENERAL: rules (OPTION, up to 7 values) resolved once the model
        !> is read; _ADD: `rule_val` holds the sets whose union this is
        integer :: nrule = 0
        character(len=10), allocatable :: rule_op(:)
        integer, allocatable :: rule_val(:, :)
        integer, allocatable :: rule_line(:)
        logical :: add = .false.
    end type set_t

    !> Constraint on a node (is_set false) or on a node set.
    type :: spc_t
        integer :: id = 0
        logical :: is_set = .false.
        integer :: ix = 0                   !< node index once checked
        integer :: dof(6) = 0               !< 1: that degree of freedom is fixed
        integer :: cid = 0                  !< local axes (mapped onto global ones when checked)
        integer :: src = 0
    end type spc_t

    type :: init_vel_t
        integer :: kind = 0                 !< iv_node_set, iv_node, iv_generation
        integer :: id = 0                   !< node set, node, or part/part set/node set
        integer :: ix = 0                   !< node index once checked (iv_node)
        integer :: exempt = 0               !< NSIDEX: node set left out
        integer :: boxid = 0                !< BOXID: only the nodes in this box
        integer :: icid = 0                 !< velocities given in these local axes (turned global when checked)
        integer :: styp = 0                 !< generation: 1 part set, 2 part, 3 node set
        real(wp) :: v(3) = 0, vr(3) = 0
        real(wp) :: omega = 0
        real(wp) :: xc(3) = 0, axis(3) = 0
        integer :: src = 0
    end type init_vel_t

    type :: init_stress_t
        integer :: eid = 0
        real(wp) :: sig(6) = 0              !< xx yy zz xy yz zx
        integer :: src = 0
    end type init_stress_t

    !> *DEFINE_CURVE, offsets and scales applied: abscissa a, ordinate o.
    type :: curve_t
        integer :: id = 0
        integer :: n = 0
        real(wp), allocatable :: a(:), o(:)
        integer :: src = 0
    end type curve_t

    !> *LOAD_BODY_X/Y/Z: base acceleration sf * curve(t) along axis `dir`,
    !> loading in the negative axis direction (LS-DYNA's sign).
    type :: body_load_t
        integer :: dir = 0
        integer :: cid = 0                  !< local axes: the load acts along their axis `dir`
        real(wp) :: d(3) = 0                !< the direction, global (set when checked)
        integer :: lcid = 0, curve_ix = 0
        real(wp) :: sf = 1.0_wp
        integer :: src = 0
    end type body_load_t

    !> *BOUNDARY_PRESCRIBED_MOTION_NODE/_SET: translation DOF 1-3 of a node or
    !> node set follows sf * curve as velocity (vad 0), acceleration (1) or
    !> displacement (2) between birth and death.
    type :: prescribed_t
        integer :: id = 0
        logical :: is_set = .false.
        logical :: rigid = .false.          !< _RIGID: id is a *MAT_RIGID part
        integer :: ix = 0                   !< node index (not a set) or part index (rigid), once checked
        integer :: dof = 0, vad = 0
        integer :: lcid = 0, curve_ix = 0
        real(wp) :: sf = 1.0_wp
        real(wp) :: birth = 0, death = 1.0e28_wp
        integer :: src = 0
    end type prescribed_t

    !> *SET_SEGMENT: segments N1..N4 (node ids, then indices once checked).
    type :: segment_set_t
        integer :: id = 0
        integer :: n = 0
        integer, allocatable :: seg(:, :)   !< (4, n)
        integer :: src = 0
        !> *SET_SEGMENT_GENERAL: OPTION E1..E7 cards, resolved with the model
        integer :: nrule = 0
        character(len=10), allocatable :: rule_op(:)
        integer, allocatable :: rule_val(:, :)
        integer, allocatable :: rule_line(:)
    end type segment_set_t

    !> *LOAD_SEGMENT (one segment) or *LOAD_SEGMENT_SET: pressure sf * curve(t - at)
    !> from t = at on, pushing against the segment normal (N1..N4 right-handed).
    type :: pressure_t
        integer :: ssid = 0                 !< segment set, or 0 for the segment below
        integer :: shell_eid = 0            !< *LOAD_SHELL_ELEMENT: the shell (replaced by seg once checked)
        integer :: shell_set = 0            !< *LOAD_SHELL_SET: the shell set (expanded once checked)
        integer :: seg(4) = 0
        integer :: lcid = 0, curve_ix = 0
        real(wp) :: sf = 1.0_wp, at = 0.0_wp
        integer :: src = 0
    end type pressure_t

    !> *CONSTRAINED_NODAL_RIGID_BODY (a node set moving as one rigid body) and
    !> *CONSTRAINED_GENERALIZED_WELD_SPOT (the same, until it fails at tfail).
    type :: nodal_rigid_t
        integer :: id = 0
        integer :: nsid = 0
        logical :: weld = .false.
        real(wp) :: tfail = 1.0e20_wp
        integer :: src = 0
        !> _INERTIA: the body's mass, centre (or node), global inertia tensor
        !> (IXX IXY IXZ IYY IYZ IZZ) and initial velocities, as the deck gives
        logical :: inertia = .false.
        real(wp) :: tm = 0, xc(3) = 0, itens(6) = 0, vt(3) = 0, vr(3) = 0
        integer :: nodeid = 0
    end type nodal_rigid_t

    !> *ELEMENT_MASS: a point mass on a node (its index once checked)
    type :: point_mass_t
        integer :: eid = 0
        integer :: nid = 0
        integer :: ix = 0
        real(wp) :: mass = 0
        integer :: src = 0
        !> *ELEMENT_MASS_NODE_SET: NID is a node set, MASS shared equally
        !> among its nodes (expanded into one point mass a node when checked)
        logical :: set = .false.
    end type point_mass_t

    !> *ELEMENT_MASS_PART / _PART_SET: mass added to a part's nodes in
    !> proportion to the part's own nodal masses, ADDMASS or enough to make
    !> the part FINMASS
    type :: part_mass_t
        integer :: id = 0                 !< PID, or PSID for _PART_SET
        logical :: set = .false.
        real(wp) :: addmass = 0, finmass = 0
        integer, allocatable :: part_ix(:)   !< the parts, once checked
        integer :: src = 0
    end type part_mass_t

    !> *CONSTRAINED_EXTRA_NODES_NODE / _SET: nodes (or a node set) joined to
    !> the rigid body of part PID (IFLAG: with *PART_INERTIA, whether the
    !> nodes' masses add to the deck's properties)
    type :: extra_nodes_t
        integer :: pid = 0
        integer :: id = 0                   !< node id (_NODE) or node set id (_SET)
        logical :: set = .false.
        integer :: iflag = 0
        integer :: src = 0
        integer :: part_ix = 0
        integer, allocatable :: node_ix(:)
    end type extra_nodes_t

    !> *RIGIDWALL_PLANAR: a stonewall through `tail` with unit normal `normal`
    !> (towards the side the nodes are on); finite walls have in-plane axes
    !> `l`, `m` with lengths lenl, lenm from the tail.
    type :: rigidwall_t
        integer :: id = 0
        character(len=70) :: heading = ''
        integer :: nsid = 0, nsidex = 0, boxid = 0
        real(wp) :: offset = 0               !< > 0: only nodes within OFFSET of the wall at t = 0
        real(wp) :: birth = 0, death = 1.0e20_wp
        real(wp) :: tail(3) = 0, normal(3) = 0
        real(wp) :: fric = 0
        logical :: finite = .false.
        real(wp) :: l(3) = 0, m(3) = 0, lenl = 0, lenm = 0
        logical :: moving = .false.          !< _MOVING: a wall of `mass` moving along its normal
        real(wp) :: mass = 0, v0 = 0
        logical :: cylinder = .false.        !< *RIGIDWALL_GEOMETRIC_CYLINDER: nodes stay outside
        real(wp) :: radius = 0, length = 0   !< cylinder: axis from tail along `normal`; length 0: infinite both ways
        logical :: forces = .false.          !< _FORCES: the optional force-segment card was given
        integer :: src = 0
    end type rigidwall_t

    !> *DEFINE_COORDINATE_SYSTEM (three points) or _NODES (three nodes at
    !> t = 0): r(:, k) is local axis k in global components.
    type :: coord_t
        integer :: id = 0
        logical :: by_nodes = .false.
        real(wp) :: o(3) = 0, l(3) = 0, p(3) = 0   !< origin, a point on local x, a point in the x-y plane
        integer :: n(3) = 0                        !< _NODES: N1 N2 N3 (ids, then indices)
        real(wp) :: r(3, 3) = 0
        integer :: src = 0
    end type coord_t

    !> *DEFINE_BOX: an axis-aligned box.
    type :: box_t
        integer :: id = 0
        real(wp) :: lo(3) = 0, hi(3) = 0
        integer :: src = 0
    end type box_t

    !> Contact variants: every one runs the same automatic algorithm; they
    !> differ in which nodes are slaves and which segments masters.
    integer, parameter :: ct_single = 1, ct_surface_to_surface = 2, ct_general = 3, ct_nodes_to_surface = 4
    !> tied contacts (*CONTACT_TIED_...): slave nodes held on the master
    !> surface, translations (nodes, surface) or translations and rotations
    !> (shell edge)
    integer, parameter :: ct_tied_nodes = 11, ct_tied_shell_edge = 12, ct_tied_surface = 13
    !> the tie of a *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK (its
    !> sliding contact is a ct_surface_to_surface beside it)
    integer, parameter :: ct_tiebreak = 14
    !> SSTYP / MSTYP codes of the contact cards.
    integer, parameter :: styp_segment_set = 0, styp_shell_set = 1, styp_part_set = 2, styp_part = 3, &
                          styp_node_set = 4, styp_all = 5, styp_all_but = 6
    !> Global search interval policy: auto (SEARCH 0, the default) searches
    !> when the motion could have used up the pool margin (4u > delta), or
    !> at the interval a deck gives (NSRCH, NSBCS, BSORT) at the longest;
    !> fixed (1) also at most every 100 cycles when none is given; adaptive
    !> (2) on the motion alone.
    integer, parameter :: search_auto = 0, search_fixed = 1, search_adaptive = 2
    integer, parameter :: mnl_minimal = 0, mnl_closest1 = 1, mnl_closest3 = 3

    !> *CONTACT_...: cards 1-3 and optional card A.
    type :: contact_t
        integer :: id = 0
        character(len=70) :: heading = ''
        character(len=48) :: keyword = ''
        integer :: kind = ct_single
        integer :: ssid = 0, msid = 0, sstyp = 0, mstyp = 0
        integer :: sboxid = 0, mboxid = 0        !< only slave (master) nodes and segments inside these boxes at t = 0
        integer :: sref = 0, mref = 0            !< index of the set, segment set or part once checked
        real(wp) :: fs = 0, fd = 0, dc = 0, vc = 0, vdc = 0
        real(wp) :: bt = 0, dt = 1.0e20_wp      !< birth and death times
        real(wp) :: sfs = 1, sfm = 1             !< penalty scale, slave and master side
        real(wp) :: sst = 0, mst = 0             !< shell thickness overrides (0: true thickness)
        real(wp) :: sfst = 1, sfmt = 1           !< shell thickness scale factors
        integer :: bsort = 0                     !< cycles between global searches (0: control value)
        !> optional card B PENMAX: a contact deeper than PENMAX times the
        !> segment's thickness is released (0: xdyna's own window, below)
        real(wp) :: penmax = 0
        !> optional card C IGNORE: 0 takes *CONTROL_CONTACT's; 1 tracks
        !> initial penetrations, 2 tracks them and names the coordinates
        !> that would remove them
        integer :: ignore = 0
        !> *CONTACT_TIED_..._OFFSET / _BEAM_OFFSET: the slave kept at its gap
        logical :: tied_offset = .false.
        !> *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK card 4: OPTION (0:
        !> no tiebreak), the normal and shear failure stresses NFLS, SFLS (0:
        !> no failure in that mode) and PARAM (OPTION 2: the separation over
        !> which the stress falls to zero)
        integer :: tb_option = 0
        real(wp) :: nfls = 0, sfls = 0, tb_param = 0
        !> OPTION 9 (the cohesive law): GIC, GIIC (ERATEN, ERATES), the
        !> tangential over the normal stiffness (CT2CN) and the normal
        !> stiffness CN (stress per length)
        real(wp) :: tb_gic = 0, tb_giic = 0, tb_ct2cn = 0, tb_cn = 0
        integer :: src = 0
        character(len=200) :: at = ''            !< 'file:line' of card 1, for set-up errors
    end type contact_t

    !> *CONTROL_CONTACT and *CONTROL_XDYNA_CONTACT.
    type :: contact_controls_t
        real(wp) :: slsfac = 0.1_wp               !< penalty scale for every interface
        integer :: nsbcs = 0                      !< cycles between global searches (0: 10)
        !> SSTHK of *CONTROL_CONTACT: 0, a single-surface contact's shell
        !> thickness is limited to 40% of the element's shortest edge (unless
        !> SST/MST give it); 1, the shell's own thickness
        integer :: ssthk = 0
        !> THKCHG: 1, a single-surface (or general) contact's shell
        !> thickness follows the shells' (with *CONTROL_SHELL ISTUPD)
        integer :: thkchg = 0
        !> IGNORE of card 4: 0 moves slave nodes out of initial penetrations
        !> at t = 0 (LS-DYNA's default); 1 tracks them (allowed, shrinking
        !> as the nodes move out); 2 tracks them and names the coordinates
        !> that would remove them
        integer :: ignore = 0
        integer :: search = search_auto           !< interval policy
        integer :: nsrch = 0                      !< fixed interval from *CONTROL_XDYNA_CONTACT (0: NSBCS)
        integer :: mnl = mnl_minimal              !< master node list policy
        logical :: tracking = .true., screens = .true.
        logical :: lagrange = .false.             !< enforcement: penalty or Lagrangian projection
        real(wp) :: pmarg = 0.5_wp                !< pool margin / median characteristic length
        integer :: dump_nsid = 0                  !< node set whose master node lists are dumped
    end type contact_controls_t

    type :: controls_t
        real(wp) :: endtim = 0
        integer :: endcyc = 0
        real(wp) :: dtmin = 0
        !> *CONTROL_TIMESTEP ERODE 1: shells whose step falls below DTMIN
        !> times the first erode (instead of the run stopping)
        integer :: erode = 0
        real(wp) :: endeng = 0
        real(wp) :: dtinit = 0
        real(wp) :: tssfac = 0.9_wp
        !> *CONTROL_TIMESTEP ISDO, the shells' step length: 0 area over the
        !> longest side, 1 over the longest diagonal (triangles: the shortest
        !> altitude for both), 2 the larger of the shortest side and area over
        !> the longest side with the bar wave speed (triangles: the shortest side)
        integer :: isdo = 0
        real(wp) :: tslimt = 0
        real(wp) :: dt2ms = 0               !< *CONTROL_TIMESTEP: mass scaling (< 0: only where needed)
        integer :: ms1st = 0                !< mass scaling at the first cycle only
        real(wp) :: endmas = 0              !< *CONTROL_TERMINATION: stop when the added mass passes this percent
        integer :: ihq = 1
        real(wp) :: qh = 0.1_wp
        real(wp) :: q1 = 1.5_wp, q2 = 0.06_wp
        integer :: hgen = 1, rwen = 2, slnten = 1, rylen = 1
        integer :: istupd = 0               !< *CONTROL_SHELL: shell thickness follows the strain
        !> *CONTROL_XDYNA_SHELL HGBOUND: the stiffness-form hourglass of plastic shells bounded
        !> by the modes' plastic capacity (1, the default; 0: elastic springs without limit)
        integer :: hgbound = 1
        !> HGBOUND was given in the deck (a 1 that acts nowhere is then warned)
        logical :: hgbound_given = .false.
        !> *CONTROL_UNITS: indices in xd_output_units' lists of length, time
        !> and mass units (0: not given)
        integer :: unit_l = 0, unit_t = 0, unit_m = 0
        logical :: termination_given = .false.
        type(contact_controls_t) :: contact
    end type controls_t

    type :: history_request_t
        real(wp) :: dt = 0
        integer :: binary = 0
        logical :: on = .false.
    end type history_request_t

    type :: database_t
        type(history_request_t) :: glstat, matsum, nodout, rwforc, rcforc
        real(wp) :: d3plot_dt = 0
        integer :: d3plot_npltc = 0
        logical :: d3plot_binary = .true.        !< the LS-DYNA d3plot family (*CONTROL_XDYNA_OUTPUT BINARY)
        logical :: d3plot_h5 = .false.           !< d3plot.h5 + d3plot.xdmf (*CONTROL_XDYNA_OUTPUT HDF5)
        integer(i8) :: d3plot_x = 7              !< d3plot member size in 262,144 words (*CONTROL_XDYNA_OUTPUT X)
        integer :: d3dump = -1                   !< *DATABASE_BINARY_D3DUMP cycles between dumps (0: only at
                                                 !< the end; -1: not asked for)
        integer, allocatable :: hist_node(:)     !< node ids for nodout
        integer, allocatable :: hist_node_ix(:)
        integer, allocatable :: hist_set(:)      !< node set ids for nodout
    end type database_t

    type :: model_t
        character(len=80) :: title = ''
        character(len=:), allocatable :: deck_path
        ! nodes, structure of arrays
        integer :: nnode = 0
        integer, allocatable :: node_id(:)
        real(wp), allocatable :: x0(:, :)        !< (3, nnode)
        integer, allocatable :: node_tc(:), node_rc(:)
        integer, allocatable :: node_src(:)
        ! solid elements
        integer :: nhex = 0
        integer, allocatable :: hex_id(:)
        integer, allocatable :: hex_pid(:)       !< part id as read
        integer, allocatable :: hex_part(:)      !< part index once checked
        integer, allocatable :: hex_conn(:, :)   !< (8, nhex) node ids, then indices
        integer, allocatable :: hex_src(:)
        ! shell elements
        integer :: nshell = 0
        integer, allocatable :: shell_id(:), shell_pid(:), shell_part(:)
        integer, allocatable :: shell_conn(:, :)     !< (4, nshell) node ids, then indices; N3 = N4: triangle
        real(wp), allocatable :: shell_t(:, :)       !< (4, nshell) thickness from the element card, 0: section's
        !> (nshell) the mean of the four, once the set-up is done and
        !> shell_t released (release_setup_mesh): shell_thickness reads either
        real(wp), allocatable :: shell_tmean(:)
        integer, allocatable :: shell_src(:)
        integer :: nsec_shell = 0
        type(section_shell_t), allocatable :: sec_shell(:)
        integer :: nsec_beam = 0
        type(section_beam_t), allocatable :: sec_beam(:)
        !> *ELEMENT_BEAM: ids, parts, nodes N1 N2 and the orientation node N3
        !> (0: none; ids, then indices once checked)
        integer :: nbeam = 0
        integer, allocatable :: beam_id(:), beam_pid(:), beam_part(:), beam_src(:)
        integer, allocatable :: beam_conn(:, :)   !< (3, nbeam)
        ! tables
        integer :: npart = 0, nsec_solid = 0, nmat = 0, nhg = 0, nset = 0
        type(part_t), allocatable :: part(:)
        type(section_solid_t), allocatable :: sec_solid(:)
        type(material_t), allocatable :: mat(:)
        type(hourglass_t), allocatable :: hg(:)
        type(set_t), allocatable :: set(:)
        integer :: ncurve = 0, nbody = 0, nwall = 0, npresc = 0, nnrb = 0, nsegset = 0, npress = 0
        integer :: npmass = 0
        type(point_mass_t), allocatable :: pmass(:)
        type(part_mass_t), allocatable :: partmass(:)   !< *ELEMENT_MASS_PART(_SET)
        !> *MAT_ADD_EROSION cards as read (id: the MID), merged into their
        !> materials when checked
        type(material_t), allocatable :: erosion(:)
        type(segment_set_t), allocatable :: segset(:)
        type(pressure_t), allocatable :: press(:)
        type(nodal_rigid_t), allocatable :: nrb(:)
        integer :: nxn = 0
        type(extra_nodes_t), allocatable :: xn(:)
        type(prescribed_t), allocatable :: presc(:)
        type(curve_t), allocatable :: curve(:)
        type(body_load_t), allocatable :: body(:)
        type(rigidwall_t), allocatable :: wall(:)
        integer :: nbox = 0
        type(box_t), allocatable :: box(:)
        integer :: ncoord = 0
        type(coord_t), allocatable :: coord(:)
        integer :: ncontact = 0
        type(contact_t), allocatable :: contact(:)
        !> *CONTACT_TIED_...: read as the sliding contacts are (cards 1-3),
        !> held apart from them (no search, no penalty)
        integer :: ntied = 0
        type(contact_t), allocatable :: tied(:)
        integer :: nspc = 0, nivel = 0, nistress = 0
        type(spc_t), allocatable :: spc(:)
        type(init_vel_t), allocatable :: ivel(:)
        type(init_stress_t), allocatable :: istress(:)
        type(controls_t) :: ctl
        type(database_t) :: db
        logical :: irigid = .false.     !< an *INITIAL_VELOCITY card with IRIGID >= 1: nodal velocities
                                        !< override *PART_INERTIA's
        integer :: nwarn = 0
        character(len=:), allocatable :: warnings   !< newline-separated, for d3hsp
    end type model_t

contains

    !> The node and element cards' arrays cut to their counts once the deck
    !> is read (they grow by doubling while it is: up to twice the room,
    !> held on every rank for the whole run).
    subroutine mesh_fit(model)
        type(model_t), intent(inout) :: model
        call fit(model%node_id, model%nnode)
        call fit(model%x0, model%nnode)
        call fit(model%node_tc, model%nnode)
        call fit(model%node_rc, model%nnode)
        call fit(model%node_src, model%nnode)
        call fit(model%hex_id, model%nhex)
        call fit(model%hex_pid, model%nhex)
        call fit(model%hex_conn, model%nhex)
        call fit(model%hex_src, model%nhex)
        call fit(model%shell_id, model%nshell)
        call fit(model%shell_pid, model%nshell)
        call fit(model%shell_conn, model%nshell)
        call fit(model%shell_t, model%nshell)
        call fit(model%shell_src, model%nshell)
        call fit(model%beam_id, model%nbeam)
        call fit(model%beam_pid, model%nbeam)
        call fit(model%beam_conn, model%nbeam)
        call fit(model%beam_src, model%nbeam)
    end subroutine mesh_fit

    !> The shells' four nodal thicknesses, which only the set-up reads,
    !> replaced by their mean (the rigid shells' thickness in the states);
    !> issue 32: every rank holds the deck's arrays whole, and this was 24
    !> of their 92 bytes a shell, held through the set-up's peak. Once the
    !> set-up (contact and rigid bodies included) is done.
    subroutine release_shell_thickness(model)
        type(model_t), intent(inout) :: model
        integer :: e
        if (.not. allocated(model%shell_t)) return
        allocate (model%shell_tmean(model%nshell))
        do e = 1, model%nshell
            model%shell_tmean(e) = sum(model%shell_t(:, e))/4
        end do
        deallocate (model%shell_t)
    end subroutine release_shell_thickness

    !> Shell e's mean thickness (its element card's, or its section's).
    pure real(wp) function shell_thickness(model, e) result(t)
        type(model_t), intent(in) :: model
        integer, intent(in) :: e
        if (allocated(model%shell_t)) then
            t = sum(model%shell_t(:, e))/4
        else
            t = model%shell_tmean(e)
        end if
    end function shell_thickness

    !> The nodes' translational and rotational constraint codes, which only
    !> the set-up and d3hsp's model summary read (the nodes' degrees of
    !> freedom keep them), released once both are done: 8 of the deck's 48
    !> bytes a node.
    subroutine release_setup_mesh(model)
        type(model_t), intent(inout) :: model
        if (allocated(model%node_tc)) deallocate (model%node_tc)
        if (allocated(model%node_rc)) deallocate (model%node_rc)
    end subroutine release_setup_mesh

    !> The bytes of the deck's node and element arrays (every rank holds
    !> them whole: the set-up reads them, the outputs' mesh and the rigid
    !> bodies' and contact's set-up take them).
    integer(i8) function mesh_bytes(model) result(b)
        type(model_t), intent(in) :: model
        b = nbytes(model%node_id) + nbytes(model%x0) + nbytes(model%node_tc) + nbytes(model%node_rc) &
            + nbytes(model%node_src) + nbytes(model%hex_id) + nbytes(model%hex_pid) + nbytes(model%hex_part) &
            + nbytes(model%hex_conn) + nbytes(model%hex_src) + nbytes(model%shell_id) + nbytes(model%shell_pid) &
            + nbytes(model%shell_part) + nbytes(model%shell_conn) + nbytes(model%shell_t) + nbytes(model%shell_src) &
            + nbytes(model%shell_tmean) &
            + nbytes(model%beam_id) + nbytes(model%beam_pid) + nbytes(model%beam_part) + nbytes(model%beam_conn) &
            + nbytes(model%beam_src)
    end function mesh_bytes

    !> Fixed directions of a deck constraint code 0-7 (none, x, y, z, xy, yz,
    !> zx, xyz): *NODE TC/RC, *MAT_RIGID CON1/CON2.
    pure function constraint_dirs(code) result(f)
        integer, intent(in) :: code
        logical :: f(3)
        f = .false.
        select case (code)
        case (1); f(1) = .true.
        case (2); f(2) = .true.
        case (3); f(3) = .true.
        case (4); f(1:2) = .true.
        case (5); f(2:3) = .true.
        case (6); f(1) = .true.; f(3) = .true.
        case (7); f = .true.
        end select
    end function constraint_dirs

    !> Part index p's hourglass type: its *HOURGLASS IHQ where given, else
    !> *CONTROL_HOURGLASS's.
    pure integer function part_ihq(model, p) result(ihq)
        type(model_t), intent(in) :: model
        integer, intent(in) :: p
        ihq = model%ctl%ihq
        if (model%part(p)%hg_ix > 0) then
            if (model%hg(model%part(p)%hg_ix)%ihq > 0) ihq = model%hg(model%part(p)%hg_ix)%ihq
        end if
    end function part_ihq

    !> Part index p's shells have what the hourglass bound acts on: the
    !> stiffness form (IHQ 4-5) on *MAT_003 or *MAT_024.
    pure logical function hg_boundable(model, p)
        type(model_t), intent(in) :: model
        integer, intent(in) :: p
        integer :: mt
        mt = model%mat(model%part(p)%mat_ix)%mtype
        hg_boundable = part_ihq(model, p) > 3 .and. (mt == mat_plastic_kinematic .or. mt == mat_piecewise_linear)
    end function hg_boundable

    !> Part index p's shells take the bounded stiffness-form hourglass
    !> (*CONTROL_XDYNA_SHELL HGBOUND 1, the default).
    pure logical function hg_bounded(model, p)
        type(model_t), intent(in) :: model
        integer, intent(in) :: p
        hg_bounded = model%ctl%hgbound == 1 .and. hg_boundable(model, p)
    end function hg_bounded

    !> Elements of material index mix can fail and erode: FAIL (plastic
    !> strain), FS, *MAT_ADD_EROSION, or ERODE 1 with DTMIN (their step).
    pure logical function can_erode(model, mix)
        type(model_t), intent(in) :: model
        integer, intent(in) :: mix
        can_erode = model%mat(mix)%fail > 0.0_wp .or. model%mat(mix)%erosion .or. &
                    (model%ctl%erode == 1 .and. model%ctl%dtmin > 0.0_wp)
    end function can_erode

    !> Some material of the model can fail and erode (can_erode).
    pure logical function any_erosion(model)
        type(model_t), intent(in) :: model
        integer :: k
        any_erosion = .false.
        do k = 1, model%nmat
            any_erosion = any_erosion .or. can_erode(model, k)
        end do
    end function any_erosion

    !> Index of the set of `kind` with id `id`, 0 if none.
    pure integer function find_set(model, kind, id) result(ix)
        type(model_t), intent(in) :: model
        integer, intent(in) :: kind, id
        do ix = 1, model%nset
            if (model%set(ix)%kind == kind .and. model%set(ix)%id == id) return
        end do
        ix = 0
    end function find_set

    !> Set mark(n) for every node of part index p's hexahedra and shells
    !> (connectivity as node indices, after the input checks).
    pure subroutine mark_part_nodes(model, p, mark)
        type(model_t), intent(in) :: model
        integer, intent(in) :: p
        logical, intent(inout) :: mark(:)
        integer :: e
        do e = 1, model%nhex
            if (model%hex_part(e) == p) mark(model%hex_conn(:, e)) = .true.
        end do
        do e = 1, model%nshell
            if (model%shell_part(e) == p) mark(model%shell_conn(:, e)) = .true.
        end do
    end subroutine mark_part_nodes

    !> Index of *DEFINE_COORDINATE_... `id` (0: none).
    pure integer function find_coord(model, id) result(ix)
        type(model_t), intent(in) :: model
        integer, intent(in) :: id
        do ix = 1, model%ncoord
            if (model%coord(ix)%id == id) return
        end do
        ix = 0
    end function find_coord

    !> Is point x inside box b (faces included)?
    pure logical function in_box(b, x)
        type(box_t), intent(in) :: b
        real(wp), intent(in) :: x(3)
        in_box = all(x >= b%lo) .and. all(x <= b%hi)
    end function in_box

    !> Index of *DEFINE_BOX `id` (0: none).
    pure integer function find_box(model, id) result(ix)
        type(model_t), intent(in) :: model
        integer, intent(in) :: id
        do ix = 1, model%nbox
            if (model%box(ix)%id == id) return
        end do
        ix = 0
    end function find_box

    !> Value of a time curve at t: linear between points, held constant beyond
    !> its first and last points.
    pure real(wp) function curve_value(c, t) result(v)
        type(curve_t), intent(in) :: c
        real(wp), intent(in) :: t
        integer :: lo, hi, mid
        if (t <= c%a(1)) then
            v = c%o(1)
            return
        end if
        if (t >= c%a(c%n)) then
            v = c%o(c%n)
            return
        end if
        lo = 1
        hi = c%n
        do while (hi - lo > 1)
            mid = (lo + hi)/2
            if (c%a(mid) <= t) then
                lo = mid
            else
                hi = mid
            end if
        end do
        v = c%o(lo) + (c%o(hi) - c%o(lo))*(t - c%a(lo))/(c%a(hi) - c%a(lo))
    end function curve_value

end module xd_model
