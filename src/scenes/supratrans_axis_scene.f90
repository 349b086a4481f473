!> The base of the scenes of tasks over the axes curve x Omega (x an inner axis of the scene's own): bifurcation,
!> continuation (by shooting and by harmonic balance), hysteresis (the stair lengths its inner axis), and the
!> amplitude sweep and the map (the amplitudes their inner axis; the sweep at the one &drive Omega, nomega = 1).
!>
!> It owns what those scenes shared as copies: the frequency axis Omega_i = omega_min + i omega_step (`scene_omegas`,
!> refused when empty; a scene may hand its own axis to `init_axes`), the run of each curve, the task index
!> t = ((curve - 1) nomega + iomega - 1) ninner + iinner and its run at its Omega (`task_run`, `curve_run_at`: the one
!> place a run's drive frequency is set from the axis), the partial snapshot (`<output>.partial.h5`, written by the scene's own
!> writer with `complete` = 0), and the scene's `write_output` (its writer, with the complete records and the wall
!> time). A scene extends `axis_tasks` with what it adds (its `run` of one task, its file `write_file`, its own runs or
!> inner axis) and `axis_scene` with its tasks (`make_tasks`, which calls `init_axes`), its summary and its checks.
module supratrans_axis_scene
    use supratrans_kinds, only: wp
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_invocation, only: invocation_type
    use supratrans_config, only: input_config, run_config
    use supratrans_task_list, only: task_list
    use supratrans_scene, only: scene_type, scene_tasks, wrong_tasks, warn_partial
    use supratrans_curves, only: curve_count, curve_run
    use supratrans_threshold, only: search_grid_size
    use supratrans_tasks, only: input_fingerprint
    implicit none
    private

    public :: init_axes, scene_omegas, axis_task_run

    !> The tasks of a scene over curve x Omega (x an inner axis): task t = ((curve - 1) nomega + iomega - 1) ninner
    !> + iinner.
    type, abstract, extends(task_list), public :: axis_tasks
        !> The validated input.
        type(input_config) :: cfg
        !> How the engine is invoked (slice, merge: `supratrans_invocation`).
        type(invocation_type) :: inv
        !> Run of each curve (`curve_run`; a scene may prepare it further), the drive's Omega set per task.
        type(run_config), allocatable :: runs(:)
        !> The frequencies Omega_i.
        real(wp), allocatable :: omegas(:)
        !> Points of the scene's inner axis per (curve, Omega) (1: none).
        integer :: ninner = 1
        !> The frequency is an axis of the tasks (and of the data). False for the amplitude sweep: each task runs at its
        !> curve's own &drive omega (which `vary = 'omega'` sets), `omegas` being the one point of the &drive omega.
        logical :: omega_axis = .true.
        !> Path of the partial output written by `snapshot`: `<output>.partial.h5`.
        character(len=:), allocatable :: partial_path
        !> Mid-run checkpoints of task t: `<checkpoint_prefix><t>`, bound to `fingerprint` and t (scenes that
        !> checkpoint their runs).
        character(len=:), allocatable :: checkpoint_prefix, fingerprint
    contains
        !> Write the partial output (the scene's `write_file`, `complete` = 0); a failure is a warning.
        procedure :: snapshot => axis_snapshot
        !> Write the scene's file from the tasks' records.
        procedure(write_file_interface), deferred :: write_file
        !> The curve of a task.
        procedure, non_overridable :: task_curve
        !> The index of a task's Omega in `omegas`.
        procedure, non_overridable :: task_omega
        !> The index of a task on the inner axis.
        procedure, non_overridable :: task_inner
        !> The run of a task: its curve's run at its Omega.
        procedure :: task_run => axis_task_run
        !> The run of a task from another run per curve (a scene's screening or checking runs), at its Omega.
        procedure, non_overridable :: run_at
        !> The run of a curve at a point of the frequency axis.
        procedure, non_overridable :: curve_run_at
        !> The Omega of a curve at a point of the frequency axis.
        procedure, non_overridable :: omega_at
    end type axis_tasks

    abstract interface
        !> Write the scene's file `path` (built in memory, written atomically): tasks not done are pending.
        subroutine write_file_interface(self, path, results, done, complete, elapsed, error)
            import :: axis_tasks, wp, error_type
            !> The tasks.
            class(axis_tasks), intent(in) :: self
            !> Final path of the file.
            character(len=*), intent(in) :: path
            !> Results, (values, tasks).
            real(wp), intent(in) :: results(:, :)
            !> Which tasks are done.
            logical, intent(in) :: done(:)
            !> Whether this is the complete result (root attribute `complete`).
            logical, intent(in) :: complete
            !> Wall time of the scene (s); negative when unknown (partial files).
            real(wp), intent(in) :: elapsed
            !> Error, allocated on failure (the file is then not created).
            type(error_type), allocatable, intent(out) :: error
        end subroutine write_file_interface
    end interface

    !> A scene whose tasks are `axis_tasks`: it runs its own frequency axis, and its file is its tasks' `write_file`.
    type, abstract, extends(scene_type), public :: axis_scene
    contains
        !> Write the scene's file, complete, with the scene's wall time (the tasks' `write_file`).
        procedure :: write_output => axis_write_output
        !> It runs omega_min .. omega_max: `&drive omega` is not used (the amplitude sweep, at &drive omega, says no).
        procedure :: frequency_axis => axis_frequency_axis
    end type axis_scene

contains

    !> The frequency axis of a scene: Omega_i = omega_min + i omega_step <= omega_max, i = 0, 1, ... (integer index;
    !> a point within 1e-9 steps of omega_max is kept).
    pure function scene_omegas(cfg) result(omegas)
        !> The input.
        type(input_config), intent(in) :: cfg
        real(wp), allocatable :: omegas(:)
        integer :: i, n

        n = search_grid_size(cfg%scene%omega_min, cfg%scene%omega_max, cfg%scene%omega_step)
        allocate (omegas(n))
        do i = 1, n
            omegas(i) = cfg%scene%omega_min + real(i - 1, wp)*cfg%scene%omega_step
        end do
    end function scene_omegas

    !> Set the axes of a scene's tasks: the input, the invocation, the frequency axis, each curve's run, the inner
    !> axis' length, the partial output and the checkpoints' names; an error when the frequency axis is empty.
    subroutine init_axes(list, cfg, inv, ninner, error, omegas)
        !> The scene's tasks.
        class(axis_tasks), intent(inout) :: list
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> How the engine is invoked.
        type(invocation_type), intent(in) :: inv
        !> Points of the inner axis per (curve, Omega).
        integer, intent(in) :: ninner
        !> Error, allocated when the frequency axis is empty.
        type(error_type), allocatable, intent(out) :: error
        !> The frequency axis, when it is not omega_min .. omega_max by omega_step (`scene_omegas`): the sweep's
        !> one &drive Omega, the map's own grid.
        real(wp), intent(in), optional :: omegas(:)
        character(len=:), allocatable :: output, source
        integer :: ic

        list%cfg = cfg
        list%inv = inv
        if (present(omegas)) then
            list%omegas = omegas
        else
            list%omegas = scene_omegas(cfg)
        end if
        list%ninner = ninner
        if (size(list%omegas) < 1) then
            source = "configuration"
            if (allocated(cfg%source)) source = cfg%source
            call fatal_error(error, source // ": &scene: the frequency axis omega_min .. omega_max is empty", err_input)
            return
        end if
        allocate (list%runs(curve_count(cfg)))
        do ic = 1, size(list%runs)
            list%runs(ic) = curve_run(cfg, ic)
        end do
        output = trim(cfg%output%file)
        list%partial_path = output // ".partial.h5"
        list%checkpoint_prefix = output // ".checkpoint-"
        list%fingerprint = input_fingerprint(cfg)
    end subroutine init_axes

    !> The curve of task `index`.
    pure integer function task_curve(self, index)
        !> The tasks.
        class(axis_tasks), intent(in) :: self
        !> Task index.
        integer, intent(in) :: index

        task_curve = (index - 1)/(self%ninner*size(self%omegas)) + 1
    end function task_curve

    !> The index in `omegas` of the Omega of task `index`.
    pure integer function task_omega(self, index)
        !> The tasks.
        class(axis_tasks), intent(in) :: self
        !> Task index.
        integer, intent(in) :: index

        task_omega = mod((index - 1)/self%ninner, size(self%omegas)) + 1
    end function task_omega

    !> The index on the inner axis of task `index`.
    pure integer function task_inner(self, index)
        !> The tasks.
        class(axis_tasks), intent(in) :: self
        !> Task index.
        integer, intent(in) :: index

        task_inner = mod(index - 1, self%ninner) + 1
    end function task_inner

    !> The run of task `index`: its curve's run driven at its Omega (a scene that overrides `task_run` calls it).
    pure function axis_task_run(self, index) result(run)
        !> The tasks.
        class(axis_tasks), intent(in) :: self
        !> Task index.
        integer, intent(in) :: index
        type(run_config) :: run

        run = self%run_at(index, self%runs)
    end function axis_task_run

    !> The run of task `index` taken from `runs` (one per curve: a scene's screening or checking runs) at its Omega.
    pure function run_at(self, index, runs) result(run)
        !> The tasks.
        class(axis_tasks), intent(in) :: self
        !> Task index.
        integer, intent(in) :: index
        !> A run per curve.
        type(run_config), intent(in) :: runs(:)
        type(run_config) :: run

        run = self%curve_run_at(self%task_curve(index), self%task_omega(index), runs)
    end function run_at

    !> The run of curve `icurve` at point `iomega` of the frequency axis (`omega_at`), from `runs` (default: the
    !> curves' runs): the one place a run's drive frequency is set from the axis.
    pure function curve_run_at(self, icurve, iomega, runs) result(run)
        !> The tasks.
        class(axis_tasks), intent(in) :: self
        !> Curve index.
        integer, intent(in) :: icurve
        !> Index on the frequency axis.
        integer, intent(in) :: iomega
        !> A run per curve (default: the curves' runs).
        type(run_config), intent(in), optional :: runs(:)
        type(run_config) :: run

        if (present(runs)) then
            run = runs(icurve)
        else
            run = self%runs(icurve)
        end if
        run%drive%omega = self%omega_at(icurve, iomega, runs)
    end function curve_run_at

    !> The Omega of curve `icurve` at point `iomega` of the frequency axis: `omegas(iomega)`, or the curve's own
    !> &drive omega when the scene has no frequency axis (`omega_axis` false).
    pure function omega_at(self, icurve, iomega, runs) result(omega)
        !> The tasks.
        class(axis_tasks), intent(in) :: self
        !> Curve index.
        integer, intent(in) :: icurve
        !> Index on the frequency axis.
        integer, intent(in) :: iomega
        !> A run per curve (default: the curves' runs).
        type(run_config), intent(in), optional :: runs(:)
        real(wp) :: omega

        if (self%omega_axis) then
            omega = self%omegas(iomega)
        else if (present(runs)) then
            omega = runs(icurve)%drive%omega
        else
            omega = self%runs(icurve)%drive%omega
        end if
    end function omega_at

    !> Write the results so far to `<output>.partial.h5` (root attribute `complete = 0`); failures are a warning (the
    !> journal, not this file, is what a resumed run reads).
    subroutine axis_snapshot(self, results, done)
        !> The tasks.
        class(axis_tasks), intent(in) :: self
        !> Results so far, (values, tasks).
        real(wp), intent(in) :: results(:, :)
        !> Which tasks are done.
        logical, intent(in) :: done(:)
        type(error_type), allocatable :: error

        call self%write_file(self%partial_path, results, done, .false., -1.0_wp, error)
        call warn_partial(error, self%cfg%output%quiet)
    end subroutine axis_snapshot

    !> Write the scene's file, complete, with the scene's wall time (the tasks' `write_file`).
    subroutine axis_write_output(self, cfg, tasks, error)
        !> The scene.
        class(axis_scene), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> The tasks (an `axis_tasks`), their records and the wall time.
        type(scene_tasks), intent(in) :: tasks
        !> Error, allocated on failure (the file is then not created).
        type(error_type), allocatable, intent(out) :: error

        select type (list => tasks%list)
        class is (axis_tasks)
            call list%write_file(trim(cfg%output%file), tasks%results, tasks%done, .true., tasks%elapsed, error)
        class default
            call wrong_tasks(error, "axis_tasks")
        end select
    end subroutine axis_write_output

    !> The scene runs its own frequency axis (omega_min .. omega_max).
    pure function axis_frequency_axis(self) result(yes)
        !> The scene.
        class(axis_scene), intent(in) :: self
        logical :: yes

        yes = .true.
    end function axis_frequency_axis

end module supratrans_axis_scene
