!> The abstract list of a scene's tasks, which the task engine (`supratrans_tasks`) runs: one task is one
!> simulation or one threshold search, computed by `run` into a record of values. A scene extends it with what its
!> tasks need (read-only while they run). Apart from the engine, so that the abstract scene (`supratrans_scene`),
!> which the input's validation knows, can name it.
module supratrans_task_list
    use supratrans_kinds, only: wp
    use supratrans_strings, only: printable
    use supratrans_error, only: error_type, fatal_error, err_input
    implicit none
    private

    !> A scene's list of tasks; the scene extends it with what its tasks need (read-only during the run).
    type, abstract, public :: task_list
    contains
        !> Compute task `index`, writing its results into `values`. Must be thread-safe (no shared mutable state).
        procedure(run_task_interface), deferred :: run
        !> Called now and then, serially, with the results so far (write a partial output); default: nothing.
        procedure :: snapshot => no_snapshot
        !> Whether a task's values are its result; false for a task stopped by a signal at its mid-run
        !> checkpoint (not journaled: a rerun resumes it). Default: always.
        procedure :: finished => always_finished
        !> Estimated cost of task `index` in any fixed unit (oscillators x time steps x work per step, times the
        !> expected number of runs of a search); only the ratios matter (`slice_owners`). Default: 1 (equal cost).
        procedure :: cost => equal_cost
        !> The measured cost of every task in an earlier output of the same study (`--costs FILE`), for
        !> `slice_owners`; default: refused (the scene keeps no per-task costs).
        procedure :: measured_costs => no_measured_costs
    end type task_list

    abstract interface
        !> Compute one task.
        subroutine run_task_interface(self, index, values)
            import :: task_list, wp
            !> The task list.
            class(task_list), intent(in) :: self
            !> Task index.
            integer, intent(in) :: index
            !> The task's results.
            real(wp), intent(out) :: values(:)
        end subroutine run_task_interface
    end interface

contains

    !> Default `finished`: every task that returns has its result.
    function always_finished(self, values) result(yes)
        !> The task list.
        class(task_list), intent(in) :: self
        !> The task's values.
        real(wp), intent(in) :: values(:)
        logical :: yes

        yes = .true.
    end function always_finished

    !> Default snapshot: nothing.
    subroutine no_snapshot(self, results, done)
        !> The task list.
        class(task_list), intent(in) :: self
        !> Results so far, (values, tasks).
        real(wp), intent(in) :: results(:, :)
        !> Which tasks are done.
        logical, intent(in) :: done(:)
    end subroutine no_snapshot

    !> Default cost of a task: 1, every task alike.
    pure function equal_cost(self, index) result(cost)
        !> The task list.
        class(task_list), intent(in) :: self
        !> Task index.
        integer, intent(in) :: index
        real(wp) :: cost

        cost = 1.0_wp
    end function equal_cost

    !> Default `measured_costs`: the scene's outputs keep no per-task cost, so `--costs` is refused.
    subroutine no_measured_costs(self, path, costs, error)
        !> The task list.
        class(task_list), intent(in) :: self
        !> The earlier output.
        character(len=*), intent(in) :: path
        !> Measured cost of each task (unallocated on error).
        real(wp), allocatable, intent(out) :: costs(:)
        !> Error: always (one line).
        type(error_type), allocatable, intent(out) :: error

        call fatal_error(error, "--costs " // printable(path) // ": this scene's outputs keep no per-task costs " &
                         // "(--costs applies to bifurcation studies)", err_input)
    end subroutine no_measured_costs

end module supratrans_task_list
