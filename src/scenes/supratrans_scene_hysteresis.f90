!> Scene `hysteresis`: the two edges of the bistable window of supratransmission, as a slow protocol sees them, over
!> the driving frequency, one curve per potential and value of the varied parameter (the layout of the bifurcation
!> scene), for several stair lengths.
!>
!> For each curve, each frequency Omega_i = omega_min + i omega_step <= omega_max and each stair length T_s of
!> `stair_times`, one task is one run of the curve's chain with the drive u_0 = A(t) sin(Omega t), A(t) the stairs of
!> `stair_amplitude` (supratrans_chain): from rest a linear ramp (&drive ramp_time) to a_0 = amplitude_min, then
!> 2K + 1 stairs of length T_s at the levels a_0, a_1, .., a_K, a_{K-1}, .., a_0, a_i = amplitude_min + i
!> stair_height (a_K the last level <= amplitude_max), each stair starting with a linear ramp of length stair_ramp
!> from the level before (the drive stays continuous). The run's T is ramp_time + (2K + 1) T_s (&numerics t_final is
!> not used).
!>
!> **What a stair transmits** and the **edges**: `supratrans_hysteresis_stairs` (the mean power through the bond
!> beyond the detector site, over the last whole drive periods of each stair's second half; the upward edge, where
!> the transmitting state is born, the downward edge, where it dies, and the window between them).
!>
!> Tasks run on OpenMP threads through `supratrans_tasks` (journal, resume, `--slice`), driven by the scene driver
!> of `supratrans_scene`, results stored by task index: identical for any number of threads and slices.
module supratrans_scene_hysteresis
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_nan
    use supratrans_kinds, only: wp, i8
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_invocation, only: invocation_type
    use supratrans_scene, only: scene_budget, scene_tasks, scene_plan
    use supratrans_axis_scene, only: axis_tasks, axis_scene, init_axes
    use supratrans_limits, only: axis_points, check_axis, check_tasks, limit_error, threads_text, sci, max_steps, &
        run_memory_bytes
    use supratrans_config, only: input_config, run_config, method_name
    use supratrans_curves, only: curve_count, curve_run, write_curves
    use supratrans_chain, only: threshold_as, band_gap_edge, detector_site, stair_level
    use supratrans_simulate, only: simulate_task
    use supratrans_result, only: run_result, run_ok
    use supratrans_status, only: status_outside_gap, status_not_run
    use supratrans_threshold, only: search_grid_size
    use supratrans_hdf5, only: h5_file, h5_create, h5_commit, h5_write_attr
    use supratrans_output_rows, only: write_row, write_row_group, write_row_attr, hysteresis_omega, hysteresis_stair_time, &
        hysteresis_stair_amplitude, hysteresis_stair_direction, hysteresis_upward_threshold, &
        hysteresis_downward_threshold, hysteresis_window, hysteresis_upward_spread, hysteresis_downward_spread, &
        hysteresis_downward_gaps, hysteresis_status, hysteresis_power, hysteresis_detector_site, &
        hysteresis_threshold_as, hysteresis_cost, hysteresis_cost_steps, hysteresis_cost_wall_time
    use supratrans_hysteresis_scalars, only: hysteresis_scalars, hysteresis_scalars_names, hysteresis_scalars_values, &
        hysteresis_scalars_from_values, empty_hysteresis_scalars
    use supratrans_output, only: write_root, write_parameters
    use supratrans_strings, only: int_str, real_str, fixed1
    use supratrans_hysteresis_stairs, only: hysteresis_drive, stair_powers, hysteresis_edges, hysteresis_status_codes, &
                                            hysteresis_found, hysteresis_status_code
    use supratrans_stairs, only: stairs_failed
    implicit none
    private

    !> Most levels above the bottom one, K (2K + 1 stairs): a task's journal line holds every stair's mean power.
    integer, parameter, public :: max_stair_top = 1000

    !> Stair length used when `stair_times` is not set.
    real(wp), parameter :: default_stair_time = 400.0_wp

    !> The tasks of a hysteresis scene: task t = ((curve - 1) nomega + iomega - 1) nlength + ilength, one run each.
    type, extends(axis_tasks) :: hysteresis_tasks
        !> The stair lengths T_s (the inner axis of `axis_tasks`).
        real(wp), allocatable :: stair_times(:)
        !> Index K of the top level: 2K + 1 stairs.
        integer :: top = 0
    contains
        !> One run up and down the stairs.
        procedure :: run => run_stairs_task
        !> Whether a task's values are its result (not a run stopped by a signal at its checkpoint).
        procedure :: finished => stairs_finished
        !> The scene's file.
        procedure :: write_file => write_hysteresis_file
    end type hysteresis_tasks

    !> The scene `hysteresis`: the stairs up and down of the amplitude per (curve, frequency, stair length).
    type, extends(axis_scene), public :: hysteresis_scene
    contains
        !> Its tasks: one run up and down the stairs per (curve, frequency, stair length).
        procedure :: make_tasks => hysteresis_make_tasks
        !> The runs that found both edges, and the wall time.
        procedure :: summary => hysteresis_summary
        !> Its axes, tasks, work and memory against the limits.
        procedure :: check_limits => hysteresis_scene_limits
        procedure :: plan => hysteresis_scene_plan
    end type hysteresis_scene

