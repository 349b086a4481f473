!> Small maps with known fixed-point branches, folds and Floquet crossings, for the tests of Newton-shooting and of
!> the continuation (test_continuation.pf). The first component is x -> x + h (A - x + c x^3): its fixed points
!> solve A = x - c x^3 and its multiplier is 1 - h (1 - 3 c x^2). With c = 1 the branch from x = 0 folds at
!> x_f = 1/sqrt(3), A_f = 2 / (3 sqrt(3)), where the multiplier passes +1; with c = -1 it has no fold. The other
!> components (`mode`):
!> - `mode_fold`: y -> y/2 + x^2 (contracting, fixed at y = 2 x^2; a 2-D branch with a known shape),
!> - `mode_doubling`: y -> (1/2 - 5 A) y + y^3 (fixed at y = 0, multiplier 1/2 - 5 A through -1 at A = 3/10),
!> - `mode_torus`: (y1, y2) -> (3/5 + 2 A) R(1) (y1, y2) - |y|^2 (y1, y2) / 10 (R(1) the rotation by 1 rad; a
!>   Neimark-Sacker normal form: fixed at y = 0, a complex pair of modulus 3/5 + 2 A through the unit circle at
!>   A = 1/5).
module continuation_maps
    use supratrans_kinds, only: wp
    use supratrans_fixed_point_map, only: fixed_point_map, map_ok
    implicit none
    private

    !> Second component contracting, y -> y/2 + x^2.
    integer, parameter, public :: mode_fold = 0
    !> Second component with a multiplier through -1 at A = 3/10.
    integer, parameter, public :: mode_doubling = 1
    !> A complex pair through the unit circle at A = 1/5 (two more components).
    integer, parameter, public :: mode_torus = 2

    !> The test map; see the module's documentation.
    type, extends(fixed_point_map), public :: model_map
        !> Relaxation factor h of the first component.
        real(wp) :: h = 0.5_wp
        !> Coefficient c of the cubic term: +1 a fold, -1 none.
        real(wp) :: c = 1.0_wp
        !> `mode_fold`, `mode_doubling` or `mode_torus`.
        integer :: mode = mode_fold
    contains
        !> P(x; A) and its derivatives.
        procedure :: apply => model_apply
    end type model_map

    public :: new_model_map

contains

    !> A model map of the given mode (dim 2, or 3 for the torus), relaxation h and cubic coefficient c.
    function new_model_map(mode, h, c) result(map)
        !> `mode_fold`, `mode_doubling` or `mode_torus`.
        integer, intent(in) :: mode
        !> Relaxation factor.
        real(wp), intent(in) :: h
        !> Cubic coefficient.
        real(wp), intent(in) :: c
        type(model_map) :: map

        map%mode = mode
        map%h = h
        map%c = c
        map%dim = merge(3, 2, mode == mode_torus)
    end function new_model_map

    !> P(x; A) with dP/dx and dP/dA.
    subroutine model_apply(self, x, amplitude, px, status, jac, dpda)
        !> The map.
        class(model_map), intent(inout) :: self
        !> The state.
        real(wp), intent(in) :: x(:)
        !> The parameter A.
        real(wp), intent(in) :: amplitude
        !> P(x; A).
        real(wp), intent(out) :: px(:)
        !> `map_ok`.
        integer, intent(out) :: status
        !> dP/dx.
        real(wp), intent(out), optional :: jac(:, :)
        !> dP/dA.
        real(wp), intent(out), optional :: dpda(:)
        real(wp) :: r, q, cs, sn, y1, y2, s2

        status = map_ok
        px(1) = x(1) + self%h*(amplitude - x(1) + self%c*x(1)**3)
        if (present(jac)) then
            jac = 0.0_wp
            jac(1, 1) = 1.0_wp + self%h*(-1.0_wp + 3.0_wp*self%c*x(1)**2)
        end if
        if (present(dpda)) then
            dpda = 0.0_wp
            dpda(1) = self%h
        end if
        select case (self%mode)
        case (mode_fold)
            px(2) = 0.5_wp*x(2) + x(1)**2
            if (present(jac)) then
                jac(2, 1) = 2.0_wp*x(1)
                jac(2, 2) = 0.5_wp
            end if
        case (mode_doubling)
            q = 0.5_wp - 5.0_wp*amplitude
            px(2) = q*x(2) + x(2)**3
            if (present(jac)) jac(2, 2) = q + 3.0_wp*x(2)**2
            if (present(dpda)) dpda(2) = -5.0_wp*x(2)
        case default  ! mode_torus
            r = 0.6_wp + 2.0_wp*amplitude
            cs = cos(1.0_wp)
            sn = sin(1.0_wp)
            y1 = x(2)
            y2 = x(3)
            s2 = y1**2 + y2**2
            px(2) = r*(cs*y1 - sn*y2) - 0.1_wp*s2*y1
            px(3) = r*(sn*y1 + cs*y2) - 0.1_wp*s2*y2
            if (present(jac)) then
                jac(2, 2) = r*cs - 0.1_wp*(s2 + 2.0_wp*y1**2)
                jac(2, 3) = -r*sn - 0.2_wp*y1*y2
                jac(3, 2) = r*sn - 0.2_wp*y1*y2
                jac(3, 3) = r*cs - 0.1_wp*(s2 + 2.0_wp*y2**2)
            end if
            if (present(dpda)) then
                dpda(2) = 2.0_wp*(cs*y1 - sn*y2)
                dpda(3) = 2.0_wp*(sn*y1 + cs*y2)
            end if
        end select
    end subroutine model_apply

end module continuation_maps
