!> The benchmark's work-precision row (issue 24, point 4): on the paper-default run (sine-Gordon, c = 4, N = 200,
!> Omega = 0.9, T = 200, ramp 50), the wall time each method needs to reach one relative error of the injected
!> energy, against the reference of the work-precision scene (rk8 at dt = 0.0125; as there, the leapfrog schemes,
!> whose ledger covers [dt/2, T - dt/2], are compared with the reference's energy over that window), and the ratios:
!> avf8 against rk8 at 1e-8 (A = 1.9; the goal is at most 2) and avf4 against the second-order schemes newton and
!> linearized at 1e-4 (A = 1.7, where they reach it; at A = 1.9 newton does not below dt = 0.003125). Each method
!> runs its steps from the largest down until its error is below the target; the time at the target is
!> interpolated log-log between the two steps that bracket it (a step at which every error is already below the
!> target gives an upper bound, marked "<="). Every time is the median over the runs of a step.
module bench_workprec
    use supratrans_kinds, only: wp
    use supratrans_config, only: run_config, method_newton, method_linearized, method_rk8, method_avf4, method_avf8
    use supratrans_simulate, only: simulate
    use supratrans_result, only: run_result, run_ok
    use supratrans_workprec_measure, only: median
    implicit none
    private

    public :: workprec_benchmark

    !> Step of the reference run (rk8), as the work-precision scene's.
    real(wp), parameter :: ref_dt = 0.0125_wp

    !> The reference: the injected energy at every step t_j = j ref_dt (j = 0 .. M).
    type :: reference
        real(wp), allocatable :: injected(:)
    end type reference

contains

    !> Print the work-precision rows and the ratios (avf8 / rk8 at 1e-8, avf4 / newton and avf4 / linearized at 1e-4).
    subroutine workprec_benchmark(repeats)
        !> Timed runs per step (at most 5 are used).
        integer, intent(in) :: repeats
        real(wp) :: ms_rk8, ms_avf8, ms_avf4, ms_newton, ms_linearized, ms_avf4_19, ms_rk8_4
        type(reference) :: ref
        integer :: nrep

        nrep = max(1, min(repeats, 5))
        write (*, "(a)") "# work-precision row: paper-default run (sine-Gordon, Omega = 0.9, N = 200, T = 200), " // &
            "wall time to reach a relative error of the injected energy (reference rk8 dt = 0.0125)"
        write (*, "(a10, 2x, a5, 2x, a8, 2x, a8, 2x, a10, 2x, a8, 2x, a10, 2x, a2, a10)") "method", "A", "target", &
            "dt_above", "err_above", "dt_below", "err_below", "", "ms"
        ref = reference_run(1.9_wp)
        ms_rk8 = cost_at("rk8", method_rk8, 1.9_wp, [0.3125_wp, 0.25_wp, 0.2_wp, 0.125_wp, 0.1_wp], 1.0e-8_wp, ref, nrep)
        ms_avf8 = cost_at("avf8", method_avf8, 1.9_wp, [0.4_wp, 0.3125_wp, 0.25_wp, 0.2_wp], 1.0e-8_wp, ref, nrep)
        ms_avf4_19 = cost_at("avf4", method_avf4, 1.9_wp, [0.2_wp, 0.125_wp, 0.1_wp, 0.0625_wp], 1.0e-4_wp, ref, nrep)
        ref = reference_run(1.7_wp)
        ms_avf4 = cost_at("avf4", method_avf4, 1.7_wp, [0.4_wp, 0.3125_wp, 0.25_wp, 0.2_wp], 1.0e-4_wp, ref, nrep)
        ms_rk8_4 = cost_at("rk8", method_rk8, 1.7_wp, [0.3125_wp, 0.25_wp, 0.2_wp], 1.0e-4_wp, ref, nrep)
        ms_linearized = cost_at("linearized", method_linearized, 1.7_wp, &
                                [0.025_wp, 0.0125_wp, 0.00625_wp, 0.003125_wp], 1.0e-4_wp, ref, nrep)
        ms_newton = cost_at("newton", method_newton, 1.7_wp, [0.025_wp, 0.0125_wp, 0.00625_wp, 0.003125_wp], &
                            1.0e-4_wp, ref, nrep)
        write (*, "(a, f8.2, a)") "avf8 / rk8 at 1e-8 (A = 1.9): ", ms_avf8/ms_rk8, "  (goal <= 2)"
        write (*, "(a, f8.2, a, f8.2, a, f8.2)") "avf4 at 1e-4 (A = 1.7): / newton ", ms_avf4/ms_newton, &
            ", / linearized ", ms_avf4/ms_linearized, ", / rk8 ", ms_avf4/ms_rk8_4
    end subroutine workprec_benchmark

    !> The paper-default run at amplitude A with a method and step (T = 200, no probes, a sparse ledger).
    function default_run(method, amplitude, dt) result(run)
        !> Method identifier.
        integer, intent(in) :: method
        !> Drive amplitude A.
        real(wp), intent(in) :: amplitude
        !> Time step.
        real(wp), intent(in) :: dt
        type(run_config) :: run

        run%drive%amplitude = amplitude
        run%drive%omega = 0.9_wp
        run%drive%ramp_time = 50.0_wp
        run%numerics%t_final = 200.0_wp
        run%numerics%method = method
        run%numerics%dt = dt
        allocate (run%record%probes(0))
        run%record%ledger_every = 4000
    end function default_run

    !> The reference run (rk8 at dt = 0.0125, as the work-precision scene's), its ledger at every step.
    function reference_run(amplitude) result(ref)
        !> Drive amplitude A.
        real(wp), intent(in) :: amplitude
        type(reference) :: ref
        type(run_config) :: run
        type(run_result) :: res

        run = default_run(method_rk8, amplitude, ref_dt)
        run%record%ledger_every = 1
        call simulate(run, res)
        if (res%status == run_ok) then
            ref%injected = res%ledger_series(1:res%n_ledger_samples, 2)
        else
            ref%injected = [huge(1.0_wp)]
        end if
    end function reference_run

    !> The reference's injected energy at time t, by the cubic through the four nearest steps.
    pure function injected_at(ref, t) result(e)
        !> The reference.
        type(reference), intent(in) :: ref
        !> Time, 0 <= t <= T.
        real(wp), intent(in) :: t
        real(wp) :: e, x, w
        integer :: j0, i, k, m

        m = size(ref%injected) - 1
        if (m < 3) then
            e = ref%injected(m + 1)
            return
        end if
        x = t/ref_dt
        j0 = max(0, min(floor(x) - 1, m - 3))
        e = 0.0_wp
        do i = 0, 3
            w = 1.0_wp
            do k = 0, 3
                if (k /= i) w = w*(x - real(j0 + k, wp))/real(i - k, wp)
            end do
            e = e + w*ref%injected(j0 + i + 1)
        end do
    end function injected_at

    !> Median ms of a method to reach `target` (relative error of the injected energy against `ref`), running `dts`
    !> in order (largest first) until the error is below the target; prints its row. Huge when not reached.
    function cost_at(name, method, amplitude, dts, target, ref, nrep) result(ms)
        !> Method label.
        character(len=*), intent(in) :: name
        !> Method identifier.
        integer, intent(in) :: method
        !> Drive amplitude A.
        real(wp), intent(in) :: amplitude
        !> Steps to try, largest first (each dividing T and the ramp).
        real(wp), intent(in) :: dts(:)
        !> Target relative error.
        real(wp), intent(in) :: target
        !> The reference.
        type(reference), intent(in) :: ref
        !> Timed runs per step.
        integer, intent(in) :: nrep
        real(wp) :: ms
        type(run_result) :: res
        real(wp) :: times(nrep), err, err_above, ms_above, dt_above, t, e_ref, e_final
        integer :: k, i
        logical :: ok

        ms = huge(1.0_wp)
        err_above = -1.0_wp
        ms_above = 0.0_wp
        dt_above = 0.0_wp
        do k = 1, size(dts)
            ok = .true.
            do i = 1, nrep
                call simulate(default_run(method, amplitude, dts(k)), res)
                times(i) = res%wall_time
                ok = ok .and. res%status == run_ok
            end do
            ! the reference over the window the method's ledger covers ([dt/2, T - dt/2] for the leapfrog schemes)
            e_final = ref%injected(size(ref%injected))
            e_ref = e_final
            if (method == method_newton .or. method == method_linearized) then
                e_ref = injected_at(ref, res%t_end - 0.5_wp*dts(k)) - injected_at(ref, 0.5_wp*dts(k))
            end if
            err = abs(res%ledger%injected - e_ref)/abs(e_final)
            if (.not. ok .or. .not. (err < huge(err))) cycle
            if (err > target) then
                err_above = err
                ms_above = 1000.0_wp*median(times)
                dt_above = dts(k)
                cycle
            end if
            if (err_above < 0.0_wp) then
                ms = 1000.0_wp*median(times)
                write (*, "(a10, 2x, f5.2, 2x, es8.1, 2x, a8, 2x, a10, 2x, f8.5, 2x, es10.3, 2x, a2, f10.2)") name, &
                    amplitude, target, "-", "-", dts(k), err, "<=", ms
            else
                t = (log(target) - log(err_above))/(log(err) - log(err_above))
                ms = exp(log(ms_above) + t*(log(1000.0_wp*median(times)) - log(ms_above)))
                write (*, "(a10, 2x, f5.2, 2x, es8.1, 2x, f8.5, 2x, es10.3, 2x, f8.5, 2x, es10.3, 2x, a2, f10.2)") &
                    name, amplitude, target, dt_above, err_above, dts(k), err, "", ms
            end if
            return
        end do
        write (*, "(a10, 2x, f5.2, 2x, es8.1, 2x, a)") name, amplitude, target, "not reached at the steps tried"
    end function cost_at

end module bench_workprec
