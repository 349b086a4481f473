!> The fold protocol's branch switch: past the first loss of stability of the branch from rest below its fold, where
!> a slow ramp leaves that branch. One outcome enumeration, `switch_*`; the entry point `past_loss` takes the
!> protocol's constants (`fold_protocol`: switch_step, switch_seed, fate_push, the stairs' and the following's keys)
!> and returns the outcome. Where the outcome is written (/branch_switch) its code is `branch_switch_code` of
!> `supratrans_protocol_codes`.
!>
!> At a branch point the other branch (`past_branch_point`); past a torus or a period doubling the stairs
!> (`past_oscillatory_loss`: no branch of periodic states leaves there to switch to).
module supratrans_protocol_switch
    use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
    use supratrans_kinds, only: wp
    use supratrans_config, only: run_config, fold_protocol
    use supratrans_period_map, only: period_map
    use supratrans_continuation, only: continuation_controls, continuation_result, continuation_stats, &
                                       cont_newton_failed, cont_no_fold
    use supratrans_continuation_corrector, only: branch_point
    use supratrans_branch_switch, only: switch_branch
    use supratrans_floquet, only: crossing_fold
    use supratrans_fold_record, only: fold_record, add_stats
    use supratrans_stairs, only: stairs_found, stairs_none, seeded
    use supratrans_protocol_follow, only: follow_to_transmission, transmission_after, counted_fate, counted_stairs, &
                                          follow_stairs_transmit, follow_fate_failed, follow_branch_ended
    implicit none
    private

    public :: past_loss, switch_side

    ! The outcomes of the branch switch (one enumeration).
    !> Switch: the other branch leaves the branch point above it (followed to its fold).
    integer, parameter, public :: switch_supercritical = 1
    !> Switch: the other branch leaves the branch point below it (the chain driven past the branch point).
    integer, parameter, public :: switch_subcritical = 2
    !> Switch: the other branch's first point lies inside the bracket of a branch point known only to its bracket, so
    !> its side is not known (the chain driven past the bracket's upper end, as past a subcritical one).
    integer, parameter, public :: switch_side_unknown = 3
    !> Switch: the other branch was not found.
    integer, parameter, public :: switch_not_found = 4
    !> Switch: past a torus or a period doubling (no branch of periodic states to switch to), the chain driven from
    !> the loss's state up in stairs.
    integer, parameter, public :: switch_stairs = 5
    !> Switch: past a torus or a period doubling less than a stair below the fold: no stair to drive, nothing done
    !> (the fold's fate is tested as without the loss).
    integer, parameter, public :: switch_no_stairs = 6

contains

    !> Past the first loss of stability of the branch from rest below its fold (its point, and next to a branch point
    !> the tangent, in `res`; `kind` its crossing type): at a branch point (`crossing_fold`: a real multiplier through
    !> +1 where the branch does not turn) `past_branch_point`, else `past_oscillatory_loss`. `outcome` is the switch's;
    !> unless it is `switch_no_stairs`, `transmission` (`follow_*` of `supratrans_protocol_follow`, with `ended`) says
    !> where the chain transmits, and `r%transmission_fold`, `r%branches` are filled.
    subroutine past_loss(map, run, proto, ctl, res, kind, fold, r, outcome, transmission, ended)
        !> The one-period map P.
        type(period_map), intent(inout) :: map
        !> The run (detector).
        type(run_config), intent(in) :: run
        !> The fold protocol.
        type(fold_protocol), intent(in) :: proto
        !> The continuation controls of the branch from rest.
        type(continuation_controls), intent(in) :: ctl
        !> The branch from rest, with `instability_point` (and `instability_tangent` at a branch point).
        type(continuation_result), intent(in) :: res
        !> The loss's crossing type (`supratrans_floquet`).
        integer, intent(in) :: kind
        !> The fold of the branch from rest (NaN: none below amplitude_max).
        real(wp), intent(in) :: fold
        !> The record.
        type(fold_record), intent(inout) :: r
        !> The switch's outcome (`switch_*`).
        integer, intent(out) :: outcome
        !> Where the chain transmits (`follow_*`); unset with `switch_no_stairs`.
        integer, intent(out) :: transmission
        !> With `follow_branch_ended`, the continuation's status of the last branch followed.
        integer, intent(out) :: ended

        if (kind == crossing_fold) then
            call past_branch_point(map, run, proto, ctl, res, r, outcome, transmission, ended)
        else
            call past_oscillatory_loss(map, run, proto, ctl, res, fold, r, outcome, transmission, ended)
        end if
    end subroutine past_loss

    !> Past a branch point below the fold (its point and the tangent next to it in `res`), where a slow ramp goes: the
    !> other branch is found (`switch_branch`, `switch_step` away; 4 `switch_step` when that fails, as from a branch
    !> point known only to its bracket it may). Where it leaves above the branch point (supercritical) the ramp
    !> follows it: it is continued to its fold, whose fate is tested, and so on (`follow_to_transmission`). Where it
    !> leaves below (subcritical), or inside the bracket of a branch point known only to its bracket, whose upper end
    !> A_b is (side unknown: the protocol holds for both kinds), nothing is near to follow: the chain is driven at A_b
    !> (1 + `fate_push`) from the branch point's state moved by `switch_seed` along the other branch's direction, and
    !> A_b is the transmission threshold when it transmits; where it stays localized, the chain is followed from where
    !> it settled. (Driven from the other branch's first point instead, the chain stayed localized at Omega = 0.44 on
    !> the paper's grid, where a slow ramp transmits just past the branch point.) Where the other branch is not found,
    !> the transmission is `follow_branch_ended` with the status of a Newton-shooting that failed.
    subroutine past_branch_point(map, run, proto, ctl, res, r, outcome, transmission, ended)
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
        !> `switch_supercritical`, `switch_subcritical`, `switch_side_unknown` or `switch_not_found`.
        integer, intent(out) :: outcome
        !> Where the chain transmits (`follow_*`).
        integer, intent(out) :: transmission
        !> With `follow_branch_ended`, the continuation's status of the last branch followed.
        integer, intent(out) :: ended
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
        ! (from a branch point only bracketed, a longer step leaves the bracket's width less weight)
        call switch_branch(map, res%instability_point, res%instability_tangent, &
                           [proto%switch_step, 4.0_wp*proto%switch_step], ctl, pt, e, ok, stats)
        call add_stats(r, stats)
        r%newton_iterations = r%newton_iterations + pt%iterations
        if (.not. ok) then
            outcome = switch_not_found
            transmission = follow_branch_ended
            ended = cont_newton_failed
            return
        end if
        outcome = switch_side(pt%y(d + 1), r%instability_lower, a_b)
        if (outcome == switch_supercritical) then
            call follow_to_transmission(map, run, proto, ctl, pt%y(1:d), pt%y(d + 1), r, transmission, ended)
            return
        end if
        call counted_fate(map, run, proto, res%instability_point(1:d) + proto%switch_seed*e(1:d), &
                          a_b*(1.0_wp + proto%fate_push), r, fate, time, settled)
        call transmission_after(map, run, proto, ctl, a_b, fate, settled, r, transmission, ended)
    end subroutine past_branch_point

    !> On which side of a branch point the other branch leaves: above the branch point (its bracket's upper end
    !> `a_b`) supercritical; inside the bracket [`a_lower`, `a_b`] of a branch point known only to its bracket side
    !> unknown (with M odd the pitchfork is an imperfect one, and the branch point may lie anywhere in the bracket);
    !> below it subcritical. A located branch point has `a_lower` = `a_b` (or NaN).
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
    !> stairs a_k = A_t + k `stair_height` below the fold, each held `stair_time` (`supratrans_stairs`);
    !> `/transmission_fold` is the first stair where the chain transmits. Where none does, the chain is driven 1%
    !> past the fold from the last stair's state (`transmission_after`: the fold, or followed; `follow_branch_ended`
    !> with the status `cont_no_fold` where the branch has no fold below amplitude_max, which bounds the stairs then).
    !> No stair lies below the fold (`switch_no_stairs`: the caller tests the fold's fate as without the loss) where
    !> the loss is less than `stair_height` below it. (On the paper's grid at Omega = 0.35 .. 0.38 the stairs of the
    !> hysteresis scene, 200 .. 800 time units long, transmit within 0.04 of each other: docs/continuation.md.)
    subroutine past_oscillatory_loss(map, run, proto, ctl, res, fold, r, outcome, transmission, ended)
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
        !> `switch_stairs`, or `switch_no_stairs` (nothing done).
        integer, intent(out) :: outcome
        !> Where the chain transmits (`follow_*`).
        integer, intent(out) :: transmission
        !> With `follow_branch_ended`, the continuation's status of the last branch followed.
        integer, intent(out) :: ended
        real(wp), allocatable :: y(:), last(:)
        real(wp) :: a_t, top, time
        integer :: d, fate, stairs

        d = map%dim
        a_t = res%instability_point(d + 1)
        top = fold
        if (ieee_is_nan(top)) top = ctl%amplitude_max
        outcome = switch_no_stairs
        transmission = follow_fate_failed
        ended = cont_no_fold
        if (.not. a_t + proto%stair_height < top) return
        outcome = switch_stairs
        r%branches = 1
        y = seeded(res%instability_point(1:d), 1, proto%switch_seed)
        call counted_stairs(map, run, proto, y, a_t, top, r, stairs)
        if (stairs == stairs_found) transmission = follow_stairs_transmit
        if (stairs /= stairs_none) return
        if (ieee_is_nan(fold)) then
            transmission = follow_branch_ended
            return
        end if
        call counted_fate(map, run, proto, y, top*(1.0_wp + proto%fate_push), r, fate, time, last)
        call transmission_after(map, run, proto, ctl, top, fate, last, r, transmission, ended)
    end subroutine past_oscillatory_loss

end module supratrans_protocol_switch
