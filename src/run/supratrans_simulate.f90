!> One run: the time loop of the paper's schemes, the energy ledger and the probes.
!>
!> The chain starts at rest, u^0 = u^1 = 0 (phi = varphi = 0), and the driven end follows u_0^k = psi(t_k).
!> Step k (k = 1 .. M-1, M = nint(T/dt)) computes u^{k+1} from u^k and u^{k-1}. All state lives in local
!> variables and in the result, so any number of runs can proceed at once in different threads.
module supratrans_simulate
    use supratrans_kinds, only: wp, i8
    use supratrans_strings, only: int_fixed, real_fixed
    use supratrans_config, only: run_config, method_newton, method_linearized, method_rk4, method_rk8
    use supratrans_rk_high, only: simulate_rk8
    use supratrans_rk4, only: simulate_rk4
    use supratrans_chain, only: drive_psi, detector_site
    use supratrans_scheme, only: scheme_type, scheme_init
    use supratrans_newton, only: newton_step, newton_ok, newton_not_converged
    use supratrans_linearized, only: linearized_step
    use supratrans_ledger, only: ledger_type, stored_energy, step_powers, ledger_add_step, ledger_close
    use supratrans_result, only: run_result, run_ok, run_diverged, run_newton_failed, run_solver_failed, init_records, &
                                 record_ledger, record_probes, observe_ramp, check_blowup, observe_detector, close_verdict
    implicit none
    private

    public :: simulate, number_of_levels

