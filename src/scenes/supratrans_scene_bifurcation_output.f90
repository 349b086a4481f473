!> The file of the scene `bifurcation` (a submodule of `supratrans_scene_bifurcation`, whose interface declares
!> `write_bifurcation_file`, the binding `write_file` of its tasks, and `search_measured_costs`): the thresholds, the
!> continuum-limit threshold, the cost of each search, the detector sites and statuses, `/screening` and `/certify`
!> as (curve, omega) grids of the search records; written atomically, as the final output or as the partial snapshot,
!> and read back for the measured costs of `--costs`.
submodule(supratrans_scene_bifurcation) supratrans_scene_bifurcation_output
    use supratrans_curves, only: write_curves
    use supratrans_chain, only: detector_site
    use supratrans_threshold, only: search_status_codes
    use supratrans_search_record, only: to_values, certify_status_codes
    use supratrans_hdf5, only: h5_file, h5_create, h5_commit, h5_write_attr, h5_open, h5_close, h5_read, h5_read_attr, &
                               h5_exists
    use supratrans_output_rows, only: output_row, write_row, write_row_group, write_row_attr, row_type, &
        bifurcation_omega, bifurcation_threshold, bifurcation_threshold_as, bifurcation_cost, bifurcation_cost_runs, &
        bifurcation_cost_steps, bifurcation_cost_wall_time, bifurcation_cost_cpu_time, bifurcation_detector_site, &
        bifurcation_status, bifurcation_verdict_margin, bifurcation_thin_verdict, bifurcation_curves_screen_dt, &
        bifurcation_screening, bifurcation_screening_runs_screened, bifurcation_screening_runs_confirmed, &
        bifurcation_screening_runs_doubtful, bifurcation_screening_steps_screened, &
        bifurcation_screening_steps_confirmed, bifurcation_screening_screen_threshold, bifurcation_screening_band_low, &
        bifurcation_screening_band_high, bifurcation_screening_rounds, bifurcation_screening_disagreements, &
        bifurcation_screening_farthest_disagreement, bifurcation_certify, bifurcation_certify_threshold, &
        bifurcation_certify_status, bifurcation_certify_runs, bifurcation_certify_steps
    use supratrans_output, only: write_root, write_parameters
    implicit none

    !> A dataset of `/screening` or `/certify`: one field of the search records written as a (curve, omega) grid
    !> (of its row's type: an integer is a count or a status, written as default integers capped at huge(1)).
    type :: grid_dataset
        !> The field's name in `search_fields`.
        character(len=24) :: field
        !> The dataset's row of the output table.
        type(output_row) :: row
    end type grid_dataset

contains

    !> Write the scene's file `path` (built in memory, written atomically): tasks not done get NaN and status
    !> `bifurcation_pending`.
    module procedure write_bifurcation_file
        type(h5_file) :: file
        real(wp), allocatable :: vals(:, :)
        integer, allocatable :: nd(:, :)
        integer :: ncurve, nomega, ic, io

        ncurve = size(self%runs)
        nomega = size(self%omegas)
        ! the records as values in `search_fields` order; tasks not done as records with nothing searched
        vals = results
        do ic = 1, size(done)
            if (.not. done(ic)) vals(:, ic) = to_values(unsearched_record())
        end do
        allocate (nd(nomega, ncurve))
        do ic = 1, ncurve
            do io = 1, nomega
                nd(io, ic) = detector_site(self%curve_run_at(ic, io))
            end do
        end do

        call h5_create(file, path, .true.)
        call write_root(file, self%cfg, "bifurcation", "Supratransmission threshold (smallest transmitting driving " &
                        // "amplitude) vs driving frequency, one curve per potential and varied value", self%inv)
        call h5_write_attr(file, "/", "complete", merge(1, 0, complete))
        call h5_write_attr(file, "/", "tasks_done", count(done))
        call write_scene_parameters(file, self%cfg)
        call write_row(file, bifurcation_omega, self%omegas)
        call write_bifurcation_curves(file, self)
        call write_row(file, bifurcation_threshold, field_grid(vals, "threshold", nomega))
        call write_row(file, bifurcation_threshold_as, field_grid(vals, "threshold_as", nomega))
        call write_row_group(file, bifurcation_cost)
        call write_row(file, bifurcation_cost_runs, count_grid(vals, "runs", nomega))
        call write_row(file, bifurcation_cost_steps, count_grid(vals, "steps", nomega))
        call write_row(file, bifurcation_cost_wall_time, field_grid(vals, "wall_time", nomega))
        call write_row(file, bifurcation_cost_cpu_time, field_grid(vals, "cpu_time", nomega))
        if (elapsed >= 0.0_wp) call write_row_attr(file, bifurcation_cost, "scene_wall_time_s", elapsed)
        call write_row(file, bifurcation_detector_site, nd)
        call write_row(file, bifurcation_status, count_grid(vals, "status", nomega))
        call write_row_attr(file, bifurcation_status, "codes", "-2: outside gap (Omega >= " &
            // "sqrt(V''(0) + m^2): not searched; NaN); -1: pending (not computed yet); " // search_status_codes())
        call write_verdict_margins(file, vals, nomega, self%cfg%run%detect%thin_margin)
        call write_screening(file, self%cfg, vals, nomega)
        call write_certification(file, self%cfg, vals, nomega)
        call h5_commit(file, error)
    end procedure write_bifurcation_file

    !> `/verdict_margin` and `/thin_verdict`: how close the run just below each threshold came to transmitting
    !> (the margin the verdict already computes), and the threshold flagged thin where that margin is below
    !> `thin_margin` (CF flags: -1 no_margin, 0 clear, 1 thin).
    subroutine write_verdict_margins(file, vals, nomega, thin_margin)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The search records as values (`search_fields`, tasks).
        real(wp), intent(in) :: vals(:, :)
        !> Frequencies per curve.
        integer, intent(in) :: nomega
        !> &detect thin_margin: a margin below it is thin.
        real(wp), intent(in) :: thin_margin
        real(wp), allocatable :: margin(:, :)
        integer, allocatable :: thin(:, :)

        margin = field_grid(vals, "margin_below", nomega)
        allocate (thin(size(margin, 1), size(margin, 2)))
        thin = -1
        where (.not. ieee_is_nan(margin)) thin = merge(1, 0, margin < thin_margin)
        call write_row(file, bifurcation_verdict_margin, margin)
        call write_row(file, bifurcation_thin_verdict, thin)
        call write_row_attr(file, bifurcation_thin_verdict, "codes", "-1 no_margin: no threshold found above " &
                            // "amplitude_min (see /status); 0 clear: /verdict_margin >= thin_margin; 1 thin: " &
                            // "/verdict_margin < thin_margin, the detector's maximum just below the threshold near " &
                            // "its detect amplitude")
        call write_row_attr(file, bifurcation_thin_verdict, "flag_values", [-1, 0, 1])
        call write_row_attr(file, bifurcation_thin_verdict, "flag_meanings", "no_margin clear thin")
        call write_row_attr(file, bifurcation_thin_verdict, "thin_margin", thin_margin)
        call write_row_attr(file, bifurcation_thin_verdict, "thin_verdicts", count(thin == 1))
    end subroutine write_verdict_margins

    !> The measured cost of every search in `path`, an earlier output (or merged file) of the same study: its
    !> `/cost/cpu_time` (curve, omega), by task index (`/cost/wall_time` in a file written before it was recorded):
    !> the processor time of a search repeats from run to run on a shared machine, its wall time does not. The file
    !> must be a bifurcation output with the same frequencies (`/omega`) and curves (`/curves/gamma`, `beta`, `m2`),
    !> else it is refused in one line.
    module procedure search_measured_costs
        type(h5_file) :: file
        type(error_type), allocatable :: cause, ignored
        character(len=:), allocatable :: kind
        real(wp), allocatable :: grid(:, :), axis(:), gamma(:), beta(:), m2(:)
        integer :: ic

        call h5_open(file, path, cause)
        if (allocated(cause)) then
            call fatal_error(error, "--costs " // printable(path) // ": " // cause%message, err_input)
            return
        end if
        call h5_read_attr(file, "/parameters", "kind", kind, cause)
        if (.not. allocated(cause)) then
            if (kind /= trim(self%cfg%scene%kind)) then        ! the earlier output of another scene
                call fatal_error(error, "--costs " // printable(path) // ": an output of a '" // printable(kind) &
                                 // "' scene, not of this " // trim(self%cfg%scene%kind) // " study", err_input)
            end if
        end if
        if (.not. allocated(cause) .and. .not. allocated(error)) call h5_read(file, "/omega", axis, cause)
        if (.not. allocated(cause) .and. .not. allocated(error)) call h5_read(file, "/curves/gamma", gamma, cause)
        if (.not. allocated(cause) .and. .not. allocated(error)) call h5_read(file, "/curves/beta", beta, cause)
        if (.not. allocated(cause) .and. .not. allocated(error)) call h5_read(file, "/curves/m2", m2, cause)
        if (.not. allocated(cause) .and. .not. allocated(error)) then
            if (.not. same(axis, self%omegas) .or. .not. same(gamma, [(self%runs(ic)%chain%gamma, ic = 1, &
                size(self%runs))]) .or. .not. same(beta, [(self%runs(ic)%chain%beta, ic = 1, size(self%runs))]) &
                .or. .not. same(m2, [(self%runs(ic)%chain%m2, ic = 1, size(self%runs))])) then
                call fatal_error(error, "--costs " // printable(path) // ": of another study (its frequencies or " &
                                 // "curves are not this namelist's)", err_input)
            end if
        end if
        if (.not. allocated(cause) .and. .not. allocated(error)) then
            if (h5_exists(file, "/cost/cpu_time")) then
                call h5_read(file, "/cost/cpu_time", grid, cause)
            else
                call h5_read(file, "/cost/wall_time", grid, cause)
            end if
            if (allocated(cause)) call fatal_error(error, "--costs " // printable(path) // ": lacks the searches' " &
                                                   // "measured costs (/cost/cpu_time)", err_input)
        end if
        call h5_close(file, ignored)
        if (allocated(error)) return
        if (allocated(cause)) then
            call fatal_error(error, "--costs " // printable(path) // ": not a bifurcation output (" &
                             // cause%message // ")", err_input)
            return
        end if
        costs = reshape(grid, [size(grid)])     ! (omega, curve) in Fortran order: task (curve - 1) nomega + iomega

    contains

        !> Equal lengths and values (to 1e-12 relative: the same namelist gives the same bits).
        pure logical function same(a, b)
            real(wp), intent(in) :: a(:), b(:)

            same = size(a) == size(b)
            if (same) same = all(abs(a - b) <= 1.0e-12_wp*max(1.0_wp, abs(b)))
        end function same

    end procedure search_measured_costs

    !> One field of the search records, by its name in `search_fields`, as an (omega, curve) grid.
    pure function field_grid(vals, name, nomega) result(g)
        !> The search records as values (`search_fields`, tasks; omega fastest).
        real(wp), intent(in) :: vals(:, :)
        !> Name of the field.
        character(len=*), intent(in) :: name
        !> Frequencies per curve.
        integer, intent(in) :: nomega
        real(wp), allocatable :: g(:, :)

        g = reshape(vals(findloc(search_fields, name, dim=1), :), [nomega, size(vals, 2)/nomega])
    end function field_grid

    !> An integer field of the search records (a count or a status), by name, as an (omega, curve) grid of default
    !> integers (counts capped at huge(1)).
    pure function count_grid(vals, name, nomega) result(g)
        !> The search records as values (`search_fields`, tasks; omega fastest).
        real(wp), intent(in) :: vals(:, :)
        !> Name of the field.
        character(len=*), intent(in) :: name
        !> Frequencies per curve.
        integer, intent(in) :: nomega
        integer, allocatable :: g(:, :)

        g = nint(min(field_grid(vals, name, nomega), real(huge(1), wp)))
    end function count_grid

    !> `/screening`: which runs of each search the screening method answered and which the scene's method confirmed.
    subroutine write_screening(file, cfg, vals, nomega)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The input.
        type(input_config), intent(in) :: cfg
        !> The search records as values (`search_fields`, tasks).
        real(wp), intent(in) :: vals(:, :)
        !> Frequencies per curve.
        integer, intent(in) :: nomega
        type(output_row), parameter :: g = bifurcation_screening
        type(grid_dataset), parameter :: datasets(*) = [ &
            grid_dataset("runs_screened", bifurcation_screening_runs_screened), &
            grid_dataset("runs_confirmed", bifurcation_screening_runs_confirmed), &
            grid_dataset("runs_doubtful", bifurcation_screening_runs_doubtful), &
            grid_dataset("steps_screened", bifurcation_screening_steps_screened), &
            grid_dataset("steps_confirmed", bifurcation_screening_steps_confirmed), &
            grid_dataset("screen_threshold", bifurcation_screening_screen_threshold), &
            grid_dataset("band_low", bifurcation_screening_band_low), &
            grid_dataset("band_high", bifurcation_screening_band_high), &
            grid_dataset("rounds", bifurcation_screening_rounds), &
            grid_dataset("disagreements", bifurcation_screening_disagreements), &
            grid_dataset("farthest_disagreement", bifurcation_screening_farthest_disagreement)]

        call write_row_group(file, g)
        call write_row_attr(file, g, "screen_method", trim(screen_choices(cfg%scene%screen_method)))
        call write_row_attr(file, g, "screen_dt", screen_dt(cfg, cfg%run))
        call write_row_attr(file, g, "confirm_band", cfg%scene%confirm_band)
        call write_row_attr(file, g, "screen_margin", cfg%scene%screen_margin)
        call write_grids(file, datasets, vals, nomega)
    end subroutine write_screening

    !> `/certify`: each threshold rechecked with the scene's method at dt/2 (only when `certify` is on).
    subroutine write_certification(file, cfg, vals, nomega)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The input.
        type(input_config), intent(in) :: cfg
        !> The search records as values (`search_fields`, tasks).
        real(wp), intent(in) :: vals(:, :)
        !> Frequencies per curve.
        integer, intent(in) :: nomega
        type(output_row), parameter :: g = bifurcation_certify
        type(grid_dataset), parameter :: datasets(*) = [ &
            grid_dataset("certified_threshold", bifurcation_certify_threshold), &
            grid_dataset("certify_status", bifurcation_certify_status), &
            grid_dataset("certify_runs", bifurcation_certify_runs), &
            grid_dataset("certify_steps", bifurcation_certify_steps)]

        if (.not. cfg%scene%certify) return
        call write_row_group(file, g)
        call write_row_attr(file, g, "dt", cfg%run%numerics%dt/2.0_wp)
        call write_row_attr(file, g, "flagged", count(count_grid(vals, "certify_status", nomega) >= certify_moved))
        call write_grids(file, datasets, vals, nomega)
        call write_row_attr(file, bifurcation_certify_status, "codes", certify_status_codes())
    end subroutine write_certification

    !> Datasets of a group, each a field of the search records as a (curve, omega) grid (`grid_dataset`).
    subroutine write_grids(file, datasets, vals, nomega)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> What to write.
        type(grid_dataset), intent(in) :: datasets(:)
        !> The search records as values (`search_fields`, tasks).
        real(wp), intent(in) :: vals(:, :)
        !> Frequencies per curve.
        integer, intent(in) :: nomega
        integer :: i

        do i = 1, size(datasets)
            associate (d => datasets(i))
                if (row_type(d%row) == "integer") then
                    call write_row(file, d%row, count_grid(vals, trim(d%field), nomega))
                else
                    call write_row(file, d%row, field_grid(vals, trim(d%field), nomega))
                end if
            end associate
        end do
    end subroutine write_grids

    !> `/parameters`: every input key (`write_parameters`), the coarse step the search used, and
    !> `stop_when_decided` = 1 (every run of the search stops once decided).
    subroutine write_scene_parameters(file, cfg)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The input.
        type(input_config), intent(in) :: cfg
        character(len=*), parameter :: g = "/parameters"

        call write_parameters(file, cfg)
        call h5_write_attr(file, g, "coarse_step_used", &
            effective_coarse_step(cfg%scene%coarse_step, cfg%scene%resolution))
        call h5_write_attr(file, g, "stop_when_decided", .true.)
    end subroutine write_scene_parameters

    !> `/curves` (`write_curves` of `supratrans_curves`, the same in every scene) and, with screening, each curve's
    !> screening time step `/curves/screen_dt`.
    subroutine write_bifurcation_curves(file, tasks)
        !> Open output file (a failure sticks in it).
        type(h5_file), intent(inout) :: file
        !> The tasks.
        type(bifurcation_tasks), intent(in) :: tasks
        real(wp) :: sdt(size(tasks%runs))
        integer :: ic

        call write_curves(file, tasks%cfg, tasks%runs)
        do ic = 1, size(tasks%runs)
            sdt(ic) = screen_dt(tasks%cfg, curve_run(tasks%cfg, ic))
        end do
        if (tasks%cfg%scene%screen_method /= screen_none) call write_row(file, bifurcation_curves_screen_dt, sdt)
    end subroutine write_bifurcation_curves

end submodule supratrans_scene_bifurcation_output
