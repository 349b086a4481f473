!> Discrete energy ledger of the paper (Sec. 3.2, with the corrections of README "Notes on the paper").
!>
!> Stored energy (levels k and k+1, u_{N+1} = 0):
!>   E_k = 1/2 sum_{n=1}^{N} ((u_n^{k+1} - u_n^k)/dt)^2 + c^2/2 sum_{n=0}^{N} (u_{n+1}^{k+1} - u_n^{k+1})(u_{n+1}^k - u_n^k)
!>         + m^2/2 sum_{n=1}^{N} ((u_n^{k+1})^2 + (u_n^k)^2)/2 + sum_{n=1}^{N} (V(u_n^{k+1}) + V(u_n^k))/2.
!> With y_n = (u_n^{k+1} - u_n^{k-1})/(2 dt), n = 0..N+1 (y_{N+1} = 0), the scheme satisfies exactly
!>   E_k - E_{k-1} = dt [P_k - D^gamma_k - D^abs_k - D^beta_k],
!>   P_k = c^2 (u_0^k - u_1^k) y_0 + beta (y_0 - y_1) y_0          (power injected at the driven end),
!>   D^gamma_k = gamma sum y_n^2,  D^abs_k = sum gamma'(n) y_n^2,  D^beta_k = beta sum_{n=1}^{N+1} (y_n - y_{n-1})^2.
!> The paper writes beta (y_1 - y_0) y_0 inside its beta bracket; here it is counted as work done by the driver
!> through the viscous coupling, so that every dissipation term is non-negative.
module supratrans_ledger
    use supratrans_kinds, only: wp
    use supratrans_scheme, only: scheme_type
    implicit none
    private

    public :: stored_energy, step_powers, ledger_add_step, ledger_close

    !> Running totals of the energy ledger of one run.
    type, public :: ledger_type
        !> Stored energy E_0 at the start.
        real(wp) :: e_start = 0.0_wp
        !> Energy injected through the driven end, sum of dt P_k.
        real(wp) :: injected = 0.0_wp
        !> Energy dissipated by the external damping gamma.
        real(wp) :: dissipated_gamma = 0.0_wp
        !> Energy dissipated by the internal damping beta.
        real(wp) :: dissipated_beta = 0.0_wp
        !> Energy dissipated by the absorbing end gamma'(n).
        real(wp) :: dissipated_absorber = 0.0_wp
        !> Last evaluated stored energy.
        real(wp) :: stored = 0.0_wp
        !> Balance residual of the last evaluation: E_k - E_0 - (injected - dissipated).
        real(wp) :: residual = 0.0_wp
        !> Largest |residual change| between two evaluations (per-step residual when evaluated every step).
        real(wp) :: max_step_residual = 0.0_wp
        !> Largest |E_k| and |injected| seen (the energy scale residuals are compared with).
        real(wp) :: energy_scale = 0.0_wp
        !> Number of evaluations of E_k.
        integer :: evaluations = 0
    end type ledger_type

