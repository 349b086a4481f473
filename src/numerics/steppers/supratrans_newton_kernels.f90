!> The array kernels of the Newton stepper (`supratrans_stepper_newton`): its degree-6 predictor (alone, or in one
!> pass with the right-hand side on long chains) and the fused update loops of a Newton iteration with the sums of
!> its stopping test. Pure loops over arrays, with no state: each is vectorised by `!$omp simd`.
module supratrans_newton_kernels
    use supratrans_kinds, only: wp
    use supratrans_scheme, only: scheme_type
    implicit none
    private

    public :: extrapolate, predict_with_rhs, diagonal_update, diagonal_update_uniform, apply_update

    !> Levels the stepper's predictor extrapolates from (u^k .. u^{k-6}: degree 6).
    integer, parameter, public :: predictor_levels = 7
    !> Largest max |difference| between the degree-6 and the cubic extrapolations for which the first is used.
    real(wp), parameter, public :: predictor_trust = 0.05_wp
    !> The predictor's weights: x = sum_j w_j u^{k-j}, the binomial coefficients (-1)^j C(7, j+1).
    real(wp), parameter :: predictor_weights(predictor_levels) = [7.0_wp, -21.0_wp, 35.0_wp, -35.0_wp, 21.0_wp, &
                                                                  -7.0_wp, 1.0_wp]

