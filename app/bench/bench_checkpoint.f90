!> The checkpoint-overhead benchmark (`fpm run --example benchmark --profile release -- REPEATS checkpoint`): one
!> long timeseries run (newton, N = 2000, T = 1500, dt = 0.05: 30,000 steps, three probes recorded every step),
!> timed with checkpoints off (`checkpoint_every` = 0), at the default interval (300 s: no checkpoint is written in
!> so short a run, only the stop flag and the clock are looked at) and at a short interval that writes several.
!> The three settings run in turn, `repeats` times; medians. Printed: the ratios to the run without checkpoints,
!> the cost of one checkpoint (the short interval's extra time over the checkpoints it wrote) and the overhead at
!> the default interval: the polling ratio plus one checkpoint's cost per 300 s of run.
module bench_checkpoint
    use supratrans_kinds, only: wp, i8
    use supratrans_config, only: run_config, method_newton
    use supratrans_simulate, only: simulate
    use supratrans_result, only: run_result
    use supratrans_checkpoint, only: checkpoint_session, open_session, close_session
    use supratrans_scene_workprec, only: median
    use supratrans_system, only: remove_file
    implicit none
    private

    public :: checkpoint_benchmark

contains

    !> Time the long run with checkpoints off, at 300 s and at a short interval; print the overhead (see above).
    subroutine checkpoint_benchmark(repeats)
        !> Runs of each setting.
        integer, intent(in) :: repeats
        real(wp), parameter :: default_every = 300.0_wp, short_every = 0.25_wp
        character(len=*), parameter :: path = "/tmp/supratrans_bench.checkpoint"
        type(run_config) :: run
        real(wp) :: off(repeats), at_default(repeats), at_short(repeats), written(repeats), per_checkpoint, polling
        integer :: r

        run%chain%n = 2000
        run%chain%n0 = 1500
        run%drive%amplitude = 1.9_wp
        run%drive%omega = 0.9_wp
        run%numerics%method = method_newton
        run%numerics%dt = 0.05_wp
        run%numerics%t_final = 1500.0_wp
        run%record%probes = [1, 1000, 1500]
        run%record%probe_every = 1
        run%record%ledger_every = 20
        do r = 1, repeats
            off(r) = timed(0.0_wp)
            at_default(r) = timed(default_every)
            at_short(r) = timed(short_every, written(r))
        end do
        per_checkpoint = max(median(at_short) - median(off), 0.0_wp)/max(median(written), 1.0_wp)
        polling = median(at_default)/median(off) - 1.0_wp
        write (*, "(a)") "# checkpoint overhead: newton timeseries N = 2000, T = 1500 (30,000 steps, 3 probes every " &
            // "step), medians of the runs, one thread"
        write (*, "(a10, 2x, a10, 2x, a12, 2x, a12)") "every_s", "median_s", "checkpoints", "ratio_to_off"
        write (*, "(f10.2, 2x, f10.3, 2x, i12, 2x, f12.4)") 0.0_wp, median(off), 0, 1.0_wp
        write (*, "(f10.2, 2x, f10.3, 2x, i12, 2x, f12.4)") default_every, median(at_default), 0, &
            median(at_default)/median(off)
        write (*, "(f10.2, 2x, f10.3, 2x, i12, 2x, f12.4)") short_every, median(at_short), nint(median(written)), &
            median(at_short)/median(off)
        write (*, "(a, f9.5, a, f8.4, a)") "# one checkpoint: ", per_checkpoint, " s; at the default 300 s: polling ", &
            100.0_wp*polling, " %"
        write (*, "(a, f8.4, a)") "# overhead at the default interval (polling + one checkpoint per 300 s): ", &
            100.0_wp*(polling + per_checkpoint/default_every), " %"

    contains

        !> Wall time of the run with checkpoints every `every` seconds (0: off); `count`: checkpoints written.
        function timed(every, count) result(seconds)
            real(wp), intent(in) :: every
            real(wp), intent(out), optional :: count
            real(wp) :: seconds
            type(checkpoint_session) :: session
            type(run_result) :: result
            integer(i8) :: c0, c1, rate

            call remove_file(path)
            call system_clock(c0, rate)
            call open_session(session, path, "benchmark", every)
            session%log_runs = .false.
            call simulate(run, result, interruptible=.true., session=session)
            call close_session(session)
            call system_clock(c1)
            seconds = real(c1 - c0, wp)/real(rate, wp)
            if (present(count)) count = real(session%written, wp)
        end function timed

    end subroutine checkpoint_benchmark

end module bench_checkpoint
