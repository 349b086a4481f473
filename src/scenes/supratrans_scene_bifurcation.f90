!> Scene `bifurcation` (paper Sec. 4.3, Figs. Bif1-Bif3): the smallest driving amplitude at which supratransmission
!> begins, as a function of the driving frequency, one curve per potential and value of the varied parameter.
!>
!> For each curve and each frequency Omega_i = omega_min + i omega_step <= omega_max (i = 0, 1, ...; integer index),
!> one task searches the threshold with `find_threshold` (supratrans_threshold): coarse upward scan of
!> [amplitude_min, amplitude_max] in steps of `coarse_step`, then a scan of the bracket at `resolution`. Its oracle is
!> one `simulate` of the curve's run at (Omega_i, A) with `detect%stop_when_decided = .true.`: a transmitting run
!> stops as soon as an oscillator beyond the detector site passes the detection amplitude (pi), a
!> non-transmitting one runs to T. Frequencies outside the curve's band gap, Omega >= sqrt(V''(0) + m^2), are skipped
!> (threshold NaN, status `bifurcation_outside_gap`) unless `allow_outside_gap` is set.
!>
!> The tasks (curves x frequencies) run on OpenMP threads through `supratrans_tasks`, driven by the scene driver
!> of `supratrans_scene` (dynamic scheduling, journal `<output>.journal` tied to the namelist by
!> `file_fingerprint`, partial output `<output>.partial.h5` with root attribute `complete = 0` now and then). Each
!> task is one sequential search and results are stored by task index, so the thresholds are bit-for-bit identical
!> for any number of threads. The final file is written as `<output>.tmp-XXXXXX` and renamed when complete
!> (`complete = 1`); the journal and the partial file are then deleted.
!>
!> Where the verdict is not monotone in A on the scale of the resolution (undamped sine-Gordon below Omega ~ 0.5,
!> the paper's "discrepancy region": e.g. at Omega = 0.05, A = 5.96 and 5.97 transmit, 5.98 .. 6.00 do not, 6.01
!> does), the threshold found depends on which coarse points the scan asks (see the assumption documented in
!> `supratrans_threshold`): there it is the smallest transmitting amplitude above the last quiet coarse point.
!> Measured on the undamped sine-Gordon diagram (Omega = 0.05 .. 0.99 by 0.01) with coarse steps 0.1 .. 0.3: 11 of
!> 95 thresholds differ between coarse steps, all at Omega <= 0.47, by up to 0.51 (Omega = 0.43).
!>
!> The searches and their runs: the submodule `supratrans_scene_bifurcation_search.f90` (one task's search, its
!> cost) and `supratrans_bifurcation_runs` (the runs and the oracle); the file: the submodule
!> `supratrans_scene_bifurcation_output.f90` (written, partial or final, and read back for `--costs`).
module supratrans_scene_bifurcation
    use, intrinsic :: iso_fortran_env, only: error_unit
    use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
    use supratrans_kinds, only: wp, i8
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_invocation, only: invocation_type
    use supratrans_scene, only: scene_budget, scene_tasks, scene_plan
    use supratrans_axis_scene, only: axis_tasks, axis_scene, init_axes, bifurcation_omegas => scene_omegas
    use supratrans_limits, only: axis_points, check_axis, check_tasks, sci
    use supratrans_config, only: input_config, run_config, screen_none, screen_choices
    use supratrans_curves, only: curve_count, curve_run
    use supratrans_threshold, only: effective_coarse_step, search_grid_size
    use supratrans_status, only: bifurcation_outside_gap => status_outside_gap, bifurcation_pending => status_not_run
    use supratrans_search_record, only: search_record, search_fields, from_values, certify_unchanged, &
                                        certify_moved_within, certify_moved
    use supratrans_strings, only: int_str, real_str, fixed1, printable
    use supratrans_bifurcation_runs, only: search_run, with_numerics, screen_integrator, screen_dt
    implicit none
    private

    public :: run_bifurcation, bifurcation_omegas

    !> Status of a task whose frequency lies outside the curve's band gap (not searched; threshold NaN), and of a
    !> task not computed yet (partial files): the task codes of `supratrans_status`, shared by every scene.
    public :: bifurcation_outside_gap, bifurcation_pending

    !> The tasks of a bifurcation scene: task t = (curve - 1) nomega + iomega searches one threshold.
    type, extends(axis_tasks) :: bifurcation_tasks
        !> The runs of the axes (`runs`) are prepared for the search (early stop, nothing recorded); the same with
        !> the screening method and step (allocated when the scene screens).
        type(run_config), allocatable :: screen_runs(:)
        !> The same at dt/2 (allocated when the scene certifies).
        type(run_config), allocatable :: half_runs(:)
    contains
        !> Search the threshold of one task.
        procedure :: run => run_search
        !> Whether a task's record is a result (not one stopped by a signal at a checkpoint).
        procedure :: finished => search_finished
        !> The scene's file.
        procedure :: write_file => write_bifurcation_file
        !> Estimated cost of one search (slices of equal cost).
        procedure :: cost => search_cost
        !> The searches' measured wall times in an earlier output of the same study (`--costs`).
        procedure :: measured_costs => search_measured_costs
    end type bifurcation_tasks

    !> The scene `bifurcation`: one threshold search A_th per (curve, frequency).
    type, extends(axis_scene), public :: bifurcation_scene
    contains
        !> Its tasks: one threshold search per (curve, frequency).
        procedure :: make_tasks => bifurcation_make_tasks
        !> The runs, time steps and wall time of the searches, and the certified thresholds.
        procedure :: summary => bifurcation_summary
        !> Its axes, tasks, work and memory against the limits.
        procedure :: check_limits => bifurcation_scene_limits
        procedure :: plan => bifurcation_scene_plan
    end type bifurcation_scene

    interface
        !> Search the threshold of task `index` (thread-safe: everything it changes is local).
        module subroutine run_search(self, index, values)
            !> The tasks.
            class(bifurcation_tasks), intent(in) :: self
            !> Task index: (curve - 1) nomega + iomega.
            integer, intent(in) :: index
            !> The task's `search_record`, as values (`to_values`).
            real(wp), intent(out) :: values(:)
        end subroutine run_search

        !> Whether a task's record is a result: a search stopped at its checkpoint by a signal returns the unsearched
        !> record (status pending), which is not journaled.
        module function search_finished(self, values) result(yes)
            !> The tasks.
            class(bifurcation_tasks), intent(in) :: self
            !> The task's values (`to_values`).
            real(wp), intent(in) :: values(:)
            logical :: yes
        end function search_finished

        !> Estimated cost of task `index`, for the largest-first slices (`supratrans_tasks::slice_owners`): the work of
        !> one run of its curve (`run_work`) x the expected runs of a search, half the coarse scan of the range and the
        !> scan of one bracket at the resolution; a screened search runs most of them with the screening method at its
        !> step. A frequency outside the gap is no search: nearly nothing.
        pure module function search_cost(self, index) result(cost)
            !> The tasks.
            class(bifurcation_tasks), intent(in) :: self
            !> Task index: (curve - 1) nomega + iomega.
            integer, intent(in) :: index
            real(wp) :: cost
        end function search_cost

        !> A record with nothing searched: thresholds NaN, counts 0, statuses "pending" / "not checked".
        pure module function unsearched_record() result(r)
            type(search_record) :: r
        end function unsearched_record

        !> Write the scene's file `path` (built in memory, written atomically): tasks not done get NaN and status
        !> `bifurcation_pending`.
        module subroutine write_bifurcation_file(self, path, results, done, complete, elapsed, error)
            !> The tasks.
            class(bifurcation_tasks), intent(in) :: self
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
        end subroutine write_bifurcation_file

        !> The measured cost of every search in `path`, an earlier output (or merged file) of the same study: its
        !> `/cost/cpu_time` (curve, omega), by task index. The file must be a bifurcation output with the same
        !> frequencies (`/omega`) and curves (`/curves/gamma`, `beta`, `m2`), else it is refused in one line.
        module subroutine search_measured_costs(self, path, costs, error)
            !> The tasks.
            class(bifurcation_tasks), intent(in) :: self
            !> The earlier output.
            character(len=*), intent(in) :: path
            !> Measured wall time of each search (s), by task index.
            real(wp), allocatable, intent(out) :: costs(:)
            !> Error: unreadable, of another study, or without costs.
            type(error_type), allocatable, intent(out) :: error
        end subroutine search_measured_costs
    end interface

