!> What the march of the continuation (`supratrans_continuation`) watches between the points with multipliers:
!> the trend of the largest multiplier moduli (`floquet_trend`: multipliers computed although not due, where that
!> trend could reach the unit circle within the step), and for the fold alone the signs of two determinants
!> (`flip_watch`: where they change, a real multiplier has passed -1 or +1). The march holds one `moduli_trend` and
!> one `sign_watch`; this module has no state of its own.
module supratrans_continuation_watch
    use supratrans_kinds, only: wp
    use supratrans_continuation_types, only: continuation_stats
    use supratrans_bordered_system, only: bordered_system, det_sign
    use supratrans_continuation_corrector, only: branch_point, flip_test
    implicit none
    private

    public :: note_trend, trend_due, note_signs

    !> Number of largest multiplier moduli whose trend decides extra multiplier checks (`floquet_trend`).
    integer, parameter :: trend_ranks = 8
    !> Safety factor on the extrapolated growth of those moduli.
    real(wp), parameter :: trend_safety = 2.0_wp

    !> The `trend_ranks` largest multiplier moduli at the last two points with multipliers, and their arclengths.
    type, public :: moduli_trend
        !> Points noted so far (at most 2 count).
        integer :: n = 0
        !> Moduli at the last point and at the one before, largest first.
        real(wp) :: top_last(trend_ranks) = 0.0_wp, top_prev(trend_ranks) = 0.0_wp
        !> Their arclengths.
        real(wp) :: s_last = 0.0_wp, s_prev = 0.0_wp
    end type moduli_trend

    !> The signs of det(J + I) (`flip_sign`) and of the bordered matrix's determinant (`det_sign`) at the last
    !> recorded point that had them. Along a branch (rows of the bordered matrices following the tangent) the first
    !> changes where an odd number of real multipliers pass -1, the second where one passes +1 while the branch does
    !> not turn (a branch point; at a fold neither changes).
    type, public :: sign_watch
        !> Sign of det(J + I); 0 when not known yet.
        integer :: flip = 0
        !> Sign of the bordered matrix's determinant; 0 when not known yet.
        integer :: bordered = 0
        !> The recorded point they belong to.
        integer :: at = 0
    end type sign_watch

contains

    !> Keep the `trend_ranks` largest moduli of the multipliers at arclength s (and those of the point before).
    pure subroutine note_trend(trend, s, wr, wi)
        !> The trend.
        type(moduli_trend), intent(inout) :: trend
        !> Arclength of the point.
        real(wp), intent(in) :: s
        !> Its multipliers.
        real(wp), intent(in) :: wr(:), wi(:)
        real(wp), allocatable :: modulus(:)
        integer :: r, k

        trend%top_prev = trend%top_last
        trend%s_prev = trend%s_last
        modulus = hypot(wr, wi)
        trend%top_last = 0.0_wp
        do r = 1, min(trend_ranks, size(modulus))
            k = maxloc(modulus, dim=1)
            trend%top_last(r) = modulus(k)
            modulus(k) = -1.0_wp
        end do
        trend%s_last = s
        trend%n = min(trend%n + 1, 2)
    end subroutine note_trend

    !> Whether the multipliers are needed at arclength s_next although not due: the r-th largest modulus
    !> (r = 1..trend_ranks), extrapolated from the last two points with multipliers at twice its rate of
    !> growth, would pass 1 + crossing_tol by s_next (or fewer than two points are known).
    pure logical function trend_due(trend, s_next, crossing_tol)
        !> The trend.
        type(moduli_trend), intent(in) :: trend
        !> Arclength of the next point.
        real(wp), intent(in) :: s_next
        !> The crossing tolerance.
        real(wp), intent(in) :: crossing_tol
        real(wp) :: rate(trend_ranks)

        trend_due = .true.
        if (trend%n < 2 .or. .not. (trend%s_last > trend%s_prev)) return
        rate = max((trend%top_last - trend%top_prev)/(trend%s_last - trend%s_prev), 0.0_wp)
        trend_due = any(trend%top_last + trend_safety*rate*max(s_next - trend%s_last, 0.0_wp) > 1.0_wp + crossing_tol)
    end function trend_due

    !> Note the signs at recorded point `position`: of the point's own Jacobian and bordered system `sys` when its
    !> tangent is exact, else those its corrector found at its last Jacobian (an iterate near the point; none when
    !> it refreshed none). `changed_from` is the recorded point of the previous signs when either changed since
    !> (0 otherwise, or when they are not known).
    subroutine note_signs(watch, pt, sys, position, stats, changed_from)
        !> The watch.
        type(sign_watch), intent(inout) :: watch
        !> The point just recorded.
        type(branch_point), intent(in) :: pt
        !> Its bordered system, when its tangent is exact.
        type(bordered_system), intent(in) :: sys
        !> Its index in the branch.
        integer, intent(in) :: position
        !> Counts and times (the LU of J + I).
        type(continuation_stats), intent(inout) :: stats
        !> The point of the previous signs when a sign changed; 0 otherwise.
        integer, intent(out) :: changed_from
        integer :: flip, bordered

        changed_from = 0
        flip = pt%flip
        bordered = pt%bordered
        if (pt%exact) then
            call flip_test(pt%jac, flip, stats)
            bordered = det_sign(sys)
        end if
        if (flip == 0 .or. bordered == 0) return
        if (watch%flip /= 0 .and. (flip /= watch%flip .or. bordered /= watch%bordered)) changed_from = watch%at
        watch = sign_watch(flip, bordered, position)
    end subroutine note_signs

end module supratrans_continuation_watch
