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
!> dt), `/order_energy`, `/order_u` (amp, method), `/reference/*`, `/lower_bound/*`, `/parameters` and `/scene`
!> attributes.
module supratrans_scene_workprec
    use, intrinsic :: iso_fortran_env, only: error_unit
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_nan
    use supratrans_kinds, only: wp, i8, pi
    use supratrans_error, only: error_type, fatal_error, err_input, err_runtime
    use supratrans_invocation, only: invocation_type
    use supratrans_strings, only: int_str, real_str, printable
    use supratrans_scene, only: scene_type
    use supratrans_config, only: input_config, run_config, method_newton, method_linearized, method_rk4, method_rk8, &
                                 method_avf4, method_avf8, method_name
    use supratrans_simulate, only: simulate
    use supratrans_result, only: run_result, run_ok, run_diverged, status_name
    use supratrans_status, only: status_not_run
    use supratrans_tasks, only: task_list, run_tasks, input_fingerprint, engine_only
    use supratrans_system, only: remove_file
    use supratrans_hdf5, only: h5_file, h5_create, h5_commit, h5_write, h5_write_attr, h5_create_group
    use supratrans_output, only: write_root, write_parameters
    use supratrans_tridiag, only: solve_tridiag
    use supratrans_stepper_rk8, only: rk8_stages
    implicit none
    private

    public :: run_work_precision, measure_step_kernels, default_methods, default_workprec_dts, fitted_order
    public :: method_stages, median

    !> Status of a (method, dt) pair that was not run (dt below the method's `dt_smallest`): `supratrans_status`'s.
    public :: status_not_run
    !> A run whose final ledger residual exceeds this fraction of its energy scale is declared diverged.
    real(wp), parameter, public :: drift_limit = 0.5_wp
    !> Errors above this are pre-asymptotic and left out of the fitted orders.
    real(wp), parameter :: order_fit_ceiling = 1.0e-2_wp
    !> The fitted orders use at most this many of the smallest time steps.
    integer, parameter :: order_fit_points = 4

    !> Positions of a task's values: status, median and minimum wall time, injected energy, relative error of the
    !> injected energy, error in u at the probe, ledger drift, steps, right-hand sides / solves, max |u|.
    integer, parameter :: w_status = 1, w_wall_time = 2, w_wall_time_min = 3, w_injected = 4, w_error_energy = 5, &
                          w_error_u = 6, w_ledger_drift = 7, w_steps = 8, w_rhs_evaluations = 9, w_max_abs_u = 10
    !> Number of values per task.
    integer, parameter :: nvalues = 10
    !> Names of a task's values in the order of their positions (the journal stores them by these names).
    character(len=*), parameter :: value_names(nvalues) = [character(len=15) :: "status", "wall_time", &
        "wall_time_min", "injected", "error_energy", "error_u", "ledger_drift", "steps", "rhs_evaluations", "max_abs_u"]

    !> The reference solution of one amplitude: the fine run's records at every level j h, j = 0..M.
    type :: reference_data
        !> Level spacing h (reference_dt / 2).
        real(wp) :: h = 0.0_wp
        !> Injected energy at t = j h.
        real(wp), allocatable :: injected(:)
        !> u at the probe at t = j h.
        real(wp), allocatable :: u(:)
        !> Injected energy at T.
        real(wp) :: injected_final = 0.0_wp
        !> Estimated relative error of the injected energy (|coarse - fine| / |fine| at T).
        real(wp) :: error_energy = 0.0_wp
        !> Estimated error of u at the probe (max |coarse - fine| over the last drive period).
        real(wp) :: error_u = 0.0_wp
        !> max |u_ref| at the probe over the last drive period.
        real(wp) :: u_scale = 0.0_wp
        !> Wall time of the fine reference run (s).
        real(wp) :: wall_time = 0.0_wp
    end type reference_data

    !> The runs of the scene: one task per (amplitude, method, dt), dt fastest.
    type, extends(task_list) :: workprec_tasks
        !> Base run (probe, ledger and detector already set for the scene).
        type(run_config) :: base
        !> Methods, time steps, smallest dt per method, amplitudes.
        integer, allocatable :: methods(:)
        real(wp), allocatable :: dts(:), dt_smallest(:), amplitudes(:)
        !> Timed repetitions per run.
        integer :: repeats = 1
        !> Length of the window at the end of the run where u is compared (one drive period).
        real(wp) :: window = 0.0_wp
        !> The scene's reference_dt (the kept reference runs at half of it).
        real(wp) :: reference_dt = 0.0_wp
        !> One reference per amplitude.
        type(reference_data), allocatable :: refs(:)
    contains
        procedure :: run => run_workprec_task
    end type workprec_tasks

    !> The scene `work_precision`: timed runs per (method, dt) against a reference.
    type, extends(scene_type), public :: workprec_scene
    contains
        !> Run it and write its output (`run_work_precision`).
        procedure :: run => workprec_scene_run
    end type workprec_scene

contains

    !> The default method list: every integrator.
    pure function default_methods() result(methods)
        integer, allocatable :: methods(:)

        methods = [method_newton, method_linearized, method_rk4, method_rk8, method_avf4, method_avf8]
    end function default_methods

    !> Default time steps: ramp_time = 50 and T = 200 are multiples of each (the ramp's kink on a step boundary).
    pure function default_workprec_dts() result(dts)
        real(wp), allocatable :: dts(:)

        dts = [0.4_wp, 0.3125_wp, 0.25_wp, 0.2_wp, 0.125_wp, 0.1_wp, 0.0625_wp, 0.05_wp, 0.025_wp, 0.0125_wp, &
               0.00625_wp, 0.003125_wp]
    end function default_workprec_dts

    !> Right-hand-side evaluations (N-sine kernels) of one step: 1 for the leapfrog schemes, the stages of an RK.
    pure function method_stages(method) result(stages)
        !> Method identifier.
        integer, intent(in) :: method
        integer :: stages

        select case (method)
        case (method_rk4)
            stages = 4
        case (method_rk8)
            stages = rk8_stages
        case default
            stages = 1
        end select
    end function method_stages

    !> Run the scene `work_precision` described by `cfg` and write `cfg%output%file`.
    subroutine run_work_precision(cfg, error, inv)
        !> Validated input (scene kind 'work_precision').
        type(input_config), intent(in) :: cfg
        !> Error, allocated on failure (bad scene keys, a failed reference run, output not writable).
        type(error_type), allocatable, intent(out) :: error
        !> How the engine is invoked (a slice, a merge: `supratrans_invocation`); default: the whole scene.
        type(invocation_type), intent(in), optional :: inv
        type(invocation_type) :: how
        type(workprec_tasks) :: tasks
        real(wp), allocatable :: results(:, :)
        logical, allocatable :: done(:)
        character(len=:), allocatable :: journal
        real(wp) :: t_sine, t_division, t_tridiag
        integer :: ntask

        if (present(inv)) how = inv
        call setup_tasks(cfg, tasks, error)
        if (allocated(error)) return
        call progress(cfg, "work_precision: reference solutions (rk8 at dt = " // real_str(cfg%scene%reference_dt) &
                      // " and " // real_str(0.5_wp*cfg%scene%reference_dt) // ")")
        call compute_references(tasks, error)
        if (allocated(error)) return

        ntask = size(tasks%amplitudes)*size(tasks%methods)*size(tasks%dts)
        journal = trim(cfg%output%file) // ".journal"
        call run_tasks(tasks, ntask, value_names, journal, input_fingerprint(cfg), "timed runs (one at a time)", &
                       cfg%output%quiet, results, done, error, cfg, how)
        if (allocated(error) .or. engine_only(how)) return

        call measure_step_kernels(tasks%base%chain%n, maxval(tasks%amplitudes), t_sine, t_division, t_tridiag)
        call write_work_precision(cfg, tasks, results, t_sine, t_division, t_tridiag, error, inv=how)
        if (allocated(error)) return
        call remove_file(journal)
    end subroutine run_work_precision

    !> Check the scene keys and fill the task list (base run, lists with their defaults).
    subroutine setup_tasks(cfg, tasks, error)
        type(input_config), intent(in) :: cfg
        type(workprec_tasks), intent(out) :: tasks
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: where
        integer :: i, probe

        where = "configuration"
        if (allocated(cfg%source)) where = cfg%source
        tasks%methods = default_methods()
        if (allocated(cfg%scene%methods)) then
            if (size(cfg%scene%methods) > 0) tasks%methods = cfg%scene%methods
        end if
        tasks%dts = default_workprec_dts()
        if (allocated(cfg%scene%dts)) then
            if (size(cfg%scene%dts) > 0) tasks%dts = cfg%scene%dts
        end if
        allocate (tasks%dt_smallest(size(tasks%methods)), source=0.0_wp)
        if (allocated(cfg%scene%dt_smallest)) then
            if (size(cfg%scene%dt_smallest) /= size(tasks%methods)) then
                call fatal_error(error, where // ": &scene: dt_smallest needs one value per method (" &
                                 // int_str(size(tasks%methods)) // "), got " // int_str(size(cfg%scene%dt_smallest)), &
                                 err_input)
                return
            end if
            tasks%dt_smallest = cfg%scene%dt_smallest
        end if
        tasks%amplitudes = [cfg%run%drive%amplitude]
        if (allocated(cfg%scene%amplitudes)) then
            if (size(cfg%scene%amplitudes) > 0) tasks%amplitudes = cfg%scene%amplitudes
        end if
        do i = 1, size(tasks%dts)
            if (.not. (tasks%dts(i) > 0.0_wp) .or. tasks%dts(i) > 0.5_wp*cfg%run%numerics%t_final) then
                call fatal_error(error, where // ": &scene: dts(" // int_str(i) // ") = " // real_str(tasks%dts(i)) &
                                 // ": need 0 < dt <= t_final/2", err_input)
                return
            end if
        end do
        if (any(.not. (tasks%amplitudes > 0.0_wp))) then
            call fatal_error(error, where // ": &scene: amplitudes must be > 0", err_input)
            return
        end if
        if (cfg%scene%repeats < 1) then
            call fatal_error(error, where // ": &scene: repeats = " // int_str(cfg%scene%repeats) // ": must be >= 1", &
                             err_input)
            return
        end if
        if (.not. (cfg%scene%reference_dt > 0.0_wp) .or. cfg%scene%reference_dt > 0.5_wp*cfg%run%numerics%t_final) then
            call fatal_error(error, where // ": &scene: reference_dt = " // real_str(cfg%scene%reference_dt) &
                             // ": need 0 < reference_dt <= t_final/2", err_input)
            return
        end if
        tasks%repeats = cfg%scene%repeats
        tasks%reference_dt = cfg%scene%reference_dt

        ! the base run: one probe, every level sampled, the ledger closed at the start and the end only
        tasks%base = cfg%run
        probe = 60
        if (allocated(cfg%run%record%probes)) then
            if (size(cfg%run%record%probes) > 0) probe = cfg%run%record%probes(1)
        end if
        probe = max(1, min(probe, cfg%run%chain%n))
        tasks%base%record%probes = [probe]
        tasks%base%record%probe_every = 1
        tasks%base%detect%stop_when_decided = .false.
        tasks%window = 2.0_wp*pi/cfg%run%drive%omega
    end subroutine setup_tasks

    !> The reference of each amplitude: rk8 at reference_dt/2 (kept) and reference_dt (its error estimate), all
    !> runs in parallel.
    subroutine compute_references(tasks, error)
        type(workprec_tasks), intent(inout) :: tasks
        type(error_type), allocatable, intent(out) :: error
        type(run_result), allocatable :: res(:)
        type(run_config) :: run
        integer :: namp, i, ia, m, j, nfail
        real(wp) :: h, t_final, t
        character(len=:), allocatable :: message

        namp = size(tasks%amplitudes)
        allocate (res(2*namp), tasks%refs(namp))
        t_final = tasks%base%numerics%t_final
        !$omp parallel do schedule(dynamic, 1) default(shared) private(i, run)
        do i = 1, 2*namp
            run = tasks%base
            run%drive%amplitude = tasks%amplitudes((i + 1)/2)
            run%numerics%method = method_rk8
            run%numerics%dt = reference_step(tasks, mod(i - 1, 2) == 0)
            run%record%ledger_every = 1
            call simulate(run, res(i))
        end do
        !$omp end parallel do

        nfail = 0
        message = ""
        do i = 1, 2*namp
            if (res(i)%status /= run_ok) then
                nfail = nfail + 1
                message = "reference run (rk8, A = " // real_str(tasks%amplitudes((i + 1)/2)) // ") ended: " &
                          // status_name(res(i)%status) // " " // res(i)%reason
            end if
        end do
        if (nfail > 0) then
            call fatal_error(error, "work_precision: " // message, err_runtime)
            return
        end if

        do ia = 1, namp
            associate (fine => res(2*ia - 1), coarse => res(2*ia), ref => tasks%refs(ia))
                h = reference_step(tasks, .true.)
                m = int(fine%steps)
                ref%h = h
                ref%injected = fine%ledger_series(1:m + 1, 2)
                ref%u = fine%probe_u(1:m + 1, 1)
                ref%injected_final = fine%ledger%injected
                ref%wall_time = fine%wall_time
                ref%error_energy = abs(coarse%ledger%injected - fine%ledger%injected)/abs(fine%ledger%injected)
                ref%error_u = 0.0_wp
                ref%u_scale = 0.0_wp
                do j = 0, int(coarse%steps)
                    t = real(j, wp)*2.0_wp*h
                    if (t < real(m, wp)*h - tasks%window - 1.0e-9_wp) cycle
                    ref%error_u = max(ref%error_u, abs(coarse%probe_u(j + 1, 1) - fine%probe_u(2*j + 1, 1)))
                end do
                do j = 0, m
                    if (real(j, wp)*h < real(m, wp)*h - tasks%window - 1.0e-9_wp) cycle
                    ref%u_scale = max(ref%u_scale, abs(fine%probe_u(j + 1, 1)))
                end do
            end associate
        end do
    end subroutine compute_references

    !> Step of the reference runs: reference_dt / 2 (fine, kept) or reference_dt (coarse, error estimate).
    pure function reference_step(tasks, fine) result(h)
        type(workprec_tasks), intent(in) :: tasks
        logical, intent(in) :: fine
        real(wp) :: h

        h = tasks%reference_dt
        if (fine) h = 0.5_wp*h
    end function reference_step

    !> Task `index` = (dt, method, amplitude), dt fastest: run it `repeats` times and measure it.
    subroutine run_workprec_task(self, index, values)
        !> The scene's tasks.
        class(workprec_tasks), intent(in) :: self
        !> Task index.
        integer, intent(in) :: index
        !> status, median wall time, min wall time, injected, error_energy, error_u, ledger_drift, steps, rhs, max|u|.
        real(wp), intent(out) :: values(:)
        type(run_config) :: run
        type(run_result) :: res
        real(wp), allocatable :: times(:)
        real(wp) :: nan, dt, t_lo, t_hi, e_ref, err_u, drift
        integer :: idt, im, ia, ndt, nm, r, i, status

        ndt = size(self%dts)
        nm = size(self%methods)
        idt = mod(index - 1, ndt) + 1
        im = mod((index - 1)/ndt, nm) + 1
        ia = (index - 1)/(ndt*nm) + 1
        nan = ieee_value(1.0_wp, ieee_quiet_nan)
        values = nan
        dt = self%dts(idt)
        if (dt < self%dt_smallest(im)*(1.0_wp - 1.0e-12_wp)) then
            values(w_status) = real(status_not_run, wp)
            return
        end if

        run = self%base
        run%drive%amplitude = self%amplitudes(ia)
        run%numerics%method = self%methods(im)
        run%numerics%dt = dt
        run%record%ledger_every = nint(run%numerics%t_final/dt) + 1
        allocate (times(self%repeats))
        !$omp critical (supratrans_workprec_timing)
        do r = 1, self%repeats
            call simulate(run, res)
            times(r) = res%wall_time
            if (res%status /= run_ok) exit
        end do
        !$omp end critical (supratrans_workprec_timing)

        status = res%status
        drift = abs(res%ledger%residual)/max(res%ledger%energy_scale, tiny(1.0_wp))
        if (status == run_ok .and. .not. (drift <= drift_limit)) status = run_diverged
        values(w_status) = real(status, wp)
        values(w_steps) = real(res%steps, wp)
        values(w_rhs_evaluations) = real(res%tridiagonal_solves + res%rhs_evaluations, wp)   ! newton: = its Newton iterations
        values(w_max_abs_u) = res%max_abs_u
        if (status /= run_ok) return

        values(w_wall_time) = median(times)
        values(w_wall_time_min) = minval(times)
        values(w_injected) = res%ledger%injected
        ! the reference's energy over the window the method's ledger covers
        if (run%numerics%method == method_newton .or. run%numerics%method == method_linearized) then
            t_lo = 0.5_wp*dt
            t_hi = res%t_end - 0.5_wp*dt
        else
            t_lo = 0.0_wp
            t_hi = res%t_end
        end if
        associate (ref => self%refs(ia))
            e_ref = interpolate(ref%injected, ref%h, t_hi) - interpolate(ref%injected, ref%h, t_lo)
            values(w_error_energy) = abs(res%ledger%injected - e_ref)/abs(ref%injected_final)
            err_u = 0.0_wp
            do i = 1, res%n_probe_samples
                if (res%probe_time(i) < res%t_end - self%window - 1.0e-9_wp) cycle
                err_u = max(err_u, abs(res%probe_u(i, 1) - interpolate(ref%u, ref%h, res%probe_time(i))))
            end do
            values(w_error_u) = err_u
        end associate
        values(w_ledger_drift) = drift
    end subroutine run_workprec_task

    !> Value at time t of a series sampled at t_j = j h, j = 0..M (`samples(1)` is t = 0): the sample itself on a
    !> level, else the 8-point Lagrange interpolant on the levels around t (one-sided near the ends).
    pure function interpolate(samples, h, t) result(v)
        !> Samples at t_j = j h.
        real(wp), intent(in) :: samples(:)
        !> Spacing.
        real(wp), intent(in) :: h
        !> Time, 0 <= t <= (size(samples) - 1) h.
        real(wp), intent(in) :: t
        real(wp) :: v
        real(wp) :: x, w
        integer :: m, j, j0, i, k

        m = size(samples) - 1
        x = t/h
        j = nint(x)
        if (abs(x - real(j, wp)) <= 1.0e-9_wp*max(1.0_wp, abs(x))) then
            v = samples(max(0, min(j, m)) + 1)
            return
        end if
        j0 = max(0, min(floor(x) - 3, m - 7))
        v = 0.0_wp
        do i = 0, min(7, m)
            w = 1.0_wp
            do k = 0, min(7, m)
                if (k /= i) w = w*(x - real(j0 + k, wp))/real(i - k, wp)
            end do
            v = v + w*samples(j0 + i + 1)
        end do
    end function interpolate

    !> Median of a small array.
    pure function median(x) result(med)
        !> Values.
        real(wp), intent(in) :: x(:)
        real(wp) :: med
        real(wp) :: y(size(x)), t
        integer :: i, j

        y = x
        do i = 2, size(y)
            t = y(i)
            j = i - 1
            do while (j >= 1)
                if (y(j) <= t) exit
                y(j + 1) = y(j)
                j = j - 1
            end do
            y(j + 1) = t
        end do
        med = y((size(y) + 1)/2)
        if (mod(size(y), 2) == 0) med = 0.5_wp*(y(size(y)/2) + y(size(y)/2 + 1))
    end function median

    !> Observed order over the asymptotic range: the least-squares slope of log(error) against log(dt) over the
    !> smallest time steps, taken in increasing dt from the smallest: errors at or below `floor` (the reference's
    !> own error, roundoff) are skipped, the first error above 1e-2 (pre-asymptotic) ends the range, and at most
    !> `order_fit_points` points are used. NaN with fewer than two points.
    pure function fitted_order(dts, errors, floor) result(order)
        !> Time steps (NaN where not run).
        real(wp), intent(in) :: dts(:)
        !> Errors (NaN where not measured).
        real(wp), intent(in) :: errors(:)
        !> Errors at or below this are not used.
        real(wp), intent(in) :: floor
        real(wp) :: order
        real(wp) :: sx, sy, sxx, sxy, x, y, dt_min
        logical :: visited(size(dts))
        integer :: i, j, np

        np = 0
        sx = 0.0_wp
        sy = 0.0_wp
        sxx = 0.0_wp
        sxy = 0.0_wp
        visited = ieee_is_nan(dts) .or. ieee_is_nan(errors)
        do
            ! the smallest time step not visited yet
            i = 0
            dt_min = huge(1.0_wp)
            do j = 1, size(dts)
                if (.not. visited(j) .and. dts(j) < dt_min) then
                    dt_min = dts(j)
                    i = j
                end if
            end do
            if (i == 0) exit
            visited(i) = .true.
            if (.not. (errors(i) > floor)) cycle
            if (errors(i) > order_fit_ceiling) exit
            x = log(dts(i))
            y = log(errors(i))
            np = np + 1
            sx = sx + x
            sy = sy + y
            sxx = sxx + x*x
            sxy = sxy + x*y
            if (np == order_fit_points) exit
        end do
        order = ieee_value(1.0_wp, ieee_quiet_nan)
        if (np < 2) return
        if (real(np, wp)*sxx - sx*sx <= 0.0_wp) return
        order = (real(np, wp)*sxy - sx*sy)/(real(np, wp)*sxx - sx*sx)
    end function fitted_order

    !> Time the kernels a step cannot avoid, on a chain of n sites (per call, seconds, best of 7 trials):
    !> n sines of values spread over [-amplitude, amplitude]; n divisions; one tridiagonal solve (`dgtsv`, with
    !> the copies of the matrix the Newton step makes).
    subroutine measure_step_kernels(n, amplitude, t_sine, t_division, t_tridiag)
        !> Number of sites N.
        integer, intent(in) :: n
        !> Spread of the sine arguments.
        real(wp), intent(in) :: amplitude
        !> Seconds for n sines, n divisions, one solve.
        real(wp), intent(out) :: t_sine, t_division, t_tridiag
        real(wp), allocatable :: u(:), f(:), b(:), dl(:), dd(:), du(:), rhs(:)
        integer :: i, trial, rep, reps, info
        integer(i8) :: c0, c1, rate
        real(wp) :: check, t

        allocate (u(n), f(n), b(n), dl(max(n - 1, 1)), dd(n), du(max(n - 1, 1)), rhs(n))
        do i = 1, n
            u(i) = amplitude*cos(real(i, wp)*2.399963229728653_wp)    ! golden-angle spread over [-A, A]
            b(i) = 400.0_wp + real(mod(i, 7), wp)
        end do
        reps = max(1, 2000000/max(n, 1))
        check = 0.0_wp
        t_sine = huge(1.0_wp)
        t_division = huge(1.0_wp)
        t_tridiag = huge(1.0_wp)
        do trial = 1, 7
            call system_clock(c0, rate)
            do rep = 1, reps
                u(1) = u(1) + 1.0e-15_wp
                f = sin(u)
                check = check + f(n)
            end do
            call system_clock(c1)
            t = real(c1 - c0, wp)/real(rate, wp)/real(reps, wp)
            t_sine = min(t_sine, t)
            call system_clock(c0)
            do rep = 1, reps
                u(1) = u(1) + 1.0e-15_wp
                f = u/b
                check = check + f(n)
            end do
            call system_clock(c1)
            t = real(c1 - c0, wp)/real(rate, wp)/real(reps, wp)
            t_division = min(t_division, t)
            call system_clock(c0)
            do rep = 1, reps/4 + 1
                dd = b
                dl = -1.0_wp
                du = -1.0_wp
                rhs = u
                call solve_tridiag(dl, dd, du, rhs, info)
                check = check + rhs(n)
            end do
            call system_clock(c1)
            t = real(c1 - c0, wp)/real(rate, wp)/real(reps/4 + 1, wp)
            t_tridiag = min(t_tridiag, t)
        end do
        if (ieee_is_nan(check)) t_sine = -1.0_wp      ! keeps the kernels from being optimised away
    end subroutine measure_step_kernels

    !> Write the scene's HDF5 file.
    subroutine write_work_precision(cfg, tasks, results, t_sine, t_division, t_tridiag, error, inv)
        type(input_config), intent(in) :: cfg
        type(workprec_tasks), intent(in) :: tasks
        real(wp), intent(in) :: results(:, :)
        real(wp), intent(in) :: t_sine, t_division, t_tridiag
        type(error_type), allocatable, intent(out) :: error
        !> How the engine was invoked (a merge records its parts).
        type(invocation_type), intent(in), optional :: inv
        type(h5_file) :: file
        integer :: ndt, nm, namp, ia, im, idt, itask
        real(wp), allocatable :: grid(:, :, :, :), dt(:, :), steps(:, :), order_e(:, :), order_u(:, :), lb(:, :, :)
        real(wp), allocatable :: ratio(:, :, :)
        real(wp) :: nan, per_step
        character(len=16), allocatable :: names(:)
        character(len=*), parameter :: dims3 = "amplitude, method, dt"

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
        call h5_create_group(file, "/scene", "Controls of the work-precision scene")
        call h5_write_attr(file, "/scene", "repeats", tasks%repeats)
        call h5_write_attr(file, "/scene", "timing", "median of the run's own wall " &
            // "clock over `repeats` runs; the runs are timed one at a time (a critical section)")
        call h5_write_attr(file, "/scene", "probe_site", tasks%base%record%probes(1))
        call h5_write_attr(file, "/scene", "error_window", tasks%window)
        call h5_write_attr(file, "/scene", "drift_limit", drift_limit)
        call h5_write_attr(file, "/scene", "dt_smallest", tasks%dt_smallest)
        call h5_write_attr(file, "/scene", "status_codes", &
            "-1 not_run, 0 ok, 1 diverged (blow-up, or ledger residual above drift_limit of the energy scale), " &
            // "2 newton_failed, 3 solver_failed")
        call h5_write(file, "/methods", names, "1", "Integrators compared", &
                                                  dims="method")
        call h5_write(file, "/amplitude", tasks%amplitudes, "rad", &
                                                  "Drive amplitudes A", dims="amplitude")
        call h5_write(file, "/dt", dt, "time", &
                                                  "Time step of each run (NaN: not run for this method)", &
                                                  dims="method, dt")
        call h5_write(file, "/steps", steps, "1", "Steps M = nint(T/dt) of each run", dims="method, dt")
        call h5_write(file, "/status", nint(grid(:, :, :, w_status)), "1", &
            "Outcome: -1 not run, 0 ok, 1 diverged, 2 newton_failed, 3 solver_failed (measured values are NaN " &
            // "unless 0)", dims=dims3)
        call h5_write(file, "/wall_time", grid(:, :, :, w_wall_time), "s", &
            "Median wall time of the run over `repeats` timed runs (one at a time)", dims=dims3)
        call h5_write(file, "/wall_time_min", grid(:, :, :, w_wall_time_min), "s", &
            "Shortest wall time of the run over `repeats` timed runs", dims=dims3)
        call h5_write(file, "/injected", grid(:, :, :, w_injected), "energy", &
            "Injected energy of the run (newton, linearized: over [dt/2, T - dt/2]; RK: over [0, T])", &
            dims=dims3)
        call h5_write(file, "/error_energy", grid(:, :, :, w_error_energy), "1", &
            "|injected - reference's injected over the same window| / reference's injected at T", dims=dims3)
        call h5_write(file, "/error_u", grid(:, :, :, w_error_u), "rad", &
            "max |u - u_ref| at the probe over the run's samples in the last drive period", dims=dims3)
        call h5_write(file, "/ledger_drift", grid(:, :, :, w_ledger_drift), "1", &
            "|E(T) - E(0) - (injected - dissipated)| / energy scale at the end of the run", dims=dims3)
        call h5_write(file, "/rhs_evaluations", grid(:, :, :, w_rhs_evaluations), "1", &
            "Newton iterations (newton), tridiagonal solves (linearized), right-hand sides (RK) of the run", &
            dims=dims3)
        call h5_write(file, "/max_abs_u", grid(:, :, :, w_max_abs_u), "rad", &
            "Largest |u_n| of the run (also for runs that diverged)", dims=dims3)
        call h5_write(file, "/order_energy", order_e, "1", &
            "Fitted order: least-squares slope of log(error_energy) vs log(dt) over the (at most 4) smallest dt, " &
            // "skipping errors at the floor (the reference's error estimate, at least 1e-13) and stopping at the " &
            // "first error above 1e-2; NaN with fewer than 2 points", dims="amplitude, method")
        call h5_write(file, "/order_u", order_u, "1", &
            "Fitted order of error_u / reference u scale, same rule", dims="amplitude, method")
        ! reference
        call h5_create_group(file, "/reference", "Reference solutions, one per amplitude")
        call h5_write_attr(file, "/reference", "method", "rk8")
        call h5_write_attr(file, "/reference", "dt", 0.5_wp*tasks%reference_dt)
        call h5_write_attr(file, "/reference", "check_dt", tasks%reference_dt)
        call h5_write(file, "/reference/injected", ref_column(1), "energy", &
            "Reference injected energy over [0, T] (rk8 at reference dt)", dims="amplitude")
        call h5_write(file, "/reference/error_energy", ref_column(2), "1", &
            "Estimated relative error of the reference injected energy: |E(check_dt) - E(dt)| / E(dt) (an upper " &
            // "bound: the reference's own error is about 2^-8 of it)", dims="amplitude")
        call h5_write(file, "/reference/error_u", ref_column(3), "rad", &
            "Estimated error of the reference u at the probe (max over the last drive period, same rule)", &
            dims="amplitude")
        call h5_write(file, "/reference/u_scale", ref_column(4), "rad", &
            "max |u_ref| at the probe over the last drive period", dims="amplitude")
        call h5_write(file, "/reference/u_final", ref_column(5), "rad", &
            "Reference u at the probe at T", dims="amplitude")
        call h5_write(file, "/reference/wall_time", ref_column(6), "s", &
            "Wall time of the reference run (run in parallel with the others)", dims="amplitude")
        ! lower bound
        call h5_create_group(file, "/lower_bound", "Work a step cannot avoid, timed alone: " &
            // "N sines (the potential) and, for the implicit schemes, one tridiagonal solve (N divisions when " &
            // "beta = 0); N sines per stage for Runge-Kutta")
        call h5_write(file, "/lower_bound/sine_time", t_sine, "s", &
            "N sines of values spread over [-A, A], N = chain sites (best of 7 trials)")
        call h5_write(file, "/lower_bound/division_time", t_division, "s", &
            "N divisions (the solve when beta = 0)")
        call h5_write(file, "/lower_bound/tridiagonal_time", t_tridiag, "s", &
            "One LAPACK dgtsv of size N with the matrix copies the Newton step makes (the solve when beta > 0)")
        call h5_write(file, "/lower_bound/run_time", lb, "s", &
            "Lower bound of each run: steps x (N sines per stage [+ the solve of the implicit schemes])", &
            dims=dims3)
        call h5_write(file, "/lower_bound/ratio", ratio, "1", &
            "wall_time / lower_bound run_time", dims=dims3)
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
        type(input_config), intent(in) :: cfg
        character(len=*), intent(in) :: line

        if (.not. cfg%output%quiet) write (error_unit, "(a)") printable(line)
    end subroutine progress

    !> Run the scene (`run_work_precision`).
    subroutine workprec_scene_run(self, cfg, error, inv)
        !> The scene.
        class(workprec_scene), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> How the engine is invoked (a slice, a merge: `supratrans_invocation`); default: the whole scene.
        type(invocation_type), intent(in), optional :: inv

        call run_work_precision(cfg, error, inv=inv)
    end subroutine workprec_scene_run

end module supratrans_scene_workprec
