!> Small maps with known fixed-point branches, folds and Floquet crossings, for the tests of Newton-shooting and of
!> the continuation (test_continuation.pf). The first component is x -> x + h (A - x + c x^3): its fixed points
!> solve A = x - c x^3 and its multiplier is 1 - h (1 - 3 c x^2). With c = 1 the branch from x = 0 folds at
!> x_f = 1/sqrt(3), A_f = 2 / (3 sqrt(3)), where the multiplier passes +1; with c = -1 it has no fold. The other
!> components (`mode`):
!> - `mode_fold`: y -> y/2 + x^2 (contracting, fixed at y = 2 x^2; a 2-D branch with a known shape),
!> - `mode_doubling`: y -> (1/2 - 5 A) y + y^3 (fixed at y = 0, multiplier 1/2 - 5 A through -1 at A = 3/10),
!> - `mode_pitchfork`: y -> (1/2 + 2 A) y - y^3 (fixed at y = 0, multiplier 1/2 + 2 A through +1 at A = 1/4: a branch
!>   point, where the branches y^2 = 2 A - 1/2 leave the branch y = 0, which does not turn there; with `c2` = +1,
!>   y -> (1/2 + 2 A) y + y^3, the branches y^2 = 1/2 - 2 A leave it below A = 1/4),
!> - `mode_torus`: (y1, y2) -> (3/5 + 2 A) R(1) (y1, y2) - |y|^2 (y1, y2) / 10 (R(1) the rotation by 1 rad; a
!>   Neimark-Sacker normal form: fixed at y = 0, a complex pair of modulus 3/5 + 2 A through the unit circle at
!>   A = 1/5),
!> - `mode_crowded`: the fold map plus `n_pairs` exact rotations (y1, y2) -> R(theta_k) (y1, y2) (multipliers on the
!>   unit circle, like the trapped modes of the undamped chain), the whole seen through the Householder reflection
!>   Q = I - 2 v v^T / |v|^2 (x -> Q P(Q x)), so that the Jacobian is a dense matrix whose eigenvalues LAPACK finds on
!>   the circle only up to roundoff.
module continuation_maps
    use supratrans_kinds, only: wp
    use supratrans_config, only: run_config, method_newton
    use supratrans_fixed_point_map, only: fixed_point_map, map_ok, map_failed
    implicit none
    private

    !> Second component contracting, y -> y/2 + x^2.
    integer, parameter, public :: mode_fold = 0
    !> Second component with a multiplier through -1 at A = 3/10.
    integer, parameter, public :: mode_doubling = 1
    !> A complex pair through the unit circle at A = 1/5 (two more components).
    integer, parameter, public :: mode_torus = 2
    !> The fold map with rotations whose multipliers lie on the unit circle, in dense coordinates.
    integer, parameter, public :: mode_crowded = 3
    !> Second component with a multiplier through +1 at A = 1/4 (a branch point of a symmetric pitchfork).
    integer, parameter, public :: mode_pitchfork = 4

    !> The test map; see the module's documentation.
    type, extends(fixed_point_map), public :: model_map
        !> Relaxation factor h of the first component.
        real(wp) :: h = 0.5_wp
        !> Coefficient c of the cubic term: +1 a fold, -1 none.
        real(wp) :: c = 1.0_wp
        !> Coefficient of the cubic term of `mode_pitchfork`'s second component: -1 supercritical (the branches
        !> y^2 = 2 A - 1/2 above A = 1/4, stable), +1 subcritical (y^2 = 1/2 - 2 A below it, unstable).
        real(wp) :: c2 = -1.0_wp
        !> `mode_fold`, `mode_doubling` or `mode_torus`.
        integer :: mode = mode_fold
        !> Number of rotation pairs of `mode_crowded`.
        integer :: n_pairs = 0
        !> The map fails (`map_failed`) for A above this (a scheme that cannot be evaluated there).
        real(wp) :: fail_above = huge(1.0_wp)
    contains
        !> P(x; A) and its derivatives.
        procedure :: apply => model_apply
    end type model_map

    public :: new_model_map, short_test_chain

