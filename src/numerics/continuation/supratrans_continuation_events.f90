!> The events of the continuation's march (`supratrans_continuation`): the march's state between its steps
!> (`march_state`: how often multipliers are due, whether the first loss of stability was seen, the last point
!> whose stability was checked) and what happened at a step, each decided in one place by a pure function of that
!> state, the controls and the branch. In the order the march asks them at each step:
!>
!> 1. `points_exhausted`: `max_points` points recorded (the march ends, `cont_max_points`);
!> 2. after a converged corrector: `nearing_circle` (the trend of the largest moduli may reach the unit circle
!>    within the step) and `multipliers_due` (the point gets its own Jacobian); `turned_too_far` (the tangent
!>    turned by more than `max_angle`: the step failed);
!> 3. after a failed step from a point with a secant tangent, that point given its exact tangent:
!>    `fold_behind_point` (its exact and its secant tangent disagree in sign: the fold lies behind it);
!> 4. after a failed step: `step_too_small` (the halved step is below `ds_min`: the march ends,
!>    `cont_step_too_small`);
!> 5. `fold_bracketed` (t_A changes sign over the step, no fold yet), and once both ends have exact tangents
!>    either still `fold_bracketed` (located between them) or `fold_before_step` (the fold was before the step);
!> 6. `multipliers_due` again for the new point, which gets them where its tangent is exact; a stable-to-unstable
!>    change then sets `stability_lost` (`check_stability`);
!> 7. with `flip_watch` (the fold alone): `sign_flipped_while_stable` (a watched sign changed before the fold);
!> 8. `fast_correction` / `slow_correction` (the step grows or shrinks);
!> 9. `past_fold` (the `beyond_fold` points, or `beyond_fold_distance`, past the fold: the march ends,
!>    `cont_fold_found`) and `beyond_max_amplitude` (A > `amplitude_max` with no fold: the march ends,
!>    `cont_no_fold`).
!>
!> After the march: `unstable_end_unexamined` (the last point past a fold, on an unstable branch, gets its
!> multipliers). No state of its own.
module supratrans_continuation_events
    use supratrans_kinds, only: wp
    use supratrans_continuation_types, only: continuation_controls, continuation_result
    use supratrans_continuation_corrector, only: branch_point
    use supratrans_continuation_watch, only: moduli_trend, trend_due
    implicit none
    private

    public :: start_march, start_unstable, points_exhausted, nearing_circle, multipliers_due, turned_too_far, &
              fold_behind_point, step_too_small, fold_bracketed, fold_before_step, sign_flipped_while_stable, &
              fast_correction, slow_correction, past_fold, beyond_max_amplitude, unstable_end_unexamined

    !> Corrector iterations more that the step control allows when the corrector started from a reused Jacobian.
    integer, parameter :: reuse_slack = 3

    !> What the march carries from one step to the next besides its points: the schedule of the multipliers (fixed
    !> by the controls) and the stability seen so far.
    type, public :: march_state
        !> Multipliers at every `every`-th point (`floquet_every`; huge for the fold alone).
        integer :: every = 1
        !> The fold alone (`floquet_every` = 0): no multipliers along the branch, the fold's own.
        logical :: fold_only = .false.
        !> The fold alone with `flip_watch`: the signs of det(J + I) and of the bordered matrix watched.
        logical :: watch_flips = .false.
        !> The first loss of stability was seen (at the start, or located between two points).
        logical :: stability_lost = .false.
        !> The last recorded point whose stability was checked: a loss is sought after it.
        integer :: last_checked = 1
    end type march_state

