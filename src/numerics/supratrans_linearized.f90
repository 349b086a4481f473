!> One step of the linearized scheme (paper Sec. 3.1): G(u^{k+1}, u^{k-1}) replaced by V'(u^k), so that
!> A u^{k+1} = B u^k + C u^{k-1} - V'(u^k) + v^k is one tridiagonal solve (`dgtsv`) a step, no Newton
!> (a division per site when beta = 0, where A is diagonal).
module supratrans_linearized
    use supratrans_kinds, only: wp
    use supratrans_potential, only: force_array
    use supratrans_scheme, only: scheme_type, scheme_rhs
    use supratrans_tridiag, only: solve_tridiag
    implicit none
    private

    public :: linearized_step

contains

    !> Advance one step of the linearized scheme. `u_new(0)` must hold psi(t_{k+1}) and `u_new(N+1)` zero.
    !> `info` is LAPACK's status (non-zero: singular matrix).
    pure subroutine linearized_step(scheme, u_old, u_cur, u_new, info)
        !> Scheme coefficients and work arrays.
        type(scheme_type), intent(inout) :: scheme
        !> Level k-1, u(0:N+1).
        real(wp), intent(in), contiguous :: u_old(0:)
        !> Level k, u(0:N+1).
        real(wp), intent(in), contiguous :: u_cur(0:)
        !> Level k+1, u(0:N+1): boundary cells in, solution out.
        real(wp), intent(inout) :: u_new(0:)
        !> LAPACK status.
        integer, intent(out) :: info
        integer :: n

        n = scheme%n
        call scheme_rhs(scheme, u_cur, u_old)
        call force_array(scheme%potential, u_cur(1:n), scheme%g)
        scheme%work = scheme%rhs - scheme%g
        scheme%work(1) = scheme%work(1) - scheme%a*u_new(0)
        scheme%work(n) = scheme%work(n) - scheme%a*u_new(n + 1)
        if (scheme%a == 0.0_wp) then      ! beta = 0: A is diagonal
            scheme%work = scheme%work/scheme%b
            info = 0
        else
            scheme%dd = scheme%b
            scheme%dl = scheme%a
            scheme%du = scheme%a
            call solve_tridiag(scheme%dl, scheme%dd, scheme%du, scheme%work, info)
        end if
        u_new(1:n) = scheme%work
    end subroutine linearized_step

end module supratrans_linearized
