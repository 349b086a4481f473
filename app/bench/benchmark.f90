!> Benchmarks, in the release profile:  fpm run --example benchmark --profile release [-- repeats [paper | runs]]
!>
!> 1. The paper-default run (sine-Gordon, Omega = 0.9, A = 1.9, N = 200, T = 200, dt = 0.05) for each scheme:
!>    median wall time of a run over `repeats` runs (ms), its floor (ms), the ratio of the two, work per step
!>    (Newton iterations for newton, tridiagonal solves for linearized, right-hand sides for the Runge-Kutta
!>    methods), ledger residual relative to the energy scale. The floor of a scheme is the time of the kernels
!>    no implementation of it can avoid, timed here over the run's number of steps on arrays of N: per step N
!>    sines and N cosines (newton: the discrete gradient and its slope) or N sines (linearized: V'(u^k)), then N
!>    divisions (beta = 0, diagonal matrix) or one LAPACK dgtsv (beta > 0); per right-hand side N sines
!>    (Runge-Kutta). The sines and cosines are timed as the code's fastest kernels evaluate them: sines alone by
!>    libmvec's vector sin, sines with cosines by `sin_cos_array` (branch-free, vectorised, about 1.6 times
!>    faster than libmvec's sin and cos here).
!> 2. The paper-default Newton run against the naive kernel (app/naive: Newton to 1e-13 from the previous
!>    level, one dgtsv, sin and cos per site per iteration), timed in this process: ratio of medians.
!> 3. A 40-amplitude sweep (A = 1.20 .. 1.98 at Omega = 0.9) on 1 and on 2 threads: seconds and speed-up.
!> 4. The undamped sine-Gordon bifurcation diagram, Omega = 0.05 .. 1.00 step 0.05, resolution 0.01
!>    (input/bif_undamped_sg.nml): runs, time steps, seconds; with the argument `paper`, also at the paper's
!>    resolution Omega = 0.05 .. 0.99 step 0.01. With the argument `runs`, only 1 and 2.
!> 5. With the argument `slices` (only this): the slice cost of Bif1 (input/bif1.nml, 380 searches; or the
!>    bifurcation namelist given as the third argument) dealt
!>    largest-first by estimated cost into 16 and into 64 slices, each slice run alone on one thread: the measured
!>    wall (and CPU) time of the slowest slice over the mean, the bound the largest task sets (its time over the
!>    mean slice), and, from the same searches' measured times, what interleaved slices and a largest-first
!>    assignment by the measured times would give (modelled). Then the same slices dealt by measured costs
!>    (`--costs`: the searches' processor times of the first pass, merged into one earlier output), run and timed.
!>    Each row also splits the measured ratio: `dealt`, the deal's ratio by the costs it was dealt by; `searches`,
!>    by this pass's own search times (what the slices' processor times would give without their time outside the
!>    searches, `outside_ms`); `repeat_sd`, how far the searches' times of this pass stray from the earlier file's
!>    (sd of the log of their ratio). With `repeats` > 1 each slice runs that many times, in turn forwards and
!>    backwards, and its fastest run counts (a load that changes during the pass then weighs less).
!> 6. With the argument `checkpoint` (only this): the cost of mid-run checkpoints (`bench_checkpoint`): one long
!>    timeseries with checkpoints off, at the default interval and at a short one; the overhead at the default.
!> 7. With the argument `fold` (only this; a third argument `paper` for the paper's grid of Omega): the cost of the
!>    continuation scene (`bench_fold`): one fold for several chains and controls, the fold line against the scan.
!>    With `fold omega [FROM TO]`: the fold continued in Omega against the fold from rest at each frequency
!>    (`bench_fold_omega`; default 0.99 .. 0.05), one thread. With `fold hb [paper]`: harmonic balance
!>    (`bench_fold_hb`): one fold at Omega = 0.9, its cost against K and N, with `paper` the fold line against the scan.
!> Scene outputs go to the system's temporary directory and are deleted. With beta = 0 (the paper default) the
!> Jacobian is diagonal; a second block repeats the runs with beta = 0.1, where every Newton iteration is one
!> LAPACK dgtsv.
program benchmark
    use supratrans_kinds, only: wp, i8
    use supratrans_strings, only: int_str
    use supratrans_config, only: run_config, method_newton, method_linearized, method_rk4, method_rk8
    use supratrans_simulate, only: simulate
    use supratrans_result, only: run_result
    use supratrans_config, only: input_config
    use supratrans_error, only: error_type
    use supratrans_input, only: read_input
    use supratrans_scene_sweep, only: run_amplitude_sweep
    use supratrans_scene_bifurcation, only: run_bifurcation
    use supratrans_hdf5, only: h5_file, h5_open, h5_read, h5_close, h5_read_attr
    use supratrans_tasks, only: slice_owners
    use supratrans_cli, only: run_command
    use supratrans_invocation, only: invocation_type
    use bench_checkpoint, only: checkpoint_benchmark
    use bench_fold, only: fold_benchmark
    use bench_fold_omega, only: fold_omega_benchmark
    use bench_fold_hb, only: fold_hb_benchmark
    use supratrans_search_record, only: from_values, search_record
    use supratrans_system, only: remove_file
    use supratrans_workprec_measure, only: median
    use supratrans_tridiag, only: solve_tridiag
    use supratrans_stepper_newton, only: newton_stepper
    use supratrans_sine_kernels, only: sin_cos_array
    use bench_workprec, only: workprec_benchmark
    use bench_scaling, only: scaling_benchmark, scaling_alone
    use bench_floor_cpu, only: floor_cpu_benchmark
    !$ use omp_lib, only: omp_set_num_threads
    implicit none
    type(run_config) :: run
    type(run_result) :: result
    integer :: repeats, i, im
    logical :: paper, runs_only, folds, slices
    character(len=256) :: arg
    character(len=*), parameter :: names(2) = [character(len=10) :: "newton", "linearized"]
    integer, parameter :: methods(2) = [method_newton, method_linearized]
    real(wp), allocatable :: times(:), floor_times(:)
    real(wp) :: floor_ms, newton_ms, omega_range(2)

    repeats = 21
    if (command_argument_count() >= 1) then
        call get_command_argument(1, arg)
        read (arg, *) repeats
    end if
    paper = .false.
    runs_only = .false.
    folds = .false.
    slices = .false.
    if (command_argument_count() >= 2) then
        call get_command_argument(2, arg)
        paper = trim(arg) == "paper"
        runs_only = trim(arg) == "runs"
        folds = trim(arg) == "fold"
        slices = trim(arg) == "slices"
    end if
    if (folds) then
        arg = ""
        if (command_argument_count() >= 3) call get_command_argument(3, arg)
        if (trim(arg) == "omega") then
            omega_range = [0.99_wp, 0.05_wp]
            do i = 1, 2
                if (command_argument_count() < 3 + i) exit
                call get_command_argument(3 + i, arg)
                read (arg, *) omega_range(i)
            end do
            !$ call omp_set_num_threads(1)
            call fold_omega_benchmark(omega_range(1), omega_range(2))
            stop
        end if
        if (trim(arg) == "hb") then
            arg = ""
            if (command_argument_count() >= 4) call get_command_argument(4, arg)
            call fold_hb_benchmark(repeats, trim(arg) == "paper")
            stop
        end if
        call fold_benchmark(trim(arg) == "paper")
        stop
    end if
    if (command_argument_count() >= 2) then
        call get_command_argument(2, arg)
        if (trim(arg) == "checkpoint") then
            !$ call omp_set_num_threads(1)
            call checkpoint_benchmark(repeats)
            stop
        end if
    end if
    if (slices) then
        arg = "input/bif1.nml"
        if (command_argument_count() >= 3) call get_command_argument(3, arg)
        call slice_benchmark(trim(arg), [16, 64], repeats)
        stop
    end if
    call scaling_alone(repeats)
    allocate (times(repeats), floor_times(repeats))
    run%drive%amplitude = 1.9_wp
    run%drive%omega = 0.9_wp
    allocate (run%record%probes(0))
    run%record%ledger_every = 4000

    write (*, "(a)") "# paper-default run: sine-Gordon, Omega = 0.9, A = 1.9, N = 200, T = 200, dt = 0.05"
    write (*, "(a10, 2x, a10, 2x, a10, 2x, a10, 2x, a8, 2x, a10, 2x, a14, 2x, a12)") "scheme", "median_ms", &
        "min_ms", "floor_ms", "/floor", "work/step", "injected", "rel_residual"
    do im = 1, 2*size(methods)
        if (im == size(methods) + 1) then
            run%chain%beta = 0.1_wp
            write (*, "(a)") "# same with internal damping beta = 0.1 (tridiagonal Jacobian: one dgtsv per iteration)"
        end if
        run%numerics%method = methods(1 + mod(im - 1, size(methods)))
        do i = 1, repeats
            call simulate(run, result)
            times(i) = result%wall_time
            floor_times(i) = floor_seconds(run%chain%n, result%steps, 1, merge(2, 1, im == 1 .or. im == 3), &
                                           run%chain%beta > 0.0_wp)
        end do
        if (im == 1) newton_ms = 1000.0_wp*median(times)
        floor_ms = 1000.0_wp*median(floor_times)
        call table_row(names(1 + mod(im - 1, size(methods))), times, floor_ms, result)
    end do

    ! the Runge-Kutta references, at the step where each reaches its accuracy class on this run (docs/method.md)
    write (*, "(a)") "# Runge-Kutta references, beta = 0 (work/step = right-hand sides per step)"
    run%chain%beta = 0.0_wp
    do im = 1, 2
        run%numerics%method = merge(method_rk4, method_rk8, im == 1)
        run%numerics%dt = merge(0.1_wp, 0.2_wp, im == 1)
        do i = 1, repeats
            call simulate(run, result)
            times(i) = result%wall_time
            floor_times(i) = floor_seconds(run%chain%n, result%steps, merge(4, 11, im == 1), 1, .false., &
                                           divisions=.false.)
        end do
        floor_ms = 1000.0_wp*median(floor_times)
        call table_row(merge("rk4 dt=0.1", "rk8 dt=0.2", im == 1), times, floor_ms, result)
    end do

    ! the Newton step alone: the stepper driven without the run engine's observers (ledger, probes, blow-up)
    write (*, "(a)") "# newton steps alone (no observers: ledger, probes, blow-up check), paper default, beta = 0"
    run%numerics%method = method_newton
    run%numerics%dt = 0.05_wp
    do i = 1, repeats
        times(i) = steps_seconds(run, floor_times(i))
    end do
    write (*, "(a, f10.3, a, f10.3, a, f8.2)") "newton steps ", 1000.0_wp*median(times), " ms, floor ", &
        1000.0_wp*median(floor_times), " ms, ratio ", median(times)/median(floor_times)

    ! the same run as the naive program (app/naive), timed in this process
    do i = 1, repeats
        times(i) = naive_seconds()
    end do
    write (*, "(a)") "# paper-default newton run against the naive kernel (app/naive), in this process"
    write (*, "(a, f10.3, a, f10.3, a, f8.4)") "newton ", newton_ms, " ms, naive ", 1000.0_wp*median(times), &
        " ms, ratio ", newton_ms/(1000.0_wp*median(times))
    call floor_cpu_benchmark(repeats)
    call scaling_benchmark(repeats)

    call workprec_benchmark(repeats)
    if (runs_only) stop
    call sweep_benchmark()
    call bifurcation_benchmark("input/bif_undamped_sg.nml", 0.05_wp, 1.00_wp)
    if (paper) call bifurcation_benchmark("input/bif_undamped_sg.nml", 0.01_wp, 0.99_wp)

contains

    !> One row of the scheme table: median and minimum ms, floor ms and the ratio, work per step, ledger.
    subroutine table_row(name, times, floor_ms, res)
        !> Scheme label.
        character(len=*), intent(in) :: name
        !> Wall times of the runs (s).
        real(wp), intent(in) :: times(:)
        !> The scheme's floor (ms).
        real(wp), intent(in) :: floor_ms
        !> The last run's result.
        type(run_result), intent(in) :: res

        write (*, "(a10, 2x, f10.3, 2x, f10.3, 2x, f10.3, 2x, f8.2, 2x, f10.4, 2x, es14.6, 2x, es12.3)") name, &
            1000.0_wp*median(times), 1000.0_wp*minval(times), floor_ms, 1000.0_wp*median(times)/floor_ms, &
            work_per_step(res), res%ledger%injected, abs(res%ledger%residual)/max(res%ledger%energy_scale, tiny(1.0_wp))
    end subroutine table_row

    !> Seconds taken by the unavoidable kernels of a run of `steps` steps on N sites: per step, `evaluations`
    !> times N sines (and N cosines when `functions` = 2), then N divisions or, when `tridiagonal`, one dgtsv
    !> (neither when `divisions` is false). The arguments of the sines move every step, as a run's do.
    function floor_seconds(n, steps, evaluations, functions, tridiagonal, divisions) result(seconds)
        !> Number of sites N.
        integer, intent(in) :: n
        !> Steps of the run.
        integer(i8), intent(in) :: steps
        !> Evaluations of the N sines per step (right-hand sides of a Runge-Kutta step; 1 for the schemes).
        integer, intent(in) :: evaluations
        !> 1: sines only; 2: sines and cosines.
        integer, intent(in) :: functions
        !> One dgtsv per step instead of N divisions.
        logical, intent(in) :: tridiagonal
        !> Whether a division or solve is part of the floor (default true).
        logical, intent(in), optional :: divisions
        real(wp) :: seconds
        real(wp), allocatable :: x(:), s(:), c(:), r(:), d(:), dl(:), dd(:), du(:)
        real(wp) :: checksum
        integer(i8) :: k
        integer :: e, j, info
        logical :: solve

        solve = .true.
        if (present(divisions)) solve = divisions
        allocate (x(n), s(n), c(n), r(n), d(n), dl(max(n - 1, 1)), dd(n), du(max(n - 1, 1)))
        do j = 1, n
            x(j) = 1.9_wp*sin(0.37_wp*j)
            d(j) = 400.0_wp + 0.01_wp*j
        end do
        c = 0.0_wp
        checksum = 0.0_wp
        seconds = wall_seconds()
        do k = 1, steps
            do e = 1, evaluations
                if (functions == 2) then
                    call sin_cos_array(x, s, c)
                else
                    do j = 1, n
                        s(j) = sin(x(j))
                    end do
                end if
                checksum = checksum + s(n)
            end do
            if (solve) then
                if (tridiagonal) then
                    r = s + c
                    dd = d
                    dl = -1.0_wp
                    du = -1.0_wp
                    call solve_tridiag(dl, dd, du, r, info)
                else
                    do j = 1, n
                        r(j) = (s(j) + c(j))/d(j)
                    end do
                end if
                checksum = checksum + r(1)
            end if
            x(1) = x(1) + 1.0e-9_wp
            x(n) = x(n) - 1.0e-9_wp
        end do
        seconds = wall_seconds() - seconds
        if (.not. (abs(checksum) < huge(1.0_wp))) write (*, "(a)") "floor: non-finite checksum"
    end function floor_seconds

    !> Seconds taken by the steps of a run's stepper alone (init excluded), and the floor of as many steps.
    function steps_seconds(run, floor) result(seconds)
        !> The run.
        type(run_config), intent(in) :: run
        !> Its floor (s).
        real(wp), intent(out) :: floor
        real(wp) :: seconds
        type(newton_stepper) :: newton
        integer(i8) :: k, m
        integer :: status

        call newton%init(run)
        m = newton%steps_to(nint(run%numerics%t_final/run%numerics%dt, i8))
        seconds = wall_seconds()
        do k = 1, m
            call newton%step(status)
            if (status /= 0) exit
        end do
        seconds = wall_seconds() - seconds
        if (status /= 0) write (*, "(a)") "steps: " // newton%reason
        floor = floor_seconds(run%chain%n, m, 1, 2, run%chain%beta > 0.0_wp)
    end function steps_seconds

    !> Seconds of the naive program's computation (app/naive/naive.f90, without its output line): the
    !> paper-default run, Newton to 1e-13 from the previous level, one dgtsv and sin, cos per site per iteration.
    function naive_seconds() result(seconds)
        real(wp) :: seconds
        integer, parameter :: n = 200, n0 = 150
        real(wp), parameter :: c = 4.0_wp, kappa = 0.5_wp, sigma = 3.0_wp, omega = 0.9_wp, amp = 1.9_wp
        real(wp), parameter :: ramp = 50.0_wp, dt = 0.05_wp, t_final = 200.0_wp, tol = 1.0e-13_wp
        real(wp) :: u_old(0:n + 1), u(0:n + 1), x(0:n + 1), alpha(n), r(n), dl(n - 1), dd(n), du(n - 1)
        real(wp) :: s, h, g, dg, t
        integer :: k, j, it, info

        seconds = wall_seconds()
        alpha = 0.0_wp
        do j = n0 + 1, n
            alpha(j) = kappa*(1.0_wp + tanh(real(2*j - n0 - n, wp)/(2.0_wp*sigma)))
        end do
        u_old = 0.0_wp
        u = 0.0_wp
        u(0) = amp*min(dt/ramp, 1.0_wp)*sin(omega*dt)
        do k = 1, nint(t_final/dt) - 1
            t = real(k + 1, wp)*dt
            x = u
            x(0) = amp*min(t/ramp, 1.0_wp)*sin(omega*t)
            x(n + 1) = 0.0_wp
            do it = 1, 50
                do j = 1, n
                    s = 0.5_wp*(x(j) + u_old(j))
                    h = 0.5_wp*(x(j) - u_old(j))
                    if (abs(h) > 1.0e-8_wp) then
                        g = sin(s)*sin(h)/h
                        dg = 0.5_wp*(cos(s)*sin(h)/h + sin(s)*(cos(h)/h - sin(h)/h**2))
                    else
                        g = sin(s)
                        dg = 0.5_wp*cos(s)
                    end if
                    r(j) = -((x(j) - 2.0_wp*u(j) + u_old(j))/dt**2 &
                             - c**2*(u(j + 1) - 2.0_wp*u(j) + u(j - 1)) + alpha(j)*(x(j) - u_old(j))/(2.0_wp*dt) + g)
                    dd(j) = 1.0_wp/dt**2 + alpha(j)/(2.0_wp*dt) + dg
                end do
                dl = 0.0_wp
                du = 0.0_wp
                call solve_tridiag(dl, dd, du, r, info)
                x(1:n) = x(1:n) + r
                if (maxval(abs(r)) <= tol) exit
            end do
            u_old = u
            u = x
        end do
        seconds = wall_seconds() - seconds
        if (.not. (abs(u(60)) < huge(1.0_wp))) write (*, "(a)") "naive: non-finite u_60"
    end function naive_seconds

    !> Work per step of a run: Newton iterations (newton), tridiagonal solves (linearized), right-hand sides (RK).
    pure function work_per_step(res) result(work)
        !> The run's result.
        type(run_result), intent(in) :: res
        real(wp) :: work
        integer(i8) :: count

        count = res%rhs_evaluations
        if (res%newton_iterations > 0) then
            count = res%newton_iterations
        else if (res%tridiagonal_solves > 0) then
            count = res%tridiagonal_solves
        end if
        work = real(count, wp)/real(max(res%steps, 1_i8), wp)
    end function work_per_step

    !> A 40-amplitude sweep on 1 and 2 threads.
    subroutine sweep_benchmark()
        type(input_config) :: cfg
        type(error_type), allocatable :: error
        character(len=*), parameter :: nml = "/tmp/supratrans_bench_sweep.nml"
        integer :: unit, threads
        real(wp) :: seconds(2)

        open (newunit=unit, file=nml, status="replace", action="write")
        write (unit, "(a)") "&drive omega = 0.9 /", "&record probes = 60 /", &
            "&scene kind = 'amplitude_sweep', amplitude_min = 1.2, amplitude_max = 1.98, amplitude_step = 0.02 /", &
            "&output file = '/tmp/supratrans_bench_sweep.h5', overwrite = .true., quiet = .true. /"
        close (unit)
        write (*, "(a)") "# 40-amplitude sweep (sine-Gordon, Omega = 0.9, A = 1.20 .. 1.98, T = 200)"
        do threads = 1, 2
            call read_input(nml, cfg, error)
            if (allocated(error)) error stop "benchmark: " // error%message
            !$ call omp_set_num_threads(threads)
            seconds(threads) = wall_seconds()
            call run_amplitude_sweep(cfg, error)
            seconds(threads) = wall_seconds() - seconds(threads)
            if (allocated(error)) error stop "benchmark: " // error%message
            write (*, "(a, i0, a, f8.3, a)") "threads ", threads, ": ", seconds(threads), " s"
        end do
        write (*, "(a, f6.3)") "speed-up 2 threads / 1 thread: ", seconds(1)/seconds(2)
        call remove_file("/tmp/supratrans_bench_sweep.h5")
        call remove_file(nml)
    end subroutine sweep_benchmark

    !> The bifurcation diagram of `input` with its frequency step replaced by `omega_step` up to `omega_max`.
    subroutine bifurcation_benchmark(input, omega_step, omega_max, omega_min)
        character(len=*), intent(in) :: input
        real(wp), intent(in) :: omega_step, omega_max
        real(wp), intent(in), optional :: omega_min
        type(input_config) :: cfg
        type(error_type), allocatable :: error
        type(h5_file) :: file
        integer, allocatable :: runs(:, :), steps(:, :)
        real(wp), allocatable :: threshold(:, :), omega(:)
        real(wp) :: seconds
        integer :: i
        character(len=*), parameter :: out = "/tmp/supratrans_bench_bif.h5"

        call read_input(input, cfg, error)
        if (allocated(error)) error stop "benchmark: " // error%message
        cfg%scene%omega_step = omega_step
        cfg%scene%omega_max = omega_max
        if (present(omega_min)) cfg%scene%omega_min = omega_min
        cfg%output%file = out
        cfg%output%overwrite = .true.
        cfg%output%quiet = .true.
        !$ call omp_set_num_threads(2)
        seconds = wall_seconds()
        call run_bifurcation(cfg, error)
        seconds = wall_seconds() - seconds
        if (allocated(error)) error stop "benchmark: " // error%message
        call h5_open(file, out, error)
        if (.not. allocated(error)) call h5_read(file, "/cost/runs", runs, error)
        if (.not. allocated(error)) call h5_read(file, "/cost/steps", steps, error)
        if (.not. allocated(error)) call h5_read(file, "/threshold", threshold, error)
        if (.not. allocated(error)) call h5_read(file, "/omega", omega, error)
        if (allocated(error)) error stop "benchmark: " // error%message
        call h5_close(file, error)
        write (*, "(a, f5.2, a, f5.2, a, f5.2, a)") "# bifurcation diagram, undamped sine-Gordon, Omega = ", &
            cfg%scene%omega_min, " ..", omega_max, &
            " step", omega_step, ", resolution 0.01, 2 threads"
        write (*, "(a, i0, a, i0, a, f8.2, a)") "runs ", sum(runs, mask=runs > 0), ", time steps ", &
            sum(int(steps, i8), mask=steps > 0), ", ", seconds, " s"
        do i = 1, size(omega)
            if (abs(omega(i) - 0.9_wp) < 1.0e-9_wp) write (*, "(a, f6.3)") "threshold at Omega = 0.9: ", threshold(i, 1)
        end do
        call remove_file(out)
    end subroutine bifurcation_benchmark

    !> The slices of `input` by cost: each of `counts(k)` slices run alone on one thread (see the program's header),
    !> each `repeats` times (the fastest run of a slice counts).
    subroutine slice_benchmark(input, counts, repeats)
        character(len=*), intent(in) :: input
        integer, intent(in) :: counts(:), repeats
        real(wp), allocatable :: task_time(:), earlier_time(:), grid(:, :)
        character(len=*), parameter :: earlier = "/tmp/supratrans_bench_costs.h5"
        type(h5_file) :: file
        type(error_type), allocatable :: error
        integer :: k

        !$ call omp_set_num_threads(1)
        write (*, "(a)") "# slices by cost: " // input // ", each slice alone on one thread, the fastest of " &
            // int_str(repeats) // " run(s) of it; ratio = slowest / mean"
        write (*, "(a)") "# deal 'estimate': by the estimated costs; 'measured': --costs, by the searches' processor " &
            // "times of the first estimate pass (merged into " // earlier // ")"
        write (*, "(a)") "# dealt: the deal's ratio by the costs it was dealt by; searches: by this pass's own search " &
            // "times; outside_ms: a slice's processor time outside its searches (mean); repeat_sd: sd of " &
            // "log(search time / its time in " // earlier // ")"
        write (*, "(a6, 2x, a9, 2x, a10, 2x, a10, 2x, a10, 2x, a10, 2x, a12, 2x, a12, 2x, a12, 4(2x, a10))") &
            "slices", "deal", "mean_s", "max_s", "wall_ratio", "cpu_ratio", "bound_1task", "interleaved", &
            "lpt_modelled", "dealt", "searches", "outside_ms", "repeat_sd"
        do k = 1, size(counts)
            call slice_pass(input, counts(k), "", k == 1, repeats, task_time, earlier_time)
            if (k == 1) then
                ! the costs the measured deal reads: /cost/cpu_time (omega, curve) of the merged file, by task index
                call h5_open(file, earlier, error)
                if (.not. allocated(error)) call h5_read(file, "/cost/cpu_time", grid, error)
                if (allocated(error)) error stop "benchmark: " // error%message
                call h5_close(file, error)
                earlier_time = reshape(grid, [size(grid)])
            end if
        end do
        do k = 1, size(counts)
            call slice_pass(input, counts(k), earlier, .false., repeats, task_time, earlier_time)
        end do
        call remove_file(earlier)
    end subroutine slice_benchmark

    !> One pass of the slice benchmark: the `n` slices of `input`, dealt by the estimate (`costs` = "") or by the
    !> measured costs of the file `costs`, each slice run `repeats` times (in turn forwards and backwards, so that a
    !> change of the machine's load does not fall on the same slices each time; the run of least processor time
    !> counts, the least wall time likewise); prints one row. With `keep`, the parts (of the last round) are merged
    !> into the file the measured pass reads. `task_time`: the searches' processor times of this pass (of each
    !> slice's counted run), by task index; `earlier_time`: those of the earlier file, when read (else unallocated).
    !> With the environment variable SUPRATRANS_BENCH_SLICES_DETAIL set to a file name, every run's slices and
    !> searches are appended to it ("slice N DEAL I TASKS WALL CPU", "task N DEAL I J TASK CPU WALL RUNS").
    subroutine slice_pass(input, n, costs, keep, repeats, task_time, earlier_time)
        character(len=*), intent(in) :: input, costs
        integer, intent(in) :: n, repeats
        logical, intent(in) :: keep
        real(wp), allocatable, intent(inout) :: task_time(:)
        real(wp), allocatable, intent(in) :: earlier_time(:)
        type(input_config) :: cfg
        type(invocation_type) :: inv
        type(error_type), allocatable :: error
        type(h5_file) :: file
        integer, allocatable :: tasks(:), owner(:), slice_of(:)
        real(wp), allocatable :: values(:, :), wall(:), cpu(:), modelled(:), run_time(:), own(:)
        real(wp) :: t0, c0, c1, mean, interleaved, run_wall, run_cpu
        integer :: i, j, k, status, round, unit, ios
        character(len=:), allocatable :: part, text, deal
        character(len=256), allocatable :: merge_args(:)
        character(len=512) :: detail
        character(len=10) :: dealt_text, repeat_text
        type(search_record) :: record
        logical :: detailed

        call get_environment_variable("SUPRATRANS_BENCH_SLICES_DETAIL", detail, status=ios)
        detailed = ios == 0 .and. len_trim(detail) > 0
        if (detailed) then
            open (newunit=unit, file=trim(detail), position="append", action="write", iostat=ios)
            detailed = ios == 0
        end if
        deal = merge("estimate", "measured", len(costs) == 0)
        allocate (wall(n), cpu(n), merge_args(n + 4))
        do round = 1, max(repeats, 1)
            do k = 1, n
                i = merge(k, n + 1 - k, mod(round, 2) == 1)
                call read_input(input, cfg, error)
                if (allocated(error)) error stop "benchmark: " // error%message
                cfg%output%overwrite = .true.
                cfg%output%quiet = .true.
                inv%slice_index = i
                inv%slice_count = n
                if (len(costs) > 0) inv%slice_costs = costs
                part = "/tmp/supratrans_bench_slices.part-" // int_str(i) // "-of-" // int_str(n) // ".h5"
                cfg%output%file = part
                call remove_file(part)
                call cpu_time(c0)
                t0 = wall_seconds()
                call run_bifurcation(cfg, error, inv=inv)
                run_wall = wall_seconds() - t0
                call cpu_time(c1)
                run_cpu = c1 - c0
                if (allocated(error)) error stop "benchmark: " // error%message
                ! the searches' own measured times, by task index
                call h5_open(file, part, error)
                if (.not. allocated(error)) call h5_read(file, "part/task", tasks, error)
                if (.not. allocated(error)) call h5_read(file, "part/values", values, error)
                if (allocated(error)) error stop "benchmark: " // error%message
                call h5_close(file, error)
                if (round == 1 .and. k == 1) then
                    if (allocated(task_time)) deallocate (task_time)
                    allocate (task_time(tasks_total(part)), slice_of(tasks_total(part)))
                    task_time = 0.0_wp
                    slice_of = 0
                end if
                if (round == 1) then
                    wall(i) = run_wall
                    cpu(i) = huge(1.0_wp)
                end if
                wall(i) = min(wall(i), run_wall)
                do j = 1, size(tasks)
                    record = from_values(values(:, j))
                    if (run_cpu < cpu(i)) task_time(tasks(j)) = record%cpu_time
                    slice_of(tasks(j)) = i
                    if (detailed) write (unit, "(a, 1x, i0, 1x, a, 1x, i0, 1x, i0, 1x, i0, 3(1x, es14.6))") "task", &
                        n, deal, i, j, tasks(j), record%cpu_time, record%wall_time, real(record%runs, wp)
                end do
                cpu(i) = min(cpu(i), run_cpu)
                if (detailed) write (unit, "(a, 1x, i0, 1x, a, 1x, i0, 1x, i0, 2(1x, es14.6))") "slice", n, deal, i, &
                    size(tasks), run_wall, run_cpu
                merge_args(i + 4) = part
            end do
        end do
        if (detailed) close (unit)
        if (keep) then
            merge_args(1:4) = [character(len=256) :: "merge", "--overwrite", "-o", "/tmp/supratrans_bench_costs.h5"]
            call run_command(merge_args, status, error, text)
            if (allocated(error)) error stop "benchmark: merge: " // error%message
        end if
        do i = 1, n
            call remove_file(trim(merge_args(i + 4)))
        end do
        mean = sum(wall)/real(n, wp)
        owner = [(mod(j - 1, n) + 1, j = 1, size(task_time))]
        modelled = slice_sums(task_time, owner, n)
        interleaved = maxval(modelled)/(sum(modelled)/real(n, wp))
        owner = slice_owners(task_time, n)
        modelled = slice_sums(task_time, owner, n)
        own = slice_sums(task_time, slice_of, n)       ! the deal run, by this pass's own search times
        dealt_text = "-"
        repeat_text = "-"
        if (allocated(earlier_time)) then
            if (len(costs) > 0) then
                run_time = slice_sums(earlier_time, slice_of, n)
                write (dealt_text, "(f10.3)") maxval(run_time)/(sum(run_time)/real(n, wp))
            end if
            write (repeat_text, "(f10.3)") log_spread(task_time, earlier_time)
        end if
        write (*, "(i6, 2x, a9, 2x, f10.3, 2x, f10.3, 2x, f10.3, 2x, f10.3, 2x, f12.3, 2x, f12.3, 2x, f12.3, 2x, " &
               // "a10, 2x, f10.3, 2x, f10.1, 2x, a10)") n, deal, mean, maxval(wall), maxval(wall)/mean, &
            maxval(cpu)/(sum(cpu)/real(n, wp)), max(1.0_wp, maxval(task_time)/(sum(task_time)/real(n, wp))), &
            interleaved, maxval(modelled)/(sum(modelled)/real(n, wp)), adjustr(dealt_text), &
            maxval(own)/(sum(own)/real(n, wp)), 1000.0_wp*sum(cpu - own)/real(n, wp), adjustr(repeat_text)
    end subroutine slice_pass

    !> The standard deviation of log(a/b) over the tasks where both are positive (how well a search's time repeats).
    pure function log_spread(a, b) result(sd)
        real(wp), intent(in) :: a(:), b(:)
        real(wp) :: sd
        real(wp), allocatable :: r(:)

        r = pack(log(max(a, tiny(1.0_wp))/max(b, tiny(1.0_wp))), a > 0.0_wp .and. b > 0.0_wp)
        sd = 0.0_wp
        if (size(r) > 1) sd = sqrt(sum((r - sum(r)/size(r))**2)/real(size(r) - 1, wp))
    end function log_spread

    !> The number of tasks of a part's scene (`tasks_total` of the part file).
    function tasks_total(part) result(total)
        character(len=*), intent(in) :: part
        type(h5_file) :: file
        type(error_type), allocatable :: error
        integer :: total

        call h5_open(file, part, error)
        if (.not. allocated(error)) call h5_read_attr(file, "part", "tasks_total", total, error)
        if (allocated(error)) error stop "benchmark: " // error%message
        call h5_close(file, error)
    end function tasks_total

    !> The summed time of each slice under an assignment.
    pure function slice_sums(times, owner, n) result(sums)
        real(wp), intent(in) :: times(:)
        integer, intent(in) :: owner(:), n
        real(wp), allocatable :: sums(:)
        integer :: j

        allocate (sums(n))
        sums = 0.0_wp
        do j = 1, size(times)
            sums(owner(j)) = sums(owner(j)) + times(j)
        end do
    end function slice_sums


    !> Wall-clock seconds since an arbitrary origin.
    function wall_seconds() result(t)
        real(wp) :: t
        integer(i8) :: count, rate

        call system_clock(count, rate)
        t = real(count, wp)/real(rate, wp)
    end function wall_seconds


end program benchmark
