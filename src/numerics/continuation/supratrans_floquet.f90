!> Floquet stability of a periodic state: the multipliers mu (eigenvalues of the monodromy matrix dP/dx of the
!> one-period map P, LAPACK `dgeev`), the largest |mu|, and how the state loses stability when a multiplier leaves
!> the unit circle: real through +1 (fold, saddle-node), real through -1 (period doubling), a complex pair (torus,
!> Neimark-Sacker).
!>
!> **The tolerance `crossing_tol`.** A state is called stable when every |mu| <= 1 + crossing_tol, and a multiplier
!> counts as having crossed only beyond that. In the undamped chain the multipliers of the modes trapped between the
!> drive and the absorber sit on the unit circle up to the absorber's small damping and roundoff (|mu| - 1 of order
!> 1e-12 .. 1e-8 in a conservative part of the spectrum); a crossing_tol well above that floor and well below the
!> growth rate of a real instability keeps the verdict from hinging on roundoff. The continuation reports the value
!> it used. On the test maps (test_continuation) the verdicts are the same for tolerances 1e-9 .. 1e-3, multipliers
!> exactly on the circle included. On a real chain they need not be: on the undamped sine-Gordon chain (N = 200,
!> c = 4, Omega = 0.9, the paper's absorber) a complex pair leaves the circle by at most ~6e-6 shortly before the
!> fold and comes back, so crossing_tol = 1e-6 reports a torus at A = 1.8266 and 1e-5 the fold at A = 1.8342 as
!> the first loss of stability: report such a loss with its size (`max_multiplier` along the branch).
module supratrans_floquet
    use supratrans_kinds, only: wp
    use supratrans_eigen, only: general_eigenvalues
    use supratrans_dense, only: complex_lu_factor, complex_lu_solve, lu_factor
    implicit none
    private

    public :: floquet_multipliers, largest_modulus, is_stable, leading_crossing, crossing_distance, crossing_name
    public :: nearest_multiplier, track_multiplier, flip_sign

    !> No multiplier beyond the unit circle (by more than crossing_tol).
    integer, parameter, public :: crossing_none = 0
    !> A real multiplier through +1: fold (saddle-node) of the periodic state.
    integer, parameter, public :: crossing_fold = 1
    !> A real multiplier through -1: period doubling.
    integer, parameter, public :: crossing_period_doubling = 2
    !> A complex pair through the unit circle: torus (Neimark-Sacker), a second frequency.
    integer, parameter, public :: crossing_torus = 3

contains

    !> The Floquet multipliers wr + i wi: the eigenvalues of the monodromy matrix (not modified; a copy is given to
    !> `dgeev`). `info` is LAPACK's status (0: success).
    pure subroutine floquet_multipliers(monodromy, wr, wi, info)
        !> Monodromy matrix dP/dx, d x d.
        real(wp), intent(in) :: monodromy(:, :)
        !> Real parts of the d multipliers.
        real(wp), allocatable, intent(out) :: wr(:)
        !> Imaginary parts of the d multipliers (a complex pair is listed as two entries, +wi and -wi).
        real(wp), allocatable, intent(out) :: wi(:)
        !> LAPACK status.
        integer, intent(out) :: info
        real(wp), allocatable :: a(:, :)

        a = monodromy
        allocate (wr(size(a, 1)), wi(size(a, 1)))
        call general_eigenvalues(a, wr, wi, info)
    end subroutine floquet_multipliers

    !> The sign of det(J + I) = prod (mu + 1) over the multipliers mu of J (a complex pair gives |mu + 1|^2 > 0): it
    !> changes exactly when an odd number of real multipliers pass through -1, which is how a branch meets a period
    !> doubling of its map without any eigenvalue computed (one LU, as costly as factorising the bordered system
    !> and a small part of a `dgeev`). 0 when J + I is singular.
    pure integer function flip_sign(monodromy)
        !> Monodromy matrix dP/dx, d x d.
        real(wp), intent(in) :: monodromy(:, :)
        real(wp), allocatable :: a(:, :)
        integer, allocatable :: ipiv(:)
        integer :: i, info

        a = monodromy
        do i = 1, size(a, 1)
            a(i, i) = a(i, i) + 1.0_wp
        end do
        allocate (ipiv(size(a, 1)))
        call lu_factor(a, ipiv, info)
        flip_sign = 0
        if (info /= 0) return
        flip_sign = 1
        do i = 1, size(a, 1)
            if (ipiv(i) /= i) flip_sign = -flip_sign
            if (a(i, i) < 0.0_wp) flip_sign = -flip_sign
        end do
    end function flip_sign

    !> The largest modulus of the multipliers, max |mu| (0 for an empty list).
    pure real(wp) function largest_modulus(wr, wi)
        !> Real parts.
        real(wp), intent(in) :: wr(:)
        !> Imaginary parts.
        real(wp), intent(in) :: wi(:)

        largest_modulus = 0.0_wp
        if (size(wr) > 0) largest_modulus = maxval(hypot(wr, wi))
    end function largest_modulus

    !> Stable in the sense of this module: every |mu| <= 1 + crossing_tol.
    pure logical function is_stable(wr, wi, crossing_tol)
        !> Real parts.
        real(wp), intent(in) :: wr(:)
        !> Imaginary parts.
        real(wp), intent(in) :: wi(:)
        !> How far beyond the unit circle a multiplier must be to count as a crossing.
        real(wp), intent(in) :: crossing_tol

        is_stable = largest_modulus(wr, wi) <= 1.0_wp + crossing_tol
    end function is_stable

    !> The kind of the leading instability: `crossing_none` when the state is stable (`is_stable`), else the class of
    !> the multiplier of largest modulus: complex (wi /= 0) `crossing_torus`, real positive `crossing_fold`, real
    !> negative `crossing_period_doubling`.
    pure integer function leading_crossing(wr, wi, crossing_tol)
        !> Real parts.
        real(wp), intent(in) :: wr(:)
        !> Imaginary parts.
        real(wp), intent(in) :: wi(:)
        !> How far beyond the unit circle a multiplier must be to count as a crossing.
        real(wp), intent(in) :: crossing_tol
        integer :: k

        leading_crossing = crossing_none
        if (is_stable(wr, wi, crossing_tol)) return
        k = maxloc(hypot(wr, wi), dim=1)
        leading_crossing = multiplier_class(wr(k), wi(k))
    end function leading_crossing

    !> max |mu| - 1 over the multipliers of one class (`crossing_fold`: real positive, `crossing_period_doubling`: real
    !> negative, `crossing_torus`: complex); -1 when the class is empty. Its zero along a branch is the crossing of
    !> that class; it is smooth there as long as the crossing multiplier stays in its class.
    pure real(wp) function crossing_distance(wr, wi, kind)
        !> Real parts.
        real(wp), intent(in) :: wr(:)
        !> Imaginary parts.
        real(wp), intent(in) :: wi(:)
        !> The class (`crossing_fold`, `crossing_period_doubling`, `crossing_torus`).
        integer, intent(in) :: kind
        integer :: k

        crossing_distance = -1.0_wp
        do k = 1, size(wr)
            if (multiplier_class(wr(k), wi(k)) == kind) then
                crossing_distance = max(crossing_distance, hypot(wr(k), wi(k)) - 1.0_wp)
            end if
        end do
    end function crossing_distance

    !> Index of the multiplier nearest to the real number `target` in the complex plane (+1 at a fold; 0 for an
    !> empty list). At a fold of the undamped chain the multiplier +1 can meet a trapped mode's multiplier near +1
    !> and the two come out of `dgeev` as a complex pair 1 +- i eps: the nearest one, real or not, is the fold's.
    pure integer function nearest_multiplier(wr, wi, target)
        !> Real parts.
        real(wp), intent(in) :: wr(:)
        !> Imaginary parts.
        real(wp), intent(in) :: wi(:)
        !> The value sought (+1 or -1).
        real(wp), intent(in) :: target

        nearest_multiplier = 0
        if (size(wr) > 0) nearest_multiplier = minloc(hypot(wr - target, wi), dim=1)
    end function nearest_multiplier

    !> One multiplier tracked by inverse iteration: the eigenvalue of the monodromy nearest the shift `mu` (a
    !> multiplier of a nearby branch point), from the LU of J - mu I (`zgetrf`) and the Rayleigh quotient of the
    !> iterate; `mu` and the unit eigenvector `v` (start: any vector, or the previous one) are updated. `ok` when the
    !> residual |J v - mu v| fell to `residual_tol` |J|_F within 8 iterations: mu is then an eigenvalue to that
    !> residual times its condition number. About a fifth of a `dgeev` of the same matrix (one complex LU).
    subroutine track_multiplier(monodromy, mu, v, ok, residual_tol)
        !> Monodromy matrix dP/dx, d x d.
        real(wp), intent(in) :: monodromy(:, :)
        !> Shift on entry, the tracked multiplier on exit.
        complex(wp), intent(inout) :: mu
        !> Start vector on entry (size d), the unit eigenvector on exit.
        complex(wp), intent(inout) :: v(:)
        !> Whether the iteration converged.
        logical, intent(out) :: ok
        !> Residual tolerance relative to the Frobenius norm of the monodromy.
        real(wp), intent(in) :: residual_tol
        complex(wp), allocatable :: a(:, :), w(:)
        integer, allocatable :: ipiv(:)
        real(wp) :: scale, res
        integer :: d, i, it, info

        ok = .false.
        d = size(monodromy, 1)
        allocate (a(d, d), w(d), ipiv(d))
        a = cmplx(monodromy, 0.0_wp, kind=wp)
        do i = 1, d
            a(i, i) = a(i, i) - mu
        end do
        call complex_lu_factor(a, ipiv, info)
        if (info /= 0) return
        scale = norm2(monodromy)
        if (.not. (norm2(abs(v)) > 0.0_wp)) return
        v = v/norm2(abs(v))
        do it = 1, 8
            call complex_lu_solve(a, ipiv, v, info)
            if (info /= 0) return
            v = v/norm2(abs(v))
            w = cmplx(matmul(monodromy, real(v, wp)), matmul(monodromy, aimag(v)), kind=wp)
            mu = dot_product(v, w)
            res = norm2(abs(w - mu*v))
            if (.not. (res == res)) return
            if (res <= residual_tol*scale) then
                ok = .true.
                return
            end if
        end do
    end subroutine track_multiplier

    !> The name of a crossing kind, as written into output files: "none", "fold", "period_doubling", "torus".
    pure function crossing_name(kind) result(name)
        !> The kind.
        integer, intent(in) :: kind
        character(len=:), allocatable :: name

        select case (kind)
        case (crossing_fold)
            name = "fold"
        case (crossing_period_doubling)
            name = "period_doubling"
        case (crossing_torus)
            name = "torus"
        case default
            name = "none"
        end select
    end function crossing_name

    !> The class of one multiplier: complex (wi /= 0; `dgeev` gives exactly zero for a real eigenvalue) torus,
    !> real >= 0 fold, real < 0 period doubling.
    pure integer function multiplier_class(wr, wi)
        real(wp), intent(in) :: wr, wi

        if (wi /= 0.0_wp) then
            multiplier_class = crossing_torus
        else if (wr >= 0.0_wp) then
            multiplier_class = crossing_fold
        else
            multiplier_class = crossing_period_doubling
        end if
    end function multiplier_class

end module supratrans_floquet
