!> Higher-order reference integrator: the explicit eighth-order, eleven-stage Runge-Kutta method of Cooper and
!> Verner on the same method-of-lines system as `supratrans_rk4` (same right-hand side `rk4_rhs`, same four
!> energy components integrated as extra ODE components, same records and observers), with a fixed step.
!>
!> Tableau: G. J. Cooper and J. H. Verner, "Some explicit Runge-Kutta methods of high order", SIAM J. Numer.
!> Anal. 9 (1972) 389-405 (the 11-stage order-8 formula built on the 5-point Lobatto rule; nodes 0,
!> (7 -+ sqrt 21)/14, 1/2, 1; weights 1/20, 49/180, 16/45, 49/180, 1/20). The coefficients below were transcribed
!> from the published formula and checked independently: in 40-digit arithmetic they satisfy all 200 order
!> conditions up to order 8 (rooted trees with up to 8 nodes) to 4e-41 and violate those of order 9.
!>
!> Why this method (measured on the paper-default run, sine-Gordon, Omega = 0.9, A = 1.9, N = 200, T = 200; scene
!> `work_precision`): a step costs its stages' right-hand sides (N sines each) plus the stage combinations. For a
!> relative error of 1e-8 in the injected energy RK4 needs dt = 0.00625 (32 000 steps, 128 000 right-hand sides,
!> 0.19 s), Butcher's 7-stage sixth-order method dt = 0.0625 (22 400 right-hand sides, 0.05 s), this method
!> dt = 0.2 (11 000 right-hand sides, 0.017 s). Its stability interval on the imaginary axis is |y| <= 3.0018
!> (RK4: 2.8284): for the undamped chain at c = 4 it is stable for dt < 3.0018 / sqrt(1 + m^2 + 4 c^2) = 0.372
!> (RK4: 0.351), and its stability function damps oscillations near the axis (|R(iy)|^2 = 1 - 4.9e-5 y^10 + ...),
!> whereas Butcher's sixth-order method amplifies every one (|R(iy)|^2 = 1 + 1.3e-3 y^8 + ...: it blows up at
!> c = 4 for dt >= 0.2).
!>
!> The drive psi(t) = A r(t) sin(Omega t) has a kink at t = ramp_time, where r' jumps. A one-step method keeps its
!> order only when the kink falls on a step boundary (ramp_time / dt an integer); each stage then takes the
!> one-sided psi' of its own step (`drive_dpsi` with the step's midpoint). If ramp_time / dt is not an integer
!> the step that contains the kink integrates across a jump of psi' and the observed order collapses to about 1
!> (measured 0.7 to 0.9; test `test_rk8_order_collapses_at_off_grid_kink`).
module supratrans_rk_high
    use supratrans_kinds, only: wp, i8
    use supratrans_config, only: run_config
    use supratrans_chain, only: damping_profile, drive_psi, detector_site
    use supratrans_ledger, only: ledger_type, ledger_close
    use supratrans_result, only: run_result, run_ok, init_records, record_ledger, record_probes, check_blowup, &
                                 observe_detector, close_verdict
    use supratrans_rk4, only: rk4_rhs, drive_dpsi, chain_energy, ledger_from_state, rk4_energy_components
    implicit none
    private

    public :: simulate_rk8, rk8_stability_coefficients

    !> Number of stages (right-hand-side evaluations) of one step.
    integer, parameter, public :: rk8_stages = 11
    !> Classical order of the method.
    integer, parameter, public :: rk8_order = 8
    !> Stability interval on the imaginary axis: |R(iy)| <= 1 for |y| <= this (computed from the stability
    !> polynomial to 1e-7; RK4's is 2 sqrt(2) = 2.8284).
    real(wp), parameter, public :: rk8_imaginary_limit = 3.0017836_wp

    real(wp), parameter :: s21 = sqrt(21.0_wp)
    ! nodes c_i
    real(wp), parameter :: c2 = 0.5_wp, c3 = 0.5_wp, c4 = (7.0_wp + s21)/14.0_wp, c5 = (7.0_wp + s21)/14.0_wp, &
                           c6 = 0.5_wp, c7 = (7.0_wp - s21)/14.0_wp, c8 = (7.0_wp - s21)/14.0_wp, c9 = 0.5_wp, &
                           c10 = (7.0_wp + s21)/14.0_wp, c11 = 1.0_wp
    ! coupling coefficients a_ij (those not listed are zero)
    real(wp), parameter :: a21 = 0.5_wp
    real(wp), parameter :: a31 = 0.25_wp, a32 = 0.25_wp
    real(wp), parameter :: a41 = 1.0_wp/7.0_wp, a42 = (-7.0_wp - 3.0_wp*s21)/98.0_wp, a43 = (21.0_wp + 5.0_wp*s21)/49.0_wp
    real(wp), parameter :: a51 = (11.0_wp + s21)/84.0_wp, a53 = (18.0_wp + 4.0_wp*s21)/63.0_wp, &
                           a54 = (21.0_wp - s21)/252.0_wp
    real(wp), parameter :: a61 = (5.0_wp + s21)/48.0_wp, a63 = (9.0_wp + s21)/36.0_wp, &
                           a64 = (-231.0_wp + 14.0_wp*s21)/360.0_wp, a65 = (63.0_wp - 7.0_wp*s21)/80.0_wp
    real(wp), parameter :: a71 = (10.0_wp - s21)/42.0_wp, a73 = (-432.0_wp + 92.0_wp*s21)/315.0_wp, &
                           a74 = (633.0_wp - 145.0_wp*s21)/90.0_wp, a75 = (-504.0_wp + 115.0_wp*s21)/70.0_wp, &
                           a76 = (63.0_wp - 13.0_wp*s21)/35.0_wp
    real(wp), parameter :: a81 = 1.0_wp/14.0_wp, a85 = (14.0_wp - 3.0_wp*s21)/126.0_wp, &
                           a86 = (13.0_wp - 3.0_wp*s21)/63.0_wp, a87 = 1.0_wp/9.0_wp
    real(wp), parameter :: a91 = 1.0_wp/32.0_wp, a95 = (91.0_wp - 21.0_wp*s21)/576.0_wp, a96 = 11.0_wp/72.0_wp, &
                           a97 = (-385.0_wp - 75.0_wp*s21)/1152.0_wp, a98 = (63.0_wp + 13.0_wp*s21)/128.0_wp
    real(wp), parameter :: a101 = 1.0_wp/14.0_wp, a105 = 1.0_wp/9.0_wp, a106 = (-733.0_wp - 147.0_wp*s21)/2205.0_wp, &
                           a107 = (515.0_wp + 111.0_wp*s21)/504.0_wp, a108 = (-51.0_wp - 11.0_wp*s21)/56.0_wp, &
                           a109 = (132.0_wp + 28.0_wp*s21)/245.0_wp
    real(wp), parameter :: a115 = (-42.0_wp + 7.0_wp*s21)/18.0_wp, a116 = (-18.0_wp + 28.0_wp*s21)/45.0_wp, &
                           a117 = (-273.0_wp - 53.0_wp*s21)/72.0_wp, a118 = (301.0_wp + 53.0_wp*s21)/72.0_wp, &
                           a119 = (28.0_wp - 28.0_wp*s21)/45.0_wp, a1110 = (49.0_wp - 7.0_wp*s21)/18.0_wp
    ! weights b_i (b_2 .. b_7 are zero)
    real(wp), parameter :: b1 = 1.0_wp/20.0_wp, b8 = 49.0_wp/180.0_wp, b9 = 16.0_wp/45.0_wp, b10 = 49.0_wp/180.0_wp, &
                           b11 = 1.0_wp/20.0_wp

    !> The whole tableau as a dense strictly lower-triangular matrix A(i, j) (for the stability polynomial).
    real(wp), parameter :: tableau_a(rk8_stages, rk8_stages) = reshape([ &
        0.0_wp, a21, a31, a41, a51, a61, a71, a81, a91, a101, 0.0_wp, &
        0.0_wp, 0.0_wp, a32, a42, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, &
        0.0_wp, 0.0_wp, 0.0_wp, a43, a53, a63, a73, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, &
        0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, a54, a64, a74, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, &
        0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, a65, a75, a85, a95, a105, a115, &
        0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, a76, a86, a96, a106, a116, &
        0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, a87, a97, a107, a117, &
        0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, a98, a108, a118, &
        0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, a109, a119, &
        0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, a1110, &
        0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
        [rk8_stages, rk8_stages])
    !> The weights as a vector.
    real(wp), parameter :: tableau_b(rk8_stages) = [b1, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, b8, b9, b10, b11]

contains

    !> Simulate one run with the eighth-order Cooper-Verner method (same contract and records as `simulate_rk4`):
    !> probes at t_k = k dt every `probe_every` steps (sample 1 at t = 0), the ledger at t_k every `ledger_every`
    !> steps and at the end, the continuous energy H of `chain_energy`, M = nint(T/dt) steps. `newton_iterations`
    !> counts right-hand-side evaluations (11 a step; `newton_max_iterations` = 11). A blow-up (|u_n| above
    !> `blowup_threshold`, or a non-finite value) ends the run with status `run_diverged` and a reason.
    subroutine simulate_rk8(run, result)
        !> Validated run configuration (`run%numerics%method` is not consulted).
        type(run_config), intent(in) :: run
        !> Outcome, statistics, ledger and records.
        type(run_result), intent(out) :: result
        type(ledger_type) :: ledger
        real(wp), allocatable :: alpha(:), y(:), ys(:), k(:, :)
        integer :: n, ny, m, step, ledger_every, probe_every, nd
        integer(i8) :: clock_start, clock_end, clock_rate
        real(wp) :: dt, t0, th, t1, umax
        logical :: stop

        call system_clock(clock_start, clock_rate)
        n = run%chain%n
        ny = 2*n + rk4_energy_components
        dt = run%numerics%dt
        m = nint(run%numerics%t_final/dt)
        ledger_every = run%record%ledger_every
        probe_every = run%record%probe_every

        call init_records(result, run%record, m)

        ! work arrays, allocated once; the chain starts at rest
        alpha = damping_profile(run%chain)
        allocate (y(ny), source=0.0_wp)
        allocate (ys(ny), k(ny, rk8_stages))

        call record_probes(result, 0.0_wp, drive_psi(run%drive, 0.0_wp), y(1:n))
        call ledger_close(ledger, chain_energy(run%chain, drive_psi(run%drive, 0.0_wp), y))
        call record_ledger(result, ledger, 0.0_wp)

        result%status = run_ok
        result%steps = 0
        nd = detector_site(run)
        result%detect_site = nd
        do step = 1, m
            t0 = real(step - 1, wp)*dt
            th = (real(step, wp) - 0.5_wp)*dt
            t1 = real(step, wp)*dt
            call rk8_step()
            result%steps = step

            umax = maxval(abs(y(1:n)))
            if (.not. (maxval(abs(y(n + 1:2*n))) <= huge(1.0_wp))) umax = huge(1.0_wp)   ! non-finite velocity
            call check_blowup(result, umax, run%numerics%blowup_threshold, t1, stop)
            if (stop) exit

            call ledger_from_state(ledger, y(2*n + 1:))
            if (mod(step, ledger_every) == 0) then
                call ledger_close(ledger, chain_energy(run%chain, drive_psi(run%drive, t1), y))
                call record_ledger(result, ledger, t1)
            end if
            if (mod(step, probe_every) == 0) call record_probes(result, t1, drive_psi(run%drive, t1), y(1:n))
            call observe_detector(result, run%detect, nd, maxval(abs(y(nd + 1:n))), t1, stop)
            if (stop) exit
        end do
        result%t_end = real(result%steps, wp)*dt
        call close_verdict(result, run%detect)
        if (result%status == run_ok .and. mod(result%steps, ledger_every) /= 0 .and. result%steps > 0) then
            call ledger_close(ledger, chain_energy(run%chain, drive_psi(run%drive, result%t_end), y))
            call record_ledger(result, ledger, result%t_end)
        end if
        result%ledger = ledger
        result%newton_iterations = int(rk8_stages, i8)*int(result%steps, i8)
        if (result%steps > 0) result%newton_max_iterations = rk8_stages
        call system_clock(clock_end)
        result%wall_time = real(clock_end - clock_start, wp)/real(clock_rate, wp)

    contains

        !> One step from t0 to t0 + dt: y is overwritten by the new state.
        subroutine rk8_step()
            real(wp) :: h

            h = dt
            call stage(1, 0.0_wp, y)
            ys = y + h*a21*k(:, 1)
            call stage(2, c2, ys)
            ys = y + h*(a31*k(:, 1) + a32*k(:, 2))
            call stage(3, c3, ys)
            ys = y + h*(a41*k(:, 1) + a42*k(:, 2) + a43*k(:, 3))
            call stage(4, c4, ys)
            ys = y + h*(a51*k(:, 1) + a53*k(:, 3) + a54*k(:, 4))
            call stage(5, c5, ys)
            ys = y + h*(a61*k(:, 1) + a63*k(:, 3) + a64*k(:, 4) + a65*k(:, 5))
            call stage(6, c6, ys)
            ys = y + h*(a71*k(:, 1) + a73*k(:, 3) + a74*k(:, 4) + a75*k(:, 5) + a76*k(:, 6))
            call stage(7, c7, ys)
            ys = y + h*(a81*k(:, 1) + a85*k(:, 5) + a86*k(:, 6) + a87*k(:, 7))
            call stage(8, c8, ys)
            ys = y + h*(a91*k(:, 1) + a95*k(:, 5) + a96*k(:, 6) + a97*k(:, 7) + a98*k(:, 8))
            call stage(9, c9, ys)
            ys = y + h*(a101*k(:, 1) + a105*k(:, 5) + a106*k(:, 6) + a107*k(:, 7) + a108*k(:, 8) + a109*k(:, 9))
            call stage(10, c10, ys)
            ys = y + h*(a115*k(:, 5) + a116*k(:, 6) + a117*k(:, 7) + a118*k(:, 8) + a119*k(:, 9) + a1110*k(:, 10))
            call stage(11, c11, ys)
            y = y + h*(b1*(k(:, 1) + k(:, 11)) + b8*(k(:, 8) + k(:, 10)) + b9*k(:, 9))
        end subroutine rk8_step

        !> Stage i: k(:, i) = f(t0 + c dt, state), with the one-sided psi' of this step at the ramp's kink.
        subroutine stage(i, c, state)
            integer, intent(in) :: i
            real(wp), intent(in) :: c
            real(wp), intent(in) :: state(:)
            real(wp) :: t

            t = t0 + c*dt
            call rk4_rhs(run%chain, alpha, drive_psi(run%drive, t), drive_dpsi(run%drive, t, th), state, k(:, i))
        end subroutine stage


    end subroutine simulate_rk8

    !> Coefficients g_0..g_11 of the method's stability polynomial R(z) = sum_j g_j z^j (R(z) = 1 + z b^T
    !> (I - z A)^{-1} 1, a polynomial because A is strictly lower triangular: g_j = b^T A^{j-1} 1).
    pure function rk8_stability_coefficients() result(g)
        real(wp) :: g(0:rk8_stages)
        real(wp) :: v(rk8_stages)
        integer :: j

        g(0) = 1.0_wp
        v = 1.0_wp
        do j = 1, rk8_stages
            g(j) = dot_product(tableau_b, v)
            v = matmul(tableau_a, v)
        end do
    end function rk8_stability_coefficients

end module supratrans_rk_high
