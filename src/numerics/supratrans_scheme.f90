!> The matrix form of the paper's finite-difference scheme (Sec. 3.1):
!>
!>     A u^{k+1} + G(u^{k+1}, u^{k-1}) = B u^k + C u^{k-1} + v^k,
!>
!> with A = tridiag(a, b_n, a), B = tridiag(c^2, d, c^2), C = tridiag(a, e_n, a) and
!> a = -beta/(2 dt), b_n = (alpha_n + 2 beta)/(2 dt) + m^2/2 + 1/dt^2, d = 2/dt^2 - 2 c^2,
!> e_n = (alpha_n + 2 beta)/(2 dt) - m^2/2 - 1/dt^2, alpha_n = gamma + gamma'(n) per site.
!>
!> Time levels are stored as arrays u(0:N+1) whose end cells hold the boundary values u_0 = psi(t) and
!> u_{N+1} = 0, so the boundary vector v^k never needs to be formed: the stencils read the end cells.
module supratrans_scheme
    use supratrans_kinds, only: wp
    use supratrans_config, only: chain_params
    use supratrans_chain, only: damping_profile
    use supratrans_potential, only: potential_type, new_potential
    implicit none
    private

    public :: scheme_init, scheme_rhs, scheme_rhs_and_predictor, scheme_apply_a

    !> Coefficients of the scheme for one chain and one time step: the matrices A, B, C (their diagonals and
    !> off-diagonals) and the site damping. Set once by `scheme_init`, read-only afterwards; the work arrays of the
    !> Newton iteration and of the tridiagonal solves belong to the steppers.
    type, public :: scheme_type
        !> Number of oscillators N.
        integer :: n = 0
        !> On-site potential V (with its parameters).
        class(potential_type), allocatable :: potential
        !> Time step Delta t.
        real(wp) :: dt = 0.0_wp
        !> Coupling squared, c^2.
        real(wp) :: c2 = 0.0_wp
        !> Off-diagonal a = -beta/(2 dt) of A and C.
        real(wp) :: a = 0.0_wp
        !> Diagonal d = 2/dt^2 - 2 c^2 of B.
        real(wp) :: d = 0.0_wp
        !> Diagonal b_n of A, size N.
        real(wp), allocatable :: b(:)
        !> min_n b_n (Newton's stopping test bounds the inverse Jacobian with it).
        real(wp) :: b_min = 0.0_wp
        !> Diagonal e_n of C, size N.
        real(wp), allocatable :: e(:)
        !> Site damping alpha_n = gamma + gamma'(n), size N.
        real(wp), allocatable :: alpha(:)
        !> The external damping gamma that `alpha` was built from.
        real(wp) :: gamma = 0.0_wp
        !> First site whose alpha_n differs from gamma (the absorber's first site; N + 1 when there is none): the
        !> terms of the absorber's dissipation before it are exactly zero (`step_powers`).
        integer :: absorber_first = 1
    end type scheme_type

contains

    !> Set up the coefficients of the scheme for a chain and a time step.
    pure subroutine scheme_init(scheme, chain, dt)
        !> The scheme to initialise.
        type(scheme_type), intent(out) :: scheme
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        !> Time step Delta t.
        real(wp), intent(in) :: dt
        integer :: n

        n = chain%n
        scheme%n = n
        call new_potential(chain, scheme%potential)
        scheme%dt = dt
        scheme%c2 = chain%c**2
        scheme%a = -chain%beta/(2.0_wp*dt)
        scheme%d = 2.0_wp/dt**2 - 2.0_wp*chain%c**2
        scheme%alpha = damping_profile(chain)
        scheme%b = (scheme%alpha + 2.0_wp*chain%beta)/(2.0_wp*dt) + chain%m2/2.0_wp + 1.0_wp/dt**2
        scheme%b_min = minval(scheme%b)
        scheme%e = (scheme%alpha + 2.0_wp*chain%beta)/(2.0_wp*dt) - chain%m2/2.0_wp - 1.0_wp/dt**2
        scheme%gamma = chain%gamma
        scheme%absorber_first = 1
        do while (scheme%absorber_first <= n)
            if (scheme%alpha(scheme%absorber_first) /= chain%gamma) exit
            scheme%absorber_first = scheme%absorber_first + 1
        end do
    end subroutine scheme_init

    !> Form rhs = B u^k + C u^{k-1} + (the u_0^k, u_0^{k-1} parts of v^k).
    !> The u_0^{k+1} part of v^k is not included: it is applied with A through `u_new(0)`.
    pure subroutine scheme_rhs(scheme, u_cur, u_old, rhs)
        !> Scheme coefficients.
        type(scheme_type), intent(in) :: scheme
        !> Level k, u(0:N+1) with boundary cells.
        real(wp), intent(in) :: u_cur(0:)
        !> Level k-1, u(0:N+1) with boundary cells.
        real(wp), intent(in) :: u_old(0:)
        !> The right-hand side, size N.
        real(wp), intent(out), contiguous :: rhs(:)
        integer :: n

        do n = 1, scheme%n
            rhs(n) = scheme%d*u_cur(n) + scheme%c2*(u_cur(n - 1) + u_cur(n + 1)) &
                            + scheme%e(n)*u_old(n) + scheme%a*(u_old(n - 1) + u_old(n + 1))
        end do
    end subroutine scheme_rhs

    !> `scheme_rhs` and, in the same pass, the cubic extrapolation x = 3 u^k - 3 u^{k-1} + u^{k-2} of the next level
    !> (Newton's predictor, into x(1:N); unless `extrapolate` is false: then x(1:N) is the caller's predictor) with
    !> max_n |x_n - u_n^{k-1}|/2.
    pure subroutine scheme_rhs_and_predictor(scheme, u_older, u_old, u_cur, rhs, x, h_max, extrapolate)
        !> Scheme coefficients.
        type(scheme_type), intent(in) :: scheme
        !> Levels k-2, k-1, k, u(0:N+1) with boundary cells.
        real(wp), intent(in), contiguous :: u_older(0:), u_old(0:), u_cur(0:)
        !> The right-hand side, size N.
        real(wp), intent(out), contiguous :: rhs(:)
        !> The next level u(0:N+1): x(1:N) set, the boundary cells untouched.
        real(wp), intent(inout), contiguous :: x(0:)
        !> max_n |x_n - u_n^{k-1}|/2.
        real(wp), intent(out) :: h_max
        !> Whether to extrapolate (default true).
        logical, intent(in), optional :: extrapolate
        integer :: n
        logical :: cubic

        cubic = .true.
        if (present(extrapolate)) cubic = extrapolate
        h_max = 0.0_wp
        if (cubic) then
            !$omp simd reduction(max: h_max)
            do n = 1, scheme%n
                rhs(n) = scheme%d*u_cur(n) + scheme%c2*(u_cur(n - 1) + u_cur(n + 1)) &
                         + scheme%e(n)*u_old(n) + scheme%a*(u_old(n - 1) + u_old(n + 1))
                x(n) = 3.0_wp*(u_cur(n) - u_old(n)) + u_older(n)
                h_max = max(h_max, 0.5_wp*abs(x(n) - u_old(n)))
            end do
        else
            !$omp simd reduction(max: h_max)
            do n = 1, scheme%n
                rhs(n) = scheme%d*u_cur(n) + scheme%c2*(u_cur(n - 1) + u_cur(n + 1)) &
                         + scheme%e(n)*u_old(n) + scheme%a*(u_old(n - 1) + u_old(n + 1))
                h_max = max(h_max, 0.5_wp*abs(x(n) - u_old(n)))
            end do
        end if
    end subroutine scheme_rhs_and_predictor

    !> y = A x for x(0:N+1) including its boundary cells (so y_1 contains a x_0).
    pure subroutine scheme_apply_a(scheme, x, y)
        !> Scheme coefficients.
        type(scheme_type), intent(in) :: scheme
        !> Vector with boundary cells, x(0:N+1).
        real(wp), intent(in) :: x(0:)
        !> Result, size N.
        real(wp), intent(out) :: y(:)
        integer :: n

        do n = 1, scheme%n
            y(n) = scheme%b(n)*x(n) + scheme%a*(x(n - 1) + x(n + 1))
        end do
    end subroutine scheme_apply_a

end module supratrans_scheme
