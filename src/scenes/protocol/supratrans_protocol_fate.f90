!> The fold protocol's fate (`fold_fate`): what the chain does when driven just past a fold (or a branch point, or on
!> a stair), with the one-period map of the fold line's run. One outcome enumeration, `fate_*`; the entry point takes
!> the protocol's constants (`fold_protocol`: fate_push, fate_watch_time, fate_min_periods) and returns the outcome.
!> Where the outcome is written (/fold_fate) its code is `fold_fate_code` of `supratrans_protocol_codes`.
!>
!> A fold is the supratransmission threshold only if the chain, driven just past it, transmits. Near Omega = 1/(2k +
!> 1), where an odd harmonic of the drive sits at the lower edge of the phonon band, the branch can fold far below the
!> scan's threshold (e.g. A_f = 1.78 at Omega = 0.34 on the paper's chain, where the scan gives 4.66): such a fold
!> depends on the chain's length and absorber (docs/continuation.md) and the state beyond it need not transmit. So
!> each fold is tested: the periodic state at the fold is driven at A_f (1 + `fate_push`) at full amplitude for
!> `fate_watch_time` (at least `fate_min_periods` periods) with the one-period map of the same scheme, and it
!> transmits when, at any time level, an oscillator beyond the run's detector site (`detector_site`, the scan's own)
!> has |u_n| > the detector amplitude (pi by default), as a run's detector sees it. (Looking at the ends of the
!> periods only, the stairs of a damped chain, gamma = 0.3 at Omega = 0.55, transmitted at 7.45, where a slow-ramp
!> scan transmits at 5.21.)
module supratrans_protocol_fate
    use supratrans_kinds, only: wp
    use supratrans_config, only: run_config, fold_protocol
    use supratrans_period_map, only: period_map
    use supratrans_fixed_point_map, only: map_ok
    use supratrans_chain, only: detector_site
    use supratrans_continuation_types, only: continuation_stats, wall_clock
    implicit none
    private

    public :: fold_fate

    ! The outcomes of a fate (one enumeration).
    !> Fate: driven just past the fold, the chain transmits (the fold is the supratransmission threshold).
    integer, parameter, public :: fate_transmits = 1
    !> Fate: driven just past the fold for the time watched, the chain stays localized (it settles on another state:
    !> the fold is not where transmission starts).
    integer, parameter, public :: fate_localized = 2
    !> Fate: the one-period map failed while watching (its implicit steps did not converge).
    integer, parameter, public :: fate_failed = 3

contains

    !> The fate of a fold (see the module's documentation): from the periodic state `x` at the fold, the drive at
    !> `amplitude` (just past the fold), one period at a time, until an oscillator beyond the detector site swings
    !> past the detector amplitude (`fate_transmits`, `time` = the end of that period) or `fate_watch_time` has
    !> passed (`fate_localized`, `time` = the time watched), or `watch` (whole periods, at least one) when given.
    subroutine fold_fate(map, run, proto, x, amplitude, fate, time, last, watch, stats)
        !> The one-period map of the branch (its work arrays change).
        type(period_map), intent(inout) :: map
        !> The run (detector site and amplitude).
        type(run_config), intent(in) :: run
        !> The fold protocol (`fate_watch_time`, `fate_min_periods`).
        type(fold_protocol), intent(in) :: proto
        !> The state at the fold (u_n at t = 0 first, n = 1..N).
        real(wp), intent(in) :: x(:)
        !> Drive amplitude just past the fold.
        real(wp), intent(in) :: amplitude
        !> The outcome: `fate_transmits`, `fate_localized` or `fate_failed`.
        integer, intent(out) :: fate
        !> Time of the first transmission, or the time watched.
        real(wp), intent(out) :: time
        !> The state at the end of the watch (where the chain has settled when it stays localized).
        real(wp), allocatable, intent(out), optional :: last(:)
        !> Time to watch instead of `fate_watch_time` (and no fewest periods but one).
        real(wp), intent(in), optional :: watch
        !> Counts and times: the maps applied and their time are added.
        type(continuation_stats), intent(inout), optional :: stats
        real(wp), allocatable :: y(:), py(:)
        real(wp) :: t0
        integer :: k, periods, nd, status

        t0 = wall_clock()
        nd = detector_site(run)
        periods = max(proto%fate_min_periods, ceiling(proto%fate_watch_time/map%period))
        if (present(watch)) periods = max(1, ceiling(watch/map%period))
        y = x
        allocate (py(size(x)))
        fate = fate_localized
        ! the detector sees every level of every period (`watch_site`), as a run's does
        map%watch_site = nd
        do k = 1, periods
            call map%apply(y, amplitude, py, status)
            time = real(k, wp)*map%period
            if (status /= map_ok) then
                fate = fate_failed
                exit
            end if
            ! (beyond_max covers the levels 0..M, the end state's u = py(1:N) among them)
            if (map%beyond_max > run%detect%amplitude) then
                fate = fate_transmits
                exit
            end if
            y = py
        end do
        map%watch_site = 0
        if (present(stats)) then
            stats%map_evaluations = stats%map_evaluations + min(k, periods)
            stats%time_map = stats%time_map + wall_clock() - t0
        end if
        if (fate == fate_localized .and. present(last)) last = y
    end subroutine fold_fate

end module supratrans_protocol_fate
