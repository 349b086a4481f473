!> The fold protocol's following to transmission: where the chain, driven just past an amplitude a (a fold, a branch
!> point, the last stair), transmits. One outcome enumeration, `follow_*`; the entry point `transmission_after` takes
!> the protocol's constants (`fold_protocol`: fate_push, follow_branches, follow_max_iter, follow_growth_limit,
!> settle_iterations, settle_tol, symmetric_tol, the stairs' keys) and returns the outcome. Where the outcome is
!> written (/transmission_status) its code is `transmission_code` of `supratrans_protocol_codes`.
!>
!> Driven just past a, the chain transmits (a is where), or it settles: the state it settled on is brought to a
!> periodic state by Newton-shooting with backtracking (`damped_shooting`), its branch is continued in A to its own
!> fold (on the half-period map when that state has the half-period symmetry, `half_period_symmetric`), and that
!> fold's fate is tested in turn, up to `max_branches` branches (`follow_to_transmission`); where the chain settled on
!> no stable periodic state, it is driven up in stairs from there (`supratrans_stairs`).
module supratrans_protocol_follow
    use supratrans_kinds, only: wp
    use supratrans_config, only: run_config, fold_protocol
    use supratrans_period_map, only: period_map, set_half_period
    use supratrans_fixed_point_map, only: map_ok
    use supratrans_dense, only: dense_solve
    use supratrans_continuation, only: continue_branch, continuation_controls, continuation_result, continuation_stats, &
                                       cont_fold_found, cont_unstable_start
    use supratrans_continuation_types, only: wall_clock
    use supratrans_fold_record, only: fold_record, add_stats, add_branch_cost
    use supratrans_protocol_fate, only: fold_fate, fate_transmits, fate_localized
    use supratrans_stairs, only: stairs_transmission, stairs_found
    implicit none
    private

    public :: transmission_after, follow_to_transmission, counted_fate, counted_stairs, damped_shooting, &
              half_period_symmetric

    ! The outcomes of following to transmission (one enumeration).
    !> Following: driven just past a, the chain transmits (/transmission_fold is a).
    integer, parameter, public :: follow_at_push = 1
    !> Following: the fold of a branch followed transmits (/transmission_fold is that fold).
    integer, parameter, public :: follow_fold_transmits = 2
    !> Following: where the chain settled on no stable periodic state, a stair driven up from there transmits
    !> (/transmission_fold is that stair).
    integer, parameter, public :: follow_stairs_transmit = 3
    !> Following: the last branch followed ended without a fold, and the stairs, where climbed, did not transmit (the
    !> continuation's status of that branch says why: no fold below amplitude_max, Newton-shooting failed from the
    !> settled state, step too small, points exhausted, the state found unstable).
    integer, parameter, public :: follow_branch_ended = 4
    !> Following: the chain stayed localized past the folds of &scene follow_branches branches.
    integer, parameter, public :: follow_too_many = 5
    !> Following: the scheme failed while the fate of a drive was watched.
    integer, parameter, public :: follow_fate_failed = 6

contains

    !> Where the chain transmits, from the fate of a drive just past the amplitude `a` (a fold, a branch point, the
    !> last stair): `a` itself when it transmits (`follow_at_push`); the fold of the branch it settled on, or a later
    !> one, or a stair (`follow_to_transmission`), when it stays localized; `follow_fate_failed` when the watch failed.
    !> Fills `r%transmission_fold` (and, past a stair, `r%transmission_stairs`, `r%transmission_spread`) and counts
    !> the branches followed in `r%branches`.
    subroutine transmission_after(map, run, proto, ctl, a, fate, settled, r, outcome, ended)
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
        !> The outcome (`follow_*`).
        integer, intent(out) :: outcome
        !> With `follow_branch_ended`, the continuation's status of the last branch followed.
        integer, intent(out) :: ended

        ended = cont_fold_found
        if (fate == fate_transmits) then
            r%transmission_fold = a
            outcome = follow_at_push
        else if (fate == fate_localized) then
            call follow_to_transmission(map, run, proto, ctl, settled, a*(1.0_wp + proto%fate_push), r, outcome, ended)
        else
            outcome = follow_fate_failed
        end if
    end subroutine transmission_after

    !> Past a fold where the chain stays localized, the branch it settles on: from the `settled` state at amplitude
    !> `a` (Newton-shooting first), continued in A to its own fold, whose fate is tested in turn, up to
    !> `max_branches` branches in all. Where the chain settled on no stable periodic state (Newton-shooting from
    !> there finds an unstable one, or none), the chain itself is driven up in stairs from there (to amplitude_max),
    !> as a slow ramp would go on. Fills `r%transmission_fold` where a fold or a stair transmits and `r%branches`; the
    !> costs of these continuations are added to the record's.
    subroutine follow_to_transmission(map, run, proto, ctl, settled, a, r, outcome, ended)
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
        !> The outcome: `follow_fold_transmits`, `follow_stairs_transmit`, `follow_branch_ended`, `follow_too_many`
        !> or `follow_fate_failed`.
        integer, intent(out) :: outcome
        !> With `follow_branch_ended`, the continuation's status of the last branch followed.
        integer, intent(out) :: ended
        type(continuation_controls) :: next
        type(continuation_result) :: res
        type(continuation_stats) :: watched
        real(wp), allocatable :: x(:), chain(:)
        real(wp) :: amplitude, time
        integer :: fate, stairs
        logical :: half

        ended = cont_fold_found
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
                outcome = follow_branch_ended
                ended = res%status
                ! no stable periodic state where the chain settled (Newton-shooting found an unstable one, or none):
                ! the chain itself is driven up in stairs from there
                if (res%status == cont_unstable_start .or. res%n_points == 0) then
                    call counted_stairs(map, run, proto, chain, amplitude, ctl%amplitude_max, r, stairs)
                    if (stairs == stairs_found) outcome = follow_stairs_transmit
                end if
                return
            end if
            call counted_fate(map, run, proto, res%states(:, res%fold_index), &
                              res%fold_amplitude*(1.0_wp + proto%fate_push), r, fate, time, x)
            if (fate == fate_transmits) then
                r%transmission_fold = res%fold_amplitude
                outcome = follow_fold_transmits
                return
            end if
            if (fate /= fate_localized) then
                outcome = follow_fate_failed
                return
            end if
            amplitude = res%fold_amplitude*(1.0_wp + proto%fate_push)
        end do
        outcome = follow_too_many
    end subroutine follow_to_transmission

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

    !> `stairs_transmission` from `y` at `a0` below `top`, its maps and their time added to the record's costs; the
    !> stair on which the chain transmits, when it does, is the record's transmission (`transmission_stairs` 1, its
    !> spread `transmission_spread`).
    subroutine counted_stairs(map, run, proto, y, a0, top, r, outcome)
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
        !> The stairs' outcome (`stairs_found`, `stairs_none`, `stairs_failed`).
        integer, intent(out) :: outcome
        type(continuation_stats) :: stats
        real(wp) :: a, spread

        call stairs_transmission(map, run, proto, y, a0, top, a, spread, outcome, stats)
        call add_stats(r, stats)
        if (outcome /= stairs_found) return
        if (spread >= 0.0_wp) r%transmission_spread = spread
        r%transmission_fold = a
        r%transmission_stairs = 1
    end subroutine counted_stairs

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
    !> shooting then has its try, and gives up once its residual has grown tenfold: `follow_growth_limit`).
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

end module supratrans_protocol_follow
