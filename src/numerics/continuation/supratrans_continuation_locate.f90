!> The fold and crossing locator of the continuation (`supratrans_continuation`, whose documentation gives the
!> method): a safeguarded secant (Illinois) along the pseudo-arclength step from a branch point for the zero of the
!> tangent's A-component (the fold) or of the distance of a class of Floquet multipliers to the unit circle (a loss of
!> stability), each evaluation a corrected point; the crossing multiplier tracked by inverse iteration between
!> secant steps. No state of its own.
module supratrans_continuation_locate
    use supratrans_kinds, only: wp
    use supratrans_fixed_point_map, only: fixed_point_map
    use supratrans_floquet, only: crossing_distance, crossing_fold, track_multiplier, crossing_torus, &
                                  crossing_period_doubling
    use supratrans_continuation_types, only: continuation_controls, continuation_stats, wall_clock
    use supratrans_bordered_system, only: bordered_system, factor_bordered, det_sign
    use supratrans_continuation_corrector, only: branch_point, correct, complete_point, point_jacobian, &
                                                 point_multipliers, flip_test
    implicit none
    private

    public :: locate, class_max, bisect_sign

contains

    !> Safeguarded secant (Illinois) on the step sigma in (0, sigma_hi) from the point `bp` for the zero of
    !> g(sigma): the tangent's A-component (kind 0, the fold) or `crossing_distance` of that kind minus `shift`.
    !> `pt` is the last corrected point (with its multipliers wr, wi); `located` tells whether the tolerance
    !> was met.
    subroutine locate(map, bp, sys, sigma_hi, kind, shift, ctl, pt, wr, wi, located, stats, hi, g_lo, g_hi, mu_guess)
        !> The map P(x; A).
        class(fixed_point_map), intent(inout) :: map
        !> The bracket's left end (sigma = 0), with its Jacobian and tangent.
        type(branch_point), intent(in) :: bp
        !> The bordered system factorised at bp (last row bp's tangent).
        type(bordered_system), intent(in) :: sys
        !> The bracket's right end, and the shift of the crossing distance (0 for the fold).
        real(wp), intent(in) :: sigma_hi, shift
        !> 0: the fold; else the class of the crossing (`crossing_fold`, `crossing_period_doubling`, `crossing_torus`).
        integer, intent(in) :: kind
        !> Controls (`fold_tol`, the corrector's).
        type(continuation_controls), intent(in) :: ctl
        !> The last corrected point (its s: bp's plus its step).
        type(branch_point), intent(inout) :: pt
        !> Its multipliers (those of the fold point for kind 0; of the last `dgeev` for a crossing).
        real(wp), allocatable, intent(out) :: wr(:), wi(:)
        !> Whether the tolerance was met.
        logical, intent(out) :: located
        !> Counts and times.
        type(continuation_stats), intent(inout) :: stats
        !> The corrected point at sigma_hi, when the caller has it.
        type(branch_point), intent(in), optional :: hi
        !> `crossing_distance` of that kind at bp and at the branch point whose step along bp's tangent is sigma_hi,
        !> when the caller has them (no multipliers recomputed there).
        real(wp), intent(in), optional :: g_lo, g_hi
        !> The crossing multiplier at a bracket end (kind /= 0): tracked by inverse iteration from there instead of
        !> a `dgeev` at every secant step (`dgeev` again whenever the tracking fails or leaves the class).
        complex(wp), intent(in), optional :: mu_guess
        type(bordered_system) :: psys, fsys, csys
        logical :: have_csys
        complex(wp) :: mu_t
        complex(wp), allocatable :: vec(:)
        logical :: tracking
        real(wp) :: a, b, c, fa, fb, fc, kappa, a_prev
        integer :: iter, side, n1, info
        logical :: ok

        n1 = size(bp%y)
        located = .false.
        have_csys = .false.
        tracking = present(mu_guess) .and. kind /= 0
        if (tracking) then
            mu_t = mu_guess
            allocate (vec(n1 - 1))
            vec = cmplx(1.0_wp, 0.5_wp, kind=wp)
        end if
        a = 0.0_wp
        if (present(g_lo) .and. kind /= 0) then
            pt = bp
            fa = g_lo - shift
        else
            call value_at(a, fa, ok)
            if (.not. ok) return
        end if
        b = sigma_hi
        if (present(hi) .and. kind == 0) then
            fb = hi%t(n1)
        else if (present(g_hi) .and. kind /= 0) then
            fb = g_hi - shift
        else
            call value_at(b, fb, ok)
            if (.not. ok) return
        end if
        if (fa*fb > 0.0_wp) return
        side = 0
        a_prev = huge(1.0_wp)
        do iter = 1, 60
            c = b - fb*(b - a)/(fb - fa)
            if (.not. (c > min(a, b) .and. c < max(a, b))) c = 0.5_wp*(a + b)
            call value_at(c, fc, ok)
            if (.not. ok) return
            if (kind == 0) then
                kappa = abs(fb - fa)/max(abs(b - a), tiny(1.0_wp))
                if (fc**2 <= 2.0_wp*kappa*ctl%fold_tol) located = .true.
            else
                if (abs(pt%y(n1) - a_prev) <= ctl%fold_tol .or. fc == 0.0_wp) located = .true.
            end if
            if (abs(b - a) <= 1.0e-3_wp*ctl%fold_tol) located = .true.
            if (located) exit
            a_prev = pt%y(n1)
            if (fc*fb < 0.0_wp) then
                a = b
                fa = fb
                b = c
                fb = fc
                side = 0
            else
                b = c
                fb = fc
                if (side == 1) fa = 0.5_wp*fa
                side = 1
            end if
        end do
        if (kind == 0) then
            call point_multipliers(pt, stats, wr, wi, info)
            if (info /= 0) located = .false.
        end if

    contains

        subroutine value_at(sigma, g, okv)
            real(wp), intent(in) :: sigma
            real(wp), intent(out) :: g
            logical, intent(out) :: okv
            integer :: linfo

            if (sigma == 0.0_wp) then
                pt = bp
                okv = .true.
            else
                if (have_csys) then
                    call correct(map, bp, csys, sigma, ctl, pt, okv, stats, fsys)
                else
                    call correct(map, bp, sys, sigma, ctl, pt, okv, stats, fsys)
                end if
                if (.not. okv) return
                if (kind == 0) then
                    call complete_point(map, pt, bp%t, psys, okv, stats)
                else
                    ! a crossing needs the monodromy only (no tangent); the bordered matrix at this iterate, with
                    ! bp's tangent as its last row, is the chord matrix of the next corrections (nearer than bp's)
                    call point_jacobian(map, pt, okv, stats)
                    if (okv) then
                        call factor_bordered(pt%jac, pt%dpda, bp%t, csys, linfo, stats)
                        have_csys = linfo == 0
                    end if
                end if
                if (.not. okv) return
            end if
            pt%s = bp%s + sigma
            if (kind == 0) then
                g = pt%t(n1)
            else
                if (tracking) then
                    call tracked_distance(g, okv)
                    if (okv) return
                end if
                call point_multipliers(pt, stats, wr, wi, linfo)
                okv = linfo == 0
                g = crossing_distance(wr, wi, kind) - shift
                if (tracking .and. okv) then
                    ! start the tracking again from this point's crossing multiplier
                    linfo = class_max(wr, wi, kind)
                    if (linfo > 0) mu_t = cmplx(wr(linfo), wi(linfo), kind=wp)
                    vec = cmplx(1.0_wp, 0.5_wp, kind=wp)
                end if
            end if
        end subroutine value_at

        !> |mu| - 1 - shift of the tracked multiplier at pt (okt false when the tracking failed or its multiplier
        !> is no longer of the class: a torus pair that became real, a real multiplier that turned complex).
        subroutine tracked_distance(g, okt)
            real(wp), intent(out) :: g
            logical, intent(out) :: okt
            complex(wp) :: mu_try
            complex(wp), allocatable :: v_try(:)
            real(wp) :: t0, im_tol

            t0 = wall_clock()
            mu_try = mu_t
            v_try = vec
            call track_multiplier(pt%jac, mu_try, v_try, okt, 1.0e-13_wp)
            stats%time_eigen = stats%time_eigen + wall_clock() - t0
            stats%tracked = stats%tracked + 1
            g = 0.0_wp
            if (.not. okt) return
            im_tol = 1.0e-8_wp*abs(mu_try)
            select case (kind)
            case (crossing_torus)
                okt = abs(aimag(mu_try)) > im_tol
            case (crossing_period_doubling)
                okt = abs(aimag(mu_try)) <= im_tol .and. real(mu_try, wp) < 0.0_wp
            case default
                okt = abs(aimag(mu_try)) <= im_tol .and. real(mu_try, wp) >= 0.0_wp
            end select
            if (.not. okt) return
            mu_t = mu_try
            vec = v_try
            g = abs(mu_t) - 1.0_wp - shift
        end subroutine tracked_distance

    end subroutine locate

    !> A real multiplier through +1 (`crossing_fold`: the sign of the bordered matrix's determinant, rows bp's
    !> tangent) or -1 (`crossing_period_doubling`: the sign of det(J + I)) between bp (sigma = 0) and sigma_hi, by
    !> bisection on that sign, each point corrected along bp's tangent. Where `locate`'s secant on the multipliers
    !> fails, at a branch point (the multipliers' distance to the circle is no smooth function there, and the
    !> corrector's matrix is singular at the crossing itself). Ends when the bracket is within `fold_tol` in A
    !> (`located`), or when a correction fails near the crossing: `pt` is then the bracket's end past the crossing,
    !> and `narrowed` says whether either end of that bracket moved (the crossing lies between `lower` and pt's A).
    subroutine bisect_sign(map, bp, sys, sigma_hi, kind, ctl, pt, located, narrowed, lower, stats)
        !> The map P(x; A).
        class(fixed_point_map), intent(inout) :: map
        !> The bracket's left end (sigma = 0), with its Jacobian and tangent.
        type(branch_point), intent(in) :: bp
        !> The bordered system factorised at bp (last row bp's tangent).
        type(bordered_system), intent(in) :: sys
        !> The bracket's right end.
        real(wp), intent(in) :: sigma_hi
        !> `crossing_fold` or `crossing_period_doubling`.
        integer, intent(in) :: kind
        !> Controls (`fold_tol`, the corrector's).
        type(continuation_controls), intent(in) :: ctl
        !> The corrected point at the bracket's right end.
        type(branch_point), intent(inout) :: pt
        !> Whether the bracket reached `fold_tol`, and whether it was narrowed at all.
        logical, intent(out) :: located, narrowed
        !> A at the bracket's other end (before the crossing).
        real(wp), intent(out) :: lower
        !> Counts and times.
        type(continuation_stats), intent(inout) :: stats
        type(branch_point) :: trial
        type(bordered_system) :: fsys
        real(wp) :: lo, hi, c, a_lo, a_hi
        integer :: s0, s, iter, n1
        logical :: ok

        n1 = size(bp%y)
        located = .false.
        narrowed = .false.
        lower = bp%y(n1)
        s0 = sign_at(bp)
        if (s0 == 0) return
        lo = 0.0_wp
        hi = sigma_hi
        a_lo = bp%y(n1)
        call corrected(hi, ok, s)
        if (.not. ok .or. s == s0 .or. s == 0) return
        a_hi = trial%y(n1)
        pt = trial
        do iter = 1, 60
            if (abs(a_hi - a_lo) <= ctl%fold_tol) then
                located = .true.
                return
            end if
            c = 0.5_wp*(lo + hi)
            call corrected(c, ok, s)
            if (.not. ok .or. s == 0) return
            narrowed = .true.
            if (s == s0) then
                lo = c
                a_lo = trial%y(n1)
                lower = a_lo
            else
                hi = c
                a_hi = trial%y(n1)
                pt = trial
                pt%s = bp%s + c
            end if
        end do

    contains

        !> The point corrected at step sigma along bp's tangent, and the sign watched there.
        subroutine corrected(sigma, okc, sg)
            real(wp), intent(in) :: sigma
            logical, intent(out) :: okc
            integer, intent(out) :: sg

            sg = 0
            call correct(map, bp, sys, sigma, ctl, trial, okc, stats, fsys)
            if (okc) call point_jacobian(map, trial, okc, stats)
            if (okc) sg = sign_at(trial)
        end subroutine corrected

        !> The sign watched at a point with its Jacobian.
        integer function sign_at(p)
            type(branch_point), intent(in) :: p
            type(bordered_system) :: psys
            integer :: linfo

            sign_at = 0
            if (kind == crossing_period_doubling) then
                call flip_test(p%jac, sign_at, stats)
            else
                call factor_bordered(p%jac, p%dpda, bp%t, psys, linfo, stats)
                if (linfo == 0) sign_at = det_sign(psys)
            end if
        end function sign_at

    end subroutine bisect_sign

    !> Index of the multiplier of largest modulus in a class (`crossing_torus`: complex, `crossing_fold`: real >= 0,
    !> `crossing_period_doubling`: real < 0); 0 when the class is empty.
    pure integer function class_max(wr, wi, kind) result(k)
        !> Real and imaginary parts of the multipliers.
        real(wp), intent(in) :: wr(:), wi(:)
        !> The class.
        integer, intent(in) :: kind
        integer :: j, c
        real(wp) :: best

        k = 0
        best = -1.0_wp
        do j = 1, size(wr)
            if (wi(j) /= 0.0_wp) then
                c = crossing_torus
            else if (wr(j) >= 0.0_wp) then
                c = crossing_fold
            else
                c = crossing_period_doubling
            end if
            if (c == kind .and. hypot(wr(j), wi(j)) > best) then
                best = hypot(wr(j), wi(j))
                k = j
            end if
        end do
    end function class_max

end module supratrans_continuation_locate
