!> One period of the paper's three-level schemes (`newton`, `linearized`) and its exact tangent: `leapfrog_run`, a
!> module procedure of `supratrans_period_map` (whose interface declares it and whose documentation defines the map),
!> with the hot loops of the tangent (`propagate_block`, `tangent_rhs`) in this one compilation unit. The tangent of
!> the discrete map:
!>
!> * Newton scheme: (A + diag(dG/da)) du^{k+1} = B du^k + (C - diag(dG/db)) du^{k-1}, with a = u^{k+1},
!>   b = u^{k-1} the converged levels (dG/db(a, b) = dG/da(b, a): G is symmetric): one `dgttrf` a step and
!>   `dgttrs` with many right-hand sides (a multiplication by the reciprocal diagonal when beta = 0, where the
!>   matrix is diagonal). The state's pass stores each step's coefficients; the columns then go through the
!>   period in blocks that stay in cache (at N = 600 twice as fast as sweeping all the columns every step; the
!>   same at N = 200, where the work is bound by arithmetic). With beta = 0 a column spreads one site a step: the
!>   blocks (within the d/du^0 columns, within the d/du^1 columns, the dA column alone) compute only the sites
!>   their columns can have reached, the rest being exactly zero (half the work at N = 200, M = 140; none when
!>   M >> N);
!> * linearized scheme: A du^{k+1} = (B - diag(V''(u^k))) du^k + C du^{k-1}, A factored once;
!> * in both, the dA column's boundary cells are du_0^k = sin(Omega t_k) (the derivative of u_0^k = A sin(Omega t_k)),
!>   the state columns' are zero;
submodule(supratrans_period_map) supratrans_period_map_leapfrog
    use supratrans_scheme, only: scheme_rhs_and_predictor, scheme_apply_a
    use supratrans_ledger, only: stored_energy
    use supratrans_stepper_linearized, only: linearized_step
    use supratrans_tridiag, only: solve_tridiag, solve_factored_tridiag
    implicit none

