!> The sine kernels of the potentials built on 1 - cos u (sine-Gordon, double sine-Gordon): the branch-free,
!> vectorised sine and cosine of an array (`sin_cos_array`), the rotation of sin(s), cos(s) by angle addition
!> between Newton iterations (`rotate_sin_cos`), sinc and its slope, and the sine-Gordon discrete gradient of
!> whole arrays. They sit in one module so that the compiler inlines the small elemental helpers into the loops
!> (gfortran inlines within a module only): the sine-Gordon kernels were tuned here (docs/benchmark.md).
!>
!> Sine-Gordon, V(u) = 1 - cos u: G(a, b) = sin(s) sinc(h), with s = (a + b)/2 and h = (a - b)/2, and
!> dG/da = (cos(s) sinc(h) + sin(s) sinc'(h))/2, never the difference quotient (0/0 at rest).
module supratrans_sine_kernels
    use supratrans_kinds, only: wp
    implicit none
    private

    public :: sine_gordon_gradient, sine_gordon_gradient_array, sine_gordon_gradient_refine, sine_gordon_force_array
    public :: sin_cos_array, rotate_sin_cos, sinc_and_slope, max_abs

    !> Below this |h| = |a - b|/2 the Taylor series of sinc and sinc' are used (truncation error < 3e-21).
    real(wp), parameter :: h_series = 0.25_wp
    !> Largest |x| for which `sin_cos_array` uses its own reduction (k pi/2 exact in parts for |k| < 2^20).
    real(wp), parameter, public :: trig_max = 1.0e5_wp
    !> Largest |x| for which sin x and cos x are taken from their Taylor polynomials without a reduction (just
    !> below pi/4, where the reduction of `sin_cos_reduced` leaves x unchanged).
    real(wp), parameter :: taylor_max = 0.78_wp
    !> Largest max |delta| for which the refinements advance sin(s), cos(s) by angle addition.
    real(wp), parameter, public :: rotate_max = 0.05_wp

contains

    !> Sine-Gordon G(a, b) and dG/da of one pair (they share their transcendental evaluations).
    elemental subroutine sine_gordon_gradient(a, b, g, dg)
        !> New value u_n^{k+1}.
        real(wp), intent(in) :: a
        !> Old value u_n^{k-1}.
        real(wp), intent(in) :: b
        !> Discrete gradient G(a, b) and dG/da.
        real(wp), intent(out) :: g, dg

        call sine_gordon_g(sin(0.5_wp*(a + b)), cos(0.5_wp*(a + b)), 0.5_wp*(a - b), g, dg)
    end subroutine sine_gordon_gradient

    !> Sine-Gordon G(a_n, b_n) and dG/da for whole arrays: the Newton step's kernel. sin(s_n) and cos(s_n),
    !> s = (a + b)/2, are returned in `ss` and `cs` so that later Newton iterations can refine them without new
    !> transcendentals (`sine_gordon_gradient_refine`).
    pure subroutine sine_gordon_gradient_array(a, b, g, dg, ss, cs, h_max)
        !> New values u^{k+1}.
        real(wp), intent(in), contiguous :: a(:)
        !> Old values u^{k-1}, same size as `a`.
        real(wp), intent(in), contiguous :: b(:)
        !> Discrete gradients G(a_n, b_n).
        real(wp), intent(out), contiguous :: g(:)
        !> Derivatives dG/da(a_n, b_n).
        real(wp), intent(out), contiguous :: dg(:)
        !> sin(s_n) and cos(s_n).
        real(wp), intent(inout), contiguous :: ss(:), cs(:)
        !> max |a_n - b_n|/2 when the caller knows it (else it is computed here).
        real(wp), intent(in), optional :: h_max

        call sine_gordon_kernel(.false., a, b, a, ss, cs, g, dg, half_difference_max(a, b, h_max))
    end subroutine sine_gordon_gradient_array

    !> Same as `sine_gordon_gradient_array` after a Newton update `delta` of `a` (a = a_previous + delta): when
    !> max |delta| <= `rotate_max`, sin(s) and cos(s) are advanced by the angle-addition formulas (s moves by
    !> delta/2) without transcendentals; otherwise they are evaluated afresh.
    pure subroutine sine_gordon_gradient_refine(a, b, delta, g, dg, ss, cs, delta_max, h_max)
        !> New values u^{k+1} (already updated by `delta`).
        real(wp), intent(in), contiguous :: a(:)
        !> Old values u^{k-1}.
        real(wp), intent(in), contiguous :: b(:)
        !> The update just applied to `a`.
        real(wp), intent(in), contiguous :: delta(:)
        !> Discrete gradients G(a_n, b_n).
        real(wp), intent(out), contiguous :: g(:)
        !> Derivatives dG/da(a_n, b_n).
        real(wp), intent(out), contiguous :: dg(:)
        !> sin(s_n), cos(s_n) on entry for the previous `a`, on exit for the new one.
        real(wp), intent(inout), contiguous :: ss(:), cs(:)
        !> max |delta_n| when the caller knows it (else it is computed here).
        real(wp), intent(in), optional :: delta_max
        !> max |a_n - b_n|/2 when the caller knows it (else it is computed here).
        real(wp), intent(in), optional :: h_max
        real(wp) :: dmax

        if (present(delta_max)) then
            dmax = delta_max
        else
            dmax = max_abs(delta)
        end if
        call sine_gordon_kernel(dmax <= rotate_max, a, b, delta, ss, cs, g, dg, half_difference_max(a, b, h_max))
    end subroutine sine_gordon_gradient_refine

    !> sin(s_n), cos(s_n) advanced by the angle delta_n/2 (s = (a + b)/2 after an update delta of a) by the
    !> angle-addition formulas, for max |delta| <= `rotate_max` (the caller checks).
    pure subroutine rotate_sin_cos(delta, ss, cs)
        !> The update of a.
        real(wp), intent(in), contiguous :: delta(:)
        !> sin(s_n), cos(s_n): in for the old s, out for the new one.
        real(wp), intent(inout), contiguous :: ss(:), cs(:)
        integer :: n
        real(wp) :: s_old, se, ce

        !$omp simd private(s_old, se, ce)
        do n = 1, size(delta)
            call small_angle(0.5_wp*delta(n), se, ce)
            s_old = ss(n)
            ss(n) = s_old*ce + cs(n)*se
            cs(n) = cs(n)*ce - s_old*se
        end do
    end subroutine rotate_sin_cos

    !> Sine-Gordon forces V'(u_n) = sin u_n for a whole array (the linearized scheme's kernel).
    pure subroutine sine_gordon_force_array(u, f)
        !> Displacements u_n (contiguous, so that the sines vectorise through libmvec).
        real(wp), intent(in), contiguous :: u(:)
        !> Forces V'(u_n).
        real(wp), intent(out), contiguous :: f(:)
        integer :: m

        m = head_length(u, taylor_max)
        f(1:m) = sin(u(1:m))        ! libmvec's vector sin: faster than a sine alone by our reduction
        f(m + 1:) = sin_taylor(u(m + 1:))   ! the quiet tail: the polynomial, 2.5 times faster here
    end subroutine sine_gordon_force_array

    !> max |a_n - b_n|/2: `h_max` when present, else computed.
    pure function half_difference_max(a, b, h_max) result(hmax)
        !> New and old values.
        real(wp), intent(in), contiguous :: a(:), b(:)
        !> The caller's value, if it has one.
        real(wp), intent(in), optional :: h_max
        real(wp) :: hmax
        integer :: n

        if (present(h_max)) then
            hmax = h_max
            return
        end if
        hmax = 0.0_wp
        do n = 1, size(a)
            if (.not. (abs(a(n) - b(n)) <= hmax)) hmax = abs(a(n) - b(n))
        end do
        hmax = 0.5_wp*hmax
    end function half_difference_max

    !> Sine-Gordon G(a_n, b_n) = sin(s_n) sinc(h_n) and dG/da = (cos(s_n) sinc(h_n) + sin(s_n) sinc'(h_n))/2, with
    !> s = (a + b)/2, h = (a - b)/2, and sin(s_n), cos(s_n) either evaluated (`rotate` false) or advanced from their
    !> previous values by the angle delta_n/2 (`rotate` true; the caller has checked max |delta| <= `rotate_max`).
    !>
    !> Every choice is made once per array, so that each loop is branch-free and vectorises: the sinc series when
    !> `h_max` < `h_series` (the usual case: h is a velocity times dt), else the per-site closed form. The sines
    !> and cosines come from the branch-free `sin_cos_reduced` (the intrinsics when some |s_n| > `trig_max`;
    !> the intrinsic pair in one loop would be a scalar `sincos` call per site). The angle addition uses
    !> the Taylor polynomials of the sine (to degree 7) and cosine (to degree 8) of delta/2: for |delta/2| <= 0.025
    !> their truncation errors are below 5e-19 relative, far under roundoff.
    pure subroutine sine_gordon_kernel(rotate, a, b, delta, ss, cs, g, dg, h_max)
        !> Advance sin(s), cos(s) by delta/2 instead of evaluating them.
        logical, intent(in) :: rotate
        !> New and old values.
        real(wp), intent(in), contiguous :: a(:), b(:)
        !> The update just applied to `a` (read only when `rotate`).
        real(wp), intent(in), contiguous :: delta(:)
        !> sin(s_n), cos(s_n): out for the current `a` (in for the previous one when `rotate`).
        real(wp), intent(inout), contiguous :: ss(:), cs(:)
        !> G(a_n, b_n) and dG/da.
        real(wp), intent(out), contiguous :: g(:), dg(:)
        !> max |h_n| (NaN selects the per-site closed form).
        real(wp), intent(in) :: h_max
        integer :: n
        real(wp) :: sc, dsc, s_old, se, ce

        if (.not. rotate) then
            do n = 1, size(a)
                g(n) = 0.5_wp*(a(n) + b(n))        ! g holds s until G is formed
            end do
            call sin_cos_array(g, ss, cs)
        end if
        if (h_max < h_series) then
            if (rotate) then
                !$omp simd private(sc, dsc, s_old, se, ce)
                do n = 1, size(a)
                    call small_angle(0.5_wp*delta(n), se, ce)
                    s_old = ss(n)
                    ss(n) = s_old*ce + cs(n)*se
                    cs(n) = cs(n)*ce - s_old*se
                    call sinc_series(0.5_wp*(a(n) - b(n)), sc, dsc)
                    g(n) = ss(n)*sc
                    dg(n) = 0.5_wp*(cs(n)*sc + ss(n)*dsc)
                end do
            else
                !$omp simd private(sc, dsc)
                do n = 1, size(a)
                    call sinc_series(0.5_wp*(a(n) - b(n)), sc, dsc)
                    g(n) = ss(n)*sc
                    dg(n) = 0.5_wp*(cs(n)*sc + ss(n)*dsc)
                end do
            end if
        else
            if (rotate) then
                do n = 1, size(a)
                    call small_angle(0.5_wp*delta(n), se, ce)
                    s_old = ss(n)
                    ss(n) = s_old*ce + cs(n)*se
                    cs(n) = cs(n)*ce - s_old*se
                end do
            end if
            do n = 1, size(a)
                call sine_gordon_g(ss(n), cs(n), 0.5_wp*(a(n) - b(n)), g(n), dg(n))
            end do
        end if
    end subroutine sine_gordon_kernel

    !> sin and cos of a small angle eps (|eps| <= 0.025) by their Taylor polynomials to degree 7 and 8, evaluated
    !> by Estrin's scheme (short dependency chains, so that consecutive sites overlap in the pipeline).
    elemental subroutine small_angle(eps, se, ce)
        !> The angle.
        real(wp), intent(in) :: eps
        !> sin(eps), cos(eps).
        real(wp), intent(out) :: se, ce
        real(wp) :: e2, e4

        e2 = eps*eps
        e4 = e2*e2
        se = eps + eps*e2*((-1.0_wp/6.0_wp + e2/120.0_wp) + e4*(-1.0_wp/5040.0_wp))
        ce = 1.0_wp + e2*((-0.5_wp + e2/24.0_wp) + e4*(-1.0_wp/720.0_wp + e2/40320.0_wp))
    end subroutine small_angle

    !> sinc(h) = sin(h)/h and its derivative by their Taylor series, for |h| < `h_series` (truncation < 3e-21),
    !> evaluated by Estrin's scheme.
    elemental subroutine sinc_series(h, sc, dsc)
        !> Argument.
        real(wp), intent(in) :: h
        !> sinc(h), sinc'(h).
        real(wp), intent(out) :: sc, dsc
        real(wp), parameter :: c1 = -1.0_wp/6.0_wp, c2 = 1.0_wp/120.0_wp, c3 = -1.0_wp/5040.0_wp, &
                               c4 = 1.0_wp/362880.0_wp, c5 = -1.0_wp/39916800.0_wp, c6 = 1.0_wp/6227020800.0_wp
        real(wp), parameter :: d1 = -1.0_wp/3.0_wp, d2 = 1.0_wp/30.0_wp, d3 = -1.0_wp/840.0_wp, &
                               d4 = 1.0_wp/45360.0_wp, d5 = -1.0_wp/3991680.0_wp, d6 = 1.0_wp/518918400.0_wp
        real(wp) :: h2, h4

        h2 = h*h
        h4 = h2*h2
        sc = 1.0_wp + h2*((c1 + c2*h2) + h4*((c3 + c4*h2) + h4*(c5 + c6*h2)))
        dsc = h*((d1 + d2*h2) + h4*((d3 + d4*h2) + h4*(d5 + d6*h2)))
    end subroutine sinc_series

    !> sin(x_n) and cos(x_n) for a whole array in branch-free loops that vectorise, without library calls: the
    !> elements up to the last with |x_n| > `taylor_max` by `sin_cos_reduced`, the rest (the quiet tail of a
    !> chain) by the same Taylor polynomials without the reduction, which leaves them unchanged there (k = 0), so
    !> the values are those of `sin_cos_reduced` everywhere; for max |x_n| > `trig_max` the array is handed to the
    !> intrinsic sin and cos.
    pure subroutine sin_cos_array(x, s, c)
        !> Arguments.
        real(wp), intent(in), contiguous :: x(:)
        !> sin(x_n) and cos(x_n).
        real(wp), intent(out), contiguous :: s(:), c(:)
        integer :: n, m
        real(wp) :: x_max

        m = head_length(x, taylor_max)
        x_max = 0.0_wp
        !$omp simd reduction(max: x_max)
        do n = 1, m
            x_max = max(x_max, abs(x(n)))
            call sin_cos_reduced(x(n), s(n), c(n))
        end do
        !$omp simd
        do n = m + 1, size(x)
            s(n) = sin_taylor(x(n))
            c(n) = cos_taylor(x(n))
        end do
        if (x_max > trig_max) then
            do n = 1, size(x)
                s(n) = sin(x(n))
            end do
            do n = 1, size(x)
                c(n) = cos(x(n))
            end do
        end if
    end subroutine sin_cos_array

    !> The number of leading elements of x up to the last with |x_n| > bound (0 when there is none): every later
    !> element is within the bound (or NaN, which the callers' polynomials carry through).
    pure function head_length(x, bound) result(m)
        !> The array.
        real(wp), intent(in), contiguous :: x(:)
        !> The bound.
        real(wp), intent(in) :: bound
        integer :: m

        do m = size(x), 1, -1
            if (abs(x(m)) > bound) return
        end do
        m = 0
    end function head_length

    !> sin x and cos x, branch-free, for |x| <= `trig_max` (NaN or infinite x give NaN; called from
    !> `sin_cos_array` only, so that it is inlined there and the loop vectorises): the reduction
    !> x = k pi/2 + r, |r| <= pi/4, with pi/2 in three parts (the first two of 33 bits, so that k times them is exact
    !> for |k| < 2^20), the Taylor polynomials of sin r (to degree 17) and cos r (to degree 18), whose truncation
    !> errors are below 1e-19, evaluated by Estrin's scheme (short dependency chains), and the quadrant k mod 4.
    !> Measured within 2 units in the last place of glibc's sin and cos; about 1.6 times faster than libmvec's
    !> vector sin and cos together on this machine (SSE2; for a sine alone libmvec is faster, and is used).
    elemental subroutine sin_cos_reduced(x, s, c)
        !> Argument.
        real(wp), intent(in) :: x
        !> sin x, cos x.
        real(wp), intent(out) :: s, c
        real(wp), parameter :: pio2_1 = 1.5707963267341256_wp, pio2_2 = 6.077100506303966e-11_wp, &
                               pio2_3 = 2.0222662487959506e-21_wp, two_over_pi = 0.6366197723675814_wp
        real(wp) :: k, q, r, sr, cr
        logical :: odd

        k = nearest_integer(x*two_over_pi)
        q = k - 4.0_wp*nearest_integer(0.25_wp*k)       ! k mod 4, in {-2, -1, 0, 1, 2}
        r = ((x - k*pio2_1) - k*pio2_2) - k*pio2_3
        sr = sin_taylor(r)
        cr = cos_taylor(r)
        ! quadrant q: 0 (sin r, cos r), 1 (cos r, -sin r), +-2 (-sin r, -cos r), -1 (-cos r, sin r)
        odd = abs(q) == 1.0_wp
        s = merge(cr, sr, odd)
        c = merge(sr, cr, odd)
        s = merge(-s, s, q < -0.5_wp .or. q > 1.5_wp)
        c = merge(-c, c, q > 0.5_wp .or. q < -1.5_wp)
    end subroutine sin_cos_reduced

    !> sin r by its Taylor polynomial to degree 17, for |r| <= pi/4 (truncation error below 1e-19), evaluated by
    !> Estrin's scheme (short dependency chains).
    elemental function sin_taylor(r) result(sr)
        !> Argument.
        real(wp), intent(in) :: r
        real(wp) :: sr
        real(wp), parameter :: s1 = -1.0_wp/6.0_wp, s2 = 1.0_wp/120.0_wp, s3 = -1.0_wp/5040.0_wp, &
                               s4 = 1.0_wp/362880.0_wp, s5 = -1.0_wp/39916800.0_wp, s6 = 1.0_wp/6227020800.0_wp, &
                               s7 = -1.0_wp/1307674368000.0_wp, s8 = 1.0_wp/355687428096000.0_wp
        real(wp) :: r2, r4, r8

        r2 = r*r
        r4 = r2*r2
        r8 = r4*r4
        sr = r + r*r2*(((s1 + s2*r2) + r4*(s3 + s4*r2)) + r8*((s5 + s6*r2) + r4*(s7 + s8*r2)))
    end function sin_taylor

    !> cos r by its Taylor polynomial to degree 18, for |r| <= pi/4 (truncation error below 1e-19), by Estrin's
    !> scheme.
    elemental function cos_taylor(r) result(cr)
        !> Argument.
        real(wp), intent(in) :: r
        real(wp) :: cr
        real(wp), parameter :: c1 = -0.5_wp, c2 = 1.0_wp/24.0_wp, c3 = -1.0_wp/720.0_wp, c4 = 1.0_wp/40320.0_wp, &
                               c5 = -1.0_wp/3628800.0_wp, c6 = 1.0_wp/479001600.0_wp, &
                               c7 = -1.0_wp/87178291200.0_wp, c8 = 1.0_wp/20922789888000.0_wp
        real(wp) :: r2, r4, r8

        r2 = r*r
        r4 = r2*r2
        r8 = r4*r4
        cr = 1.0_wp + r2*(((c1 + c2*r2) + r4*(c3 + c4*r2)) + r8*((c5 + c6*r2) + r4*(c7 + c8*r2)))
    end function cos_taylor

    !> The integer nearest to x (ties to even) as a real, for |x| < 2^51, branch-free: adding and subtracting
    !> 1.5 * 2^52 leaves the rounded value (round-to-nearest arithmetic; no fast-math reassociation).
    elemental function nearest_integer(x) result(k)
        !> Argument.
        real(wp), intent(in) :: x
        real(wp) :: k
        real(wp), parameter :: round_shift = 6755399441055744.0_wp

        k = (x + round_shift) - round_shift
    end function nearest_integer

    !> max |x_n| of an array (NaN if any element is NaN, so that a caller's `<=` test fails on it).
    pure function max_abs(x) result(m)
        !> The array.
        real(wp), intent(in), contiguous :: x(:)
        real(wp) :: m
        integer :: n

        m = 0.0_wp
        do n = 1, size(x)
            if (.not. (abs(x(n)) <= m)) m = abs(x(n))
        end do
    end function max_abs

    !> Sine-Gordon G = sin(s) sinc(h) and dG/da = (cos(s) sinc(h) + sin(s) sinc'(h))/2 from sin(s), cos(s), h.
    elemental subroutine sine_gordon_g(ss, cs, h, g, dg)
        !> sin(s), cos(s), s = (a + b)/2.
        real(wp), intent(in) :: ss, cs
        !> h = (a - b)/2.
        real(wp), intent(in) :: h
        !> G(a, b) and dG/da.
        real(wp), intent(out) :: g, dg
        real(wp) :: sc, dsc

        call sinc_and_slope(h, sc, dsc)
        g = ss*sc
        dg = 0.5_wp*(cs*sc + ss*dsc)
    end subroutine sine_gordon_g


    !> sinc(h) = sin(h)/h and its derivative, by Taylor series near 0 and directly elsewhere.
    elemental subroutine sinc_and_slope(h, sc, dsc)
        !> Argument.
        real(wp), intent(in) :: h
        !> sin(h)/h (1 at h = 0).
        real(wp), intent(out) :: sc
        !> d/dh of sin(h)/h (0 at h = 0).
        real(wp), intent(out) :: dsc

        if (abs(h) < h_series) then
            call sinc_series(h, sc, dsc)
        else
            sc = sin(h)/h
            dsc = (cos(h) - sc)/h
        end if
    end subroutine sinc_and_slope

end module supratrans_sine_kernels
