!> The points of a continuation branch (`supratrans_continuation`) and how they are computed: the map evaluated
!> (counted, timed, its values checked finite), the predictor and the chord/Newton (Shamanskii) corrector on the
!> bordered system of `supratrans_bordered_system`, and at a corrected point its Jacobian, tangent and Floquet
!> multipliers; a recorded point rebuilt from the branch. No state of its own.
module supratrans_continuation_corrector
    use supratrans_kinds, only: wp
    use supratrans_fixed_point_map, only: fixed_point_map, map_ok
    use supratrans_floquet, only: floquet_multipliers, flip_sign
    use supratrans_continuation_types, only: continuation_controls, continuation_stats, continuation_result, wall_clock
    use supratrans_bordered_system, only: bordered_system, factor_bordered, bordered_solve, tangent, det_sign
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: correct, complete_point, point_jacobian, point_multipliers, stored_point, move_point, flip_test

    !> Most Jacobian refreshes in one corrector attempt.
    integer, parameter :: max_refreshes = 3

    !> A converged branch point with its derivatives.
    type, public :: branch_point
        !> The point y = (x, A), size d + 1.
        real(wp), allocatable :: y(:)
        !> Its unit tangent (exact, or the secant from the previous point when `exact` is false).
        real(wp), allocatable :: t(:)
        !> dP/dx (d x d) and dP/dA (d) at y, where they were evaluated.
        real(wp), allocatable :: jac(:, :), dpda(:)
        !> Pseudo-arclength from the start of the branch.
        real(wp) :: s = 0.0_wp
        !> max |P(x) - x| at y.
        real(wp) :: residual = 0.0_wp
        !> Corrector iterations that gave the point.
        integer :: iterations = 0
        !> Jacobian refreshes in its corrector.
        integer :: refreshes = 0
        !> Whether `t` was computed from the Jacobian at y.
        logical :: exact = .false.
        !> With `flip_watch`: the sign of det(J + I) of the last Jacobian its corrector evaluated (at an iterate
        !> near y; `flip_sign`); 0 when none was.
        integer :: flip = 0
        !> With `flip_watch`: the sign of the determinant of that Jacobian's bordered matrix (`det_sign`); 0 when none.
        integer :: bordered = 0
    end type branch_point

