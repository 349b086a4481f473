!> The file of the scene `continuation` (a submodule of `supratrans_scene_continuation`, whose interface declares
!> `write_continuation_file`, the binding `write_file` of its tasks): per (curve, Omega) the fold, the first loss of
!> stability and their statuses, the convergence of each fold and its cost, and the sampled branches and multipliers;
!> written atomically, as the final output or as the partial snapshot.
submodule(supratrans_scene_continuation) supratrans_scene_continuation_output
    use supratrans_output_rows, only: output_row, write_row, write_row_group, write_row_attr, continuation_omega, &
        continuation_fold_fate, continuation_transmission_status, continuation_branch_switch, &
        continuation_instability_type, continuation_threshold_kind, continuation_status, continuation_cost, &
        continuation_outside_gap, continuation_multipliers, continuation_multipliers_real, &
        continuation_multipliers_imag, continuation_multipliers_amplitude, continuation_branch_amplitude, &
        continuation_branch_umax, continuation_branch_energy, continuation_branch_multiplier_max, &
        continuation_branch_stable, continuation_branch_newton_iterations, continuation_branch_residual
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
        call write_row(file, continuation_omega, self%omegas)
        call write_curves(file, self%cfg, self%runs)
        ! the datasets of the record's scalar fields and their groups: the output table's (continuation.toml)
        call write_fold_scalars(file, [recs%fold_scalars], nomega, real_str(self%cfg%scene%protocol%stair_height, 3), &
                                real_str(self%cfg%scene%protocol%stair_time, 4), &
                                int_str(self%cfg%scene%protocol%other_climbs), &
                                real_str(self%cfg%scene%protocol%switch_seed, 3))
        call write_row_attr(file, continuation_fold_fate, "codes", fate_codes(self%cfg%scene%protocol))
        call write_row_attr(file, continuation_transmission_status, "codes", &
                            transmission_status_codes(self%cfg%scene%protocol))
        call write_row_attr(file, continuation_branch_switch, "codes", branch_switch_codes(self%cfg%scene%protocol))
        call write_row_attr(file, continuation_instability_type, "codes", instability_type_codes())
        call write_row_attr(file, continuation_threshold_kind, "codes", instability_type_codes())
        call write_row_attr(file, continuation_status, "codes", "-2: outside gap (not computed); " &
            // "-1: pending (not computed yet); " // fold_status_codes())
        if (elapsed >= 0.0_wp) call write_row_attr(file, continuation_cost, "scene_wall_time_s", elapsed)
        call write_row(file, continuation_outside_gap, reshape(merge(1, 0, &
            [(self%omegas(mod(t - 1, nomega) + 1) >= band_gap_edge(self%runs((t - 1)/nomega + 1)%chain), &
            t=1, ntask)]), [nomega, ncurve]))
        allocate (branch(npts, nomega, ncurve))
        do q = 1, size(branch_quantities)
            do t = 1, ntask
                branch(:, mod(t - 1, nomega) + 1, (t - 1)/nomega + 1) = recs(t)%branch(q, :)
            end do
            call write_row(file, branch_row(q), branch)
        end do
        call write_row_group(file, continuation_multipliers)
        allocate (mult(kept_multipliers, multiplier_samples, ntask))
        do t = 1, ntask
            mult(:, :, t) = recs(t)%multiplier_re
        end do
        call write_row(file, continuation_multipliers_real, mult)
        do t = 1, ntask
            mult(:, :, t) = recs(t)%multiplier_im
        end do
        call write_row(file, continuation_multipliers_imag, mult)
        call write_row(file, continuation_multipliers_amplitude, reshape([(recs(t)%multiplier_amplitude, t=1, ntask)], &
                       [multiplier_samples, ntask]))
        call h5_commit(file, error)

    end procedure write_continuation_file

    !> The row of `/branch/<quantity>` of a branch quantity (its units and description: continuation.toml).
    pure function branch_row(q) result(row)
        !> Index in `branch_quantities`.
        integer, intent(in) :: q
        type(output_row) :: row

        select case (trim(branch_quantities(q)))
        case ("amplitude")
            row = continuation_branch_amplitude
        case ("umax")
            row = continuation_branch_umax
        case ("energy")
            row = continuation_branch_energy
        case ("multiplier_max")
            row = continuation_branch_multiplier_max
        case ("stable")
            row = continuation_branch_stable
        case ("newton_iterations")
            row = continuation_branch_newton_iterations
        case default
            row = continuation_branch_residual
        end select
    end function branch_row

end submodule supratrans_scene_continuation_output
