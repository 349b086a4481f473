!> The stair protocol of the scene `hysteresis` (`supratrans_scene_hysteresis`) and what it measures: the drive of
!> a run up and down the stairs (`hysteresis_drive`), the mean power of each stair (`stair_powers`), the two edges
!> and the status of a run (`hysteresis_edges`, codes `hysteresis_*`). The stairs themselves, their plan, levels and
!> the reading of their verdicts into edges, are the ones of the fold protocol (`supratrans_stairs`); what is the
!> scene's own is how a stair is held (one run whose drive ramps from stair to stair) and its verdict (the power).
!>
!> **What a stair transmits.** The mean power through the bond (n_d, n_d + 1) just beyond the detector site n_d
!> (`detector_site`, the one of the bifurcation scene's verdict): J = c^2 (u_{n_d} - u_{n_d+1}) v_{n_d+1} + beta
!> (v_{n_d} - v_{n_d+1}) v_{n_d+1}, the energy per time that enters the sites beyond the detector, with v the
!> centred difference (u^{k+1} - u^{k-1}) / (2 dt) of the probes at n_d and n_d + 1 (recorded every step), averaged
!> over the last whole number of drive periods that fits in the stair's second half. Why not the injected power at
!> the driven end: with damping (gamma, beta) the evanescent, non-transmitting state dissipates near the driven end
!> a power comparable with what a transmitting state carries (0.86 measured at gamma = 0.1, Omega = 0.9, A = 1.8), so
!> the injected power does not tell transmission from local dissipation; the flux beyond the detector does, for
!> every damping: on the stable periodic state the evanescent wave is a standing wave whose flux averages to zero
!> over whole periods, and what remains is the radiation of the drive's harmonics that lie in the phonon band
!> (3 Omega at Omega = 0.9): measured 0.006 - 0.013 on the paper's chain below the threshold, against 0.3 - 4 on
!> a transmitting stair (the default power_threshold 0.05 lies between). Why not the power into the absorber: a
!> breather slowed or damped before N0 never reaches it, and the lag from the driven end to N0 (~100 time units)
!> moves a stair's energy into the next one; the lag to n_d is a few drive periods. Averaging over the second half
!> skips the transient of the stair's ramp; whole periods remove the oscillating part.
!>
!> **Edges.** A stair transmits when its mean power exceeds `power_threshold`. The upward edge is the level of the
!> first stair on the way up (j = 0 .. K) that transmits: where the transmitting state is born. The downward edge is
!> the level of the last stair on the way down (j = K .. 2K, the top included) that still transmits: where it dies.
!> The window is upward - downward (the bistable window, >= 0 when the transmitting state outlives its birth). The
!> edges are on the stair grid. Each is NaN where it does not exist, and the status says why (`hysteresis_status_codes`):
!> nothing transmits up to a_K; a_0 already transmits (the upward edge lies below amplitude_min); the last stair
!> a_0 still transmits (the downward edge lies below amplitude_min); the transmission died before the top; a run
!> failed. `/downward_gaps` counts the quiet stairs between the top and the downward edge: the transmitting regime
!> is intermittent, and this says how much. The spreads are max - min of each edge over the stair lengths (the
!> protocol's part of the edge: the model's edge, the fold of the branch of periodic states, has none).
module supratrans_hysteresis_stairs
    use supratrans_kinds, only: wp
    use supratrans_config, only: input_config, run_config, drive_params
    use supratrans_chain, only: stair_count, stair_start
    use supratrans_stairs, only: stair_plan, stairs_profile, drive_plan, plan_level, read_stairs, stairs_found, &
                                 stairs_none, stairs_at_bottom, stairs_died_before_top, stairs_still_at_end, stairs_failed
    use supratrans_result, only: run_result
    implicit none
    private

    public :: hysteresis_drive, stair_powers, hysteresis_edges, hysteresis_status_codes, hysteresis_status_code

    ! The codes of /status (a run's outcome, `stairs_*` of `supratrans_stairs`, as `hysteresis_status_code` writes it).
    !> Status: both edges found.
    integer, parameter, public :: hysteresis_found = 0
    !> Status: no stair up to a_K transmits (both edges NaN).
    integer, parameter, public :: hysteresis_none = 1
    !> Status: the first stair a_0 already transmits (the upward edge lies at or below amplitude_min: NaN).
    integer, parameter, public :: hysteresis_at_bottom = 2
    !> Status: transmission died on the way up, before the top stair (downward edge NaN).
    integer, parameter, public :: hysteresis_died_before_top = 3
    !> Status: the last stair a_0 still transmits (the downward edge lies below amplitude_min: NaN).
    integer, parameter, public :: hysteresis_still_at_end = 4
    !> Status: the run failed (diverged, Newton failed); both edges NaN.
    integer, parameter, public :: hysteresis_failed = 5

contains

    !> The drive of a hysteresis run: the curve's drive at Omega with the stair profile (a_0 = amplitude_min, height
    !> stair_height, top K, stair length T_s, ramp stair_ramp; the ramp from rest is &drive ramp_time).
    pure function hysteresis_drive(run, cfg, top, stair_time) result(r)
        !> The curve's run at its Omega.
        type(run_config), intent(in) :: run
        !> The input.
        type(input_config), intent(in) :: cfg
        !> Index K of the top level.
        integer, intent(in) :: top
        !> Stair length T_s.
        real(wp), intent(in) :: stair_time
        type(run_config) :: r
        type(stair_plan) :: plan

        plan = stair_plan(low=cfg%scene%amplitude_min, height=cfg%scene%stair_height, top=top, time=stair_time, &
                          ramp=cfg%scene%stair_ramp, down=.true.)
        r = run
        r%drive = stairs_profile(plan, r%drive)
        r%drive%amplitude = plan_level(plan, top)
        r%numerics%t_final = stair_start(r%drive, stair_count(r%drive))
        r%detect%stop_when_decided = .false.
    end function hysteresis_drive

    !> Mean power through the bond (n_d, n_d + 1) on each stair of a run (see the module documentation): from the
    !> probes at n_d and n_d + 1 recorded every step, J_k = c^2 (u_{n_d} - u_{n_d+1}) v_{n_d+1} + beta (v_{n_d} -
    !> v_{n_d+1}) v_{n_d+1} at level k with centred velocities, averaged over the levels of the last whole number of
    !> drive periods (at least one, at most the stair's second half) before the stair's end.
    pure function stair_powers(run, result) result(power)
        !> The run (stair profile).
        type(run_config), intent(in) :: run
        !> Its result, probes (n_d, n_d + 1) every step.
        type(run_result), intent(in) :: result
        real(wp), allocatable :: power(:)
        real(wp) :: dt, t_end, t_begin, period, c2, v1, v2, flux, total
        integer :: j, k, nsamp, kcount

        dt = run%numerics%dt
        c2 = run%chain%c**2
        period = 8.0_wp*atan(1.0_wp)/run%drive%omega
        nsamp = result%n_probe_samples
        allocate (power(stair_count(run%drive)))
        do j = 0, stair_count(run%drive) - 1
            t_end = stair_start(run%drive, j + 1)
            t_begin = t_end - max(1.0_wp, real(floor(0.5_wp*run%drive%stair_time/period), wp))*period
            total = 0.0_wp
            kcount = 0
            do k = 2, nsamp - 1
                associate (t => result%probe_time(k), u => result%probe_u)
                    if (t < t_begin - 0.5_wp*dt .or. t >= t_end - 0.5_wp*dt) cycle
                    v1 = (u(k + 1, 1) - u(k - 1, 1))/(2.0_wp*dt)
                    v2 = (u(k + 1, 2) - u(k - 1, 2))/(2.0_wp*dt)
                    flux = c2*(u(k, 1) - u(k, 2))*v2 + run%chain%beta*(v1 - v2)*v2
                end associate
                total = total + flux
                kcount = kcount + 1
            end do
            power(j + 1) = total/real(max(kcount, 1), wp)
        end do
    end function stair_powers

    !> The edges from the stairs' mean powers (see the module documentation): a stair transmits when its power exceeds
    !> `threshold`, and its verdicts are read by `read_stairs` into the upward edge (first transmitting stair on the
    !> way up), the downward edge (last transmitting stair on the way down, the top included), the quiet stairs
    !> between the top and the downward edge, and the status.
    pure subroutine hysteresis_edges(drive, power, threshold, up, down, gaps, status)
        !> The drive (stair profile: levels).
        type(drive_params), intent(in) :: drive
        !> Mean power of each stair, 2K + 1 values (K the drive's `stair_top`).
        real(wp), intent(in) :: power(:)
        !> A stair transmits when its power exceeds this.
        real(wp), intent(in) :: threshold
        !> Upward edge; NaN when none.
        real(wp), intent(out) :: up
        !> Downward edge; NaN when none.
        real(wp), intent(out) :: down
        !> Quiet stairs from the top down to the downward edge.
        integer, intent(out) :: gaps
        !> `hysteresis_*` status.
        integer, intent(out) :: status
        type(stair_plan) :: plan
        integer :: outcome

        plan = drive_plan(drive)
        call read_stairs(plan, power > threshold, up, down, gaps, outcome)
        status = hysteresis_status_code(outcome)
    end subroutine hysteresis_edges

    !> The /status code of a run's stairs (`stairs_*` of `supratrans_stairs`): the one place they are mapped.
    pure integer function hysteresis_status_code(outcome)
        !> The outcome.
        integer, intent(in) :: outcome

        select case (outcome)
        case (stairs_found)
            hysteresis_status_code = hysteresis_found
        case (stairs_none)
            hysteresis_status_code = hysteresis_none
        case (stairs_at_bottom)
            hysteresis_status_code = hysteresis_at_bottom
        case (stairs_died_before_top)
            hysteresis_status_code = hysteresis_died_before_top
        case (stairs_still_at_end)
            hysteresis_status_code = hysteresis_still_at_end
        case (stairs_failed)
            hysteresis_status_code = hysteresis_failed
        case default
            hysteresis_status_code = hysteresis_failed
        end select
    end function hysteresis_status_code

    !> The status codes of the scene, "code: meaning" clauses separated by "; ".
    pure function hysteresis_status_codes() result(text)
        character(len=:), allocatable :: text

        text = "-2: outside gap (Omega >= sqrt(V''(0) + m^2): not run; NaN); -1: pending (not computed yet); " &
               // "0: found (both edges); 1: none transmits (no stair up to the top transmits; NaN); " &
               // "2: at bottom (the first stair amplitude_min already transmits: the upward edge lies below it; NaN); " &
               // "3: died before top (the transmission stopped on the way up: downward edge NaN); " &
               // "4: still at end (the last stair amplitude_min still transmits: the downward edge lies below it; NaN); " &
               // "5: run failed (diverged or Newton failed; NaN)"
    end function hysteresis_status_codes

end module supratrans_hysteresis_stairs
