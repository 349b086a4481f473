!> The fold continued in Omega, measured against the fold from rest (`fpm run --example benchmark --profile release
!> -- 1 fold omega [FROM TO]`): what the two-parameter route of docs/continuation.md ("Why the fold line does not
!> reach the scan's time") would give on the undamped sine-Gordon fold line, frequency by frequency, on the short
!> chains of fold lines (`shortest_chain`), newton, dt ~ 0.05, one thread.
!>
!> At each Omega of the grid FROM .. TO (step 0.01 towards TO; default 0.99 .. 0.05):
!> * **from rest**: the fold of the branch continued in A from the chain at rest (`continue_branch`, the fold alone:
!>   the fold-line scene's controls with `floquet_every = 0`, `continuation_step_max = 0.5`, `beyond_fold = 0`);
!> * **continued**: Newton on the minimally augmented system {P(x; A) - x = 0, g(x, A) = 0} from the fold of the
!>   previous frequency (at the third frequency on, the secant through the last two), its state carried to the new
!>   chain site by site. g is the last component of K^{-1} e_{d+1}, K = [[J - I, dP/dA]; [c^T, 0]] with c the last
!>   fold's null vector (g is the branch tangent's A-component, up to its scale). Its derivative along a direction
!>   u is -w^T D^2 P[(v, g), u] (w the first d components of K^{-T} e_{d+1}), taken by second differences of P
!>   (6 maps a step); the Newton step is the particular solution z of [J - I, dP/dA] z = -F, c . z_x = 0, plus the
!>   multiple of the null direction (v, g) that zeroes the linearised g. It stops when the quadratic rate puts the
!>   next change of A below 1e-10 and P(x) - x is below 1e-10. A continued curve that fails (a map failure, a
!>   residual grown tenfold, 8 steps) restarts from the fold from rest.
!>
!> A row gives both folds, their difference, and the Jacobians (2N + 1 tangent columns) and maps of each; the last
!> lines the totals and the CPU seconds. A continued fold that converges to another fold than the one from rest is
!> reported as such: the continued curve carries no proof that its fold is the first one of the branch from rest.
module bench_fold_omega
    use supratrans_kinds, only: wp
    use supratrans_error, only: error_type
    use supratrans_config, only: run_config, method_newton, short_chain_params
    use supratrans_period_map, only: period_map, period_map_init
    use supratrans_fixed_point_map, only: map_ok
    use supratrans_dense, only: lu_solve
    use supratrans_bordered_system, only: bordered_system, factor_bordered
    use supratrans_continuation, only: continue_branch, continuation_controls, continuation_result, cont_fold_found, &
        continuation_stats
    use supratrans_fold_line, only: shortest_chain
    implicit none
    private

    public :: fold_omega_benchmark

    !> Most Newton steps of a continued fold.
    integer, parameter :: max_steps = 8
    !> Step of the second differences of P (along unit directions in (x, A)).
    real(wp), parameter :: fd_step = 1.0e-4_wp
    !> Accuracy asked of A_f and of the residual max |P(x) - x|.
    real(wp), parameter :: fold_tol = 1.0e-10_wp
    !> Two folds closer than this in A are the same fold.
    real(wp), parameter :: same_fold = 1.0e-8_wp

    !> A fold on its chain: state, amplitude, null vector (the state part of the branch tangent), chain length.
    type :: fold_point
        real(wp), allocatable :: x(:), c(:)
        real(wp) :: amplitude = 0.0_wp
        real(wp) :: omega = 0.0_wp
        integer :: n = 0
    end type fold_point

contains

    !> The table described in the module's documentation, for Omega from `omega_from` to `omega_to` (step 0.01).
    subroutine fold_omega_benchmark(omega_from, omega_to)
        !> First and last frequency of the grid.
        real(wp), intent(in) :: omega_from, omega_to
        type(run_config) :: run
        type(period_map) :: map
        type(error_type), allocatable :: error
        type(continuation_controls) :: ctl
        type(continuation_result) :: res
        type(fold_point) :: older, last, rest
        real(wp), allocatable :: x(:), c(:)
        real(wp) :: step, omega, a, c0, c1, cpu_rest, cpu_cont
        integer :: nomega, j, jac, maps, steps, jac_rest, jac_cont, map_rest, map_cont, n_agree, n_other, n_failed
        logical :: ok, have_rest
        character(len=12) :: outcome

        step = sign(0.01_wp, omega_to - omega_from)
        nomega = nint((omega_to - omega_from)/step) + 1
        ctl%newton_tol = 1.0e-10_wp
        ctl%ds_max = 0.5_wp
        ctl%amplitude_max = 7.0_wp
        ctl%beyond_fold = 0
        ctl%floquet_every = 0
        jac_rest = 0
        jac_cont = 0
        map_rest = 0
        map_cont = 0
        cpu_rest = 0.0_wp
        cpu_cont = 0.0_wp
        n_agree = 0
        n_other = 0
        n_failed = 0
        write (*, "(a)") "# the fold continued in Omega against the fold from rest: undamped sine-Gordon, short chains, " &
            // "newton, dt ~ 0.05, one thread"
        write (*, "(a6, 1x, a4, 1x, a5, 1x, a15, 1x, a5, 1x, a15, 1x, a9, 1x, a5, 1x, a5, 1x, a5, 1x, a12)") "Omega", &
            "N", "M", "A_f from rest", "jacs", "A_f continued", "diff", "steps", "jacs", "maps", "outcome"
        do j = 1, nomega
            omega = omega_from + real(j - 1, wp)*step
            run = run_config()
            run%numerics%method = method_newton
            run%numerics%dt = 0.05_wp
            run%drive%omega = omega
            call shortest_chain(run%chain, omega, run%numerics%dt, short_chain_params())
            call period_map_init(map, run, error)
            if (allocated(error)) error stop "benchmark: " // error%message

            call cpu_time(c0)
            call continue_branch(map, ctl, res)
            call cpu_time(c1)
            cpu_rest = cpu_rest + (c1 - c0)
            jac_rest = jac_rest + res%stats%jacobian_evaluations
            map_rest = map_rest + res%stats%map_evaluations
            have_rest = res%status == cont_fold_found
            if (have_rest) then
                rest%x = res%states(:, res%fold_index)
                rest%c = res%tangents(1:map%dim, res%fold_index)
                rest%amplitude = res%fold_amplitude
                rest%omega = omega
                rest%n = run%chain%n
            end if

            outcome = "start"
            jac = 0
            maps = 0
            steps = 0
            ok = .false.
            if (last%n > 0) then
                x = carried(last%x, last%n, run%chain%n)
                a = last%amplitude
                if (older%n > 0) then
                    x = x + (x - carried(older%x, older%n, run%chain%n))*((omega - last%omega)/(last%omega - older%omega))
                    a = a + (a - older%amplitude)*((omega - last%omega)/(last%omega - older%omega))
                end if
                c = carried(last%c, last%n, run%chain%n)
                call cpu_time(c0)
                call fold_newton(map, x, a, c, ok, steps, jac, maps)
                call cpu_time(c1)
                cpu_cont = cpu_cont + (c1 - c0)
                jac_cont = jac_cont + jac
                map_cont = map_cont + maps
                outcome = "failed"
                if (ok .and. have_rest) then
                    outcome = "other fold"
                    if (abs(a - rest%amplitude) <= same_fold) outcome = "agree"
                else if (ok) then
                    outcome = "no rest fold"
                end if
            end if
            select case (trim(outcome))
            case ("agree")
                n_agree = n_agree + 1
            case ("other fold", "no rest fold")
                n_other = n_other + 1
            case ("failed")
                n_failed = n_failed + 1
            case default
                ! "start": the first frequency, or the first after a frequency with no fold from rest
            end select
            if (ok) then
                write (*, "(f6.3, 1x, i4, 1x, i5, 1x, f15.11, 1x, i5, 1x, f15.11, 1x, es9.1, 1x, i5, 1x, i5, 1x, i5, 1x, a12)") &
                    omega, run%chain%n, map%steps, res%fold_amplitude, res%stats%jacobian_evaluations, a, &
                    a - res%fold_amplitude, steps, jac, maps, outcome
                older = last
                last = fold_point(x, c, a, omega, run%chain%n)
            else
                write (*, "(f6.3, 1x, i4, 1x, i5, 1x, f15.11, 1x, i5, 1x, a15, 1x, a9, 1x, i5, 1x, i5, 1x, i5, 1x, a12)") &
                    omega, run%chain%n, map%steps, res%fold_amplitude, res%stats%jacobian_evaluations, "-", "-", &
                    steps, jac, maps, outcome
                ! the curve restarts from the fold from rest (or stops where there is none)
                older = fold_point()
                last = fold_point()
                if (have_rest) last = rest
            end if
        end do
        write (*, "(a, i0, a, i0, a, i0, a, i0, a)") "# of ", nomega - 1, " continued: ", n_agree, " agree with the fold " &
            // "from rest (to 1e-8), ", n_other, " converged to another fold (or to one where the branch from rest " &
            // "has none), ", n_failed, " failed"
        write (*, "(a, i0, a, i0, a, f8.2, a)") "# from rest: ", jac_rest, " Jacobians, ", map_rest, " maps, ", cpu_rest, &
            " s CPU"
        write (*, "(a, i0, a, i0, a, f8.2, a)") "# continued: ", jac_cont, " Jacobians, ", map_cont, " maps, ", cpu_cont, &
            " s CPU"
    end subroutine fold_omega_benchmark

    !> The state x of a chain of n sites on a chain of m sites: u^0 and u^1 (or u and u_t) each cut or padded with 0.
    pure function carried(x, n, m) result(y)
        !> The state, size 2n.
        real(wp), intent(in) :: x(:)
        !> Sites of its chain and of the new one.
        integer, intent(in) :: n, m
        real(wp), allocatable :: y(:)
        integer :: k

        allocate (y(2*m), source=0.0_wp)
        k = min(n, m)
        y(1:k) = x(1:k)
        y(m + 1:m + k) = x(n + 1:n + k)
    end function carried

    !> Newton on the minimally augmented system from (x, a), the border row c (see the module's documentation);
    !> on success x, a are the fold and c its null vector (unit, state part).
    subroutine fold_newton(map, x, a, c, ok, steps, jac_count, map_count)
        !> The one-period map at the new frequency.
        type(period_map), intent(inout) :: map
        !> The predicted state and amplitude; the fold on success.
        real(wp), intent(inout) :: x(:), a
        !> The border row (the predicted null vector); the fold's on success.
        real(wp), intent(inout) :: c(:)
        !> Whether the fold was found.
        logical, intent(out) :: ok
        !> Newton steps taken.
        integer, intent(out) :: steps
        !> Jacobians and maps evaluated (added to).
        integer, intent(inout) :: jac_count, map_count
        real(wp), allocatable :: jac(:, :), dpda(:), px(:), tv(:), y(:), z(:), tn(:), zn(:), d2(:), pp(:, :)
        type(bordered_system) :: ksys
        type(continuation_stats) :: stats
        integer :: d, it, st, info, i
        real(wp) :: g, dg_t, dg_z, alpha, tnorm, znorm, res0, resk, da, da_prev, e2
        logical :: quadratic

        d = size(x)
        allocate (jac(d, d), dpda(d), px(d), pp(d, 4))
        ok = .false.
        steps = 0
        res0 = -1.0_wp
        da_prev = huge(1.0_wp)
        c = c/norm2(c)
        e2 = fd_step**2
        do it = 1, max_steps
            call map%apply(x, a, px, st, jac, dpda)
            jac_count = jac_count + 1
            if (st /= map_ok) return
            resk = maxval(abs(px - x))
            if (res0 < 0.0_wp) res0 = resk
            if (resk > 10.0_wp*max(res0, 1.0e-6_wp)) return
            ! K = [[J - I, dP/dA]; [c^T, 0]], the continuation's bordered matrix with c as its last row
            call factor_bordered(jac, dpda, [c, 0.0_wp], ksys, info, stats)
            if (info /= 0) return
            tv = [(0.0_wp, i=1, d), 1.0_wp]
            call lu_solve(ksys%lu, ksys%ipiv, tv, info)
            g = tv(d + 1)
            y = [(0.0_wp, i=1, d), 1.0_wp]
            call lu_solve(ksys%lu, ksys%ipiv, y, info, transposed=.true.)
            z = [x - px, 0.0_wp]
            call lu_solve(ksys%lu, ksys%ipiv, z, info)
            tnorm = norm2(tv)
            tn = tv/tnorm
            znorm = norm2(z)
            ! D^2 P[tn, tn] by a central second difference, D^2 P[tn, zn] by polarisation
            call map%apply(x + fd_step*tn(1:d), a + fd_step*tn(d + 1), pp(:, 1), st)
            call map%apply(x - fd_step*tn(1:d), a - fd_step*tn(d + 1), pp(:, 2), st)
            map_count = map_count + 2
            d2 = (pp(:, 1) - 2.0_wp*px + pp(:, 2))/e2
            dg_t = -tnorm*dot_product(y(1:d), d2)
            dg_z = 0.0_wp
            if (znorm > 0.0_wp) then
                zn = z/znorm
                call map%apply(x + fd_step*(tn(1:d) + zn(1:d)), a + fd_step*(tn(d + 1) + zn(d + 1)), pp(:, 1), st)
                call map%apply(x + fd_step*(tn(1:d) - zn(1:d)), a + fd_step*(tn(d + 1) - zn(d + 1)), pp(:, 2), st)
                call map%apply(x - fd_step*(tn(1:d) - zn(1:d)), a - fd_step*(tn(d + 1) - zn(d + 1)), pp(:, 3), st)
                call map%apply(x - fd_step*(tn(1:d) + zn(1:d)), a - fd_step*(tn(d + 1) + zn(d + 1)), pp(:, 4), st)
                map_count = map_count + 4
                d2 = (pp(:, 1) - pp(:, 2) - pp(:, 3) + pp(:, 4))/(4.0_wp*e2)
                dg_z = -tnorm*znorm*dot_product(y(1:d), d2)
            end if
            if (.not. (abs(dg_t) > 0.0_wp)) return
            alpha = -(g + dg_z)/dg_t
            z = z + alpha*tn
            x = x + z(1:d)
            da = z(d + 1)
            a = a + da
            c = tn(1:d)/norm2(tn(1:d))
            steps = it
            ! quadratic convergence: the next change of A is about |da|^3 / da_prev^2 (after the first step)
            quadratic = abs(da) <= fold_tol
            if (it > 1) quadratic = abs(da)**3 <= fold_tol*da_prev**2
            if (abs(da) < 1.0e-6_wp .and. quadratic) then
                call map%apply(x, a, px, st)
                map_count = map_count + 1
                ok = st == map_ok .and. maxval(abs(px - x)) <= fold_tol
                if (ok) return
            end if
            da_prev = da
        end do
    end subroutine fold_newton

end module bench_fold_omega
