!> Thin typed wrapper over BLAS's matrix product (`dgemm`): the transforms of harmonic balance between the harmonics
!> and the time grid, and its Galerkin matrices of V'', are products with (time points x 2K) matrices of cosines
!> and sines.
module supratrans_blas
    use supratrans_kinds, only: wp
    implicit none
    private

    public :: matrix_product

    interface
        !> BLAS: C = alpha op(A) op(B) + beta C.
        pure subroutine dgemm(transa, transb, m, n, k, alpha, a, lda, b, ldb, beta, c, ldc)
            import :: wp
            character(len=1), intent(in) :: transa, transb
            integer, intent(in) :: m, n, k, lda, ldb, ldc
            real(wp), intent(in) :: alpha, beta
            real(wp), intent(in) :: a(lda, *), b(ldb, *)
            real(wp), intent(inout) :: c(ldc, *)
        end subroutine dgemm
    end interface

contains

    !> C = op(A) B (BLAS `dgemm`), op(A) = A or, with `transpose_a`, A^T.
    pure subroutine matrix_product(a, b, c, transpose_a)
        !> A, m x k (k x m when transposed).
        real(wp), intent(in), contiguous :: a(:, :)
        !> B, k x n.
        real(wp), intent(in), contiguous :: b(:, :)
        !> C, m x n, overwritten.
        real(wp), intent(inout), contiguous :: c(:, :)
        !> Use A^T (default false).
        logical, intent(in), optional :: transpose_a
        logical :: t

        t = .false.
        if (present(transpose_a)) t = transpose_a
        if (t) then
            call dgemm("T", "N", size(c, 1), size(c, 2), size(a, 1), 1.0_wp, a, size(a, 1), b, size(b, 1), 0.0_wp, c, &
                       size(c, 1))
        else
            call dgemm("N", "N", size(c, 1), size(c, 2), size(a, 2), 1.0_wp, a, size(a, 1), b, size(b, 1), 0.0_wp, c, &
                       size(c, 1))
        end if
    end subroutine matrix_product

end module supratrans_blas
