!> Pseudo-arclength continuation in the drive amplitude A of the fixed points x = P(x; A) of a `fixed_point_map`
!> (the periodic states of the driven chain, when P is the one-period map), through the fold and some way along the
!> unstable branch beyond it, with the Floquet stability of every point.
!>
!> **Method** (Keller's pseudo-arclength, as in AUTO-07p and BifurcationKit.jl). A branch point is y = (x, A) with
!> F(y) = P(x; A) - x = 0. At a converged point y_i with Jacobian [J - I, dP/dA] the unit tangent t_i solves the
!> bordered system [[J - I, dP/dA]; [t_{i-1}^T]] z = e_{d+1}, t_i = z / |z| (oriented along t_{i-1}; at the start
!> t_0 = e_A, A increasing). The next point is predicted at y_i + ds t_i and corrected by Newton on
!> {F(y) = 0, t_i . (y - y_i) = ds} with the bordered matrix K_i = [[J - I, dP/dA]; [t_i^T]]. K_i differs from the
!> factorised tangent matrix in its last row only: it is solved with the same LU and a rank-one (Sherman-Morrison)
!> correction, whose denominator is |z| > 0, so one LU per point serves both the tangent and the corrector.
!>
!> **Chord / Shamanskii corrector.** The corrector reuses K_i (the Jacobian of the last point) and evaluates only P
!> (no Jacobian) while the Newton steps shrink by at least `chord_rate` per iteration and fast enough to reach the
!> tolerance within `newton_max_iter`; otherwise the Jacobian is evaluated at the current iterate and factorised,
!> and the corrector goes on with that one. With `floquet_every` = k > 1 and `reuse_jacobian`, the points without
!> multipliers get no Jacobian of their own: their tangent is the secant from the previous point and the last
!> factorised matrix is carried on (its last row changed by rank one); the points with multipliers, the fold and
!> the located crossings always have their own. The step ds grows (x1.5) after a fast correction
!> (<= `newton_fast` iterations, no refresh; 3 more allowed after a reused Jacobian), shrinks (x0.6) after a slow
!> one, and is halved and retried when the corrector fails or the tangent turns by more than `max_angle`.
!>
!> **Cost.** `continuation_stats` counts the evaluations of P alone and with its Jacobian, the LU factorisations, the
!> solves and the eigenvalue computations, with their wall-clock times. No state gets two `dgeev`: the multipliers of
!> every point where they were computed are kept (`spectra`), for the stability checks and for `branch_multipliers`; the
!> point the march stands on lends its Jacobian to the checks instead of a new one. Past the fold, once the stability is
!> lost and `floquet_every` > 1, only the first and the last point get multipliers (the unstable part's ends). A
!> crossing's secant needs the monodromy only (no tangent), and its corrector uses the bordered matrix of the secant's
!> last iterate (nearer than the bracket's left end: no refresh). On the sine-Gordon chain (N = 200, d = 400) the full
!> `dgeev` of the monodromy dominates (about 0.1 s of CPU against 0.010 s for a Jacobian, OpenBLAS): `floquet_every`
!> with `floquet_trend` is the control. Krylov (Arnoldi) eigenvalues are no substitute here: the monodromy is far from
!> normal, and its Ritz values leave the unit circle where no multiplier does.
!>
!> **Fold.** The fold (saddle-node) of the branch is where the tangent's A-component t_A changes sign. Between the two
!> points it is located by a safeguarded secant (Illinois) on t_A as a function of the pseudo-arclength step from the
!> point before it; each evaluation is a corrected point with its own tangent. Near the fold A(s) = A_f - kappa (s -
!> s_f)^2 / 2 and t_A = -kappa (s - s_f), so the located point is within t_A^2 / (2 kappa) of A_f; the secant stops when
!> that is below `fold_tol` (default 1e-10). The fold point is inserted in the branch, with its Newton residual and its
!> multipliers (one of them is +1 up to the location error). Between points with reused Jacobians the sign change is
!> first seen on the secants; both neighbours then get their exact tangents, and when the exact tangent of the current
!> point shows the fold already behind it, the fold is located between the previous point and the current one and
!> inserted there. The accuracy of A_f is also bounded by the residual: near the fold dA ~ |P(x) - x| / |l . dP/dA| (l
!> the left null vector of J - I), so `newton_tol` = 1e-10 leaves A_f good to ~1e-10 on the test maps.
!>
!> **Stability.** The Floquet multipliers are the eigenvalues of J = dP/dx at each point (every point, or every
!> `floquet_every`-th point; the points in between are examined when the verdict changes). The first point that is
!> not stable (`supratrans_floquet`, tolerance `crossing_tol`) ends the stable part; the crossing is classified by
!> its leading multiplier (+1 fold, -1 period doubling, complex pair torus) and located like the fold, by a secant on
!> max |mu| - 1 over the multipliers of that class, between the unstable point and the last point (at most 10 back)
!> where that class is strictly inside the unit circle, so that the location does not depend on crossing_tol (on
!> max |mu| - 1 - crossing_tol between the two points when no such point exists: a multiplier that hugs the
!> circle). A crossing through +1 after the fold is the fold itself. Only the first loss of stability is located; a
!> branch that regains stability before its fold (a weak instability bubble) shows it in `stable` and
!> `max_multiplier`.
!>
!> **The fold alone** (`floquet_every` = 0) computes no multipliers along the branch, but with `flip_watch` it
!> keeps two signs at every Jacobian it evaluates before the fold (in the corrector's refreshes, the Jacobian of an
!> iterate near the point; `supratrans_continuation_watch`): of det(J + I) (`flip_sign`, one more LU), which changes
!> where an odd number of real multipliers pass -1, and of the bordered matrix's determinant (from its LU), which
!> changes where a real multiplier passes +1 while the branch does not turn (a branch point), neither at a fold.
!> Where one changes, the multipliers of the two points say whether the stability was lost in between, and if so
!> that loss is located and classified as above (from the first point when the earlier one is already unstable:
!> the walk then finds what came first, a complex pair included). A complex pair that leaves the circle with no
!> real multiplier through +-1 after it is not seen: that needs `floquet_every` > 0.
!>
!> **The march** is a sequence of named events (multipliers due, fold bracketed, fold behind the point, past the
!> fold, ...), each decided in one place from the march's state (`supratrans_continuation_events`, which lists them
!> in the order the march asks them).
!>
!> An implementation of `fixed_point_map` holds its own work arrays: one map and one call per thread; this module
!> has no state of its own.
module supratrans_continuation
    use supratrans_kinds, only: wp
    use supratrans_fixed_point_map, only: fixed_point_map
    use supratrans_floquet, only: leading_crossing, crossing_distance, nearest_multiplier, crossing_fold, &
                                  crossing_period_doubling
    use supratrans_shooting, only: shoot, shooting_controls, shooting_result, shoot_converged
    use supratrans_continuation_types, only: continuation_controls, continuation_stats, point_spectrum, &
                                             continuation_result, continuation_status_name, wall_clock, &
                                             cont_fold_found, cont_no_fold, cont_newton_failed, cont_step_too_small, &
                                             cont_max_points, cont_unstable_start
    use supratrans_bordered_system, only: bordered_system, factor_bordered, tangent, set_row, move_system
    use supratrans_continuation_corrector, only: branch_point, correct, complete_point, point_multipliers, &
                                                 stored_point, move_point
    use supratrans_continuation_locate, only: locate, class_max, bisect_sign
    use supratrans_continuation_watch, only: moduli_trend, note_trend, sign_watch, note_signs
    use supratrans_continuation_events, only: march_state, start_march, start_unstable, points_exhausted, &
                                              nearing_circle, multipliers_due, turned_too_far, fold_behind_point, &
                                              step_too_small, fold_bracketed, fold_before_step, &
                                              sign_flipped_while_stable, fast_correction, slow_correction, past_fold, &
                                              beyond_max_amplitude, unstable_end_unexamined
    use supratrans_continuation_branch, only: branch_multipliers, allocate_branch, record_point, keep_spectrum, &
                                              update_tangent, set_stop, finish
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    implicit none
    private

    public :: continue_branch
    ! the interface of the continuation, defined with the branch's record and re-exported here
    public :: continuation_controls, continuation_stats, point_spectrum, continuation_result, branch_multipliers, &
              continuation_status_name
    public :: cont_fold_found, cont_no_fold, cont_newton_failed, cont_step_too_small, cont_max_points, &
              cont_unstable_start

    !> Most points examined backwards from the first unstable one for a bracket of the crossing |mu| = 1.
    integer, parameter :: walk_back = 10

contains

    !> Continue the fixed points of `map` in A from `amplitude_start` (controls), starting from `x0` (default 0),
    !> through the fold and `beyond_fold` points past it, with Floquet stability; see the module's documentation.
    subroutine continue_branch(map, ctl, res, x0)
        !> The map P(x; A).
        class(fixed_point_map), intent(inout) :: map
        !> Controls.
        type(continuation_controls), intent(in) :: ctl
        !> The branch, fold, stability and costs.
        type(continuation_result), intent(out) :: res
        !> Initial guess of the state at `amplitude_start` (default: x = 0).
        real(wp), intent(in), optional :: x0(:)
        type(bordered_system) :: base, next, fresh, psys
        type(branch_point) :: cur, trial, fold_pt, lost_pt, prev
        type(shooting_result) :: sres
        real(wp), allocatable :: x(:), wr(:), wi(:), row(:)
        real(wp) :: ds, nan, t_start, sigma
        integer :: d, n1, info, j, from
        ! ok: the last corrector or Jacobian succeeded; located: `locate` found the fold; nearing: `nearing_circle`
        ! at this step; behind: `fold_behind_point` at this step; have_mult: the new point got its multipliers
        logical :: ok, located, nearing, behind, have_mult
        type(march_state) :: ms
        type(moduli_trend) :: trend
        type(sign_watch) :: signs
        type(continuation_controls) :: march_ctl, side_ctl

        t_start = wall_clock()
        nan = ieee_value(1.0_wp, ieee_quiet_nan)
        d = map%dim
        n1 = d + 1
        res%fold_amplitude = nan
        res%fold_residual = nan
        res%fold_multiplier = nan
        res%fold_multiplier_imag = nan
        res%instability_amplitude = nan
        res%instability_lower = nan
        res%crossing_tol = ctl%crossing_tol
        call allocate_branch(res, d, ctl%max_points + 1)

        ! The start: Newton-shooting at fixed A
        allocate (x(d))
        x = 0.0_wp
        if (present(x0)) then
            if (size(x0) /= d) then
                call set_stop(res, cont_newton_failed)
                call finish(res, t_start)
                return
            end if
            x = x0
        end if
        call shoot(map, x, ctl%amplitude_start, shooting_controls(tol=ctl%newton_tol, &
                   max_iter=merge(ctl%start_max_iter, ctl%newton_max_iter, ctl%start_max_iter > 0), &
                   growth_limit=ctl%start_growth_limit), sres)
        res%stats%jacobian_evaluations = sres%jacobians
        res%stats%map_evaluations = 1      ! shoot's first evaluation, of P alone
        res%stats%factorisations = sres%iterations
        if (sres%status /= shoot_converged) then
            res%status = cont_newton_failed
            res%stop_reason = cont_newton_failed
            call finish(res, t_start)
            return
        end if
        cur%y = [x, ctl%amplitude_start]
        cur%iterations = sres%iterations
        row = [(0.0_wp, j=1, d), 1.0_wp]
        call complete_point(map, cur, row, base, ok, res%stats)
        if (.not. ok) then
            res%status = cont_newton_failed
            res%stop_reason = cont_newton_failed
            call finish(res, t_start)
            return
        end if
        ms = start_march(ctl)
        info = 1
        ! (the fold alone computes none but the fold's, and the first point's when its stability may end the branch)
        if (.not. ms%fold_only .or. ctl%stop_at_unstable_start) call point_multipliers(cur, res%stats, wr, wi, info)
        call record_point(map, res, cur, wr, wi, info == 0)
        if (info == 0) call note_trend(trend, cur%s, wr, wi)
        ms%stability_lost = start_unstable(res)
        if (ms%stability_lost) then
            res%instability_amplitude = ctl%amplitude_start
            res%instability_lower = ctl%amplitude_start
            res%instability_type = leading_crossing(wr, wi, ctl%crossing_tol)
            if (ctl%stop_at_unstable_start) then
                call set_stop(res, cont_unstable_start)
                call finish(res, t_start)
                return
            end if
        end if

        ! the fold alone: the signs of det(J + I) and of the bordered matrix watched along the branch (a real
        ! multiplier through -1 or +1)
        march_ctl = ctl
        march_ctl%flip_watch = ms%watch_flips
        ! (the points a secant or a bisection corrects are not the branch's: no signs watched there)
        side_ctl = ctl
        side_ctl%flip_watch = .false.
        if (ms%watch_flips) call note_signs(signs, cur, base, 1, res%stats, from)
        ds = min(max(ctl%ds0, ctl%ds_min), ctl%ds_max)
        nearing = .false.
        ! Each step asks the events of `supratrans_continuation_events` in the order of its documentation
        march: do
            if (points_exhausted(ctl, res)) then
                call set_stop(res, cont_max_points)
                exit march
            end if
            call correct(map, cur, base, ds, march_ctl, trial, ok, res%stats, fresh)
            if (ok) then
                ! the new point gets its own Jacobian where its multipliers are due
                nearing = nearing_circle(ms, ctl, trend, cur%s + ds)
                if (multipliers_due(ms, res, nearing) .or. .not. ctl%reuse_jacobian) then
                    call complete_point(map, trial, cur%t, next, ok, res%stats)
                else
                    ! Shamanskii across points: the secant as tangent, the last factorised system kept
                    trial%t = (trial%y - cur%y)/norm2(trial%y - cur%y)
                    if (trial%refreshes > 0) then
                        call move_system(fresh, next)
                    else
                        next = base
                    end if
                    call set_row(next, trial%t, info, res%stats)
                    ! the carried matrix cannot take the secant as its last row: a Jacobian here after all
                    if (info /= 0) call complete_point(map, trial, cur%t, next, ok, res%stats)
                end if
                if (ok) ok = .not. turned_too_far(ctl, cur, trial)
            end if
            if (.not. ok .and. .not. cur%exact) then
                ! before shrinking the step, give the point we stand on its own Jacobian and tangent
                call complete_point(map, cur, cur%t, base, ok, res%stats)
                if (ok) then
                    ! (asked before the recorded secant is replaced by the exact tangent)
                    behind = fold_behind_point(res, cur)
                    call update_tangent(res, res%n_points, cur)
                    if (behind) call fold_before_cur()
                    cycle march
                end if
            end if
            if (.not. ok) then
                ds = 0.5_wp*ds
                if (step_too_small(ctl, ds)) then
                    call set_stop(res, cont_step_too_small)
                    exit march
                end if
                cycle march
            end if
            trial%s = cur%s + ds

            ! The fold: t_A changes sign between cur and trial (secants first, then exact tangents on both sides)
            if (fold_bracketed(res, cur, trial)) then
                if (.not. trial%exact) call complete_point(map, trial, cur%t, next, ok, res%stats)
                if (ok .and. .not. cur%exact) then
                    call complete_point(map, cur, cur%t, base, ok, res%stats)
                    if (ok) call update_tangent(res, res%n_points, cur)
                end if
                if (ok .and. fold_bracketed(res, cur, trial)) then
                    ! the bracket is trial's step along cur's (now exact) tangent; the fold's arclength lies
                    ! between theirs in proportion
                    sigma = max(dot_product(cur%t, trial%y - cur%y), tiny(1.0_wp))
                    call locate(map, cur, base, sigma, 0, 0.0_wp, side_ctl, fold_pt, wr, wi, located, res%stats, trial)
                    if (.not. located) then
                        fold_pt = trial
                        call point_multipliers(fold_pt, res%stats, wr, wi, info)
                    end if
                    fold_pt%s = cur%s + (trial%s - cur%s)*min(max((fold_pt%s - cur%s)/sigma, 0.0_wp), 1.0_wp)
                    call record_fold(res%n_points + 1)
                else if (ok) then
                    ! the exact tangent at cur already points the way the branch goes after the fold
                    if (fold_before_step(cur, trial)) call fold_before_cur()
                end if
                ok = .true.
            end if

            ! (asked again: a fold recorded at this step, or the stability lost there, changes what is due)
            have_mult = trial%exact .and. multipliers_due(ms, res, nearing)
            if (have_mult) then
                call point_multipliers(trial, res%stats, wr, wi, info)
                have_mult = info == 0
                if (have_mult) call note_trend(trend, trial%s, wr, wi)
            end if
            call record_point(map, res, trial, wr, wi, have_mult)
            if (have_mult) call check_stability(res%n_points, trial)
            if (ms%watch_flips) then
                ! the fold alone: a real multiplier through -1 or +1 since the last signs, before the fold
                call note_signs(signs, trial, next, res%n_points, res%stats, from)
                if (sign_flipped_while_stable(ms, res, from)) call flip_crossing(from, res%n_points)
            end if
            if (res%fold_index > 0) res%points_beyond_fold = res%points_beyond_fold + 1

            ! Step control (a corrector that started from a reused Jacobian, cur's secant, is allowed more steps)
            if (fast_correction(ctl, trial, cur%exact)) then
                ds = min(1.5_wp*ds, ctl%ds_max)
            else if (slow_correction(ctl, trial, cur%exact)) then
                ds = max(0.6_wp*ds, ctl%ds_min)
            end if
            call move_point(trial, cur)
            call move_system(next, base)

            if (past_fold(ctl, res, cur)) then
                call set_stop(res, cont_fold_found)
                exit march
            end if
            if (beyond_max_amplitude(ctl, res, cur)) then
                call set_stop(res, cont_no_fold)
                exit march
            end if
        end do march
        if (unstable_end_unexamined(ms, res)) then
            ! the last point past the fold gets its multipliers (the end of the unstable part)
            call point_with_jacobian(res%n_points, prev, info)
            if (info == 0) call point_multipliers(prev, res%stats, wr, wi, info)
            if (info == 0) call keep_spectrum(res, res%n_points, wr, wi)
        end if
        call finish(res, t_start)

    contains

        !> The fold between the previous recorded point and cur (the last one): the exact tangent at the previous
        !> point, the secant on t_A from there, the fold point inserted before cur.
        subroutine fold_before_cur()
            integer :: linfo
            real(wp) :: sig

            if (res%n_points < 2) return
            call stored_point(map, res, res%n_points - 1, prev, res%stats, linfo)
            if (linfo /= 0) return
            call factor_bordered(prev%jac, prev%dpda, prev%t, psys, linfo, res%stats)
            if (linfo == 0) call tangent(psys, prev%t, linfo, res%stats)
            if (linfo /= 0) return
            if (prev%t(n1)*cur%t(n1) >= 0.0_wp) return
            sig = dot_product(prev%t, cur%y - prev%y)
            if (sig <= 0.0_wp) return
            call locate(map, prev, psys, sig, 0, 0.0_wp, side_ctl, fold_pt, wr, wi, located, res%stats, cur)
            if (.not. located) then
                fold_pt = cur
                call point_multipliers(fold_pt, res%stats, wr, wi, linfo)
            end if
            fold_pt%s = prev%s + (cur%s - prev%s)*min(max((fold_pt%s - prev%s)/sig, 0.0_wp), 1.0_wp)
            call record_fold(res%n_points)
        end subroutine fold_before_cur

        !> Record the located fold point `fold_pt` (multipliers wr, wi) at branch index `pos` (appended, or inserted
        !> before the last point), with its amplitude, residual and multiplier nearest +1.
        subroutine record_fold(pos)
            !> (by value: the caller may pass res%n_points, which recording the point changes)
            integer, value :: pos
            integer :: kk

            res%fold_amplitude = fold_pt%y(n1)
            res%fold_residual = fold_pt%residual
            kk = nearest_multiplier(wr, wi, 1.0_wp)
            if (kk > 0) then
                res%fold_multiplier = wr(kk)
                res%fold_multiplier_imag = wi(kk)
            end if
            call record_point(map, res, fold_pt, wr, wi, .true., pos)
            res%fold_index = pos
            if (ms%fold_only) then
                ! no stability along the branch: the fold's multipliers are its own record, no crossing is sought
                if (pos < res%n_points .and. res%points_beyond_fold == 0) res%points_beyond_fold = 1
            else if (pos == res%n_points) then
                call check_stability(pos, fold_pt)
            else
                ! inserted before the last point, which is past the fold
                if (res%points_beyond_fold == 0) res%points_beyond_fold = 1
                if (ms%last_checked >= pos) then
                    ms%last_checked = ms%last_checked + 1
                else
                    call check_stability(pos, fold_pt)
                end if
            end if
        end subroutine record_fold

        !> The multipliers of branch point `i` (computed now, or recomputed from its stored state) decide whether
        !> it is stable; the first stable-to-unstable change is located and classified.
        subroutine check_stability(i, pt)
            integer, intent(in) :: i
            type(branch_point), intent(in) :: pt
            type(branch_point) :: left
            real(wp), allocatable :: lr(:), li(:)
            real(wp) :: shift, g_k, g_m, sigma_k, lower
            complex(wp) :: mu_k
            integer :: k, linfo, kind, m, jl, have_left
            logical :: inside, narrowed

            if (ms%stability_lost) then
                ms%last_checked = i
                return
            end if
            if (res%stable(i) == 1) then
                ms%last_checked = i
                return
            end if
            ! Unstable at i, stable at last_checked: find the first unstable point in between
            k = ms%last_checked + 1
            do while (k < i)
                if (res%stable(k) < 0) then
                    call point_with_jacobian(k, left, linfo)
                    if (linfo == 0) call point_multipliers(left, res%stats, lr, li, linfo)
                    if (linfo == 0) call keep_spectrum(res, k, lr, li)
                end if
                if (res%stable(k) == 0) exit
                k = k + 1
            end do
            ms%stability_lost = .true.
            ms%last_checked = i
            ! Multipliers at k (kept when computed; computed again otherwise)
            if (allocated(res%spectra(k)%wr)) then
                lr = res%spectra(k)%wr
                li = res%spectra(k)%wi
            else if (k == i) then
                call point_multipliers(pt, res%stats, lr, li, linfo)
            else
                call point_with_jacobian(k, left, linfo)
                call point_multipliers(left, res%stats, lr, li, linfo)
            end if
            kind = leading_crossing(lr, li, ctl%crossing_tol)
            g_k = crossing_distance(lr, li, kind)
            mu_k = cmplx(0.0_wp, 0.0_wp, kind=wp)
            if (class_max(lr, li, kind) > 0) mu_k = cmplx(lr(class_max(lr, li, kind)), li(class_max(lr, li, kind)), kind=wp)
            if (kind == crossing_fold .and. res%fold_index > 0 .and. k >= res%fold_index - 1) then
                ! A real multiplier through +1 after the fold: the fold itself
                res%instability_amplitude = res%fold_amplitude
                res%instability_lower = res%fold_amplitude
                res%instability_type = crossing_fold
                return
            end if
            res%instability_type = kind
            res%instability_amplitude = res%amplitude(k)
            res%instability_lower = res%amplitude(max(k - 1, 1))
            ! The bracket: back from k - 1 to the last point whose multipliers of this kind are strictly inside the
            ! unit circle (at most walk_back points), and |mu| = 1 located between it and the next point; where
            ! there is none (a multiplier that hugs the circle), |mu| = 1 + crossing_tol between k - 1 and k
            inside = .false.
            have_left = 0
            do m = k - 1, max(1, k - walk_back), -1
                if (allocated(res%spectra(m)%wr)) then
                    lr = res%spectra(m)%wr
                    li = res%spectra(m)%wi
                else
                    call point_with_jacobian(m, left, linfo)
                    if (linfo /= 0) return
                    have_left = m
                    call point_multipliers(left, res%stats, lr, li, linfo)
                    if (linfo /= 0) return
                    call keep_spectrum(res, m, lr, li)
                end if
                g_m = crossing_distance(lr, li, kind)
                if (g_m < 0.0_wp) then
                    inside = .true.
                    exit
                end if
            end do
            if (inside) then
                shift = 0.0_wp
                jl = m
            else
                shift = ctl%crossing_tol
                jl = k - 1
            end if
            if (have_left /= jl) then
                call point_with_jacobian(jl, left, linfo)
                if (linfo /= 0) return
            end if
            narrowed = .false.
            block
                type(bordered_system) :: sys
                call factor_bordered(left%jac, left%dpda, left%t, sys, linfo, res%stats)
                if (linfo /= 0) return
                if (inside .and. jl + 1 == k) then
                    ! both ends known: the bracket is point k's step along left's tangent
                    sigma_k = dot_product(left%t, [res%states(:, k), res%amplitude(k)] - left%y)
                    if (sigma_k > 0.0_wp) then
                        call locate(map, left, sys, sigma_k, kind, shift, side_ctl, lost_pt, lr, li, located, res%stats, &
                                    g_lo=g_m, g_hi=g_k, mu_guess=mu_k)
                    else
                        call locate(map, left, sys, res%arclength(jl + 1) - res%arclength(jl), kind, shift, side_ctl, &
                                    lost_pt, lr, li, located, res%stats, g_lo=g_m)
                    end if
                else if (inside) then
                    call locate(map, left, sys, res%arclength(jl + 1) - res%arclength(jl), kind, shift, side_ctl, lost_pt, &
                                lr, li, located, res%stats, g_lo=g_m)
                else
                    call locate(map, left, sys, res%arclength(jl + 1) - res%arclength(jl), kind, shift, side_ctl, lost_pt, &
                                lr, li, located, res%stats)
                end if
                if (.not. located .and. (kind == crossing_fold .or. kind == crossing_period_doubling)) then
                    ! a real multiplier through +-1 that the secant on the multipliers did not locate (a branch
                    ! point): bisection on the sign it changes, from the last point before k
                    sigma_k = dot_product(left%t, [res%states(:, k), res%amplitude(k)] - left%y)
                    if (sigma_k > 0.0_wp) then
                        call bisect_sign(map, left, sys, sigma_k, kind, side_ctl, lost_pt, located, narrowed, lower, &
                                         res%stats)
                        if (narrowed) res%instability_amplitude = lost_pt%y(n1)
                        if (narrowed) res%instability_lower = lower
                    end if
                end if
            end block
            if (located) res%instability_amplitude = lost_pt%y(n1)
            if (located) res%instability_lower = res%instability_amplitude
            if (located .or. narrowed) res%instability_point = lost_pt%y
            if (located .or. narrowed) res%instability_tangent = left%t
        end subroutine check_stability

        !> A change of the watched signs between the recorded points a and b: their multipliers say whether the
        !> branch lost its stability in between (a stable, b not); that loss is then located and classified like
        !> every first loss (`check_stability`, from a). A branch already unstable at a lost its stability before
        !> it (a complex pair, which the signs do not see): the first loss is then sought from the first point.
        subroutine flip_crossing(a, b)
            integer, intent(in) :: a, b
            type(branch_point) :: unused
            integer :: linfo

            call spectrum_at(b, linfo)
            if (linfo /= 0 .or. res%stable(b) /= 0) return
            call spectrum_at(a, linfo)
            if (linfo /= 0) return
            ms%last_checked = a
            if (res%stable(a) /= 1) then
                call spectrum_at(1, linfo)
                if (linfo /= 0 .or. res%stable(1) /= 1) return
                ms%last_checked = 1
            end if
            call check_stability(b, unused)          ! (b's multipliers are kept: `unused` is not read)
        end subroutine flip_crossing

        !> The multipliers of recorded point i kept with the branch (computed unless they are).
        subroutine spectrum_at(i, linfo)
            integer, intent(in) :: i
            integer, intent(out) :: linfo
            type(branch_point) :: p
            real(wp), allocatable :: lr(:), li(:)

            linfo = 0
            if (allocated(res%spectra(i)%wr)) return
            call point_with_jacobian(i, p, linfo)
            if (linfo == 0) call point_multipliers(p, res%stats, lr, li, linfo)
            if (linfo == 0) call keep_spectrum(res, i, lr, li)
        end subroutine spectrum_at

        !> Recorded point `i` with its Jacobian: `cur` when it is that point and has its own Jacobian (no
        !> evaluation), else rebuilt from the stored state (`stored_point`).
        subroutine point_with_jacobian(i, p, linfo)
            integer, intent(in) :: i
            type(branch_point), intent(inout) :: p
            integer, intent(out) :: linfo
            logical :: same

            linfo = 0
            same = .false.
            if (cur%exact .and. allocated(cur%jac) .and. allocated(cur%y)) then
                same = cur%y(n1) == res%amplitude(i) .and. cur%s == res%arclength(i)
                if (same) same = all(cur%y(1:d) == res%states(:, i)) .and. all(cur%t == res%tangents(:, i))
            end if
            if (same) then
                p%y = cur%y
                p%t = cur%t
                p%s = cur%s
                p%iterations = cur%iterations
                p%residual = cur%residual
                p%exact = .true.
                p%jac = cur%jac
                p%dpda = cur%dpda
            else
                call stored_point(map, res, i, p, res%stats, linfo)
            end if
        end subroutine point_with_jacobian

    end subroutine continue_branch

end module supratrans_continuation
