!> The runs of a threshold search of the scene `bifurcation` (`supratrans_scene_bifurcation`): a curve's run prepared
!> for the search (`search_run`: stopped once decided, nothing recorded), the same with another integrator and step
!> (`with_numerics`: the screening method `screen_integrator` at `screen_dt`, or the scene's method at dt/2 for the
!> certification), and the oracle that answers each question of a search with one simulation (`simulation_oracle`).
module supratrans_bifurcation_runs
    use supratrans_kinds, only: wp, i8
    use supratrans_config, only: input_config, run_config, method_newton, method_linearized, method_rk4, method_rk8, &
        screen_newton, screen_linearized, screen_rk4
    use supratrans_chain, only: stable_by_paper_condition
    use supratrans_simulate, only: simulate, number_of_levels
    use supratrans_result, only: run_result, run_ok, status_name
    use supratrans_threshold, only: verdict_oracle
    use supratrans_checkpoint, only: checkpoint_session
    use supratrans_strings, only: real_str
    implicit none
    private

    public :: search_run, with_numerics, screen_integrator, screen_dt

    !> Oracle of the search: one simulation of `run` at the amplitude asked, stopped as soon as it transmits.
    !> `transmits` runs inside OpenMP threads and builds no text (gfortran 12 keeps the lengths of deferred-length
    !> function results in statics, see `supratrans_strings`): a failure is kept as numbers and the run's own
    !> reason, and `failure_reason` formats it (call it from one thread at a time).
    type, extends(verdict_oracle), public :: simulation_oracle
        !> The run (drive frequency set; the amplitude is set per question).
        type(run_config) :: run
        !> The last run failed before its verdict.
        logical :: run_failed = .false.
        !> Amplitude of the failed run.
        real(wp) :: failed_amplitude = 0.0_wp
        !> Status of the failed run (`supratrans_result` codes).
        integer :: failed_status = run_ok
        !> The failed run's own reason.
        character(len=:), allocatable :: reason
        !> Margin of the last run's verdict (`run_result%verdict_margin`).
        real(wp) :: last_margin = 1.0_wp
        !> The checkpoints of the task (every oracle of one search shares them), or null.
        type(checkpoint_session), pointer :: session => null()
        !> A run was stopped by a signal (SIGTERM, SIGINT, SIGUSR1): the search's answers are no result.
        logical :: interrupted = .false.
    contains
        !> One simulation: transmitting or not, and the time steps it took.
        procedure :: transmits => simulation_transmits
        !> Whether the last run failed before its verdict.
        procedure :: failed => simulation_failed
        !> Why it failed.
        procedure :: failure_reason => simulation_failure_reason
        !> The margin of the last verdict.
        procedure :: margin => simulation_margin
    end type simulation_oracle

contains

    !> A curve's run prepared for the search: stop when decided, no probes, the ledger closed once (the oracle
    !> runs it for its verdict alone: no ledger at all).
    pure function search_run(curve) result(run)
        !> The curve's run.
        type(run_config), intent(in) :: curve
        type(run_config) :: run
        integer :: m

        run = curve
        run%detect%stop_when_decided = .true.
        m = int(min(max(1_i8, number_of_levels(run) - 1), int(huge(1), i8)))
        if (allocated(run%record%probes)) deallocate (run%record%probes)
        allocate (run%record%probes(0))
        run%record%probe_every = m
        run%record%ledger_every = m
    end function search_run

    !> The integrator (`method_*`) of a screening method (`screen_*` of &scene screen_method, not `screen_none`).
    pure integer function screen_integrator(screen)
        !> The screening method.
        integer, intent(in) :: screen

        select case (screen)
        case (screen_newton)
            screen_integrator = method_newton
        case (screen_linearized)
            screen_integrator = method_linearized
        case (screen_rk4)
            screen_integrator = method_rk4
        case default
            screen_integrator = method_rk8
        end select
    end function screen_integrator

    !> Time step of the screening runs of `run`: `screen_dt`, or when it is 0, twice the run's dt where that meets
    !> the paper's stability condition for the run's chain, else the run's dt.
    pure function screen_dt(cfg, run) result(dt)
        !> The input.
        type(input_config), intent(in) :: cfg
        !> The run screened (a curve's run).
        type(run_config), intent(in) :: run
        real(wp) :: dt

        dt = cfg%scene%screen_dt
        if (dt > 0.0_wp) return
        dt = run%numerics%dt
        if (stable_by_paper_condition(run%chain, 2.0_wp*dt) .and. 2.0_wp*dt <= run%numerics%t_final/2.0_wp) dt = 2.0_wp*dt
    end function screen_dt

    !> A curve's run with another integrator and time step.
    pure function with_numerics(run, method, dt) result(r)
        !> The run.
        type(run_config), intent(in) :: run
        !> Integrator (`method_*`).
        integer, intent(in) :: method
        !> Time step.
        real(wp), intent(in) :: dt
        type(run_config) :: r

        r = run
        r%numerics%method = method
        r%numerics%dt = dt
    end function with_numerics

    !> One simulation at amplitude `amplitude`: its verdict, and the time steps it took.
    function simulation_transmits(self, amplitude, cost) result(transmitting)
        !> The oracle.
        class(simulation_oracle), intent(inout) :: self
        !> Driving amplitude A.
        real(wp), intent(in) :: amplitude
        !> Time steps taken.
        integer(i8), intent(out) :: cost
        logical :: transmitting
        type(run_result) :: result

        self%run%drive%amplitude = amplitude
        ! every run looks at the stop flag at each step, also without checkpoints (it used to run to its end)
        if (associated(self%session)) then
            call simulate(self%run, result, verdict_only=.true., interruptible=.true., session=self%session)
        else
            call simulate(self%run, result, verdict_only=.true., interruptible=.true.)
        end if
        self%interrupted = self%interrupted .or. result%interrupted
        cost = int(result%steps, i8)
        transmitting = result%transmitting
        self%last_margin = result%verdict_margin
        self%run_failed = result%status /= run_ok .and. .not. result%transmitting
        if (self%run_failed) then
            self%failed_amplitude = amplitude
            self%failed_status = result%status
            self%reason = result%reason
        end if
    end function simulation_transmits

    !> Margin of the last run's verdict, relative to the detection amplitude (NaN for a run stopped at its crossing
    !> or failed).
    function simulation_margin(self) result(margin)
        !> The oracle.
        class(simulation_oracle), intent(in) :: self
        real(wp) :: margin

        margin = self%last_margin
    end function simulation_margin

    !> Whether the last run failed before its verdict.
    function simulation_failed(self) result(failed)
        !> The oracle.
        class(simulation_oracle), intent(in) :: self
        logical :: failed

        failed = self%run_failed
    end function simulation_failed

    !> Why the last run failed (empty if it did not); not for concurrent use (deferred-length text).
    function simulation_failure_reason(self) result(reason)
        !> The oracle.
        class(simulation_oracle), intent(in) :: self
        character(len=:), allocatable :: reason

        reason = ""
        if (.not. self%run_failed) return
        reason = "the run at A = " // real_str(self%failed_amplitude, 6) // " ended " // status_name(self%failed_status)
        if (allocated(self%reason)) reason = reason // ": " // self%reason
    end function simulation_failure_reason

end module supratrans_bifurcation_runs
