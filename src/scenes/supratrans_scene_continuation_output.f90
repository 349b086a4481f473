!> The file of the scene `continuation` (a submodule of `supratrans_scene_continuation`, whose interface declares
!> `write_continuation_file`, the binding `write_file` of its tasks): per (curve, Omega) the fold, the first loss of
!> stability and their statuses, the convergence of each fold and its cost, and the sampled branches and multipliers;
!> written atomically, as the final output or as the partial snapshot.
submodule(supratrans_scene_continuation) supratrans_scene_continuation_output
    implicit none

contains

    !> Tasks not done get NaN and status -1 (pending); the file is built in memory and written atomically (the
    !> interface, with its arguments, is in the parent module).
    module procedure write_continuation_file
        type(h5_file) :: file
        type(fold_record), allocatable :: recs(:)
        real(wp), allocatable :: branch(:, :, :), mult(:, :, :)
        integer :: ncurve, nomega, ntask, t, q, npts

        ncurve = size(self%runs)
        nomega = size(self%omegas)
        ntask = ncurve*nomega
        npts = self%cfg%scene%continuation_points
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
        call write_root(file, self%cfg, "continuation", "Fold (saddle-node) of the branch of driven periodic " &
                        // "states vs driving frequency: the supratransmission threshold of the model, one curve per " &
                        // "potential and varied value, with Floquet stability and convergence", self%inv)
        call h5_write_attr(file, "/", "complete", merge(1, 0, complete))
        call h5_write_attr(file, "/", "tasks_done", count(done))
        call write_parameters(file, self%cfg)
        call h5_write(file, "/omega", self%omegas, "1/time", &
            "Driving frequency Omega_i = omega_min + i omega_step", dims="omega")
        call write_curves(file, self%cfg, self%runs)
        ! the datasets of the record's scalar fields and their groups: the output table's (continuation.toml)
        call write_fold_scalars(file, recs%fold_scalars, nomega, real_str(self%cfg%scene%protocol%stair_height, 3), &
                                real_str(self%cfg%scene%protocol%stair_time, 4), &
                                int_str(self%cfg%scene%protocol%other_climbs), &
                                real_str(self%cfg%scene%protocol%switch_seed, 3))
        call h5_write_attr(file, "/fold_fate", "codes", fate_codes(self%cfg%scene%protocol))
        call h5_write_attr(file, "/transmission_status", "codes", transmission_status_codes(self%cfg%scene%protocol))
        call h5_write_attr(file, "/branch_switch", "codes", branch_switch_codes(self%cfg%scene%protocol))
        call h5_write_attr(file, "/instability_type", "codes", instability_type_codes())
        call h5_write_attr(file, "/threshold_kind", "codes", instability_type_codes())
        call h5_write_attr(file, "/status", "codes", "-2: outside gap (not computed); " &
            // "-1: pending (not computed yet); " // fold_status_codes())
        if (elapsed >= 0.0_wp) call h5_write_attr(file, "/cost", "scene_wall_time_s", elapsed)
        call h5_write(file, "/outside_gap", reshape(merge(1, 0, &
            [(self%omegas(mod(t - 1, nomega) + 1) >= band_gap_edge(self%runs((t - 1)/nomega + 1)%chain), &
            t=1, ntask)]), [nomega, ncurve]), "1", "1 where Omega >= sqrt(V''(0) + m^2), outside the curve's band gap: " &
            // "computed only with allow_outside_gap, and no fold is expected there", dims="curve, omega")
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

    end procedure write_continuation_file

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
