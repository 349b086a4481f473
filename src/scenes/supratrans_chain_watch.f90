!> The driven chain watched with the one-period map of a fold line's run: the fate of a drive just past a fold (or a
!> branch point), the stairs past a loss of stability, the damped Newton-shooting from where the chain settled and
!> the half-period symmetry of a periodic state (used by `supratrans_fold_fate`, which decides from them where the
!> chain transmits).
!>
!> **The fold's fate** (`fold_fate`). A fold is the supratransmission threshold only if the chain, driven just past
!> it, transmits. Near Omega = 1/(2k + 1), where an odd harmonic of the drive sits at the lower edge of the phonon
!> band, the branch can fold far below the scan's threshold (e.g. A_f = 1.78 at Omega = 0.34 on the paper's chain,
!> where the scan gives 4.66): such a fold depends on the chain's length and absorber (docs/continuation.md) and the
!> state beyond it need not transmit. So each fold is tested: the periodic state at the fold is driven at
!> A_f (1 + `fate_push`) at full amplitude for `fate_watch_time` (at least `fate_min_periods` periods) with the
!> one-period map of the same scheme, and it transmits when, at any time level, an oscillator beyond the run's
!> detector site (`detector_site`, the scan's own) has |u_n| > the detector amplitude (pi by default), as a run's
!> detector sees it. (Looking at the ends of the periods only, the stairs of a damped chain, gamma = 0.3 at
!> Omega = 0.55, transmitted at 7.45, where a slow-ramp scan transmits at 5.21.)
!>
!> **Stairs** (`climb_stairs`). Where no stable periodic state is there to be followed, the chain is driven up in
!> stairs of `stair_height`, each held `stair_time`, with the same detector, as a slow ramp would go on.
module supratrans_chain_watch
    use supratrans_kinds, only: wp
    use supratrans_config, only: run_config, fold_protocol
    use supratrans_strings, only: int_str, real_str
    use supratrans_period_map, only: period_map, set_half_period
    use supratrans_fixed_point_map, only: map_ok
    use supratrans_dense, only: dense_solve
    use supratrans_chain, only: detector_site
    use supratrans_continuation_types, only: continuation_stats, wall_clock
    implicit none
    private

    public :: fold_fate, fate_codes, climb_stairs, damped_shooting, half_period_symmetric

    !> Fate of a fold: not computed (no fold).
    integer, parameter, public :: fate_not_computed = 0
    !> Fate of a fold: driven just past it, the chain transmits (the fold is the supratransmission threshold).
    integer, parameter, public :: fate_transmits = 1
    !> Fate of a fold: driven just past it for `fate_watch_time`, the chain stays localized (it settles on another
    !> state: the fold is not where transmission starts).
    integer, parameter, public :: fate_localized = 2
    !> Fate of a fold: the one-period map failed while watching (its implicit steps did not converge).
    integer, parameter, public :: fate_failed = 3
    ! The protocol's constants are input keys (`fold_protocol`, &scene fate_push, fate_watch_time, fate_min_periods,
    ! settle_iterations, settle_tol, symmetric_tol, fold_stair_height, fold_stair_time), so /parameters records them.
    ! (Stairs held 1000 time units, as long as a fate is watched, transmit 0.01 .. 0.22 lower on the paper grid's fold
    ! line at all 17 frequencies with stairs than with the default 200, for 1.24 times the task time:
    ! docs/continuation.md.)

