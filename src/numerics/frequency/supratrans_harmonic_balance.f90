!> Harmonic balance of the driven chain (paper eq. (1)): the time-periodic state driven by u_0(t) = A sin(Omega t) as
!> Fourier coefficients per site, its residual and its exact Jacobian.
!>
!> Every potential has an odd V' and the drive changes sign over half a period, so the branch from rest keeps the
!> half-period symmetry u(t + T/2) = -u(t): only the odd harmonics w_j = (2j - 1) Omega, j = 1..K, appear,
!>
!>     u_n(t) = sum_j [a_{n,j} cos(w_j t) + b_{n,j} sin(w_j t)],    x = (a_{n,1}, b_{n,1}, ..., a_{n,K}, b_{n,K})_n,
!>
!> 2K unknowns per site, sites n = 1..N in order. The balance of harmonic w at site n, in complex form with
!> U = a - i b (u = Re(U e^{i w t})), is
!>
!>     (-w^2 + m^2 + i alpha_n w) U_n - (c^2 + i beta w)(U_{n+1} - 2 U_n + U_{n-1}) + F_n = 0,
!>
!> with U_0 = -i A at w = Omega (zero at the others), U_{N+1} = 0 (the paper's fixed end) or, with the radiation
!> closure, U_{N+1} = z_w U_N (`supratrans_radiation`), and F_n the coefficients of V'(u_n(t)). F is computed
!> pseudo-spectrally: u_n on a grid of `time_points` instants of the half period (enough, by the symmetry), V' there,
!> projected back; both transforms are products with a (time points x 2K) matrix of cosines and sines (BLAS). The
!> Jacobian is block-tridiagonal in n: the diagonal 2K x 2K block is the linear part per harmonic plus the Galerkin
!> matrix of V''(u_n(t)), (2 / mt) sum_m V''(u_n(t_m)) phi_p(t_m) phi_q(t_m), computed for all sites at once as one
!> product; the off-diagonal blocks are the coupling -(c^2 + i beta w), the same at every site, and diagonal in the
!> harmonics. The LU is block-tridiagonal (block Thomas): for n = 1..N, S_n = D_n - C S_{n-1}^{-1} C, each S_n
!> inverted by Gauss-Jordan elimination with partial pivoting (`invert_block`; by LAPACK from K = 16 on), about
!> 21 K^3 N flops; C, 2 x 2 per
!> harmonic, costs nothing, and a solve is two products with small blocks per site. LAPACK's banded LU (`dgbtrf`,
!> kl = ku = 2K + 1) does the same work column by column through rank-one updates of 2K + 1 entries, and LAPACK's
!> `dgetrf`/`dgetri` on blocks of 8 .. 32 rows pay a library call's overhead per site that exceeds the block's
!> arithmetic: both measured several times slower at K = 4-16 (docs/continuation_reference.md).
!>
!> Every work array is allocated once by `hb_init`; nothing here keeps state between calls but the last Jacobian and
!> its factors. One object per thread.
module supratrans_harmonic_balance
    use supratrans_kinds, only: wp, pi
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_strings, only: int_str
    use supratrans_config, only: chain_params, closure_absorber, closure_radiation
    use supratrans_chain, only: damping_profile
    use supratrans_potential, only: potential_type, new_potential
    use supratrans_chain, only: gap_squared
    use supratrans_blas, only: matrix_product
    use supratrans_dense, only: invert
    use supratrans_radiation, only: radiation_root
    implicit none
    private

    public :: hb_init, hb_residual, hb_jacobian, hb_factor, hb_solve, hb_apply_jacobian, hb_amplitude_column
    public :: hb_time_state, hb_measures, hb_spectrum, hb_size, hb_pad

    !> Blocks of at least this many rows (K >= 16) are inverted by LAPACK (`dgetrf`, `dgetri`), whose blocked kernels
    !> then outweigh a call's overhead; smaller ones in place (`invert_block`).
    integer, parameter :: lapack_block = 32

    !> The harmonic-balance system of one chain at one driving frequency and number of harmonics.
    type, public :: hb_system
        !> Oscillators N.
        integer :: n = 0
        !> Odd harmonics K (frequencies (2j - 1) Omega, j = 1..K).
        integer :: k = 0
        !> Instants of the half period on which V' and V'' are evaluated.
        integer :: mt = 0
        !> Unknowns 2 K N.
        integer :: dim = 0
        !> Driving frequency Omega.
        real(wp) :: omega = 0.0_wp
        !> Closure at site N (`closure_absorber`: u_{N+1} = 0; `closure_radiation`), numbers of `supratrans_config`.
        integer :: closure = closure_absorber
        !> Chain parameters.
        type(chain_params) :: chain
        !> On-site potential V of the chain.
        class(potential_type), allocatable :: potential
        !> Frequencies w_j = (2j - 1) Omega.
        real(wp), allocatable :: w(:)
        !> Site damping alpha_n = gamma + gamma'(n).
        real(wp), allocatable :: alpha(:)
        !> Radiation root z_j per harmonic (closure_radiation).
        complex(wp), allocatable :: z(:)
        !> cos(w_j t_m), sin(w_j t_m) in columns 2j - 1, 2j, (mt, 2K); their time derivatives; the projection 2/mt basis.
        real(wp), allocatable :: basis(:, :), dbasis(:, :), proj(:, :)
        !> Products (2/mt) phi_p(t_m) phi_q(t_m), (mt, (2K)^2): the Galerkin matrices of V'' for all sites at once.
        real(wp), allocatable :: phi2(:, :)
        !> Work: u_n(t_m), V'(u) or V''(u) there, (mt, N); the nonlinear coefficients (2K, N).
        real(wp), allocatable :: ut(:, :), ft(:, :), fc(:, :)
        !> The last Jacobian's diagonal blocks (2K, 2K, N) and its constant off-diagonal 2 x 2 blocks per harmonic.
        real(wp), allocatable :: diag(:, :, :), offd(:, :, :)
        !> The block LU of the last Jacobian: S_n^{-1}, (2K, 2K, N).
        real(wp), allocatable :: sinv(:, :, :)
        !> S_n^{-1} C, (2K, 2K, N): the back substitution's multipliers.
        real(wp), allocatable :: sc(:, :, :)
        !> J^{-1} dR/dA with the current factors (kept by the caller's bordered solves; reset by `hb_factor`).
        real(wp), allocatable :: ja(:)
        !> Whether `ja` belongs to the current factors.
        logical :: ja_ready = .false.
    end type hb_system

contains

    !> Unknowns 2 K N of a system.
    pure integer function hb_size(sys)
        !> The system.
        type(hb_system), intent(in) :: sys

        hb_size = sys%dim
    end function hb_size

    !> Set up the system of `chain` driven at `omega` with `harmonics` odd harmonics and `time_points` instants of the
    !> half period (0: 3K + 1, enough that the Galerkin products of the truncated series are exact up to the
    !> harmonics kept for a cubic nonlinearity).
    subroutine hb_init(sys, chain, omega, harmonics, closure, error, time_points)
        !> The system, (re)allocated.
        type(hb_system), intent(out) :: sys
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        !> Driving frequency Omega > 0.
        real(wp), intent(in) :: omega
        !> Odd harmonics K >= 1.
        integer, intent(in) :: harmonics
        !> `closure_absorber` (u_{N+1} = 0) or `closure_radiation` (`supratrans_config`).
        integer, intent(in) :: closure
        !> Error, allocated for a bad size or frequency.
        type(error_type), allocatable, intent(out) :: error
        !> Instants of the half period (default 3K + 1).
        integer, intent(in), optional :: time_points
        integer :: j, m, p, q, k2
        real(wp) :: t, w

        if (harmonics < 1 .or. chain%n < 1 .or. .not. omega > 0.0_wp) then
            call fatal_error(error, "harmonic balance: K = " // int_str(harmonics) // ", N = " // int_str(chain%n) &
                             // " and Omega > 0 are needed", err_input)
            return
        end if
        sys%n = chain%n
        sys%k = harmonics
        sys%mt = 3*harmonics + 1
        if (present(time_points)) then
            if (time_points > 0) sys%mt = max(time_points, 2*harmonics)
        end if
        k2 = 2*harmonics
        sys%dim = k2*chain%n
        sys%omega = omega
        sys%closure = closure
        sys%chain = chain
        call new_potential(chain, sys%potential)
        sys%w = [(real(2*j - 1, wp)*omega, j=1, harmonics)]
        sys%alpha = damping_profile(chain)
        allocate (sys%basis(sys%mt, k2), sys%dbasis(sys%mt, k2))
        do m = 1, sys%mt
            t = real(m - 1, wp)*pi/(omega*real(sys%mt, wp))     ! t_m = (m - 1) (T/2) / mt
            do j = 1, harmonics
                w = sys%w(j)
                sys%basis(m, 2*j - 1) = cos(w*t)
                sys%basis(m, 2*j) = sin(w*t)
                sys%dbasis(m, 2*j - 1) = -w*sin(w*t)
                sys%dbasis(m, 2*j) = w*cos(w*t)
            end do
        end do
        sys%proj = (2.0_wp/real(sys%mt, wp))*sys%basis
        allocate (sys%phi2(sys%mt, k2*k2))
        do q = 1, k2
            do p = 1, k2
                sys%phi2(:, p + (q - 1)*k2) = sys%proj(:, p)*sys%basis(:, q)
            end do
        end do
        allocate (sys%ut(sys%mt, sys%n), sys%ft(sys%mt, sys%n), sys%fc(k2, sys%n))
        allocate (sys%diag(k2, k2, sys%n), sys%offd(2, 2, harmonics))
        do j = 1, harmonics      ! -(c^2 + i beta w) as a real 2 x 2 block acting on (a, b)
            sys%offd(:, :, j) = complex_block(cmplx(-chain%c**2, -chain%beta*sys%w(j), wp))
        end do
        allocate (sys%z(harmonics))
        sys%z = (0.0_wp, 0.0_wp)
        if (closure == closure_radiation) then
            do j = 1, harmonics
                sys%z(j) = radiation_root(sys%w(j), chain%c, chain%beta, sys%alpha(sys%n), &
                                          gap_squared(chain))
            end do
        end if
        allocate (sys%sinv(k2, k2, sys%n), sys%sc(k2, k2, sys%n), sys%ja(sys%dim))
    end subroutine hb_init

    !> The real 2 x 2 matrix of the multiplication by the complex q on (a, b), U = a - i b.
    pure function complex_block(q) result(b)
        !> The complex factor.
        complex(wp), intent(in) :: q
        real(wp) :: b(2, 2)

        b(1, 1) = real(q, wp)
        b(1, 2) = aimag(q)
        b(2, 1) = -aimag(q)
        b(2, 2) = real(q, wp)
    end function complex_block

    !> u_n(t_m) on the half-period grid from the coefficients (`sys%ut`).
    subroutine synthesize(sys, x)
        !> The system.
        type(hb_system), intent(inout) :: sys
        !> Coefficients, size 2 K N.
        real(wp), intent(in), target, contiguous :: x(:)
        real(wp), pointer, contiguous :: xc(:, :)

        xc(1:2*sys%k, 1:sys%n) => x
        call matrix_product(sys%basis, xc, sys%ut)
    end subroutine synthesize

    !> The residual R(x; A) of the balance of every harmonic at every site (size 2 K N).
    subroutine hb_residual(sys, x, amplitude, r)
        !> The system.
        type(hb_system), intent(inout) :: sys
        !> Coefficients.
        real(wp), intent(in), contiguous :: x(:)
        !> Drive amplitude A.
        real(wp), intent(in) :: amplitude
        !> Residual, size 2 K N.
        real(wp), intent(out), contiguous :: r(:)
        integer :: n, j, i, k2
        real(wp) :: lin(2, 2), xl(2), xr(2)

        k2 = 2*sys%k
        call synthesize(sys, x)
        do n = 1, sys%n
            call sys%potential%dv_each(sys%ut(:, n), sys%ft(:, n))
        end do
        call matrix_product(sys%proj, sys%ft, sys%fc, transpose_a=.true.)
        do n = 1, sys%n
            do j = 1, sys%k
                i = (n - 1)*k2 + 2*j - 1
                lin = diagonal_linear(sys, n, j)
                r(i:i + 1) = matmul(lin, x(i:i + 1)) + sys%fc(2*j - 1:2*j, n)
                if (n > 1) then
                    xl = x(i - k2:i - k2 + 1)
                else if (j == 1) then
                    xl = [0.0_wp, amplitude]             ! u_0 = A sin(Omega t)
                else
                    xl = 0.0_wp
                end if
                xr = 0.0_wp
                if (n < sys%n) xr = x(i + k2:i + k2 + 1)
                r(i:i + 1) = r(i:i + 1) + matmul(sys%offd(:, :, j), xl + xr)
            end do
        end do
    end subroutine hb_residual

    !> The linear part of the diagonal block of site n, harmonic j (the closure's term included at n = N).
    pure function diagonal_linear(sys, n, j) result(b)
        !> The system.
        type(hb_system), intent(in) :: sys
        !> Site.
        integer, intent(in) :: n
        !> Harmonic.
        integer, intent(in) :: j
        real(wp) :: b(2, 2)
        complex(wp) :: q, coupling
        real(wp) :: w

        w = sys%w(j)
        coupling = cmplx(sys%chain%c**2, sys%chain%beta*w, wp)
        q = cmplx(-w*w + sys%chain%m2, sys%alpha(n)*w, wp) + 2.0_wp*coupling
        if (n == sys%n .and. sys%closure == closure_radiation) q = q - coupling*sys%z(j)
        b = complex_block(q)
    end function diagonal_linear

    !> The Jacobian dR/dx at x (its diagonal blocks in `sys%diag`; the off-diagonal ones are constant).
    subroutine hb_jacobian(sys, x)
        !> The system.
        type(hb_system), intent(inout) :: sys
        !> Coefficients.
        real(wp), intent(in), contiguous :: x(:)
        integer :: n, j, k2

        k2 = 2*sys%k
        call synthesize(sys, x)
        do n = 1, sys%n
            call sys%potential%d2v_each(sys%ut(:, n), sys%ft(:, n))
        end do
        call galerkin_blocks(sys)
        do n = 1, sys%n
            do j = 1, sys%k
                sys%diag(2*j - 1:2*j, 2*j - 1:2*j, n) = sys%diag(2*j - 1:2*j, 2*j - 1:2*j, n) + diagonal_linear(sys, n, j)
            end do
        end do
    end subroutine hb_jacobian

    !> The Galerkin matrices of V''(u_n(t)) of every site into `sys%diag`: one product phi2^T V''.
    subroutine galerkin_blocks(sys)
        !> The system (`ft` holds V'' on the grid).
        type(hb_system), intent(inout), target :: sys
        real(wp), pointer, contiguous :: d(:, :)

        d(1:(2*sys%k)**2, 1:sys%n) => sys%diag
        call matrix_product(sys%phi2, sys%ft, d, transpose_a=.true.)
    end subroutine galerkin_blocks

    !> dR/dA: the drive enters the balance of the first harmonic at site 1 through the coupling.
    pure subroutine hb_amplitude_column(sys, da)
        !> The system.
        type(hb_system), intent(in) :: sys
        !> dR/dA, size 2 K N.
        real(wp), intent(out) :: da(:)

        da = 0.0_wp
        da(1:2) = matmul(sys%offd(:, :, 1), [0.0_wp, 1.0_wp])
    end subroutine hb_amplitude_column

    !> J v with the last Jacobian's blocks.
    pure subroutine hb_apply_jacobian(sys, v, jv)
        !> The system (after `hb_jacobian`).
        type(hb_system), intent(in) :: sys
        !> Vector, size 2 K N.
        real(wp), intent(in) :: v(:)
        !> J v.
        real(wp), intent(out) :: jv(:)
        integer :: n, j, i0, i, k2

        k2 = 2*sys%k
        do n = 1, sys%n
            i0 = (n - 1)*k2
            jv(i0 + 1:i0 + k2) = matmul(sys%diag(:, :, n), v(i0 + 1:i0 + k2))
            do j = 1, sys%k
                i = i0 + 2*j - 1
                if (n > 1) jv(i:i + 1) = jv(i:i + 1) + matmul(sys%offd(:, :, j), v(i - k2:i - k2 + 1))
                if (n < sys%n) jv(i:i + 1) = jv(i:i + 1) + matmul(sys%offd(:, :, j), v(i + k2:i + k2 + 1))
            end do
        end do
    end subroutine hb_apply_jacobian

    !> Factor the last Jacobian by block elimination: S_1 = D_1, S_n = D_n - C S_{n-1}^{-1} C, each S_n inverted by
    !> LAPACK; `info` > 0 when one is singular.
    subroutine hb_factor(sys, info)
        !> The system (after `hb_jacobian`).
        type(hb_system), intent(inout) :: sys
        !> LAPACK status of the first failing block (0: all factored).
        integer, intent(out) :: info
        integer :: n, j, q

        do n = 1, sys%n
            sys%sinv(:, :, n) = sys%diag(:, :, n)
            if (n > 1) then          ! - C (S_{n-1}^{-1} C): C acts on the rows of each harmonic's pair
                do j = 1, sys%k
                    do q = 1, 2*sys%k
                        sys%sinv(2*j - 1, q, n) = sys%sinv(2*j - 1, q, n) - sys%offd(1, 1, j)*sys%sc(2*j - 1, q, n - 1) &
                                                  - sys%offd(1, 2, j)*sys%sc(2*j, q, n - 1)
                        sys%sinv(2*j, q, n) = sys%sinv(2*j, q, n) - sys%offd(2, 1, j)*sys%sc(2*j - 1, q, n - 1) &
                                              - sys%offd(2, 2, j)*sys%sc(2*j, q, n - 1)
                    end do
                end do
            end if
            if (2*sys%k < lapack_block) then
                call invert_block(sys%sinv(:, :, n), info)
            else
                call invert(sys%sinv(:, :, n), info)
            end if
            if (info /= 0) then
                info = n
                return
            end if
            do j = 1, sys%k          ! S_n^{-1} C: C is block-diagonal, so a pair of columns at a time
                sys%sc(:, 2*j - 1, n) = sys%sinv(:, 2*j - 1, n)*sys%offd(1, 1, j) + sys%sinv(:, 2*j, n)*sys%offd(2, 1, j)
                sys%sc(:, 2*j, n) = sys%sinv(:, 2*j - 1, n)*sys%offd(1, 2, j) + sys%sinv(:, 2*j, n)*sys%offd(2, 2, j)
            end do
        end do
        sys%ja_ready = .false.
    end subroutine hb_factor

    !> The inverse of a small square matrix in place, by Gauss-Jordan elimination with partial pivoting; `info` = 1
    !> when a pivot is exactly zero (singular), else 0.
    pure subroutine invert_block(a, info)
        !> The matrix; its inverse on exit.
        real(wp), intent(inout) :: a(:, :)
        !> 0, or 1 when singular.
        integer, intent(out) :: info
        integer :: m, i, p, piv(size(a, 1)), t
        real(wp) :: row(size(a, 2)), pivot, f

        m = size(a, 1)
        piv = [(i, i=1, m)]
        info = 0
        do i = 1, m
            p = i - 1 + maxloc(abs(a(i:m, i)), 1)
            if (a(p, i) == 0.0_wp) then
                info = 1
                return
            end if
            if (p /= i) then
                row = a(i, :)
                a(i, :) = a(p, :)
                a(p, :) = row
                t = piv(i)
                piv(i) = piv(p)
                piv(p) = t
            end if
            pivot = 1.0_wp/a(i, i)
            a(i, i) = 1.0_wp
            a(i, :) = a(i, :)*pivot
            do p = 1, m
                if (p == i) cycle
                f = a(p, i)
                a(p, i) = 0.0_wp
                a(p, :) = a(p, :) - f*a(i, :)
            end do
        end do
        row = 0.0_wp
        do i = 1, m                  ! undo the row exchanges as column exchanges of the inverse
            do while (piv(i) /= i)
                t = piv(i)
                row(1:m) = a(:, i)
                a(:, i) = a(:, t)
                a(:, t) = row(1:m)
                piv(i) = piv(t)
                piv(t) = t
            end do
        end do
    end subroutine invert_block

    !> Solve J X = B with the factors of `hb_factor` (B, (2 K N, nrhs), overwritten): forward y_n = S_n^{-1} (b_n -
    !> C y_{n-1}), back x_n = y_n - (S_n^{-1} C) x_{n+1}.
    pure subroutine hb_solve(sys, b, info)
        !> The system (after `hb_factor`).
        type(hb_system), intent(in) :: sys
        !> Right-hand sides, solutions on exit.
        real(wp), intent(inout), contiguous :: b(:, :)
        !> Status (always 0: the blocks were inverted by `hb_factor`).
        integer, intent(out) :: info
        integer :: n, j, i0, k2, r
        real(wp) :: y(2*sys%k)

        k2 = 2*sys%k
        info = 0
        do r = 1, size(b, 2)
            do n = 1, sys%n
                i0 = (n - 1)*k2
                y = b(i0 + 1:i0 + k2, r)
                if (n > 1) then
                    do j = 1, sys%k
                        y(2*j - 1:2*j) = y(2*j - 1:2*j) - matmul(sys%offd(:, :, j), b(i0 - k2 + 2*j - 1:i0 - k2 + 2*j, r))
                    end do
                end if
                b(i0 + 1:i0 + k2, r) = matmul(sys%sinv(:, :, n), y)
            end do
            do n = sys%n - 1, 1, -1
                i0 = (n - 1)*k2
                b(i0 + 1:i0 + k2, r) = b(i0 + 1:i0 + k2, r) - matmul(sys%sc(:, :, n), b(i0 + k2 + 1:i0 + 2*k2, r))
            end do
        end do
    end subroutine hb_solve

    !> u_n(t) and u_n'(t) of every site at time t (the state for the time domain: the ODE from this state returns to
    !> it after a period).
    pure subroutine hb_time_state(sys, x, t, u, ut)
        !> The system.
        type(hb_system), intent(in) :: sys
        !> Coefficients.
        real(wp), intent(in) :: x(:)
        !> Time.
        real(wp), intent(in) :: t
        !> u_n(t), size N.
        real(wp), intent(out) :: u(:)
        !> u_n'(t), size N.
        real(wp), intent(out) :: ut(:)
        integer :: n, j, i

        u = 0.0_wp
        ut = 0.0_wp
        do n = 1, sys%n
            do j = 1, sys%k
                i = (n - 1)*2*sys%k + 2*j - 1
                u(n) = u(n) + x(i)*cos(sys%w(j)*t) + x(i + 1)*sin(sys%w(j)*t)
                ut(n) = ut(n) + sys%w(j)*(-x(i)*sin(sys%w(j)*t) + x(i + 1)*cos(sys%w(j)*t))
            end do
        end do
    end subroutine hb_time_state

    !> max |u_n(t)| over the sites and the grid of the half period (|u| is the same on the other half), and the
    !> stored energy averaged over the period: sum_n [u_n'^2/2 + m^2 u_n^2/2 + V(u_n)] + c^2/2 sum_{n=0}^{N}
    !> (u_{n+1} - u_n)^2, u_0 the drive and u_{N+1} = 0.
    subroutine hb_measures(sys, x, amplitude, umax, energy)
        !> The system.
        type(hb_system), intent(inout) :: sys
        !> Coefficients.
        real(wp), intent(in), contiguous :: x(:)
        !> Drive amplitude A.
        real(wp), intent(in) :: amplitude
        !> max |u_n(t)|.
        real(wp), intent(out) :: umax
        !> Mean stored energy.
        real(wp), intent(out) :: energy
        real(wp), allocatable :: v(:, :), vt(:, :)
        real(wp), pointer, contiguous :: xc(:, :)
        real(wp), target :: copy(size(x))
        integer :: n

        call synthesize(sys, x)
        umax = maxval(abs(sys%ut))
        copy = x
        xc(1:2*sys%k, 1:sys%n) => copy
        allocate (v(sys%mt, sys%n), vt(sys%mt, sys%n))
        call matrix_product(sys%dbasis, xc, v)
        do n = 1, sys%n
            call sys%potential%v_each(sys%ut(:, n), vt(:, n))
        end do
        energy = sum(0.5_wp*v**2 + 0.5_wp*sys%chain%m2*sys%ut**2 + vt)
        energy = energy + 0.5_wp*sys%chain%c**2*sum((sys%ut(:, 1) - amplitude*sys%basis(:, 2))**2)
        do n = 1, sys%n - 1
            energy = energy + 0.5_wp*sys%chain%c**2*sum((sys%ut(:, n + 1) - sys%ut(:, n))**2)
        end do
        energy = energy + 0.5_wp*sys%chain%c**2*sum(sys%ut(:, sys%n)**2)
        energy = energy/real(sys%mt, wp)
    end subroutine hb_measures

    !> Amplitude sqrt(a^2 + b^2) of each harmonic at each site, (K, N): the state's spectrum.
    pure subroutine hb_spectrum(sys, x, amp)
        !> The system.
        type(hb_system), intent(in) :: sys
        !> Coefficients.
        real(wp), intent(in) :: x(:)
        !> Amplitudes, (K, N).
        real(wp), intent(out) :: amp(:, :)
        integer :: n, j, i

        do n = 1, sys%n
            do j = 1, sys%k
                i = (n - 1)*2*sys%k + 2*j - 1
                amp(j, n) = hypot(x(i), x(i + 1))
            end do
        end do
    end subroutine hb_spectrum

    !> The coefficients of K_from harmonics as those of K_to (zeros added, or the highest dropped).
    pure function hb_pad(x, n, k_from, k_to) result(y)
        !> Coefficients, size 2 k_from n.
        real(wp), intent(in) :: x(:)
        !> Sites.
        integer, intent(in) :: n
        !> Harmonics of x.
        integer, intent(in) :: k_from
        !> Harmonics of the result.
        integer, intent(in) :: k_to
        real(wp) :: y(2*k_to*n)
        integer :: s, kc

        y = 0.0_wp
        kc = min(k_from, k_to)
        do s = 1, n
            y((s - 1)*2*k_to + 1:(s - 1)*2*k_to + 2*kc) = x((s - 1)*2*k_from + 1:(s - 1)*2*k_from + 2*kc)
        end do
    end function hb_pad

end module supratrans_harmonic_balance
