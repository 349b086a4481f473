!> The search for a supratransmission threshold: the *smallest* driving amplitude at which a run transmits (the
!> paper's definition, Sec. 4.3: "smallest driving amplitude value at which supratransmission begins").
!>
!> The search is generic over the verdict: it asks a `verdict_oracle` whether amplitude A transmits, and the
!> oracle says what the answer cost (time steps). The scene `bifurcation` uses an oracle that runs one simulation;
!> the tests use synthetic ones.
!>
!> ## Algorithm
!> All amplitudes are points of the integer grid A_k = a_min + k * resolution, k = 0 .. k_max,
!> k_max = floor((a_max - a_min) / resolution) (with a tolerance of 1e-9 grid units against roundoff), so that a
!> threshold is always a grid point, computed the same way by every thread and every run. The coarse step is
!> m = max(1, nint(coarse_step / resolution)) grid points (`effective_coarse_step` gives m * resolution).
!>
!> 1. Coarse scan, upward: k = 0, m, 2m, ..., and k_max itself if it is not a multiple of m, up to the first
!>    transmitting point k_hit. None transmits: status `search_none`, threshold NaN.
!> 2. Fine scan of the bracket (k_hit - m, k_hit], upward, one grid point at a time, up to the first transmitting
!>    point (k_hit itself is known to transmit and is not asked again). This is a scan, not a bisection: if the
!>    verdict is not monotone inside the bracket (transmits, stops, transmits again), the smallest transmitting
!>    point of the bracket is still the one found.
!>
!> If k_hit = 0 (a_min already transmits) the threshold returned is a_min with status `search_at_lower_bound`: the
!> true threshold may lie below the search range.
!>
!> ## The one assumption
!> The coarse scan only sees transmitting amplitudes that are coarse points. A transmitting window that holds no
!> coarse point (necessarily narrower than the coarse step) and lies below the first coarse hit is missed: the
!> threshold returned is then the smallest transmitting amplitude *above the last non-transmitting coarse point*,
!> not the global one. A window at least one coarse step wide always holds a coarse point and is never missed.
!> Inside the final bracket nothing is missed.
!>
!> ## Cost
!> With the first coarse hit at k_hit, the coarse point before it at k_prev (= k_hit - m, except at the end point
!> k_max) and the threshold at k_t, the search asks k_hit/m + 1 coarse points (one more when k_hit = k_max is not a
!> multiple of m) and k_t - k_prev fine points (k_hit - k_prev - 1 when k_t = k_hit): about
!> (A_t - a_min)/coarse_step + coarse_step/(2 resolution) runs on average, at most
!> (A_t - a_min)/coarse_step + coarse_step/resolution + 1. coarse_step ~ sqrt(2 resolution (A_t - a_min)) minimises
!> it. A search where nothing transmits asks every coarse point. Every question but the last of each scan is
!> answered "does not transmit", which for a simulation oracle is the expensive answer (a full-length run).
module supratrans_threshold
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan, ieee_is_finite
    use supratrans_kinds, only: wp, i8
    use supratrans_status, only: search_found, search_at_lower_bound, search_none, search_failed, &
                                 search_bad_arguments, search_status_name, search_status_codes
    implicit none
    private

    public :: find_threshold, effective_coarse_step, search_grid_size, search_status_name, search_status_codes

    !> The search statuses (`supratrans_status`).
    public :: search_found, search_at_lower_bound, search_none, search_failed, search_bad_arguments

    !> Tolerance, in grid units, of the number of grid points that fit in a range (against roundoff).
    real(wp), parameter :: grid_tolerance = 1.0e-9_wp

    !> Something that decides whether a run at a given driving amplitude transmits.
    type, abstract, public :: verdict_oracle
    contains
        !> Whether amplitude `amplitude` transmits; `cost` returns what the answer cost (time steps).
        procedure(transmits_interface), deferred :: transmits
        !> Whether the last verdict is unusable (the run failed before deciding); default: never.
        procedure :: failed => oracle_never_fails
        !> Why the oracle failed (empty when it did not); default: empty.
        procedure :: failure_reason => oracle_no_reason
        !> Margin of the last verdict: how far the run stayed from the detection amplitude, relative to it.
        procedure :: margin => oracle_full_margin
    end type verdict_oracle

    abstract interface
        !> Ask the oracle whether amplitude `amplitude` transmits.
        function transmits_interface(self, amplitude, cost) result(transmitting)
            import :: verdict_oracle, wp, i8
            !> The oracle (may keep counts or the last failure).
            class(verdict_oracle), intent(inout) :: self
            !> Driving amplitude A.
            real(wp), intent(in) :: amplitude
            !> Cost of the answer: time steps spent.
            integer(i8), intent(out) :: cost
            logical :: transmitting
        end function transmits_interface
    end interface

contains

    !> Default `failed`: an oracle that cannot fail.
    function oracle_never_fails(self) result(failed)
        !> The oracle.
        class(verdict_oracle), intent(in) :: self
        logical :: failed

        failed = .false.
    end function oracle_never_fails

    !> Default `failure_reason`: empty.
    function oracle_no_reason(self) result(reason)
        !> The oracle.
        class(verdict_oracle), intent(in) :: self
        character(len=:), allocatable :: reason

        reason = ""
    end function oracle_no_reason

    !> Default margin: 1 (an oracle without a measure of doubt: every verdict is clear).
    function oracle_full_margin(self) result(margin)
        !> The oracle.
        class(verdict_oracle), intent(in) :: self
        real(wp) :: margin

        margin = 1.0_wp
    end function oracle_full_margin

    !> The coarse step actually used: the nearest multiple (at least 1) of `resolution`.
    elemental function effective_coarse_step(coarse_step, resolution) result(step)
        !> Requested coarse step.
        real(wp), intent(in) :: coarse_step
        !> Resolution of the threshold.
        real(wp), intent(in) :: resolution
        real(wp) :: step

        step = real(coarse_multiple(coarse_step, resolution), wp)*resolution
    end function effective_coarse_step

    !> Number of points of the grid x_k = x_min + k step, k = 0 .. n-1, that lie in [x_min, x_max] (with a tolerance of
    !> 1e-9 steps against roundoff); 0 if x_max < x_min or step <= 0 or anything is not finite.
    elemental function search_grid_size(x_min, x_max, step) result(n)
        !> Start of the grid.
        real(wp), intent(in) :: x_min
        !> Upper end of the range.
        real(wp), intent(in) :: x_max
        !> Grid step.
        real(wp), intent(in) :: step
        integer :: n

        n = 0
        if (.not. (ieee_is_finite(x_min) .and. ieee_is_finite(x_max) .and. ieee_is_finite(step))) return
        if (step <= 0.0_wp .or. x_max < x_min) return
        n = floor((x_max - x_min)/step + grid_tolerance) + 1
    end function search_grid_size

    !> Find the smallest amplitude of [a_min, a_max] at which `oracle` transmits, to within `resolution` (see the
    !> module documentation for the algorithm, its one assumption and its cost).
    subroutine find_threshold(oracle, a_min, a_max, coarse_step, resolution, threshold, runs, steps, status, bisect, &
                              margin_below)
        !> Decides whether an amplitude transmits.
        class(verdict_oracle), intent(inout) :: oracle
        !> Lower end of the search range.
        real(wp), intent(in) :: a_min
        !> Upper end of the search range.
        real(wp), intent(in) :: a_max
        !> Step of the coarse upward scan (rounded to a multiple of `resolution`).
        real(wp), intent(in) :: coarse_step
        !> Resolution of the threshold: the grid step of the fine scan.
        real(wp), intent(in) :: resolution
        !> The smallest transmitting grid amplitude a_min + k resolution found; NaN when none.
        real(wp), intent(out) :: threshold
        !> Number of questions asked (runs).
        integer, intent(out) :: runs
        !> Total cost of the questions (time steps).
        integer(i8), intent(out) :: steps
        !> `search_found`, `search_at_lower_bound`, `search_none`, `search_failed` or `search_bad_arguments`.
        integer, intent(out) :: status
        !> Bisect the bracket instead of scanning it (default false): log2(coarse_step/resolution) questions instead
        !> of up to coarse_step/resolution - 1, and *a* grid point where the verdict changes inside the bracket, not
        !> necessarily the smallest; an estimate (the screened search places its confirmation band with it).
        logical, intent(in), optional :: bisect
        !> The oracle's margin (`margin`) of its quiet answer at the grid point just below the threshold, the run
        !> that came closest to transmitting without doing so; NaN unless the status is `search_found`.
        real(wp), intent(out), optional :: margin_below
        integer :: m, kmax, k, k_prev, k_hit, k_found, k_low, k_fine
        logical :: hit, bisecting
        real(wp) :: m_prev, m_fine, m_low

        threshold = ieee_value(threshold, ieee_quiet_nan)
        if (present(margin_below)) margin_below = threshold
        m_prev = threshold
        m_fine = threshold
        k_fine = -1
        runs = 0
        steps = 0_i8
        if (.not. (ieee_is_finite(a_min) .and. ieee_is_finite(a_max) .and. ieee_is_finite(coarse_step) &
                   .and. ieee_is_finite(resolution))) then
            status = search_bad_arguments
            return
        end if
        if (resolution <= 0.0_wp .or. coarse_step < resolution .or. a_max < a_min) then
            status = search_bad_arguments
            return
        end if
        m = coarse_multiple(coarse_step, resolution)
        kmax = search_grid_size(a_min, a_max, resolution) - 1

        ! 1. coarse scan k = 0, m, 2m, ... (and k_max), up to the first transmitting point
        k_prev = -1
        k_hit = -1
        k = 0
        do
            call ask(k, hit)
            if (status == search_failed) return
            if (hit) then
                k_hit = k
                exit
            end if
            if (k == kmax) exit
            k_prev = k
            m_prev = oracle%margin()
            k = min(k + m, kmax)
        end do
        if (k_hit < 0) then
            status = search_none
            return
        end if
        if (k_hit == 0) then
            threshold = grid_amplitude(0)
            status = search_at_lower_bound
            return
        end if

        ! 2. fine scan of the bracket (k_prev, k_hit), upward; k_hit is known to transmit
        k_found = k_hit
        bisecting = .false.
        if (present(bisect)) bisecting = bisect
        if (bisecting) then
            k_low = k_prev
            m_low = m_prev
            do while (k_found - k_low > 1)
                k = k_low + (k_found - k_low)/2
                call ask(k, hit)
                if (status == search_failed) return
                if (hit) then
                    k_found = k
                else
                    k_low = k
                    m_low = oracle%margin()
                end if
            end do
            k_fine = k_low
            m_fine = m_low
        else
            do k = k_prev + 1, k_hit - 1
                call ask(k, hit)
                if (status == search_failed) return
                if (hit) then
                    k_found = k
                    exit
                end if
                k_fine = k
                m_fine = oracle%margin()
            end do
        end if
        threshold = grid_amplitude(k_found)
        status = search_found
        ! the grid point below the threshold was the last quiet answer of the fine scan, or the coarse one before it
        if (present(margin_below)) margin_below = merge(m_fine, m_prev, k_fine == k_found - 1)

    contains

        !> Amplitude of grid point kk.
        pure function grid_amplitude(kk) result(a)
            !> Grid index.
            integer, intent(in) :: kk
            real(wp) :: a

            a = a_min + real(kk, wp)*resolution
        end function grid_amplitude

        !> Ask the oracle about grid point kk; a failure sets `status = search_failed`.
        subroutine ask(kk, transmitting)
            !> Grid index.
            integer, intent(in) :: kk
            !> The verdict (false when the oracle failed).
            logical, intent(out) :: transmitting
            integer(i8) :: cost

            transmitting = oracle%transmits(grid_amplitude(kk), cost)
            runs = runs + 1
            steps = steps + cost
            status = search_found
            if (oracle%failed()) then
                transmitting = .false.
                status = search_failed
            end if
        end subroutine ask

    end subroutine find_threshold



    !> Coarse step in grid points: nint(coarse_step / resolution), at least 1.
    elemental function coarse_multiple(coarse_step, resolution) result(m)
        !> Requested coarse step.
        real(wp), intent(in) :: coarse_step
        !> Resolution of the threshold.
        real(wp), intent(in) :: resolution
        integer :: m

        m = 1
        if (resolution > 0.0_wp .and. ieee_is_finite(coarse_step/resolution)) m = max(1, nint(coarse_step/resolution))
    end function coarse_multiple

end module supratrans_threshold
