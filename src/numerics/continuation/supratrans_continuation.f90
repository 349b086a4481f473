!> Pseudo-arclength continuation in the drive amplitude A of the fixed points x = P(x; A) of a `fixed_point_map`
!> (the periodic states of the driven chain, when P is the one-period map), through the fold and some way along the
!> unstable branch beyond it, with the Floquet stability of every point.
!>
!> **Method** (Keller's pseudo-arclength, as in AUTO-07p and BifurcationKit.jl). A branch point is y = (x, A) with
!> F(y) = P(x; A) - x = 0. At a converged point y_i with Jacobian [J - I, dP/dA] the unit tangent t_i solves the
!> bordered system [[J - I, dP/dA]; [t_{i-1}^T]] z = e_{d+1}, t_i = z / |z| (oriented along t_{i-1}; at the start
!> t_0 = e_A, A increasing). The next point is predicted at y_i + ds t_i and corrected by Newton on
!> {F(y) = 0, t_i . (y - y_i) = ds} with the bordered matrix K_i = [[J - I, dP/dA]; [t_i^T]]. K_i differs from the
!> factorised tangent matrix in its last row only: it is solved with the same LU and a rank-one (Sherman-Morrison)
!> correction, whose denominator is |z| > 0, so one LU per point serves both the tangent and the corrector.
!>
!> **Chord / Shamanskii corrector.** The corrector reuses K_i (the Jacobian of the last point) and evaluates only P
!> (no Jacobian) while the Newton steps shrink by at least `chord_rate` per iteration and fast enough to reach the
!> tolerance within `newton_max_iter`; otherwise the Jacobian is evaluated at the current iterate and factorised,
!> and the corrector goes on with that one. With `floquet_every` = k > 1 and `reuse_jacobian`, the points without
!> multipliers get no Jacobian of their own: their tangent is the secant from the previous point and the last
!> factorised matrix is carried on (its last row changed by rank one); the points with multipliers, the fold and
!> the located crossings always have their own. The step ds grows (x1.5) after a fast correction
!> (<= `newton_fast` iterations, no refresh; 3 more allowed after a reused Jacobian), shrinks (x0.6) after a slow
!> one, and is halved and retried when the corrector fails or the tangent turns by more than `max_angle`.
!>
!> **Cost.** `continuation_stats` counts the evaluations of P alone and with its Jacobian, the LU factorisations,
!> the solves and the eigenvalue computations, with their wall-clock times. No state gets two `dgeev`: the
!> multipliers of every point where they were computed are kept (`spectra`), for the stability checks and for
!> `branch_multipliers`; the point the march stands on lends its Jacobian to the checks instead of a new one. Past
!> the fold, once the stability is lost and `floquet_every` > 1, only the first and the last point get multipliers
!> (the unstable part's ends). A crossing's secant needs the monodromy only (no tangent), and its corrector uses
!> the bordered matrix of the secant's last iterate (nearer than the bracket's left end: no refresh). On the
!> sine-Gordon chain (N = 200, d = 400) the full `dgeev` of the monodromy dominates (about 0.1 s of CPU against
!> 0.010 s for a Jacobian, OpenBLAS): `floquet_every` with `floquet_trend` is the control. Krylov (Arnoldi)
!> eigenvalues are no substitute here: the monodromy is far from normal, and its Ritz values leave the unit circle
!> where no multiplier does.
!>
!> **Fold.** The fold (saddle-node) of the branch is where the tangent's A-component t_A changes sign. Between the
!> two points it is located by a safeguarded secant (Illinois) on t_A as a function of the pseudo-arclength step
!> from the point before it; each evaluation is a corrected point with its own tangent. Near the fold
!> A(s) = A_f - kappa (s - s_f)^2 / 2 and t_A = -kappa (s - s_f), so the located point is within t_A^2 / (2 kappa)
!> of A_f; the secant stops when that is below `fold_tol` (default 1e-10). The fold point is inserted in the
!> branch, with its Newton residual and its multipliers (one of them is +1 up to the location error). Between
!> points with reused Jacobians the sign change is first seen on the secants; both neighbours then get their exact
!> tangents, and when the exact tangent of the current point shows the fold already behind it, the fold is located
!> between the previous point and the current one and inserted there. The accuracy of A_f is also bounded by
!> the residual: near the fold dA ~ |P(x) - x| / |l . dP/dA| (l the left null vector of J - I), so
!> `newton_tol` = 1e-10 leaves A_f good to ~1e-10 on the test maps.
!>
!> **Stability.** The Floquet multipliers are the eigenvalues of J = dP/dx at each point (every point, or every
!> `floquet_every`-th point; the points in between are examined when the verdict changes). The first point that is
!> not stable (`supratrans_floquet`, tolerance `crossing_tol`) ends the stable part; the crossing is classified by
!> its leading multiplier (+1 fold, -1 period doubling, complex pair torus) and located like the fold, by a secant on
!> max |mu| - 1 over the multipliers of that class, between the unstable point and the last point (at most 10 back)
!> where that class is strictly inside the unit circle, so that the location does not depend on crossing_tol (on
!> max |mu| - 1 - crossing_tol between the two points when no such point exists: a multiplier that hugs the
!> circle). A crossing through +1 after the fold is the fold itself. Only the first loss of stability is located; a
!> branch that regains stability before its fold (a weak instability bubble) shows it in `stable` and
!> `max_multiplier`.
!>
!> An implementation of `fixed_point_map` holds its own work arrays: one map and one call per thread; this module
!> has no state of its own.
module supratrans_continuation
    use supratrans_kinds, only: wp, i8
    use supratrans_fixed_point_map, only: fixed_point_map, map_ok
    use supratrans_dense, only: lu_factor, lu_solve
    use supratrans_floquet, only: floquet_multipliers, largest_modulus, is_stable, leading_crossing, &
                                  crossing_distance, nearest_multiplier, crossing_none, crossing_fold, &
                                  track_multiplier, crossing_torus, crossing_period_doubling
    use supratrans_shooting, only: shoot, shooting_controls, shooting_result, shoot_converged
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_finite
    implicit none
    private

    public :: continue_branch, branch_multipliers, continuation_status_name

    !> Status: a fold was found and located (the march then went up to `beyond_fold` points past it).
    integer, parameter, public :: cont_fold_found = 0
    !> Status: the branch reached A > `amplitude_max` with no fold.
    integer, parameter, public :: cont_no_fold = 1
    !> Status: Newton-shooting did not converge at the starting amplitude (or x0 has the wrong size).
    integer, parameter, public :: cont_newton_failed = 2
    !> Status: the corrector kept failing until the step fell below `ds_min`, before any fold.
    integer, parameter, public :: cont_step_too_small = 3
    !> Status: `max_points` points computed before any fold and below `amplitude_max`.
    integer, parameter, public :: cont_max_points = 4

    !> Most points examined backwards from the first unstable one for a bracket of the crossing |mu| = 1.
    integer, parameter :: walk_back = 10
    !> Corrector iterations more that the step control allows when the corrector started from a reused Jacobian.
    integer, parameter :: reuse_slack = 3
    !> Most Jacobian refreshes in one corrector attempt.
    integer, parameter :: max_refreshes = 3
    !> Number of largest multiplier moduli whose trend decides extra multiplier checks (`floquet_trend`).
    integer, parameter :: trend_ranks = 8
    !> Safety factor on the extrapolated growth of those moduli.
    real(wp), parameter :: trend_safety = 2.0_wp

    !> Controls of the continuation, with their defaults.
    type, public :: continuation_controls
        !> Newton convergence: max_i |P(x)_i - x_i| <= newton_tol.
        real(wp) :: newton_tol = 1.0e-10_wp
        !> Most corrector iterations per attempt (chord and Newton steps together).
        integer :: newton_max_iter = 12
        !> A chord step that is not at least this factor smaller than the previous one triggers a Jacobian refresh.
        real(wp) :: chord_rate = 0.5_wp
        !> Corrections in at most this many iterations (and no refresh) let the step grow by 1.5.
        integer :: newton_fast = 3
        !> Corrections in this many iterations or more (or with two refreshes) shrink the step by 0.6.
        integer :: newton_slow = 7
        !> Amplitude at which the branch starts (from the given state, or x = 0: the chain at rest at A = 0).
        real(wp) :: amplitude_start = 0.0_wp
        !> First pseudo-arclength step (in the Euclidean norm of (x, A)).
        real(wp) :: ds0 = 0.05_wp
        !> Smallest step: below it the continuation stops (`cont_step_too_small`).
        real(wp) :: ds_min = 1.0e-8_wp
        !> Largest step.
        real(wp) :: ds_max = 0.5_wp
        !> Largest turn of the tangent in one step (radians); a larger one halves the step and retries.
        real(wp) :: max_angle = 0.5_wp
        !> Most branch points (the fold point included).
        integer :: max_points = 1000
        !> Largest amplitude: a branch beyond it with no fold ends with `cont_no_fold`.
        real(wp) :: amplitude_max = 10.0_wp
        !> A multiplier counts as beyond the unit circle when |mu| > 1 + crossing_tol (`supratrans_floquet`).
        real(wp) :: crossing_tol = 1.0e-6_wp
        !> Points computed past the fold, along the unstable branch.
        integer :: beyond_fold = 10
        !> If > 0, the march past the fold also ends once the amplitude has fallen by this much below A_f
        !> (whichever of the two comes first).
        real(wp) :: beyond_fold_distance = 0.0_wp
        !> Multipliers at every floquet_every-th point (1: all), at the fold, and where the verdict changes; 0: at
        !> the fold only (the fold alone, no stability along the branch: no first loss of stability is sought).
        integer :: floquet_every = 1
        !> With floquet_every > 1, also compute the multipliers (and the Jacobian) at a point that is not due when
        !> one of the `trend_ranks` largest moduli, extrapolated at twice its growth over the last two points with
        !> multipliers, would pass 1 + crossing_tol by that point: the skipped points are those where the spectrum
        !> stays clear of the circle.
        logical :: floquet_trend = .true.
        !> Between the points with multipliers, reuse the last factorised Jacobian (Shamanskii across points): no
        !> Jacobian at such a point, the secant (y_i - y_{i-1}) / |y_i - y_{i-1}| as its tangent. Without effect
        !> when floquet_every = 1 (every point then has its Jacobian).
        logical :: reuse_jacobian = .true.
        !> Accuracy in A of the located fold and of the located loss of stability.
        real(wp) :: fold_tol = 1.0e-10_wp
    end type continuation_controls

    !> Where the work went: counts and wall-clock seconds.
    type, public :: continuation_stats
        !> Evaluations of P alone.
        integer :: map_evaluations = 0
        !> Evaluations of P with dP/dx and dP/dA.
        integer :: jacobian_evaluations = 0
        !> Dense LU factorisations (bordered systems and Newton-shooting).
        integer :: factorisations = 0
        !> Solves with a factorised matrix.
        integer :: solves = 0
        !> Eigenvalue computations (`dgeev` of the monodromy).
        integer :: eigen_calls = 0
        !> Multipliers tracked by inverse iteration (one complex LU each) while a crossing is located.
        integer :: tracked = 0
        !> Seconds in evaluations of P alone.
        real(wp) :: time_map = 0.0_wp
        !> Seconds in evaluations with the Jacobian.
        real(wp) :: time_jacobian = 0.0_wp
        !> Seconds in LU factorisations and solves.
        real(wp) :: time_lu = 0.0_wp
        !> Seconds in eigenvalue computations.
        real(wp) :: time_eigen = 0.0_wp
        !> Seconds in the whole continuation.
        real(wp) :: time_total = 0.0_wp
    end type continuation_stats

    !> The Floquet multipliers of one branch point, as `dgeev` gave them (not allocated where they were not computed).
    type, public :: point_spectrum
        !> Real parts of the multipliers.
        real(wp), allocatable :: wr(:)
        !> Imaginary parts of the multipliers.
        real(wp), allocatable :: wi(:)
    end type point_spectrum

    !> The branch, its fold and its first loss of stability.
    type, public :: continuation_result
        !> `cont_fold_found`, `cont_no_fold`, `cont_newton_failed`, `cont_step_too_small`, `cont_max_points`.
        integer :: status = cont_newton_failed
        !> Why the march ended (same codes; `cont_fold_found`: the `beyond_fold` points past the fold were done).
        integer :: stop_reason = cont_newton_failed
        !> Amplitude A_f of the fold (NaN when there is none).
        real(wp) :: fold_amplitude = 0.0_wp
        !> max |P(x) - x| at the located fold point (NaN when there is none).
        real(wp) :: fold_residual = 0.0_wp
        !> Real part of the multiplier nearest +1 at the fold point (NaN when there is none).
        real(wp) :: fold_multiplier = 0.0_wp
        !> Imaginary part of that multiplier (0 when it is real; a small value when +1 met a trapped mode's
        !> multiplier and the two form a complex pair; NaN when there is no fold).
        real(wp) :: fold_multiplier_imag = 0.0_wp
        !> Index of the fold point in the branch arrays (0 when there is none).
        integer :: fold_index = 0
        !> Points computed past the fold.
        integer :: points_beyond_fold = 0
        !> Amplitude where the branch first loses stability (NaN when it stays stable as far as computed).
        real(wp) :: instability_amplitude = 0.0_wp
        !> Kind of that loss (`supratrans_floquet`: crossing_none, crossing_fold, crossing_period_doubling,
        !> crossing_torus).
        integer :: instability_type = crossing_none
        !> The crossing tolerance used for the stability verdicts.
        real(wp) :: crossing_tol = 0.0_wp
        !> Number of branch points.
        integer :: n_points = 0
        !> Per point: the drive amplitude A.
        real(wp), allocatable :: amplitude(:)
        !> Per point: pseudo-arclength from the start.
        real(wp), allocatable :: arclength(:)
        !> Per point: the largest |u_n| over the orbit (`measures` of the map).
        real(wp), allocatable :: umax(:)
        !> Per point: the mean stored energy over the orbit (`measures` of the map).
        real(wp), allocatable :: energy(:)
        !> Per point: the largest |mu| (NaN where the multipliers were not computed).
        real(wp), allocatable :: max_multiplier(:)
        !> Per point: 1 stable, 0 unstable, -1 not computed.
        integer, allocatable :: stable(:)
        !> Per point: corrector iterations.
        integer, allocatable :: newton_iterations(:)
        !> Per point: max |P(x) - x|.
        real(wp), allocatable :: residual(:)
        !> Per point: the A-component of the unit tangent (its sign change is the fold).
        real(wp), allocatable :: tangent_amplitude(:)
        !> Per point: 1 when the tangent was computed from the Jacobian at that point, 0 when it is the secant from
        !> the previous point (`reuse_jacobian`).
        integer, allocatable :: exact_tangent(:)
        !> Per point: the state x (dim x n_points).
        real(wp), allocatable :: states(:, :)
        !> Per point: the unit tangent (dx, dA) ((dim + 1) x n_points).
        real(wp), allocatable :: tangents(:, :)
        !> Per point: the multipliers where they were computed (kept, so that no point's `dgeev` is done twice:
        !> the stability checks and `branch_multipliers` read them).
        type(point_spectrum), allocatable :: spectra(:)
        !> Where the work went.
        type(continuation_stats) :: stats
    end type continuation_result

    !> A factorised bordered matrix B = [[J - I, dP/dA]; [r0^T]], with an optional rank-one change of its last row to
    !> r0 + w (Sherman-Morrison: K^{-1} b = v - z (w . v) / denom, v = B^{-1} b, z = B^{-1} e_{d+1},
    !> denom = 1 + w . z).
    type :: bordered_system
        real(wp), allocatable :: lu(:, :)
        integer, allocatable :: ipiv(:)
        real(wp), allocatable :: row0(:), z(:), w(:)
        real(wp) :: denom = 1.0_wp
        logical :: updated = .false.
    end type bordered_system

    !> A converged branch point with its derivatives.
    type :: branch_point
        real(wp), allocatable :: y(:)
        real(wp), allocatable :: t(:)
        real(wp), allocatable :: jac(:, :), dpda(:)
        real(wp) :: s = 0.0_wp
        real(wp) :: residual = 0.0_wp
        integer :: iterations = 0
        integer :: refreshes = 0
        logical :: exact = .false.
    end type branch_point

contains

    !> Continue the fixed points of `map` in A from `amplitude_start` (controls), starting from `x0` (default 0),
    !> through the fold and `beyond_fold` points past it, with Floquet stability; see the module's documentation.
    subroutine continue_branch(map, ctl, res, x0)
        !> The map P(x; A).
        class(fixed_point_map), intent(inout) :: map
        !> Controls.
        type(continuation_controls), intent(in) :: ctl
        !> The branch, fold, stability and costs.
        type(continuation_result), intent(out) :: res
        !> Initial guess of the state at `amplitude_start` (default: x = 0).
        real(wp), intent(in), optional :: x0(:)
        type(bordered_system) :: base, next, fresh, psys
        type(branch_point) :: cur, trial, fold_pt, lost_pt, prev
        type(shooting_result) :: sres
        real(wp), allocatable :: x(:), wr(:), wi(:), row(:)
        real(wp) :: ds, nan, t_start, sigma
        integer :: d, n1, info, last_checked, j, every, slack, n_trend
        logical :: ok, have_mult, lost, located, past, due, watch, fold_only
        real(wp) :: top_last(trend_ranks), top_prev(trend_ranks), s_last, s_prev

        t_start = wall_clock()
        nan = ieee_value(1.0_wp, ieee_quiet_nan)
        d = map%dim
        n1 = d + 1
        res%fold_amplitude = nan
        res%fold_residual = nan
        res%fold_multiplier = nan
        res%fold_multiplier_imag = nan
        res%instability_amplitude = nan
        res%crossing_tol = ctl%crossing_tol
        call allocate_branch(res, d, ctl%max_points + 1)

        ! The start: Newton-shooting at fixed A
        allocate (x(d))
        x = 0.0_wp
        if (present(x0)) then
            if (size(x0) /= d) then
                call set_stop(res, cont_newton_failed)
                call finish(res, t_start)
                return
            end if
            x = x0
        end if
        call shoot(map, x, ctl%amplitude_start, shooting_controls(tol=ctl%newton_tol, max_iter=ctl%newton_max_iter), &
                   sres)
        res%stats%jacobian_evaluations = sres%jacobians
        res%stats%map_evaluations = 1      ! shoot's first evaluation, of P alone
        res%stats%factorisations = sres%iterations
        if (sres%status /= shoot_converged) then
            res%status = cont_newton_failed
            res%stop_reason = cont_newton_failed
            call finish(res, t_start)
            return
        end if
        cur%y = [x, ctl%amplitude_start]
        cur%iterations = sres%iterations
        row = [(0.0_wp, j=1, d), 1.0_wp]
        call complete_point(map, cur, row, base, ok, res%stats)
        if (.not. ok) then
            res%status = cont_newton_failed
            res%stop_reason = cont_newton_failed
            call finish(res, t_start)
            return
        end if
        fold_only = ctl%floquet_every == 0
        info = 1
        if (.not. fold_only) call point_multipliers(cur, res%stats, wr, wi, info)
        call record_point(map, res, cur, wr, wi, info == 0)
        n_trend = 0
        s_last = 0.0_wp
        s_prev = 0.0_wp
        top_last = 0.0_wp
        top_prev = 0.0_wp
        if (info == 0) call note_trend(cur%s, wr, wi)
        last_checked = 1
        lost = res%stable(1) == 0
        if (lost) then
            res%instability_amplitude = ctl%amplitude_start
            res%instability_type = leading_crossing(wr, wi, ctl%crossing_tol)
        end if

        ds = min(max(ctl%ds0, ctl%ds_min), ctl%ds_max)
        past = .false.
        every = max(1, ctl%floquet_every)
        if (fold_only) every = huge(1)
        watch = .false.
        march: do
            if (res%n_points >= ctl%max_points) then
                call set_stop(res, cont_max_points)
                exit march
            end if
            call correct(map, cur, base, ds, ctl, trial, ok, res%stats, fresh)
            if (ok) then
                ! multipliers due here: every `every` points, and right after the fold (appended or inserted)
                due = mod(res%n_points, every) == 0 .or. (res%fold_index > 0 .and. res%fold_index >= res%n_points - 1)
                ! past the fold with the stability already lost: only the first point after the fold
                if (every > 1 .and. res%fold_index > 0 .and. lost) due = first_after_fold()
                ! and wherever the trend of the largest moduli may reach the circle within this step
                watch = every > 1 .and. ctl%floquet_trend .and. .not. lost .and. trend_due(cur%s + ds)
                due = (due .or. watch) .and. .not. fold_only
                watch = watch .and. .not. fold_only
                if (due .or. .not. ctl%reuse_jacobian) then
                    call complete_point(map, trial, cur%t, next, ok, res%stats)
                else
                    ! Shamanskii across points: the secant as tangent, the last factorised system kept
                    trial%t = (trial%y - cur%y)/norm2(trial%y - cur%y)
                    if (trial%refreshes > 0) then
                        call move_system(fresh, next)
                    else
                        next = base
                    end if
                    call set_row(next, trial%t, info, res%stats)
                    ! the carried matrix cannot take the secant as its last row: a Jacobian here after all
                    if (info /= 0) call complete_point(map, trial, cur%t, next, ok, res%stats)
                end if
                if (ok) ok = dot_product(cur%t, trial%t) >= cos(ctl%max_angle)
            end if
            if (.not. ok .and. .not. cur%exact) then
                ! before shrinking the step, give the point we stand on its own Jacobian and tangent
                call complete_point(map, cur, cur%t, base, ok, res%stats)
                if (ok) then
                    ! a secant and the exact tangent with A-components of opposite signs: the fold lies behind cur
                    located = res%tangent_amplitude(res%n_points)*cur%t(n1) < 0.0_wp
                    call update_tangent(res, res%n_points, cur)
                    if (located .and. res%fold_index == 0) call fold_before_cur()
                    cycle march
                end if
            end if
            if (.not. ok) then
                ds = 0.5_wp*ds
                if (ds < ctl%ds_min) then
                    call set_stop(res, cont_step_too_small)
                    exit march
                end if
                cycle march
            end if
            trial%s = cur%s + ds

            ! The fold: t_A changes sign between cur and trial (secants first, then exact tangents on both sides)
            if (res%fold_index == 0 .and. cur%t(n1)*trial%t(n1) < 0.0_wp) then
                if (.not. trial%exact) call complete_point(map, trial, cur%t, next, ok, res%stats)
                if (ok .and. .not. cur%exact) then
                    call complete_point(map, cur, cur%t, base, ok, res%stats)
                    if (ok) call update_tangent(res, res%n_points, cur)
                end if
                if (ok .and. cur%t(n1)*trial%t(n1) < 0.0_wp) then
                    ! the bracket is trial's step along cur's (now exact) tangent; the fold's arclength lies
                    ! between theirs in proportion
                    sigma = max(dot_product(cur%t, trial%y - cur%y), tiny(1.0_wp))
                    call locate(map, cur, base, sigma, 0, 0.0_wp, ctl, fold_pt, wr, wi, located, res%stats, trial)
                    if (.not. located) then
                        fold_pt = trial
                        call point_multipliers(fold_pt, res%stats, wr, wi, info)
                    end if
                    fold_pt%s = cur%s + (trial%s - cur%s)*min(max((fold_pt%s - cur%s)/sigma, 0.0_wp), 1.0_wp)
                    call record_fold(res%n_points + 1)
                else if (ok .and. cur%t(n1)*trial%t(n1) > 0.0_wp .and. (trial%y(n1) - cur%y(n1))*cur%t(n1) > 0.0_wp) then
                    ! the exact tangent at cur already points the way the branch goes after the fold
                    call fold_before_cur()
                end if
                ok = .true.
            end if

            have_mult = mod(res%n_points, every) == 0 .or. res%fold_index == res%n_points
            have_mult = have_mult .or. watch
            have_mult = trial%exact .and. (have_mult .or. (res%fold_index > 0 .and. res%fold_index == res%n_points - 1))
            if (every > 1 .and. res%fold_index > 0 .and. lost) have_mult = trial%exact .and. first_after_fold()
            have_mult = have_mult .and. .not. fold_only
            if (have_mult) then
                call point_multipliers(trial, res%stats, wr, wi, info)
                have_mult = info == 0
                if (have_mult) call note_trend(trial%s, wr, wi)
            end if
            call record_point(map, res, trial, wr, wi, have_mult)
            if (have_mult) call check_stability(res%n_points, trial)
            if (res%fold_index > 0) res%points_beyond_fold = res%points_beyond_fold + 1

            ! Step control (a corrector that started from a reused Jacobian is allowed `reuse_slack` more steps)
            slack = merge(0, reuse_slack, cur%exact)
            if (trial%iterations <= ctl%newton_fast + slack .and. trial%refreshes == 0) then
                ds = min(1.5_wp*ds, ctl%ds_max)
            else if (trial%iterations >= ctl%newton_slow + slack .or. trial%refreshes >= 2) then
                ds = max(0.6_wp*ds, ctl%ds_min)
            end if
            call move_point(trial, cur)
            call move_system(next, base)

            if (res%fold_index > 0) then
                past = res%points_beyond_fold >= ctl%beyond_fold
                if (ctl%beyond_fold_distance > 0.0_wp) then
                    past = past .or. res%fold_amplitude - cur%y(n1) >= ctl%beyond_fold_distance
                end if
            end if
            if (past) then
                call set_stop(res, cont_fold_found)
                exit march
            end if
            if (res%fold_index == 0 .and. cur%y(n1) > ctl%amplitude_max) then
                call set_stop(res, cont_no_fold)
                exit march
            end if
        end do march
        if (res%fold_index > 0 .and. lost .and. res%n_points > res%fold_index) then
            ! the last point past the fold gets its multipliers (the end of the unstable part)
            if (res%stable(res%n_points) < 0) then
                call point_with_jacobian(res%n_points, prev, info)
                if (info == 0) call point_multipliers(prev, res%stats, wr, wi, info)
                if (info == 0) call keep_spectrum(res, res%n_points, wr, wi)
            end if
        end if
        call finish(res, t_start)

    contains

        !> Whether no point past the fold has its multipliers yet (the next one recorded is then the first).
        logical function first_after_fold()
            first_after_fold = .true.
            if (res%fold_index < res%n_points) first_after_fold = all(res%stable(res%fold_index + 1:res%n_points) < 0)
        end function first_after_fold

        !> Keep the `trend_ranks` largest moduli of the multipliers at arclength s (and those of the point before).
        subroutine note_trend(s, wr, wi)
            real(wp), intent(in) :: s
            real(wp), intent(in) :: wr(:), wi(:)
            real(wp), allocatable :: modulus(:)
            integer :: r, k

            top_prev = top_last
            s_prev = s_last
            modulus = hypot(wr, wi)
            top_last = 0.0_wp
            do r = 1, min(trend_ranks, size(modulus))
                k = maxloc(modulus, dim=1)
                top_last(r) = modulus(k)
                modulus(k) = -1.0_wp
            end do
            s_last = s
            n_trend = min(n_trend + 1, 2)
        end subroutine note_trend

        !> Whether the multipliers are needed at arclength s_next although not due: the r-th largest modulus
        !> (r = 1..trend_ranks), extrapolated from the last two points with multipliers at twice its rate of
        !> growth, would pass 1 + crossing_tol by s_next (or fewer than two points are known).
        logical function trend_due(s_next)
            real(wp), intent(in) :: s_next
            real(wp) :: rate(trend_ranks)

            trend_due = .true.
            if (n_trend < 2 .or. .not. (s_last > s_prev)) return
            rate = max((top_last - top_prev)/(s_last - s_prev), 0.0_wp)
            trend_due = any(top_last + trend_safety*rate*max(s_next - s_last, 0.0_wp) > 1.0_wp + ctl%crossing_tol)
        end function trend_due

        !> The fold between the previous recorded point and cur (the last one): the exact tangent at the previous
        !> point, the secant on t_A from there, the fold point inserted before cur.
        subroutine fold_before_cur()
            integer :: linfo
            real(wp) :: sig

            if (res%n_points < 2) return
            call stored_point(map, res, res%n_points - 1, prev, res%stats, linfo)
            if (linfo /= 0) return
            call factor_bordered(prev%jac, prev%dpda, prev%t, psys, linfo, res%stats)
            if (linfo == 0) call tangent(psys, prev%t, linfo, res%stats)
            if (linfo /= 0) return
            if (prev%t(n1)*cur%t(n1) >= 0.0_wp) return
            sig = dot_product(prev%t, cur%y - prev%y)
            if (sig <= 0.0_wp) return
            call locate(map, prev, psys, sig, 0, 0.0_wp, ctl, fold_pt, wr, wi, located, res%stats, cur)
            if (.not. located) then
                fold_pt = cur
                call point_multipliers(fold_pt, res%stats, wr, wi, linfo)
            end if
            fold_pt%s = prev%s + (cur%s - prev%s)*min(max((fold_pt%s - prev%s)/sig, 0.0_wp), 1.0_wp)
            call record_fold(res%n_points)
        end subroutine fold_before_cur

        !> Record the located fold point `fold_pt` (multipliers wr, wi) at branch index `pos` (appended, or inserted
        !> before the last point), with its amplitude, residual and multiplier nearest +1.
        subroutine record_fold(pos)
            !> (by value: the caller may pass res%n_points, which recording the point changes)
            integer, value :: pos
            integer :: kk

            res%fold_amplitude = fold_pt%y(n1)
            res%fold_residual = fold_pt%residual
            kk = nearest_multiplier(wr, wi, 1.0_wp)
            if (kk > 0) then
                res%fold_multiplier = wr(kk)
                res%fold_multiplier_imag = wi(kk)
            end if
            call record_point(map, res, fold_pt, wr, wi, .true., pos)
            res%fold_index = pos
            if (fold_only) then
                ! no stability along the branch: the fold's multipliers are its own record, no crossing is sought
                if (pos < res%n_points .and. res%points_beyond_fold == 0) res%points_beyond_fold = 1
            else if (pos == res%n_points) then
                call check_stability(pos, fold_pt)
            else
                ! inserted before the last point, which is past the fold
                if (res%points_beyond_fold == 0) res%points_beyond_fold = 1
                if (last_checked >= pos) then
                    last_checked = last_checked + 1
                else
                    call check_stability(pos, fold_pt)
                end if
            end if
        end subroutine record_fold

        !> The multipliers of branch point `i` (computed now, or recomputed from its stored state) decide whether
        !> it is stable; the first stable-to-unstable change is located and classified.
        subroutine check_stability(i, pt)
            integer, intent(in) :: i
            type(branch_point), intent(in) :: pt
            type(branch_point) :: left
            real(wp), allocatable :: lr(:), li(:)
            real(wp) :: shift, g_k, g_m, sigma_k
            complex(wp) :: mu_k
            integer :: k, linfo, kind, m, jl, have_left
            logical :: inside

            if (lost) then
                last_checked = i
                return
            end if
            if (res%stable(i) == 1) then
                last_checked = i
                return
            end if
            ! Unstable at i, stable at last_checked: find the first unstable point in between
            k = last_checked + 1
            do while (k < i)
                if (res%stable(k) < 0) then
                    call point_with_jacobian(k, left, linfo)
                    if (linfo == 0) call point_multipliers(left, res%stats, lr, li, linfo)
                    if (linfo == 0) call keep_spectrum(res, k, lr, li)
                end if
                if (res%stable(k) == 0) exit
                k = k + 1
            end do
            lost = .true.
            last_checked = i
            ! Multipliers at k (kept when computed; computed again otherwise)
            if (allocated(res%spectra(k)%wr)) then
                lr = res%spectra(k)%wr
                li = res%spectra(k)%wi
            else if (k == i) then
                call point_multipliers(pt, res%stats, lr, li, linfo)
            else
                call point_with_jacobian(k, left, linfo)
                call point_multipliers(left, res%stats, lr, li, linfo)
            end if
            kind = leading_crossing(lr, li, ctl%crossing_tol)
            g_k = crossing_distance(lr, li, kind)
            mu_k = cmplx(0.0_wp, 0.0_wp, kind=wp)
            if (class_max(lr, li, kind) > 0) mu_k = cmplx(lr(class_max(lr, li, kind)), li(class_max(lr, li, kind)), kind=wp)
            if (kind == crossing_fold .and. res%fold_index > 0 .and. k >= res%fold_index - 1) then
                ! A real multiplier through +1 after the fold: the fold itself
                res%instability_amplitude = res%fold_amplitude
                res%instability_type = crossing_fold
                return
            end if
            res%instability_type = kind
            res%instability_amplitude = res%amplitude(k)
            ! The bracket: back from k - 1 to the last point whose multipliers of this kind are strictly inside the
            ! unit circle (at most walk_back points), and |mu| = 1 located between it and the next point; where
            ! there is none (a multiplier that hugs the circle), |mu| = 1 + crossing_tol between k - 1 and k
            inside = .false.
            have_left = 0
            do m = k - 1, max(1, k - walk_back), -1
                if (allocated(res%spectra(m)%wr)) then
                    lr = res%spectra(m)%wr
                    li = res%spectra(m)%wi
                else
                    call point_with_jacobian(m, left, linfo)
                    if (linfo /= 0) return
                    have_left = m
                    call point_multipliers(left, res%stats, lr, li, linfo)
                    if (linfo /= 0) return
                    call keep_spectrum(res, m, lr, li)
                end if
                g_m = crossing_distance(lr, li, kind)
                if (g_m < 0.0_wp) then
                    inside = .true.
                    exit
                end if
            end do
            if (inside) then
                shift = 0.0_wp
                jl = m
            else
                shift = ctl%crossing_tol
                jl = k - 1
            end if
            if (have_left /= jl) then
                call point_with_jacobian(jl, left, linfo)
                if (linfo /= 0) return
            end if
            block
                type(bordered_system) :: sys
                call factor_bordered(left%jac, left%dpda, left%t, sys, linfo, res%stats)
                if (linfo /= 0) return
                if (inside .and. jl + 1 == k) then
                    ! both ends known: the bracket is point k's step along left's tangent
                    sigma_k = dot_product(left%t, [res%states(:, k), res%amplitude(k)] - left%y)
                    if (sigma_k > 0.0_wp) then
                        call locate(map, left, sys, sigma_k, kind, shift, ctl, lost_pt, lr, li, located, res%stats, &
                                    g_lo=g_m, g_hi=g_k, mu_guess=mu_k)
                    else
                        call locate(map, left, sys, res%arclength(jl + 1) - res%arclength(jl), kind, shift, ctl, &
                                    lost_pt, lr, li, located, res%stats, g_lo=g_m)
                    end if
                else if (inside) then
                    call locate(map, left, sys, res%arclength(jl + 1) - res%arclength(jl), kind, shift, ctl, lost_pt, &
                                lr, li, located, res%stats, g_lo=g_m)
                else
                    call locate(map, left, sys, res%arclength(jl + 1) - res%arclength(jl), kind, shift, ctl, lost_pt, &
                                lr, li, located, res%stats)
                end if
            end block
            if (located) res%instability_amplitude = lost_pt%y(n1)
        end subroutine check_stability

        !> Recorded point `i` with its Jacobian: `cur` when it is that point and has its own Jacobian (no
        !> evaluation), else rebuilt from the stored state (`stored_point`).
        subroutine point_with_jacobian(i, p, linfo)
            integer, intent(in) :: i
            type(branch_point), intent(inout) :: p
            integer, intent(out) :: linfo
            logical :: same

            linfo = 0
            same = .false.
            if (cur%exact .and. allocated(cur%jac) .and. allocated(cur%y)) then
                same = cur%y(n1) == res%amplitude(i) .and. cur%s == res%arclength(i)
                if (same) same = all(cur%y(1:d) == res%states(:, i)) .and. all(cur%t == res%tangents(:, i))
            end if
            if (same) then
                p%y = cur%y
                p%t = cur%t
                p%s = cur%s
                p%iterations = cur%iterations
                p%residual = cur%residual
                p%exact = .true.
                p%jac = cur%jac
                p%dpda = cur%dpda
            else
                call stored_point(map, res, i, p, res%stats, linfo)
            end if
        end subroutine point_with_jacobian

    end subroutine continue_branch

    !> The Floquet multipliers at branch point `i` of a computed branch: those kept from the continuation where they
    !> were computed, else from its stored state (one Jacobian evaluation and one `dgeev`): for the record of the
    !> spectrum at a few amplitudes. `info` /= 0 when the map or LAPACK failed.
    subroutine branch_multipliers(map, res, i, wr, wi, info)
        !> The map the branch was computed with.
        class(fixed_point_map), intent(inout) :: map
        !> The branch.
        type(continuation_result), intent(in) :: res
        !> The branch point, 1 .. res%n_points.
        integer, intent(in) :: i
        !> Real parts of the multipliers.
        real(wp), allocatable, intent(out) :: wr(:)
        !> Imaginary parts of the multipliers.
        real(wp), allocatable, intent(out) :: wi(:)
        !> 0 on success.
        integer, intent(out) :: info
        real(wp), allocatable :: px(:), jac(:, :)
        integer :: status

        info = 1
        if (i < 1 .or. i > res%n_points) return
        if (allocated(res%spectra)) then
            if (size(res%spectra) >= i) then
                if (allocated(res%spectra(i)%wr)) then
                    ! computed during the continuation, from the same state: the same multipliers, bit for bit
                    wr = res%spectra(i)%wr
                    wi = res%spectra(i)%wi
                    info = 0
                    return
                end if
            end if
        end if
        allocate (px(map%dim), jac(map%dim, map%dim))
        call map%apply(res%states(:, i), res%amplitude(i), px, status, jac=jac)
        if (status /= map_ok) return
        call floquet_multipliers(jac, wr, wi, info)
    end subroutine branch_multipliers

    !> The name of a continuation status: "fold_found", "no_fold", "newton_failed", "step_too_small", "max_points".
    pure function continuation_status_name(status) result(name)
        !> The status.
        integer, intent(in) :: status
        character(len=:), allocatable :: name

        select case (status)
        case (cont_fold_found)
            name = "fold_found"
        case (cont_no_fold)
            name = "no_fold"
        case (cont_newton_failed)
            name = "newton_failed"
        case (cont_step_too_small)
            name = "step_too_small"
        case (cont_max_points)
            name = "max_points"
        case default
            name = "unknown"
        end select
    end function continuation_status_name

    ! ------------------------------------------------------------------------------------------------------------

    !> Predictor y_b + sigma t_b and chord/Newton corrector on {F(y) = 0, t_b . (y - y_pred) = 0} starting with the
    !> factorised base system; a slow chord step brings a fresh Jacobian at the current iterate.
    subroutine correct(map, bp, sys, sigma, ctl, pt, ok, stats, fresh_sys)
        class(fixed_point_map), intent(inout) :: map
        type(branch_point), intent(in) :: bp
        type(bordered_system), intent(in) :: sys
        real(wp), intent(in) :: sigma
        type(continuation_controls), intent(in) :: ctl
        type(branch_point), intent(inout) :: pt
        logical, intent(out) :: ok
        type(continuation_stats), intent(inout) :: stats
        !> The system factorised at the last refresh (pt%refreshes > 0).
        type(bordered_system), intent(inout) :: fresh_sys
        real(wp), allocatable :: y(:), ypred(:), r(:), px(:), jac(:, :), dpda(:)
        real(wp) :: dn, dn_prev, rate
        integer :: d, n1, status, info, loops
        logical :: want_jac, fresh, use_fresh

        d = size(bp%y) - 1
        n1 = d + 1
        ok = .false.
        pt%exact = .false.
        y = bp%y + sigma*bp%t
        ypred = y
        allocate (r(n1), px(d))
        want_jac = .false.
        use_fresh = .false.
        dn_prev = huge(1.0_wp)
        pt%iterations = 0
        pt%refreshes = 0
        loops = 0
        do
            loops = loops + 1
            if (loops > 3*ctl%newton_max_iter) return
            fresh = want_jac
            if (want_jac) then
                if (.not. allocated(jac)) allocate (jac(d, d), dpda(d))
                call evaluate(map, y, px, status, stats, jac, dpda)
            else
                call evaluate(map, y, px, status, stats)
            end if
            if (status /= map_ok) return
            r(1:d) = px - y(1:d)
            pt%residual = maxval(abs(r(1:d)))
            if (pt%residual <= ctl%newton_tol) exit
            if (pt%iterations >= ctl%newton_max_iter) return
            if (want_jac) then
                ! a corrector that needs more than max_refreshes Jacobians is not converging: a shorter step will
                if (pt%refreshes >= max_refreshes) return
                call factor_bordered(jac, dpda, bp%t, fresh_sys, info, stats)
                if (info /= 0) return
                use_fresh = .true.
                want_jac = .false.
                pt%refreshes = pt%refreshes + 1
            end if
            r(n1) = dot_product(bp%t, y - ypred)
            r = -r
            if (use_fresh) then
                call bordered_solve(fresh_sys, r, info, stats)
            else
                call bordered_solve(sys, r, info, stats)
            end if
            if (info /= 0) return
            dn = norm2(r)
            if (.not. ieee_is_finite(dn)) return
            if (.not. fresh .and. pt%iterations > 0) then
                ! Shamanskii: a fresh Jacobian when the chord contracts by less than chord_rate per step, or too
                ! slowly to reach the tolerance within the iterations left
                rate = dn/dn_prev
                ! growing although the Jacobian was refreshed in this attempt: the iterate has left Newton's basin,
                ! a shorter step will do better than more Jacobians
                if (rate >= 1.0_wp .and. pt%refreshes > 0) return
                if (rate > ctl%chord_rate) then
                    want_jac = .true.
                else if (dn > ctl%newton_tol .and. rate > 0.0_wp) then
                    want_jac = log(ctl%newton_tol/dn)/log(rate) > real(ctl%newton_max_iter - pt%iterations - 1, wp)
                end if
                if (want_jac) cycle
            end if
            y = y + r
            dn_prev = dn
            pt%iterations = pt%iterations + 1
        end do
        pt%y = y
        ok = .true.
    end subroutine correct

    !> At a corrected point: the Jacobian, the factorised bordered matrix with the previous tangent `row`, the unit
    !> tangent (oriented along `row`), and the rank-one change of the last row to the new tangent for the next
    !> corrector.
    subroutine complete_point(map, pt, row, sys, ok, stats)
        class(fixed_point_map), intent(inout) :: map
        type(branch_point), intent(inout) :: pt
        real(wp), intent(in) :: row(:)
        type(bordered_system), intent(inout) :: sys
        logical, intent(out) :: ok
        type(continuation_stats), intent(inout) :: stats
        real(wp), allocatable :: px(:)
        integer :: d, status, info

        d = size(pt%y) - 1
        ok = .false.
        if (.not. allocated(pt%jac)) allocate (pt%jac(d, d), pt%dpda(d))
        allocate (px(d))
        call evaluate(map, pt%y, px, status, stats, pt%jac, pt%dpda)
        if (status /= map_ok) return
        pt%residual = maxval(abs(px - pt%y(1:d)))
        call factor_bordered(pt%jac, pt%dpda, row, sys, info, stats)
        if (info /= 0) return
        call tangent(sys, pt%t, info, stats)
        ok = info == 0
        pt%exact = ok
    end subroutine complete_point

    !> At a corrected point: the Jacobian only (dP/dx and dP/dA) and the residual; the tangent is not computed.
    subroutine point_jacobian(map, pt, ok, stats)
        class(fixed_point_map), intent(inout) :: map
        type(branch_point), intent(inout) :: pt
        logical, intent(out) :: ok
        type(continuation_stats), intent(inout) :: stats
        real(wp), allocatable :: px(:)
        integer :: d, status

        d = size(pt%y) - 1
        if (.not. allocated(pt%jac)) allocate (pt%jac(d, d), pt%dpda(d))
        allocate (px(d))
        call evaluate(map, pt%y, px, status, stats, pt%jac, pt%dpda)
        ok = status == map_ok
        if (ok) pt%residual = maxval(abs(px - pt%y(1:d)))
        pt%exact = .false.
    end subroutine point_jacobian

    !> The unit tangent from a freshly factorised B = [[J - I, dP/dA]; [r0^T]]: z = B^{-1} e_{d+1}, t = z / |z|
    !> (oriented along r0: r0 . z = 1); the system is then changed (rank one) to have t as its last row.
    subroutine tangent(sys, t, info, stats)
        type(bordered_system), intent(inout) :: sys
        real(wp), allocatable, intent(inout) :: t(:)
        integer, intent(out) :: info
        type(continuation_stats), intent(inout) :: stats

        call unit_solution(sys, info, stats)
        if (info /= 0) return
        t = sys%z/norm2(sys%z)
        call set_row(sys, t, info, stats)
    end subroutine tangent

    !> z = B^{-1} e_{d+1} for the factorised matrix (without its rank-one change), if not yet known.
    subroutine unit_solution(sys, info, stats)
        type(bordered_system), intent(inout) :: sys
        integer, intent(out) :: info
        type(continuation_stats), intent(inout) :: stats
        real(wp) :: t0
        integer :: n1, i

        info = 0
        if (allocated(sys%z)) return
        n1 = size(sys%row0)
        allocate (sys%z(n1))
        sys%z = [(0.0_wp, i=1, n1 - 1), 1.0_wp]
        t0 = wall_clock()
        call lu_solve(sys%lu, sys%ipiv, sys%z, info)
        stats%solves = stats%solves + 1
        stats%time_lu = stats%time_lu + wall_clock() - t0
        if (info == 0 .and. .not. all(ieee_is_finite(sys%z))) info = 1
        if (info /= 0) deallocate (sys%z)
    end subroutine unit_solution

    !> Change the last row of a factorised bordered system to `row` (rank one, Sherman-Morrison). `info` /= 0 when
    !> the changed matrix is (nearly) singular: 1 + w . z, which is r . z, vanishes when `row` is orthogonal to the
    !> branch direction z of the factorised matrix.
    subroutine set_row(sys, row, info, stats)
        type(bordered_system), intent(inout) :: sys
        real(wp), intent(in) :: row(:)
        integer, intent(out) :: info
        type(continuation_stats), intent(inout) :: stats

        call unit_solution(sys, info, stats)
        if (info /= 0) return
        sys%w = row - sys%row0
        sys%denom = 1.0_wp + dot_product(sys%w, sys%z)
        sys%updated = .true.
        if (abs(sys%denom) <= 1.0e-3_wp*norm2(sys%z)*norm2(row)) info = 1
    end subroutine set_row

    !> Build and factorise [[J - I, dP/dA]; [row^T]].
    subroutine factor_bordered(jac, dpda, row, sys, info, stats)
        real(wp), intent(in) :: jac(:, :), dpda(:), row(:)
        type(bordered_system), intent(inout) :: sys
        integer, intent(out) :: info
        type(continuation_stats), intent(inout) :: stats
        real(wp) :: t0
        integer :: d, i

        t0 = wall_clock()
        d = size(dpda)
        if (allocated(sys%lu)) then
            if (size(sys%lu, 1) /= d + 1) deallocate (sys%lu, sys%ipiv)
        end if
        if (.not. allocated(sys%lu)) allocate (sys%lu(d + 1, d + 1), sys%ipiv(d + 1))
        sys%lu(1:d, 1:d) = jac
        do i = 1, d
            sys%lu(i, i) = sys%lu(i, i) - 1.0_wp
        end do
        sys%lu(1:d, d + 1) = dpda
        sys%lu(d + 1, :) = row
        call lu_factor(sys%lu, sys%ipiv, info)
        sys%row0 = row
        if (allocated(sys%z)) deallocate (sys%z)
        sys%updated = .false.
        stats%factorisations = stats%factorisations + 1
        stats%time_lu = stats%time_lu + wall_clock() - t0
    end subroutine factor_bordered

    !> Solve with a bordered system (and its rank-one change of the last row, if any); b is overwritten.
    subroutine bordered_solve(sys, b, info, stats)
        type(bordered_system), intent(in) :: sys
        real(wp), intent(inout) :: b(:)
        integer, intent(out) :: info
        type(continuation_stats), intent(inout) :: stats
        real(wp) :: t0

        t0 = wall_clock()
        call lu_solve(sys%lu, sys%ipiv, b, info)
        if (info == 0 .and. sys%updated) b = b - sys%z*(dot_product(sys%w, b)/sys%denom)
        stats%solves = stats%solves + 1
        stats%time_lu = stats%time_lu + wall_clock() - t0
    end subroutine bordered_solve

    !> Safeguarded secant (Illinois) on the step sigma in (0, sigma_hi) from the point `bp` for the zero of
    !> g(sigma): the tangent's A-component (kind 0, the fold) or `crossing_distance` of that kind minus `shift`.
    !> `pt` is the last corrected point (with its multipliers wr, wi); `located` tells whether the tolerance
    !> was met.
    subroutine locate(map, bp, sys, sigma_hi, kind, shift, ctl, pt, wr, wi, located, stats, hi, g_lo, g_hi, mu_guess)
        class(fixed_point_map), intent(inout) :: map
        type(branch_point), intent(in) :: bp
        type(bordered_system), intent(in) :: sys
        real(wp), intent(in) :: sigma_hi, shift
        integer, intent(in) :: kind
        type(continuation_controls), intent(in) :: ctl
        type(branch_point), intent(inout) :: pt
        real(wp), allocatable, intent(out) :: wr(:), wi(:)
        logical, intent(out) :: located
        type(continuation_stats), intent(inout) :: stats
        !> The corrected point at sigma_hi, when the caller has it.
        type(branch_point), intent(in), optional :: hi
        !> `crossing_distance` of that kind at bp and at the branch point whose step along bp's tangent is sigma_hi,
        !> when the caller has them (no multipliers recomputed there).
        real(wp), intent(in), optional :: g_lo, g_hi
        !> The crossing multiplier at a bracket end (kind /= 0): tracked by inverse iteration from there instead of
        !> a `dgeev` at every secant step (`dgeev` again whenever the tracking fails or leaves the class).
        complex(wp), intent(in), optional :: mu_guess
        type(bordered_system) :: psys, fsys, csys
        logical :: have_csys
        complex(wp) :: mu_t
        complex(wp), allocatable :: vec(:)
        logical :: tracking
        real(wp) :: a, b, c, fa, fb, fc, kappa, a_prev
        integer :: iter, side, n1, info
        logical :: ok

        n1 = size(bp%y)
        located = .false.
        have_csys = .false.
        tracking = present(mu_guess) .and. kind /= 0
        if (tracking) then
            mu_t = mu_guess
            allocate (vec(n1 - 1))
            vec = cmplx(1.0_wp, 0.5_wp, kind=wp)
        end if
        a = 0.0_wp
        if (present(g_lo) .and. kind /= 0) then
            pt = bp
            fa = g_lo - shift
        else
            call value_at(a, fa, ok)
            if (.not. ok) return
        end if
        b = sigma_hi
        if (present(hi) .and. kind == 0) then
            fb = hi%t(n1)
        else if (present(g_hi) .and. kind /= 0) then
            fb = g_hi - shift
        else
            call value_at(b, fb, ok)
            if (.not. ok) return
        end if
        if (fa*fb > 0.0_wp) return
        side = 0
        a_prev = huge(1.0_wp)
        do iter = 1, 60
            c = b - fb*(b - a)/(fb - fa)
            if (.not. (c > min(a, b) .and. c < max(a, b))) c = 0.5_wp*(a + b)
            call value_at(c, fc, ok)
            if (.not. ok) return
            if (kind == 0) then
                kappa = abs(fb - fa)/max(abs(b - a), tiny(1.0_wp))
                if (fc**2 <= 2.0_wp*kappa*ctl%fold_tol) located = .true.
            else
                if (abs(pt%y(n1) - a_prev) <= ctl%fold_tol .or. fc == 0.0_wp) located = .true.
            end if
            if (abs(b - a) <= 1.0e-3_wp*ctl%fold_tol) located = .true.
            if (located) exit
            a_prev = pt%y(n1)
            if (fc*fb < 0.0_wp) then
                a = b
                fa = fb
                b = c
                fb = fc
                side = 0
            else
                b = c
                fb = fc
                if (side == 1) fa = 0.5_wp*fa
                side = 1
            end if
        end do
        if (kind == 0) then
            call point_multipliers(pt, stats, wr, wi, info)
            if (info /= 0) located = .false.
        end if

    contains

        subroutine value_at(sigma, g, okv)
            real(wp), intent(in) :: sigma
            real(wp), intent(out) :: g
            logical, intent(out) :: okv
            integer :: linfo

            if (sigma == 0.0_wp) then
                pt = bp
                okv = .true.
            else
                if (have_csys) then
                    call correct(map, bp, csys, sigma, ctl, pt, okv, stats, fsys)
                else
                    call correct(map, bp, sys, sigma, ctl, pt, okv, stats, fsys)
                end if
                if (.not. okv) return
                if (kind == 0) then
                    call complete_point(map, pt, bp%t, psys, okv, stats)
                else
                    ! a crossing needs the monodromy only (no tangent); the bordered matrix at this iterate, with
                    ! bp's tangent as its last row, is the chord matrix of the next corrections (nearer than bp's)
                    call point_jacobian(map, pt, okv, stats)
                    if (okv) then
                        call factor_bordered(pt%jac, pt%dpda, bp%t, csys, linfo, stats)
                        have_csys = linfo == 0
                    end if
                end if
                if (.not. okv) return
            end if
            pt%s = bp%s + sigma
            if (kind == 0) then
                g = pt%t(n1)
            else
                if (tracking) then
                    call tracked_distance(g, okv)
                    if (okv) return
                end if
                call point_multipliers(pt, stats, wr, wi, linfo)
                okv = linfo == 0
                g = crossing_distance(wr, wi, kind) - shift
                if (tracking .and. okv) then
                    ! start the tracking again from this point's crossing multiplier
                    linfo = class_max(wr, wi, kind)
                    if (linfo > 0) mu_t = cmplx(wr(linfo), wi(linfo), kind=wp)
                    vec = cmplx(1.0_wp, 0.5_wp, kind=wp)
                end if
            end if
        end subroutine value_at

        !> |mu| - 1 - shift of the tracked multiplier at pt (okt false when the tracking failed or its multiplier
        !> is no longer of the class: a torus pair that became real, a real multiplier that turned complex).
        subroutine tracked_distance(g, okt)
            real(wp), intent(out) :: g
            logical, intent(out) :: okt
            complex(wp) :: mu_try
            complex(wp), allocatable :: v_try(:)
            real(wp) :: t0, im_tol

            t0 = wall_clock()
            mu_try = mu_t
            v_try = vec
            call track_multiplier(pt%jac, mu_try, v_try, okt, 1.0e-13_wp)
            stats%time_eigen = stats%time_eigen + wall_clock() - t0
            stats%tracked = stats%tracked + 1
            g = 0.0_wp
            if (.not. okt) return
            im_tol = 1.0e-8_wp*abs(mu_try)
            select case (kind)
            case (crossing_torus)
                okt = abs(aimag(mu_try)) > im_tol
            case (crossing_period_doubling)
                okt = abs(aimag(mu_try)) <= im_tol .and. real(mu_try, wp) < 0.0_wp
            case default
                okt = abs(aimag(mu_try)) <= im_tol .and. real(mu_try, wp) >= 0.0_wp
            end select
            if (.not. okt) return
            mu_t = mu_try
            vec = v_try
            g = abs(mu_t) - 1.0_wp - shift
        end subroutine tracked_distance

    end subroutine locate

    !> Index of the multiplier of largest modulus in a class (`crossing_torus`: complex, `crossing_fold`: real >= 0,
    !> `crossing_period_doubling`: real < 0); 0 when the class is empty.
    pure integer function class_max(wr, wi, kind) result(k)
        real(wp), intent(in) :: wr(:), wi(:)
        integer, intent(in) :: kind
        integer :: j, c
        real(wp) :: best

        k = 0
        best = -1.0_wp
        do j = 1, size(wr)
            if (wi(j) /= 0.0_wp) then
                c = crossing_torus
            else if (wr(j) >= 0.0_wp) then
                c = crossing_fold
            else
                c = crossing_period_doubling
            end if
            if (c == kind .and. hypot(wr(j), wi(j)) > best) then
                best = hypot(wr(j), wi(j))
                k = j
            end if
        end do
    end function class_max

    !> The multipliers at a point with its Jacobian.
    subroutine point_multipliers(pt, stats, wr, wi, info)
        type(branch_point), intent(in) :: pt
        type(continuation_stats), intent(inout) :: stats
        real(wp), allocatable, intent(out) :: wr(:), wi(:)
        integer, intent(out) :: info
        real(wp) :: t0

        t0 = wall_clock()
        call floquet_multipliers(pt%jac, wr, wi, info)
        stats%eigen_calls = stats%eigen_calls + 1
        stats%time_eigen = stats%time_eigen + wall_clock() - t0
    end subroutine point_multipliers

    !> Evaluate P (and, when asked, its derivatives) at y = (x, A), counted and timed.
    subroutine evaluate(map, y, px, status, stats, jac, dpda)
        class(fixed_point_map), intent(inout) :: map
        real(wp), intent(in) :: y(:)
        real(wp), intent(out) :: px(:)
        integer, intent(out) :: status
        type(continuation_stats), intent(inout) :: stats
        real(wp), intent(out), optional :: jac(:, :), dpda(:)
        real(wp) :: t0
        integer :: d

        d = size(y) - 1
        t0 = wall_clock()
        if (present(jac)) then
            call map%apply(y(1:d), y(d + 1), px, status, jac=jac, dpda=dpda)
            stats%jacobian_evaluations = stats%jacobian_evaluations + 1
            stats%time_jacobian = stats%time_jacobian + wall_clock() - t0
            if (status == map_ok) then
                if (.not. (all(ieee_is_finite(jac)) .and. all(ieee_is_finite(dpda)))) status = map_ok + 1
            end if
        else
            call map%apply(y(1:d), y(d + 1), px, status)
            stats%map_evaluations = stats%map_evaluations + 1
            stats%time_map = stats%time_map + wall_clock() - t0
        end if
        if (status == map_ok) then
            if (.not. all(ieee_is_finite(px))) status = map_ok + 1
        end if
    end subroutine evaluate

    !> Append a point to the branch arrays (with its multipliers when `have_mult`), or insert it at `position`.
    subroutine record_point(map, res, pt, wr, wi, have_mult, position)
        class(fixed_point_map), intent(inout) :: map
        type(continuation_result), intent(inout) :: res
        type(branch_point), intent(in) :: pt
        real(wp), intent(in) :: wr(:), wi(:)
        logical, intent(in) :: have_mult
        integer, intent(in), optional :: position
        integer :: i, d, n, k

        d = size(pt%y) - 1
        res%n_points = res%n_points + 1
        n = res%n_points
        i = n
        if (present(position)) i = position
        if (i < n) then
            res%amplitude(i + 1:n) = res%amplitude(i:n - 1)
            res%arclength(i + 1:n) = res%arclength(i:n - 1)
            res%umax(i + 1:n) = res%umax(i:n - 1)
            res%energy(i + 1:n) = res%energy(i:n - 1)
            res%max_multiplier(i + 1:n) = res%max_multiplier(i:n - 1)
            res%stable(i + 1:n) = res%stable(i:n - 1)
            res%newton_iterations(i + 1:n) = res%newton_iterations(i:n - 1)
            res%residual(i + 1:n) = res%residual(i:n - 1)
            res%tangent_amplitude(i + 1:n) = res%tangent_amplitude(i:n - 1)
            res%exact_tangent(i + 1:n) = res%exact_tangent(i:n - 1)
            res%states(:, i + 1:n) = res%states(:, i:n - 1)
            res%tangents(:, i + 1:n) = res%tangents(:, i:n - 1)
            do k = n, i + 1, -1
                call move_spectrum(res%spectra(k - 1), res%spectra(k))
            end do
        end if
        res%amplitude(i) = pt%y(d + 1)
        res%arclength(i) = pt%s
        call map%measures(pt%y(1:d), pt%y(d + 1), res%umax(i), res%energy(i))
        res%newton_iterations(i) = pt%iterations
        res%residual(i) = pt%residual
        res%tangent_amplitude(i) = pt%t(d + 1)
        res%exact_tangent(i) = merge(1, 0, pt%exact)
        res%states(:, i) = pt%y(1:d)
        res%tangents(:, i) = pt%t
        res%max_multiplier(i) = ieee_value(1.0_wp, ieee_quiet_nan)
        res%stable(i) = -1
        if (allocated(res%spectra(i)%wr)) deallocate (res%spectra(i)%wr, res%spectra(i)%wi)
        if (have_mult) call keep_spectrum(res, i, wr, wi)
    end subroutine record_point

    !> Keep the multipliers of recorded point `i` (and its largest modulus and stability verdict).
    subroutine keep_spectrum(res, i, wr, wi)
        type(continuation_result), intent(inout) :: res
        integer, intent(in) :: i
        real(wp), intent(in) :: wr(:), wi(:)

        res%spectra(i)%wr = wr
        res%spectra(i)%wi = wi
        res%max_multiplier(i) = largest_modulus(wr, wi)
        res%stable(i) = merge(1, 0, is_stable(wr, wi, res%crossing_tol))
    end subroutine keep_spectrum

    !> Move a kept spectrum from one point's slot to another's.
    subroutine move_spectrum(from, to)
        type(point_spectrum), intent(inout) :: from, to

        if (allocated(to%wr)) deallocate (to%wr, to%wi)
        if (allocated(from%wr)) then
            call move_alloc(from%wr, to%wr)
            call move_alloc(from%wi, to%wi)
        end if
    end subroutine move_spectrum

    !> Replace the recorded tangent of point `i` by the exact one of `pt`.
    subroutine update_tangent(res, i, pt)
        type(continuation_result), intent(inout) :: res
        integer, intent(in) :: i
        type(branch_point), intent(in) :: pt

        res%tangents(:, i) = pt%t
        res%tangent_amplitude(i) = pt%t(size(pt%t))
        res%exact_tangent(i) = 1
    end subroutine update_tangent

    !> A recorded point rebuilt from its stored state and tangent, with its Jacobian evaluated again.
    subroutine stored_point(map, res, i, pt, stats, info)
        class(fixed_point_map), intent(inout) :: map
        type(continuation_result), intent(in) :: res
        integer, intent(in) :: i
        type(branch_point), intent(inout) :: pt
        type(continuation_stats), intent(inout) :: stats
        integer, intent(out) :: info
        real(wp), allocatable :: px(:)
        integer :: d, status

        d = size(res%states, 1)
        pt%y = [res%states(:, i), res%amplitude(i)]
        pt%t = res%tangents(:, i)
        pt%s = res%arclength(i)
        pt%iterations = res%newton_iterations(i)
        pt%residual = res%residual(i)
        pt%exact = res%exact_tangent(i) == 1
        if (.not. allocated(pt%jac)) allocate (pt%jac(d, d), pt%dpda(d))
        allocate (px(d))
        call evaluate(map, pt%y, px, status, stats, pt%jac, pt%dpda)
        info = merge(0, 1, status == map_ok)
    end subroutine stored_point

    subroutine allocate_branch(res, d, capacity)
        type(continuation_result), intent(inout) :: res
        integer, intent(in) :: d, capacity
        real(wp) :: nan

        nan = ieee_value(1.0_wp, ieee_quiet_nan)
        allocate (res%amplitude(capacity), res%arclength(capacity), res%umax(capacity), res%energy(capacity), &
                  res%max_multiplier(capacity), res%residual(capacity), res%tangent_amplitude(capacity))
        allocate (res%stable(capacity), res%newton_iterations(capacity), res%exact_tangent(capacity))
        allocate (res%states(d, capacity), res%tangents(d + 1, capacity), res%spectra(capacity))
        res%max_multiplier = nan
        res%stable = -1
    end subroutine allocate_branch

    !> Stop reason and status: a located fold makes the status `cont_fold_found` whatever ended the march.
    subroutine set_stop(res, reason)
        type(continuation_result), intent(inout) :: res
        integer, intent(in) :: reason

        res%stop_reason = reason
        res%status = reason
        if (res%fold_index > 0) res%status = cont_fold_found
    end subroutine set_stop

    !> Trim the branch arrays to n_points and record the total time.
    subroutine finish(res, t_start)
        type(continuation_result), intent(inout) :: res
        real(wp), intent(in) :: t_start
        integer :: n

        n = res%n_points
        res%amplitude = res%amplitude(1:n)
        res%arclength = res%arclength(1:n)
        res%umax = res%umax(1:n)
        res%energy = res%energy(1:n)
        res%max_multiplier = res%max_multiplier(1:n)
        res%residual = res%residual(1:n)
        res%tangent_amplitude = res%tangent_amplitude(1:n)
        res%exact_tangent = res%exact_tangent(1:n)
        res%stable = res%stable(1:n)
        res%newton_iterations = res%newton_iterations(1:n)
        res%states = res%states(:, 1:n)
        res%tangents = res%tangents(:, 1:n)
        res%spectra = res%spectra(1:n)
        res%stats%time_total = wall_clock() - t_start
    end subroutine finish

    subroutine move_point(from, to)
        type(branch_point), intent(inout) :: from, to

        call move_alloc(from%y, to%y)
        call move_alloc(from%t, to%t)
        call move_alloc(from%jac, to%jac)
        call move_alloc(from%dpda, to%dpda)
        to%s = from%s
        to%residual = from%residual
        to%iterations = from%iterations
        to%refreshes = from%refreshes
        to%exact = from%exact
    end subroutine move_point

    subroutine move_system(from, to)
        type(bordered_system), intent(inout) :: from, to

        call move_alloc(from%lu, to%lu)
        call move_alloc(from%ipiv, to%ipiv)
        call move_alloc(from%row0, to%row0)
        call move_alloc(from%z, to%z)
        call move_alloc(from%w, to%w)
        to%denom = from%denom
        to%updated = from%updated
    end subroutine move_system

    !> Wall-clock seconds (for the cost record only; no result depends on it).
    real(wp) function wall_clock()
        integer(i8) :: count, rate

        call system_clock(count, rate)
        wall_clock = real(count, wp)/real(max(rate, 1_i8), wp)
    end function wall_clock

end module supratrans_continuation
