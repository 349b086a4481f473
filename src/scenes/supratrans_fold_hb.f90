!> The continuation scene with `solver = 'harmonic_balance'`: per (curve, Omega) the fold of the branch of driven
!> periodic states of the ODE (paper eq. (1)) by harmonic balance (`supratrans_hb_continuation`), converged in the
!> number of harmonics, with
!>
!> * the independent check of the time domain: one period of the rk8 method from the state at the fold, u_n(0) and
!>   u_n'(0) of the Fourier series, returns to it (`/fold_period_closure`, max |P(x) - x|), and with
!>   `floquet_every` > 0 the Floquet multipliers at the fold from the rk8 monodromy (one of them is +1 there);
!> * with `absorber_family` > 0, the fold again with absorbers 2, 4, .. times as long and as wide (the core N0 kept)
!>   and on the core closed by the exact radiation condition: how far the fold moves with the absorber, and the
!>   longest absorber's fold as the best value for the semi-infinite chain (`/convergence`);
!> * with `c_values`, the fold at each coupling c with N, N0 and sigma scaled by c / (&chain c), and its
!>   extrapolation c -> infinity in 1/c^2 (`/continuum`), beside A_s.
!>
!> A record is a list of named values (`hb_fields`) built and read by one cursor (`put`, `take`) in one order, so
!> no field has a hand-kept index. The file keeps the layout of the shooting scene where a dataset means the same
!> (`/fold_amplitude`, `/status`, the groups `/branch`, `/cost`, `/convergence`).
module supratrans_fold_hb
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_nan
    use supratrans_kinds, only: wp, i8, pi
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_invocation, only: invocation_type
    use supratrans_scene, only: scene_tasks
    use supratrans_config, only: input_config, run_config, chain_params, method_rk8, closure_absorber, &
                                 closure_radiation, solver_choices
    use supratrans_curves, only: write_curves
    use supratrans_chain, only: threshold_as, band_gap_edge
    use supratrans_status, only: status_outside_gap, status_not_run
    use supratrans_tasks, only: task_list
    use supratrans_hdf5, only: h5_file, h5_create, h5_commit, h5_write_attr
    use supratrans_output_rows, only: output_row, write_row, write_row_group, write_row_attr, &
        continuation_harmonic_balance_omega, continuation_harmonic_balance_status, &
        continuation_harmonic_balance_instability_type, continuation_harmonic_balance_cost, &
        continuation_harmonic_balance_outside_gap, continuation_harmonic_balance_spectrum, &
        continuation_harmonic_balance_multipliers, continuation_harmonic_balance_multipliers_real, &
        continuation_harmonic_balance_multipliers_imag, continuation_harmonic_balance_convergence_absorber_folds, &
        continuation_harmonic_balance_continuum_c, continuation_harmonic_balance_continuum_folds, &
        continuation_harmonic_balance_branch_amplitude, continuation_harmonic_balance_branch_umax, &
        continuation_harmonic_balance_branch_energy, continuation_harmonic_balance_branch_newton_iterations, &
        continuation_harmonic_balance_branch_residual, continuation_harmonic_balance_branch_multiplier_max, &
        continuation_harmonic_balance_branch_stable
    use supratrans_output, only: write_root, write_parameters
    use supratrans_strings, only: int_str, fixed1
    use supratrans_axis_scene, only: axis_tasks, init_axes
    use supratrans_fold_line, only: fold_status_codes, fold_found, instability_type_codes
    use supratrans_harmonic_balance, only: hb_system, hb_init, hb_time_state, hb_spectrum
    use supratrans_hb_continuation, only: hb_controls, hb_result, hb_fold_converged
    use supratrans_period_map, only: period_map, period_map_init
    use supratrans_fixed_point_map, only: map_ok
    use supratrans_hb_scalars, only: hb_scalars, hb_scalars_names, hb_scalars_values, hb_scalars_from_values, &
                                     empty_hb_scalars, write_hb_scalars
    use supratrans_floquet, only: floquet_multipliers, largest_modulus, is_stable, leading_crossing
    implicit none
    private

    public :: make_hb_tasks, write_hb_file, hb_summary, hb_fields, hb_record, hb_to_values, hb_from_values

    !> Harmonics whose amplitudes at the fold are kept per site (`/spectrum`): the odd harmonics 1, 3, .., 15.
    integer, parameter, public :: spectrum_harmonics = 8
    !> Floquet multipliers kept at the fold, those of largest modulus.
    integer, parameter, public :: hb_kept_multipliers = 8
    !> Quantities of each branch point (`/branch/<name>`).
    character(len=*), parameter, public :: hb_branch_quantities(*) = [character(len=17) :: "amplitude", "umax", &
        "energy", "newton_iterations", "residual", "multiplier_max", "stable"]

    !> The tasks of a harmonic-balance continuation (the axes of `axis_tasks`): task t = (curve - 1) nomega + iomega.
    type, extends(axis_tasks), public :: hb_fold_tasks
        !> The couplings of the continuum limit (empty: none).
        real(wp), allocatable :: c_values(:)
    contains
        !> Locate the fold of one task.
        procedure :: run => run_hb_task
        !> The scene's file.
        procedure :: write_file => write_hb_file
        !> Estimated cost of a task: K^3 N of its first K.
        procedure :: cost => hb_task_cost
    end type hb_fold_tasks

    !> One (curve, Omega) task of the harmonic-balance continuation: its scalar fields, one dataset each, are those of
    !> the output table src/io/outputs/continuation_harmonic_balance.toml (`hb_scalars`); the arrays follow.
    type, extends(hb_scalars), public :: hb_record
        !> Folds with the absorber 2, 4, .. times as long and wide (NaN when not computed).
        real(wp), allocatable :: absorber_folds(:)
        !> Folds at each c of `c_values`; NaN when not computed.
        real(wp), allocatable :: continuum_folds(:)
        !> The branch: `hb_branch_quantities` (rows) at each point (columns).
        real(wp), allocatable :: branch(:, :)
        !> Amplitudes of the harmonics 1, 3, .. (`spectrum_harmonics`) at each site at the fold, (8, N).
        real(wp), allocatable :: spectrum(:, :)
        !> Real and imaginary parts of the kept multipliers at the fold.
        real(wp) :: multiplier_re(hb_kept_multipliers) = 0.0_wp, multiplier_im(hb_kept_multipliers) = 0.0_wp
    end type hb_record

