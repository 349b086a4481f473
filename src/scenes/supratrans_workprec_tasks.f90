!> The runs of the scene `work_precision` (`supratrans_scene_workprec`): its task list, one task per (amplitude,
!> method, dt) run `repeats` times one at a time and measured against the reference of its amplitude (rk8 at
!> reference_dt/2, with reference_dt's run for its error estimate), and what a task's record holds (`w_*`).
module supratrans_workprec_tasks
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_nan
    use supratrans_kinds, only: wp, pi
    use supratrans_error, only: error_type, fatal_error, err_input, err_runtime, err_interrupted
    use supratrans_system, only: stop_signal
    use supratrans_strings, only: int_str, real_str
    use supratrans_config, only: input_config, run_config, method_newton, method_linearized, method_rk4, method_rk8, &
                                 method_avf4, method_avf8
    use supratrans_simulate, only: simulate
    use supratrans_result, only: run_result, run_ok, run_diverged, status_name
    use supratrans_status, only: status_not_run
    use supratrans_tasks, only: task_list
    use supratrans_workprec_measure, only: median, interpolate
    implicit none
    private

    public :: default_methods, default_workprec_dts, setup_tasks, compute_references

    !> A run whose final ledger residual exceeds this fraction of its energy scale is declared diverged.
    real(wp), parameter, public :: drift_limit = 0.5_wp

    !> Positions of a task's values: status, median and minimum wall time, injected energy, relative error of the
    !> injected energy, error in u at the probe, ledger drift, steps, right-hand sides / solves, max |u|.
    integer, parameter, public :: w_status = 1, w_wall_time = 2, w_wall_time_min = 3, w_injected = 4, &
                                  w_error_energy = 5, w_error_u = 6, w_ledger_drift = 7, w_steps = 8, &
                                  w_rhs_evaluations = 9, w_max_abs_u = 10
    !> Number of values per task.
    integer, parameter, public :: nvalues = 10
    !> Names of a task's values in the order of their positions (the journal stores them by these names).
    character(len=*), parameter, public :: value_names(nvalues) = [character(len=15) :: "status", "wall_time", &
        "wall_time_min", "injected", "error_energy", "error_u", "ledger_drift", "steps", "rhs_evaluations", "max_abs_u"]

    !> The reference solution of one amplitude: the fine run's records at every level j h, j = 0..M.
    type, public :: reference_data
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
    type, extends(task_list), public :: workprec_tasks
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
        !> Run one task `repeats` times (one at a time) and measure it against its amplitude's reference.
        procedure :: run => run_workprec_task
        !> Whether a task's values are its result (not a task a stop signal cut short).
        procedure :: finished => workprec_finished
    end type workprec_tasks

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

    !> Check the scene keys and fill the task list (base run, lists with their defaults).
    subroutine setup_tasks(cfg, tasks, error)
        !> Validated input (scene kind 'work_precision').
        type(input_config), intent(in) :: cfg
        !> The task list (references not computed yet: `compute_references`).
        type(workprec_tasks), intent(out) :: tasks
        !> Error, allocated when a scene key is not valid.
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
        !> The task list (from `setup_tasks`): its `refs` are filled.
        type(workprec_tasks), intent(inout) :: tasks
        !> Error, allocated when a reference run fails.
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
            call simulate(run, res(i), interruptible=.true.)
        end do
        !$omp end parallel do
        if (any(res%interrupted)) then
            call fatal_error(error, "work_precision: stopped by signal " // int_str(max(stop_signal(), 0)) &
                             // " during the reference runs, before any timed run: nothing journaled; run the same " &
                             // "command again", err_interrupted)
            return
        end if

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
        !> The task list.
        type(workprec_tasks), intent(in) :: tasks
        !> The fine run (kept) rather than the coarse one.
        logical, intent(in) :: fine
        real(wp) :: h

        h = tasks%reference_dt
        if (fine) h = 0.5_wp*h
    end function reference_step

    !> Whether a task's values are its result: a task stopped by a signal returns a NaN status (every task that ran,
    !> or was skipped by `dt_smallest`, has a status), is not journaled, and runs again on resume.
    function workprec_finished(self, values) result(yes)
        !> The task list.
        class(workprec_tasks), intent(in) :: self
        !> The task's values.
        real(wp), intent(in) :: values(:)
        logical :: yes

        yes = .not. ieee_is_nan(values(w_status))
    end function workprec_finished

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
        logical :: stopped

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
        stopped = .false.
        !$omp critical (supratrans_workprec_timing)
        do r = 1, self%repeats
            ! a stop signal ends the repeats, and the run in progress within a step (`interruptible`): the task is
            ! then no result (`workprec_finished`) and runs again on resume (it used to ignore SIGTERM for minutes)
            if (stop_signal() /= 0) then
                stopped = .true.
                exit
            end if
            call simulate(run, res, interruptible=.true.)
            if (res%interrupted) then
                stopped = .true.
                exit
            end if
            times(r) = res%wall_time
            if (res%status /= run_ok) exit
        end do
        !$omp end critical (supratrans_workprec_timing)
        if (stopped) return

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

end module supratrans_workprec_tasks
