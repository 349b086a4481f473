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
!> integrand has degree 6s - 1 and the rule of 3s nodes is exact. For sine-Gordon the rule has 2s nodes and is not
!> exact: its error (the integrand is analytic, sigma_u moves by about h |v| over a step) is the balance residual
!> of a step, measured (test_avf, A = 1.9, dt = 0.1) at 2e-14 (avf4) and 2e-15 (avf8) of the energy scale, 1e-12
!> for avf4 at dt = 0.5; the methods' own errors there are 5e-5 and 4e-10 relative (docs/method.md).
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
!> max(1, max |u0|), or when it stagnates at its roundoff floor below 1e-11 max(1, max |u0|); a run that keeps no
!> ledger (`exact_energy` false) stops at &numerics newton_tol. The cap is &numerics newton_max_iter. Measured on
!> the paper-default run at A = 1.9 (avf8, dt = 0.3125): 4.0 iterations a step, the first update 1e-4 .. 3e-2,
!> contraction 3e-5 .. 7e-4 per iteration.
!>
!> Linear stability: the method reduces to Gauss collocation on a linear chain (V' linear), which is A-stable
!> (its stability function is the (s, s) Pade approximant of exp, |R(z)| <= 1 for Re z <= 0): no step limit.
!>
!> Counters: every iteration is one Newton iteration and one (block-)tridiagonal solve, and `nq` right-hand sides
!> (N-force kernels: sines for sine-Gordon).
!>
!> The continuation scene has no one-period map for these methods and refuses them (`supratrans_period_map`).
module supratrans_stepper_avf
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
    !> Nodes per stage of the averaging rule for sine-Gordon (not exact: its error, measured in test_avf and
    !> reported in docs/method.md, is far below the method's error at the steps used; with s + 2 nodes for avf8
    !> the balance was 6e-14 of the energy a step instead of 6e-16 and the run no faster: the sines are not its
    !> bottleneck).
    integer, parameter, public :: avf_quadrature_sine_gordon = 2
    !> Relative size of the Newton update at which a step is accepted (the energy identity is then exact to
    !> roundoff).
    real(wp), parameter :: tight_tol = 1.0e-14_wp
    !> Below this relative update, an iteration that no longer shrinks the update 4-fold has reached roundoff.
    real(wp), parameter :: floor_tol = 1.0e-11_wp

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
        !> stage velocities V, averaged forces Gbar, residual / update (N x s).
        real(wp), allocatable :: uu(:, :), vv(:, :), gg(:, :), rr(:, :)
        !> The previous step's increments Z, for the predictor (N x s).
        real(wp), allocatable :: prev(:, :)
        !> Block Thomas factors: inverses of the pivot blocks and X_n = pivot^{-1} O (s x s x N).
        !> In the eigenbasis of W the simplified Newton matrix splits into s/2 complex tridiagonal matrices
        !> lambda_k^2/h^2 + K + (lambda_k/h) L (K, L the stiffness and damping matrices): the reciprocals of
        !> their Thomas pivots and the multipliers e/pivot (N x s/2), and the right-hand sides / solutions.
        complex(wp), allocatable :: winv(:, :), cfac(:, :), rho(:, :)
        !> Work: sigma_u at one rule node, V' there (size N).
        real(wp), allocatable :: sig(:), fq(:)
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
        ! the averaging rule: exact for Klein-Gordon (3s nodes); for sine-Gordon 2s nodes (module header)
        if (run%chain%potential == sine_gordon) then
            call avf_make_tableau(s, avf_quadrature_sine_gordon*s, self%tab)
        else
            call avf_make_tableau(s, avf_quadrature_per_stage*s, self%tab)
        end if
        self%tol = run%numerics%newton_tol
        self%max_iter = run%numerics%newton_max_iter
        if (allocated(self%uu)) deallocate (self%uu)
        if (allocated(self%vv)) deallocate (self%vv)
        if (allocated(self%gg)) deallocate (self%gg)
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
        if (st == 0) allocate (self%gg(n, s), stat=st)
        if (st == 0) allocate (self%rr(n, s), stat=st)
        if (st == 0) allocate (self%prev(n, s), stat=st)
        if (st == 0) allocate (self%winv(n, s/2), stat=st)
        if (st == 0) allocate (self%cfac(n, s/2), stat=st)
        if (st == 0) allocate (self%rho(n, s/2), stat=st)
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
        integer :: n, s, i, j, it, iters
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
                    self%uu(:, i) = tab%ext(i, 1)*self%prev(:, 1)
                    do j = 2, s
                        self%uu(:, i) = self%uu(:, i) + tab%ext(i, j)*self%prev(:, j)
                    end do
                end if
            end do
            scale = max(1.0_wp, maxval(abs(u0)))
            ! V'' frozen at the predictor's midpoint sigma_u(1/2) = u0 + sum_j L_j(1/2) Z_j (its deviation along the
            ! step is half that from u0: a smaller contraction factor)
            self%sig = u0
            do j = 1, s
                self%sig = self%sig + tab%mid(j)*self%uu(:, j)
            end do
            call factorize(self, self%sig, ok)
            status = step_breakdown
            iters = 0
            accepted = .false.
            change_prev = huge(1.0_wp)
            if (ok) then
                do it = 1, self%max_iter
                    iters = it
                    call residual(self, u0, v0)
                    call solve(self)
                    change = 0.0_wp
                    do j = 1, s
                        self%uu(:, j) = self%uu(:, j) + self%rr(:, j)
                        change = max(change, maxval(abs(self%rr(:, j))))
                    end do
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
                        accepted = change <= tight_tol*scale .or. (change <= floor_tol*scale .and. theta > 0.25_wp)
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
                self%vv(:, i) = 0.0_wp
                do j = 1, s
                    self%vv(:, i) = self%vv(:, i) + (tab%w(i, j)/h)*self%uu(:, j)
                end do
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
        real(wp) :: c2, beta
        complex(wp) :: lam, e, w

        n = self%n
        c2 = self%chain%c**2
        beta = self%chain%beta
        ok = .true.
        do m = 1, n
            self%fq(m) = 2.0_wp*c2 + self%chain%m2 + potential_d2v(self%chain%potential, u0(m))
        end do
        do k = 1, self%tab%s/2
            lam = self%tab%lam(k)/self%dt
            e = -c2 - lam*beta
            do m = 1, n
                w = lam*lam + self%fq(m) + lam*(self%alpha(m) + 2.0_wp*beta)
                if (m > 1) w = w - e*self%cfac(m - 1, k)
                if (.not. (abs(real(w, wp)) + abs(aimag(w)) > 0.0_wp &
                           .and. abs(real(w, wp)) + abs(aimag(w)) <= huge(1.0_wp))) then
                    ok = .false.
                    return
                end if
                ! 1/w as conj(w)/|w|^2 (the library's scaled complex division is not needed: |w| ~ 1/h^2)
                self%winv(m, k) = conjg(w)/(real(w, wp)**2 + aimag(w)**2)
                self%cfac(m, k) = e*self%winv(m, k)
            end do
        end do
    end subroutine factorize

    !> Minus the residual of the stage equations at the current U, into `rr`: F_i(U, V) - (W (V - v0))_i / h, with
    !> V = W (U - u0)/h and Gbar averaged along sigma_u by the rule of `nq` nodes.
    pure subroutine residual(self, u0, v0)
        !> The stepper.
        class(avf_stepper), intent(inout) :: self
        !> The old level.
        real(wp), intent(in) :: u0(:), v0(:)
        integer :: n, s, i, j, q, m
        real(wp) :: h, c2, beta, m2

        n = self%n
        s = self%tab%s
        h = self%dt
        c2 = self%chain%c**2
        beta = self%chain%beta
        m2 = self%chain%m2
        associate (tab => self%tab, uu => self%uu, vv => self%vv, gg => self%gg, rr => self%rr)
            do i = 1, s
                vv(:, i) = 0.0_wp
                do j = 1, s
                    vv(:, i) = vv(:, i) + (tab%w(i, j)/h)*uu(:, j)
                end do
            end do
            gg = 0.0_wp
            do q = 1, tab%nq
                self%sig = u0            ! sigma_u(tau_q) = u0 + sum_j L_j(tau_q) Z_j (the basis sums to 1)
                do j = 1, s
                    self%sig = self%sig + tab%lag(q, j)*uu(:, j)
                end do
                call force_array(self%chain%potential, self%sig, self%fq)
                do i = 1, s
                    gg(:, i) = gg(:, i) + tab%qw(i, q)*self%fq
                end do
            end do
            do i = 1, s
                ! rr_i = - (W (V - v0))_i / h, then + F_i
                rr(:, i) = 0.0_wp
                do j = 1, s
                    rr(:, i) = rr(:, i) - (tab%w(i, j)/h)*(vv(:, j) - v0)
                end do
                ! U = u0 + Z; the ends u_0 = psi(t_i), v_0 = psi'(t_i), u_{N+1} = v_{N+1} = 0 (end sites apart, so
                ! that the interior loop vectorises)
                do m = 1, n
                    self%sig(m) = u0(m) + uu(m, i)
                end do
                rr(1, i) = rr(1, i) + c2*(self%sig(2) - 2.0_wp*self%sig(1) + self%psi_s(i)) &
                           + beta*(vv(2, i) - 2.0_wp*vv(1, i) + self%dpsi_s(i)) - self%alpha(1)*vv(1, i) &
                           - m2*self%sig(1) - gg(1, i)
                do m = 2, n - 1
                    rr(m, i) = rr(m, i) + c2*(self%sig(m + 1) - 2.0_wp*self%sig(m) + self%sig(m - 1)) &
                               + beta*(vv(m + 1, i) - 2.0_wp*vv(m, i) + vv(m - 1, i)) - self%alpha(m)*vv(m, i) &
                               - m2*self%sig(m) - gg(m, i)
                end do
                rr(n, i) = rr(n, i) + c2*(-2.0_wp*self%sig(n) + self%sig(n - 1)) &
                           + beta*(-2.0_wp*vv(n, i) + vv(n - 1, i)) - self%alpha(n)*vv(n, i) - m2*self%sig(n) - gg(n, i)
            end do
        end associate
    end subroutine residual

    !> Solve the factorised system in place: `rr` (right-hand side, N x s) becomes the update. To the eigenbasis
    !> (rho_k = sum_j tinvf(k, j) r_j), s/2 complex tridiagonal solves, back (r_j = sum_k 2 Re(tf(j, k) rho_k)).
    pure subroutine solve(self)
        !> The stepper.
        class(avf_stepper), intent(inout) :: self
        integer :: n, s, m, j, k
        real(wp) :: c2, beta
        complex(wp) :: e(self%tab%s/2)

        n = self%n
        s = self%tab%s
        c2 = self%chain%c**2
        beta = self%chain%beta
        associate (rho => self%rho, rr => self%rr, tab => self%tab)
            do k = 1, s/2
                rho(:, k) = tab%tinvf(k, 1)*rr(:, 1)
                do j = 2, s
                    rho(:, k) = rho(:, k) + tab%tinvf(k, j)*rr(:, j)
                end do
                e(k) = -c2 - (tab%lam(k)/self%dt)*beta
            end do
            ! forward: y_1 = r_1/w_1, y_m = (r_m - e y_{m-1})/w_m; back: x_m = y_m - (e/w_m) x_{m+1}; the s/2
            ! independent recurrences interleaved (their latency chains overlap)
            do k = 1, s/2
                rho(1, k) = rho(1, k)*self%winv(1, k)
            end do
            do m = 2, n
                do k = 1, s/2
                    rho(m, k) = (rho(m, k) - e(k)*rho(m - 1, k))*self%winv(m, k)
                end do
            end do
            do m = n - 1, 1, -1
                do k = 1, s/2
                    rho(m, k) = rho(m, k) - self%cfac(m, k)*rho(m + 1, k)
                end do
            end do
            do j = 1, s
                rr(:, j) = 2.0_wp*real(tab%tf(j, 1)*rho(:, 1), wp)
                do k = 2, s/2
                    rr(:, j) = rr(:, j) + 2.0_wp*real(tab%tf(j, k)*rho(:, k), wp)
                end do
            end do
        end associate
    end subroutine solve

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
