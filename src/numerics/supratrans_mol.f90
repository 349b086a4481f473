!> The method-of-lines system of the paper's chain (eq. 1 on N sites, Sec. 3.1) that the Runge-Kutta steppers
!> integrate, with the same drive and absorbing end as the finite-difference schemes.
!>
!> For n = 1..N, with u_0(t) = psi(t) = A r(t) sin(Omega t) and u_{N+1} = 0,
!>
!>     u_n'' = (c^2 + beta d/dt)(u_{n+1} - 2 u_n + u_{n-1}) - alpha_n u_n' - m^2 u_n - V'(u_n),
!>
!> alpha_n = gamma + gamma'(n). The state is (u, v) of size 2N. The boundary velocity is
!> v_0 = psi'(t) = A [r'(t) sin(Omega t) + r(t) Omega cos(Omega t)], r' = 1/ramp_time for t < ramp_time and
!> 0 after; at the ramp's kink each stage takes the one-sided value of the step it belongs to, so a ramp that
!> ends on a time level keeps a method's order.
!>
!> Energy (continuous; a Runge-Kutta method does not conserve it, the ledger measures its drift):
!>
!>     H = sum_{n=1}^{N} [v_n^2/2 + m^2 u_n^2/2 + V(u_n)] + c^2/2 sum_{n=0}^{N} (u_{n+1} - u_n)^2,
!>     dH/dt = P - D^gamma - D^beta - D^abs,
!>     P = c^2 (u_0 - u_1) psi' + beta (psi' - v_1) psi',   D^gamma = gamma sum v_n^2,
!>     D^abs = sum gamma'(n) v_n^2,   D^beta = beta sum_{n=1}^{N+1} (v_n - v_{n-1})^2,  v_0 = psi', v_{N+1} = 0.
!>
!> The four cumulative energies (injected, dissipated by gamma, by beta, by the absorber) are integrated as
!> four extra ODE components with the same stages as (u, v), so they are as accurate as the method and the ledger
!> residual H(t) - H(0) - (injected - dissipated) is the method's energy drift, not a quadrature error.
module supratrans_mol
    use supratrans_kinds, only: wp
    use supratrans_config, only: chain_params, drive_params
    use supratrans_chain, only: drive_psi, ramp_factor, profile_ramp, stair_amplitude, stair_slope
    use supratrans_potential, only: potential_type
    use supratrans_ledger, only: ledger_type
    implicit none
    private

    public :: rk_stage, chain_rhs, drive_dpsi, chain_energy, ledger_from_state

    !> Number of energy components appended to the state (u, v): injected, dissipated by gamma, by beta, by the
    !> absorber, in this order (the order of `ledger_columns` 2..5).
    integer, parameter, public :: mol_energy_components = 4

