!> Newton-shooting for a periodic state at a fixed drive amplitude A: the fixed point x = P(x; A) of a
!> `fixed_point_map` (the one-period map of the scheme), by Newton's method with the map's exact Jacobian,
!> (J - I) dx = -(P(x) - x), solved by LAPACK `dgesv`. The Jacobian at the last iterate is the monodromy matrix of
!> the state found (its eigenvalues are the Floquet multipliers, `supratrans_floquet`).
module supratrans_shooting
    use supratrans_kinds, only: wp
    use supratrans_fixed_point_map, only: fixed_point_map, map_ok
    use supratrans_dense, only: dense_solve
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: shoot

    !> Converged: max |P(x) - x| <= tol.
    integer, parameter, public :: shoot_converged = 0
    !> Not converged within max_iter Newton steps.
    integer, parameter, public :: shoot_max_iter = 1
    !> J - I singular (x is not an isolated fixed point: a fold or a branch point) at some iterate.
    integer, parameter, public :: shoot_singular = 2
    !> The map could not be evaluated (or gave a non-finite value) at some iterate.
    integer, parameter, public :: shoot_map_failed = 3
    !> Given up: the residual grew beyond `growth_limit` times its first value.
    integer, parameter, public :: shoot_diverged = 4

    !> Controls of Newton-shooting.
    type, public :: shooting_controls
        !> Convergence: max_i |P(x)_i - x_i| <= tol.
        real(wp) :: tol = 1.0e-10_wp
        !> Largest number of Newton steps.
        integer :: max_iter = 20
        !> Give up (`shoot_diverged`) once max |P(x) - x| exceeds this multiple of its value at the initial guess:
        !> Newton with the exact Jacobian shrinks the residual inside its basin, and iterates that have left it
        !> wander, to converge (if ever) on a state far from the guess. Default: never.
        real(wp) :: growth_limit = huge(1.0_wp)
    end type shooting_controls

    !> What Newton-shooting did.
    type, public :: shooting_result
        !> `shoot_converged`, `shoot_max_iter`, `shoot_singular`, `shoot_map_failed` or `shoot_diverged`.
        integer :: status = shoot_max_iter
        !> Newton steps taken.
        integer :: iterations = 0
        !> max |P(x_k) - x_k| at the iterates k = 0 .. iterations (at indices 1 .. iterations + 1).
        real(wp), allocatable :: residuals(:)
        !> Evaluations of P with its Jacobian (the first evaluation is of P alone when `monodromy` is not asked for:
        !> a converged initial guess costs no Jacobian).
        integer :: jacobians = 0
        !> max |dx_k| of the Newton steps k = 1 .. iterations.
        real(wp), allocatable :: steps(:)
    end type shooting_result

contains

    !> Newton-shooting from the initial guess x (overwritten by the last iterate) at amplitude A. Every iterate
    !> evaluates P with its Jacobian (but for an initial guess that is already converged, when `monodromy` is not
    !> asked for); the residual is tested before the step, so on convergence `monodromy` (when present) holds dP/dx
    !> at the returned x.
    subroutine shoot(map, x, amplitude, controls, res, monodromy)
        !> The map P(x; A).
        class(fixed_point_map), intent(inout) :: map
        !> Initial guess on entry, last iterate on exit (the fixed point when converged), size map%dim.
        real(wp), intent(inout) :: x(:)
        !> The drive amplitude A (fixed).
        real(wp), intent(in) :: amplitude
        !> Tolerance and iteration limit.
        type(shooting_controls), intent(in) :: controls
        !> Status, iterations, residual history.
        type(shooting_result), intent(out) :: res
        !> dP/dx at the returned x, d x d.
        real(wp), intent(out), optional :: monodromy(:, :)
        real(wp), allocatable :: px(:), jac(:, :), dx(:), history(:), steps(:)
        integer :: status, info, i, d

        d = map%dim
        allocate (px(d), jac(d, d), dx(d), history(0:controls%max_iter), steps(controls%max_iter))
        res%iterations = 0
        res%jacobians = 0
        if (.not. present(monodromy)) then
            ! an initial guess that is already a fixed point (the chain at rest at A = 0) needs no Jacobian
            call map%apply(x, amplitude, px, status)
            if (status == map_ok .and. all(ieee_is_finite(px))) then
                history(0) = maxval(abs(px - x))
                if (history(0) <= controls%tol) then
                    res%status = shoot_converged
                    res%residuals = history(0:0)
                    res%steps = steps(1:0)
                    return
                end if
            end if
        end if
        do
            call map%apply(x, amplitude, px, status, jac=jac)
            res%jacobians = res%jacobians + 1
            if (status /= map_ok .or. .not. all(ieee_is_finite(px))) then
                res%status = shoot_map_failed
                exit
            end if
            if (present(monodromy)) monodromy = jac
            dx = px - x
            history(res%iterations) = maxval(abs(dx))
            if (history(res%iterations) <= controls%tol) then
                res%status = shoot_converged
                exit
            end if
            if (res%iterations >= controls%max_iter) then
                res%status = shoot_max_iter
                exit
            end if
            if (res%iterations > 0 .and. history(res%iterations)/controls%growth_limit > history(0)) then
                res%status = shoot_diverged
                exit
            end if
            do i = 1, d
                jac(i, i) = jac(i, i) - 1.0_wp
            end do
            dx = -dx
            call dense_solve(jac, dx, info)
            if (info /= 0) then
                res%status = shoot_singular
                exit
            end if
            x = x + dx
            res%iterations = res%iterations + 1
            steps(res%iterations) = maxval(abs(dx))
        end do
        if (res%status == shoot_map_failed) then
            res%residuals = history(0:res%iterations - 1)
        else
            res%residuals = history(0:res%iterations)
        end if
        res%steps = steps(1:res%iterations)
    end subroutine shoot

end module supratrans_shooting
