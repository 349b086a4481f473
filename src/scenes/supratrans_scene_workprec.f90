!> Scene `work_precision`: speed against accuracy of every integrator on one physical problem.
!>
!> For each drive amplitude of the scene (`amplitudes`, default the &drive amplitude), each method of `methods`
!> (default: newton, linearized, rk4, rk8) and each time step of `dts` not below the method's `dt_smallest`, one
!> run of the base problem is made with a single probe (the first site of &record `probes`) and the ledger closed
!> only at the start and at the end, and compared with a reference solution:
!>
!> * reference: the eighth-order method (`rk8`) at `reference_dt`/2, every level recorded; the same run at
!>   `reference_dt` gives its error estimate (the difference of the two, a conservative bound for the finer one,
!>   whose error is about 2^-8 of it). Values between the reference's levels are 8-point Lagrange interpolants
!>   (interpolation error ~ (omega h)^8 / 8!, below 1e-14 for h = 0.0125 and the band top omega = 8.06);
!> * error in the injected energy, relative to the reference's injected energy at T: the leapfrog schemes
!>   (newton, linearized) sum dt P_k over k = 1..M-1, the energy injected over [dt/2, T - dt/2] (their energy
!>   lives on half levels), so they are compared with the reference's energy injected over that window; the
!>   Runge-Kutta methods with the energy injected over [0, T];
!> * error in u at the probe: the largest |u - u_ref| over the method's samples in the last drive period
!>   [T - 2 pi/Omega, T] (absolute, rad);
!> * ledger drift: |E(T) - E(0) - (injected - dissipated)| / energy scale at the end of the run (roundoff for the
!>   energy-conserving scheme, the method's energy error for the others);
!> * wall time: median over `repeats` runs of the run's own clock. The runs are timed one at a time: the timed
!>   runs of a task are a critical section, so no two overlap, whatever the number of threads of the task engine
!>   (the global OpenMP setting is left alone; the reference runs before, on all threads).
!>
!> A run that blows up (status `diverged`), whose Newton iteration fails, or whose ledger does not close to
!> `drift_limit` of its energy scale (it ran outside its stability region without reaching the blow-up
!> threshold: e.g. the linearized scheme at dt = 0.25, c = 4, where it needs dt < 0.248) is recorded with its
!> status and NaN in every measured quantity: it is not data.
!>
!> Lower bound (`measure_step_kernels`): a step of any of these methods cannot avoid N sines (the potential), and
!> the implicit schemes one tridiagonal solve (N divisions when beta = 0, where the matrix is diagonal); a
!> Runge-Kutta method needs N sines per stage. These kernels are timed alone, and each run's wall time is
!> compared with steps x (its unavoidable kernels).
!>
!> HDF5 layout (h5py shapes; amp = amplitudes, method = methods, dt = dts):
!> `/methods` (method), `/amplitude` (amp), `/dt` (method, dt: NaN where not run), `/steps` (method, dt),
!> `/status` (amp, method, dt: -1 not run, 0 ok, 1 diverged, 2 newton_failed, 3 solver_failed), `/wall_time`,
!> `/wall_time_min`, `/injected`, `/error_energy`, `/error_u`, `/ledger_drift`, `/rhs_evaluations` (amp, method,
!> dt), `/order_energy`, `/order_u` (amp, method), the groups `/reference` and `/lower_bound`, `/parameters` and `/scene`
!> attributes.
module supratrans_scene_workprec
    use, intrinsic :: iso_fortran_env, only: error_unit
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp
    use supratrans_error, only: error_type
    use supratrans_invocation, only: invocation_type
    use supratrans_strings, only: real_str, printable, int_str
    use supratrans_scene, only: scene_type, scene_tasks, wrong_tasks, scene_budget, scene_plan
    use supratrans_limits, only: check_tasks, sci, limit_error, max_site_steps
    use supratrans_tasks, only: run_work
    use supratrans_config, only: input_config, run_config, method_newton, method_linearized, method_rk8, method_name
    use supratrans_status, only: status_not_run
    use supratrans_hdf5, only: h5_file, h5_create, h5_commit
    use supratrans_output_rows, only: write_row, write_row_group, write_row_attr, work_precision_scene, &
        work_precision_methods, work_precision_amplitude, work_precision_dt, work_precision_steps, work_precision_status, &
        work_precision_wall_time, work_precision_wall_time_min, work_precision_injected, work_precision_error_energy, &
        work_precision_error_u, work_precision_ledger_drift, work_precision_rhs_evaluations, work_precision_max_abs_u, &
        work_precision_order_energy, work_precision_order_u, work_precision_reference, work_precision_reference_injected, &
        work_precision_reference_error_energy, work_precision_reference_error_u, work_precision_reference_u_scale, &
        work_precision_reference_u_final, work_precision_reference_wall_time, work_precision_lower_bound, &
        work_precision_lower_bound_sine_time, work_precision_lower_bound_division_time, &
        work_precision_lower_bound_tridiagonal_time, work_precision_lower_bound_run_time, work_precision_lower_bound_ratio
    use supratrans_output, only: write_root, write_parameters
    use supratrans_workprec_measure, only: fitted_order, method_stages, measure_step_kernels
    use supratrans_workprec_tasks, only: workprec_tasks, setup_tasks, compute_references, drift_limit, value_names, &
                                         default_methods, default_workprec_dts, &
                                         nvalues, w_status, w_wall_time, w_wall_time_min, w_injected, w_error_energy, &
                                         w_error_u, w_ledger_drift, w_rhs_evaluations, w_max_abs_u
    implicit none
    private

    public :: run_work_precision

    !> Status of a (method, dt) pair that was not run (dt below the method's `dt_smallest`): `supratrans_status`'s.
    public :: status_not_run

    !> The scene `work_precision`: timed runs per (method, dt) against a reference.
    type, extends(scene_type), public :: workprec_scene
    contains
        !> Its tasks: the references computed, one timed task per (amplitude, method, dt).
        procedure :: make_tasks => workprec_make_tasks
        !> Its file, with the step's kernels timed (`write_work_precision`).
        procedure :: write_output => workprec_write_output
        !> Its task count and work (repeats, methods, time steps, amplitudes and the references) against the limits.
        procedure :: check_limits => workprec_scene_limits
        !> Its keys (`setup_tasks`' checks), for validation: before anything is created, also by --check.
        procedure :: check_input => workprec_check_input
        !> Its timed runs and their work from the sizes (`--check`).
        procedure :: plan => workprec_scene_plan
    end type workprec_scene

contains

    !> Run the scene `work_precision` described by `cfg` and write `cfg%output%file`: the scene's `run`
    !> (`supratrans_scene`), under the name the tests call.
    subroutine run_work_precision(cfg, error, inv)
        !> Validated input (scene kind 'work_precision').
        type(input_config), intent(in) :: cfg
        !> Error, allocated on failure (bad scene keys, a failed reference run, output not writable).
        type(error_type), allocatable, intent(out) :: error
        !> How the engine is invoked (a slice, a merge: `supratrans_invocation`); default: the whole scene.
        type(invocation_type), intent(in), optional :: inv
        type(workprec_scene) :: scene

        call scene%run(cfg, error, inv)
    end subroutine run_work_precision

    !> The timed runs of the scene (`setup_tasks`), after the reference solution of each amplitude.
    subroutine workprec_make_tasks(self, cfg, tasks, error)
        !> The scene.
        class(workprec_scene), intent(in) :: self
        !> Validated input (scene kind 'work_precision').
        type(input_config), intent(in) :: cfg
        !> Its tasks: a `workprec_tasks`, (dt, method, amplitude), dt fastest.
        type(scene_tasks), intent(inout) :: tasks
        !> Error, allocated when a scene key is not valid or a reference run fails.
        type(error_type), allocatable, intent(out) :: error
        type(workprec_tasks), allocatable :: list

        allocate (list)
        call setup_tasks(cfg, list, error)
        if (allocated(error)) return
        call progress(cfg, "work_precision: reference solutions (rk8 at dt = " // real_str(cfg%scene%reference_dt) &
                      // " and " // real_str(0.5_wp*cfg%scene%reference_dt) // ")")
        call compute_references(list, error)
        if (allocated(error)) return
        tasks%count = size(list%amplitudes)*size(list%methods)*size(list%dts)
        tasks%fields = value_names
        tasks%label = "timed runs (one at a time)"
        call move_alloc(list, tasks%list)
    end subroutine workprec_make_tasks

    !> The scene's work against the limits before any run: every timed run (`repeats` of each amplitude, method and
    !> dt, of t_final/dt steps) and the two reference runs of each amplitude (at reference_dt and reference_dt/2), in
    !> oscillator-steps, against `max_site_steps` (a scene's work limit); the timed runs against `max_tasks`.
    !> `repeats = 2147483647` used to pass `--check` and run for days, unstoppable by SIGTERM.
    pure subroutine workprec_scene_limits(self, cfg, where, budget, error)
        !> The scene.
        class(workprec_scene), intent(in) :: self
        !> The configuration (values already within their ranges and rules).
        type(input_config), intent(in) :: cfg
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Threads and memory of the machine.
        type(scene_budget), intent(in) :: budget
        !> Allocated when a limit is exceeded.
        type(error_type), allocatable, intent(out) :: error
        real(wp), allocatable :: dts(:)
        real(wp) :: methods, amplitudes, repeats, t_final, timed, reference, work, n

        dts = default_workprec_dts()
        if (allocated(cfg%scene%dts)) then
            if (size(cfg%scene%dts) > 0) dts = cfg%scene%dts
        end if
        methods = real(size(default_methods()), wp)
        if (allocated(cfg%scene%methods)) then
            if (size(cfg%scene%methods) > 0) methods = real(size(cfg%scene%methods), wp)
        end if
        amplitudes = 1.0_wp
        if (allocated(cfg%scene%amplitudes)) then
            if (size(cfg%scene%amplitudes) > 0) amplitudes = real(size(cfg%scene%amplitudes), wp)
        end if
        repeats = real(max(cfg%scene%repeats, 1), wp)
        t_final = cfg%run%numerics%t_final
        n = real(cfg%run%chain%n, wp)
        ! steps of the timed runs of one (amplitude, method) pair, once each (a dt <= 0 is refused by the scene)
        timed = sum(t_final/dts, mask=dts > 0.0_wp)
        reference = 0.0_wp
        if (cfg%scene%reference_dt > 0.0_wp) reference = 3.0_wp*t_final/cfg%scene%reference_dt
        ! the count of timed runs here; their work, repeats and references included, below
        call check_tasks(cfg, amplitudes*methods*real(size(dts), wp), 1.0_wp, 0.0_wp, "timed runs", where, error)
        if (allocated(error)) return
        work = n*amplitudes*(methods*repeats*timed + reference)
        if (.not. (work <= max_site_steps)) then
            call limit_error(error, where, "scene", "about " // sci(work) // " oscillator-steps (repeats = " &
                             // sci(repeats) // " x " // sci(methods) // " methods x " // sci(timed) // " steps over " &
                             // "the dts x " // sci(amplitudes) // " amplitudes x " // sci(n) // " oscillators, and " &
                             // "the references): more than the limit " // sci(max_site_steps) // " (about a day on " &
                             // "one core); fewer repeats, dts or amplitudes, or a shorter chain")
        end if
    end subroutine workprec_scene_limits
    !> The timed tasks (amplitude, method, dt) and their work from the sizes, for `--check`: each (method, dt) not
    !> below the method's dt_smallest run `repeats` times to T (one at a time: the timed runs do not overlap, so the
    !> threads do not divide it), and per amplitude the references, rk8 at reference_dt/2 and reference_dt.
    pure function workprec_scene_plan(self, cfg) result(p)
        !> The scene.
        class(workprec_scene), intent(in) :: self
        !> The configuration (values within their ranges).
        type(input_config), intent(in) :: cfg
        type(scene_plan) :: p
        integer, allocatable :: methods(:)
        real(wp), allocatable :: dts(:), smallest(:)
        type(run_config) :: run
        real(wp) :: amplitudes, repeats, timed, runs
        integer :: im, idt

        methods = default_methods()
        if (allocated(cfg%scene%methods)) then
            if (size(cfg%scene%methods) > 0) methods = cfg%scene%methods
        end if
        dts = default_workprec_dts()
        if (allocated(cfg%scene%dts)) then
            if (size(cfg%scene%dts) > 0) dts = cfg%scene%dts
        end if
        allocate (smallest(size(methods)), source=0.0_wp)
        if (allocated(cfg%scene%dt_smallest)) then
            if (size(cfg%scene%dt_smallest) == size(methods)) smallest = cfg%scene%dt_smallest
        end if
        amplitudes = 1.0_wp
        if (allocated(cfg%scene%amplitudes)) then
            if (size(cfg%scene%amplitudes) > 0) amplitudes = real(size(cfg%scene%amplitudes), wp)
        end if
        repeats = real(max(cfg%scene%repeats, 1), wp)
        p%noun = "timed tasks"
        p%tasks = amplitudes*real(size(methods)*size(dts), wp)
        p%serial = .true.
        run = cfg%run
        timed = 0.0_wp
        runs = 0.0_wp
        do im = 1, size(methods)
            run%numerics%method = methods(im)
            do idt = 1, size(dts)
                if (.not. (dts(idt) > 0.0_wp) .or. dts(idt) < smallest(im)*(1.0_wp - 1.0e-12_wp)) cycle
                run%numerics%dt = dts(idt)
                timed = timed + run_work(run)
                runs = runs + 1.0_wp
            end do
        end do
        p%work = amplitudes*repeats*timed
        p%runs_per_task = repeats*runs/real(max(size(methods)*size(dts), 1), wp)
        if (cfg%scene%reference_dt > 0.0_wp) then
            run%numerics%method = method_rk8
            run%numerics%dt = cfg%scene%reference_dt
            p%work = p%work + 3.0_wp*amplitudes*run_work(run)     ! reference_dt/2 and reference_dt
        end if
        p%counts = int_str(nint(amplitudes*runs)) // " (amplitude, method, dt) x repeats = " // int_str(nint(repeats)) &
            // " runs to T = " // real_str(cfg%run%numerics%t_final) // " x N = " // int_str(cfg%run%chain%n) &
            // ", one at a time, and the rk8 references"
    end function workprec_scene_plan

    !> The scene's keys as `setup_tasks` checks them (dt_smallest one per method, dts and reference_dt within
    !> t_final/2, amplitudes, repeats), made by validation so that --check refuses what the run would, before the
    !> output's folder and lock; nothing is run.
    subroutine workprec_check_input(self, cfg, where, error)
        !> The scene.
        class(workprec_scene), intent(in) :: self
        !> The configuration (values already within their ranges, rules and limits).
        type(input_config), intent(in) :: cfg
        !> Prefix of messages (the file name; `setup_tasks` takes it from `cfg`).
        character(len=*), intent(in) :: where
        !> Allocated when a key is not valid.
        type(error_type), allocatable, intent(out) :: error
        type(workprec_tasks) :: probe

        call setup_tasks(cfg, probe, error)
    end subroutine workprec_check_input

    !> Time the kernels of a step (the lower bound) and write the scene's file (`write_work_precision`).
    subroutine workprec_write_output(self, cfg, tasks, error)
        !> The scene.
        class(workprec_scene), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> The tasks (a `workprec_tasks`) and their records.
        type(scene_tasks), intent(in) :: tasks
        !> Error, allocated when the file is not written.
        type(error_type), allocatable, intent(out) :: error
        real(wp) :: t_sine, t_division, t_tridiag

        select type (list => tasks%list)
        type is (workprec_tasks)
            call measure_step_kernels(list%base%chain%n, maxval(list%amplitudes), t_sine, t_division, t_tridiag)
            call write_work_precision(cfg, list, tasks%results, t_sine, t_division, t_tridiag, error, inv=tasks%inv)
        class default
            call wrong_tasks(error, "workprec_tasks")
        end select
    end subroutine workprec_write_output

    !> Write the scene's HDF5 file.
    subroutine write_work_precision(cfg, tasks, results, t_sine, t_division, t_tridiag, error, inv)
        !> Validated input.
        type(input_config), intent(in) :: cfg
        !> The task list, references computed.
        type(workprec_tasks), intent(in) :: tasks
        !> Every task's values (`w_*`, tasks).
        real(wp), intent(in) :: results(:, :)
        !> Seconds of N sines, N divisions and one tridiagonal solve (`measure_step_kernels`).
        real(wp), intent(in) :: t_sine, t_division, t_tridiag
        !> Error, allocated when the file cannot be written.
        type(error_type), allocatable, intent(out) :: error
        !> How the engine was invoked (a merge records its parts).
        type(invocation_type), intent(in), optional :: inv
        type(h5_file) :: file
        integer :: ndt, nm, namp, ia, im, idt, itask
        real(wp), allocatable :: grid(:, :, :, :), dt(:, :), steps(:, :), order_e(:, :), order_u(:, :), lb(:, :, :)
        real(wp), allocatable :: ratio(:, :, :)
        real(wp) :: nan, per_step
        character(len=16), allocatable :: names(:)

        ndt = size(tasks%dts)
        nm = size(tasks%methods)
        namp = size(tasks%amplitudes)
        nan = ieee_value(1.0_wp, ieee_quiet_nan)
        allocate (grid(ndt, nm, namp, nvalues))
        do ia = 1, namp
            do im = 1, nm
                do idt = 1, ndt
                    itask = idt + ndt*((im - 1) + nm*(ia - 1))
                    grid(idt, im, ia, :) = results(:, itask)
                end do
            end do
        end do
        allocate (dt(ndt, nm), steps(ndt, nm), order_e(nm, namp), order_u(nm, namp), names(nm))
        allocate (lb(ndt, nm, namp), ratio(ndt, nm, namp))
        do im = 1, nm
            names(im) = method_name(tasks%methods(im))
            do idt = 1, ndt
                if (nint(grid(idt, im, 1, w_status)) == status_not_run) then
                    dt(idt, im) = nan
                    steps(idt, im) = nan
                else
                    dt(idt, im) = tasks%dts(idt)
                    steps(idt, im) = real(nint(tasks%base%numerics%t_final/tasks%dts(idt)), wp)
                end if
            end do
            if (tasks%methods(im) == method_newton .or. tasks%methods(im) == method_linearized) then
                per_step = t_sine + merge(t_tridiag, t_division, tasks%base%chain%beta > 0.0_wp)
            else
                per_step = real(method_stages(tasks%methods(im)), wp)*t_sine
            end if
            do ia = 1, namp
                order_e(im, ia) = fitted_order(dt(:, im), grid(:, im, ia, w_error_energy), &
                                               max(tasks%refs(ia)%error_energy, 1.0e-13_wp))
                order_u(im, ia) = fitted_order(dt(:, im), grid(:, im, ia, w_error_u)/tasks%refs(ia)%u_scale, &
                                               max(tasks%refs(ia)%error_u/tasks%refs(ia)%u_scale, 1.0e-13_wp))
                lb(:, im, ia) = steps(:, im)*per_step
                ratio(:, im, ia) = grid(:, im, ia, w_wall_time)/lb(:, im, ia)
            end do
        end do

        call h5_create(file, trim(cfg%output%file), cfg%output%overwrite)
        call write_root(file, cfg, "work_precision", "Speed against accuracy: wall time, errors against a reference " &
                        // "and ledger drift for each integrator, time step and drive amplitude", inv)
        call write_parameters(file, cfg)
        call write_row_group(file, work_precision_scene)
        call write_row_attr(file, work_precision_scene, "repeats", tasks%repeats)
        call write_row_attr(file, work_precision_scene, "timing", "median of the run's own wall " &
            // "clock over `repeats` runs; the runs are timed one at a time (a critical section)")
        call write_row_attr(file, work_precision_scene, "probe_site", tasks%base%record%probes(1))
        call write_row_attr(file, work_precision_scene, "error_window", tasks%window)
        call write_row_attr(file, work_precision_scene, "drift_limit", drift_limit)
        call write_row_attr(file, work_precision_scene, "dt_smallest", tasks%dt_smallest)
        call write_row_attr(file, work_precision_scene, "status_codes", &
            "-1 not_run, 0 ok, 1 diverged (blow-up, or ledger residual above drift_limit of the energy scale), " &
            // "2 newton_failed, 3 solver_failed")
        call write_row(file, work_precision_methods, names)
        call write_row(file, work_precision_amplitude, tasks%amplitudes)
        call write_row(file, work_precision_dt, dt)
        call write_row(file, work_precision_steps, steps)
        call write_row(file, work_precision_status, nint(grid(:, :, :, w_status)))
        call write_row(file, work_precision_wall_time, grid(:, :, :, w_wall_time))
        call write_row(file, work_precision_wall_time_min, grid(:, :, :, w_wall_time_min))
        call write_row(file, work_precision_injected, grid(:, :, :, w_injected))
        call write_row(file, work_precision_error_energy, grid(:, :, :, w_error_energy))
        call write_row(file, work_precision_error_u, grid(:, :, :, w_error_u))
        call write_row(file, work_precision_ledger_drift, grid(:, :, :, w_ledger_drift))
        call write_row(file, work_precision_rhs_evaluations, grid(:, :, :, w_rhs_evaluations))
        call write_row(file, work_precision_max_abs_u, grid(:, :, :, w_max_abs_u))
        call write_row(file, work_precision_order_energy, order_e)
        call write_row(file, work_precision_order_u, order_u)
        ! reference
        call write_row_group(file, work_precision_reference)
        call write_row_attr(file, work_precision_reference, "method", "rk8")
        call write_row_attr(file, work_precision_reference, "dt", 0.5_wp*tasks%reference_dt)
        call write_row_attr(file, work_precision_reference, "check_dt", tasks%reference_dt)
        call write_row(file, work_precision_reference_injected, ref_column(1))
        call write_row(file, work_precision_reference_error_energy, ref_column(2))
        call write_row(file, work_precision_reference_error_u, ref_column(3))
        call write_row(file, work_precision_reference_u_scale, ref_column(4))
        call write_row(file, work_precision_reference_u_final, ref_column(5))
        call write_row(file, work_precision_reference_wall_time, ref_column(6))
        ! lower bound
        call write_row_group(file, work_precision_lower_bound)
        call write_row(file, work_precision_lower_bound_sine_time, t_sine)
        call write_row(file, work_precision_lower_bound_division_time, t_division)
        call write_row(file, work_precision_lower_bound_tridiagonal_time, t_tridiag)
        call write_row(file, work_precision_lower_bound_run_time, lb)
        call write_row(file, work_precision_lower_bound_ratio, ratio)
        call h5_commit(file, error)

    contains

        !> One quantity of every amplitude's reference, as a contiguous array: 1 injected energy, 2 its error
        !> estimate, 3 u's error estimate, 4 u scale, 5 u at T, 6 wall time.
        function ref_column(k) result(column)
            integer, intent(in) :: k
            real(wp) :: column(namp)
            integer :: i

            do i = 1, namp
                associate (ref => tasks%refs(i))
                    select case (k)
                    case (1)
                        column(i) = ref%injected_final
                    case (2)
                        column(i) = ref%error_energy
                    case (3)
                        column(i) = ref%error_u
                    case (4)
                        column(i) = ref%u_scale
                    case (5)
                        column(i) = ref%u(size(ref%u))
                    case default
                        column(i) = ref%wall_time
                    end select
                end associate
            end do
        end function ref_column

    end subroutine write_work_precision

    !> Progress line on stderr unless the output is quiet.
    subroutine progress(cfg, line)
        !> The input (for the quiet flag).
        type(input_config), intent(in) :: cfg
        !> Text.
        character(len=*), intent(in) :: line

        if (.not. cfg%output%quiet) write (error_unit, "(a)") printable(line)
    end subroutine progress

end module supratrans_scene_workprec
