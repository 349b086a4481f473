!> The branch of driven periodic states from rest to its fold, by harmonic balance: pseudo-arclength continuation
!> in (x, A) of R(x; A) = 0 (`supratrans_harmonic_balance`), the fold located where the tangent's A component
!> changes sign, and the fold converged in the number K of harmonics.
!>
!> **Corrector.** Newton on [R(x; A); t . (X - X_p)] = 0 from the predictor X_p = X + h t, X = (x, A). The bordered
!> system [J, R_A; t_x^T, t_A] is solved by block elimination on the banded LU of J (the border stays off the band)
!> with one step of iterative refinement on the whole bordered system (Govaerts' mixed block elimination), which keeps
!> it accurate next to the fold, where J is singular. Along the branch the corrector is the chord method to
!> `branch_tol`; the points that locate the fold are Newton's to max |R| <= `residual_tol` and an update's max-norm
!> <= `step_tol`.
!>
!> **Fold.** Between the last point with tangent t_A > 0 and the first with t_A < 0 the fold is bracketed in the
!> arclength sigma along the last tangent t0 (points X(sigma) on the planes t0 . (X - X0) = sigma); the tangent's A
!> component there, tau_A(sigma), is zero at the fold and is driven to zero by the Illinois method. A is stationary
!> in sigma there, so the fold amplitude is located to roundoff long before sigma is.
!>
!> **Harmonics.** `hb_fold_converged` locates the fold with K = min(ceiling(3 / Omega), 16) harmonics from rest,
!> then with K' = K + max(2, K/2) from the fold of K (its state and tangent padded with zeros), until the two folds
!> agree within `harmonics_tol` and the highest harmonic's amplitude at the fold is below it too (the state, not
!> only the fold's amplitude, is converged: A_f is stationary at the fold, so it converges faster than the state);
!> the fold of the larger K is kept and |A_f(K') - A_f(K)| is its truncation estimate (an upper bound, as the
!> series converges spectrally).
module supratrans_hb_continuation
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_finite
    use supratrans_kinds, only: wp
    use supratrans_error, only: error_type
    use supratrans_config, only: chain_params, closure_absorber
    use supratrans_harmonic_balance, only: hb_system, hb_init, hb_residual, hb_jacobian, hb_factor, hb_solve, &
                                           hb_apply_jacobian, hb_amplitude_column, hb_measures, &
                                           hb_pad
    use supratrans_continuation_types, only: cont_fold_found, cont_no_fold, cont_newton_failed, cont_step_too_small, &
                                             cont_max_points
    implicit none
    private

    public :: hb_fold, hb_fold_converged, hb_first_harmonics

    !> Most harmonics of the branch traced from rest when K is chosen (harmonics = 0): at low Omega the branch is
    !> traced with these and its fold carried to more (about a tenth of the LU work of a branch at K = 3 / Omega).
    integer, parameter, public :: branch_harmonics_max = 16

    !> Controls of a harmonic-balance continuation.
    type, public :: hb_controls
        !> First pseudo-arclength step.
        real(wp) :: step = 0.05_wp
        !> Largest step.
        real(wp) :: step_max = 0.2_wp
        !> Smallest step before giving up.
        real(wp) :: step_min = 1.0e-8_wp
        !> Most branch points (the fold and the points past it included).
        integer :: points_max = 150
        !> Points continued past the fold, on the unstable branch.
        integer :: beyond_fold = 0
        !> Largest A: beyond it with no fold, the branch has none (status `cont_no_fold`).
        real(wp) :: amplitude_max = 10.0_wp
        !> Newton's test on max |R| at the fold (and the points that locate it).
        real(wp) :: residual_tol = 1.0e-11_wp
        !> Newton's test on max |R| and on the update at the points along the branch, which only lead to the fold.
        real(wp) :: branch_tol = 1.0e-8_wp
        !> Newton's test on the update's max-norm.
        real(wp) :: step_tol = 1.0e-10_wp
        !> Newton iterations per point.
        integer :: newton_max_iter = 12
        !> Harmonics to start from in `hb_fold_converged` (0: `hb_first_harmonics`).
        integer :: harmonics = 0
        !> Most harmonics.
        integer :: harmonics_max = 64
        !> Agreement of the folds at K and K' that ends the search in K.
        real(wp) :: harmonics_tol = 1.0e-9_wp
        !> Closure at site N (`closure_absorber`, `closure_radiation` of `supratrans_config`).
        integer :: closure = closure_absorber
        !> Keep the state (x, A) of every branch point (`hb_result%states`), for their stability.
        logical :: keep_states = .false.
    end type hb_controls

    !> The branch from rest and its fold.
    type, public :: hb_result
        !> `cont_*` status (`supratrans_continuation_types`): 0 fold found.
        integer :: status = cont_no_fold
        !> Fold amplitude A_f; NaN when none.
        real(wp) :: fold_amplitude = 0.0_wp
        !> max |R| at the located fold.
        real(wp) :: fold_residual = 0.0_wp
        !> Harmonics K of the kept fold.
        integer :: harmonics = 0
        !> |A_f(K) - A_f(K_previous)| of the last step in K; NaN when K was not varied.
        real(wp) :: harmonics_error = 0.0_wp
        !> The state at the fold (2 K N coefficients).
        real(wp), allocatable :: fold_state(:)
        !> The branch's unit tangent at the fold, (dx, dA) (dA = 0 there up to the location's tolerance).
        real(wp), allocatable :: fold_tangent(:)
        !> Points of the branch recorded.
        integer :: points = 0
        !> Per point: A, max |u|, mean energy, Newton iterations, max |R| (5, points_max).
        real(wp), allocatable :: branch(:, :)
        !> With `keep_states`: the state (x, A) of each branch point, (2 K_b N + 1, points_max), K_b =
        !> `branch_harmonics`; the fold's point among them.
        real(wp), allocatable :: states(:, :)
        !> Harmonics K_b of the branch from rest (of `branch` and `states`).
        integer :: branch_harmonics = 0
        !> Index of the fold's point in the branch (0: none).
        integer :: fold_point = 0
        !> Newton iterations, LU factorisations and residual evaluations over everything done (every K).
        integer :: newton_iterations = 0, factorizations = 0, residuals = 0
        !> Branches traced from rest (one per K tried).
        integer :: continuations = 0
    end type hb_result

