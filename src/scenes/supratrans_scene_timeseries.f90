!> Scene `timeseries` (paper Fig. 1): one run of the chain driven at the &drive amplitude A and frequency Omega,
!> its probes u_n(t) and energy ledger over time and its outcome (transmitting or not) written to the output file
!> (`write_timeseries`: `/probes`, `/ledger`, `/run`, besides the root, `/provenance` and `/parameters` of every file).
!>
!> It is one run, not a task list: no journal, no `--slice`. A run stopped by a signal writes no result; with
!> `checkpoint_every` > 0 it leaves its checkpoint `<output>.checkpoint`, from which the same command resumes. A run
!> longer than a few seconds prints its progress on stderr (t of T, elapsed and remaining time: `supratrans_progress`,
!> its interval the invocation's) unless quiet.
!> Omega must lie inside the band gap unless allow_outside_gap.
module supratrans_scene_timeseries
    use, intrinsic :: iso_fortran_env, only: error_unit
    use supratrans_kinds, only: wp, supratrans_version
    use supratrans_error, only: error_type, fatal_error, err_input, err_interrupted
    use supratrans_config, only: input_config
    use supratrans_scene, only: scene_type
    use supratrans_invocation, only: invocation_type
    use supratrans_simulate, only: simulate
    use supratrans_checkpoint, only: checkpoint_session, open_session, close_session
    use supratrans_tasks, only: input_fingerprint
    use supratrans_result, only: run_result, status_name, ledger_columns
    use supratrans_hdf5, only: h5_file, h5_create, h5_commit
    use supratrans_output_rows, only: output_row, write_row, write_row_group, write_row_attr, row_name, &
        timeseries_probes_sites, timeseries_probes_time, timeseries_probes_u, timeseries_ledger_time, &
        timeseries_ledger_stored, timeseries_ledger_injected, timeseries_ledger_dissipated_gamma, &
        timeseries_ledger_dissipated_beta, timeseries_ledger_dissipated_absorber, timeseries_ledger_residual, &
        timeseries_run
    use supratrans_output, only: write_root, write_parameters
    use supratrans_strings, only: int_str, real_str, printable
    use supratrans_system, only: stop_signal
    implicit none
    private

    !> The rows of the energy ledger's datasets (their names those of `ledger_columns` of `supratrans_result`), in the
    !> order they are written.
    type(output_row), parameter :: ledger_rows(*) = [timeseries_ledger_stored, timeseries_ledger_injected, &
        timeseries_ledger_dissipated_gamma, timeseries_ledger_dissipated_beta, timeseries_ledger_dissipated_absorber, &
        timeseries_ledger_residual]

    !> The scene `timeseries`: one run.
    type, extends(scene_type), public :: timeseries_scene
    contains
        !> Run it and write its output (`run_timeseries`).
        procedure :: run_one => timeseries_run_one
        !> One run.
        procedure :: one_run => timeseries_one_run
        !> At one frequency: inside the band gap.
        procedure :: gap_rule => timeseries_gap_rule
    end type timeseries_scene

contains

    !> Run the one run `cfg` describes (stoppable by a signal), print its end and verdict, and write
    !> `cfg%output%file` (`write_timeseries`).
    subroutine run_timeseries(cfg, error, progress_every)
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Error, allocated on failure: stopped by a signal (no result written), out of memory, output not written.
        type(error_type), allocatable, intent(out) :: error
        !> Least wall time (s) between two lines of the run's progress (`supratrans_progress`; none when quiet).
        real(wp), intent(in) :: progress_every
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
        call simulate(cfg%run, result, interruptible=.true., session=session, &
                      progress_every=merge(0.0_wp, progress_every, cfg%output%quiet))
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

    !> Write the `timeseries` scene: one run's probes u_n(t), its energy ledger over time and its outcome.
    subroutine write_timeseries(cfg, result, error)
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> The run's result.
        type(run_result), intent(in) :: result
        !> Error, allocated on failure (the output file is then not created: nothing under its name, no temporary).
        type(error_type), allocatable, intent(out) :: error
        type(h5_file) :: file
        integer :: ns, nl, j, k
        real(wp), allocatable :: probe_u(:, :)

        call h5_create(file, trim(cfg%output%file), cfg%output%overwrite)
        call write_root(file, cfg, "timeseries", "One driven chain: u_n(t) at probe sites and the energy ledger")
        call write_parameters(file, cfg)
        ns = result%n_probe_samples
        nl = result%n_ledger_samples
        call write_row(file, timeseries_probes_sites, result%probes)
        call write_row(file, timeseries_probes_time, result%probe_time(1:ns))
        probe_u = result%probe_u(1:ns, :)          ! contiguous copy of the filled samples
        call write_row(file, timeseries_probes_u, probe_u)
        call write_row(file, timeseries_ledger_time, result%ledger_time(1:nl))
        do j = 1, size(ledger_rows)
            ! the column of the row's name (a row without its column is left out: test_output_tables finds it)
            do k = 1, size(ledger_columns)
                if (trim(ledger_columns(k)) == row_name(ledger_rows(j))) then
                    call write_row(file, ledger_rows(j), result%ledger_series(1:nl, k))
                    exit
                end if
            end do
        end do
        call write_outcome(file, result)
        call h5_commit(file, error)
    end subroutine write_timeseries

    !> Outcome and statistics of one run as attributes of the group `/run`.
    subroutine write_outcome(file, result)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The run's result.
        type(run_result), intent(in) :: result

        call write_row_group(file, timeseries_run)
        call write_row_attr(file, timeseries_run, "status", status_name(result%status))
        call write_row_attr(file, timeseries_run, "reason", result%reason)
        call write_row_attr(file, timeseries_run, "steps", result%steps)
        call write_row_attr(file, timeseries_run, "t_end", result%t_end)
        call write_row_attr(file, timeseries_run, "newton_iterations", int(result%newton_iterations))
        call write_row_attr(file, timeseries_run, "newton_max_iterations", result%newton_max_iterations)
        call write_row_attr(file, timeseries_run, "tridiagonal_solves", result%tridiagonal_solves)
        call write_row_attr(file, timeseries_run, "rhs_evaluations", result%rhs_evaluations)
        call write_row_attr(file, timeseries_run, "wall_time_s", result%wall_time)
        call write_row_attr(file, timeseries_run, "max_abs_u", result%max_abs_u)
        call write_row_attr(file, timeseries_run, "energy_injected", result%ledger%injected)
        call write_row_attr(file, timeseries_run, "energy_stored", result%ledger%stored)
        call write_row_attr(file, timeseries_run, "energy_dissipated_gamma", result%ledger%dissipated_gamma)
        call write_row_attr(file, timeseries_run, "energy_dissipated_beta", result%ledger%dissipated_beta)
        call write_row_attr(file, timeseries_run, "energy_dissipated_absorber", result%ledger%dissipated_absorber)
        call write_row_attr(file, timeseries_run, "ledger_max_step_residual", result%ledger%max_step_residual)
        call write_row_attr(file, timeseries_run, "ledger_energy_scale", result%ledger%energy_scale)
        call write_row_attr(file, timeseries_run, "transmitting", result%transmitting)
        call write_row_attr(file, timeseries_run, "t_decided", result%t_decided)
        call write_row_attr(file, timeseries_run, "verdict_reason", result%verdict_reason)
        call write_row_attr(file, timeseries_run, "detect_site", result%detect_site)
        call write_row_attr(file, timeseries_run, "u_beyond_max", result%u_beyond_max)
        call write_row_attr(file, timeseries_run, "verdict_margin", result%verdict_margin)
        call write_row_attr(file, timeseries_run, "thin_verdict", result%thin_verdict)
        if (result%ramp_passed) call write_row_attr(file, timeseries_run, &
            "energy_injected_after_ramp", result%ledger%injected - result%injected_at_ramp)
    end subroutine write_outcome

    !> A line of progress on stderr, unless the output is quiet.
    subroutine progress(cfg, line)
        !> Input (for the quiet flag).
        type(input_config), intent(in) :: cfg
        !> Text.
        character(len=*), intent(in) :: line

        if (.not. cfg%output%quiet) write (error_unit, "(a)") printable(line)
    end subroutine progress

    !> Run the scene (`run_timeseries`): its own run phase, called by the scene driver (`supratrans_scene`).
    subroutine timeseries_run_one(self, cfg, inv, error)
        !> The scene.
        class(timeseries_scene), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> How it is invoked (the interval of its progress lines).
        type(invocation_type), intent(in) :: inv
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error

        call run_timeseries(cfg, error, inv%progress_every)
    end subroutine timeseries_run_one

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
