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
!> (the columns asked for: an `apply` without `jac` and `dpda` propagates none): for the three-level schemes in the
!> submodule `supratrans_period_map_leapfrog.f90` (`leapfrog_run`), for Runge-Kutta in `supratrans_period_map_rk.f90`
!> (`rk_run`), whose documentation gives the equations.
!>
!> `measures` gives max |u_n| (n = 1..N) over the levels 0..M of one period and the mean over the period of the
!> stored energy: the scheme's E_k (`stored_energy`, k = 0..M-1) for the three-level schemes, H of the
!> method-of-lines system (`chain_energy`, levels 0..M-1) for Runge-Kutta.
!>
!> **The half-period map** (`set_half_period`). Every potential has an odd V' and every other term of the
!> equations is linear, and the drive changes sign over half a period: u(t) solves them if and only if -u(t + T/2)
!> does. So with M even, the map over M/2 steps negated, G(x) = -(state after M/2 steps), gives P = G o G for every
!> x, and a fixed point of G is a fixed point of P (a periodic state with u(t + T/2) = -u(t), as the branch from
!> rest is). At such a state dP/dx = (dG/dx)^2, so P's multipliers are the squares of G's, a fold of G's branch is
!> a fold of P's, and max |u_n| and the mean energy over half a period are those over the period. With `half` set,
!> `apply` and `measures` are those of G: half the work.
!>
!> Every work array is allocated once, by `period_map_init`; `apply` allocates nothing. One object per thread.
module supratrans_period_map
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_strings, only: int_str, real_str
    use supratrans_config, only: run_config, chain_params, method_newton, method_linearized, method_rk4, method_rk8
    use supratrans_chain, only: damping_profile
    use supratrans_scheme, only: scheme_type, scheme_init
    use supratrans_potential, only: new_potential
    use supratrans_mol, only: mol_energy_components
    use supratrans_stepper_linearized, only: linearized_work, linearized_work_init
    use supratrans_stepper_rk4, only: rk4_stages
    use supratrans_stepper_rk8, only: rk8_stages, rk8_tableau_a, rk8_tableau_b, rk8_tableau_c
    use supratrans_tridiag, only: factor_tridiag
    use supratrans_fixed_point_map, only: fixed_point_map, map_ok, map_failed
    implicit none
    private

    public :: period_map_init, set_half_period

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
        !> Whether `apply` and `measures` are those of the half-period map G (`set_half_period`; M even).
        logical :: half = .false.
        !> Newton iterations of the implicit steps in the last `apply` or `measures` (Newton scheme; 0 otherwise).
        integer :: newton_iterations = 0
        !> When positive, `apply` also keeps `beyond_max`, the largest |u_n| over the sites n > `watch_site` and every
        !> level of the period (a detector that sees every step, as a run's does, not only the period's end).
        integer :: watch_site = 0
        !> max |u_n|, n > `watch_site`, over the levels 0..M of the last `apply` (when `watch_site` > 0).
        real(wp) :: beyond_max = 0.0_wp
        !> Chain parameters (c, beta, gamma, m^2, absorber).
        type(chain_params) :: chain
        !> Work: P(x; A) of `measures`, size 2N.
        real(wp), allocatable :: px_work(:)
        !> The scheme's matrices at dt_used (three-level schemes; for every method its potential).
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
        !> Steps of one `apply`: M, or M / 2 for the half-period map.
        procedure :: run_steps => period_map_run_steps
    end type period_map

    interface
        !> One period of a three-level scheme (`newton`, `linearized`) from x = (u^0, u^1): P = (u^M, u^{M+1}), the
        !> measures when asked for, and the tangent columns c_first..c_last (the submodule
        !> `supratrans_period_map_leapfrog.f90`).
        module subroutine leapfrog_run(self, x, amplitude, c_first, c_last, measure, px, status, umax, energy, jac, dpda)
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
        end subroutine leapfrog_run

        !> One period of a Runge-Kutta method (`rk4`, `rk8`) from x = (u, v) at t = 0, the tangent columns
        !> c_first..c_last alongside, the measures when asked for (the submodule `supratrans_period_map_rk.f90`).
        module subroutine rk_run(self, x, amplitude, c_first, c_last, measure, px, status, umax, energy, jac, dpda)
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
        end subroutine rk_run
    end interface

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
        call new_potential(run%chain, map%scheme%potential)   ! (again by `scheme_init` for the schemes)
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
        if (status == map_ok .and. self%half) then
            px = -px
            if (present(jac)) jac = -jac
            if (present(dpda)) dpda = -dpda
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

    !> Make `map` the half-period map G (`on`, where M is even: `ok`) or the one-period map P again (`on` false).
    pure subroutine set_half_period(map, on, ok)
        !> The map.
        type(period_map), intent(inout) :: map
        !> Whether G is wanted.
        logical, intent(in) :: on
        !> Whether the map is now what was asked for (false for G when M is odd: it stays P).
        logical, intent(out) :: ok

        ok = .not. on .or. mod(map%steps, 2) == 0
        map%half = on .and. ok
    end subroutine set_half_period

    !> Steps of one `apply`: M, or M / 2 for the half-period map.
    pure integer function period_map_run_steps(self) result(m)
        !> The map.
        class(period_map), intent(in) :: self

        m = merge(self%steps/2, self%steps, self%half)
    end function period_map_run_steps

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
