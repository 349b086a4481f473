!> One period of the Runge-Kutta methods (`rk4`, `rk8`) and its exact tangent: `rk_run`, a module procedure of
!> `supratrans_period_map` (whose interface declares it and whose documentation defines the map).
!>
!> The tangent of the discrete map: the derivative of an explicit step is the same tableau applied to the variational
!> equation dY' = J(t, Y) dY + f_A(t), with the stage Jacobians J taken at the stage states Y_i (rebuilt from the
!> step's stage derivatives) and f_A the drive's part of the right-hand side: c^2 sin(Omega t) + beta Omega
!> cos(Omega t) in the equation of u_1'' (u_0 = psi and psi' enter there only).
submodule(supratrans_period_map) supratrans_period_map_rk
    use supratrans_config, only: drive_params
    use supratrans_mol, only: chain_energy
    use supratrans_stepper_rk4, only: rk4_step
    use supratrans_stepper_rk8, only: rk8_step
    implicit none

contains

    !> One period of a Runge-Kutta method from x = (u, v) at t = 0 (the stepper's own step, M times), the tangent
    !> columns c_first..c_last alongside, the measures when asked for.
    module subroutine rk_run(self, x, amplitude, c_first, c_last, measure, px, status, umax, energy, jac, dpda)
        !> The map.
        class(period_map), intent(inout) :: self
        !> The state (u, v), size 2N.
        real(wp), intent(in) :: x(:)
        !> The drive amplitude A.
        real(wp), intent(in) :: amplitude
        !> Tangent columns to propagate (none when c_first > c_last).
        integer, intent(in) :: c_first, c_last
        !> Whether to compute the measures.
        logical, intent(in) :: measure
        !> P(x; A), size 2N.
        real(wp), intent(out) :: px(:)
        !> `map_ok`.
        integer, intent(out) :: status
        !> max |u_n| over levels 0..M and the mean of H over levels 0..M-1 (when `measure`).
        real(wp), intent(out) :: umax, energy
        !> dP/dx (columns 1..2N of the tangent).
        real(wp), intent(inout), optional :: jac(:, :)
        !> dP/dA (column 2N + 1).
        real(wp), intent(inout), optional :: dpda(:)
        type(drive_params) :: drive
        integer :: n, m, step, i, l, j
        real(wp) :: dt, t0, t, energy_sum
        logical :: tangent

        n = self%n
        m = self%run_steps()
        dt = self%dt_used
        tangent = c_first <= c_last
        status = map_ok
        umax = 0.0_wp
        energy = 0.0_wp
        energy_sum = 0.0_wp
        drive%amplitude = amplitude
        drive%omega = self%omega
        drive%ramp_time = 0.0_wp
        self%y = 0.0_wp
        self%y(1:2*n) = x
        if (tangent) then
            self%ty(:, c_first:c_last) = 0.0_wp
            do j = c_first, min(c_last, 2*n)
                self%ty(j, j) = 1.0_wp
            end do
        end if
        self%beyond_max = 0.0_wp
        if (self%watch_site > 0) self%beyond_max = maxval(abs(self%y(self%watch_site + 1:n)))
        if (measure) then
            umax = maxval(abs(self%y(1:n)))
            energy_sum = chain_energy(self%chain, self%scheme%potential, amplitude*sin(self%omega*0.0_wp), self%y)
        end if
        do step = 1, m
            t0 = real(step - 1, wp)*dt
            if (tangent) self%y0 = self%y
            if (self%method == method_rk4) then
                call rk4_step(self%chain, self%scheme%potential, drive, self%alpha, t0, dt, self%y, self%ys, self%k)
            else
                call rk8_step(self%chain, self%scheme%potential, drive, self%alpha, t0, dt, self%y, self%ys, self%k)
            end if
            if (tangent) then
                ! the stage states' u (rebuilt from the stage derivatives), V'' there, the drive's forcing
                do i = 1, self%stages
                    self%ys(1:n) = self%y0(1:n)
                    do l = 1, i - 1
                        if (self%rk_a(i, l) /= 0.0_wp) then
                            self%ys(1:n) = self%ys(1:n) + (dt*self%rk_a(i, l))*self%k(1:n, l)
                        end if
                    end do
                    call self%scheme%potential%d2v_each(self%ys(1:n), self%curvature(:, i))
                    t = t0 + self%rk_c(i)*dt
                    self%forcing(i) = self%chain%c**2*sin(self%omega*t) + self%chain%beta*self%omega*cos(self%omega*t)
                end do
                do j = c_first, c_last
                    call rk_tangent_step(self, dt, j == 2*n + 1, self%ty(:, j))
                end do
            end if
            if (self%watch_site > 0) self%beyond_max = max(self%beyond_max, maxval(abs(self%y(self%watch_site + 1:n))))
            if (measure .and. step <= m - 1) then
                umax = max(umax, maxval(abs(self%y(1:n))))
                energy_sum = energy_sum + chain_energy(self%chain, self%scheme%potential, &
                                                     amplitude*sin(self%omega*real(step, wp)*dt), self%y)
            end if
        end do
        if (measure) then
            umax = max(umax, maxval(abs(self%y(1:n))))
            energy = energy_sum/real(m, wp)
        end if
        px = self%y(1:2*n)
        if (present(jac)) jac = self%ty(:, 1:2*n)
        if (present(dpda)) dpda = self%ty(:, 2*n + 1)
    end subroutine rk_run

    !> One Runge-Kutta step of one tangent column dy (2N): the tableau applied to dY' = J_i dY (+ f_A for the dA
    !> column), J_i the Jacobian of the method-of-lines system at stage state i (V'' in `curvature`).
    subroutine rk_tangent_step(self, dt, forced, dy)
        !> The map (tableau, chain, stage data; work arrays tys, tk).
        class(period_map), intent(inout) :: self
        !> Step size.
        real(wp), intent(in) :: dt
        !> Whether this is the dA column (the drive's forcing f_A added).
        logical, intent(in) :: forced
        !> The column, advanced in place, size 2N.
        real(wp), intent(inout), contiguous :: dy(:)
        integer :: i, l, n
        real(wp) :: c2, beta, m2

        n = self%n
        c2 = self%chain%c**2
        beta = self%chain%beta
        m2 = self%chain%m2
        do i = 1, self%stages
            self%tys = dy
            do l = 1, i - 1
                if (self%rk_a(i, l) /= 0.0_wp) self%tys = self%tys + (dt*self%rk_a(i, l))*self%tk(:, l)
            end do
            call variational_rhs(n, c2, beta, m2, self%alpha, self%curvature(:, i), self%tys, self%tk(:, i))
            if (forced) self%tk(n + 1, i) = self%tk(n + 1, i) + self%forcing(i)
        end do
        do i = 1, self%stages
            if (self%rk_b(i) /= 0.0_wp) dy = dy + (dt*self%rk_b(i))*self%tk(:, i)
        end do
    end subroutine rk_tangent_step

    !> The linearised method-of-lines right-hand side with zero boundary values: dk = J dy, J the Jacobian of
    !> `chain_rhs` in (u, v) at a state whose V''(u_n) is `curv`.
    pure subroutine variational_rhs(n, c2, beta, m2, alpha, curv, dy, dk)
        !> Number of sites N (>= 2).
        integer, intent(in) :: n
        !> Coupling c^2, internal damping beta, mass term m^2.
        real(wp), intent(in) :: c2, beta, m2
        !> Site damping alpha_n and V''(u_n), size N.
        real(wp), intent(in), contiguous :: alpha(:), curv(:)
        !> Tangent (du, dv), size 2N.
        real(wp), intent(in), contiguous :: dy(:)
        !> Its derivative, size 2N.
        real(wp), intent(out), contiguous :: dk(:)
        integer :: i

        dk(1:n) = dy(n + 1:2*n)
        dk(n + 1) = c2*(dy(2) - 2.0_wp*dy(1)) - alpha(1)*dy(n + 1) - (m2 + curv(1))*dy(1)
        do i = 2, n - 1
            dk(n + i) = c2*(dy(i + 1) - 2.0_wp*dy(i) + dy(i - 1)) - alpha(i)*dy(n + i) - (m2 + curv(i))*dy(i)
        end do
        dk(2*n) = c2*(dy(n - 1) - 2.0_wp*dy(n)) - alpha(n)*dy(2*n) - (m2 + curv(n))*dy(n)
        if (beta /= 0.0_wp) then
            dk(n + 1) = dk(n + 1) + beta*(dy(n + 2) - 2.0_wp*dy(n + 1))
            do i = 2, n - 1
                dk(n + i) = dk(n + i) + beta*(dy(n + i + 1) - 2.0_wp*dy(n + i) + dy(n + i - 1))
            end do
            dk(2*n) = dk(2*n) + beta*(dy(2*n - 1) - 2.0_wp*dy(2*n))
        end if
    end subroutine variational_rhs

end submodule supratrans_period_map_rk
