!> Benchmarks, in the release profile:  fpm run --example benchmark --profile release [-- repeats [paper]]
!>
!> 1. The paper-default run (sine-Gordon, Omega = 0.9, A = 1.9, N = 200, T = 200, dt = 0.05) for each scheme:
!>    median wall time of a run over `repeats` runs (ms), work per step (Newton iterations for newton,
!>    tridiagonal solves for linearized, right-hand sides for the Runge-Kutta methods), ledger residual relative
!>    to the energy scale.
!> 2. A 40-amplitude sweep (A = 1.20 .. 1.98 at Omega = 0.9) on 1 and on 2 threads: seconds and speed-up.
!> 3. The undamped sine-Gordon bifurcation diagram, Omega = 0.05 .. 1.00 step 0.05, resolution 0.01
!>    (input/bif_undamped_sg.nml): runs, time steps, seconds; with the argument `paper`, also at the paper's
!>    resolution Omega = 0.05 .. 0.99 step 0.01.
!> Scene outputs go to the system's temporary directory and are deleted. With beta = 0 (the paper default) the Jacobian is diagonal;
!> a second block repeats the runs with beta = 0.1, where every Newton iteration is one LAPACK dgtsv.
program benchmark
    use supratrans_kinds, only: wp, i8
    use supratrans_config, only: run_config, method_newton, method_linearized, method_rk4, method_rk8
    use supratrans_simulate, only: simulate
    use supratrans_result, only: run_result
    use supratrans_config, only: input_config
    use supratrans_error, only: error_type
    use supratrans_input, only: read_input
    use supratrans_scene_sweep, only: run_amplitude_sweep
    use supratrans_scene_bifurcation, only: run_bifurcation
    use supratrans_hdf5, only: h5_file, h5_open, h5_read, h5_close
    use supratrans_system, only: remove_file
    use supratrans_scene_workprec, only: median
    !$ use omp_lib, only: omp_set_num_threads, omp_get_max_threads
    implicit none
    type(run_config) :: run
    type(run_result) :: result
    integer :: repeats, i, im
    logical :: paper
    character(len=32) :: arg
    character(len=*), parameter :: names(2) = [character(len=10) :: "newton", "linearized"]
    integer, parameter :: methods(2) = [method_newton, method_linearized]
    real(wp), allocatable :: times(:)

    repeats = 21
    if (command_argument_count() >= 1) then
        call get_command_argument(1, arg)
        read (arg, *) repeats
    end if
    paper = .false.
    if (command_argument_count() >= 2) then
        call get_command_argument(2, arg)
        paper = trim(arg) == "paper"
    end if
    allocate (times(repeats))
    run%drive%amplitude = 1.9_wp
    run%drive%omega = 0.9_wp
    allocate (run%record%probes(0))
    run%record%ledger_every = 4000

    write (*, "(a)") "# paper-default run: sine-Gordon, Omega = 0.9, A = 1.9, N = 200, T = 200, dt = 0.05"
    write (*, "(a10, 2x, a12, 2x, a12, 2x, a14, 2x, a14, 2x, a14)") "scheme", "median_ms", "min_ms", &
        "work/step", "injected", "rel_residual"
    do im = 1, 2*size(methods)
        if (im == size(methods) + 1) then
            run%chain%beta = 0.1_wp
            write (*, "(a)") "# same with internal damping beta = 0.1 (tridiagonal Jacobian: one dgtsv per iteration)"
        end if
        run%numerics%method = methods(1 + mod(im - 1, size(methods)))
        do i = 1, repeats
            call simulate(run, result)
            times(i) = result%wall_time
        end do
        write (*, "(a10, 2x, f12.3, 2x, f12.3, 2x, f14.4, 2x, es14.6, 2x, es14.3)") names(1 + mod(im - 1, size(methods))), &
            1000.0_wp*median(times), 1000.0_wp*minval(times), &
            work_per_step(result), result%ledger%injected, &
            abs(result%ledger%residual)/max(result%ledger%energy_scale, tiny(1.0_wp))
    end do

    ! the Runge-Kutta references, at the step where each reaches its accuracy class on this run (README)
    write (*, "(a)") "# Runge-Kutta references, beta = 0 (work/step = right-hand sides per step)"
    run%chain%beta = 0.0_wp
    do im = 1, 2
        run%numerics%method = merge(method_rk4, method_rk8, im == 1)
        run%numerics%dt = merge(0.1_wp, 0.2_wp, im == 1)
        do i = 1, repeats
            call simulate(run, result)
            times(i) = result%wall_time
        end do
        write (*, "(a10, 2x, f12.3, 2x, f12.3, 2x, f14.4, 2x, es14.6, 2x, es14.3)") &
            merge("rk4 dt=0.1", "rk8 dt=0.2", im == 1), 1000.0_wp*median(times), 1000.0_wp*minval(times), &
            work_per_step(result), result%ledger%injected, &
            abs(result%ledger%residual)/max(result%ledger%energy_scale, tiny(1.0_wp))
    end do

    call sweep_benchmark()
    call bifurcation_benchmark("input/bif_undamped_sg.nml", 0.05_wp, 1.00_wp)
    if (paper) call bifurcation_benchmark("input/bif_undamped_sg.nml", 0.01_wp, 0.99_wp)

contains

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
    subroutine bifurcation_benchmark(input, omega_step, omega_max)
        character(len=*), intent(in) :: input
        real(wp), intent(in) :: omega_step, omega_max
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
        cfg%output%file = out
        cfg%output%overwrite = .true.
        cfg%output%quiet = .true.
        !$ call omp_set_num_threads(2)
        seconds = wall_seconds()
        call run_bifurcation(cfg, error)
        seconds = wall_seconds() - seconds
        if (allocated(error)) error stop "benchmark: " // error%message
        call h5_open(file, out, .false., error)
        if (.not. allocated(error)) call h5_read(file, "/cost/runs", runs, error)
        if (.not. allocated(error)) call h5_read(file, "/cost/steps", steps, error)
        if (.not. allocated(error)) call h5_read(file, "/threshold", threshold, error)
        if (.not. allocated(error)) call h5_read(file, "/omega", omega, error)
        if (allocated(error)) error stop "benchmark: " // error%message
        call h5_close(file, error)
        write (*, "(a, f5.2, a, f5.2, a)") "# bifurcation diagram, undamped sine-Gordon, Omega = 0.05 ..", omega_max, &
            " step", omega_step, ", resolution 0.01, 2 threads"
        write (*, "(a, i0, a, i0, a, f8.2, a)") "runs ", sum(runs, mask=runs > 0), ", time steps ", &
            sum(int(steps, i8), mask=steps > 0), ", ", seconds, " s"
        do i = 1, size(omega)
            if (abs(omega(i) - 0.9_wp) < 1.0e-9_wp) write (*, "(a, f6.3)") "threshold at Omega = 0.9: ", threshold(i, 1)
        end do
        call remove_file(out)
    end subroutine bifurcation_benchmark

    !> Wall-clock seconds since an arbitrary origin.
    function wall_seconds() result(t)
        real(wp) :: t
        integer(i8) :: count, rate

        call system_clock(count, rate)
        t = real(count, wp)/real(rate, wp)
    end function wall_seconds


end program benchmark
