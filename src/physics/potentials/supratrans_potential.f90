!> The on-site potential V(u) of eq. (1) as a type: an abstract `potential_type` and the catalog of its members.
!>
!> A member (one module each in `src/physics/potentials/`) carries its own parameters and provides V, V', V'', the
!> exact discrete gradient G(a, b) = (V(a) - V(b))/(a - b) of the energy-conserving scheme and dG/da in closed
!> form (never that division: it is 0/0 at rest and loses its digits near it), the array kernels of the steppers
!> (one dispatch per array, never per site), the bounds of Newton's stopping test and the number of nodes the
!> AVF methods average V' with. The linear theory follows from V''(0) (`d2v_zero`) and m^2 (`supratrans_chain`).
!>
!> The catalog: the identifiers of the members (the order of the names in the schema's choices, checked by the
!> tests), their names in the namelist and in output attributes, the keys that set their parameters, and the
!> factory `new_potential` (the submodule `supratrans_potential_factory`, the one place that names every member).
!> An identifier outside the catalog is an error value (`check_potential`, checked once per run), never a silent
!> choice of a member; `new_potential` leaves the potential unallocated for it.
!>
!> Adding a potential: one module extending `potential_type`, its identifier and name here, its line in the
!> factory, its name in the schema's potential choices (and any parameter as a &chain key).
module supratrans_potential
    use supratrans_kinds, only: wp
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_strings, only: int_str
    use supratrans_config, only: chain_params
    implicit none
    private

    public :: potential_name, potential_from_name, is_potential, check_potential, potential_takes, new_potential
    public :: potential_stiffness

    !> Not a potential: what `potential_from_name` returns for an unknown name.
    integer, parameter, public :: potential_unknown = 0
    !> Identifier of the sine-Gordon potential V(u) = 1 - cos u.
    integer, parameter, public :: sine_gordon = 1
    !> Identifier of the Klein-Gordon potential V(u) = u^2/2 - u^4/24 + u^6/720 (phi^6 truncation of 1 - cos u).
    integer, parameter, public :: klein_gordon = 2
    !> Identifier of the double sine-Gordon potential V(u) = 1 - cos u + eta (1 - cos 2u).
    integer, parameter, public :: double_sine_gordon = 3
    !> The catalog: every valid potential identifier.
    integer, parameter, public :: potential_ids(3) = [sine_gordon, klein_gordon, double_sine_gordon]
    !> Names of the potentials in the namelist and in output attributes, in the order of their identifiers.
    character(len=*), parameter, public :: potential_names(3) = [character(len=18) :: "sine-gordon", &
                                                                   "klein-gordon", "double-sine-gordon"]
    !> The &chain key of each potential's parameter (blank: none), in the order of their identifiers.
    character(len=*), parameter :: potential_keys(3) = [character(len=3) :: "", "", "eta"]

    !> An on-site potential V(u) with its parameters. Every array procedure dispatches once per call.
    type, abstract, public :: potential_type
    contains
        !> Its name in the namelist and in output attributes.
        procedure(potential_name_i), deferred :: name
        !> V(u).
        procedure(potential_scalar_i), deferred :: v
        !> V'(u).
        procedure(potential_scalar_i), deferred :: dv
        !> V''(u).
        procedure(potential_scalar_i), deferred :: d2v
        !> G(a, b) and dG/da of one pair, in closed form.
        procedure(potential_pair_i), deferred :: gradient_and_slope
        !> V(u_n) of an array, site by site with the scalar functions (the bits of `v`).
        procedure(potential_map_i), deferred :: v_each
        !> V'(u_n) of an array, site by site with the scalar functions (the bits of `dv`).
        procedure(potential_map_i), deferred :: dv_each
        !> V''(u_n) of an array, site by site with the scalar functions (the bits of `d2v`).
        procedure(potential_map_i), deferred :: d2v_each
        !> V'(u_n) of an array, vectorised (the linearized scheme's and the method of lines' kernel); by default
        !> `dv_each`, overridden where a faster kernel gives other bits.
        procedure :: force_array => force_from_each
        !> V''(u_n) of an array, vectorised; by default `d2v_each`.
        procedure :: d2v_array => d2v_from_each
        !> The sum of V(u_n) over an array (the potential part of the discrete energy).
        procedure(potential_sum_i), deferred :: potential_sum
        !> G(a_n, b_n) and dG/da of arrays: the Newton step's kernel (with work it may keep for the refinement).
        procedure(potential_kernel_i), deferred :: gradient_and_slope_array
        !> The same after a Newton update `delta` of `a`, reusing the work of the previous call.
        procedure(potential_refine_i), deferred :: gradient_and_slope_refine
        !> A lower bound of dG/da(a, b) over all a, b: min V''/2.
        procedure(potential_constant_i), deferred :: slope_lower_bound
        !> An upper bound of |d2G/da2(a, b)| for |a|, |b| <= u_max: max |V'''|/3 there.
        procedure(potential_bound_i), deferred :: curvature_bound
        !> True when `curvature_bound` grows with u_max (else it holds for every u, and u_max may be 0).
        procedure(potential_flag_i), deferred :: curvature_grows
        !> Nodes of the rule that averages V' along a stage of an s-stage AVF method.
        procedure(potential_nodes_i), deferred :: averaging_nodes
        !> V''(0), the on-site stiffness at rest: with m^2 it makes the linear theory.
        procedure :: d2v_zero
        !> G(a, b) alone.
        procedure :: discrete_gradient
        !> dG/da alone.
        procedure :: discrete_gradient_da
    end type potential_type

    abstract interface
        !> The name of a potential.
        pure function potential_name_i(self) result(name)
            import :: potential_type
            !> The potential.
            class(potential_type), intent(in) :: self
            character(len=:), allocatable :: name
        end function potential_name_i

        !> A function of the displacement u.
        pure function potential_scalar_i(self, u) result(y)
            import :: potential_type, wp
            !> The potential.
            class(potential_type), intent(in) :: self
            !> Displacement u.
            real(wp), intent(in) :: u
            real(wp) :: y
        end function potential_scalar_i

        !> G(a, b) and dG/da.
        pure subroutine potential_pair_i(self, a, b, g, dg)
            import :: potential_type, wp
            !> The potential.
            class(potential_type), intent(in) :: self
            !> New value u_n^{k+1} and old value u_n^{k-1}.
            real(wp), intent(in) :: a, b
            !> G(a, b) and dG/da.
            real(wp), intent(out) :: g, dg
        end subroutine potential_pair_i

        !> A function of u_n for every element of an array.
        pure subroutine potential_map_i(self, u, y)
            import :: potential_type, wp
            !> The potential.
            class(potential_type), intent(in) :: self
            !> Displacements u_n.
            real(wp), intent(in), contiguous :: u(:)
            !> The values, same size.
            real(wp), intent(out), contiguous :: y(:)
        end subroutine potential_map_i

        !> The sum of V(u_n).
        pure function potential_sum_i(self, u) result(total)
            import :: potential_type, wp
            !> The potential.
            class(potential_type), intent(in) :: self
            !> Displacements u_n.
            real(wp), intent(in), contiguous :: u(:)
            real(wp) :: total
        end function potential_sum_i

        !> G(a_n, b_n) and dG/da for whole arrays.
        pure subroutine potential_kernel_i(self, a, b, g, dg, ss, cs, h_max)
            import :: potential_type, wp
            !> The potential.
            class(potential_type), intent(in) :: self
            !> New values u^{k+1}.
            real(wp), intent(in), contiguous :: a(:)
            !> Old values u^{k-1}, same size as `a`.
            real(wp), intent(in), contiguous :: b(:)
            !> Discrete gradients G(a_n, b_n).
            real(wp), intent(out), contiguous :: g(:)
            !> Derivatives dG/da(a_n, b_n).
            real(wp), intent(out), contiguous :: dg(:)
            !> Work kept for `gradient_and_slope_refine` (sin and cos of (a + b)/2 for the sine potentials).
            real(wp), intent(inout), contiguous :: ss(:), cs(:)
            !> max |a_n - b_n|/2 when the caller knows it.
            real(wp), intent(in), optional :: h_max
        end subroutine potential_kernel_i

        !> G(a_n, b_n) and dG/da after a Newton update `delta` of `a`.
        pure subroutine potential_refine_i(self, a, b, delta, g, dg, ss, cs, delta_max, h_max)
            import :: potential_type, wp
            !> The potential.
            class(potential_type), intent(in) :: self
            !> New values u^{k+1} (already updated by `delta`).
            real(wp), intent(in), contiguous :: a(:)
            !> Old values u^{k-1}.
            real(wp), intent(in), contiguous :: b(:)
            !> The update just applied to `a`.
            real(wp), intent(in), contiguous :: delta(:)
            !> Discrete gradients G(a_n, b_n).
            real(wp), intent(out), contiguous :: g(:)
            !> Derivatives dG/da(a_n, b_n).
            real(wp), intent(out), contiguous :: dg(:)
            !> The work of the previous call on entry, of this one on exit.
            real(wp), intent(inout), contiguous :: ss(:), cs(:)
            !> max |delta_n| when the caller knows it.
            real(wp), intent(in), optional :: delta_max
            !> max |a_n - b_n|/2 when the caller knows it.
            real(wp), intent(in), optional :: h_max
        end subroutine potential_refine_i

        !> A constant of the potential.
        pure function potential_constant_i(self) result(x)
            import :: potential_type, wp
            !> The potential.
            class(potential_type), intent(in) :: self
            real(wp) :: x
        end function potential_constant_i

        !> A bound that may depend on the largest |u|.
        pure function potential_bound_i(self, u_max) result(bound)
            import :: potential_type, wp
            !> The potential.
            class(potential_type), intent(in) :: self
            !> Largest |u| of the arguments.
            real(wp), intent(in) :: u_max
            real(wp) :: bound
        end function potential_bound_i

        !> A property of the potential.
        pure function potential_flag_i(self) result(flag)
            import :: potential_type
            !> The potential.
            class(potential_type), intent(in) :: self
            logical :: flag
        end function potential_flag_i

        !> A number of quadrature nodes for an s-stage method.
        pure function potential_nodes_i(self, stages) result(nodes)
            import :: potential_type
            !> The potential.
            class(potential_type), intent(in) :: self
            !> Stages s of the method.
            integer, intent(in) :: stages
            integer :: nodes
        end function potential_nodes_i
    end interface

    interface
        !> The potential of a chain (`chain%potential` with its parameters, e.g. `chain%eta`); unallocated for an
        !> identifier outside the catalog (`check_potential` tells).
        pure module subroutine new_potential(chain, potential)
            !> Chain parameters.
            type(chain_params), intent(in) :: chain
            !> The potential (reallocated).
            class(potential_type), allocatable, intent(inout) :: potential
        end subroutine new_potential
    end interface

contains

    !> V'(u_n) of an array: `dv_each` (a member whose site-by-site form already vectorises needs no second copy).
    pure subroutine force_from_each(self, u, y)
        !> The potential.
        class(potential_type), intent(in) :: self
        !> Displacements.
        real(wp), intent(in), contiguous :: u(:)
        !> V'(u_n).
        real(wp), intent(out), contiguous :: y(:)

        call self%dv_each(u, y)
    end subroutine force_from_each

    !> V''(u_n) of an array: `d2v_each`.
    pure subroutine d2v_from_each(self, u, y)
        !> The potential.
        class(potential_type), intent(in) :: self
        !> Displacements.
        real(wp), intent(in), contiguous :: u(:)
        !> V''(u_n).
        real(wp), intent(out), contiguous :: y(:)

        call self%d2v_each(u, y)
    end subroutine d2v_from_each

    !> V''(0) of a chain's potential, the on-site stiffness at rest (with m^2 it makes the linear theory of
    !> `supratrans_chain`); NaN for an unknown potential.
    elemental function potential_stiffness(chain) result(k)
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        real(wp) :: k
        class(potential_type), allocatable :: potential

        call new_potential(chain, potential)
        if (allocated(potential)) then
            k = potential%d2v_zero()
        else
            k = 0.0_wp
            k = k/k
        end if
    end function potential_stiffness

    !> V''(0).
    pure function d2v_zero(self) result(k)
        !> The potential.
        class(potential_type), intent(in) :: self
        real(wp) :: k

        k = self%d2v(0.0_wp)
    end function d2v_zero

    !> Discrete gradient G(a, b) = (V(a) - V(b))/(a - b) in closed form; equals V'(a) when a = b.
    pure function discrete_gradient(self, a, b) result(g)
        !> The potential.
        class(potential_type), intent(in) :: self
        !> New value u_n^{k+1} and old value u_n^{k-1}.
        real(wp), intent(in) :: a, b
        real(wp) :: g, dg

        call self%gradient_and_slope(a, b, g, dg)
    end function discrete_gradient

    !> Partial derivative dG/da of the discrete gradient, the Newton Jacobian's nonlinear diagonal.
    pure function discrete_gradient_da(self, a, b) result(dg)
        !> The potential.
        class(potential_type), intent(in) :: self
        !> New value u_n^{k+1} and old value u_n^{k-1}.
        real(wp), intent(in) :: a, b
        real(wp) :: g, dg

        call self%gradient_and_slope(a, b, g, dg)
    end function discrete_gradient_da

    !> Name of a potential as used in the namelist and in output attributes ("unknown" outside the catalog).
    pure function potential_name(id) result(name)
        !> Potential identifier.
        integer, intent(in) :: id
        character(len=:), allocatable :: name

        if (is_potential(id)) then
            name = trim(potential_names(id))
        else
            name = "unknown"
        end if
    end function potential_name

    !> Identifier of a potential from its name (one of `potential_names`); `potential_unknown` if unknown.
    pure function potential_from_name(name) result(id)
        !> Name as written in the namelist (case-sensitive, lower case).
        character(len=*), intent(in) :: name
        integer :: id

        do id = 1, size(potential_names)
            if (potential_names(id) == trim(adjustl(name))) return
        end do
        id = potential_unknown
    end function potential_from_name

    !> True when `id` is one of the catalog `potential_ids`.
    elemental function is_potential(id) result(valid)
        !> Potential identifier.
        integer, intent(in) :: id
        logical :: valid

        valid = any(potential_ids == id)
    end function is_potential

    !> True when the potential `id` takes its parameter from the &chain key `key` (e.g. 'eta').
    elemental function potential_takes(id, key) result(takes)
        !> Potential identifier.
        integer, intent(in) :: id
        !> The key.
        character(len=*), intent(in) :: key
        logical :: takes

        takes = .false.
        if (is_potential(id)) takes = potential_keys(id) == key .and. len_trim(key) > 0
    end function potential_takes

    !> Validate a potential identifier: `error` is allocated (input class) when `id` is not a known potential.
    pure subroutine check_potential(id, error)
        !> Potential identifier.
        integer, intent(in) :: id
        !> Error, allocated when `id` is unknown.
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: known
        integer :: i

        if (is_potential(id)) return
        known = ""
        do i = 1, size(potential_ids)
            known = known // merge(", ", "  ", i > 1) // int_str(potential_ids(i)) // " " // trim(potential_names(i))
        end do
        call fatal_error(error, "unknown potential identifier " // int_str(id) // " (known: " // known(3:) // ")", &
                         err_input)
    end subroutine check_potential

end module supratrans_potential
