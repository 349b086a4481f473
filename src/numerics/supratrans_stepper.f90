!> The abstract time stepper: what the run engine (`supratrans_simulate`) needs from an integrator.
!>
!> A stepper owns the state of one run (the time levels it needs), the work arrays of its step (allocated once,
!> by `init`: `step` allocates nothing), its work counters and its energy bookkeeping. The run engine calls
!> `init` once, then `step` until T; after every step the observers read the new level through `displacement`,
!> `max_abs_u` and `blowup_measure`, and the energy ledger through `account` and `stored_energy`.
!>
!> Time levels: the initial condition gives `initial_levels` levels t_0 .. t_{L-1} (the chain at rest; the
!> two-step schemes of the paper need two of them, the one-step Runge-Kutta methods one), and step s (s = 1, 2,
!> ...) computes level s + L - 1. So a run to T = M dt takes M - L + 1 steps, and the newest level after `steps`
!> steps is at t = (steps + L - 1) dt (`level_time`). The stored energy lives at t = (steps + energy_offset) dt
!> (`energy_time`): on the half level t_{k+1/2} for the paper's schemes (E_k of levels k and k+1), on the level
!> itself for the Runge-Kutta methods.
!>
!> Implementations (one module each, made by `new_stepper` of `supratrans_steppers` from the method id): newton
!> and linearized (two-level schemes, `supratrans_stepper_leapfrog`), rk4 and rk8 (explicit Runge-Kutta methods,
!> `supratrans_stepper_rk`).
module supratrans_stepper
    use supratrans_kinds, only: wp, i8
    use supratrans_config, only: run_config
    use supratrans_ledger, only: ledger_type
    use supratrans_state_buffer, only: state_buffer, put_int, get_int
    implicit none
    private

    public :: save_counters, load_counters

    !> `step` status: the new level was computed.
    integer, parameter, public :: step_ok = 0
    !> `step` status: Newton's method reached its iteration cap without converging.
    integer, parameter, public :: step_not_converged = 1
    !> `step` status: the iteration broke down (non-finite residual or update, singular Jacobian).
    integer, parameter, public :: step_breakdown = 2
    !> `step` status: the linear solver failed (singular tridiagonal matrix).
    integer, parameter, public :: step_solver_failed = 3

    !> An integrator of the chain: state, work arrays, counters and energy bookkeeping of one run.
    type, abstract, public :: stepper
        !> Number of oscillators N.
        integer :: n = 0
        !> Time step Delta t.
        real(wp) :: dt = 0.0_wp
        !> Classical order of accuracy in dt (for the convergence tests).
        integer :: order = 0
        !> Time levels given by the initial condition (2 for the two-step schemes, 1 for one-step methods).
        integer :: initial_levels = 1
        !> The stored energy after `steps` steps lives at t = (steps + energy_offset) dt.
        real(wp) :: energy_offset = 0.0_wp
        !> Steps taken.
        integer(i8) :: steps = 0
        !> Newton iterations over the run (0 for methods without Newton).
        integer(i8) :: newton_iterations = 0
        !> Largest number of Newton iterations in one step (0 for methods without Newton).
        integer :: newton_max_iterations = 0
        !> Tridiagonal systems solved over the run (LAPACK `dgtsv`, or N divisions when the matrix is diagonal).
        integer(i8) :: tridiagonal_solves = 0
        !> Right-hand-side evaluations of the method-of-lines system over the run (the stages of a Runge-Kutta
        !> method; 0 for the finite-difference schemes, which have no such right-hand side).
        integer(i8) :: rhs_evaluations = 0
        !> Why the last step failed (allocated by `step` when its status is not `step_ok`), or why `init` could not
        !> set the run up (its arrays could not be allocated: the stepper is then not to be stepped).
        character(len=:), allocatable :: reason
        !> Every step keeps the discrete energy identity exact to roundoff, so that the energy ledger closes
        !> (the default). A run that keeps no ledger (verdict-only) sets it false after `init`: the Newton scheme
        !> then stops at its tolerance alone (one iteration fewer in one of eight of a search's Newton steps).
        logical :: exact_energy = .true.
    contains
        !> Set up a run: coefficients, the initial levels (chain at rest, driven end), work arrays (allocated here,
        !> once, with `stat=`: when memory runs out `reason` is allocated and says so), counters at zero.
        procedure(stepper_init), deferred :: init
        !> Take one step: compute the next time level. Status `step_ok` or a failure (then `reason` says why,
        !> `steps` is unchanged and the state is not to be used).
        procedure(stepper_step), deferred :: step
        !> Stored energy of the newest level(s): E_k of the paper's schemes, H of the method-of-lines system.
        procedure(stepper_energy), deferred :: stored_energy
        !> Bring the ledger's cumulative energies (injected, dissipated by gamma, beta, the absorber) up to the
        !> last step.
        procedure(stepper_account), deferred :: account
        !> u_n at a level: site 0 the drive psi, 1..N the chain, anything else (the fixed end) 0.
        procedure(stepper_displacement), deferred :: displacement
        !> max |u_n| over the sites first..N of the newest level.
        procedure(stepper_max_abs_u), deferred :: max_abs_u
        !> What the blow-up check compares with its threshold: max |u_n| of the newest level (NaN counts).
        procedure :: blowup_measure
        !> Both measures a verdict-only run watches: `blowup_measure` and max |u_n| over sites first..N.
        procedure :: verdict_measures
        !> Time of the newest level, (steps + initial_levels - 1) dt.
        procedure :: level_time
        !> Time at which the stored energy lives, (steps + energy_offset) dt.
        procedure :: energy_time
        !> Steps a run to T = M dt takes: M - initial_levels + 1 (0 if negative).
        procedure :: steps_to
        !> Mid-run checkpoints: append to a buffer everything a step reads that `init` does not set (the time levels
        !> the method keeps), with exact bits. The default marks the buffer `unsupported` (no checkpoint is then
        !> written); a method overrides it and `load_levels`. The counters are saved by `save_counters`.
        procedure :: save_levels => stepper_no_save
        !> Restore what `save_levels` saved, after `init` of the same run: `buf%ok` false when it does not fit.
        procedure :: load_levels => stepper_no_load
    end type stepper

    abstract interface
        !> Set up a run.
        subroutine stepper_init(self, run)
            import :: stepper, run_config
            !> The stepper (re-initialised).
            class(stepper), intent(inout) :: self
            !> Validated run configuration (chain, drive, numerics).
            type(run_config), intent(in) :: run
        end subroutine stepper_init

        !> Take one step.
        subroutine stepper_step(self, status)
            import :: stepper
            !> The stepper.
            class(stepper), intent(inout) :: self
            !> `step_ok` or a failure code.
            integer, intent(out) :: status
        end subroutine stepper_step

        !> Stored energy of the newest level(s).
        pure function stepper_energy(self) result(e)
            import :: stepper, wp
            !> The stepper.
            class(stepper), intent(in) :: self
            real(wp) :: e
        end function stepper_energy

        !> Bring the ledger's cumulative energies up to the last step.
        pure subroutine stepper_account(self, ledger)
            import :: stepper, ledger_type
            !> The stepper.
            class(stepper), intent(in) :: self
            !> The ledger of the run.
            type(ledger_type), intent(inout) :: ledger
        end subroutine stepper_account

        !> u_n at a level.
        pure function stepper_displacement(self, site, back) result(u)
            import :: stepper, wp
            !> The stepper.
            class(stepper), intent(in) :: self
            !> Site n (0: the driven end).
            integer, intent(in) :: site
            !> Which level: 0 the newest, 1 the one before (up to initial_levels - 1).
            integer, intent(in) :: back
            real(wp) :: u
        end function stepper_displacement

        !> max |u_n| over sites first..N of the newest level.
        pure function stepper_max_abs_u(self, first) result(umax)
            import :: stepper, wp
            !> The stepper.
            class(stepper), intent(in) :: self
            !> First site, 1 <= first <= N.
            integer, intent(in) :: first
            real(wp) :: umax
        end function stepper_max_abs_u
    end interface

contains

    !> Default `save_levels`: this method cannot save its state (the buffer is marked `unsupported`).
    pure subroutine stepper_no_save(self, buf)
        !> The stepper.
        class(stepper), intent(in) :: self
        !> The state so far.
        type(state_buffer), intent(inout) :: buf

        buf%unsupported = .true.
    end subroutine stepper_no_save

    !> Default `load_levels`: nothing to restore from (`buf%ok` false).
    pure subroutine stepper_no_load(self, buf)
        !> The stepper.
        class(stepper), intent(inout) :: self
        !> The saved state.
        type(state_buffer), intent(inout) :: buf

        buf%ok = .false.
    end subroutine stepper_no_load

    !> Append the step index and the work counters of a stepper (every method has them) to a checkpoint's buffer.
    pure subroutine save_counters(self, buf)
        !> The stepper.
        class(stepper), intent(in) :: self
        !> The state so far.
        type(state_buffer), intent(inout) :: buf

        call put_int(buf, self%steps)
        call put_int(buf, self%newton_iterations)
        call put_int(buf, int(self%newton_max_iterations, i8))
        call put_int(buf, self%tridiagonal_solves)
        call put_int(buf, self%rhs_evaluations)
    end subroutine save_counters

    !> Restore what `save_counters` saved.
    pure subroutine load_counters(self, buf)
        !> The stepper, initialised.
        class(stepper), intent(inout) :: self
        !> The saved state.
        type(state_buffer), intent(inout) :: buf
        integer(i8) :: v

        call get_int(buf, self%steps)
        call get_int(buf, self%newton_iterations)
        call get_int(buf, v)
        if (v < 0 .or. v > huge(0)) buf%ok = .false.
        if (buf%ok) self%newton_max_iterations = int(v)
        call get_int(buf, self%tridiagonal_solves)
        call get_int(buf, self%rhs_evaluations)
        if (self%steps < 0) buf%ok = .false.
    end subroutine load_counters

    !> Default blow-up measure: max |u_n| over the whole chain at the newest level.
    pure function blowup_measure(self) result(umax)
        !> The stepper.
        class(stepper), intent(in) :: self
        real(wp) :: umax

        umax = self%max_abs_u(1)
    end function blowup_measure

    !> Default: `blowup_measure` and `max_abs_u(first)`, one after the other.
    pure subroutine verdict_measures(self, first, blowup, beyond)
        !> The stepper.
        class(stepper), intent(in) :: self
        !> First site of the detector's range.
        integer, intent(in) :: first
        !> `blowup_measure()`.
        real(wp), intent(out) :: blowup
        !> `max_abs_u(first)`.
        real(wp), intent(out) :: beyond

        blowup = self%blowup_measure()
        beyond = self%max_abs_u(first)
    end subroutine verdict_measures

    !> Time of the newest level.
    pure function level_time(self) result(t)
        !> The stepper.
        class(stepper), intent(in) :: self
        real(wp) :: t

        t = real(self%steps + (self%initial_levels - 1), wp)*self%dt
    end function level_time

    !> Time at which the stored energy of the newest level(s) lives.
    pure function energy_time(self) result(t)
        !> The stepper.
        class(stepper), intent(in) :: self
        real(wp) :: t

        t = (real(self%steps, wp) + self%energy_offset)*self%dt
    end function energy_time

    !> Steps a run of `m` time steps (levels t_0 .. t_M) takes with this stepper.
    pure function steps_to(self, m) result(nsteps)
        !> The stepper.
        class(stepper), intent(in) :: self
        !> M = T/dt.
        integer(i8), intent(in) :: m
        integer(i8) :: nsteps

        nsteps = max(0_i8, m - (self%initial_levels - 1))
    end function steps_to

end module supratrans_stepper