contains

    !> A model map of the given mode (dim 2, or 3 for the torus), relaxation h and cubic coefficient c.
    function new_model_map(mode, h, c, n_pairs) result(map)
        !> `mode_fold`, `mode_doubling` or `mode_torus`.
        integer, intent(in) :: mode
        !> Relaxation factor.
        real(wp), intent(in) :: h
        !> Cubic coefficient.
        real(wp), intent(in) :: c
        !> Rotation pairs of `mode_crowded` (default 0).
        integer, intent(in), optional :: n_pairs
        type(model_map) :: map

        map%mode = mode
        map%h = h
        map%c = c
        map%dim = merge(3, 2, mode == mode_torus)
        if (present(n_pairs)) map%n_pairs = n_pairs
        if (mode == mode_crowded) map%dim = 2 + 2*map%n_pairs
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

        if (amplitude > self%fail_above) then
            px = 0.0_wp
            status = map_failed
            return
        end if
        if (self%mode == mode_crowded) then
            call crowded_apply(self, x, amplitude, px, jac, dpda)
            status = map_ok
            return
        end if
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
        case (mode_pitchfork)
            q = 0.5_wp + 2.0_wp*amplitude
            px(2) = q*x(2) + self%c2*x(2)**3
            if (present(jac)) jac(2, 2) = q + 3.0_wp*self%c2*x(2)**2
            if (present(dpda)) dpda(2) = 2.0_wp*x(2)
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

    !> `mode_crowded`: Q P~(Q x) with the block map P~ (fold map, rotations) and the reflection Q.
    pure subroutine crowded_apply(self, x, amplitude, px, jac, dpda)
        type(model_map), intent(in) :: self
        real(wp), intent(in) :: x(:), amplitude
        real(wp), intent(out) :: px(:)
        real(wp), intent(out), optional :: jac(:, :), dpda(:)
        real(wp), allocatable :: v(:), z(:), pz(:), jz(:, :), q(:, :)
        real(wp) :: theta
        integer :: n, k, i, j

        n = size(x)
        v = [(1.0_wp + 0.3_wp*i, i=1, n)]
        allocate (q(n, n), jz(n, n), pz(n))
        do j = 1, n
            do i = 1, n
                q(i, j) = merge(1.0_wp, 0.0_wp, i == j) - 2.0_wp*v(i)*v(j)/sum(v**2)
            end do
        end do
        z = matmul(q, x)
        jz = 0.0_wp
        pz(1) = z(1) + self%h*(amplitude - z(1) + self%c*z(1)**3)
        pz(2) = 0.5_wp*z(2) + z(1)**2
        jz(1, 1) = 1.0_wp + self%h*(-1.0_wp + 3.0_wp*self%c*z(1)**2)
        jz(2, 1) = 2.0_wp*z(1)
        jz(2, 2) = 0.5_wp
        do k = 1, self%n_pairs
            theta = 0.7_wp*k
            i = 2*k + 1
            pz(i) = cos(theta)*z(i) - sin(theta)*z(i + 1)
            pz(i + 1) = sin(theta)*z(i) + cos(theta)*z(i + 1)
            jz(i, i) = cos(theta)
            jz(i, i + 1) = -sin(theta)
            jz(i + 1, i) = sin(theta)
            jz(i + 1, i + 1) = cos(theta)
        end do
        px = matmul(q, pz)
        if (present(jac)) jac = matmul(q, matmul(jz, q))
        if (present(dpda)) dpda = self%h*q(:, 1)
    end subroutine crowded_apply

    !> The physics run of the continuation tests on the paper's chain, made short: undamped sine-Gordon, Omega = 0.9,
    !> c = 4, dt ~ 0.05 (newton), N = 40 with the absorber on N0 = 20 < n <= 40, the drive at full amplitude (no ramp).
    pure function short_test_chain() result(run)
        type(run_config) :: run

        run%chain%n = 40
        run%chain%n0 = 20
        run%drive%omega = 0.9_wp
        run%drive%ramp_time = 0.0_wp
        run%numerics%method = method_newton
        run%numerics%dt = 0.05_wp
    end function short_test_chain

end module continuation_maps