contains

    !> The runs of the scene: the frequency axis, the stair lengths and levels (checked), each curve's run.
    subroutine hysteresis_make_tasks(self, cfg, tasks, error)
        !> The scene.
        class(hysteresis_scene), intent(in) :: self
        !> The validated input (`&scene kind = 'hysteresis'`).
        type(input_config), intent(in) :: cfg
        !> Its tasks: a `hysteresis_tasks`, ((curve - 1) nomega + iomega - 1) nlength + ilength.
        type(scene_tasks), intent(inout) :: tasks
        !> Error, allocated when the stairs are not valid or the frequency axis is empty.
        type(error_type), allocatable, intent(out) :: error
        type(hysteresis_tasks), allocatable :: list
        integer :: ncurve, nomega, nlen

        allocate (list)
        list%stair_times = scene_stair_times(cfg)
        ! checked already by validation (hysteresis_scene_limits, also for --check): here for the top level
        call check_stairs(cfg, list%stair_times, source_of(cfg), list%top, error)
        if (allocated(error)) return
        nlen = size(list%stair_times)
        call init_axes(list, cfg, tasks%inv, nlen, error)
        if (allocated(error)) return
        ncurve = size(list%runs)
        nomega = size(list%omegas)
        tasks%header = "supratrans: hysteresis from " // cfg%source // ": " // int_str(ncurve) // " curve(s) x " &
            // int_str(nomega) // " frequencies x " // int_str(nlen) // " stair length(s), " &
            // int_str(2*list%top + 1) // " stairs " // real_str(cfg%scene%amplitude_min, 6) // " .. " &
            // real_str(cfg%scene%amplitude_min + real(list%top, wp)*cfg%scene%stair_height, 6) // " and back, " &
            // "method " // method_name(cfg%run%numerics%method)
        tasks%count = ncurve*nomega*nlen
        tasks%fields = task_fields(2*list%top + 1)
        tasks%label = "stair runs"
        call move_alloc(list, tasks%list)
    end subroutine hysteresis_make_tasks

    !> The runs that found both edges, and the wall time.
    function hysteresis_summary(self, cfg, tasks) result(text)
        !> The scene.
        class(hysteresis_scene), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> The tasks' records and the wall time.
        type(scene_tasks), intent(in) :: tasks
        character(len=:), allocatable :: text
        type(hysteresis_scalars) :: s
        integer :: t, found

        found = 0
        do t = 1, size(tasks%done)
            if (.not. tasks%done(t)) cycle
            s = hysteresis_scalars_from_values(tasks%results(:, t))
            if (s%status == hysteresis_found) found = found + 1
        end do
        text = "  " // int_str(found) // " of " // int_str(size(tasks%done)) // " runs with both edges, " &
               // fixed1(tasks%elapsed) // " s"
    end function hysteresis_summary

    !> The stair lengths of the scene: `stair_times`, or `default_stair_time` when unset.
    pure function scene_stair_times(cfg) result(times)
        !> The input.
        type(input_config), intent(in) :: cfg
        real(wp), allocatable :: times(:)

        times = [default_stair_time]
        if (allocated(cfg%scene%stair_times)) then
            if (size(cfg%scene%stair_times) > 0) times = cfg%scene%stair_times
        end if
    end function scene_stair_times

    !> Check the stairs (before any work, by validation: `hysteresis_scene_limits`): at least one stair up
    !> (amplitude_min + stair_height <= amplitude_max) and at most `max_stair_top`, a ramp no longer than half of
    !> every stair, stairs of at least 4 dt.
    pure subroutine check_stairs(cfg, times, where, top, error)
        !> The input.
        type(input_config), intent(in) :: cfg
        !> The stair lengths.
        real(wp), intent(in) :: times(:)
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Index K of the top level.
        integer, intent(out) :: top
        !> Error, allocated when the stairs are not valid.
        type(error_type), allocatable, intent(out) :: error
        integer :: i

        associate (sc => cfg%scene)
            top = search_grid_size(sc%amplitude_min, sc%amplitude_max, sc%stair_height) - 1
            if (top < 1) then
                call fatal_error(error, where // ": &scene: stair_height = " // real_str(sc%stair_height, 6) &
                                 // ": hysteresis needs amplitude_min + stair_height <= amplitude_max (at least one " &
                                 // "stair up; amplitude_min = " // real_str(sc%amplitude_min, 6) // ", amplitude_max = " &
                                 // real_str(sc%amplitude_max, 6) // ")", err_input)
                return
            end if
            if (top > max_stair_top) then
                call fatal_error(error, where // ": &scene: stair_height = " // real_str(sc%stair_height, 6) &
                                 // ": amplitude_min .. amplitude_max by stair_height makes " // int_str(2*top + 1) &
                                 // " stairs: more than the limit " // int_str(2*max_stair_top + 1) &
                                 // " (a journal line holds every stair's power)", err_input)
                return
            end if
            do i = 1, size(times)
                if (.not. (2.0_wp*sc%stair_ramp <= times(i))) then
                    call fatal_error(error, where // ": &scene: stair_ramp = " // real_str(sc%stair_ramp, 6) &
                                     // " is longer than half the stair length " // real_str(times(i), 6) &
                                     // " (the mean power is taken over the stair's second half)", err_input)
                    return
                end if
                if (.not. (times(i) >= 4.0_wp*cfg%run%numerics%dt)) then
                    call fatal_error(error, where // ": &scene: stair length " // real_str(times(i), 6) &
                                     // " is shorter than 4 dt = " // real_str(4.0_wp*cfg%run%numerics%dt, 6), err_input)
                    return
                end if
            end do
        end associate
    end subroutine check_stairs

    !> The namelist file of the input ("configuration" when not set).
    pure function source_of(cfg) result(name)
        !> The input.
        type(input_config), intent(in) :: cfg
        character(len=:), allocatable :: name

        name = "configuration"
        if (allocated(cfg%source)) name = cfg%source
    end function source_of

    !> Names of a task's values: the record's scalar fields (`hysteresis_scalars_names`, its output table's), then
    !> power_0 .. power_{nstair - 1} (the mean power of each stair).
    pure function task_fields(nstair) result(fields)
        !> Number of stairs 2K + 1.
        integer, intent(in) :: nstair
        character(len=16), allocatable :: fields(:)
        integer :: j, ns

        ns = size(hysteresis_scalars_names)
        allocate (fields(ns + nstair))
        fields(1:ns) = hysteresis_scalars_names
        do j = 1, nstair
            write (fields(ns + j), "(a, i0)") "power_", j - 1
        end do
    end function task_fields

    !> One run up and down the stairs for task `index` (thread-safe: everything it changes is local).
    subroutine run_stairs_task(self, index, values)
        !> The tasks.
        class(hysteresis_tasks), intent(in) :: self
        !> Task index: ((curve - 1) nomega + iomega - 1) nlength + ilength.
        integer, intent(in) :: index
        !> The task's values (`task_fields`).
        real(wp), intent(out) :: values(:)
        type(run_config) :: run
        type(run_result) :: result
        type(hysteresis_scalars) :: s
        integer :: ilen, nd, nstair, status, gaps, ns
        integer(i8) :: clock_start, clock_end, clock_rate
        real(wp), allocatable :: power(:)
        real(wp) :: up, down, nan
        character(len=12) :: task_text

        call system_clock(clock_start, clock_rate)
        nan = ieee_value(nan, ieee_quiet_nan)
        ilen = self%task_inner(index)
        nstair = 2*self%top + 1
        ns = size(hysteresis_scalars_names)
        values = nan
        s = empty_hysteresis_scalars()
        run = hysteresis_drive(self%task_run(index), self%cfg, self%top, self%stair_times(ilen))
        nd = detector_site(run)
        s%detector_site = nd
        if (run%drive%omega >= band_gap_edge(run%chain) .and. .not. self%cfg%allow_outside_gap) then
            s%status = status_outside_gap
            values(1:ns) = hysteresis_scalars_values(s)
            return
        end if
        if (allocated(run%record%probes)) deallocate (run%record%probes)
        run%record%probes = [nd, nd + 1]
        run%record%probe_every = 1
        run%record%ledger_every = int(min(huge(1)/2_i8, int(run%numerics%t_final/run%numerics%dt, i8) + 1_i8))
        write (task_text, "(i0)") index
        call simulate_task(run, result, self%checkpoint_prefix // trim(task_text), self%fingerprint // " task " &
                           // trim(task_text), self%cfg%output%checkpoint_every, self%cfg%output%quiet)
        if (result%interrupted) then
            ! stopped by a signal at its checkpoint: no result (not journaled; a rerun resumes it)
            s%status = status_not_run
            values(1:ns) = hysteresis_scalars_values(s)
            return
        end if
        s%steps = real(result%steps, wp)
        if (result%status /= run_ok) then
            s%status = hysteresis_status_code(stairs_failed)
        else
            power = stair_powers(run, result)
            call hysteresis_edges(run%drive, power, self%cfg%scene%power_threshold, up, down, gaps, status)
            s%status = status
            s%upward = up
            s%downward = down
            s%window = up - down
            s%downward_gaps = gaps
            values(ns + 1:ns + nstair) = power
        end if
        call system_clock(clock_end)
        s%wall_time = real(clock_end - clock_start, wp)/real(clock_rate, wp)
        values(1:ns) = hysteresis_scalars_values(s)
    end subroutine run_stairs_task

    !> Whether a task's values are its result: a run stopped at its checkpoint by a signal has status not-run.
    function stairs_finished(self, values) result(yes)
        !> The tasks.
        class(hysteresis_tasks), intent(in) :: self
        !> The task's values (`task_fields`).
        real(wp), intent(in) :: values(:)
        logical :: yes
        type(hysteresis_scalars) :: s

        s = hysteresis_scalars_from_values(values)
        yes = s%status /= status_not_run
    end function stairs_finished

    !> Write the scene's file `path` (as a temporary file, renamed when complete): tasks not done get NaN and status
    !> -1 (pending).
    subroutine write_hysteresis_file(self, path, results, done, complete, elapsed, error)
        !> The tasks.
        class(hysteresis_tasks), intent(in) :: self
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
        type(h5_file) :: file
        type(run_config) :: run
        type(hysteresis_scalars), allocatable :: s(:)
        real(wp), allocatable :: power(:, :), levels(:), spread_up(:, :), spread_down(:, :), as(:, :)
        integer, allocatable :: direction(:), nd(:, :)
        integer :: ncurve, nomega, nlen, nstair, ntask, t, ns, ic, io

        ncurve = size(self%runs)
        nomega = size(self%omegas)
        nlen = size(self%stair_times)
        nstair = 2*self%top + 1
        ntask = ncurve*nomega*nlen
        ns = size(hysteresis_scalars_names)
        ! the records' scalar fields, and the stairs' mean powers after them; tasks not done: the empty record
        ! (status not run) and NaN powers
        allocate (s(ntask))
        power = results(ns + 1:ns + nstair, :)
        do t = 1, ntask
            if (done(t)) then
                s(t) = hysteresis_scalars_from_values(results(:, t))
            else
                s(t) = empty_hysteresis_scalars()
                power(:, t) = ieee_value(1.0_wp, ieee_quiet_nan)
            end if
        end do
        run = hysteresis_drive(self%curve_run_at(1, 1), self%cfg, self%top, self%stair_times(1))
        levels = [(stair_level(run%drive, t), t=0, nstair - 1)]
        direction = [(merge(1, merge(0, -1, t == self%top), t < self%top), t=0, nstair - 1)]
        allocate (spread_up(nomega, ncurve), spread_down(nomega, ncurve), as(nomega, ncurve), nd(nomega, ncurve))
        do ic = 1, ncurve
            do io = 1, nomega
                t = ((ic - 1)*nomega + io - 1)*nlen
                spread_up(io, ic) = spread([s(t + 1:t + nlen)%upward])
                spread_down(io, ic) = spread([s(t + 1:t + nlen)%downward])
                as(io, ic) = ieee_value(1.0_wp, ieee_quiet_nan)
                nd(io, ic) = detector_site(hysteresis_drive(self%curve_run_at(ic, io), self%cfg, self%top, self%stair_times(1)))
                if (self%omegas(io) < band_gap_edge(self%runs(ic)%chain)) as(io, ic) = threshold_as(self%runs(ic)%chain, &
                                                                                                    self%omegas(io))
            end do
        end do

        call h5_create(file, path, .true.)
        call write_root(file, self%cfg, "hysteresis", "Hysteresis of supratransmission: the drive amplitude goes up " &
                        // "and down in slow stairs; the upward edge (where the transmitting state is born), the " &
                        // "downward edge (where it dies) and the bistable window, per curve, Omega and stair length", self%inv)
        call h5_write_attr(file, "/", "complete", merge(1, 0, complete))
        call h5_write_attr(file, "/", "tasks_done", count(done))
        call write_parameters(file, self%cfg)
        call h5_write_attr(file, "/parameters", "stair_times_used", self%stair_times)
        call h5_write_attr(file, "/parameters", "power_measure", "mean energy flux " &
            // "c^2 (u_nd - u_nd+1) v_nd+1 + beta (v_nd - v_nd+1) v_nd+1 through the bond beyond the detector site " &
            // "n_d, over the last whole drive periods of each stair's second half")
        call write_row(file, hysteresis_omega, self%omegas)
        call write_row(file, hysteresis_stair_time, self%stair_times)
        call write_row(file, hysteresis_stair_amplitude, levels)
        call write_row(file, hysteresis_stair_direction, direction)
        call write_curves(file, self%cfg, self%runs)
        call write_row(file, hysteresis_upward_threshold, grid3([s%upward]))
        call write_row(file, hysteresis_downward_threshold, grid3([s%downward]))
        call write_row(file, hysteresis_window, grid3([s%window]))
        call write_row(file, hysteresis_upward_spread, spread_up)
        call write_row(file, hysteresis_downward_spread, spread_down)
        call write_row(file, hysteresis_downward_gaps, igrid3([s%downward_gaps]))
        call write_row(file, hysteresis_status, igrid3([s%status]))
        call write_row_attr(file, hysteresis_status, "codes", hysteresis_status_codes())
        call write_row(file, hysteresis_power, reshape(power, [nstair, nlen, nomega, ncurve]))
        call write_row_attr(file, hysteresis_power, "power_threshold", self%cfg%scene%power_threshold)
        call write_row(file, hysteresis_detector_site, nd)
        call write_row(file, hysteresis_threshold_as, as)
        call write_row_group(file, hysteresis_cost)
        call write_row(file, hysteresis_cost_steps, grid3([s%steps]))
        call write_row(file, hysteresis_cost_wall_time, grid3([s%wall_time]))
        if (elapsed >= 0.0_wp) call write_row_attr(file, hysteresis_cost, "scene_wall_time_s", elapsed)
        call h5_commit(file, error)

    contains

        !> A per-task real as a (stair_length, omega, curve) grid: h5py (curve, omega, stair_length).
        pure function grid3(x) result(g)
            real(wp), intent(in) :: x(:)
            real(wp), allocatable :: g(:, :, :)

            g = reshape(x, [nlen, nomega, ncurve])
        end function grid3

        !> A per-task integer as a (stair_length, omega, curve) grid.
        pure function igrid3(x) result(g)
            integer, intent(in) :: x(:)
            integer, allocatable :: g(:, :, :)

            g = reshape(x, [nlen, nomega, ncurve])
        end function igrid3

    end subroutine write_hysteresis_file

    !> max - min of the values that are not NaN; NaN when all are.
    pure function spread(x) result(s)
        !> The values.
        real(wp), intent(in) :: x(:)
        real(wp) :: s
        logical :: ok(size(x))

        ok = .not. ieee_is_nan(x)
        if (.not. any(ok)) then
            s = ieee_value(s, ieee_quiet_nan)
        else
            s = maxval(x, mask=ok) - minval(x, mask=ok)
        end if
    end function spread

    !> The frequency axis and the stairs (levels, time steps and probe memory of each stair length), then the
    !> runs (curves x frequencies) and their work: one run per (curve, Omega, stair length) of ramp_time +
    !> (2K + 1) T_s; its probes at two sites every step.
    pure subroutine hysteresis_scene_limits(self, cfg, where, budget, error)
        !> The scene.
        class(hysteresis_scene), intent(in) :: self
        !> The configuration (values already within their ranges and rules).
        type(input_config), intent(in) :: cfg
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Threads and memory of the machine.
        type(scene_budget), intent(in) :: budget
        !> Allocated when a limit is exceeded.
        type(error_type), allocatable, intent(out) :: error
        real(wp) :: nomega, ngrid, steps, run_steps, need
        real(wp), allocatable :: stair_times(:)
        integer :: i, top

        associate (sc => cfg%scene)
            nomega = axis_points(sc%omega_min, sc%omega_max, sc%omega_step)
            call check_axis(nomega, "omega_step = " // sci(sc%omega_step) // " makes " // sci(nomega) // " frequencies", &
                            where, error)
            if (allocated(error)) return
            ngrid = axis_points(sc%amplitude_min, sc%amplitude_max, sc%stair_height)
            call check_axis(ngrid, "stair_height = " // sci(sc%stair_height) // " makes " // sci(ngrid) // " levels", &
                            where, error)
            if (allocated(error)) return
            stair_times = scene_stair_times(cfg)
            ! the stairs themselves, as the run's task making checks them: refused here, before any file is made
            call check_stairs(cfg, stair_times, where, top, error)
            if (allocated(error)) return
            steps = 0.0_wp
            need = 0.0_wp
            do i = 1, size(stair_times)
                run_steps = stair_run_steps(cfg, ngrid, stair_times(i))
                if (.not. (run_steps <= max_steps)) then
                    call limit_error(error, where, "scene", "a stair run of " // sci(run_steps) // " time steps (stair " &
                                     // "length " // sci(stair_times(i)) // "): more than the limit " // sci(max_steps))
                    return
                end if
                steps = steps + run_steps
                need = max(need, 3.0_wp*8.0_wp*run_steps)
            end do
            need = (need + run_memory_bytes(cfg, .false.))*real(budget%threads, wp)
            if (budget%memory > 0.0_wp .and. need > 0.8_wp*budget%memory) then
                call limit_error(error, where, "scene", "the stair runs' probes need about " // sci(need/1.0e9_wp) &
                                 // " GB" // threads_text(budget) // ", more than the " &
                                 // sci(budget%memory/1.0e9_wp) // " GB available")
                return
            end if
            call check_tasks(cfg, real(curve_count(cfg), wp)*nomega*1.0_wp, 1.0_wp, steps, "runs", where, error)
        end associate
    end subroutine hysteresis_scene_limits

    !> Time steps of one stair run: the ramp from rest, then 2K + 1 stairs of length `stair_time` (K + 1 the
    !> levels of `ngrid` grid points), over dt.
    pure function stair_run_steps(cfg, ngrid, stair_time) result(steps)
        !> The configuration.
        type(input_config), intent(in) :: cfg
        !> Grid points of amplitude_min .. amplitude_max by stair_height (real).
        real(wp), intent(in) :: ngrid
        !> The stair length.
        real(wp), intent(in) :: stair_time
        real(wp) :: steps

        steps = (cfg%run%drive%ramp_time + (2.0_wp*real(floor(ngrid + 1.0e-9_wp), wp) - 1.0_wp)*stair_time) &
                /cfg%run%numerics%dt
    end function stair_run_steps

    !> The stair runs: curves x frequencies x stair lengths, each of its ramp and 2K + 1 stairs (steps: their mean).
    pure function hysteresis_scene_plan(self, cfg) result(p)
        !> The scene.
        class(hysteresis_scene), intent(in) :: self
        !> The configuration (values within their ranges).
        type(input_config), intent(in) :: cfg
        type(scene_plan) :: p
        real(wp), allocatable :: times(:)
        real(wp) :: ngrid
        integer :: i

        associate (sc => cfg%scene)
            times = scene_stair_times(cfg)
            ngrid = axis_points(sc%amplitude_min, sc%amplitude_max, sc%stair_height)
            p%tasks = real(curve_count(cfg), wp)*axis_points(sc%omega_min, sc%omega_max, sc%omega_step) &
                      *real(size(times), wp)
            p%noun = "stair runs"
            p%steps = 0.0_wp
            do i = 1, size(times)
                p%steps = p%steps + stair_run_steps(cfg, ngrid, times(i))/real(size(times), wp)
            end do
        end associate
    end function hysteresis_scene_plan

end module supratrans_scene_hysteresis
