!> The double sine-Gordon potential V(u) = 1 - cos u + eta (1 - cos 2u), with its parameter eta (&chain eta):
!> V' = sin u + 2 eta sin 2u, V'' = cos u + 4 eta cos 2u, V''(0) = 1 + 4 eta.
!>
!> Discrete gradient, without division: with s = (a + b)/2, h = (a - b)/2, cos 2b - cos 2a = 2 sin 2s sin 2h, so
!>
!>     G(a, b) = sin(s) sinc(h) + 2 eta sin(2s) sinc(2h),
!>     dG/da  = (cos(s) sinc(h) + sin(s) sinc'(h))/2 + 2 eta (cos(2s) sinc(2h) + sin(2s) sinc'(2h)),
!>
!> with sin 2s = 2 sin s cos s and cos 2s = cos^2 s - sin^2 s from the sine-Gordon's sin(s), cos(s) (`sin_cos_array`
!> at the first Newton iteration, the angle-addition rotation at the later ones, as for sine-Gordon).
!>
!> Bounds: with x = cos u, V'' = 8 eta x^2 + x - 4 eta on [-1, 1]: its least value is 4 eta - 1 for eta < 1/16 and
!> -1/(32 eta) - 4 eta for eta >= 1/16 (at x = -1/(16 eta)); dG/da >= min V''/2. |V'''| = |sin u + 8 eta sin 2u| <=
!> 1 + 8 |eta| for every u, so |d2G/da2| <= (1 + 8 |eta|)/3.
module supratrans_potential_double_sine_gordon
    use supratrans_kinds, only: wp
    use supratrans_potential, only: potential_type
    use supratrans_sine_kernels, only: sin_cos_array, rotate_sin_cos, sinc_and_slope, max_abs, rotate_max
    implicit none
    private

    !> Nodes beyond the s stages of the AVF averaging rule (s + 3: one more than sine-Gordon, for the second
    !> harmonic cos 2u; not exact, its error is part of the ledger's residual).
    integer, parameter, public :: double_sine_gordon_extra_nodes = 3

    !> V(u) = 1 - cos u + eta (1 - cos 2u).
    type, extends(potential_type), public :: double_sine_gordon_potential
        !> Weight eta of the second harmonic (&chain eta).
        real(wp) :: eta = 0.0_wp
    contains
        procedure :: name => dsg_name
        procedure :: v => dsg_v
        procedure :: dv => dsg_dv
        procedure :: d2v => dsg_d2v
        procedure :: gradient_and_slope => dsg_gradient_and_slope
        procedure :: v_each => dsg_v_each
        procedure :: dv_each => dsg_dv_each
        procedure :: d2v_each => dsg_d2v_each
        procedure :: potential_sum => dsg_potential_sum
        procedure :: gradient_and_slope_array => dsg_gradient_and_slope_array
        procedure :: gradient_and_slope_refine => dsg_gradient_and_slope_refine
        procedure :: slope_lower_bound => dsg_slope_lower_bound
        procedure :: curvature_bound => dsg_curvature_bound
        procedure :: curvature_grows => dsg_curvature_grows
        procedure :: averaging_nodes => dsg_averaging_nodes
    end type double_sine_gordon_potential

contains

    !> "double-sine-gordon".
    pure function dsg_name(self) result(name)
        !> The potential.
        class(double_sine_gordon_potential), intent(in) :: self
        character(len=:), allocatable :: name

        name = "double-sine-gordon"
    end function dsg_name

    !> V(u) = 2 sin^2(u/2) + 2 eta sin^2 u (1 - cos u and 1 - cos 2u without cancellation near u = 0).
    pure function dsg_v(self, u) result(y)
        !> The potential.
        class(double_sine_gordon_potential), intent(in) :: self
        !> Displacement u.
        real(wp), intent(in) :: u
        real(wp) :: y

        y = 2.0_wp*sin(0.5_wp*u)**2 + 2.0_wp*self%eta*sin(u)**2
    end function dsg_v

    !> V'(u) = sin u + 2 eta sin 2u.
    pure function dsg_dv(self, u) result(y)
        !> The potential.
        class(double_sine_gordon_potential), intent(in) :: self
        !> Displacement u.
        real(wp), intent(in) :: u
        real(wp) :: y

        y = sin(u) + 2.0_wp*self%eta*sin(2.0_wp*u)
    end function dsg_dv

    !> V''(u) = cos u + 4 eta cos 2u.
    pure function dsg_d2v(self, u) result(y)
        !> The potential.
        class(double_sine_gordon_potential), intent(in) :: self
        !> Displacement u.
        real(wp), intent(in) :: u
        real(wp) :: y

        y = cos(u) + 4.0_wp*self%eta*cos(2.0_wp*u)
    end function dsg_d2v

    !> G(a, b) and dG/da of one pair.
    pure subroutine dsg_gradient_and_slope(self, a, b, g, dg)
        !> The potential.
        class(double_sine_gordon_potential), intent(in) :: self
        !> New and old values.
        real(wp), intent(in) :: a, b
        !> G(a, b) and dG/da.
        real(wp), intent(out) :: g, dg
        real(wp) :: ga(1), dga(1), ss(1), cs(1)

        ss(1) = sin(0.5_wp*(a + b))
        cs(1) = cos(0.5_wp*(a + b))
        call dsg_finish(self%eta, [a], [b], ss, cs, ga, dga)
        g = ga(1)
        dg = dga(1)
    end subroutine dsg_gradient_and_slope

    !> V(u_n), site by site.
    pure subroutine dsg_v_each(self, u, y)
        !> The potential.
        class(double_sine_gordon_potential), intent(in) :: self
        !> Displacements.
        real(wp), intent(in), contiguous :: u(:)
        !> V(u_n).
        real(wp), intent(out), contiguous :: y(:)

        y = 2.0_wp*sin(0.5_wp*u)**2 + 2.0_wp*self%eta*sin(u)**2
    end subroutine dsg_v_each

    !> V'(u_n), site by site.
    pure subroutine dsg_dv_each(self, u, y)
        !> The potential.
        class(double_sine_gordon_potential), intent(in) :: self
        !> Displacements.
        real(wp), intent(in), contiguous :: u(:)
        !> V'(u_n).
        real(wp), intent(out), contiguous :: y(:)

        y = sin(u) + 2.0_wp*self%eta*sin(2.0_wp*u)
    end subroutine dsg_dv_each

    !> V''(u_n), site by site.
    pure subroutine dsg_d2v_each(self, u, y)
        !> The potential.
        class(double_sine_gordon_potential), intent(in) :: self
        !> Displacements.
        real(wp), intent(in), contiguous :: u(:)
        !> V''(u_n).
        real(wp), intent(out), contiguous :: y(:)

        y = cos(u) + 4.0_wp*self%eta*cos(2.0_wp*u)
    end subroutine dsg_d2v_each



    !> Sum of V(u_n).
    pure function dsg_potential_sum(self, u) result(total)
        !> The potential.
        class(double_sine_gordon_potential), intent(in) :: self
        !> Displacements.
        real(wp), intent(in), contiguous :: u(:)
        real(wp) :: total

        total = 2.0_wp*sum(sin(0.5_wp*u)**2 + self%eta*sin(u)**2)
    end function dsg_potential_sum

    !> G and dG/da of arrays; sin(s_n), cos(s_n) kept in `ss`, `cs` for the refinement.
    pure subroutine dsg_gradient_and_slope_array(self, a, b, g, dg, ss, cs, h_max)
        !> The potential.
        class(double_sine_gordon_potential), intent(in) :: self
        !> New and old values.
        real(wp), intent(in), contiguous :: a(:), b(:)
        !> G(a_n, b_n) and dG/da.
        real(wp), intent(out), contiguous :: g(:), dg(:)
        !> sin(s_n), cos(s_n).
        real(wp), intent(inout), contiguous :: ss(:), cs(:)
        !> Not used (sinc chooses its branch per site).
        real(wp), intent(in), optional :: h_max
        integer :: n

        do n = 1, size(a)
            g(n) = 0.5_wp*(a(n) + b(n))        ! g holds s until G is formed
        end do
        call sin_cos_array(g, ss, cs)
        call dsg_finish(self%eta, a, b, ss, cs, g, dg)
    end subroutine dsg_gradient_and_slope_array

    !> G and dG/da after a Newton update: sin(s), cos(s) rotated by delta/2 when max |delta| <= `rotate_max`,
    !> else evaluated afresh.
    pure subroutine dsg_gradient_and_slope_refine(self, a, b, delta, g, dg, ss, cs, delta_max, h_max)
        !> The potential.
        class(double_sine_gordon_potential), intent(in) :: self
        !> New values (updated by `delta`) and old values.
        real(wp), intent(in), contiguous :: a(:), b(:)
        !> The update just applied to `a`.
        real(wp), intent(in), contiguous :: delta(:)
        !> G(a_n, b_n) and dG/da.
        real(wp), intent(out), contiguous :: g(:), dg(:)
        !> sin(s_n), cos(s_n) of the previous `a` on entry, of the new one on exit.
        real(wp), intent(inout), contiguous :: ss(:), cs(:)
        !> max |delta_n| when the caller knows it; max |a_n - b_n|/2 (not used).
        real(wp), intent(in), optional :: delta_max, h_max
        real(wp) :: dmax
        integer :: n

        if (present(delta_max)) then
            dmax = delta_max
        else
            dmax = max_abs(delta)
        end if
        if (dmax <= rotate_max) then
            call rotate_sin_cos(delta, ss, cs)
        else
            do n = 1, size(a)
                g(n) = 0.5_wp*(a(n) + b(n))
            end do
            call sin_cos_array(g, ss, cs)
        end if
        call dsg_finish(self%eta, a, b, ss, cs, g, dg)
    end subroutine dsg_gradient_and_slope_refine

    !> dG/da >= min V''/2: (4 eta - 1)/2 for eta < 1/16, (-1/(32 eta) - 4 eta)/2 otherwise.
    pure function dsg_slope_lower_bound(self) result(x)
        !> The potential.
        class(double_sine_gordon_potential), intent(in) :: self
        real(wp) :: x

        if (self%eta < 1.0_wp/16.0_wp) then
            x = 0.5_wp*(4.0_wp*self%eta - 1.0_wp)
        else
            x = 0.5_wp*(-1.0_wp/(32.0_wp*self%eta) - 4.0_wp*self%eta)
        end if
    end function dsg_slope_lower_bound

    !> |d2G/da2| <= (1 + 8 |eta|)/3, for every u.
    pure function dsg_curvature_bound(self, u_max) result(bound)
        !> The potential.
        class(double_sine_gordon_potential), intent(in) :: self
        !> Largest |u| (not needed).
        real(wp), intent(in) :: u_max
        real(wp) :: bound

        bound = (1.0_wp + 8.0_wp*abs(self%eta))/3.0_wp
    end function dsg_curvature_bound

    !> False: the curvature bound holds for every u.
    pure function dsg_curvature_grows(self) result(flag)
        !> The potential.
        class(double_sine_gordon_potential), intent(in) :: self
        logical :: flag

        flag = .false.
    end function dsg_curvature_grows

    !> s + `double_sine_gordon_extra_nodes` nodes.
    pure function dsg_averaging_nodes(self, stages) result(nodes)
        !> The potential.
        class(double_sine_gordon_potential), intent(in) :: self
        !> Stages s.
        integer, intent(in) :: stages
        integer :: nodes

        nodes = stages + double_sine_gordon_extra_nodes
    end function dsg_averaging_nodes

    !> G and dG/da from sin(s_n), cos(s_n) and h_n = (a_n - b_n)/2 (sinc by its series or directly, per site).
    pure subroutine dsg_finish(eta, a, b, ss, cs, g, dg)
        !> Weight eta.
        real(wp), intent(in) :: eta
        !> New and old values.
        real(wp), intent(in) :: a(:), b(:)
        !> sin(s_n), cos(s_n).
        real(wp), intent(in) :: ss(:), cs(:)
        !> G(a_n, b_n) and dG/da.
        real(wp), intent(out) :: g(:), dg(:)
        integer :: n
        real(wp) :: h, sc, dsc, sc2, dsc2, s2, c2

        do n = 1, size(a)
            h = 0.5_wp*(a(n) - b(n))
            call sinc_and_slope(h, sc, dsc)
            call sinc_and_slope(2.0_wp*h, sc2, dsc2)
            s2 = 2.0_wp*ss(n)*cs(n)
            c2 = (cs(n) - ss(n))*(cs(n) + ss(n))
            g(n) = ss(n)*sc + 2.0_wp*eta*s2*sc2
            dg(n) = 0.5_wp*(cs(n)*sc + ss(n)*dsc) + 2.0_wp*eta*(c2*sc2 + s2*dsc2)
        end do
    end subroutine dsg_finish

end module supratrans_potential_double_sine_gordon
