!> The record of one run of a sweep or map: the scalar fields of its output table (`run_scalars` of
!> `supratrans_run_scalars`, generated from src/io/outputs/amplitude_sweep.toml), filled from the run's result. A
!> task's record is `run_values` of the run's result; the journal stores it under `run_scalars_names`.
module supratrans_run_record
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp, i8
    use supratrans_result, only: run_result, run_ok
    use supratrans_run_scalars, only: run_scalars, run_scalars_names, run_scalars_values, run_scalars_from_values, &
        empty_run_scalars
    implicit none
    private

    public :: run_values, nan
    public :: run_scalars, run_scalars_names, run_scalars_values, run_scalars_from_values, empty_run_scalars

contains

    !> A run's values as journalled: the ledger totals at T (NaN if the run failed), status, verdict, statistics
    !> (a count beyond the default integer's range is its largest value).
    pure function run_values(result) result(values)
        !> The run's result.
        type(run_result), intent(in) :: result
        real(wp) :: values(size(run_scalars_names))
        type(run_scalars) :: s

        s = empty_run_scalars()
        if (result%status == run_ok) then
            s%injected = result%ledger%injected
            if (result%ramp_passed) s%injected_after_ramp = result%ledger%injected - result%injected_at_ramp
            s%stored = result%ledger%stored
            s%dissipated_gamma = result%ledger%dissipated_gamma
            s%dissipated_beta = result%ledger%dissipated_beta
            s%dissipated_absorber = result%ledger%dissipated_absorber
            s%residual = result%ledger%residual
        end if
        s%status = result%status
        s%transmitting = merge(1, 0, result%transmitting)
        s%t_decided = result%t_decided
        s%steps = count_of(result%steps)
        s%newton_iterations = count_of(result%newton_iterations)
        s%tridiagonal_solves = count_of(result%tridiagonal_solves)
        s%rhs_evaluations = count_of(result%rhs_evaluations)
        s%wall_time = result%wall_time
        s%t_end = result%t_end
        s%max_abs_u = result%max_abs_u
        s%u_beyond_max = result%u_beyond_max
        s%detect_site = result%detect_site
        s%verdict_margin = result%verdict_margin
        s%thin_verdict = merge(1, 0, result%thin_verdict)
        values = run_scalars_values(s)
    end function run_values

    !> An 8-byte count as a default integer field: at most `huge(1)`.
    elemental function count_of(n) result(c)
        !> The count.
        integer(i8), intent(in) :: n
        integer :: c

        c = int(min(n, int(huge(1), i8)))
    end function count_of

    !> Quiet NaN.
    pure function nan() result(x)
        real(wp) :: x

        x = ieee_value(x, ieee_quiet_nan)
    end function nan

end module supratrans_run_record
