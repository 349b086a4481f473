!> Limits checked before any work: counts of time steps, grid points, runs and search depths, computed in real
!> arithmetic (so that nothing can overflow before it is checked), and the memory a run needs against the memory
!> the machine has (`supratrans_resources`). Each limit is documented in docs/input.md ("Limits"); a configuration
!> beyond one is refused with one line naming the key and the estimate. The budget of a scene's work and memory
!> (`scene_budget`), beside the scenes that check theirs: arithmetic on a configuration, no file read or written.
module supratrans_limits
    use supratrans_kinds, only: wp
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_config, only: input_config
    use supratrans_scene, only: scene_type, scene_budget
    use supratrans_strings, only: int_str, real_str
    !$ use omp_lib, only: omp_get_max_threads
    use supratrans_resources, only: available_memory_bytes
    implicit none
    private

    public :: check_limits, run_memory_bytes
    public :: axis_points, check_axis, check_tasks, threads_text, limit_error, sci

    !> Most time steps of one run (T/dt) an input may ask for: 10^9 steps of the paper's chain take about an hour
    !> (the engine itself counts up to `max_step_count` of `supratrans_simulate`, 2^62 - 1).
    real(wp), parameter, public :: max_steps = 1.0e9_wp
    !> Most oscillators N of a chain.
    real(wp), parameter, public :: max_sites = 1.0e8_wp
    !> Most points of an amplitude or frequency axis, or of a threshold search grid ((max - min)/resolution).
    real(wp), parameter, public :: max_axis_points = 1.0e6_wp
    !> Most runs of a sweep or map, and most searches of a bifurcation diagram.
    real(wp), parameter, public :: max_tasks = 1.0e7_wp
    !> Most work of one invocation (a scene, or one slice of it), in oscillator-steps: about a day on one core.
    real(wp), parameter, public :: max_site_steps = 5.0e13_wp
    !> Address space a dense LAPACK call maps on each thread the first time (OpenBLAS's working buffer of 128 MiB and
    !> its alignment): a scene that factors dense matrices (continuation, stability) needs it beside its own arrays.
    !> Under `ulimit -v` 250 MiB such a scene used to hang there (OpenBLAS retries the mmap forever).
    real(wp), parameter, public :: dense_buffer_bytes = 135266304.0_wp
    !> Bytes of state per oscillator of a run (levels, scheme coefficients, work arrays: measured ~100).
    real(wp), parameter :: bytes_per_site = 160.0_wp

