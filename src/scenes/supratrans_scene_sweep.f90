!> Scene `amplitude_sweep` (paper Figs. 2, 3, 3-and-a-half and 4): the total energy injected into the chain over
!> a whole run, 0..T, against the driving amplitude A, one curve per (potential, value of the varied parameter).
!>
!> Every (curve, amplitude) is one task of the engine `supratrans_tasks`: a full-length run (no early stop, no
!> probes, the ledger closed once at T) whose outcome is reduced to `n_run_values` numbers (`run_values`). The tasks
!> run on OpenMP threads; the journal `<output file>.journal` makes a killed sweep resumable, and now and then a
!> partial file `<output file>.partial.h5` (attribute `complete` = 0, runs not done yet NaN with status -1) is
!> written so that a figure can be drawn while the sweep runs or after it was killed. The final file is written
!> under a temporary name and renamed when complete; the journal and the partial file are then deleted.
!>
!> The machinery is shared with the scene `map` (`supratrans_scene_map`, paper Fig. 11), which is the same sweep
!> over a second axis, the driving frequency: `sweep_tasks` holds a grid of curves x frequencies x amplitudes
!> (one frequency, the &drive omega, for the sweep), `run_grid_scene` runs it and writes the file, and the map
!> extends `sweep_tasks` only to write its own axes (`write_axes`).
!>
!> ## Runs that fail
!> A run that diverges or whose Newton iteration fails does not stop the sweep: it is recorded with its status
!> (`/runs/status`, codes in the attribute `status_codes` of `/runs`: those of `supratrans_result` plus
!> `status_not_run` and `status_outside_gap`), the time it ended and its largest |u_n|; its energies are NaN (the
!> run did not reach T), and `/runs/failures` lists it in words.
!>
!> ## Grids
!> An axis from `first` to `last` by `step` holds `first + i step`, i = 0, 1, ..., for as long as the value is at
!> most `last` + 1e-9 (`axis_grid`): computed from the integer index, so it is exact and reproducible.
!>
!> ## Order of the data
!> Task `index` = ia + namp ((iw - 1) + nomega (ic - 1)) for amplitude ia, frequency iw, curve ic (amplitude
!> fastest). The per-run datasets are stored as Fortran arrays (namp, ncurve) for the sweep and
!> (namp, nomega, ncurve) for the map, which h5py sees as (ncurve, namp) and (ncurve, nomega, namp): `d[ic-1, ia-1]`
!> and `d[ic-1, iw-1, ia-1]`. Each dataset's attribute `dimensions` names them in that (h5py) order.
!>
!> The file (`write_grid_file`, the axes, the per-run datasets) is written by the submodule
!> `supratrans_scene_sweep_output.f90`.
module supratrans_scene_sweep
    use, intrinsic :: iso_fortran_env, only: error_unit, int64
    use supratrans_kinds, only: wp, i8, supratrans_version
    use supratrans_error, only: error_type, fatal_error, err_input, err_io
    use supratrans_invocation, only: invocation_type
    use supratrans_scene, only: scene_type, scene_budget
    use supratrans_limits, only: axis_points, check_axis, check_tasks, sci
    use supratrans_config, only: input_config, run_config
    use supratrans_curves, only: curve_count, curve_run
    use supratrans_validate, only: validate_config
    use supratrans_chain, only: band_gap_edge
    use supratrans_simulate, only: simulate_task, number_of_levels
    use supratrans_result, only: run_result, run_ok
    use supratrans_status, only: status_not_run, status_outside_gap, run_status_codes
    use supratrans_run_record, only: run_value_names, run_values, not_run_values, nan, fields, field_spec, n_run_values, &
        iv_injected, iv_stored, iv_dissipated_gamma, iv_dissipated_beta, iv_dissipated_absorber, iv_residual, &
        iv_status, iv_transmitting, iv_t_decided, iv_steps, iv_newton_iterations, iv_wall_time, iv_t_end, &
        iv_max_abs_u, iv_injected_after_ramp, iv_u_beyond_max, iv_detect_site, iv_tridiagonal_solves, &
        iv_rhs_evaluations, iv_verdict_margin, iv_thin_verdict
    use supratrans_tasks, only: task_list, run_tasks, input_fingerprint, engine_only
    use supratrans_system, only: remove_file
    use supratrans_hdf5, only: h5_file
    use supratrans_strings, only: int_str, printable
    implicit none
    private

    !> The run record (`supratrans_run_record`), for the map scene and the tests.
    public :: run_value_names, run_values, not_run_values, fields, field_spec, n_run_values
    public :: iv_injected, iv_stored, iv_dissipated_gamma, iv_dissipated_beta, iv_dissipated_absorber, iv_residual, &
              iv_status, iv_transmitting, iv_t_decided, iv_steps, iv_newton_iterations, iv_wall_time, iv_t_end, &
              iv_max_abs_u, iv_injected_after_ramp, iv_u_beyond_max, iv_detect_site, iv_tridiagonal_solves, &
              iv_rhs_evaluations, iv_verdict_margin, iv_thin_verdict
    public :: run_amplitude_sweep
    public :: sweep_tasks, init_sweep_tasks, run_grid_scene, write_common_axes, write_grid_file
    public :: axis_grid, journal_path, partial_path, status_codes_text

    !> Status of a run not computed (yet), and of a grid point outside the curve's band gap: the task codes of
    !> `supratrans_status`, shared by every scene.
    public :: status_not_run, status_outside_gap

    !> Slack of the end point of an axis: `first + i step` is on the axis while it is at most `last` + this.
    real(wp), parameter :: grid_slack = 1.0e-9_wp
    !> A verdict change along the amplitude axis is backed by the energy when the energy injected after the ramp
    !> changes there by at least this factor (measured: 20-100 at the threshold, 1.0-1.3 between neighbours elsewhere).
    real(wp), parameter :: min_energy_jump = 3.0_wp
    !> Largest number of tasks of one scene (a guard against a step that is far too small).
    integer, parameter :: max_tasks = 10000000

    !> The tasks of a sweep or map: a grid of curves x driving frequencies x amplitudes, one full run each.
    !> Read-only while the tasks run.
    type, extends(task_list), public :: sweep_tasks
        !> The validated input.
        type(input_config) :: cfg
        !> How the engine is invoked (slice, merge: `supratrans_invocation`).
        type(invocation_type) :: inv
        !> Scene name written to the file: 'amplitude_sweep' or 'map'.
        character(len=:), allocatable :: scene
        !> One-line description of the file written.
        character(len=:), allocatable :: description
        !> Run configuration of each curve, prepared for the sweep (full length, no probes, no early stop).
        type(run_config), allocatable :: curves(:)
        !> Driving frequencies: the &drive omega alone for the sweep, the frequency axis for the map.
        real(wp), allocatable :: omegas(:)
        !> Driving amplitudes.
        real(wp), allocatable :: amplitudes(:)
        !> The frequency is an axis of the data (map): datasets are (curve, omega, amplitude), not (curve, amplitude).
        logical :: omega_axis = .false.
        !> Mid-run checkpoints of task t: `<checkpoint_prefix><t>`, bound to `fingerprint` and t.
        character(len=:), allocatable :: checkpoint_prefix, fingerprint
    contains
        !> Run one task (thread-safe).
        procedure :: run => sweep_run
        !> Whether a task's values are its result (not a run stopped by a signal at its checkpoint).
        procedure :: finished => sweep_finished
        !> Write the partial file.
        procedure :: snapshot => sweep_snapshot
        !> Write the axes of the scene (the sweep: /amplitude, /curves; the map overrides it).
        procedure :: write_axes => sweep_write_axes
        !> Number of tasks.
        procedure :: task_count
        !> Amplitude, frequency and curve index of a task.
        procedure :: task_position
        !> Whether a (frequency, curve) is run: inside the curve's band gap, or allow_outside_gap.
        procedure :: runnable
    end type sweep_tasks

    !> The scene `amplitude_sweep`: one full run per (curve, amplitude) at the &drive frequency.
    type, extends(scene_type), public :: sweep_scene
    contains
        !> Run it and write its output (`run_amplitude_sweep`).
        procedure :: run => sweep_scene_run
        !> Its axes, tasks, work and memory against the limits.
        procedure :: check_limits => sweep_scene_limits
        !> At one frequency: inside the band gap.
        procedure :: gap_rule => sweep_scene_gap
    end type sweep_scene

    interface
        !> Write the scene's HDF5 file `path` from the results so far (atomically: built in memory, written to a fresh
        !> temporary, renamed). With every task done the file is the final output (root attribute `complete` = 1);
        !> otherwise a partial file (`complete` = 0) in which the missing runs are NaN with status `status_not_run`.
        module subroutine write_grid_file(tasks, path, overwrite, results, done, error, wall_time)
            !> The task list.
            class(sweep_tasks), intent(in) :: tasks
            !> Path of the file.
            character(len=*), intent(in) :: path
            !> Replace an existing file.
            logical, intent(in) :: overwrite
            !> Results, (n_run_values, ntask).
            real(wp), intent(in) :: results(:, :)
            !> Which tasks are done.
            logical, intent(in) :: done(:)
            !> Error, allocated on failure (nothing is then left under `path`).
            type(error_type), allocatable, intent(out) :: error
            !> Wall-clock time of the scene (this invocation, s), written as the root attribute `wall_time_s`.
            real(wp), intent(in), optional :: wall_time
        end subroutine write_grid_file

        !> The axes of the sweep: `/amplitude`, `/curves/...` (`write_common_axes`) and `/curves/threshold_As`, the
        !> continuum-limit threshold at the sweep's frequency.
        module subroutine sweep_write_axes(self, file)
            !> The task list.
            class(sweep_tasks), intent(in) :: self
            !> Open output file (a failure sticks in it).
            type(h5_file), intent(inout) :: file
        end subroutine sweep_write_axes

        !> The axes shared by sweep and map: `/amplitude` and `/curves` (`write_curves`).
        module subroutine write_common_axes(tasks, file)
            !> The task list.
            class(sweep_tasks), intent(in) :: tasks
            !> Open output file (a failure sticks in it).
            type(h5_file), intent(inout) :: file
        end subroutine write_common_axes

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
        end subroutine jumps_along_amplitude
    end interface

