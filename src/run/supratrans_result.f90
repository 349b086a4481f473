!> What one simulation produces: its outcome, solver statistics, energy totals and the recorded time series.
module supratrans_result
    use supratrans_kinds, only: wp, i8
    use supratrans_ledger, only: ledger_type
    use supratrans_config, only: detect_params, record_params
    use supratrans_strings, only: int_fixed, real_fixed
    implicit none
    private

    public :: status_name, init_records, record_ledger, record_probes, observe_ramp, check_blowup, observe_detector, close_verdict

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
        !> Energy injected up to the end of the drive's ramp (the paper computes "the total energy" after the
        !> ramp): injected - injected_at_ramp is the energy injected after it. Valid when `ramp_passed`.
        real(wp) :: injected_at_ramp = 0.0_wp
        !> The run went past the end of the ramp.
        logical :: ramp_passed = .false.
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

    !> Append the current ledger state to the records (ignored when the records are full).
    pure subroutine record_ledger(result, ledger, t)
        !> Result whose ledger records grow by one.
        type(run_result), intent(inout) :: result
        !> Current ledger.
        type(ledger_type), intent(in) :: ledger
        !> Time of the record.
        real(wp), intent(in) :: t
        integer :: i

        if (result%n_ledger_samples >= size(result%ledger_time)) return
        result%n_ledger_samples = result%n_ledger_samples + 1
        i = result%n_ledger_samples
        result%ledger_time(i) = t
        result%ledger_series(i, :) = [ledger%stored, ledger%injected, ledger%dissipated_gamma, ledger%dissipated_beta, &
                                      ledger%dissipated_absorber, ledger%residual]
    end subroutine record_ledger

    !> Allocate the records of a run of `m` steps: probe samples every `record%probe_every` steps (and at t = 0),
    !> ledger records every `record%ledger_every` steps (and at the start and the end).
    pure subroutine init_records(result, record, m)
        !> The run's result.
        type(run_result), intent(inout) :: result
        !> What to record.
        type(record_params), intent(in) :: record
        !> Number of steps of the run.
        integer, intent(in) :: m
        integer :: nsample, nledger

        if (allocated(record%probes)) then
            result%probes = record%probes
        else
            allocate (result%probes(0))
        end if
        nsample = m/record%probe_every + 1
        allocate (result%probe_time(nsample), result%probe_u(nsample, size(result%probes)))
        nledger = m/record%ledger_every + 2
        allocate (result%ledger_time(nledger), result%ledger_series(nledger, size(ledger_columns)))
    end subroutine init_records

    !> Append a probe sample at time `t` (ignored when the records are full): probe site n reads u(n) for
    !> 1 <= n <= N, the drive `psi` for n = 0, and 0 for the fixed end n = N + 1.
    pure subroutine record_probes(result, t, psi, u)
        !> Result whose probe records grow by one.
        type(run_result), intent(inout) :: result
        !> Time of the sample.
        real(wp), intent(in) :: t
        !> Drive u_0(t).
        real(wp), intent(in) :: psi
        !> Displacements u_1 .. u_N.
        real(wp), intent(in) :: u(:)
        integer :: i, j, site

        if (result%n_probe_samples >= size(result%probe_time)) return
        result%n_probe_samples = result%n_probe_samples + 1
        i = result%n_probe_samples
        result%probe_time(i) = t
        do j = 1, size(result%probes)
            site = result%probes(j)
            if (site >= 1 .and. site <= size(u)) then
                result%probe_u(i, j) = u(site)
            else if (site == 0) then
                result%probe_u(i, j) = psi
            else
                result%probe_u(i, j) = 0.0_wp
            end if
        end do
    end subroutine record_probes

    !> Note the energy injected up to the end of the ramp: call after each step with the time `t` up to which the
    !> ledger's injected energy is summed; the first call with t >= ramp_time records it.
    pure subroutine observe_ramp(result, injected, t, ramp_time)
        !> The run's result.
        type(run_result), intent(inout) :: result
        !> Energy injected so far.
        real(wp), intent(in) :: injected
        !> Time up to which `injected` is summed.
        real(wp), intent(in) :: t
        !> End of the drive's ramp.
        real(wp), intent(in) :: ramp_time

        if (result%ramp_passed .or. t < ramp_time) return
        result%ramp_passed = .true.
        result%injected_at_ramp = injected
    end subroutine observe_ramp

    !> Blow-up check of a step: `umax` = max |u_n| (NaN counts as blown up). Sets the status and reason.
    pure subroutine check_blowup(result, umax, threshold, t, diverged)
        !> The run's result.
        type(run_result), intent(inout) :: result
        !> Largest |u_n| of the new level (or NaN/Inf).
        real(wp), intent(in) :: umax
        !> Blow-up threshold.
        real(wp), intent(in) :: threshold
        !> Time of the new level.
        real(wp), intent(in) :: t
        !> True when the run has blown up and must stop.
        logical, intent(out) :: diverged

        result%max_abs_u = max(result%max_abs_u, umax)
        diverged = .not. (umax <= threshold)
        if (diverged) then
            result%status = run_diverged
            result%reason = "blow-up: max |u_n| = " // trim(real_fixed(umax, 6)) // " exceeds " &
                // trim(real_fixed(threshold, 6)) &
                            // " at t = " // trim(real_fixed(t, 6))
        end if
    end subroutine check_blowup

    !> Transmission detector of a step: `ufar` = max |u_n| beyond the detector site `nd` at time `t`.
    !> The run transmits once `ufar` exceeds `detect%amplitude`; `halt` asks the time loop to end the run there.
    pure subroutine observe_detector(result, detect, nd, ufar, t, halt)
        !> The run's result.
        type(run_result), intent(inout) :: result
        !> Detector parameters.
        type(detect_params), intent(in) :: detect
        !> Detector site n_d.
        integer, intent(in) :: nd
        !> max |u_n| over n > n_d.
        real(wp), intent(in) :: ufar
        !> Time of the level.
        real(wp), intent(in) :: t
        !> True when the verdict was just decided and the run should stop early.
        logical, intent(out) :: halt

        halt = .false.
        result%detect_site = nd
        result%u_beyond_max = max(result%u_beyond_max, ufar)
        if (result%transmitting .or. .not. (ufar > detect%amplitude)) return
        result%transmitting = .true.
        result%t_decided = t
        result%verdict_reason = "|u_n| beyond site " // trim(int_fixed(nd)) // " reached " &
            // trim(real_fixed(ufar, 6)) // " > " &
                                // trim(real_fixed(detect%amplitude, 6)) // " at t = " // trim(real_fixed(t, 6))
        if (detect%stop_when_decided) then
            result%stopped_early = .true.
            halt = .true.
        end if
    end subroutine observe_detector

    !> After the time loop: the verdict of a run that never transmitted (decided at its end, or undecided if it
    !> failed), and empty reasons filled.
    pure subroutine close_verdict(result, detect)
        !> The run's result (t_end set).
        type(run_result), intent(inout) :: result
        !> Detector parameters.
        type(detect_params), intent(in) :: detect

        if (.not. allocated(result%reason)) result%reason = ""
        if (result%transmitting) return
        result%t_decided = result%t_end
        if (result%status /= run_ok) then
            result%verdict_reason = "undecided: the run failed"
        else
            result%verdict_reason = "|u_n| beyond site " // trim(int_fixed(result%detect_site)) // " stayed below " &
                                    // trim(real_fixed(detect%amplitude, 6)) // " (max " &
                                        // trim(real_fixed(result%u_beyond_max, 6)) // ")"
        end if
    end subroutine close_verdict

end module supratrans_result
