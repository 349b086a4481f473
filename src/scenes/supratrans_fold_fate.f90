!> The fate of a fold of a fold line (`supratrans_fold_line`), and the branches the chain is followed to past a fold
!> where it stays localized (`follow_to_transmission`), up to the fold past which it transmits.
!>
!> **The fold's fate** (`fold_fate`). A fold is the supratransmission threshold only if the chain, driven just past
!> it, transmits. Near Omega = 1/(2k + 1), where an odd harmonic of the drive sits at the lower edge of the phonon
!> band, the branch can fold far below the scan's threshold (e.g. A_f = 1.78 at Omega = 0.34 on the paper's chain,
!> where the scan gives 4.66): such a fold depends on the chain's length and absorber (docs/continuation.md) and the
!> state beyond it need not transmit. So each fold is tested: the periodic state at the fold is driven at
!> A_f (1 + `fate_push`) at full amplitude for `fate_watch_time` (at least `fate_min_periods` periods) with the
!> one-period map of the same scheme, and it transmits when, at the end of a period, an oscillator beyond the
!> run's detector site (`detector_site`, the scan's own) has |u_n| > the detector amplitude (pi by default).
!>
!> **Following the chain past a localized fold.** The state it settled on is brought to a periodic state by
!> Newton-shooting with backtracking (`damped_shooting`), its branch is continued in A to its own fold (on the
!> half-period map when that state has the half-period symmetry, `half_period_symmetric`), and that fold's fate is
!> tested in turn, up to `max_branches` branches.
module supratrans_fold_fate
    use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
    use supratrans_kinds, only: wp
    use supratrans_config, only: run_config
    use supratrans_strings, only: int_str, real_str
    use supratrans_period_map, only: period_map, set_half_period
    use supratrans_fixed_point_map, only: map_ok
    use supratrans_dense, only: dense_solve
    use supratrans_chain, only: detector_site
    use supratrans_continuation_types, only: wall_clock
    use supratrans_continuation, only: continue_branch, continuation_controls, continuation_result, continuation_stats, &
                                       cont_fold_found, cont_no_fold, cont_newton_failed, cont_step_too_small, &
                                       cont_max_points, cont_unstable_start
    use supratrans_fold_record, only: fold_record
    use supratrans_continuation_corrector, only: branch_point
    use supratrans_branch_switch, only: switch_branch
    implicit none
    private

    public :: fold_fate, fate_codes, transmission_status_codes, half_period_symmetric, follow_to_transmission, &
              add_branch_cost, add_stats, past_branch_point, branch_switch_codes, transmission_after, past_oscillatory_loss

    !> Fate of a fold: not computed (no fold).
    integer, parameter, public :: fate_not_computed = 0
    !> Fate of a fold: driven just past it, the chain transmits (the fold is the supratransmission threshold).
    integer, parameter, public :: fate_transmits = 1
    !> Fate of a fold: driven just past it for `fate_watch_time`, the chain stays localized (it settles on another
    !> state: the fold is not where transmission starts).
    integer, parameter, public :: fate_localized = 2
    !> Fate of a fold: the one-period map failed while watching (its implicit steps did not converge).
    integer, parameter, public :: fate_failed = 3
    !> Relative push past the fold: the fate is watched at A_f (1 + fate_push).
    real(wp), parameter, public :: fate_push = 1.0e-2_wp
    !> Time the pushed state is watched (in units of the model's time).
    real(wp), parameter, public :: fate_watch_time = 1000.0_wp
    !> Fewest drive periods the pushed state is watched.
    integer, parameter, public :: fate_min_periods = 20
    !> Most branches followed from rest to the fold past which the chain transmits (`follow_to_transmission`).
    integer, parameter, public :: max_branches = 4
    !> Why no transmission fold (beside the continuation's statuses of the last branch followed): the state Newton
    !> found where the chain settled is unstable.
    integer, parameter, public :: follow_unstable_start = cont_unstable_start
    !> Why no transmission fold: the chain stayed localized past the folds of `max_branches` branches.
    integer, parameter, public :: follow_too_many = 7
    !> Why no transmission fold: the scheme failed while the fate of a fold was watched.
    integer, parameter, public :: follow_fate_failed = 8
    !> Most damped Newton-shooting steps from where the chain settled (`damped_shooting`).
    integer, parameter :: settle_iterations = 30
    !> max |P(x) - x| at which `damped_shooting` stops (the continuation's own shooting polishes to newton_tol).
    real(wp), parameter :: settle_tol = 1.0e-9_wp
    !> max |G(x) - x| below which a settled periodic state counts as symmetric (its branch then continued on G).
    real(wp), parameter, public :: symmetric_tol = 1.0e-8_wp
    !> The Newton-shooting of a followed branch gives up when its residual grows this many times its first value.
    real(wp), parameter :: follow_growth_limit = 10.0_wp
    !> Branch switching (/branch_switch): no branch point below the fold.
    integer, parameter, public :: switch_none = 0
    !> Branch switching: the other branch leaves the branch point above it (followed to its fold).
    integer, parameter, public :: switch_supercritical = 1
    !> Branch switching: the other branch leaves the branch point below it (the chain driven past the branch point).
    integer, parameter, public :: switch_subcritical = 2
    !> Branch switching: the other branch was not found.
    integer, parameter, public :: switch_failed = 3
    !> Past a torus or a period doubling below the fold (no branch of periodic states to switch to): the chain driven
    !> from the loss's state up in stairs (`past_oscillatory_loss`).
    integer, parameter, public :: switch_stairs = 4
    !> Stairs past a torus or a period doubling: the amplitude step between two stairs (the scan's resolution).
    real(wp), parameter, public :: stair_height = 1.0e-2_wp
    !> Stairs past a torus or a period doubling: the time the chain is driven on each stair.
    real(wp), parameter, public :: stair_time = 200.0_wp
    !> Distance (Euclidean norm of (x, A)) of the other branch's first point from the branch point.
    real(wp), parameter, public :: switch_step = 5.0e-2_wp
    !> Past a subcritical branch point the chain is driven from the branch point's state moved this far along the
    !> other branch's direction (a small asymmetry, as a slow ramp leaves the symmetric state with one).
    real(wp), parameter, public :: switch_seed = 1.0e-3_wp

contains

    !> Add what a continuation cost (its counts and times) to the record's costs.
    pure subroutine add_branch_cost(r, res)
        !> The record.
        type(fold_record), intent(inout) :: r
        !> The continuation.
        type(continuation_result), intent(in) :: res

        r%newton_iterations = r%newton_iterations + sum(res%newton_iterations(1:res%n_points))
        call add_stats(r, res%stats)
    end subroutine add_branch_cost

    !> Add counts and times to the record's costs.
    pure subroutine add_stats(r, stats)
        !> The record.
        type(fold_record), intent(inout) :: r
        !> The counts and times.
        type(continuation_stats), intent(in) :: stats

        r%map_evaluations = r%map_evaluations + stats%map_evaluations + stats%jacobian_evaluations
        r%jacobians = r%jacobians + stats%jacobian_evaluations
        r%factorizations = r%factorizations + stats%factorisations
        r%eigen_calls = r%eigen_calls + stats%eigen_calls
        r%time_map = r%time_map + stats%time_map
        r%time_tangent = r%time_tangent + stats%time_jacobian
        r%time_lu = r%time_lu + stats%time_lu
        r%time_eigen = r%time_eigen + stats%time_eigen
    end subroutine add_stats

    !> Past a branch point below the fold (the first loss of stability of the branch from rest, a real multiplier
    !> through +1 where the branch does not turn; its point and the tangent next to it in `res`), where a slow ramp
    !> goes: the other branch is found (`switch_branch`, `switch_step` away; 4 `switch_step` when that fails, as from
    !> a branch point known only to its bracket it may). Where it leaves above the branch point
    !> (supercritical) the ramp follows it: it is continued to its fold, whose fate is tested, and so on
    !> (`follow_to_transmission`). Where it leaves below (subcritical; also where it does not leave above a branch
    !> point known only to its bracket, whose upper end A_b is: the label may then be wrong, the protocol holds for
    !> both kinds) nothing is near to follow: the chain is driven
    !> at A_b (1 + `fate_push`) from the branch point's state moved by `switch_seed` along the other branch's
    !> direction, and A_b is the transmission threshold when it transmits; where it stays localized, the chain is
    !> followed from where it settled. (Driven from the other branch's first point instead, the chain stayed
    !> localized at Omega = 0.44 on the paper's grid, where a slow ramp transmits just past the branch point.) Fills
    !> `r%branch_switch`, and `r%transmission_fold`, `r%branches`, `r%transmission_status`.
    subroutine past_branch_point(map, run, ctl, res, r)
        !> The one-period map P.
        type(period_map), intent(inout) :: map
        !> The run (detector).
        type(run_config), intent(in) :: run
        !> The continuation controls of the branch from rest.
        type(continuation_controls), intent(in) :: ctl
        !> The branch from rest, with `instability_point` and `instability_tangent`.
        type(continuation_result), intent(in) :: res
        !> The record.
        type(fold_record), intent(inout) :: r
        type(continuation_stats) :: stats
        type(branch_point) :: pt
        real(wp), allocatable :: e(:), settled(:)
        real(wp) :: a_b, time
        integer :: d, fate
        logical :: ok

        d = map%dim
        a_b = res%instability_point(d + 1)
        allocate (e(d + 1))
        r%branches = 1
        r%transmission_status = follow_fate_failed
        ! (from a branch point only bracketed, a longer step leaves the bracket's width less weight)
        call switch_branch(map, res%instability_point, res%instability_tangent, [switch_step, 4.0_wp*switch_step], ctl, &
                           pt, e, ok, stats)
        call add_stats(r, stats)
        r%newton_iterations = r%newton_iterations + pt%iterations
        if (.not. ok) then
            r%branch_switch = switch_failed
            r%transmission_status = cont_newton_failed
            return
        end if
        if (pt%y(d + 1) > a_b) then
            r%branch_switch = switch_supercritical
            call follow_to_transmission(map, run, ctl, pt%y(1:d), pt%y(d + 1), r)
            return
        end if
        r%branch_switch = switch_subcritical
        stats = continuation_stats()
        call fold_fate(map, run, res%instability_point(1:d) + switch_seed*e(1:d), a_b*(1.0_wp + fate_push), fate, time, &
                       settled, stats=stats)
        call add_stats(r, stats)
        call transmission_after(map, run, ctl, a_b, fate, settled, r)
    end subroutine past_branch_point

    !> Past a torus or a period doubling below the fold (the first loss of stability of the branch from rest, located:
    !> `res%instability_point`), where a slow ramp goes: no branch of periodic states leaves there to be followed,
    !> the chain goes onto a quasi-periodic (or period-2T) state, and how far it goes on it before it transmits is
    !> found by driving it. From the loss's state, moved by `switch_seed` (a fixed direction), the drive goes up in
    !> stairs a_k = A_t + k `stair_height` below the fold, each held `stair_time` (whole periods, `fold_fate` with the
    !> detector); `/transmission_fold` is the first stair where the chain transmits. Where none does, the chain is
    !> driven 1% past the fold from the last stair's state (`transmission_after`: the fold, or followed; NaN, status
    !> `cont_no_fold`, where the branch has no fold below amplitude_max, which bounds the stairs then). No stair
    !> lies below the fold (`done` false: the caller tests the fold's fate as without the loss) where the loss is
    !> less than `stair_height` below it. (On the paper's grid at Omega = 0.35 .. 0.38 the stairs of the hysteresis
    !> scene, 200 .. 800 time units long, transmit within 0.04 of each other: docs/continuation.md.)
    subroutine past_oscillatory_loss(map, run, ctl, res, fold, r, done)
        !> The one-period map P.
        type(period_map), intent(inout) :: map
        !> The run (detector).
        type(run_config), intent(in) :: run
        !> The continuation controls of the branch from rest.
        type(continuation_controls), intent(in) :: ctl
        !> The branch from rest, with `instability_point`.
        type(continuation_result), intent(in) :: res
        !> The fold of the branch from rest (NaN: none below amplitude_max, which then bounds the stairs).
        real(wp), intent(in) :: fold
        !> The record.
        type(fold_record), intent(inout) :: r
        !> Whether the stairs ran (and filled `r%transmission_fold`, `r%branches`, `r%transmission_status`).
        logical, intent(out) :: done
        type(continuation_stats) :: watched
        real(wp), allocatable :: y(:), last(:)
        real(wp) :: a_t, top, a, time
        integer :: d, k, fate

        d = map%dim
        a_t = res%instability_point(d + 1)
        top = fold
        if (ieee_is_nan(top)) top = ctl%amplitude_max
        done = a_t + stair_height < top
        if (.not. done) return
        r%branch_switch = switch_stairs
        r%branches = 1
        r%transmission_status = follow_fate_failed
        y = seeded(res%instability_point(1:d))
        k = 1
        do
            a = a_t + real(k, wp)*stair_height
            if (a >= top) exit
            call fold_fate(map, run, y, a, fate, time, last, watch=stair_time, stats=watched)
            if (fate /= fate_localized) then
                call add_stats(r, watched)
                if (fate == fate_transmits) r%transmission_fold = a
                if (fate == fate_transmits) r%transmission_status = cont_fold_found
                return
            end if
            call move_alloc(last, y)
            k = k + 1
        end do
        if (ieee_is_nan(fold)) then
            call add_stats(r, watched)
            r%transmission_status = cont_no_fold
            return
        end if
        call fold_fate(map, run, y, top*(1.0_wp + fate_push), fate, time, last, stats=watched)
        call add_stats(r, watched)
        call transmission_after(map, run, ctl, top, fate, last, r)
    end subroutine past_oscillatory_loss

    !> x moved by `switch_seed` along the fixed unit direction (sin i)_i: the small asymmetry a slow ramp leaves.
    pure function seeded(x) result(y)
        !> The state.
        real(wp), intent(in) :: x(:)
        real(wp), allocatable :: y(:)
        real(wp), allocatable :: s(:)
        integer :: i

        s = [(sin(real(i, wp)), i=1, size(x))]
        y = x + (switch_seed/norm2(s))*s
    end function seeded

    !> Where the chain transmits, from the fate of a drive just past the amplitude `a` (a fold, or a branch point):
    !> `a` itself when it transmits; the fold of the branch it settled on, or a later one (`follow_to_transmission`),
    !> when it stays localized; nothing when the watch failed (the caller's status stands).
    subroutine transmission_after(map, run, ctl, a, fate, settled, r)
        !> The one-period map.
        type(period_map), intent(inout) :: map
        !> The run (detector).
        type(run_config), intent(in) :: run
        !> The continuation controls of the branch from rest.
        type(continuation_controls), intent(in) :: ctl
        !> The amplitude driven just past (by `fate_push`).
        real(wp), intent(in) :: a
        !> The fate (`fold_fate`) of that drive.
        integer, intent(in) :: fate
        !> Where the chain was at the end of the watch (allocated where it stayed localized).
        real(wp), allocatable, intent(in) :: settled(:)
        !> The record.
        type(fold_record), intent(inout) :: r

        if (fate == fate_transmits) then
            r%transmission_fold = a
            r%transmission_status = cont_fold_found
        else if (fate == fate_localized) then
            call follow_to_transmission(map, run, ctl, settled, a*(1.0_wp + fate_push), r)
        end if
    end subroutine transmission_after

    !> The codes of /branch_switch as "code name: meaning" clauses.
    pure function branch_switch_codes() result(text)
        character(len=:), allocatable :: text

        text = int_str(switch_none) // " none: no branch point below the fold (or no fate asked); " &
            // int_str(switch_supercritical) // " supercritical: the other branch leaves above the branch point and " &
            // "is followed (/transmission_fold is its fold, or a later one); " // int_str(switch_subcritical) &
            // " subcritical: it leaves below (or not above a branch point known only to its bracket, " &
            // "/instability_lower); driven 1% past the branch point, the chain transmits " &
            // "(/transmission_fold is the branch point) or settles and is followed; " // int_str(switch_failed) &
            // " failed: the other branch was not found; " // int_str(switch_stairs) // " stairs: past a torus or " &
            // "a period doubling below the fold (no branch of periodic states to switch to), the chain is driven " &
            // "from the loss's state (moved by " // real_str(switch_seed, 3) // ") up in stairs of " &
            // real_str(stair_height, 3) // " held " // real_str(stair_time, 4) // " time units each; " &
            // "/transmission_fold is the first stair where it transmits (the one below it did not), or where " &
            // "none does below the fold, as past the fold from the last stair's state"
    end function branch_switch_codes

    !> Past a fold where the chain stays localized, the branch it settles on: from the `settled` state at amplitude
    !> `a` (Newton-shooting first), continued in A to its own fold, whose fate is tested in turn, up to
    !> `max_branches` branches in all. Fills `r%transmission_fold` (NaN when no branch ends in a fold that transmits)
    !> and `r%branches`; the costs of these continuations are added to the record's.
    subroutine follow_to_transmission(map, run, ctl, settled, a, r)
        !> The one-period map.
        type(period_map), intent(inout) :: map
        !> The run (detector).
        type(run_config), intent(in) :: run
        !> The continuation controls of the first branch.
        type(continuation_controls), intent(in) :: ctl
        !> Where the chain settled past the first fold.
        real(wp), intent(in) :: settled(:)
        !> The amplitude it settled at.
        real(wp), intent(in) :: a
        !> The record.
        type(fold_record), intent(inout) :: r
        type(continuation_controls) :: next
        type(continuation_result) :: res
        type(continuation_stats) :: watched
        real(wp), allocatable :: x(:)
        real(wp) :: amplitude, time
        integer :: fate
        logical :: half

        x = settled
        amplitude = a
        next = ctl
        next%beyond_fold = 0
        ! the fold alone: what is asked of a followed branch is its fold and that fold's fate; no loss of stability
        ! is sought along it (its multipliers at the first point, for stop_at_unstable_start, and at the fold only)
        next%floquet_every = 0
        next%flip_watch = .false.
        next%start_max_iter = 40
        ! from a settled state that damped_shooting could not bring to a periodic state, the undamped Newton gives
        ! up once it has left its basin (on the paper's grid it then wandered through all its 40 Jacobians, 7 of 7)
        next%start_growth_limit = follow_growth_limit
        next%max_points = 4*ctl%max_points
        ! a settled state that is not stable ends the following at its first point (below), not after its branch
        next%stop_at_unstable_start = .true.
        do while (r%branches < max_branches)
            watched = continuation_stats()
            call damped_shooting(map, x, amplitude, watched)
            call add_stats(r, watched)
            next%amplitude_start = amplitude
            ! a settled periodic state with the half-period symmetry: its branch on G too (half the cost)
            half = half_period_symmetric(map, x, amplitude)
            if (mod(map%steps, 2) == 0) r%map_evaluations = r%map_evaluations + 1
            call continue_branch(map, next, res, x)
            if (half) call set_half_period(map, .false., half)
            r%branches = r%branches + 1
            call add_branch_cost(r, res)
            ! (a state Newton found where the chain cannot have settled, not stable, stops it: cont_unstable_start)
            if (res%status /= cont_fold_found .or. res%fold_index < 1) then
                r%transmission_status = res%status
                return
            end if
            watched = continuation_stats()
            call fold_fate(map, run, res%states(:, res%fold_index), res%fold_amplitude*(1.0_wp + fate_push), fate, &
                           time, x, stats=watched)
            call add_stats(r, watched)
            if (fate == fate_transmits) then
                r%transmission_fold = res%fold_amplitude
                r%transmission_status = cont_fold_found
                return
            end if
            if (fate /= fate_localized) then
                r%transmission_status = follow_fate_failed
                return
            end if
            amplitude = res%fold_amplitude*(1.0_wp + fate_push)
        end do
        r%transmission_status = follow_too_many
    end subroutine follow_to_transmission

    !> Whether x is a periodic state with the half-period symmetry, G(x) = x to `symmetric_tol` (M even); if so,
    !> `map` is left as the half-period map G, else as P.
    function half_period_symmetric(map, x, amplitude) result(yes)
        !> The one-period map (P on entry).
        type(period_map), intent(inout) :: map
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
        if (yes) yes = maxval(abs(gx - x)) <= symmetric_tol
        if (.not. yes) call set_half_period(map, .false., ok)
    end function half_period_symmetric

    !> Newton-shooting with backtracking from where the chain settled (`x`, not yet periodic: the modes trapped
    !> between the drive and the absorber ring for long) towards the periodic state nearby: each full Newton step
    !> is halved (down to 1/64) until it lowers max |P(x) - x|, so that the first steps, made large by the
    !> multipliers near +1, do not throw x far away. At most `settle_iterations` steps; `x` is the periodic state
    !> when max |P(x) - x| <= `settle_tol` was reached, else left as it came (the continuation's own, undamped
    !> shooting then has its try, and gives up once its residual has grown tenfold: `follow_growth_limit`).
    subroutine damped_shooting(map, x, amplitude, stats)
        !> The one-period map.
        type(period_map), intent(inout) :: map
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
        do it = 1, settle_iterations
            if (residual <= settle_tol) then
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
        if (residual <= settle_tol) x = y

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
    subroutine fold_fate(map, run, x, amplitude, fate, time, last, watch, stats)
        !> The one-period map of the branch (its work arrays change).
        type(period_map), intent(inout) :: map
        !> The run (detector site and amplitude).
        type(run_config), intent(in) :: run
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
        periods = max(fate_min_periods, ceiling(fate_watch_time/map%period))
        if (present(watch)) periods = max(1, ceiling(watch/map%period))
        y = x
        allocate (py(size(x)))
        fate = fate_localized
        do k = 1, periods
            call map%apply(y, amplitude, py, status)
            time = real(k, wp)*map%period
            if (status /= map_ok) then
                fate = fate_failed
                exit
            end if
            if (maxval(abs(py(nd + 1:map%n))) > run%detect%amplitude) then
                fate = fate_transmits
                exit
            end if
            y = py
        end do
        if (present(stats)) then
            stats%map_evaluations = stats%map_evaluations + min(k, periods)
            stats%time_map = stats%time_map + wall_clock() - t0
        end if
        if (fate == fate_localized .and. present(last)) last = y
    end subroutine fold_fate

    !> The fates of a fold as "code name: meaning" clauses (the `codes` attribute of /fold_fate).
    pure function fate_codes() result(text)
        character(len=:), allocatable :: text

        text = int_str(fate_not_computed) // " none: no fold; " // int_str(fate_transmits) // " transmits: driven " &
            // "at A_f (1 + " // real_str(fate_push, 3) // ") from the fold's state, an oscillator beyond the " &
            // "detector site passes the detector amplitude (the fold is the supratransmission threshold); " &
            // int_str(fate_localized) // " localized: no transmission within /fold_fate_time (the chain " &
            // "settles on another state: the fold is not where transmission starts); " // int_str(fate_failed) &
            // " failed: the scheme's implicit step did not converge"
    end function fate_codes

    !> The codes of /transmission_status as "code: meaning" clauses.
    pure function transmission_status_codes() result(text)
        character(len=:), allocatable :: text

        text = "-1: no fold on the first branch (see /status); " // int_str(cont_fold_found) // ": found; " &
            // int_str(cont_no_fold) // ", " // int_str(cont_newton_failed) // ", " // int_str(cont_step_too_small) &
            // ", " // int_str(cont_max_points) // ": the last branch followed ended as /status says of the first " &
            // "(no fold below amplitude_max, Newton-shooting failed from the settled state, step too small, " &
            // "points exhausted); " // int_str(follow_unstable_start) // ": the state found where the chain settled " &
            // "is unstable; " // int_str(follow_too_many) // ": still localized past the folds of " &
            // int_str(max_branches) // " branches; " // int_str(follow_fate_failed) // ": the scheme failed " &
            // "while a fold's fate was watched"
    end function transmission_status_codes

end module supratrans_fold_fate
