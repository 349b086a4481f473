!> The measurements of the scene `work_precision` (`supratrans_scene_workprec`) reduced to numbers, apart from the
!> scene's runs: the median of timed runs, the 8-point Lagrange interpolant of the reference between its levels,
!> the order fitted over the asymptotic range of errors, the stages (right-hand sides) of a step, and the timing of
!> the kernels a step cannot avoid (its lower bound: N sines, and for the implicit schemes one tridiagonal solve).
module supratrans_workprec_measure
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_nan
    use supratrans_kinds, only: wp, i8
    use supratrans_config, only: method_rk4, method_rk8
    use supratrans_tridiag, only: solve_tridiag
    use supratrans_stepper_rk8, only: rk8_stages
    implicit none
    private

    public :: median, interpolate, fitted_order, method_stages, measure_step_kernels

    !> Errors above this are pre-asymptotic and left out of the fitted orders.
    real(wp), parameter :: order_fit_ceiling = 1.0e-2_wp
    !> The fitted orders use at most this many of the smallest time steps.
    integer, parameter :: order_fit_points = 4

contains

    !> Median of a small array.
    pure function median(x) result(med)
        !> Values.
        real(wp), intent(in) :: x(:)
        real(wp) :: med
        real(wp) :: y(size(x)), t
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

    !> Value at time t of a series sampled at t_j = j h, j = 0..M (`samples(1)` is t = 0): the sample itself on a
    !> level, else the 8-point Lagrange interpolant on the levels around t (one-sided near the ends).
    pure function interpolate(samples, h, t) result(v)
        !> Samples at t_j = j h.
        real(wp), intent(in) :: samples(:)
        !> Spacing.
        real(wp), intent(in) :: h
        !> Time, 0 <= t <= (size(samples) - 1) h.
        real(wp), intent(in) :: t
        real(wp) :: v
        real(wp) :: x, w
        integer :: m, j, j0, i, k

        m = size(samples) - 1
        x = t/h
        j = nint(x)
        if (abs(x - real(j, wp)) <= 1.0e-9_wp*max(1.0_wp, abs(x))) then
            v = samples(max(0, min(j, m)) + 1)
            return
        end if
        j0 = max(0, min(floor(x) - 3, m - 7))
        v = 0.0_wp
        do i = 0, min(7, m)
            w = 1.0_wp
            do k = 0, min(7, m)
                if (k /= i) w = w*(x - real(j0 + k, wp))/real(i - k, wp)
            end do
            v = v + w*samples(j0 + i + 1)
        end do
    end function interpolate

    !> Observed order over the asymptotic range: the least-squares slope of log(error) against log(dt) over the
    !> smallest time steps, taken in increasing dt from the smallest: errors at or below `floor` (the reference's
    !> own error, roundoff) are skipped, the first error above 1e-2 (pre-asymptotic) ends the range, and at most
    !> `order_fit_points` points are used. NaN with fewer than two points.
    pure function fitted_order(dts, errors, floor) result(order)
        !> Time steps (NaN where not run).
        real(wp), intent(in) :: dts(:)
        !> Errors (NaN where not measured).
        real(wp), intent(in) :: errors(:)
        !> Errors at or below this are not used.
        real(wp), intent(in) :: floor
        real(wp) :: order
        real(wp) :: sx, sy, sxx, sxy, x, y, dt_min
        logical :: visited(size(dts))
        integer :: i, j, np

        np = 0
        sx = 0.0_wp
        sy = 0.0_wp
        sxx = 0.0_wp
        sxy = 0.0_wp
        visited = ieee_is_nan(dts) .or. ieee_is_nan(errors)
        do
            ! the smallest time step not visited yet
            i = 0
            dt_min = huge(1.0_wp)
            do j = 1, size(dts)
                if (.not. visited(j) .and. dts(j) < dt_min) then
                    dt_min = dts(j)
                    i = j
                end if
            end do
            if (i == 0) exit
            visited(i) = .true.
            if (.not. (errors(i) > floor)) cycle
            if (errors(i) > order_fit_ceiling) exit
            x = log(dts(i))
            y = log(errors(i))
            np = np + 1
            sx = sx + x
            sy = sy + y
            sxx = sxx + x*x
            sxy = sxy + x*y
            if (np == order_fit_points) exit
        end do
        order = ieee_value(1.0_wp, ieee_quiet_nan)
        if (np < 2) return
        if (real(np, wp)*sxx - sx*sx <= 0.0_wp) return
        order = (real(np, wp)*sxy - sx*sy)/(real(np, wp)*sxx - sx*sx)
    end function fitted_order

    !> Right-hand-side evaluations (N-sine kernels) of one step: 1 for the leapfrog schemes, the stages of an RK.
    pure function method_stages(method) result(stages)
        !> Method identifier.
        integer, intent(in) :: method
        integer :: stages

        select case (method)
        case (method_rk4)
            stages = 4
        case (method_rk8)
            stages = rk8_stages
        case default
            stages = 1
        end select
    end function method_stages

    !> Time the kernels a step cannot avoid, on a chain of n sites (per call, seconds, best of 7 trials):
    !> n sines of values spread over [-amplitude, amplitude]; n divisions; one tridiagonal solve (`dgtsv`, with
    !> the copies of the matrix the Newton step makes).
    subroutine measure_step_kernels(n, amplitude, t_sine, t_division, t_tridiag)
        !> Number of sites N.
        integer, intent(in) :: n
        !> Spread of the sine arguments.
        real(wp), intent(in) :: amplitude
        !> Seconds for n sines, n divisions, one solve.
        real(wp), intent(out) :: t_sine, t_division, t_tridiag
        real(wp), allocatable :: u(:), f(:), b(:), dl(:), dd(:), du(:), rhs(:)
        integer :: i, trial, rep, reps, info
        integer(i8) :: c0, c1, rate
        real(wp) :: check, t

        allocate (u(n), f(n), b(n), dl(max(n - 1, 1)), dd(n), du(max(n - 1, 1)), rhs(n))
        do i = 1, n
            u(i) = amplitude*cos(real(i, wp)*2.399963229728653_wp)    ! golden-angle spread over [-A, A]
            b(i) = 400.0_wp + real(mod(i, 7), wp)
        end do
        reps = max(1, 2000000/max(n, 1))
        check = 0.0_wp
        t_sine = huge(1.0_wp)
        t_division = huge(1.0_wp)
        t_tridiag = huge(1.0_wp)
        do trial = 1, 7
            call system_clock(c0, rate)
            do rep = 1, reps
                u(1) = u(1) + 1.0e-15_wp
                f = sin(u)
                check = check + f(n)
            end do
            call system_clock(c1)
            t = real(c1 - c0, wp)/real(rate, wp)/real(reps, wp)
            t_sine = min(t_sine, t)
            call system_clock(c0)
            do rep = 1, reps
                u(1) = u(1) + 1.0e-15_wp
                f = u/b
                check = check + f(n)
            end do
            call system_clock(c1)
            t = real(c1 - c0, wp)/real(rate, wp)/real(reps, wp)
            t_division = min(t_division, t)
            call system_clock(c0)
            do rep = 1, reps/4 + 1
                dd = b
                dl = -1.0_wp
                du = -1.0_wp
                rhs = u
                call solve_tridiag(dl, dd, du, rhs, info)
                check = check + rhs(n)
            end do
            call system_clock(c1)
            t = real(c1 - c0, wp)/real(rate, wp)/real(reps/4 + 1, wp)
            t_tridiag = min(t_tridiag, t)
        end do
        if (ieee_is_nan(check)) t_sine = -1.0_wp      ! keeps the kernels from being optimised away
    end subroutine measure_step_kernels

end module supratrans_workprec_measure
