!> The continuation's benchmark (`fpm run --example benchmark --profile release -- REPEATS fold [paper]`): one fold
!> of the undamped sine-Gordon chain at Omega = 0.9 for several chains and controls, with its cost by phase (tangent,
!> maps, LU, eigenvalues), and the undamped fold line against the ramped scan of input/bif_undamped_sg.nml on the
!> same grid (the rows are described at `fold_benchmark`). Scene outputs go to /tmp and are deleted.
module bench_fold
    use supratrans_kinds, only: wp, i8
    use supratrans_config, only: run_config, input_config, scene_params
    use supratrans_error, only: error_type
    use supratrans_input, only: read_input
    use supratrans_scene_bifurcation, only: run_bifurcation
    use supratrans_scene_continuation, only: continuation_scene
    use supratrans_hdf5, only: h5_file, h5_open, h5_read, h5_close
    use supratrans_system, only: remove_file
    use supratrans_fold_record, only: fold_record, empty_fold_record
    use supratrans_fold_line, only: trace_fold, shortest_chain
    !$ use omp_lib, only: omp_set_num_threads
    implicit none
    private

    public :: fold_benchmark, timed_scan, wall_seconds

contains

    !> The continuation scene's cost (the program's argument `fold`; with `paper_grid` the fold line runs on the
    !> paper's grid Omega = 0.05 .. 0.99 step 0.01, otherwise on its subset 0.05 .. 0.95 step 0.05):
    !> 1. one fold (undamped sine-Gordon, Omega = 0.9, c = 4, dt ~ 0.05, one thread) at N = 100, 200, 400 with the
    !>    paper's absorber (N0 = 3N/4, sigma = 3), floquet_every = 4 (with the trend) and, at N = 200, 1 (the
    !>    multipliers at every point); then the short chain of fold lines: wall and CPU seconds, the CPU seconds
    !>    of the tangent (Jacobians), the maps, the LU and the eigenvalues, points, Jacobians, dgeev calls (the
    !>    scene's four multiplier samples included); the growth of the CPU time with N;
    !>    the fold alone (floquet_every = 0) at N = 200, with the default steps and with larger ones;
    !> 2. the undamped fold line on the short chains (input without n), with floquet_every = 4 and then the fold
    !>    alone, against the scan of input/bif_undamped_sg.nml on the same grid, all on 2 threads: wall seconds and
    !>    the thresholds at each Omega.
    subroutine fold_benchmark(paper_grid)
        !> Whether the fold line runs on the paper's grid (the program's third argument `paper`).
        logical, intent(in) :: paper_grid
        type(run_config) :: frun
        type(scene_params) :: sc
        integer :: k, n
        real(wp) :: cpu(3)
        character(len=*), parameter :: fold_alone = "floquet_every = 0, continuation_step_max = 0.5, beyond_fold = 0"

        sc%amplitude_max = 4.0_wp
        sc%continuation_points = 150
        frun%drive%omega = 0.9_wp
        frun%drive%ramp_time = 0.0_wp
        ! one thread, also for OpenBLAS (its OpenMP build follows omp_get_max_threads outside a parallel region:
        ! two threads on a loaded machine made dgeev 30x slower)
        !$ call omp_set_num_threads(1)
        write (*, "(a)") "# one fold: undamped sine-Gordon, Omega = 0.9, c = 4, dt ~ 0.05, newton, 1 thread " &
            // "(seconds: wall, then CPU of the whole fold and of its phases)"
        write (*, "(a6, 1x, a5, 1x, a5, 1x, a12, 1x, a12, 6(1x, a7), 3(1x, a6))") "N", "N0", "every", "A_f", &
            "A_unstable", "wall", "cpu", "tangent", "map", "lu", "eigen", "points", "jacobs", "dgeev"
        do k = 1, 3
            n = 100*2**(k - 1)
            frun%chain%n = n
            frun%chain%n0 = 3*n/4
            sc%floquet_every = 4
            call fold_row(frun, sc, cpu(k))
        end do
        write (*, "(a, f5.2, a, f5.2, a)") "# CPU growth with N (floquet_every = 4): 100 -> 200 as N^", &
            log(cpu(2)/cpu(1))/log(2.0_wp), ", 200 -> 400 as N^", log(cpu(3)/cpu(2))/log(2.0_wp), &
            " (tangent ~ N^2 a Jacobian, LU and dgeev ~ N^3)"
        frun%chain%n = 200
        frun%chain%n0 = 150
        sc%floquet_every = 1
        call fold_row(frun, sc, cpu(3))
        write (*, "(a)") "# the fold alone (floquet_every = 0: the fold's multipliers only), N = 200; then also with " &
            // "continuation_step_max = 0.5 and beyond_fold = 0"
        sc%floquet_every = 0
        call fold_row(frun, sc, cpu(3))
        sc%continuation_step_max = 0.5_wp
        sc%beyond_fold = 0
        call fold_row(frun, sc, cpu(3))
        sc = scene_params(amplitude_max=sc%amplitude_max, continuation_points=sc%continuation_points)
        sc%floquet_every = 4
        call shortest_chain(frun%chain, frun%drive%omega, frun%numerics%dt, sc%short)
        write (*, "(a)") "# the short chain of fold lines (N0 = ceil(7 / lambda'), absorber sigma 3.4 / q in 6 .. 20 " &
            // "over 10 sigma sites)"
        call fold_row(frun, sc, cpu(1))
        if (paper_grid) then
            call fold_line_against_scan(0.05_wp, 0.99_wp, 0.01_wp, "floquet_every = 4")
            call fold_line_against_scan(0.05_wp, 0.99_wp, 0.01_wp, fold_alone)
        else
            call fold_line_against_scan(0.05_wp, 0.95_wp, 0.05_wp, "floquet_every = 4")
            call fold_line_against_scan(0.05_wp, 0.95_wp, 0.05_wp, fold_alone)
        end if
    end subroutine fold_benchmark

    !> One fold of `frun` with the controls `sc`: a row of the fold table; `cpu` its CPU seconds.
    subroutine fold_row(frun, sc, cpu)
        !> The run (chain, Omega, method).
        type(run_config), intent(in) :: frun
        !> The continuation's controls.
        type(scene_params), intent(in) :: sc
        !> CPU seconds of the fold.
        real(wp), intent(out) :: cpu
        type(fold_record) :: r
        real(wp) :: t0, c0, c1, seconds, share

        r = empty_fold_record(sc%continuation_points)
        t0 = wall_seconds()
        call cpu_time(c0)
        call trace_fold(frun, sc, r, .false.)
        call cpu_time(c1)
        seconds = wall_seconds() - t0
        cpu = c1 - c0
        ! the phases are timed by the wall clock: scaled to CPU seconds by the fold's CPU / wall ratio
        share = cpu/max(seconds, tiny(1.0_wp))
        write (*, "(i6, 1x, i5, 1x, i5, 1x, f12.8, 1x, f12.8, 6(1x, f7.3), 3(1x, i6))") frun%chain%n, frun%chain%n0, &
            sc%floquet_every, r%fold_amplitude, r%instability_amplitude, seconds, cpu, share*r%time_tangent, &
            share*r%time_map, share*r%time_lu, share*r%time_eigen, r%points, r%jacobians, r%eigen_calls
    end subroutine fold_row

    !> The undamped sine-Gordon fold line (short chains: the input gives no n) and the scan of
    !> input/bif_undamped_sg.nml on the grid omega_min .. omega_max step omega_step, 2 threads each.
    subroutine fold_line_against_scan(omega_min, omega_max, omega_step, controls)
        !> The grid of Omega.
        real(wp), intent(in) :: omega_min, omega_max, omega_step
        !> The continuation's controls in the namelist's words (e.g. "floquet_every = 4").
        character(len=*), intent(in) :: controls
        type(input_config) :: cfg
        type(error_type), allocatable :: error
        type(h5_file) :: file
        type(continuation_scene) :: fold_line
        character(len=*), parameter :: nml = "/tmp/supratrans_bench_fold_line.nml"
        character(len=*), parameter :: out = "/tmp/supratrans_bench_fold_line.h5"
        real(wp), allocatable :: fold(:, :), scan(:, :), omega(:), wall(:, :)
        integer, allocatable :: chain_n(:, :), status(:, :)
        real(wp) :: seconds_fold, seconds_scan
        integer :: unit, i

        open (newunit=unit, file=nml, status="replace", action="write")
        write (unit, "(a)") "&chain potential = 'sine-gordon' /", "&numerics method = 'newton', dt = 0.05 /"
        write (unit, "(a, f5.2, a, f5.2, a, f5.2, a)") "&scene kind = 'continuation', omega_min = ", omega_min, &
            ", omega_max = ", omega_max, ", omega_step = ", omega_step, &
            ", amplitude_max = 7.0, " // controls // ", fold_convergence = .false. /"
        write (unit, "(a)") "&output file = '" // out // "', overwrite = .true., quiet = .true. /"
        close (unit)
        call read_input(nml, cfg, error)
        if (allocated(error)) error stop "benchmark: " // error%message
        !$ call omp_set_num_threads(2)
        seconds_fold = wall_seconds()
        call fold_line%run(cfg, error)
        seconds_fold = wall_seconds() - seconds_fold
        if (allocated(error)) error stop "benchmark: " // error%message
        call h5_open(file, out, error)
        if (.not. allocated(error)) call h5_read(file, "/fold_amplitude", fold, error)
        if (.not. allocated(error)) call h5_read(file, "/chain_n", chain_n, error)
        if (.not. allocated(error)) call h5_read(file, "/status", status, error)
        if (.not. allocated(error)) call h5_read(file, "/cost/wall_time", wall, error)
        if (.not. allocated(error)) call h5_read(file, "/omega", omega, error)
        if (allocated(error)) error stop "benchmark: " // error%message
        call h5_close(file, error)

        call timed_scan(omega_min, omega_max, omega_step, scan, seconds_scan)
        write (*, "(a, f5.2, a, f5.2, a, f5.2, a)") "# undamped sine-Gordon, Omega = ", omega_min, " ..", omega_max, &
            " step", omega_step, ", 2 threads: the fold line (short chains; " // controls // &
            ") against the scan (N = 200, ramp 50)"
        write (*, "(a8, 1x, a6, 1x, a10, 1x, a6, 1x, a8, 1x, a8)") "Omega", "N", "A_f", "status", "scan", "task_s"
        do i = 1, size(omega)
            write (*, "(f8.3, 1x, i6, 1x, f10.5, 1x, i6, 1x, f8.3, 1x, f8.2)") omega(i), chain_n(i, 1), fold(i, 1), &
                status(i, 1), scan(i, 1), wall(i, 1)
        end do
        write (*, "(a, f9.2, a, f8.2, a, f8.2)") "fold line wall s: ", seconds_fold, ", scan wall s: ", seconds_scan, &
            ", ratio ", seconds_fold/max(seconds_scan, tiny(1.0_wp))
        call remove_file(out)
        call remove_file(nml)
    end subroutine fold_line_against_scan

    !> The scan of input/bif_undamped_sg.nml on the grid omega_min .. omega_max step omega_step (2 threads, as set by
    !> the caller): its thresholds (omega, curve) and its wall seconds; the file is deleted.
    subroutine timed_scan(omega_min, omega_max, omega_step, scan, seconds)
        !> The grid of Omega.
        real(wp), intent(in) :: omega_min, omega_max, omega_step
        !> The scan's /threshold.
        real(wp), allocatable, intent(out) :: scan(:, :)
        !> Wall seconds of the scene.
        real(wp), intent(out) :: seconds
        character(len=*), parameter :: scan_out = "/tmp/supratrans_bench_fold_scan.h5"
        type(input_config) :: cfg
        type(error_type), allocatable :: error
        type(h5_file) :: file

        call read_input("input/bif_undamped_sg.nml", cfg, error)
        if (allocated(error)) error stop "benchmark: " // error%message
        cfg%scene%omega_min = omega_min
        cfg%scene%omega_max = omega_max
        cfg%scene%omega_step = omega_step
        cfg%output%file = scan_out
        cfg%output%overwrite = .true.
        cfg%output%quiet = .true.
        seconds = wall_seconds()
        call run_bifurcation(cfg, error)
        seconds = wall_seconds() - seconds
        if (allocated(error)) error stop "benchmark: " // error%message
        call h5_open(file, scan_out, error)
        if (.not. allocated(error)) call h5_read(file, "/threshold", scan, error)
        if (allocated(error)) error stop "benchmark: " // error%message
        call h5_close(file, error)
        call remove_file(scan_out)
    end subroutine timed_scan

    !> Wall-clock seconds since an arbitrary origin.
    function wall_seconds() result(t)
        real(wp) :: t
        integer(i8) :: count, rate

        call system_clock(count, rate)
        t = real(count, wp)/real(rate, wp)
    end function wall_seconds

end module bench_fold
