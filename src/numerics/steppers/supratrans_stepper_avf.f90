!> Steppers `avf4` and `avf8`: the energy-preserving collocation method of Hairer (E. Hairer, "Energy-preserving
!> variant of collocation methods", JNAIAM 5 (2010) 73-84; the continuous-stage form of the average-vector-field
!> method, Cohen & Hairer, BIT 51 (2011) 91-101) with s Gauss nodes (s = 2: order 4; s = 4: order 8), applied to
!> the method-of-lines system of the chain (`supratrans_mol`) in the variables (u, v = u_t), with the drive, both
!> dampings and the absorber, and a discrete energy balance that closes every step.
!>
!> The method. Write the chain as y' = (J - R) grad H0(y) + f(t), y = (u, v), where H0 is the energy of the chain
!> with u_0 = 0 (H0 = sum v^2/2 + m^2 u^2/2 + V(u) + c^2/2 sum_{n=0}^{N} (u_{n+1} - u_n)^2, u_0 = u_{N+1} = 0), J the
!> canonical matrix, R = diag(0, alpha_n - beta Delta) >= 0 (Delta the second difference with v_0 = v_{N+1} = 0),
!> and f = (0, (c^2 psi + beta psi') e_1) the drive. A step of size h from t0 is the polynomial sigma of degree s
!> with sigma(t0) = y0 and, at the Gauss nodes t_i = t0 + c_i h,
!>     sigma'(t_i) = (J - R) g_i + f(t_i),   g_i = (1/b_i) int_0^1 l_i(tau) grad H0(sigma(t0 + tau h)) dtau,
!> l_i the Lagrange polynomials of the nodes, b_i the Gauss weights; y1 = sigma(t0 + h). The quadratic part of
!> H0 makes g_i the value at the node (the integrand has degree 2s - 1), so only the on-site force V' is averaged:
!>     Gbar_{n,i} = (1/b_i) int_0^1 l_i(tau) V'(sigma_{u,n}(tau)) dtau,
!> computed with a Gauss-Legendre rule of `nq` nodes. For Klein-Gordon (V' of degree 5, sigma_u of degree s) the
!> integrand has degree 6s - 1 and the rule of 3s nodes is exact. For sine-Gordon the rule has s + 2 nodes (4 for
!> avf4, 6 for avf8) and is not exact: its error (the integrand is analytic, sigma_u moves by about h |v| over a
!> step) is the balance residual of a step, measured (test_avf, A = 1.9, dt = 0.1) at 2e-14 (avf4) and 1e-15 (avf8)
!> of the energy scale, 1e-12 for avf4 at dt = 0.5; the methods' own errors there are 5e-5 and 4e-10 relative
!> (docs/method.md). On the paper-default run at A = 1.9, avf8 (6 nodes): 4e-15 a step at dt = 0.1, 8e-14 at
!> 0.3125, 1.3e-12 at 0.4, where the method's error of the injected energy is 4e-8 (8 nodes: 4e-15 throughout,
!> and 13% more time).
!> Everything else is s-stage Gauss collocation: U_i = u0 + h sum_j a_ij V_j, V_i = v0 + h sum_j a_ij F_i.
!>
!> The discrete energy balance. Since sigma' has degree s - 1 and the rule is exact for it,
!>     H0(y1) - H0(y0) = int grad H0(sigma) . sigma' = h sum_i b_i g_i . sigma'(t_i)
!>                     = h sum_i b_i [ - g_i . R g_i + g_i . f(t_i) ]                  (g_i . J g_i = 0),
!> exactly (to the stage equations' residual and the rule's error). With H = H0 + c^2 psi^2/2 - c^2 u_1 psi (the
!> ledger's energy, u_0 = psi) the ledger of the step is, with V_{0,i} = psi'(t_i), V_{N+1,i} = 0:
!>     injected  = h sum_i b_i [c^2 psi(t_i) V_{1,i} + beta (psi'(t_i) - V_{1,i}) psi'(t_i)]
!>                 + c^2 [psi^2/2 - u_1 psi]_{t0}^{t0+h},
!>     D^gamma = h sum_i b_i gamma sum_n V_{n,i}^2,   D^abs = h sum_i b_i sum_n gamma'(n) V_{n,i}^2,
!>     D^beta  = h sum_i b_i beta sum_{n=1}^{N+1} (V_{n,i} - V_{n-1,i})^2,
!> and H(y1) - H(y0) = injected - D^gamma - D^beta - D^abs holds exactly: to roundoff for Klein-Gordon, to the
!> rule's error for sine-Gordon. Each term is a Gauss quadrature of the continuous power of `supratrans_mol`, so it
!> converges at the method's order.
!>
!> Solving a step. The unknowns are the stage increments Z_i = U_i - u0 (N x s: small, so their roundoff is
!> eps |Z|); V = W Z/h, W = A^{-1}. The residual R(Z)_i = (W (V - v0))_i / h - F_i(u0 + Z, V) is driven to zero by
!> simplified Newton: the Jacobian with V'' frozen at the predictor's midpoint sigma_u(1/2) (then
!> d Gbar_i / d Z_j = V'' delta_ij exactly), block tridiagonal in the sites with the s x s blocks
!> W^2/h^2 + (2 c^2 + m^2 + V''_n) I + ((alpha_n + 2 beta)/h) W (diagonal) and -c^2 I - (beta/h) W (off). Every
!> block is a polynomial in W, so in the eigenbasis of W (s/2 complex conjugate pairs lambda_k) the system splits
!> into s/2 complex tridiagonal systems (lambda_k/h)^2 + K + (lambda_k/h) L, K and L the stiffness and damping
!> matrices of the chain, factorised once a step by Thomas without pivoting: the matrices are diagonally dominant
!> when |Im lambda_k^2|/h^2 >= 2 c^2 (lambda^2 = 6 +- 10.39i for s = 2; -10.54 +- 44.73i, 30.54 +- 20.09i for
!> s = 4), i.e. for h <= 0.57 (avf4) and 0.79 (avf8) at c = 4; beyond, the real parts usually keep the pivots
!> away from zero, and a zero or non-finite pivot is reported as a breakdown. The predictor
!> extrapolates the previous step's collocation polynomial. The iteration stops when max |delta Z| <= 1e-14
!> max(1, max |u0|); or when the update is below 1e-12 max(1, max |u0|) after a contraction of at least 1e-3 (the
!> next update would be below 1e-15 relative: a sweep at roundoff, which changes nothing, is not done); or when it
!> stagnates at its roundoff floor below 1e-11 max(1, max |u0|). A run that keeps no ledger (`exact_energy`
!> false) stops at &numerics newton_tol. The cap is &numerics newton_max_iter. Measured on the paper-default run at
!> A = 1.9 (avf8, dt = 0.3125, T = 200): 3.7 iterations a step (4.0 without the second test), the first update
!> 1e-4 .. 3e-2 relative, contraction 3e-5 .. 7e-4 per iteration.
!>
!> Cost of an iteration: N sigma_u values and sines per node of the rule, the residual's stencil, the two
!> transforms to and from the eigenbasis of W (real combinations, vectorised) and the s/2 complex recurrences of
!> Thomas (latency-bound: the only serial passes). The part of the residual fixed during a step (stencil of u0 and
!> v0, drive) is formed once a step. The first iteration, from the predictor, takes V' at the stage nodes (s sines,
!> no node sums): the difference from the average is far below the predictor's error (iterations a step unchanged,
!> 3.72 -> 3.75 on that run), and every later iteration solves the method's own equations.
!>
!> Linear stability: the method reduces to Gauss collocation on a linear chain (V' linear), which is A-stable
!> (its stability function is the (s, s) Pade approximant of exp, |R(z)| <= 1 for Re z <= 0): no step limit.
!>
!> Counters: every iteration is one Newton iteration and one (block-)tridiagonal solve, and `nq` right-hand sides
!> (N-force kernels: sines for sine-Gordon).
!>
!> The continuation scene has no one-period map for these methods and refuses them (`supratrans_period_map`).
module supratrans_stepper_avf
    use, intrinsic :: ieee_arithmetic, only: ieee_is_nan, ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp
    use supratrans_strings, only: int_fixed, real_fixed
    use supratrans_config, only: run_config, method_avf8
    use supratrans_chain, only: drive_psi
    use supratrans_mol, only: drive_dpsi
    use supratrans_potential, only: force_array, potential_d2v, sine_gordon
    use supratrans_stepper, only: step_ok, step_not_converged, step_breakdown
    use supratrans_stepper_rk, only: rk_stepper, rk_init
    use supratrans_eigen, only: general_eigenvalues
    use supratrans_state_buffer, only: state_buffer, put_reals, put_reals2, get_reals, get_reals2
    implicit none
    private

    public :: avf_make_tableau, gauss_legendre

    !> Gauss nodes (stages) of `avf4`.
    integer, parameter, public :: avf4_stages = 2
    !> Gauss nodes (stages) of `avf8`.
    integer, parameter, public :: avf8_stages = 4
    !> Nodes of the rule that averages V' per stage node: exact for the Klein-Gordon potential.
    integer, parameter, public :: avf_quadrature_per_stage = 3
    !> Nodes beyond the s stages of the averaging rule for sine-Gordon (s + 2 nodes: 4 for avf4, 6 for avf8). Not
    !> exact: its error is the balance residual of a step, measured (module header) far below the method's error at
    !> every step used. (2s = 8 nodes for avf8 left 1e-15 instead of 1e-12 at dt = 0.4 and cost 13% more.)
    integer, parameter, public :: avf_quadrature_sine_gordon = 2
    !> Relative size of the Newton update at which a step is accepted (the energy identity is then exact to
    !> roundoff).
    real(wp), parameter :: tight_tol = 1.0e-14_wp
    !> Below this relative update, an iteration that no longer shrinks the update 4-fold has reached roundoff.
    real(wp), parameter :: floor_tol = 1.0e-11_wp
    !> An update below this relative size, after one that shrank it at least `settle_rate`-fold, is the last one:
    !> the next would be below settle_tol settle_rate = 1e-15 relative, at roundoff (it would be a sweep that
    !> changes nothing).
    real(wp), parameter :: settle_tol = 1.0e-12_wp
    !> The contraction that `settle_tol` asks to have been observed.
    real(wp), parameter :: settle_rate = 1.0e-3_wp

    !> The coefficients of the s-stage energy-preserving collocation method on [0, 1].
    type, public :: avf_tableau
        !> Stages s (Gauss nodes) and nodes nq of the averaging rule.
        integer :: s = 0, nq = 0
        !> Gauss nodes c_i and weights b_i (size s).
        real(wp), allocatable :: c(:), b(:)
        !> Collocation matrix A (a_ij = int_0^{c_i} l_j), its inverse W and W^2 (s x s).
        real(wp), allocatable :: a(:, :), w(:, :), w2(:, :)
        !> b^T W: y1 = y0 + sum_j bw_j (Y_j - y0) for u and for v (size s).
        real(wp), allocatable :: bw(:)
        !> lag(q, k): Lagrange basis of the nodes (0, c_1 .. c_s) at the averaging rule's node tau_q, k = 0..s.
        real(wp), allocatable :: lag(:, :)
        !> qw(i, q) = w_q l_i(tau_q) / b_i: Gbar_i = sum_q qw(i, q) V'(sigma(tau_q)).
        real(wp), allocatable :: qw(:, :)
        !> The eigenvalues lambda_k of W with positive imaginary part (W has s/2 conjugate pairs, s even), an
        !> eigenvector for each (the columns of tf, s x s/2) and the matching rows of T^{-1} (tinvf, s/2 x s),
        !> T = [t_1, conj t_1, t_2, conj t_2, ...]: a real r is sum_k 2 Re(t_k (tinvf r)_k).
        complex(wp), allocatable :: lam(:), tf(:, :), tinvf(:, :)
        !> The same as real matrices (s x s): row 2k - 1 and 2k of tin are the real and imaginary parts of row k of
        !> tinvf; column 2k - 1 and 2k of tb are 2 Re and -2 Im of column k of tf (delta = tb (Re rho, Im rho)).
        real(wp), allocatable :: tin(:, :), tb(:, :)
        !> mid(j) = L_j(1/2), j = 1..s: sigma_u(1/2) = u0 + sum_j mid(j) Z_j.
        real(wp), allocatable :: mid(:)
        !> ext(i, j) = L_j(1 + c_i) - bw_j, j = 1..s (L the Lagrange basis of lag): the predictor Z_i = sum_j ext(i, j)
        !> Z_j^prev, the previous step's collocation polynomial extrapolated, relative to the new level.
        real(wp), allocatable :: ext(:, :)
    end type avf_tableau

    !> The energy-preserving collocation method on the chain.
    type, extends(rk_stepper), public :: avf_stepper
        !> The method's coefficients.
        type(avf_tableau) :: tab
        !> Update size at which a verdict-only run (no ledger) accepts a step (&numerics newton_tol).
        real(wp) :: tol = 1.0e-10_wp
        !> Iteration cap (&numerics newton_max_iter).
        integer :: max_iter = 20
        !> Stage increments Z_i = U_i - u0 (the unknowns: small, so that their roundoff is eps |Z|, not eps |u|),
        !> stage velocities V, residual (N x s), and the part of the residual fixed during a step (`residual_base`).
        real(wp), allocatable :: uu(:, :), vv(:, :), rr(:, :), rbase(:, :)
        !> sigma_u at the averaging rule's nodes and V' there (N x nq).
        real(wp), allocatable :: sigq(:, :), fqq(:, :)
        !> The previous step's increments Z, for the predictor (N x s).
        real(wp), allocatable :: prev(:, :)
        !> In the eigenbasis of W the simplified Newton matrix splits into s/2 complex tridiagonal matrices
        !> lambda_k^2/h^2 + K + (lambda_k/h) L (K, L the stiffness and damping matrices): the reciprocals of
        !> their Thomas pivots, the multipliers e/pivot, and the right-hand sides / solutions, each as real arrays
        !> N x s whose columns 2k - 1 and 2k are the real and imaginary parts of pair k (so that every pass but the
        !> two recurrences vectorises).
        real(wp), allocatable :: winv(:, :), cfac(:, :), rho(:, :)
        !> Work: sigma_u at the predictor's midpoint, the diagonal of the Newton matrix; the new level's v (size N).
        real(wp), allocatable :: sig(:), fq(:)
        !> The coefficient rows the stage sums use, as contiguous columns (so that no sum copies a row): W(i, :)/h
        !> and its negative (s x s), -qw(i, :) (nq x s), lag(q, 1:s) (s x nq), tin(p, :), tb(j, :), ext(i, :).
        real(wp), allocatable :: wh(:, :), mwh(:, :), mqw(:, :), lagc(:, :), tinc(:, :), tbc(:, :), extc(:, :)
        !> psi and psi' at the stage times (size s).
        real(wp), allocatable :: psi_s(:), dpsi_s(:)
    contains
        !> Set up a run.
        procedure :: init => avf_init
        !> One step.
        procedure :: step => avf_step
        !> Append the state (y and the previous step's increments, which the predictor reads) to a checkpoint.
        procedure :: save_levels => avf_save_levels
        !> Restore what `save_levels` saved (after `init` of the same run).
        procedure :: load_levels => avf_load_levels
    end type avf_stepper

contains

    !> Gauss-Legendre rule of k nodes on [0, 1] (nodes ascending), by Newton's method on P_k.
    pure subroutine gauss_legendre(k, x, w)
        !> Number of nodes.
        integer, intent(in) :: k
        !> Nodes and weights, size k.
        real(wp), intent(out) :: x(:), w(:)
        real(wp), parameter :: pi = acos(-1.0_wp)
        integer :: i, it
        real(wp) :: z, p1, dp, dz

        do i = 1, k
            z = cos(pi*(real(i, wp) - 0.25_wp)/(real(k, wp) + 0.5_wp))
            do it = 1, 100
                call legendre(z, p1, dp)
                dz = p1/dp
                z = z - dz
                if (abs(dz) <= 1.0e-17_wp .or. it > 8 .and. abs(dz) <= 4.0_wp*epsilon(z)) exit
            end do
            call legendre(z, p1, dp)
            x(k + 1 - i) = 0.5_wp*(1.0_wp + z)
            w(k + 1 - i) = 1.0_wp/((1.0_wp - z*z)*dp*dp)
        end do

    contains

        !> P_k(z) and P_k'(z) by the three-term recurrence.
        pure subroutine legendre(z, pk, dpk)
            real(wp), intent(in) :: z
            real(wp), intent(out) :: pk, dpk
            real(wp) :: p0, p1, p2
            integer :: j

            p0 = 1.0_wp
            p1 = z
            do j = 2, k
                p2 = (real(2*j - 1, wp)*z*p1 - real(j - 1, wp)*p0)/real(j, wp)
                p0 = p1
                p1 = p2
            end do
            pk = p1
            dpk = real(k, wp)*(z*p1 - p0)/(z*z - 1.0_wp)
        end subroutine legendre
    end subroutine gauss_legendre

    !> The Lagrange basis polynomial j of `nodes` at t.
    pure function lagrange(nodes, j, t) result(l)
        !> Interpolation nodes.
        real(wp), intent(in) :: nodes(:)
        !> Which basis polynomial (1-based).
        integer, intent(in) :: j
        !> Argument.
        real(wp), intent(in) :: t
        real(wp) :: l
        integer :: m

        l = 1.0_wp
        do m = 1, size(nodes)
            if (m /= j) l = l*(t - nodes(m))/(nodes(j) - nodes(m))
        end do
    end function lagrange

    !> Inverse of a small matrix by Gauss-Jordan elimination with partial pivoting; ok false if singular.
    pure subroutine invert(m, minv, ok)
        !> The matrix (s x s).
        real(wp), intent(in) :: m(:, :)
        !> Its inverse.
        real(wp), intent(out) :: minv(:, :)
        !> False when a pivot is zero or not finite.
        logical, intent(out) :: ok
        real(wp) :: a(size(m, 1), size(m, 1)), row(size(m, 1)), piv, f
        integer :: s, i, j, p

        s = size(m, 1)
        a = m
        minv = 0.0_wp
        do i = 1, s
            minv(i, i) = 1.0_wp
        end do
        ok = .true.
        do i = 1, s
            p = i
            do j = i + 1, s
                if (abs(a(j, i)) > abs(a(p, i))) p = j
            end do
            if (p /= i) then
                row = a(i, :)
                a(i, :) = a(p, :)
                a(p, :) = row
                row = minv(i, :)
                minv(i, :) = minv(p, :)
                minv(p, :) = row
            end if
            piv = a(i, i)
            if (.not. (abs(piv) > 0.0_wp .and. abs(piv) <= huge(piv))) then
                ok = .false.
                return
            end if
            a(i, :) = a(i, :)/piv
            minv(i, :) = minv(i, :)/piv
            do j = 1, s
                if (j == i) cycle
                f = a(j, i)
                a(j, :) = a(j, :) - f*a(i, :)
                minv(j, :) = minv(j, :) - f*minv(i, :)
            end do
        end do
    end subroutine invert

    !> Inverse of a small complex matrix by Gauss-Jordan elimination with partial pivoting; ok false if singular.
    pure subroutine cinvert(m, minv, ok)
        !> The matrix (s x s).
        complex(wp), intent(in) :: m(:, :)
        !> Its inverse.
        complex(wp), intent(out) :: minv(:, :)
        !> False when a pivot is zero.
        logical, intent(out) :: ok
        complex(wp) :: a(size(m, 1), size(m, 1)), row(size(m, 1)), piv, f
        integer :: s, i, j, p

        s = size(m, 1)
        a = m
        minv = (0.0_wp, 0.0_wp)
        do i = 1, s
            minv(i, i) = (1.0_wp, 0.0_wp)
        end do
        ok = .true.
        do i = 1, s
            p = i
            do j = i + 1, s
                if (abs(a(j, i)) > abs(a(p, i))) p = j
            end do
            if (p /= i) then
                row = a(i, :)
                a(i, :) = a(p, :)
                a(p, :) = row
                row = minv(i, :)
                minv(i, :) = minv(p, :)
                minv(p, :) = row
            end if
            piv = a(i, i)
            if (.not. (abs(piv) > 0.0_wp)) then
                ok = .false.
                return
            end if
            a(i, :) = a(i, :)/piv
            minv(i, :) = minv(i, :)/piv
            do j = 1, s
                if (j == i) cycle
                f = a(j, i)
                a(j, :) = a(j, :) - f*a(i, :)
                minv(j, :) = minv(j, :) - f*minv(i, :)
            end do
        end do
    end subroutine cinvert

    !> The eigen-decomposition of W = A^{-1} (s even: s/2 complex conjugate pairs, no real eigenvalue, as for
    !> every Gauss method of even order s): the eigenvalues with positive imaginary part, their eigenvectors (the
    !> last component 1, the others from the first s - 1 rows of (W - lambda I) t = 0), and the rows of T^{-1}.
    pure subroutine eigen_pairs(w, lam, tf, tinvf)
        !> The matrix W (s x s).
        real(wp), intent(in) :: w(:, :)
        !> Eigenvalues with Im > 0, eigenvectors, rows of T^{-1}.
        complex(wp), allocatable, intent(out) :: lam(:), tf(:, :), tinvf(:, :)
        real(wp) :: a(size(w, 1), size(w, 1)), wr(size(w, 1)), wi(size(w, 1))
        complex(wp) :: m(size(w, 1) - 1, size(w, 1) - 1), minv(size(w, 1) - 1, size(w, 1) - 1)
        complex(wp) :: t(size(w, 1), size(w, 1)), tinv(size(w, 1), size(w, 1))
        integer :: s, i, k, info
        logical :: ok

        s = size(w, 1)
        a = w
        call general_eigenvalues(a, wr, wi, info)
        allocate (lam(s/2), tf(s, s/2), tinvf(s/2, s))
        k = 0
        do i = 1, s
            if (wi(i) > 0.0_wp .and. k < s/2) then
                k = k + 1
                lam(k) = cmplx(wr(i), wi(i), kind=wp)
            end if
        end do
        do k = 1, s/2
            m = w(1:s - 1, 1:s - 1)
            do i = 1, s - 1
                m(i, i) = m(i, i) - lam(k)
            end do
            call cinvert(m, minv, ok)
            tf(1:s - 1, k) = -matmul(minv, cmplx(w(1:s - 1, s), 0.0_wp, kind=wp))
            tf(s, k) = (1.0_wp, 0.0_wp)
            t(:, 2*k - 1) = tf(:, k)
            t(:, 2*k) = conjg(tf(:, k))
        end do
        call cinvert(t, tinv, ok)
        do k = 1, s/2
            tinvf(k, :) = tinv(2*k - 1, :)
        end do
    end subroutine eigen_pairs

    !> The coefficients of the s-stage method (Gauss nodes) with an averaging rule of nq nodes.
    pure subroutine avf_make_tableau(s, nq, tab)
        !> Stages.
        integer, intent(in) :: s
        !> Nodes of the averaging rule.
        integer, intent(in) :: nq
        !> The coefficients.
        type(avf_tableau), intent(out) :: tab
        real(wp) :: gx(s), gw(s), tq(nq), wq(nq), z(0:s)
        integer :: i, j, q, k
        logical :: ok

        tab%s = s
        tab%nq = nq
        allocate (tab%c(s), tab%b(s), tab%a(s, s), tab%w(s, s), tab%w2(s, s), tab%bw(s))
        allocate (tab%lag(nq, 0:s), tab%qw(s, nq), tab%ext(s, s), tab%mid(s))
        call gauss_legendre(s, tab%c, tab%b)
        call gauss_legendre(s, gx, gw)
        do i = 1, s
            do j = 1, s
                tab%a(i, j) = 0.0_wp
                do q = 1, s
                    tab%a(i, j) = tab%a(i, j) + tab%c(i)*gw(q)*lagrange(tab%c, j, tab%c(i)*gx(q))
                end do
            end do
        end do
        call invert(tab%a, tab%w, ok)
        tab%w2 = matmul(tab%w, tab%w)
        call eigen_pairs(tab%w, tab%lam, tab%tf, tab%tinvf)
        allocate (tab%tin(s, s), tab%tb(s, s))
        do k = 1, s/2
            tab%tin(2*k - 1, :) = real(tab%tinvf(k, :), wp)
            tab%tin(2*k, :) = aimag(tab%tinvf(k, :))
            tab%tb(:, 2*k - 1) = 2.0_wp*real(tab%tf(:, k), wp)
            tab%tb(:, 2*k) = -2.0_wp*aimag(tab%tf(:, k))
        end do
        tab%bw = matmul(tab%b, tab%w)
        call gauss_legendre(nq, tq, wq)
        z(0) = 0.0_wp
        z(1:s) = tab%c
        do q = 1, nq
            do k = 0, s
                tab%lag(q, k) = lagrange(z, k + 1, tq(q))
            end do
            do i = 1, s
                tab%qw(i, q) = wq(q)*lagrange(tab%c, i, tq(q))/tab%b(i)
            end do
        end do
        do k = 1, s
            tab%mid(k) = lagrange(z, k + 1, 0.5_wp)
        end do
        do i = 1, s
            do k = 1, s
                tab%ext(i, k) = lagrange(z, k + 1, 1.0_wp + tab%c(i)) - tab%bw(k)
            end do
        end do
    end subroutine avf_make_tableau

    !> Set up a run: the chain at rest, the method of `run%numerics%method` (avf4 or avf8), work arrays.
    subroutine avf_init(self, run)
        !> The stepper.
        class(avf_stepper), intent(inout) :: self
        !> Validated run configuration.
        type(run_config), intent(in) :: run
        integer :: s, n, st

        s = avf4_stages
        if (run%numerics%method == method_avf8) s = avf8_stages
        n = run%chain%n
        call rk_init(self, run, s, 2*s)
        if (allocated(self%reason)) return
        ! the averaging rule: exact for Klein-Gordon (3s nodes); for sine-Gordon s + 2 nodes (module header)
        if (run%chain%potential == sine_gordon) then
            call avf_make_tableau(s, s + avf_quadrature_sine_gordon, self%tab)
        else
            call avf_make_tableau(s, avf_quadrature_per_stage*s, self%tab)
        end if
        self%wh = transpose(self%tab%w)/self%dt
        self%mwh = -self%wh
        self%mqw = -transpose(self%tab%qw)
        self%lagc = transpose(self%tab%lag(:, 1:s))
        self%tinc = transpose(self%tab%tin)
        self%tbc = transpose(self%tab%tb)
        self%extc = transpose(self%tab%ext)
        self%tol = run%numerics%newton_tol
        self%max_iter = run%numerics%newton_max_iter
        if (allocated(self%uu)) deallocate (self%uu)
        if (allocated(self%vv)) deallocate (self%vv)
        if (allocated(self%rbase)) deallocate (self%rbase)
        if (allocated(self%sigq)) deallocate (self%sigq)
        if (allocated(self%fqq)) deallocate (self%fqq)
        if (allocated(self%rr)) deallocate (self%rr)
        if (allocated(self%prev)) deallocate (self%prev)
        if (allocated(self%winv)) deallocate (self%winv)
        if (allocated(self%cfac)) deallocate (self%cfac)
        if (allocated(self%rho)) deallocate (self%rho)
        if (allocated(self%sig)) deallocate (self%sig)
        if (allocated(self%fq)) deallocate (self%fq)
        if (allocated(self%psi_s)) deallocate (self%psi_s)
        if (allocated(self%dpsi_s)) deallocate (self%dpsi_s)
        allocate (self%uu(n, s), stat=st)
        if (st == 0) allocate (self%vv(n, s), stat=st)
        if (st == 0) allocate (self%rbase(n, s), stat=st)
        if (st == 0) allocate (self%sigq(n, self%tab%nq), stat=st)
        if (st == 0) allocate (self%fqq(n, self%tab%nq), stat=st)
        if (st == 0) allocate (self%rr(n, s), stat=st)
        if (st == 0) allocate (self%prev(n, s), stat=st)
        if (st == 0) allocate (self%winv(n, s), stat=st)
        if (st == 0) allocate (self%cfac(n, s), stat=st)
        if (st == 0) allocate (self%rho(n, s), stat=st)
        if (st == 0) allocate (self%sig(n), stat=st)
        if (st == 0) allocate (self%fq(n), stat=st)
        if (st == 0) allocate (self%psi_s(s), stat=st)
        if (st == 0) allocate (self%dpsi_s(s), stat=st)
        if (st /= 0) self%reason = "cannot allocate the collocation work arrays of " // trim(int_fixed(n)) &
                                   // " oscillators"
    end subroutine avf_init

    !> One step from t0 = steps dt to t0 + dt.
    subroutine avf_step(self, status)
        !> The stepper.
        class(avf_stepper), intent(inout) :: self
        !> `step_ok`, `step_not_converged` or `step_breakdown`.
        integer, intent(out) :: status
        integer :: n, s, i, it, iters
        real(wp) :: h, t0, change, change_prev, scale, theta
        logical :: ok, accepted

        n = self%n
        s = self%tab%s
        h = self%dt
        t0 = real(self%steps, wp)*h
        do i = 1, s
            self%psi_s(i) = drive_psi(self%drive, t0 + self%tab%c(i)*h)
            self%dpsi_s(i) = drive_dpsi(self%drive, t0 + self%tab%c(i)*h, t0 + 0.5_wp*h)
        end do
        associate (u0 => self%y(1:n), v0 => self%y(n + 1:2*n), tab => self%tab)
            ! predictor: the previous step's collocation polynomial extrapolated (first step: Z_i = c_i h v0)
            do i = 1, s
                if (self%steps == 0) then
                    self%uu(:, i) = (tab%c(i)*h)*v0
                else
                    call lincomb(self%uu(:, i), self%extc(:, i), self%prev, .false.)
                end if
            end do
            scale = max(1.0_wp, maxval(abs(u0)))
            ! V'' frozen at the predictor's midpoint sigma_u(1/2) = u0 + sum_j L_j(1/2) Z_j (its deviation along the
            ! step is half that from u0: a smaller contraction factor)
            self%sig = u0
            call lincomb(self%sig, tab%mid, self%uu, .true.)
            call factorize(self, self%sig, ok)
            status = step_breakdown
            iters = 0
            accepted = .false.
            change_prev = huge(1.0_wp)
            if (ok) then
                call residual_base(self, u0, v0)
                do it = 1, self%max_iter
                    iters = it
                    call residual(self, u0, v0, it == 1)
                    call solve(self, change)
                    if (.not. (change <= huge(change) .and. scale <= huge(scale))) then
                        status = step_breakdown
                        exit
                    end if
                    status = step_not_converged
                    ! (accepting instead when the error left, estimated as theta/(1 - theta) change with theta the
                    ! observed contraction, is below 1e-16 relative saves 10% of the iterations but leaves the
                    ! balance at 1.5e-14 of the energy a step instead of 6e-16: measured, not taken)
                    theta = 1.0_wp
                    if (it > 1) theta = change/change_prev
                    if (self%exact_energy) then
                        accepted = change <= tight_tol*scale .or. (change <= floor_tol*scale .and. theta > 0.25_wp) &
                                   .or. (change <= settle_tol*scale .and. theta <= settle_rate)
                    else
                        accepted = change <= self%tol
                    end if
                    if (accepted) then
                        status = step_ok
                        exit
                    end if
                    change_prev = change
                end do
            end if
            self%newton_iterations = self%newton_iterations + iters
            self%newton_max_iterations = max(self%newton_max_iterations, iters)
            self%tridiagonal_solves = self%tridiagonal_solves + iters
            self%rhs_evaluations = self%rhs_evaluations + int(iters, kind(self%rhs_evaluations))*tab%nq
            if (status /= step_ok) then
                if (status == step_not_converged) then
                    self%reason = "collocation did not converge in " // trim(int_fixed(iters)) // " iterations at t = " &
                                  // trim(real_fixed(t0 + h))
                else
                    self%reason = "collocation broke down (non-finite or singular) at t = " // trim(real_fixed(t0 + h))
                end if
                return
            end if

            ! the stage velocities of the accepted U, then the ledger of the step and the new level
            do i = 1, s
                call lincomb(self%vv(:, i), self%wh(:, i), self%uu, .false.)
            end do
            self%prev = self%uu
        end associate
        call advance(self, t0, h)
        self%steps = self%steps + 1
    end subroutine avf_step

    !> The new level y1 = sigma(t0 + h) from the accepted stages, and the step's ledger terms (module header) added to
    !> the cumulative energies y(2N+1 .. 2N+4).
    pure subroutine advance(self, t0, h)
        !> The stepper: `prev` holds the increments Z, `vv` the stage velocities, `y` the old level (overwritten).
        class(avf_stepper), intent(inout) :: self
        !> Start of the step and step size.
        real(wp), intent(in) :: t0, h
        integer :: n, s, i, m
        real(wp) :: c2, beta, gamma, injected, sum_vv, sum_abs, sum_dv, psi0, psi1, u1_first, u0_first, vn

        n = self%n
        s = self%tab%s
        c2 = self%chain%c**2
        beta = self%chain%beta
        gamma = self%chain%gamma
        injected = 0.0_wp
        sum_vv = 0.0_wp
        sum_abs = 0.0_wp
        sum_dv = 0.0_wp
        do i = 1, s
            associate (v => self%vv(:, i), bi => self%tab%b(i))
                injected = injected + bi*(c2*self%psi_s(i)*v(1) + beta*(self%dpsi_s(i) - v(1))*self%dpsi_s(i))
                sum_dv = sum_dv + bi*((v(1) - self%dpsi_s(i))**2 + v(n)**2)
                do m = 1, n
                    vn = v(m)
                    sum_vv = sum_vv + bi*vn*vn
                    sum_abs = sum_abs + bi*(self%alpha(m) - gamma)*vn*vn
                end do
                do m = 2, n
                    sum_dv = sum_dv + bi*(v(m) - v(m - 1))**2
                end do
            end associate
        end do
        ! the new level: sigma(1) = y0 + sum_j (b^T W)_j (Y_j - y0), for u and for v
        u0_first = self%y(1)
        do i = 1, s
            self%y(1:n) = self%y(1:n) + self%tab%bw(i)*self%prev(:, i)
        end do
        self%fq = self%y(n + 1:2*n)
        do i = 1, s
            self%y(n + 1:2*n) = self%y(n + 1:2*n) + self%tab%bw(i)*(self%vv(:, i) - self%fq)
        end do
        u1_first = self%y(1)
        psi0 = drive_psi(self%drive, t0)
        psi1 = drive_psi(self%drive, t0 + h)
        self%y(2*n + 1) = self%y(2*n + 1) + h*injected &
                          + c2*((0.5_wp*psi1*psi1 - u1_first*psi1) - (0.5_wp*psi0*psi0 - u0_first*psi0))
        self%y(2*n + 2) = self%y(2*n + 2) + h*gamma*sum_vv
        self%y(2*n + 3) = self%y(2*n + 3) + h*beta*sum_dv
        self%y(2*n + 4) = self%y(2*n + 4) + h*sum_abs
    end subroutine advance

    !> Factorise the simplified Newton matrix of the step (module header) in the eigenbasis of W: for each pair k,
    !> Thomas on the complex tridiagonal matrix with diagonal lambda^2 + 2 c^2 + m^2 + V''(u0_n) + lambda
    !> (alpha_n + 2 beta) and off-diagonal e = -c^2 - lambda beta, lambda = lambda_k/h. ok false if a pivot is zero
    !> or not finite.
    pure subroutine factorize(self, u0, ok)
        !> The stepper.
        class(avf_stepper), intent(inout) :: self
        !> Where V'' is frozen (the predictor's midpoint; not `fq`, which holds the diagonal's real part here).
        real(wp), intent(in) :: u0(:)
        !> False when a pivot is zero or not finite.
        logical, intent(out) :: ok
        integer :: n, k, m
        real(wp) :: c2, beta, wre, wim, den
        complex(wp) :: lam(self%tab%s/2), e(self%tab%s/2), d(self%tab%s/2), w, wi, cf

        n = self%n
        c2 = self%chain%c**2
        beta = self%chain%beta
        ok = .true.
        if (self%chain%potential == sine_gordon) then
            self%fq = cos(u0)       ! the array form: libmvec's vector cos (the elemental call is a scalar cos)
        else
            self%fq = potential_d2v(self%chain%potential, u0)
        end if
        self%fq = self%fq + (2.0_wp*c2 + self%chain%m2)
        do k = 1, self%tab%s/2
            lam(k) = self%tab%lam(k)/self%dt
            e(k) = -c2 - lam(k)*beta
            d(k) = lam(k)*lam(k) + 2.0_wp*beta*lam(k)
        end do
        ! the s/2 recurrences interleaved (m outer): their latency chains overlap
        do m = 1, n
            do k = 1, self%tab%s/2
                w = d(k) + self%fq(m) + lam(k)*self%alpha(m)
                if (m > 1) w = w - e(k)*cmplx(self%cfac(m - 1, 2*k - 1), self%cfac(m - 1, 2*k), kind=wp)
                wre = real(w, wp)
                wim = aimag(w)
                if (.not. (abs(wre) + abs(wim) > 0.0_wp .and. abs(wre) + abs(wim) <= huge(1.0_wp))) then
                    ok = .false.
                    return
                end if
                ! 1/w as conj(w)/|w|^2 (the library's scaled complex division is not needed: |w| ~ 1/h^2)
                den = 1.0_wp/(wre*wre + wim*wim)
                wi = cmplx(wre*den, -wim*den, kind=wp)
                cf = e(k)*wi
                self%winv(m, 2*k - 1) = real(wi, wp)
                self%winv(m, 2*k) = aimag(wi)
                self%cfac(m, 2*k - 1) = real(cf, wp)
                self%cfac(m, 2*k) = aimag(cf)
            end do
        end do
    end subroutine factorize

    !> The part of minus the residual that is fixed during a step, into `rbase` (N x s): for stage i,
    !> c^2 (Delta u0)_n - m^2 u0_n + beta (Delta v0)_n - alpha_n v0_n, with the driven end's u_0 = psi(t_i) and
    !> v_0 = psi'(t_i).
    pure subroutine residual_base(self, u0, v0)
        !> The stepper.
        class(avf_stepper), intent(inout) :: self
        !> The old level.
        real(wp), intent(in) :: u0(:), v0(:)
        integer :: n, s, i, m
        real(wp) :: c2, beta, m2

        n = self%n
        s = self%tab%s
        c2 = self%chain%c**2
        beta = self%chain%beta
        m2 = self%chain%m2
        do i = 1, s
            associate (rb => self%rbase(:, i))
                rb(1) = c2*(u0(2) - 2.0_wp*u0(1) + self%psi_s(i)) - m2*u0(1) &
                        + beta*(v0(2) - 2.0_wp*v0(1) + self%dpsi_s(i)) - self%alpha(1)*v0(1)
                do m = 2, n - 1
                    rb(m) = c2*(u0(m + 1) - 2.0_wp*u0(m) + u0(m - 1)) - m2*u0(m) &
                            + beta*(v0(m + 1) - 2.0_wp*v0(m) + v0(m - 1)) - self%alpha(m)*v0(m)
                end do
                rb(n) = c2*(-2.0_wp*u0(n) + u0(n - 1)) - m2*u0(n) + beta*(-2.0_wp*v0(n) + v0(n - 1)) &
                        - self%alpha(n)*v0(n)
            end associate
        end do
    end subroutine residual_base

    !> out = sum_j coef(j) z(:, j) (add: out + that), the columns taken four and two at a time (stage and rule node
    !> counts are even), so that the accumulator is loaded and stored once per four terms, not once per term.
    pure subroutine lincomb(out, coef, z, add)
        !> The combination (size N).
        real(wp), intent(inout), contiguous :: out(:)
        !> Coefficients (size k).
        real(wp), intent(in) :: coef(:)
        !> Columns (N x k).
        real(wp), intent(in), contiguous :: z(:, :)
        !> Add to out instead of overwriting it.
        logical, intent(in) :: add
        integer :: k, j, m
        real(wp) :: c1, c2, c3, c4

        k = size(coef)
        j = 1
        if (.not. add) then
            if (k >= 2) then
                c1 = coef(1)
                c2 = coef(2)
                do m = 1, size(out)
                    out(m) = c1*z(m, 1) + c2*z(m, 2)
                end do
                j = 3
            else
                out = coef(1)*z(:, 1)
                j = 2
            end if
        end if
        do while (j + 3 <= k)
            c1 = coef(j)
            c2 = coef(j + 1)
            c3 = coef(j + 2)
            c4 = coef(j + 3)
            do m = 1, size(out)
                out(m) = out(m) + ((c1*z(m, j) + c2*z(m, j + 1)) + (c3*z(m, j + 2) + c4*z(m, j + 3)))
            end do
            j = j + 4
        end do
        do while (j + 1 <= k)
            c1 = coef(j)
            c2 = coef(j + 1)
            do m = 1, size(out)
                out(m) = out(m) + (c1*z(m, j) + c2*z(m, j + 1))
            end do
            j = j + 2
        end do
        if (j == k) out = out + coef(k)*z(:, k)
    end subroutine lincomb

    !> Minus the residual of the stage equations at the current Z, into `rr`: F_i(u0 + Z, V) - (W (V - v0))_i / h,
    !> with V = W Z / h (`vv` holds V - v0: formed before W acts on it, so that its roundoff is eps |V - v0|, not
    !> eps |V|) and Gbar averaged along sigma_u by the rule of `nq` nodes (sigma_u at the nodes
    !> and V' there into `sigq`, `fqq`); the part fixed during the step comes from `rbase`. With `nodal`, Gbar_i is
    !> replaced by V'(U_i) (the rule of the s stage nodes: Gauss collocation's force), for the first iteration from
    !> the predictor, whose error is far larger than the difference.
    pure subroutine residual(self, u0, v0, nodal)
        !> The stepper.
        class(avf_stepper), intent(inout) :: self
        !> The old level.
        real(wp), intent(in) :: u0(:), v0(:)
        !> V' at the stage nodes instead of the averaged V'.
        logical, intent(in) :: nodal
        integer :: n, s, i, q, m
        real(wp) :: h, c2, beta, m2

        n = self%n
        s = self%tab%s
        h = self%dt
        c2 = self%chain%c**2
        beta = self%chain%beta
        m2 = self%chain%m2
        associate (tab => self%tab, uu => self%uu, vv => self%vv, rr => self%rr)
            do i = 1, s
                call lincomb(vv(:, i), self%wh(:, i), uu, .false.)
                vv(:, i) = vv(:, i) - v0
            end do
            if (nodal) then
                do i = 1, s
                    self%sigq(:, i) = u0 + uu(:, i)
                    call force_array(self%chain%potential, self%sigq(:, i), self%fqq(:, i))
                end do
            else
                do q = 1, tab%nq
                    ! sigma_u(tau_q) = u0 + sum_j L_j(tau_q) Z_j (the basis sums to 1)
                    self%sigq(:, q) = u0
                    call lincomb(self%sigq(:, q), self%lagc(:, q), uu, .true.)
                    call force_array(self%chain%potential, self%sigq(:, q), self%fqq(:, q))
                end do
            end if
            do i = 1, s
                ! rr_i = rbase_i + c^2 Delta Z_i - m^2 Z_i + beta Delta (V_i - v0) - alpha (V_i - v0) - Gbar_i
                !        - (W (V - v0))_i / h
                ! (the ends u_{N+1} = v_{N+1} = 0 and the drive's share in rbase; end sites apart, so that the
                ! interior loop vectorises)
                rr(1, i) = self%rbase(1, i) + c2*(uu(2, i) - 2.0_wp*uu(1, i)) + beta*(vv(2, i) - 2.0_wp*vv(1, i)) &
                           - self%alpha(1)*vv(1, i) - m2*uu(1, i)
                do m = 2, n - 1
                    rr(m, i) = self%rbase(m, i) + c2*(uu(m + 1, i) - 2.0_wp*uu(m, i) + uu(m - 1, i)) &
                               + beta*(vv(m + 1, i) - 2.0_wp*vv(m, i) + vv(m - 1, i)) - self%alpha(m)*vv(m, i) &
                               - m2*uu(m, i)
                end do
                rr(n, i) = self%rbase(n, i) + c2*(-2.0_wp*uu(n, i) + uu(n - 1, i)) &
                           + beta*(-2.0_wp*vv(n, i) + vv(n - 1, i)) - self%alpha(n)*vv(n, i) - m2*uu(n, i)
                if (nodal) then
                    rr(:, i) = rr(:, i) - self%fqq(:, i)
                else
                    call lincomb(rr(:, i), self%mqw(:, i), self%fqq, .true.)
                end if
                call lincomb(rr(:, i), self%mwh(:, i), vv, .true.)
            end do
        end associate
    end subroutine residual

    !> Solve the factorised system for the residual in `rr` (N x s) and add the update to Z (`uu`); change is its
    !> largest magnitude. To the eigenbasis (rho_k = sum_j tinvf(k, j) r_j, real and imaginary parts as real
    !> combinations), times the pivots' reciprocals, the s/2 complex recurrences of Thomas (forward
    !> y_m = r_m/w_m - (e/w_m) y_{m-1}, back x_m = y_m - (e/w_m) x_{m+1}), back (delta_j = sum_k 2 Re(tf(j, k) rho_k)).
    !> Only the recurrences are serial; every other pass vectorises.
    pure subroutine solve(self, change)
        !> The stepper.
        class(avf_stepper), intent(inout) :: self
        !> max |delta Z| (NaN if an update is not finite).
        real(wp), intent(out) :: change
        integer :: n, s, m, j, k, p
        real(wp) :: a, b, wr, wi

        n = self%n
        s = self%tab%s
        associate (rho => self%rho, rr => self%rr, tab => self%tab, uu => self%uu, cf => self%cfac, wv => self%winv)
            do p = 1, s
                call lincomb(rho(:, p), self%tinc(:, p), rr, .false.)
            end do
            do k = 1, s/2
                do m = 1, n
                    a = rho(m, 2*k - 1)
                    b = rho(m, 2*k)
                    wr = wv(m, 2*k - 1)
                    wi = wv(m, 2*k)
                    rho(m, 2*k - 1) = a*wr - b*wi
                    rho(m, 2*k) = a*wi + b*wr
                end do
            end do
            ! the recurrences, two pairs at a time (avf8) so that their latency chains overlap
            do k = 1, s/2, 2
                call recurrences(rho(:, 2*k - 1:min(2*k + 2, s)), cf(:, 2*k - 1:min(2*k + 2, s)))
            end do
            change = 0.0_wp
            do j = 1, s
                call lincomb(rr(:, j), self%tbc(:, j), rho, .false.)
                uu(:, j) = uu(:, j) + rr(:, j)
                change = max(change, maxval(abs(rr(:, j))))
                if (any(ieee_is_nan(rr(:, j)))) change = ieee_value(change, ieee_quiet_nan)
            end do
        end associate
    end subroutine solve

    !> The forward and back recurrences of Thomas for one or two complex tridiagonal systems (columns: real and
    !> imaginary parts of each), the previous values carried in registers: y_m = t_m - f_m y_{m-1}, then
    !> x_m = y_m - f_m x_{m+1}, f = e/w_m (`cfac`).
    pure subroutine recurrences(rho, cf)
        !> t (the right-hand sides over the pivots), overwritten by x (N x 2 or N x 4).
        real(wp), intent(inout) :: rho(:, :)
        !> f (N x 2 or N x 4).
        real(wp), intent(in) :: cf(:, :)
        integer :: n, m
        real(wp) :: a1, b1, a2, b2, x1, y1, x2, y2

        n = size(rho, 1)
        if (size(rho, 2) == 4) then
            a1 = rho(1, 1)
            b1 = rho(1, 2)
            a2 = rho(1, 3)
            b2 = rho(1, 4)
            do m = 2, n
                x1 = rho(m, 1) - (cf(m, 1)*a1 - cf(m, 2)*b1)
                y1 = rho(m, 2) - (cf(m, 1)*b1 + cf(m, 2)*a1)
                x2 = rho(m, 3) - (cf(m, 3)*a2 - cf(m, 4)*b2)
                y2 = rho(m, 4) - (cf(m, 3)*b2 + cf(m, 4)*a2)
                rho(m, 1) = x1
                rho(m, 2) = y1
                rho(m, 3) = x2
                rho(m, 4) = y2
                a1 = x1
                b1 = y1
                a2 = x2
                b2 = y2
            end do
            do m = n - 1, 1, -1
                x1 = rho(m, 1) - (cf(m, 1)*a1 - cf(m, 2)*b1)
                y1 = rho(m, 2) - (cf(m, 1)*b1 + cf(m, 2)*a1)
                x2 = rho(m, 3) - (cf(m, 3)*a2 - cf(m, 4)*b2)
                y2 = rho(m, 4) - (cf(m, 3)*b2 + cf(m, 4)*a2)
                rho(m, 1) = x1
                rho(m, 2) = y1
                rho(m, 3) = x2
                rho(m, 4) = y2
                a1 = x1
                b1 = y1
                a2 = x2
                b2 = y2
            end do
        else
            a1 = rho(1, 1)
            b1 = rho(1, 2)
            do m = 2, n
                x1 = rho(m, 1) - (cf(m, 1)*a1 - cf(m, 2)*b1)
                y1 = rho(m, 2) - (cf(m, 1)*b1 + cf(m, 2)*a1)
                rho(m, 1) = x1
                rho(m, 2) = y1
                a1 = x1
                b1 = y1
            end do
            do m = n - 1, 1, -1
                x1 = rho(m, 1) - (cf(m, 1)*a1 - cf(m, 2)*b1)
                y1 = rho(m, 2) - (cf(m, 1)*b1 + cf(m, 2)*a1)
                rho(m, 1) = x1
                rho(m, 2) = y1
                a1 = x1
                b1 = y1
            end do
        end if
    end subroutine recurrences

    !> Append the state y (u, v, the integrated energies) and the previous step's stage increments Z (the
    !> predictor's start, so that a resumed run iterates from the same guess and gives the same bits).
    pure subroutine avf_save_levels(self, buf)
        !> The stepper.
        class(avf_stepper), intent(in) :: self
        !> The state so far.
        type(state_buffer), intent(inout) :: buf

        call put_reals(buf, self%y)
        call put_reals2(buf, self%prev)
    end subroutine avf_save_levels

    !> Restore y and the previous increments (after `init` of the same run).
    pure subroutine avf_load_levels(self, buf)
        !> The stepper.
        class(avf_stepper), intent(inout) :: self
        !> The saved state.
        type(state_buffer), intent(inout) :: buf

        call get_reals(buf, self%y)
        call get_reals2(buf, self%prev)
    end subroutine avf_load_levels

end module supratrans_stepper_avf
