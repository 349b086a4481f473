!> A scene: the study one namelist describes (the `&scene kind`: a timeseries, an amplitude sweep, a map, a
!> bifurcation diagram of the threshold A_th(Omega), ...), behind one abstract type.
!>
!> What the rest of the program asks a scene, and nothing else:
!> - `run`: make its tasks, run them on the task engine (`supratrans_tasks`; one run for a timeseries), gather their
!>   records and write the output file;
!> - `one_run`: whether it is one run rather than a task list (no `--slice`, no journal; it keeps its records, so
!>   its memory estimate counts them);
!> - `gap_rule`: whether the drive's Omega must lie inside the band gap 0 < Omega < sqrt(1 + m^2) (unless
!>   allow_outside_gap): scenes at one frequency; scenes over a frequency axis skip the points outside instead;
!> - `check_limits`: its own sizes (axes, task count, work, memory) against the limits of `supratrans_limits`.
!>
!> `new_scene` (implemented in the submodule `supratrans_scene_factory`) is the only place that maps a kind's name
!> to a module: adding a scene is one module extending `scene_type` and one line there. The submodule keeps the
!> modules that validate an input (which ask the scene) free of the scene modules (which use them).
module supratrans_scene
    use supratrans_kinds, only: wp
    use supratrans_error, only: error_type
    use supratrans_invocation, only: invocation_type
    use supratrans_config, only: input_config
    implicit none
    private

    public :: scene_type, scene_budget, new_scene

    !> What the machine gives a scene, for the memory estimates of `check_limits`.
    type :: scene_budget
        !> OpenMP threads the scene's tasks run on (each holds one run).
        integer :: threads = 1
        !> Bytes of memory available to the process (0: unknown, nothing is checked).
        real(wp) :: memory = 0.0_wp
        !> What gives `memory` (for messages): "MemAvailable of /proc/meminfo", a cgroup file, "ulimit -v", ...
        character(len=:), allocatable :: source
    end type scene_budget

    !> A scene: a study made of runs (or threshold searches) of the chain, written to one HDF5 file.
    type, abstract :: scene_type
    contains
        !> Run the scene of a validated input and write its output file.
        procedure(run_interface), deferred :: run
        !> Check the scene's own sizes (axes, tasks, work, memory) against the limits (default: nothing beyond the
        !> limits of one run).
        procedure :: check_limits
        !> Whether the scene is one run rather than a task list (default: a task list).
        procedure :: one_run
        !> Whether the drive's Omega must lie inside the band gap (default: no).
        procedure :: gap_rule
    end type scene_type

    abstract interface
        !> Run the scene `cfg` describes and write `cfg%output%file`.
        subroutine run_interface(self, cfg, error, inv)
            import :: scene_type, input_config, error_type, invocation_type
            !> The scene.
            class(scene_type), intent(in) :: self
            !> The validated input.
            type(input_config), intent(in) :: cfg
            !> Error, allocated on failure.
            type(error_type), allocatable, intent(out) :: error
            !> How the engine is invoked (a slice, a merge: `supratrans_invocation`); default: the whole scene.
            type(invocation_type), intent(in), optional :: inv
        end subroutine run_interface
    end interface

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
    end interface

contains

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

end module supratrans_scene
