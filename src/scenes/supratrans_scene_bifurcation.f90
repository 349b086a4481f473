!> Scene `bifurcation` (paper Sec. 4.3, Figs. Bif1-Bif3): the smallest driving amplitude at which supratransmission
!> begins, as a function of the driving frequency, one curve per potential and value of the varied parameter.
!>
!> For each curve and each frequency Omega_i = omega_min + i omega_step <= omega_max (i = 0, 1, ...; integer index),
!> one task searches the threshold with `find_threshold` (supratrans_threshold): coarse upward scan of
!> [amplitude_min, amplitude_max] in steps of `coarse_step`, then a scan of the bracket at `resolution`. Its oracle is
!> one `simulate` of the curve's run at (Omega_i, A) with `detect%stop_when_decided = .true.`: a transmitting run
!> stops as soon as an oscillator beyond the detector site passes the detection amplitude (pi), a
!> non-transmitting one runs to T. Frequencies outside the curve's band gap, Omega >= sqrt(1 + m^2), are skipped
!> (threshold NaN, status `bifurcation_outside_gap`) unless `allow_outside_gap` is set.
!>
!> The tasks (curves x frequencies) run on OpenMP threads through `supratrans_tasks` (dynamic scheduling, journal
!> `<output>.journal` tied to the namelist by `file_fingerprint`, partial output `<output>.partial.h5` with root
!> attribute `complete = 0` now and then). Each task is one sequential search and results are stored by task index,
!> so the thresholds are bit-for-bit identical for any number of threads. The final file is written as
!> `<output>.tmp-XXXXXX` and renamed when complete (`complete = 1`); the journal and the partial file are then deleted.
!>
!> Where the verdict is not monotone in A on the scale of the resolution (undamped sine-Gordon below Omega ~ 0.5,
!> the paper's "discrepancy region": e.g. at Omega = 0.05, A = 5.96 and 5.97 transmit, 5.98 .. 6.00 do not, 6.01
!> does), the threshold found depends on which coarse points the scan asks (see the assumption documented in
!> `supratrans_threshold`): there it is the smallest transmitting amplitude above the last quiet coarse point.
!> Measured on the undamped sine-Gordon diagram (Omega = 0.05 .. 0.99 by 0.01) with coarse steps 0.1 .. 0.3: 11 of
!> 95 thresholds differ between coarse steps, all at Omega <= 0.47, by up to 0.51 (Omega = 0.43).
module supratrans_scene_bifurcation
    use, intrinsic :: iso_fortran_env, only: error_unit
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp, i8
    use supratrans_error, only: error_type, fatal_error, err_input, err_io
    use supratrans_invocation, only: invocation_type
    use supratrans_scene, only: scene_type, scene_budget
    use supratrans_limits, only: axis_points, check_axis, check_tasks, sci
    use supratrans_config, only: input_config, run_config, method_newton, method_linearized, method_rk4, method_rk8, &
        screen_none, screen_newton, screen_linearized, screen_rk4, screen_rk8, screen_choices
    use supratrans_curves, only: curve_count, curve_run, write_curves
    use supratrans_chain, only: threshold_as, band_gap_edge, detector_site, stable_by_paper_condition
    use supratrans_potential, only: potential_name
    use supratrans_simulate, only: simulate, number_of_levels
    use supratrans_result, only: run_result, run_ok, status_name
    use supratrans_threshold, only: verdict_oracle, find_threshold, effective_coarse_step, search_grid_size, &
                                    search_status_codes, search_found, search_failed
    use supratrans_screened_search, only: find_threshold_screened, screen_report
    use supratrans_status, only: bifurcation_outside_gap => status_outside_gap, bifurcation_pending => status_not_run
    use supratrans_search_record, only: search_record, search_fields, to_values, from_values, certify_status_codes, &
                                        certify_not_checked, certify_unchanged, certify_moved_within, certify_moved, &
                                        certify_unresolved, certify_failed
    use supratrans_tasks, only: task_list, run_tasks, input_fingerprint, engine_only, run_work
    use supratrans_checkpoint, only: checkpoint_session, open_session, close_session
    use supratrans_system, only: remove_file
    use supratrans_hdf5, only: h5_file, h5_create, h5_commit, h5_write, h5_write_attr, h5_create_group, h5_open, &
                               h5_close, h5_read, h5_read_attr
    use supratrans_output, only: write_root, write_parameters
    use supratrans_strings, only: int_str, real_str, fixed1, printable
    implicit none
    private

    public :: run_bifurcation, bifurcation_omegas


    !> Status of a task whose frequency lies outside the curve's band gap (not searched; threshold NaN), and of a
    !> task not computed yet (partial files): the task codes of `supratrans_status`, shared by every scene.
    public :: bifurcation_outside_gap, bifurcation_pending

    !> Oracle of the search: one simulation of `run` at the amplitude asked, stopped as soon as it transmits.
    !> `transmits` runs inside OpenMP threads and builds no text (gfortran 12 keeps the lengths of deferred-length
    !> function results in statics, see `supratrans_strings`): a failure is kept as numbers and the run's own
    !> reason, and `failure_reason` formats it (call it from one thread at a time).
    type, extends(verdict_oracle) :: simulation_oracle
        !> The run (drive frequency set; the amplitude is set per question).
        type(run_config) :: run
        !> The last run failed before its verdict.
        logical :: run_failed = .false.
        !> Amplitude of the failed run.
        real(wp) :: failed_amplitude = 0.0_wp
        !> Status of the failed run (`supratrans_result` codes).
        integer :: failed_status = run_ok
        !> The failed run's own reason.
        character(len=:), allocatable :: reason
        !> Margin of the last run's verdict (`run_result%verdict_margin`).
        real(wp) :: last_margin = 1.0_wp
        !> The checkpoints of the task (every oracle of one search shares them), or null.
        type(checkpoint_session), pointer :: session => null()
    contains
        !> One simulation: transmitting or not, and the time steps it took.
        procedure :: transmits => simulation_transmits
        !> Whether the last run failed before its verdict.
        procedure :: failed => simulation_failed
        !> Why it failed.
        procedure :: failure_reason => simulation_failure_reason
        !> The margin of the last verdict.
        procedure :: margin => simulation_margin
    end type simulation_oracle

    !> The tasks of a bifurcation scene: task t = (curve - 1) nomega + iomega searches one threshold.
    type, extends(task_list) :: bifurcation_tasks
        !> The validated input.
        type(input_config) :: cfg
        !> How the engine is invoked (slice, merge: `supratrans_invocation`).
        type(invocation_type) :: inv
        !> Run of each curve, prepared for the search (early stop, nothing recorded).
        type(run_config), allocatable :: runs(:)
        !> The same with the screening method and step (allocated when the scene screens).
        type(run_config), allocatable :: screen_runs(:)
        !> The same at dt/2 (allocated when the scene certifies).
        type(run_config), allocatable :: half_runs(:)
        !> The frequencies.
        real(wp), allocatable :: omegas(:)
        !> Path of the partial output written by `snapshot`.
        character(len=:), allocatable :: partial_path
        !> Mid-run checkpoints of task t: `<checkpoint_prefix><t>`, bound to `fingerprint` and t.
        character(len=:), allocatable :: checkpoint_prefix, fingerprint
    contains
        !> Search the threshold of one task.
        procedure :: run => run_search
        !> Whether a task's record is a result (not one stopped by a signal at a checkpoint).
        procedure :: finished => search_finished
        !> Write the partial output.
        procedure :: snapshot => write_snapshot
        !> Estimated cost of one search (slices of equal cost).
        procedure :: cost => search_cost
        !> The searches' measured wall times in an earlier output of the same study (`--costs`).
        procedure :: measured_costs => search_measured_costs
    end type bifurcation_tasks

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

    !> The scene `bifurcation`: one threshold search A_th per (curve, frequency).
    type, extends(scene_type), public :: bifurcation_scene
    contains
        !> Run it and write its output (`run_bifurcation`).
        procedure :: run => bifurcation_scene_run
        !> Its axes, tasks, work and memory against the limits.
        procedure :: check_limits => bifurcation_scene_limits
    end type bifurcation_scene

