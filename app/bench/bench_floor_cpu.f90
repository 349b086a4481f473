!> The paper-default Newton run against its floor in processor time (issue 24, point 2): the same run, steps and
!> floor as the benchmark's first table and its "newton steps alone" row, but each timed by the processor seconds of
!> this one-threaded process, run, steps and floor in turn, so that the time a shared machine gives to other jobs is
!> in none of them (the wall-clock ratios of the first table move by 30% from run to run when the machine is busy).
!> The floor: per step N sines and N cosines by `sin_cos_array` (the code's fastest kernel for the pair) and N
!> divisions, as `floor_seconds` of the benchmark.
module bench_floor_cpu
    use supratrans_kinds, only: wp, i8
    use supratrans_config, only: run_config, method_newton
    use supratrans_simulate, only: simulate
    use supratrans_result, only: run_result
    use supratrans_stepper_newton, only: newton_stepper
    use supratrans_sine_kernels, only: sin_cos_array
    use supratrans_workprec_measure, only: median
    !$ use omp_lib, only: omp_set_num_threads
    implicit none
    private

    public :: floor_cpu_benchmark

contains

    !> Print the medians (ms of processor time) of the paper-default newton run, of its steps alone and of its
    !> floor over `repeats` rounds, and the ratios run/floor and steps/floor (the issue's goal: run <= 2 floors).
    subroutine floor_cpu_benchmark(repeats)
        !> Rounds (each times the run, the steps and the floor once).
        integer, intent(in) :: repeats
        type(run_config) :: run
        type(run_result) :: result
        real(wp), allocatable :: t_run(:), t_steps(:), t_floor(:)
        real(wp) :: c0, c1
        integer :: i

        !$ call omp_set_num_threads(1)
        run%drive%amplitude = 1.9_wp
        run%drive%omega = 0.9_wp
        allocate (run%record%probes(0))
        run%record%ledger_every = 4000
        run%numerics%method = method_newton
        allocate (t_run(repeats), t_steps(repeats), t_floor(repeats))
        do i = 1, repeats
            call cpu_time(c0)
            call simulate(run, result)
            call cpu_time(c1)
            t_run(i) = c1 - c0
            t_steps(i) = steps_cpu(run)
            t_floor(i) = floor_cpu(run%chain%n, result%steps)
        end do
        write (*, "(a)") "# paper-default newton run against its floor in processor time (one thread, medians)"
        write (*, "(a, f9.3, a, f9.3, a, f9.3, a, f6.2, a, f6.2)") "newton cpu: run ", 1000.0_wp*median(t_run), &
            " ms, steps alone ", 1000.0_wp*median(t_steps), " ms, floor ", 1000.0_wp*median(t_floor), &
            " ms; run/floor ", median(t_run)/median(t_floor), ", steps/floor ", median(t_steps)/median(t_floor)
    end subroutine floor_cpu_benchmark

    !> Processor seconds of the run's steps by the newton stepper alone (init excluded).
    function steps_cpu(run) result(seconds)
        !> The run.
        type(run_config), intent(in) :: run
        real(wp) :: seconds
        type(newton_stepper) :: newton
        integer(i8) :: k, m
        integer :: status
        real(wp) :: c0, c1

        call newton%init(run)
        m = newton%steps_to(nint(run%numerics%t_final/run%numerics%dt, i8))
        call cpu_time(c0)
        do k = 1, m
            call newton%step(status)
            if (status /= 0) exit
        end do
        call cpu_time(c1)
        seconds = c1 - c0
    end function steps_cpu

    !> Processor seconds of `steps` times: sin and cos of N moving arguments (`sin_cos_array`), N divisions.
    function floor_cpu(n, steps) result(seconds)
        !> Number of sites N.
        integer, intent(in) :: n
        !> Steps.
        integer(i8), intent(in) :: steps
        real(wp) :: seconds
        real(wp), allocatable :: x(:), s(:), c(:), r(:), d(:)
        real(wp) :: checksum, c0, c1
        integer(i8) :: k
        integer :: j

        allocate (x(n), s(n), c(n), r(n), d(n))
        do j = 1, n
            x(j) = 1.9_wp*sin(0.37_wp*j)
            d(j) = 400.0_wp + 0.01_wp*j
        end do
        checksum = 0.0_wp
        call cpu_time(c0)
        do k = 1, steps
            call sin_cos_array(x, s, c)
            do j = 1, n
                r(j) = (s(j) + c(j))/d(j)
            end do
            checksum = checksum + s(n) + r(1)
            x(1) = x(1) + 1.0e-9_wp
            x(n) = x(n) - 1.0e-9_wp
        end do
        call cpu_time(c1)
        seconds = c1 - c0
        if (.not. (abs(checksum) < huge(1.0_wp))) write (*, "(a)") "floor: non-finite checksum"
    end function floor_cpu

end module bench_floor_cpu
