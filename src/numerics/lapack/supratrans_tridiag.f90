!> Thin typed wrapper over LAPACK `dgtsv` (tridiagonal solve with partial pivoting), with an explicit interface.
!> With `supratrans_eigen` (`dgeev`) this folder holds every LAPACK routine the code calls.
module supratrans_tridiag
    use supratrans_kinds, only: wp
    implicit none
    private

    public :: solve_tridiag

    interface
        !> LAPACK: solve A X = B for a general tridiagonal A (Gaussian elimination with partial pivoting).
        pure subroutine dgtsv(n, nrhs, dl, d, du, b, ldb, info)
            import :: wp
            integer, intent(in) :: n, nrhs, ldb
            real(wp), intent(inout) :: dl(*), d(*), du(*), b(ldb, *)
            integer, intent(out) :: info
        end subroutine dgtsv
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

end module supratrans_tridiag