contains

    !> Stored energy E_k from levels k (`u_cur`) and k+1 (`u_new`), arrays u(0:N+1) with boundary cells.
    pure function stored_energy(scheme, m2, u_new, u_cur) result(e)
        !> Scheme (N, dt, c^2, potential).
        type(scheme_type), intent(in) :: scheme
        !> Mass term m^2.
        real(wp), intent(in) :: m2
        !> Level k+1.
        real(wp), intent(in), contiguous :: u_new(0:)
        !> Level k.
        real(wp), intent(in), contiguous :: u_cur(0:)
        real(wp) :: e
        integer :: n

        n = scheme%n
        e = 0.5_wp*sum(((u_new(1:n) - u_cur(1:n))/scheme%dt)**2) &
            + 0.5_wp*scheme%c2*sum((u_new(1:n + 1) - u_new(0:n))*(u_cur(1:n + 1) - u_cur(0:n))) &
            + 0.25_wp*m2*sum(u_new(1:n)**2 + u_cur(1:n)**2) &
            + 0.5_wp*(scheme%potential%potential_sum(u_new(1:n)) + scheme%potential%potential_sum(u_cur(1:n)))
    end function stored_energy

    !> Powers of step k: injected P_k and the dissipation rates D^gamma, D^beta, D^abs.
    !>
    !> The three sums run in one scalar loop in site order. Without damping in the bulk (gamma = beta = 0, as in most
    !> of the paper's runs) only the absorber's sum is needed, and only from its first site (`absorber_first`): once a
    !> vectorised pass has shown every y_n finite and below 1e100, the other sums are finite (so gamma times its sum
    !> is gamma, exactly, and so for beta) and every earlier term of the absorber's sum is an exact zero, which
    !> leaves the running sum unchanged; the results have the same bits as the full loop's, at a quarter of its cost
    !> on the paper's chain.
    pure subroutine step_powers(scheme, gamma, beta, u_old, u_cur, u_new, p_in, d_gamma, d_beta, d_abs)
        !> Scheme (N, dt, c^2, alpha_n).
        type(scheme_type), intent(in) :: scheme
        !> External damping gamma (alpha_n - gamma is the absorber).
        real(wp), intent(in) :: gamma
        !> Internal damping beta.
        real(wp), intent(in) :: beta
        !> Levels k-1, k, k+1, arrays u(0:N+1).
        real(wp), intent(in), contiguous :: u_old(0:), u_cur(0:), u_new(0:)
        !> Injected power P_k.
        real(wp), intent(out) :: p_in
        !> Dissipation rates.
        real(wp), intent(out) :: d_gamma, d_beta, d_abs
        !> Largest |y_n| for which the sums of the bulk are known to be finite without forming them.
        real(wp), parameter :: y_safe = 1.0e100_wp
        real(wp) :: y, y_prev, inv2dt, sum_y2, sum_abs, sum_dy2, y_max, nan_probe
        integer :: n

        inv2dt = 0.5_wp/scheme%dt
        y_prev = (u_new(0) - u_old(0))*inv2dt
        p_in = scheme%c2*(u_cur(0) - u_cur(1))*y_prev + beta*(y_prev - (u_new(1) - u_old(1))*inv2dt)*y_prev
        if (gamma == 0.0_wp .and. beta == 0.0_wp .and. gamma == scheme%gamma) then
            y_max = 0.0_wp
            nan_probe = 0.0_wp
            !$omp simd private(y) reduction(max: y_max) reduction(+: nan_probe)
            do n = 0, scheme%n
                y = (u_new(n) - u_old(n))*inv2dt
                y_max = max(y_max, abs(y))
                nan_probe = nan_probe + 0.0_wp*y          ! NaN when some y is NaN or infinite
            end do
            if (nan_probe == 0.0_wp .and. y_max <= y_safe) then
                sum_abs = 0.0_wp
                do n = scheme%absorber_first, scheme%n
                    y = (u_new(n) - u_old(n))*inv2dt
                    sum_abs = sum_abs + (scheme%alpha(n) - gamma)*y*y
                end do
                d_gamma = gamma
                d_abs = sum_abs
                d_beta = beta
                return
            end if
        end if
        sum_y2 = 0.0_wp
        sum_abs = 0.0_wp
        sum_dy2 = 0.0_wp
        ! one vectorised pass (the sums in SIMD order: a roundoff-level change of the order of summation)
        !$omp simd private(y, y_prev) reduction(+: sum_y2, sum_abs, sum_dy2)
        do n = 1, scheme%n
            y = (u_new(n) - u_old(n))*inv2dt
            y_prev = (u_new(n - 1) - u_old(n - 1))*inv2dt
            sum_y2 = sum_y2 + y*y
            sum_abs = sum_abs + (scheme%alpha(n) - gamma)*y*y
            sum_dy2 = sum_dy2 + (y - y_prev)**2
        end do
        y = (u_new(scheme%n) - u_old(scheme%n))*inv2dt
        sum_dy2 = sum_dy2 + y**2           ! bond to the fixed end, y_{N+1} = 0
        d_gamma = gamma*sum_y2
        d_abs = sum_abs
        d_beta = beta*sum_dy2
    end subroutine step_powers

    !> Add the contributions dt * (powers) of one step to the running totals.
    pure subroutine ledger_add_step(ledger, dt, p_in, d_gamma, d_beta, d_abs)
        !> The ledger.
        type(ledger_type), intent(inout) :: ledger
        !> Time step.
        real(wp), intent(in) :: dt
        !> Injected power and dissipation rates of the step.
        real(wp), intent(in) :: p_in, d_gamma, d_beta, d_abs

        ledger%injected = ledger%injected + dt*p_in
        ledger%dissipated_gamma = ledger%dissipated_gamma + dt*d_gamma
        ledger%dissipated_beta = ledger%dissipated_beta + dt*d_beta
        ledger%dissipated_absorber = ledger%dissipated_absorber + dt*d_abs
    end subroutine ledger_add_step

    !> Record an evaluation of the stored energy and update the balance residual.
    pure subroutine ledger_close(ledger, e)
        !> The ledger.
        type(ledger_type), intent(inout) :: ledger
        !> Stored energy E_k just evaluated.
        real(wp), intent(in) :: e
        real(wp) :: residual

        if (ledger%evaluations == 0) then
            ledger%e_start = e
            residual = 0.0_wp
        else
            residual = e - ledger%e_start - (ledger%injected - ledger%dissipated_gamma - ledger%dissipated_beta &
                                             - ledger%dissipated_absorber)
            ledger%max_step_residual = max(ledger%max_step_residual, abs(residual - ledger%residual))
        end if
        ledger%evaluations = ledger%evaluations + 1
        ledger%stored = e
        ledger%residual = residual
        ledger%energy_scale = max(ledger%energy_scale, abs(e), abs(ledger%injected))
    end subroutine ledger_close

end module supratrans_ledger