contains

    !> The tasks of the scene (the frequency axis of the bifurcation scene, so that fold lines lie over diagrams).
    subroutine make_hb_tasks(cfg, tasks, error)
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Its tasks: an `hb_fold_tasks`.
        type(scene_tasks), intent(inout) :: tasks
        !> Error, allocated when the axis is empty.
        type(error_type), allocatable, intent(out) :: error
        type(hb_fold_tasks), allocatable :: list
        integer :: ncurve, nomega

        allocate (list)
        call init_axes(list, cfg, tasks%inv, 1, error)
        if (allocated(error)) return
        ncurve = size(list%runs)
        nomega = size(list%omegas)
        allocate (list%c_values(0))
        if (allocated(cfg%scene%c_values)) list%c_values = cfg%scene%c_values
        tasks%header = "supratrans: continuation (" // trim(solver_choices(2)) // ") from " // cfg%source // ": " &
            // int_str(ncurve) // " curve(s) x " // int_str(nomega) // " frequencies, N = " &
            // int_str(cfg%run%chain%n) // ", K up to " // int_str(cfg%scene%harmonics_max)
        tasks%count = ncurve*nomega
        tasks%fields = hb_fields(cfg%scene%continuation_points, cfg%run%chain%n, cfg%scene%absorber_family, &
                                 size(list%c_values))
        tasks%label = "folds by harmonic balance"
        call move_alloc(list, tasks%list)
    end subroutine make_hb_tasks

    !> An empty record (numbers NaN) for the given sizes.
    pure function empty_hb_record(npts, n, nfamily, nc) result(r)
        !> Most branch points, sites, absorber family members, couplings.
        integer, intent(in) :: npts, n, nfamily, nc
        type(hb_record) :: r
        real(wp) :: nan

        nan = ieee_value(nan, ieee_quiet_nan)
        r%hb_scalars = empty_hb_scalars()
        allocate (r%absorber_folds(nfamily), source=nan)
        allocate (r%continuum_folds(nc), source=nan)
        allocate (r%branch(size(hb_branch_quantities), npts), source=nan)
        r%branch(size(hb_branch_quantities), :) = -1.0_wp     ! stable: -1 not computed
        allocate (r%spectrum(spectrum_harmonics, n), source=nan)
        r%multiplier_re = nan
        r%multiplier_im = nan
    end function empty_hb_record

    !> The names of a record's values (the order of `hb_to_values`).
    function hb_fields(npts, n, nfamily, nc) result(names)
        !> Most branch points, sites, absorber family members, couplings.
        integer, intent(in) :: npts, n, nfamily, nc
        character(len=64), allocatable :: names(:)
        type(hb_record) :: r
        real(wp), allocatable :: v(:)
        integer :: i

        r = empty_hb_record(npts, n, nfamily, nc)
        call serialize(r, v, names)
        do i = 1, size(names)
            if (len_trim(names(i)) == 0) names(i) = "value_" // int_str(i)
        end do
    end function hb_fields

    !> The record as values.
    function hb_to_values(r) result(v)
        !> The record.
        type(hb_record), intent(in) :: r
        real(wp), allocatable :: v(:)
        character(len=64), allocatable :: names(:)

        call serialize(r, v, names)
    end function hb_to_values

    !> The record's values and their names, in one order (the one place that lists the fields).
    subroutine serialize(r, v, names)
        !> The record.
        type(hb_record), intent(in) :: r
        !> Its values.
        real(wp), allocatable, intent(out) :: v(:)
        !> Their names.
        character(len=64), allocatable, intent(out) :: names(:)
        integer :: k, j, i

        i = 0
        k = size(hb_scalars_names) + size(r%absorber_folds) + size(r%continuum_folds) + 2*hb_kept_multipliers + size(r%branch) &
            + size(r%spectrum)
        allocate (v(k), names(k))
        i = size(hb_scalars_names)
        v(1:i) = hb_scalars_values(r%hb_scalars)
        names(1:i) = hb_scalars_names
        do k = 1, size(r%absorber_folds)
            call put("absorber_fold_" // int_str(k), r%absorber_folds(k))
        end do
        do k = 1, size(r%continuum_folds)
            call put("continuum_fold_" // int_str(k), r%continuum_folds(k))
        end do
        do k = 1, hb_kept_multipliers
            call put("multiplier_re_" // int_str(k), r%multiplier_re(k))
            call put("multiplier_im_" // int_str(k), r%multiplier_im(k))
        end do
        do k = 1, size(r%branch, 2)
            do j = 1, size(hb_branch_quantities)
                call put("branch_" // trim(hb_branch_quantities(j)) // "_" // int_str(k), r%branch(j, k))
            end do
        end do
        do k = 1, size(r%spectrum, 2)
            do j = 1, spectrum_harmonics
                call put("spectrum_" // int_str(2*j - 1) // "_" // int_str(k), r%spectrum(j, k))
            end do
        end do

    contains

        !> Append one named value.
        subroutine put(name, x)
            character(len=*), intent(in) :: name
            real(wp), intent(in) :: x

            i = i + 1
            v(i) = x
            names(i) = name
        end subroutine put

    end subroutine serialize

    !> The record of values in the order of `hb_fields`.
    function hb_from_values(v, npts, n, nfamily, nc) result(r)
        !> The values.
        real(wp), intent(in) :: v(:)
        !> Most branch points, sites, absorber family members, couplings.
        integer, intent(in) :: npts, n, nfamily, nc
        type(hb_record) :: r
        integer :: i, k, j

        r = empty_hb_record(npts, n, nfamily, nc)
        i = 0
        r%hb_scalars = hb_scalars_from_values(v)
        i = size(hb_scalars_names)
        do k = 1, nfamily
            r%absorber_folds(k) = take()
        end do
        do k = 1, nc
            r%continuum_folds(k) = take()
        end do
        do k = 1, hb_kept_multipliers
            r%multiplier_re(k) = take()
            r%multiplier_im(k) = take()
        end do
        do k = 1, npts
            do j = 1, size(hb_branch_quantities)
                r%branch(j, k) = take()
            end do
        end do
        do k = 1, n
            do j = 1, spectrum_harmonics
                r%spectrum(j, k) = take()
            end do
        end do

    contains

        !> The next value.
        real(wp) function take()
            i = i + 1
            take = v(i)
        end function take

    end function hb_from_values

    !> The controls of the harmonic-balance continuation from the scene's keys.
    pure function scene_controls(cfg) result(ctl)
        !> The validated input.
        type(input_config), intent(in) :: cfg
        type(hb_controls) :: ctl

        ctl%step = cfg%scene%continuation_step
        ctl%step_max = cfg%scene%continuation_step_max
        ctl%points_max = cfg%scene%continuation_points
        ctl%beyond_fold = cfg%scene%beyond_fold
        ctl%amplitude_max = cfg%scene%amplitude_max
        ctl%harmonics = cfg%scene%harmonics
        ctl%harmonics_max = cfg%scene%harmonics_max
        ctl%harmonics_tol = cfg%scene%harmonics_tol
        ctl%closure = cfg%scene%closure
        ctl%keep_states = cfg%scene%floquet_every > 0
    end function scene_controls

    !> Locate the fold of task `index` and what the scene adds to it (thread-safe: everything it changes is local).
    subroutine run_hb_task(self, index, values)
        !> The tasks.
        class(hb_fold_tasks), intent(in) :: self
        !> Task index.
        integer, intent(in) :: index
        !> The task's record as values.
        real(wp), intent(out) :: values(:)
        type(hb_record) :: r
        type(run_config) :: run
        type(hb_controls) :: ctl, quick
        type(hb_result) :: res, other
        type(chain_params) :: chain
        type(error_type), allocatable :: error
        integer :: m
        integer(i8) :: clock_start, clock_end, clock_rate
        real(wp) :: scale

        call system_clock(clock_start, clock_rate)
        run = self%task_run(index)
        r = empty_hb_record(self%cfg%scene%continuation_points, run%chain%n, self%cfg%scene%absorber_family, &
                            size(self%c_values))
        r%chain_n = run%chain%n
        r%chain_n0 = run%chain%n0
        r%chain_sigma = run%chain%sigma
        if (run%drive%omega < band_gap_edge(run%chain)) r%threshold_as = threshold_as(run%chain, run%drive%omega)
        if (run%drive%omega >= band_gap_edge(run%chain) .and. .not. self%cfg%allow_outside_gap) then
            r%status = status_outside_gap
            values = hb_to_values(r)
            return
        end if
        ctl = scene_controls(self%cfg)
        call hb_fold_converged(run%chain, run%drive%omega, ctl, res, error)
        r%status = res%status
        if (.not. allocated(error)) then
            call take_result(res, r)
            if (res%status == fold_found) then
                call check_in_time_domain(run, res, ctl%closure, self%cfg%scene%floquet_every > 0, r)
                if (self%cfg%scene%floquet_every > 0) call branch_stability(run, res, ctl%closure, &
                    self%cfg%scene%floquet_every, self%cfg%scene%crossing_tol, r)
            end if
        end if
        ! the checks need the fold alone, started from the K found
        quick = ctl
        quick%beyond_fold = 0
        quick%keep_states = .false.
        quick%harmonics = res%harmonics
        if (res%status == fold_found .and. size(r%absorber_folds) > 0) then
            do m = 1, size(r%absorber_folds)
                chain = run%chain
                chain%n = run%chain%n0 + (run%chain%n - run%chain%n0)*2**m
                chain%sigma = run%chain%sigma*real(2**m, wp)
                call fold_of(chain, r%absorber_folds(m))
            end do
            chain = run%chain
            chain%n = run%chain%n0
            quick%closure = closure_radiation
            call fold_of(chain, r%fold_radiation)
            quick%closure = ctl%closure
            r%fold_semi_infinite = r%absorber_folds(size(r%absorber_folds))
            r%absorber_spread = maxval(abs(r%absorber_folds - r%fold_amplitude))
        end if
        if (res%status == fold_found .and. size(self%c_values) > 0) then
            do m = 1, size(self%c_values)
                scale = self%c_values(m)/run%chain%c
                chain = run%chain
                chain%c = self%c_values(m)
                chain%n = nint(real(run%chain%n, wp)*scale)
                chain%n0 = nint(real(run%chain%n0, wp)*scale)
                chain%sigma = run%chain%sigma*scale
                quick%harmonics = 0
                call fold_of(chain, r%continuum_folds(m))
            end do
            call extrapolate_continuum(self%c_values, r%continuum_folds, r%continuum_fold, r%continuum_error)
        end if
        call system_clock(clock_end)
        r%wall_time = real(clock_end - clock_start, wp)/real(clock_rate, wp)
        values = hb_to_values(r)

    contains

        !> The fold of another chain, its cost added to the record.
        subroutine fold_of(other_chain, fold)
            type(chain_params), intent(in) :: other_chain
            real(wp), intent(out) :: fold

            call hb_fold_converged(other_chain, run%drive%omega, quick, other, error)
            fold = ieee_value(fold, ieee_quiet_nan)
            if (allocated(error)) return
            if (other%status == fold_found) fold = other%fold_amplitude
            r%newton_iterations = r%newton_iterations + other%newton_iterations
            r%factorizations = r%factorizations + other%factorizations
            r%residuals = r%residuals + other%residuals
            r%continuations = r%continuations + other%continuations
        end subroutine fold_of

    end subroutine run_hb_task

    !> The continuation's result into the record: the fold, its truncation estimate, counts, branch and spectrum.
    subroutine take_result(res, r)
        !> The result.
        type(hb_result), intent(in) :: res
        !> The record.
        type(hb_record), intent(inout) :: r
        integer :: np

        r%fold_amplitude = res%fold_amplitude
        r%fold_residual = res%fold_residual
        r%harmonics = res%harmonics
        r%harmonics_error = res%harmonics_error
        r%newton_iterations = res%newton_iterations
        r%factorizations = res%factorizations
        r%residuals = res%residuals
        r%continuations = res%continuations
        np = min(res%points, size(r%branch, 2))
        r%points = np
        r%branch(1:size(res%branch, 1), 1:np) = res%branch(:, 1:np)
    end subroutine take_result

    !> The state at the fold in the time domain: its spectrum, max |u|, max |u_{N0}|, one rk8 period from it (its
    !> closure) and, with `multipliers`, the rk8 Floquet multipliers there.
    subroutine check_in_time_domain(run, res, closure, multipliers, r)
        !> The task's run (chain, Omega, &numerics dt).
        type(run_config), intent(in) :: run
        !> The harmonic-balance fold.
        type(hb_result), intent(in) :: res
        !> The closure used.
        integer, intent(in) :: closure
        !> Whether to compute the multipliers.
        logical, intent(in) :: multipliers
        !> The record.
        type(hb_record), intent(inout) :: r
        type(hb_system) :: sys
        type(run_config) :: rk
        type(period_map) :: map
        type(error_type), allocatable :: error
        real(wp), allocatable :: amp(:, :), u(:), ut(:), x(:), px(:), jac(:, :), wr(:), wi(:)
        real(wp) :: t, excess
        integer :: n, status, info, i, m, j, kk
        integer, allocatable :: order(:)

        n = run%chain%n
        call hb_init(sys, run%chain, run%drive%omega, res%harmonics, closure, error)
        if (allocated(error)) return
        allocate (amp(res%harmonics, n), u(n), ut(n))
        call hb_spectrum(sys, res%fold_state, amp)
        kk = min(spectrum_harmonics, res%harmonics)
        r%spectrum(1:kk, :) = amp(1:kk, :)
        r%fold_umax = 0.0_wp
        r%far_field_umax = 0.0_wp
        m = 8*res%harmonics                               ! |u| sampled finer than the harmonics' wavelength
        do i = 0, m - 1
            t = real(i, wp)*pi/(run%drive%omega*real(m, wp))
            call hb_time_state(sys, res%fold_state, t, u, ut)
            r%fold_umax = max(r%fold_umax, maxval(abs(u)))
            if (run%chain%n0 >= 1 .and. run%chain%n0 <= n) r%far_field_umax = max(r%far_field_umax, abs(u(run%chain%n0)))
        end do
        if (closure /= closure_absorber) return           ! the time domain knows only the fixed end
        rk = run
        rk%numerics%method = method_rk8
        call period_map_init(map, rk, error)
        if (allocated(error)) return
        call hb_time_state(sys, res%fold_state, 0.0_wp, u, ut)
        x = [u, ut]
        allocate (px(2*n))
        if (multipliers) then
            allocate (jac(2*n, 2*n))
            call map%apply(x, res%fold_amplitude, px, status, jac=jac)
        else
            call map%apply(x, res%fold_amplitude, px, status)
        end if
        if (status /= map_ok) return
        r%period_closure = maxval(abs(px - x))
        if (.not. multipliers) return
        call floquet_multipliers(jac, wr, wi, info)
        if (info /= 0) return
        order = sorted_by_modulus(wr, wi)
        do j = 1, min(hb_kept_multipliers, size(order))
            r%multiplier_re(j) = wr(order(j))
            r%multiplier_im(j) = wi(order(j))
        end do
        ! the fold's own multiplier is the real one nearest +1; the rest say whether the fold's state is stable
        excess = -huge(1.0_wp)
        i = minloc(abs(cmplx(wr, wi, wp) - 1.0_wp), 1)
        do j = 1, size(wr)
            if (j /= i) excess = max(excess, hypot(wr(j), wi(j)) - 1.0_wp)
        end do
        r%multiplier_excess = excess
    end subroutine check_in_time_domain

    !> The stability of the branch below the fold: the rk8 multipliers (monodromy from each point's state) at every
    !> `every`-th branch point and at the last point before the fold, into the branch's `multiplier_max` and `stable`
    !> rows; the first sampled point that is not stable (a multiplier beyond 1 + `crossing_tol`) and the last stable
    !> one below it bracket the first loss of stability, typed by its leading multiplier.
    subroutine branch_stability(run, res, closure, every, crossing_tol, r)
        !> The task's run (chain, Omega, &numerics dt).
        type(run_config), intent(in) :: run
        !> The harmonic-balance branch with its states.
        type(hb_result), intent(in) :: res
        !> The closure used (the time domain knows only the fixed end).
        integer, intent(in) :: closure
        !> Stride of the sampled points.
        integer, intent(in) :: every
        !> How far beyond the unit circle a multiplier must be to count.
        real(wp), intent(in) :: crossing_tol
        !> The record.
        type(hb_record), intent(inout) :: r
        type(hb_system) :: sys
        type(run_config) :: rk
        type(period_map) :: map
        type(error_type), allocatable :: error
        real(wp), allocatable :: u(:), ut(:), x(:), px(:), jac(:, :), wr(:), wi(:)
        real(wp) :: lower
        integer :: n, p, status, info, qs, qm, last

        if (closure /= closure_absorber .or. .not. allocated(res%states) .or. res%fold_point < 3) return
        n = run%chain%n
        call hb_init(sys, run%chain, run%drive%omega, res%branch_harmonics, closure, error)
        if (allocated(error)) return
        rk = run
        rk%numerics%method = method_rk8
        call period_map_init(map, rk, error)
        if (allocated(error)) return
        allocate (u(n), ut(n), px(2*n), jac(2*n, 2*n))
        qm = size(hb_branch_quantities) - 1
        qs = size(hb_branch_quantities)
        last = res%fold_point - 1
        lower = 0.0_wp                                    ! rest is stable
        do p = 2, last
            if (mod(p - 1, every) /= 0 .and. p /= last) cycle
            call hb_time_state(sys, res%states(1:sys%dim, p), 0.0_wp, u, ut)
            x = [u, ut]
            call map%apply(x, res%states(sys%dim + 1, p), px, status, jac=jac)
            if (status /= map_ok) cycle
            call floquet_multipliers(jac, wr, wi, info)
            if (info /= 0) cycle
            r%branch(qm, p) = largest_modulus(wr, wi)
            r%branch(qs, p) = merge(1.0_wp, 0.0_wp, is_stable(wr, wi, crossing_tol))
            if (r%branch(qs, p) > 0.5_wp) then
                if (ieee_is_nan(r%instability_amplitude)) lower = res%states(sys%dim + 1, p)
            else if (ieee_is_nan(r%instability_amplitude)) then
                r%instability_amplitude = res%states(sys%dim + 1, p)
                r%instability_lower = lower
                r%instability_type = leading_crossing(wr, wi, crossing_tol)
            end if
        end do
    end subroutine branch_stability

    !> Indices of the multipliers by decreasing modulus.
    pure function sorted_by_modulus(wr, wi) result(order)
        !> Real and imaginary parts.
        real(wp), intent(in) :: wr(:), wi(:)
        integer, allocatable :: order(:)
        logical :: used(size(wr))
        integer :: j, best

        allocate (order(size(wr)))
        used = .false.
        do j = 1, size(wr)
            best = maxloc(hypot(wr, wi), 1, mask=.not. used)
            order(j) = best
            used(best) = .true.
        end do
    end function sorted_by_modulus

    !> The folds at the couplings c_values extrapolated to c -> infinity in 1/c^2 (Richardson from the two largest
    !> c); the error estimate is the change from the extrapolation of the next pair, or with two couplings the
    !> change from the largest c's fold.
    pure subroutine extrapolate_continuum(c, folds, limit, estimate)
        !> The couplings (ascending).
        real(wp), intent(in) :: c(:)
        !> The folds there.
        real(wp), intent(in) :: folds(:)
        !> The extrapolation; NaN with fewer than two couplings.
        real(wp), intent(out) :: limit
        !> Its error estimate.
        real(wp), intent(out) :: estimate
        integer :: m

        m = size(c)
        limit = ieee_value(limit, ieee_quiet_nan)
        estimate = limit
        if (m < 2) return
        limit = pair(m - 1, m)
        if (m >= 3) then
            estimate = abs(limit - pair(m - 2, m - 1))
        else
            estimate = abs(limit - folds(m))
        end if

    contains

        !> Richardson in 1/c^2 from couplings i and j.
        pure real(wp) function pair(i, j)
            integer, intent(in) :: i, j

            pair = (c(j)**2*folds(j) - c(i)**2*folds(i))/(c(j)**2 - c(i)**2)
        end function pair

    end subroutine extrapolate_continuum

    !> Estimated cost of task `index`: (first K)^3 N, so that the engine runs the low frequencies first.
    pure function hb_task_cost(self, index) result(cost)
        !> The tasks.
        class(hb_fold_tasks), intent(in) :: self
        !> Task index.
        integer, intent(in) :: index
        real(wp) :: cost
        type(run_config) :: run

        run = self%task_run(index)
        cost = 0.0_wp
        if (run%drive%omega >= band_gap_edge(run%chain) .and. .not. self%cfg%allow_outside_gap) return
        cost = real(run%chain%n, wp)*max(3.0_wp, 3.0_wp/run%drive%omega)**3
    end function hb_task_cost

    !> The number of folds found, and the wall time.
    function hb_summary(cfg, tasks) result(text)
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> The tasks' records.
        type(scene_tasks), intent(in) :: tasks
        character(len=:), allocatable :: text
        type(hb_scalars) :: r
        integer :: i, found

        found = 0
        do i = 1, size(tasks%done)
            r = hb_scalars_from_values(tasks%results(:, i))
            if (r%status == fold_found .and. tasks%done(i)) found = found + 1
        end do
        text = "  " // int_str(found) // " of " // int_str(size(tasks%done)) // " folds found by harmonic balance, " &
               // fixed1(tasks%elapsed) // " s, K up to " // int_str(cfg%scene%harmonics_max)
    end function hb_summary

    !> Write the scene's file `path` (built in memory, written atomically): tasks not done get NaN and status -1.
    subroutine write_hb_file(self, path, results, done, complete, elapsed, error)
        !> The tasks.
        class(hb_fold_tasks), intent(in) :: self
        !> Final path of the file.
        character(len=*), intent(in) :: path
        !> Results, (values, tasks).
        real(wp), intent(in) :: results(:, :)
        !> Which tasks are done.
        logical, intent(in) :: done(:)
        !> Whether this is the complete result.
        logical, intent(in) :: complete
        !> Wall time of the scene (s); negative when unknown.
        real(wp), intent(in) :: elapsed
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        type(h5_file) :: file
        type(hb_record), allocatable :: recs(:)
        real(wp), allocatable :: a4(:, :, :, :)
        integer :: ncurve, nomega, ntask, t, q, npts, n, nfam, nc

        ncurve = size(self%runs)
        nomega = size(self%omegas)
        ntask = ncurve*nomega
        npts = self%cfg%scene%continuation_points
        n = self%cfg%run%chain%n
        nfam = self%cfg%scene%absorber_family
        nc = size(self%c_values)
        allocate (recs(ntask))
        do t = 1, ntask
            if (done(t)) then
                recs(t) = hb_from_values(results(:, t), npts, n, nfam, nc)
            else
                recs(t) = empty_hb_record(npts, n, nfam, nc)
                recs(t)%status = status_not_run
            end if
        end do

        call h5_create(file, path, .true.)
        call write_root(file, self%cfg, "continuation", "Fold (saddle-node) of the branch of driven periodic " &
                        // "states of the ODE vs driving frequency by harmonic balance: the supratransmission " &
                        // "threshold of the model, one curve per potential and varied value", self%inv)
        call h5_write_attr(file, "/", "solver", "harmonic_balance")
        call h5_write_attr(file, "/", "complete", merge(1, 0, complete))
        call h5_write_attr(file, "/", "tasks_done", count(done))
        call write_parameters(file, self%cfg)
        call write_row(file, continuation_harmonic_balance_omega, self%omegas)
        call write_curves(file, self%cfg, self%runs)
        ! the datasets of the record's scalar fields and their groups: the output table's
        ! (continuation_harmonic_balance.toml)
        call write_hb_scalars(file, [recs%hb_scalars], nomega, nc > 0)
        call write_row_attr(file, continuation_harmonic_balance_status, "codes", "-2: outside gap (not computed); " &
            // "-1: pending (not computed yet); " // fold_status_codes())
        call write_row_attr(file, continuation_harmonic_balance_instability_type, "codes", instability_type_codes())
        if (elapsed >= 0.0_wp) call write_row_attr(file, continuation_harmonic_balance_cost, "scene_wall_time_s", &
                                                   elapsed)
        call write_row(file, continuation_harmonic_balance_outside_gap, reshape(merge(1, 0, &
            [(self%omegas(mod(t - 1, nomega) + 1) >= band_gap_edge(self%runs((t - 1)/nomega + 1)%chain), &
            t=1, ntask)]), [nomega, ncurve]))
        a4 = reshape([(transpose(recs(t)%spectrum), t=1, ntask)], [n, spectrum_harmonics, nomega, ncurve])
        call write_row(file, continuation_harmonic_balance_spectrum, a4, fill=[int_str(2*spectrum_harmonics - 1)])
        call write_row_group(file, continuation_harmonic_balance_multipliers)
        call write_row(file, continuation_harmonic_balance_multipliers_real, &
                       cube([(recs(t)%multiplier_re, t=1, ntask)], hb_kept_multipliers))
        call write_row(file, continuation_harmonic_balance_multipliers_imag, &
                       cube([(recs(t)%multiplier_im, t=1, ntask)], hb_kept_multipliers))
        if (nfam > 0) then
            call write_row(file, continuation_harmonic_balance_convergence_absorber_folds, &
                           cube([(recs(t)%absorber_folds, t=1, ntask)], nfam))
        end if
        if (nc > 0) then
            call write_row(file, continuation_harmonic_balance_continuum_c, self%c_values)
            call write_row(file, continuation_harmonic_balance_continuum_folds, &
                           cube([(recs(t)%continuum_folds, t=1, ntask)], nc))
        end if
        do q = 1, size(hb_branch_quantities)
            call write_row(file, branch_row(q), cube([(recs(t)%branch(q, :), t=1, ntask)], npts))
        end do
        call h5_commit(file, error)

    contains

        !> Per-task vectors of length m, task after task (task t = (curve - 1) nomega + omega), as an (m, omega, curve)
        !> array: h5py (curve, omega, m).
        pure function cube(x, m) result(c)
            real(wp), intent(in) :: x(:)
            integer, intent(in) :: m
            real(wp), allocatable :: c(:, :, :)

            c = reshape(x, [m, nomega, ncurve])
        end function cube

    end subroutine write_hb_file

    !> The row of `/branch/<quantity>` of a branch quantity (its units and description:
    !> continuation_harmonic_balance.toml).
    pure function branch_row(q) result(row)
        !> Index in `hb_branch_quantities`.
        integer, intent(in) :: q
        type(output_row) :: row

        select case (trim(hb_branch_quantities(q)))
        case ("amplitude")
            row = continuation_harmonic_balance_branch_amplitude
        case ("umax")
            row = continuation_harmonic_balance_branch_umax
        case ("energy")
            row = continuation_harmonic_balance_branch_energy
        case ("newton_iterations")
            row = continuation_harmonic_balance_branch_newton_iterations
        case ("multiplier_max")
            row = continuation_harmonic_balance_branch_multiplier_max
        case ("stable")
            row = continuation_harmonic_balance_branch_stable
        case default
            row = continuation_harmonic_balance_branch_residual
        end select
    end function branch_row

end module supratrans_fold_hb