contains

    !> The predictor x(1:N) = sum_j w_j u(1:N, columns(j)), columns of the levels k, k-1, ... (`predictor_weights`),
    !> unless it differs from the cubic extrapolation 3 u^k - 3 u^{k-1} + u^{k-2} by more than `predictor_trust`
    !> somewhere: then the motion is not smooth on the scale of dt (a kink, or a numerically unstable dt, whose
    !> growing sawtooth the degree-6 extrapolation amplifies 128 times), and the cubic one is used.
    pure subroutine extrapolate(u, columns, x)
        !> Time levels u(0:N+1, L).
        real(wp), intent(in), contiguous :: u(0:, :)
        !> Columns of u^k, u^{k-1}, ..., u^{k-6}.
        integer, intent(in) :: columns(predictor_levels)
        !> The predictor, size N.
        real(wp), intent(out), contiguous :: x(:)
        integer :: j, c1, c2, c3, c4, c5, c6, c7
        real(wp) :: gap, high

        c1 = columns(1)
        c2 = columns(2)
        c3 = columns(3)
        c4 = columns(4)
        c5 = columns(5)
        c6 = columns(6)
        c7 = columns(7)
        gap = 0.0_wp
        !$omp simd private(high) reduction(max: gap)
        do j = 1, size(x)
            high = predictor_weights(1)*u(j, c1) + predictor_weights(2)*u(j, c2) + predictor_weights(3)*u(j, c3) &
                   + predictor_weights(4)*u(j, c4) + predictor_weights(5)*u(j, c5) + predictor_weights(6)*u(j, c6) &
                   + predictor_weights(7)*u(j, c7)
            x(j) = high
            gap = max(gap, abs(high - (3.0_wp*(u(j, c1) - u(j, c2)) + u(j, c3))))
        end do
        if (.not. (gap <= predictor_trust)) then
            do j = 1, size(x)
                x(j) = 3.0_wp*(u(j, c1) - u(j, c2)) + u(j, c3)
            end do
        end if
    end subroutine extrapolate

    !> The predictor x = sum_j w_j u(1:N, columns(j)) of degree 6 (`predictor_weights`), its largest difference from
    !> the cubic extrapolation (`gap`), the right-hand side B u^k + C u^{k-1} (`scheme_rhs_and_predictor`'s, term for
    !> term) and max |x_n - u^{k-1}_n|/2, in one pass, so that on a long chain the levels stream from memory once a
    !> step.
    pure subroutine predict_with_rhs(scheme, e, u, columns, x, rhs, h_max, gap)
        !> Scheme coefficients.
        type(scheme_type), intent(in) :: scheme
        !> The scheme's e_n (`scheme%e`, passed as an array of its own: the loop then vectorises without a run-time
        !> check of overlap with x and rhs).
        real(wp), intent(in), contiguous :: e(:)
        !> Time levels u(0:N+1, L).
        real(wp), intent(in), contiguous :: u(0:, :)
        !> Columns of u^k, u^{k-1}, ..., u^{k-6} (the first two, with their boundary cells, also give the right-hand
        !> side).
        integer, intent(in) :: columns(predictor_levels)
        !> The predictor and the right-hand side, size N.
        real(wp), intent(out), contiguous :: x(:), rhs(:)
        !> max_n |x_n - u^{k-1}_n|/2 and max_n |x_n - cubic_n|.
        real(wp), intent(out) :: h_max, gap
        integer :: j, c1, c2, c3, c4, c5, c6, c7
        real(wp) :: high

        c1 = columns(1)
        c2 = columns(2)
        c3 = columns(3)
        c4 = columns(4)
        c5 = columns(5)
        c6 = columns(6)
        c7 = columns(7)
        gap = 0.0_wp
        h_max = 0.0_wp
        !$omp simd private(high) reduction(max: gap, h_max)
        do j = 1, size(x)
            high = predictor_weights(1)*u(j, c1) + predictor_weights(2)*u(j, c2) + predictor_weights(3)*u(j, c3) &
                   + predictor_weights(4)*u(j, c4) + predictor_weights(5)*u(j, c5) + predictor_weights(6)*u(j, c6) &
                   + predictor_weights(7)*u(j, c7)
            x(j) = high
            gap = max(gap, abs(high - (3.0_wp*(u(j, c1) - u(j, c2)) + u(j, c3))))
            rhs(j) = scheme%d*u(j, c1) + scheme%c2*(u(j - 1, c1) + u(j + 1, c1)) &
                     + e(j)*u(j, c2) + scheme%a*(u(j - 1, c2) + u(j + 1, c2))
            h_max = max(h_max, 0.5_wp*abs(high - u(j, c2)))
        end do
    end subroutine predict_with_rhs

    !> One Newton iteration with a diagonal Jacobian (beta = 0), fused: residual r_n = rhs_n - b_n x_n - G_n,
    !> update delta_n = r_n/(b_n + dG/da_n), x_n += delta_n, and the sums of the stopping test.
    pure subroutine diagonal_update(b, rhs, g, dg, x_old, x, delta, change, defect, scale, h_max, x_max)
        !> Diagonal b_n of A, right-hand side, G and dG/da at the current iterate.
        real(wp), intent(in), contiguous :: b(:), rhs(:), g(:), dg(:)
        !> Level k-1 (the second argument of G).
        real(wp), intent(in), contiguous :: x_old(:)
        !> The iterate: in the current one, out the updated one.
        real(wp), intent(inout), contiguous :: x(:)
        !> The update.
        real(wp), intent(out), contiguous :: delta(:)
        !> max |delta_n|, sum delta_n^2 |h_n|, sum b_n |x_n| |h_n| (h = (x - x_old)/2 after the update).
        real(wp), intent(out) :: change, defect, scale
        !> max |h_n| after the update.
        real(wp), intent(out) :: h_max
        !> max |x_n| after the update (the blow-up measure of an accepted step: its x is finite).
        real(wp), intent(out) :: x_max
        integer :: j
        real(wp) :: d, xn, h

        change = 0.0_wp
        defect = 0.0_wp
        scale = 0.0_wp
        h_max = 0.0_wp
        x_max = 0.0_wp
        !$omp simd private(d, xn, h) reduction(max: change, h_max, x_max) reduction(+: defect, scale)
        do j = 1, size(x)
            d = (rhs(j) - b(j)*x(j) - g(j))/(b(j) + dg(j))
            xn = x(j) + d
            h = 0.5_wp*abs(xn - x_old(j))
            x(j) = xn
            delta(j) = d
            change = max(change, abs(d))
            h_max = max(h_max, h)
            x_max = max(x_max, abs(xn))
            defect = defect + d*d*h
            scale = scale + b(j)*abs(xn)*h
        end do
    end subroutine diagonal_update

    !> `diagonal_update` on sites before the absorber, where every b_n is b_1 (alpha_n = gamma exactly): the same
    !> loop with b_1 in a register (one stream less through memory on a long chain).
    pure subroutine diagonal_update_uniform(b1, rhs, g, dg, x_old, x, delta, change, defect, scale, h_max, x_max)
        !> The common diagonal b_1 of A.
        real(wp), intent(in) :: b1
        !> Right-hand side, G and dG/da at the current iterate.
        real(wp), intent(in), contiguous :: rhs(:), g(:), dg(:)
        !> Level k-1 (the second argument of G).
        real(wp), intent(in), contiguous :: x_old(:)
        !> The iterate: in the current one, out the updated one.
        real(wp), intent(inout), contiguous :: x(:)
        !> The update.
        real(wp), intent(out), contiguous :: delta(:)
        !> As in `diagonal_update`.
        real(wp), intent(out) :: change, defect, scale, h_max, x_max
        integer :: j
        real(wp) :: d, xn, h

        change = 0.0_wp
        defect = 0.0_wp
        scale = 0.0_wp
        h_max = 0.0_wp
        x_max = 0.0_wp
        !$omp simd private(d, xn, h) reduction(max: change, h_max, x_max) reduction(+: defect, scale)
        do j = 1, size(x)
            d = (rhs(j) - b1*x(j) - g(j))/(b1 + dg(j))
            xn = x(j) + d
            h = 0.5_wp*abs(xn - x_old(j))
            x(j) = xn
            delta(j) = d
            change = max(change, abs(d))
            h_max = max(h_max, h)
            x_max = max(x_max, abs(xn))
            defect = defect + d*d*h
            scale = scale + b1*abs(xn)*h
        end do
    end subroutine diagonal_update_uniform

    !> Apply a Newton update (tridiagonal case) and form the sums of the stopping test (as `diagonal_update`).
    pure subroutine apply_update(b, x_old, x, delta, change, defect, scale, h_max, x_max)
        !> Diagonal b_n of A.
        real(wp), intent(in), contiguous :: b(:)
        !> Level k-1.
        real(wp), intent(in), contiguous :: x_old(:)
        !> The iterate, updated.
        real(wp), intent(inout), contiguous :: x(:)
        !> The update.
        real(wp), intent(in), contiguous :: delta(:)
        !> As in `diagonal_update`.
        real(wp), intent(out) :: change, defect, scale, h_max, x_max
        integer :: j
        real(wp) :: d, xn, h

        change = 0.0_wp
        defect = 0.0_wp
        scale = 0.0_wp
        h_max = 0.0_wp
        x_max = 0.0_wp
        !$omp simd private(d, xn, h) reduction(max: change, h_max, x_max) reduction(+: defect, scale)
        do j = 1, size(x)
            d = delta(j)
            xn = x(j) + d
            h = 0.5_wp*abs(xn - x_old(j))
            x(j) = xn
            change = max(change, abs(d))
            h_max = max(h_max, h)
            x_max = max(x_max, abs(xn))
            defect = defect + d*d*h
            scale = scale + b(j)*abs(xn)*h
        end do
    end subroutine apply_update

end module supratrans_newton_kernels
