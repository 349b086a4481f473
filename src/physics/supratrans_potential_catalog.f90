!> The catalog of the paper's potentials: the closed enumeration (`sine_gordon`, `klein_gordon`) with each
!> potential's name in the namelist and in output attributes and the check of an identifier, and what is known of
!> each potential without evaluating it: the bounds of dG/da and d2G/da2 that Newton's stopping test uses
!> (`slope_lower_bound`, `curvature_bound`). An identifier outside the enumeration is an error, never a silent
!> choice of one of them: `check_potential` turns it into an error value (the run engine checks once per run), and
!> the bounds and the kernels of `supratrans_potential`, which cannot return errors, give NaN for it.
!>
!> Cold code (names, validation, constants of a run), apart from the kernels; `supratrans_potential` re-exports all
!> of it, so that its users name one module.
module supratrans_potential_catalog
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_strings, only: int_str
    implicit none
    private

    public :: potential_name, potential_from_name, is_potential, check_potential
    public :: slope_lower_bound, curvature_bound

    !> Not a potential: what `potential_from_name` returns for an unknown name.
    integer, parameter, public :: potential_unknown = 0
    !> Identifier of the sine-Gordon potential V(u) = 1 - cos u.
    integer, parameter, public :: sine_gordon = 1
    !> Identifier of the Klein-Gordon potential V(u) = u^2/2 - u^4/24 + u^6/720 (phi^6 truncation of 1 - cos u).
    integer, parameter, public :: klein_gordon = 2
    !> The enumeration: every valid potential identifier.
    integer, parameter, public :: potential_ids(2) = [sine_gordon, klein_gordon]

contains

    !> A lower bound of dG/da(a, b) over all a, b: dG/da = int_0^1 t V''(b + t (a - b)) dt >= min V''/2, with
    !> min V'' = -1 (sine-Gordon, V'' = cos u) and -1/2 (Klein-Gordon, V'' = 1 - u^2/2 + u^4/24, at u^2 = 6).
    !> Newton's stopping test uses it to bound the inverse Jacobian of the scheme. NaN for an unknown potential.
    pure function slope_lower_bound(id) result(bound)
        !> Potential identifier.
        integer, intent(in) :: id
        real(wp) :: bound

        select case (id)
        case (sine_gordon)
            bound = -0.5_wp
        case (klein_gordon)
            bound = -0.25_wp
        case default
            bound = ieee_value(bound, ieee_quiet_nan)
        end select
    end function slope_lower_bound

    !> An upper bound L of |d2G/da2(a, b)| for |a|, |b| <= `u_max`: d2G/da2 = int_0^1 t^2 V'''(b + t (a - b)) dt, so
    !> L = max |V'''|/3 with |V'''| <= 1 (sine-Gordon) and <= u_max + u_max^3/6 (Klein-Gordon, V''' = u^3/6 - u).
    !> NaN for an unknown potential.
    pure function curvature_bound(id, u_max) result(bound)
        !> Potential identifier.
        integer, intent(in) :: id
        !> Largest |u| of the arguments.
        real(wp), intent(in) :: u_max
        real(wp) :: bound

        select case (id)
        case (sine_gordon)
            bound = 1.0_wp/3.0_wp
        case (klein_gordon)
            bound = (u_max + u_max**3/6.0_wp)/3.0_wp
        case default
            bound = ieee_value(bound, ieee_quiet_nan)
        end select
    end function curvature_bound

    !> Name of a potential as used in the namelist and in output attributes.
    pure function potential_name(id) result(name)
        !> Potential identifier.
        integer, intent(in) :: id
        character(len=:), allocatable :: name

        select case (id)
        case (sine_gordon)
            name = "sine-gordon"
        case (klein_gordon)
            name = "klein-gordon"
        case default
            name = "unknown"
        end select
    end function potential_name

    !> Identifier of a potential from its name ('sine-gordon' or 'klein-gordon'); `potential_unknown` if unknown.
    pure function potential_from_name(name) result(id)
        !> Name as written in the namelist (case-sensitive, lower case).
        character(len=*), intent(in) :: name
        integer :: id

        select case (trim(adjustl(name)))
        case ("sine-gordon")
            id = sine_gordon
        case ("klein-gordon")
            id = klein_gordon
        case default
            id = potential_unknown
        end select
    end function potential_from_name

    !> True when `id` is one of the enumeration `potential_ids`.
    elemental function is_potential(id) result(valid)
        !> Potential identifier.
        integer, intent(in) :: id
        logical :: valid

        valid = any(potential_ids == id)
    end function is_potential

    !> Validate a potential identifier: `error` is allocated (input class) when `id` is not a known potential.
    pure subroutine check_potential(id, error)
        !> Potential identifier.
        integer, intent(in) :: id
        !> Error, allocated when `id` is unknown.
        type(error_type), allocatable, intent(out) :: error

        if (is_potential(id)) return
        call fatal_error(error, "unknown potential identifier " // int_str(id) // " (known: " &
                         // int_str(sine_gordon) // " sine-gordon, " // int_str(klein_gordon) // " klein-gordon)", &
                         err_input)
    end subroutine check_potential

end module supratrans_potential_catalog
