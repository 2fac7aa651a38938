!> The keyword table: every keyword xdyna reads, its family (which reader
!> handles it), aliases, the `_TITLE` / `_ID` options, and the skip list of
!> output-only keywords. New keywords plug in here and in their family reader.
module xd_input_keyword_table
    use xd_core_strings, only: to_upper
    use xd_input_field_reader, only: width_standard, width_long, width_i10
    implicit none
    private
    public :: keyword_t, lookup_keyword, skip_list_text
    public :: fam_unknown, fam_meta, fam_geometry, fam_section, fam_material, fam_set, &
              fam_condition, fam_control, fam_database, fam_skip, fam_planned, fam_load, fam_contact

    integer, parameter :: fam_unknown = 0, fam_meta = 1, fam_geometry = 2, fam_section = 3, &
                          fam_material = 4, fam_set = 5, fam_condition = 6, fam_control = 7, &
                          fam_database = 8, fam_skip = 9, fam_planned = 10, fam_load = 11, &
                          fam_contact = 12

    !> A keyword occurrence in the deck and the card lines under it.
    type :: keyword_t
        character(len=48) :: name = ''          !< canonical name, options stripped, alias resolved
        character(len=:), allocatable :: written  !< first token as in the deck, with '*'
        integer :: family = fam_unknown
        logical :: title = .false.              !< _TITLE: an A80 title card first
        logical :: has_id = .false.             !< _ID: an ID/HEADING card first
        integer :: width_mode = width_standard
        integer :: kw_line = 0                  !< deck line of the keyword
        integer :: ncard = 0
        integer, allocatable :: card_line(:)    !< deck lines of its cards, comments removed
    end type keyword_t

    type :: entry_t
        character(len=48) :: name
        integer :: family
        character(len=48) :: canonical      !< alias target ('' = itself)
        logical :: id_option
    end type entry_t

    type(entry_t), parameter :: table(*) = [ &
        entry_t('KEYWORD', fam_meta, '', .false.), &
        entry_t('KEYWORD_ID', fam_meta, '', .false.), &
        entry_t('TITLE', fam_meta, '', .false.), &
        entry_t('PARAMETER', fam_meta, '', .false.), &
        entry_t('PARAMETER_LOCAL', fam_meta, '', .false.), &
        entry_t('PARAMETER_EXPRESSION', fam_meta, '', .false.), &
        entry_t('PARAMETER_EXPRESSION_LOCAL', fam_meta, '', .false.), &
        entry_t('PARAMETER_NOECHO', fam_meta, 'PARAMETER', .false.), &
        entry_t('PARAMETER_EXPRESSION_NOECHO', fam_meta, 'PARAMETER_EXPRESSION', .false.), &
        entry_t('NODE', fam_geometry, '', .false.), &
        entry_t('ELEMENT_SOLID', fam_geometry, '', .false.), &
        entry_t('ELEMENT_MASS', fam_geometry, '', .false.), &
        entry_t('ELEMENT_MASS_NODE_SET', fam_geometry, '', .false.), &
        entry_t('ELEMENT_MASS_PART', fam_geometry, '', .false.), &
        entry_t('ELEMENT_MASS_PART_SET', fam_geometry, '', .false.), &
        entry_t('PART', fam_geometry, '', .false.), &
        entry_t('PART_INERTIA', fam_geometry, '', .false.), &
        entry_t('ELEMENT_SHELL', fam_geometry, '', .false.), &
        entry_t('ELEMENT_BEAM', fam_geometry, '', .false.), &
        entry_t('ELEMENT_SHELL_THICKNESS', fam_geometry, '', .false.), &
        entry_t('SECTION_SOLID', fam_section, '', .false.), &
        entry_t('SECTION_SHELL', fam_section, '', .false.), &
        entry_t('SECTION_BEAM', fam_section, '', .false.), &
        entry_t('MAT_ELASTIC', fam_material, '', .false.), &
        entry_t('MAT_001', fam_material, 'MAT_ELASTIC', .false.), &
        entry_t('MAT_PLASTIC_KINEMATIC', fam_material, '', .false.), &
        entry_t('MAT_003', fam_material, 'MAT_PLASTIC_KINEMATIC', .false.), &
        entry_t('MAT_PIECEWISE_LINEAR_PLASTICITY', fam_material, '', .false.), &
        entry_t('MAT_024', fam_material, 'MAT_PIECEWISE_LINEAR_PLASTICITY', .false.), &
        entry_t('MAT_RIGID', fam_material, '', .false.), &
        entry_t('MAT_ADD_EROSION', fam_material, '', .false.), &
        entry_t('MAT_SPOTWELD', fam_material, '', .false.), &
        entry_t('MAT_100', fam_material, 'MAT_SPOTWELD', .false.), &
        entry_t('MAT_020', fam_material, 'MAT_RIGID', .false.), &
        entry_t('HOURGLASS', fam_material, '', .false.), &
        entry_t('SET_NODE_LIST', fam_set, '', .false.), &
        entry_t('SET_NODE', fam_set, 'SET_NODE_LIST', .false.), &
        entry_t('SET_NODE_LIST_GENERATE', fam_set, '', .false.), &
        entry_t('SET_PART_LIST', fam_set, '', .false.), &
        entry_t('SET_PART', fam_set, 'SET_PART_LIST', .false.), &
        entry_t('SET_PART_LIST_GENERATE', fam_set, '', .false.), &
        entry_t('SET_SHELL_LIST', fam_set, '', .false.), &
        entry_t('SET_SHELL', fam_set, 'SET_SHELL_LIST', .false.), &
        entry_t('SET_SHELL_LIST_GENERATE', fam_set, '', .false.), &
        entry_t('SET_NODE_GENERAL', fam_set, '', .false.), &
        entry_t('SET_SHELL_GENERAL', fam_set, '', .false.), &
        entry_t('SET_PART_GENERAL', fam_set, '', .false.), &
        entry_t('SET_NODE_ADD', fam_set, '', .false.), &
        entry_t('SET_PART_ADD', fam_set, '', .false.), &
        entry_t('SET_SHELL_ADD', fam_set, '', .false.), &
        entry_t('BOUNDARY_SPC_NODE', fam_condition, '', .true.), &
        entry_t('BOUNDARY_SPC_SET', fam_condition, '', .true.), &
        entry_t('BOUNDARY_PRESCRIBED_MOTION_NODE', fam_condition, '', .true.), &
        entry_t('BOUNDARY_PRESCRIBED_MOTION_SET', fam_condition, '', .true.), &
        entry_t('BOUNDARY_PRESCRIBED_MOTION_RIGID', fam_condition, '', .true.), &
        entry_t('CONSTRAINED_NODAL_RIGID_BODY', fam_condition, '', .false.), &
        entry_t('CONSTRAINED_NODAL_RIGID_BODY_INERTIA', fam_condition, '', .false.), &
        entry_t('CONSTRAINED_EXTRA_NODES_NODE', fam_condition, '', .false.), &
        entry_t('CONSTRAINED_EXTRA_NODES_SET', fam_condition, '', .false.), &
        entry_t('CONSTRAINED_GENERALIZED_WELD_SPOT', fam_condition, '', .true.), &
        entry_t('INITIAL_VELOCITY', fam_condition, '', .false.), &
        entry_t('INITIAL_VELOCITY_NODE', fam_condition, '', .false.), &
        entry_t('INITIAL_VELOCITY_GENERATION', fam_condition, '', .false.), &
        entry_t('INITIAL_STRESS_SOLID', fam_condition, '', .false.), &
        entry_t('CONTROL_TERMINATION', fam_control, '', .false.), &
        entry_t('CONTROL_TIMESTEP', fam_control, '', .false.), &
        entry_t('CONTROL_HOURGLASS', fam_control, '', .false.), &
        entry_t('CONTROL_BULK_VISCOSITY', fam_control, '', .false.), &
        entry_t('CONTROL_ENERGY', fam_control, '', .false.), &
        entry_t('CONTROL_SHELL', fam_control, '', .false.), &
        entry_t('CONTROL_XDYNA_SHELL', fam_control, '', .false.), &
        entry_t('CONTROL_ACCURACY', fam_control, '', .false.), &
        entry_t('CONTROL_UNITS', fam_control, '', .false.), &
        entry_t('DEFINE_CURVE', fam_load, '', .false.), &
        entry_t('SET_SEGMENT', fam_load, '', .false.), &
        entry_t('SET_SEGMENT_GENERAL', fam_load, '', .false.), &
        entry_t('LOAD_SEGMENT', fam_load, '', .true.), &
        entry_t('LOAD_SEGMENT_SET', fam_load, '', .true.), &
        entry_t('LOAD_SHELL_ELEMENT', fam_load, '', .true.), &
        entry_t('LOAD_SHELL_SET', fam_load, '', .true.), &
        entry_t('LOAD_BODY_X', fam_load, '', .false.), &
        entry_t('LOAD_BODY_Y', fam_load, '', .false.), &
        entry_t('LOAD_BODY_Z', fam_load, '', .false.), &
        entry_t('DEFINE_BOX', fam_load, '', .false.), &
        entry_t('DEFINE_COORDINATE_SYSTEM', fam_load, '', .false.), &
        entry_t('DEFINE_COORDINATE_NODES', fam_load, '', .false.), &
        entry_t('RIGIDWALL_PLANAR', fam_load, '', .true.), &
        entry_t('RIGIDWALL_PLANAR_FORCES', fam_load, '', .true.), &
        entry_t('RIGIDWALL_PLANAR_FINITE_FORCES', fam_load, '', .true.), &
        entry_t('RIGIDWALL_PLANAR_MOVING_FORCES', fam_load, '', .true.), &
        entry_t('RIGIDWALL_PLANAR_FINITE_MOVING_FORCES', fam_load, '', .true.), &
        entry_t('RIGIDWALL_PLANAR_FINITE', fam_load, '', .true.), &
        entry_t('RIGIDWALL_PLANAR_MOVING', fam_load, '', .true.), &
        entry_t('RIGIDWALL_PLANAR_FINITE_MOVING', fam_load, '', .true.), &
        entry_t('RIGIDWALL_GEOMETRIC_CYLINDER', fam_load, '', .true.), &
        entry_t('RIGIDWALL_GEOMETRIC_CYLINDER_DISPLAY', fam_load, 'RIGIDWALL_GEOMETRIC_CYLINDER', .true.), &
        entry_t('DATABASE_GLSTAT', fam_database, '', .false.), &
        entry_t('DATABASE_MATSUM', fam_database, '', .false.), &
        entry_t('DATABASE_NODOUT', fam_database, '', .false.), &
        entry_t('DATABASE_RCFORC', fam_database, '', .false.), &
        entry_t('DATABASE_RWFORC', fam_database, '', .false.), &
        entry_t('DATABASE_HISTORY_NODE', fam_database, '', .false.), &
        entry_t('DATABASE_HISTORY_NODE_ID', fam_database, '', .false.), &
        entry_t('DATABASE_HISTORY_NODE_SET', fam_database, '', .false.), &
        entry_t('DATABASE_BINARY_D3PLOT', fam_database, '', .false.), &
        entry_t('DATABASE_BINARY_D3DUMP', fam_database, '', .false.), &
        entry_t('CONTROL_XDYNA_OUTPUT', fam_database, '', .false.), &
        ! output-only or tuning keywords xdyna does not need: one warning each
        entry_t('DATABASE_BINARY_RUNRSF', fam_skip, '', .false.), &
        entry_t('DATABASE_BINARY_D3THDT', fam_skip, '', .false.), &
        entry_t('DATABASE_BINARY_INTFOR', fam_skip, '', .false.), &
        entry_t('DATABASE_EXTENT_BINARY', fam_skip, '', .false.), &
        entry_t('DATABASE_SLEOUT', fam_skip, '', .false.), &
        entry_t('DATABASE_ELOUT', fam_skip, '', .false.), &
        entry_t('DATABASE_SPCFORC', fam_skip, '', .false.), &
        entry_t('DATABASE_BNDOUT', fam_skip, '', .false.), &
        entry_t('DATABASE_DEFORC', fam_skip, '', .false.), &
        entry_t('DATABASE_GCEOUT', fam_skip, '', .false.), &
        entry_t('DATABASE_RBDOUT', fam_skip, '', .false.), &
        entry_t('DATABASE_FORMAT', fam_skip, '', .false.), &
        entry_t('DATABASE_HISTORY_SHELL', fam_skip, '', .false.), &
        entry_t('DATABASE_HISTORY_SOLID', fam_skip, '', .false.), &
        entry_t('CONTROL_OUTPUT', fam_skip, '', .false.), &
        entry_t('CONTROL_CPU', fam_skip, '', .false.), &
        entry_t('CONTROL_PARALLEL', fam_skip, '', .false.), &
        entry_t('CONTROL_MPP_*', fam_skip, '', .false.), &
        entry_t('SENSOR_DEFINE_*', fam_skip, '', .false.), &
        ! any other output request (keywords read above come first: a
        ! pattern is tried only after the exact names and their _TITLE and
        ! _ID forms)
        entry_t('DATABASE_*', fam_skip, '', .false.), &
        ! in KEYWORDS.md, arriving with later work: a clear message until then
        entry_t('SET_SOLID_GENERAL', fam_planned, '', .false.), &
        entry_t('CONTACT_AUTOMATIC_SINGLE_SURFACE', fam_contact, '', .true.), &
        entry_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE', fam_contact, '', .true.), &
        entry_t('CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TIEBREAK', fam_contact, '', .true.), &
        entry_t('CONTACT_AUTOMATIC_GENERAL', fam_contact, '', .true.), &
        entry_t('CONTACT_AUTOMATIC_NODES_TO_SURFACE', fam_contact, '', .true.), &
        entry_t('CONTACT_SINGLE_SURFACE', fam_contact, '', .true.), &
        entry_t('CONTACT_ERODING_SINGLE_SURFACE', fam_contact, '', .true.), &
        entry_t('CONTACT_ERODING_SURFACE_TO_SURFACE', fam_contact, '', .true.), &
        entry_t('CONTACT_ERODING_NODES_TO_SURFACE', fam_contact, '', .true.), &
        entry_t('CONTACT_TIED_NODES_TO_SURFACE', fam_contact, '', .true.), &
        entry_t('CONTACT_TIED_SHELL_EDGE_TO_SURFACE', fam_contact, '', .true.), &
        entry_t('CONTACT_TIED_SURFACE_TO_SURFACE', fam_contact, '', .true.), &
        entry_t('CONTACT_TIED_NODES_TO_SURFACE_OFFSET', fam_contact, '', .true.), &
        entry_t('CONTACT_TIED_SHELL_EDGE_TO_SURFACE_OFFSET', fam_contact, '', .true.), &
        entry_t('CONTACT_TIED_SHELL_EDGE_TO_SURFACE_BEAM_OFFSET', fam_contact, '', .true.), &
        entry_t('CONTACT_TIED_SURFACE_TO_SURFACE_OFFSET', fam_contact, '', .true.), &
        entry_t('CONTACT_SPOTWELD', fam_contact, '', .true.), &
        entry_t('CONTROL_CONTACT', fam_contact, '', .false.), &
        entry_t('CONTROL_XDYNA_CONTACT', fam_contact, '', .false.) &
        ]