contains

    !> Number of time levels M + 1 of a run (levels t_0 .. t_M, M = nint(T/dt)).
    pure function number_of_levels(run) result(levels)
        !> Run configuration.
        type(run_config), intent(in) :: run
        integer :: levels

        levels = nint(run%numerics%t_final/run%numerics%dt) + 1
    end function number_of_levels

    !> Simulate one run of the energy-conserving or the linearized scheme (RK4 runs are handed to `simulate_rk4`).
    subroutine simulate(run, result)
        !> Validated run configuration.
        type(run_config), intent(in) :: run
        !> Outcome, statistics, ledger and records.
        type(run_result), intent(out) :: result
        type(scheme_type) :: scheme
        type(ledger_type) :: ledger
        real(wp), allocatable :: u(:, :)
        integer :: n, m, k, io2, io, ic, inew, itmp, iters, status, info
        integer :: ledger_every, probe_every
        integer(i8) :: clock_start, clock_end, clock_rate
        real(wp) :: dt, p_in, d_gamma, d_beta, d_abs, t_new
        logical :: halt
        integer :: nd

        if (run%numerics%method == method_rk4) then
            call simulate_rk4(run, result)
            return
        end if
        if (run%numerics%method == method_rk8) then
            call simulate_rk8(run, result)
            return
        end if
        call system_clock(clock_start, clock_rate)
        n = run%chain%n
        dt = run%numerics%dt
        m = number_of_levels(run) - 1
        ledger_every = run%record%ledger_every
        probe_every = run%record%probe_every
        call scheme_init(scheme, run%chain, dt)

        call init_records(result, run%record, m)

        ! levels 0 and 1: at rest, boundary from the drive
        allocate (u(0:n + 1, 4), source=0.0_wp)
        io2 = 4
        io = 1
        ic = 2
        inew = 3
        u(0, io) = drive_psi(run%drive, 0.0_wp)
        u(0, ic) = drive_psi(run%drive, dt)
        call record_probes(result, 0.0_wp, u(0, io), u(1:n, io))
        if (probe_every == 1) call record_probes(result, dt, u(0, ic), u(1:n, ic))
        call ledger_close(ledger, stored_energy(scheme, run%chain%m2, u(:, ic), u(:, io)))
        call record_ledger(result, ledger, 0.5_wp*dt)

        result%status = run_ok
        result%steps = 0
        nd = detector_site(run)
        result%detect_site = nd
        halt = .false.
        do k = 1, m - 1
            u(0, inew) = drive_psi(run%drive, real(k + 1, wp)*dt)
            u(n + 1, inew) = 0.0_wp
            select case (run%numerics%method)
            case (method_newton)
                call newton_step(scheme, u(:, io2), u(:, io), u(:, ic), u(:, inew), run%numerics%newton_tol, &
                                 run%numerics%newton_max_iter, iters, status)
                result%newton_iterations = result%newton_iterations + iters
                result%newton_max_iterations = max(result%newton_max_iterations, iters)
                if (status /= newton_ok) then
                    if (status == newton_not_converged) then
                        result%status = run_newton_failed
                        result%reason = "Newton did not converge in " // trim(int_fixed(iters)) &
                            // " iterations at t = " &
                                        // trim(real_fixed(real(k + 1, wp)*dt))
                    else
                        result%status = run_diverged
                        result%reason = "Newton broke down (non-finite or singular) at t = " &
                            // trim(real_fixed(real(k + 1, wp)*dt))
                    end if
                    exit
                end if
            case (method_linearized)
                call linearized_step(scheme, u(:, io), u(:, ic), u(:, inew), info)
                result%newton_iterations = result%newton_iterations + 1
                result%newton_max_iterations = 1
                if (info /= 0) then
                    result%status = run_solver_failed
                    result%reason = "dgtsv failed (info = " // trim(int_fixed(info)) // ") at t = " &
                        // trim(real_fixed(real(k + 1, wp)*dt))
                    exit
                end if
            case default
                result%status = run_solver_failed
                result%reason = "unknown method " // trim(int_fixed(run%numerics%method))
                exit
            end select
            result%steps = k
            t_new = real(k + 1, wp)*dt
            call check_blowup(result, maxval(abs(u(1:n, inew))), run%numerics%blowup_threshold, t_new, halt)
            if (halt) exit

            call step_powers(scheme, run%chain%gamma, run%chain%beta, u(:, io), u(:, ic), u(:, inew), &
                             p_in, d_gamma, d_beta, d_abs)
            call ledger_add_step(ledger, dt, p_in, d_gamma, d_beta, d_abs)
            ! the ledger now sums the powers P_1 .. P_k, i.e. over [t_{1/2}, t_{k+1/2}]
            call observe_ramp(result, ledger%injected, (real(k, wp) + 0.5_wp)*dt, run%drive%ramp_time)
            if (mod(k, ledger_every) == 0) then
                call ledger_close(ledger, stored_energy(scheme, run%chain%m2, u(:, inew), u(:, ic)))
                call record_ledger(result, ledger, (real(k, wp) + 0.5_wp)*dt)
            end if
            if (mod(k + 1, probe_every) == 0) call record_probes(result, t_new, u(0, inew), u(1:n, inew))
            call observe_detector(result, run%detect, nd, maxval(abs(u(nd + 1:n, inew))), t_new, halt)

            ! rotate the levels: k-1 -> k-2, k -> k-1, k+1 -> k
            itmp = io2
            io2 = io
            io = ic
            ic = inew
            inew = itmp
            if (halt) exit
        end do
        result%t_end = real(result%steps + 1, wp)*dt
        call close_verdict(result, run%detect)
        if (result%status == run_ok .and. mod(result%steps, ledger_every) /= 0 .and. result%steps > 0) then
            ! close the ledger on the last step taken (levels `io` = k and `ic` = k+1 after the rotation)
            call ledger_close(ledger, stored_energy(scheme, run%chain%m2, u(:, ic), u(:, io)))
            call record_ledger(result, ledger, (real(result%steps, wp) + 0.5_wp)*dt)
        end if
        result%ledger = ledger
        call system_clock(clock_end)
        result%wall_time = real(clock_end - clock_start, wp)/real(clock_rate, wp)

    end subroutine simulate


end module supratrans_simulate
