!> The sine-Gordon potential V(u) = 1 - cos u (paper Sec. 2.1): V' = sin u, V'' = cos u, V''(0) = 1.
!>
!> Discrete gradient G(a, b) = sin(s) sinc(h), s = (a + b)/2, h = (a - b)/2, and dG/da = (cos(s) sinc(h) +
!> sin(s) sinc'(h))/2 (the tuned array kernels of `supratrans_sine_kernels`: sin(s), cos(s) by the branch-free
!> `sin_cos_array` at the first Newton iteration, advanced by angle addition at the later ones). Bounds: min V'' = -1,
!> so dG/da >= -1/2; |V'''| <= 1, so |d2G/da2| <= 1/3 for every u.
module supratrans_potential_sine_gordon
    use supratrans_kinds, only: wp
    use supratrans_potential, only: potential_type
    use supratrans_sine_kernels, only: sine_gordon_gradient, sine_gordon_gradient_array, sine_gordon_gradient_refine, &
                                       sine_gordon_force_array
    implicit none
    private

    !> Nodes beyond the s stages of the AVF averaging rule (s + 2 nodes: 4 for avf4, 6 for avf8). Not exact: its
    !> error (the integrand is analytic, sigma_u moves by about h |v| over a step) is the balance residual of a
    !> step, measured (test_avf, A = 1.9, dt = 0.1) at 2e-14 (avf4) and 1e-15 (avf8) of the energy scale, 1e-12 for
    !> avf4 at dt = 0.5; the methods' own errors there are 5e-5 and 4e-10 relative (docs/method.md). On the
    !> paper-default run at A = 1.9, avf8 (6 nodes): 4e-15 a step at dt = 0.1, 8e-14 at 0.3125, 1.3e-12 at 0.4,
    !> where the method's error of the injected energy is 4e-8 (8 nodes: 4e-15 throughout, and 13% more time).
    integer, parameter, public :: sine_gordon_extra_nodes = 2

    !> V(u) = 1 - cos u.
    type, extends(potential_type), public :: sine_gordon_potential
    contains
        procedure :: name => sg_name
        procedure :: v => sg_v
        procedure :: dv => sg_dv
        procedure :: d2v => sg_d2v
        procedure :: gradient_and_slope => sg_gradient_and_slope
        procedure :: v_each => sg_v_each
        procedure :: dv_each => sg_dv_each
        procedure :: d2v_each => sg_d2v_each
        procedure :: force_array => sg_force_array
        procedure :: d2v_array => sg_d2v_array
        procedure :: potential_sum => sg_potential_sum
        procedure :: gradient_and_slope_array => sg_gradient_and_slope_array
        procedure :: gradient_and_slope_refine => sg_gradient_and_slope_refine
        procedure :: slope_lower_bound => sg_slope_lower_bound
        procedure :: curvature_bound => sg_curvature_bound
        procedure :: curvature_grows => sg_curvature_grows
        procedure :: averaging_nodes => sg_averaging_nodes
    end type sine_gordon_potential

contains

    !> "sine-gordon".
    pure function sg_name(self) result(name)
        !> The potential.
        class(sine_gordon_potential), intent(in) :: self
        character(len=:), allocatable :: name

        name = "sine-gordon"
    end function sg_name

    !> V(u) = 1 - cos u, as 2 sin^2(u/2) (no cancellation near u = 0).
    pure function sg_v(self, u) result(y)
        !> The potential.
        class(sine_gordon_potential), intent(in) :: self
        !> Displacement u.
        real(wp), intent(in) :: u
        real(wp) :: y

        y = 2.0_wp*sin(0.5_wp*u)**2
    end function sg_v

    !> V'(u) = sin u.
    pure function sg_dv(self, u) result(y)
        !> The potential.
        class(sine_gordon_potential), intent(in) :: self
        !> Displacement u.
        real(wp), intent(in) :: u
        real(wp) :: y

        y = sin(u)
    end function sg_dv

    !> V''(u) = cos u.
    pure function sg_d2v(self, u) result(y)
        !> The potential.
        class(sine_gordon_potential), intent(in) :: self
        !> Displacement u.
        real(wp), intent(in) :: u
        real(wp) :: y

        y = cos(u)
    end function sg_d2v

    !> G(a, b) = sin(s) sinc(h) and dG/da.
    pure subroutine sg_gradient_and_slope(self, a, b, g, dg)
        !> The potential.
        class(sine_gordon_potential), intent(in) :: self
        !> New and old values.
        real(wp), intent(in) :: a, b
        !> G(a, b) and dG/da.
        real(wp), intent(out) :: g, dg

        call sine_gordon_gradient(a, b, g, dg)
    end subroutine sg_gradient_and_slope

    !> V(u_n), site by site.
    pure subroutine sg_v_each(self, u, y)
        !> The potential.
        class(sine_gordon_potential), intent(in) :: self
        !> Displacements.
        real(wp), intent(in), contiguous :: u(:)
        !> V(u_n).
        real(wp), intent(out), contiguous :: y(:)
        integer :: n

        !GCC$ novector
        do n = 1, size(u)
            y(n) = 2.0_wp*sin(0.5_wp*u(n))**2
        end do
    end subroutine sg_v_each

    !> V'(u_n) = sin u_n, site by site.
    pure subroutine sg_dv_each(self, u, y)
        !> The potential.
        class(sine_gordon_potential), intent(in) :: self
        !> Displacements.
        real(wp), intent(in), contiguous :: u(:)
        !> V'(u_n).
        real(wp), intent(out), contiguous :: y(:)
        integer :: n

        !GCC$ novector
        do n = 1, size(u)
            y(n) = sin(u(n))
        end do
    end subroutine sg_dv_each

    !> V''(u_n) = cos u_n, site by site.
    pure subroutine sg_d2v_each(self, u, y)
        !> The potential.
        class(sine_gordon_potential), intent(in) :: self
        !> Displacements.
        real(wp), intent(in), contiguous :: u(:)
        !> V''(u_n).
        real(wp), intent(out), contiguous :: y(:)
        integer :: n

        !GCC$ novector
        do n = 1, size(u)
            y(n) = cos(u(n))
        end do
    end subroutine sg_d2v_each

    !> V'(u_n) = sin u_n, vectorised (libmvec's sine; the quiet tail by its Taylor polynomial).
    pure subroutine sg_force_array(self, u, y)
        !> The potential.
        class(sine_gordon_potential), intent(in) :: self
        !> Displacements.
        real(wp), intent(in), contiguous :: u(:)
        !> V'(u_n).
        real(wp), intent(out), contiguous :: y(:)

        call sine_gordon_force_array(u, y)
    end subroutine sg_force_array

    !> V''(u_n) = cos u_n, vectorised (the array form: libmvec's vector cos).
    pure subroutine sg_d2v_array(self, u, y)
        !> The potential.
        class(sine_gordon_potential), intent(in) :: self
        !> Displacements.
        real(wp), intent(in), contiguous :: u(:)
        !> V''(u_n).
        real(wp), intent(out), contiguous :: y(:)

        y = cos(u)
    end subroutine sg_d2v_array

    !> Sum of 1 - cos u_n.
    pure function sg_potential_sum(self, u) result(total)
        !> The potential.
        class(sine_gordon_potential), intent(in) :: self
        !> Displacements (contiguous, so that the sines vectorise through libmvec).
        real(wp), intent(in), contiguous :: u(:)
        real(wp) :: total

        total = 2.0_wp*sum(sin(0.5_wp*u)**2)
    end function sg_potential_sum

    !> G and dG/da of arrays; sin(s_n), cos(s_n) kept in `ss`, `cs` for the refinement.
    pure subroutine sg_gradient_and_slope_array(self, a, b, g, dg, ss, cs, h_max)
        !> The potential.
        class(sine_gordon_potential), intent(in) :: self
        !> New and old values.
        real(wp), intent(in), contiguous :: a(:), b(:)
        !> G(a_n, b_n) and dG/da.
        real(wp), intent(out), contiguous :: g(:), dg(:)
        !> sin(s_n), cos(s_n).
        real(wp), intent(inout), contiguous :: ss(:), cs(:)
        !> max |a_n - b_n|/2 when the caller knows it.
        real(wp), intent(in), optional :: h_max

        call sine_gordon_gradient_array(a, b, g, dg, ss, cs, h_max)
    end subroutine sg_gradient_and_slope_array

    !> G and dG/da after a Newton update: sin(s), cos(s) rotated by delta/2 when max |delta| <= `rotate_max`.
    pure subroutine sg_gradient_and_slope_refine(self, a, b, delta, g, dg, ss, cs, delta_max, h_max)
        !> The potential.
        class(sine_gordon_potential), intent(in) :: self
        !> New values (updated by `delta`) and old values.
        real(wp), intent(in), contiguous :: a(:), b(:)
        !> The update just applied to `a`.
        real(wp), intent(in), contiguous :: delta(:)
        !> G(a_n, b_n) and dG/da.
        real(wp), intent(out), contiguous :: g(:), dg(:)
        !> sin(s_n), cos(s_n) of the previous `a` on entry, of the new one on exit.
        real(wp), intent(inout), contiguous :: ss(:), cs(:)
        !> max |delta_n| and max |a_n - b_n|/2 when the caller knows them.
        real(wp), intent(in), optional :: delta_max, h_max

        call sine_gordon_gradient_refine(a, b, delta, g, dg, ss, cs, delta_max, h_max)
    end subroutine sg_gradient_and_slope_refine

    !> dG/da >= min V''/2 = -1/2.
    pure function sg_slope_lower_bound(self) result(x)
        !> The potential.
        class(sine_gordon_potential), intent(in) :: self
        real(wp) :: x

        x = -0.5_wp
    end function sg_slope_lower_bound

    !> |d2G/da2| <= max |V'''|/3 = 1/3, for every u.
    pure function sg_curvature_bound(self, u_max) result(bound)
        !> The potential.
        class(sine_gordon_potential), intent(in) :: self
        !> Largest |u| (not needed).
        real(wp), intent(in) :: u_max
        real(wp) :: bound

        bound = 1.0_wp/3.0_wp
    end function sg_curvature_bound

    !> False: the curvature bound holds for every u.
    pure function sg_curvature_grows(self) result(flag)
        !> The potential.
        class(sine_gordon_potential), intent(in) :: self
        logical :: flag

        flag = .false.
    end function sg_curvature_grows

    !> s + `sine_gordon_extra_nodes` nodes.
    pure function sg_averaging_nodes(self, stages) result(nodes)
        !> The potential.
        class(sine_gordon_potential), intent(in) :: self
        !> Stages s.
        integer, intent(in) :: stages
        integer :: nodes

        nodes = stages + sine_gordon_extra_nodes
    end function sg_averaging_nodes

end module supratrans_potential_sine_gordon
