!> Writes results to self-describing HDF5 files: every input parameter (`write_parameters`), where the file comes
!> from (`/provenance`, written by `write_root`), units and a description on every dataset. Files are written under
!> a temporary name and renamed when complete, so a finished file is never half-written.
module supratrans_output
    use supratrans_kinds, only: wp, supratrans_version
    use supratrans_error, only: error_type
    use supratrans_config, only: input_config
    use supratrans_result, only: run_result, status_name, ledger_columns
    use supratrans_hdf5, only: h5_file, h5_create, h5_commit, h5_write, h5_write_attr, h5_create_group
    use supratrans_parameters, only: write_parameters
    use supratrans_provenance, only: write_provenance, timestamp
    use supratrans_invocation, only: invocation_type
    implicit none
    private

    public :: write_timeseries, write_parameters, write_root, write_outcome, timestamp

    !> What each column of the energy ledger (`ledger_columns` of `supratrans_result`) is.
    character(len=*), parameter :: ledger_description(*) = [character(len=96) :: &
        "Stored discrete energy E_k (paper Sec. 3.2, sums over n = 1..N)", &
        "Energy injected through the driven end up to t: sum dt [c^2 (u_0 - u_1) + beta (y_0 - y_1)] y_0", &
        "Energy dissipated by the external damping gamma up to t", &
        "Energy dissipated by the internal damping beta up to t", &
        "Energy dissipated by the absorbing end gamma'(n) up to t", &
        "Balance residual E_k - E_0 - (injected - dissipated): zero to roundoff for the Newton scheme"]

contains

    !> Write the `timeseries` scene: one run's probes u_n(t), its energy ledger over time and its outcome.
    subroutine write_timeseries(cfg, result, error)
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> The run's result.
        type(run_result), intent(in) :: result
        !> Error, allocated on failure (the output file is then not created: nothing under its name, no temporary).
        type(error_type), allocatable, intent(out) :: error
        type(h5_file) :: file
        integer :: ns, nl, j
        real(wp), allocatable :: probe_u(:, :)

        call h5_create(file, trim(cfg%output%file), cfg%output%overwrite)
        call write_root(file, cfg, "timeseries", "One driven chain: u_n(t) at probe sites and the energy ledger")
        call write_parameters(file, cfg)
        ns = result%n_probe_samples
        nl = result%n_ledger_samples
        call h5_write(file, "/probes/sites", result%probes, "1", "Site index n of each probe (1 = first oscillator)", &
                      dims="probe")
        call h5_write(file, "/probes/time", result%probe_time(1:ns), "time", "Sample times t_k = k dt", dims="time")
        probe_u = result%probe_u(1:ns, :)          ! contiguous copy of the filled samples
        call h5_write(file, "/probes/u", probe_u, "rad", "Displacement u_n(t_k) at the probe sites", &
                      dims="probe, time")
        call h5_write(file, "/ledger/time", result%ledger_time(1:nl), "time", &
                      "Record times t_{k+1/2} (E_k is defined on levels k and k+1)", dims="time")
        do j = 1, size(ledger_columns)
            call h5_write(file, "/ledger/"//trim(ledger_columns(j)), result%ledger_series(1:nl, j), "energy", &
                          trim(ledger_description(j)), dims="time")
        end do
        call write_outcome(file, "/run", result)
        call h5_commit(file, error)
    end subroutine write_timeseries

    !> Root attributes shared by every scene (code, version, scene, description, input file, creation time) and the
    !> `/provenance` group.
    subroutine write_root(file, cfg, scene, description, inv)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Scene name.
        character(len=*), intent(in) :: scene
        !> One-line description of the file's contents.
        character(len=*), intent(in) :: description
        !> How the engine was invoked (a merge records its parts); default: computed here.
        type(invocation_type), intent(in), optional :: inv

        call h5_write_attr(file, "/", "code", "supratrans")
        call h5_write_attr(file, "/", "version", supratrans_version)
        call h5_write_attr(file, "/", "scene", scene)
        call h5_write_attr(file, "/", "description", description)
        call h5_write_attr(file, "/", "input_file", cfg%source)
        call h5_write_attr(file, "/", "created", timestamp())
        call h5_write_attr(file, "/", "reference", &
            "J. E. Macias-Diaz and A. Puri, An energy-based computational method in the analysis of the " // &
            "transmission of energy in a chain of coupled oscillators")
        call write_provenance(file, cfg, inv)
    end subroutine write_root

    !> Outcome and statistics of one run as attributes of `group`.
    subroutine write_outcome(file, group, result)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> Group that receives the attributes (created).
        character(len=*), intent(in) :: group
        !> The run's result.
        type(run_result), intent(in) :: result

        call h5_create_group(file, group, "Outcome of the run, solver statistics and final energy totals")
        call h5_write_attr(file, group, "status", status_name(result%status))
        call h5_write_attr(file, group, "reason", result%reason)
        call h5_write_attr(file, group, "steps", result%steps)
        call h5_write_attr(file, group, "t_end", result%t_end)
        call h5_write_attr(file, group, "newton_iterations", int(result%newton_iterations))
        call h5_write_attr(file, group, "newton_max_iterations", result%newton_max_iterations)
        call h5_write_attr(file, group, "tridiagonal_solves", result%tridiagonal_solves)
        call h5_write_attr(file, group, "rhs_evaluations", result%rhs_evaluations)
        call h5_write_attr(file, group, "wall_time_s", result%wall_time)
        call h5_write_attr(file, group, "max_abs_u", result%max_abs_u)
        call h5_write_attr(file, group, "energy_injected", result%ledger%injected)
        call h5_write_attr(file, group, "energy_stored", result%ledger%stored)
        call h5_write_attr(file, group, "energy_dissipated_gamma", result%ledger%dissipated_gamma)
        call h5_write_attr(file, group, "energy_dissipated_beta", result%ledger%dissipated_beta)
        call h5_write_attr(file, group, "energy_dissipated_absorber", result%ledger%dissipated_absorber)
        call h5_write_attr(file, group, "ledger_max_step_residual", result%ledger%max_step_residual)
        call h5_write_attr(file, group, "ledger_energy_scale", result%ledger%energy_scale)
        call h5_write_attr(file, group, "transmitting", result%transmitting)
        call h5_write_attr(file, group, "t_decided", result%t_decided)
        call h5_write_attr(file, group, "verdict_reason", result%verdict_reason)
        call h5_write_attr(file, group, "detect_site", result%detect_site)
        call h5_write_attr(file, group, "u_beyond_max", result%u_beyond_max)
        call h5_write_attr(file, group, "verdict_margin", result%verdict_margin)
        call h5_write_attr(file, group, "thin_verdict", result%thin_verdict)
        if (result%ramp_passed) call h5_write_attr(file, group, &
            "energy_injected_after_ramp", result%ledger%injected - result%injected_at_ramp)
    end subroutine write_outcome

end module supratrans_output