contains

    !> The march's state at its start, from the controls: its multiplier schedule, the stability not yet lost.
    pure function start_march(ctl) result(ms)
        !> Controls.
        type(continuation_controls), intent(in) :: ctl
        type(march_state) :: ms

        ms%fold_only = ctl%floquet_every == 0
        ms%every = max(1, ctl%floquet_every)
        if (ms%fold_only) ms%every = huge(1)
        ms%watch_flips = ms%fold_only .and. ctl%flip_watch
        ms%stability_lost = .false.
        ms%last_checked = 1
    end function start_march

    !> The first point of the branch has multipliers and is not stable.
    pure logical function start_unstable(res)
        !> The branch (its first point recorded).
        type(continuation_result), intent(in) :: res

        start_unstable = res%stable(1) == 0
    end function start_unstable

    !> The branch has its `max_points` points: no step more.
    pure logical function points_exhausted(ctl, res)
        !> Controls.
        type(continuation_controls), intent(in) :: ctl
        !> The branch.
        type(continuation_result), intent(in) :: res

        points_exhausted = res%n_points >= ctl%max_points
    end function points_exhausted

    !> The multipliers are needed at arclength `s_next` although not due: with `floquet_every` > 1 and
    !> `floquet_trend`, before any loss of stability, the trend of the largest moduli may reach the unit circle
    !> by then (`trend_due`).
    pure logical function nearing_circle(ms, ctl, trend, s_next)
        !> The march's state.
        type(march_state), intent(in) :: ms
        !> Controls.
        type(continuation_controls), intent(in) :: ctl
        !> The trend of the largest moduli.
        type(moduli_trend), intent(in) :: trend
        !> Arclength of the next point.
        real(wp), intent(in) :: s_next

        nearing_circle = ms%every > 1 .and. ctl%floquet_trend .and. .not. ms%stability_lost
        nearing_circle = nearing_circle .and. trend_due(trend, s_next, ctl%crossing_tol)
        nearing_circle = nearing_circle .and. .not. ms%fold_only
    end function nearing_circle

    !> The multipliers are due at the point about to be recorded (the branch's point `res%n_points` + 1): never
    !> for the fold alone; past the fold with the stability already lost and `floquet_every` > 1, only at the first
    !> point with multipliers past the fold (the unstable part's first end); otherwise every `every`-th point, right
    !> after the fold (appended or inserted), and where the trend is `nearing` the circle.
    pure logical function multipliers_due(ms, res, nearing)
        !> The march's state.
        type(march_state), intent(in) :: ms
        !> The branch.
        type(continuation_result), intent(in) :: res
        !> `nearing_circle` at this step.
        logical, intent(in) :: nearing

        if (ms%fold_only) then
            multipliers_due = .false.
        else if (ms%every > 1 .and. res%fold_index > 0 .and. ms%stability_lost) then
            ! (true when no point is past the fold)
            multipliers_due = all(res%stable(res%fold_index + 1:res%n_points) < 0)
        else
            multipliers_due = mod(res%n_points, ms%every) == 0 .or. &
                              (res%fold_index > 0 .and. res%fold_index >= res%n_points - 1) .or. nearing
        end if
    end function multipliers_due

    !> The tangent turned by more than `max_angle` from `cur` to `trial` (the step is refused).
    pure logical function turned_too_far(ctl, cur, trial)
        !> Controls.
        type(continuation_controls), intent(in) :: ctl
        !> The point the march stands on and the corrected next one.
        type(branch_point), intent(in) :: cur, trial

        turned_too_far = .not. (dot_product(cur%t, trial%t) >= cos(ctl%max_angle))
    end function turned_too_far

    !> No fold yet, and the exact tangent just computed at `cur` (the last recorded point) has an A-component of
    !> the sign opposite to its recorded secant's: the fold lies between the previous point and `cur`. Asked
    !> before the recorded tangent is replaced by the exact one.
    pure logical function fold_behind_point(res, cur)
        !> The branch.
        type(continuation_result), intent(in) :: res
        !> The last recorded point, with its exact tangent.
        type(branch_point), intent(in) :: cur

        fold_behind_point = res%tangent_amplitude(res%n_points)*cur%t(size(cur%t)) < 0.0_wp .and. res%fold_index == 0
    end function fold_behind_point

    !> The step `ds`, halved after a failure, is below `ds_min`: the march gives up.
    pure logical function step_too_small(ctl, ds)
        !> Controls.
        type(continuation_controls), intent(in) :: ctl
        !> The step.
        real(wp), intent(in) :: ds

        step_too_small = ds < ctl%ds_min
    end function step_too_small

    !> No fold yet, and the tangents' A-components at `cur` and `trial` have opposite signs: the fold lies
    !> between them (where both tangents are exact; secants first show where to look).
    pure logical function fold_bracketed(res, cur, trial)
        !> The branch.
        type(continuation_result), intent(in) :: res
        !> The point the march stands on and the corrected next one.
        type(branch_point), intent(in) :: cur, trial

        fold_bracketed = res%fold_index == 0 .and. cur%t(size(cur%t))*trial%t(size(trial%t)) < 0.0_wp
    end function fold_bracketed

    !> With exact tangents at both ends of a step whose secants bracketed the fold: the tangents agree in sign and
    !> the step goes the way cur's tangent points, the way the branch goes after the fold: the fold was before the
    !> step, between the previous recorded point and `cur`.
    pure logical function fold_before_step(cur, trial)
        !> The point the march stands on and the corrected next one (exact tangents).
        type(branch_point), intent(in) :: cur, trial
        integer :: n1

        n1 = size(cur%t)
        fold_before_step = cur%t(n1)*trial%t(n1) > 0.0_wp .and. (trial%y(n1) - cur%y(n1))*cur%t(n1) > 0.0_wp
    end function fold_before_step

    !> A watched sign changed since recorded point `from` (> 0; `note_signs`), while the branch is still stable
    !> and that point lies before the fold: a real multiplier may have passed -1 or +1 there.
    pure logical function sign_flipped_while_stable(ms, res, from)
        !> The march's state.
        type(march_state), intent(in) :: ms
        !> The branch.
        type(continuation_result), intent(in) :: res
        !> The recorded point of the previous signs when they changed, else 0.
        integer, intent(in) :: from

        sign_flipped_while_stable = from > 0 .and. .not. ms%stability_lost .and. &
                                    (res%fold_index == 0 .or. from < res%fold_index)
    end function sign_flipped_while_stable

    !> The corrector of `trial` converged fast (at most `newton_fast` iterations, `reuse_slack` more when the step
    !> started from a reused Jacobian, `from_exact` false; no refresh): the step may grow.
    pure logical function fast_correction(ctl, trial, from_exact)
        !> Controls.
        type(continuation_controls), intent(in) :: ctl
        !> The corrected point.
        type(branch_point), intent(in) :: trial
        !> Whether the step started from a point with its own Jacobian.
        logical, intent(in) :: from_exact

        fast_correction = trial%iterations <= ctl%newton_fast + merge(0, reuse_slack, from_exact) .and. &
                          trial%refreshes == 0
    end function fast_correction

    !> The corrector of `trial` was slow (at least `newton_slow` iterations, `reuse_slack` more when the step
    !> started from a reused Jacobian, or two refreshes): the step shrinks.
    pure logical function slow_correction(ctl, trial, from_exact)
        !> Controls.
        type(continuation_controls), intent(in) :: ctl
        !> The corrected point.
        type(branch_point), intent(in) :: trial
        !> Whether the step started from a point with its own Jacobian.
        logical, intent(in) :: from_exact

        slow_correction = trial%iterations >= ctl%newton_slow + merge(0, reuse_slack, from_exact) .or. &
                          trial%refreshes >= 2
    end function slow_correction

    !> The march has gone far enough past the fold: `beyond_fold` points, or (`beyond_fold_distance` > 0) the
    !> amplitude of `cur`, the last point, that far below A_f, whichever comes first.
    pure logical function past_fold(ctl, res, cur)
        !> Controls.
        type(continuation_controls), intent(in) :: ctl
        !> The branch.
        type(continuation_result), intent(in) :: res
        !> The last recorded point.
        type(branch_point), intent(in) :: cur

        past_fold = .false.
        if (res%fold_index > 0) then
            past_fold = res%points_beyond_fold >= ctl%beyond_fold
            if (ctl%beyond_fold_distance > 0.0_wp) then
                past_fold = past_fold .or. res%fold_amplitude - cur%y(size(cur%y)) >= ctl%beyond_fold_distance
            end if
        end if
    end function past_fold

    !> No fold, and `cur`, the last point, lies beyond `amplitude_max`: the branch has no fold below it.
    pure logical function beyond_max_amplitude(ctl, res, cur)
        !> Controls.
        type(continuation_controls), intent(in) :: ctl
        !> The branch.
        type(continuation_result), intent(in) :: res
        !> The last recorded point.
        type(branch_point), intent(in) :: cur

        beyond_max_amplitude = res%fold_index == 0 .and. cur%y(size(cur%y)) > ctl%amplitude_max
    end function beyond_max_amplitude

    !> After the march, with multipliers along the branch: its last point lies past the fold on a branch that lost
    !> its stability and has no multipliers yet (the unstable part's last end).
    pure logical function unstable_end_unexamined(ms, res)
        !> The march's state.
        type(march_state), intent(in) :: ms
        !> The branch.
        type(continuation_result), intent(in) :: res

        unstable_end_unexamined = .false.
        if (res%fold_index > 0 .and. ms%stability_lost .and. res%n_points > res%fold_index .and. .not. ms%fold_only) then
            unstable_end_unexamined = res%stable(res%n_points) < 0
        end if
    end function unstable_end_unexamined

end module supratrans_continuation_events
