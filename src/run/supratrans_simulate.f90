!> The run engine: one time loop for every method.
!>
!> `simulate` makes the stepper of the run's method (`new_stepper`), sets it up (the chain at rest, the driven end
!> following u_0 = psi(t)), and steps it from t = 0 to T = M dt, M = nint(T/dt), while the observers of
!> `supratrans_observers` watch every step (blow-up, energy ledger, ramp, probes, detector, early stop). All state
!> lives in local variables and in the result, so any number of runs can proceed at once in different threads.
!>
!> Step counts are 64-bit: M is computed in real arithmetic and refused (status `run_invalid`, with a reason) when
!> T/dt is not finite or exceeds `max_step_count` = huge(0_i8)/2 (about 4.6e18), so that no count ever wraps.
module supratrans_simulate
    use, intrinsic :: iso_fortran_env, only: error_unit
    use supratrans_kinds, only: wp, i8
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_strings, only: real_str, real_fixed
    use supratrans_progress, only: progress_clock, start_progress, progress_due, progress_tail
    use supratrans_config, only: run_config
    use supratrans_potential, only: check_potential
    use supratrans_stepper, only: stepper, step_ok, step_not_converged, step_breakdown, save_counters, load_counters
    use supratrans_state_buffer, only: state_buffer
    use supratrans_checkpoint, only: checkpoint_session, session_active, checkpoint_due, write_checkpoint, &
                                     clock_stride, open_session, close_session
    use supratrans_steppers, only: new_stepper
    use supratrans_system, only: stop_signal, note_out_of_memory
    use supratrans_observers, only: observer_item, standard_observers
    use supratrans_result, only: run_result, run_ok, run_diverged, run_newton_failed, run_solver_failed, run_invalid, &
                                 init_records, close_verdict, save_result, load_result
    implicit none
    private

    public :: simulate, simulate_task, number_of_levels, step_count

    !> Largest number of time steps M the engine counts: huge(0_i8)/2 = 2^62 - 1 (so that M + 1 and any step index
    !> plus a few levels stay far from overflow). Not the limit of an input: `max_steps` of `supratrans_limits`
    !> (10^9) refuses a longer run before any work.
    integer(i8), parameter, public :: max_step_count = 2_i8**62 - 1_i8

