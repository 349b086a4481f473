!> The record of one run of a sweep or map: its values by position (`iv_*`), their names, and the dataset each
!> one is written to (`fields`: path, units, whether an integer, description). A task's record is `run_values` of
!> the run's result; the journal stores it under `run_value_names`.
module supratrans_run_record
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp
    use supratrans_result, only: run_result, run_ok
    use supratrans_status, only: status_not_run
    implicit none
    private

    public :: run_value_names, run_values, not_run_values, nan

    !> Position in a task's values: energy injected through the driven end over the run (paper: "total energy").
    integer, parameter, public :: iv_injected = 1
    !> Position: stored discrete energy E at the end of the run.
    integer, parameter, public :: iv_stored = 2
    !> Position: energy dissipated by the external damping gamma.
    integer, parameter, public :: iv_dissipated_gamma = 3
    !> Position: energy dissipated by the internal damping beta.
    integer, parameter, public :: iv_dissipated_beta = 4
    !> Position: energy dissipated by the absorbing end gamma'(n).
    integer, parameter, public :: iv_dissipated_absorber = 5
    !> Position: balance residual of the ledger at the end of the run.
    integer, parameter, public :: iv_residual = 6
    !> Position: run status (`supratrans_result` codes, `status_not_run`, `status_outside_gap`).
    integer, parameter, public :: iv_status = 7
    !> Position: verdict, 1 transmitting, 0 not.
    integer, parameter, public :: iv_transmitting = 8
    !> Position: time of the verdict (crossing time, or the end of the run).
    integer, parameter, public :: iv_t_decided = 9
    !> Position: time steps taken.
    integer, parameter, public :: iv_steps = 10
    !> Position: Newton iterations over the run (0 for the methods without Newton).
    integer, parameter, public :: iv_newton_iterations = 11
    !> Position: wall-clock time of the run (s).
    integer, parameter, public :: iv_wall_time = 12
    !> Position: time at which the run ended (T, or when it failed).
    integer, parameter, public :: iv_t_end = 13
    !> Position: largest |u_n| over the run.
    integer, parameter, public :: iv_max_abs_u = 14
    !> Position: energy injected after the end of the ramp (the paper's "total energy").
    integer, parameter, public :: iv_injected_after_ramp = 15
    !> Position: largest |u_n| beyond the detector site (what the verdict compares with `detect_amplitude`).
    integer, parameter, public :: iv_u_beyond_max = 16
    !> Position: the detector site n_d of the run.
    integer, parameter, public :: iv_detect_site = 17
    !> Position: tridiagonal solves over the run (newton: one per iteration; linearized: one per step).
    integer, parameter, public :: iv_tridiagonal_solves = 18
    !> Position: right-hand-side evaluations over the run (the stages of rk4, rk8).
    integer, parameter, public :: iv_rhs_evaluations = 19
    !> Position: margin of the verdict relative to the detect amplitude (`supratrans_result%verdict_margin`).
    integer, parameter, public :: iv_verdict_margin = 20
    !> Position: 1 if the margin is thin (below `&detect thin_margin`), 0 if not.
    integer, parameter, public :: iv_thin_verdict = 21
    !> Number of values a task produces (the columns of the journal).
    integer, parameter, public :: n_run_values = 21

    !> One per-run dataset: where its value is in a task's values, its name under the root, units, meaning.
    type, public :: field_spec
        !> Position in the values (`iv_*`).
        integer :: iv
        !> Dataset path.
        character(len=32) :: name
        !> Units.
        character(len=8) :: units
        !> Stored as integer (missing entries -1) rather than real (missing entries NaN).
        logical :: is_int
        !> Description.
        character(len=160) :: description
    end type field_spec

    !> The per-run datasets, in the order they are written.
    type(field_spec), parameter, public :: fields(*) = [ &
        field_spec(iv_injected, "/energy/injected", "energy", .false., "Energy injected through the driven end " &
                   // "over the run 0..T (the paper's total energy transmitted); NaN unless status = 0"), &
        field_spec(iv_injected_after_ramp, "/energy/injected_after_ramp", "energy", .false., "Energy injected " &
                   // "after the drive's ramp, from ramp_time to T (the paper: 'before we start to compute the total " &
                   // "energy'); NaN unless status = 0"), &
        field_spec(iv_stored, "/energy/stored", "energy", .false., "Discrete energy E stored in the chain at T " &
                   // "(paper Sec. 3.2); NaN unless status = 0"), &
        field_spec(iv_dissipated_gamma, "/energy/dissipated_gamma", "energy", .false., "Energy dissipated by the " &
                   // "external damping gamma over the run; NaN unless status = 0"), &
        field_spec(iv_dissipated_beta, "/energy/dissipated_beta", "energy", .false., "Energy dissipated by the " &
                   // "internal damping beta over the run; NaN unless status = 0"), &
        field_spec(iv_dissipated_absorber, "/energy/dissipated_absorber", "energy", .false., "Energy dissipated " &
                   // "by the absorbing end gamma'(n) over the run; NaN unless status = 0"), &
        field_spec(iv_residual, "/energy/residual", "energy", .false., "Ledger balance residual E(T) - E(0) - " &
                   // "(injected - dissipated): roundoff for the Newton scheme; NaN unless status = 0"), &
        field_spec(iv_status, "/runs/status", "1", .true., "Run status: see the attribute status_codes of /runs " &
                   // "(0 ok, > 0 failed, < 0 not run)"), &
        field_spec(iv_transmitting, "/runs/transmitting", "1", .true., "Verdict: 1 if an oscillator beyond the " &
                   // "detector site swung past the detect amplitude (supratransmission), 0 if not; -1 if not run"), &
        field_spec(iv_t_decided, "/runs/t_decided", "time", .false., "Time of the verdict: when the detector " &
                   // "amplitude was passed if transmitting, else the end of the run; NaN if not run"), &
        field_spec(iv_steps, "/runs/steps", "1", .true., "Time steps taken; -1 if not run"), &
        field_spec(iv_newton_iterations, "/runs/newton_iterations", "1", .true., "Newton iterations over the run " &
                   // "(0 for methods without Newton); -1 if not run"), &
        field_spec(iv_tridiagonal_solves, "/runs/tridiagonal_solves", "1", .true., "Tridiagonal solves over the " &
                   // "run (newton: one per iteration, linearized: one per step); -1 if not run"), &
        field_spec(iv_rhs_evaluations, "/runs/rhs_evaluations", "1", .true., "Right-hand-side evaluations over " &
                   // "the run (rk4, rk8: their stages); -1 if not run"), &
        field_spec(iv_wall_time, "/runs/wall_time", "s", .false., "Wall-clock time of the run; NaN if not run"), &
        field_spec(iv_t_end, "/runs/t_end", "time", .false., "Time at which the run ended: T, or when it failed; " &
                   // "NaN if not run"), &
        field_spec(iv_max_abs_u, "/runs/max_abs_u", "rad", .false., "Largest |u_n| over the run; NaN if not run"), &
        field_spec(iv_u_beyond_max, "/runs/u_beyond_max", "rad", .false., "Reason of the verdict: largest |u_n| " &
                   // "beyond the detector site (transmitting once it exceeds detect_amplitude); NaN if not run"), &
        field_spec(iv_detect_site, "/runs/detect_site", "1", .true., "Detector site n_d of the verdict; -1 if not " &
                   // "run"), &
        field_spec(iv_verdict_margin, "/runs/verdict_margin", "1", .false., "Margin of the verdict: 1 - u_beyond_max/" &
                   // "detect_amplitude below, u_beyond_max/detect_amplitude - 1 above; NaN if not run or failed"), &
        field_spec(iv_thin_verdict, "/runs/thin_verdict", "1", .true., "1 if the verdict's margin is below &detect " &
                   // "thin_margin (it could flip under a small change: check it), 0 if not; -1 if not run")]

contains

    !> Names of a run's values, position `iv_*` holding the value of the dataset `fields(:)%name` (its last path
    !> component: "injected", "status", ...): the journal stores a task's values under these names.
    pure function run_value_names() result(names)
        character(len=32) :: names(n_run_values)
        integer :: i

        names = ""
        do i = 1, size(fields)
            names(fields(i)%iv) = fields(i)%name(index(fields(i)%name, "/", back=.true.) + 1:)
        end do
    end function run_value_names

    !> A run's values as journalled: the ledger totals at T (NaN if the run failed), status, verdict, statistics.
    pure function run_values(result) result(values)
        !> The run's result.
        type(run_result), intent(in) :: result
        real(wp) :: values(n_run_values)

        values = nan()
        if (result%status == run_ok) then
            values(iv_injected) = result%ledger%injected
            if (result%ramp_passed) values(iv_injected_after_ramp) = result%ledger%injected - result%injected_at_ramp
            values(iv_stored) = result%ledger%stored
            values(iv_dissipated_gamma) = result%ledger%dissipated_gamma
            values(iv_dissipated_beta) = result%ledger%dissipated_beta
            values(iv_dissipated_absorber) = result%ledger%dissipated_absorber
            values(iv_residual) = result%ledger%residual
        end if
        values(iv_status) = real(result%status, wp)
        values(iv_transmitting) = merge(1.0_wp, 0.0_wp, result%transmitting)
        values(iv_t_decided) = result%t_decided
        values(iv_steps) = real(result%steps, wp)
        values(iv_newton_iterations) = real(result%newton_iterations, wp)
        values(iv_tridiagonal_solves) = real(result%tridiagonal_solves, wp)
        values(iv_rhs_evaluations) = real(result%rhs_evaluations, wp)
        values(iv_wall_time) = result%wall_time
        values(iv_t_end) = result%t_end
        values(iv_max_abs_u) = result%max_abs_u
        values(iv_u_beyond_max) = result%u_beyond_max
        values(iv_detect_site) = real(result%detect_site, wp)
        values(iv_verdict_margin) = result%verdict_margin
        values(iv_thin_verdict) = merge(1.0_wp, 0.0_wp, result%thin_verdict)
    end function run_values

    !> The values of a run not computed: NaN, status `status_not_run`.
    pure function not_run_values() result(values)
        real(wp) :: values(n_run_values)

        values = nan()
        values(iv_status) = real(status_not_run, wp)
    end function not_run_values
    !> Quiet NaN.
    pure function nan() result(x)
        real(wp) :: x

        x = ieee_value(x, ieee_quiet_nan)
    end function nan

end module supratrans_run_record
