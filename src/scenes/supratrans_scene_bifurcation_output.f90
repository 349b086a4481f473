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
    use supratrans_hdf5, only: h5_file, h5_create, h5_commit, h5_write, h5_write_attr, h5_create_group, h5_open, &
                               h5_close, h5_read, h5_read_attr, h5_exists
    use supratrans_output, only: write_root, write_parameters
    use supratrans_bifurcation_runs, only: with_omega
    implicit none

    !> A dataset of `/screening` or `/certify`: one field of the search records written as a (curve, omega) grid.
    type :: grid_dataset
        !> The field's name in `search_fields`.
        character(len=24) :: field
        !> The dataset's name in its group.
        character(len=24) :: name
        !> Units attribute.
        character(len=4) :: units
        !> A count or a status (written as default integers, capped at huge(1)), else a real value.
        logical :: count
        !> Description attribute.
        character(len=120) :: description
    end type grid_dataset

contains

    !> Write the scene's file `path` (built in memory, written atomically): tasks not done get NaN and status
    !> `bifurcation_pending`.
    module subroutine write_bifurcation_file(self, path, results, done, complete, elapsed, error)
        !> The tasks.
        class(bifurcation_tasks), intent(in) :: self
        !> Final path of the file.
        character(len=*), intent(in) :: path
        !> Results, (values, tasks).
        real(wp), intent(in) :: results(:, :)
        !> Which tasks are done.
        logical, intent(in) :: done(:)
        !> Whether this is the complete result (root attribute `complete`).
        logical, intent(in) :: complete
        !> Wall time of the scene (s); negative when unknown (partial files).
        real(wp), intent(in) :: elapsed
        !> Error, allocated on failure (the file is then not created).
        type(error_type), allocatable, intent(out) :: error
        type(h5_file) :: file
        real(wp), allocatable :: vals(:, :)
        integer, allocatable :: nd(:, :)
        integer :: ncurve, nomega, ic, io
        character(len=*), parameter :: dims = "curve, omega"

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
                nd(io, ic) = detector_site(with_omega(self%runs(ic), self%omegas(io)))
            end do
        end do

        call h5_create(file, path, .true.)
        call write_root(file, self%cfg, "bifurcation", "Supratransmission threshold (smallest transmitting driving " &
                        // "amplitude) vs driving frequency, one curve per potential and varied value", self%inv)
        call h5_write_attr(file, "/", "complete", merge(1, 0, complete))
        call h5_write_attr(file, "/", "tasks_done", count(done))
        call write_scene_parameters(file, self%cfg)
        call h5_write(file, "/omega", self%omegas, "1/time", &
            "Driving frequency Omega_i = omega_min + i omega_step", dims="omega")
        call write_bifurcation_curves(file, self)
        call h5_write(file, "/threshold", field_grid(vals, "threshold", nomega), "rad", "Smallest driving amplitude " &
                      // "A (grid amplitude_min + k resolution) at which the run transmits: the supratransmission " &
                      // "threshold; NaN when not found (see /status)", dims=dims)
        call h5_write(file, "/threshold_As", field_grid(vals, "threshold_as", nomega), "rad", "Continuum-limit " &
                      // "threshold A_s = 4 arctan(lambda c / Omega) of the curve's chain (undamped theory); NaN " &
                      // "outside the band gap", dims=dims)
        call h5_create_group(file, "/cost", "What each threshold search cost")
        call h5_write(file, "/cost/runs", count_grid(vals, "runs", nomega), &
            "1", "Simulations run by the search (coarse scan + fine scan)", dims=dims)
        call h5_write(file, "/cost/steps", &
            count_grid(vals, "steps", nomega), "1", &
            "Time steps taken by all the search's simulations (transmitting runs stop when decided)", dims=dims)
        call h5_write(file, "/cost/wall_time", field_grid(vals, "wall_time", nomega), &
            "s", "Wall-clock time of the search (one thread)", dims=dims)
        call h5_write(file, "/cost/cpu_time", field_grid(vals, "cpu_time", nomega), "s", "Processor time of the " &
            // "search's thread: its cost whatever else the machine ran (--costs deals slices by it)", dims=dims)
        if (elapsed >= 0.0_wp) call h5_write_attr(file, "/cost", "scene_wall_time_s", elapsed)
        call h5_write(file, "/detector_site", nd, "1", &
            "Detector site n_d of the verdict (a run transmits once |u_n| > detect amplitude for some n > n_d)", &
            dims=dims)
        call h5_write(file, "/status", count_grid(vals, "status", nomega), &
            "1", "Outcome of the search (codes in attribute 'codes')", dims=dims)
        call h5_write_attr(file, "/status", "codes", "-2: outside gap (Omega >= " &
            // "sqrt(V''(0) + m^2): not searched; NaN); -1: pending (not computed yet); " // search_status_codes())
        call write_verdict_margins(file, vals, nomega, self%cfg%run%detect%thin_margin)
        call write_screening(file, self%cfg, vals, nomega)
        call write_certification(file, self%cfg, vals, nomega)
        call h5_commit(file, error)
    end subroutine write_bifurcation_file

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
        character(len=*), parameter :: dims = "curve, omega"

        margin = field_grid(vals, "margin_below", nomega)
        allocate (thin(size(margin, 1), size(margin, 2)))
        thin = -1
        where (.not. ieee_is_nan(margin)) thin = merge(1, 0, margin < thin_margin)
        call h5_write(file, "/verdict_margin", margin, "1", "Margin of the verdict of the run one resolution below " &
                      // "the threshold (quiet, run to T): 1 - max|u_n|/a beyond the detector site, a the detect " &
                      // "amplitude; NaN unless status is 0 (found above amplitude_min)", dims=dims)
        call h5_write(file, "/thin_verdict", thin, "1", "The threshold is a thin verdict: the run just below it " &
                      // "came within thin_margin of the detect amplitude (codes in attribute 'codes')", dims=dims)
        call h5_write_attr(file, "/thin_verdict", "codes", "-1 no_margin: no threshold found above " &
                           // "amplitude_min (see /status); 0 clear: /verdict_margin >= thin_margin; 1 thin: " &
                           // "/verdict_margin < thin_margin, the detector's maximum just below the threshold near " &
                           // "its detect amplitude")
        call h5_write_attr(file, "/thin_verdict", "flag_values", [-1, 0, 1])
        call h5_write_attr(file, "/thin_verdict", "flag_meanings", "no_margin clear thin")
        call h5_write_attr(file, "/thin_verdict", "thin_margin", thin_margin)
        call h5_write_attr(file, "/thin_verdict", "thin_verdicts", count(thin == 1))
    end subroutine write_verdict_margins

    !> The measured cost of every search in `path`, an earlier output (or merged file) of the same study: its
    !> `/cost/cpu_time` (curve, omega), by task index (`/cost/wall_time` in a file written before it was recorded):
    !> the processor time of a search repeats from run to run on a shared machine, its wall time does not. The file
    !> must be a bifurcation output with the same frequencies (`/omega`) and curves (`/curves/gamma`, `beta`, `m2`),
    !> else it is refused in one line.
    module subroutine search_measured_costs(self, path, costs, error)
        !> The tasks.
        class(bifurcation_tasks), intent(in) :: self
        !> The earlier output.
        character(len=*), intent(in) :: path
        !> Measured processor time (or wall time) of each search (s), by task index.
        real(wp), allocatable, intent(out) :: costs(:)
        !> Error: unreadable, of another study, or without costs.
        type(error_type), allocatable, intent(out) :: error
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

    end subroutine search_measured_costs

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
        character(len=*), parameter :: g = "/screening"
        type(grid_dataset), parameter :: datasets(*) = [ &
            grid_dataset("runs_screened", "runs_screened", "1", .true., "Simulations run by the screening method"), &
            grid_dataset("runs_confirmed", "runs_confirmed", "1", .true., &
                         "Simulations run by the scene's method (every verdict near the threshold)"), &
            grid_dataset("runs_doubtful", "runs_doubtful", "1", .true., &
                         "Screening runs quiet with a margin below screen_margin, run again by the scene's method"), &
            grid_dataset("steps_screened", "steps_screened", "1", .true., "Time steps of the screening runs"), &
            grid_dataset("steps_confirmed", "steps_confirmed", "1", .true., "Time steps of the scene method's runs"), &
            grid_dataset("screen_threshold", "screen_threshold", "rad", .false., "Threshold the screening method " &
                         // "alone finds (its bracket bisected); NaN when none or not screened"), &
            grid_dataset("band_low", "band_low", "rad", .false., &
                         "Lowest amplitude of the confirmation band; NaN when not screened"), &
            grid_dataset("band_high", "band_high", "rad", .false., &
                         "Highest amplitude of the confirmation band; NaN when not screened"), &
            grid_dataset("rounds", "rounds", "1", .true., &
                         "Searches with the confirmation band (more than 1: the band grew)"), &
            grid_dataset("disagreements", "disagreements", "1", .true., &
                         "Amplitudes answered by both methods with different verdicts"), &
            grid_dataset("farthest_disagreement", "farthest_disagreement", "rad", .false., "Largest distance " &
                         // "between the threshold and an amplitude where the two methods disagree (0 when none)")]

        call h5_create_group(file, g, "Screening of each threshold search: amplitudes far below the threshold are " &
            // "answered by the screening method, every amplitude the search asked within [band_low, band_high] by " &
            // "the scene's &numerics method (README, Screening)")
        call h5_write_attr(file, g, "screen_method", trim(screen_choices(cfg%scene%screen_method)))
        call h5_write_attr(file, g, "screen_dt", screen_dt(cfg, cfg%run))
        call h5_write_attr(file, g, "confirm_band", cfg%scene%confirm_band)
        call h5_write_attr(file, g, "screen_margin", cfg%scene%screen_margin)
        call write_grids(file, g, datasets, vals, nomega)
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
        character(len=*), parameter :: g = "/certify"
        type(grid_dataset), parameter :: datasets(*) = [ &
            grid_dataset("certified_threshold", "threshold", "rad", .false., &
                         "Threshold at dt/2 near the threshold; NaN when not checked or not found"), &
            grid_dataset("certify_status", "status", "1", .true., &
                         "Outcome of the check (codes in attribute 'codes'); >= 2 is flagged"), &
            grid_dataset("certify_runs", "runs", "1", .true., "Simulations at dt/2 run by the check"), &
            grid_dataset("certify_steps", "steps", "1", .true., "Time steps of those simulations")]

        if (.not. cfg%scene%certify) return
        call h5_create_group(file, g, "Each threshold rechecked with the scene's method at dt/2: the threshold must " &
            // "transmit and the grid point below it must not; otherwise the dt/2 threshold within one coarse step")
        call h5_write_attr(file, g, "dt", cfg%run%numerics%dt/2.0_wp)
        call h5_write_attr(file, g, "flagged", count(count_grid(vals, "certify_status", nomega) >= certify_moved))
        call write_grids(file, g, datasets, vals, nomega)
        call h5_write_attr(file, g // "/status", "codes", certify_status_codes())
    end subroutine write_certification

    !> Datasets of a group, each a field of the search records as a (curve, omega) grid (`grid_dataset`).
    subroutine write_grids(file, group, datasets, vals, nomega)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The group the datasets go into.
        character(len=*), intent(in) :: group
        !> What to write.
        type(grid_dataset), intent(in) :: datasets(:)
        !> The search records as values (`search_fields`, tasks).
        real(wp), intent(in) :: vals(:, :)
        !> Frequencies per curve.
        integer, intent(in) :: nomega
        character(len=*), parameter :: dims = "curve, omega"
        integer :: i

        do i = 1, size(datasets)
            associate (d => datasets(i))
                if (d%count) then
                    call h5_write(file, group // "/" // trim(d%name), count_grid(vals, trim(d%field), nomega), &
                                  trim(d%units), trim(d%description), dims=dims)
                else
                    call h5_write(file, group // "/" // trim(d%name), field_grid(vals, trim(d%field), nomega), &
                                  trim(d%units), trim(d%description), dims=dims)
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
        if (tasks%cfg%scene%screen_method /= screen_none) call h5_write(file, &
            "/curves/screen_dt", sdt, "time", "Time step of each curve's screening runs (/screening)", dims="curve")
    end subroutine write_bifurcation_curves

end submodule supratrans_scene_bifurcation_output
