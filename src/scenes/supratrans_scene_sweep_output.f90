!> The file of the scenes `amplitude_sweep` and `map` (a submodule of `supratrans_scene_sweep`, whose interface
!> declares `write_grid_file`, `sweep_write_axes`, `write_common_axes` and `jumps_along_amplitude`): the root
!> attributes, the axes, the per-run datasets `/energy/...` and `/runs/...` (the fields of the run record,
!> `run_scalars`) with the energy jumps and verdict changes along the amplitude axis, and `/runs/failures` in words,
!> each by its row of the sweep's or the map's output table (`supratrans_output_rows`).
submodule(supratrans_scene_sweep) supratrans_scene_sweep_output
    use supratrans_config, only: vary_none, vary_choices
    use supratrans_curves, only: curve_indices, write_curves
    use supratrans_potential, only: potential_name
    use supratrans_chain, only: threshold_as
    use supratrans_result, only: status_name
    use supratrans_hdf5, only: h5_create, h5_commit, h5_write_attr
    use supratrans_output_rows, only: output_row, write_row, write_row_group, write_row_attr, amplitude_sweep_amplitude, &
        amplitude_sweep_curves_threshold_as, amplitude_sweep_energy, amplitude_sweep_runs, amplitude_sweep_energy_injected, &
        amplitude_sweep_energy_injected_after_ramp, amplitude_sweep_energy_stored, amplitude_sweep_energy_dissipated_gamma, &
        amplitude_sweep_energy_dissipated_beta, amplitude_sweep_energy_dissipated_absorber, amplitude_sweep_energy_residual, &
        amplitude_sweep_runs_status, amplitude_sweep_runs_transmitting, amplitude_sweep_runs_t_decided, &
        amplitude_sweep_runs_steps, amplitude_sweep_runs_newton_iterations, amplitude_sweep_runs_tridiagonal_solves, &
        amplitude_sweep_runs_rhs_evaluations, amplitude_sweep_runs_wall_time, amplitude_sweep_runs_t_end, &
        amplitude_sweep_runs_max_abs_u, amplitude_sweep_runs_u_beyond_max, amplitude_sweep_runs_detect_site, &
        amplitude_sweep_runs_verdict_margin, amplitude_sweep_runs_thin_verdict, amplitude_sweep_runs_energy_jump, &
        amplitude_sweep_runs_verdict_change, amplitude_sweep_runs_failures, map_amplitude, map_energy, map_runs, &
        map_energy_injected, map_energy_injected_after_ramp, map_energy_stored, map_energy_dissipated_gamma, &
        map_energy_dissipated_beta, map_energy_dissipated_absorber, map_energy_residual, map_runs_status, &
        map_runs_transmitting, map_runs_t_decided, map_runs_steps, map_runs_newton_iterations, map_runs_tridiagonal_solves, &
        map_runs_rhs_evaluations, map_runs_wall_time, map_runs_t_end, map_runs_max_abs_u, map_runs_u_beyond_max, &
        map_runs_detect_site, map_runs_verdict_margin, map_runs_thin_verdict, map_runs_energy_jump, &
        map_runs_verdict_change, map_runs_failures
    use supratrans_output, only: write_root, write_parameters
    use supratrans_strings, only: real_str
    implicit none

