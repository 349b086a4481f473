!> The one-period map of the discrete schemes and its exact tangent: the map whose fixed points are the chain's
!> driven time-periodic states (issue 25, points 1-2), an implementation of `fixed_point_map`.
!>
!> The drive is u_0(t) = A sin(Omega t) at full amplitude A (no ramp: `drive%ramp_time` is ignored), of period
!> T = 2 pi / Omega. The time step is adjusted so that one period is a whole number of steps: M = ceiling(T / dt)
!> (T / dt an integer up to roundoff counts as that integer), dt_used = T / M. The state x has 2N components:
!>
!> * `newton`, `linearized` (the paper's three-level schemes): x = (u^0, u^1) at t_0 = 0, t_1 = dt_used, and
!>   P(x; A) = (u^M, u^{M+1}) after M steps of the scheme A u^{k+1} + G(u^{k+1}, u^{k-1}) = B u^k + C u^{k-1} + v^k
!>   (`supratrans_scheme`; the linearized scheme with V'(u^k) in place of G). The Newton scheme's implicit steps
!>   are solved to roundoff (not to the stepper's `newton_tol`), so that P is smooth to roundoff: a shooting Newton
!>   method and finite differences see the map, not the solver's stopping rule.
!> * `rk4`, `rk8`: x = (u, u_t) at t = 0, P(x; A) = (u, u_t) at t = T after M steps of the stepper's own step
!>   (`rk4_step`, `rk8_step` on the method-of-lines system of `supratrans_mol`).
!>
!> The tangent (the monodromy matrix dP/dx, whose eigenvalues are the Floquet multipliers of the discrete scheme,
!> and dP/dA) is the derivative of the discrete map itself, propagated with the state, its 2N + 1 columns together
!> (the columns asked for: an `apply` without `jac` and `dpda` propagates none):
!>
!> * Newton scheme: (A + diag(dG/da)) du^{k+1} = B du^k + (C - diag(dG/db)) du^{k-1}, with a = u^{k+1},
!>   b = u^{k-1} the converged levels (dG/db(a, b) = dG/da(b, a): G is symmetric): one `dgttrf` a step and
!>   `dgttrs` with many right-hand sides (a multiplication by the reciprocal diagonal when beta = 0, where the
!>   matrix is diagonal). The state's pass stores each step's coefficients; the columns then go through the
!>   period in blocks that stay in cache (at N = 600 twice as fast as sweeping all the columns every step; the
!>   same at N = 200, where the work is bound by arithmetic). With beta = 0 a column spreads one site a step: the
!>   blocks (within the d/du^0 columns, within the d/du^1 columns, the dA column alone) compute only the sites
!>   their columns can have reached, the rest being exactly zero (half the work at N = 200, M = 140; none when
!>   M >> N);
!> * linearized scheme: A du^{k+1} = (B - diag(V''(u^k))) du^k + C du^{k-1}, A factored once;
!> * in both, the dA column's boundary cells are du_0^k = sin(Omega t_k) (the derivative of u_0^k = A sin(Omega t_k)),
!>   the state columns' are zero;
!> * Runge-Kutta: the derivative of an explicit step is the same tableau applied to the variational equation
!>   dY' = J(t, Y) dY + f_A(t), with the stage Jacobians J taken at the stage states Y_i (rebuilt from the step's
!>   stage derivatives) and f_A the drive's part of the right-hand side: c^2 sin(Omega t) + beta Omega cos(Omega t)
!>   in the equation of u_1'' (u_0 = psi and psi' enter there only).
!>
!> `measures` gives max |u_n| (n = 1..N) over the levels 0..M of one period and the mean over the period of the
!> stored energy: the scheme's E_k (`stored_energy`, k = 0..M-1) for the three-level schemes, H of the
!> method-of-lines system (`chain_energy`, levels 0..M-1) for Runge-Kutta.
!>
!> Every work array is allocated once, by `period_map_init`; `apply` allocates nothing. One object per thread.
module supratrans_period_map
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_strings, only: int_str, real_str
    use supratrans_config, only: run_config, chain_params, drive_params, method_newton, method_linearized, &
                                 method_rk4, method_rk8
    use supratrans_chain, only: damping_profile
    use supratrans_potential, only: gradient_and_slope_array, curvature_bound, slope_lower_bound, potential_d2v
    use supratrans_scheme, only: scheme_type, scheme_init, scheme_rhs_and_predictor, scheme_apply_a
    use supratrans_ledger, only: stored_energy
    use supratrans_mol, only: chain_energy, mol_energy_components
    use supratrans_stepper_linearized, only: linearized_work, linearized_work_init, linearized_step
    use supratrans_stepper_rk4, only: rk4_step, rk4_stages
    use supratrans_stepper_rk8, only: rk8_step, rk8_stages, rk8_tableau_a, rk8_tableau_b, rk8_tableau_c
    use supratrans_tridiag, only: solve_tridiag, factor_tridiag, solve_factored_tridiag
    use supratrans_fixed_point_map, only: fixed_point_map, map_ok, map_failed
    implicit none
    private

    public :: period_map_init

    !> Whether every element is finite.
    interface all_finite
        module procedure all_finite_vector, all_finite_matrix
    end interface all_finite

    !> Iteration cap of the Newton scheme's implicit step (solved to roundoff).
    integer, parameter, public :: period_newton_max_iter = 50
    !> Most steps a period may take (T / dt beyond this is an input error, not a run).
    integer, parameter, public :: period_max_steps = 100000000
    !> Tangent entries (sites x columns) propagated together through a period (three levels of them stay in cache).
    integer, parameter :: block_entries = 4096

    !> The one-period map P(x; A) of a stepper's discrete scheme (see the module's description).
    type, extends(fixed_point_map), public :: period_map
        !> Method (`method_newton`, `method_linearized`, `method_rk4`, `method_rk8`).
        integer :: method = 0
        !> Number of oscillators N (dim = 2N).
        integer :: n = 0
        !> Steps per period M = ceiling(T / dt).
        integer :: steps = 0
        !> Driving frequency Omega.
        real(wp) :: omega = 0.0_wp
        !> Drive period T = 2 pi / Omega.
        real(wp) :: period = 0.0_wp
        !> The time step used, T / M (the configured dt, adjusted so that a period is M steps).
        real(wp) :: dt_used = 0.0_wp
        !> Tangent columns propagated together by the three-level schemes (0: `block_entries` / N, so that their
        !> three levels stay in cache; the results do not depend on it).
        integer :: block_columns = 0
        !> Newton iterations of the implicit steps in the last `apply` or `measures` (Newton scheme; 0 otherwise).
        integer :: newton_iterations = 0
        !> Chain parameters (c, beta, gamma, m^2, potential, absorber).
        type(chain_params) :: chain
        !> Work: P(x; A) of `measures`, size 2N.
        real(wp), allocatable :: px_work(:)
        !> The scheme's matrices at dt_used (three-level schemes).
        type(scheme_type) :: scheme
        !> Time levels u(0:N+1, 4) with boundary cells (three-level schemes; the columns rotate).
        real(wp), allocatable :: u(:, :)
        !> Newton's right-hand side B u^k + C u^{k-1} + v^k, its update, G and dG/da at the iterate, dG/db.
        real(wp), allocatable :: rhs(:), delta(:), g(:), dga(:), dgb(:)
        !> sin and cos of (a + b)/2 (work of `gradient_and_slope_array`).
        real(wp), allocatable :: sin_s(:), cos_s(:)
        !> Tridiagonal matrix and its LU factors (`dgttrf`): dl, du of size max(N - 1, 1), du2 max(N - 2, 1).
        real(wp), allocatable :: dl(:), dd(:), du(:), du2(:)
        !> Pivots of the factorization.
        integer, allocatable :: ipiv(:)
        !> sin(Omega t_k), k = 0..M+1: the drive u_0^k = A sin(Omega t_k) and the dA column's boundary cells.
        real(wp), allocatable :: sin_t(:)
        !> Each step's tangent coefficients (`store_tangent_step`), (N, M): the diagonals of B' and C', and J's
        !> diagonal (its LU factors' diagonal; its reciprocal when beta = 0).
        real(wp), allocatable :: step_b(:, :), step_c(:, :), step_d(:, :)
        !> The rest of J's LU factors per step (Newton scheme, beta /= 0): (max(N-1, 1), M), (max(N-2, 1), M), (N, M).
        real(wp), allocatable :: step_dl(:, :), step_du(:, :), step_du2(:, :)
        !> J's pivots per step.
        integer, allocatable :: step_ipiv(:, :)
        !> Tangent levels du^{k-1}, du^k, du^{k+1}: (N, 2N + 1, 3), columns d/dx_1..d/dx_2N, d/dA.
        real(wp), allocatable :: tangent(:, :, :)
        !> Work of the linearized step (the stepper's own).
        type(linearized_work) :: lin
        !> LU factors of the linearized scheme's constant matrix A (beta /= 0; when beta = 0, `add` is 1/b_n).
        real(wp), allocatable :: adl(:), add(:), adu(:), adu2(:)
        !> Pivots of A's factorization.
        integer, allocatable :: apiv(:)
        !> Runge-Kutta: number of stages s.
        integer :: stages = 0
        !> Runge-Kutta tableau: A (s x s, strictly lower), weights b, nodes c.
        real(wp), allocatable :: rk_a(:, :), rk_b(:), rk_c(:)
        !> Site damping alpha_n = gamma + gamma'(n).
        real(wp), allocatable :: alpha(:)
        !> Runge-Kutta state (u, v, 4 energies), the state at the start of the step, stage state, stage derivatives.
        real(wp), allocatable :: y(:), y0(:), ys(:), k(:, :)
        !> V''(u) at each stage state, (N, s); the drive's forcing of the dA column at each stage, (s).
        real(wp), allocatable :: curvature(:, :), forcing(:)
        !> Runge-Kutta tangent (2N, 2N + 1); its stage state (2N) and stage derivatives (2N, s) for one column.
        real(wp), allocatable :: ty(:, :), tys(:), tk(:, :)
    contains
        !> P(x; A) and, when present, dP/dx and dP/dA.
        procedure :: apply => period_map_apply
        !> max |u_n| over one period and the mean stored energy.
        procedure :: measures => period_map_measures
    end type period_map

contains

    !> Set up the one-period map of the run's method: chain, Omega, method and dt of a validated `run_config` (the
    !> drive's amplitude and ramp are not used). `error` (input class) for Omega <= 0, N < 2, dt <= 0, an unknown
    !> method, more than `period_max_steps` steps a period, or a singular matrix A (linearized scheme).
    subroutine period_map_init(map, run, error)
        !> The map (re-initialised; its work arrays allocated here, once).
        type(period_map), intent(out) :: map
        !> Validated run configuration (chain, drive%omega, numerics%method, numerics%dt).
        type(run_config), intent(in) :: run
        !> Allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        real(wp) :: ratio
        integer :: n, ncol, info, i

        n = run%chain%n
        if (.not. (run%drive%omega > 0.0_wp .and. run%drive%omega <= huge(1.0_wp))) then
            call fatal_error(error, "period map: omega = " // real_str(run%drive%omega) // ": need Omega > 0", err_input)
            return
        end if
        if (n < 2) then
            call fatal_error(error, "period map: n = " // int_str(n) // ": need N >= 2", err_input)
            return
        end if
        if (.not. (run%numerics%dt > 0.0_wp)) then
            call fatal_error(error, "period map: dt = " // real_str(run%numerics%dt) // ": need dt > 0", err_input)
            return
        end if
        select case (run%numerics%method)
        case (method_newton, method_linearized, method_rk4, method_rk8)
        case default
            call fatal_error(error, "period map: unknown method identifier " // int_str(run%numerics%method), err_input)
            return
        end select
        map%method = run%numerics%method
        map%n = n
        map%dim = 2*n
        map%chain = run%chain
        map%omega = run%drive%omega
        map%period = 2.0_wp*acos(-1.0_wp)/map%omega
        ratio = map%period/run%numerics%dt
        if (.not. (ratio <= real(period_max_steps, wp))) then
            call fatal_error(error, "period map: period / dt = " // real_str(ratio) // " steps: more than " &
                             // int_str(period_max_steps), err_input)
            return
        end if
        ! T / dt an integer up to roundoff is that integer (not one step more)
        map%steps = max(1, ceiling(ratio*(1.0_wp - 1.0e-12_wp)))
        map%dt_used = map%period/real(map%steps, wp)
        ncol = 2*n + 1
        allocate (map%px_work(2*n))

        select case (map%method)
        case (method_newton, method_linearized)
            call scheme_init(map%scheme, run%chain, map%dt_used)
            allocate (map%u(0:n + 1, 4), source=0.0_wp)
            allocate (map%rhs(n), map%delta(n), map%g(n), map%dga(n), map%dgb(n), map%sin_s(n), map%cos_s(n))
            allocate (map%dl(max(n - 1, 1)), map%dd(n), map%du(max(n - 1, 1)), map%du2(max(n - 2, 1)), map%ipiv(n))
            allocate (map%sin_t(0:map%steps + 1))
            do i = 0, map%steps + 1
                map%sin_t(i) = sin(map%omega*(real(i, wp)*map%dt_used))
            end do
            allocate (map%step_b(n, map%steps), map%step_c(n, map%steps), map%step_d(n, map%steps))
            if (map%method == method_newton .and. map%scheme%a /= 0.0_wp) then
                allocate (map%step_dl(max(n - 1, 1), map%steps), map%step_du(max(n - 1, 1), map%steps), &
                          map%step_du2(max(n - 2, 1), map%steps), map%step_ipiv(n, map%steps))
            end if
            allocate (map%tangent(n, ncol, 3), source=0.0_wp)
            if (map%method == method_linearized) then
                call linearized_work_init(map%lin, n, info)
                if (info /= 0) then
                    call fatal_error(error, "period map: cannot allocate the work arrays of " // int_str(n) &
                                     // " oscillators", err_input)
                    return
                end if
                allocate (map%adl(max(n - 1, 1)), map%add(n), map%adu(max(n - 1, 1)), map%adu2(max(n - 2, 1)), &
                          map%apiv(n))
                map%adl = map%scheme%a
                map%adu = map%scheme%a
                map%add = map%scheme%b
                if (map%scheme%a == 0.0_wp) then
                    map%add = 1.0_wp/map%add            ! A diagonal: its reciprocal
                else
                    call factor_tridiag(map%adl, map%add, map%adu, map%adu2, map%apiv, info)
                    if (info /= 0) then
                        call fatal_error(error, "period map: the linearized scheme's matrix A is singular (dgttrf info = " &
                                         // int_str(info) // ")", err_input)
                        return
                    end if
                end if
            end if
        case default
            map%stages = merge(rk4_stages, rk8_stages, map%method == method_rk4)
            allocate (map%rk_a(map%stages, map%stages), map%rk_b(map%stages), map%rk_c(map%stages))
            if (map%method == method_rk4) then
                call rk4_tableau(map%rk_a, map%rk_b, map%rk_c)
            else
                map%rk_a = rk8_tableau_a
                map%rk_b = rk8_tableau_b
                map%rk_c = rk8_tableau_c
            end if
            map%alpha = damping_profile(run%chain)
            allocate (map%y(2*n + mol_energy_components), source=0.0_wp)
            allocate (map%y0(size(map%y)), map%ys(size(map%y)), map%k(size(map%y), map%stages))
            allocate (map%curvature(n, map%stages), map%forcing(map%stages))
            allocate (map%ty(2*n, ncol), source=0.0_wp)
            allocate (map%tys(2*n), map%tk(2*n, map%stages))
        end select
    end subroutine period_map_init

    !> P(x; A) and, when present, dP/dx (the monodromy matrix) and dP/dA, propagated together (only the columns
    !> asked for). `status` is `map_failed` when an implicit step did not converge, a solve failed, a value is not
    !> finite or x has not 2N components; P (and the derivatives) are then NaN.
    subroutine period_map_apply(self, x, amplitude, px, status, jac, dpda)
        !> The map (its work arrays change).
        class(period_map), intent(inout) :: self
        !> The state x at t = 0, size 2N.
        real(wp), intent(in) :: x(:)
        !> The drive amplitude A.
        real(wp), intent(in) :: amplitude
        !> P(x; A), size 2N.
        real(wp), intent(out) :: px(:)
        !> `map_ok` or `map_failed`.
        integer, intent(out) :: status
        !> dP/dx, 2N x 2N.
        real(wp), intent(out), optional :: jac(:, :)
        !> dP/dA, size 2N.
        real(wp), intent(out), optional :: dpda(:)
        integer :: c_first, c_last, n
        real(wp) :: umax, energy

        n = self%n
        status = map_failed
        ! the tangent's columns: d/dx_1 .. d/dx_2N (jac), d/dA (dpda); none when neither is asked for
        c_first = 2*n + 1
        if (present(jac)) c_first = 1
        c_last = 2*n
        if (present(dpda)) c_last = 2*n + 1
        if (size(x) == 2*n .and. size(px) == 2*n) then
            select case (self%method)
            case (method_newton, method_linearized)
                call leapfrog_run(self, x, amplitude, c_first, c_last, .false., px, status, umax, energy, jac, dpda)
            case default
                call rk_run(self, x, amplitude, c_first, c_last, .false., px, status, umax, energy, jac, dpda)
            end select
        end if
        if (status == map_ok) then
            if (.not. all_finite(px)) status = map_failed
        end if
        if (status == map_ok .and. present(jac)) then
            if (.not. all_finite(jac)) status = map_failed
        end if
        if (status == map_ok .and. present(dpda)) then
            if (.not. all_finite(dpda)) status = map_failed
        end if
        if (status /= map_ok) then
            px = ieee_value(1.0_wp, ieee_quiet_nan)
            if (present(jac)) jac = ieee_value(1.0_wp, ieee_quiet_nan)
            if (present(dpda)) dpda = ieee_value(1.0_wp, ieee_quiet_nan)
        end if
    end subroutine period_map_apply

    !> max |u_n| (n = 1..N) over the levels 0..M of the period through x, and the mean over the period of the
    !> stored energy (see the module's description); NaN for both when the map fails at x.
    subroutine period_map_measures(self, x, amplitude, umax, energy)
        !> The map.
        class(period_map), intent(inout) :: self
        !> The state x, size 2N.
        real(wp), intent(in) :: x(:)
        !> The drive amplitude A.
        real(wp), intent(in) :: amplitude
        !> Largest |u_n| over the period.
        real(wp), intent(out) :: umax
        !> Mean stored energy over the period.
        real(wp), intent(out) :: energy
        integer :: status

        status = map_failed
        if (size(x) == 2*self%n) then
            select case (self%method)
            case (method_newton, method_linearized)
                call leapfrog_run(self, x, amplitude, 2*self%n + 1, 2*self%n, .true., self%px_work, status, umax, &
                                  energy)
            case default
                call rk_run(self, x, amplitude, 2*self%n + 1, 2*self%n, .true., self%px_work, status, umax, energy)
            end select
        end if
        if (status /= map_ok .or. .not. all_finite(self%px_work)) then
            umax = ieee_value(1.0_wp, ieee_quiet_nan)
            energy = umax
        end if
    end subroutine period_map_measures

    !> One period of a three-level scheme from x = (u^0, u^1): P = (u^M, u^{M+1}), the measures when asked for,
    !> and the tangent columns c_first..c_last: the state's pass stores each step's tangent coefficients (the
    !> diagonals of B', C' and the factored matrix), then the columns are propagated through the whole period in
    !> blocks of `block_entries` / N columns, which stay in cache (column after column, one sweep over the
    !> tangent levels per step would be bound by memory bandwidth).
    subroutine leapfrog_run(self, x, amplitude, c_first, c_last, measure, px, status, umax, energy, jac, dpda)
        !> The map.
        class(period_map), intent(inout) :: self
        !> The state (u^0, u^1), size 2N.
        real(wp), intent(in) :: x(:)
        !> The drive amplitude A.
        real(wp), intent(in) :: amplitude
        !> Tangent columns to propagate (none when c_first > c_last).
        integer, intent(in) :: c_first, c_last
        !> Whether to compute the measures.
        logical, intent(in) :: measure
        !> P(x; A), size 2N.
        real(wp), intent(out) :: px(:)
        !> `map_ok` or `map_failed`.
        integer, intent(out) :: status
        !> max |u_n| over levels 0..M and the mean of E_k, k = 0..M-1 (when `measure`).
        real(wp), intent(out) :: umax, energy
        !> dP/dx (columns 1..2N of the tangent).
        real(wp), intent(inout), optional :: jac(:, :)
        !> dP/dA (column 2N + 1).
        real(wp), intent(inout), optional :: dpda(:)
        integer :: n, m, step, info, j, lm2, lm1, lc, ln, swap, block, cb, tm, tm1, half, c_lo, c_hi
        real(wp) :: energy_sum

        n = self%n
        m = self%steps
        status = map_ok
        umax = 0.0_wp
        energy = 0.0_wp
        energy_sum = 0.0_wp
        self%newton_iterations = 0
        ! state columns: lm2, lm1, lc = levels k-2, k-1, k; ln = the next level
        lm2 = 1
        lm1 = 2
        lc = 3
        ln = 4
        self%u(:, lm1) = 0.0_wp
        self%u(:, lc) = 0.0_wp
        self%u(1:n, lm1) = x(1:n)
        self%u(1:n, lc) = x(n + 1:2*n)
        self%u(0, lm1) = amplitude*self%sin_t(0)
        self%u(0, lc) = amplitude*self%sin_t(1)
        ! the predictor's level -1: its first prediction is the linear extrapolation 2 u^1 - u^0
        self%u(:, lm2) = 2.0_wp*self%u(:, lm1) - self%u(:, lc)
        if (measure) then
            umax = max(maxval(abs(self%u(1:n, lm1))), maxval(abs(self%u(1:n, lc))))
            energy_sum = stored_energy(self%scheme, self%chain%m2, self%u(:, lc), self%u(:, lm1))
        end if
        do step = 1, m
            ! level k + 1 = step + 1
            self%u(0, ln) = amplitude*self%sin_t(step + 1)
            self%u(n + 1, ln) = 0.0_wp
            if (self%method == method_newton) then
                call newton_solve(self, lm2, lm1, lc, ln, status)
            else
                call linearized_step(self%scheme, self%lin, self%u(:, lm1), self%u(:, lc), self%u(:, ln), info)
                if (info /= 0) status = map_failed
            end if
            if (status /= map_ok) return
            if (c_first <= c_last) then
                call store_tangent_step(self, step, lm1, lc, ln, status)
                if (status /= map_ok) return
            end if
            if (measure) then
                if (step <= m - 1) then
                    ! E_k of levels k = step and k + 1
                    energy_sum = energy_sum + stored_energy(self%scheme, self%chain%m2, self%u(:, ln), self%u(:, lc))
                    umax = max(umax, maxval(abs(self%u(1:n, ln))))
                end if
            end if
            swap = lm2
            lm2 = lm1
            lm1 = lc
            lc = ln
            ln = swap
        end do
        ! lm1, lc hold the levels M and M + 1
        px(1:n) = self%u(1:n, lm1)
        px(n + 1:2*n) = self%u(1:n, lc)
        if (measure) energy = energy_sum/real(m, wp)
        block = self%block_columns
        if (block < 1) block = max(1, block_entries/n)
        tm1 = 1
        tm = 2
        ! blocks within the d/du^0 columns, within the d/du^1 columns, and the dA column alone: each block's
        ! columns start from nearby sites (see propagate_block)
        do half = 0, 2
            c_lo = max(c_first, half*n + 1)
            c_hi = min(c_last, merge(2*n + 1, half*n + n, half == 2))
            do cb = c_lo, c_hi, block
                call propagate_block(self, cb, min(c_hi, cb + block - 1), tm1, tm, status)
                if (status /= map_ok) return
            end do
        end do
        if (present(jac)) then
            do j = 1, 2*n
                jac(1:n, j) = self%tangent(:, j, tm1)
                jac(n + 1:2*n, j) = self%tangent(:, j, tm)
            end do
        end if
        if (present(dpda)) then
            dpda(1:n) = self%tangent(:, 2*n + 1, tm1)
            dpda(n + 1:2*n) = self%tangent(:, 2*n + 1, tm)
        end if
    end subroutine leapfrog_run

    !> One implicit step of the Newton scheme, solved to roundoff: the level in column `ln` (its boundary cells
    !> set) from the columns lm1, lc (levels k-1, k; lm2, level k-2, for the cubic predictor). Newton's iteration
    !> stops when the update is at roundoff (<= 4 eps max |u^{k+1}|), when the Kantorovich bound of the new
    !> iterate's error, (L / (2 mu)) |delta|^2 (as in the stepper), is below eps max |u^{k+1}|, or when the update
    !> stops decreasing at the 1e-12 level (roundoff noise); `map_failed` after `period_newton_max_iter` iterations,
    !> on a singular matrix or a non-finite update.
    subroutine newton_solve(self, lm2, lm1, lc, ln, status)
        !> The map.
        class(period_map), intent(inout) :: self
        !> Columns of the levels k-2, k-1, k and of the new level.
        integer, intent(in) :: lm2, lm1, lc, ln
        !> `map_ok` or `map_failed`.
        integer, intent(out) :: status
        integer :: n, it, j, info
        real(wp) :: h_max, mu, change, previous, scale, u_max, curvature

        n = self%n
        status = map_failed
        associate (s => self%scheme)
            call scheme_rhs_and_predictor(s, self%u(:, lm2), self%u(:, lm1), self%u(:, lc), self%rhs, &
                                          self%u(:, ln), h_max)
            mu = s%b_min + slope_lower_bound(s%potential) - 2.0_wp*abs(s%a)
            previous = huge(1.0_wp)
            do it = 1, period_newton_max_iter
                self%newton_iterations = self%newton_iterations + 1
                call gradient_and_slope_array(s%potential, self%u(1:n, ln), self%u(1:n, lm1), self%g, self%dga, &
                                              self%sin_s, self%cos_s)
                call scheme_apply_a(s, self%u(:, ln), self%delta)
                if (s%a == 0.0_wp) then
                    do j = 1, n
                        self%delta(j) = (self%rhs(j) - self%delta(j) - self%g(j))/(s%b(j) + self%dga(j))
                    end do
                    info = 0
                else
                    do j = 1, n
                        self%delta(j) = self%rhs(j) - self%delta(j) - self%g(j)
                        self%dd(j) = s%b(j) + self%dga(j)
                    end do
                    self%dl = s%a
                    self%du = s%a
                    call solve_tridiag(self%dl, self%dd, self%du, self%delta, info)
                end if
                if (info /= 0) return
                change = 0.0_wp
                scale = 0.0_wp
                u_max = 0.0_wp
                do j = 1, n
                    self%u(j, ln) = self%u(j, ln) + self%delta(j)
                    change = max(change, abs(self%delta(j)))
                    scale = max(scale, abs(self%u(j, ln)))
                    u_max = max(u_max, abs(self%u(j, lm1)))
                end do
                if (.not. (change <= huge(1.0_wp) .and. scale <= huge(1.0_wp))) return
                if (change <= 4.0_wp*epsilon(1.0_wp)*scale) exit
                if (mu > 0.0_wp) then
                    curvature = curvature_bound(s%potential, max(scale, u_max) + change)
                    if (curvature/(2.0_wp*mu)*change**2 <= epsilon(1.0_wp)*scale) exit
                end if
                if (change >= previous .and. change <= 1.0e-12_wp*scale) exit
                previous = change
                if (it == period_newton_max_iter) return
            end do
        end associate
        status = map_ok
    end subroutine newton_solve

    !> Store the tangent coefficients of step `step` (levels k-1, k, k+1 = step + 1 in columns lm1, lc, ln,
    !> converged): du^{k+1} = J^{-1} (B' du^k + C' du^{k-1}) with
    !> Newton: J = A + diag(dG/da(u^{k+1}, u^{k-1})), B' = B, C' = C - diag(dG/db) (dG/db(a, b) = dG/da(b, a));
    !> linearized: J = A (factored once), B' = B - diag(V''(u^k)), C' = C. The diagonals of B' and C' go to
    !> `step_b`, `step_c`; J's LU factors (`dgttrf`) to `step_dl`, `step_d`, `step_du`, `step_du2`, `step_ipiv`, or
    !> when beta = 0 (J diagonal) its reciprocal to `step_d`.
    subroutine store_tangent_step(self, step, lm1, lc, ln, status)
        !> The map.
        class(period_map), intent(inout) :: self
        !> The step (1..M).
        integer, intent(in) :: step
        !> State columns of the levels k-1, k, k+1.
        integer, intent(in) :: lm1, lc, ln
        !> `map_ok` or `map_failed` (a singular J).
        integer, intent(out) :: status
        integer :: n, info, j

        n = self%n
        status = map_ok
        associate (s => self%scheme)
            if (self%method == method_newton) then
                call gradient_and_slope_array(s%potential, self%u(1:n, ln), self%u(1:n, lm1), self%g, self%dga, &
                                              self%sin_s, self%cos_s)
                call gradient_and_slope_array(s%potential, self%u(1:n, lm1), self%u(1:n, ln), self%g, self%dgb, &
                                              self%sin_s, self%cos_s)
                do j = 1, n
                    self%step_b(j, step) = s%d
                    self%step_c(j, step) = s%e(j) - self%dgb(j)
                end do
                if (s%a == 0.0_wp) then
                    do j = 1, n
                        self%step_d(j, step) = 1.0_wp/(s%b(j) + self%dga(j))
                    end do
                else
                    do j = 1, n
                        self%step_d(j, step) = s%b(j) + self%dga(j)
                    end do
                    self%step_dl(:, step) = s%a
                    self%step_du(:, step) = s%a
                    call factor_tridiag(self%step_dl(:, step), self%step_d(:, step), self%step_du(:, step), &
                                        self%step_du2(:, step), self%step_ipiv(:, step), info)
                    if (info /= 0) status = map_failed
                end if
            else
                do j = 1, n
                    self%step_b(j, step) = s%d - potential_d2v(s%potential, self%u(j, lc))
                    self%step_c(j, step) = s%e(j)
                end do
            end if
        end associate
    end subroutine store_tangent_step

    !> Propagate the tangent columns cb..ce through the period with the stored coefficients of each step; on exit
    !> columns cb..ce of tangent levels `tm1`, `tm` hold du^M and du^{M+1}. The dA column (2N + 1) gets the boundary
    !> cells du_0^k = sin(Omega t_k): c^2 du_0^k + a (du_0^{k-1} - du_0^{k+1}) in the right-hand side's first row.
    subroutine propagate_block(self, cb, ce, tm1, tm, status)
        !> The map.
        class(period_map), intent(inout) :: self
        !> First and last column of the block.
        integer, intent(in) :: cb, ce
        !> Tangent levels holding du^M and du^{M+1} on exit.
        integer, intent(out) :: tm1, tm
        !> `map_ok` or `map_failed`.
        integer, intent(out) :: status
        integer :: n, j, step, tn, swap, forced, info, site_lo, site_hi, lo, hi
        real(wp) :: boundary
        logical :: newton

        n = self%n
        status = map_ok
        newton = self%method == method_newton
        forced = 0
        if (ce == 2*n + 1) forced = ce - cb + 1
        tm1 = 1
        tm = 2
        tn = 3
        self%tangent(:, cb:ce, tm1) = 0.0_wp
        self%tangent(:, cb:ce, tm) = 0.0_wp
        self%tangent(:, cb:ce, tn) = 0.0_wp
        ! the sites the block's columns start from (the dA column from the driven boundary, site 0): with beta = 0
        ! every step spreads a column by one site each way, so after `step` steps only the sites within `step` of
        ! them can be nonzero, and the others are not computed (they stay exactly zero)
        site_lo = n + 1
        site_hi = 0
        do j = cb, ce
            if (j <= 2*n) then
                site_lo = min(site_lo, mod(j - 1, n) + 1)
                site_hi = max(site_hi, mod(j - 1, n) + 1)
            else
                site_lo = 0
            end if
        end do
        do j = cb, min(ce, n)
            self%tangent(j, j, tm1) = 1.0_wp
        end do
        do j = max(cb, n + 1), min(ce, 2*n)
            self%tangent(j - n, j, tm) = 1.0_wp
        end do
        associate (s => self%scheme)
            do step = 1, self%steps
                ! levels k - 1, k, k + 1 = step - 1, step, step + 1
                lo = max(1, site_lo - step)
                hi = min(n, site_hi + step)
                boundary = s%c2*self%sin_t(step) + s%a*(self%sin_t(step - 1) - self%sin_t(step + 1))
                if (s%a == 0.0_wp) then
                    if (newton) then
                        call tangent_rhs(n, s%c2, s%a, self%step_b(:, step), self%step_c(:, step), .true., &
                                         self%step_d(:, step), forced, boundary, self%tangent(:, cb:ce, tm1), &
                                         self%tangent(:, cb:ce, tm), self%tangent(:, cb:ce, tn), lo, hi)
                    else
                        call tangent_rhs(n, s%c2, s%a, self%step_b(:, step), self%step_c(:, step), .true., &
                                         self%add, forced, boundary, self%tangent(:, cb:ce, tm1), &
                                         self%tangent(:, cb:ce, tm), self%tangent(:, cb:ce, tn), lo, hi)
                    end if
                else
                    call tangent_rhs(n, s%c2, s%a, self%step_b(:, step), self%step_c(:, step), .false., &
                                     self%step_b(:, step), forced, boundary, self%tangent(:, cb:ce, tm1), &
                                     self%tangent(:, cb:ce, tm), self%tangent(:, cb:ce, tn), 1, n)
                    if (newton) then
                        call solve_factored_tridiag(self%step_dl(:, step), self%step_d(:, step), self%step_du(:, step), &
                                                    self%step_du2(:, step), self%step_ipiv(:, step), &
                                                    self%tangent(:, cb:ce, tn), info)
                    else
                        call solve_factored_tridiag(self%adl, self%add, self%adu, self%adu2, self%apiv, &
                                                    self%tangent(:, cb:ce, tn), info)
                    end if
                    if (info /= 0) then
                        status = map_failed
                        return
                    end if
                end if
                swap = tm1
                tm1 = tm
                tm = tn
                tn = swap
            end do
        end associate
    end subroutine propagate_block

    !> The tangent step's right-hand side for a block of columns, t_new = B' t_cur + C' t_old with
    !> B' = tridiag(c^2, diag_b, c^2), C' = tridiag(a, diag_c, a), zero boundary cells but for column `forced`
    !> (the dA column; 0: none), whose first row gets `boundary`; when `scaled`, multiplied row by row by `recip`
    !> in the same pass (the diagonal solve when beta = 0).
    pure subroutine tangent_rhs(n, c2, a, diag_b, diag_c, scaled, recip, forced, boundary, t_old, t_cur, t_new, lo, hi)
        !> Number of sites N (>= 2).
        integer, intent(in) :: n
        !> Coupling c^2 and the off-diagonal a = -beta/(2 dt).
        real(wp), intent(in) :: c2, a
        !> Diagonals of B' and C'.
        real(wp), intent(in), contiguous :: diag_b(:), diag_c(:)
        !> Whether to scale by `recip`.
        logical, intent(in) :: scaled
        !> Row factors (the reciprocal of the diagonal matrix J), size N.
        real(wp), intent(in), contiguous :: recip(:)
        !> Column of the block that is d/dA (0: none).
        integer, intent(in) :: forced
        !> Its boundary term.
        real(wp), intent(in) :: boundary
        !> Tangent levels k-1 and k, (N, columns).
        real(wp), intent(in), contiguous :: t_old(:, :), t_cur(:, :)
        !> The right-hand side (or solution, when `scaled`), (N, columns): rows lo..hi computed when a = 0 and
        !> `scaled` (the others left as they are: zero, where no column can have spread yet), every row otherwise.
        real(wp), intent(inout), contiguous :: t_new(:, :)
        !> Rows that can be nonzero (1 <= lo <= hi <= N).
        integer, intent(in) :: lo, hi
        integer :: i, j
        real(wp) :: extra

        if (a == 0.0_wp .and. scaled) then
            ! beta = 0 (the paper's default): no C' off-diagonals, and the diagonal solve in the same pass; the
            ! terms in the order of the general loop (a zero term dropped), so the values are the same bits
            do j = 1, size(t_new, 2)
                extra = 0.0_wp
                if (j == forced) extra = boundary
                if (lo == 1) then
                    t_new(1, j) = (diag_b(1)*t_cur(1, j) + c2*t_cur(2, j) + diag_c(1)*t_old(1, j) + extra)*recip(1)
                end if
                do i = max(lo, 2), min(hi, n - 1)
                    t_new(i, j) = (diag_b(i)*t_cur(i, j) + c2*(t_cur(i - 1, j) + t_cur(i + 1, j)) &
                                   + diag_c(i)*t_old(i, j))*recip(i)
                end do
                if (hi == n) then
                    t_new(n, j) = (diag_b(n)*t_cur(n, j) + c2*t_cur(n - 1, j) + diag_c(n)*t_old(n, j))*recip(n)
                end if
            end do
            return
        end if
        do j = 1, size(t_new, 2)
            extra = 0.0_wp
            if (j == forced) extra = boundary
            t_new(1, j) = diag_b(1)*t_cur(1, j) + c2*t_cur(2, j) + diag_c(1)*t_old(1, j) + a*t_old(2, j) + extra
            do i = 2, n - 1
                t_new(i, j) = diag_b(i)*t_cur(i, j) + c2*(t_cur(i - 1, j) + t_cur(i + 1, j)) &
                              + diag_c(i)*t_old(i, j) + a*(t_old(i - 1, j) + t_old(i + 1, j))
            end do
            t_new(n, j) = diag_b(n)*t_cur(n, j) + c2*t_cur(n - 1, j) + diag_c(n)*t_old(n, j) + a*t_old(n - 1, j)
            if (scaled) then
                do i = 1, n
                    t_new(i, j) = t_new(i, j)*recip(i)
                end do
            end if
        end do
    end subroutine tangent_rhs

    !> One period of a Runge-Kutta method from x = (u, v) at t = 0 (the stepper's own step, M times), the tangent
    !> columns c_first..c_last alongside, the measures when asked for.
    subroutine rk_run(self, x, amplitude, c_first, c_last, measure, px, status, umax, energy, jac, dpda)
        !> The map.
        class(period_map), intent(inout) :: self
        !> The state (u, v), size 2N.
        real(wp), intent(in) :: x(:)
        !> The drive amplitude A.
        real(wp), intent(in) :: amplitude
        !> Tangent columns to propagate (none when c_first > c_last).
        integer, intent(in) :: c_first, c_last
        !> Whether to compute the measures.
        logical, intent(in) :: measure
        !> P(x; A), size 2N.
        real(wp), intent(out) :: px(:)
        !> `map_ok`.
        integer, intent(out) :: status
        !> max |u_n| over levels 0..M and the mean of H over levels 0..M-1 (when `measure`).
        real(wp), intent(out) :: umax, energy
        !> dP/dx (columns 1..2N of the tangent).
        real(wp), intent(inout), optional :: jac(:, :)
        !> dP/dA (column 2N + 1).
        real(wp), intent(inout), optional :: dpda(:)
        type(drive_params) :: drive
        integer :: n, m, step, i, l, j
        real(wp) :: dt, t0, t, energy_sum
        logical :: tangent

        n = self%n
        m = self%steps
        dt = self%dt_used
        tangent = c_first <= c_last
        status = map_ok
        umax = 0.0_wp
        energy = 0.0_wp
        energy_sum = 0.0_wp
        drive%amplitude = amplitude
        drive%omega = self%omega
        drive%ramp_time = 0.0_wp
        self%y = 0.0_wp
        self%y(1:2*n) = x
        if (tangent) then
            self%ty(:, c_first:c_last) = 0.0_wp
            do j = c_first, min(c_last, 2*n)
                self%ty(j, j) = 1.0_wp
            end do
        end if
        if (measure) then
            umax = maxval(abs(self%y(1:n)))
            energy_sum = chain_energy(self%chain, amplitude*sin(self%omega*0.0_wp), self%y)
        end if
        do step = 1, m
            t0 = real(step - 1, wp)*dt
            if (tangent) self%y0 = self%y
            if (self%method == method_rk4) then
                call rk4_step(self%chain, drive, self%alpha, t0, dt, self%y, self%ys, self%k)
            else
                call rk8_step(self%chain, drive, self%alpha, t0, dt, self%y, self%ys, self%k)
            end if
            if (tangent) then
                ! the stage states' u (rebuilt from the stage derivatives), V'' there, the drive's forcing
                do i = 1, self%stages
                    self%ys(1:n) = self%y0(1:n)
                    do l = 1, i - 1
                        if (self%rk_a(i, l) /= 0.0_wp) then
                            self%ys(1:n) = self%ys(1:n) + (dt*self%rk_a(i, l))*self%k(1:n, l)
                        end if
                    end do
                    self%curvature(:, i) = potential_d2v(self%chain%potential, self%ys(1:n))
                    t = t0 + self%rk_c(i)*dt
                    self%forcing(i) = self%chain%c**2*sin(self%omega*t) + self%chain%beta*self%omega*cos(self%omega*t)
                end do
                do j = c_first, c_last
                    call rk_tangent_step(self, dt, j == 2*n + 1, self%ty(:, j))
                end do
            end if
            if (measure .and. step <= m - 1) then
                umax = max(umax, maxval(abs(self%y(1:n))))
                energy_sum = energy_sum + chain_energy(self%chain, amplitude*sin(self%omega*real(step, wp)*dt), self%y)
            end if
        end do
        if (measure) then
            umax = max(umax, maxval(abs(self%y(1:n))))
            energy = energy_sum/real(m, wp)
        end if
        px = self%y(1:2*n)
        if (present(jac)) jac = self%ty(:, 1:2*n)
        if (present(dpda)) dpda = self%ty(:, 2*n + 1)
    end subroutine rk_run

    !> One Runge-Kutta step of one tangent column dy (2N): the tableau applied to dY' = J_i dY (+ f_A for the dA
    !> column), J_i the Jacobian of the method-of-lines system at stage state i (V'' in `curvature`).
    subroutine rk_tangent_step(self, dt, forced, dy)
        !> The map (tableau, chain, stage data; work arrays tys, tk).
        class(period_map), intent(inout) :: self
        !> Step size.
        real(wp), intent(in) :: dt
        !> Whether this is the dA column (the drive's forcing f_A added).
        logical, intent(in) :: forced
        !> The column, advanced in place, size 2N.
        real(wp), intent(inout), contiguous :: dy(:)
        integer :: i, l, n
        real(wp) :: c2, beta, m2

        n = self%n
        c2 = self%chain%c**2
        beta = self%chain%beta
        m2 = self%chain%m2
        do i = 1, self%stages
            self%tys = dy
            do l = 1, i - 1
                if (self%rk_a(i, l) /= 0.0_wp) self%tys = self%tys + (dt*self%rk_a(i, l))*self%tk(:, l)
            end do
            call variational_rhs(n, c2, beta, m2, self%alpha, self%curvature(:, i), self%tys, self%tk(:, i))
            if (forced) self%tk(n + 1, i) = self%tk(n + 1, i) + self%forcing(i)
        end do
        do i = 1, self%stages
            if (self%rk_b(i) /= 0.0_wp) dy = dy + (dt*self%rk_b(i))*self%tk(:, i)
        end do
    end subroutine rk_tangent_step

    !> The linearised method-of-lines right-hand side with zero boundary values: dk = J dy, J the Jacobian of
    !> `chain_rhs` in (u, v) at a state whose V''(u_n) is `curv`.
    pure subroutine variational_rhs(n, c2, beta, m2, alpha, curv, dy, dk)
        !> Number of sites N (>= 2).
        integer, intent(in) :: n
        !> Coupling c^2, internal damping beta, mass term m^2.
        real(wp), intent(in) :: c2, beta, m2
        !> Site damping alpha_n and V''(u_n), size N.
        real(wp), intent(in), contiguous :: alpha(:), curv(:)
        !> Tangent (du, dv), size 2N.
        real(wp), intent(in), contiguous :: dy(:)
        !> Its derivative, size 2N.
        real(wp), intent(out), contiguous :: dk(:)
        integer :: i

        dk(1:n) = dy(n + 1:2*n)
        dk(n + 1) = c2*(dy(2) - 2.0_wp*dy(1)) - alpha(1)*dy(n + 1) - (m2 + curv(1))*dy(1)
        do i = 2, n - 1
            dk(n + i) = c2*(dy(i + 1) - 2.0_wp*dy(i) + dy(i - 1)) - alpha(i)*dy(n + i) - (m2 + curv(i))*dy(i)
        end do
        dk(2*n) = c2*(dy(n - 1) - 2.0_wp*dy(n)) - alpha(n)*dy(2*n) - (m2 + curv(n))*dy(n)
        if (beta /= 0.0_wp) then
            dk(n + 1) = dk(n + 1) + beta*(dy(n + 2) - 2.0_wp*dy(n + 1))
            do i = 2, n - 1
                dk(n + i) = dk(n + i) + beta*(dy(n + i + 1) - 2.0_wp*dy(n + i) + dy(n + i - 1))
            end do
            dk(2*n) = dk(2*n) + beta*(dy(2*n - 1) - 2.0_wp*dy(2*n))
        end if
    end subroutine variational_rhs

    !> True when every element of a vector is finite.
    pure function all_finite_vector(a) result(ok)
        !> The values.
        real(wp), intent(in) :: a(:)
        logical :: ok
        integer :: i

        ok = .true.
        do i = 1, size(a)
            if (.not. (abs(a(i)) <= huge(1.0_wp))) ok = .false.
        end do
    end function all_finite_vector

    !> True when every element of a matrix is finite.
    pure function all_finite_matrix(a) result(ok)
        !> The values.
        real(wp), intent(in) :: a(:, :)
        logical :: ok
        integer :: j

        ok = .true.
        do j = 1, size(a, 2)
            if (.not. all_finite_vector(a(:, j))) ok = .false.
        end do
    end function all_finite_matrix

    !> The classical RK4 tableau (that of `rk4_step`).
    pure subroutine rk4_tableau(a, b, c)
        !> Coupling coefficients (4 x 4, strictly lower triangular), weights, nodes.
        real(wp), intent(out) :: a(:, :), b(:), c(:)

        a = 0.0_wp
        a(2, 1) = 0.5_wp
        a(3, 2) = 0.5_wp
        a(4, 3) = 1.0_wp
        b = [1.0_wp/6.0_wp, 1.0_wp/3.0_wp, 1.0_wp/3.0_wp, 1.0_wp/6.0_wp]
        c = [0.0_wp, 0.5_wp, 0.5_wp, 1.0_wp]
    end subroutine rk4_tableau

end module supratrans_period_map
