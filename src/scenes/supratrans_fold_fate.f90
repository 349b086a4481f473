!> Where the chain of a fold line (`supratrans_fold_line`) transmits, from the fate of its fold and what it does past
!> it (the watches and stairs of `supratrans_chain_watch`, re-exported here).
!>
!> **Following the chain past a localized fold** (`follow_to_transmission`). The state it settled on is brought to a
!> periodic state by Newton-shooting with backtracking (`damped_shooting`), its branch is continued in A to its own
!> fold (on the half-period map when that state has the half-period symmetry, `half_period_symmetric`), and that
!> fold's fate is tested in turn, up to `max_branches` branches; where the chain settled on no stable periodic
!> state, it is driven up in stairs from there.
!>
!> **Past a loss of stability below the fold**: at a branch point the other branch (`past_branch_point`), past a
!> torus or a period doubling the stairs (`past_oscillatory_loss`).
module supratrans_fold_fate
    use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
    use supratrans_kinds, only: wp
    use supratrans_config, only: run_config, fold_protocol
    use supratrans_strings, only: int_str, real_str
    use supratrans_period_map, only: period_map, set_half_period
    use supratrans_chain_watch, only: fold_fate, fate_codes, climb_stairs, damped_shooting, half_period_symmetric, &
                                      fate_not_computed, fate_transmits, fate_localized, fate_failed
    use supratrans_continuation, only: continue_branch, continuation_controls, continuation_result, continuation_stats, &
                                       cont_fold_found, cont_no_fold, cont_newton_failed, cont_step_too_small, &
                                       cont_max_points, cont_unstable_start
    use supratrans_fold_record, only: fold_record, add_stats, add_branch_cost
    use supratrans_continuation_corrector, only: branch_point
    use supratrans_branch_switch, only: switch_branch
    implicit none
    private

    public :: fold_fate, fate_codes, transmission_status_codes, half_period_symmetric, follow_to_transmission, &
              add_branch_cost, counted_fate, past_branch_point, branch_switch_codes, transmission_after, &
              past_oscillatory_loss, switch_side
    public :: fate_not_computed, fate_transmits, fate_localized, fate_failed

    !> Why no transmission fold (beside the continuation's statuses of the last branch followed): the state Newton
    !> found where the chain settled is unstable.
    integer, parameter, public :: follow_unstable_start = cont_unstable_start
    !> Why no transmission fold: the chain stayed localized past the folds of &scene follow_branches branches.
    integer, parameter, public :: follow_too_many = 7
    !> Why no transmission fold: the scheme failed while the fate of a fold was watched.
    integer, parameter, public :: follow_fate_failed = 8
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
    !> Branch switching: the other branch's first point lies inside the bracket of a branch point known only to its
    !> bracket, so its side is not known (the chain driven past the bracket's upper end, as past a subcritical one).
    integer, parameter, public :: switch_side_unknown = 5
    ! The protocol's constants are input keys (`fold_protocol`): switch_step (distance of the other branch's first
    ! point from a branch point), switch_seed (the small asymmetry a slow ramp leaves), stair_climbs (the climbs of
    ! stairs besides the first, from the first's start moved by switch_seed along (sin k i)_i, k = 2, 3, ...: their
    ! spread is /transmission_spread), follow_branches, follow_max_iter, follow_growth_limit.

contains

    !> Past a branch point below the fold (the first loss of stability of the branch from rest, a real multiplier
    !> through +1 where the branch does not turn; its point and the tangent next to it in `res`), where a slow ramp
    !> goes: the other branch is found (`switch_branch`, `switch_step` away; 4 `switch_step` when that fails, as from
    !> a branch point known only to its bracket it may). Where it leaves above the branch point
    !> (supercritical) the ramp follows it: it is continued to its fold, whose fate is tested, and so on
    !> (`follow_to_transmission`). Where it leaves below (subcritical), or inside the bracket of a branch point known
    !> only to its bracket, whose upper end A_b is (side unknown: the protocol holds for both kinds), nothing is
    !> near to follow: the chain is driven
    !> at A_b (1 + `fate_push`) from the branch point's state moved by `switch_seed` along the other branch's
    !> direction, and A_b is the transmission threshold when it transmits; where it stays localized, the chain is
    !> followed from where it settled. (Driven from the other branch's first point instead, the chain stayed
    !> localized at Omega = 0.44 on the paper's grid, where a slow ramp transmits just past the branch point.) Fills
    !> `r%branch_switch`, and `r%transmission_fold`, `r%branches`, `r%transmission_status`.
    subroutine past_branch_point(map, run, proto, ctl, res, r)
        !> The one-period map P.
        type(period_map), intent(inout) :: map
        !> The run (detector).
        type(run_config), intent(in) :: run
        !> The fold protocol.
        type(fold_protocol), intent(in) :: proto
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
        call switch_branch(map, res%instability_point, res%instability_tangent, &
                           [proto%switch_step, 4.0_wp*proto%switch_step], ctl, pt, e, ok, stats)
        call add_stats(r, stats)
        r%newton_iterations = r%newton_iterations + pt%iterations
        if (.not. ok) then
            r%branch_switch = switch_failed
            r%transmission_status = cont_newton_failed
            return
        end if
        r%branch_switch = switch_side(pt%y(d + 1), r%instability_lower, a_b)
        if (r%branch_switch == switch_supercritical) then
            call follow_to_transmission(map, run, proto, ctl, pt%y(1:d), pt%y(d + 1), r)
            return
        end if
        call counted_fate(map, run, proto, res%instability_point(1:d) + proto%switch_seed*e(1:d), &
                          a_b*(1.0_wp + proto%fate_push), r, fate, time, settled)
        call transmission_after(map, run, proto, ctl, a_b, fate, settled, r)
    end subroutine past_branch_point

    !> On which side of a branch point the other branch leaves (`/branch_switch`): above the branch point (its
    !> bracket's upper end `a_b`) supercritical; inside the bracket [`a_lower`, `a_b`] of a branch point known only
    !> to its bracket side unknown (with M odd the pitchfork is an imperfect one, and the branch point may lie
    !> anywhere in the bracket); below it subcritical. A located branch point has `a_lower` = `a_b` (or NaN).
    pure integer function switch_side(a_first, a_lower, a_b)
        !> Amplitude of the other branch's first point.
        real(wp), intent(in) :: a_first
        !> Lower end of the branch point's bracket.
        real(wp), intent(in) :: a_lower
        !> The branch point (its bracket's upper end).
        real(wp), intent(in) :: a_b

        if (a_first > a_b) then
            switch_side = switch_supercritical
        else if (a_lower < a_b .and. a_first >= a_lower) then
            switch_side = switch_side_unknown
        else
            switch_side = switch_subcritical
        end if
    end function switch_side

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
    subroutine past_oscillatory_loss(map, run, proto, ctl, res, fold, r, done)
        !> The one-period map P.
        type(period_map), intent(inout) :: map
        !> The run (detector).
        type(run_config), intent(in) :: run
        !> The fold protocol.
        type(fold_protocol), intent(in) :: proto
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
        real(wp), allocatable :: y(:), last(:)
        real(wp) :: a_t, top, time
        integer :: d, fate

        d = map%dim
        a_t = res%instability_point(d + 1)
        top = fold
        if (ieee_is_nan(top)) top = ctl%amplitude_max
        done = a_t + proto%stair_height < top
        if (.not. done) return
        r%branch_switch = switch_stairs
        r%branches = 1
        r%transmission_status = follow_fate_failed
        y = seeded(res%instability_point(1:d), 1, proto%switch_seed)
        call counted_stairs(map, run, proto, y, a_t, top, r, fate)
        if (fate /= fate_localized) return
        if (ieee_is_nan(fold)) then
            r%transmission_status = cont_no_fold
            return
        end if
        call counted_fate(map, run, proto, y, top*(1.0_wp + proto%fate_push), r, fate, time, last)
        call transmission_after(map, run, proto, ctl, top, fate, last, r)
    end subroutine past_oscillatory_loss

    !> `fold_fate` from `x` at `amplitude`, its maps and their time added to the record's costs.
    subroutine counted_fate(map, run, proto, x, amplitude, r, fate, time, last)
        !> The one-period map P.
        type(period_map), intent(inout) :: map
        !> The run (detector).
        type(run_config), intent(in) :: run
        !> The fold protocol (the fate's watch).
        type(fold_protocol), intent(in) :: proto
        !> The chain's state at the start.
        real(wp), intent(in) :: x(:)
        !> Drive amplitude.
        real(wp), intent(in) :: amplitude
        !> The record (its costs).
        type(fold_record), intent(inout) :: r
        !> `fate_transmits`, `fate_localized` or `fate_failed`.
        integer, intent(out) :: fate
        !> Time of the first transmission, or the time watched.
        real(wp), intent(out) :: time
        !> The state at the end of the watch (where the chain stays localized).
        real(wp), allocatable, intent(out) :: last(:)
        type(continuation_stats) :: stats

        call fold_fate(map, run, proto, x, amplitude, fate, time, last, stats=stats)
        call add_stats(r, stats)
    end subroutine counted_fate

    !> `climb_stairs` from `y` at `a0` below `top`, its maps and their time added to the record's costs; the stair
    !> on which the chain transmits, when it does, is the record's transmission (`transmission_stairs` 1), and
    !> `other_climbs` more climbs from the start moved by `switch_seed` along other fixed directions give its spread,
    !> the farthest of their stairs from it: where the chain is intermittent, a change of 1e-17 in Omega can move the
    !> stair by 0.1 (docs/continuation.md). Each goes at most as far above the first's stair as that went above `a0`
    !> (it costs no more than the first).
    subroutine counted_stairs(map, run, proto, y, a0, top, r, fate)
        !> The one-period map P.
        type(period_map), intent(inout) :: map
        !> The run (detector).
        type(run_config), intent(in) :: run
        !> The fold protocol (the stairs, the other climbs and their seed).
        type(fold_protocol), intent(in) :: proto
        !> The chain's state: in, at the start; out, at the end of the last stair held without transmission.
        real(wp), allocatable, intent(inout) :: y(:)
        !> The amplitude the chain was driven at before (the stairs start one step above it).
        real(wp), intent(in) :: a0
        !> The stairs stay below it.
        real(wp), intent(in) :: top
        !> The record.
        type(fold_record), intent(inout) :: r
        !> `fate_transmits`, `fate_localized` or `fate_failed` (`climb_stairs`).
        integer, intent(out) :: fate
        type(continuation_stats) :: stats
        real(wp), allocatable :: start(:), other(:)
        real(wp) :: a, ak, spread
        integer :: fate_k, k

        start = y
        call climb_stairs(map, run, proto, y, a0, top, a, fate, stats)
        if (fate == fate_transmits) then
            spread = -1.0_wp
            do k = 2, 1 + proto%other_climbs
                other = seeded(start, k, proto%switch_seed)
                call climb_stairs(map, run, proto, other, a0, min(top, 2*a - a0 + proto%stair_height/2), ak, fate_k, &
                                  stats)
                ! (not transmitted within its bound: its next stair, a lower bound of where it would)
                if (fate_k == fate_localized) ak = ak + proto%stair_height
                if (fate_k /= fate_failed) spread = max(spread, abs(ak - a))
            end do
            if (spread >= 0.0_wp) r%transmission_spread = spread
        end if
        call add_stats(r, stats)
        if (fate /= fate_transmits) return
        r%transmission_fold = a
        r%transmission_status = cont_fold_found
        r%transmission_stairs = 1
    end subroutine counted_stairs

    !> x moved by `switch_seed` along the fixed unit direction (sin k i)_i (k = 1: the small asymmetry a slow ramp
    !> leaves; k = 2, 3, ...: others of the same size, for the stairs' other climbs).
    pure function seeded(x, k, seed) result(y)
        !> The state.
        real(wp), intent(in) :: x(:)
        !> Which direction.
        integer, intent(in) :: k
        !> How far (`switch_seed`).
        real(wp), intent(in) :: seed
        real(wp), allocatable :: y(:)
        real(wp), allocatable :: s(:)
        integer :: i

        s = [(sin(real(k*i, wp)), i=1, size(x))]
        y = x + (seed/norm2(s))*s
    end function seeded

    !> Where the chain transmits, from the fate of a drive just past the amplitude `a` (a fold, or a branch point):
    !> `a` itself when it transmits; the fold of the branch it settled on, or a later one (`follow_to_transmission`),
    !> when it stays localized; nothing when the watch failed (the caller's status stands).
    subroutine transmission_after(map, run, proto, ctl, a, fate, settled, r)
        !> The one-period map.
        type(period_map), intent(inout) :: map
        !> The run (detector).
        type(run_config), intent(in) :: run
        !> The fold protocol.
        type(fold_protocol), intent(in) :: proto
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
            call follow_to_transmission(map, run, proto, ctl, settled, a*(1.0_wp + proto%fate_push), r)
        end if
    end subroutine transmission_after

    !> The codes of /branch_switch as "code name: meaning" clauses.
    pure function branch_switch_codes(proto) result(text)
        !> The fold protocol (the stairs and their seed).
        type(fold_protocol), intent(in) :: proto
        character(len=:), allocatable :: text

        text = int_str(switch_none) // " none: no branch point below the fold (or no fate asked); " &
            // int_str(switch_supercritical) // " supercritical: the other branch leaves above the branch point and " &
            // "is followed (/transmission_fold is its fold, or a later one); " // int_str(switch_subcritical) &
            // " subcritical: it leaves below; driven 1% past the branch point, the chain transmits " &
            // "(/transmission_fold is the branch point) or settles and is followed; " // int_str(switch_failed) &
            // " failed: the other branch was not found; " // int_str(switch_stairs) // " stairs: past a torus or " &
            // "a period doubling below the fold (no branch of periodic states to switch to), the chain is driven " &
            // "from the loss's state (moved by " // real_str(proto%switch_seed, 3) // ") up in stairs of " &
            // real_str(proto%stair_height, 3) // " held " // real_str(proto%stair_time, 4) // " time units each; " &
            // "/transmission_fold is the first stair where it transmits (the one below it did not), or where " &
            // "none does below the fold, as past the fold from the last stair's state; " &
            // int_str(switch_side_unknown) // " side unknown: the branch point is known only to its bracket " &
            // "(/instability_lower .. /instability_amplitude) and the other branch's first point lies inside it; " &
            // "the chain is driven 1% past the bracket's upper end, as past a subcritical one"
    end function branch_switch_codes

    !> Past a fold where the chain stays localized, the branch it settles on: from the `settled` state at amplitude
    !> `a` (Newton-shooting first), continued in A to its own fold, whose fate is tested in turn, up to
    !> `max_branches` branches in all. Where the chain settled on no stable periodic state (Newton-shooting from
    !> there finds an unstable one, or none), the chain itself is driven up in stairs from there (`climb_stairs`, to
    !> amplitude_max), as a slow ramp would go on. Fills `r%transmission_fold` (NaN when no branch ends in a fold
    !> that transmits and no stair does) and `r%branches`; the costs of these continuations are added to the
    !> record's.
    subroutine follow_to_transmission(map, run, proto, ctl, settled, a, r)
        !> The one-period map.
        type(period_map), intent(inout) :: map
        !> The run (detector).
        type(run_config), intent(in) :: run
        !> The fold protocol.
        type(fold_protocol), intent(in) :: proto
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
        real(wp), allocatable :: x(:), chain(:)
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
        next%start_max_iter = proto%follow_max_iter
        ! from a settled state that damped_shooting could not bring to a periodic state, the undamped Newton gives
        ! up once it has left its basin (on the paper's grid it then wandered through all its 40 Jacobians, 7 of 7)
        next%start_growth_limit = proto%follow_growth_limit
        next%max_points = 4*ctl%max_points
        ! a settled state that is not stable ends the following at its first point (below), not after its branch
        next%stop_at_unstable_start = .true.
        do while (r%branches < proto%max_branches)
            chain = x
            watched = continuation_stats()
            call damped_shooting(map, proto, x, amplitude, watched)
            call add_stats(r, watched)
            next%amplitude_start = amplitude
            ! a settled periodic state with the half-period symmetry: its branch on G too (half the cost)
            half = half_period_symmetric(map, proto, x, amplitude)
            if (mod(map%steps, 2) == 0) r%map_evaluations = r%map_evaluations + 1
            call continue_branch(map, next, res, x)
            if (half) call set_half_period(map, .false., half)
            r%branches = r%branches + 1
            call add_branch_cost(r, res)
            ! (a state Newton found where the chain cannot have settled, not stable, stops it: cont_unstable_start)
            if (res%status /= cont_fold_found .or. res%fold_index < 1) then
                r%transmission_status = res%status
                ! no stable periodic state where the chain settled (Newton-shooting found an unstable one, or none):
                ! the chain itself is driven up in stairs from there
                if (res%status == cont_unstable_start .or. res%n_points == 0) then
                    call counted_stairs(map, run, proto, chain, amplitude, ctl%amplitude_max, r, fate)
                end if
                return
            end if
            call counted_fate(map, run, proto, res%states(:, res%fold_index), &
                              res%fold_amplitude*(1.0_wp + proto%fate_push), r, fate, time, x)
            if (fate == fate_transmits) then
                r%transmission_fold = res%fold_amplitude
                r%transmission_status = cont_fold_found
                return
            end if
            if (fate /= fate_localized) then
                r%transmission_status = follow_fate_failed
                return
            end if
            amplitude = res%fold_amplitude*(1.0_wp + proto%fate_push)
        end do
        r%transmission_status = follow_too_many
    end subroutine follow_to_transmission

    !> The codes of /transmission_status as "code: meaning" clauses.
    pure function transmission_status_codes(proto) result(text)
        !> The fold protocol (`max_branches`).
        type(fold_protocol), intent(in) :: proto
        character(len=:), allocatable :: text

        text = "-1: no fold on the first branch (see /status); " // int_str(cont_fold_found) // ": found; " &
            // int_str(cont_no_fold) // ", " // int_str(cont_newton_failed) // ", " // int_str(cont_step_too_small) &
            // ", " // int_str(cont_max_points) // ": the last branch followed ended as /status says of the first " &
            // "(no fold below amplitude_max, Newton-shooting failed from the settled state, step too small, " &
            // "points exhausted); " // int_str(follow_unstable_start) // ": the state found where the chain settled " &
            // "is unstable; " // int_str(follow_too_many) // ": still localized past the folds of " &
            // int_str(proto%max_branches) // " branches; " // int_str(follow_fate_failed) // ": the scheme failed " &
            // "while a fold's fate was watched"
    end function transmission_status_codes

end module supratrans_fold_fate
