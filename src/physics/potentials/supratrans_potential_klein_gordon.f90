!> The Klein-Gordon potential (phi^6 truncation of 1 - cos u, paper Sec. 2.1): V(u) = u^2/2 - u^4/24 + u^6/720,
!> V' = u - u^3/6 + u^5/120, V'' = 1 - u^2/2 + u^4/24, V''(0) = 1.
!>
!> Discrete gradient, a polynomial: G(a, b) = (a + b) [1/2 - (a^2 + b^2)/24 + (a^4 + a^2 b^2 + b^4)/720], dG/da
!> likewise (no transcendentals). Bounds: min V'' = -1/2 (at u^2 = 6), so dG/da >= -1/4; |V'''| = |u^3/6 - u|
!> <= u_max + u_max^3/6, so |d2G/da2| <= (u_max + u_max^3/6)/3: it grows with |u|. The AVF averaging rule with
!> 3s nodes is exact (V' of degree 5 along a stage polynomial).
module supratrans_potential_klein_gordon
    use supratrans_kinds, only: wp
    use supratrans_potential, only: potential_type
    implicit none
    private

    !> Nodes of the AVF averaging rule per stage: 3s nodes are exact for V' of degree 5.
    integer, parameter, public :: klein_gordon_nodes_per_stage = 3

    !> V(u) = u^2/2 - u^4/24 + u^6/720.
    type, extends(potential_type), public :: klein_gordon_potential
    contains
        procedure :: name => kg_name
        procedure :: v => kg_v
        procedure :: dv => kg_dv
        procedure :: d2v => kg_d2v
        procedure :: gradient_and_slope => kg_gradient_and_slope
        procedure :: v_each => kg_v_each
        procedure :: dv_each => kg_dv_each
        procedure :: d2v_each => kg_d2v_each
        procedure :: potential_sum => kg_potential_sum
        procedure :: gradient_and_slope_array => kg_gradient_and_slope_array
        procedure :: gradient_and_slope_refine => kg_gradient_and_slope_refine
        procedure :: slope_lower_bound => kg_slope_lower_bound
        procedure :: curvature_bound => kg_curvature_bound
        procedure :: curvature_grows => kg_curvature_grows
        procedure :: averaging_nodes => kg_averaging_nodes
    end type klein_gordon_potential

contains

    !> "klein-gordon".
    pure function kg_name(self) result(name)
        !> The potential.
        class(klein_gordon_potential), intent(in) :: self
        character(len=:), allocatable :: name

        name = "klein-gordon"
    end function kg_name

    !> V(u) = u^2/2 - u^4/24 + u^6/720.
    pure function kg_v(self, u) result(y)
        !> The potential.
        class(klein_gordon_potential), intent(in) :: self
        !> Displacement u.
        real(wp), intent(in) :: u
        real(wp) :: y

        y = u*u*(0.5_wp + u*u*(-1.0_wp/24.0_wp + u*u/720.0_wp))
    end function kg_v

    !> V'(u) = u - u^3/6 + u^5/120.
    pure function kg_dv(self, u) result(y)
        !> The potential.
        class(klein_gordon_potential), intent(in) :: self
        !> Displacement u.
        real(wp), intent(in) :: u
        real(wp) :: y

        y = u*(1.0_wp + u*u*(-1.0_wp/6.0_wp + u*u/120.0_wp))
    end function kg_dv

    !> V''(u) = 1 - u^2/2 + u^4/24.
    pure function kg_d2v(self, u) result(y)
        !> The potential.
        class(klein_gordon_potential), intent(in) :: self
        !> Displacement u.
        real(wp), intent(in) :: u
        real(wp) :: y

        y = 1.0_wp + u*u*(-0.5_wp + u*u/24.0_wp)
    end function kg_d2v

    !> G(a, b) and dG/da (the array kernel on one pair: the same bits).
    pure subroutine kg_gradient_and_slope(self, a, b, g, dg)
        !> The potential.
        class(klein_gordon_potential), intent(in) :: self
        !> New and old values.
        real(wp), intent(in) :: a, b
        !> G(a, b) and dG/da.
        real(wp), intent(out) :: g, dg
        real(wp) :: ga(1), dga(1)

        call klein_gordon_array([a], [b], ga, dga)
        g = ga(1)
        dg = dga(1)
    end subroutine kg_gradient_and_slope

    !> V(u_n) (a polynomial: the same bits site by site or vectorised).
    pure subroutine kg_v_each(self, u, y)
        !> The potential.
        class(klein_gordon_potential), intent(in) :: self
        !> Displacements.
        real(wp), intent(in), contiguous :: u(:)
        !> The values.
        real(wp), intent(out), contiguous :: y(:)

        y = u*u*(0.5_wp + u*u*(-1.0_wp/24.0_wp + u*u/720.0_wp))
    end subroutine kg_v_each

    !> V'(u_n).
    pure subroutine kg_dv_each(self, u, y)
        !> The potential.
        class(klein_gordon_potential), intent(in) :: self
        !> Displacements.
        real(wp), intent(in), contiguous :: u(:)
        !> The values.
        real(wp), intent(out), contiguous :: y(:)

        y = u*(1.0_wp + u*u*(-1.0_wp/6.0_wp + u*u/120.0_wp))
    end subroutine kg_dv_each

    !> V''(u_n).
    pure subroutine kg_d2v_each(self, u, y)
        !> The potential.
        class(klein_gordon_potential), intent(in) :: self
        !> Displacements.
        real(wp), intent(in), contiguous :: u(:)
        !> The values.
        real(wp), intent(out), contiguous :: y(:)

        y = 1.0_wp + u*u*(-0.5_wp + u*u/24.0_wp)
    end subroutine kg_d2v_each



    !> Sum of V(u_n).
    pure function kg_potential_sum(self, u) result(total)
        !> The potential.
        class(klein_gordon_potential), intent(in) :: self
        !> Displacements.
        real(wp), intent(in), contiguous :: u(:)
        real(wp) :: total

        total = sum(u*u*(0.5_wp + u*u*(-1.0_wp/24.0_wp + u*u/720.0_wp)))
    end function kg_potential_sum

    !> G and dG/da of arrays (`ss`, `cs` untouched).
    pure subroutine kg_gradient_and_slope_array(self, a, b, g, dg, ss, cs, h_max)
        !> The potential.
        class(klein_gordon_potential), intent(in) :: self
        !> New and old values.
        real(wp), intent(in), contiguous :: a(:), b(:)
        !> G(a_n, b_n) and dG/da.
        real(wp), intent(out), contiguous :: g(:), dg(:)
        !> Not used.
        real(wp), intent(inout), contiguous :: ss(:), cs(:)
        !> Not used.
        real(wp), intent(in), optional :: h_max

        call klein_gordon_array(a, b, g, dg)
    end subroutine kg_gradient_and_slope_array

    !> G and dG/da after a Newton update: computed afresh (polynomials; `ss`, `cs` untouched).
    pure subroutine kg_gradient_and_slope_refine(self, a, b, delta, g, dg, ss, cs, delta_max, h_max)
        !> The potential.
        class(klein_gordon_potential), intent(in) :: self
        !> New values (updated by `delta`) and old values.
        real(wp), intent(in), contiguous :: a(:), b(:)
        !> The update just applied to `a`.
        real(wp), intent(in), contiguous :: delta(:)
        !> G(a_n, b_n) and dG/da.
        real(wp), intent(out), contiguous :: g(:), dg(:)
        !> Not used.
        real(wp), intent(inout), contiguous :: ss(:), cs(:)
        !> Not used.
        real(wp), intent(in), optional :: delta_max, h_max

        call klein_gordon_array(a, b, g, dg)
    end subroutine kg_gradient_and_slope_refine

    !> dG/da >= min V''/2 = -1/4 (V'' = 1 - u^2/2 + u^4/24 is least, -1/2, at u^2 = 6).
    pure function kg_slope_lower_bound(self) result(x)
        !> The potential.
        class(klein_gordon_potential), intent(in) :: self
        real(wp) :: x

        x = -0.25_wp
    end function kg_slope_lower_bound

    !> |d2G/da2| <= max |V'''|/3 <= (u_max + u_max^3/6)/3 for |a|, |b| <= u_max.
    pure function kg_curvature_bound(self, u_max) result(bound)
        !> The potential.
        class(klein_gordon_potential), intent(in) :: self
        !> Largest |u| of the arguments.
        real(wp), intent(in) :: u_max
        real(wp) :: bound

        bound = (u_max + u_max**3/6.0_wp)/3.0_wp
    end function kg_curvature_bound

    !> True: the curvature bound grows with |u|.
    pure function kg_curvature_grows(self) result(flag)
        !> The potential.
        class(klein_gordon_potential), intent(in) :: self
        logical :: flag

        flag = .true.
    end function kg_curvature_grows

    !> 3s nodes: exact.
    pure function kg_averaging_nodes(self, stages) result(nodes)
        !> The potential.
        class(klein_gordon_potential), intent(in) :: self
        !> Stages s.
        integer, intent(in) :: stages
        integer :: nodes

        nodes = klein_gordon_nodes_per_stage*stages
    end function kg_averaging_nodes

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

end module supratrans_potential_klein_gordon
