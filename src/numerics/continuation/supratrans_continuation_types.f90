!> The controls, the result and the cost record of a pseudo-arclength continuation (`supratrans_continuation`, whose
!> module documentation describes the method; it re-exports them), its status codes and their names, and the clock
!> of the cost record. No state of its own.
module supratrans_continuation_types
    use supratrans_kinds, only: wp, i8
    use supratrans_floquet, only: crossing_none
    implicit none
    private

    public :: continuation_status_name, wall_clock

    public :: cont_fold_found, cont_no_fold, cont_newton_failed, cont_step_too_small, cont_max_points, &
              cont_unstable_start

    !> The statuses of a continuation, why its march ended: one enumeration, with the numbers the result files have
    !> always stored (5 is the continuation scene's `fold_map_failed`, `supratrans_fold_line`): not renumbered.
    enum, bind(c)
        !> Status: a fold was found and located (the march then went up to `beyond_fold` points past it).
        enumerator :: cont_fold_found = 0
        !> Status: the branch reached A > `amplitude_max` with no fold.
        enumerator :: cont_no_fold = 1
        !> Status: Newton-shooting did not converge at the starting amplitude (or x0 has the wrong size).
        enumerator :: cont_newton_failed = 2
        !> Status: the corrector kept failing until the step fell below `ds_min`, before any fold.
        enumerator :: cont_step_too_small = 3
        !> Status: `max_points` points computed before any fold and below `amplitude_max`.
        enumerator :: cont_max_points = 4
        !> Status: the starting state is not stable and `stop_at_unstable_start` asked for no branch from it.
        enumerator :: cont_unstable_start = 6
    end enum

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
        !> Most iterations of the Newton-shooting at the start; 0: `newton_max_iter` (a start far from its periodic
        !> state may need more than a corrector, which refreshes its Jacobian sooner when it has fewer).
        integer :: start_max_iter = 0
        !> The Newton-shooting at the start gives up (`cont_newton_failed`) once its residual exceeds this multiple
        !> of its first value (`shooting_controls%growth_limit`); default: never.
        real(wp) :: start_growth_limit = huge(1.0_wp)
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
        !> the fold only (the fold alone: no multipliers along the branch; a loss of stability is sought only where
        !> `flip_watch` sees a real multiplier pass -1 or +1).
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
        !> End the continuation at its first point when that point has multipliers and is not stable
        !> (`cont_unstable_start`): a state the chain cannot have settled on has no branch worth following. The
        !> first point gets its multipliers for this also when `floquet_every` = 0.
        logical :: stop_at_unstable_start = .false.
        !> With `floquet_every` = 0 (the fold alone), watch the signs of det(J + I) and of the bordered matrix's
        !> determinant at every Jacobian of the branch before its fold (`supratrans_continuation_watch`): where one
        !> changes, a real multiplier has passed -1 or +1, and the multipliers of the two points around it say whether
        !> the branch lost its stability there (located like every crossing). A complex pair leaving the unit circle
        !> is not seen this way: that needs the multipliers along the branch.
        logical :: flip_watch = .true.
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
        !> `cont_fold_found`, `cont_no_fold`, `cont_newton_failed`, `cont_step_too_small`, `cont_max_points`,
        !> `cont_unstable_start`.
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
        !> Lower end of the bracket of that loss: `instability_amplitude` where it was located (to `fold_tol`), else
        !> the last amplitude known stable below it (the loss lies between the two); NaN with it.
        real(wp) :: instability_lower = 0.0_wp
        !> Kind of that loss (`supratrans_floquet`: crossing_none, crossing_fold, crossing_period_doubling,
        !> crossing_torus).
        integer :: instability_type = crossing_none
        !> The point (x, A) reported as that loss where it is a corrected point (located, or the unstable end of a
        !> narrowed bisection): where a branch point is, for `switch_branch`. Not allocated otherwise.
        real(wp), allocatable :: instability_point(:)
        !> With `instability_point`: the unit tangent of the branch at the last point before that loss.
        real(wp), allocatable :: instability_tangent(:)
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

contains

    !> The name of a continuation status: "fold_found", "no_fold", "newton_failed", "step_too_small", "max_points",
    !> "unstable_start".
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
        case (cont_unstable_start)
            name = "unstable_start"
        case default
            name = "unknown"
        end select
    end function continuation_status_name

    !> Wall-clock seconds (for the cost record only; no result depends on it).
    real(wp) function wall_clock()
        integer(i8) :: count, rate

        call system_clock(count, rate)
        wall_clock = real(count, wp)/real(max(rate, 1_i8), wp)
    end function wall_clock

end module supratrans_continuation_types
