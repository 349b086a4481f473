!> Thin typed wrappers over LAPACK's dense LU (`dgetrf`, `dgetrs`, `dgesv`; complex `zgetrf`, `zgetrs`), with
!> explicit interfaces: the Newton systems of the shooting method, the bordered systems of the continuation in the
!> drive amplitude A, and the shifted monodromy of the inverse iteration that tracks one Floquet multiplier.
!> With `supratrans_tridiag` (`dgtsv`) and `supratrans_eigen` (`dgeev`) this folder holds every LAPACK routine the
!> code calls.
module supratrans_dense
    use supratrans_kinds, only: wp
    implicit none
    private

    public :: lu_factor, lu_solve, dense_solve, complex_lu_factor, complex_lu_solve, invert

    !> Solve with the LU factors of `lu_factor`, for one right-hand side (a vector) or several (a matrix).
    interface lu_solve
        module procedure lu_solve_vector, lu_solve_matrix
    end interface lu_solve

    interface
        !> LAPACK: LU factorisation with partial pivoting of a general matrix.
        pure subroutine dgetrf(m, n, a, lda, ipiv, info)
            import :: wp
            integer, intent(in) :: m, n, lda
            real(wp), intent(inout) :: a(lda, *)
            integer, intent(out) :: ipiv(*), info
        end subroutine dgetrf

        !> LAPACK: solve A X = B with the LU factors of `dgetrf`.
        pure subroutine dgetrs(trans, n, nrhs, a, lda, ipiv, b, ldb, info)
            import :: wp
            character(len=1), intent(in) :: trans
            integer, intent(in) :: n, nrhs, lda, ldb
            real(wp), intent(in) :: a(lda, *)
            integer, intent(in) :: ipiv(*)
            real(wp), intent(inout) :: b(ldb, *)
            integer, intent(out) :: info
        end subroutine dgetrs

        !> LAPACK: LU factorisation with partial pivoting of a general complex matrix.
        pure subroutine zgetrf(m, n, a, lda, ipiv, info)
            import :: wp
            integer, intent(in) :: m, n, lda
            complex(wp), intent(inout) :: a(lda, *)
            integer, intent(out) :: ipiv(*), info
        end subroutine zgetrf

        !> LAPACK: solve A X = B with the complex LU factors of `zgetrf`.
        pure subroutine zgetrs(trans, n, nrhs, a, lda, ipiv, b, ldb, info)
            import :: wp
            character(len=1), intent(in) :: trans
            integer, intent(in) :: n, nrhs, lda, ldb
            complex(wp), intent(in) :: a(lda, *)
            integer, intent(in) :: ipiv(*)
            complex(wp), intent(inout) :: b(ldb, *)
            integer, intent(out) :: info
        end subroutine zgetrs

        !> LAPACK: the inverse of a matrix from its LU factors (`dgetrf`).
        pure subroutine dgetri(n, a, lda, ipiv, work, lwork, info)
            import :: wp
            integer, intent(in) :: n, lda, lwork
            real(wp), intent(inout) :: a(lda, *)
            integer, intent(in) :: ipiv(*)
            real(wp), intent(out) :: work(*)
            integer, intent(out) :: info
        end subroutine dgetri

        !> LAPACK: solve A X = B by LU with partial pivoting (factorisation and solve in one call).
        pure subroutine dgesv(n, nrhs, a, lda, ipiv, b, ldb, info)
            import :: wp
            integer, intent(in) :: n, nrhs, lda, ldb
            real(wp), intent(inout) :: a(lda, *)
            integer, intent(out) :: ipiv(*)
            real(wp), intent(inout) :: b(ldb, *)
            integer, intent(out) :: info
        end subroutine dgesv
    end interface

