!> Benchmark of the paper-default run (sine-Gordon, Omega = 0.9, A = 1.9, N = 200, T = 200, dt = 0.05) for each
!> scheme. Build and run in the release profile:  fpm run --example benchmark --profile release [-- repeats]
!> Prints, per scheme, the median wall time of a run over the repeats (ms), Newton iterations per step, and the
!> energy-ledger residual relative to the energy scale. With beta = 0 (the paper default) the Jacobian is diagonal;
!> a second block repeats the runs with beta = 0.1, where every Newton iteration is one LAPACK dgtsv.
program benchmark
    use supratrans_kinds, only: wp
    use supratrans_config, only: run_config, method_newton, method_linearized
    use supratrans_simulate, only: simulate
    use supratrans_result, only: run_result
    implicit none
    type(run_config) :: run
    type(run_result) :: result
    integer :: repeats, i, im
    character(len=32) :: arg
    character(len=*), parameter :: names(2) = [character(len=10) :: "newton", "linearized"]
    integer, parameter :: methods(2) = [method_newton, method_linearized]
    real(wp), allocatable :: times(:)

    repeats = 21
    if (command_argument_count() >= 1) then
        call get_command_argument(1, arg)
        read (arg, *) repeats
    end if
    allocate (times(repeats))
    run%drive%amplitude = 1.9_wp
    run%drive%omega = 0.9_wp
    allocate (run%record%probes(0))
    run%record%ledger_every = 4000

    write (*, '(a)') "# paper-default run: sine-Gordon, Omega = 0.9, A = 1.9, N = 200, T = 200, dt = 0.05"
    write (*, '(a10, 2x, a12, 2x, a12, 2x, a14, 2x, a14, 2x, a14)') "scheme", "median_ms", "min_ms", &
        "iters/step", "injected", "rel_residual"
    do im = 1, 2*size(methods)
        if (im == size(methods) + 1) then
            run%chain%beta = 0.1_wp
            write (*, '(a)') "# same with internal damping beta = 0.1 (tridiagonal Jacobian: one dgtsv per iteration)"
        end if
        run%numerics%method = methods(1 + mod(im - 1, size(methods)))
        do i = 1, repeats
            call simulate(run, result)
            times(i) = result%wall_time
        end do
        write (*, '(a10, 2x, f12.3, 2x, f12.3, 2x, f14.4, 2x, es14.6, 2x, es14.3)') names(1 + mod(im - 1, size(methods))), &
            1000.0_wp*median(times), 1000.0_wp*minval(times), &
            real(result%newton_iterations, wp)/real(max(result%steps, 1), wp), result%ledger%injected, &
            abs(result%ledger%residual)/max(result%ledger%energy_scale, tiny(1.0_wp))
    end do

contains

    !> Median of a small array.
    pure function median(x) result(med)
        real(wp), intent(in) :: x(:)
        real(wp) :: med, y(size(x)), t
        integer :: i, j

        y = x
        do i = 2, size(y)
            t = y(i)
            j = i - 1
            do while (j >= 1)
                if (y(j) <= t) exit
                y(j + 1) = y(j)
                j = j - 1
            end do
            y(j + 1) = t
        end do
        med = y((size(y) + 1)/2)
        if (mod(size(y), 2) == 0) med = 0.5_wp*(y(size(y)/2) + y(size(y)/2 + 1))
    end function median

end program benchmark
