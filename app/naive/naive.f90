!> The paper-default run written as a newcomer would write it, to pair against `supratrans` in the benchmark:
!> the same scheme and parameters (sine-Gordon, N = 200, N0 = 150, kappa = 0.5, sigma = 3, c = 4, Omega = 0.9,
!> A = 1.9, ramp 50, dt = 0.05, T = 200), Newton from the previous level to 1e-13 in the max-norm, one LAPACK
!> `dgtsv` per iteration, sin and cos per site per iteration, no output file. Prints u_60(T) and the iterations.
program naive
    use, intrinsic :: iso_fortran_env, only: dp => real64
    implicit none
    interface
        subroutine dgtsv(n, nrhs, dl, d, du, b, ldb, info)
            import :: dp
            integer, intent(in) :: n, nrhs, ldb
            real(dp), intent(inout) :: dl(*), d(*), du(*), b(ldb, *)
            integer, intent(out) :: info
        end subroutine dgtsv
    end interface
    integer, parameter :: n = 200, n0 = 150
    real(dp), parameter :: c = 4.0_dp, kappa = 0.5_dp, sigma = 3.0_dp, omega = 0.9_dp, amp = 1.9_dp
    real(dp), parameter :: ramp = 50.0_dp, dt = 0.05_dp, t_final = 200.0_dp, tol = 1.0e-13_dp
    real(dp) :: u_old(0:n + 1), u(0:n + 1), x(0:n + 1), alpha(n), r(n), dl(n - 1), dd(n), du(n - 1)
    real(dp) :: s, h, g, dg, t
    integer :: k, j, it, info, iterations

    alpha = 0.0_dp
    do j = n0 + 1, n
        alpha(j) = kappa*(1.0_dp + tanh(real(2*j - n0 - n, dp)/(2.0_dp*sigma)))
    end do
    u_old = 0.0_dp
    u = 0.0_dp
    u(0) = psi(dt)
    iterations = 0
    do k = 1, nint(t_final/dt) - 1
        t = real(k + 1, dp)*dt
        x = u
        x(0) = psi(t)
        x(n + 1) = 0.0_dp
        do it = 1, 50
            do j = 1, n
                s = 0.5_dp*(x(j) + u_old(j))
                h = 0.5_dp*(x(j) - u_old(j))
                if (abs(h) > 1.0e-8_dp) then
                    g = sin(s)*sin(h)/h
                    dg = 0.5_dp*(cos(s)*sin(h)/h + sin(s)*(cos(h)/h - sin(h)/h**2))
                else
                    g = sin(s)
                    dg = 0.5_dp*cos(s)
                end if
                r(j) = -((x(j) - 2.0_dp*u(j) + u_old(j))/dt**2 &
                         - c**2*(u(j + 1) - 2.0_dp*u(j) + u(j - 1)) + alpha(j)*(x(j) - u_old(j))/(2.0_dp*dt) + g)
                dd(j) = 1.0_dp/dt**2 + alpha(j)/(2.0_dp*dt) + dg
            end do
            dl = 0.0_dp
            du = 0.0_dp
            call dgtsv(n, 1, dl, dd, du, r, n, info)
            x(1:n) = x(1:n) + r
            iterations = iterations + 1
            if (maxval(abs(r)) <= tol) exit
        end do
        u_old = u
        u = x
    end do
    print "(a, es24.16, a, i0)", "u_60(T) = ", u(60), "  Newton iterations: ", iterations

contains

    !> Drive psi(t) = A min(t/ramp, 1) sin(Omega t).
    pure function psi(time) result(value)
        real(dp), intent(in) :: time
        real(dp) :: value

        value = amp*min(time/ramp, 1.0_dp)*sin(omega*time)
    end function psi

end program naive
