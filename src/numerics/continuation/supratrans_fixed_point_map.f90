!> A smooth map P(x; A) of R^d with a parameter A (the drive amplitude), whose fixed points x = P(x; A) are found by
!> Newton-shooting and continued in A (`supratrans_continuation`).
!>
!> The map of the physics is the one-period map of a stepper (`supratrans_period_map`): x is the state of the
!> discrete scheme at t = 0 (the pair (u^0, u^1) of the paper's three-level schemes, (u, u_t) of the Runge-Kutta
!> methods), P(x; A) the state one drive period 2 pi / Omega later, driven at amplitude A without a ramp. Its
!> Jacobian dP/dx is the monodromy matrix of the discrete scheme (its eigenvalues are the Floquet multipliers), dP/dA
!> the response to the amplitude. Tests use small maps with a known fold.
!>
!> An implementation holds its own work arrays: one object per thread.
module supratrans_fixed_point_map
    use supratrans_kinds, only: wp
    implicit none
    private

    !> `apply` status: P(x; A) (and its derivatives, if asked for) computed.
    integer, parameter, public :: map_ok = 0
    !> `apply` status: the map could not be evaluated (an implicit step did not converge, a non-finite value).
    integer, parameter, public :: map_failed = 1

    !> A parameter-dependent map P(x; A) of R^dim with its derivatives.
    type, abstract, public :: fixed_point_map
        !> Dimension d of the state x.
        integer :: dim = 0
    contains
        !> P(x; A) and, when present, its Jacobian dP/dx (d x d) and dP/dA (d).
        procedure(map_apply), deferred :: apply
        !> Scalar measures of the orbit through x at amplitude A, for the branch's record: the largest |u_n| over
        !> the orbit and its mean stored energy (default: max |x_i| and sum x_i^2 / 2).
        procedure :: measures => default_measures
    end type fixed_point_map

    abstract interface
        !> P(x; A) and, when present, dP/dx and dP/dA.
        subroutine map_apply(self, x, amplitude, px, status, jac, dpda)
            import :: fixed_point_map, wp
            !> The map (its work arrays change).
            class(fixed_point_map), intent(inout) :: self
            !> The state x, size dim.
            real(wp), intent(in) :: x(:)
            !> The parameter A.
            real(wp), intent(in) :: amplitude
            !> P(x; A), size dim.
            real(wp), intent(out) :: px(:)
            !> `map_ok` or `map_failed`.
            integer, intent(out) :: status
            !> dP/dx, dim x dim.
            real(wp), intent(out), optional :: jac(:, :)
            !> dP/dA, size dim.
            real(wp), intent(out), optional :: dpda(:)
        end subroutine map_apply
    end interface

contains

    !> Default measures of the orbit through x: max |x_i| and sum x_i^2 / 2.
    subroutine default_measures(self, x, amplitude, umax, energy)
        !> The map.
        class(fixed_point_map), intent(inout) :: self
        !> The state x.
        real(wp), intent(in) :: x(:)
        !> The parameter A.
        real(wp), intent(in) :: amplitude
        !> Largest |u_n| over the orbit.
        real(wp), intent(out) :: umax
        !> Mean stored energy over the orbit.
        real(wp), intent(out) :: energy

        umax = maxval(abs(x))
        energy = 0.5_wp*sum(x**2)
    end subroutine default_measures

end module supratrans_fixed_point_map
