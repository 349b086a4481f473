!> The result of one task of the continuation scene (one curve at one driving frequency), as a typed record, and its
!> serialisation by name: the journal and the part files store a task's record as named values (`fold_fields`).
!>
!> A record holds the fold of the branch of driven periodic states (the model's supratransmission threshold), the
!> first loss of Floquet stability met on the way, how converged the fold is in dt and in N, what the continuation
!> cost, the branch itself (up to `points_max` points, the rest NaN) and the multipliers nearest the unit circle at
!> a few points of the branch.
module supratrans_fold_record
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp
    use supratrans_strings, only: int_str
    implicit none
    private

    public :: fold_fields, fold_to_values, fold_from_values, empty_fold_record, add_fold_cost

    !> Quantities recorded at each branch point, in this order (`fold_record%branch` rows, `/branch/<name>`).
    character(len=*), parameter, public :: branch_quantities(*) = [character(len=17) :: "amplitude", "umax", &
        "energy", "multiplier_max", "stable", "newton_iterations", "residual"]
    !> Multipliers kept at each sampled point: the `kept_multipliers` of largest modulus.
    integer, parameter, public :: kept_multipliers = 8
    !> Branch points at which the multipliers are kept: the first point, the point with multipliers nearest half the
    !> fold, the fold (the nearest point), the last point.
    integer, parameter, public :: multiplier_samples = 4

    !> The scalar fields of a record, in the order of `fold_fields`.
    character(len=*), parameter :: scalar_fields(*) = [character(len=24) :: "fold_amplitude", "fold_residual", &
        "status", "instability_amplitude", "instability_type", "instability_size", "threshold", "threshold_kind", "threshold_as", &
        "dt_used", "steps_per_period", "points", "newton_iterations", "map_evaluations", "jacobians", &
        "factorizations", "eigen_calls", "wall_time", "time_map", "time_tangent", "time_lu", "time_eigen", &
        "fold_half_dt", "fold_long_chain", "richardson", &
        "error_estimate", "digits", "chain_n", "chain_n0", "chain_sigma", "fate", "fate_time", &
        "transmission_fold", "branches", "transmission_status", "instability_lower", "branch_switch", &
        "transmission_stairs", "transmission_spread"]

    !> One (curve, Omega) task: the fold and stability of its branch, their convergence, the branch.
    type, public :: fold_record
        !> Fold amplitude A_f (saddle-node of the branch of periodic states); NaN when none was found.
        real(wp) :: fold_amplitude = 0.0_wp
        !> max-norm of the shooting residual P(x) - x at the located fold.
        real(wp) :: fold_residual = 0.0_wp
        !> Outcome (`supratrans_continuation` status, or the scene's -2 outside gap, -1 pending).
        integer :: status = 0
        !> Amplitude of the first loss of Floquet stability along the branch; NaN when the branch stays stable.
        real(wp) :: instability_amplitude = 0.0_wp
        !> Lower end of the bracket of that loss: the same amplitude where it was located, else the last amplitude
        !> known stable below it; NaN with it.
        real(wp) :: instability_lower = 0.0_wp
        !> Type of that loss: 0 none, 1 real multiplier through +1 (fold), 2 through -1 (period doubling), 3 complex
        !> pair (torus).
        integer :: instability_type = 0
        !> How far the multipliers leave the unit circle before the fold: max |mu| - 1 over the branch points up to
        !> the fold (negative: stable throughout; NaN when no multipliers were computed).
        real(wp) :: instability_size = 0.0_wp
        !> The model's threshold: the smaller of the fold and the first loss of stability; NaN when neither.
        real(wp) :: threshold = 0.0_wp
        !> Which one the threshold is (the `instability_type` codes; 1 also when it is the fold itself).
        integer :: threshold_kind = 0
        !> Continuum-limit threshold A_s of the curve's chain; NaN outside the gap.
        real(wp) :: threshold_as = 0.0_wp
        !> Time step used: the drive period over a whole number of steps.
        real(wp) :: dt_used = 0.0_wp
        !> Steps per drive period M.
        integer :: steps_per_period = 0
        !> Branch points computed.
        integer :: points = 0
        !> Newton (shooting) iterations over the whole continuation.
        integer :: newton_iterations = 0
        !> Evaluations of the period map, with and without its Jacobian.
        integer :: map_evaluations = 0
        !> Evaluations of the Jacobian (tangent propagations of 2N + 1 columns).
        integer :: jacobians = 0
        !> LU factorisations of the shooting system.
        integer :: factorizations = 0
        !> Eigenvalue computations (Floquet multipliers).
        integer :: eigen_calls = 0
        !> Wall-clock time of the task (s), the convergence runs included.
        real(wp) :: wall_time = 0.0_wp
        !> Seconds in evaluations of the period map alone, in those with the tangent (2N + 1 columns), in dense LU
        !> factorisations and solves, in eigenvalue computations.
        real(wp) :: time_map = 0.0_wp, time_tangent = 0.0_wp, time_lu = 0.0_wp, time_eigen = 0.0_wp
        !> The fold located again at dt/2 (NaN when not computed).
        real(wp) :: fold_half_dt = 0.0_wp
        !> The fold located again on a chain twice as long (N0 and N shifted by N: the same absorber; NaN when not
        !> computed).
        real(wp) :: fold_long_chain = 0.0_wp
        !> Richardson extrapolation of the fold in dt from dt and dt/2 with the method's order.
        real(wp) :: richardson = 0.0_wp
        !> Estimated error of the fold: the larger of |A_f(dt/2) - A_f(dt)| / (2^p - 1) and |A_f(2N) - A_f(N)|.
        real(wp) :: error_estimate = 0.0_wp
        !> Converged decimal digits of A_f: floor(-log10(error_estimate / A_f)), capped at 15; NaN when unknown.
        real(wp) :: digits = 0.0_wp
        !> The chain used: N, N0 and the absorber's sigma (a fold line that gives no chain length uses the short
        !> chain of `supratrans_fold_line`).
        integer :: chain_n = 0, chain_n0 = 0
        !> The absorber's sigma used.
        real(wp) :: chain_sigma = 0.0_wp
        !> What the chain does when driven just past the fold (`supratrans_fold_line`, `fate_*` codes): 0 not computed,
        !> 1 it transmits (the fold is the supratransmission threshold), 2 it stays localized.
        integer :: fate = 0
        !> Time from the push past the fold to the first transmission (fate 1), or the time watched (fate 2); NaN when
        !> not computed.
        real(wp) :: fate_time = 0.0_wp
        !> The fold past which the chain transmits: the first fold when its fate is to transmit; else the fold of the
        !> branch the chain settles on past it, and so on (`branches`); NaN when none was found.
        real(wp) :: transmission_fold = 0.0_wp
        !> Branches followed to `transmission_fold` (1: the first fold transmits; 0: no fold).
        integer :: branches = 0
        !> Why `transmission_fold` is what it is (`supratrans_fold_line`: 0 found, -1 no first fold, else the reason).
        integer :: transmission_status = -1
        !> What was done past a loss of stability below the fold (`supratrans_fold_fate`: 0 none, 1 supercritical,
        !> 2 subcritical, 3 the other branch not found, 4 stairs past a torus or a period doubling).
        integer :: branch_switch = 0
        !> 1 where `transmission_fold` is the stair on which the chain, driven up in stairs, transmitted; 0 where it
        !> is a fold or a branch point (or NaN).
        integer :: transmission_stairs = 0
        !> Where `transmission_fold` is a stair: how far from it the other climbs (`other_climbs` of
        !> `supratrans_fold_fate`, from the first's start moved by `switch_seed` along other fixed directions) transmit
        !> (max |A_k - A_1|; a climb that did not transmit within its bound counts at its next stair, a lower bound).
        !> NaN where `transmission_fold` is not a stair.
        real(wp) :: transmission_spread = 0.0_wp
        !> The branch: `branch_quantities` (rows) at each point (columns), NaN past `points`.
        real(wp), allocatable :: branch(:, :)
        !> Real and imaginary parts of the kept multipliers (`kept_multipliers`, `multiplier_samples`); NaN when not
        !> computed.
        real(wp) :: multiplier_re(kept_multipliers, multiplier_samples) = 0.0_wp
        !> Imaginary parts.
        real(wp) :: multiplier_im(kept_multipliers, multiplier_samples) = 0.0_wp
        !> Amplitude of each sampled point; NaN when not computed.
        real(wp) :: multiplier_amplitude(multiplier_samples) = 0.0_wp
    end type fold_record

contains

    !> The names of a record's values for a branch of at most `points_max` points: the scalar fields, then
    !> `branch_<quantity>_<k>`, then `multiplier_re|im_<sample>_<k>` and `multiplier_amplitude_<sample>`.
    function fold_fields(points_max) result(names)
        !> Most points of a branch.
        integer, intent(in) :: points_max
        character(len=40), allocatable :: names(:)
        integer :: i, k, j, s

        allocate (names(size(scalar_fields) + size(branch_quantities)*points_max &
                        + multiplier_samples*(2*kept_multipliers + 1)))
        names(1:size(scalar_fields)) = scalar_fields
        i = size(scalar_fields)
        do k = 1, points_max
            do j = 1, size(branch_quantities)
                i = i + 1
                names(i) = "branch_" // trim(branch_quantities(j)) // "_" // int_str(k)
            end do
        end do
        do s = 1, multiplier_samples
            do k = 1, kept_multipliers
                names(i + 1) = "multiplier_re_" // int_str(s) // "_" // int_str(k)
                names(i + 2) = "multiplier_im_" // int_str(s) // "_" // int_str(k)
                i = i + 2
            end do
            i = i + 1
            names(i) = "multiplier_amplitude_" // int_str(s)
        end do
    end function fold_fields

    !> A record with nothing computed: numbers NaN, counts 0, the branch of `points_max` NaN points.
    pure function empty_fold_record(points_max) result(r)
        !> Most points of a branch.
        integer, intent(in) :: points_max
        type(fold_record) :: r
        real(wp) :: nan

        nan = ieee_value(nan, ieee_quiet_nan)
        r%fold_amplitude = nan
        r%fold_residual = nan
        r%instability_amplitude = nan
        r%instability_lower = nan
        r%instability_size = nan
        r%threshold = nan
        r%threshold_as = nan
        r%dt_used = nan
        r%wall_time = 0.0_wp
        r%fold_half_dt = nan
        r%fold_long_chain = nan
        r%richardson = nan
        r%error_estimate = nan
        r%digits = nan
        r%chain_sigma = nan
        r%fate_time = nan
        r%transmission_fold = nan
        r%transmission_spread = nan
        allocate (r%branch(size(branch_quantities), points_max), source=nan)
        r%multiplier_re = nan
        r%multiplier_im = nan
        r%multiplier_amplitude = nan
    end function empty_fold_record

    !> The record as values in `fold_fields` order.
    pure function fold_to_values(r) result(v)
        !> The record.
        type(fold_record), intent(in) :: r
        real(wp), allocatable :: v(:)
        integer :: s

        v = [r%fold_amplitude, r%fold_residual, real(r%status, wp), r%instability_amplitude, &
             real(r%instability_type, wp), r%instability_size, r%threshold, real(r%threshold_kind, wp), r%threshold_as, r%dt_used, &
             real(r%steps_per_period, wp), real(r%points, wp), real(r%newton_iterations, wp), &
             real(r%map_evaluations, wp), real(r%jacobians, wp), real(r%factorizations, wp), real(r%eigen_calls, wp), &
             r%wall_time, r%time_map, r%time_tangent, r%time_lu, r%time_eigen, r%fold_half_dt, r%fold_long_chain, &
             r%richardson, r%error_estimate, r%digits, real(r%chain_n, wp), real(r%chain_n0, wp), r%chain_sigma, &
             real(r%fate, wp), r%fate_time, r%transmission_fold, real(r%branches, wp), &
             real(r%transmission_status, wp), r%instability_lower, real(r%branch_switch, wp), &
             real(r%transmission_stairs, wp), r%transmission_spread, reshape(r%branch, [size(r%branch)])]
        do s = 1, multiplier_samples
            v = [v, reshape(transpose(reshape([r%multiplier_re(:, s), r%multiplier_im(:, s)], &
                                              [kept_multipliers, 2])), [2*kept_multipliers]), r%multiplier_amplitude(s)]
        end do
    end function fold_to_values

    !> The record of values in `fold_fields` order for a branch of at most `points_max` points.
    pure function fold_from_values(v, points_max) result(r)
        !> The values.
        real(wp), intent(in) :: v(:)
        !> Most points of a branch.
        integer, intent(in) :: points_max
        type(fold_record) :: r
        integer :: i, s, nb

        r%fold_amplitude = v(1)
        r%fold_residual = v(2)
        r%status = nint(v(3))
        r%instability_amplitude = v(4)
        r%instability_type = nint(v(5))
        r%instability_size = v(6)
        r%threshold = v(7)
        r%threshold_kind = nint(v(8))
        r%threshold_as = v(9)
        r%dt_used = v(10)
        r%steps_per_period = nint(v(11))
        r%points = nint(v(12))
        r%newton_iterations = nint(v(13))
        r%map_evaluations = nint(v(14))
        r%jacobians = nint(v(15))
        r%factorizations = nint(v(16))
        r%eigen_calls = nint(v(17))
        r%wall_time = v(18)
        r%time_map = v(19)
        r%time_tangent = v(20)
        r%time_lu = v(21)
        r%time_eigen = v(22)
        r%fold_half_dt = v(23)
        r%fold_long_chain = v(24)
        r%richardson = v(25)
        r%error_estimate = v(26)
        r%digits = v(27)
        r%chain_n = nint(v(28))
        r%chain_n0 = nint(v(29))
        r%chain_sigma = v(30)
        r%fate = nint(v(31))
        r%fate_time = v(32)
        r%transmission_fold = v(33)
        r%branches = nint(v(34))
        r%transmission_status = nint(v(35))
        r%instability_lower = v(36)
        r%branch_switch = nint(v(37))
        r%transmission_stairs = nint(v(38))
        r%transmission_spread = v(39)
        i = size(scalar_fields)
        nb = size(branch_quantities)*points_max
        r%branch = reshape(v(i + 1:i + nb), [size(branch_quantities), points_max])
        i = i + nb
        do s = 1, multiplier_samples
            r%multiplier_re(:, s) = v(i + 1:i + 2*kept_multipliers:2)
            r%multiplier_im(:, s) = v(i + 2:i + 2*kept_multipliers:2)
            i = i + 2*kept_multipliers + 1
            r%multiplier_amplitude(s) = v(i)
        end do
    end function fold_from_values

    !> Add the cost counters of another record (a convergence check's) to a task's record.
    pure subroutine add_fold_cost(r, check)
        !> The task's record.
        type(fold_record), intent(inout) :: r
        !> The check's record.
        type(fold_record), intent(in) :: check

        r%newton_iterations = r%newton_iterations + check%newton_iterations
        r%map_evaluations = r%map_evaluations + check%map_evaluations
        r%jacobians = r%jacobians + check%jacobians
        r%factorizations = r%factorizations + check%factorizations
        r%eigen_calls = r%eigen_calls + check%eigen_calls
        r%time_map = r%time_map + check%time_map
        r%time_tangent = r%time_tangent + check%time_tangent
        r%time_lu = r%time_lu + check%time_lu
        r%time_eigen = r%time_eigen + check%time_eigen
    end subroutine add_fold_cost

end module supratrans_fold_record
