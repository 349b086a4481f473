!> The checkpoint-overhead benchmark (`fpm run --example benchmark --profile release -- REPEATS checkpoint`): one
!> long timeseries run (newton, N = 2000, T = 500, dt = 0.05: 10,000 steps, three probes recorded every step),
!> timed with checkpoints off (`checkpoint_every` = 0), at the default interval (300 s: no checkpoint is written in
!> so short a run, only the stop flag and the clock are looked at) and at a short interval that writes several.
!> The three settings run in turn, `repeats` times. Printed for each: the median wall time and the least CPU time
!> (the figure a loaded machine disturbs least) and its ratio to the run without checkpoints; the cost of one
!> checkpoint (the short interval's extra time over the checkpoints it wrote, wall and CPU) and the overhead at the
!> default interval: the polling ratio (CPU) plus one checkpoint's wall cost per 300 s of run.
module bench_checkpoint
    use supratrans_kinds, only: wp, i8
    use supratrans_strings, only: int_str
    use supratrans_config, only: run_config, method_newton
    use supratrans_simulate, only: simulate
    use supratrans_result, only: run_result
    use supratrans_checkpoint, only: checkpoint_session, open_session, close_session
    use supratrans_workprec_measure, only: median
    use supratrans_system, only: remove_file
    implicit none
    private

    public :: checkpoint_benchmark

contains

    !> Time the long run with checkpoints off, at 300 s and at a short interval; print the overhead (see above).
    subroutine checkpoint_benchmark(repeats)
        !> Runs of each setting.
        integer, intent(in) :: repeats
        real(wp), parameter :: default_every = 300.0_wp, short_every = 0.1_wp
        character(len=*), parameter :: path = "/tmp/supratrans_bench.checkpoint"
        type(run_config) :: run
        real(wp) :: off(repeats), at_default(repeats), at_short(repeats), written(repeats), per_checkpoint, polling
        real(wp) :: cpu_off(repeats), cpu_default(repeats), cpu_short(repeats), per_checkpoint_cpu
        integer :: r

        run%chain%n = 2000
        run%chain%n0 = 1500
        run%drive%amplitude = 1.9_wp
        run%drive%omega = 0.9_wp
        run%numerics%method = method_newton
        run%numerics%dt = 0.05_wp
        run%numerics%t_final = 500.0_wp
        run%record%probes = [1, 1000, 1500]
        run%record%probe_every = 1
        run%record%ledger_every = 20
        do r = 1, repeats
            off(r) = timed(0.0_wp, cpu_off(r))
            at_default(r) = timed(default_every, cpu_default(r))
            at_short(r) = timed(short_every, cpu_short(r), written(r))
        end do
        per_checkpoint = max(median(at_short) - median(off), 0.0_wp)/max(median(written), 1.0_wp)
        per_checkpoint_cpu = max(minval(cpu_short) - minval(cpu_off), 0.0_wp)/max(median(written), 1.0_wp)
        polling = minval(cpu_default)/minval(cpu_off) - 1.0_wp
        write (*, "(a)") "# checkpoint overhead: newton timeseries N = 2000, T = 500 (10,000 steps, 3 probes every " &
            // "step), one thread, " // int_str(repeats) // " runs of each setting in turn"
        write (*, "(a10, 2x, a14, 2x, a12, 2x, a12, 2x, a16)") "every_s", "median_wall_s", "least_cpu_s", &
            "checkpoints", "cpu_ratio_to_off"
        write (*, "(f10.2, 2x, f14.3, 2x, f12.3, 2x, i12, 2x, f16.4)") 0.0_wp, median(off), minval(cpu_off), 0, 1.0_wp
        write (*, "(f10.2, 2x, f14.3, 2x, f12.3, 2x, i12, 2x, f16.4)") default_every, median(at_default), &
            minval(cpu_default), 0, minval(cpu_default)/minval(cpu_off)
        write (*, "(f10.2, 2x, f14.3, 2x, f12.3, 2x, i12, 2x, f16.4)") short_every, median(at_short), &
            minval(cpu_short), nint(median(written)), minval(cpu_short)/minval(cpu_off)
        write (*, "(a, f9.5, a, f9.5, a, f8.4, a)") "# one checkpoint: ", per_checkpoint, " s wall, ", &
            per_checkpoint_cpu, " s CPU; polling at the default 300 s: ", 100.0_wp*polling, " % (CPU)"
        write (*, "(a, f8.4, a)") "# overhead at the default interval (polling + one checkpoint per 300 s): ", &
            100.0_wp*(polling + per_checkpoint/default_every), " %"

    contains

        !> Wall time of the run with checkpoints every `every` seconds (0: off); `cpu`: its CPU time; `count`:
        !> checkpoints written.
        function timed(every, cpu, count) result(seconds)
            real(wp), intent(in) :: every
            real(wp), intent(out) :: cpu
            real(wp), intent(out), optional :: count
            real(wp) :: seconds
            type(checkpoint_session) :: session
            type(run_result) :: result
            integer(i8) :: c0, c1, rate
            real(wp) :: t0, t1

            call remove_file(path)
            call cpu_time(t0)
            call system_clock(c0, rate)
            call open_session(session, path, "benchmark", every)
            session%log_runs = .false.
            call simulate(run, result, interruptible=.true., session=session)
            call close_session(session)
            call system_clock(c1)
            call cpu_time(t1)
            cpu = t1 - t0
            seconds = real(c1 - c0, wp)/real(rate, wp)
            if (present(count)) count = real(session%written, wp)
        end function timed

    end subroutine checkpoint_benchmark


end module bench_checkpoint
