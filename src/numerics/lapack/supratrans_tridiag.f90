!> Thin typed wrappers over LAPACK's tridiagonal solvers, with explicit interfaces: `dgtsv` (factor and solve in one
!> call, one right-hand side) and `dgttrf` / `dgttrs` (factor once, then solve for many right-hand sides at once:
!> the tangent equations of the one-period map, `supratrans_period_map`). With `supratrans_eigen` (`dgeev`) this
!> folder holds every LAPACK routine the code calls.
module supratrans_tridiag
    use supratrans_kinds, only: wp
    implicit none
    private

    public :: solve_tridiag, factor_tridiag, solve_factored_tridiag

    interface
        !> LAPACK: solve A X = B for a general tridiagonal A (Gaussian elimination with partial pivoting).
        pure subroutine dgtsv(n, nrhs, dl, d, du, b, ldb, info)
            import :: wp
            integer, intent(in) :: n, nrhs, ldb
            real(wp), intent(inout) :: dl(*), d(*), du(*), b(ldb, *)
            integer, intent(out) :: info
        end subroutine dgtsv

        !> LAPACK: LU factorization of a general tridiagonal matrix with partial pivoting (row interchanges).
        pure subroutine dgttrf(n, dl, d, du, du2, ipiv, info)
            import :: wp
            integer, intent(in) :: n
            real(wp), intent(inout) :: dl(*), d(*), du(*)
            real(wp), intent(out) :: du2(*)
            integer, intent(out) :: ipiv(*), info
        end subroutine dgttrf

        !> LAPACK: solve A X = B (trans = 'N') with the factorization of `dgttrf`.
        pure subroutine dgttrs(trans, n, nrhs, dl, d, du, du2, ipiv, b, ldb, info)
            import :: wp
            character(len=1), intent(in) :: trans
            integer, intent(in) :: n, nrhs, ldb
            real(wp), intent(in) :: dl(*), d(*), du(*), du2(*)
            integer, intent(in) :: ipiv(*)
            real(wp), intent(inout) :: b(ldb, *)
            integer, intent(out) :: info
        end subroutine dgttrs
    end interface

contains

    !> Solve the tridiagonal system with sub-diagonal `dl`, diagonal `d`, super-diagonal `du` for one right-hand
    !> side `b`, overwritten by the solution. `dl`, `d`, `du` are destroyed (LAPACK's factors).
    !> `info` = 0 on success, i > 0 when the pivot U(i,i) is exactly zero (singular).
    pure subroutine solve_tridiag(dl, d, du, b, info)
        !> Sub-diagonal, size n - 1 (overwritten).
        real(wp), intent(inout) :: dl(:)
        !> Diagonal, size n (overwritten).
        real(wp), intent(inout) :: d(:)
        !> Super-diagonal, size n - 1 (overwritten).
        real(wp), intent(inout) :: du(:)
        !> Right-hand side on entry, solution on exit, size n.
        real(wp), intent(inout) :: b(:)
        !> LAPACK status.
        integer, intent(out) :: info

        call dgtsv(size(d), 1, dl, d, du, b, size(b), info)
    end subroutine solve_tridiag

    !> LU factorization (`dgttrf`) of the tridiagonal matrix with sub-diagonal `dl`, diagonal `d`, super-diagonal
    !> `du`, which are overwritten by the factors; `du2` (size n - 2) and `ipiv` (size n) receive the rest of them.
    !> `info` = 0 on success, i > 0 when U(i,i) is exactly zero (singular; the factors are still complete).
    pure subroutine factor_tridiag(dl, d, du, du2, ipiv, info)
        !> Sub-diagonal, size n - 1 (overwritten: the multipliers of L).
        real(wp), intent(inout) :: dl(:)
        !> Diagonal, size n (overwritten: the diagonal of U).
        real(wp), intent(inout) :: d(:)
        !> Super-diagonal, size n - 1 (overwritten: the first super-diagonal of U).
        real(wp), intent(inout) :: du(:)
        !> The second super-diagonal of U, size max(n - 2, 1).
        real(wp), intent(out) :: du2(:)
        !> Pivot indices, size n.
        integer, intent(out) :: ipiv(:)
        !> LAPACK status.
        integer, intent(out) :: info

        call dgttrf(size(d), dl, d, du, du2, ipiv, info)
    end subroutine factor_tridiag

    !> Solve A X = B with the factors of `factor_tridiag`, for all the columns of `b` at once (`dgttrs`); `b` is
    !> overwritten by X. `info` = 0 on success (< 0: an argument was illegal).
    pure subroutine solve_factored_tridiag(dl, d, du, du2, ipiv, b, info)
        !> Factors from `factor_tridiag`.
        real(wp), intent(in) :: dl(:), d(:), du(:), du2(:)
        !> Pivot indices from `factor_tridiag`.
        integer, intent(in) :: ipiv(:)
        !> Right-hand sides on entry, solutions on exit, n x nrhs (contiguous, so that no copy is made).
        real(wp), intent(inout), contiguous :: b(:, :)
        !> LAPACK status.
        integer, intent(out) :: info

        call dgttrs("N", size(d), size(b, 2), dl, d, du, du2, ipiv, b, max(1, size(b, 1)), info)
    end subroutine solve_factored_tridiag

end module supratrans_tridiag
