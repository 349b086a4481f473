!> Scene `timeseries` (paper Fig. 1): one run of the chain driven at the &drive amplitude A and frequency Omega,
!> its probes u_n(t) and energy ledger over time and its outcome (transmitting or not) written to the output file.
!>
!> It is one run, not a task list: no journal, no `--slice`. A run stopped by a signal writes no result; with
!> `checkpoint_every` > 0 it leaves its checkpoint `<output>.checkpoint`, from which the same command resumes.
!> Omega must lie inside the band gap unless allow_outside_gap.
module supratrans_scene_timeseries
    use, intrinsic :: iso_fortran_env, only: error_unit
    use supratrans_kinds, only: supratrans_version
    use supratrans_error, only: error_type, fatal_error, err_input, err_interrupted
    use supratrans_invocation, only: invocation_type
    use supratrans_config, only: input_config
    use supratrans_scene, only: scene_type
    use supratrans_simulate, only: simulate
    use supratrans_checkpoint, only: checkpoint_session, open_session, close_session
    use supratrans_tasks, only: input_fingerprint
    use supratrans_result, only: run_result, status_name
    use supratrans_output, only: write_timeseries
    use supratrans_strings, only: int_str, real_str, printable
    use supratrans_system, only: stop_signal
    implicit none
    private

    public :: run_timeseries

    !> The scene `timeseries`: one run.
    type, extends(scene_type), public :: timeseries_scene
    contains
        !> Run it and write its output (`run_timeseries`).
        procedure :: run => timeseries_run
        !> One run.
        procedure :: one_run => timeseries_one_run
        !> At one frequency: inside the band gap.
        procedure :: gap_rule => timeseries_gap_rule
    end type timeseries_scene

contains

    !> Run the one run `cfg` describes (stoppable by a signal), print its end and verdict, and write
    !> `cfg%output%file` (`write_timeseries`).
    subroutine run_timeseries(cfg, error)
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Error, allocated on failure: stopped by a signal (no result written), out of memory, output not written.
        type(error_type), allocatable, intent(out) :: error
        type(run_result) :: result
        type(checkpoint_session) :: session

        call progress(cfg, "supratrans " // supratrans_version // ": timeseries from " // cfg%source)
        ! mid-run checkpoints: <output>.checkpoint, bound to the input (supratrans_checkpoint)
        call open_session(session, trim(cfg%output%file) // ".checkpoint", input_fingerprint(cfg) // " timeseries", &
                          cfg%output%checkpoint_every)
        if (len_trim(session%note) > 0) call progress(cfg, "  checkpoint " // trim(cfg%output%file) &
                                                      // ".checkpoint " // trim(session%note))
        if (session%resumed) call progress(cfg, "  resumed from its checkpoint")
        session%note = ""
        session%log_runs = .false.        ! one run: nothing to replay
        call simulate(cfg%run, result, interruptible=.true., session=session)
        if (len_trim(session%note) > 0) call progress(cfg, "  checkpoint " // trim(session%note))
        if (result%interrupted) then
            ! a cut run is no result, and a file under the output's name would look like one: its checkpoint is
            if (session%written > 0 .and. len_trim(session%note) == 0) then
                call fatal_error(error, trim(cfg%output%file) // ": timeseries stopped by signal " &
                                 // int_str(stop_signal()) // " at t = " // real_str(result%t_end, 6) // " of " &
                                 // real_str(cfg%run%numerics%t_final, 6) // ": checkpoint written; the same " &
                                 // "command resumes from there", err_interrupted)
            else
                call fatal_error(error, trim(cfg%output%file) // ": timeseries stopped by signal " &
                                 // int_str(stop_signal()) // " at t = " // real_str(result%t_end, 6) // " of " &
                                 // real_str(cfg%run%numerics%t_final, 6) // ": nothing written (no checkpoint: " &
                                 // "the same command runs it again from t = 0)", err_interrupted)
            end if
            return
        end if
        if (result%no_memory) then
            call fatal_error(error, trim(cfg%output%file) // ": " // result%reason // " (out of memory; " &
                             // "nothing written): a shorter chain or t_final, sparser records, or more memory", &
                             err_input)
            return
        end if
        call progress(cfg, "  run ended: " // status_name(result%status) // " " // result%reason)
        call progress(cfg, "  verdict: " // trim(merge("transmitting    ", "not transmitting", result%transmitting)) &
                      // " (" // result%verdict_reason // "); energy injected " // real_str(result%ledger%injected, 6))
        call write_timeseries(cfg, result, error)
        if (.not. allocated(error)) call close_session(session)
    end subroutine run_timeseries

    !> A line of progress on stderr, unless the output is quiet.
    subroutine progress(cfg, line)
        !> Input (for the quiet flag).
        type(input_config), intent(in) :: cfg
        !> Text.
        character(len=*), intent(in) :: line

        if (.not. cfg%output%quiet) write (error_unit, "(a)") printable(line)
    end subroutine progress

    !> Run the scene (`run_timeseries`).
    subroutine timeseries_run(self, cfg, error, inv)
        !> The scene.
        class(timeseries_scene), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> How the engine is invoked (a slice, a merge: `supratrans_invocation`); a timeseries is one run: unused.
        type(invocation_type), intent(in), optional :: inv

        call run_timeseries(cfg, error)
    end subroutine timeseries_run

    !> A timeseries is one run.
    pure function timeseries_one_run(self) result(yes)
        !> The scene.
        class(timeseries_scene), intent(in) :: self
        logical :: yes

        yes = .true.
    end function timeseries_one_run

    !> A timeseries is driven at one frequency, which must lie inside the band gap.
    pure function timeseries_gap_rule(self) result(yes)
        !> The scene.
        class(timeseries_scene), intent(in) :: self
        logical :: yes

        yes = .true.
    end function timeseries_gap_rule

end module supratrans_scene_timeseries
