!> Scene `amplitude_sweep` (paper Figs. 2, 3, 3-and-a-half and 4): the total energy injected into the chain over
!> a whole run, 0..T, against the driving amplitude A, one curve per (potential, value of the varied parameter).
!>
!> Every (curve, amplitude) is one task of the engine `supratrans_tasks`: a full-length run (no early stop, no
!> probes, the ledger closed once at T) whose outcome is reduced to its record's scalar fields (`run_values`). The tasks
!> run on OpenMP threads; the journal `<output file>.journal` makes a killed sweep resumable, and now and then a
!> partial file `<output file>.partial.h5` (attribute `complete` = 0, runs not done yet NaN with status -1) is
!> written so that a figure can be drawn while the sweep runs or after it was killed. The final file is written
!> under a temporary name and renamed when complete; the journal and the partial file are then deleted.
!>
!> The machinery is shared with the scene `map` (`supratrans_scene_map`, paper Fig. 11), which is the same sweep
!> over a second axis, the driving frequency. Both are on the axis base (`supratrans_axis_scene`): `sweep_tasks`
!> extends `axis_tasks` with the amplitudes, the inner axis of curve x Omega x amplitude (one frequency, the &drive
!> omega, for the sweep: nomega = 1), the base owning each curve's run, the task index, a task's run at its Omega,
!> the partial snapshot, the checkpoints' names and the scene's `write_output`; `make_grid_tasks` checks the grid
!> and hands it to the scene driver (`supratrans_scene`), both scenes extend `grid_scene` (an `axis_scene` with
!> the summary), and the map extends `sweep_tasks` only to write its own axes (`write_axes`).
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
!> Task `index` = ia + namp ((iw - 1) + nomega (ic - 1)) for amplitude ia, frequency iw, curve ic (amplitude fastest:
!> the base's `task_inner`, `task_omega`, `task_curve`). The per-run datasets are stored as Fortran arrays (namp,
!> ncurve) for the sweep and (namp, nomega, ncurve) for the map, which h5py sees as (ncurve, namp) and (ncurve,
!> nomega, namp): `d[ic-1, ia-1]` and `d[ic-1, iw-1, ia-1]`. Each dataset's attribute `dimensions` names them in that
!> (h5py) order.
!>
!> The file (`write_grid_file`, the tasks' `write_file`: the axes, the per-run datasets) is written by the submodule
!> `supratrans_scene_sweep_output.f90`.
module supratrans_scene_sweep
    use, intrinsic :: iso_fortran_env, only: int64
    use supratrans_kinds, only: wp, i8, supratrans_version
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_invocation, only: invocation_type
    use supratrans_scene, only: scene_budget, scene_tasks, scene_plan
    use supratrans_axis_scene, only: axis_tasks, axis_scene, init_axes
    use supratrans_limits, only: axis_points, check_axis, check_tasks, sci
    use supratrans_config, only: input_config, run_config
    use supratrans_curves, only: curve_count
    use supratrans_validate, only: validate_config
    use supratrans_chain, only: band_gap_edge
    use supratrans_simulate, only: simulate_task, number_of_levels
    use supratrans_result, only: run_result, run_ok
    use supratrans_status, only: status_not_run, status_outside_gap, run_status_codes
    use supratrans_run_record, only: run_values, nan, run_scalars, run_scalars_names, run_scalars_values, &
        run_scalars_from_values, empty_run_scalars
    use supratrans_hdf5, only: h5_file
    use supratrans_strings, only: int_str, printable
    implicit none
    private

    !> The run record (`supratrans_run_record`), for the map scene and the tests.
    public :: run_values, run_scalars, run_scalars_names, run_scalars_values, run_scalars_from_values, empty_run_scalars
    public :: run_amplitude_sweep
    public :: sweep_tasks, init_sweep_tasks, make_grid_tasks, write_common_axes
    public :: axis_grid, journal_path, partial_path, status_codes_text

    !> Status of a run not computed (yet), and of a grid point outside the curve's band gap: the task codes of
    !> `supratrans_status`, shared by every scene.
    public :: status_not_run, status_outside_gap

    !> Slack of the end point of an axis: `first + i step` is on the axis while it is at most `last` + this.
    real(wp), parameter :: grid_slack = 1.0e-9_wp
    !> Largest number of tasks of one scene (a guard against a step that is far too small).
    integer, parameter :: max_tasks = 10000000

    !> The tasks of a sweep or map: a grid of curves x driving frequencies x amplitudes, one full run each (the axes
    !> of `axis_tasks`, the amplitudes its inner axis; its `runs` prepared for the sweep: full length, no probes, no
    !> early stop; its `omegas` the &drive omega alone for the sweep, the frequency axis for the map). Read-only
    !> while the tasks run.
    type, extends(axis_tasks), public :: sweep_tasks
        !> Scene name written to the file: 'amplitude_sweep' or 'map'.
        character(len=:), allocatable :: scene
        !> One-line description of the file written.
        character(len=:), allocatable :: description
        !> Driving amplitudes (the inner axis).
        real(wp), allocatable :: amplitudes(:)
    contains
        !> Run one task (thread-safe).
        procedure :: run => sweep_run
        !> Whether a task's values are its result (not a run stopped by a signal at its checkpoint).
        procedure :: finished => sweep_finished
        !> Write the scene's file, final or partial (`write_grid_file`).
        procedure :: write_file => write_grid_file
        !> Write the axes of the scene (the sweep: /amplitude, /curves; the map overrides it).
        procedure :: write_axes => sweep_write_axes
        !> Number of tasks.
        procedure :: task_count
        !> Whether a (frequency, curve) is run: inside the curve's band gap, or allow_outside_gap.
        procedure :: runnable
    end type sweep_tasks

    !> The scenes of a grid of full runs (`sweep_tasks`): the amplitude sweep and the map. Their file is the axis
    !> base's `write_output`; they add the summary.
    type, abstract, extends(axis_scene), public :: grid_scene
    contains
        !> How many runs ended ok, transmitting, failed; a warning for thin or unbacked verdicts.
        procedure :: summary => grid_summary
    end type grid_scene

    !> The scene `amplitude_sweep`: one full run per (curve, amplitude) at the &drive frequency.
    type, extends(grid_scene), public :: sweep_scene
    contains
        !> Its tasks: curves x amplitudes at the &drive frequency.
        procedure :: make_tasks => sweep_make_tasks
        !> Its axes, tasks, work and memory against the limits.
        procedure :: check_limits => sweep_scene_limits
        procedure :: plan => sweep_scene_plan
        !> At one frequency: inside the band gap.
        procedure :: gap_rule => sweep_scene_gap
        !> At the &drive frequency: no frequency axis of its own.
        procedure :: frequency_axis => sweep_scene_frequency_axis
    end type sweep_scene

    interface
        !> Write the scene's HDF5 file `path` from the results so far (atomically: built in memory, written to a fresh
        !> temporary, renamed). With every task done the file is the final output (root attribute `complete` = 1);
        !> otherwise a partial file (`complete` = 0) in which the missing runs are NaN with status `status_not_run`.
        module subroutine write_grid_file(self, path, results, done, complete, elapsed, error)
            !> The task list.
            class(sweep_tasks), intent(in) :: self
            !> Path of the file.
            character(len=*), intent(in) :: path
            !> Results, (size(run_scalars_names), ntask).
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
        pure module subroutine jumps_along_amplitude(s, namp, jump, change)
            !> The records of every task.
            type(run_scalars), intent(in) :: s(:)
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
    !> left one. The scene's `run` (`supratrans_scene`), under the name the tests and the benchmark call.
    subroutine run_amplitude_sweep(cfg, error, inv)
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Error, allocated on failure (bad configuration, journal of another input, unwritable files). Runs that
        !> diverge or whose Newton fails are not errors: they are recorded with their status.
        type(error_type), allocatable, intent(out) :: error
        !> How the engine is invoked (a slice, a merge: `supratrans_invocation`); default: the whole scene.
        type(invocation_type), intent(in), optional :: inv
        type(sweep_scene) :: scene

        call scene%run(cfg, error, inv)
    end subroutine run_amplitude_sweep

    !> The tasks of the sweep: every curve's runs over the amplitude axis at the &drive frequency.
    subroutine sweep_make_tasks(self, cfg, tasks, error)
        !> The scene.
        class(sweep_scene), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Its tasks (`make_grid_tasks`).
        type(scene_tasks), intent(inout) :: tasks
        !> Error, allocated when the configuration is not valid or makes too many runs.
        type(error_type), allocatable, intent(out) :: error
        class(sweep_tasks), allocatable :: list

        allocate (sweep_tasks :: list)
        call init_sweep_tasks(list, cfg, tasks%inv, "amplitude_sweep", "Total energy injected vs driving amplitude: " &
                              // "one full run (0..T) per curve and amplitude (paper Figs. 2, 3, 3-and-a-half, 4)", &
                              [cfg%run%drive%omega], .false., error)
        if (allocated(error)) return
        call make_grid_tasks(list, tasks, error)
    end subroutine sweep_make_tasks

    !> Fill a task list: the axes (`init_axes`: the input, the invocation, the frequencies, the run of every curve,
    !> the partial file's and the checkpoints' names) with the amplitude axis of the &scene group as the inner axis,
    !> the scene's name and description, and the runs prepared for the sweep.
    subroutine init_sweep_tasks(tasks, cfg, inv, scene, description, omegas, omega_axis, error)
        !> The task list (a `sweep_tasks` or an extension of it).
        class(sweep_tasks), intent(inout) :: tasks
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> How the engine is invoked (slice, merge: `supratrans_invocation`).
        type(invocation_type), intent(in) :: inv
        !> Scene name.
        character(len=*), intent(in) :: scene
        !> One-line description of the output file.
        character(len=*), intent(in) :: description
        !> Driving frequencies of the grid.
        real(wp), intent(in) :: omegas(:)
        !> Whether the frequency is an axis of the data (map).
        logical, intent(in) :: omega_axis
        !> Error, allocated when the frequency axis is empty.
        type(error_type), allocatable, intent(out) :: error
        integer :: ic

        tasks%scene = scene
        tasks%description = description
        tasks%omega_axis = omega_axis
        tasks%amplitudes = axis_grid(cfg%scene%amplitude_min, cfg%scene%amplitude_max, cfg%scene%amplitude_step)
        if (allocated(tasks%runs)) deallocate (tasks%runs)
        call init_axes(tasks, cfg, inv, size(tasks%amplitudes), error, omegas)
        if (allocated(error)) return
        do ic = 1, size(tasks%runs)
            ! the figures need the totals at T: no early stop, no probes, the ledger closed once at the end
            tasks%runs(ic)%detect%stop_when_decided = .false.
            if (allocated(tasks%runs(ic)%record%probes)) deallocate (tasks%runs(ic)%record%probes)
            allocate (tasks%runs(ic)%record%probes(0))
            tasks%runs(ic)%record%probe_every = int(min(number_of_levels(tasks%runs(ic)), int(huge(1), i8)))
            tasks%runs(ic)%record%ledger_every = huge(1)
        end do
    end subroutine init_sweep_tasks

    !> Hand a filled task list of a sweep or map to the scene driver: validate its input, bound its number of runs,
    !> and name its records' fields, its tasks ("runs") and its first line (the scene, the grid, the output file).
    subroutine make_grid_tasks(list, tasks, error)
        !> The task list, filled by `init_sweep_tasks`; moved into `tasks%list`.
        class(sweep_tasks), allocatable, intent(inout) :: list
        !> The scene's tasks.
        type(scene_tasks), intent(inout) :: tasks
        !> Error, allocated when the configuration is not valid or makes too many runs.
        type(error_type), allocatable, intent(out) :: error
        integer(int64) :: ntask
        integer :: nskip, i

        call validate_config(list%cfg, error)
        if (allocated(error)) return
        if (.not. allocated(list%cfg%source)) then
            call fatal_error(error, "configuration: cfg%source must name the input file (it fingerprints the " &
                             // "journal)", err_input)
            return
        end if
        ntask = int(size(list%amplitudes), int64)*int(size(list%omegas), int64)*int(size(list%runs), int64)
        if (ntask > max_tasks) then
            call fatal_error(error, list%cfg%source // ": &scene: " // int_str(int(min(ntask, 2000000000_int64))) &
                             // " runs is more than the limit " // int_str(max_tasks) // " (check the steps)", err_input)
            return
        end if

        tasks%header = "supratrans " // supratrans_version // ": " // list%scene // " from " // list%cfg%source &
                       // ": " // int_str(size(list%runs)) // " curve(s) x "
        if (list%omega_axis) tasks%header = tasks%header // int_str(size(list%omegas)) // " frequencies x "
        tasks%header = tasks%header // int_str(size(list%amplitudes)) // " amplitudes = " // int_str(list%task_count()) &
                       // " runs -> " // trim(list%cfg%output%file)
        nskip = 0
        do i = 1, list%task_count()
            if (.not. task_is_runnable(list, i)) nskip = nskip + 1
        end do
        if (nskip > 0) tasks%header = tasks%header // " (" // int_str(nskip) // " outside the band gap, not run)"
        tasks%header = printable(tasks%header)
        tasks%count = list%task_count()
        tasks%fields = run_scalars_names
        tasks%label = "runs"
        call move_alloc(list, tasks%list)
    end subroutine make_grid_tasks

    !> The runs ok (transmitting) and failed, and a warning when verdicts have a thin margin or change along the
    !> amplitude axis without a jump of the energy.
    function grid_summary(self, cfg, tasks) result(text)
        !> The scene.
        class(grid_scene), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> The tasks (a `sweep_tasks`), their records.
        type(scene_tasks), intent(in) :: tasks
        character(len=:), allocatable :: text
        integer :: nfail, ntrans, nthin, nflat, namp, i
        real(wp), allocatable :: jump(:)
        integer, allocatable :: change(:)
        type(run_scalars) :: s(size(tasks%results, 2))

        do i = 1, size(s)
            s(i) = run_scalars_from_values(tasks%results(:, i))
        end do
        associate (status => s%status)
            nfail = count(status > 0)
            ntrans = count(status == run_ok .and. s%transmitting == 1)
            text = "  " // int_str(count(status == run_ok)) // " runs ok (" // int_str(ntrans) // " transmitting), " &
                   // int_str(nfail) // " failed (see /runs/failures)"
        end associate
        namp = 1
        select type (list => tasks%list)
        class is (sweep_tasks)
            namp = size(list%amplitudes)
        end select
        nthin = count(s%thin_verdict == 1)
        call jumps_along_amplitude(s, namp, jump, change)
        associate (min_jump => cfg%scene%min_energy_jump)
            nflat = count(change == 1 .and. .not. (jump >= min_jump .or. jump <= 1.0_wp/min_jump))
        end associate
        if (nthin > 0 .or. nflat > 0) text = text // new_line("a") // "  warning: " // int_str(nthin) &
            // " verdict(s) with a thin margin (/runs/thin_verdict), " // int_str(nflat) // " verdict change(s) " &
            // "without an energy jump (/runs/energy_jump): check them"
    end function grid_summary

    !> Run one task: the curve's run at the task's frequency and amplitude, reduced to `run_values`; a point
    !> outside the curve's band gap is not run (status `status_outside_gap`).
    subroutine sweep_run(self, index, values)
        !> The task list.
        class(sweep_tasks), intent(in) :: self
        !> Task index, 1..task_count().
        integer, intent(in) :: index
        !> The task's results, its record's values (`run_scalars_values`).
        real(wp), intent(out) :: values(:)
        type(run_config) :: run
        type(run_result) :: result
        type(run_scalars) :: s
        character(len=12) :: task_text

        s = empty_run_scalars()
        if (.not. self%runnable(self%task_omega(index), self%task_curve(index))) then
            s%status = status_outside_gap
            values = run_scalars_values(s)
            return
        end if
        run = self%task_run(index)
        run%drive%amplitude = self%amplitudes(self%task_inner(index))
        write (task_text, "(i0)") index
        call simulate_task(run, result, self%checkpoint_prefix // trim(task_text), self%fingerprint // " task " &
                           // trim(task_text), self%cfg%output%checkpoint_every, self%cfg%output%quiet)
        if (result%interrupted) then
            ! stopped by a signal at its checkpoint: no result (not journaled; a rerun resumes it)
            s%status = status_not_run
            values = run_scalars_values(s)
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
        type(run_scalars) :: s

        s = run_scalars_from_values(values)
        yes = s%status /= status_not_run
    end function sweep_finished

    !> Number of tasks: amplitudes x frequencies x curves.
    pure function task_count(self) result(n)
        !> The task list.
        class(sweep_tasks), intent(in) :: self
        integer :: n

        n = size(self%amplitudes)*size(self%omegas)*size(self%runs)
    end function task_count

    !> Whether frequency `iw` is run for curve `ic`: inside the curve's band gap, Omega < sqrt(V''(0) + m^2), or the
    !> input allows frequencies outside it.
    pure function runnable(self, iw, ic) result(ok)
        !> The task list.
        class(sweep_tasks), intent(in) :: self
        !> Frequency index.
        integer, intent(in) :: iw
        !> Curve index.
        integer, intent(in) :: ic
        logical :: ok

        ok = self%omega_at(ic, iw) < band_gap_edge(self%runs(ic)%chain) .or. self%cfg%allow_outside_gap
    end function runnable

    !> Whether task `index` is run (not outside the gap).
    pure function task_is_runnable(tasks, index) result(ok)
        !> The task list.
        class(sweep_tasks), intent(in) :: tasks
        !> Task index.
        integer, intent(in) :: index
        logical :: ok

        ok = tasks%runnable(tasks%task_omega(index), tasks%task_curve(index))
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
        type(scene_plan) :: p

        namp = axis_points(cfg%scene%amplitude_min, cfg%scene%amplitude_max, cfg%scene%amplitude_step)
        call check_axis(namp, "amplitude_step = " // sci(cfg%scene%amplitude_step) // " makes " // sci(namp) &
                        // " amplitudes", where, error)
        if (allocated(error)) return
        p = sweep_scene_plan(self, cfg)
        call check_tasks(cfg, p%tasks, p%runs_per_task, p%steps, p%noun, where, error)
    end subroutine sweep_scene_limits

    !> The runs: curves x amplitudes, each of t_final/dt steps.
    pure function sweep_scene_plan(self, cfg) result(p)
        !> The scene.
        class(sweep_scene), intent(in) :: self
        !> The configuration (values within their ranges).
        type(input_config), intent(in) :: cfg
        type(scene_plan) :: p

        p%tasks = real(curve_count(cfg), wp)*axis_points(cfg%scene%amplitude_min, cfg%scene%amplitude_max, &
                                                         cfg%scene%amplitude_step)
        p%noun = "runs"
        p%steps = cfg%run%numerics%t_final/cfg%run%numerics%dt
    end function sweep_scene_plan

    !> An amplitude sweep is driven at one frequency, which must lie inside each curve's band gap.
    pure function sweep_scene_gap(self) result(yes)
        !> The scene.
        class(sweep_scene), intent(in) :: self
        logical :: yes

        yes = .true.
    end function sweep_scene_gap

    !> An amplitude sweep is driven at the &drive frequency: it has no frequency axis of its own.
    pure function sweep_scene_frequency_axis(self) result(yes)
        !> The scene.
        class(sweep_scene), intent(in) :: self
        logical :: yes

        yes = .false.
    end function sweep_scene_frequency_axis

end module supratrans_scene_sweep
