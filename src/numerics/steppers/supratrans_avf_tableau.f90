!> The coefficients of the steppers `avf4` and `avf8` (`supratrans_stepper_avf`): the energy-preserving collocation
!> method of Hairer (E. Hairer, "Energy-preserving variant of collocation methods", JNAIAM 5 (2010) 73-84) with s
!> Gauss nodes (s = 2: order 4; s = 4: order 8), on [0, 1]; its notation is used by the stepper.
!>
!> The method. Write the chain as y' = (J - R) grad H0(y) + f(t), y = (u, v), where H0 is the energy of the chain
!> with u_0 = 0 (H0 = sum v^2/2 + m^2 u^2/2 + V(u) + c^2/2 sum_{n=0}^{N} (u_{n+1} - u_n)^2, u_0 = u_{N+1} = 0), J the
!> canonical matrix, R = diag(0, alpha_n - beta Delta) >= 0 (Delta the second difference with v_0 = v_{N+1} = 0),
!> and f = (0, (c^2 psi + beta psi') e_1) the drive. A step of size h from t0 is the polynomial sigma of degree s
!> with sigma(t0) = y0 and, at the Gauss nodes t_i = t0 + c_i h,
!>     sigma'(t_i) = (J - R) g_i + f(t_i),   g_i = (1/b_i) int_0^1 l_i(tau) grad H0(sigma(t0 + tau h)) dtau,
!> l_i the Lagrange polynomials of the nodes, b_i the Gauss weights; y1 = sigma(t0 + h). The quadratic part of
!> H0 makes g_i the value at the node (the integrand has degree 2s - 1), so only the on-site force V' is averaged:
!>     Gbar_{n,i} = (1/b_i) int_0^1 l_i(tau) V'(sigma_{u,n}(tau)) dtau,
!> computed with a Gauss-Legendre rule of `nq` nodes, the potential's `averaging_nodes(s)`. For a polynomial V' of
!> degree p (sigma_u of degree s) the integrand has degree (p + 1) s - 1, and a rule of (p + 1) s / 2 nodes is exact
!> (3s for the phi^6 truncation). For a transcendental V' the rule is not exact: its error is the balance residual of
!> a step (the potential's module says what was measured).
!> Everything else is s-stage Gauss collocation: U_i = u0 + h sum_j a_ij V_j, V_i = v0 + h sum_j a_ij F_i.
!>
!> Linear stability: the method reduces to Gauss collocation on a linear chain (V' linear), which is A-stable
!> (its stability function is the (s, s) Pade approximant of exp, |R(z)| <= 1 for Re z <= 0): no step limit.
!>
!> The tableau (`avf_tableau`, made once a run by `avf_make_tableau`): the Gauss nodes c_i and weights b_i, the
!> collocation matrix A, W = A^{-1} and its eigen-decomposition (s/2 complex conjugate pairs, in which the stepper's
!> simplified Newton matrix splits), the averaging rule's weights and the predictor's extrapolation. Set-up code,
!> apart from the stage iteration it serves.
module supratrans_avf_tableau
    use supratrans_kinds, only: wp
    use supratrans_eigen, only: general_eigenvalues
    implicit none
    private

    public :: avf_make_tableau, gauss_legendre

    !> Gauss nodes (stages) of `avf4`.
    integer, parameter, public :: avf4_stages = 2
    !> Gauss nodes (stages) of `avf8`.
    integer, parameter, public :: avf8_stages = 4

    !> The coefficients of the s-stage energy-preserving collocation method on [0, 1].
    type, public :: avf_tableau
        !> Stages s (Gauss nodes) and nodes nq of the averaging rule.
        integer :: s = 0, nq = 0
        !> Gauss nodes c_i and weights b_i (size s).
        real(wp), allocatable :: c(:), b(:)
        !> Collocation matrix A (a_ij = int_0^{c_i} l_j), its inverse W and W^2 (s x s).
        real(wp), allocatable :: a(:, :), w(:, :), w2(:, :)
        !> b^T W: y1 = y0 + sum_j bw_j (Y_j - y0) for u and for v (size s).
        real(wp), allocatable :: bw(:)
        !> lag(q, k): Lagrange basis of the nodes (0, c_1 .. c_s) at the averaging rule's node tau_q, k = 0..s.
        real(wp), allocatable :: lag(:, :)
        !> qw(i, q) = w_q l_i(tau_q) / b_i: Gbar_i = sum_q qw(i, q) V'(sigma(tau_q)).
        real(wp), allocatable :: qw(:, :)
        !> The eigenvalues lambda_k of W with positive imaginary part (W has s/2 conjugate pairs, s even), an
        !> eigenvector for each (the columns of tf, s x s/2) and the matching rows of T^{-1} (tinvf, s/2 x s),
        !> T = [t_1, conj t_1, t_2, conj t_2, ...]: a real r is sum_k 2 Re(t_k (tinvf r)_k).
        complex(wp), allocatable :: lam(:), tf(:, :), tinvf(:, :)
        !> The same as real matrices (s x s): row 2k - 1 and 2k of tin are the real and imaginary parts of row k of
        !> tinvf; column 2k - 1 and 2k of tb are 2 Re and -2 Im of column k of tf (delta = tb (Re rho, Im rho)).
        real(wp), allocatable :: tin(:, :), tb(:, :)
        !> mid(j) = L_j(1/2), j = 1..s: sigma_u(1/2) = u0 + sum_j mid(j) Z_j.
        real(wp), allocatable :: mid(:)
        !> ext(i, j) = L_j(1 + c_i) - bw_j, j = 1..s (L the Lagrange basis of lag): the predictor Z_i = sum_j ext(i, j)
        !> Z_j^prev, the previous step's collocation polynomial extrapolated, relative to the new level.
        real(wp), allocatable :: ext(:, :)
    end type avf_tableau

contains

    !> Gauss-Legendre rule of k nodes on [0, 1] (nodes ascending), by Newton's method on P_k.
    pure subroutine gauss_legendre(k, x, w)
        !> Number of nodes.
        integer, intent(in) :: k
        !> Nodes and weights, size k.
        real(wp), intent(out) :: x(:), w(:)
        real(wp), parameter :: pi = acos(-1.0_wp)
        integer :: i, it
        real(wp) :: z, p1, dp, dz

        do i = 1, k
            z = cos(pi*(real(i, wp) - 0.25_wp)/(real(k, wp) + 0.5_wp))
            do it = 1, 100
                call legendre(z, p1, dp)
                dz = p1/dp
                z = z - dz
                if (abs(dz) <= 1.0e-17_wp .or. it > 8 .and. abs(dz) <= 4.0_wp*epsilon(z)) exit
            end do
            call legendre(z, p1, dp)
            x(k + 1 - i) = 0.5_wp*(1.0_wp + z)
            w(k + 1 - i) = 1.0_wp/((1.0_wp - z*z)*dp*dp)
        end do

    contains

        !> P_k(z) and P_k'(z) by the three-term recurrence.
        pure subroutine legendre(z, pk, dpk)
            real(wp), intent(in) :: z
            real(wp), intent(out) :: pk, dpk
            real(wp) :: p0, p1, p2
            integer :: j

            p0 = 1.0_wp
            p1 = z
            do j = 2, k
                p2 = (real(2*j - 1, wp)*z*p1 - real(j - 1, wp)*p0)/real(j, wp)
                p0 = p1
                p1 = p2
            end do
            pk = p1
            dpk = real(k, wp)*(z*p1 - p0)/(z*z - 1.0_wp)
        end subroutine legendre
    end subroutine gauss_legendre

    !> The Lagrange basis polynomial j of `nodes` at t.
    pure function lagrange(nodes, j, t) result(l)
        !> Interpolation nodes.
        real(wp), intent(in) :: nodes(:)
        !> Which basis polynomial (1-based).
        integer, intent(in) :: j
        !> Argument.
        real(wp), intent(in) :: t
        real(wp) :: l
        integer :: m

        l = 1.0_wp
        do m = 1, size(nodes)
            if (m /= j) l = l*(t - nodes(m))/(nodes(j) - nodes(m))
        end do
    end function lagrange

    !> Inverse of a small matrix by Gauss-Jordan elimination with partial pivoting; ok false if singular.
    pure subroutine invert(m, minv, ok)
        !> The matrix (s x s).
        real(wp), intent(in) :: m(:, :)
        !> Its inverse.
        real(wp), intent(out) :: minv(:, :)
        !> False when a pivot is zero or not finite.
        logical, intent(out) :: ok
        real(wp) :: a(size(m, 1), size(m, 1)), row(size(m, 1)), piv, f
        integer :: s, i, j, p

        s = size(m, 1)
        a = m
        minv = 0.0_wp
        do i = 1, s
            minv(i, i) = 1.0_wp
        end do
        ok = .true.
        do i = 1, s
            p = i
            do j = i + 1, s
                if (abs(a(j, i)) > abs(a(p, i))) p = j
            end do
            if (p /= i) then
                row = a(i, :)
                a(i, :) = a(p, :)
                a(p, :) = row
                row = minv(i, :)
                minv(i, :) = minv(p, :)
                minv(p, :) = row
            end if
            piv = a(i, i)
            if (.not. (abs(piv) > 0.0_wp .and. abs(piv) <= huge(piv))) then
                ok = .false.
                return
            end if
            a(i, :) = a(i, :)/piv
            minv(i, :) = minv(i, :)/piv
            do j = 1, s
                if (j == i) cycle
                f = a(j, i)
                a(j, :) = a(j, :) - f*a(i, :)
                minv(j, :) = minv(j, :) - f*minv(i, :)
            end do
        end do
    end subroutine invert

    !> Inverse of a small complex matrix by Gauss-Jordan elimination with partial pivoting; ok false if singular.
    pure subroutine cinvert(m, minv, ok)
        !> The matrix (s x s).
        complex(wp), intent(in) :: m(:, :)
        !> Its inverse.
        complex(wp), intent(out) :: minv(:, :)
        !> False when a pivot is zero.
        logical, intent(out) :: ok
        complex(wp) :: a(size(m, 1), size(m, 1)), row(size(m, 1)), piv, f
        integer :: s, i, j, p

        s = size(m, 1)
        a = m
        minv = (0.0_wp, 0.0_wp)
        do i = 1, s
            minv(i, i) = (1.0_wp, 0.0_wp)
        end do
        ok = .true.
        do i = 1, s
            p = i
            do j = i + 1, s
                if (abs(a(j, i)) > abs(a(p, i))) p = j
            end do
            if (p /= i) then
                row = a(i, :)
                a(i, :) = a(p, :)
                a(p, :) = row
                row = minv(i, :)
                minv(i, :) = minv(p, :)
                minv(p, :) = row
            end if
            piv = a(i, i)
            if (.not. (abs(piv) > 0.0_wp)) then
                ok = .false.
                return
            end if
            a(i, :) = a(i, :)/piv
            minv(i, :) = minv(i, :)/piv
            do j = 1, s
                if (j == i) cycle
                f = a(j, i)
                a(j, :) = a(j, :) - f*a(i, :)
                minv(j, :) = minv(j, :) - f*minv(i, :)
            end do
        end do
    end subroutine cinvert

    !> The eigen-decomposition of W = A^{-1} (s even: s/2 complex conjugate pairs, no real eigenvalue, as for
    !> every Gauss method of even order s): the eigenvalues with positive imaginary part, their eigenvectors (the
    !> last component 1, the others from the first s - 1 rows of (W - lambda I) t = 0), and the rows of T^{-1}.
    pure subroutine eigen_pairs(w, lam, tf, tinvf)
        !> The matrix W (s x s).
        real(wp), intent(in) :: w(:, :)
        !> Eigenvalues with Im > 0, eigenvectors, rows of T^{-1}.
        complex(wp), allocatable, intent(out) :: lam(:), tf(:, :), tinvf(:, :)
        real(wp) :: a(size(w, 1), size(w, 1)), wr(size(w, 1)), wi(size(w, 1))
        complex(wp) :: m(size(w, 1) - 1, size(w, 1) - 1), minv(size(w, 1) - 1, size(w, 1) - 1)
        complex(wp) :: t(size(w, 1), size(w, 1)), tinv(size(w, 1), size(w, 1))
        integer :: s, i, k, info
        logical :: ok

        s = size(w, 1)
        a = w
        call general_eigenvalues(a, wr, wi, info)
        allocate (lam(s/2), tf(s, s/2), tinvf(s/2, s))
        k = 0
        do i = 1, s
            if (wi(i) > 0.0_wp .and. k < s/2) then
                k = k + 1
                lam(k) = cmplx(wr(i), wi(i), kind=wp)
            end if
        end do
        do k = 1, s/2
            m = w(1:s - 1, 1:s - 1)
            do i = 1, s - 1
                m(i, i) = m(i, i) - lam(k)
            end do
            call cinvert(m, minv, ok)
            tf(1:s - 1, k) = -matmul(minv, cmplx(w(1:s - 1, s), 0.0_wp, kind=wp))
            tf(s, k) = (1.0_wp, 0.0_wp)
            t(:, 2*k - 1) = tf(:, k)
            t(:, 2*k) = conjg(tf(:, k))
        end do
        call cinvert(t, tinv, ok)
        do k = 1, s/2
            tinvf(k, :) = tinv(2*k - 1, :)
        end do
    end subroutine eigen_pairs

    !> The coefficients of the s-stage method (Gauss nodes) with an averaging rule of nq nodes.
    pure subroutine avf_make_tableau(s, nq, tab)
        !> Stages.
        integer, intent(in) :: s
        !> Nodes of the averaging rule.
        integer, intent(in) :: nq
        !> The coefficients.
        type(avf_tableau), intent(out) :: tab
        real(wp) :: gx(s), gw(s), tq(nq), wq(nq), z(0:s)
        integer :: i, j, q, k
        logical :: ok

        tab%s = s
        tab%nq = nq
        allocate (tab%c(s), tab%b(s), tab%a(s, s), tab%w(s, s), tab%w2(s, s), tab%bw(s))
        allocate (tab%lag(nq, 0:s), tab%qw(s, nq), tab%ext(s, s), tab%mid(s))
        call gauss_legendre(s, tab%c, tab%b)
        call gauss_legendre(s, gx, gw)
        do i = 1, s
            do j = 1, s
                tab%a(i, j) = 0.0_wp
                do q = 1, s
                    tab%a(i, j) = tab%a(i, j) + tab%c(i)*gw(q)*lagrange(tab%c, j, tab%c(i)*gx(q))
                end do
            end do
        end do
        call invert(tab%a, tab%w, ok)
        tab%w2 = matmul(tab%w, tab%w)
        call eigen_pairs(tab%w, tab%lam, tab%tf, tab%tinvf)
        allocate (tab%tin(s, s), tab%tb(s, s))
        do k = 1, s/2
            tab%tin(2*k - 1, :) = real(tab%tinvf(k, :), wp)
            tab%tin(2*k, :) = aimag(tab%tinvf(k, :))
            tab%tb(:, 2*k - 1) = 2.0_wp*real(tab%tf(:, k), wp)
            tab%tb(:, 2*k) = -2.0_wp*aimag(tab%tf(:, k))
        end do
        tab%bw = matmul(tab%b, tab%w)
        call gauss_legendre(nq, tq, wq)
        z(0) = 0.0_wp
        z(1:s) = tab%c
        do q = 1, nq
            do k = 0, s
                tab%lag(q, k) = lagrange(z, k + 1, tq(q))
            end do
            do i = 1, s
                tab%qw(i, q) = wq(q)*lagrange(tab%c, i, tq(q))/tab%b(i)
            end do
        end do
        do k = 1, s
            tab%mid(k) = lagrange(z, k + 1, 0.5_wp)
        end do
        do i = 1, s
            do k = 1, s
                tab%ext(i, k) = lagrange(z, k + 1, 1.0_wp + tab%c(i)) - tab%bw(k)
            end do
        end do
    end subroutine avf_make_tableau

end module supratrans_avf_tableau