contains

    !> Run the bifurcation scene described by `cfg` and write `cfg%output%file` (see the module documentation).
    subroutine run_bifurcation(cfg, error, keep_journal, inv)
        !> The validated input (`&scene kind = 'bifurcation'`).
        type(input_config), intent(in) :: cfg
        !> Error, allocated on failure (output exists, journal of another input, unwritable files).
        type(error_type), allocatable, intent(out) :: error
        !> Keep the journal after a complete run (tests of the resume); default false.
        logical, intent(in), optional :: keep_journal
        !> How the engine is invoked (a slice, a merge: `supratrans_invocation`); default: the whole scene.
        type(invocation_type), intent(in), optional :: inv
        type(bifurcation_tasks) :: tasks
        type(search_record), allocatable :: records(:)
        real(wp), allocatable :: results(:, :)
        logical, allocatable :: done(:)
        character(len=:), allocatable :: output, journal
        integer :: ncurve, nomega, ic
        integer(i8) :: clock_start, clock_end, clock_rate
        logical :: exists, keep
        real(wp) :: elapsed
        character(len=24) :: steps_text

        call system_clock(clock_start, clock_rate)
        keep = .false.
        if (present(keep_journal)) keep = keep_journal
        output = trim(cfg%output%file)
        inquire (file=output, exist=exists)
        if (exists .and. .not. cfg%output%overwrite) then
            call fatal_error(error, output // ": output file exists (set overwrite = .true. to replace it)", err_input)
            return
        end if

        tasks%cfg = cfg
        if (present(inv)) tasks%inv = inv
        tasks%omegas = bifurcation_omegas(cfg)
        ncurve = curve_count(cfg)
        nomega = size(tasks%omegas)
        if (nomega < 1) then
            call fatal_error(error, source_name(cfg) // ": &scene: the frequency axis omega_min .. omega_max is empty", &
                             err_input)
            return
        end if
        allocate (tasks%runs(ncurve))
        do ic = 1, ncurve
            tasks%runs(ic) = search_run(curve_run(cfg, ic))
        end do
        if (cfg%scene%screen_method /= screen_none) then
            allocate (tasks%screen_runs(ncurve))
            do ic = 1, ncurve
                tasks%screen_runs(ic) = search_run(with_numerics(curve_run(cfg, ic), &
                    screen_integrator(cfg%scene%screen_method), screen_dt(cfg, curve_run(cfg, ic))))
            end do
        end if
        if (cfg%scene%certify) then
            allocate (tasks%half_runs(ncurve))
            do ic = 1, ncurve
                tasks%half_runs(ic) = search_run(with_numerics(curve_run(cfg, ic), cfg%run%numerics%method, &
                                                               cfg%run%numerics%dt/2.0_wp))
            end do
        end if
        tasks%partial_path = output // ".partial.h5"
        tasks%checkpoint_prefix = output // ".checkpoint-"
        tasks%fingerprint = input_fingerprint(cfg)
        journal = output // ".journal"
        if (.not. cfg%output%quiet) then
            write (error_unit, "(a)") "supratrans: bifurcation from " // printable(source_name(cfg)) // ": " // int_str(ncurve) &
                // " curve(s) x " // int_str(nomega) // " frequencies, amplitudes " // real_str(cfg%scene%amplitude_min, 6) &
                // " .. " // real_str(cfg%scene%amplitude_max, 6) // " (coarse step " &
                // real_str(effective_coarse_step(cfg%scene%coarse_step, cfg%scene%resolution), 6) // ", resolution " &
                // real_str(cfg%scene%resolution, 6) // ")" // trim(screening_text(cfg))
        end if

        call run_tasks(tasks, ncurve*nomega, search_fields, journal, input_fingerprint(cfg), &
                       "threshold searches", cfg%output%quiet, results, done, error, cfg, inv)
        if (allocated(error) .or. engine_only(tasks%inv)) return

        call system_clock(clock_end)
        elapsed = real(clock_end - clock_start, wp)/real(clock_rate, wp)
        if (tasks%inv%merge_wall_time >= 0.0_wp) elapsed = tasks%inv%merge_wall_time     ! a merge: the slices' cost
        call write_bifurcation_file(tasks, output, results, done, .true., elapsed, error)
        if (allocated(error)) return
        if (.not. keep) call remove_file(journal)
        call remove_file(tasks%partial_path)
        if (.not. cfg%output%quiet) then
            allocate (records(size(done)))
            do ic = 1, size(done)
                records(ic) = from_values(results(:, ic))
            end do
            write (steps_text, "(i0)") sum(records%steps)
            write (error_unit, "(a)") "  " // int_str(sum(records%runs)) // " runs (" &
                // int_str(sum(records%runs_screened)) // " screened), " // trim(steps_text) // " time steps, " &
                // fixed1(elapsed) // " s"
            if (cfg%scene%certify) write (error_unit, "(a)") "  certified at dt/2: " &
                // int_str(count(records%certify_status == certify_unchanged .or. records%certify_status &
                                 == certify_moved_within)) // " thresholds stand, " &
                // int_str(count(records%certify_status >= certify_moved)) // " flagged"
        end if
    end subroutine run_bifurcation

    !> The screening and certification settings, for the progress line ("" when neither is on).
    function screening_text(cfg) result(text)
        !> The input.
        type(input_config), intent(in) :: cfg
        character(len=:), allocatable :: text

        text = ""
        if (cfg%scene%screen_method /= screen_none) text = "; screened by " &
            // trim(screen_choices(cfg%scene%screen_method)) &
            // " at dt = " // real_str(screen_dt(cfg, cfg%run), 6) &
            // ", confirmed within " // real_str(cfg%scene%confirm_band, 6) // " and below margin " &
            // real_str(cfg%scene%screen_margin, 6)
        if (cfg%scene%certify) text = text // "; certified at dt/2"
    end function screening_text

    !> The frequency axis of a scene: Omega_i = omega_min + i omega_step <= omega_max, i = 0, 1, ... (integer index;
    !> a point within 1e-9 steps of omega_max is kept).
    pure function bifurcation_omegas(cfg) result(omegas)
        !> The input.
        type(input_config), intent(in) :: cfg
        real(wp), allocatable :: omegas(:)
        integer :: i, n

        n = search_grid_size(cfg%scene%omega_min, cfg%scene%omega_max, cfg%scene%omega_step)
        allocate (omegas(n))
        do i = 1, n
            omegas(i) = cfg%scene%omega_min + real(i - 1, wp)*cfg%scene%omega_step
        end do
    end function bifurcation_omegas

    !> A curve's run prepared for the search: stop when decided, no probes, the ledger closed once (the oracle
    !> runs it for its verdict alone: no ledger at all).
    pure function search_run(curve) result(run)
        !> The curve's run.
        type(run_config), intent(in) :: curve
        type(run_config) :: run
        integer :: m

        run = curve
        run%detect%stop_when_decided = .true.
        m = int(min(max(1_i8, number_of_levels(run) - 1), int(huge(1), i8)))
        if (allocated(run%record%probes)) deallocate (run%record%probes)
        allocate (run%record%probes(0))
        run%record%probe_every = m
        run%record%ledger_every = m
    end function search_run

    !> Search the threshold of task `index` (thread-safe: everything it changes is local).
    subroutine run_search(self, index, values)
        !> The tasks.
        class(bifurcation_tasks), intent(in) :: self
        !> Task index: (curve - 1) nomega + iomega.
        integer, intent(in) :: index
        !> The task's `search_record`, as values (`to_values`).
        real(wp), intent(out) :: values(:)
        type(simulation_oracle) :: oracle, screen, check
        type(screen_report) :: report
        type(search_record) :: r
        type(checkpoint_session), target :: session
        integer :: icurve, iomega, nomega
        integer(i8) :: clock_start, clock_end, clock_rate
        real(wp) :: omega, nan
        character(len=24) :: task_text

        call system_clock(clock_start, clock_rate)
        nan = ieee_value(nan, ieee_quiet_nan)
        nomega = size(self%omegas)
        icurve = (index - 1)/nomega + 1
        iomega = mod(index - 1, nomega) + 1
        omega = self%omegas(iomega)
        oracle%run = self%runs(icurve)
        oracle%run%drive%omega = omega
        r = unsearched_record()
        r%status = bifurcation_outside_gap
        if (omega < band_gap_edge(oracle%run%chain)) r%threshold_as = threshold_as(oracle%run%chain, omega)
        if (omega >= band_gap_edge(oracle%run%chain) .and. .not. self%cfg%allow_outside_gap) then
            values = to_values(r)
            return
        end if

        ! mid-run checkpoints of this search: its verdicts so far and its run in progress (supratrans_checkpoint)
        write (task_text, "(i0)") index
        if (allocated(self%checkpoint_prefix)) then
            call open_session(session, self%checkpoint_prefix // trim(task_text), self%fingerprint // " task " &
                              // trim(task_text), self%cfg%output%checkpoint_every)
            if (session%resumed) write (session%note, "(a, i0, a, a)") "resumed: ", session%nlog, &
                " run(s) of the search done", trim(merge(", one in progress", "                 ", session%has_pending))
            call checkpoint_note()
            oracle%session => session
            screen%session => session
            check%session => session
        end if
        associate (sc => self%cfg%scene)
            if (allocated(self%screen_runs)) then
                screen%run = self%screen_runs(icurve)
                screen%run%drive%omega = omega
                call find_threshold_screened(oracle, screen, sc%amplitude_min, sc%amplitude_max, sc%coarse_step, &
                                             sc%resolution, sc%confirm_band, sc%screen_margin, r%threshold, r%runs, &
                                             r%steps, r%status, report)
                r%runs_screened = report%runs_screened
                r%runs_confirmed = report%runs_confirmed
                r%runs_doubtful = report%runs_doubtful
                r%steps_screened = report%steps_screened
                r%steps_confirmed = report%steps_confirmed
                r%screen_threshold = report%screen_threshold
                r%band_low = report%band_low
                r%band_high = report%band_high
                r%rounds = report%rounds
                r%disagreements = report%disagreements
                r%farthest_disagreement = report%farthest_disagreement
            else
                call find_threshold(oracle, sc%amplitude_min, sc%amplitude_max, sc%coarse_step, sc%resolution, &
                                    r%threshold, r%runs, r%steps, r%status)
                r%runs_confirmed = r%runs
                r%steps_confirmed = r%steps
            end if
            if (allocated(self%half_runs) .and. r%status == search_found) call certify()
        end associate
        call checkpoint_note()
        if (session%interrupted) then
            ! stopped by a signal at its checkpoint: no result (the engine journals nothing; a rerun resumes it)
            values = to_values(unsearched_record())
            return
        end if
        call close_session(session)
        call system_clock(clock_end)
        r%wall_time = real(clock_end - clock_start, wp)/real(clock_rate, wp)
        values = to_values(r)
        if (r%status == search_failed .and. .not. self%cfg%output%quiet) then
            ! text only inside the critical section: deferred-length results are not thread-safe in gfortran 12
            !$omp critical (supratrans_bifurcation_messages)
            write (error_unit, "(a)") "  warning: curve " // int_str(icurve) // ", omega = " // real_str(omega, 6) &
                // ": search abandoned, " // oracle%failure_reason()
            !$omp end critical (supratrans_bifurcation_messages)
        end if
        if (r%certify_status >= certify_moved .and. .not. self%cfg%output%quiet) then
            !$omp critical (supratrans_bifurcation_messages)
            write (error_unit, "(a)") "  warning: curve " // int_str(icurve) // ", omega = " // real_str(omega, 6) &
                // ": threshold " // real_str(r%threshold, 6) // " not certified at dt/2 (" &
                // trim(merge("moved to " // real_str(r%certified_threshold, 6), "no threshold nearby   ", &
                              r%certify_status == certify_moved)) // ")"
            !$omp end critical (supratrans_bifurcation_messages)
        end if

    contains

        !> The session's note (an ignored or unwritable checkpoint), one line, then cleared.
        subroutine checkpoint_note()
            if (len_trim(session%note) == 0) return
            if (.not. self%cfg%output%quiet) then
                !$omp critical (supratrans_bifurcation_messages)
                write (error_unit, "(a)") "  checkpoint " // self%checkpoint_prefix // trim(task_text) // " " &
                    // trim(session%note)
                !$omp end critical (supratrans_bifurcation_messages)
            end if
            session%note = ""
        end subroutine checkpoint_note

        !> Recheck the threshold r%threshold with the scene's method at dt/2: it must transmit and the grid point below
        !> it must not; otherwise look for the dt/2 threshold within one coarse step. Fills r%certify_*.
        subroutine certify()
            integer :: k_t, k, m, kmax, k_new
            logical :: at, below

            associate (sc => self%cfg%scene)
                check%run = self%half_runs(icurve)
                check%run%drive%omega = omega
                k_t = nint((r%threshold - sc%amplitude_min)/sc%resolution)
                kmax = search_grid_size(sc%amplitude_min, sc%amplitude_max, sc%resolution) - 1
                m = max(1, nint(effective_coarse_step(sc%coarse_step, sc%resolution)/sc%resolution))
                k_new = -1
                r%certify_status = certify_unresolved
                at = ask(k_t)
                if (check%failed()) return
                if (at) then
                    below = .false.
                    if (k_t > 0) below = ask(k_t - 1)
                    if (check%failed()) return
                    if (.not. below) then
                        k_new = k_t
                    else
                        do k = k_t - 2, max(0, k_t - m), -1
                            if (.not. ask(k)) then
                                k_new = k + 1
                                exit
                            end if
                            if (check%failed()) return
                        end do
                    end if
                else
                    do k = k_t + 1, min(kmax, k_t + m)
                        if (ask(k)) then
                            k_new = k
                            exit
                        end if
                        if (check%failed()) return
                    end do
                end if
                if (k_new < 0) return
                r%certified_threshold = sc%amplitude_min + real(k_new, wp)*sc%resolution
                select case (abs(k_new - k_t))
                case (0)
                    r%certify_status = certify_unchanged
                case (1)
                    r%certify_status = certify_moved_within
                case default
                    r%certify_status = certify_moved
                end select
            end associate

        end subroutine certify

        !> One dt/2 run at grid point k: its verdict; a failure sets the status `certify_failed`.
        function ask(k) result(transmitting)
            !> Grid index.
            integer, intent(in) :: k
            logical :: transmitting
            integer(i8) :: cost

            transmitting = check%transmits(self%cfg%scene%amplitude_min + real(k, wp)*self%cfg%scene%resolution, cost)
            r%certify_runs = r%certify_runs + 1
            r%certify_steps = r%certify_steps + cost
            if (check%failed()) r%certify_status = certify_failed
        end function ask

    end subroutine run_search

    !> Whether a task's record is a result: a search stopped at its checkpoint by a signal returns the unsearched
    !> record (status pending), which is not journaled.
    function search_finished(self, values) result(yes)
        !> The tasks.
        class(bifurcation_tasks), intent(in) :: self
        !> The task's values (`to_values`).
        real(wp), intent(in) :: values(:)
        logical :: yes
        type(search_record) :: r

        r = from_values(values)
        yes = r%status /= bifurcation_pending
    end function search_finished

    !> The measured cost of every search in `path`, an earlier output (or merged file) of the same study: its
    !> `/cost/wall_time` (curve, omega), by task index. The file must be a bifurcation output with the same
    !> frequencies (`/omega`) and curves (`/curves/gamma`, `beta`, `m2`), else it is refused in one line.
    subroutine search_measured_costs(self, path, costs, error)
        !> The tasks.
        class(bifurcation_tasks), intent(in) :: self
        !> The earlier output.
        character(len=*), intent(in) :: path
        !> Measured wall time of each search (s), by task index.
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
            call h5_read(file, "/cost/wall_time", grid, cause)
            if (allocated(cause)) call fatal_error(error, "--costs " // printable(path) // ": lacks the searches' " &
                                                   // "measured costs (/cost/wall_time)", err_input)
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

    !> Estimated cost of task `index`, for the largest-first slices (`supratrans_tasks::slice_owners`): the work of
    !> one run of its curve (`run_work`) x the expected runs of a search, half the coarse scan of the range and the
    !> scan of one bracket at the resolution; a screened search runs most of them with the screening method at its
    !> step. A frequency outside the gap is no search: nearly nothing.
    pure function search_cost(self, index) result(cost)
        !> The tasks.
        class(bifurcation_tasks), intent(in) :: self
        !> Task index: (curve - 1) nomega + iomega.
        integer, intent(in) :: index
        real(wp) :: cost
        integer :: icurve
        real(wp) :: coarse, runs

        icurve = (index - 1)/size(self%omegas) + 1
        cost = 1.0e-6_wp*run_work(self%runs(icurve))
        if (self%omegas(mod(index - 1, size(self%omegas)) + 1) >= band_gap_edge(self%runs(icurve)%chain) &
            .and. .not. self%cfg%allow_outside_gap) return
        associate (sc => self%cfg%scene)
            coarse = effective_coarse_step(sc%coarse_step, sc%resolution)
            runs = 0.5_wp*(sc%amplitude_max - sc%amplitude_min)/coarse + coarse/sc%resolution
        end associate
        if (allocated(self%screen_runs)) then
            cost = (runs - 4.0_wp)*run_work(self%screen_runs(icurve)) + 4.0_wp*run_work(self%runs(icurve))
        else
            cost = runs*run_work(self%runs(icurve))
        end if
        if (allocated(self%half_runs)) cost = cost + 2.0_wp*run_work(self%half_runs(icurve))
    end function search_cost

    !> A record with nothing searched: thresholds NaN, counts 0, statuses "pending" / "not checked".
    pure function unsearched_record() result(r)
        type(search_record) :: r
        real(wp) :: nan

        nan = ieee_value(nan, ieee_quiet_nan)
        r%threshold = nan
        r%threshold_as = nan
        r%status = bifurcation_pending
        r%screen_threshold = nan
        r%band_low = nan
        r%band_high = nan
        r%certified_threshold = nan
        r%certify_status = certify_not_checked
    end function unsearched_record

    !> One simulation at amplitude `amplitude`: its verdict, and the time steps it took.
    function simulation_transmits(self, amplitude, cost) result(transmitting)
        !> The oracle.
        class(simulation_oracle), intent(inout) :: self
        !> Driving amplitude A.
        real(wp), intent(in) :: amplitude
        !> Time steps taken.
        integer(i8), intent(out) :: cost
        logical :: transmitting
        type(run_result) :: result

        self%run%drive%amplitude = amplitude
        if (associated(self%session)) then
            call simulate(self%run, result, verdict_only=.true., session=self%session)
        else
            call simulate(self%run, result, verdict_only=.true.)
        end if
        cost = int(result%steps, i8)
        transmitting = result%transmitting
        self%last_margin = result%verdict_margin
        self%run_failed = result%status /= run_ok .and. .not. result%transmitting
        if (self%run_failed) then
            self%failed_amplitude = amplitude
            self%failed_status = result%status
            self%reason = result%reason
        end if
    end function simulation_transmits

    !> Margin of the last run's verdict, relative to the detection amplitude (NaN for a run stopped at its crossing
    !> or failed).
    function simulation_margin(self) result(margin)
        !> The oracle.
        class(simulation_oracle), intent(in) :: self
        real(wp) :: margin

        margin = self%last_margin
    end function simulation_margin

    !> Whether the last run failed before its verdict.
    function simulation_failed(self) result(failed)
        !> The oracle.
        class(simulation_oracle), intent(in) :: self
        logical :: failed

        failed = self%run_failed
    end function simulation_failed

    !> Why the last run failed (empty if it did not); not for concurrent use (deferred-length text).
    function simulation_failure_reason(self) result(reason)
        !> The oracle.
        class(simulation_oracle), intent(in) :: self
        character(len=:), allocatable :: reason

        reason = ""
        if (.not. self%run_failed) return
        reason = "the run at A = " // real_str(self%failed_amplitude, 6) // " ended " // status_name(self%failed_status)
        if (allocated(self%reason)) reason = reason // ": " // self%reason
    end function simulation_failure_reason

    !> Write the results so far to `<output>.partial.h5` (root attribute `complete = 0`); failures are ignored (the
    !> journal, not this file, is what a resumed run reads).
    subroutine write_snapshot(self, results, done)
        !> The tasks.
        class(bifurcation_tasks), intent(in) :: self
        !> Results so far, (values, tasks).
        real(wp), intent(in) :: results(:, :)
        !> Which tasks are done.
        logical, intent(in) :: done(:)
        type(error_type), allocatable :: error

        call write_bifurcation_file(self, self%partial_path, results, done, .false., -1.0_wp, error)
        if (allocated(error) .and. .not. self%cfg%output%quiet) then
            write (error_unit, "(a)") "  warning: partial output not written: " // printable(error%message)
        end if
    end subroutine write_snapshot

    !> Write the scene's file `path` (built in memory, written atomically): tasks not done get NaN and status
    !> `bifurcation_pending`.
    subroutine write_bifurcation_file(tasks, path, results, done, complete, elapsed, error)
        !> The tasks.
        type(bifurcation_tasks), intent(in) :: tasks
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

        ncurve = size(tasks%runs)
        nomega = size(tasks%omegas)
        ! the records as values in `search_fields` order; tasks not done as records with nothing searched
        vals = results
        do ic = 1, size(done)
            if (.not. done(ic)) vals(:, ic) = to_values(unsearched_record())
        end do
        allocate (nd(nomega, ncurve))
        do ic = 1, ncurve
            do io = 1, nomega
                nd(io, ic) = detector_site(with_omega(tasks%runs(ic), tasks%omegas(io)))
            end do
        end do

        call h5_create(file, path, .true.)
        call write_root(file, tasks%cfg, "bifurcation", "Supratransmission threshold (smallest transmitting driving " &
                        // "amplitude) vs driving frequency, one curve per potential and varied value", tasks%inv)
        call h5_write_attr(file, "/", "complete", merge(1, 0, complete))
        call h5_write_attr(file, "/", "tasks_done", count(done))
        call write_scene_parameters(file, tasks%cfg)
        call h5_write(file, "/omega", tasks%omegas, "1/time", &
            "Driving frequency Omega_i = omega_min + i omega_step", dims="omega")
        call write_bifurcation_curves(file, tasks)
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
        if (elapsed >= 0.0_wp) call h5_write_attr(file, "/cost", "scene_wall_time_s", elapsed)
        call h5_write(file, "/detector_site", nd, "1", &
            "Detector site n_d of the verdict (a run transmits once |u_n| > detect amplitude for some n > n_d)", &
            dims=dims)
        call h5_write(file, "/status", count_grid(vals, "status", nomega), &
            "1", "Outcome of the search (codes in attribute 'codes')", dims=dims)
        call h5_write_attr(file, "/status", "codes", "-2: outside gap (Omega >= " &
            // "sqrt(1 + m^2): not searched; NaN); -1: pending (not computed yet); " // search_status_codes())
        call write_screening(file, tasks%cfg, vals, nomega)
        call write_certification(file, tasks%cfg, vals, nomega)
        call h5_commit(file, error)
    end subroutine write_bifurcation_file

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

    !> The integrator (`method_*`) of a screening method (`screen_*` of &scene screen_method, not `screen_none`).
    pure integer function screen_integrator(screen)
        !> The screening method.
        integer, intent(in) :: screen

        select case (screen)
        case (screen_newton)
            screen_integrator = method_newton
        case (screen_linearized)
            screen_integrator = method_linearized
        case (screen_rk4)
            screen_integrator = method_rk4
        case default
            screen_integrator = method_rk8
        end select
    end function screen_integrator

    !> Time step of the screening runs of `run`: `screen_dt`, or when it is 0, twice the run's dt where that meets
    !> the paper's stability condition for the run's chain, else the run's dt.
    pure function screen_dt(cfg, run) result(dt)
        !> The input.
        type(input_config), intent(in) :: cfg
        !> The run screened (a curve's run).
        type(run_config), intent(in) :: run
        real(wp) :: dt

        dt = cfg%scene%screen_dt
        if (dt > 0.0_wp) return
        dt = run%numerics%dt
        if (stable_by_paper_condition(run%chain, 2.0_wp*dt) .and. 2.0_wp*dt <= run%numerics%t_final/2.0_wp) dt = 2.0_wp*dt
    end function screen_dt

    !> A curve's run with another integrator and time step.
    pure function with_numerics(run, method, dt) result(r)
        !> The run.
        type(run_config), intent(in) :: run
        !> Integrator (`method_*`).
        integer, intent(in) :: method
        !> Time step.
        real(wp), intent(in) :: dt
        type(run_config) :: r

        r = run
        r%numerics%method = method
        r%numerics%dt = dt
    end function with_numerics

    !> A run with its drive frequency set.
    pure function with_omega(run, omega) result(r)
        !> The run.
        type(run_config), intent(in) :: run
        !> Driving frequency.
        real(wp), intent(in) :: omega
        type(run_config) :: r

        r = run
        r%drive%omega = omega
    end function with_omega

    !> The namelist file of the input ("configuration" when not set).
    pure function source_name(cfg) result(name)
        !> The input.
        type(input_config), intent(in) :: cfg
        character(len=:), allocatable :: name

        name = "configuration"
        if (allocated(cfg%source)) name = cfg%source
    end function source_name


    !> Run the scene (`run_bifurcation`).
    subroutine bifurcation_scene_run(self, cfg, error, inv)
        !> The scene.
        class(bifurcation_scene), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> How the engine is invoked (a slice, a merge: `supratrans_invocation`); default: the whole scene.
        type(invocation_type), intent(in), optional :: inv

        call run_bifurcation(cfg, error, inv=inv)
    end subroutine bifurcation_scene_run

    !> The frequency axis, the search grid (amplitude_min..amplitude_max by resolution, coarse_step), then the
    !> searches (curves x frequencies) and their work: a search asks about (range)/coarse_step coarse amplitudes
    !> and up to coarse_step/resolution fine ones.
    pure subroutine bifurcation_scene_limits(self, cfg, where, budget, error)
        !> The scene.
        class(bifurcation_scene), intent(in) :: self
        !> The configuration (values already within their ranges and rules).
        type(input_config), intent(in) :: cfg
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Threads and memory of the machine.
        type(scene_budget), intent(in) :: budget
        !> Allocated when a limit is exceeded.
        type(error_type), allocatable, intent(out) :: error
        real(wp) :: nomega, ngrid

        associate (sc => cfg%scene)
            nomega = axis_points(sc%omega_min, sc%omega_max, sc%omega_step)
            call check_axis(nomega, "omega_step = " // sci(sc%omega_step) // " makes " // sci(nomega) // " frequencies", &
                            where, error)
            if (allocated(error)) return
            ngrid = axis_points(sc%amplitude_min, sc%amplitude_max, sc%resolution)
            call check_axis(ngrid, "resolution = " // sci(sc%resolution) // " makes a search grid of " // sci(ngrid) &
                            // " amplitudes", where, error)
            if (allocated(error)) return
            call check_axis(sc%coarse_step/sc%resolution, "coarse_step/resolution = " &
                            // sci(sc%coarse_step/sc%resolution), where, error)
            if (allocated(error)) return
            call check_tasks(cfg, real(curve_count(cfg), wp)*nomega*1.0_wp, &
                             (sc%amplitude_max - sc%amplitude_min)/sc%coarse_step + sc%coarse_step/sc%resolution, &
                             cfg%run%numerics%t_final/cfg%run%numerics%dt, "searches", where, error)
        end associate
    end subroutine bifurcation_scene_limits

end module supratrans_scene_bifurcation
