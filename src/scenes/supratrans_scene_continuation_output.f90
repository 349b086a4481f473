!> The file of the scene `continuation` (a submodule of `supratrans_scene_continuation`, whose interface declares
!> `write_snapshot` and `write_continuation_file`): per (curve, Omega) the fold, the first loss of stability and their
!> statuses, the convergence of each fold and its cost, and the sampled branches and multipliers; written atomically,
!> as the final output or as the partial snapshot.
submodule(supratrans_scene_continuation) supratrans_scene_continuation_output
    implicit none

contains

    !> (the interface, with its arguments, is in the parent module)
    module procedure write_snapshot
        type(error_type), allocatable :: error

        call write_continuation_file(self, self%partial_path, results, done, .false., -1.0_wp, error)
        call warn_partial(error, self%cfg%output%quiet)
    end procedure write_snapshot

    !> Tasks not done get NaN and status -1 (pending); the file is built in memory and written atomically (the
    !> interface, with its arguments, is in the parent module).
    module procedure write_continuation_file
        type(h5_file) :: file
        type(fold_record), allocatable :: recs(:)
        real(wp), allocatable :: branch(:, :, :), mult(:, :, :)
        integer :: ncurve, nomega, ntask, t, q, npts
        character(len=*), parameter :: dims = "curve, omega"

        ncurve = size(tasks%runs)
        nomega = size(tasks%omegas)
        ntask = ncurve*nomega
        npts = tasks%cfg%scene%continuation_points
        allocate (recs(ntask))
        do t = 1, ntask
            if (done(t)) then
                recs(t) = fold_from_values(results(:, t), npts)
            else
                recs(t) = empty_fold_record(npts)
                recs(t)%status = status_not_run
            end if
        end do

        call h5_create(file, path, .true.)
        call write_root(file, tasks%cfg, "continuation", "Fold (saddle-node) of the branch of driven periodic " &
                        // "states vs driving frequency: the supratransmission threshold of the model, one curve per " &
                        // "potential and varied value, with Floquet stability and convergence", tasks%inv)
        call h5_write_attr(file, "/", "complete", merge(1, 0, complete))
        call h5_write_attr(file, "/", "tasks_done", count(done))
        call write_parameters(file, tasks%cfg)
        call h5_write(file, "/omega", tasks%omegas, "1/time", &
            "Driving frequency Omega_i = omega_min + i omega_step", dims="omega")
        call write_curves(file, tasks%cfg, tasks%runs)
        call h5_write(file, "/fold_amplitude", grid(recs%fold_amplitude), "rad", &
            "Fold A_f of the branch of periodic states (the model's supratransmission threshold when the branch is " &
            // "stable up to it); NaN when none (see /status)", dims=dims)
        call h5_write(file, "/fold_residual", grid(recs%fold_residual), "rad", &
            "max-norm of the shooting residual P(x) - x at the located fold", dims=dims)
        call h5_write(file, "/fold_fate", igrid(recs%fate), "1", &
            "What the chain does when driven 1% past the fold from the fold's state (codes in attribute 'codes')", &
            dims=dims)
        call h5_write_attr(file, "/fold_fate", "codes", fate_codes(tasks%cfg%scene%protocol))
        call h5_write(file, "/fold_fate_time", grid(recs%fate_time), "time", &
            "Time from the push past the fold to the first transmission (/fold_fate 1), or the time watched without " &
            // "one (2); NaN when there is no fold", dims=dims)
        call h5_write(file, "/transmission_fold", grid(recs%transmission_fold), "rad", &
            "The fold past which the chain transmits: /fold_amplitude when its fate is to transmit; else the fold of " &
            // "the branch the chain settles on past it, and so on (/branches); past a branch point below the fold, " &
            // "the fold of the other branch, or the branch point; past a torus or a period doubling below it, the " &
            // "stair where the chain transmits (/branch_switch); NaN when none was found", dims=dims)
        call h5_write(file, "/branches", igrid(recs%branches), "1", &
            "Branches of periodic states followed from rest to /transmission_fold (1: the first fold transmits)", &
            dims=dims)
        call h5_write(file, "/transmission_status", igrid(recs%transmission_status), "1", &
            "Whether /transmission_fold was found, and if not why (codes in attribute 'codes')", dims=dims)
        call h5_write_attr(file, "/transmission_status", "codes", transmission_status_codes(tasks%cfg%scene%protocol))
        call h5_write(file, "/branch_switch", igrid(recs%branch_switch), "1", "Past a loss of stability below the " &
            // "fold (/threshold below /fold_amplitude): at a branch point (/threshold_kind 1) where the other branch " &
            // "leaves, past a torus or a period doubling the stairs (codes in attribute 'codes'); 0 where there is " &
            // "no such loss (or the stairs would start above the fold)", dims=dims)
        call h5_write_attr(file, "/branch_switch", "codes", branch_switch_codes(tasks%cfg%scene%protocol))
        call h5_write(file, "/transmission_stairs", igrid(recs%transmission_stairs), "1", "1 where " &
            // "/transmission_fold is the stair on which the chain, driven up in stairs of " &
            // real_str(tasks%cfg%scene%protocol%stair_height, 3) &
            // " held " // real_str(tasks%cfg%scene%protocol%stair_time, 4) &
            // " time units each, transmitted (the one below it did not): past " &
            // "a torus or a period doubling below the fold (/branch_switch 4), or from where the chain settled on " &
            // "no stable periodic state past a fold; 0 where it is a fold or a branch point, or NaN", dims=dims)
        call h5_write(file, "/transmission_spread", grid(recs%transmission_spread), "rad", "Where " &
            // "/transmission_fold is a stair (/transmission_stairs 1): max |A_k - A_1| over " &
            // int_str(tasks%cfg%scene%protocol%other_climbs) &
            // " more climbs of the same stairs, each from the first's start moved by " &
            // real_str(tasks%cfg%scene%protocol%switch_seed, 3) &
            // " along another fixed direction (the chain is intermittent there: how " &
            // "reproducible the stair is; a lower bound of its uncertainty). A climb, which goes at most as far " &
            // "above A_1 as the first went above its start, that did not transmit counts at its next stair; NaN " &
            // "where /transmission_fold is not a stair", dims=dims)
        call h5_write(file, "/instability_amplitude", grid(recs%instability_amplitude), &
            "rad", "First amplitude along the branch where a Floquet multiplier leaves the unit circle; NaN when " &
            // "the branch stays stable up to its fold (the fold alone, floquet_every = 0, looks only where a real " &
            // "multiplier passes -1)", dims=dims)
        call h5_write(file, "/instability_lower", grid(recs%instability_lower), "rad", "Lower end of the bracket " &
            // "of the first loss of stability: /instability_amplitude itself where that loss was located (to 1e-10), " &
            // "else the last amplitude known stable below it (the loss lies between the two); NaN with it", dims=dims)
        call h5_write(file, "/instability_size", grid(recs%instability_size), "1", &
            "How far the Floquet multipliers leave the unit circle before the fold: max |mu| - 1 over the branch up " &
            // "to it (a weak instability has a small size: compare it with crossing_tol)", dims=dims)
        call h5_write(file, "/instability_type", igrid(recs%instability_type), "1", &
            "How the branch first loses stability (codes in attribute 'codes')", dims=dims)
        call h5_write_attr(file, "/instability_type", "codes", instability_type_codes())
        call h5_write(file, "/threshold", grid(recs%threshold), "rad", &
            "The model's threshold: the smaller of the fold and the first loss of stability (/threshold_kind says " &
            // "which)", dims=dims)
        call h5_write(file, "/threshold_kind", igrid(recs%threshold_kind), "1", &
            "Which one /threshold is (the codes of /instability_type; 1: the fold)", dims=dims)
        call h5_write_attr(file, "/threshold_kind", "codes", instability_type_codes())
        call h5_write(file, "/threshold_As", grid(recs%threshold_as), "rad", &
            "Continuum-limit threshold A_s = 4 arctan(lambda c / Omega) of the curve's chain; NaN outside the gap", &
            dims=dims)
        call h5_write(file, "/status", igrid(recs%status), "1", &
            "Outcome of the continuation (codes in attribute 'codes')", dims=dims)
        call h5_write_attr(file, "/status", "codes", "-2: outside gap (not computed); " &
            // "-1: pending (not computed yet); " // fold_status_codes())
        call h5_write(file, "/outside_gap", task_igrid(merge(1, 0, &
            [(tasks%omegas(mod(t - 1, nomega) + 1) >= band_gap_edge(tasks%runs((t - 1)/nomega + 1)%chain), &
            t=1, ntask)]), nomega), "1", "1 where Omega >= sqrt(V''(0) + m^2), outside the curve's band gap: computed only " &
            // "with allow_outside_gap, and no fold is expected there", dims=dims)
        call h5_write(file, "/dt_used", grid(recs%dt_used), "time", &
            "Time step used: the drive period 2 pi / Omega over a whole number M of steps", dims=dims)
        call h5_write(file, "/steps_per_period", igrid(recs%steps_per_period), "1", &
            "Steps M per drive period", dims=dims)
        call h5_write(file, "/chain_n", igrid(recs%chain_n), "1", "Oscillators N of the chain used (the short " &
            // "chain of its Omega when the input gives no n, n0, sigma; docs/continuation.md)", dims=dims)
        call h5_write(file, "/chain_n0", igrid(recs%chain_n0), "1", "Last site N0 before the absorber", dims=dims)
        call h5_write(file, "/chain_sigma", grid(recs%chain_sigma), "1", "Width sigma of the absorber's ramp", &
            dims=dims)
        call write_convergence(file, recs, nomega)
        call write_cost(file, recs, nomega, elapsed)
        call h5_create_group(file, "/branch", "The branch of periodic states of each task, point by point " &
            // "from A = 0 (NaN past /branch/points)")
        call h5_write(file, "/branch/points", igrid(recs%points), "1", &
            "Points computed on the branch", dims=dims)
        allocate (branch(npts, nomega, ncurve))
        do q = 1, size(branch_quantities)
            do t = 1, ntask
                branch(:, mod(t - 1, nomega) + 1, (t - 1)/nomega + 1) = recs(t)%branch(q, :)
            end do
            call h5_write(file, "/branch/" // trim(branch_quantities(q)), branch, branch_units(q), &
                          branch_description(q), dims="curve, omega, point")
        end do
        call h5_create_group(file, "/multipliers", "Floquet multipliers of largest modulus at a few points of " &
            // "each branch: the first point, the one nearest half the fold, the fold, the last point")
        allocate (mult(kept_multipliers, multiplier_samples, ntask))
        do t = 1, ntask
            mult(:, :, t) = recs(t)%multiplier_re
        end do
        call h5_write(file, "/multipliers/real", mult, "1", "Real parts of the multipliers (task = (curve - 1) " &
                      // "nomega + omega)", dims="task, sample, multiplier")
        do t = 1, ntask
            mult(:, :, t) = recs(t)%multiplier_im
        end do
        call h5_write(file, "/multipliers/imag", mult, "1", "Imaginary parts of the multipliers", &
                      dims="task, sample, multiplier")
        call h5_write(file, "/multipliers/amplitude", reshape([(recs(t)%multiplier_amplitude, t=1, ntask)], &
                      [multiplier_samples, ntask]), "rad", "Amplitude of each sampled branch point", &
                      dims="task, sample")
        call h5_commit(file, error)

    contains

        !> A per-task real as an (omega, curve) grid.
        pure function grid(x) result(g)
            real(wp), intent(in) :: x(:)
            real(wp), allocatable :: g(:, :)

            g = task_grid(x, nomega)
        end function grid

        !> A per-task integer as an (omega, curve) grid.
        pure function igrid(x) result(g)
            integer, intent(in) :: x(:)
            integer, allocatable :: g(:, :)

            g = task_igrid(x, nomega)
        end function igrid

    end procedure write_continuation_file

    !> A per-task real (task = (curve - 1) nomega + omega) as an (omega, curve) grid: h5py (curve, omega).
    pure function task_grid(x, nomega) result(g)
        !> One value per task.
        real(wp), intent(in) :: x(:)
        !> Frequencies per curve.
        integer, intent(in) :: nomega
        real(wp), allocatable :: g(:, :)

        g = reshape(x, [nomega, size(x)/nomega])
    end function task_grid

    !> A per-task integer as an (omega, curve) grid.
    pure function task_igrid(x, nomega) result(g)
        !> One value per task.
        integer, intent(in) :: x(:)
        !> Frequencies per curve.
        integer, intent(in) :: nomega
        integer, allocatable :: g(:, :)

        g = reshape(x, [nomega, size(x)/nomega])
    end function task_igrid

    !> `/convergence`: each fold again at dt/2 and on a chain twice as long, the extrapolation and the digits.
    subroutine write_convergence(file, recs, nomega)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The records, one per task.
        type(fold_record), intent(in) :: recs(:)
        !> Frequencies per curve.
        integer, intent(in) :: nomega
        character(len=*), parameter :: g = "/convergence/", dims = "curve, omega"

        call h5_create_group(file, "/convergence", "How many digits of each fold are converged: the fold located " &
            // "again at dt/2 and on a chain twice as long (&scene fold_convergence); NaN when not computed")
        call h5_write(file, g // "fold_half_dt", task_grid(recs%fold_half_dt, nomega), &
            "rad", "Fold at dt/2 (the same method, M doubled)", dims=dims)
        call h5_write(file, g // "fold_long_chain", task_grid(recs%fold_long_chain, &
            nomega), "rad", "Fold on the chain of 2N sites (N0 + N, the same absorber)", dims=dims)
        call h5_write(file, g // "richardson", task_grid(recs%richardson, nomega), "rad", &
            "Richardson extrapolation of the fold in dt (the method's order)", dims=dims)
        call h5_write(file, g // "error_estimate", task_grid(recs%error_estimate, nomega), &
            "rad", "Estimated error of /fold_amplitude: max(|A(dt/2) - A(dt)| / (2^p - 1), |A(2N) - A(N)|)", &
            dims=dims)
        call h5_write(file, g // "digits", task_grid(recs%digits, nomega), "1", &
            "Converged decimal digits of /fold_amplitude, floor(-log10(error_estimate / A_f))", dims=dims)
    end subroutine write_convergence

    !> `/cost`: what each continuation cost.
    subroutine write_cost(file, recs, nomega, elapsed)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The records, one per task.
        type(fold_record), intent(in) :: recs(:)
        !> Frequencies per curve.
        integer, intent(in) :: nomega
        !> Wall time of the scene (s); negative when unknown.
        real(wp), intent(in) :: elapsed
        character(len=*), parameter :: g = "/cost/", dims = "curve, omega"

        call h5_create_group(file, "/cost", "What each task cost (the convergence checks included)")
        call h5_write(file, g // "newton_iterations", task_igrid(recs%newton_iterations, &
            nomega), "1", "Newton-shooting iterations", dims=dims)
        call h5_write(file, g // "map_evaluations", task_igrid(recs%map_evaluations, &
            nomega), "1", "Evaluations of the map continued: the one-period map P, or for the branch from rest " &
            // "of the fold alone (floquet_every = 0) with /steps_per_period even the half-period map G (P = G o G); " &
            // "with the periods of P the fates watched (past a fold, a branch point, on the stairs past a torus) " &
            // "and the damped Newton-shooting from where the chain settled", dims=dims)
        call h5_write(file, g // "jacobians", task_igrid(recs%jacobians, nomega), "1", &
            "Of those, with the tangent (2N + 1 columns)", dims=dims)
        call h5_write(file, g // "factorizations", task_igrid(recs%factorizations, &
            nomega), "1", "LU factorisations of the shooting system", dims=dims)
        call h5_write(file, g // "eigen_calls", task_igrid(recs%eigen_calls, nomega), &
            "1", "Eigenvalue computations (Floquet multipliers)", dims=dims)
        call h5_write(file, g // "wall_time", task_grid(recs%wall_time, nomega), "s", &
            "Wall-clock time of the task (one thread)", dims=dims)
        call h5_write(file, g // "wall_time_map", task_grid(recs%time_map, nomega), "s", &
            "Of the wall time: evaluations of the period map alone", dims=dims)
        call h5_write(file, g // "wall_time_tangent", task_grid(recs%time_tangent, nomega), &
            "s", "Of the wall time: evaluations of the period map with its tangent (2N + 1 columns)", dims=dims)
        call h5_write(file, g // "wall_time_lu", task_grid(recs%time_lu, nomega), "s", &
            "Of the wall time: dense LU factorisations and solves of the shooting systems", dims=dims)
        call h5_write(file, g // "wall_time_eigen", task_grid(recs%time_eigen, nomega), "s", &
            "Of the wall time: eigenvalues of the monodromy matrices (Floquet multipliers)", dims=dims)
        if (elapsed >= 0.0_wp) call h5_write_attr(file, "/cost", "scene_wall_time_s", elapsed)
    end subroutine write_cost

    !> Units of a branch quantity.
    pure function branch_units(q) result(units)
        !> Index in `branch_quantities`.
        integer, intent(in) :: q
        character(len=:), allocatable :: units

        select case (trim(branch_quantities(q)))
        case ("amplitude", "umax", "residual")
            units = "rad"
        case ("energy")
            units = "energy"
        case default
            units = "1"
        end select
    end function branch_units

    !> Description of a branch quantity.
    pure function branch_description(q) result(text)
        !> Index in `branch_quantities`.
        integer, intent(in) :: q
        character(len=:), allocatable :: text

        select case (trim(branch_quantities(q)))
        case ("amplitude")
            text = "Driving amplitude A of each branch point"
        case ("umax")
            text = "Largest |u_n| over the chain and one drive period"
        case ("energy")
            text = "Stored energy of the chain, averaged over one drive period"
        case ("multiplier_max")
            text = "Largest modulus of the Floquet multipliers"
        case ("stable")
            text = "1 when every multiplier has modulus <= 1 + crossing_tol, else 0"
        case ("newton_iterations")
            text = "Newton-shooting iterations of the point"
        case default
            text = "max-norm of the shooting residual P(x) - x at the point"
        end select
    end function branch_description

end submodule supratrans_scene_continuation_output