contains

    !> Stage derivative f(t0 + c dt, state) of a step from t0, with the one-sided psi' of this step at the ramp's
    !> kink (the side of the step's midpoint).
    pure subroutine rk_stage(chain, potential, drive, alpha, t0, dt, c, state, derivative)
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        !> On-site potential V.
        class(potential_type), intent(in) :: potential
        !> Drive parameters.
        type(drive_params), intent(in) :: drive
        !> Site damping alpha_n.
        real(wp), intent(in), contiguous :: alpha(:)
        !> Start of the step, step size, stage node.
        real(wp), intent(in) :: t0, dt, c
        !> Stage state.
        real(wp), intent(in), contiguous :: state(:)
        !> Its derivative.
        real(wp), intent(out), contiguous :: derivative(:)
        real(wp) :: t

        t = t0 + c*dt
        call chain_rhs(chain, potential, alpha, drive_psi(drive, t), drive_dpsi(drive, t, t0 + 0.5_wp*dt), state, derivative)
    end subroutine rk_stage

    !> Right-hand side of the method-of-lines system extended by the energy rates.
    !>
    !> Layout of `y` and `dydt` (size 2N + 4): u_1..u_N, v_1..v_N, then the cumulative energies injected,
    !> dissipated by gamma, by beta, by the absorber; their rates P, D^gamma, D^beta, D^abs do not depend on them.
    pure subroutine chain_rhs(chain, potential, alpha, psi, dpsi, y, dydt)
        !> Chain parameters (c, beta, gamma, m^2, N).
        type(chain_params), intent(in) :: chain
        !> On-site potential V.
        class(potential_type), intent(in) :: potential
        !> Site damping alpha_n = gamma + gamma'(n), size N.
        real(wp), intent(in), contiguous :: alpha(:)
        !> Boundary displacement u_0 = psi(t) at the stage time.
        real(wp), intent(in) :: psi
        !> Boundary velocity v_0 = psi'(t) at the stage time.
        real(wp), intent(in) :: dpsi
        !> State (u, v, energies), size 2N + 4.
        real(wp), intent(in), contiguous :: y(:)
        !> Its time derivative, size 2N + 4.
        real(wp), intent(out), contiguous :: dydt(:)
        integer :: n, i
        real(wp) :: c2, beta, sum_vv, sum_abs, sum_dv

        ! Written as whole-array operations on the interior with the two end sites apart, so that the compiler
        ! vectorises the loops (and the sines, through libmvec).
        n = chain%n
        c2 = chain%c**2
        beta = chain%beta
        associate (u => y(1:n), v => y(n + 1:2*n), du => dydt(1:n), dv => dydt(n + 1:2*n))
            call potential%force_array(u, dv)
            du = v
            dv(2:n - 1) = c2*(u(3:n) - 2.0_wp*u(2:n - 1) + u(1:n - 2)) - alpha(2:n - 1)*v(2:n - 1) &
                          - chain%m2*u(2:n - 1) - dv(2:n - 1)
            dv(1) = c2*(u(2) - 2.0_wp*u(1) + psi) - alpha(1)*v(1) - chain%m2*u(1) - dv(1)
            dv(n) = c2*(-2.0_wp*u(n) + u(n - 1)) - alpha(n)*v(n) - chain%m2*u(n) - dv(n)
            if (beta /= 0.0_wp) then
                dv(2:n - 1) = dv(2:n - 1) + beta*(v(3:n) - 2.0_wp*v(2:n - 1) + v(1:n - 2))
                dv(1) = dv(1) + beta*(v(2) - 2.0_wp*v(1) + dpsi)
                dv(n) = dv(n) + beta*(-2.0_wp*v(n) + v(n - 1))
            end if
            ! the energy rates' sums in one vectorised pass (SIMD order of summation: a roundoff-level change;
            ! in source order these latency-bound reductions cost about as much as the N sines)
            sum_vv = v(1)*v(1)
            sum_abs = (alpha(1) - chain%gamma)*v(1)*v(1)
            sum_dv = 0.0_wp
            !$omp simd reduction(+: sum_vv, sum_abs, sum_dv)
            do i = 2, n
                sum_vv = sum_vv + v(i)*v(i)
                sum_abs = sum_abs + (alpha(i) - chain%gamma)*v(i)*v(i)
                sum_dv = sum_dv + (v(i) - v(i - 1))**2
            end do
            if (beta /= 0.0_wp) then
                ! bonds 0-1, ..., (N-1)-N and the bond to the fixed end, v_{N+1} = 0
                dydt(2*n + 3) = beta*((v(1) - dpsi)**2 + sum_dv + v(n)**2)
            else
                dydt(2*n + 3) = 0.0_wp
            end if
            dydt(2*n + 1) = c2*(psi - u(1))*dpsi + beta*(dpsi - v(1))*dpsi
            dydt(2*n + 2) = chain%gamma*sum_vv
            dydt(2*n + 4) = sum_abs
        end associate
    end subroutine chain_rhs

    !> Boundary velocity psi'(t) = A [r'(t) sin(Omega t) + r(t) Omega cos(Omega t)] (for the stair profile of the
    !> hysteresis scene, A'(t) sin(Omega t) + A(t) Omega cos(Omega t), A' from the piece holding `t_side`).
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

        if (drive%profile /= profile_ramp) then
            ! the stairs: A'(t) of the piece holding the step's midpoint (one-sided at the kinks)
            dpsi = stair_slope(drive, t_side)*sin(drive%omega*t) &
                   + stair_amplitude(drive, t)*drive%omega*cos(drive%omega*t)
            return
        end if
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
    pure function chain_energy(chain, potential, psi, y) result(h)
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        !> On-site potential V.
        class(potential_type), intent(in) :: potential
        !> Boundary displacement u_0.
        real(wp), intent(in) :: psi
        !> State (u, v, energies).
        real(wp), intent(in), contiguous :: y(:)
        real(wp) :: h
        real(wp) :: kinetic, onsite, bonds, u_left, v(chain%n)
        integer :: n, i

        n = chain%n
        call potential%v_each(y(1:n), v)
        kinetic = 0.0_wp
        onsite = 0.0_wp
        bonds = 0.0_wp
        u_left = psi
        do i = 1, n
            kinetic = kinetic + y(n + i)**2
            onsite = onsite + 0.5_wp*chain%m2*y(i)**2 + v(i)
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

end module supratrans_mol
