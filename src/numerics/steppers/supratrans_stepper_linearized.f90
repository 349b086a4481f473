!> Stepper `linearized`: the linearized scheme of the paper (Sec. 3.1), G(u^{k+1}, u^{k-1}) replaced by V'(u^k), so
!> that A u^{k+1} = B u^k + C u^{k-1} - V'(u^k) + v^k is one tridiagonal solve (`dgtsv`) a step, no Newton (N
!> divisions when beta = 0, where A is diagonal). It does not conserve the discrete energy: its ledger residual is
!> the scheme's energy error.
!>
!> Counters: one tridiagonal solve a step; no Newton iterations, no right-hand sides.
module supratrans_stepper_linearized
    use supratrans_kinds, only: wp
    use supratrans_strings, only: int_fixed, real_fixed
    use supratrans_config, only: run_config
    use supratrans_scheme, only: scheme_type, scheme_rhs
    use supratrans_tridiag, only: solve_tridiag
    use supratrans_stepper, only: step_ok, step_solver_failed
    use supratrans_stepper_leapfrog, only: leapfrog_stepper, leapfrog_init
    implicit none
    private

    public :: linearized_step, linearized_work_init

    !> Work arrays of one linearized step (allocated once per run by `linearized_work_init`), size N unless noted.
    type, public :: linearized_work
        !> Right-hand side B u^k + C u^{k-1} + v^k of the current step.
        real(wp), allocatable :: rhs(:)
        !> Right-hand side of the solve, then its solution u^{k+1}_{1..N}.
        real(wp), allocatable :: work(:)
        !> Forces V'(u^k).
        real(wp), allocatable :: g(:)
        !> Copies of the tridiagonal matrix A handed to `dgtsv` (it overwrites them); dl, du of size max(N-1, 1).
        real(wp), allocatable :: dl(:), dd(:), du(:)
    end type linearized_work

    !> The linearized scheme.
    type, extends(leapfrog_stepper), public :: linearized_stepper
        !> Work arrays.
        type(linearized_work) :: work
    contains
        !> Set up a run.
        procedure :: init => linearized_init
        !> One step of the scheme.
        procedure :: step => linearized_stepper_step
    end type linearized_stepper

contains

    !> Allocate the work arrays of a linearized step on N sites.
    pure subroutine linearized_work_init(work, n, stat)
        !> The work arrays.
        type(linearized_work), intent(out) :: work
        !> Number of sites N.
        integer, intent(in) :: n
        !> Nonzero when memory ran out (every caller of the program passes it; a failure without it leaves the
        !> arrays unallocated).
        integer, intent(out), optional :: stat
        integer :: st

        allocate (work%rhs(n), stat=st)
        if (st == 0) allocate (work%work(n), stat=st)
        if (st == 0) allocate (work%g(n), stat=st)
        if (st == 0) allocate (work%dl(max(n - 1, 1)), stat=st)
        if (st == 0) allocate (work%dd(n), stat=st)
        if (st == 0) allocate (work%du(max(n - 1, 1)), stat=st)
        if (present(stat)) stat = st
    end subroutine linearized_work_init

    !> Set up a run: the scheme, the initial levels, the work arrays.
    subroutine linearized_init(self, run)
        !> The stepper.
        class(linearized_stepper), intent(inout) :: self
        !> Validated run configuration.
        type(run_config), intent(in) :: run

        integer :: stat

        call leapfrog_init(self, run)
        if (allocated(self%reason)) return
        call linearized_work_init(self%work, run%chain%n, stat)
        if (stat /= 0) self%reason = "cannot allocate the work arrays of " // trim(int_fixed(run%chain%n)) &
                                     // " oscillators"
    end subroutine linearized_init

    !> One step: u^{k+1} from u^k and u^{k-1}.
    subroutine linearized_stepper_step(self, status)
        !> The stepper.
        class(linearized_stepper), intent(inout) :: self
        !> `step_ok` or `step_solver_failed`.
        integer, intent(out) :: status
        integer :: info
        real(wp) :: t_new

        t_new = self%begin_step()
        call linearized_step(self%scheme, self%work, self%u(:, self%io), self%u(:, self%ic), self%u(:, self%inew), info)
        self%tridiagonal_solves = self%tridiagonal_solves + 1
        if (info == 0) then
            status = step_ok
            call self%end_step()
        else
            status = step_solver_failed
            self%reason = "dgtsv failed (info = " // trim(int_fixed(info)) // ") at t = " // trim(real_fixed(t_new))
        end if
    end subroutine linearized_stepper_step

    !> Advance one step of the linearized scheme. `u_new(0)` must hold psi(t_{k+1}) and `u_new(N+1)` zero.
    !> `info` is LAPACK's status (non-zero: singular matrix).
    pure subroutine linearized_step(scheme, ws, u_old, u_cur, u_new, info)
        !> Scheme coefficients.
        type(scheme_type), intent(in) :: scheme
        !> Work arrays (`linearized_work_init`).
        type(linearized_work), intent(inout) :: ws
        !> Level k-1, u(0:N+1).
        real(wp), intent(in), contiguous :: u_old(0:)
        !> Level k, u(0:N+1).
        real(wp), intent(in), contiguous :: u_cur(0:)
        !> Level k+1, u(0:N+1): boundary cells in, solution out.
        real(wp), intent(inout), contiguous :: u_new(0:)
        !> LAPACK status.
        integer, intent(out) :: info
        integer :: n, j

        n = scheme%n
        call scheme%potential%force_array(u_cur(1:n), ws%g)
        if (scheme%a == 0.0_wp) then      ! beta = 0: A is diagonal: right-hand side and division in one pass
            do j = 1, n
                u_new(j) = (scheme%d*u_cur(j) + scheme%c2*(u_cur(j - 1) + u_cur(j + 1)) + scheme%e(j)*u_old(j) &
                            - ws%g(j))/scheme%b(j)
            end do
            info = 0
            return
        end if
        call scheme_rhs(scheme, u_cur, u_old, ws%rhs)
        ws%work = ws%rhs - ws%g
        ws%work(1) = ws%work(1) - scheme%a*u_new(0)
        ws%work(n) = ws%work(n) - scheme%a*u_new(n + 1)
        ws%dd = scheme%b
        ws%dl = scheme%a
        ws%du = scheme%a
        call solve_tridiag(ws%dl, ws%dd, ws%du, ws%work, info)
        u_new(1:n) = ws%work
    end subroutine linearized_step

end module supratrans_stepper_linearized
