!> Scene `stability`: where each integrator blows up, over a grid of (dt, c), for each curve of the scene
!> (`vary` = gamma, beta or m2), next to the paper's necessary condition and linear stability theory.
!>
!> A run is *stable* when it reaches T with every |u_n| below `blowup_threshold` (status ok); otherwise its status
!> says how it failed (diverged: blow-up or non-finite; newton_failed; solver_failed). For every curve, method and
!> c the scene stores:
!>
!> * the verdict of every (c, dt) of the grid;
!> * the observed boundary, by bisection in dt from a bracket around the linear-theory prediction: the largest dt
!>   found stable and the smallest found unstable, closer than `resolution` (the grid is the check: where it holds
!>   a stable dt above the boundary or an unstable one below it, `grid_consistent` is 0). A run slightly beyond
!>   the boundary grows slowly, so the observed boundary is the boundary *for this T*, at or above the linear one;
!> * the paper's necessary condition (c^2 - m^2/4) dt^2 < 1 + (gamma/4 + beta) dt as its critical dt
!>   (`critical_dt` of `supratrans_chain`);
!> * linear stability theory of each method for the chain linearised at rest (`supratrans_linear_stability`); where
!>   the paper's condition allows a larger dt than the newton scheme's linear limit (gamma > 0 or beta > 0), it is
!>   necessary but not sufficient.
!>
!> Tasks (task engine: OpenMP threads, resumable journal `<output>.journal`, driven by the scene driver of
!> `supratrans_scene`): first one bisection per (curve, method, c), then one run per grid point.
!>
!> HDF5 layout (h5py shapes): `/methods` (method), `/c` (c), `/dt` (dt), `/curves/value` (curve),
!> `/curves/potential` (curve), `/verdict/<method>` (curve, c, dt: 0 stable, 1 diverged, 2 newton_failed,
!> 3 solver_failed), `/max_abs_u/<method>` (curve, c, dt), `/boundary/observed` and `/boundary/observed_unstable`
!> (curve, method, c), `/boundary/linear` (curve, method, c), `/boundary/paper` (curve, c), `/boundary/rk4`
!> (curve, c: RK4's linear limit), `/boundary/rk4_undamped` (curve, c: 2 sqrt(2) / sqrt(V''(0) + m^2 + 4 c^2)),
!> `/boundary/grid_consistent` (curve, method, c), `/boundary/bisection_runs` (curve, method, c).
module supratrans_scene_stability
    use, intrinsic :: iso_fortran_env, only: error_unit
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_nan
    use supratrans_kinds, only: wp
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_invocation, only: invocation_type
    use supratrans_strings, only: int_str, real_str
    use supratrans_scene, only: scene_type, scene_tasks, wrong_tasks, scene_budget, scene_plan
    use supratrans_limits, only: limit_error, threads_text, sci, dense_buffer_bytes
    use supratrans_config, only: input_config, run_config, vary_choices, chain_params, method_newton, method_linearized, &
                                 method_rk4, method_rk8, method_avf4, method_avf8, method_name
    use supratrans_potential, only: potential_name
    use supratrans_chain, only: critical_dt, gap_squared
    use supratrans_curves, only: curve_count, curve_run, write_curves
    use supratrans_simulate, only: simulate
    use supratrans_result, only: run_result, run_ok
    use supratrans_status, only: run_status_codes
    use supratrans_tasks, only: task_list, run_work
    use supratrans_system, only: stop_signal
    use supratrans_hdf5, only: h5_file, h5_create, h5_commit
    use supratrans_output_rows, only: write_row, write_row_group, write_row_attr, stability_methods, &
        stability_c, stability_dt, stability_verdict_method, stability_max_abs_u_method, stability_boundary_observed, &
        stability_boundary_observed_unstable, stability_boundary_linear, stability_boundary_paper, &
        stability_boundary_rk4, stability_boundary_rk4_undamped, stability_boundary_grid_consistent, &
        stability_boundary_bisection_runs, scene_group => stability_scene
    use supratrans_output, only: write_root, write_parameters
    use supratrans_linear_stability, only: linear_stability_dt, rk_spectrum_dt, chain_spectrum, stability_polynomial
    implicit none
    private

    public :: run_stability, linear_stability_dt, rk_spectrum_dt, chain_spectrum, stability_polynomial
    public :: default_stability_dts, run_is_stable

    !> Positions of a task's values. A bisection task fills the largest stable dt, the smallest unstable dt, the runs
    !> it made and the status of the smallest unstable run; a grid task its run's status, max |u| and end time; the
    !> other kind's values are 0.
    integer, parameter :: s_dt_stable = 1, s_dt_unstable = 2, s_bisection_runs = 3, s_unstable_status = 4, &
                          s_status = 5, s_max_abs_u = 6, s_t_end = 7
    !> Number of values per task.
    integer, parameter :: nvalues = 7
    !> Names of a task's values in the order of their positions (the journal stores them by these names).
    character(len=*), parameter :: value_names(nvalues) = [character(len=15) :: "dt_stable", "dt_unstable", &
        "bisection_runs", "unstable_status", "status", "max_abs_u", "t_end"]

    !> Bisection gives up widening its bracket after this many factors of 1.5.
    integer, parameter :: max_widen = 12

    !> A dense eigenvalue problem (dgeev) of order 2N in Newton oscillator-steps, per (2N)^3 (0.78 ns at 60 ns a
    !> step: the continuation's measured `dgeev`), for the estimate of `--check`.
    real(wp), parameter :: spectrum_cube = 0.013_wp

    !> The scene's runs: bisections first (they take longest), then the grid.
    type, extends(task_list) :: stability_tasks
        !> One run configuration per curve (amplitude, T, N, ... of the base run).
        type(run_config), allocatable :: curves(:)
        !> Methods, c axis, dt axis.
        integer, allocatable :: methods(:)
        real(wp), allocatable :: c(:), dts(:)
        !> Linear-theory prediction of each (curve, method, c): the bisection's starting point. (nc, nmethod, ncurve)
        real(wp), allocatable :: predicted(:, :, :)
        !> Critical dt of the paper's condition, RK4's linear limit and its undamped band-top value per (c, curve).
        real(wp), allocatable :: paper(:, :), rk4_limit(:, :), rk4_undamped(:, :)
        !> Bisection resolution in dt.
        real(wp) :: resolution = 1.0e-3_wp
    contains
        !> One task: a bisection for the largest stable dt, or one run of the grid (`stability_task_values`).
        procedure :: run => run_stability_task
        !> Whether a task's values are its result (not a task a stop signal cut short).
        procedure :: finished => stability_finished
    end type stability_tasks

    !> The scene `stability`: the largest stable dt per (curve, method), measured and predicted.
    type, extends(scene_type), public :: stability_scene
    contains
        !> Its tasks: the bisections, then the grid runs (and the linear theory they start from).
        procedure :: make_tasks => stability_make_tasks
        !> Its file (`write_stability`).
        procedure :: write_output => stability_write_output
        !> The address space its dense eigenvalue problems need (OpenBLAS's working buffer) against the memory.
        procedure :: check_limits => stability_scene_limits
        !> Its axes are c (c_values) and dt (dts): `vary` may not name them.
        procedure :: sets_itself => stability_sets_itself
        !> Its tasks and their work from the sizes (`--check`).
        procedure :: plan => stability_scene_plan
    end type stability_scene

contains

    !> Default dt axis of the grid: 24 steps spaced geometrically from 0.05 to 1.5.
    pure function default_stability_dts() result(dts)
        real(wp), allocatable :: dts(:)
        integer :: i

        dts = [(0.05_wp*30.0_wp**(real(i, wp)/23.0_wp), i = 0, 23)]
    end function default_stability_dts

    !> Run the scene `stability` described by `cfg` and write `cfg%output%file`: the scene's `run`
    !> (`supratrans_scene`), under the name the tests call.
    subroutine run_stability(cfg, error, inv)
        !> Validated input (scene kind 'stability').
        type(input_config), intent(in) :: cfg
        !> Error, allocated on failure (bad scene keys, journal or output not writable).
        type(error_type), allocatable, intent(out) :: error
        !> How the engine is invoked (a slice, a merge: `supratrans_invocation`); default: the whole scene.
        type(invocation_type), intent(in), optional :: inv
        type(stability_scene) :: scene

        call scene%run(cfg, error, inv)
    end subroutine run_stability

    !> The tasks of the scene: its methods, c and dt axes (checked), each curve's run, and the linear theory of
    !> every (curve, c): the paper's condition and each method's linear limit, the bisections' starting points.
    subroutine stability_make_tasks(self, cfg, tasks, error)
        !> The scene.
        class(stability_scene), intent(in) :: self
        !> Validated input (scene kind 'stability').
        type(input_config), intent(in) :: cfg
        !> Its tasks: a `stability_tasks`, the bisections then the grid runs.
        type(scene_tasks), intent(inout) :: tasks
        !> Error, allocated when a scene key is not valid.
        type(error_type), allocatable, intent(out) :: error
        type(stability_tasks), allocatable :: list
        real(wp), allocatable :: linear(:, :, :), paper(:, :), rk4_limit(:, :), rk4_undamped(:, :)
        real(wp), allocatable :: re(:), im_part(:)
        character(len=:), allocatable :: where
        type(chain_params) :: chain
        integer :: ncurve, nm, nc, ndt, icurve, im, ic

        allocate (list)
        where = "configuration"
        if (allocated(cfg%source)) where = cfg%source
        list%methods = [method_newton, method_linearized, method_rk4, method_rk8, method_avf4, method_avf8]
        if (allocated(cfg%scene%methods)) then
            if (size(cfg%scene%methods) > 0) list%methods = cfg%scene%methods
        end if
        list%dts = default_stability_dts()
        if (allocated(cfg%scene%dts)) then
            if (size(cfg%scene%dts) > 0) list%dts = cfg%scene%dts
        end if
        list%c = [cfg%run%chain%c]
        if (allocated(cfg%scene%c_values)) then
            if (size(cfg%scene%c_values) > 0) list%c = cfg%scene%c_values
        end if
        if (any(.not. (list%dts > 0.0_wp))) then
            call fatal_error(error, where // ": &scene: dts must be > 0", err_input)
            return
        end if
        if (any(.not. (list%c > 0.0_wp))) then
            call fatal_error(error, where // ": &scene: c_values must be > 0", err_input)
            return
        end if
        list%resolution = cfg%scene%resolution
        ncurve = curve_count(cfg)
        nm = size(list%methods)
        nc = size(list%c)
        ndt = size(list%dts)
        allocate (list%curves(ncurve))
        do icurve = 1, ncurve
            list%curves(icurve) = curve_run(cfg, icurve)
            list%curves(icurve)%record%probes = [integer ::]
            list%curves(icurve)%record%ledger_every = huge(1) - 1
            list%curves(icurve)%detect%stop_when_decided = .false.
        end do

        ! linear theory: the paper's condition, each method's linear limit
        if (.not. cfg%output%quiet) write (error_unit, "(a)") "stability: linear theory (spectra of " &
            // int_str(ncurve*nc) // " linearised chains)"
        allocate (linear(nc, nm, ncurve), paper(nc, ncurve), rk4_limit(nc, ncurve), rk4_undamped(nc, ncurve))
        ! in a parallel region, so that LAPACK's dgeev runs on one thread whatever OMP_NUM_THREADS says (a threaded
        ! BLAS splits its blocks by the thread count, and the last bits of the spectra then move with it)
        !$omp parallel do collapse(2) schedule(static) default(shared) private(chain, re, im_part, im)
        do icurve = 1, ncurve
            do ic = 1, nc
                chain = list%curves(icurve)%chain
                chain%c = list%c(ic)
                paper(ic, icurve) = critical_dt(chain)
                call chain_spectrum(chain, re, im_part)
                rk4_limit(ic, icurve) = rk_spectrum_dt(stability_polynomial(method_rk4), re, im_part)
                rk4_undamped(ic, icurve) = 2.0_wp*sqrt(2.0_wp)/sqrt(max(gap_squared(chain) + 4.0_wp*chain%c**2, &
                                                                        tiny(1.0_wp)))
                do im = 1, nm
                    select case (list%methods(im))
                    case (method_rk4, method_rk8)
                        linear(ic, im, icurve) = rk_spectrum_dt(stability_polynomial(list%methods(im)), re, im_part)
                    case default
                        linear(ic, im, icurve) = linear_stability_dt(chain, list%methods(im))
                    end select
                end do
            end do
        end do
        !$omp end parallel do

        list%predicted = linear
        list%paper = paper
        list%rk4_limit = rk4_limit
        list%rk4_undamped = rk4_undamped
        tasks%count = ncurve*nm*nc + ncurve*nm*nc*ndt
        tasks%fields = value_names
        tasks%label = "stability runs and bisections"
        call move_alloc(list, tasks%list)
    end subroutine stability_make_tasks

    !> Write the scene's file (`write_stability`).
    subroutine stability_write_output(self, cfg, tasks, error)
        !> The scene.
        class(stability_scene), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> The tasks (a `stability_tasks`) and their records.
        type(scene_tasks), intent(in) :: tasks
        !> Error, allocated when the file is not written.
        type(error_type), allocatable, intent(out) :: error

        select type (list => tasks%list)
        type is (stability_tasks)
            call write_stability(cfg, list, tasks%results, error, inv=tasks%inv)
        class default
            call wrong_tasks(error, "stability_tasks")
        end select
    end subroutine stability_write_output

    !> Task `index`: 1..nbis bisections (c fastest, then method, then curve), then grid runs (dt fastest, then c,
    !> method, curve).
    subroutine run_stability_task(self, index, values)
        !> The scene's tasks.
        class(stability_tasks), intent(in) :: self
        !> Task index.
        integer, intent(in) :: index
        !> The task's values (positions `s_*`; all NaN for a task a stop signal cut short).
        real(wp), intent(out) :: values(:)

        call stability_task_values(self, index, values)
        ! its runs stop within a step once a signal has arrived (`interruptible`): what they gave is no result, the
        ! task is not journaled and runs again on resume (it used to run every remaining run of the bisection)
        if (stop_signal() /= 0) values = ieee_value(1.0_wp, ieee_quiet_nan)
    end subroutine run_stability_task

    !> Whether a task's values are its result: those of a task cut short by a stop signal are all NaN.
    function stability_finished(self, values) result(yes)
        !> The task list.
        class(stability_tasks), intent(in) :: self
        !> The task's values.
        real(wp), intent(in) :: values(:)
        logical :: yes

        yes = .not. all(ieee_is_nan(values))
    end function stability_finished

    !> The values of task `index`: a bisection's (largest stable and smallest unstable dt, runs, status) or a grid
    !> run's (status, max |u|, end time).
    subroutine stability_task_values(self, index, values)
        !> The scene's tasks.
        class(stability_tasks), intent(in) :: self
        !> Task index.
        integer, intent(in) :: index
        !> The task's values (positions `s_*`).
        real(wp), intent(out) :: values(:)
        type(run_config) :: run
        type(run_result) :: res
        integer :: ncurve, nm, nc, ndt, nbis, i, idt, ic, im, icurve, runs, status_hi, status
        real(wp) :: lo, hi, mid, nan
        logical :: stable, found_stable

        ncurve = size(self%curves)
        nm = size(self%methods)
        nc = size(self%c)
        ndt = size(self%dts)
        nbis = ncurve*nm*nc
        nan = ieee_value(1.0_wp, ieee_quiet_nan)
        values = 0.0_wp
        if (index <= nbis) then
            i = index - 1
            ic = mod(i, nc) + 1
            im = mod(i/nc, nm) + 1
            icurve = i/(nc*nm) + 1
            run = self%curves(icurve)
            run%chain%c = self%c(ic)
            run%numerics%method = self%methods(im)
            runs = 0
            hi = self%predicted(ic, im, icurve)
            if (.not. (hi < 1.0e3_wp)) hi = 1.0_wp
            hi = 1.05_wp*hi
            lo = 0.0_wp
            found_stable = .false.
            status_hi = run_ok
            ! widen upwards until unstable, then downwards until stable
            do i = 1, max_widen
                call try(hi, stable, status)
                if (.not. stable) then
                    status_hi = status
                    exit
                end if
                lo = hi
                found_stable = .true.
                hi = 1.5_wp*hi
            end do
            if (stable) then
                call bisection_values(lo, nan, runs, run_ok)
                return
            end if
            if (.not. found_stable) then
                lo = hi/1.5_wp
                do i = 1, max_widen
                    call try(lo, stable, status)
                    if (stable) exit
                    hi = lo
                    status_hi = status
                    lo = lo/1.5_wp
                end do
                if (.not. stable) then
                    call bisection_values(nan, hi, runs, status_hi)
                    return
                end if
            end if
            do while (hi - lo > self%resolution)
                mid = 0.5_wp*(lo + hi)
                call try(mid, stable, status)
                if (stable) then
                    lo = mid
                else
                    hi = mid
                    status_hi = status
                end if
            end do
            call bisection_values(lo, hi, runs, status_hi)
        else
            i = index - nbis - 1
            idt = mod(i, ndt) + 1
            ic = mod(i/ndt, nc) + 1
            im = mod(i/(ndt*nc), nm) + 1
            icurve = i/(ndt*nc*nm) + 1
            run = self%curves(icurve)
            run%chain%c = self%c(ic)
            run%numerics%method = self%methods(im)
            run%numerics%dt = self%dts(idt)
            call simulate(run, res, interruptible=.true.)
            values(s_status) = real(res%status, wp)
            values(s_max_abs_u) = res%max_abs_u
            values(s_t_end) = res%t_end
        end if

    contains

        !> The values of a bisection task.
        subroutine bisection_values(dt_stable, dt_unstable, nruns, unstable_status)
            real(wp), intent(in) :: dt_stable, dt_unstable
            integer, intent(in) :: nruns, unstable_status

            values(s_dt_stable) = dt_stable
            values(s_dt_unstable) = dt_unstable
            values(s_bisection_runs) = real(nruns, wp)
            values(s_unstable_status) = real(unstable_status, wp)
        end subroutine bisection_values

        !> One run at step dt: is it stable?
        subroutine try(dt, stable, status)
            real(wp), intent(in) :: dt
            logical, intent(out) :: stable
            integer, intent(out) :: status

            run%numerics%dt = dt
            call simulate(run, res, interruptible=.true.)
            runs = runs + 1
            status = res%status
            stable = run_is_stable(res)
        end subroutine try

    end subroutine stability_task_values

    !> The scene's memory against what the machine gives, before any work: the linear theory solves dense eigenvalue
    !> problems (LAPACK), for which OpenBLAS maps a working buffer on each thread (`dense_buffer_bytes`); under a small
    !> `ulimit -v` the scene used to hang there (OpenBLAS retries the mmap forever). Now one line, status 2.
    pure subroutine stability_scene_limits(self, cfg, where, budget, error)
        !> The scene.
        class(stability_scene), intent(in) :: self
        !> The configuration (values already within their ranges and rules).
        type(input_config), intent(in) :: cfg
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Threads and memory of the machine.
        type(scene_budget), intent(in) :: budget
        !> Allocated when a limit is exceeded.
        type(error_type), allocatable, intent(out) :: error
        real(wp) :: need

        need = dense_buffer_bytes*real(budget%threads, wp)
        if (budget%memory > 0.0_wp .and. need > 0.8_wp*budget%memory) then
            call limit_error(error, where, "scene", "the dense eigenvalue problems of the linear theory need about " &
                             // sci(need/1.0e9_wp) // " GB (OpenBLAS's working buffer)" // threads_text(budget) &
                             // ", more than the " // sci(budget%memory/1.0e9_wp) // " GB available (" &
                             // budget%source // ")")
        end if
    end subroutine stability_scene_limits

    !> The tasks (bisections, then grid runs) and their work from the sizes, for `--check`: every grid run to T (a
    !> run that blows up stops sooner: an upper bound), each bisection as 2 + log2(dt_p / (3 resolution)) runs at the
    !> paper's critical dt dt_p (its bracket starts a factor 1.5 wide around the linear limit), and the spectra of the
    !> linear theory (one 2N x 2N per curve and c).
    pure function stability_scene_plan(self, cfg) result(p)
        !> The scene.
        class(stability_scene), intent(in) :: self
        !> The configuration (values within their ranges).
        type(input_config), intent(in) :: cfg
        type(scene_plan) :: p
        integer, allocatable :: methods(:)
        real(wp), allocatable :: dts(:), c(:)
        type(run_config) :: run
        real(wp) :: dt_p, runs, bisection_runs, bisections, n
        integer :: icurve, im, ic, idt

        methods = [method_newton, method_linearized, method_rk4, method_rk8, method_avf4, method_avf8]
        if (allocated(cfg%scene%methods)) then
            if (size(cfg%scene%methods) > 0) methods = cfg%scene%methods
        end if
        dts = default_stability_dts()
        if (allocated(cfg%scene%dts)) then
            if (size(cfg%scene%dts) > 0) dts = cfg%scene%dts
        end if
        c = [cfg%run%chain%c]
        if (allocated(cfg%scene%c_values)) then
            if (size(cfg%scene%c_values) > 0) c = cfg%scene%c_values
        end if
        p%noun = "bisections and grid runs"
        p%tasks = real(curve_count(cfg)*size(methods)*size(c)*(1 + size(dts)), wp)
        p%work = 0.0_wp
        runs = 0.0_wp
        bisections = 0.0_wp
        n = real(cfg%run%chain%n, wp)
        do icurve = 1, curve_count(cfg)
            do ic = 1, size(c)
                run = curve_run(cfg, icurve)
                run%chain%c = c(ic)
                p%work = p%work + (2.0_wp*n)**3*spectrum_cube
                dt_p = min(critical_dt(run%chain), 1.0_wp)
                if (.not. (dt_p > 0.0_wp)) dt_p = 1.0_wp
                do im = 1, size(methods)
                    run%numerics%method = methods(im)
                    do idt = 1, size(dts)
                        if (.not. (dts(idt) > 0.0_wp)) cycle        ! refused by the scene
                        run%numerics%dt = dts(idt)
                        p%work = p%work + run_work(run)
                        runs = runs + 1.0_wp
                    end do
                    run%numerics%dt = dt_p
                    bisection_runs = max(2.0_wp + log(dt_p/(3.0_wp*max(cfg%scene%resolution, 1.0e-12_wp)))/log(2.0_wp), &
                                         2.0_wp)
                    p%work = p%work + bisection_runs*run_work(run)
                    bisections = bisections + bisection_runs
                end do
            end do
        end do
        p%runs_per_task = (runs + bisections)/max(p%tasks, 1.0_wp)
        p%counts = int_str(nint(runs)) // " grid runs to T = " // real_str(cfg%run%numerics%t_final) // " x N = " &
            // int_str(cfg%run%chain%n) // ", about " // int_str(nint(bisections)) // " bisection runs at the " &
            // "paper's critical dt, the linear theory's spectra"
    end function stability_scene_plan

    !> A run is stable when it reached its final time without blowing up or failing.
    pure function run_is_stable(res) result(stable)
        !> The run's result.
        type(run_result), intent(in) :: res
        logical :: stable

        stable = res%status == run_ok
    end function run_is_stable

    !> Write the scene's HDF5 file: the grid's verdicts, the observed boundaries and the linear theory of `tasks`.
    subroutine write_stability(cfg, tasks, results, error, inv)
        !> Validated input.
        type(input_config), intent(in) :: cfg
        !> The tasks, with their linear theory.
        type(stability_tasks), intent(in) :: tasks
        !> Every task's values (`s_*`, tasks).
        real(wp), intent(in), contiguous :: results(:, :)
        !> Error, allocated when the file cannot be written.
        type(error_type), allocatable, intent(out) :: error
        !> How the engine was invoked (a merge records its parts).
        type(invocation_type), intent(in), optional :: inv
        type(h5_file) :: file
        integer :: ncurve, nm, nc, ndt, nbis, icurve, im, ic, idt, itask
        integer, allocatable :: verdict(:, :, :)
        real(wp), allocatable :: umax(:, :, :), observed(:, :, :), observed_hi(:, :, :)
        real(wp), allocatable :: consistent(:, :, :), runs(:, :, :)
        character(len=16), allocatable :: names(:)
        real(wp) :: status
        logical :: ok

        ncurve = size(tasks%curves)
        nm = size(tasks%methods)
        nc = size(tasks%c)
        ndt = size(tasks%dts)
        nbis = ncurve*nm*nc
        allocate (observed(nc, nm, ncurve), observed_hi(nc, nm, ncurve), consistent(nc, nm, ncurve), &
                  runs(nc, nm, ncurve), names(nm))
        do icurve = 1, ncurve
            do im = 1, nm
                do ic = 1, nc
                    itask = ic + nc*((im - 1) + nm*(icurve - 1))
                    observed(ic, im, icurve) = results(s_dt_stable, itask)
                    observed_hi(ic, im, icurve) = results(s_dt_unstable, itask)
                    runs(ic, im, icurve) = results(s_bisection_runs, itask)
                end do
            end do
        end do
        call h5_create(file, trim(cfg%output%file), cfg%output%overwrite)
        call write_root(file, cfg, "stability", "Where each integrator blows up over a grid of (dt, c), observed " &
                        // "boundaries next to the paper's necessary condition and linear stability theory", inv)
        call write_parameters(file, cfg)
        call write_row_group(file, scene_group)
        call write_row_attr(file, scene_group, "vary", trim(vary_choices(cfg%scene%vary)))
        call write_row_attr(file, scene_group, "resolution", tasks%resolution)
        call write_row_attr(file, scene_group, "stable_means", "the run reaches T with " &
            // "every |u_n| <= blowup_threshold (status ok)")
        call write_row_attr(file, scene_group, "status_codes", &
            "stable means 0 ok; " // run_status_codes(outside_gap=.false., not_run=.false.))
        do im = 1, nm
            names(im) = method_name(tasks%methods(im))
        end do
        call write_row(file, stability_methods, names)
        call write_row(file, stability_c, tasks%c)
        call write_row(file, stability_dt, tasks%dts)
        call write_curves(file, cfg, tasks%curves)

        allocate (verdict(ndt, nc, ncurve), umax(ndt, nc, ncurve))
        do im = 1, nm
            do icurve = 1, ncurve
                do ic = 1, nc
                    ok = .true.
                    do idt = 1, ndt
                        itask = nbis + idt + ndt*((ic - 1) + nc*((im - 1) + nm*(icurve - 1)))
                        status = results(s_status, itask)
                        verdict(idt, ic, icurve) = nint(status)
                        umax(idt, ic, icurve) = results(s_max_abs_u, itask)
                        ! the grid agrees with the bisection: stable at or below the stable dt, unstable at or above
                        ! the unstable one
                        if (tasks%dts(idt) <= observed(ic, im, icurve) .and. nint(status) /= run_ok) ok = .false.
                        if (tasks%dts(idt) >= observed_hi(ic, im, icurve) .and. nint(status) == run_ok) ok = .false.
                    end do
                    consistent(ic, im, icurve) = merge(1.0_wp, 0.0_wp, ok)
                end do
            end do
            call write_row(file, stability_verdict_method, verdict, name=trim(names(im)))
            call write_row(file, stability_max_abs_u_method, umax, name=trim(names(im)))
        end do
        call write_row(file, stability_boundary_observed, observed)
        call write_row(file, stability_boundary_observed_unstable, observed_hi)
        call write_row(file, stability_boundary_linear, tasks%predicted)
        call write_row(file, stability_boundary_paper, tasks%paper)
        call write_row(file, stability_boundary_rk4, tasks%rk4_limit)
        call write_row(file, stability_boundary_rk4_undamped, tasks%rk4_undamped)
        call write_row(file, stability_boundary_grid_consistent, consistent)
        call write_row(file, stability_boundary_bisection_runs, runs)
        call h5_commit(file, error)
    end subroutine write_stability

    !> Whether the stability scene sets `key` itself: c and dt, its two axes (the runs keep the base run's amplitude).
    pure logical function stability_sets_itself(self, key) result(yes)
        !> The scene.
        class(stability_scene), intent(in) :: self
        !> The key's name.
        character(len=*), intent(in) :: key

        yes = key == "c" .or. key == "dt"
    end function stability_sets_itself

end module supratrans_scene_stability
