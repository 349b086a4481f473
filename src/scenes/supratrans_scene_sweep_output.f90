!> The file of the scenes `amplitude_sweep` and `map` (a submodule of `supratrans_scene_sweep`, whose interface
!> declares `write_grid_file`, `sweep_write_axes`, `write_common_axes` and `jumps_along_amplitude`): the root
!> attributes, the axes, the per-run datasets `/energy/...` and `/runs/...` (table `fields` of
!> `supratrans_run_record`) with the energy jumps and verdict changes along the amplitude axis, and
!> `/runs/failures` in words.
submodule(supratrans_scene_sweep) supratrans_scene_sweep_output
    use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
    use supratrans_config, only: vary_none, vary_choices
    use supratrans_curves, only: curve_indices, write_curves
    use supratrans_potential, only: potential_name
    use supratrans_chain, only: threshold_as
    use supratrans_result, only: status_name
    use supratrans_hdf5, only: h5_create, h5_commit, h5_write, h5_write_attr, h5_create_group
    use supratrans_output, only: write_root, write_parameters
    use supratrans_strings, only: real_str
    implicit none

contains

    !> Write the scene's HDF5 file `path` from the results so far (atomically: built in memory, written to a fresh
    !> temporary, renamed): the final output (root attribute `complete` = 1) or a partial file, `<output>.partial.h5`
    !> (`complete` = 0, as every scene's, even when every task is done), in which the missing runs are NaN with status
    !> `status_not_run`.
    module subroutine write_grid_file(self, path, results, done, complete, elapsed, error)
        !> The task list.
        class(sweep_tasks), intent(in) :: self
        !> Path of the file.
        character(len=*), intent(in) :: path
        !> Results, (n_run_values, ntask).
        real(wp), intent(in) :: results(:, :)
        !> Which tasks are done.
        logical, intent(in) :: done(:)
        !> Whether this is the scene's output (replaced only with `overwrite`, with the wall time), not the
        !> partial snapshot.
        logical, intent(in) :: complete
        !> Wall time of the scene (s; of a merge, the slices' summed wall time), the root attribute `wall_time_s`
        !> of the output; negative (unused) for the partial snapshot.
        real(wp), intent(in) :: elapsed
        !> Error, allocated on failure (nothing is then left under `path`).
        type(error_type), allocatable, intent(out) :: error
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
    end subroutine write_grid_file

    !> The axes of the sweep: `/amplitude`, `/curves/...` (`write_common_axes`) and `/curves/threshold_As`, the
    !> continuum-limit threshold at the sweep's frequency.
    module subroutine sweep_write_axes(self, file)
        !> The task list.
        class(sweep_tasks), intent(in) :: self
        !> Open output file (a failure sticks in it).
        type(h5_file), intent(inout) :: file
        real(wp) :: as(size(self%runs))
        integer :: ic

        call write_common_axes(self, file)
        do ic = 1, size(self%runs)
            as(ic) = threshold_as_or_nan(self%runs(ic), self%omega_at(ic, 1))
        end do
        call h5_write(file, "/curves/threshold_As", as, "rad", "Continuum-limit supratransmission threshold A_s = " &
                      // "4 arctan(lambda c / Omega) of each curve at the sweep's frequency (massless, undamped " &
                      // "theory); NaN outside the band gap", dims="curve")
    end subroutine sweep_write_axes

    !> The axes shared by sweep and map: `/amplitude` and `/curves` (`write_curves`).
    module subroutine write_common_axes(tasks, file)
        !> The task list.
        class(sweep_tasks), intent(in) :: tasks
        !> Open output file (a failure sticks in it).
        type(h5_file), intent(inout) :: file

        call h5_write(file, "/amplitude", tasks%amplitudes, "rad", "Driving amplitude A of each run: amplitude_min" &
                      // " + i amplitude_step, i = 0, 1, ...", dims="amplitude")
        call write_curves(file, tasks%cfg, tasks%runs)
    end subroutine write_common_axes

    !> The per-run datasets `/energy/...` and `/runs/...` (table `fields`), `/runs/failures` and the attribute
    !> `status_codes` of `/runs`.
    subroutine write_run_datasets(file, tasks, results, done)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The task list.
        class(sweep_tasks), intent(in) :: tasks
        !> Results, (n_run_values, ntask).
        real(wp), intent(in) :: results(:, :)
        !> Which tasks are done.
        logical, intent(in) :: done(:)
        real(wp), allocatable :: values(:, :), real2(:, :), real3(:, :, :)
        integer, allocatable :: iflat(:), int2(:, :), int3(:, :, :)
        character(len=240), allocatable :: failures(:)
        character(len=:), allocatable :: dims
        integer :: i, j, namp, nomega, ncurve
        real(wp), allocatable :: jump(:)
        integer, allocatable :: change(:)

        namp = size(tasks%amplitudes)
        nomega = size(tasks%omegas)
        ncurve = size(tasks%runs)
        allocate (values(n_run_values, size(done)))
        do i = 1, size(done)
            if (done(i)) then
                values(:, i) = results(:, i)
            else
                values(:, i) = not_run_values()
            end if
        end do
        dims = "curve, amplitude"
        if (tasks%omega_axis) dims = "curve, omega, amplitude"

        call h5_create_group(file, "/energy", "Energy totals of each run over 0..T (the ledger at T)")
        call h5_create_group(file, "/runs", "Outcome and statistics of each run")
        call h5_write_attr(file, "/runs", "status_codes", status_codes_text())
        do j = 1, size(fields)
            if (fields(j)%is_int) then
                iflat = to_int(values(fields(j)%iv, :))
                if (tasks%omega_axis) then
                    int3 = reshape(iflat, [namp, nomega, ncurve])
                    call h5_write(file, trim(fields(j)%name), int3, trim(fields(j)%units), &
                                  trim(fields(j)%description), dims=dims)
                else
                    int2 = reshape(iflat, [namp, ncurve])
                    call h5_write(file, trim(fields(j)%name), int2, trim(fields(j)%units), &
                                  trim(fields(j)%description), dims=dims)
                end if
            else
                if (tasks%omega_axis) then
                    real3 = reshape(values(fields(j)%iv, :), [namp, nomega, ncurve])
                    call h5_write(file, trim(fields(j)%name), real3, trim(fields(j)%units), &
                                  trim(fields(j)%description), dims=dims)
                else
                    real2 = reshape(values(fields(j)%iv, :), [namp, ncurve])
                    call h5_write(file, trim(fields(j)%name), real2, trim(fields(j)%units), &
                                  trim(fields(j)%description), dims=dims)
                end if
            end if
        end do

        ! where the verdict changes along the amplitude axis, does the energy jump? (ratio to the previous amplitude)
        call jumps_along_amplitude(values, namp, jump, change)
        if (tasks%omega_axis) then
            call h5_write(file, "/runs/energy_jump", reshape(jump, [namp, nomega, ncurve]), "1", "Energy injected " &
                          // "after the ramp over that of the previous amplitude (NaN for the first or a run not ok)", &
                          dims=dims)
            call h5_write(file, "/runs/verdict_change", &
                reshape(change, [namp, nomega, ncurve]), "1", "1 where the verdict differs from the previous " &
                // "amplitude's, 0 where not, -1 for the first or a run not ok", dims=dims)
        else
            call h5_write(file, "/runs/energy_jump", reshape(jump, [namp, ncurve]), "1", "Energy injected after the " &
                          // "ramp over that of the previous amplitude (NaN for the first or a run not ok)", &
                          dims=dims)
            call h5_write(file, "/runs/verdict_change", reshape(change, [namp, ncurve]), &
                "1", "1 where the verdict differs from the previous amplitude's, 0 where not, -1 for the first or a " &
                // "run not ok", dims=dims)
        end if
        call h5_write_attr(file, "/runs", "thin_verdicts", count(nint(values(iv_thin_verdict, :)) == 1))
        call h5_write_attr(file, "/runs", "verdict_changes_without_energy_jump", &
                           count(change == 1 .and. .not. (jump >= tasks%cfg%scene%min_energy_jump &
                                                          .or. jump <= 1.0_wp/tasks%cfg%scene%min_energy_jump)))

        allocate (failures(0))
        do i = 1, size(done)
            if (nint(values(iv_status, i)) > 0) then
                failures = [character(len=len(failures)) :: failures, failure_text(tasks, i, values(:, i))]
            end if
        end do
        call h5_write(file, "/runs/failures", failures, "1", "One line per run that failed (status > 0): curve, " &
                      // "amplitude, frequency, status, when it ended and its largest |u_n|", dims="failure")
        call h5_write_attr(file, "/runs", "failed", size(failures))
    end subroutine write_run_datasets

    !> One line describing a failed run (its reason, re-derived from the journalled values).
    function failure_text(tasks, index, values) result(text)
        !> The task list.
        class(sweep_tasks), intent(in) :: tasks
        !> Task index.
        integer, intent(in) :: index
        !> The task's values.
        real(wp), intent(in) :: values(:)
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
               // status_name(nint(values(iv_status))) &
               // ", the run ended at t = " // real_str(values(iv_t_end), 6) // " (max |u_n| = " &
               // real_str(values(iv_max_abs_u), 6) // ")"
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

    !> Journalled reals to integers: nearest integer, -1 for NaN.
    pure function to_int(x) result(i)
        !> Journalled values.
        real(wp), intent(in) :: x(:)
        integer :: i(size(x))
        integer :: k

        do k = 1, size(x)
            if (ieee_is_nan(x(k))) then
                i(k) = -1
            else
                i(k) = nint(x(k))
            end if
        end do
    end function to_int

    !> Along the amplitude axis (the fastest index of the tasks): the ratio of each run's energy injected after the
    !> ramp to the previous amplitude's, and whether the verdict changed there (-1: first amplitude or a run not ok).
    pure module subroutine jumps_along_amplitude(values, namp, jump, change)
        !> Values of every task, (n_run_values, ntask).
        real(wp), intent(in) :: values(:, :)
        !> Amplitudes per line of the grid.
        integer, intent(in) :: namp
        !> Energy ratio to the previous amplitude.
        real(wp), allocatable, intent(out) :: jump(:)
        !> Verdict change flags.
        integer, allocatable, intent(out) :: change(:)
        integer :: i

        allocate (jump(size(values, 2)), change(size(values, 2)))
        jump = nan()
        change = -1
        do i = 1, size(values, 2)
            if (mod(i - 1, namp) == 0) cycle
            if (nint(values(iv_status, i)) /= run_ok .or. nint(values(iv_status, i - 1)) /= run_ok) cycle
            jump(i) = values(iv_injected_after_ramp, i)/values(iv_injected_after_ramp, i - 1)
            change(i) = merge(1, 0, nint(values(iv_transmitting, i)) /= nint(values(iv_transmitting, i - 1)))
        end do
    end subroutine jumps_along_amplitude

end submodule supratrans_scene_sweep_output
