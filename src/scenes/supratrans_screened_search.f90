!> A threshold search that screens with a cheap oracle and confirms near the threshold with the exact one, so that
!> it reports what the exact search alone (`find_threshold` with the exact oracle) would report.
!>
!> Both oracles answer questions on the search grid A_k = a_min + k resolution. A *hybrid* oracle answers grid point
!> k with the exact oracle when k lies in the confirmation set, with the cheap one otherwise, and remembers every
!> answer of each oracle (no point is asked twice of the same oracle). The search:
!>
!> 1. runs `find_threshold` with the cheap oracle alone (where a cheap run fails, the exact oracle answers), its
!>    bracket bisected rather than scanned (the answer only places the band: of the points a scan would ask, those
!>    within the band would be asked again of the exact oracle): threshold a_c (index k_c; "none transmits" counts
!>    as k_c = k_max + 1, just above the range). If it fails, the confirmation set becomes the whole grid: the
!>    exact search, no saving;
!> 2. confirmation set = the grid points within `band` of a_c;
!>
!> Everywhere, a cheap *quiet* answer whose margin (the oracle's `margin`: how far the run stayed below the
!> detection amplitude, relative to it) is below `doubt` is not used: the exact oracle answers that point too. A
!> run that came that close to transmitting is where a cheap integrator's verdict can differ from the exact one
!> (damped chains whose response hovers near the detection amplitude over a range of amplitudes);
!> 3. runs `find_threshold` with the hybrid oracle: threshold a (index k_a, or k_max + 1 for none). Every point it
!>    asked at or above k_a - band/resolution must have been answered by the exact oracle; if one was not, the set
!>    grows to cover [k_a - band/resolution, highest such point] (wider, by doubling, from the third round on) and
!>    step 3 runs again (memoised, so only new points cost).
!>
!> It ends with the threshold, the point below it, the coarse hit that bracketed it and every point the search
!> asked within `band` below it answered by the exact oracle. `find_threshold` is a deterministic function of the
!> answers it gets, so the result is the exact search's whenever the cheap answers it used (all more than `band`
!> below the threshold) agree with the exact oracle; the confirmation also walks down, `band` at a time, through
!> a stretch where the cheap oracle calls transmitting amplitudes quiet. Worst case it is the exact search plus the
!> screening search. How far from the threshold a cheap answer can be wrong was measured (README, "Screening"); the
!> report counts the disagreements the search saw (points both oracles answered) and the farthest of them.
module supratrans_screened_search
    use, intrinsic :: iso_fortran_env, only: int8
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp, i8
    use supratrans_threshold, only: verdict_oracle, find_threshold, search_grid_size, search_found, &
                                    search_at_lower_bound, search_none, search_failed
    implicit none
    private

    public :: find_threshold_screened

    !> What a screened search did.
    type, public :: screen_report
        !> Questions answered by the cheap (screening) oracle.
        integer :: runs_screened = 0
        !> Questions answered by the exact oracle.
        integer :: runs_confirmed = 0
        !> Of the screening answers, the quiet ones set aside for a margin below `doubt` (the exact oracle answered).
        integer :: runs_doubtful = 0
        !> Cost of the screening answers (time steps).
        integer(i8) :: steps_screened = 0_i8
        !> Cost of the exact answers (time steps).
        integer(i8) :: steps_confirmed = 0_i8
        !> Threshold of the screening search alone, its bracket bisected (NaN when it found none).
        real(wp) :: screen_threshold = 0.0_wp
        !> Lowest amplitude of the final confirmation set (NaN when empty).
        real(wp) :: band_low = 0.0_wp
        !> Highest amplitude of the final confirmation set (NaN when empty).
        real(wp) :: band_high = 0.0_wp
        !> Hybrid searches run (1 when the first confirmation set sufficed).
        integer :: rounds = 0
        !> Grid points answered by both oracles with different verdicts.
        integer :: disagreements = 0
        !> Largest distance (amplitude) between the threshold and a point of disagreement; 0 when none.
        real(wp) :: farthest_disagreement = 0.0_wp
        !> Margin of the quiet answer at the grid point just below the threshold (`find_threshold`'s
        !> `margin_below`, from the oracle that answered it); NaN unless a threshold was found above a_min.
        real(wp) :: margin_below = 0.0_wp
    end type screen_report

    !> Memo values: not asked, quiet, transmitting, failed, quiet with a margin below `doubt` (cheap oracle only).
    integer(int8), parameter :: unknown = 0_int8, quiet = 1_int8, transmitting = 2_int8, failing = 3_int8, &
                                doubtful = 4_int8

    !> The hybrid oracle: exact inside the confirmation set, cheap outside, each answer remembered.
    type, extends(verdict_oracle) :: hybrid_oracle
        !> The exact oracle.
        class(verdict_oracle), pointer :: exact => null()
        !> The cheap oracle.
        class(verdict_oracle), pointer :: cheap => null()
        !> Start of the search grid.
        real(wp) :: a_min = 0.0_wp
        !> Step of the search grid.
        real(wp) :: resolution = 1.0_wp
        !> Answers of the exact oracle by grid index.
        integer(int8), allocatable :: exact_memo(:)
        !> Answers of the cheap oracle by grid index.
        integer(int8), allocatable :: cheap_memo(:)
        !> Margins (the oracle's `margin`) of the exact oracle's answers by grid index.
        real(wp), allocatable :: exact_margin(:)
        !> Margins of the cheap oracle's answers by grid index.
        real(wp), allocatable :: cheap_margin(:)
        !> Margin of the last answer (remembered answers too).
        real(wp) :: last_margin = 1.0_wp
        !> The confirmation set.
        logical, allocatable :: confirm(:)
        !> Points of this search that the cheap oracle answered.
        logical, allocatable :: asked_cheap(:)
        !> The last answer came from a failed exact run.
        logical :: last_failed = .false.
        !> Cheap quiet answers with a margin below this are answered again by the exact oracle.
        real(wp) :: doubt = 0.0_wp
        !> Running counts (see `screen_report`).
        integer :: runs_screened = 0, runs_confirmed = 0, runs_doubtful = 0
        !> Running costs (see `screen_report`).
        integer(i8) :: steps_screened = 0_i8, steps_confirmed = 0_i8
    contains
        !> Answer one grid amplitude.
        procedure :: transmits => hybrid_transmits
        !> Whether the last answer failed.
        procedure :: failed => hybrid_failed
        !> Margin of the last answer.
        procedure :: margin => hybrid_margin
    end type hybrid_oracle

contains

    !> Find the threshold that `find_threshold(exact, ...)` would find, asking `cheap` wherever the answer is far
    !> from the threshold (see the module documentation). Arguments as `find_threshold`, plus the oracles' roles,
    !> the confirmation `band` (amplitude units, >= 0), the margin `doubt` below which a cheap quiet answer is
    !> not used (0: every one is) and the `report`; `runs` and `steps` count real questions.
    subroutine find_threshold_screened(exact, cheap, a_min, a_max, coarse_step, resolution, band, doubt, threshold, &
                                       runs, steps, status, report)
        !> The oracle whose answer the search must reproduce.
        class(verdict_oracle), intent(inout), target :: exact
        !> The cheap screening oracle.
        class(verdict_oracle), intent(inout), target :: cheap
        !> Lower end of the search range.
        real(wp), intent(in) :: a_min
        !> Upper end of the search range.
        real(wp), intent(in) :: a_max
        !> Step of the coarse upward scan.
        real(wp), intent(in) :: coarse_step
        !> Resolution of the threshold.
        real(wp), intent(in) :: resolution
        !> Confirmation band (amplitude): answers within it below the threshold come from `exact`.
        real(wp), intent(in) :: band
        !> Cheap quiet answers with a margin below this are answered again by `exact`.
        real(wp), intent(in) :: doubt
        !> The threshold (NaN when none).
        real(wp), intent(out) :: threshold
        !> Questions asked of either oracle.
        integer, intent(out) :: runs
        !> Their total cost (time steps).
        integer(i8), intent(out) :: steps
        !> Status, as `find_threshold`'s.
        integer, intent(out) :: status
        !> What the screening did.
        type(screen_report), intent(out) :: report
        type(hybrid_oracle) :: hybrid
        integer :: kmax, nb, k_ref, lo, hi, k, n_asked
        integer(i8) :: ignored_steps
        real(wp) :: nan

        nan = ieee_value(nan, ieee_quiet_nan)
        report%screen_threshold = nan
        report%band_low = nan
        report%band_high = nan
        report%margin_below = nan
        kmax = search_grid_size(a_min, a_max, resolution) - 1
        if (kmax < 0 .or. .not. (coarse_step >= resolution)) then
            call find_threshold(exact, a_min, a_max, coarse_step, resolution, threshold, runs, steps, status, &
                                margin_below=report%margin_below)
            report%runs_confirmed = runs
            report%steps_confirmed = steps
            return
        end if
        nb = max(0, floor(band/resolution + 1.0e-9_wp))
        hybrid%exact => exact
        hybrid%cheap => cheap
        hybrid%a_min = a_min
        hybrid%resolution = resolution
        hybrid%doubt = doubt
        allocate (hybrid%exact_memo(0:kmax), hybrid%cheap_memo(0:kmax), hybrid%confirm(0:kmax), &
                  hybrid%asked_cheap(0:kmax), hybrid%exact_margin(0:kmax), hybrid%cheap_margin(0:kmax))
        hybrid%exact_margin = nan
        hybrid%cheap_margin = nan
        hybrid%exact_memo = unknown
        hybrid%cheap_memo = unknown
        hybrid%confirm = .false.

        ! 1. the screening search alone, bisecting; "none transmits" is taken as a threshold just above a_max
        call search(threshold, status, bisect=.true.)
        if (status /= search_failed) report%screen_threshold = threshold
        if (status == search_failed) then
            hybrid%confirm = .true.
        else
            k_ref = reference_index(threshold, status)
            hybrid%confirm(max(0, min(kmax, k_ref - nb)):min(kmax, k_ref + nb)) = .true.
        end if

        ! 2. hybrid searches until everything near the answer was asked of the exact oracle; a band that has to
        !    grow more than once grows by doubling widths (a long stretch of wrong cheap answers costs few rounds)
        do
            report%rounds = report%rounds + 1
            call search(threshold, status, margin=report%margin_below)
            if (status == search_failed) exit
            k_ref = reference_index(threshold, status)
            lo = max(0, min(kmax, k_ref - nb))
            if (.not. any(hybrid%asked_cheap(lo:kmax))) exit
            lo = max(0, min(kmax, k_ref - nb*2**min(20, max(0, report%rounds - 2))))
            hi = min(kmax, k_ref)
            do k = kmax, lo, -1
                if (hybrid%asked_cheap(k)) then
                    hi = max(k, hi)
                    exit
                end if
            end do
            hybrid%confirm(lo:hi) = .true.
        end do
        call finish()

    contains

        !> One `find_threshold` with the hybrid oracle as it stands; the oracle's own counts are the real cost.
        subroutine search(a, st, bisect, margin)
            !> Threshold found.
            real(wp), intent(out) :: a
            !> Its status.
            integer, intent(out) :: st
            !> Bisect the bracket (the first, screening search).
            logical, intent(in), optional :: bisect
            !> Margin of the answer just below the threshold (`find_threshold`'s `margin_below`).
            real(wp), intent(out), optional :: margin

            hybrid%asked_cheap = .false.
            hybrid%last_failed = .false.
            call find_threshold(hybrid, a_min, a_max, coarse_step, resolution, a, n_asked, ignored_steps, st, bisect, &
                                margin)
        end subroutine search

        !> Fill the report and the totals.
        subroutine finish()
            integer :: kk, k_t
            integer(int8) :: cheap_answer

            report%runs_screened = hybrid%runs_screened
            report%runs_confirmed = hybrid%runs_confirmed
            report%runs_doubtful = hybrid%runs_doubtful
            report%steps_screened = hybrid%steps_screened
            report%steps_confirmed = hybrid%steps_confirmed
            runs = hybrid%runs_screened + hybrid%runs_confirmed
            steps = hybrid%steps_screened + hybrid%steps_confirmed
            if (any(hybrid%confirm)) then
                report%band_low = a_min + real(findloc(hybrid%confirm, .true., dim=1) - 1, wp)*resolution
                report%band_high = a_min + real(findloc(hybrid%confirm, .true., dim=1, back=.true.) - 1, wp)*resolution
            end if
            k_t = -1
            if (status == search_found .or. status == search_at_lower_bound) k_t = grid_index(threshold)
            do kk = 0, kmax
                if (hybrid%exact_memo(kk) == unknown .or. hybrid%cheap_memo(kk) == unknown) cycle
                if (hybrid%exact_memo(kk) == failing .or. hybrid%cheap_memo(kk) == failing) cycle
                cheap_answer = merge(quiet, hybrid%cheap_memo(kk), hybrid%cheap_memo(kk) == doubtful)
                if (hybrid%exact_memo(kk) == cheap_answer) cycle
                report%disagreements = report%disagreements + 1
                if (k_t >= 0) report%farthest_disagreement = max(report%farthest_disagreement, &
                                                                 real(abs(kk - k_t), wp)*resolution)
            end do
        end subroutine finish

        !> Grid index the confirmation is centred on: the threshold's, or k_max + 1 when none transmits.
        pure function reference_index(a, st) result(kk)
            !> Threshold found.
            real(wp), intent(in) :: a
            !> Its status.
            integer, intent(in) :: st
            integer :: kk

            kk = kmax + 1
            if (st == search_found .or. st == search_at_lower_bound) kk = grid_index(a)
        end function reference_index

        !> Grid index of a grid amplitude.
        pure function grid_index(a) result(kk)
            !> Grid amplitude.
            real(wp), intent(in) :: a
            integer :: kk

            kk = nint((a - a_min)/resolution)
        end function grid_index

    end subroutine find_threshold_screened

    !> Answer grid amplitude `amplitude`: the exact oracle inside the confirmation set (or where the cheap one
    !> failed, or was quiet with a margin below `doubt`), the cheap one outside; remembered answers cost nothing.
    function hybrid_transmits(self, amplitude, cost) result(verdict)
        !> The hybrid oracle.
        class(hybrid_oracle), intent(inout) :: self
        !> Grid amplitude.
        real(wp), intent(in) :: amplitude
        !> Cost of this answer (0 when remembered).
        integer(i8), intent(out) :: cost
        logical :: verdict
        integer :: k
        integer(i8) :: c

        cost = 0_i8
        k = max(0, min(ubound(self%confirm, 1), nint((amplitude - self%a_min)/self%resolution)))
        self%last_failed = .false.
        if (.not. self%confirm(k)) then
            if (self%cheap_memo(k) == unknown) then
                verdict = self%cheap%transmits(amplitude, c)
                cost = cost + c
                self%runs_screened = self%runs_screened + 1
                self%steps_screened = self%steps_screened + c
                self%cheap_memo(k) = merge(transmitting, quiet, verdict)
                self%cheap_margin(k) = self%cheap%margin()
                if (self%cheap%failed()) then
                    self%cheap_memo(k) = failing
                else if (.not. verdict .and. self%cheap%margin() < self%doubt) then
                    self%cheap_memo(k) = doubtful
                    self%runs_doubtful = self%runs_doubtful + 1
                end if
            end if
            if (self%cheap_memo(k) /= failing .and. self%cheap_memo(k) /= doubtful) then
                self%asked_cheap(k) = .true.
                verdict = self%cheap_memo(k) == transmitting
                self%last_margin = self%cheap_margin(k)
                return
            end if
        end if
        if (self%exact_memo(k) == unknown) then
            verdict = self%exact%transmits(amplitude, c)
            cost = cost + c
            self%runs_confirmed = self%runs_confirmed + 1
            self%steps_confirmed = self%steps_confirmed + c
            self%exact_memo(k) = merge(transmitting, quiet, verdict)
            self%exact_margin(k) = self%exact%margin()
            if (self%exact%failed()) self%exact_memo(k) = failing
        end if
        self%last_failed = self%exact_memo(k) == failing
        self%last_margin = self%exact_margin(k)
        verdict = self%exact_memo(k) == transmitting
    end function hybrid_transmits

    !> Whether the last answer came from a failed exact run.
    function hybrid_failed(self) result(failed)
        !> The hybrid oracle.
        class(hybrid_oracle), intent(in) :: self
        logical :: failed

        failed = self%last_failed
    end function hybrid_failed

    !> Margin of the last answer: that of the oracle's run that gave it (remembered with the answer).
    function hybrid_margin(self) result(margin)
        !> The hybrid oracle.
        class(hybrid_oracle), intent(in) :: self
        real(wp) :: margin

        margin = self%last_margin
    end function hybrid_margin

end module supratrans_screened_search