contains

    !> Fill name/family/options/width mode of `kw` from the keyword line `text`.
    subroutine lookup_keyword(text, deck_width, kw)
        character(len=*), intent(in) :: text
        integer, intent(in) :: deck_width
        type(keyword_t), intent(inout) :: kw
        character(len=:), allocatable :: tok, rest, base
        character(len=1) :: suffix
        integer :: k

        k = index(text, ' ')
        if (k == 0) then
            tok = to_upper(trim(text))
            rest = ''
        else
            tok = to_upper(text(1:k - 1))
            rest = adjustl(text(k:))
        end if
        kw%written = tok
        kw%width_mode = deck_width
        suffix = ' '
        k = len(tok)
        if (k > 1) then
            if (scan(tok(k:k), '+-%') > 0) then
                suffix = tok(k:k)
                tok = tok(1:k - 1)
            end if
        end if
        if (suffix == ' ' .and. len(rest) > 0) then
            if (rest == '+' .or. rest == '-' .or. rest == '%') suffix = rest(1:1)
        end if
        select case (suffix)
        case ('+'); kw%width_mode = width_long
        case ('-'); kw%width_mode = width_standard
        case ('%'); kw%width_mode = width_i10
        end select

        base = tok(2:)
        if (find(base, kw, .false.)) return
        if (ends_with(base, '_TITLE')) then
            base = base(1:len(base) - 6)
            kw%title = .true.
            if (find(base, kw, .false.)) return
        end if
        if (ends_with(base, '_ID')) then
            base = base(1:len(base) - 3)
            if (find(base, kw, .false.)) then
                if (table_id_option(base)) then
                    kw%has_id = .true.
                    return
                end if
            end if
        end if
        kw%title = .false.
        if (find(tok(2:), kw, .true.)) return
        kw%family = fam_unknown
        kw%name = tok(2:)
    end subroutine lookup_keyword

    !> The table's entry for base: its exact name, or (pattern) the first
    !> entry ending in '*' whose stem begins base.
    logical function find(base, kw, pattern)
        character(len=*), intent(in) :: base
        type(keyword_t), intent(inout) :: kw
        logical, intent(in) :: pattern
        integer :: i, k
        find = .false.
        do i = 1, size(table)
            k = index(table(i)%name, '*')
            if ((k > 0) .neqv. pattern) cycle
            if (k > 0) then
                find = len(base) >= k - 1
                if (find) find = base(1:k - 1) == table(i)%name(1:k - 1)
            else
                find = base == table(i)%name
            end if
            if (find) then
                kw%family = table(i)%family
                kw%name = base
                if (len_trim(table(i)%canonical) > 0) kw%name = table(i)%canonical
                return
            end if
        end do
    end function find

    logical function table_id_option(base)
        character(len=*), intent(in) :: base
        integer :: i
        table_id_option = .false.
        do i = 1, size(table)
            if (base == table(i)%name) table_id_option = table(i)%id_option
        end do
    end function table_id_option

    pure logical function ends_with(s, tail)
        character(len=*), intent(in) :: s, tail
        ends_with = .false.
        if (len(s) > len(tail)) ends_with = s(len(s) - len(tail) + 1:) == tail
    end function ends_with

    !> The skip list, one keyword a line, for the manual and --help.
    function skip_list_text() result(s)
        character(len=:), allocatable :: s
        integer :: i
        s = ''
        do i = 1, size(table)
            if (table(i)%family == fam_skip) s = s//'  *'//trim(table(i)%name)//new_line('a')
        end do
    end function skip_list_text

end module xd_input_keyword_table
