!> The bordered linear systems of the continuation (`supratrans_continuation`): B = [[J - I, dP/dA]; [r0^T]] built
!> from a point's Jacobian and factorised once (LU), and the rank-one (Sherman-Morrison) change of its last row that
!> lets one factorisation serve the tangent and the corrector of a point (and, with `reuse_jacobian`, the points
!> after it): K^{-1} b = v - z (w . v) / (1 + w . z), v = B^{-1} b, z = B^{-1} e_{d+1}, w the change of the last row.
!> The unit tangent is z / |z| (oriented along r0: r0 . z = 1), and K with the tangent as its last row is the
!> corrector's matrix. Every factorisation and solve is counted and timed in the `continuation_stats` passed along.
!> No state of its own.
module supratrans_bordered_system
    use supratrans_kinds, only: wp
    use supratrans_dense, only: lu_factor, lu_solve
    use supratrans_continuation_types, only: continuation_stats, wall_clock
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    implicit none
    private

    public :: factor_bordered, bordered_solve, tangent, set_row, move_system, det_sign

    !> A factorised bordered matrix B = [[J - I, dP/dA]; [r0^T]], with an optional rank-one change of its last row to
    !> r0 + w (Sherman-Morrison: K^{-1} b = v - z (w . v) / denom, v = B^{-1} b, z = B^{-1} e_{d+1},
    !> denom = 1 + w . z).
    type, public :: bordered_system
        !> LU factors of B ((d + 1) x (d + 1), `lu_factor`).
        real(wp), allocatable :: lu(:, :)
        !> Their pivots.
        integer, allocatable :: ipiv(:)
        !> The last row r0 of B as factorised, z = B^{-1} e_{d+1} (allocated once computed), and the change w of the
        !> last row (r0 + w: the matrix K solved with when `updated`).
        real(wp), allocatable :: row0(:), z(:), w(:)
        !> 1 + w . z, the Sherman-Morrison denominator.
        real(wp) :: denom = 1.0_wp
        !> Whether the last row is changed to r0 + w.
        logical :: updated = .false.
    end type bordered_system