contains

    !> The number of odd harmonics to start the search in K from: the fold's state is the sharper the lower Omega
    !> (a kink at the edge of the chain), about 4 / Omega harmonics at the fold converge it to 1e-9 (docs).
    pure integer function hb_first_harmonics(omega)
        !> Driving frequency.
        real(wp), intent(in) :: omega

        hb_first_harmonics = max(3, ceiling(3.0_wp/omega))
    end function hb_first_harmonics

    !> The fold converged in K (see the module's description); `res%status` says whether a fold was found at every K.
    subroutine hb_fold_converged(chain, omega, ctl, res, error)
        !> Chain.
        type(chain_params), intent(in) :: chain
        !> Driving frequency.
        real(wp), intent(in) :: omega
        !> Controls.
        type(hb_controls), intent(in) :: ctl
        !> The fold of the largest K tried, its truncation estimate and the cost of all.
        type(hb_result), intent(out) :: res
        !> Error from the set-up (sizes).
        type(error_type), allocatable, intent(out) :: error
        type(hb_result) :: next
        integer :: k, k_next
        integer :: newton, lus, resid, branches

        k = ctl%harmonics
        if (k <= 0) k = min(hb_first_harmonics(omega), branch_harmonics_max)
        k = min(k, ctl%harmonics_max)
        call hb_fold(chain, omega, k, ctl, res, error)
        if (allocated(error)) return
        res%harmonics_error = ieee_value(1.0_wp, ieee_quiet_nan)
        do
            if (res%status /= cont_fold_found .or. k >= ctl%harmonics_max) exit
            k_next = min(ctl%harmonics_max, k + max(2, k/2))
            call refine_fold(chain, omega, k, k_next, res, ctl, next, error)
            if (allocated(error)) return
            if (next%status /= cont_fold_found) then    ! not bracketed near the old fold: from rest
                call hb_fold(chain, omega, k_next, ctl, next, error)
                if (allocated(error)) return
            end if
            newton = res%newton_iterations + next%newton_iterations
            lus = res%factorizations + next%factorizations
            resid = res%residuals + next%residuals
            branches = res%continuations + next%continuations
            next%harmonics_error = abs(next%fold_amplitude - res%fold_amplitude)
            if (next%status /= cont_fold_found) next%harmonics_error = ieee_value(1.0_wp, ieee_quiet_nan)
            if (next%points == 0) then                  ! keep the branch from rest, with the new fold
                next%points = res%points
                next%branch = res%branch
                next%branch_harmonics = res%branch_harmonics
                next%fold_point = res%fold_point
                if (allocated(res%states)) next%states = res%states
            end if
            call move_alloc_result(next, res)
            res%newton_iterations = newton
            res%factorizations = lus
            res%residuals = resid
            res%continuations = branches
            k = k_next
            if (res%harmonics_error <= ctl%harmonics_tol .and. top_harmonic(res%fold_state, chain%n, k) &
                <= ctl%harmonics_tol) exit
        end do
    end subroutine hb_fold_converged

    !> The fold with `k_to` harmonics located again from the fold `old` of `k_from` (its state and tangent padded with
    !> zeros): the planes normal to the old tangent at sigma = -delta and +delta bracket the new fold (delta = 0.01
    !> doubled up to seven times when they do not). `res%status` is `cont_no_fold` when no bracket was found, and the branch
    !> is left empty (the caller keeps the one from rest).
    subroutine refine_fold(chain, omega, k_from, k_to, old, ctl, res, error)
        !> Chain.
        type(chain_params), intent(in) :: chain
        !> Driving frequency.
        real(wp), intent(in) :: omega
        !> Harmonics of `old` and of the result.
        integer, intent(in) :: k_from, k_to
        !> The fold with k_from harmonics.
        type(hb_result), intent(in) :: old
        !> Controls.
        type(hb_controls), intent(in) :: ctl
        !> The fold with k_to harmonics.
        type(hb_result), intent(out) :: res
        !> Error from the set-up.
        type(error_type), allocatable, intent(out) :: error
        type(hb_system) :: sys
        real(wp), allocatable :: x0(:), t0(:), xs(:), tau(:)
        real(wp) :: delta, f(2), sigma
        integer :: nd, tries, side, iters
        logical :: ok

        call hb_init(sys, chain, omega, k_to, ctl%closure, error)
        if (allocated(error)) return
        nd = sys%dim + 1
        res%status = cont_no_fold
        res%harmonics = k_to
        res%fold_amplitude = ieee_value(1.0_wp, ieee_quiet_nan)
        res%fold_residual = res%fold_amplitude
        res%continuations = 0
        allocate (res%branch(5, ctl%points_max), source=res%fold_amplitude)
        x0 = [hb_pad(old%fold_state, chain%n, k_from, k_to), old%fold_amplitude]
        t0 = [hb_pad(old%fold_tangent(1:size(old%fold_tangent) - 1), chain%n, k_from, k_to), &
              old%fold_tangent(size(old%fold_tangent))]
        t0 = t0/norm2(t0)
        allocate (xs(nd), tau(nd))
        delta = 0.01_wp
        do tries = 1, 8
            ok = .true.
            do side = 1, 2
                sigma = merge(-delta, delta, side == 1)
                xs = x0 + sigma*t0
                call correct(sys, xs, t0, ctl, res, iters, ok, .true.)
                if (ok) call tangent(sys, t0, tau, ok)
                if (.not. ok) exit
                f(side) = tau(nd)
            end do
            if (ok) then
                if (f(1) > 0.0_wp .and. f(2) <= 0.0_wp) exit
            end if
            ok = .false.
            delta = 2.0_wp*delta
        end do
        if (.not. ok) return
        call locate_fold(sys, x0, t0, -delta, delta, f(1), f(2), ctl, res, sigma, ok)
        if (ok) res%status = cont_fold_found
        res%points = 0
    end subroutine refine_fold

    !> The largest amplitude sqrt(a^2 + b^2) of the highest harmonic K over the sites: the spectral tail of a state.
    pure real(wp) function top_harmonic(x, n, k)
        !> Coefficients, 2 K n.
        real(wp), intent(in) :: x(:)
        !> Sites.
        integer, intent(in) :: n
        !> Harmonics.
        integer, intent(in) :: k
        integer :: s, i

        top_harmonic = 0.0_wp
        do s = 1, n
            i = (s - 1)*2*k + 2*k - 1
            top_harmonic = max(top_harmonic, hypot(x(i), x(i + 1)))
        end do
    end function top_harmonic

    !> res = from (a plain assignment of the allocatable components).
    subroutine move_alloc_result(from, res)
        !> Source.
        type(hb_result), intent(inout) :: from
        !> Destination.
        type(hb_result), intent(inout) :: res

        res = from
    end subroutine move_alloc_result

    !> The branch from rest with K harmonics, its fold located and `ctl%beyond_fold` points past it.
    subroutine hb_fold(chain, omega, harmonics, ctl, res, error)
        !> Chain.
        type(chain_params), intent(in) :: chain
        !> Driving frequency.
        real(wp), intent(in) :: omega
        !> Harmonics K.
        integer, intent(in) :: harmonics
        !> Controls.
        type(hb_controls), intent(in) :: ctl
        !> The branch and its fold.
        type(hb_result), intent(out) :: res
        !> Error from the set-up.
        type(error_type), allocatable, intent(out) :: error
        type(hb_system) :: sys
        real(wp), allocatable :: x(:), t(:), xn(:), tn(:), x0(:), t0(:)
        real(wp) :: h, sigma
        integer :: nd, iters, info, past
        logical :: ok, fold_seen

        call hb_init(sys, chain, omega, harmonics, ctl%closure, error)
        if (allocated(error)) return
        nd = sys%dim + 1
        res%harmonics = harmonics
        res%fold_amplitude = ieee_value(1.0_wp, ieee_quiet_nan)
        res%fold_residual = res%fold_amplitude
        res%continuations = 1
        allocate (res%branch(5, ctl%points_max), source=res%fold_amplitude)
        res%branch_harmonics = harmonics
        if (ctl%keep_states) allocate (res%states(nd, ctl%points_max), source=0.0_wp)
        allocate (x(nd), t(nd), xn(nd), tn(nd))
        x = 0.0_wp                                       ! rest at A = 0
        t = 0.0_wp
        t(nd) = 1.0_wp
        call jacobian_and_factor(sys, x, res, info)
        if (info /= 0) then
            res%status = cont_newton_failed
            return
        end if
        call tangent(sys, t, tn, ok)                      ! the border t = (0, 1) at rest
        if (.not. ok) then
            res%status = cont_newton_failed
            return
        end if
        t = tn
        call record_point(sys, x, 0, res)
        h = ctl%step
        fold_seen = .false.
        past = 0
        do
            if (res%points >= ctl%points_max) then
                if (.not. fold_seen) res%status = cont_max_points
                exit
            end if
            xn = x + h*t
            call correct(sys, xn, t, ctl, res, iters, ok, .false.)
            if (ok) call tangent(sys, t, tn, ok)
            if (.not. ok) then
                h = 0.5_wp*h
                if (h < ctl%step_min) then
                    if (.not. fold_seen) res%status = merge(cont_newton_failed, cont_step_too_small, res%points <= 1)
                    exit
                end if
                cycle
            end if
            if (.not. fold_seen .and. t(nd) > 0.0_wp .and. tn(nd) <= 0.0_wp) then
                x0 = x
                t0 = t
                call locate_fold(sys, x0, t0, 0.0_wp, dot_product(t0, xn - x0), t0(nd), tn(nd), ctl, res, sigma, ok)
                fold_seen = .true.
                if (.not. ok) then
                    res%status = cont_newton_failed
                    exit
                end if
                res%status = cont_fold_found
                if (ctl%beyond_fold <= 0) exit
            end if
            x = xn
            t = tn
            call record_point(sys, x, iters, res)
            if (fold_seen) then
                past = past + 1
                if (past >= ctl%beyond_fold) exit
            else if (x(nd) > ctl%amplitude_max) then
                res%status = cont_no_fold
                exit
            end if
            if (iters <= 4) h = min(ctl%step_max, 1.5_wp*h)
            if (iters >= 8) h = 0.5_wp*h
        end do
    end subroutine hb_fold

    !> The Jacobian at x and its banded LU (counted).
    subroutine jacobian_and_factor(sys, x, res, info)
        !> The system.
        type(hb_system), intent(inout) :: sys
        !> (x, A).
        real(wp), intent(in), contiguous :: x(:)
        !> Counters.
        type(hb_result), intent(inout) :: res
        !> LAPACK status.
        integer, intent(out) :: info

        call hb_jacobian(sys, x(1:sys%dim))
        call hb_factor(sys, info)
        res%factorizations = res%factorizations + 1
    end subroutine jacobian_and_factor

    !> Solve the bordered system [J, R_A; c^T, d] (y, mu) = (f, g) with J's LU by block elimination (J^{-1} R_A
    !> kept with the factors, `sys%ja`), with `refine` one step of iterative refinement on the whole system (mixed
    !> block elimination: accurate next to the fold, where J is singular; the chord corrector needs none, its own
    !> iterations refine).
    subroutine bordered_solve(sys, c, f, g, y, ok, refine)
        !> The system (after `jacobian_and_factor`).
        type(hb_system), intent(inout) :: sys
        !> The border row (c, d), size 2 K N + 1.
        real(wp), intent(in) :: c(:)
        !> Right-hand side f, size 2 K N.
        real(wp), intent(in) :: f(:)
        !> Right-hand side g.
        real(wp), intent(in) :: g
        !> Solution (y, mu), size 2 K N + 1.
        real(wp), intent(out) :: y(:)
        !> False when the solve failed or is not finite.
        logical, intent(out) :: ok
        !> One step of iterative refinement.
        logical, intent(in) :: refine
        real(wp) :: work(sys%dim, 1), ra(sys%dim), jy(sys%dim)
        real(wp) :: rg, denominator, mu
        integer :: info, nd

        nd = sys%dim + 1
        call hb_amplitude_column(sys, ra)
        if (.not. sys%ja_ready) then
            work(:, 1) = ra
            call hb_solve(sys, work, info)
            ok = info == 0
            if (.not. ok) return
            sys%ja = work(:, 1)
            sys%ja_ready = .true.
        end if
        work(:, 1) = f
        call hb_solve(sys, work, info)
        ok = info == 0
        if (.not. ok) return
        denominator = c(nd) - dot_product(c(1:sys%dim), sys%ja)
        mu = (g - dot_product(c(1:sys%dim), work(:, 1)))/denominator
        y(1:sys%dim) = work(:, 1) - mu*sys%ja
        y(nd) = mu
        if (refine) then                                 ! the residual of the whole bordered system, solved again
            call hb_apply_jacobian(sys, y(1:sys%dim), jy)
            work(:, 1) = f - jy - ra*y(nd)
            rg = g - dot_product(c, y)
            call hb_solve(sys, work, info)
            ok = info == 0
            if (.not. ok) return
            mu = (rg - dot_product(c(1:sys%dim), work(:, 1)))/denominator
            y(1:sys%dim) = y(1:sys%dim) + work(:, 1) - mu*sys%ja
            y(nd) = y(nd) + mu
        end if
        ok = all(ieee_is_finite(y))
    end subroutine bordered_solve

    !> The chord corrector onto the plane through x_pred normal to `t` (x overwritten with the solution): the Jacobian
    !> is factored at the predictor and again only when an update shrinks by less than `chord_rate`. With `strict`
    !> the tolerances are `residual_tol` and `step_tol` (the points that locate the fold), else `branch_tol`.
    subroutine correct(sys, x, t, ctl, res, iters, ok, strict)
        !> The system.
        type(hb_system), intent(inout) :: sys
        !> (x, A): the predictor on entry, the point on exit.
        real(wp), intent(inout), contiguous :: x(:)
        !> The plane's normal (the predictor's tangent).
        real(wp), intent(in) :: t(:)
        !> Controls.
        type(hb_controls), intent(in) :: ctl
        !> Counters.
        type(hb_result), intent(inout) :: res
        !> Iterations taken.
        integer, intent(out) :: iters
        !> Whether it converged.
        logical, intent(out) :: ok
        !> The fold's tolerances.
        logical, intent(in) :: strict
        real(wp), parameter :: chord_rate = 0.25_wp
        real(wp) :: r(sys%dim), dx(size(x)), last
        integer :: info, nd
        logical :: factor

        nd = sys%dim + 1
        ok = .false.
        factor = .true.
        last = huge(1.0_wp)
        do iters = 1, ctl%newton_max_iter
            call hb_residual(sys, x(1:sys%dim), x(nd), r)
            res%residuals = res%residuals + 1
            if (.not. all(ieee_is_finite(r))) return
            if (maxval(abs(r)) <= merge(ctl%residual_tol, ctl%branch_tol, strict) &
                .and. last <= merge(ctl%step_tol, ctl%branch_tol, strict)) then
                ok = .true.
                return
            end if
            if (factor) then
                call jacobian_and_factor(sys, x, res, info)
                if (info /= 0) return
                factor = .false.
            end if
            call bordered_solve(sys, t, -r, 0.0_wp, dx, ok, strict)   ! the plane: t . dx = 0 keeps x on it
            if (.not. ok) return
            ok = .false.
            x = x + dx
            res%newton_iterations = res%newton_iterations + 1
            if (maxval(abs(dx)) > chord_rate*last) factor = .true.
            last = maxval(abs(dx))
        end do
        iters = ctl%newton_max_iter
    end subroutine correct

    !> The unit tangent of the branch at the last Jacobian's point, oriented along `t_previous`: [J, R_A; t_previous^T]
    !> tau = (0, 1).
    subroutine tangent(sys, t_previous, tau, ok)
        !> The system (after `jacobian_and_factor` at the point).
        type(hb_system), intent(inout) :: sys
        !> The previous tangent (the border).
        real(wp), intent(in) :: t_previous(:)
        !> The unit tangent.
        real(wp), intent(out) :: tau(:)
        !> False when the solve failed.
        logical, intent(out) :: ok
        real(wp) :: zero(sys%dim)

        zero = 0.0_wp
        call bordered_solve(sys, t_previous, zero, 1.0_wp, tau, ok, .true.)
        if (.not. ok) return
        tau = tau/norm2(tau)
        if (dot_product(tau, t_previous) < 0.0_wp) tau = -tau
    end subroutine tangent

    !> The fold between sigma = sa (tangent's A component fa > 0) and sigma = sb (fb <= 0) along t0 from x0, by the
    !> Illinois method on tau_A(sigma); the fold's amplitude, residual, state and tangent into `res`.
    subroutine locate_fold(sys, x0, t0, sa_in, sb_in, fa_in, fb_in, ctl, res, sigma, ok)
        !> The system.
        type(hb_system), intent(inout) :: sys
        !> The last point before the fold.
        real(wp), intent(in) :: x0(:)
        !> Its tangent.
        real(wp), intent(in) :: t0(:)
        !> Arclengths of the last point before and the first point past the fold.
        real(wp), intent(in) :: sa_in, sb_in
        !> tau_A at 0 and at sb.
        real(wp), intent(in) :: fa_in, fb_in
        !> Controls.
        type(hb_controls), intent(in) :: ctl
        !> The fold into it.
        type(hb_result), intent(inout) :: res
        !> Arclength of the fold.
        real(wp), intent(out) :: sigma
        !> Whether every corrector converged.
        logical, intent(out) :: ok
        real(wp) :: sa, sb, fa, fb, f, xs(size(x0)), tau(size(x0)), r(sys%dim), x1(size(x0)), x2(size(x0))
        real(wp) :: s1, s2
        integer :: it, side, iters, nd

        nd = sys%dim + 1
        sa = sa_in
        sb = sb_in
        fa = fa_in
        fb = fb_in
        side = 0
        ok = .true.
        xs = x0
        x2 = x0
        s2 = 0.0_wp
        do it = 1, 60
            sigma = sb - fb*(sb - sa)/(fb - fa)
            if (it <= 2) then                              ! predictors: along t0, then through the last two points
                xs = x0 + sigma*t0
            else
                xs = x2 + (sigma - s2)/(s2 - s1)*(x2 - x1)
            end if
            call correct(sys, xs, t0, ctl, res, iters, ok, .true.)
            x1 = x2
            s1 = s2
            x2 = xs
            s2 = sigma
            if (.not. ok) return
            call tangent(sys, t0, tau, ok)
            if (.not. ok) return
            f = tau(nd)
            if (f > 0.0_wp) then
                sa = sigma
                fa = f
                if (side == -1) fb = 0.5_wp*fb
                side = -1
            else
                sb = sigma
                fb = f
                if (side == 1) fa = 0.5_wp*fa
                side = 1
            end if
            if (abs(f) < 1.0e-12_wp .or. abs(sb - sa) < 1.0e-12_wp*max(1.0_wp, abs(sigma))) exit
        end do
        res%fold_amplitude = xs(nd)
        res%fold_state = xs(1:sys%dim)
        res%fold_tangent = tau
        call hb_residual(sys, xs(1:sys%dim), xs(nd), r)
        res%fold_residual = maxval(abs(r))
        call record_point(sys, xs, iters, res)
        if (res%points > 0) res%fold_point = res%points
    end subroutine locate_fold

    !> Append a point to the branch (A, max |u|, energy, Newton iterations, max |R|).
    subroutine record_point(sys, x, iters, res)
        !> The system.
        type(hb_system), intent(inout) :: sys
        !> (x, A).
        real(wp), intent(in), contiguous :: x(:)
        !> Newton iterations of the point.
        integer, intent(in) :: iters
        !> The branch.
        type(hb_result), intent(inout) :: res
        real(wp) :: umax, energy, r(sys%dim)
        integer :: nd

        if (res%points >= size(res%branch, 2)) return
        nd = sys%dim + 1
        call hb_measures(sys, x(1:sys%dim), x(nd), umax, energy)
        call hb_residual(sys, x(1:sys%dim), x(nd), r)
        res%points = res%points + 1
        res%branch(:, res%points) = [x(nd), umax, energy, real(iters, wp), maxval(abs(r))]
        if (allocated(res%states)) res%states(:, res%points) = x
    end subroutine record_point

end module supratrans_hb_continuation
