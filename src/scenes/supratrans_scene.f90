!> A scene: the study one namelist describes (the `&scene kind`: a timeseries, an amplitude sweep, a map, a
!> bifurcation diagram of the threshold A_th(Omega), ...), behind one abstract type.
!>
!> What the rest of the program asks a scene, and nothing else:
!> - `run`: run it and write its output file. One driver for every scene (`run_scene`, the submodule
!>   `supratrans_scene_driver`), not overridden: it refuses an existing output (unless overwrite), asks the scene to
!>   `make_tasks`, prints the scene's first line, runs the tasks on the task engine (`supratrans_tasks`: journal
!>   `<output>.journal`, OpenMP threads, slices, merge), has the scene `write_output` from the records gathered,
!>   deletes the journal and the partial file `<output>.partial.h5`, and prints the scene's `summary`. A scene that
!>   is one run (a timeseries) is run by its own `run_one` instead;
!> - `one_run`: whether it is one run rather than a task list (no `--slice`, no journal; it keeps its records, so
!>   its memory estimate counts them);
!> - `gap_rule`: whether the drive's Omega must lie inside the band gap 0 < Omega < sqrt(V''(0) + m^2) (unless
!>   allow_outside_gap): scenes at one frequency; scenes over a frequency axis skip the points outside instead;
!> - `check_limits`: its own sizes (axes, task count, work, memory) against the limits of `supratrans_limits`;
!> - `check_input`: the scene's own rules that need more than a pure check (a method's linear stability limit),
!>   made by validation, so that `--check` refuses what the run would and nothing is created before.
!>
!> A scene of tasks implements three phases: `make_tasks` (its extension of `task_list`, which runs one task and
!> writes the partial snapshot, with the names of a task's values, what the progress lines call the tasks and its
!> first line), `write_output` (its file from the records, which tasks are done and the wall time) and, if it has
!> one, `summary`. A one-run scene implements `run_one`.
!>
!> `new_scene` (implemented in the submodule `supratrans_scene_factory`) is the only place that maps a kind's name
!> to a module: adding a scene is one module extending `scene_type` and one line there. The submodules keep the
!> modules that validate an input (which ask the scene) free of the scene modules and the task engine (which use
!> them).
module supratrans_scene
    use, intrinsic :: iso_fortran_env, only: error_unit
    use supratrans_kinds, only: wp
    use supratrans_strings, only: printable
    use supratrans_error, only: error_type, fatal_error, err_runtime
    use supratrans_invocation, only: invocation_type
    use supratrans_config, only: input_config
    use supratrans_task_list, only: task_list
    implicit none
    private

    public :: scene_type, scene_budget, scene_tasks, scene_plan, new_scene, wrong_tasks, warn_partial

    !> Longest name of a field of a task's record.
    integer, parameter, public :: field_name_length = 64

    !> What the machine gives a scene, for the memory estimates of `check_limits`.
    type :: scene_budget
        !> OpenMP threads the scene's tasks run on (each holds one run).
        integer :: threads = 1
        !> Bytes of memory available to the process (0: unknown, nothing is checked).
        real(wp) :: memory = 0.0_wp
        !> What gives `memory` (for messages): "MemAvailable of /proc/meminfo", a cgroup file, "ulimit -v", ...
        character(len=:), allocatable :: source
    end type scene_budget

    !> What a scene will run, from its sizes alone (nothing made, nothing run): for `--check`'s count and estimate,
    !> and the numbers `check_limits` bounds. Real counts (they may be huge before they are checked).
    type :: scene_plan
        !> Number of tasks (0: not known).
        real(wp) :: tasks = 0.0_wp
        !> What a task is, plural ("runs", "searches").
        character(len=:), allocatable :: noun
        !> Runs of one task (a search: the runs it is expected to ask for).
        real(wp) :: runs_per_task = 1.0_wp
        !> Time steps of one run (0: not known).
        real(wp) :: steps = 0.0_wp
        !> The scene's own estimate of its work in Newton oscillator-steps, for a scene whose tasks are not runs of
        !> one length (continuation, stability, work_precision); 0: tasks x runs x steps x N x the method's cost.
        real(wp) :: work = 0.0_wp
        !> Whether that work runs one task at a time whatever the threads (work_precision's timed runs).
        logical :: serial = .false.
        !> What `work` counts, for the line of `--check` (with `work`).
        character(len=:), allocatable :: counts
    end type scene_plan

    !> The tasks of one run of a scene and what the task engine gathers of them: made by the scene's `make_tasks`,
    !> run by the driver, read by the scene's `write_output` and `summary`.
    type :: scene_tasks
        !> The tasks: the scene's extension of `task_list`.
        class(task_list), allocatable :: list
        !> Number of tasks.
        integer :: count = 0
        !> Names of the values of a task's record, in their order (the journal's header names them).
        character(len=field_name_length), allocatable :: fields(:)
        !> What the progress lines call the tasks (e.g. "runs").
        character(len=:), allocatable :: label
        !> The scene's first progress line, printed before the tasks run unless the output is quiet (unallocated:
        !> none).
        character(len=:), allocatable :: header
        !> How the engine is invoked (a slice, a merge: `supratrans_invocation`); set before `make_tasks`.
        type(invocation_type) :: inv
        !> The tasks' records, (values, tasks), set by the engine.
        real(wp), allocatable :: results(:, :)
        !> Which tasks are done (every one when the output is written).
        logical, allocatable :: done(:)
        !> Wall time of the scene (s): this invocation's, or for a merge the slices' summed wall time.
        real(wp) :: elapsed = -1.0_wp
    end type scene_tasks

    !> A scene: a study made of runs (or threshold searches) of the chain, written to one HDF5 file.
    type, abstract :: scene_type
    contains
        !> Run the scene of a validated input and write its output file (the driver `run_scene`).
        procedure, non_overridable :: run => run_scene
        !> Make the scene's tasks (a scene of tasks overrides it).
        procedure :: make_tasks
        !> Write the output file from the tasks' records (a scene of tasks overrides it).
        procedure :: write_output
        !> The lines printed once the output is written (default: none).
        procedure :: summary
        !> Run a one-run scene and write its output (a one-run scene overrides it).
        procedure :: run_one
        !> Check the scene's own sizes (axes, tasks, work, memory) against the limits (default: nothing beyond the
        !> limits of one run).
        procedure :: check_limits
        !> Check the scene's own rules on the input that need more than a pure check (default: none).
        procedure :: check_input
        !> What the scene will run: tasks, runs and steps (default: one run of the input, or not known).
        procedure :: plan
        !> Whether the scene is one run rather than a task list (default: a task list).
        procedure :: one_run
        !> Whether the drive's Omega must lie inside the band gap (default: no).
        procedure :: gap_rule
        !> Whether the scene runs its own axis of frequencies (omega_min .. omega_max), so that `&drive omega` is
        !> not used (default: no).
        procedure :: frequency_axis
        !> The keys of &chain, &drive and &numerics the scene sets itself in every task, which `vary` may not name
        !> (default: the drive's amplitude, and its omega where the scene runs its own frequency axis).
        procedure :: sets_itself
    end type scene_type

    interface
        !> The scene of kind `kind` (a name of `scene_choices`); an error of status `err_input` naming the known
        !> kinds when there is none of that name.
        module subroutine new_scene(kind, scene, error)
            !> The scene's name (&scene kind).
            character(len=*), intent(in) :: kind
            !> The scene, allocated on success.
            class(scene_type), allocatable, intent(out) :: scene
            !> Error, allocated when the kind is unknown.
            type(error_type), allocatable, intent(out) :: error
        end subroutine new_scene

        !> Run the scene `cfg` describes and write `cfg%output%file`: the skeleton every scene of tasks shares (see
        !> the module documentation), or the one-run scene's `run_one`.
        module subroutine run_scene(self, cfg, error, inv, keep_journal)
            !> The scene.
            class(scene_type), intent(in) :: self
            !> The validated input.
            type(input_config), intent(in) :: cfg
            !> Error, allocated on failure (output exists, bad scene keys, journal of another input, stopped by a
            !> signal, unwritable files). Runs that fail are no error: the scene records them.
            type(error_type), allocatable, intent(out) :: error
            !> How the engine is invoked (a slice, a merge: `supratrans_invocation`); default: the whole scene.
            type(invocation_type), intent(in), optional :: inv
            !> Keep the journal after a complete run (tests of the resume); default false.
            logical, intent(in), optional :: keep_journal
        end subroutine run_scene
    end interface

contains

    !> Make the tasks of the scene `cfg` describes (`tasks%inv` set): a scene of tasks overrides it; here, an error.
    subroutine make_tasks(self, cfg, tasks, error)
        !> The scene.
        class(scene_type), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Its tasks: on return `list`, `count`, `fields`, `label`, `header`.
        type(scene_tasks), intent(inout) :: tasks
        !> Error, allocated when the scene's keys do not make a task list.
        type(error_type), allocatable, intent(out) :: error

        call fatal_error(error, trim(cfg%scene%kind) // ": this scene makes no task list", err_runtime)
    end subroutine make_tasks

    !> Write `cfg%output%file` from the records of every task: a scene of tasks overrides it; here, an error.
    subroutine write_output(self, cfg, tasks, error)
        !> The scene.
        class(scene_type), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> The tasks, their records and the wall time.
        type(scene_tasks), intent(in) :: tasks
        !> Error, allocated when the file is not written (nothing is then left under its name).
        type(error_type), allocatable, intent(out) :: error

        call fatal_error(error, trim(cfg%scene%kind) // ": this scene writes no file of task records", err_runtime)
    end subroutine write_output

    !> The lines printed once the output is written (joined by new lines; "": none). Default: none.
    function summary(self, cfg, tasks) result(text)
        !> The scene.
        class(scene_type), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> The tasks, their records and the wall time.
        type(scene_tasks), intent(in) :: tasks
        character(len=:), allocatable :: text

        text = ""
    end function summary

    !> Run a one-run scene and write its output: a one-run scene overrides it; here, an error.
    subroutine run_one(self, cfg, inv, error)
        !> The scene.
        class(scene_type), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> How it is invoked (the interval of its progress lines).
        type(invocation_type), intent(in) :: inv
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error

        call fatal_error(error, trim(cfg%scene%kind) // ": this scene is not one run", err_runtime)
    end subroutine run_one

    !> The error of a scene's phase handed a task list of another kind than the `expected` one its `make_tasks`
    !> makes (a defect of the program, not of the input).
    pure subroutine wrong_tasks(error, expected)
        !> The error, allocated.
        type(error_type), allocatable, intent(out) :: error
        !> The kind of task list the phase expected.
        character(len=*), intent(in) :: expected

        call fatal_error(error, "scene: a task list that is not a " // expected // " handed to its phases", err_runtime)
    end subroutine wrong_tasks

    !> The one warning of a snapshot whose partial output could not be written (on stderr, unless `quiet`): a
    !> snapshot's failure is not the run's, since the journal, not that file, is what a resumed run reads.
    subroutine warn_partial(error, quiet)
        !> The snapshot's error (nothing is said when it is not allocated).
        type(error_type), allocatable, intent(in) :: error
        !> &output quiet.
        logical, intent(in) :: quiet

        if (allocated(error) .and. .not. quiet) then
            write (error_unit, "(a)") "  warning: partial output not written: " // printable(error%message)
        end if
    end subroutine warn_partial

    !> The scene's own sizes against the limits: none by default (a scene of a few runs, each bounded by the limits
    !> of one run that `check_limits` of `supratrans_limits` checks for every scene).
    pure subroutine check_limits(self, cfg, where, budget, error)
        !> The scene.
        class(scene_type), intent(in) :: self
        !> The configuration (values already within their ranges and rules).
        type(input_config), intent(in) :: cfg
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Threads and memory of the machine.
        type(scene_budget), intent(in) :: budget
        !> Allocated when a limit is exceeded.
        type(error_type), allocatable, intent(out) :: error
    end subroutine check_limits

    !> The scene's own rules on the input beyond the pure checks: none by default.
    subroutine check_input(self, cfg, where, error)
        !> The scene.
        class(scene_type), intent(in) :: self
        !> The configuration (values already within their ranges, rules and limits).
        type(input_config), intent(in) :: cfg
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Allocated when a rule is broken.
        type(error_type), allocatable, intent(out) :: error
    end subroutine check_input

    !> What the scene will run: a one-run scene, its run of t_final/dt steps; another, not known unless it says.
    pure function plan(self, cfg) result(p)
        !> The scene.
        class(scene_type), intent(in) :: self
        !> The configuration (values within their ranges).
        type(input_config), intent(in) :: cfg
        type(scene_plan) :: p

        p%noun = "runs"
        if (.not. self%one_run()) return
        p%tasks = 1.0_wp
        p%noun = "run"
        p%steps = cfg%run%numerics%t_final/cfg%run%numerics%dt
    end function plan

    !> Whether the scene is one run rather than a task list: false unless a scene says so.
    pure function one_run(self) result(yes)
        !> The scene.
        class(scene_type), intent(in) :: self
        logical :: yes

        yes = .false.
    end function one_run

    !> Whether the drive's Omega must lie inside the band gap: false unless a scene says so.
    pure function gap_rule(self) result(yes)
        !> The scene.
        class(scene_type), intent(in) :: self
        logical :: yes

        yes = .false.
    end function gap_rule

    !> Whether the scene runs its own frequency axis: false unless a scene says so.
    pure function frequency_axis(self) result(yes)
        !> The scene.
        class(scene_type), intent(in) :: self
        logical :: yes

        yes = .false.
    end function frequency_axis

    !> Whether the scene sets `key` (of &chain, &drive or &numerics) itself in every task: the drive's amplitude (each
    !> scene with curves runs its own amplitudes: an axis, a search, stairs or a branch), and omega with a frequency
    !> axis.
    pure logical function sets_itself(self, key) result(yes)
        !> The scene.
        class(scene_type), intent(in) :: self
        !> The key's name.
        character(len=*), intent(in) :: key

        yes = key == "amplitude" .or. (self%frequency_axis() .and. key == "omega")
    end function sets_itself

end module supratrans_scene
