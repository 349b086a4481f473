!> Steppers `avf4` and `avf8`: the energy-preserving collocation method of Hairer (E. Hairer, "Energy-preserving
!> variant of collocation methods", JNAIAM 5 (2010) 73-84; the continuous-stage form of the average-vector-field
!> method, Cohen & Hairer, BIT 51 (2011) 91-101) with s Gauss nodes (s = 2: order 4; s = 4: order 8), applied to
!> the method-of-lines system of the chain (`supratrans_mol`) in the variables (u, v = u_t), with the drive, both
!> dampings and the absorber, and a discrete energy balance that closes every step.
!>
!> The method (notation, averaging rule, linear stability) and its coefficients: `supratrans_avf_tableau`. A step is
!> s-stage Gauss collocation with the on-site force V' averaged along sigma_u (Gbar_i): U_i = u0 + h sum_j a_ij V_j,
!> V_i = v0 + h sum_j a_ij F_i. Set-up and checkpoint: the submodule `supratrans_stepper_avf_setup.f90`.
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
!> and H(y1) - H(y0) = injected - D^gamma - D^beta - D^abs holds exactly: to roundoff where the averaging rule is
!> exact (a polynomial V'), else to the rule's error. Each term is a Gauss quadrature of the continuous power of
!> `supratrans_mol`, so it converges at the method's order.
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
!> Counters: every iteration is one Newton iteration and one (block-)tridiagonal solve, and `nq` right-hand sides
!> (N-force kernels of the potential).
!>
!> The continuation scene has no one-period map for these methods and refuses them (`supratrans_period_map`).
module supratrans_stepper_avf
    use, intrinsic :: ieee_arithmetic, only: ieee_is_nan, ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp
    use supratrans_strings, only: int_fixed, real_fixed
    use supratrans_config, only: run_config
    use supratrans_chain, only: drive_psi
    use supratrans_mol, only: drive_dpsi
    use supratrans_stepper, only: step_ok, step_not_converged, step_breakdown
    use supratrans_stepper_rk, only: rk_stepper
    use supratrans_state_buffer, only: state_buffer
    use supratrans_avf_tableau, only: avf_tableau
    implicit none
    private

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

    interface
        !> Set up a run: the chain at rest, the method of `run%numerics%method` (avf4 or avf8), work arrays.
        module subroutine avf_init(self, run)
            !> The stepper.
            class(avf_stepper), intent(inout) :: self
            !> Validated run configuration.
            type(run_config), intent(in) :: run
        end subroutine avf_init

        !> Append the state y (u, v, the integrated energies) and the previous step's stage increments Z (the
        !> predictor's start, so that a resumed run iterates from the same guess and gives the same bits).
        pure module subroutine avf_save_levels(self, buf)
            !> The stepper.
            class(avf_stepper), intent(in) :: self
            !> The state so far.
            type(state_buffer), intent(inout) :: buf
        end subroutine avf_save_levels

        !> Restore y and the previous increments (after `init` of the same run).
        pure module subroutine avf_load_levels(self, buf)
            !> The stepper.
            class(avf_stepper), intent(inout) :: self
            !> The saved state.
            type(state_buffer), intent(inout) :: buf
        end subroutine avf_load_levels
    end interface

contains

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
        real(wp), intent(in), contiguous :: u0(:)
        !> False when a pivot is zero or not finite.
        logical, intent(out) :: ok
        integer :: n, k, m
        real(wp) :: c2, beta, wre, wim, den
        complex(wp) :: lam(self%tab%s/2), e(self%tab%s/2), d(self%tab%s/2), w, wi, cf

        n = self%n
        c2 = self%chain%c**2
        beta = self%chain%beta
        ok = .true.
        call self%potential%d2v_array(u0, self%fq)       ! vectorised (for the sines: libmvec's vector cos)
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
                    call self%potential%force_array(self%sigq(:, i), self%fqq(:, i))
                end do
            else
                do q = 1, tab%nq
                    ! sigma_u(tau_q) = u0 + sum_j L_j(tau_q) Z_j (the basis sums to 1)
                    self%sigq(:, q) = u0
                    call lincomb(self%sigq(:, q), self%lagc(:, q), uu, .true.)
                    call self%potential%force_array(self%sigq(:, q), self%fqq(:, q))
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
end module supratrans_stepper_avf