contains

    !> Check every count and size of a validated configuration against its limit and the machine's memory: those of
    !> one run here, then the scene's own (`check_limits` of `scene`: axes, tasks, work).
    subroutine check_limits(cfg, scene, where, error)
        !> The configuration (values already within their ranges).
        type(input_config), intent(in) :: cfg
        !> The scene of `cfg` (&scene kind).
        class(scene_type), intent(in) :: scene
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Allocated when a limit is exceeded.
        type(error_type), allocatable, intent(out) :: error
        type(scene_budget) :: budget
        real(wp) :: steps, n, work, need
        integer :: length, ios
        character(len=:), allocatable :: source

        steps = cfg%run%numerics%t_final/cfg%run%numerics%dt
        if (.not. (steps <= max_steps)) then
            call limit_error(error, where, "numerics", "t_final/dt = " // sci(steps) // " time steps: more than the limit " &
                             // sci(max_steps) // " (a larger dt or a shorter t_final)")
            return
        end if
        n = real(cfg%run%chain%n, wp)
        if (n > max_sites) then
            call limit_error(error, where, "chain", "n = " // sci(n) // " oscillators: more than the limit " &
                             // sci(max_sites))
            return
        end if
        if (scene%one_run()) then
            ! the work limit of every scene, for its one run (t_final/dt steps x n oscillators)
            work = steps*n
            if (.not. (work <= max_site_steps)) then
                call limit_error(error, where, "numerics", "about " // sci(work) // " oscillator-steps (" // sci(steps) &
                                 // " steps x " // sci(n) // " oscillators): more than the limit " &
                                 // sci(max_site_steps) // " (about a day on one core); a shorter t_final, a larger " &
                                 // "dt or a shorter chain")
                return
            end if
        end if
        !$ budget%threads = omp_get_max_threads()
        if (scene%one_run()) then
            budget%threads = 1
            need = run_memory_bytes(cfg, .true.)
        else
            need = run_memory_bytes(cfg, .false.)*real(budget%threads, wp)
        end if
        budget%memory = available_memory_bytes(source)
        budget%source = source
        ! fault injection for the tests: SUPRATRANS_TEST_NO_MEMORY_CHECK=1 skips the comparison (have 0: unknown),
        ! so that a run meets its allocation failure (one line, status 2) instead of this check
        call get_environment_variable("SUPRATRANS_TEST_NO_MEMORY_CHECK", length=length, status=ios)
        if (ios == 0 .and. length > 0) budget%memory = 0.0_wp
        if (budget%memory > 0.0_wp .and. need > 0.8_wp*budget%memory) then
            call limit_error(error, where, "chain", "n = " // int_str(cfg%run%chain%n) // " with t_final/dt = " &
                             // sci(steps) // " needs about " // sci(need/1.0e9_wp) // " GB" // threads_text(budget) &
                             // ", more than the " // sci(budget%memory/1.0e9_wp) // " GB available (" // source // ")")
            return
        end if
        call scene%check_limits(cfg, where, budget, error)
    end subroutine check_limits

    !> The points of an axis from `first` to `last` by `step`, in real arithmetic (for the limits).
    pure function axis_points(first, last, step) result(points)
        !> First value.
        real(wp), intent(in) :: first
        !> Last value.
        real(wp), intent(in) :: last
        !> Step.
        real(wp), intent(in) :: step
        real(wp) :: points

        points = (last - first)/step + 1.0_wp
    end function axis_points

    !> An axis of `points` points against `max_axis_points`; `what` says what makes them ("omega_step = 0.01 makes
    !> 100 frequencies"), for the message.
    pure subroutine check_axis(points, what, where, error)
        !> Number of points (real: it may be huge).
        real(wp), intent(in) :: points
        !> What makes them.
        character(len=*), intent(in) :: what
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Allocated when there are too many.
        type(error_type), allocatable, intent(out) :: error

        if (.not. (points <= max_axis_points)) then
            call limit_error(error, where, "scene", what // ": more than the limit " // sci(max_axis_points))
        end if
    end subroutine check_axis

    !> The task count and the work of a scene against `max_tasks` and `max_site_steps` (the work shared among the
    !> slices of `--slice`): `tasks` runs or searches (`noun`) of `runs_per_task` runs of `steps` time steps each.
    pure subroutine check_tasks(cfg, tasks, runs_per_task, steps, noun, where, error)
        !> The configuration (chain length, slices).
        type(input_config), intent(in) :: cfg
        !> Number of tasks.
        real(wp), intent(in) :: tasks
        !> Runs of one task (a search asks several amplitudes).
        real(wp), intent(in) :: runs_per_task
        !> Time steps of one run.
        real(wp), intent(in) :: steps
        !> What a task is ("runs", "searches").
        character(len=*), intent(in) :: noun
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Allocated when a limit is exceeded.
        type(error_type), allocatable, intent(out) :: error
        real(wp) :: n, work

        if (.not. (tasks <= max_tasks)) then
            call limit_error(error, where, "scene", sci(tasks) // " " // noun // ": more than the limit " &
                             // sci(max_tasks) // " (check the steps)")
            return
        end if
        ! the study as read: a slice of it (--slice) is validated as the whole
        n = real(cfg%run%chain%n, wp)
        work = tasks*runs_per_task*steps*n
        if (.not. (work <= max_site_steps)) then
            call limit_error(error, where, "scene", "about " // sci(work) // " oscillator-steps (" // sci(tasks) &
                             // " " // noun // " x " // sci(runs_per_task*steps) // " steps x " // sci(n) &
                             // " oscillators): more than the limit " // sci(max_site_steps) &
                             // " (about a day on one core); split it with --slice I/N")
        end if
    end subroutine check_tasks

    !> " (N threads)" when a scene's tasks run on more than one thread, "" otherwise (for memory messages).
    pure function threads_text(budget) result(text)
        !> Threads and memory of the machine.
        type(scene_budget), intent(in) :: budget
        character(len=:), allocatable :: text

        text = ""
        if (budget%threads > 1) text = " (" // int_str(budget%threads) // " threads)"
    end function threads_text

    !> The error of a limit exceeded: `<where>: &<group>: <message>`, status `err_input`.
    pure subroutine limit_error(error, where, group, message)
        !> The error to create.
        type(error_type), allocatable, intent(out) :: error
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Group of the key.
        character(len=*), intent(in) :: group
        !> What is wrong.
        character(len=*), intent(in) :: message

        call fatal_error(error, where // ": &" // group // ": " // message, err_input)
    end subroutine limit_error

    !> Bytes one run of `cfg` needs: its state (`bytes_per_site` a site) and, with `records`, the probe samples and
    !> the ledger records kept for the output.
    pure function run_memory_bytes(cfg, records) result(bytes)
        !> The configuration.
        type(input_config), intent(in) :: cfg
        !> Count the records (a timeseries keeps them; scenes do not).
        logical, intent(in) :: records
        real(wp) :: bytes
        real(wp) :: steps, nprobe

        bytes = bytes_per_site*real(cfg%run%chain%n + 2, wp)
        if (.not. records) return
        steps = cfg%run%numerics%t_final/cfg%run%numerics%dt
        nprobe = 0.0_wp
        if (allocated(cfg%run%record%probes)) nprobe = real(size(cfg%run%record%probes), wp)
        bytes = bytes + 8.0_wp*(nprobe + 2.0_wp)*(steps/real(max(cfg%run%record%probe_every, 1), wp) + 2.0_wp) &
                + 8.0_wp*8.0_wp*(steps/real(max(cfg%run%record%ledger_every, 1), wp) + 2.0_wp)
    end function run_memory_bytes

    !> A number with 3 significant digits, for messages.
    pure function sci(x) result(text)
        !> The number.
        real(wp), intent(in) :: x
        character(len=:), allocatable :: text

        text = real_str(x, 3)
    end function sci

end module supratrans_limits