contains

    !> The chain driven from `y` (where the drive before left it) up in stairs a0 + k `stair_height`, k = 1, 2, ...,
    !> below `top`, each held `stair_time` (whole periods) with the fate's detector. `fate_transmits`: on the stair
    !> `a`; `fate_localized`: no stair below `top` transmits (`y` the last stair's state, `a` its amplitude, a0 when
    !> there was none); `fate_failed`: the scheme failed on the stair `a`. The maps are added to `stats`.
    subroutine climb_stairs(map, run, proto, y, a0, top, a, fate, stats)
        !> The one-period map P.
        type(period_map), intent(inout) :: map
        !> The run (detector).
        type(run_config), intent(in) :: run
        !> The fold protocol (stair height and time, the fate's watch).
        type(fold_protocol), intent(in) :: proto
        !> The chain's state: in, at the start; out, at the end of the last stair held without transmission.
        real(wp), allocatable, intent(inout) :: y(:)
        !> The amplitude the chain was driven at before (the stairs start one step above it).
        real(wp), intent(in) :: a0
        !> The stairs stay below it.
        real(wp), intent(in) :: top
        !> The last stair's amplitude.
        real(wp), intent(out) :: a
        !> `fate_transmits`, `fate_localized` or `fate_failed`.
        integer, intent(out) :: fate
        !> Counts and times: the maps applied are added.
        type(continuation_stats), intent(inout) :: stats
        real(wp), allocatable :: last(:)
        real(wp) :: time
        integer :: k

        a = a0
        fate = fate_localized
        k = 1
        do while (a0 + real(k, wp)*proto%stair_height < top)
            a = a0 + real(k, wp)*proto%stair_height
            call fold_fate(map, run, proto, y, a, fate, time, last, watch=proto%stair_time, stats=stats)
            if (fate /= fate_localized) return
            call move_alloc(last, y)
            k = k + 1
        end do
    end subroutine climb_stairs

    !> Whether x is a periodic state with the half-period symmetry, G(x) = x to `symmetric_tol` (M even); if so,
    !> `map` is left as the half-period map G, else as P.
    function half_period_symmetric(map, proto, x, amplitude) result(yes)
        !> The one-period map (P on entry).
        type(period_map), intent(inout) :: map
        !> The fold protocol (`symmetric_tol`).
        type(fold_protocol), intent(in) :: proto
        !> The state.
        real(wp), intent(in) :: x(:)
        !> Drive amplitude.
        real(wp), intent(in) :: amplitude
        logical :: yes
        real(wp), allocatable :: gx(:)
        integer :: status
        logical :: ok

        call set_half_period(map, .true., yes)
        if (.not. yes) return
        allocate (gx(size(x)))
        call map%apply(x, amplitude, gx, status)
        yes = status == map_ok
        if (yes) yes = maxval(abs(gx - x)) <= proto%symmetric_tol
        if (.not. yes) call set_half_period(map, .false., ok)
    end function half_period_symmetric

    !> Newton-shooting with backtracking from where the chain settled (`x`, not yet periodic: the modes trapped
    !> between the drive and the absorber ring for long) towards the periodic state nearby: each full Newton step
    !> is halved (down to 1/64) until it lowers max |P(x) - x|, so that the first steps, made large by the
    !> multipliers near +1, do not throw x far away. At most `settle_iterations` steps; `x` is the periodic state
    !> when max |P(x) - x| <= `settle_tol` was reached, else left as it came (the continuation's own, undamped
    !> shooting then has its try, and gives up once its residual has grown tenfold: `follow_growth_limit` of
    !> `supratrans_fold_fate`).
    subroutine damped_shooting(map, proto, x, amplitude, stats)
        !> The one-period map.
        type(period_map), intent(inout) :: map
        !> The fold protocol (`settle_iterations`, `settle_tol`).
        type(fold_protocol), intent(in) :: proto
        !> The state: in, where the chain settled; out, the best iterate.
        real(wp), intent(inout) :: x(:)
        !> Drive amplitude.
        real(wp), intent(in) :: amplitude
        !> Counts and times: its maps, Jacobians and factorisations are added.
        type(continuation_stats), intent(inout) :: stats
        real(wp), allocatable :: px(:), jac(:, :), dx(:), trial(:), y(:)
        real(wp) :: residual, t, r_trial, t0
        integer :: it, i, status, info

        allocate (px(size(x)), jac(size(x), size(x)), trial(size(x)))
        y = x
        call apply(y, status)
        if (status /= map_ok) return
        residual = maxval(abs(px - y))
        do it = 1, proto%settle_iterations
            if (residual <= proto%settle_tol) then
                x = y
                return
            end if
            t0 = wall_clock()
            call map%apply(y, amplitude, px, status, jac=jac)
            stats%jacobian_evaluations = stats%jacobian_evaluations + 1
            stats%time_jacobian = stats%time_jacobian + wall_clock() - t0
            if (status /= map_ok) return
            do i = 1, size(y)
                jac(i, i) = jac(i, i) - 1.0_wp
            end do
            dx = y - px
            t0 = wall_clock()
            call dense_solve(jac, dx, info)
            stats%factorisations = stats%factorisations + 1
            stats%time_lu = stats%time_lu + wall_clock() - t0
            if (info /= 0) return
            t = 1.0_wp
            do
                trial = y + t*dx
                call apply(trial, status)
                r_trial = huge(1.0_wp)
                if (status == map_ok) r_trial = maxval(abs(px - trial))
                if (r_trial < residual .or. t <= 1.0_wp/64.0_wp) exit
                t = 0.5_wp*t
            end do
            if (.not. (r_trial < residual)) return
            y = trial
            residual = r_trial
        end do
        if (residual <= proto%settle_tol) x = y

    contains

        !> px = P(z), counted.
        subroutine apply(z, status)
            real(wp), intent(in) :: z(:)
            integer, intent(out) :: status
            real(wp) :: t1

            t1 = wall_clock()
            call map%apply(z, amplitude, px, status)
            stats%map_evaluations = stats%map_evaluations + 1
            stats%time_map = stats%time_map + wall_clock() - t1
        end subroutine apply

    end subroutine damped_shooting

    !> The fate of a fold (see the module's documentation): from the periodic state `x` at the fold, the drive at
    !> `amplitude` (just past the fold), one period at a time, until an oscillator beyond the detector site swings
    !> past the detector amplitude (`fate_transmits`, `time` = the end of that period) or `fate_watch_time` has
    !> passed (`fate_localized`, `time` = the time watched), or `watch` (whole periods, at least one) when given.
    subroutine fold_fate(map, run, proto, x, amplitude, fate, time, last, watch, stats)
        !> The one-period map of the branch (its work arrays change).
        type(period_map), intent(inout) :: map
        !> The run (detector site and amplitude).
        type(run_config), intent(in) :: run
        !> The fold protocol (`fate_watch_time`, `fate_min_periods`).
        type(fold_protocol), intent(in) :: proto
        !> The state at the fold (u_n at t = 0 first, n = 1..N).
        real(wp), intent(in) :: x(:)
        !> Drive amplitude just past the fold.
        real(wp), intent(in) :: amplitude
        !> `fate_transmits`, `fate_localized` or `fate_failed`.
        integer, intent(out) :: fate
        !> Time of the first transmission, or the time watched.
        real(wp), intent(out) :: time
        !> The state at the end of the watch (where the chain has settled when it stays localized).
        real(wp), allocatable, intent(out), optional :: last(:)
        !> Time to watch instead of `fate_watch_time` (and no fewest periods but one).
        real(wp), intent(in), optional :: watch
        !> Counts and times: the maps applied and their time are added.
        type(continuation_stats), intent(inout), optional :: stats
        real(wp), allocatable :: y(:), py(:)
        real(wp) :: t0
        integer :: k, periods, nd, status

        t0 = wall_clock()
        nd = detector_site(run)
        periods = max(proto%fate_min_periods, ceiling(proto%fate_watch_time/map%period))
        if (present(watch)) periods = max(1, ceiling(watch/map%period))
        y = x
        allocate (py(size(x)))
        fate = fate_localized
        ! the detector sees every level of every period (`watch_site`), as a run's does
        map%watch_site = nd
        do k = 1, periods
            call map%apply(y, amplitude, py, status)
            time = real(k, wp)*map%period
            if (status /= map_ok) then
                fate = fate_failed
                exit
            end if
            ! (beyond_max covers the levels 0..M, the end state's u = py(1:N) among them)
            if (map%beyond_max > run%detect%amplitude) then
                fate = fate_transmits
                exit
            end if
            y = py
        end do
        map%watch_site = 0
        if (present(stats)) then
            stats%map_evaluations = stats%map_evaluations + min(k, periods)
            stats%time_map = stats%time_map + wall_clock() - t0
        end if
        if (fate == fate_localized .and. present(last)) last = y
    end subroutine fold_fate

    !> The fates of a fold as "code name: meaning" clauses (the `codes` attribute of /fold_fate).
    pure function fate_codes(proto) result(text)
        !> The fold protocol (`fate_push`).
        type(fold_protocol), intent(in) :: proto
        character(len=:), allocatable :: text

        text = int_str(fate_not_computed) // " none: no fold; " // int_str(fate_transmits) // " transmits: driven " &
            // "at A_f (1 + " // real_str(proto%fate_push, 3) // ") from the fold's state, an oscillator beyond the " &
            // "detector site passes the detector amplitude (the fold is the supratransmission threshold); " &
            // int_str(fate_localized) // " localized: no transmission within /fold_fate_time (the chain " &
            // "settles on another state: the fold is not where transmission starts); " // int_str(fate_failed) &
            // " failed: the scheme's implicit step did not converge"
    end function fate_codes

end module supratrans_chain_watch
