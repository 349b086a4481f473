!> The threshold search of one task of the scene `bifurcation` (a submodule of `supratrans_scene_bifurcation`, whose
!> interface declares these procedures): the search itself (`find_threshold`, or `find_threshold_screened` with a
!> screening method), its certification at dt/2, its mid-run checkpoints, the record it leaves (`search_record`),
!> and its estimated cost for the slices.
submodule(supratrans_scene_bifurcation) supratrans_scene_bifurcation_search
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_chain, only: threshold_as, band_gap_edge
    use supratrans_threshold, only: find_threshold, search_found, search_failed
    use supratrans_screened_search, only: find_threshold_screened, screen_report
    use supratrans_search_record, only: to_values, certify_not_checked, certify_unresolved, certify_failed
    use supratrans_tasks, only: run_work
    use supratrans_checkpoint, only: checkpoint_session, open_session, close_session
    use supratrans_bifurcation_runs, only: simulation_oracle
    use supratrans_system, only: thread_cpu_seconds
    implicit none

contains

    !> Search the threshold of task `index` (thread-safe: everything it changes is local).
    module procedure run_search
        type(simulation_oracle) :: oracle, screen, check
        type(screen_report) :: report
        type(search_record) :: r
        type(checkpoint_session), target :: session
        integer :: icurve
        integer(i8) :: clock_start, clock_end, clock_rate
        real(wp) :: omega, nan, cpu_start
        character(len=24) :: task_text

        call system_clock(clock_start, clock_rate)
        cpu_start = thread_cpu_seconds()
        nan = ieee_value(nan, ieee_quiet_nan)
        icurve = self%task_curve(index)
        oracle%run = self%task_run(index)
        omega = oracle%run%drive%omega
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
                screen%run = self%run_at(index, self%screen_runs)
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
                r%margin_below = report%margin_below
            else
                call find_threshold(oracle, sc%amplitude_min, sc%amplitude_max, sc%coarse_step, sc%resolution, &
                                    r%threshold, r%runs, r%steps, r%status, margin_below=r%margin_below)
                r%runs_confirmed = r%runs
                r%steps_confirmed = r%steps
            end if
            if (allocated(self%half_runs) .and. r%status == search_found) call certify()
        end associate
        call checkpoint_note()
        if (session%interrupted .or. oracle%interrupted .or. screen%interrupted .or. check%interrupted) then
            ! stopped by a signal (at its checkpoint, if any): no result (the engine journals nothing; a rerun resumes
            ! it)
            values = to_values(unsearched_record())
            return
        end if
        call close_session(session)
        call system_clock(clock_end)
        r%wall_time = real(clock_end - clock_start, wp)/real(clock_rate, wp)
        r%cpu_time = thread_cpu_seconds() - cpu_start
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
                check%run = self%run_at(index, self%half_runs)
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

    end procedure run_search

    !> Whether a task's record is a result: a search stopped at its checkpoint by a signal returns the unsearched
    !> record (status pending), which is not journaled.
    module procedure search_finished
        type(search_record) :: r

        r = from_values(values)
        yes = r%status /= bifurcation_pending
    end procedure search_finished

    !> Estimated cost of task `index`, for the largest-first slices (`supratrans_tasks::slice_owners`): the work of
    !> one run of its curve (`run_work`) x the expected runs of a search, half the coarse scan of the range and the
    !> scan of one bracket at the resolution; a screened search runs most of them with the screening method at its
    !> step. A frequency outside the gap is no search: nearly nothing.
    module procedure search_cost
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
    end procedure search_cost

    !> A record with nothing searched: thresholds NaN, counts 0, statuses "pending" / "not checked".
    module procedure unsearched_record
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
        r%margin_below = nan
    end procedure unsearched_record

end submodule supratrans_scene_bifurcation_search
