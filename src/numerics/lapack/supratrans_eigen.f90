!> Thin typed wrapper over LAPACK `dgeev` (eigenvalues of a general real matrix), with an explicit interface.
!> With `supratrans_tridiag` (`dgtsv`) this folder holds every LAPACK routine the code calls.
module supratrans_eigen
    use supratrans_kinds, only: wp
    implicit none
    private

    public :: general_eigenvalues

    interface
        !> LAPACK: eigenvalues (and optionally vectors) of a general real matrix.
        pure subroutine dgeev(jobvl, jobvr, n, a, lda, wr, wi, vl, ldvl, vr, ldvr, work, lwork, info)
            import :: wp
            character(len=1), intent(in) :: jobvl, jobvr
            integer, intent(in) :: n, lda, ldvl, ldvr, lwork
            real(wp), intent(inout) :: a(lda, *)
            real(wp), intent(out) :: wr(*), wi(*), vl(ldvl, *), vr(ldvr, *), work(*)
            integer, intent(out) :: info
        end subroutine dgeev
    end interface

contains

    !> Eigenvalues wr + i wi of the square matrix `a` (destroyed), no eigenvectors: a workspace query, then the
    !> computation with the optimal workspace. `info` is LAPACK's status (0: success; > 0: the QR algorithm failed
    !> to converge, eigenvalues info+1.. are valid).
    pure subroutine general_eigenvalues(a, wr, wi, info)
        !> The matrix, n x n (overwritten).
        real(wp), intent(inout) :: a(:, :)
        !> Real parts of the n eigenvalues.
        real(wp), intent(out) :: wr(:)
        !> Imaginary parts of the n eigenvalues.
        real(wp), intent(out) :: wi(:)
        !> LAPACK status.
        integer, intent(out) :: info
        real(wp), allocatable :: work(:)
        real(wp) :: vl(1, 1), vr(1, 1), query(1)
        integer :: n, lwork

        n = size(a, 1)
        call dgeev("N", "N", n, a, n, wr, wi, vl, 1, vr, 1, query, -1, info)
        lwork = max(1, int(query(1)))
        allocate (work(lwork))
        call dgeev("N", "N", n, a, n, wr, wi, vl, 1, vr, 1, work, lwork, info)
    end subroutine general_eigenvalues

end module supratrans_eigen