contains

    !> Number of time steps M = nint(T/dt) of a run, computed in real arithmetic. `error` is allocated (and M is
    !> 0) when T/dt is negative, not finite, or not below 2^62 (so M <= `max_step_count`).
    pure subroutine step_count(run, m, error)
        !> Run configuration.
        type(run_config), intent(in) :: run
        !> M.
        integer(i8), intent(out) :: m
        !> Error, allocated when M is not a valid count.
        type(error_type), allocatable, intent(out) :: error
        real(wp) :: ratio

        m = 0
        ratio = run%numerics%t_final/run%numerics%dt
        ! real(max_step_count, wp) rounds to 2^62: a ratio below it rounds to at most 2^62 - 512 <= max_step_count
        if (.not. (ratio >= 0.0_wp .and. ratio < real(max_step_count, wp))) then
            call fatal_error(error, "t_final/dt = " // real_str(ratio, 6) // " is not a number of time steps " &
                             // "between 0 and " // real_str(real(max_step_count, wp), 3) // " (t_final = " &
                             // real_str(run%numerics%t_final) // ", dt = " // real_str(run%numerics%dt) // ")", &
                             err_input)
            return
        end if
        m = nint(ratio, i8)
    end subroutine step_count

    !> Number of time levels M + 1 of a run (levels t_0 .. t_M, M = nint(T/dt)); 0 when T/dt is not a valid
    !> number of steps (see `step_count`).
    pure function number_of_levels(run) result(levels)
        !> Run configuration.
        type(run_config), intent(in) :: run
        integer(i8) :: levels
        integer(i8) :: m
        type(error_type), allocatable :: error

        call step_count(run, m, error)
        levels = 0
        if (.not. allocated(error)) levels = m + 1
    end function number_of_levels

    !> Simulate the one run of a task of a scene (a sweep or map point, a hysteresis stair run) with mid-run
    !> checkpoints: `<path>` every `every` seconds of wall time and at once on a stop signal (`every` <= 0: none, a
    !> plain `simulate`). A checkpoint of the same `binding` (the input's fingerprint and the task) left by a killed
    !> run is resumed from its step; the result is bit-identical to an uninterrupted run. A run stopped by a signal
    !> returns `result%interrupted` and keeps its checkpoint (its caller records no result: a rerun resumes it); a run
    !> that ends deletes it. Notes (a checkpoint ignored, resumed or not written) go to stderr unless `quiet`.
    subroutine simulate_task(run, result, path, binding, every, quiet)
        !> Validated run configuration.
        type(run_config), intent(in) :: run
        !> Outcome, statistics, ledger and records.
        type(run_result), intent(out) :: result
        !> Checkpoint file of the task.
        character(len=*), intent(in) :: path
        !> Binding text: the input's fingerprint and the task.
        character(len=*), intent(in) :: binding
        !> Seconds of wall time between two checkpoints (<= 0: none).
        real(wp), intent(in) :: every
        !> No notes on stderr.
        logical, intent(in) :: quiet
        type(checkpoint_session) :: session

        if (.not. (every > 0.0_wp)) then
            ! no checkpoints: still stopped by a signal within a step (`result%interrupted`: its caller journals nothing)
            call simulate(run, result, interruptible=.true.)
            return
        end if
        call open_session(session, path, binding, every)
        session%log_runs = .false.        ! one run: nothing to replay
        if (session%resumed .and. len_trim(session%note) == 0) session%note = "resumed: its run continues"
        call note()
        call simulate(run, result, session=session)
        call note()
        if (.not. result%interrupted) call close_session(session)

    contains

        !> The session's note, one line, then cleared.
        subroutine note()
            if (len_trim(session%note) == 0) return
            if (.not. quiet) then
                !$omp critical (supratrans_simulate_notes)
                write (error_unit, "(a)") "  checkpoint " // path // " " // trim(session%note)
                flush (error_unit)
                !$omp end critical (supratrans_simulate_notes)
            end if
            session%note = ""
        end subroutine note

    end subroutine simulate_task

    !> Simulate one run: any method, the same observers (with `verdict_only`, those of the verdict alone: the
    !> ledger, the ramp energy and the records then stay empty, and the stepper need not keep the energy identity
    !> exact, `exact_energy`). With `interruptible` the run polls the stop flag (`stop_signal`, one load of
    !> a C variable) before every step and ends there, `result%interrupted`, when a stop signal has arrived (the timeseries
    !> scene: one long run); the runs of the other scenes finish, their task loop stops between runs.
    !>
    !> With an active checkpoint `session` (`supratrans_checkpoint`) the run is one of a task that checkpoints: it
    !> polls the stop flag too, writes the task's checkpoint every `checkpoint_every` seconds and at once on a stop
    !> signal (then ends `interrupted`, and so does every later call with the session), replays a finished run of a
    !> resumed task from its saved record and continues the run that was in progress from its saved step. A run
    !> that ends is added to the session's records.
    !>
    !> With `progress_every` > 0 (the timeseries scene: one long run) a line of progress goes to stderr whenever
    !> the rule of `supratrans_progress` says one is due (max(`progress_every`, a tenth of the time elapsed) seconds
    !> of wall time since the last): the simulated time t of T, then `progress_tail` (the fraction done, the wall
    !> time elapsed and the time left at the rate so far). Polled with the checkpoint clock, every `clock_stride`
    !> steps.
    subroutine simulate(run, result, verdict_only, interruptible, session, progress_every)
        !> Validated run configuration.
        type(run_config), intent(in) :: run
        !> Outcome, statistics, ledger and records.
        type(run_result), intent(out) :: result
        !> Only the verdict is wanted (default false).
        logical, intent(in), optional :: verdict_only
        !> Stop at a stop signal (default false).
        logical, intent(in), optional :: interruptible
        !> The checkpoints of the task this run belongs to.
        type(checkpoint_session), intent(inout), optional :: session
        !> Least wall time (s) between two lines of progress on stderr (absent or <= 0: none).
        real(wp), intent(in), optional :: progress_every
        class(stepper), allocatable :: integrator
        type(observer_item), allocatable :: observers(:)
        type(error_type), allocatable :: error
        integer(i8) :: clock_start, clock_end, clock_rate, m, nsteps, countdown
        integer :: i, status
        logical :: halt, verdict, poll, keep, resumed, report
        real(wp) :: earlier_wall, t_begin
        type(progress_clock) :: clock

        call system_clock(clock_start, clock_rate)
        keep = .false.
        if (present(session)) keep = session_active(session)
        earlier_wall = 0.0_wp
        if (keep) then
            if (session%interrupted) then
                ! the task was stopped: every further run is cut short at once (its caller discards the task)
                result%interrupted = .true.
                call close_verdict(result, run%detect)
                return
            end if
            if (session%replayed < session%nlog) then
                ! a finished run of a resumed task: its record as it was
                call load_result(result, session%log, fresh=.true.)
                session%replayed = session%replayed + 1
                return
            end if
        end if
        call new_stepper(run%numerics%method, integrator, error)
        if (.not. allocated(error)) call check_potential(run%chain%potential, error)
        if (.not. allocated(error)) call step_count(run, m, error)
        if (allocated(error)) then
            result%status = run_invalid
            result%reason = error%message
            m = 0
        end if
        call init_records(result, run%record, m)
        if (result%no_memory) call note_out_of_memory()
        if (result%status /= run_ok) then
            call close_verdict(result, run%detect)
            call stop_clock()
            return
        end if

        call integrator%init(run)
        if (allocated(integrator%reason)) then
            ! its arrays could not be allocated: no run, and a note that stops the program (`out_of_memory`)
            result%status = run_invalid
            result%no_memory = .true.
            result%reason = integrator%reason
            call note_out_of_memory()
            call close_verdict(result, run%detect)
            call stop_clock()
            return
        end if
        verdict = .false.
        if (present(verdict_only)) verdict = verdict_only
        integrator%exact_energy = .not. verdict     ! no ledger to close
        call standard_observers(run, verdict, observers)
        resumed = .false.
        if (keep) then
            if (session%has_pending) call resume_run()
        end if
        if (.not. resumed) then
            do i = 1, size(observers)
                call observers(i)%item%start(integrator, result)
            end do
        end if
        nsteps = integrator%steps_to(m)
        poll = keep
        countdown = clock_stride
        if (present(interruptible)) poll = poll .or. interruptible
        report = .false.
        if (present(progress_every)) then
            clock = start_progress(progress_every, quiet=.false.)
            report = clock%every > 0.0_wp
        end if
        t_begin = integrator%level_time()
        do while (integrator%steps < nsteps)
            if (poll) then
                if (stop_signal() /= 0) then
                    if (keep) call save_task(.true.)
                    result%interrupted = .true.
                    exit
                end if
            end if
            if (keep .or. report) then
                ! the wall clock every clock_stride steps (a countdown: no division in the loop)
                countdown = countdown - 1
                if (countdown <= 0) then
                    countdown = clock_stride
                    if (keep) then
                        if (checkpoint_due(session)) call save_task(.false.)
                    end if
                    if (report) call report_progress()
                end if
            end if
            call integrator%step(status)
            if (status /= step_ok) then
                select case (status)
                case (step_not_converged)
                    result%status = run_newton_failed
                case (step_breakdown)
                    result%status = run_diverged
                case default
                    result%status = run_solver_failed
                end select
                result%reason = integrator%reason
                exit
            end if
            result%steps = integrator%steps
            halt = .false.
            do i = 1, size(observers)
                call observers(i)%item%after_step(integrator, result, halt)
                if (halt) exit
            end do
            if (halt) exit
        end do
        result%t_end = integrator%level_time()
        do i = 1, size(observers)
            call observers(i)%item%finish(integrator, result)
        end do
        result%newton_iterations = integrator%newton_iterations
        result%newton_max_iterations = integrator%newton_max_iterations
        result%tridiagonal_solves = integrator%tridiagonal_solves
        result%rhs_evaluations = integrator%rhs_evaluations
        call stop_clock()
        if (keep) then
            ! (nested: `session` may be absent, and Fortran's .and. does not stop at the first false operand)
            if (.not. result%interrupted .and. session%log_runs) then
                call save_result(result, session%log)
                session%nlog = session%nlog + 1
                session%replayed = session%nlog
            end if
        end if

    contains

        !> A line of progress on stderr when one is due (`progress_due`): t of T, then the fraction done, the wall
        !> time elapsed in this process and the time left at its rate so far (`progress_tail`).
        subroutine report_progress()
            integer(i8) :: now
            real(wp) :: elapsed, t
            logical :: due

            call system_clock(now)
            elapsed = real(now - clock_start, wp)/real(clock_rate, wp)
            call progress_due(clock, elapsed, due)
            if (.not. due) return
            t = integrator%level_time()
            !$omp critical (supratrans_simulate_notes)
            write (error_unit, "(a)") "  t = " // trim(real_fixed(t, 6)) // " of " &
                // trim(real_fixed(run%numerics%t_final, 6)) &
                // trim(progress_tail(t_begin, t, run%numerics%t_final, elapsed))
            flush (error_unit)
            !$omp end critical (supratrans_simulate_notes)
        end subroutine report_progress

        !> Wall-clock time of the run (with the time before the checkpoint it resumed from).
        subroutine stop_clock()
            call system_clock(clock_end)
            result%wall_time = earlier_wall + real(clock_end - clock_start, wp)/real(clock_rate, wp)
        end subroutine stop_clock

        !> Write the task's checkpoint with this run's state; `stop`: the task stops here.
        subroutine save_task(stop)
            !> A stop signal arrived.
            logical, intent(in) :: stop
            type(state_buffer) :: flight

            call stop_clock()
            call save_result(result, flight)
            call save_counters(integrator, flight)
            call integrator%save_levels(flight)
            if (flight%unsupported) then
                session%note = "not written: the method cannot save its state (it starts again from t = 0)"
                call system_clock(session%last_clock)      ! not tried again before the next interval
            else
                call write_checkpoint(session, flight, .true.)
            end if
            if (stop) session%interrupted = .true.
        end subroutine save_task

        !> Continue the run in progress of a resumed task from its saved state (once); a state that does not fit
        !> this run is ignored with a note and the run starts afresh.
        subroutine resume_run()
            type(run_result) :: saved

            session%has_pending = .false.
            saved = result
            call load_result(result, session%pending, fresh=.false.)
            call load_counters(integrator, session%pending)
            if (session%pending%ok) call integrator%load_levels(session%pending)
            if (session%pending%ok .and. session%pending%pos == session%pending%used + 1 &
                .and. integrator%steps <= integrator%steps_to(m)) then
                resumed = .true.
                earlier_wall = result%wall_time
                do i = 1, size(observers)
                    call observers(i)%item%resume(integrator, result)
                end do
            else
                session%note = "ignored: its run in progress does not fit this run (it starts again from t = 0)"
                result = saved
                call integrator%init(run)
                integrator%exact_energy = .not. verdict
            end if
            session%pending = state_buffer()
        end subroutine resume_run

    end subroutine simulate

end module supratrans_simulate
