!> Reference integrator: classical fourth-order Runge-Kutta (RK4) on the method-of-lines system of the paper's
!> chain (eq. 1 on N sites, Sec. 3.1), with the same drive and absorbing end as the finite-difference schemes.
!>
!> For n = 1..N, with u_0(t) = psi(t) = A r(t) sin(Omega t) and u_{N+1} = 0,
!>
!>     u_n'' = (c^2 + beta d/dt)(u_{n+1} - 2 u_n + u_{n-1}) - alpha_n u_n' - m^2 u_n - V'(u_n),
!>
!> alpha_n = gamma + gamma'(n). The state is (u, v) of size 2N, the chain starts at rest at t = 0 and
!> M = nint(T/dt) steps are taken, as in the other schemes. The boundary velocity is
!> v_0 = psi'(t) = A [r'(t) sin(Omega t) + r(t) Omega cos(Omega t)], r' = 1/ramp_time for t < ramp_time and
!> 0 after; at the ramp's kink each stage takes the one-sided value of the step it belongs to, so a ramp that
!> ends on a time level keeps the method fourth-order.
!>
!> Energy (continuous; RK4 does not conserve it, the ledger measures its drift):
!>
!>     H = sum_{n=1}^{N} [v_n^2/2 + m^2 u_n^2/2 + V(u_n)] + c^2/2 sum_{n=0}^{N} (u_{n+1} - u_n)^2,
!>     dH/dt = P - D^gamma - D^beta - D^abs,
!>     P = c^2 (u_0 - u_1) psi' + beta (psi' - v_1) psi',   D^gamma = gamma sum v_n^2,
!>     D^abs = sum gamma'(n) v_n^2,   D^beta = beta sum_{n=1}^{N+1} (v_n - v_{n-1})^2,  v_0 = psi', v_{N+1} = 0.
!>
!> The four cumulative energies (injected, dissipated by gamma, by beta, by the absorber) are integrated as
!> four extra ODE components with the same RK4 stages, so they are fourth-order accurate and the ledger
!> residual H(t) - H(0) - (injected - dissipated) is the method's O(dt^4) energy drift, not a quadrature error.
!>
!> The transmission verdict uses the same detector as the other schemes (`detector_site` of `supratrans_chain`);
!> `simulate` of `supratrans_simulate` hands `method_rk4` runs to `simulate_rk4`.
module supratrans_rk4
    use supratrans_kinds, only: wp, i8
    use supratrans_config, only: run_config, chain_params, drive_params
    use supratrans_chain, only: damping_profile, drive_psi, ramp_factor, detector_site
    use supratrans_potential, only: force_array, potential_v
    use supratrans_ledger, only: ledger_type, ledger_close
    use supratrans_result, only: run_result, run_ok, init_records, record_ledger, record_probes, observe_ramp, check_blowup, &
                                 observe_detector, close_verdict
    implicit none
    private

    public :: simulate_rk4, simulate_explicit_rk, rk_stage, rk4_rhs, drive_dpsi, chain_energy, ledger_from_state

    !> Number of energy components appended to the state (u, v): injected, dissipated by gamma, by beta, by the
    !> absorber, in this order (the order of `ledger_columns` 2..5).
    integer, parameter, public :: rk4_energy_components = 4

