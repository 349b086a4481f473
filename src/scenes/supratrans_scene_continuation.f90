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
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_nan
    use supratrans_kinds, only: wp, i8, pi
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_invocation, only: invocation_type
    use supratrans_scene, only: scene_budget, scene_tasks, scene_plan
    use supratrans_axis_scene, only: axis_tasks, axis_scene, init_axes, axis_task_run, scene_omegas
    use supratrans_limits, only: axis_points, check_axis, limit_error, threads_text, sci, dense_buffer_bytes
    use supratrans_config, only: input_config, run_config, scene_params, method_newton, method_linearized, method_rk4, &
                                 method_rk8, method_avf4, method_avf8, method_name, solver_harmonic_balance, chain_short, &
                                 chain_input
    use supratrans_short_chain, only: old_short_chain_rule
    use supratrans_fold_hb, only: make_hb_tasks, hb_summary
    use supratrans_curves, only: curve_count, curve_run, write_curves
    use supratrans_chain, only: threshold_as, band_gap_edge, phonon_band_top
    use supratrans_potential, only: potential_name
    use supratrans_status, only: status_outside_gap, status_not_run
    use supratrans_fold_record, only: fold_record, fold_fields, fold_to_values, fold_from_values, empty_fold_record, &
                                      branch_quantities, kept_multipliers, multiplier_samples, add_fold_cost
    use supratrans_fold_line, only: trace_fold, fold_status_codes, instability_type_codes, fold_found, &
                                    shortest_chain, fate_codes, transmission_status_codes, branch_switch_codes
    use supratrans_fold_scalars, only: write_fold_scalars
    use supratrans_tasks, only: task_list, run_work
    use supratrans_hdf5, only: h5_file, h5_create, h5_commit, h5_write_attr
    use supratrans_output, only: write_root, write_parameters
    use supratrans_strings, only: int_str, real_str, fixed1
    use supratrans_linear_stability, only: linear_stability_dt
    use supratrans_stepper_rk4, only: rk4_order
    use supratrans_stepper_rk8, only: rk8_order
    implicit none
    private

    ! A fold's typical counts and the cost of its phases in Newton oscillator-steps (60 ns, `--check`'s unit), for the
    ! estimate of `--check`. Counts: medians of the 20 shooting folds of the quick figure set (fold_sg, fold_sg_090,
    ! fold_sg_050, fold_bif1; N = 200, M = 133 .. 2514; 2026-11-29, their /cost); one fold's counts range over a
    ! factor 4 (localized folds at low Omega take more). Costs: the phases of one fold at Omega = 0.9, N = 200, M =
    ! 140 in CPU seconds at load 3 (docs/continuation_reference.md, "The fold alone"); by harmonic balance, fitted to
    ! the 95 folds of input/fold_hb_sg.nml (each within a factor 3) and scaled to its wall time at a quiet moment.
    !> Jacobians of the one-period map a fold takes (median 52).
    real(wp), parameter :: fold_jacobians = 50.0_wp
    !> Periods of the state alone a fold takes (median 710).
    real(wp), parameter :: fold_maps = 700.0_wp
    !> Dense spectra of the monodromy a fold takes with floquet_every > 0 (median 25).
    real(wp), parameter :: fold_spectra = 25.0_wp
    !> One tangent column through one oscillator-step (0.5 ns).
    real(wp), parameter :: tangent_step = 0.0083_wp
    !> One oscillator-step of a period of the state alone, the Newton iteration to the map's tolerance (15 ns).
    real(wp), parameter :: map_step = 0.25_wp
    !> A dense LU of order 2N, per (2N)^3 (0.034 ns).
    real(wp), parameter :: lu_cube = 0.00057_wp
    !> A dense eigenvalue problem (dgeev) of order 2N, per (2N)^3 (0.78 ns).
    real(wp), parameter :: spectrum_cube = 0.013_wp
    !> A harmonic-balance fold, per site and (2K)^3 of the fold's K plus 2.5 (2K')^3 of the branch's K' = min(K, 16)
    !> (9 ns).
    real(wp), parameter :: hb_fold_cube = 0.15_wp
    !> Points of a harmonic-balance branch at which floquet_every counts (the multipliers of one in floquet_every).
    real(wp), parameter :: hb_branch_points = 20.0_wp
    !> Cost of an rk8 step relative to a Newton step (`run_work`).
    real(wp), parameter :: rk8_step = 1.6_wp

    !> The tasks of a continuation scene (the axes of `axis_tasks`): task t = (curve - 1) nomega + iomega traces one
    !> branch to its fold.
    type, extends(axis_tasks) :: continuation_tasks
        !> &scene chain = 'short': each task uses the short chain of its Omega.
        logical :: short_chain = .false.
    contains
        !> Trace the branch of one task.
        procedure :: run => run_fold_task
        !> The scene's file.
        procedure :: write_file => write_continuation_file
        !> Estimated cost of one task (a Jacobian of its one-period map).
        procedure :: cost => fold_task_cost
        !> The run of a task, on the short chain of its Omega with &scene chain = 'short'.
        procedure :: task_run => continuation_task_run
    end type continuation_tasks

    !> The scene `continuation`: the fold line of the periodic states over the frequency axis, per curve.
    type, extends(axis_scene), public :: continuation_scene
    contains
        !> Its tasks: one branch traced to its fold per (curve, frequency).
        procedure :: make_tasks => continuation_make_tasks
        !> The folds found and the wall time.
        procedure :: summary => continuation_summary
        !> Its axes, tasks, work and memory against the limits.
        procedure :: check_limits => continuation_scene_limits
        !> Its method and dt (shooting) or harmonics (harmonic balance), before any work.
        procedure :: check_input => continuation_check_input
        !> Its tasks and their work from the sizes (`--check`).
        procedure :: plan => continuation_scene_plan
    end type continuation_scene

    interface
        !> Write the scene's file `path` (built in memory, written atomically): tasks not done get NaN and status
        !> -1 (pending).
        module subroutine write_continuation_file(self, path, results, done, complete, elapsed, error)
            !> The tasks.
            class(continuation_tasks), intent(in) :: self
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
        end subroutine write_continuation_file
    end interface

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

        if (cfg%scene%solver == solver_harmonic_balance) then     ! the ODE's fold in the frequency domain
            call make_hb_tasks(cfg, tasks, error)
            return
        end if
        allocate (list)
        call init_axes(list, cfg, tasks%inv, 1, error)   ! the bifurcation scene's axis, so fold lines lie over diagrams
        if (allocated(error)) return
        ncurve = size(list%runs)
        nomega = size(list%omegas)
        ! the method and dt: checked by validation already (continuation_check_input, also for --check)
        call continuation_check_input(self, cfg, cfg%source, error)
        if (allocated(error)) return
        do ic = 1, ncurve
            list%runs(ic)%drive%ramp_time = 0.0_wp
        end do
        list%short_chain = cfg%scene%chain == chain_short
        tasks%header = "supratrans: continuation from " // cfg%source // ": " // int_str(ncurve) // " curve(s) x " &
            // int_str(nomega) // " frequencies, method " // method_name(cfg%run%numerics%method) // ", N = " &
            // int_str(cfg%run%chain%n) // ", branches up to A = " // real_str(cfg%scene%amplitude_max, 6)
        tasks%count = ncurve*nomega
        tasks%fields = fold_fields(cfg%scene%continuation_points)
        tasks%label = "fold continuations"
        call move_alloc(list, tasks%list)
    end subroutine continuation_make_tasks

    !> Refuse, before any work (by validation, also for --check), a method without a one-period map (avf4, avf8) and
    !> a dt beyond the method's linear stability limit for a curve's chain: the scheme has no periodic state to
    !> continue; and an input written for the old rule of the short chain (`old_short_chain_rule`). With harmonic
    !> balance: harmonics above harmonics_max (the dt only sets the rk8 period that checks each fold;
    !> `/fold_period_closure` shows an unstable one).
    subroutine continuation_check_input(self, cfg, where, error)
        !> The scene.
        class(continuation_scene), intent(in) :: self
        !> The configuration (values already within their ranges, rules and limits).
        type(input_config), intent(in) :: cfg
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Allocated when the method or dt has no periodic state to continue.
        type(error_type), allocatable, intent(out) :: error
        type(run_config) :: run
        real(wp) :: limit
        integer :: ic, method

        method = cfg%run%numerics%method
        if (cfg%scene%solver == solver_harmonic_balance) then
            ! no scheme is continued (no dt to refuse: the rk8 spectrum of a long chain would cost --check seconds)
            if (cfg%scene%harmonics > cfg%scene%harmonics_max) then
                call fatal_error(error, where // ": &scene: harmonics = " // int_str(cfg%scene%harmonics) &
                                 // " is above harmonics_max = " // int_str(cfg%scene%harmonics_max), err_input)
                return
            end if
            return      ! the &numerics dt only sets the rk8 period that checks each fold: an unstable one shows there
        end if
        if (cfg%scene%protocol%continuation_slow_iter <= cfg%scene%protocol%continuation_fast_iter) then
            call fatal_error(error, where // ": &scene: continuation_slow_iter = " &
                             // int_str(cfg%scene%protocol%continuation_slow_iter) // ": must be > continuation_fast_iter = " &
                             // int_str(cfg%scene%protocol%continuation_fast_iter), err_input)
            return
        end if
        if (cfg%scene%protocol%continuation_step_min > cfg%scene%continuation_step) then
            call fatal_error(error, where // ": &scene: continuation_step_min = " &
                             // real_str(cfg%scene%protocol%continuation_step_min) // ": must be <= continuation_step = " &
                             // real_str(cfg%scene%continuation_step), err_input)
            return
        end if
        if (cfg%scene%short%sigma_min > cfg%scene%short%sigma_max) then
            call fatal_error(error, where // ": &scene: short_sigma_min = " // real_str(cfg%scene%short%sigma_min) &
                             // ": must be <= short_sigma_max = " // real_str(cfg%scene%short%sigma_max), err_input)
            return
        end if
        if (cfg%scene%chain == chain_input .and. allocated(cfg%text)) then
            if (len(old_short_chain_rule(cfg%text)) > 0) then
                call fatal_error(error, where // ": " // old_short_chain_rule(cfg%text), err_input)
                return
            end if
        end if
        if (any(method == [method_avf4, method_avf8])) then   ! no period map (supratrans_period_map)
            call fatal_error(error, where // ": &numerics: method '" // method_name(cfg%run%numerics%method) &
                // "' has no one-period map: continue folds with 'newton', 'linearized', 'rk4' or 'rk8'", err_input)
            return
        end if
        do ic = 1, curve_count(cfg)
            run = curve_run(cfg, ic)
            ! a periodic state needs a stable scheme: dt within the method's linear stability limit for the chain
            limit = linear_stability_dt(run%chain, method)
            if (cfg%run%numerics%dt >= limit) then
                call fatal_error(error, where // ": &numerics: dt = " // real_str(cfg%run%numerics%dt, 6) &
                    // " is beyond the linear stability limit " // real_str(limit, 6) // " of method '" &
                    // method_name(method) // "' for curve " // int_str(ic) &
                    // ": the scheme has no periodic state to continue", err_input)
                return
            end if
        end do
    end subroutine continuation_check_input

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

        if (cfg%scene%solver == solver_harmonic_balance) then
            text = hb_summary(cfg, tasks)
            return
        end if
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
        run = self%task_run(index)
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

    !> The run of task `index`: its curve's run at its frequency, on the short chain of that frequency with &scene
    !> chain = 'short'.
    pure function continuation_task_run(self, index) result(run)
        !> The tasks.
        class(continuation_tasks), intent(in) :: self
        !> Task index: (curve - 1) nomega + iomega.
        integer, intent(in) :: index
        type(run_config) :: run

        run = axis_task_run(self, index)
        if (self%short_chain) call shortest_chain(run%chain, run%drive%omega, run%numerics%dt, self%cfg%scene%short)
    end function continuation_task_run

    !> Estimated cost of task `index`: what one Jacobian of its one-period map costs, 2N tangent columns of N sites
    !> through the M = period / dt steps of a period (`run_work` of one period, times 2N), with the chain the task
    !> runs (the short chain of its Omega with chain = 'short'); 0 for a frequency outside the gap that is not
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

        run = self%task_run(index)
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
            ! the matrices and the working buffer OpenBLAS maps for a dense solve, on every thread
            need = (5.0_wp*(2.0_wp*n + 1.0_wp)**2*8.0_wp + dense_buffer_bytes)*real(budget%threads, wp)
            if (sc%solver == solver_harmonic_balance) then
                ! blocks of 2K x 2K per site; dense only for the rk8 monodromy and its eigenvalues (floquet_every > 0)
                if (sc%floquet_every == 0) return
                n = real(cfg%run%chain%n, wp)
                need = (3.0_wp*(2.0_wp*n)**2*8.0_wp + dense_buffer_bytes)*real(budget%threads, wp)
            end if
            if (budget%memory > 0.0_wp .and. need > 0.8_wp*budget%memory) then
                call limit_error(error, where, "chain", "n = " // int_str(cfg%run%chain%n) // ": the dense shooting " &
                                 // "matrices and OpenBLAS's working buffer need about " // sci(need/1.0e9_wp) // " GB" &
                                 // threads_text(budget) &
                                 // ", more than the " // sci(budget%memory/1.0e9_wp) // " GB available (" &
                                 // budget%source // "; a shorter chain)")
            end if
        end associate
    end subroutine continuation_scene_limits

    !> The fold continuations: curves x frequencies, and their work in Newton oscillator-steps from the sizes of each
    !> task's chain (N, M = period / dt, K) and a fold's typical counts (`fold_jacobians` and the constants beside
    !> it; by harmonic balance `hb_fold_cube`): an order of magnitude, since a localized fold takes up to four times
    !> the median counts.
    pure function continuation_scene_plan(self, cfg) result(p)
        !> The scene.
        class(continuation_scene), intent(in) :: self
        !> The configuration (values within their ranges).
        type(input_config), intent(in) :: cfg
        type(scene_plan) :: p
        real(wp), allocatable :: omegas(:)
        type(run_config) :: run
        logical :: short
        integer :: ic, io

        omegas = scene_omegas(cfg)
        p%tasks = real(curve_count(cfg)*size(omegas), wp)
        p%noun = "fold continuations"
        p%steps = 0.0_wp
        p%runs_per_task = 0.0_wp
        short = cfg%scene%chain == chain_short
        p%work = 0.0_wp
        do ic = 1, curve_count(cfg)
            do io = 1, size(omegas)
                run = curve_run(cfg, ic)
                run%drive%omega = omegas(io)
                if (run%drive%omega >= band_gap_edge(run%chain) .and. .not. cfg%allow_outside_gap) cycle
                if (cfg%scene%solver == solver_harmonic_balance) then
                    p%work = p%work + hb_fold_work(cfg, run)
                else
                    if (short) call shortest_chain(run%chain, run%drive%omega, run%numerics%dt, cfg%scene%short)
                    p%work = p%work + shooting_fold_work(cfg%scene, run)
                end if
            end do
        end do
        if (cfg%scene%solver == solver_harmonic_balance) then
            p%counts = "each fold: N x (2K)^3 for its K = the band top / Omega (at most harmonics_max) and the " &
                // "branch's at K <= 16, on every chain of absorber_family and c_values"
        else
            p%counts = "each fold: " // int_str(nint(fold_jacobians)) // " Jacobians of the one-period map (2N columns " &
                // "x M steps x N) and their LUs, " // int_str(nint(fold_maps)) // " periods, "
            if (cfg%scene%floquet_every == 0) then
                p%counts = p%counts // "1 spectrum 2N x 2N (floquet_every = 0)"
            else
                p%counts = p%counts // int_str(nint(fold_spectra)) // " spectra 2N x 2N"
            end if
            if (cfg%scene%fold_convergence) p%counts = p%counts // "; the fold alone again at dt/2 and at 2N"
        end if
    end function continuation_scene_plan

    !> Work of one shooting task in Newton oscillator-steps: `fold_jacobians` Jacobians of the one-period map (2N
    !> tangent columns through the M = period / dt steps of N sites) and their LUs, `fold_maps` periods and
    !> `fold_spectra` dense eigenvalue problems of 2N x 2N (one with `floquet_every = 0`); with `fold_convergence`
    !> the fold alone again at dt/2 and on the chain of 2N sites.
    pure function shooting_fold_work(sc, run) result(work)
        !> The scene's keys.
        type(scene_params), intent(in) :: sc
        !> The task's run (its chain, dt and Omega).
        type(run_config), intent(in) :: run
        real(wp) :: work
        real(wp) :: n, m, spectra

        n = real(run%chain%n, wp)
        m = real(ceiling(2.0_wp*pi/(run%drive%omega*run%numerics%dt)), wp)
        spectra = fold_spectra
        if (sc%floquet_every == 0) spectra = 1.0_wp
        work = one_fold(n, m, spectra)
        if (sc%fold_convergence) work = work + one_fold(n, 2.0_wp*m, 1.0_wp) + one_fold(2.0_wp*n, m, 1.0_wp)

    contains

        !> One fold of N sites and M steps a period.
        pure real(wp) function one_fold(n, m, spectra)
            real(wp), intent(in) :: n, m, spectra
            type(run_config) :: one_step

            one_step = run
            one_step%numerics%t_final = one_step%numerics%dt
            one_step%chain%n = 1     ! the method's cost of one oscillator-step relative to a Newton step
            one_fold = fold_jacobians*(2.0_wp*n*m*n*tangent_step*run_work(one_step) + (2.0_wp*n)**3*lu_cube) &
                       + fold_maps*m*n*map_step*run_work(one_step) + spectra*(2.0_wp*n)**3*spectrum_cube
        end function one_fold

    end function shooting_fold_work

    !> Work of one harmonic-balance task in Newton oscillator-steps: per site of its chain, of each chain of the
    !> absorber family and of c_values, (2K)^3 for the fold and 2.5 (2K')^3 for the branch from rest (K: the odd
    !> harmonics that reach the base chain's band top, between harmonics and harmonics_max; K' = min(K, 16), the most
    !> the branch is traced with); with floquet_every > 0 the rk8 monodromies and their spectra too.
    pure function hb_fold_work(cfg, run) result(work)
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> The task's run (its chain and Omega).
        type(run_config), intent(in) :: run
        real(wp) :: work
        real(wp) :: k, kb, n, n0, sites, m
        integer :: j

        associate (sc => cfg%scene)
            k = real(min(sc%harmonics_max, max(sc%harmonics, 3, &
                                               ceiling(phonon_band_top(run%chain)/run%drive%omega))), wp)
            kb = min(k, 16.0_wp)
            n = real(run%chain%n, wp)
            n0 = real(run%chain%n0, wp)
            sites = n
            if (sc%absorber_family > 0) then
                do j = 1, sc%absorber_family
                    sites = sites + n0 + 2.0_wp**j*(n - n0)
                end do
                sites = sites + n0          ! the core closed by the radiation condition
            end if
            if (allocated(sc%c_values)) sites = sites + n*sum(sc%c_values)/run%chain%c
            work = sites*((2.0_wp*k)**3 + 2.5_wp*(2.0_wp*kb)**3)*hb_fold_cube
            if (sc%floquet_every > 0) then
                m = real(ceiling(2.0_wp*pi/(run%drive%omega*run%numerics%dt)), wp)
                work = work + (1.0_wp + hb_branch_points/real(sc%floquet_every, wp)) &
                    *(2.0_wp*n*m*n*tangent_step*rk8_step + (2.0_wp*n)**3*spectrum_cube)
            end if
        end associate
    end function hb_fold_work

end module supratrans_scene_continuation
