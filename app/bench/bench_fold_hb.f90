!> The harmonic-balance benchmark (`fpm run --example benchmark --profile release -- REPEATS fold hb [paper]`):
!> 1. one fold of the paper's chain (undamped sine-Gordon, N = 200, c = 4) at Omega = 0.9 from rest, converged in K
!>    to 1e-9 (the scene's controls of input/fold_hb_sg.nml), one thread: median, min and max wall ms over REPEATS;
!> 2. its cost against K and N (K fixed: the branch from rest to the fold at Omega = 0.9): ms per block LU and that
!>    over K^3 N, which is constant when the cost scales as K^3 N;
!> 3. with `paper`: the fold line of input/fold_hb_sg.nml (Omega = 0.05 .. 0.99 step 0.01) and from Omega = 0.1
!>    up, each against the scan of input/bif_undamped_sg.nml on the same grid, 2 threads: wall seconds, the ratio,
!>    and each task's K and seconds.
module bench_fold_hb
    use supratrans_kinds, only: wp
    use supratrans_config, only: input_config, chain_params
    use supratrans_error, only: error_type
    use supratrans_input, only: read_input
    use supratrans_scene_continuation, only: continuation_scene
    use supratrans_hdf5, only: h5_file, h5_open, h5_read, h5_close
    use supratrans_system, only: remove_file
    use supratrans_workprec_measure, only: median
    use bench_fold, only: timed_scan, wall_seconds
    use supratrans_hb_continuation, only: hb_controls, hb_result, hb_fold_converged, hb_fold
    !$ use omp_lib, only: omp_set_num_threads
    implicit none
    private

    public :: fold_hb_benchmark

contains

    !> The rows described in the module's header.
    subroutine fold_hb_benchmark(repeats, paper_grid)
        !> Timed repetitions of the one fold.
        integer, intent(in) :: repeats
        !> Whether to run the fold line against the scan on the paper's grid.
        logical, intent(in) :: paper_grid
        type(chain_params) :: chain
        type(hb_controls) :: ctl
        type(hb_result) :: res
        type(error_type), allocatable :: error
        real(wp), allocatable :: times(:)
        real(wp) :: t0, per_lu
        integer :: i, k, n
        integer, parameter :: ks(3) = [4, 8, 16], ns(3) = [100, 200, 400]

        !$ call omp_set_num_threads(1)
        ctl%step_max = 1.0_wp
        allocate (times(max(1, repeats)))
        do i = 1, size(times)
            t0 = wall_seconds()
            call hb_fold_converged(chain, 0.9_wp, ctl, res, error)
            times(i) = 1.0e3_wp*(wall_seconds() - t0)
            if (allocated(error)) error stop "benchmark: " // error%message
        end do
        write (*, "(a)") "# one fold by harmonic balance: undamped sine-Gordon, N = 200, c = 4, Omega = 0.9, from rest," &
            // " converged in K to 1e-9, one thread"
        write (*, "(a, f12.9, a, i0, a, es8.1, a, i0, a, i0)") "A_f = ", res%fold_amplitude, ", K = ", res%harmonics, &
            ", |dA_f(K)| = ", res%harmonics_error, ", LU = ", res%factorizations, ", residuals = ", res%residuals
        write (*, "(a, i0, a, 3f9.2)") "one fold ms (median, min, max of ", size(times), "): ", median(times), &
            minval(times), maxval(times)

        write (*, "(a)") "# cost against K and N (K fixed; branch from rest to the fold at Omega = 0.9)"
        write (*, "(a6, 1x, a6, 1x, a6, 1x, a10, 1x, a12, 1x, a14)") "K", "N", "LU", "fold ms", "ms per LU", &
            "ns / (K^3 N)"
        do k = 1, size(ks)
            do n = 1, size(ns)
                chain%n = ns(n)
                chain%n0 = 3*ns(n)/4
                t0 = wall_seconds()
                call hb_fold(chain, 0.9_wp, ks(k), ctl, res, error)
                t0 = 1.0e3_wp*(wall_seconds() - t0)
                if (allocated(error)) error stop "benchmark: " // error%message
                per_lu = t0/real(max(res%factorizations, 1), wp)
                write (*, "(i6, 1x, i6, 1x, i6, 1x, f10.2, 1x, f12.4, 1x, f14.4)") ks(k), ns(n), res%factorizations, &
                    t0, per_lu, 1.0e6_wp*per_lu/(real(ks(k), wp)**3*real(ns(n), wp))
            end do
        end do
        if (paper_grid) then
            call fold_line_against_scan(0.05_wp)
            call fold_line_against_scan(0.10_wp)
        end if
    end subroutine fold_hb_benchmark

    !> The fold line of input/fold_hb_sg.nml from omega_min to 0.99 against the scan of input/bif_undamped_sg.nml
    !> on the same grid (step 0.01), 2 threads each.
    subroutine fold_line_against_scan(omega_min)
        !> Lowest frequency.
        real(wp), intent(in) :: omega_min
        type(input_config) :: cfg
        type(error_type), allocatable :: error
        type(h5_file) :: file
        type(continuation_scene) :: fold_line
        character(len=*), parameter :: out = "/tmp/supratrans_bench_fold_hb.h5"
        real(wp), allocatable :: fold(:, :), scan(:, :), omega(:), wall(:, :)
        integer, allocatable :: harmonics(:, :)
        real(wp) :: seconds_fold, seconds_scan
        integer :: i

        call read_input("input/fold_hb_sg.nml", cfg, error)
        if (allocated(error)) error stop "benchmark: " // error%message
        cfg%scene%omega_min = omega_min
        cfg%output%file = out
        cfg%output%quiet = .true.
        !$ call omp_set_num_threads(2)
        seconds_fold = wall_seconds()
        call fold_line%run(cfg, error)
        seconds_fold = wall_seconds() - seconds_fold
        if (allocated(error)) error stop "benchmark: " // error%message
        call h5_open(file, out, error)
        if (.not. allocated(error)) call h5_read(file, "/fold_amplitude", fold, error)
        if (.not. allocated(error)) call h5_read(file, "/harmonics", harmonics, error)
        if (.not. allocated(error)) call h5_read(file, "/cost/wall_time", wall, error)
        if (.not. allocated(error)) call h5_read(file, "/omega", omega, error)
        if (allocated(error)) error stop "benchmark: " // error%message
        call h5_close(file, error)

        call timed_scan(omega_min, 0.99_wp, 0.01_wp, scan, seconds_scan)
        write (*, "(a, f5.2, a)") "# the fold line by harmonic balance (input/fold_hb_sg.nml), Omega = ", omega_min, &
            " .. 0.99 step 0.01, against the scan (input/bif_undamped_sg.nml, same grid), 2 threads"
        write (*, "(a8, 1x, a4, 1x, a12, 1x, a8, 1x, a8)") "Omega", "K", "A_f", "scan", "task_s"
        do i = 1, size(omega)
            write (*, "(f8.3, 1x, i4, 1x, f12.8, 1x, f8.3, 1x, f8.3)") omega(i), harmonics(i, 1), fold(i, 1), &
                scan(i, 1), wall(i, 1)
        end do
        write (*, "(a, f9.2, a, f8.2, a, f8.3)") "fold line wall s: ", seconds_fold, ", scan wall s: ", seconds_scan, &
            ", ratio ", seconds_fold/max(seconds_scan, tiny(1.0_wp))
        call remove_file(out)
    end subroutine fold_line_against_scan

end module bench_fold_hb
