!> The cost of a Newton site-step against the chain length N, next to what the memory system can deliver (issue 24,
!> point 3): `fpm run --example benchmark --profile release -- repeats scaling` (this part alone, after
!> `floor_cpu_benchmark`) or any run of the
!> benchmark without `fold` and `slices` (after the paper-default runs).
!>
!> 1. The machine's bandwidth: a STREAM-like triad a = b + s c on three arrays of 2^25 doubles (768 MiB in all,
!>    beyond any last-level cache measured here), one thread, 24 bytes per element (STREAM's count: no
!>    write-allocate traffic), median GB/s of `repeats` passes. Both parts are timed in processor seconds of the
!>    process (one thread: the time the shared machine gives to other jobs is not counted).
!> 2. The Newton steps alone (the stepper without the run engine's observers, start-up excluded: the state is set,
!>    one step is taken untimed) of the paper's chain (sine-Gordon, dt = 0.05, beta = 0, N0 = 3N/4) at
!>    N = 10^3 .. 10^7, one thread, about 10^7 site-steps per timing, median of `repeats` timings (3 .. 7):
!>    nanoseconds per
!>    site-step, Newton iterations per step, the bytes the step's loops move per site (`step_bytes`), the bandwidth
!>    that is (bytes / time) and its share of the triad's, and the cost relative to N = 10^3 (the issue's goal:
!>    N = 10^6 within 1.2 times N = 10^3). Every level starts on a travelling wave u_n = sin(q n - w t) of unit
!>    amplitude (q = 0.5, w from the linear dispersion), so that every site takes the full argument reduction of
!>    the sines, as in the driven part of a run, whatever N (a chain at rest would be the cheap quiet tail).
!>
!> The rows are also written as CSV (`scaling_csv`, read by `postprocess/site_cost.py` for the figure).
module bench_scaling
    use supratrans_kinds, only: wp, i8
    use supratrans_strings, only: int_str
    use supratrans_config, only: run_config, method_newton
    use supratrans_stepper_newton, only: newton_stepper, newton_block
    use supratrans_workprec_measure, only: median
    use bench_floor_cpu, only: floor_cpu_benchmark
    !$ use omp_lib, only: omp_set_num_threads
    implicit none
    private

    public :: scaling_benchmark, scaling_alone, step_bytes

    !> Where the rows go (relative to the working directory, the repository's root for `fpm run`).
    character(len=*), parameter, public :: scaling_csv = "postprocess/data/site_cost.csv"
    !> Chain lengths timed.
    integer, parameter :: sizes(5) = [1000, 10000, 100000, 1000000, 10000000]
    !> Share of the chain before its absorber (N0 = 3N/4 in `site_step_cost`), counted in `step_bytes`.
    real(wp), parameter :: uniform_share = 0.75_wp
    !> Site-steps per timing (the steps are this over N, at least 3).
    real(wp), parameter :: site_steps = 1.0e7_wp
    !> Elements of each triad array (2^25: 256 MiB an array).
    integer, parameter :: triad_n = 2**25

contains

    !> `floor_cpu_benchmark` and `scaling_benchmark` alone, then stop, when the second argument of the benchmark is
    !> `scaling`; `floor_cpu_benchmark` alone when it is `cpu`.
    subroutine scaling_alone(repeats)
        !> Timings per point (the medians are over these).
        integer, intent(in) :: repeats
        character(len=32) :: arg

        if (command_argument_count() < 2) return
        call get_command_argument(2, arg)
        if (trim(arg) /= "scaling" .and. trim(arg) /= "cpu") return
        call floor_cpu_benchmark(repeats)
        if (trim(arg) == "scaling") call scaling_benchmark(repeats)
        stop
    end subroutine scaling_alone

    !> Bytes the Newton step's loops read and write per site (8 bytes per array element touched, each array counted
    !> once per loop, as STREAM counts) for a step of `iterations` iterations, beta = 0, sine-Gordon, on N sites.
    !> Before the iterations, on a chain of one block, 13 arrays (the predictor: 7 levels read, the new level
    !> written; the right-hand side: 2 levels, e_n and the new level read, the right-hand side written); on a longer
    !> chain 10, in one pass (`predict_with_rhs`: 7 levels and e_n read, the new level and the right-hand side
    !> written; the right-hand side's 2 levels are among the 7). Each iteration runs its loops block by
    !> block (`newton_block` sites); within a block the arrays it writes and reads again stay in the cache, so that
    !> through memory the first iteration streams 8 (2 levels, b_n and the right-hand side read; the new level, the
    !> update, sin and cos written) and every later one 11 (the update, sin, cos, 2 levels, b_n and the right-hand
    !> side read; sin, cos, the new level and the update written). On a chain of one block (N <= `newton_block`)
    !> every loop runs over the whole chain, as counted here by the loops: 20 in the first iteration (s: 3; sin and
    !> cos: 3; G and dG/da: 6; the update: 8) and 17 in each later one (G, dG/da and the rotation: 9; the update: 8).
    !> On a longer chain, the whole blocks before the absorber (`absorber_first`; here the chain's first 3/4 at least)
    !> take b_n from a register: one array less in every iteration there.
    pure function step_bytes(iterations, n) result(bytes)
        !> Newton iterations per step (a mean).
        real(wp), intent(in) :: iterations
        !> Number of sites N.
        integer, intent(in) :: n
        real(wp) :: bytes

        if (n <= newton_block) then
            bytes = 8.0_wp*(13.0_wp + 20.0_wp + 17.0_wp*max(iterations - 1.0_wp, 0.0_wp))
        else
            bytes = 8.0_wp*(10.0_wp + 8.0_wp + 11.0_wp*max(iterations - 1.0_wp, 0.0_wp) &
                            - uniform_share*max(iterations, 1.0_wp))
        end if
    end function step_bytes

    !> The triad bandwidth, then the site-step cost at every N of `sizes`; printed and written to `scaling_csv`.
    subroutine scaling_benchmark(repeats)
        !> Timings per point.
        integer, intent(in) :: repeats
        real(wp) :: triad_gbs, ns(size(sizes)), iters(size(sizes)), bytes, gbs
        integer :: k, unit, stat, timings

        !$ call omp_set_num_threads(1)
        timings = min(max(repeats, 3), 7)
        triad_gbs = triad_bandwidth(timings)
        write (*, "(a)") "# site-step cost against N: newton steps alone, one thread, start-up excluded"
        write (*, "(a, f8.2, a)") "# triad bandwidth (a = b + s c, 3 x 256 MiB, 24 B/element): ", triad_gbs, " GB/s"
        write (*, "(a10, 2x, a10, 2x, a10, 2x, a10, 2x, a10, 2x, a10, 2x, a10)") "N", "ns/site", "iter/step", &
            "B/site", "GB/s", "/triad", "/N=1e3"
        do k = 1, size(sizes)
            call site_step_cost(sizes(k), timings, ns(k), iters(k))
            bytes = step_bytes(iters(k), sizes(k))
            gbs = bytes/ns(k)
            write (*, "(i10, 2x, f10.3, 2x, f10.4, 2x, f10.1, 2x, f10.2, 2x, f10.3, 2x, f10.3)") sizes(k), ns(k), &
                iters(k), bytes, gbs, gbs/triad_gbs, ns(k)/ns(1)
        end do
        open (newunit=unit, file=scaling_csv, status="replace", action="write", iostat=stat)
        if (stat /= 0) then
            write (*, "(a)") "# cannot write " // scaling_csv
            return
        end if
        write (unit, "(a)") "n,ns_per_site_step,iterations_per_step,bytes_per_site_step,gb_per_s,triad_gb_per_s"
        do k = 1, size(sizes)
            write (unit, "(i0, 5(',', es14.6))") sizes(k), ns(k), iters(k), step_bytes(iters(k), sizes(k)), &
                step_bytes(iters(k), sizes(k))/ns(k), triad_gbs
        end do
        close (unit)
        write (*, "(a)") "# written to " // scaling_csv
    end subroutine scaling_benchmark

    !> Median GB/s of a triad a = b + s c over `repeats` passes (after one untimed pass that touches the pages).
    function triad_bandwidth(repeats) result(gbs)
        !> Timed passes.
        integer, intent(in) :: repeats
        real(wp) :: gbs
        real(wp), allocatable :: a(:), b(:), c(:), t(:)
        real(wp) :: s
        integer :: r, j, stat

        allocate (t(repeats))
        allocate (a(triad_n), stat=stat)
        if (stat == 0) allocate (b(triad_n), stat=stat)
        if (stat == 0) allocate (c(triad_n), stat=stat)
        if (stat /= 0) then
            write (*, "(a)") "# triad: cannot allocate 768 MiB"
            gbs = 0.0_wp
            return
        end if
        do j = 1, triad_n
            b(j) = real(j, wp)
            c(j) = 1.0_wp/real(j, wp)
        end do
        s = 3.0_wp
        do r = 0, repeats
            if (r > 0) t(r) = cpu_seconds()
            do j = 1, triad_n
                a(j) = b(j) + s*c(j)
            end do
            if (r > 0) t(r) = cpu_seconds() - t(r)
            s = s + a(triad_n/2)*1.0e-30_wp        ! a depends on the previous pass: none is skipped
        end do
        gbs = 24.0_wp*real(triad_n, wp)/median(t)/1.0e9_wp
        if (.not. (abs(s) < huge(s))) write (*, "(a)") "triad: non-finite"
    end function triad_bandwidth

    !> Median nanoseconds per site-step and mean Newton iterations per step of the newton stepper on N sites.
    subroutine site_step_cost(n, repeats, ns, iterations)
        !> Number of sites N.
        integer, intent(in) :: n
        !> Timings.
        integer, intent(in) :: repeats
        !> Median ns per site-step.
        real(wp), intent(out) :: ns
        !> Newton iterations per step over the timed steps.
        real(wp), intent(out) :: iterations
        type(run_config) :: run
        type(newton_stepper) :: newton
        real(wp), allocatable :: t(:)
        real(wp) :: q, w
        integer(i8) :: k, m, iter0, steps0
        integer :: r, l, j, status

        run%numerics%method = method_newton
        run%numerics%dt = 0.05_wp
        run%drive%amplitude = 1.9_wp
        run%drive%omega = 0.9_wp
        run%chain%n = n
        run%chain%n0 = 3*(n/4)
        call newton%init(run)
        if (allocated(newton%reason)) then
            write (*, "(a)") "# N = " // int_str(n) // ": " // newton%reason
            ns = huge(ns)
            iterations = 0.0_wp
            return
        end if
        q = 0.5_wp
        w = sqrt(1.0_wp + 4.0_wp*run%chain%c**2*sin(0.5_wp*q)**2)
        do l = 1, newton%levels - 1                 ! column col(l) holds the level at t = -(l - 1) dt
            do j = 1, n
                newton%u(j, newton%col(l)) = sin(q*real(j, wp) + w*real(l - 1, wp)*run%numerics%dt)
            end do
        end do
        m = max(3_i8, nint(site_steps/real(n, wp), i8))
        allocate (t(repeats))
        call newton%step(status)                    ! first touch of the work arrays, untimed
        iter0 = newton%newton_iterations
        steps0 = newton%steps
        do r = 1, repeats
            t(r) = cpu_seconds()
            do k = 1, m
                call newton%step(status)
                if (status /= 0) exit
            end do
            t(r) = cpu_seconds() - t(r)
            if (status /= 0) then
                write (*, "(a)") "# N = " // int_str(n) // ": " // newton%reason
                exit
            end if
        end do
        ns = 1.0e9_wp*median(t)/(real(m, wp)*real(n, wp))
        iterations = real(newton%newton_iterations - iter0, wp)/real(max(newton%steps - steps0, 1_i8), wp)
    end subroutine site_step_cost


    !> Processor seconds of this process since an arbitrary origin (one thread runs here: unlike the wall clock,
    !> they do not count the time the shared machine gives to other jobs).
    function cpu_seconds() result(t)
        real(wp) :: t

        call cpu_time(t)
    end function cpu_seconds

end module bench_scaling
