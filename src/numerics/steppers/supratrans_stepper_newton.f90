!> Stepper `newton`: the paper's energy-conserving implicit scheme (eq. DiscreteMainDiscr), each step solved by
!> Newton's method.
!>
!> Unknown x = u^{k+1}; residual F(x) = A x + G(x, u^{k-1}) - (B u^k + C u^{k-1} + v^k); Jacobian
!> J = A + diag(dG/da(x, u^{k-1})), tridiagonal: one LAPACK `dgtsv` per iteration (N divisions when beta = 0, where
!> J is diagonal). The predictor is the cubic extrapolation 3 u^k - 3 u^{k-1} + u^{k-2}. Newton stops when the
!> max-norm of its update is at most `tol`; that update is applied, so the remaining error is of order
!> |G''| tol^2 / b (quadratic convergence), far below `tol`.
!>
!> Counters: every iteration is one Newton iteration and one tridiagonal solve; no right-hand sides.
module supratrans_stepper_newton
    use supratrans_kinds, only: wp
    use supratrans_strings, only: int_fixed, real_fixed
    use supratrans_config, only: run_config
    use supratrans_potential, only: gradient_and_slope_array, gradient_and_slope_refine
    use supratrans_scheme, only: scheme_type, scheme_rhs, scheme_apply_a
    use supratrans_tridiag, only: solve_tridiag
    use supratrans_stepper, only: step_ok, step_not_converged, step_breakdown
    use supratrans_stepper_leapfrog, only: leapfrog_stepper, leapfrog_init
    implicit none
    private

    public :: newton_step, newton_work_init

    !> Newton converged.
    integer, parameter, public :: newton_ok = step_ok
    !> The iteration cap was reached without convergence.
    integer, parameter, public :: newton_not_converged = step_not_converged
    !> The residual or the update became non-finite, or the Jacobian was singular.
    integer, parameter, public :: newton_breakdown = step_breakdown

    !> Work arrays of one Newton step (allocated once per run by `newton_work_init`), size N unless noted.
    type, public :: newton_work
        !> Right-hand side B u^k + C u^{k-1} + v^k of the current step.
        real(wp), allocatable :: rhs(:)
        !> Residual, then the Newton update (the solution of the tridiagonal solve).
        real(wp), allocatable :: work(:)
        !> Discrete gradient G and its slope dG/da at the current iterate.
        real(wp), allocatable :: g(:), dg(:)
        !> sin(s_n), cos(s_n) of the current iterate (sine-Gordon).
        real(wp), allocatable :: sin_s(:), cos_s(:)
        !> Copies of the tridiagonal Jacobian handed to `dgtsv` (it overwrites them); dl, du of size max(N-1, 1).
        real(wp), allocatable :: dl(:), dd(:), du(:)
    end type newton_work

    !> The energy-conserving scheme solved by Newton's method.
    type, extends(leapfrog_stepper), public :: newton_stepper
        !> Convergence tolerance on the max-norm of the Newton update.
        real(wp) :: tol = 1.0e-10_wp
        !> Iteration cap.
        integer :: max_iter = 20
        !> Work arrays.
        type(newton_work) :: work
    contains
        !> Set up a run.
        procedure :: init => newton_init
        !> One step of the scheme.
        procedure :: step => newton_stepper_step
    end type newton_stepper

contains

    !> Allocate the work arrays of a Newton step on N sites.
    pure subroutine newton_work_init(work, n)
        !> The work arrays.
        type(newton_work), intent(out) :: work
        !> Number of sites N.
        integer, intent(in) :: n

        allocate (work%rhs(n), work%work(n), work%g(n), work%dg(n), work%sin_s(n), work%cos_s(n))
        allocate (work%dl(max(n - 1, 1)), work%dd(n), work%du(max(n - 1, 1)))
    end subroutine newton_work_init

    !> Set up a run: the scheme, the initial levels, the work arrays, Newton's controls.
    subroutine newton_init(self, run)
        !> The stepper.
        class(newton_stepper), intent(inout) :: self
        !> Validated run configuration.
        type(run_config), intent(in) :: run

        call leapfrog_init(self, run)
        self%tol = run%numerics%newton_tol
        self%max_iter = run%numerics%newton_max_iter
        call newton_work_init(self%work, run%chain%n)
    end subroutine newton_init

    !> One step: u^{k+1} from u^k, u^{k-1} (and u^{k-2} for the predictor).
    subroutine newton_stepper_step(self, status)
        !> The stepper.
        class(newton_stepper), intent(inout) :: self
        !> `step_ok`, `step_not_converged` or `step_breakdown`.
        integer, intent(out) :: status
        integer :: iters
        real(wp) :: t_new

        t_new = self%begin_step()
        call newton_step(self%scheme, self%work, self%u(:, self%io2), self%u(:, self%io), self%u(:, self%ic), &
                         self%u(:, self%inew), self%tol, self%max_iter, iters, status)
        self%newton_iterations = self%newton_iterations + iters
        self%tridiagonal_solves = self%tridiagonal_solves + iters
        self%newton_max_iterations = max(self%newton_max_iterations, iters)
        if (status == step_ok) then
            call self%end_step()
        else if (status == step_not_converged) then
            self%reason = "Newton did not converge in " // trim(int_fixed(iters)) // " iterations at t = " &
                          // trim(real_fixed(t_new))
        else
            self%reason = "Newton broke down (non-finite or singular) at t = " // trim(real_fixed(t_new))
        end if
    end subroutine newton_stepper_step

    !> Advance one step: compute u^{k+1} (into `u_new(1:N)`) from u^k and u^{k-1}.
    !> `u_new(0)` must already hold the boundary value psi(t_{k+1}) and `u_new(N+1)` zero.
    pure subroutine newton_step(scheme, ws, u_older, u_old, u_cur, u_new, tol, max_iter, iterations, status)
        !> Scheme coefficients.
        type(scheme_type), intent(in) :: scheme
        !> Work arrays (`newton_work_init`).
        type(newton_work), intent(inout) :: ws
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
        call scheme_rhs(scheme, u_cur, u_old, ws%rhs)
        u_new(1:n) = 3.0_wp*(u_cur(1:n) - u_old(1:n)) + u_older(1:n)
        status = newton_not_converged
        iterations = 0
        do it = 1, max_iter
            iterations = it
            if (it == 1) then
                call gradient_and_slope_array(scheme%potential, u_new(1:n), u_old(1:n), ws%g, ws%dg, &
                                              ws%sin_s, ws%cos_s)
            else
                call gradient_and_slope_refine(scheme%potential, u_new(1:n), u_old(1:n), ws%work, ws%g, &
                                               ws%dg, ws%sin_s, ws%cos_s)
            end if
            call scheme_apply_a(scheme, u_new, ws%work)
            ws%work = ws%rhs - ws%work - ws%g
            if (scheme%a == 0.0_wp) then
                ws%work = ws%work/(scheme%b + ws%dg)
                info = 0
            else
                ws%dd = scheme%b + ws%dg
                ws%dl = scheme%a
                ws%du = scheme%a
                call solve_tridiag(ws%dl, ws%dd, ws%du, ws%work, info)
            end if
            change = maxval(abs(ws%work))
            if (info /= 0 .or. .not. (change <= huge(change))) then
                status = newton_breakdown
                return
            end if
            u_new(1:n) = u_new(1:n) + ws%work
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

end module supratrans_stepper_newton
