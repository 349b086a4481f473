!> The result of one task of the continuation scene (one curve at one driving frequency), as a typed record, and its
!> serialisation by name: the journal and the part files store a task's record as named values (`fold_fields`).
!>
!> The scalar fields (their names, their order among the values, the record as values and back) are generated from the
!> scene's output table (`supratrans_fold_scalars`, src/io/outputs/continuation.toml); this module adds the branch
!> and the multipliers.
!>
!> A record holds the fold of the branch of driven periodic states (the model's supratransmission threshold), the
!> first loss of Floquet stability met on the way, how converged the fold is in dt and in N, what the continuation
!> cost, the branch itself (up to `points_max` points, the rest NaN) and the multipliers nearest the unit circle at
!> a few points of the branch.
module supratrans_fold_record
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp
    use supratrans_strings, only: int_str
    use supratrans_continuation_types, only: continuation_result, continuation_stats
    use supratrans_fold_scalars, only: fold_scalars, fold_scalars_names, fold_scalars_values, fold_scalars_from_values, &
                                       empty_fold_scalars
    implicit none
    private

    public :: fold_fields, fold_to_values, fold_from_values, empty_fold_record, add_fold_cost, add_stats, add_branch_cost

    !> Quantities recorded at each branch point, in this order (`fold_record%branch` rows, `/branch/<name>`).
    character(len=*), parameter, public :: branch_quantities(*) = [character(len=17) :: "amplitude", "umax", &
        "energy", "multiplier_max", "stable", "newton_iterations", "residual"]
    !> Multipliers kept at each sampled point: the `kept_multipliers` of largest modulus.
    integer, parameter, public :: kept_multipliers = 8
    !> Branch points at which the multipliers are kept: the first point, the point with multipliers nearest half the
    !> fold, the fold (the nearest point), the last point.
    integer, parameter, public :: multiplier_samples = 4

    !> One (curve, Omega) task: the fold and stability of its branch, their convergence (its scalar fields, one
    !> dataset each, are those of the output table src/io/outputs/continuation.toml, `fold_scalars`), the branch.
    type, extends(fold_scalars), public :: fold_record
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

        allocate (names(size(fold_scalars_names) + size(branch_quantities)*points_max &
                        + multiplier_samples*(2*kept_multipliers + 1)))
        names(1:size(fold_scalars_names)) = fold_scalars_names
        i = size(fold_scalars_names)
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
        r%fold_scalars = empty_fold_scalars()
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

        v = [fold_scalars_values(r%fold_scalars), reshape(r%branch, [size(r%branch)])]
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

        r%fold_scalars = fold_scalars_from_values(v)
        i = size(fold_scalars_names)
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

    !> Add what a continuation cost (its counts and times) to the record's costs.
    pure subroutine add_branch_cost(r, res)
        !> The record.
        type(fold_record), intent(inout) :: r
        !> The continuation.
        type(continuation_result), intent(in) :: res

        r%newton_iterations = r%newton_iterations + sum(res%newton_iterations(1:res%n_points))
        call add_stats(r, res%stats)
    end subroutine add_branch_cost

    !> Add counts and times (of a continuation, a fate's watch, stairs, damped shooting) to the record's costs.
    pure subroutine add_stats(r, stats)
        !> The record.
        type(fold_record), intent(inout) :: r
        !> The counts and times.
        type(continuation_stats), intent(in) :: stats

        r%map_evaluations = r%map_evaluations + stats%map_evaluations + stats%jacobian_evaluations
        r%jacobians = r%jacobians + stats%jacobian_evaluations
        r%factorizations = r%factorizations + stats%factorisations
        r%eigen_calls = r%eigen_calls + stats%eigen_calls
        r%time_map = r%time_map + stats%time_map
        r%time_tangent = r%time_tangent + stats%time_jacobian
        r%time_lu = r%time_lu + stats%time_lu
        r%time_eigen = r%time_eigen + stats%time_eigen
    end subroutine add_stats

end module supratrans_fold_record