contains

    !> Run the scene `amplitude_sweep` described by `cfg` and write `cfg%output%file` (layout in README.md,
    !> "Output"): for each curve (`curve_run`) and each amplitude of the &scene axis amplitude_min..amplitude_max
    !> by amplitude_step, one full run at the &drive frequency. Resumes from `<file>.journal` if a killed sweep
    !> left one.
    subroutine run_amplitude_sweep(cfg, error, inv)
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Error, allocated on failure (bad configuration, journal of another input, unwritable files). Runs that
        !> diverge or whose Newton fails are not errors: they are recorded with their status.
        type(error_type), allocatable, intent(out) :: error
        !> How the engine is invoked (a slice, a merge: `supratrans_invocation`); default: the whole scene.
        type(invocation_type), intent(in), optional :: inv
        type(sweep_tasks) :: tasks

        call init_sweep_tasks(tasks, cfg, "amplitude_sweep", "Total energy injected vs driving amplitude: one " &
                              // "full run (0..T) per curve and amplitude (paper Figs. 2, 3, 3-and-a-half, 4)", &
                              [cfg%run%drive%omega], .false.)
        if (present(inv)) tasks%inv = inv
        call run_grid_scene(tasks, error)
    end subroutine run_amplitude_sweep

    !> Fill a task list: the input, the scene's name and description, the frequencies, the amplitude axis of the
    !> &scene group and the run of every curve, prepared for the sweep.
    subroutine init_sweep_tasks(tasks, cfg, scene, description, omegas, omega_axis)
        !> The task list (a `sweep_tasks` or an extension of it).
        class(sweep_tasks), intent(inout) :: tasks
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Scene name.
        character(len=*), intent(in) :: scene
        !> One-line description of the output file.
        character(len=*), intent(in) :: description
        !> Driving frequencies of the grid.
        real(wp), intent(in) :: omegas(:)
        !> Whether the frequency is an axis of the data (map).
        logical, intent(in) :: omega_axis
        integer :: ic

        tasks%cfg = cfg
        tasks%scene = scene
        tasks%description = description
        tasks%omegas = omegas
        tasks%omega_axis = omega_axis
        tasks%amplitudes = axis_grid(cfg%scene%amplitude_min, cfg%scene%amplitude_max, cfg%scene%amplitude_step)
        tasks%checkpoint_prefix = trim(cfg%output%file) // ".checkpoint-"
        tasks%fingerprint = input_fingerprint(cfg)
        if (allocated(tasks%curves)) deallocate (tasks%curves)
        allocate (tasks%curves(curve_count(cfg)))
        do ic = 1, size(tasks%curves)
            tasks%curves(ic) = curve_run(cfg, ic)
            ! the figures need the totals at T: no early stop, no probes, the ledger closed once at the end
            tasks%curves(ic)%detect%stop_when_decided = .false.
            if (allocated(tasks%curves(ic)%record%probes)) deallocate (tasks%curves(ic)%record%probes)
            allocate (tasks%curves(ic)%record%probes(0))
            tasks%curves(ic)%record%probe_every = int(min(number_of_levels(tasks%curves(ic)), int(huge(1), i8)))
            tasks%curves(ic)%record%ledger_every = huge(1)
        end do
    end subroutine init_sweep_tasks

    !> Run the tasks of a sweep or map (resuming from the journal), write the output file atomically, then delete
    !> the journal and the partial file. Prints a first line naming the scene and the number of runs, and the
    !> engine's progress, unless `quiet`.
    subroutine run_grid_scene(tasks, error)
        !> The task list, filled by `init_sweep_tasks`.
        class(sweep_tasks), intent(in) :: tasks
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        real(wp), allocatable :: results(:, :)
        logical, allocatable :: done(:)
        character(len=:), allocatable :: line
        integer(int64) :: ntask, clock_start, clock_end, clock_rate
        integer :: nskip, nfail, ntrans, i, nthin, nflat
        real(wp), allocatable :: jump(:)
        integer, allocatable :: change(:)

        call system_clock(clock_start, clock_rate)
        call validate_config(tasks%cfg, error)
        if (allocated(error)) return
        if (.not. allocated(tasks%cfg%source)) then
            call fatal_error(error, "configuration: cfg%source must name the input file (it fingerprints the " &
                             // "journal)", err_input)
            return
        end if
        ntask = int(size(tasks%amplitudes), int64)*int(size(tasks%omegas), int64)*int(size(tasks%curves), int64)
        if (ntask > max_tasks) then
            call fatal_error(error, tasks%cfg%source // ": &scene: " // int_str(int(min(ntask, 2000000000_int64))) &
                             // " runs is more than the limit " // int_str(max_tasks) // " (check the steps)", err_input)
            return
        end if

        if (.not. tasks%cfg%output%quiet) then
            line = "supratrans " // supratrans_version // ": " // tasks%scene // " from " // tasks%cfg%source // ": " &
                   // int_str(size(tasks%curves)) // " curve(s) x "
            if (tasks%omega_axis) line = line // int_str(size(tasks%omegas)) // " frequencies x "
            line = line // int_str(size(tasks%amplitudes)) // " amplitudes = " // int_str(tasks%task_count()) &
                   // " runs -> " // trim(tasks%cfg%output%file)
            nskip = 0
            do i = 1, tasks%task_count()
                if (.not. task_is_runnable(tasks, i)) nskip = nskip + 1
            end do
            if (nskip > 0) line = line // " (" // int_str(nskip) // " outside the band gap, not run)"
            write (error_unit, "(a)") printable(line)
            flush (error_unit)
        end if

        call run_tasks(tasks, tasks%task_count(), run_value_names(), journal_path(tasks%cfg), &
                       input_fingerprint(tasks%cfg), "runs", tasks%cfg%output%quiet, results, done, error, tasks%cfg, tasks%inv)
        if (allocated(error) .or. engine_only(tasks%inv)) return
        if (.not. all(done)) then
            call fatal_error(error, trim(tasks%cfg%output%file) // ": the task engine returned with runs missing", &
                             err_io)
            return
        end if

        call system_clock(clock_end)
        call write_grid_file(tasks, trim(tasks%cfg%output%file), tasks%cfg%output%overwrite, results, done, error, &
                             real(clock_end - clock_start, wp)/real(clock_rate, wp))
        if (allocated(error)) return
        call remove_file(journal_path(tasks%cfg))
        call remove_file(partial_path(tasks%cfg))

        if (.not. tasks%cfg%output%quiet) then
            nfail = count(nint(results(iv_status, :)) > 0)
            ntrans = count(nint(results(iv_status, :)) == run_ok .and. nint(results(iv_transmitting, :)) == 1)
            write (error_unit, "(a)") "  " // int_str(count(nint(results(iv_status, :)) == run_ok)) // " runs ok (" &
                // int_str(ntrans) // " transmitting), " // int_str(nfail) // " failed (see /runs/failures)"
            nthin = count(nint(results(iv_thin_verdict, :)) == 1)
            call jumps_along_amplitude(results, size(tasks%amplitudes), jump, change)
            nflat = count(change == 1 .and. .not. (jump >= min_energy_jump .or. jump <= 1.0_wp/min_energy_jump))
            if (nthin > 0 .or. nflat > 0) write (error_unit, "(a)") "  warning: " // int_str(nthin) &
                // " verdict(s) with a thin margin (/runs/thin_verdict), " // int_str(nflat) // " verdict change(s) " &
                // "without an energy jump (/runs/energy_jump): check them"
            flush (error_unit)
        end if
    end subroutine run_grid_scene

    !> Run one task: the curve's run at the task's frequency and amplitude, reduced to `run_values`; a point
    !> outside the curve's band gap is not run (status `status_outside_gap`).
    subroutine sweep_run(self, index, values)
        !> The task list.
        class(sweep_tasks), intent(in) :: self
        !> Task index, 1..task_count().
        integer, intent(in) :: index
        !> The task's results, `n_run_values` of them.
        real(wp), intent(out) :: values(:)
        type(run_config) :: run
        type(run_result) :: result
        integer :: ia, iw, ic
        character(len=12) :: task_text

        call self%task_position(index, ia, iw, ic)
        if (.not. self%runnable(iw, ic)) then
            values = nan()
            values(iv_status) = real(status_outside_gap, wp)
            return
        end if
        run = self%curves(ic)
        run%drive%amplitude = self%amplitudes(ia)
        run%drive%omega = self%omegas(iw)
        write (task_text, "(i0)") index
        call simulate_task(run, result, self%checkpoint_prefix // trim(task_text), self%fingerprint // " task " &
                           // trim(task_text), self%cfg%output%checkpoint_every, self%cfg%output%quiet)
        if (result%interrupted) then
            ! stopped by a signal at its checkpoint: no result (not journaled; a rerun resumes it)
            values = nan()
            values(iv_status) = real(status_not_run, wp)
            return
        end if
        values = run_values(result)
    end subroutine sweep_run

    !> Whether a task's values are its result: a run stopped at its checkpoint by a signal has status not-run.
    function sweep_finished(self, values) result(yes)
        !> The task list.
        class(sweep_tasks), intent(in) :: self
        !> The task's values.
        real(wp), intent(in) :: values(:)
        logical :: yes

        yes = nint(values(iv_status)) /= status_not_run
    end function sweep_finished

    !> Write the partial file `<output file>.partial.h5` (called serially by the task engine). A failure to write it
    !> is reported on stderr (unless quiet) and does not stop the scene.
    subroutine sweep_snapshot(self, results, done)
        !> The task list.
        class(sweep_tasks), intent(in) :: self
        !> Results so far, (n_run_values, ntask).
        real(wp), intent(in) :: results(:, :)
        !> Which tasks are done.
        logical, intent(in) :: done(:)
        type(error_type), allocatable :: error

        call write_grid_file(self, partial_path(self%cfg), .true., results, done, error)
        if (allocated(error) .and. .not. self%cfg%output%quiet) then
            write (error_unit, "(a)") "  warning: partial file not written: " // printable(error%message)
        end if
    end subroutine sweep_snapshot

    !> Number of tasks: amplitudes x frequencies x curves.
    pure function task_count(self) result(n)
        !> The task list.
        class(sweep_tasks), intent(in) :: self
        integer :: n

        n = size(self%amplitudes)*size(self%omegas)*size(self%curves)
    end function task_count

    !> Amplitude index `ia`, frequency index `iw` and curve index `ic` of task `index` (amplitude fastest).
    pure subroutine task_position(self, index, ia, iw, ic)
        !> The task list.
        class(sweep_tasks), intent(in) :: self
        !> Task index, 1..task_count().
        integer, intent(in) :: index
        !> Amplitude, frequency and curve index.
        integer, intent(out) :: ia, iw, ic
        integer :: namp, nomega

        namp = size(self%amplitudes)
        nomega = size(self%omegas)
        ia = mod(index - 1, namp) + 1
        iw = mod((index - 1)/namp, nomega) + 1
        ic = (index - 1)/(namp*nomega) + 1
    end subroutine task_position

    !> Whether frequency `iw` is run for curve `ic`: inside the curve's band gap, Omega < sqrt(1 + m^2), or the
    !> input allows frequencies outside it.
    pure function runnable(self, iw, ic) result(ok)
        !> The task list.
        class(sweep_tasks), intent(in) :: self
        !> Frequency index.
        integer, intent(in) :: iw
        !> Curve index.
        integer, intent(in) :: ic
        logical :: ok

        ok = self%omegas(iw) < band_gap_edge(self%curves(ic)%chain) .or. self%cfg%allow_outside_gap
    end function runnable

    !> Whether task `index` is run (not outside the gap).
    pure function task_is_runnable(tasks, index) result(ok)
        !> The task list.
        class(sweep_tasks), intent(in) :: tasks
        !> Task index.
        integer, intent(in) :: index
        logical :: ok
        integer :: ia, iw, ic

        call tasks%task_position(index, ia, iw, ic)
        ok = tasks%runnable(iw, ic)
    end function task_is_runnable

    !> Points of an axis: `first + i step`, i = 0, 1, ..., while at most `last` + 1e-9 (at least `first`).
    pure function axis_grid(first, last, step) result(axis)
        !> First point.
        real(wp), intent(in) :: first
        !> Last point (included up to the slack).
        real(wp), intent(in) :: last
        !> Step, > 0.
        real(wp), intent(in) :: step
        real(wp), allocatable :: axis(:)
        integer :: n, i

        n = 1
        if (step > 0.0_wp .and. last >= first) n = floor(min((last - first + grid_slack)/step, real(max_tasks, wp))) + 1
        axis = [(first + real(i, wp)*step, i=0, n - 1)]
    end function axis_grid

    !> Journal of a scene: `<output file>.journal`.
    pure function journal_path(cfg) result(path)
        !> The input.
        type(input_config), intent(in) :: cfg
        character(len=:), allocatable :: path

        path = trim(cfg%output%file) // ".journal"
    end function journal_path

    !> Partial file of a scene: `<output file>.partial.h5`.
    pure function partial_path(cfg) result(path)
        !> The input.
        type(input_config), intent(in) :: cfg
        character(len=:), allocatable :: path

        path = trim(cfg%output%file) // ".partial.h5"
    end function partial_path

    !> The codes of `/runs/status` (`supratrans_status`).
    pure function status_codes_text() result(text)
        character(len=:), allocatable :: text

        text = run_status_codes(outside_gap=.true., not_run=.true.)
    end function status_codes_text

    !> Run the scene (`run_amplitude_sweep`).
    subroutine sweep_scene_run(self, cfg, error, inv)
        !> The scene.
        class(sweep_scene), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> How the engine is invoked (a slice, a merge: `supratrans_invocation`); default: the whole scene.
        type(invocation_type), intent(in), optional :: inv

        call run_amplitude_sweep(cfg, error, inv=inv)
    end subroutine sweep_scene_run

    !> The amplitude axis, then the runs (curves x amplitudes) and their work.
    pure subroutine sweep_scene_limits(self, cfg, where, budget, error)
        !> The scene.
        class(sweep_scene), intent(in) :: self
        !> The configuration (values already within their ranges and rules).
        type(input_config), intent(in) :: cfg
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Threads and memory of the machine.
        type(scene_budget), intent(in) :: budget
        !> Allocated when a limit is exceeded.
        type(error_type), allocatable, intent(out) :: error
        real(wp) :: namp

        namp = axis_points(cfg%scene%amplitude_min, cfg%scene%amplitude_max, cfg%scene%amplitude_step)
        call check_axis(namp, "amplitude_step = " // sci(cfg%scene%amplitude_step) // " makes " // sci(namp) &
                        // " amplitudes", where, error)
        if (allocated(error)) return
        call check_tasks(cfg, real(curve_count(cfg), wp)*1.0_wp*namp, 1.0_wp, &
                         cfg%run%numerics%t_final/cfg%run%numerics%dt, "runs", where, error)
    end subroutine sweep_scene_limits

    !> An amplitude sweep is driven at one frequency, which must lie inside each curve's band gap.
    pure function sweep_scene_gap(self) result(yes)
        !> The scene.
        class(sweep_scene), intent(in) :: self
        logical :: yes

        yes = .true.
    end function sweep_scene_gap

end module supratrans_scene_sweep