contains

    !> Run the bifurcation scene described by `cfg` and write `cfg%output%file` (see the module documentation): the
    !> scene's `run` (`supratrans_scene`), under the name the tests and the benchmark call.
    subroutine run_bifurcation(cfg, error, keep_journal, inv)
        !> The validated input (`&scene kind = 'bifurcation'`).
        type(input_config), intent(in) :: cfg
        !> Error, allocated on failure (output exists, journal of another input, unwritable files).
        type(error_type), allocatable, intent(out) :: error
        !> Keep the journal after a complete run (tests of the resume); default false.
        logical, intent(in), optional :: keep_journal
        !> How the engine is invoked (a slice, a merge: `supratrans_invocation`); default: the whole scene.
        type(invocation_type), intent(in), optional :: inv
        type(bifurcation_scene) :: scene

        call scene%run(cfg, error, inv, keep_journal)
    end subroutine run_bifurcation

    !> The searches of the scene: the frequency axis and, per curve, its run prepared for the search (with the
    !> screening method, at dt/2 when certifying).
    subroutine bifurcation_make_tasks(self, cfg, tasks, error)
        !> The scene.
        class(bifurcation_scene), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Its tasks: a `bifurcation_tasks`, (curve - 1) nomega + iomega.
        type(scene_tasks), intent(inout) :: tasks
        !> Error, allocated when the frequency axis is empty.
        type(error_type), allocatable, intent(out) :: error
        type(bifurcation_tasks), allocatable :: list
        integer :: ncurve, nomega, ic

        allocate (list)
        call init_axes(list, cfg, tasks%inv, 1, error)
        if (allocated(error)) return
        ncurve = size(list%runs)
        nomega = size(list%omegas)
        do ic = 1, ncurve
            list%runs(ic) = search_run(list%runs(ic))
        end do
        if (cfg%scene%screen_method /= screen_none) then
            allocate (list%screen_runs(ncurve))
            do ic = 1, ncurve
                list%screen_runs(ic) = search_run(with_numerics(curve_run(cfg, ic), &
                    screen_integrator(cfg%scene%screen_method), screen_dt(cfg, curve_run(cfg, ic))))
            end do
        end if
        if (cfg%scene%certify) then
            allocate (list%half_runs(ncurve))
            do ic = 1, ncurve
                list%half_runs(ic) = search_run(with_numerics(curve_run(cfg, ic), cfg%run%numerics%method, &
                                                              cfg%run%numerics%dt/2.0_wp))
            end do
        end if
        tasks%header = "supratrans: bifurcation from " // printable(source_name(cfg)) // ": " // int_str(ncurve) &
            // " curve(s) x " // int_str(nomega) // " frequencies, amplitudes " // real_str(cfg%scene%amplitude_min, 6) &
            // " .. " // real_str(cfg%scene%amplitude_max, 6) // " (coarse step " &
            // real_str(effective_coarse_step(cfg%scene%coarse_step, cfg%scene%resolution), 6) // ", resolution " &
            // real_str(cfg%scene%resolution, 6) // ")" // trim(screening_text(cfg))
        tasks%count = ncurve*nomega
        tasks%fields = search_fields
        tasks%label = "threshold searches"
        call move_alloc(list, tasks%list)
    end subroutine bifurcation_make_tasks

    !> The runs (screened), time steps and wall time of the searches; with `certify`, the thresholds that stand at
    !> dt/2 and those flagged.
    function bifurcation_summary(self, cfg, tasks) result(text)
        !> The scene.
        class(bifurcation_scene), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> The tasks' records and the wall time.
        type(scene_tasks), intent(in) :: tasks
        character(len=:), allocatable :: text
        type(search_record), allocatable :: records(:)
        character(len=24) :: steps_text
        integer :: i, nthin

        allocate (records(size(tasks%done)))
        do i = 1, size(tasks%done)
            records(i) = from_values(tasks%results(:, i))
        end do
        write (steps_text, "(i0)") sum(records%steps)
        text = "  " // int_str(sum(records%runs)) // " runs (" // int_str(sum(records%runs_screened)) // " screened), " &
               // trim(steps_text) // " time steps, " // fixed1(tasks%elapsed) // " s"
        if (cfg%scene%certify) text = text // new_line("a") // "  certified at dt/2: " &
            // int_str(count(records%certify_status == certify_unchanged .or. records%certify_status &
                             == certify_moved_within)) // " thresholds stand, " &
            // int_str(count(records%certify_status >= certify_moved)) // " flagged"
        nthin = count(records%margin_below < cfg%run%detect%thin_margin)
        if (nthin > 0) text = text // new_line("a") // "  " // int_str(nthin) // " of " &
            // int_str(count(.not. ieee_is_nan(records%margin_below))) &
            // " thresholds are thin verdicts (the run just below came within " // real_str(cfg%run%detect%thin_margin, 2) &
            // " of the detect amplitude: /thin_verdict)"
    end function bifurcation_summary

    !> The screening and certification settings, for the progress line ("" when neither is on).
    function screening_text(cfg) result(text)
        !> The input.
        type(input_config), intent(in) :: cfg
        character(len=:), allocatable :: text

        text = ""
        if (cfg%scene%screen_method /= screen_none) text = "; screened by " &
            // trim(screen_choices(cfg%scene%screen_method)) &
            // " at dt = " // real_str(screen_dt(cfg, cfg%run), 6) &
            // ", confirmed within " // real_str(cfg%scene%confirm_band, 6) // " and below margin " &
            // real_str(cfg%scene%screen_margin, 6)
        if (cfg%scene%certify) text = text // "; certified at dt/2"
    end function screening_text

    !> The namelist file of the input ("configuration" when not set).
    pure function source_name(cfg) result(name)
        !> The input.
        type(input_config), intent(in) :: cfg
        character(len=:), allocatable :: name

        name = "configuration"
        if (allocated(cfg%source)) name = cfg%source
    end function source_name

    !> The frequency axis, the search grid (amplitude_min..amplitude_max by resolution, coarse_step), then the
    !> searches (curves x frequencies) and their work: a search asks about (range)/coarse_step coarse amplitudes
    !> and up to coarse_step/resolution fine ones.
    pure subroutine bifurcation_scene_limits(self, cfg, where, budget, error)
        !> The scene.
        class(bifurcation_scene), intent(in) :: self
        !> The configuration (values already within their ranges and rules).
        type(input_config), intent(in) :: cfg
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Threads and memory of the machine.
        type(scene_budget), intent(in) :: budget
        !> Allocated when a limit is exceeded.
        type(error_type), allocatable, intent(out) :: error
        real(wp) :: nomega, ngrid
        type(scene_plan) :: p

        associate (sc => cfg%scene)
            nomega = axis_points(sc%omega_min, sc%omega_max, sc%omega_step)
            call check_axis(nomega, "omega_step = " // sci(sc%omega_step) // " makes " // sci(nomega) // " frequencies", &
                            where, error)
            if (allocated(error)) return
            ngrid = axis_points(sc%amplitude_min, sc%amplitude_max, sc%resolution)
            call check_axis(ngrid, "resolution = " // sci(sc%resolution) // " makes a search grid of " // sci(ngrid) &
                            // " amplitudes", where, error)
            if (allocated(error)) return
            call check_axis(sc%coarse_step/sc%resolution, "coarse_step/resolution = " &
                            // sci(sc%coarse_step/sc%resolution), where, error)
            if (allocated(error)) return
            p = bifurcation_scene_plan(self, cfg)
            call check_tasks(cfg, p%tasks, p%runs_per_task, p%steps, p%noun, where, error)
        end associate
    end subroutine bifurcation_scene_limits

    !> The searches: curves x frequencies, each asking at most (range)/coarse_step + coarse_step/resolution
    !> amplitudes (the bound the limits take; screening makes most of them cheaper), each of t_final/dt steps.
    pure function bifurcation_scene_plan(self, cfg) result(p)
        !> The scene.
        class(bifurcation_scene), intent(in) :: self
        !> The configuration (values within their ranges).
        type(input_config), intent(in) :: cfg
        type(scene_plan) :: p

        associate (sc => cfg%scene)
            p%tasks = real(curve_count(cfg), wp)*axis_points(sc%omega_min, sc%omega_max, sc%omega_step)
            p%runs_per_task = (sc%amplitude_max - sc%amplitude_min)/sc%coarse_step + sc%coarse_step/sc%resolution
        end associate
        p%noun = "searches"
        p%steps = cfg%run%numerics%t_final/cfg%run%numerics%dt
    end function bifurcation_scene_plan

end module supratrans_scene_bifurcation