contains

    !> Build and factorise [[J - I, dP/dA]; [row^T]].
    subroutine factor_bordered(jac, dpda, row, sys, info, stats)
        !> J = dP/dx (d x d), dP/dA (d) and the last row (d + 1).
        real(wp), intent(in) :: jac(:, :), dpda(:), row(:)
        !> The system (its arrays reused when of the right size; no rank-one change after this).
        type(bordered_system), intent(inout) :: sys
        !> 0, or the `lu_factor` status (singular matrix).
        integer, intent(out) :: info
        !> Counts and times (a factorisation).
        type(continuation_stats), intent(inout) :: stats
        real(wp) :: t0
        integer :: d, i

        t0 = wall_clock()
        d = size(dpda)
        if (allocated(sys%lu)) then
            if (size(sys%lu, 1) /= d + 1) deallocate (sys%lu, sys%ipiv)
        end if
        if (.not. allocated(sys%lu)) allocate (sys%lu(d + 1, d + 1), sys%ipiv(d + 1))
        sys%lu(1:d, 1:d) = jac
        do i = 1, d
            sys%lu(i, i) = sys%lu(i, i) - 1.0_wp
        end do
        sys%lu(1:d, d + 1) = dpda
        sys%lu(d + 1, :) = row
        call lu_factor(sys%lu, sys%ipiv, info)
        sys%row0 = row
        if (allocated(sys%z)) deallocate (sys%z)
        sys%updated = .false.
        stats%factorisations = stats%factorisations + 1
        stats%time_lu = stats%time_lu + wall_clock() - t0
    end subroutine factor_bordered

    !> Solve with a bordered system (and its rank-one change of the last row, if any); b is overwritten.
    subroutine bordered_solve(sys, b, info, stats)
        !> The factorised system.
        type(bordered_system), intent(in) :: sys
        !> Right-hand side on entry, solution on exit (d + 1).
        real(wp), intent(inout) :: b(:)
        !> 0, or the `lu_solve` status.
        integer, intent(out) :: info
        !> Counts and times (a solve).
        type(continuation_stats), intent(inout) :: stats
        real(wp) :: t0

        t0 = wall_clock()
        call lu_solve(sys%lu, sys%ipiv, b, info)
        if (info == 0 .and. sys%updated) b = b - sys%z*(dot_product(sys%w, b)/sys%denom)
        stats%solves = stats%solves + 1
        stats%time_lu = stats%time_lu + wall_clock() - t0
    end subroutine bordered_solve

    !> The unit tangent from a freshly factorised B = [[J - I, dP/dA]; [r0^T]]: z = B^{-1} e_{d+1}, t = z / |z|
    !> (oriented along r0: r0 . z = 1); the system is then changed (rank one) to have t as its last row.
    subroutine tangent(sys, t, info, stats)
        !> The freshly factorised system (its last row changed to t on exit).
        type(bordered_system), intent(inout) :: sys
        !> The unit tangent (d + 1).
        real(wp), allocatable, intent(inout) :: t(:)
        !> 0; /= 0 when the solve failed or t cannot be the last row (`set_row`).
        integer, intent(out) :: info
        !> Counts and times.
        type(continuation_stats), intent(inout) :: stats

        call unit_solution(sys, info, stats)
        if (info /= 0) return
        t = sys%z/norm2(sys%z)
        call set_row(sys, t, info, stats)
    end subroutine tangent

    !> z = B^{-1} e_{d+1} for the factorised matrix (without its rank-one change), if not yet known.
    subroutine unit_solution(sys, info, stats)
        type(bordered_system), intent(inout) :: sys
        integer, intent(out) :: info
        type(continuation_stats), intent(inout) :: stats
        real(wp) :: t0
        integer :: n1, i

        info = 0
        if (allocated(sys%z)) return
        n1 = size(sys%row0)
        allocate (sys%z(n1))
        sys%z = [(0.0_wp, i=1, n1 - 1), 1.0_wp]
        t0 = wall_clock()
        call lu_solve(sys%lu, sys%ipiv, sys%z, info)
        stats%solves = stats%solves + 1
        stats%time_lu = stats%time_lu + wall_clock() - t0
        if (info == 0 .and. .not. all(ieee_is_finite(sys%z))) info = 1
        if (info /= 0) deallocate (sys%z)
    end subroutine unit_solution

    !> Change the last row of a factorised bordered system to `row` (rank one, Sherman-Morrison). `info` /= 0 when
    !> the changed matrix is (nearly) singular: 1 + w . z, which is r . z, vanishes when `row` is orthogonal to the
    !> branch direction z of the factorised matrix.
    subroutine set_row(sys, row, info, stats)
        !> The factorised system.
        type(bordered_system), intent(inout) :: sys
        !> The new last row (d + 1).
        real(wp), intent(in) :: row(:)
        !> 0, or 1 when the changed matrix is (nearly) singular or the solve for z failed.
        integer, intent(out) :: info
        !> Counts and times.
        type(continuation_stats), intent(inout) :: stats

        call unit_solution(sys, info, stats)
        if (info /= 0) return
        sys%w = row - sys%row0
        sys%denom = 1.0_wp + dot_product(sys%w, sys%z)
        sys%updated = .true.
        if (abs(sys%denom) <= 1.0e-3_wp*norm2(sys%z)*norm2(row)) info = 1
    end subroutine set_row

    !> The sign of det B of the factorised matrix B = [[J - I, dP/dA]; [r0^T]] (without its rank-one change), from
    !> its LU factors. Along a branch whose rows r0 follow the tangent (r0 . t > 0) it changes sign where a real
    !> multiplier passes +1 while the branch does not turn (a branch point), not at a fold.
    pure integer function det_sign(sys)
        !> The factorised system.
        type(bordered_system), intent(in) :: sys
        integer :: i

        det_sign = 1
        do i = 1, size(sys%ipiv)
            if (sys%ipiv(i) /= i) det_sign = -det_sign
            if (sys%lu(i, i) < 0.0_wp) det_sign = -det_sign
            if (sys%lu(i, i) == 0.0_wp) det_sign = 0
            if (det_sign == 0) return
        end do
    end function det_sign

    !> Move a system's factors and rank-one change to another (no copy; `from`'s arrays are deallocated).
    subroutine move_system(from, to)
        !> The system moved, and where it goes.
        type(bordered_system), intent(inout) :: from, to

        call move_alloc(from%lu, to%lu)
        call move_alloc(from%ipiv, to%ipiv)
        call move_alloc(from%row0, to%row0)
        call move_alloc(from%z, to%z)
        call move_alloc(from%w, to%w)
        to%denom = from%denom
        to%updated = from%updated
    end subroutine move_system

end module supratrans_bordered_system
