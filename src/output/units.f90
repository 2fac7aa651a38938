!> Units of the outputs from the deck's unit system (*CONTROL_UNITS: LENGTH,
!> TIME, MASS as LS-DYNA names them). LS-DYNA itself asks only for
!> consistent units, so a deck without *CONTROL_UNITS has none known: the
!> outputs then say which dimension a value has, and that its units are
!> the deck's own. Derived units: force M L / T^2 named where it is a
!> newton, kilonewton, meganewton, millinewton, dyne or pound-force (mm, s,
!> mtrc_ton: N; mm, ms, kg: kN); energy that force times the length
!> (N*m is written J).
module xd_output_units
    use xd_kinds, only: dp
    implicit none
    private
    public :: unit_name, unit_system_text, length_units, time_units, mass_units

    character(len=8), parameter :: length_units(5) = [character(len=8) :: 'm', 'mm', 'cm', 'in', 'ft']
    character(len=8), parameter :: time_units(3) = [character(len=8) :: 'sec', 'ms', 'micro_s']
    character(len=8), parameter :: mass_units(7) = [character(len=8) :: 'kg', 'g', 'mg', 'lb', 'slug', 'slinch', &
                                                    'mtrc_ton']
    !> each in SI (m, s, kg); lb is the pound-mass
    real(dp), parameter :: length_si(5) = [1.0_dp, 1.0e-3_dp, 1.0e-2_dp, 0.0254_dp, 0.3048_dp]
    real(dp), parameter :: time_si(3) = [1.0_dp, 1.0e-3_dp, 1.0e-6_dp]
    real(dp), parameter :: mass_si(7) = [1.0_dp, 1.0e-3_dp, 1.0e-6_dp, 0.45359237_dp, 14.593903_dp, &
                                         175.126836_dp, 1000.0_dp]
    character(len=8), parameter :: length_sym(5) = [character(len=8) :: 'm', 'mm', 'cm', 'in', 'ft']
    character(len=8), parameter :: time_sym(3) = [character(len=8) :: 's', 'ms', 'us']
    character(len=8), parameter :: mass_sym(7) = [character(len=8) :: 'kg', 'g', 'mg', 'lbm', 'slug', 'slinch', 't']

contains

    !> The unit of a value of dimension `dim` (as the histories write it:
    !> 'time', 'length/time^2', 'mass*length^2/time', 'force', 'energy',
    !> 'radian/time', '1', ...) in the system with indices il, it, im of
    !> the lists above; '' where no system is given (il = 0).
    function unit_name(dim, il, it, im) result(u)
        character(len=*), intent(in) :: dim
        integer, intent(in) :: il, it, im
        character(len=:), allocatable :: u
        character(len=:), allocatable :: l, t, m
        u = ''
        if (il <= 0 .or. it <= 0 .or. im <= 0) return
        l = trim(length_sym(il))
        t = trim(time_sym(it))
        m = trim(mass_sym(im))
        select case (dim)
        case ('time'); u = t
        case ('length'); u = l
        case ('mass'); u = m
        case ('1'); u = '1'
        case ('radian'); u = 'rad'
        case ('length/time'); u = l//'/'//t
        case ('length/time^2'); u = l//'/'//t//'^2'
        case ('1/time'); u = '1/'//t
        case ('radian/time'); u = 'rad/'//t
        case ('radian/time^2'); u = 'rad/'//t//'^2'
        case ('mass*length/time'); u = m//'*'//l//'/'//t
        case ('mass*length^2/time'); u = m//'*'//l//'^2/'//t
        case ('force'); u = force_name(il, it, im)
        case ('energy')
            u = force_name(il, it, im)//'*'//l
            if (u == 'N*m') u = 'J'
            if (u == 'kN*mm') u = 'J'
        case default; u = dim
        end select
    end function unit_name

    !> The force unit M L / T^2 by name where it has one, else spelt out.
    function force_name(il, it, im) result(u)
        integer, intent(in) :: il, it, im
        character(len=:), allocatable :: u
        real(dp) :: f
        f = mass_si(im)*length_si(il)/time_si(it)**2
        u = trim(mass_sym(im))//'*'//trim(length_sym(il))//'/'//trim(time_sym(it))//'^2'
        if (near(f, 1.0_dp)) u = 'N'
        if (near(f, 1.0e3_dp)) u = 'kN'
        if (near(f, 1.0e6_dp)) u = 'MN'
        if (near(f, 1.0e-3_dp)) u = 'mN'
        if (near(f, 1.0e-5_dp)) u = 'dyn'
        if (near(f, 4.4482216152605_dp)) u = 'lbf'
    contains
        pure logical function near(a, b)
            real(dp), intent(in) :: a, b
            near = abs(a/b - 1.0_dp) < 1.0e-5_dp
        end function near
    end function force_name

    !> The unit system in words, for the outputs' headers.
    function unit_system_text(il, it, im) result(s)
        integer, intent(in) :: il, it, im
        character(len=:), allocatable :: s
        if (il <= 0 .or. it <= 0 .or. im <= 0) then
            s = 'not given (no *CONTROL_UNITS): the deck''s own consistent units'
        else
            s = 'length '//trim(length_sym(il))//', time '//trim(time_sym(it))//', mass '//trim(mass_sym(im))// &
                ', force '//unit_name('force', il, it, im)//', energy '//unit_name('energy', il, it, im)// &
                ' (*CONTROL_UNITS)'
        end if
    end function unit_system_text

end module xd_output_units