contains

    !> Write the scene's HDF5 file `path` from the results so far (atomically: built in memory, written to a fresh
    !> temporary, renamed): the final output (root attribute `complete` = 1) or a partial file, `<output>.partial.h5`
    !> (`complete` = 0, as every scene's, even when every task is done), in which the missing runs are NaN with status
    !> `status_not_run`.
    module procedure write_grid_file
        type(h5_file) :: file

        ! the partial snapshot replaces its predecessor; the output only with overwrite
        call h5_create(file, path, self%cfg%output%overwrite .or. .not. complete)
        call write_root(file, self%cfg, self%scene, self%description, self%inv)
        call h5_write_attr(file, "/", "complete", merge(1, 0, complete))
        call h5_write_attr(file, "/", "runs_done", count(done))
        call h5_write_attr(file, "/", "runs_total", size(done))
        if (complete) call h5_write_attr(file, "/", "wall_time_s", elapsed)
        call write_parameters(file, self%cfg)
        call self%write_axes(file)
        call write_run_datasets(file, self, results, done)
        call h5_commit(file, error)
    end procedure write_grid_file

    !> The axes of the sweep: `/amplitude`, `/curves/...` (`write_common_axes`) and `/curves/threshold_As`, the
    !> continuum-limit threshold at the sweep's frequency.
    module procedure sweep_write_axes
        real(wp) :: as(size(self%runs))
        integer :: ic

        call write_common_axes(self, file)
        do ic = 1, size(self%runs)
            as(ic) = threshold_as_or_nan(self%runs(ic), self%omega_at(ic, 1))
        end do
        call write_row(file, amplitude_sweep_curves_threshold_as, as)
    end procedure sweep_write_axes

    !> The axes shared by sweep and map: `/amplitude` and `/curves` (`write_curves`).
    module procedure write_common_axes
        call write_row(file, merge(map_amplitude, amplitude_sweep_amplitude, tasks%omega_axis), tasks%amplitudes)
        call write_curves(file, tasks%cfg, tasks%runs)
    end procedure write_common_axes

    !> The per-run datasets `/energy/...` and `/runs/...` (the fields of the run record, by the rows of the sweep's or
    !> the map's table), `/runs/failures` and the attributes of `/runs`.
    subroutine write_run_datasets(file, tasks, results, done)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The task list.
        class(sweep_tasks), intent(in) :: tasks
        !> Results, (size(run_scalars_names), ntask).
        real(wp), intent(in) :: results(:, :)
        !> Which tasks are done.
        logical, intent(in) :: done(:)
        type(run_scalars), allocatable :: s(:)
        character(len=240), allocatable :: failures(:)
        integer :: i
        logical :: o
        real(wp), allocatable :: jump(:)
        integer, allocatable :: change(:)

        o = tasks%omega_axis
        allocate (s(size(done)))
        do i = 1, size(done)
            if (done(i)) then
                s(i) = run_scalars_from_values(results(:, i))
            else
                s(i) = empty_run_scalars()
            end if
        end do

        call write_row_group(file, merge(map_energy, amplitude_sweep_energy, o))
        call write_row_group(file, merge(map_runs, amplitude_sweep_runs, o))
        call write_row_attr(file, merge(map_runs, amplitude_sweep_runs, o), "status_codes", status_codes_text())
        ! each field as an array of its own, [s%x]: a strided component passed on would be copied to a temporary
        call write_grid(merge(map_energy_injected, amplitude_sweep_energy_injected, o), [s%injected])
        call write_grid(merge(map_energy_injected_after_ramp, amplitude_sweep_energy_injected_after_ramp, o), &
                        [s%injected_after_ramp])
        call write_grid(merge(map_energy_stored, amplitude_sweep_energy_stored, o), [s%stored])
        call write_grid(merge(map_energy_dissipated_gamma, amplitude_sweep_energy_dissipated_gamma, o), &
                        [s%dissipated_gamma])
        call write_grid(merge(map_energy_dissipated_beta, amplitude_sweep_energy_dissipated_beta, o), &
                        [s%dissipated_beta])
        call write_grid(merge(map_energy_dissipated_absorber, amplitude_sweep_energy_dissipated_absorber, o), &
                        [s%dissipated_absorber])
        call write_grid(merge(map_energy_residual, amplitude_sweep_energy_residual, o), [s%residual])
        call write_grid_int(merge(map_runs_status, amplitude_sweep_runs_status, o), [s%status])
        call write_grid_int(merge(map_runs_transmitting, amplitude_sweep_runs_transmitting, o), [s%transmitting])
        call write_grid(merge(map_runs_t_decided, amplitude_sweep_runs_t_decided, o), [s%t_decided])
        call write_grid_int(merge(map_runs_steps, amplitude_sweep_runs_steps, o), [s%steps])
        call write_grid_int(merge(map_runs_newton_iterations, amplitude_sweep_runs_newton_iterations, o), &
                            [s%newton_iterations])
        call write_grid_int(merge(map_runs_tridiagonal_solves, amplitude_sweep_runs_tridiagonal_solves, o), &
                            [s%tridiagonal_solves])
        call write_grid_int(merge(map_runs_rhs_evaluations, amplitude_sweep_runs_rhs_evaluations, o), &
                            [s%rhs_evaluations])
        call write_grid(merge(map_runs_wall_time, amplitude_sweep_runs_wall_time, o), [s%wall_time])
        call write_grid(merge(map_runs_t_end, amplitude_sweep_runs_t_end, o), [s%t_end])
        call write_grid(merge(map_runs_max_abs_u, amplitude_sweep_runs_max_abs_u, o), [s%max_abs_u])
        call write_grid(merge(map_runs_u_beyond_max, amplitude_sweep_runs_u_beyond_max, o), [s%u_beyond_max])
        call write_grid_int(merge(map_runs_detect_site, amplitude_sweep_runs_detect_site, o), [s%detect_site])
        call write_grid(merge(map_runs_verdict_margin, amplitude_sweep_runs_verdict_margin, o), [s%verdict_margin])
        call write_grid_int(merge(map_runs_thin_verdict, amplitude_sweep_runs_thin_verdict, o), [s%thin_verdict])

        ! where the verdict changes along the amplitude axis, does the energy jump? (ratio to the previous amplitude)
        call jumps_along_amplitude(s, size(tasks%amplitudes), jump, change)
        call write_grid(merge(map_runs_energy_jump, amplitude_sweep_runs_energy_jump, o), jump)
        call write_grid_int(merge(map_runs_verdict_change, amplitude_sweep_runs_verdict_change, o), change)
        call write_row_attr(file, merge(map_runs, amplitude_sweep_runs, o), "thin_verdicts", count(s%thin_verdict == 1))
        call write_row_attr(file, merge(map_runs, amplitude_sweep_runs, o), "verdict_changes_without_energy_jump", &
                            count(change == 1 .and. .not. (jump >= tasks%cfg%scene%min_energy_jump &
                                                           .or. jump <= 1.0_wp/tasks%cfg%scene%min_energy_jump)))

        allocate (failures(0))
        do i = 1, size(done)
            if (s(i)%status > 0) then
                failures = [character(len=len(failures)) :: failures, failure_text(tasks, i, s(i))]
            end if
        end do
        call write_row(file, merge(map_runs_failures, amplitude_sweep_runs_failures, o), failures)
        call write_row_attr(file, merge(map_runs, amplitude_sweep_runs, o), "failed", size(failures))

    contains

        !> A real field over the tasks by its row: (namp, ncurve), or (namp, nomega, ncurve) for the map.
        subroutine write_grid(row, x)
            !> The dataset's row.
            type(output_row), intent(in) :: row
            !> One value per task.
            real(wp), intent(in) :: x(:)

            if (o) then
                call write_row(file, row, reshape(x, [size(tasks%amplitudes), size(tasks%omegas), size(tasks%runs)]))
            else
                call write_row(file, row, reshape(x, [size(tasks%amplitudes), size(tasks%runs)]))
            end if
        end subroutine write_grid

        !> An integer field over the tasks by its row, as `write_grid`.
        subroutine write_grid_int(row, x)
            !> The dataset's row.
            type(output_row), intent(in) :: row
            !> One value per task.
            integer, intent(in) :: x(:)

            if (o) then
                call write_row(file, row, reshape(x, [size(tasks%amplitudes), size(tasks%omegas), size(tasks%runs)]))
            else
                call write_row(file, row, reshape(x, [size(tasks%amplitudes), size(tasks%runs)]))
            end if
        end subroutine write_grid_int
    end subroutine write_run_datasets

    !> One line describing a failed run (its reason, from its record).
    function failure_text(tasks, index, s) result(text)
        !> The task list.
        class(sweep_tasks), intent(in) :: tasks
        !> Task index.
        integer, intent(in) :: index
        !> The task's record.
        type(run_scalars), intent(in) :: s
        character(len=:), allocatable :: text
        integer :: ia, iw, ic, ipot, ival

        ia = tasks%task_inner(index)
        iw = tasks%task_omega(index)
        ic = tasks%task_curve(index)
        call curve_indices(tasks%cfg, ic, ipot, ival)
        text = "curve " // int_str(ic) // " (" // potential_name(tasks%runs(ic)%chain%potential)
        if (tasks%cfg%scene%vary /= vary_none) text = text // ", " // trim(vary_choices(tasks%cfg%scene%vary)) // " = " &
            // real_str(tasks%cfg%scene%values(ival), 6)
        text = text // "), A = " // real_str(tasks%amplitudes(ia), 6) // ", Omega = " &
               // real_str(tasks%omega_at(ic, iw), 6) // ": " &
               // status_name(s%status) &
               // ", the run ended at t = " // real_str(s%t_end, 6) // " (max |u_n| = " &
               // real_str(s%max_abs_u, 6) // ")"
    end function failure_text

    !> Continuum-limit threshold A_s of a curve at frequency omega; NaN outside the band gap.
    elemental function threshold_as_or_nan(run, omega) result(as)
        !> The curve's run.
        type(run_config), intent(in) :: run
        !> Driving frequency.
        real(wp), intent(in) :: omega
        real(wp) :: as

        if (omega < band_gap_edge(run%chain)) then
            as = threshold_as(run%chain, omega)
        else
            as = nan()
        end if
    end function threshold_as_or_nan

    !> Along the amplitude axis (the fastest index of the tasks): the ratio of each run's energy injected after the
    !> ramp to the previous amplitude's, and whether the verdict changed there (-1: first amplitude or a run not ok).
    module procedure jumps_along_amplitude
        integer :: i

        allocate (jump(size(s)), change(size(s)))
        jump = nan()
        change = -1
        do i = 1, size(s)
            if (mod(i - 1, namp) == 0) cycle
            if (s(i)%status /= run_ok .or. s(i - 1)%status /= run_ok) cycle
            jump(i) = s(i)%injected_after_ramp/s(i - 1)%injected_after_ramp
            change(i) = merge(1, 0, s(i)%transmitting /= s(i - 1)%transmitting)
        end do
    end procedure jumps_along_amplitude

end submodule supratrans_scene_sweep_output
