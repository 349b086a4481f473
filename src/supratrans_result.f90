!> What one simulation produces: its outcome, solver statistics, energy totals and the recorded time series.
module supratrans_result
    use supratrans_kinds, only: wp, i8
    use supratrans_ledger, only: ledger_type
    implicit none
    private

    public :: status_name

    !> The run reached its final time (or was stopped early with its outcome decided).
    integer, parameter, public :: run_ok = 0
    !> The solution blew up: non-finite values or |u_n| above the blow-up threshold.
    integer, parameter, public :: run_diverged = 1
    !> Newton's method did not converge within its iteration cap.
    integer, parameter, public :: run_newton_failed = 2
    !> The linear solver failed (singular tridiagonal matrix) or produced non-finite values.
    integer, parameter, public :: run_solver_failed = 3

    !> Result of one run.
    type, public :: run_result
        !> Outcome: `run_ok`, `run_diverged`, `run_newton_failed`, `run_solver_failed`.
        integer :: status = run_ok
        !> Why the run ended as it did (empty for a normal end).
        character(len=:), allocatable :: reason
        !> Time steps taken.
        integer :: steps = 0
        !> Time at which the run ended.
        real(wp) :: t_end = 0.0_wp
        !> Total Newton iterations (tridiagonal solves) over the run.
        integer(i8) :: newton_iterations = 0
        !> Largest number of Newton iterations in one step.
        integer :: newton_max_iterations = 0
        !> Final energy ledger.
        type(ledger_type) :: ledger
        !> Wall-clock time of the run (s).
        real(wp) :: wall_time = 0.0_wp
        !> Largest |u_n| over the run.
        real(wp) :: max_abs_u = 0.0_wp
        !> Verdict: the run transmitted energy beyond the detector site.
        logical :: transmitting = .false.
        !> Time at which the verdict was decided (crossing time, or the end of the run).
        real(wp) :: t_decided = 0.0_wp
        !> Detector site n_d used.
        integer :: detect_site = 0
        !> Largest |u_n| beyond the detector site (n > n_d) seen.
        real(wp) :: u_beyond_max = 0.0_wp
        !> The run was stopped as soon as its verdict was decided.
        logical :: stopped_early = .false.
        !> Why the verdict is what it is.
        character(len=:), allocatable :: verdict_reason
        !> Probe sites.
        integer, allocatable :: probes(:)
        !> Probe sample times t_k.
        real(wp), allocatable :: probe_time(:)
        !> u_n(t_k) at the probe sites, shape (time, probe).
        real(wp), allocatable :: probe_u(:, :)
        !> Number of probe samples filled.
        integer :: n_probe_samples = 0
        !> Times t_{k+1/2} of the ledger records (E_k lives on levels k and k+1).
        real(wp), allocatable :: ledger_time(:)
        !> Ledger records, shape (time, 6): stored E_k, injected, dissipated by gamma, by beta, by the absorber,
        !> balance residual.
        real(wp), allocatable :: ledger_series(:, :)
        !> Number of ledger records filled.
        integer :: n_ledger_samples = 0
    end type run_result

    !> Names of the columns of `ledger_series`.
    character(len=*), parameter, public :: ledger_columns(6) = [character(len=19) :: "stored", "injected", &
        "dissipated_gamma", "dissipated_beta", "dissipated_absorber", "residual"]

contains

    !> Name of a run status, as written to output files.
    pure function status_name(status) result(name)
        !> Run status.
        integer, intent(in) :: status
        character(len=:), allocatable :: name

        select case (status)
        case (run_ok)
            name = "ok"
        case (run_diverged)
            name = "diverged"
        case (run_newton_failed)
            name = "newton_failed"
        case (run_solver_failed)
            name = "solver_failed"
        case default
            name = "unknown"
        end select
    end function status_name

end module supratrans_result
