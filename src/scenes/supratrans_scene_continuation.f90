!> Scene `continuation`: the supratransmission threshold as a property of the model, the fold (saddle-node) of the
!> branch of driven time-periodic states of the discrete scheme, over the driving frequency, one curve per potential
!> and value of the varied parameter (the layout of the bifurcation scene, so that a fold line lies over a diagram).
!>
!> For each curve and each frequency Omega_i = omega_min + i omega_step <= omega_max, one task continues the periodic
!> states of the &numerics method driven at full amplitude A (no ramp) with period 2 pi / Omega, from the chain at
!> rest at A = 0, in pseudo-arclength up the branch, through its fold and `beyond_fold` points along the unstable
!> branch after it (`supratrans_continuation` on the one-period map of `supratrans_period_map`, dt = period / M, M
!> = ceiling(period / dt)). Every point's Floquet multipliers (the eigenvalues of the discrete monodromy matrix) say
!> whether it is stable (no multiplier of modulus above 1 + crossing_tol); the first loss of stability is located
!> with its type. The model's threshold is the smaller of the fold and that loss, and the file says which it is.
!> With `fold_convergence` the fold is located again at dt/2 and on a chain twice as long (N0 and N shifted by N,
!> the same absorber), and the record gives the Richardson value, an error estimate and the converged digits.
!>
!> Frequencies outside the curve's band gap are not computed (status -2) unless `allow_outside_gap`, when they are
!> computed and flagged (`/outside_gap`): no fold is expected there. The tasks run on OpenMP threads through
!> `supratrans_tasks` (journal, resume, `--slice`), driven by the scene driver of `supratrans_scene`, results stored
!> by task index: identical for any number of threads and slices.
module supratrans_scene_continuation
    use, intrinsic :: iso_fortran_env, only: error_unit
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_nan
    use supratrans_kinds, only: wp, i8, pi
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_invocation, only: invocation_type
    use supratrans_scene, only: scene_type, scene_budget, scene_tasks, wrong_tasks
    use supratrans_limits, only: axis_points, check_axis, limit_error, threads_text, sci
    use supratrans_config, only: input_config, run_config, scene_params, method_newton, method_linearized, method_rk4, &
                                 method_rk8, method_avf4, method_avf8, method_name
    use supratrans_curves, only: curve_count, curve_run, write_curves
    use supratrans_chain, only: threshold_as, band_gap_edge
    use supratrans_potential, only: potential_name
    use supratrans_status, only: status_outside_gap, status_not_run
    use supratrans_fold_record, only: fold_record, fold_fields, fold_to_values, fold_from_values, empty_fold_record, &
                                      branch_quantities, kept_multipliers, multiplier_samples, add_fold_cost
    use supratrans_fold_line, only: trace_fold, fold_status_codes, instability_type_codes, fold_found, &
                                    shortest_chain, chain_length_given, fate_codes, &
                                    transmission_status_codes
    use supratrans_tasks, only: task_list, run_work
    use supratrans_hdf5, only: h5_file, h5_create, h5_commit, h5_write, h5_write_attr, h5_create_group
    use supratrans_output, only: write_root, write_parameters
    use supratrans_strings, only: int_str, real_str, fixed1
    use supratrans_scene_bifurcation, only: bifurcation_omegas
    use supratrans_linear_stability, only: linear_stability_dt
    use supratrans_stepper_rk4, only: rk4_order
    use supratrans_stepper_rk8, only: rk8_order
    implicit none
    private

    !> The tasks of a continuation scene: task t = (curve - 1) nomega + iomega traces one branch to its fold.
    type, extends(task_list) :: continuation_tasks
        !> The validated input.
        type(input_config) :: cfg
        !> How the engine is invoked (slice, merge: `supratrans_invocation`).
        type(invocation_type) :: inv
        !> Run of each curve (chain, numerics; the drive's frequency and amplitude are set per task).
        type(run_config), allocatable :: runs(:)
        !> The frequencies.
        real(wp), allocatable :: omegas(:)
        !> Path of the partial output written by `snapshot`.
        character(len=:), allocatable :: partial_path
        !> The input gives no chain length (n, n0, sigma): each task uses the short chain of its Omega.
        logical :: short_chain = .false.
    contains
        !> Trace the branch of one task.
        procedure :: run => run_fold_task
        !> Write the partial output.
        procedure :: snapshot => write_snapshot
        !> Estimated cost of one task (a Jacobian of its one-period map).
        procedure :: cost => fold_task_cost
    end type continuation_tasks

    !> The scene `continuation`: the fold line of the periodic states over the frequency axis, per curve.
    type, extends(scene_type), public :: continuation_scene
    contains
        !> Its tasks: one branch traced to its fold per (curve, frequency).
        procedure :: make_tasks => continuation_make_tasks
        !> Its file (`write_continuation_file`).
        procedure :: write_output => continuation_write_output
        !> The folds found and the wall time.
        procedure :: summary => continuation_summary
        !> Its axes, tasks, work and memory against the limits.
        procedure :: check_limits => continuation_scene_limits
    end type continuation_scene

contains

    !> The continuations of the scene: the frequency axis (the bifurcation scene's) and each curve's run, driven at
    !> full amplitude from the start; refused for a method without a one-period map or a dt beyond its linear
    !> stability limit.
    subroutine continuation_make_tasks(self, cfg, tasks, error)
        !> The scene.
        class(continuation_scene), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Its tasks: a `continuation_tasks`, (curve - 1) nomega + iomega.
        type(scene_tasks), intent(inout) :: tasks
        !> Error, allocated when the axis is empty or the method or dt has no periodic state to continue.
        type(error_type), allocatable, intent(out) :: error
        type(continuation_tasks), allocatable :: list
        integer :: ncurve, nomega, ic

        allocate (list)
        list%cfg = cfg
        list%inv = tasks%inv
        list%omegas = bifurcation_omegas(cfg)  ! the bifurcation scene's axis, so fold lines lie over diagrams
        ncurve = curve_count(cfg)
        nomega = size(list%omegas)
        if (nomega < 1) then
            call fatal_error(error, cfg%source // ": &scene: the frequency axis omega_min .. omega_max is empty", err_input)
            return
        end if
        if (any(cfg%run%numerics%method == [method_avf4, method_avf8])) then   ! no period map (supratrans_period_map)
            call fatal_error(error, cfg%source // ": &numerics: method '" // method_name(cfg%run%numerics%method) &
                // "' has no one-period map: continue folds with 'newton', 'linearized', 'rk4' or 'rk8'", err_input)
            return
        end if
        allocate (list%runs(ncurve))
        do ic = 1, ncurve
            list%runs(ic) = curve_run(cfg, ic)
            list%runs(ic)%drive%ramp_time = 0.0_wp
            ! a periodic state needs a stable scheme: dt within the method's linear stability limit for the chain
            if (cfg%run%numerics%dt >= linear_stability_dt(list%runs(ic)%chain, cfg%run%numerics%method)) then
                call fatal_error(error, cfg%source // ": &numerics: dt = " // real_str(cfg%run%numerics%dt, 6) &
                    // " is beyond the linear stability limit " // real_str(linear_stability_dt(list%runs(ic)%chain, &
                    cfg%run%numerics%method), 6) // " of method '" // method_name(cfg%run%numerics%method) &
                    // "' for curve " // int_str(ic) // ": the scheme has no periodic state to continue", err_input)
                return
            end if
        end do
        list%partial_path = trim(cfg%output%file) // ".partial.h5"
        if (allocated(cfg%text)) list%short_chain = .not. chain_length_given(cfg%text)
        tasks%header = "supratrans: continuation from " // cfg%source // ": " // int_str(ncurve) // " curve(s) x " &
            // int_str(nomega) // " frequencies, method " // method_name(cfg%run%numerics%method) // ", N = " &
            // int_str(cfg%run%chain%n) // ", branches up to A = " // real_str(cfg%scene%amplitude_max, 6)
        tasks%count = ncurve*nomega
        tasks%fields = fold_fields(cfg%scene%continuation_points)
        tasks%label = "fold continuations"
        call move_alloc(list, tasks%list)
    end subroutine continuation_make_tasks

    !> Write the scene's file, complete, with the scene's wall time (`write_continuation_file`).
    subroutine continuation_write_output(self, cfg, tasks, error)
        !> The scene.
        class(continuation_scene), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> The tasks (a `continuation_tasks`), their records and the wall time.
        type(scene_tasks), intent(in) :: tasks
        !> Error, allocated on failure (the file is then not created).
        type(error_type), allocatable, intent(out) :: error

        select type (list => tasks%list)
        type is (continuation_tasks)
            call write_continuation_file(list, trim(cfg%output%file), tasks%results, tasks%done, .true., &
                                         tasks%elapsed, error)
        class default
            call wrong_tasks(error, "continuation_tasks")
        end select
    end subroutine continuation_write_output

    !> The folds found of the tasks, and the wall time.
    function continuation_summary(self, cfg, tasks) result(text)
        !> The scene.
        class(continuation_scene), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> The tasks' records and the wall time.
        type(scene_tasks), intent(in) :: tasks
        character(len=:), allocatable :: text
        type(fold_record) :: r
        integer :: i, found

        found = 0
        do i = 1, size(tasks%done)
            r = fold_from_values(tasks%results(:, i), cfg%scene%continuation_points)
            if (r%status == fold_found) found = found + 1
        end do
        text = "  " // int_str(found) // " of " // int_str(size(tasks%done)) // " folds found, " &
               // fixed1(tasks%elapsed) // " s"
    end function continuation_summary

    !> Trace the branch of task `index` to its fold (thread-safe: everything it changes is local).
    subroutine run_fold_task(self, index, values)
        !> The tasks.
        class(continuation_tasks), intent(in) :: self
        !> Task index: (curve - 1) nomega + iomega.
        integer, intent(in) :: index
        !> The task's `fold_record`, as values (`fold_to_values`).
        real(wp), intent(out) :: values(:)
        type(fold_record) :: r, check
        type(run_config) :: run, other
        type(scene_params) :: fold_alone
        integer :: p
        integer(i8) :: clock_start, clock_end, clock_rate

        call system_clock(clock_start, clock_rate)
        run = task_run(self, index)
        r = empty_fold_record(self%cfg%scene%continuation_points)
        if (run%drive%omega < band_gap_edge(run%chain)) r%threshold_as = threshold_as(run%chain, run%drive%omega)
        if (run%drive%omega >= band_gap_edge(run%chain) .and. .not. self%cfg%allow_outside_gap) then
            r%status = status_outside_gap
            values = fold_to_values(r)
            return
        end if

        call trace_fold(run, self%cfg%scene, r, .true.)
        if (self%cfg%scene%fold_convergence .and. r%status == fold_found) then
            ! the checks need the fold alone: no multipliers along the branch, no points past it, no fate
            fold_alone = self%cfg%scene
            fold_alone%floquet_every = 0
            fold_alone%beyond_fold = 0
            other = run
            other%numerics%dt = r%dt_used/2.0_wp
            check = empty_fold_record(self%cfg%scene%continuation_points)
            call trace_fold(other, fold_alone, check, .false., fate=.false.)
            r%fold_half_dt = check%fold_amplitude
            call add_fold_cost(r, check)
            other = run
            other%chain%n0 = run%chain%n0 + run%chain%n
            other%chain%n = 2*run%chain%n
            check = empty_fold_record(self%cfg%scene%continuation_points)
            call trace_fold(other, fold_alone, check, .false., fate=.false.)
            r%fold_long_chain = check%fold_amplitude
            call add_fold_cost(r, check)
            p = method_order(run%numerics%method)
            r%richardson = r%fold_half_dt + (r%fold_half_dt - r%fold_amplitude)/real(2**p - 1, wp)
            r%error_estimate = max(abs(r%fold_half_dt - r%fold_amplitude)/real(2**p - 1, wp), &
                                   abs(r%fold_long_chain - r%fold_amplitude))
            if (.not. ieee_is_nan(r%error_estimate)) then
                r%digits = real(min(15, max(0, floor(-log10(max(r%error_estimate, tiny(1.0_wp)) &
                                                              /abs(r%fold_amplitude))))), wp)
            end if
        end if
        call system_clock(clock_end)
        r%wall_time = real(clock_end - clock_start, wp)/real(clock_rate, wp)
        values = fold_to_values(r)
    end subroutine run_fold_task

    !> The run of task `index`: its curve's run at its frequency, on the short chain of that frequency when the input
    !> gives no chain length.
    pure function task_run(self, index) result(run)
        !> The tasks.
        class(continuation_tasks), intent(in) :: self
        !> Task index: (curve - 1) nomega + iomega.
        integer, intent(in) :: index
        type(run_config) :: run
        integer :: nomega

        nomega = size(self%omegas)
        run = self%runs((index - 1)/nomega + 1)
        run%drive%omega = self%omegas(mod(index - 1, nomega) + 1)
        if (self%short_chain) call shortest_chain(run%chain, run%drive%omega, run%numerics%dt)
    end function task_run

    !> Estimated cost of task `index`: what one Jacobian of its one-period map costs, 2N tangent columns of N sites
    !> through the M = period / dt steps of a period (`run_work` of one period, times 2N), with the chain the task
    !> runs (the short chain of its Omega when the input gives none); 0 for a frequency outside the gap that is not
    !> computed. A branch takes some tens of Jacobians wherever it is, so their cost sets the ratios: at Omega = 0.05
    !> the tasks cost about 40 times those at 0.5 (a longer chain, ten times the steps). The engine runs the tasks
    !> largest first and deals slices by it.
    pure function fold_task_cost(self, index) result(cost)
        !> The tasks.
        class(continuation_tasks), intent(in) :: self
        !> Task index: (curve - 1) nomega + iomega.
        integer, intent(in) :: index
        real(wp) :: cost
        type(run_config) :: run

        run = task_run(self, index)
        cost = 0.0_wp
        if (run%drive%omega >= band_gap_edge(run%chain) .and. .not. self%cfg%allow_outside_gap) return
        run%numerics%t_final = 2.0_wp*pi/run%drive%omega
        cost = 2.0_wp*real(run%chain%n, wp)*run_work(run)
    end function fold_task_cost

    !> Order of accuracy in dt of a method (2 for the paper's schemes).
    pure function method_order(method) result(p)
        !> The method (`method_*`).
        integer, intent(in) :: method
        integer :: p

        select case (method)
        case (method_rk4)
            p = rk4_order
        case (method_rk8)
            p = rk8_order
        case default
            p = 2
        end select
    end function method_order

    !> Write the results so far to `<output>.partial.h5` (root attribute `complete = 0`); failures are ignored (the
    !> journal, not this file, is what a resumed run reads).
    subroutine write_snapshot(self, results, done)
        !> The tasks.
        class(continuation_tasks), intent(in) :: self
        !> Results so far, (values, tasks).
        real(wp), intent(in) :: results(:, :)
        !> Which tasks are done.
        logical, intent(in) :: done(:)
        type(error_type), allocatable :: error

        call write_continuation_file(self, self%partial_path, results, done, .false., -1.0_wp, error)
        if (allocated(error) .and. .not. self%cfg%output%quiet) then
            write (error_unit, "(a)") "  warning: partial output not written: " // error%message
        end if
    end subroutine write_snapshot

    !> Write the scene's file `path` (as a temporary file, renamed when complete): tasks not done get NaN and status
    !> -1 (pending).
    subroutine write_continuation_file(tasks, path, results, done, complete, elapsed, error)
        !> The tasks.
        type(continuation_tasks), intent(in) :: tasks
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
        type(fold_record), allocatable :: recs(:)
        real(wp), allocatable :: branch(:, :, :), mult(:, :, :)
        integer :: ncurve, nomega, ntask, t, q, npts
        character(len=*), parameter :: dims = "curve, omega"

        ncurve = size(tasks%runs)
        nomega = size(tasks%omegas)
        ntask = ncurve*nomega
        npts = tasks%cfg%scene%continuation_points
        allocate (recs(ntask))
        do t = 1, ntask
            if (done(t)) then
                recs(t) = fold_from_values(results(:, t), npts)
            else
                recs(t) = empty_fold_record(npts)
                recs(t)%status = status_not_run
            end if
        end do

        call h5_create(file, path, .true.)
        call write_root(file, tasks%cfg, "continuation", "Fold (saddle-node) of the branch of driven periodic " &
                        // "states vs driving frequency: the supratransmission threshold of the model, one curve per " &
                        // "potential and varied value, with Floquet stability and convergence", tasks%inv)
        call h5_write_attr(file, "/", "complete", merge(1, 0, complete))
        call h5_write_attr(file, "/", "tasks_done", count(done))
        call write_parameters(file, tasks%cfg)
        call h5_write(file, "/omega", tasks%omegas, "1/time", &
            "Driving frequency Omega_i = omega_min + i omega_step", dims="omega")
        call write_curves(file, tasks%cfg, tasks%runs)
        call h5_write(file, "/fold_amplitude", grid(recs%fold_amplitude), "rad", &
            "Fold A_f of the branch of periodic states (the model's supratransmission threshold when the branch is " &
            // "stable up to it); NaN when none (see /status)", dims=dims)
        call h5_write(file, "/fold_residual", grid(recs%fold_residual), "rad", &
            "max-norm of the shooting residual P(x) - x at the located fold", dims=dims)
        call h5_write(file, "/fold_fate", igrid(recs%fate), "1", &
            "What the chain does when driven 1% past the fold from the fold's state (codes in attribute 'codes')", &
            dims=dims)
        call h5_write_attr(file, "/fold_fate", "codes", fate_codes())
        call h5_write(file, "/fold_fate_time", grid(recs%fate_time), "time", &
            "Time from the push past the fold to the first transmission (/fold_fate 1), or the time watched without " &
            // "one (2); NaN when there is no fold", dims=dims)
        call h5_write(file, "/transmission_fold", grid(recs%transmission_fold), "rad", &
            "The fold past which the chain transmits: /fold_amplitude when its fate is to transmit; else the fold of " &
            // "the branch the chain settles on past it, and so on (/branches); NaN when none was found", dims=dims)
        call h5_write(file, "/branches", igrid(recs%branches), "1", &
            "Branches of periodic states followed from rest to /transmission_fold (1: the first fold transmits)", &
            dims=dims)
        call h5_write(file, "/transmission_status", igrid(recs%transmission_status), "1", &
            "Whether /transmission_fold was found, and if not why (codes in attribute 'codes')", dims=dims)
        call h5_write_attr(file, "/transmission_status", "codes", transmission_status_codes())
        call h5_write(file, "/instability_amplitude", grid(recs%instability_amplitude), &
            "rad", "First amplitude along the branch where a Floquet multiplier leaves the unit circle; NaN when " &
            // "the branch stays stable up to its fold", dims=dims)
        call h5_write(file, "/instability_size", grid(recs%instability_size), "1", &
            "How far the Floquet multipliers leave the unit circle before the fold: max |mu| - 1 over the branch up " &
            // "to it (a weak instability has a small size: compare it with crossing_tol)", dims=dims)
        call h5_write(file, "/instability_type", igrid(recs%instability_type), "1", &
            "How the branch first loses stability (codes in attribute 'codes')", dims=dims)
        call h5_write_attr(file, "/instability_type", "codes", instability_type_codes())
        call h5_write(file, "/threshold", grid(recs%threshold), "rad", &
            "The model's threshold: the smaller of the fold and the first loss of stability (/threshold_kind says " &
            // "which)", dims=dims)
        call h5_write(file, "/threshold_kind", igrid(recs%threshold_kind), "1", &
            "Which one /threshold is (the codes of /instability_type; 1: the fold)", dims=dims)
        call h5_write_attr(file, "/threshold_kind", "codes", instability_type_codes())
        call h5_write(file, "/threshold_As", grid(recs%threshold_as), "rad", &
            "Continuum-limit threshold A_s = 4 arctan(lambda c / Omega) of the curve's chain; NaN outside the gap", &
            dims=dims)
        call h5_write(file, "/status", igrid(recs%status), "1", &
            "Outcome of the continuation (codes in attribute 'codes')", dims=dims)
        call h5_write_attr(file, "/status", "codes", "-2: outside gap (not computed); " &
            // "-1: pending (not computed yet); " // fold_status_codes())
        call h5_write(file, "/outside_gap", task_igrid(merge(1, 0, &
            [(tasks%omegas(mod(t - 1, nomega) + 1) >= band_gap_edge(tasks%runs((t - 1)/nomega + 1)%chain), &
            t=1, ntask)]), nomega), "1", "1 where Omega >= sqrt(1 + m^2), outside the curve's band gap: computed only " &
            // "with allow_outside_gap, and no fold is expected there", dims=dims)
        call h5_write(file, "/dt_used", grid(recs%dt_used), "time", &
            "Time step used: the drive period 2 pi / Omega over a whole number M of steps", dims=dims)
        call h5_write(file, "/steps_per_period", igrid(recs%steps_per_period), "1", &
            "Steps M per drive period", dims=dims)
        call h5_write(file, "/chain_n", igrid(recs%chain_n), "1", "Oscillators N of the chain used (the short " &
            // "chain of its Omega when the input gives no n, n0, sigma; docs/continuation.md)", dims=dims)
        call h5_write(file, "/chain_n0", igrid(recs%chain_n0), "1", "Last site N0 before the absorber", dims=dims)
        call h5_write(file, "/chain_sigma", grid(recs%chain_sigma), "1", "Width sigma of the absorber's ramp", &
            dims=dims)
        call write_convergence(file, recs, nomega)
        call write_cost(file, recs, nomega, elapsed)
        call h5_create_group(file, "/branch", "The branch of periodic states of each task, point by point " &
            // "from A = 0 (NaN past /branch/points)")
        call h5_write(file, "/branch/points", igrid(recs%points), "1", &
            "Points computed on the branch", dims=dims)
        allocate (branch(npts, nomega, ncurve))
        do q = 1, size(branch_quantities)
            do t = 1, ntask
                branch(:, mod(t - 1, nomega) + 1, (t - 1)/nomega + 1) = recs(t)%branch(q, :)
            end do
            call h5_write(file, "/branch/" // trim(branch_quantities(q)), branch, branch_units(q), &
                          branch_description(q), dims="curve, omega, point")
        end do
        call h5_create_group(file, "/multipliers", "Floquet multipliers of largest modulus at a few points of " &
            // "each branch: the first point, the one nearest half the fold, the fold, the last point")
        allocate (mult(kept_multipliers, multiplier_samples, ntask))
        do t = 1, ntask
            mult(:, :, t) = recs(t)%multiplier_re
        end do
        call h5_write(file, "/multipliers/real", mult, "1", "Real parts of the multipliers (task = (curve - 1) " &
                      // "nomega + omega)", dims="task, sample, multiplier")
        do t = 1, ntask
            mult(:, :, t) = recs(t)%multiplier_im
        end do
        call h5_write(file, "/multipliers/imag", mult, "1", "Imaginary parts of the multipliers", &
                      dims="task, sample, multiplier")
        call h5_write(file, "/multipliers/amplitude", reshape([(recs(t)%multiplier_amplitude, t=1, ntask)], &
                      [multiplier_samples, ntask]), "rad", "Amplitude of each sampled branch point", &
                      dims="task, sample")
        call h5_commit(file, error)

    contains

        !> A per-task real as an (omega, curve) grid.
        pure function grid(x) result(g)
            real(wp), intent(in) :: x(:)
            real(wp), allocatable :: g(:, :)

            g = task_grid(x, nomega)
        end function grid

        !> A per-task integer as an (omega, curve) grid.
        pure function igrid(x) result(g)
            integer, intent(in) :: x(:)
            integer, allocatable :: g(:, :)

            g = task_igrid(x, nomega)
        end function igrid

    end subroutine write_continuation_file

    !> A per-task real (task = (curve - 1) nomega + omega) as an (omega, curve) grid: h5py (curve, omega).
    pure function task_grid(x, nomega) result(g)
        !> One value per task.
        real(wp), intent(in) :: x(:)
        !> Frequencies per curve.
        integer, intent(in) :: nomega
        real(wp), allocatable :: g(:, :)

        g = reshape(x, [nomega, size(x)/nomega])
    end function task_grid

    !> A per-task integer as an (omega, curve) grid.
    pure function task_igrid(x, nomega) result(g)
        !> One value per task.
        integer, intent(in) :: x(:)
        !> Frequencies per curve.
        integer, intent(in) :: nomega
        integer, allocatable :: g(:, :)

        g = reshape(x, [nomega, size(x)/nomega])
    end function task_igrid

    !> `/convergence`: each fold again at dt/2 and on a chain twice as long, the extrapolation and the digits.
    subroutine write_convergence(file, recs, nomega)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The records, one per task.
        type(fold_record), intent(in) :: recs(:)
        !> Frequencies per curve.
        integer, intent(in) :: nomega
        character(len=*), parameter :: g = "/convergence/", dims = "curve, omega"

        call h5_create_group(file, "/convergence", "How many digits of each fold are converged: the fold located " &
            // "again at dt/2 and on a chain twice as long (&scene fold_convergence); NaN when not computed")
        call h5_write(file, g // "fold_half_dt", task_grid(recs%fold_half_dt, nomega), &
            "rad", "Fold at dt/2 (the same method, M doubled)", dims=dims)
        call h5_write(file, g // "fold_long_chain", task_grid(recs%fold_long_chain, &
            nomega), "rad", "Fold on the chain of 2N sites (N0 + N, the same absorber)", dims=dims)
        call h5_write(file, g // "richardson", task_grid(recs%richardson, nomega), "rad", &
            "Richardson extrapolation of the fold in dt (the method's order)", dims=dims)
        call h5_write(file, g // "error_estimate", task_grid(recs%error_estimate, nomega), &
            "rad", "Estimated error of /fold_amplitude: max(|A(dt/2) - A(dt)| / (2^p - 1), |A(2N) - A(N)|)", &
            dims=dims)
        call h5_write(file, g // "digits", task_grid(recs%digits, nomega), "1", &
            "Converged decimal digits of /fold_amplitude, floor(-log10(error_estimate / A_f))", dims=dims)
    end subroutine write_convergence

    !> `/cost`: what each continuation cost.
    subroutine write_cost(file, recs, nomega, elapsed)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The records, one per task.
        type(fold_record), intent(in) :: recs(:)
        !> Frequencies per curve.
        integer, intent(in) :: nomega
        !> Wall time of the scene (s); negative when unknown.
        real(wp), intent(in) :: elapsed
        character(len=*), parameter :: g = "/cost/", dims = "curve, omega"

        call h5_create_group(file, "/cost", "What each task cost (the convergence checks included)")
        call h5_write(file, g // "newton_iterations", task_igrid(recs%newton_iterations, &
            nomega), "1", "Newton-shooting iterations", dims=dims)
        call h5_write(file, g // "map_evaluations", task_igrid(recs%map_evaluations, &
            nomega), "1", "Evaluations of the one-period map", dims=dims)
        call h5_write(file, g // "jacobians", task_igrid(recs%jacobians, nomega), "1", &
            "Of those, with the tangent (2N + 1 columns)", dims=dims)
        call h5_write(file, g // "factorizations", task_igrid(recs%factorizations, &
            nomega), "1", "LU factorisations of the shooting system", dims=dims)
        call h5_write(file, g // "eigen_calls", task_igrid(recs%eigen_calls, nomega), &
            "1", "Eigenvalue computations (Floquet multipliers)", dims=dims)
        call h5_write(file, g // "wall_time", task_grid(recs%wall_time, nomega), "s", &
            "Wall-clock time of the task (one thread)", dims=dims)
        call h5_write(file, g // "wall_time_map", task_grid(recs%time_map, nomega), "s", &
            "Of the wall time: evaluations of the period map alone", dims=dims)
        call h5_write(file, g // "wall_time_tangent", task_grid(recs%time_tangent, nomega), &
            "s", "Of the wall time: evaluations of the period map with its tangent (2N + 1 columns)", dims=dims)
        call h5_write(file, g // "wall_time_lu", task_grid(recs%time_lu, nomega), "s", &
            "Of the wall time: dense LU factorisations and solves of the shooting systems", dims=dims)
        call h5_write(file, g // "wall_time_eigen", task_grid(recs%time_eigen, nomega), "s", &
            "Of the wall time: eigenvalues of the monodromy matrices (Floquet multipliers)", dims=dims)
        if (elapsed >= 0.0_wp) call h5_write_attr(file, "/cost", "scene_wall_time_s", elapsed)
    end subroutine write_cost

    !> Units of a branch quantity.
    pure function branch_units(q) result(units)
        !> Index in `branch_quantities`.
        integer, intent(in) :: q
        character(len=:), allocatable :: units

        select case (trim(branch_quantities(q)))
        case ("amplitude", "umax", "residual")
            units = "rad"
        case ("energy")
            units = "energy"
        case default
            units = "1"
        end select
    end function branch_units

    !> Description of a branch quantity.
    pure function branch_description(q) result(text)
        !> Index in `branch_quantities`.
        integer, intent(in) :: q
        character(len=:), allocatable :: text

        select case (trim(branch_quantities(q)))
        case ("amplitude")
            text = "Driving amplitude A of each branch point"
        case ("umax")
            text = "Largest |u_n| over the chain and one drive period"
        case ("energy")
            text = "Stored energy of the chain, averaged over one drive period"
        case ("multiplier_max")
            text = "Largest modulus of the Floquet multipliers"
        case ("stable")
            text = "1 when every multiplier has modulus <= 1 + crossing_tol, else 0"
        case ("newton_iterations")
            text = "Newton-shooting iterations of the point"
        case default
            text = "max-norm of the shooting residual P(x) - x at the point"
        end select
    end function branch_description

    !> The frequency axis, then the dense 2N x (2N + 1) matrices of the shooting: the tangent, the shooting system,
    !> its LU and the eigenvalue copy (x 4 on the chain of 2N sites of the convergence check), per thread.
    pure subroutine continuation_scene_limits(self, cfg, where, budget, error)
        !> The scene.
        class(continuation_scene), intent(in) :: self
        !> The configuration (values already within their ranges and rules).
        type(input_config), intent(in) :: cfg
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Threads and memory of the machine.
        type(scene_budget), intent(in) :: budget
        !> Allocated when a limit is exceeded.
        type(error_type), allocatable, intent(out) :: error
        real(wp) :: nomega, n, need

        associate (sc => cfg%scene)
            nomega = axis_points(sc%omega_min, sc%omega_max, sc%omega_step)
            call check_axis(nomega, "omega_step = " // sci(sc%omega_step) // " makes " // sci(nomega) // " frequencies", &
                            where, error)
            if (allocated(error)) return
            n = real(cfg%run%chain%n, wp)*merge(2.0_wp, 1.0_wp, sc%fold_convergence)
            need = 5.0_wp*(2.0_wp*n + 1.0_wp)**2*8.0_wp*real(budget%threads, wp)
            if (budget%memory > 0.0_wp .and. need > 0.8_wp*budget%memory) then
                call limit_error(error, where, "chain", "n = " // int_str(cfg%run%chain%n) // ": the dense shooting " &
                                 // "matrices need about " // sci(need/1.0e9_wp) // " GB" // threads_text(budget) &
                                 // ", more than the " // sci(budget%memory/1.0e9_wp) // " GB available (" &
                                 // budget%source // "; a shorter chain)")
            end if
        end associate
    end subroutine continuation_scene_limits

end module supratrans_scene_continuation
