!> One step of the paper's energy-conserving implicit scheme, solved by Newton's method.
!>
!> Unknown x = u^{k+1}; residual F(x) = A x + G(x, u^{k-1}) - (B u^k + C u^{k-1} + v^k); Jacobian
!> J = A + diag(dG/da(x, u^{k-1})), tridiagonal: one LAPACK `dgtsv` per iteration. The predictor is the
!> cubic extrapolation 3 u^k - 3 u^{k-1} + u^{k-2}. Newton stops when the max-norm of its update is at most `tol`; that update is
!> applied, so the remaining error is of order |G''| tol^2 / b (quadratic convergence), far below `tol`.
module supratrans_newton
    use supratrans_kinds, only: wp
    use supratrans_potential, only: gradient_and_slope_array, gradient_and_slope_refine
    use supratrans_scheme, only: scheme_type, scheme_rhs, scheme_apply_a
    use supratrans_tridiag, only: solve_tridiag
    implicit none
    private

    public :: newton_step

    !> Newton converged.
    integer, parameter, public :: newton_ok = 0
    !> The iteration cap was reached without convergence.
    integer, parameter, public :: newton_not_converged = 1
    !> The residual or the update became non-finite, or the Jacobian was singular.
    integer, parameter, public :: newton_breakdown = 2

contains

    !> Advance one step: compute u^{k+1} (into `u_new(1:N)`) from u^k and u^{k-1}.
    !> `u_new(0)` must already hold the boundary value psi(t_{k+1}) and `u_new(N+1)` zero.
    pure subroutine newton_step(scheme, u_older, u_old, u_cur, u_new, tol, max_iter, iterations, status)
        !> Scheme coefficients and work arrays.
        type(scheme_type), intent(inout) :: scheme
        !> Level k-2, u(0:N+1) (used by the predictor only).
        real(wp), intent(in) :: u_older(0:)
        !> Level k-1, u(0:N+1).
        real(wp), intent(in) :: u_old(0:)
        !> Level k, u(0:N+1).
        real(wp), intent(in) :: u_cur(0:)
        !> Level k+1, u(0:N+1): boundary cells in, solution out.
        real(wp), intent(inout) :: u_new(0:)
        !> Convergence tolerance on the max-norm of the Newton update.
        real(wp), intent(in) :: tol
        !> Iteration cap.
        integer, intent(in) :: max_iter
        !> Iterations used (solves performed).
        integer, intent(out) :: iterations
        !> `newton_ok`, `newton_not_converged` or `newton_breakdown`.
        integer, intent(out) :: status
        integer :: n, it, info
        real(wp) :: change, change_prev, theta

        n = scheme%n
        call scheme_rhs(scheme, u_cur, u_old)
        u_new(1:n) = 3.0_wp*(u_cur(1:n) - u_old(1:n)) + u_older(1:n)
        status = newton_not_converged
        iterations = 0
        do it = 1, max_iter
            iterations = it
            if (it == 1) then
                call gradient_and_slope_array(scheme%potential, u_new(1:n), u_old(1:n), scheme%g, scheme%dg, &
                                              scheme%sin_s, scheme%cos_s)
            else
                call gradient_and_slope_refine(scheme%potential, u_new(1:n), u_old(1:n), scheme%work, scheme%g, &
                                               scheme%dg, scheme%sin_s, scheme%cos_s)
            end if
            call scheme_apply_a(scheme, u_new, scheme%work)
            scheme%work = scheme%rhs - scheme%work - scheme%g
            if (scheme%a == 0.0_wp) then
                scheme%work = scheme%work/(scheme%b + scheme%dg)
                info = 0
            else
                scheme%dd = scheme%b + scheme%dg
                scheme%dl = scheme%a
                scheme%du = scheme%a
                call solve_tridiag(scheme%dl, scheme%dd, scheme%du, scheme%work, info)
            end if
            change = maxval(abs(scheme%work))
            if (info /= 0 .or. .not. (change <= huge(change))) then
                status = newton_breakdown
                return
            end if
            u_new(1:n) = u_new(1:n) + scheme%work
            if (change <= tol) then
                status = newton_ok
                return
            end if
            if (it > 1) then
                theta = change/change_prev
                if (theta < 1.0_wp) then
                    if (theta/(1.0_wp - theta)*change <= tol) then
                        status = newton_ok
                        return
                    end if
                end if
            end if
            change_prev = change
        end do
    end subroutine newton_step

end module supratrans_newton
