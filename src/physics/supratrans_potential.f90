!> On-site potentials V(u) of the paper (Sec. 2.1) and their discrete gradients.
!>
!> The energy-conserving scheme (paper eq. DiscreteMainDiscr) uses the difference quotient
!> G(a, b) = (V(a) - V(b)) / (a - b), with a = u_n^{k+1} and b = u_n^{k-1}. That quotient is 0/0 at rest and
!> loses all its digits to cancellation near it, so it is never computed by division here:
!>
!> * sine-Gordon, V(u) = 1 - cos u:  G(a, b) = sin(s) sinc(h), with s = (a + b)/2 and h = (a - b)/2;
!> * Klein-Gordon (phi^6 truncation), V(u) = u^2/2 - u^4/24 + u^6/720:
!>   G(a, b) = (a + b) [1/2 - (a^2 + b^2)/24 + (a^4 + a^2 b^2 + b^4)/720].
!>
!> dG/da, the diagonal added to the Newton Jacobian, is equally direct. All procedures are pure.
!>
!> The potentials form a closed enumeration (`sine_gordon`, `klein_gordon`): an identifier outside it is an error,
!> never a silent choice of one of them. `check_potential` turns it into an error value (the run engine checks
!> once per run); the kernels below, which cannot return errors, give NaN for it (V, V', G, dG/da, sums), so a
!> caller that skipped the check sees a loud, non-finite result rather than another potential's numbers.
module supratrans_potential
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_strings, only: int_str
    implicit none
    private

    public :: potential_v, potential_dv, discrete_gradient, discrete_gradient_da
    public :: gradient_and_slope, gradient_and_slope_array, gradient_and_slope_refine, potential_sum, force_array
    public :: potential_name, potential_from_name, is_potential, check_potential

    !> Not a potential: what `potential_from_name` returns for an unknown name.
    integer, parameter, public :: potential_unknown = 0
    !> Identifier of the sine-Gordon potential V(u) = 1 - cos u.
    integer, parameter, public :: sine_gordon = 1
    !> Identifier of the Klein-Gordon potential V(u) = u^2/2 - u^4/24 + u^6/720 (phi^6 truncation of 1 - cos u).
    integer, parameter, public :: klein_gordon = 2
    !> The enumeration: every valid potential identifier.
    integer, parameter, public :: potential_ids(2) = [sine_gordon, klein_gordon]

    !> Below this |h| = |a - b|/2 the Taylor series of sinc and sinc' are used (truncation error < 3e-21).
    real(wp), parameter :: h_series = 0.25_wp

contains

    !> Potential V(u) of the paper: `sine_gordon` or `klein_gordon`.
    elemental function potential_v(id, u) result(v)
        !> Potential identifier.
        integer, intent(in) :: id
        !> Displacement u_n.
        real(wp), intent(in) :: u
        real(wp) :: v

        select case (id)
        case (sine_gordon)
            v = 2.0_wp*sin(0.5_wp*u)**2          ! 1 - cos u without cancellation near u = 0
        case (klein_gordon)
            v = u*u*(0.5_wp + u*u*(-1.0_wp/24.0_wp + u*u/720.0_wp))
        case default
            v = ieee_value(v, ieee_quiet_nan)
        end select
    end function potential_v

    !> Derivative V'(u), the force used by the linearized scheme.
    elemental function potential_dv(id, u) result(dv)
        !> Potential identifier.
        integer, intent(in) :: id
        !> Displacement u_n.
        real(wp), intent(in) :: u
        real(wp) :: dv

        select case (id)
        case (sine_gordon)
            dv = sin(u)
        case (klein_gordon)
            dv = u*(1.0_wp + u*u*(-1.0_wp/6.0_wp + u*u/120.0_wp))
        case default
            dv = ieee_value(dv, ieee_quiet_nan)
        end select
    end function potential_dv

    !> Discrete gradient G(a, b) = (V(a) - V(b))/(a - b) in closed form; equals V'(a) when a = b.
    elemental function discrete_gradient(id, a, b) result(g)
        !> Potential identifier.
        integer, intent(in) :: id
        !> New value u_n^{k+1}.
        real(wp), intent(in) :: a
        !> Old value u_n^{k-1}.
        real(wp), intent(in) :: b
        real(wp) :: g, dg

        call gradient_and_slope(id, a, b, g, dg)
    end function discrete_gradient

    !> Partial derivative dG/da of the discrete gradient, the Newton Jacobian's nonlinear diagonal.
    elemental function discrete_gradient_da(id, a, b) result(dg)
        !> Potential identifier.
        integer, intent(in) :: id
        !> New value u_n^{k+1}.
        real(wp), intent(in) :: a
        !> Old value u_n^{k-1}.
        real(wp), intent(in) :: b
        real(wp) :: g, dg

        call gradient_and_slope(id, a, b, g, dg)
    end function discrete_gradient_da

    !> G(a, b) and dG/da together (they share their transcendental evaluations).
    elemental subroutine gradient_and_slope(id, a, b, g, dg)
        !> Potential identifier.
        integer, intent(in) :: id
        !> New value u_n^{k+1}.
        real(wp), intent(in) :: a
        !> Old value u_n^{k-1}.
        real(wp), intent(in) :: b
        !> Discrete gradient G(a, b).
        real(wp), intent(out) :: g
        !> Derivative dG/da.
        real(wp), intent(out) :: dg
        real(wp) :: ga(1), dga(1)

        select case (id)
        case (sine_gordon)
            call sine_gordon_g(sin(0.5_wp*(a + b)), cos(0.5_wp*(a + b)), 0.5_wp*(a - b), g, dg)
        case (klein_gordon)
            call klein_gordon_array([a], [b], ga, dga)
            g = ga(1)
            dg = dga(1)
        case default
            g = ieee_value(g, ieee_quiet_nan)
            dg = g
        end select
    end subroutine gradient_and_slope

    !> G(a_n, b_n) and dG/da for whole arrays: the Newton step's kernel (the branch on the potential is hoisted
    !> out of the loop so that the loop body inlines). For sine-Gordon, sin(s_n) and cos(s_n), s = (a + b)/2, are
    !> returned in `ss` and `cs` so that later Newton iterations can refine them without new transcendentals.
    pure subroutine gradient_and_slope_array(id, a, b, g, dg, ss, cs)
        !> Potential identifier.
        integer, intent(in) :: id
        !> New values u^{k+1}.
        real(wp), intent(in) :: a(:)
        !> Old values u^{k-1}, same size as `a`.
        real(wp), intent(in) :: b(:)
        !> Discrete gradients G(a_n, b_n).
        real(wp), intent(out) :: g(:)
        !> Derivatives dG/da(a_n, b_n).
        real(wp), intent(out) :: dg(:)
        !> sin(s_n) and cos(s_n) (sine-Gordon only; untouched for Klein-Gordon).
        real(wp), intent(inout) :: ss(:), cs(:)
        integer :: n

        select case (id)
        case (sine_gordon)
            do n = 1, size(a)
                ss(n) = sin(0.5_wp*(a(n) + b(n)))
                cs(n) = cos(0.5_wp*(a(n) + b(n)))
                call sine_gordon_g(ss(n), cs(n), 0.5_wp*(a(n) - b(n)), g(n), dg(n))
            end do
        case (klein_gordon)
            call klein_gordon_array(a, b, g, dg)
        case default
            g = ieee_value(1.0_wp, ieee_quiet_nan)
            dg = g
        end select
    end subroutine gradient_and_slope_array

    !> Same as `gradient_and_slope_array` after a Newton update `delta` of `a` (a = a_previous + delta), with
    !> sin(s) and cos(s) advanced by the angle-addition formulas: s moves by delta/2, and for
    !> |delta/2| < 1e-3 the 7-term Taylor polynomials of sin and cos of that small angle are exact to roundoff.
    pure subroutine gradient_and_slope_refine(id, a, b, delta, g, dg, ss, cs)
        !> Potential identifier.
        integer, intent(in) :: id
        !> New values u^{k+1} (already updated by `delta`).
        real(wp), intent(in) :: a(:)
        !> Old values u^{k-1}.
        real(wp), intent(in) :: b(:)
        !> The update just applied to `a`.
        real(wp), intent(in) :: delta(:)
        !> Discrete gradients G(a_n, b_n).
        real(wp), intent(out) :: g(:)
        !> Derivatives dG/da(a_n, b_n).
        real(wp), intent(out) :: dg(:)
        !> sin(s_n), cos(s_n) on entry for the previous `a`, on exit for the new one.
        real(wp), intent(inout) :: ss(:), cs(:)
        integer :: n
        real(wp) :: eps, e2, se, ce, s_old

        select case (id)
        case (sine_gordon)
            do n = 1, size(a)
                eps = 0.5_wp*delta(n)
                if (abs(eps) < 1.0e-3_wp) then
                    e2 = eps*eps
                    se = eps*(1.0_wp + e2*(-1.0_wp/6.0_wp + e2*(1.0_wp/120.0_wp - e2/5040.0_wp)))
                    ce = 1.0_wp + e2*(-0.5_wp + e2*(1.0_wp/24.0_wp + e2*(-1.0_wp/720.0_wp + e2/40320.0_wp)))
                    s_old = ss(n)
                    ss(n) = s_old*ce + cs(n)*se
                    cs(n) = cs(n)*ce - s_old*se
                else
                    ss(n) = sin(0.5_wp*(a(n) + b(n)))
                    cs(n) = cos(0.5_wp*(a(n) + b(n)))
                end if
                call sine_gordon_g(ss(n), cs(n), 0.5_wp*(a(n) - b(n)), g(n), dg(n))
            end do
        case (klein_gordon)
            call klein_gordon_array(a, b, g, dg)
        case default
            g = ieee_value(1.0_wp, ieee_quiet_nan)
            dg = g
        end select
    end subroutine gradient_and_slope_refine

    !> Sine-Gordon G = sin(s) sinc(h) and dG/da = (cos(s) sinc(h) + sin(s) sinc'(h))/2 from sin(s), cos(s), h.
    elemental subroutine sine_gordon_g(ss, cs, h, g, dg)
        !> sin(s), cos(s), s = (a + b)/2.
        real(wp), intent(in) :: ss, cs
        !> h = (a - b)/2.
        real(wp), intent(in) :: h
        !> G(a, b) and dG/da.
        real(wp), intent(out) :: g, dg
        real(wp) :: sc, dsc

        call sinc_and_slope(h, sc, dsc)
        g = ss*sc
        dg = 0.5_wp*(cs*sc + ss*dsc)
    end subroutine sine_gordon_g

    !> Klein-Gordon G(a, b) and dG/da for whole arrays (polynomials: no transcendentals).
    pure subroutine klein_gordon_array(a, b, g, dg)
        !> New and old values.
        real(wp), intent(in) :: a(:), b(:)
        !> G(a_n, b_n) and dG/da.
        real(wp), intent(out) :: g(:), dg(:)
        integer :: n
        real(wp) :: a2, b2, q

        do n = 1, size(a)
            a2 = a(n)*a(n)
            b2 = b(n)*b(n)
            q = 0.5_wp - (a2 + b2)/24.0_wp + (a2*a2 + a2*b2 + b2*b2)/720.0_wp
            g(n) = (a(n) + b(n))*q
            dg(n) = q + (a(n) + b(n))*a(n)*(-1.0_wp/12.0_wp + (4.0_wp*a2 + 2.0_wp*b2)/720.0_wp)
        end do
    end subroutine klein_gordon_array

    !> Forces V'(u_n) for a whole array (the linearized scheme's kernel).
    pure subroutine force_array(id, u, f)
        !> Potential identifier.
        integer, intent(in) :: id
        !> Displacements u_n (contiguous, so that the sines vectorise through libmvec).
        real(wp), intent(in), contiguous :: u(:)
        !> Forces V'(u_n).
        real(wp), intent(out), contiguous :: f(:)

        select case (id)
        case (sine_gordon)
            f = sin(u)
        case (klein_gordon)
            f = u*(1.0_wp + u*u*(-1.0_wp/6.0_wp + u*u/120.0_wp))
        case default
            f = ieee_value(1.0_wp, ieee_quiet_nan)
        end select
    end subroutine force_array

    !> Sum of V(u_n) over an array (the potential part of the discrete energy).
    pure function potential_sum(id, u) result(total)
        !> Potential identifier.
        integer, intent(in) :: id
        !> Displacements u_n (contiguous, so that the sines vectorise).
        real(wp), intent(in), contiguous :: u(:)
        real(wp) :: total

        select case (id)
        case (sine_gordon)
            total = 2.0_wp*sum(sin(0.5_wp*u)**2)
        case (klein_gordon)
            total = sum(u*u*(0.5_wp + u*u*(-1.0_wp/24.0_wp + u*u/720.0_wp)))
        case default
            total = ieee_value(total, ieee_quiet_nan)
        end select
    end function potential_sum

    !> sinc(h) = sin(h)/h and its derivative, by Taylor series near 0 and directly elsewhere.
    elemental subroutine sinc_and_slope(h, sc, dsc)
        !> Argument.
        real(wp), intent(in) :: h
        !> sin(h)/h (1 at h = 0).
        real(wp), intent(out) :: sc
        !> d/dh of sin(h)/h (0 at h = 0).
        real(wp), intent(out) :: dsc
        real(wp) :: h2

        if (abs(h) < h_series) then
            h2 = h*h
            sc = 1.0_wp + h2*(-1.0_wp/6.0_wp + h2*(1.0_wp/120.0_wp + h2*(-1.0_wp/5040.0_wp &
                 + h2*(1.0_wp/362880.0_wp + h2*(-1.0_wp/39916800.0_wp + h2/6227020800.0_wp)))))
            dsc = h*(-1.0_wp/3.0_wp + h2*(1.0_wp/30.0_wp + h2*(-1.0_wp/840.0_wp + h2*(1.0_wp/45360.0_wp &
                  + h2*(-1.0_wp/3991680.0_wp + h2/518918400.0_wp)))))
        else
            sc = sin(h)/h
            dsc = (cos(h) - sc)/h
        end if
    end subroutine sinc_and_slope

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

end module supratrans_potential
