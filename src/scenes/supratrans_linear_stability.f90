!> Linear stability theory of the integrators for the chain linearised at rest (V''(0) = 1 for both
!> potentials), the prediction the scene `stability` (`supratrans_scene_stability`) measures against, and the bound on
!> dt of the continuation scene. Dirichlet modes with sin^2(theta/2), theta = k pi/(N+1), k = 1..N, the largest
!> s^2 = sin^2(N pi/(2(N+1)))):
!> - newton (energy-conserving): the discrete energy is positive definite, hence the scheme stable, iff
!>   4 c^2 s^2 dt^2 < 4 + (V''(0) + m^2) dt^2; damping (gamma, beta, absorber) only dissipates and does not move this
!>   bound (per mode, the characteristic roots of a z^2 - b z + c' = 0 stay inside the unit circle iff
!>   |b| <= a + c', independent of the damping). So where the paper's condition allows a larger dt
!>   (gamma > 0 or beta > 0), it is necessary but not sufficient;
!> - linearized (V'(u^k) explicit): (4 c^2 s^2 + 1 - m^2) dt^2 < 4, again independent of the damping;
!> - rk4, rk8: the largest dt with |R(dt lambda)| <= 1 for every eigenvalue lambda of the linearised system
!>   u' = v, v' = -(c^2 L + (V''(0) + m^2)) u - (diag(alpha_n) + beta L) v (L the Dirichlet Laplacian, absorber
!>   included), computed with LAPACK `dgeev`; R is the method's stability polynomial. Undamped: 2 sqrt(2) /
!>   omega_max for RK4, 3.0018 / omega_max for rk8, omega_max^2 = V''(0) + m^2 + 4 c^2 s^2;
!> - avf4, avf8 (Gauss collocation): A-stable on the linear chain, no bound.
module supratrans_linear_stability
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_nan
    use supratrans_kinds, only: wp
    use supratrans_config, only: chain_params, method_newton, method_linearized, method_rk8, method_avf4, method_avf8
    use supratrans_chain, only: damping_profile, gap_squared, onsite_stiffness
    use supratrans_stepper_rk8, only: rk8_stability_coefficients
    use supratrans_eigen, only: general_eigenvalues
    implicit none
    private

    public :: linear_stability_dt, rk_spectrum_dt, chain_spectrum, stability_polynomial

contains

    !> Linear-stability limit of `method` for `chain` linearised at rest (see the module documentation):
    !> closed forms for the leapfrog schemes, the spectrum and the stability polynomial for the Runge-Kutta
    !> methods. huge() when no dt is too large.
    function linear_stability_dt(chain, method) result(dt)
        !> Chain parameters (c, m^2, gamma, beta, absorber, N).
        type(chain_params), intent(in) :: chain
        !> Method identifier.
        integer, intent(in) :: method
        real(wp) :: dt
        real(wp) :: s2, q
        real(wp), allocatable :: re(:), im(:)

        s2 = sin(0.5_wp*acos(-1.0_wp)*real(chain%n, wp)/real(chain%n + 1, wp))**2
        select case (method)
        case (method_avf4, method_avf8)   ! Gauss collocation on the linear chain: A-stable (supratrans_stepper_avf)
            dt = huge(1.0_wp)
        case (method_newton)
            q = 4.0_wp*chain%c**2*s2 - gap_squared(chain)
            dt = huge(1.0_wp)
            if (q > 0.0_wp) dt = 2.0_wp/sqrt(q)
        case (method_linearized)
            q = 4.0_wp*chain%c**2*s2 + 1.0_wp - chain%m2
            dt = huge(1.0_wp)
            if (q > 0.0_wp) dt = 2.0_wp/sqrt(q)
        case default
            call chain_spectrum(chain, re, im)
            dt = rk_spectrum_dt(stability_polynomial(method), re, im)
        end select
    end function linear_stability_dt

    !> Coefficients g_0.. of the stability polynomial R(z) = sum g_j z^j of an explicit Runge-Kutta method.
    pure function stability_polynomial(method) result(g)
        !> `method_rk4` or `method_rk8`.
        integer, intent(in) :: method
        real(wp), allocatable :: g(:)

        select case (method)
        case (method_rk8)
            g = rk8_stability_coefficients()
        case default
            g = [1.0_wp, 1.0_wp, 0.5_wp, 1.0_wp/6.0_wp, 1.0_wp/24.0_wp]
        end select
    end function stability_polynomial

    !> Eigenvalues of the chain linearised at rest, as a first-order system of size 2N:
    !> u' = v, v' = -(c^2 L + (V''(0) + m^2) I) u - (diag(alpha_n) + beta L) v, L = tridiag(-1, 2, -1) (Dirichlet ends).
    subroutine chain_spectrum(chain, re, im)
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        !> Real and imaginary parts of the 2N eigenvalues.
        real(wp), allocatable, intent(out) :: re(:), im(:)
        real(wp), allocatable :: a(:, :), alpha(:)
        real(wp) :: k0
        integer :: n, i, info

        n = chain%n
        k0 = onsite_stiffness(chain)      ! V''(0): the chain at rest
        allocate (alpha(n))
        alpha = damping_profile(chain)
        allocate (a(2*n, 2*n), source=0.0_wp)
        allocate (re(2*n), im(2*n))
        do i = 1, n
            a(i, n + i) = 1.0_wp
            a(n + i, i) = -(2.0_wp*chain%c**2 + k0 + chain%m2)
            a(n + i, n + i) = -(alpha(i) + 2.0_wp*chain%beta)
            if (i > 1) then
                a(n + i, i - 1) = chain%c**2
                a(n + i, n + i - 1) = chain%beta
            end if
            if (i < n) then
                a(n + i, i + 1) = chain%c**2
                a(n + i, n + i + 1) = chain%beta
            end if
        end do
        call general_eigenvalues(a, re, im, info)
        if (info /= 0) then
            re = ieee_value(1.0_wp, ieee_quiet_nan)
            im = re
        end if
    end subroutine chain_spectrum

    !> Largest dt with |R(dt lambda)| <= 1 (to 1e-9) for every eigenvalue lambda = re + i im: along each
    !> eigenvalue's ray the first exit from the stability region, found by a scan of |z| in steps of 1/512 up to 8
    !> and bisection; the smallest over the eigenvalues. huge() if none exits.
    pure function rk_spectrum_dt(g, re, im) result(dt)
        !> Stability polynomial coefficients g_0, g_1, ...
        real(wp), intent(in) :: g(:)
        !> Eigenvalues.
        real(wp), intent(in) :: re(:), im(:)
        real(wp) :: dt
        real(wp) :: r, tau, tau_lo, tau_hi, radius_max, step
        integer :: i, j, k

        dt = huge(1.0_wp)
        radius_max = 8.0_wp
        step = 1.0_wp/512.0_wp
        do i = 1, size(re)
            if (ieee_is_nan(re(i)) .or. ieee_is_nan(im(i))) then
                dt = ieee_value(1.0_wp, ieee_quiet_nan)
                return
            end if
            r = hypot(re(i), im(i))
            if (.not. (r > 0.0_wp)) cycle
            ! scan tau |lambda| = j step up to min(radius_max, dt |lambda|)
            tau_hi = -1.0_wp
            do j = 1, nint(radius_max/step)
                tau = real(j, wp)*step/r
                if (tau >= dt) exit
                if (outside(tau)) then
                    tau_hi = tau
                    exit
                end if
            end do
            if (tau_hi < 0.0_wp) cycle
            tau_lo = tau_hi - step/r
            do k = 1, 60
                tau = 0.5_wp*(tau_lo + tau_hi)
                if (outside(tau)) then
                    tau_hi = tau
                else
                    tau_lo = tau
                end if
            end do
            dt = min(dt, tau_lo)
        end do

    contains

        !> |R(tau lambda_i)| > 1 + 1e-9?
        pure logical function outside(tau)
            real(wp), intent(in) :: tau
            complex(wp) :: z, p
            integer :: jj

            z = cmplx(tau*re(i), tau*im(i), kind=wp)
            p = cmplx(g(size(g)), 0.0_wp, kind=wp)
            do jj = size(g) - 1, 1, -1
                p = p*z + g(jj)
            end do
            outside = abs(p) > 1.0_wp + 1.0e-9_wp
        end function outside

    end function rk_spectrum_dt

end module supratrans_linear_stability
