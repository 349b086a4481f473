!> Branch switching at a branch point of a continuation (`supratrans_continuation`): where a real multiplier passes
!> +1 while the branch does not turn, a second branch of fixed points crosses the first. In the driven chain the
!> half-period symmetry breaks there, and a pair of periodic states without it (each the other half a period later)
!> leaves the symmetric state.
!>
!> **Method** (Keller's branch switching, as AUTO-07p and BifurcationKit.jl switch at a branch point). At the branch
!> point y_b = (x_b, A_b) the Jacobian F_y = [J - I, dP/dA] has a two-dimensional null space: the tangent t_b of the
!> branch that was followed and the direction e of the other one. The bordered matrix K = [[F_y]; [t_b^T]] is
!> singular exactly there, with e (made orthogonal to t_b) its null vector: two steps of inverse iteration with K's
!> one LU give it, to the relative distance of y_b from the branch point (1e-10 where the loss was located). The
!> first point of the other branch is corrected on the hyperplane e . (y - y_b) = h from the predictor y_b + h e,
!> with the chord/Newton corrector of the continuation on a Jacobian evaluated at the predictor (K's own is singular
!> along e). On a pitchfork (the symmetric case) that branch is A - A_b = kappa h^2 + O(h^4): above A_b where it is
!> supercritical (its states take over the stability the old branch loses), below where it is subcritical.
!>
!> Pure in its effects: the map holds its work arrays (one map per thread), this module has no state of its own.
module supratrans_branch_switch
    use supratrans_kinds, only: wp
    use supratrans_fixed_point_map, only: fixed_point_map
    use supratrans_continuation_types, only: continuation_controls, continuation_stats
    use supratrans_bordered_system, only: bordered_system, factor_bordered, bordered_solve
    use supratrans_continuation_corrector, only: branch_point, correct, point_jacobian
    implicit none
    private

    public :: switch_branch

contains

    !> The first point of the branch that crosses the followed one at the branch point `y_b` (tangent `t_b` of the
    !> followed branch there, or next to it): corrected at the distance h along the other branch's direction `e`, for
    !> each h of `hs` in turn until one gives it (e is computed once). `ok` is false when the map fails, K cannot be
    !> factorised, or for every h the corrector does not converge within h of its predictor (it would have left for
    !> another branch).
    subroutine switch_branch(map, y_b, t_b, hs, ctl, pt, e, ok, stats)
        !> The map P(x; A).
        class(fixed_point_map), intent(inout) :: map
        !> The branch point (x, A), size d + 1.
        real(wp), intent(in) :: y_b(:)
        !> Unit tangent of the followed branch at y_b (size d + 1).
        real(wp), intent(in) :: t_b(:)
        !> Distances of the first point from y_b along e to try, in order (in the Euclidean norm of (x, A)).
        real(wp), intent(in) :: hs(:)
        !> Controls of the corrector (tolerance, iterations, chord rate); `flip_watch` is not used.
        type(continuation_controls), intent(in) :: ctl
        !> The corrected point on the other branch: y, residual, iterations (no Jacobian kept).
        type(branch_point), intent(inout) :: pt
        !> The unit direction e of the other branch at y_b (its largest component positive), size d + 1.
        real(wp), intent(out) :: e(:)
        !> Whether the point was found.
        logical, intent(out) :: ok
        !> Counts and times.
        type(continuation_stats), intent(inout) :: stats
        type(branch_point) :: b, start
        type(bordered_system) :: sys, fresh
        type(continuation_controls) :: plain
        real(wp), allocatable :: z(:)
        integer :: n1, i, info, it, k

        n1 = size(y_b)
        e = 0.0_wp
        b%y = y_b
        call point_jacobian(map, b, ok, stats)
        if (.not. ok) return
        ok = .false.
        call factor_bordered(b%jac, b%dpda, t_b, sys, info, stats)
        if (info /= 0) return
        ! inverse iteration from a fixed vector with no special direction (orthogonal to t_b: K z's last entry 0)
        z = [(sin(real(i, wp)), i=1, n1)]
        do it = 1, 2
            z(n1) = 0.0_wp
            call bordered_solve(sys, z, info, stats)
            if (info /= 0) return
            z = z - dot_product(z, t_b)*t_b
            z = z/norm2(z)
        end do
        i = maxloc(abs(z), dim=1)
        e = sign(1.0_wp, z(i))*z

        ! the corrector from y_b + h e on the hyperplane e . (y - y_b) = h, its first matrix at the predictor
        start%y = y_b
        start%t = e
        plain = ctl
        plain%flip_watch = .false.
        do k = 1, size(hs)
            b%y = y_b + hs(k)*e
            call point_jacobian(map, b, ok, stats)
            if (.not. ok) return
            call factor_bordered(b%jac, b%dpda, e, sys, info, stats)
            if (info /= 0) cycle
            call correct(map, start, sys, hs(k), plain, pt, ok, stats, fresh)
            if (ok) ok = norm2(pt%y - b%y) <= hs(k)
            if (ok) return
        end do
        ok = .false.
    end subroutine switch_branch

end module supratrans_branch_switch