contains

    !> One period of a three-level scheme from x = (u^0, u^1): P = (u^M, u^{M+1}), the measures when asked for,
    !> and the tangent columns c_first..c_last: the state's pass stores each step's tangent coefficients (the
    !> diagonals of B', C' and the factored matrix), then the columns are propagated through the whole period in
    !> blocks of `block_entries` / N columns, which stay in cache (column after column, one sweep over the
    !> tangent levels per step would be bound by memory bandwidth).
    module subroutine leapfrog_run(self, x, amplitude, c_first, c_last, measure, px, status, umax, energy, jac, dpda)
        !> The map.
        class(period_map), intent(inout) :: self
        !> The state (u^0, u^1), size 2N.
        real(wp), intent(in) :: x(:)
        !> The drive amplitude A.
        real(wp), intent(in) :: amplitude
        !> Tangent columns to propagate (none when c_first > c_last).
        integer, intent(in) :: c_first, c_last
        !> Whether to compute the measures.
        logical, intent(in) :: measure
        !> P(x; A), size 2N.
        real(wp), intent(out) :: px(:)
        !> `map_ok` or `map_failed`.
        integer, intent(out) :: status
        !> max |u_n| over levels 0..M and the mean of E_k, k = 0..M-1 (when `measure`).
        real(wp), intent(out) :: umax, energy
        !> dP/dx (columns 1..2N of the tangent).
        real(wp), intent(inout), optional :: jac(:, :)
        !> dP/dA (column 2N + 1).
        real(wp), intent(inout), optional :: dpda(:)
        integer :: n, m, step, info, j, lm2, lm1, lc, ln, swap, block, cb, tm, tm1, half, c_lo, c_hi
        real(wp) :: energy_sum

        n = self%n
        m = self%run_steps()
        status = map_ok
        umax = 0.0_wp
        energy = 0.0_wp
        energy_sum = 0.0_wp
        self%newton_iterations = 0
        ! state columns: lm2, lm1, lc = levels k-2, k-1, k; ln = the next level
        lm2 = 1
        lm1 = 2
        lc = 3
        ln = 4
        self%u(:, lm1) = 0.0_wp
        self%u(:, lc) = 0.0_wp
        self%u(1:n, lm1) = x(1:n)
        self%u(1:n, lc) = x(n + 1:2*n)
        self%u(0, lm1) = amplitude*self%sin_t(0)
        self%u(0, lc) = amplitude*self%sin_t(1)
        ! the predictor's level -1: its first prediction is the linear extrapolation 2 u^1 - u^0
        self%u(:, lm2) = 2.0_wp*self%u(:, lm1) - self%u(:, lc)
        self%beyond_max = 0.0_wp
        if (self%watch_site > 0) self%beyond_max = max(maxval(abs(self%u(self%watch_site + 1:n, lm1))), &
                                                       maxval(abs(self%u(self%watch_site + 1:n, lc))))
        if (measure) then
            umax = max(maxval(abs(self%u(1:n, lm1))), maxval(abs(self%u(1:n, lc))))
            energy_sum = stored_energy(self%scheme, self%chain%m2, self%u(:, lc), self%u(:, lm1))
        end if
        do step = 1, m
            ! level k + 1 = step + 1
            self%u(0, ln) = amplitude*self%sin_t(step + 1)
            self%u(n + 1, ln) = 0.0_wp
            if (self%method == method_newton) then
                call newton_solve(self, lm2, lm1, lc, ln, status)
            else
                call linearized_step(self%scheme, self%lin, self%u(:, lm1), self%u(:, lc), self%u(:, ln), info)
                if (info /= 0) status = map_failed
            end if
            if (status /= map_ok) return
            if (c_first <= c_last) then
                call store_tangent_step(self, step, lm1, lc, ln, status)
                if (status /= map_ok) return
            end if
            if (self%watch_site > 0 .and. step <= m - 1) then
                self%beyond_max = max(self%beyond_max, maxval(abs(self%u(self%watch_site + 1:n, ln))))
            end if
            if (measure) then
                if (step <= m - 1) then
                    ! E_k of levels k = step and k + 1
                    energy_sum = energy_sum + stored_energy(self%scheme, self%chain%m2, self%u(:, ln), self%u(:, lc))
                    umax = max(umax, maxval(abs(self%u(1:n, ln))))
                end if
            end if
            swap = lm2
            lm2 = lm1
            lm1 = lc
            lc = ln
            ln = swap
        end do
        ! lm1, lc hold the levels M and M + 1
        px(1:n) = self%u(1:n, lm1)
        px(n + 1:2*n) = self%u(1:n, lc)
        if (measure) energy = energy_sum/real(m, wp)
        block = self%block_columns
        if (block < 1) block = max(1, block_entries/n)
        tm1 = 1
        tm = 2
        ! blocks within the d/du^0 columns, within the d/du^1 columns, and the dA column alone: each block's
        ! columns start from nearby sites (see propagate_block)
        do half = 0, 2
            c_lo = max(c_first, half*n + 1)
            c_hi = min(c_last, merge(2*n + 1, half*n + n, half == 2))
            do cb = c_lo, c_hi, block
                call propagate_block(self, cb, min(c_hi, cb + block - 1), tm1, tm, status)
                if (status /= map_ok) return
            end do
        end do
        if (present(jac)) then
            do j = 1, 2*n
                jac(1:n, j) = self%tangent(:, j, tm1)
                jac(n + 1:2*n, j) = self%tangent(:, j, tm)
            end do
        end if
        if (present(dpda)) then
            dpda(1:n) = self%tangent(:, 2*n + 1, tm1)
            dpda(n + 1:2*n) = self%tangent(:, 2*n + 1, tm)
        end if
    end subroutine leapfrog_run

    !> One implicit step of the Newton scheme, solved to roundoff: the level in column `ln` (its boundary cells
    !> set) from the columns lm1, lc (levels k-1, k; lm2, level k-2, for the cubic predictor). Newton's iteration
    !> stops when the update is at roundoff (<= 4 eps max |u^{k+1}|), when the Kantorovich bound of the new
    !> iterate's error, (L / (2 mu)) |delta|^2 (as in the stepper), is below eps max |u^{k+1}|, or when the update
    !> stops decreasing at the 1e-12 level (roundoff noise); `map_failed` after `period_newton_max_iter` iterations,
    !> on a singular matrix or a non-finite update.
    subroutine newton_solve(self, lm2, lm1, lc, ln, status)
        !> The map.
        class(period_map), intent(inout) :: self
        !> Columns of the levels k-2, k-1, k and of the new level.
        integer, intent(in) :: lm2, lm1, lc, ln
        !> `map_ok` or `map_failed`.
        integer, intent(out) :: status
        integer :: n, it, j, info
        real(wp) :: h_max, mu, change, previous, scale, u_max, curvature

        n = self%n
        status = map_failed
        associate (s => self%scheme)
            call scheme_rhs_and_predictor(s, self%u(:, lm2), self%u(:, lm1), self%u(:, lc), self%rhs, &
                                          self%u(:, ln), h_max)
            mu = s%b_min + s%potential%slope_lower_bound() - 2.0_wp*abs(s%a)
            previous = huge(1.0_wp)
            do it = 1, period_newton_max_iter
                self%newton_iterations = self%newton_iterations + 1
                call s%potential%gradient_and_slope_array(self%u(1:n, ln), self%u(1:n, lm1), self%g, self%dga, &
                                              self%sin_s, self%cos_s)
                call scheme_apply_a(s, self%u(:, ln), self%delta)
                if (s%a == 0.0_wp) then
                    do j = 1, n
                        self%delta(j) = (self%rhs(j) - self%delta(j) - self%g(j))/(s%b(j) + self%dga(j))
                    end do
                    info = 0
                else
                    do j = 1, n
                        self%delta(j) = self%rhs(j) - self%delta(j) - self%g(j)
                        self%dd(j) = s%b(j) + self%dga(j)
                    end do
                    self%dl = s%a
                    self%du = s%a
                    call solve_tridiag(self%dl, self%dd, self%du, self%delta, info)
                end if
                if (info /= 0) return
                change = 0.0_wp
                scale = 0.0_wp
                u_max = 0.0_wp
                do j = 1, n
                    self%u(j, ln) = self%u(j, ln) + self%delta(j)
                    change = max(change, abs(self%delta(j)))
                    scale = max(scale, abs(self%u(j, ln)))
                    u_max = max(u_max, abs(self%u(j, lm1)))
                end do
                if (.not. (change <= huge(1.0_wp) .and. scale <= huge(1.0_wp))) return
                if (change <= 4.0_wp*epsilon(1.0_wp)*scale) exit
                if (mu > 0.0_wp) then
                    curvature = s%potential%curvature_bound(max(scale, u_max) + change)
                    if (curvature/(2.0_wp*mu)*change**2 <= epsilon(1.0_wp)*scale) exit
                end if
                if (change >= previous .and. change <= 1.0e-12_wp*scale) exit
                previous = change
                if (it == period_newton_max_iter) return
            end do
        end associate
        status = map_ok
    end subroutine newton_solve

    !> Store the tangent coefficients of step `step` (levels k-1, k, k+1 = step + 1 in columns lm1, lc, ln,
    !> converged): du^{k+1} = J^{-1} (B' du^k + C' du^{k-1}) with
    !> Newton: J = A + diag(dG/da(u^{k+1}, u^{k-1})), B' = B, C' = C - diag(dG/db) (dG/db(a, b) = dG/da(b, a));
    !> linearized: J = A (factored once), B' = B - diag(V''(u^k)), C' = C. The diagonals of B' and C' go to
    !> `step_b`, `step_c`; J's LU factors (`dgttrf`) to `step_dl`, `step_d`, `step_du`, `step_du2`, `step_ipiv`, or
    !> when beta = 0 (J diagonal) its reciprocal to `step_d`.
    subroutine store_tangent_step(self, step, lm1, lc, ln, status)
        !> The map.
        class(period_map), intent(inout) :: self
        !> The step (1..M).
        integer, intent(in) :: step
        !> State columns of the levels k-1, k, k+1.
        integer, intent(in) :: lm1, lc, ln
        !> `map_ok` or `map_failed` (a singular J).
        integer, intent(out) :: status
        integer :: n, info, j

        n = self%n
        status = map_ok
        associate (s => self%scheme)
            if (self%method == method_newton) then
                call s%potential%gradient_and_slope_array(self%u(1:n, ln), self%u(1:n, lm1), self%g, self%dga, &
                                              self%sin_s, self%cos_s)
                call s%potential%gradient_and_slope_array(self%u(1:n, lm1), self%u(1:n, ln), self%g, self%dgb, &
                                              self%sin_s, self%cos_s)
                do j = 1, n
                    self%step_b(j, step) = s%d
                    self%step_c(j, step) = s%e(j) - self%dgb(j)
                end do
                if (s%a == 0.0_wp) then
                    do j = 1, n
                        self%step_d(j, step) = 1.0_wp/(s%b(j) + self%dga(j))
                    end do
                else
                    do j = 1, n
                        self%step_d(j, step) = s%b(j) + self%dga(j)
                    end do
                    self%step_dl(:, step) = s%a
                    self%step_du(:, step) = s%a
                    call factor_tridiag(self%step_dl(:, step), self%step_d(:, step), self%step_du(:, step), &
                                        self%step_du2(:, step), self%step_ipiv(:, step), info)
                    if (info /= 0) status = map_failed
                end if
            else
                call s%potential%d2v_each(self%u(1:n, lc), self%g)     ! V''(u^k), in the work array of G
                do j = 1, n
                    self%step_b(j, step) = s%d - self%g(j)
                    self%step_c(j, step) = s%e(j)
                end do
            end if
        end associate
    end subroutine store_tangent_step

    !> Propagate the tangent columns cb..ce through the period with the stored coefficients of each step; on exit
    !> columns cb..ce of tangent levels `tm1`, `tm` hold du^M and du^{M+1}. The dA column (2N + 1) gets the boundary
    !> cells du_0^k = sin(Omega t_k): c^2 du_0^k + a (du_0^{k-1} - du_0^{k+1}) in the right-hand side's first row.
    subroutine propagate_block(self, cb, ce, tm1, tm, status)
        !> The map.
        class(period_map), intent(inout) :: self
        !> First and last column of the block.
        integer, intent(in) :: cb, ce
        !> Tangent levels holding du^M and du^{M+1} on exit.
        integer, intent(out) :: tm1, tm
        !> `map_ok` or `map_failed`.
        integer, intent(out) :: status
        integer :: n, j, step, tn, swap, forced, info, site_lo, site_hi, lo, hi, nsteps
        real(wp) :: boundary
        logical :: newton

        n = self%n
        nsteps = self%run_steps()
        status = map_ok
        newton = self%method == method_newton
        forced = 0
        if (ce == 2*n + 1) forced = ce - cb + 1
        tm1 = 1
        tm = 2
        tn = 3
        self%tangent(:, cb:ce, tm1) = 0.0_wp
        self%tangent(:, cb:ce, tm) = 0.0_wp
        self%tangent(:, cb:ce, tn) = 0.0_wp
        ! the sites the block's columns start from (the dA column from the driven boundary, site 0): with beta = 0
        ! every step spreads a column by one site each way, so after `step` steps only the sites within `step` of
        ! them can be nonzero, and the others are not computed (they stay exactly zero)
        site_lo = n + 1
        site_hi = 0
        do j = cb, ce
            if (j <= 2*n) then
                site_lo = min(site_lo, mod(j - 1, n) + 1)
                site_hi = max(site_hi, mod(j - 1, n) + 1)
            else
                site_lo = 0
            end if
        end do
        do j = cb, min(ce, n)
            self%tangent(j, j, tm1) = 1.0_wp
        end do
        do j = max(cb, n + 1), min(ce, 2*n)
            self%tangent(j - n, j, tm) = 1.0_wp
        end do
        associate (s => self%scheme)
            do step = 1, nsteps
                ! levels k - 1, k, k + 1 = step - 1, step, step + 1
                lo = max(1, site_lo - step)
                hi = min(n, site_hi + step)
                boundary = s%c2*self%sin_t(step) + s%a*(self%sin_t(step - 1) - self%sin_t(step + 1))
                if (s%a == 0.0_wp) then
                    if (newton) then
                        call tangent_rhs(n, s%c2, s%a, self%step_b(:, step), self%step_c(:, step), .true., &
                                         self%step_d(:, step), forced, boundary, self%tangent(:, cb:ce, tm1), &
                                         self%tangent(:, cb:ce, tm), self%tangent(:, cb:ce, tn), lo, hi)
                    else
                        call tangent_rhs(n, s%c2, s%a, self%step_b(:, step), self%step_c(:, step), .true., &
                                         self%add, forced, boundary, self%tangent(:, cb:ce, tm1), &
                                         self%tangent(:, cb:ce, tm), self%tangent(:, cb:ce, tn), lo, hi)
                    end if
                else
                    call tangent_rhs(n, s%c2, s%a, self%step_b(:, step), self%step_c(:, step), .false., &
                                     self%step_b(:, step), forced, boundary, self%tangent(:, cb:ce, tm1), &
                                     self%tangent(:, cb:ce, tm), self%tangent(:, cb:ce, tn), 1, n)
                    if (newton) then
                        call solve_factored_tridiag(self%step_dl(:, step), self%step_d(:, step), self%step_du(:, step), &
                                                    self%step_du2(:, step), self%step_ipiv(:, step), &
                                                    self%tangent(:, cb:ce, tn), info)
                    else
                        call solve_factored_tridiag(self%adl, self%add, self%adu, self%adu2, self%apiv, &
                                                    self%tangent(:, cb:ce, tn), info)
                    end if
                    if (info /= 0) then
                        status = map_failed
                        return
                    end if
                end if
                swap = tm1
                tm1 = tm
                tm = tn
                tn = swap
            end do
        end associate
    end subroutine propagate_block

    !> The tangent step's right-hand side for a block of columns, t_new = B' t_cur + C' t_old with
    !> B' = tridiag(c^2, diag_b, c^2), C' = tridiag(a, diag_c, a), zero boundary cells but for column `forced`
    !> (the dA column; 0: none), whose first row gets `boundary`; when `scaled`, multiplied row by row by `recip`
    !> in the same pass (the diagonal solve when beta = 0).
    pure subroutine tangent_rhs(n, c2, a, diag_b, diag_c, scaled, recip, forced, boundary, t_old, t_cur, t_new, lo, hi)
        !> Number of sites N (>= 2).
        integer, intent(in) :: n
        !> Coupling c^2 and the off-diagonal a = -beta/(2 dt).
        real(wp), intent(in) :: c2, a
        !> Diagonals of B' and C'.
        real(wp), intent(in), contiguous :: diag_b(:), diag_c(:)
        !> Whether to scale by `recip`.
        logical, intent(in) :: scaled
        !> Row factors (the reciprocal of the diagonal matrix J), size N.
        real(wp), intent(in), contiguous :: recip(:)
        !> Column of the block that is d/dA (0: none).
        integer, intent(in) :: forced
        !> Its boundary term.
        real(wp), intent(in) :: boundary
        !> Tangent levels k-1 and k, (N, columns).
        real(wp), intent(in), contiguous :: t_old(:, :), t_cur(:, :)
        !> The right-hand side (or solution, when `scaled`), (N, columns): rows lo..hi computed when a = 0 and
        !> `scaled` (the others left as they are: zero, where no column can have spread yet), every row otherwise.
        real(wp), intent(inout), contiguous :: t_new(:, :)
        !> Rows that can be nonzero (1 <= lo <= hi <= N).
        integer, intent(in) :: lo, hi
        integer :: i, j
        real(wp) :: extra

        if (a == 0.0_wp .and. scaled) then
            ! beta = 0 (the paper's default): no C' off-diagonals, and the diagonal solve in the same pass; the
            ! terms in the order of the general loop (a zero term dropped), so the values are the same bits
            do j = 1, size(t_new, 2)
                extra = 0.0_wp
                if (j == forced) extra = boundary
                if (lo == 1) then
                    t_new(1, j) = (diag_b(1)*t_cur(1, j) + c2*t_cur(2, j) + diag_c(1)*t_old(1, j) + extra)*recip(1)
                end if
                do i = max(lo, 2), min(hi, n - 1)
                    t_new(i, j) = (diag_b(i)*t_cur(i, j) + c2*(t_cur(i - 1, j) + t_cur(i + 1, j)) &
                                   + diag_c(i)*t_old(i, j))*recip(i)
                end do
                if (hi == n) then
                    t_new(n, j) = (diag_b(n)*t_cur(n, j) + c2*t_cur(n - 1, j) + diag_c(n)*t_old(n, j))*recip(n)
                end if
            end do
            return
        end if
        do j = 1, size(t_new, 2)
            extra = 0.0_wp
            if (j == forced) extra = boundary
            t_new(1, j) = diag_b(1)*t_cur(1, j) + c2*t_cur(2, j) + diag_c(1)*t_old(1, j) + a*t_old(2, j) + extra
            do i = 2, n - 1
                t_new(i, j) = diag_b(i)*t_cur(i, j) + c2*(t_cur(i - 1, j) + t_cur(i + 1, j)) &
                              + diag_c(i)*t_old(i, j) + a*(t_old(i - 1, j) + t_old(i + 1, j))
            end do
            t_new(n, j) = diag_b(n)*t_cur(n, j) + c2*t_cur(n - 1, j) + diag_c(n)*t_old(n, j) + a*t_old(n - 1, j)
            if (scaled) then
                do i = 1, n
                    t_new(i, j) = t_new(i, j)*recip(i)
                end do
            end if
        end do
    end subroutine tangent_rhs

end submodule supratrans_period_map_leapfrog