contains

    !> LU factorisation with partial pivoting of the square matrix `a` (overwritten by its factors).
    !> `info` = 0 on success, i > 0 when U(i,i) is exactly zero (singular; the factors are still complete).
    pure subroutine lu_factor(a, ipiv, info)
        !> The matrix, n x n; its L and U factors on exit.
        real(wp), intent(inout) :: a(:, :)
        !> Pivot indices, size n.
        integer, intent(out) :: ipiv(:)
        !> LAPACK status.
        integer, intent(out) :: info

        call dgetrf(size(a, 1), size(a, 2), a, size(a, 1), ipiv, info)
    end subroutine lu_factor

    !> The inverse of the square matrix `a` in place (LU with partial pivoting, `dgetrf` and `dgetri`): the small
    !> diagonal blocks of a block-tridiagonal elimination, applied afterwards by matrix products. `info` > 0 when
    !> singular.
    pure subroutine invert(a, info)
        !> The matrix, n x n; its inverse on exit.
        real(wp), intent(inout) :: a(:, :)
        !> LAPACK status.
        integer, intent(out) :: info
        integer :: ipiv(size(a, 1))
        real(wp) :: work(64*size(a, 1))

        call dgetrf(size(a, 1), size(a, 2), a, size(a, 1), ipiv, info)
        if (info /= 0) return
        call dgetri(size(a, 1), a, size(a, 1), ipiv, work, size(work), info)
    end subroutine invert

    !> Solve A x = b (or A^T x = b with `transposed`: a left null vector's system) with the factors of `lu_factor`;
    !> `b` is overwritten by x.
    pure subroutine lu_solve_vector(lu, ipiv, b, info, transposed)
        !> LU factors from `lu_factor`, n x n.
        real(wp), intent(in) :: lu(:, :)
        !> Pivot indices from `lu_factor`.
        integer, intent(in) :: ipiv(:)
        !> Right-hand side on entry, solution on exit, size n.
        real(wp), intent(inout) :: b(:)
        !> LAPACK status.
        integer, intent(out) :: info
        !> Solve with A^T instead (default false).
        logical, intent(in), optional :: transposed
        character(len=1) :: trans

        trans = "N"
        if (present(transposed)) then
            if (transposed) trans = "T"
        end if
        call dgetrs(trans, size(lu, 1), 1, lu, size(lu, 1), ipiv, b, size(b), info)
    end subroutine lu_solve_vector

    !> Solve A X = B with the factors of `lu_factor`; `b` (n x nrhs) is overwritten by X.
    pure subroutine lu_solve_matrix(lu, ipiv, b, info)
        !> LU factors from `lu_factor`, n x n.
        real(wp), intent(in) :: lu(:, :)
        !> Pivot indices from `lu_factor`.
        integer, intent(in) :: ipiv(:)
        !> Right-hand sides on entry, solutions on exit, n x nrhs.
        real(wp), intent(inout) :: b(:, :)
        !> LAPACK status.
        integer, intent(out) :: info

        call dgetrs("N", size(lu, 1), size(b, 2), lu, size(lu, 1), ipiv, b, size(b, 1), info)
    end subroutine lu_solve_matrix

    !> Complex LU factorisation with partial pivoting (`zgetrf`) of the square matrix `a` (overwritten by its factors):
    !> the shifted monodromy J - sigma I of the inverse iteration that tracks one Floquet multiplier.
    pure subroutine complex_lu_factor(a, ipiv, info)
        !> The matrix, n x n; its L and U factors on exit.
        complex(wp), intent(inout) :: a(:, :)
        !> Pivot indices, size n.
        integer, intent(out) :: ipiv(:)
        !> LAPACK status (> 0: exactly singular).
        integer, intent(out) :: info

        call zgetrf(size(a, 1), size(a, 2), a, size(a, 1), ipiv, info)
    end subroutine complex_lu_factor

    !> Solve A x = b with the factors of `complex_lu_factor`; `b` is overwritten by x.
    pure subroutine complex_lu_solve(lu, ipiv, b, info)
        !> LU factors, n x n.
        complex(wp), intent(in) :: lu(:, :)
        !> Pivot indices.
        integer, intent(in) :: ipiv(:)
        !> Right-hand side on entry, solution on exit, size n.
        complex(wp), intent(inout) :: b(:)
        !> LAPACK status.
        integer, intent(out) :: info

        call zgetrs("N", size(lu, 1), 1, lu, size(lu, 1), ipiv, b, size(b), info)
    end subroutine complex_lu_solve

    !> Solve A x = b by LU with partial pivoting in one call: `a` is destroyed, `b` overwritten by x.
    !> `info` = 0 on success, i > 0 when A is singular (x is then not computed).
    pure subroutine dense_solve(a, b, info)
        !> The matrix, n x n (overwritten by its factors).
        real(wp), intent(inout) :: a(:, :)
        !> Right-hand side on entry, solution on exit, size n.
        real(wp), intent(inout) :: b(:)
        !> LAPACK status.
        integer, intent(out) :: info
        integer, allocatable :: ipiv(:)

        allocate (ipiv(size(a, 1)))
        call dgesv(size(a, 1), 1, a, size(a, 1), ipiv, b, size(b), info)
    end subroutine dense_solve

end module supratrans_dense
