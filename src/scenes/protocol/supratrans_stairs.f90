!> Stairs: the one stair implementation of the fold protocol's stairs (by the one-period map) and of the hysteresis
!> scene's (one time-domain run with a staircase drive, `supratrans_hysteresis_stairs`). One outcome enumeration,
!> `stairs_*`.
!>
!> **What the two share** is here: the stair plan (`stair_plan`: the bottom level a_0, the height, the top index K,
!> how long a stair is held), its levels a_i = a_0 + i height (`plan_level`, which is the drive profile's own
!> `stair_level` of `supratrans_chain`: one formula for the run's A(t) and for both protocols' levels), and the
!> reading of the stairs' verdicts (`read_stairs`: the upward edge, the first stair on the way up that transmits; on
!> a plan that comes down, the downward edge, the last that still transmits on the way down, and the quiet stairs
!> between; the outcome). **What they do not share**, and why: how a stair is held and what its verdict is. The
!> protocol's stairs go up only, one stair at a time from the state the stair below left (the one-period map at a
!> fixed amplitude, no ramp between stairs), stop at the first stair that transmits and decide a stair by the
!> detector (an oscillator beyond the detector site past the detector amplitude: `fold_fate`); the hysteresis scene
!> holds all 2K + 1 stairs, up and down, in one run whose drive ramps between them (`stairs_profile` gives it the
!> plan), and decides a stair afterwards by the mean power through the bond beyond the detector site over its
!> second half (`stair_powers`): its downward edge needs the transmitting state carried down, which a climb that
!> stops at the first transmission never holds, and the detector's verdict cannot see a transmitting state die.
!>
!> **The protocol's climb** (`climb_stairs`, entry point `stairs_transmission`): where no stable periodic state is
!> there to be followed, the chain is driven up in stairs of `stair_height` (&scene fold_stair_height), each held
!> `stair_time` (&scene fold_stair_time), with the fate's detector, as a slow ramp would go on; `other_climbs`
!> (&scene stair_climbs) more climbs from the start moved by `switch_seed` along other fixed directions give the
!> stair's spread. (Stairs held 1000 time units, as long as a fate is watched, transmit 0.01 .. 0.22 lower on the
!> paper grid's fold line at all 17 frequencies with stairs than with the default 200, for 1.24 times the task time:
!> docs/continuation.md.)
module supratrans_stairs
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp
    use supratrans_config, only: run_config, fold_protocol, drive_params
    use supratrans_chain, only: profile_stairs, stair_level
    use supratrans_period_map, only: period_map
    use supratrans_continuation_types, only: continuation_stats
    use supratrans_protocol_fate, only: fold_fate, fate_transmits, fate_localized
    implicit none
    private

    public :: stairs_profile, drive_plan, plan_level, climb_plan, read_stairs, climb_stairs, stairs_transmission, seeded

    ! The outcomes of stairs (one enumeration). A climb of the fold protocol (up only, from a stair known not to
    ! transmit) ends `stairs_found`, `stairs_none` or `stairs_failed`; the hysteresis scene's stairs in all six.
    !> Stairs: the edges were found (the upward edge; on a plan that comes down, the downward edge too).
    integer, parameter, public :: stairs_found = 1
    !> Stairs: no stair up to the top transmits.
    integer, parameter, public :: stairs_none = 2
    !> Stairs: the first stair a_0 already transmits (the upward edge lies at or below it).
    integer, parameter, public :: stairs_at_bottom = 3
    !> Stairs (a plan that comes down): the transmission died on the way up, before the top stair.
    integer, parameter, public :: stairs_died_before_top = 4
    !> Stairs (a plan that comes down): the last stair a_0 still transmits (the downward edge lies below it).
    integer, parameter, public :: stairs_still_at_end = 5
    !> Stairs: the scheme failed (on a stair of a climb; the run of the hysteresis scene).
    integer, parameter, public :: stairs_failed = 6

    !> A plan of stairs: the levels a_j = a_0 + i `height`, i = min(j, 2K - j), j = 0 .. 2K (up to a_K, then down
    !> again; a climb holds j = 1 .. K only), each held `time`.
    type, public :: stair_plan
        !> The bottom level a_0.
        real(wp) :: low = 0.0_wp
        !> The height of a stair.
        real(wp) :: height = 0.0_wp
        !> The index K of the top level.
        integer :: top = 0
        !> How long a stair is held (its ramp included).
        real(wp) :: time = 0.0_wp
        !> The ramp from one level to the next at the start of a stair (0: none, the protocol's stairs).
        real(wp) :: ramp = 0.0_wp
        !> Whether the stairs come back down from a_K (the hysteresis scene's; a climb goes up only).
        logical :: down = .false.
    end type stair_plan

contains

    !> `drive` with the stair profile of `plan` (the drive of the hysteresis scene's run).
    pure function stairs_profile(plan, drive) result(r)
        !> The plan.
        type(stair_plan), intent(in) :: plan
        !> The drive (its frequency, its ramp from rest).
        type(drive_params), intent(in) :: drive
        type(drive_params) :: r

        r = drive
        r%profile = profile_stairs
        r%stair_low = plan%low
        r%stair_height = plan%height
        r%stair_top = plan%top
        r%stair_time = plan%time
        r%stair_ramp = plan%ramp
    end function stairs_profile

    !> The plan of a drive's stair profile (up and down).
    pure function drive_plan(drive) result(plan)
        !> The drive (profile_stairs).
        type(drive_params), intent(in) :: drive
        type(stair_plan) :: plan

        plan = stair_plan(low=drive%stair_low, height=drive%stair_height, top=drive%stair_top, time=drive%stair_time, &
                          ramp=drive%stair_ramp, down=.true.)
    end function drive_plan

    !> The level of stair j of `plan` (0 .. 2K): the drive profile's `stair_level`.
    elemental function plan_level(plan, j) result(a)
        !> The plan.
        type(stair_plan), intent(in) :: plan
        !> Stair index.
        integer, intent(in) :: j
        real(wp) :: a

        a = stair_level(stairs_profile(plan, drive_params()), j)
    end function plan_level

    !> The fold protocol's plan of a climb from `a0` (where the chain was driven before: stair 0, not held): stairs of
    !> `stair_height` held `stair_time`, up to the last level below `top` (K = 0: none).
    pure function climb_plan(a0, proto, top) result(plan)
        !> The amplitude the chain was driven at before.
        real(wp), intent(in) :: a0
        !> The fold protocol (`stair_height`, `stair_time`).
        type(fold_protocol), intent(in) :: proto
        !> The stairs stay below it.
        real(wp), intent(in) :: top
        type(stair_plan) :: plan

        plan = stair_plan(low=a0, height=proto%stair_height, top=0, time=proto%stair_time)
        do
            plan%top = plan%top + 1
            if (.not. plan_level(plan, plan%top) < top) exit
        end do
        plan%top = plan%top - 1
    end function climb_plan

    !> The edges from the verdicts `on(j)` (transmits) of the plan's stairs j = 0 .. 2K (a plan that comes down) or
    !> 0 .. K (up only; a stair not held counts as quiet): the upward edge (the first transmitting stair on the way up;
    !> NaN where it is a_0 or none), on a plan that comes down the downward edge (the last transmitting stair on the
    !> way down, the top included; NaN where it is a_0, none, or nothing transmitted on the way up) and the quiet
    !> stairs from the top down to it, and the outcome (`stairs_found`, `stairs_none`, `stairs_at_bottom`,
    !> `stairs_died_before_top`, `stairs_still_at_end`).
    pure subroutine read_stairs(plan, on, up, down, gaps, outcome)
        !> The plan.
        type(stair_plan), intent(in) :: plan
        !> Whether each stair transmits, 0-based.
        logical, intent(in) :: on(0:)
        !> Upward edge; NaN when none.
        real(wp), intent(out) :: up
        !> Downward edge; NaN when none (always on a plan that goes up only).
        real(wp), intent(out) :: down
        !> Quiet stairs from the top down to the downward edge.
        integer, intent(out) :: gaps
        !> The outcome.
        integer, intent(out) :: outcome
        integer :: top, j, ju, jd

        top = plan%top
        up = ieee_value(up, ieee_quiet_nan)
        down = up
        gaps = 0
        ju = -1
        do j = 0, top
            if (on(j)) then
                ju = j
                exit
            end if
        end do
        jd = -1
        if (plan%down) then
            do j = 2*top, top, -1
                if (on(j)) then
                    jd = j
                    exit
                end if
            end do
        end if
        if (ju > 0) up = plan_level(plan, ju)
        if (jd >= top .and. jd < 2*top) down = plan_level(plan, jd)
        if (jd >= top) gaps = count(.not. on(top:jd))
        if (ju < 0) then
            outcome = stairs_none
        else if (ju == 0) then
            outcome = stairs_at_bottom
        else if (.not. plan%down) then
            outcome = stairs_found
        else if (jd < 0) then
            outcome = stairs_died_before_top
        else if (jd == 2*top) then
            outcome = stairs_still_at_end
        else
            outcome = stairs_found
        end if
        if (ju < 0) down = ieee_value(down, ieee_quiet_nan)
    end subroutine read_stairs

    !> One climb: the chain driven from `y` (where the drive before left it) up the stairs of `climb_plan(a0, proto,
    !> top)`, each held `stair_time` (whole periods) with the fate's detector. `stairs_found`: it transmits on the
    !> stair `a`; `stairs_none`: no stair below `top` transmits (`y` the last stair's state, `a` its amplitude, a0
    !> when there was none); `stairs_failed`: the scheme failed on the stair `a`. The maps are added to `stats`.
    subroutine climb_stairs(map, run, proto, y, a0, top, a, outcome, stats)
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
        !> `stairs_found`, `stairs_none` or `stairs_failed`.
        integer, intent(out) :: outcome
        !> Counts and times: the maps applied are added.
        type(continuation_stats), intent(inout) :: stats
        type(stair_plan) :: plan
        real(wp), allocatable :: last(:)
        logical, allocatable :: on(:)
        real(wp) :: time, up, down
        integer :: k, fate, gaps

        plan = climb_plan(a0, proto, top)
        allocate (on(0:plan%top), source=.false.)
        a = a0
        do k = 1, plan%top
            a = plan_level(plan, k)
            call fold_fate(map, run, proto, y, a, fate, time, last, watch=plan%time, stats=stats)
            on(k) = fate == fate_transmits
            if (fate /= fate_localized .and. .not. on(k)) then
                outcome = stairs_failed
                return
            end if
            if (on(k)) exit
            call move_alloc(last, y)
        end do
        call read_stairs(plan, on, up, down, gaps, outcome)
        if (outcome == stairs_found) a = up
    end subroutine climb_stairs

    !> The fold protocol's stairs (its entry point): `climb_stairs` from `y` at `a0` below `top`; where the chain
    !> transmits (`stairs_found`) on the stair `a`, `other_climbs` more climbs from the start moved by `switch_seed`
    !> along other fixed directions give its `spread`, the farthest of their stairs from it (NaN where none could
    !> tell): where the chain is intermittent, a change of 1e-17 in Omega can move the stair by 0.1
    !> (docs/continuation.md). Each goes at most as far above the first's stair as that went above `a0` (it costs no
    !> more than the first).
    subroutine stairs_transmission(map, run, proto, y, a0, top, a, spread, outcome, stats)
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
        !> The stair where the chain transmits (`stairs_found`); else as `climb_stairs` leaves it.
        real(wp), intent(out) :: a
        !> The farthest of the other climbs' stairs from `a` (`stairs_found`); NaN where none tells.
        real(wp), intent(out) :: spread
        !> `stairs_found`, `stairs_none` or `stairs_failed` (of the first climb).
        integer, intent(out) :: outcome
        !> Counts and times: the maps applied are added.
        type(continuation_stats), intent(inout) :: stats
        real(wp), allocatable :: start(:), other(:)
        real(wp) :: ak
        integer :: outcome_k, k

        start = y
        spread = ieee_value(spread, ieee_quiet_nan)
        call climb_stairs(map, run, proto, y, a0, top, a, outcome, stats)
        if (outcome /= stairs_found) return
        do k = 2, 1 + proto%other_climbs
            other = seeded(start, k, proto%switch_seed)
            call climb_stairs(map, run, proto, other, a0, min(top, 2*a - a0 + proto%stair_height/2), ak, outcome_k, &
                              stats)
            ! (not transmitted within its bound: its next stair, a lower bound of where it would)
            if (outcome_k == stairs_none) ak = ak + proto%stair_height
            if (outcome_k /= stairs_failed) then
                if (spread >= 0.0_wp) then
                    spread = max(spread, abs(ak - a))
                else
                    spread = abs(ak - a)
                end if
            end if
        end do
    end subroutine stairs_transmission

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

end module supratrans_stairs