contains

    !> Predictor y_b + sigma t_b and chord/Newton corrector on {F(y) = 0, t_b . (y - y_pred) = 0} starting with the
    !> factorised base system; a slow chord step brings a fresh Jacobian at the current iterate.
    subroutine correct(map, bp, sys, sigma, ctl, pt, ok, stats, fresh_sys)
        !> The map P(x; A).
        class(fixed_point_map), intent(inout) :: map
        !> The point the step starts from, with its tangent t_b.
        type(branch_point), intent(in) :: bp
        !> The factorised bordered system to start the chord steps with (last row t_b).
        type(bordered_system), intent(in) :: sys
        !> The pseudo-arclength step.
        real(wp), intent(in) :: sigma
        !> Controls (tolerance, iterations, chord rate).
        type(continuation_controls), intent(in) :: ctl
        !> The corrected point: y, residual, iterations, refreshes (no tangent, no Jacobian: `exact` false).
        type(branch_point), intent(inout) :: pt
        !> Whether the corrector converged.
        logical, intent(out) :: ok
        !> Counts and times.
        type(continuation_stats), intent(inout) :: stats
        !> The system factorised at the last refresh (pt%refreshes > 0).
        type(bordered_system), intent(inout) :: fresh_sys
        real(wp), allocatable :: y(:), ypred(:), r(:), px(:), jac(:, :), dpda(:)
        real(wp) :: dn, dn_prev, rate
        integer :: d, n1, status, info, loops
        logical :: want_jac, fresh, use_fresh

        d = size(bp%y) - 1
        n1 = d + 1
        ok = .false.
        pt%exact = .false.
        y = bp%y + sigma*bp%t
        ypred = y
        allocate (r(n1), px(d))
        want_jac = .false.
        use_fresh = .false.
        dn_prev = huge(1.0_wp)
        pt%iterations = 0
        pt%refreshes = 0
        pt%flip = 0
        pt%bordered = 0
        loops = 0
        do
            loops = loops + 1
            if (loops > 3*ctl%newton_max_iter) return
            fresh = want_jac
            if (want_jac) then
                if (.not. allocated(jac)) allocate (jac(d, d), dpda(d))
                call evaluate(map, y, px, status, stats, jac, dpda)
            else
                call evaluate(map, y, px, status, stats)
            end if
            if (status /= map_ok) return
            r(1:d) = px - y(1:d)
            pt%residual = maxval(abs(r(1:d)))
            if (pt%residual <= ctl%newton_tol) exit
            if (pt%iterations >= ctl%newton_max_iter) return
            if (want_jac) then
                ! a corrector that needs more than max_refreshes Jacobians is not converging: a shorter step will
                if (pt%refreshes >= max_refreshes) return
                call factor_bordered(jac, dpda, bp%t, fresh_sys, info, stats)
                if (info /= 0) return
                if (ctl%flip_watch) call flip_test(jac, pt%flip, stats)
                if (ctl%flip_watch) pt%bordered = det_sign(fresh_sys)
                use_fresh = .true.
                want_jac = .false.
                pt%refreshes = pt%refreshes + 1
            end if
            r(n1) = dot_product(bp%t, y - ypred)
            r = -r
            if (use_fresh) then
                call bordered_solve(fresh_sys, r, info, stats)
            else
                call bordered_solve(sys, r, info, stats)
            end if
            if (info /= 0) return
            dn = norm2(r)
            if (.not. ieee_is_finite(dn)) return
            if (.not. fresh .and. pt%iterations > 0) then
                ! Shamanskii: a fresh Jacobian when the chord contracts by less than chord_rate per step, or too
                ! slowly to reach the tolerance within the iterations left
                rate = dn/dn_prev
                ! growing although the Jacobian was refreshed in this attempt: the iterate has left Newton's basin,
                ! a shorter step will do better than more Jacobians
                if (rate >= 1.0_wp .and. pt%refreshes > 0) return
                if (rate > ctl%chord_rate) then
                    want_jac = .true.
                else if (dn > ctl%newton_tol .and. rate > 0.0_wp) then
                    want_jac = log(ctl%newton_tol/dn)/log(rate) > real(ctl%newton_max_iter - pt%iterations - 1, wp)
                end if
                if (want_jac) cycle
            end if
            y = y + r
            dn_prev = dn
            pt%iterations = pt%iterations + 1
        end do
        pt%y = y
        ok = .true.
    end subroutine correct

    !> At a corrected point: the Jacobian, the factorised bordered matrix with the previous tangent `row`, the unit
    !> tangent (oriented along `row`), and the rank-one change of the last row to the new tangent for the next
    !> corrector.
    subroutine complete_point(map, pt, row, sys, ok, stats)
        !> The map P(x; A).
        class(fixed_point_map), intent(inout) :: map
        !> The corrected point: its Jacobian, residual and tangent set (`exact` when all went well).
        type(branch_point), intent(inout) :: pt
        !> The previous tangent (d + 1).
        real(wp), intent(in) :: row(:)
        !> The bordered system at pt, its last row changed to pt's tangent.
        type(bordered_system), intent(inout) :: sys
        !> Whether the map, the factorisation and the tangent succeeded.
        logical, intent(out) :: ok
        !> Counts and times.
        type(continuation_stats), intent(inout) :: stats
        real(wp), allocatable :: px(:)
        integer :: d, status, info

        d = size(pt%y) - 1
        ok = .false.
        if (.not. allocated(pt%jac)) allocate (pt%jac(d, d), pt%dpda(d))
        allocate (px(d))
        call evaluate(map, pt%y, px, status, stats, pt%jac, pt%dpda)
        if (status /= map_ok) return
        pt%residual = maxval(abs(px - pt%y(1:d)))
        call factor_bordered(pt%jac, pt%dpda, row, sys, info, stats)
        if (info /= 0) return
        call tangent(sys, pt%t, info, stats)
        ok = info == 0
        pt%exact = ok
    end subroutine complete_point

    !> `flip_sign` of a Jacobian, counted and timed as a factorisation.
    subroutine flip_test(jac, flip, stats)
        !> dP/dx.
        real(wp), intent(in) :: jac(:, :)
        !> The sign of det(J + I) (0: singular).
        integer, intent(out) :: flip
        !> Counts and times.
        type(continuation_stats), intent(inout) :: stats
        real(wp) :: t0

        t0 = wall_clock()
        flip = flip_sign(jac)
        stats%factorisations = stats%factorisations + 1
        stats%time_lu = stats%time_lu + wall_clock() - t0
    end subroutine flip_test

    !> At a corrected point: the Jacobian only (dP/dx and dP/dA) and the residual; the tangent is not computed.
    subroutine point_jacobian(map, pt, ok, stats)
        !> The map P(x; A).
        class(fixed_point_map), intent(inout) :: map
        !> The corrected point: its Jacobian and residual set (`exact` false).
        type(branch_point), intent(inout) :: pt
        !> Whether the map succeeded.
        logical, intent(out) :: ok
        !> Counts and times.
        type(continuation_stats), intent(inout) :: stats
        real(wp), allocatable :: px(:)
        integer :: d, status

        d = size(pt%y) - 1
        if (.not. allocated(pt%jac)) allocate (pt%jac(d, d), pt%dpda(d))
        allocate (px(d))
        call evaluate(map, pt%y, px, status, stats, pt%jac, pt%dpda)
        ok = status == map_ok
        if (ok) pt%residual = maxval(abs(px - pt%y(1:d)))
        pt%exact = .false.
    end subroutine point_jacobian

    !> The multipliers at a point with its Jacobian.
    subroutine point_multipliers(pt, stats, wr, wi, info)
        !> The point (its Jacobian dP/dx).
        type(branch_point), intent(in) :: pt
        !> Counts and times (an eigenvalue computation).
        type(continuation_stats), intent(inout) :: stats
        !> Real and imaginary parts of the multipliers.
        real(wp), allocatable, intent(out) :: wr(:), wi(:)
        !> 0, or the LAPACK status.
        integer, intent(out) :: info
        real(wp) :: t0

        t0 = wall_clock()
        call floquet_multipliers(pt%jac, wr, wi, info)
        stats%eigen_calls = stats%eigen_calls + 1
        stats%time_eigen = stats%time_eigen + wall_clock() - t0
    end subroutine point_multipliers

    !> Evaluate P (and, when asked, its derivatives) at y = (x, A), counted and timed.
    subroutine evaluate(map, y, px, status, stats, jac, dpda)
        class(fixed_point_map), intent(inout) :: map
        real(wp), intent(in) :: y(:)
        real(wp), intent(out) :: px(:)
        integer, intent(out) :: status
        type(continuation_stats), intent(inout) :: stats
        real(wp), intent(out), optional :: jac(:, :), dpda(:)
        real(wp) :: t0
        integer :: d

        d = size(y) - 1
        t0 = wall_clock()
        if (present(jac)) then
            call map%apply(y(1:d), y(d + 1), px, status, jac=jac, dpda=dpda)
            stats%jacobian_evaluations = stats%jacobian_evaluations + 1
            stats%time_jacobian = stats%time_jacobian + wall_clock() - t0
            if (status == map_ok) then
                if (.not. (all(ieee_is_finite(jac)) .and. all(ieee_is_finite(dpda)))) status = map_ok + 1
            end if
        else
            call map%apply(y(1:d), y(d + 1), px, status)
            stats%map_evaluations = stats%map_evaluations + 1
            stats%time_map = stats%time_map + wall_clock() - t0
        end if
        if (status == map_ok) then
            if (.not. all(ieee_is_finite(px))) status = map_ok + 1
        end if
    end subroutine evaluate

    !> A recorded point rebuilt from its stored state and tangent, with its Jacobian evaluated again.
    subroutine stored_point(map, res, i, pt, stats, info)
        !> The map P(x; A).
        class(fixed_point_map), intent(inout) :: map
        !> The branch.
        type(continuation_result), intent(in) :: res
        !> The recorded point, 1 .. res%n_points.
        integer, intent(in) :: i
        !> The point rebuilt, with its Jacobian.
        type(branch_point), intent(inout) :: pt
        !> Counts and times.
        type(continuation_stats), intent(inout) :: stats
        !> 0, or 1 when the map failed.
        integer, intent(out) :: info
        real(wp), allocatable :: px(:)
        integer :: d, status

        d = size(res%states, 1)
        pt%y = [res%states(:, i), res%amplitude(i)]
        pt%t = res%tangents(:, i)
        pt%s = res%arclength(i)
        pt%iterations = res%newton_iterations(i)
        pt%residual = res%residual(i)
        pt%exact = res%exact_tangent(i) == 1
        if (.not. allocated(pt%jac)) allocate (pt%jac(d, d), pt%dpda(d))
        allocate (px(d))
        call evaluate(map, pt%y, px, status, stats, pt%jac, pt%dpda)
        info = merge(0, 1, status == map_ok)
    end subroutine stored_point

    !> Move a point to another (its arrays without a copy; `from`'s are deallocated).
    subroutine move_point(from, to)
        !> The point moved, and where it goes.
        type(branch_point), intent(inout) :: from, to

        call move_alloc(from%y, to%y)
        call move_alloc(from%t, to%t)
        call move_alloc(from%jac, to%jac)
        call move_alloc(from%dpda, to%dpda)
        to%s = from%s
        to%residual = from%residual
        to%iterations = from%iterations
        to%refreshes = from%refreshes
        to%exact = from%exact
        to%flip = from%flip
        to%bordered = from%bordered
    end subroutine move_point

end module supratrans_continuation_corrector