contains

    !> Simulate one run with classical RK4 (same contract as `simulate`; see `simulate_explicit_rk`).
    subroutine simulate_rk4(run, result)
        !> Validated run configuration (`run%numerics%method` is not consulted).
        type(run_config), intent(in) :: run
        !> Outcome, statistics, ledger and records.
        type(run_result), intent(out) :: result

        call simulate_explicit_rk(run, result, 4, rk4_step)
    end subroutine simulate_rk4

    !> One classical RK4 step from t0 to t0 + dt: `y` is overwritten by the new state.
    pure subroutine rk4_step(chain, drive, alpha, t0, dt, y, ys, k)
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        !> Drive parameters.
        type(drive_params), intent(in) :: drive
        !> Site damping alpha_n.
        real(wp), intent(in) :: alpha(:)
        !> Start of the step and step size.
        real(wp), intent(in) :: t0, dt
        !> State (u, v, energies), advanced in place.
        real(wp), intent(inout) :: y(:)
        !> Work: stage state.
        real(wp), intent(inout) :: ys(:)
        !> Work: stage derivatives, (size(y), 4).
        real(wp), intent(inout) :: k(:, :)

        call rk_stage(chain, drive, alpha, t0, dt, 0.0_wp, y, k(:, 1))
        ys = y + (0.5_wp*dt)*k(:, 1)
        call rk_stage(chain, drive, alpha, t0, dt, 0.5_wp, ys, k(:, 2))
        ys = y + (0.5_wp*dt)*k(:, 2)
        call rk_stage(chain, drive, alpha, t0, dt, 0.5_wp, ys, k(:, 3))
        ys = y + dt*k(:, 3)
        call rk_stage(chain, drive, alpha, t0, dt, 1.0_wp, ys, k(:, 4))
        y = y + (dt/6.0_wp)*(k(:, 1) + 2.0_wp*(k(:, 2) + k(:, 3)) + k(:, 4))
    end subroutine rk4_step

    !> Stage derivative f(t0 + c dt, state) of a step from t0, with the one-sided psi' of this step at the ramp's
    !> kink (the side of the step's midpoint).
    pure subroutine rk_stage(chain, drive, alpha, t0, dt, c, state, derivative)
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        !> Drive parameters.
        type(drive_params), intent(in) :: drive
        !> Site damping alpha_n.
        real(wp), intent(in) :: alpha(:)
        !> Start of the step, step size, stage node.
        real(wp), intent(in) :: t0, dt, c
        !> Stage state.
        real(wp), intent(in) :: state(:)
        !> Its derivative.
        real(wp), intent(out) :: derivative(:)
        real(wp) :: t

        t = t0 + c*dt
        call rk4_rhs(chain, alpha, drive_psi(drive, t), drive_dpsi(drive, t, t0 + 0.5_wp*dt), state, derivative)
    end subroutine rk_stage

    !> The time loop of an explicit Runge-Kutta method on the method-of-lines system, with `stages` stages taken by
    !> `step`. Records as `simulate` does: probes at t_k = k dt every `probe_every` steps (sample 1 at t = 0); the
    !> ledger at t_k = k dt every `ledger_every` steps (record 1 at t = 0; unlike the leapfrog schemes, whose energy
    !> lives on half levels, H is evaluated on the time level itself), plus a last record at t_end when the run ends
    !> between records. The transmission verdict uses the same detector (`detector_site`, `run%detect`). `steps`
    !> counts steps, `t_end = steps dt`, and `newton_iterations` counts right-hand-side evaluations (`stages` a
    !> step). A blow-up (|u_n| above `blowup_threshold`, or a non-finite value) ends the run with status
    !> `run_diverged` and a reason.
    subroutine simulate_explicit_rk(run, result, stages, step)
        !> Validated run configuration.
        type(run_config), intent(in) :: run
        !> Outcome, statistics, ledger and records.
        type(run_result), intent(out) :: result
        !> Stages of the method (right-hand sides a step).
        integer, intent(in) :: stages
        !> One step of the method.
        procedure(rk4_step) :: step
        type(ledger_type) :: ledger
        real(wp), allocatable :: alpha(:), y(:), ys(:), k(:, :)
        integer :: n, m, istep, nd
        integer(i8) :: clock_start, clock_end, clock_rate
        real(wp) :: dt, t1, umax
        logical :: halt

        call system_clock(clock_start, clock_rate)
        n = run%chain%n
        dt = run%numerics%dt
        m = nint(run%numerics%t_final/dt)
        call init_records(result, run%record, m)

        ! work arrays, allocated once; the chain starts at rest
        alpha = damping_profile(run%chain)
        allocate (y(2*n + rk4_energy_components), source=0.0_wp)
        allocate (ys(size(y)), k(size(y), stages))

        call record_probes(result, 0.0_wp, drive_psi(run%drive, 0.0_wp), y(1:n))
        call ledger_close(ledger, chain_energy(run%chain, drive_psi(run%drive, 0.0_wp), y))
        call record_ledger(result, ledger, 0.0_wp)

        result%status = run_ok
        result%steps = 0
        nd = detector_site(run)
        result%detect_site = nd
        do istep = 1, m
            t1 = real(istep, wp)*dt
            call step(run%chain, run%drive, alpha, real(istep - 1, wp)*dt, dt, y, ys, k)
            result%steps = istep

            umax = maxval(abs(y(1:n)))
            if (.not. (maxval(abs(y(n + 1:2*n))) <= huge(1.0_wp))) umax = huge(1.0_wp)   ! non-finite velocity
            call check_blowup(result, umax, run%numerics%blowup_threshold, t1, halt)
            if (halt) exit

            call ledger_from_state(ledger, y(2*n + 1:))
            call observe_ramp(result, ledger%injected, t1, run%drive%ramp_time)
            if (mod(istep, run%record%ledger_every) == 0) then
                call ledger_close(ledger, chain_energy(run%chain, drive_psi(run%drive, t1), y))
                call record_ledger(result, ledger, t1)
            end if
            if (mod(istep, run%record%probe_every) == 0) call record_probes(result, t1, drive_psi(run%drive, t1), y(1:n))
            call observe_detector(result, run%detect, nd, maxval(abs(y(nd + 1:n))), t1, halt)
            if (halt) exit
        end do
        result%t_end = real(result%steps, wp)*dt
        call close_verdict(result, run%detect)
        if (result%status == run_ok .and. mod(result%steps, run%record%ledger_every) /= 0 .and. result%steps > 0) then
            ! close the ledger on the last level reached
            call ledger_close(ledger, chain_energy(run%chain, drive_psi(run%drive, result%t_end), y))
            call record_ledger(result, ledger, result%t_end)
        end if
        result%ledger = ledger
        result%newton_iterations = int(stages, i8)*int(result%steps, i8)
        if (result%steps > 0) result%newton_max_iterations = stages
        call system_clock(clock_end)
        result%wall_time = real(clock_end - clock_start, wp)/real(clock_rate, wp)
    end subroutine simulate_explicit_rk

    !> Right-hand side of the method-of-lines system extended by the energy rates.
    !>
    !> Layout of `y` and `dydt` (size 2N + 4): u_1..u_N, v_1..v_N, then the cumulative energies injected,
    !> dissipated by gamma, by beta, by the absorber; their rates P, D^gamma, D^beta, D^abs do not depend on them.
    pure subroutine rk4_rhs(chain, alpha, psi, dpsi, y, dydt)
        !> Chain parameters (c, beta, gamma, m^2, potential, N).
        type(chain_params), intent(in) :: chain
        !> Site damping alpha_n = gamma + gamma'(n), size N.
        real(wp), intent(in) :: alpha(:)
        !> Boundary displacement u_0 = psi(t) at the stage time.
        real(wp), intent(in) :: psi
        !> Boundary velocity v_0 = psi'(t) at the stage time.
        real(wp), intent(in) :: dpsi
        !> State (u, v, energies), size 2N + 4.
        real(wp), intent(in) :: y(:)
        !> Its time derivative, size 2N + 4.
        real(wp), intent(out) :: dydt(:)
        integer :: n
        real(wp) :: c2, beta

        ! Written as whole-array operations on the interior with the two end sites apart, so that the compiler
        ! vectorises the loops (and the sines, through libmvec).
        n = chain%n
        c2 = chain%c**2
        beta = chain%beta
        associate (u => y(1:n), v => y(n + 1:2*n), du => dydt(1:n), dv => dydt(n + 1:2*n))
            call force_array(chain%potential, u, dv)
            du = v
            dv(2:n - 1) = c2*(u(3:n) - 2.0_wp*u(2:n - 1) + u(1:n - 2)) - alpha(2:n - 1)*v(2:n - 1) &
                          - chain%m2*u(2:n - 1) - dv(2:n - 1)
            dv(1) = c2*(u(2) - 2.0_wp*u(1) + psi) - alpha(1)*v(1) - chain%m2*u(1) - dv(1)
            dv(n) = c2*(-2.0_wp*u(n) + u(n - 1)) - alpha(n)*v(n) - chain%m2*u(n) - dv(n)
            if (beta /= 0.0_wp) then
                dv(2:n - 1) = dv(2:n - 1) + beta*(v(3:n) - 2.0_wp*v(2:n - 1) + v(1:n - 2))
                dv(1) = dv(1) + beta*(v(2) - 2.0_wp*v(1) + dpsi)
                dv(n) = dv(n) + beta*(-2.0_wp*v(n) + v(n - 1))
                ! bonds 0-1, ..., (N-1)-N and the bond to the fixed end, v_{N+1} = 0
                dydt(2*n + 3) = beta*((v(1) - dpsi)**2 + sum((v(2:n) - v(1:n - 1))**2) + v(n)**2)
            else
                dydt(2*n + 3) = 0.0_wp
            end if
            dydt(2*n + 1) = c2*(psi - u(1))*dpsi + beta*(dpsi - v(1))*dpsi
            dydt(2*n + 2) = chain%gamma*sum(v*v)
            dydt(2*n + 4) = sum((alpha - chain%gamma)*v*v)
        end associate
    end subroutine rk4_rhs

    !> Boundary velocity psi'(t) = A [r'(t) sin(Omega t) + r(t) Omega cos(Omega t)].
    !> r' = 1/ramp_time on [0, ramp_time), 0 after. At the kink (t = ramp_time to 1e-12 relative, so that a time
    !> level k dt that is the kink up to rounding counts as the kink) the one-sided value from the side of
    !> `t_side` (a time inside the current step) is taken.
    elemental function drive_dpsi(drive, t, t_side) result(dpsi)
        !> Drive parameters.
        type(drive_params), intent(in) :: drive
        !> Stage time t >= 0.
        real(wp), intent(in) :: t
        !> A time inside the current step (its midpoint), which chooses the side at the kink.
        real(wp), intent(in) :: t_side
        real(wp) :: dpsi
        real(wp) :: dr
        logical :: ramping

        dr = 0.0_wp
        if (drive%ramp_time > 0.0_wp) then
            if (abs(t - drive%ramp_time) <= 1.0e-12_wp*drive%ramp_time) then
                ramping = t_side < drive%ramp_time
            else
                ramping = t < drive%ramp_time
            end if
            if (ramping) dr = 1.0_wp/drive%ramp_time
        end if
        dpsi = drive%amplitude*(dr*sin(drive%omega*t) + ramp_factor(drive, t)*drive%omega*cos(drive%omega*t))
    end function drive_dpsi

    !> Continuous energy H of the chain for state `y` = (u, v, ...) and boundary value u_0 = psi.
    pure function chain_energy(chain, psi, y) result(h)
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        !> Boundary displacement u_0.
        real(wp), intent(in) :: psi
        !> State (u, v, energies).
        real(wp), intent(in) :: y(:)
        real(wp) :: h
        real(wp) :: kinetic, onsite, bonds, u_left
        integer :: n, i

        n = chain%n
        kinetic = 0.0_wp
        onsite = 0.0_wp
        bonds = 0.0_wp
        u_left = psi
        do i = 1, n
            kinetic = kinetic + y(n + i)**2
            onsite = onsite + 0.5_wp*chain%m2*y(i)**2 + potential_v(chain%potential, y(i))
            bonds = bonds + (y(i) - u_left)**2
            u_left = y(i)
        end do
        bonds = bonds + u_left**2          ! bond to the fixed end, u_{N+1} = 0
        h = 0.5_wp*kinetic + onsite + 0.5_wp*chain%c**2*bonds
    end function chain_energy

    !> Copy the integrated cumulative energies (injected, dissipated by gamma, beta, absorber) into the ledger.
    pure subroutine ledger_from_state(ledger, e)
        !> The ledger.
        type(ledger_type), intent(inout) :: ledger
        !> The energy components of the state, size 4.
        real(wp), intent(in) :: e(:)

        ledger%injected = e(1)
        ledger%dissipated_gamma = e(2)
        ledger%dissipated_beta = e(3)
        ledger%dissipated_absorber = e(4)
    end subroutine ledger_from_state


end module supratrans_rk4
