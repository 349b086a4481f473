!> Stepper `rk4`: classical fourth-order Runge-Kutta on the method-of-lines system of the chain (`supratrans_mol`),
!> the reference integrator: four right-hand sides a step, the cumulative energies integrated with the same stages
!> (so the ledger residual is RK4's O(dt^4) energy drift). The chain starts at rest at t = 0 and M = nint(T/dt)
!> steps are taken.
!>
!> Counters: 4 right-hand-side evaluations a step; no Newton iterations, no tridiagonal solves.
module supratrans_stepper_rk4
    use supratrans_kinds, only: wp
    use supratrans_config, only: run_config, chain_params, drive_params
    use supratrans_mol, only: rk_stage
    use supratrans_potential, only: potential_type
    use supratrans_stepper, only: step_ok
    use supratrans_stepper_rk, only: rk_stepper, rk_init
    implicit none
    private

    public :: rk4_step

    !> Number of stages (right-hand-side evaluations) of one step.
    integer, parameter, public :: rk4_stages = 4
    !> Classical order of the method.
    integer, parameter, public :: rk4_order = 4

    !> Classical RK4.
    type, extends(rk_stepper), public :: rk4_stepper
    contains
        !> Set up a run.
        procedure :: init => rk4_init
        !> One step.
        procedure :: step => rk4_stepper_step
    end type rk4_stepper

contains

    !> Set up a run: the chain at rest, four stages.
    subroutine rk4_init(self, run)
        !> The stepper.
        class(rk4_stepper), intent(inout) :: self
        !> Validated run configuration.
        type(run_config), intent(in) :: run

        call rk_init(self, run, rk4_stages, rk4_order)
    end subroutine rk4_init

    !> One step from t_{s-1} to t_s (it cannot fail; a blow-up is the observers' to see).
    subroutine rk4_stepper_step(self, status)
        !> The stepper.
        class(rk4_stepper), intent(inout) :: self
        !> Always `step_ok`.
        integer, intent(out) :: status

        call rk4_step(self%chain, self%potential, self%drive, self%alpha, &
                      real(self%steps, wp)*self%dt, self%dt, self%y, self%ys, self%k)
        call self%end_step()
        status = step_ok
    end subroutine rk4_stepper_step

    !> One classical RK4 step from t0 to t0 + dt: `y` is overwritten by the new state.
    pure subroutine rk4_step(chain, potential, drive, alpha, t0, dt, y, ys, k)
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        !> On-site potential V.
        class(potential_type), intent(in) :: potential
        !> Drive parameters.
        type(drive_params), intent(in) :: drive
        !> Site damping alpha_n.
        real(wp), intent(in), contiguous :: alpha(:)
        !> Start of the step and step size.
        real(wp), intent(in) :: t0, dt
        !> State (u, v, energies), advanced in place.
        real(wp), intent(inout), contiguous :: y(:)
        !> Work: stage state.
        real(wp), intent(inout), contiguous :: ys(:)
        !> Work: stage derivatives, (size(y), 4).
        real(wp), intent(inout), contiguous :: k(:, :)

        call rk_stage(chain, potential, drive, alpha, t0, dt, 0.0_wp, y, k(:, 1))
        ys = y + (0.5_wp*dt)*k(:, 1)
        call rk_stage(chain, potential, drive, alpha, t0, dt, 0.5_wp, ys, k(:, 2))
        ys = y + (0.5_wp*dt)*k(:, 2)
        call rk_stage(chain, potential, drive, alpha, t0, dt, 0.5_wp, ys, k(:, 3))
        ys = y + dt*k(:, 3)
        call rk_stage(chain, potential, drive, alpha, t0, dt, 1.0_wp, ys, k(:, 4))
        y = y + (dt/6.0_wp)*(k(:, 1) + 2.0_wp*(k(:, 2) + k(:, 3)) + k(:, 4))
    end subroutine rk4_step

end module supratrans_stepper_rk4
