!> What one simulation produces: its outcome, solver statistics, energy totals and the recorded time series.
module supratrans_result
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp, i8
    use supratrans_ledger, only: ledger_type
    use supratrans_config, only: detect_params, record_params
    use supratrans_strings, only: int_fixed, real_fixed
    use supratrans_state_buffer, only: state_buffer, put_int, put_real, put_logical, put_text, put_reals, &
                                       put_reals2, put_ints, get_int, get_real, get_logical, get_text, get_reals, &
                                       get_reals2, get_ints
    use supratrans_status, only: run_ok => status_ok, run_diverged => status_diverged, &
                                 run_newton_failed => status_newton_failed, run_solver_failed => status_solver_failed, &
                                 run_invalid => status_invalid, status_name => run_status_name
    implicit none
    private

    !> The run statuses (`supratrans_status`, under the names the run engine uses) and their names.
    public :: run_ok, run_diverged, run_newton_failed, run_solver_failed, run_invalid, status_name
    public :: init_records, record_ledger, record_probes, observe_ramp, check_blowup, observe_detector, &
              observe_early_stop, close_verdict, save_result, load_result

    !> Result of one run.
    type, public :: run_result
        !> Outcome: `run_ok`, `run_diverged`, `run_newton_failed`, `run_solver_failed`, `run_invalid`.
        integer :: status = run_ok
        !> Why the run ended as it did (empty for a normal end).
        character(len=:), allocatable :: reason
        !> Time steps taken.
        integer(i8) :: steps = 0
        !> Time at which the run ended.
        real(wp) :: t_end = 0.0_wp
        !> Newton iterations over the run (0 for the methods without Newton: linearized, rk4, rk8).
        integer(i8) :: newton_iterations = 0
        !> Largest number of Newton iterations in one step (0 without Newton).
        integer :: newton_max_iterations = 0
        !> Tridiagonal systems solved over the run: one per Newton iteration (newton), one per step (linearized),
        !> none for the Runge-Kutta methods. A solve is LAPACK `dgtsv`, or N divisions when beta = 0.
        integer(i8) :: tridiagonal_solves = 0
        !> Right-hand-side evaluations of the method-of-lines system over the run: the stages of the Runge-Kutta
        !> methods (4 or 11 a step); none for the finite-difference schemes.
        integer(i8) :: rhs_evaluations = 0
        !> Energy ledger: running totals during the run, final at its end.
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
        !> The run was cut short by a stop signal (SIGTERM, SIGINT, SIGUSR1) before T: its records end at `t_end`
        !> and it is no result (only a run asked to be `interruptible` by `simulate` can be).
        logical :: interrupted = .false.
        !> The run could not allocate its state or records (`reason` says which): no result, and no verdict of
        !> the physics; the program stops with one line rather than record it.
        logical :: no_memory = .false.
        !> Why the verdict is what it is.
        character(len=:), allocatable :: verdict_reason
        !> Margin of the verdict, relative to the detect amplitude a: 1 - max|u|/a beyond the detector for a run that
        !> stayed below, max|u|/a - 1 for one that crossed and ran on to T; NaN when it stopped at the crossing
        !> (early stop: the margin is that of the search's run below) or failed.
        real(wp) :: verdict_margin = 0.0_wp
        !> The margin is below `&detect thin_margin`: the verdict could flip under a small change (flagged in the output).
        logical :: thin_verdict = .false.
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

    !> Append a run's record as it stands (outcome, ledger, verdict so far, the filled part of the series) to a
    !> checkpoint's buffer, every real with its exact bits.
    pure subroutine save_result(result, buf)
        !> The run's record.
        type(run_result), intent(in) :: result
        !> The state so far.
        type(state_buffer), intent(inout) :: buf

        call put_int(buf, int(result%status, i8))
        if (allocated(result%reason)) then
            call put_text(buf, result%reason)
        else
            call put_text(buf, "")
        end if
        call put_int(buf, result%steps)
        call put_real(buf, result%t_end)
        call put_int(buf, result%newton_iterations)
        call put_int(buf, int(result%newton_max_iterations, i8))
        call put_int(buf, result%tridiagonal_solves)
        call put_int(buf, result%rhs_evaluations)
        associate (l => result%ledger)
            call put_reals(buf, [l%e_start, l%injected, l%dissipated_gamma, l%dissipated_beta, l%dissipated_absorber, &
                                 l%stored, l%residual, l%max_step_residual, l%energy_scale])
            call put_int(buf, int(l%evaluations, i8))
        end associate
        call put_real(buf, result%injected_at_ramp)
        call put_logical(buf, result%ramp_passed)
        call put_real(buf, result%wall_time)
        call put_real(buf, result%max_abs_u)
        call put_logical(buf, result%transmitting)
        call put_real(buf, result%t_decided)
        call put_int(buf, int(result%detect_site, i8))
        call put_real(buf, result%u_beyond_max)
        call put_logical(buf, result%stopped_early)
        call put_logical(buf, result%interrupted)
        call put_logical(buf, result%no_memory)
        if (allocated(result%verdict_reason)) then
            call put_text(buf, result%verdict_reason)
        else
            call put_text(buf, "")
        end if
        call put_logical(buf, allocated(result%verdict_reason))
        call put_real(buf, result%verdict_margin)
        call put_logical(buf, result%thin_verdict)
        call put_logical(buf, allocated(result%probes))
        if (allocated(result%probes)) then
            call put_ints(buf, result%probes)
            call put_int(buf, size(result%probe_time, kind=i8))
            call put_int(buf, size(result%ledger_time, kind=i8))
            call put_int(buf, int(result%n_probe_samples, i8))
            call put_reals(buf, result%probe_time(1:result%n_probe_samples))
            call put_reals2(buf, result%probe_u(1:result%n_probe_samples, :))
            call put_int(buf, int(result%n_ledger_samples, i8))
            call put_reals(buf, result%ledger_time(1:result%n_ledger_samples))
            call put_reals2(buf, result%ledger_series(1:result%n_ledger_samples, :))
        end if
    end subroutine save_result

    !> Restore a run's record saved by `save_result`. With `fresh` the record's series are allocated here (a
    !> finished run read back whole); otherwise they must already have the sizes saved (`init_records` of the same
    !> run). `buf%ok` is false when the saved record does not fit.
    pure subroutine load_result(result, buf, fresh)
        !> The run's record.
        type(run_result), intent(inout) :: result
        !> The saved state.
        type(state_buffer), intent(inout) :: buf
        !> Allocate the series (a finished run's record).
        logical, intent(in) :: fresh
        real(wp) :: sums(9)
        integer(i8) :: v, nsample, nledger, nfilled
        logical :: has, has_probes
        character(len=:), allocatable :: text

        call get_int(buf, v)
        result%status = int(v)
        call get_text(buf, result%reason)
        call get_int(buf, result%steps)
        call get_real(buf, result%t_end)
        call get_int(buf, result%newton_iterations)
        call get_int(buf, v)
        result%newton_max_iterations = int(max(0_i8, min(v, int(huge(0), i8))))
        call get_int(buf, result%tridiagonal_solves)
        call get_int(buf, result%rhs_evaluations)
        call get_reals(buf, sums)
        associate (l => result%ledger)
            l%e_start = sums(1)
            l%injected = sums(2)
            l%dissipated_gamma = sums(3)
            l%dissipated_beta = sums(4)
            l%dissipated_absorber = sums(5)
            l%stored = sums(6)
            l%residual = sums(7)
            l%max_step_residual = sums(8)
            l%energy_scale = sums(9)
            call get_int(buf, v)
            l%evaluations = int(max(0_i8, min(v, int(huge(0), i8))))
        end associate
        call get_real(buf, result%injected_at_ramp)
        call get_logical(buf, result%ramp_passed)
        call get_real(buf, result%wall_time)
        call get_real(buf, result%max_abs_u)
        call get_logical(buf, result%transmitting)
        call get_real(buf, result%t_decided)
        call get_int(buf, v)
        result%detect_site = int(max(0_i8, min(v, int(huge(0), i8))))
        call get_real(buf, result%u_beyond_max)
        call get_logical(buf, result%stopped_early)
        call get_logical(buf, result%interrupted)
        call get_logical(buf, result%no_memory)
        call get_text(buf, text)
        call get_logical(buf, has)
        if (has) then
            result%verdict_reason = text
        else if (allocated(result%verdict_reason)) then
            deallocate (result%verdict_reason)
        end if
        call get_real(buf, result%verdict_margin)
        call get_logical(buf, result%thin_verdict)
        call get_logical(buf, has_probes)
        if (.not. buf%ok .or. .not. has_probes) return
        call get_int(buf, v)
        if (.not. buf%ok) return
        if (fresh) then
            if (allocated(result%probes)) deallocate (result%probes)
            allocate (result%probes(max(0_i8, min(v, 1000000_i8))))
        end if
        buf%pos = buf%pos - 8
        call get_ints(buf, result%probes)
        call get_int(buf, nsample)
        call get_int(buf, nledger)
        if (fresh .and. buf%ok) then
            if (nsample < 0 .or. nledger < 0 .or. nsample > buf%used .or. nledger > buf%used) buf%ok = .false.
            if (.not. buf%ok) return
            if (allocated(result%probe_time)) deallocate (result%probe_time, result%probe_u)
            if (allocated(result%ledger_time)) deallocate (result%ledger_time, result%ledger_series)
            allocate (result%probe_time(nsample), result%probe_u(nsample, size(result%probes)))
            allocate (result%ledger_time(nledger), result%ledger_series(nledger, size(ledger_columns)))
            result%probe_time = 0.0_wp
            result%probe_u = 0.0_wp
            result%ledger_time = 0.0_wp
            result%ledger_series = 0.0_wp
        end if
        if (.not. allocated(result%probe_time) .or. .not. allocated(result%ledger_time)) buf%ok = .false.
        if (.not. buf%ok) return
        if (nsample /= size(result%probe_time, kind=i8) .or. nledger /= size(result%ledger_time, kind=i8)) buf%ok = .false.
        call get_int(buf, nfilled)
        if (nfilled < 0 .or. nfilled > nsample) buf%ok = .false.
        if (.not. buf%ok) return
        result%n_probe_samples = int(nfilled)
        call get_reals(buf, result%probe_time(1:nfilled))
        call get_reals2(buf, result%probe_u(1:nfilled, :))
        call get_int(buf, nfilled)
        if (nfilled < 0 .or. nfilled > nledger) buf%ok = .false.
        if (.not. buf%ok) return
        result%n_ledger_samples = int(nfilled)
        call get_reals(buf, result%ledger_time(1:nfilled))
        call get_reals2(buf, result%ledger_series(1:nfilled, :))
    end subroutine load_result


    !> Append the current state of the run's ledger (`result%ledger`) to the records (ignored when they are full).
    pure subroutine record_ledger(result, t)
        !> Result whose ledger records grow by one.
        type(run_result), intent(inout) :: result
        !> Time of the record.
        real(wp), intent(in) :: t
        integer :: i

        if (result%n_ledger_samples >= size(result%ledger_time)) return
        result%n_ledger_samples = result%n_ledger_samples + 1
        i = result%n_ledger_samples
        result%ledger_time(i) = t
        associate (ledger => result%ledger)
            result%ledger_series(i, :) = [ledger%stored, ledger%injected, ledger%dissipated_gamma, &
                                          ledger%dissipated_beta, ledger%dissipated_absorber, ledger%residual]
        end associate
    end subroutine record_ledger

    !> Allocate the records of a run of `m` time steps (levels t_0 .. t_M): probe samples every
    !> `record%probe_every` levels (and at t = 0), ledger records every `record%ledger_every` steps (and at the
    !> start and the end). When the records cannot be held (a sampling interval below 1, or more than huge(0)
    !> samples) they are allocated empty and the run is marked `run_invalid` with a reason; so too when memory runs
    !> out (`no_memory`).
    pure subroutine init_records(result, record, m)
        !> The run's result.
        type(run_result), intent(inout) :: result
        !> What to record.
        type(record_params), intent(in) :: record
        !> Number of time steps M of the run.
        integer(i8), intent(in) :: m
        integer(i8) :: nsample, nledger
        integer :: st

        if (allocated(record%probes)) then
            result%probes = record%probes
        else
            allocate (result%probes(0))
        end if
        if (record%probe_every < 1 .or. record%ledger_every < 1) then
            result%status = run_invalid
            result%reason = "probe_every and ledger_every must be >= 1 (got " // trim(int_fixed(record%probe_every)) &
                            // " and " // trim(int_fixed(record%ledger_every)) // ")"
            nsample = 0
            nledger = 0
        else
            nsample = m/record%probe_every + 1
            nledger = m/record%ledger_every + 2
            if (nsample > huge(0) .or. nledger > huge(0)) then
                result%status = run_invalid
                result%reason = "too many records: " // trim(real_fixed(real(nsample, wp), 6)) // " probe samples, " &
                                // trim(real_fixed(real(nledger, wp), 6)) // " ledger records (at most " &
                                // trim(int_fixed(huge(0))) // " each)"
                nsample = 0
                nledger = 0
            end if
        end if
        allocate (result%probe_time(nsample), stat=st)
        if (st == 0) allocate (result%probe_u(nsample, size(result%probes)), stat=st)
        if (st == 0) allocate (result%ledger_time(nledger), stat=st)
        if (st == 0) allocate (result%ledger_series(nledger, size(ledger_columns)), stat=st)
        if (st /= 0) then
            result%status = run_invalid
            result%no_memory = .true.
            result%reason = "cannot allocate " // trim(real_fixed(8.0_wp*(real(nsample, wp)*real(size(result%probes) &
                            + 1, wp) + real(nledger, wp)*real(size(ledger_columns) + 1, wp))/1.0e9_wp, 3)) &
                            // " GB for the records (" // trim(real_fixed(real(nsample, wp), 6)) // " probe samples, " &
                            // trim(real_fixed(real(nledger, wp), 6)) // " ledger records)"
            if (allocated(result%probe_time)) deallocate (result%probe_time)
            if (allocated(result%probe_u)) deallocate (result%probe_u)
            if (allocated(result%ledger_time)) deallocate (result%ledger_time)
            if (allocated(result%ledger_series)) deallocate (result%ledger_series)
            allocate (result%probe_time(0), result%probe_u(0, size(result%probes)))
            allocate (result%ledger_time(0), result%ledger_series(0, size(ledger_columns)))
        end if
    end subroutine init_records

    !> Append a probe sample at time `t` (ignored when the records are full): `u(j)` is u_n at probe site j
    !> (the drive psi for n = 0, 0 for the fixed end n = N + 1).
    pure subroutine record_probes(result, t, u)
        !> Result whose probe records grow by one.
        type(run_result), intent(inout) :: result
        !> Time of the sample.
        real(wp), intent(in) :: t
        !> u_n at the probe sites, one per entry of `result%probes`.
        real(wp), intent(in) :: u(:)
        integer :: i

        if (result%n_probe_samples >= size(result%probe_time)) return
        result%n_probe_samples = result%n_probe_samples + 1
        i = result%n_probe_samples
        result%probe_time(i) = t
        result%probe_u(i, :) = u
    end subroutine record_probes

    !> Note the energy injected up to the end of the ramp: call after each step with the time `t` up to which the
    !> run's ledger (`result%ledger`) sums the injected energy; the first call with t >= ramp_time records it.
    pure subroutine observe_ramp(result, t, ramp_time)
        !> The run's result.
        type(run_result), intent(inout) :: result
        !> Time up to which the ledger's injected energy is summed.
        real(wp), intent(in) :: t
        !> End of the drive's ramp.
        real(wp), intent(in) :: ramp_time

        if (result%ramp_passed .or. t < ramp_time) return
        result%ramp_passed = .true.
        result%injected_at_ramp = result%ledger%injected
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
    !> The run transmits once `ufar` exceeds `detect%amplitude` (the verdict is then decided: see
    !> `observe_early_stop`).
    pure subroutine observe_detector(result, detect, nd, ufar, t)
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

        result%detect_site = nd
        result%u_beyond_max = max(result%u_beyond_max, ufar)
        if (result%transmitting .or. .not. (ufar > detect%amplitude)) return
        result%transmitting = .true.
        result%t_decided = t
        result%verdict_reason = "|u_n| beyond site " // trim(int_fixed(nd)) // " reached " &
            // trim(real_fixed(ufar, 6)) // " > " &
                                // trim(real_fixed(detect%amplitude, 6)) // " at t = " // trim(real_fixed(t, 6))
    end subroutine observe_detector

    !> Early stop: once the verdict is decided (the run transmits) and `detect%stop_when_decided`, `halt` asks
    !> the time loop to end the run there (`stopped_early`).
    pure subroutine observe_early_stop(result, detect, halt)
        !> The run's result.
        type(run_result), intent(inout) :: result
        !> Detector parameters.
        type(detect_params), intent(in) :: detect
        !> True when the run should stop now.
        logical, intent(out) :: halt

        halt = result%transmitting .and. detect%stop_when_decided
        if (halt) result%stopped_early = .true.
    end subroutine observe_early_stop

    !> After the time loop: the verdict of a run that never transmitted (decided at its end, or undecided if it
    !> failed), and empty reasons filled.
    pure subroutine close_verdict(result, detect)
        !> The run's result (t_end set).
        type(run_result), intent(inout) :: result
        !> Detector parameters.
        type(detect_params), intent(in) :: detect

        if (.not. allocated(result%reason)) result%reason = ""
        result%verdict_margin = ieee_value(1.0_wp, ieee_quiet_nan)
        result%thin_verdict = .false.
        if (result%status == run_ok .and. .not. result%stopped_early) then
            if (result%transmitting) then
                result%verdict_margin = result%u_beyond_max/detect%amplitude - 1.0_wp
            else
                result%verdict_margin = 1.0_wp - result%u_beyond_max/detect%amplitude
            end if
            result%thin_verdict = result%verdict_margin < detect%thin_margin
        end if
        if (result%transmitting) then
            if (result%thin_verdict) result%verdict_reason = result%verdict_reason // "; thin margin " &
                // trim(real_fixed(result%verdict_margin, 3))
            return
        end if
        result%t_decided = result%t_end
        if (result%status /= run_ok) then
            result%verdict_reason = "undecided: the run failed"
        else
            result%verdict_reason = "|u_n| beyond site " // trim(int_fixed(result%detect_site)) // " stayed below " &
                                    // trim(real_fixed(detect%amplitude, 6)) // " (max " &
                                        // trim(real_fixed(result%u_beyond_max, 6)) // ")"
            if (result%thin_verdict) result%verdict_reason = result%verdict_reason // "; thin margin " &
                // trim(real_fixed(result%verdict_margin, 3))
        end if
    end subroutine close_verdict

end module supratrans_result
