!> One point of a fold line: the branch of driven periodic states of one run (chain, Omega, method, dt) continued
!> from rest to its fold (`supratrans_continuation` on the one-period map `supratrans_period_map`), reduced to the
!> continuation scene's record (`supratrans_fold_record`).
!>
!> The model's threshold is the smaller of the fold A_f and the first loss of Floquet stability met on the way;
!> the record says which one it is (`threshold_kind`, the codes of `instability_type_codes`). With &scene chain =
!> 'short' the run's chain is the short chain of `supratrans_short_chain` (re-exported here).
!>
!> **The fold protocol** past the fold or a loss of stability below it: its units in `src/scenes/protocol/` (the
!> fate `supratrans_protocol_fate`, the following `supratrans_protocol_follow`, the branch switch
!> `supratrans_protocol_switch`, the stairs `supratrans_stairs`), their outcomes written as the files' codes by
!> `supratrans_protocol_codes` (`fate_codes`, `fold_fate`, ... re-exported here).
!>
!> **The branch from rest on half a period.** For the fold alone (`floquet_every = 0`) with M even, the branch from
!> rest is continued on the half-period map G of `supratrans_period_map` (P = G o G; the branch from rest is made of
!> G's fixed points), at half the cost of every map and Jacobian; the fold's state is a fixed point of P, its residual
!> is P's, its multipliers are P's (the squares of G's), and its fate is tested with P. The fold is G's, which is
!> P's (to the location tolerance) unless P's continuation leaves the symmetric branch at a branch point, which G
!> cannot (docs/continuation_reference.md gives the paper grid both ways). Such a branch point is where a real multiplier of G
!> passes -1 (P's passes +1 and the half-period symmetry breaks): the fold alone watches for it (`flip_watch` of the
!> continuation, which also sees P's real multipliers through +1 where M is odd) and reports it as the first loss
!> of stability, type 1 (a real multiplier through +1 where the branch does not turn), below the symmetric branch's
!> fold. A slow ramp never reaches that fold: where the transmission is asked for (`fate`), the scene switches there
!> to the branch of states without the symmetry (`past_loss` of `supratrans_protocol_switch`, on P). A branch
!> followed past a localized fold goes on G too when the periodic state the chain settled on has the symmetry
!> (G(x) = x to `symmetric_tol`; the chain may settle on one without it), and on P otherwise.
module supratrans_fold_line
    use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
    use supratrans_kinds, only: wp
    use supratrans_error, only: error_type
    use supratrans_config, only: run_config, scene_params
    use supratrans_short_chain, only: shortest_chain, chain_length_given, scheme_decay_rate, harmonic_wavenumber
    use supratrans_strings, only: int_str
    use supratrans_period_map, only: period_map, period_map_init, set_half_period
    use supratrans_fixed_point_map, only: map_ok
    use supratrans_continuation, only: continue_branch, branch_multipliers, continuation_controls, &
                                       continuation_result, cont_fold_found, cont_no_fold, &
                                       cont_newton_failed, cont_step_too_small, cont_max_points, cont_unstable_start, &
                                       continuation_status_name
    use supratrans_floquet, only: crossing_none, crossing_fold, crossing_period_doubling, crossing_torus, &
                                  crossing_name
    use supratrans_fold_record, only: fold_record, branch_quantities, kept_multipliers, multiplier_samples, &
                                      add_branch_cost
    use supratrans_protocol_fate, only: fold_fate
    use supratrans_protocol_follow, only: transmission_after, counted_fate, half_period_symmetric
    use supratrans_protocol_switch, only: past_loss, switch_no_stairs
    use supratrans_protocol_codes, only: fate_codes, transmission_status_codes, branch_switch_codes, fold_fate_code, &
                                         transmission_code, branch_switch_code
    implicit none
    private

    public :: trace_fold, fold_status_codes, instability_type_codes, shortest_chain, chain_length_given
    public :: scheme_decay_rate, harmonic_wavenumber, fate_codes, fold_fate, transmission_status_codes, branch_switch_codes
    public :: half_period_symmetric

    !> Status: the fold was found and located.
    integer, parameter, public :: fold_found = cont_fold_found
    !> Status: the one-period map could not be set up (e.g. more steps a period than the limit).
    integer, parameter, public :: fold_map_failed = 5

contains

    !> Continue the branch of `run` (its drive frequency set; amplitude and ramp unused) with the scene's controls
    !> and fill `r`: fold, stability, branch, multipliers at four points (`keep_multipliers`), costs.
    subroutine trace_fold(run, scene, r, keep_multipliers, fate)
        !> The run: chain, drive frequency, numerics.
        type(run_config), intent(in) :: run
        !> The scene's controls (amplitude_max, continuation_step, continuation_step_max, continuation_points,
        !> beyond_fold, crossing_tol, floquet_every) and its fold protocol (`scene%protocol`).
        type(scene_params), intent(in) :: scene
        !> The record (from `empty_fold_record`): filled.
        type(fold_record), intent(inout) :: r
        !> Compute the multipliers at the sampled points (one Jacobian and one eigenvalue call each).
        logical, intent(in) :: keep_multipliers
        !> Test the fold's fate and follow the chain past a localized fold (default: yes; no for a fold alone).
        logical, intent(in), optional :: fate
        type(period_map) :: map
        type(continuation_controls) :: ctl
        type(continuation_result) :: res
        type(error_type), allocatable :: error
        integer :: npts, k, s, last, fate_outcome, switch_outcome, transmission, ended
        real(wp) :: fate_time
        integer :: samples(multiplier_samples)
        real(wp), allocatable :: settled(:)
        logical :: test_fate, half, switch

        call period_map_init(map, run, error)
        if (allocated(error)) then
            r%status = fold_map_failed
            return
        end if
        r%dt_used = map%dt_used
        r%chain_n = run%chain%n
        r%chain_n0 = run%chain%n0
        r%chain_sigma = run%chain%sigma
        r%steps_per_period = map%steps
        ctl%newton_tol = scene%protocol%continuation_tol
        ctl%newton_max_iter = scene%protocol%continuation_max_iter
        ctl%chord_rate = scene%protocol%continuation_chord_rate
        ctl%newton_fast = scene%protocol%continuation_fast_iter
        ctl%newton_slow = scene%protocol%continuation_slow_iter
        ctl%ds_min = scene%protocol%continuation_step_min
        ctl%max_angle = scene%protocol%continuation_max_angle
        ctl%fold_tol = scene%protocol%fold_tol
        ctl%ds0 = scene%continuation_step
        ctl%ds_max = scene%continuation_step_max
        ctl%max_points = scene%continuation_points
        ctl%amplitude_max = scene%amplitude_max
        ctl%crossing_tol = scene%crossing_tol
        ctl%beyond_fold = scene%beyond_fold
        ctl%floquet_every = scene%floquet_every
        test_fate = .true.
        if (present(fate)) test_fate = fate
        ! the fold alone watches the sign of det(J + I) for a loss of stability before the fold; the fold of a
        ! convergence check (no fate) is all that is asked of it
        ctl%flip_watch = test_fate
        ! the fold alone, with M even: the branch from rest on the half-period map G (P = G o G; module docs)
        half = .false.
        if (scene%floquet_every == 0) call set_half_period(map, .true., half)
        call continue_branch(map, ctl, res)
        if (half) call back_to_period(map, res)

        r%status = res%status
        r%fold_amplitude = res%fold_amplitude
        r%fold_residual = res%fold_residual
        r%instability_amplitude = res%instability_amplitude
        r%instability_lower = res%instability_lower
        r%instability_type = res%instability_type
        r%threshold = r%fold_amplitude
        r%threshold_kind = merge(crossing_fold, crossing_none, .not. ieee_is_nan(r%fold_amplitude))
        if (.not. ieee_is_nan(r%instability_amplitude)) then
            if (ieee_is_nan(r%threshold) .or. r%instability_amplitude < r%threshold) then
                r%threshold = r%instability_amplitude
                r%threshold_kind = r%instability_type
            end if
        end if
        last = res%n_points
        if (res%fold_index > 0) last = res%fold_index
        if (last > 0) then
            if (any(.not. ieee_is_nan(res%max_multiplier(1:last)))) then
                r%instability_size = maxval(res%max_multiplier(1:last), &
                                            mask=.not. ieee_is_nan(res%max_multiplier(1:last))) - 1.0_wp
            end if
        end if
        ! a loss of stability below the fold: a slow ramp leaves the branch from rest there, at a branch point (a
        ! real multiplier through +1, the branch not turning) for the other branch or for what the chain does past it
        ! (a branch point: the other branch; a torus or a period doubling: no branch to switch to, the stairs)
        switch = test_fate .and. r%threshold_kind /= crossing_none .and. allocated(res%instability_point)
        if (switch) switch = .not. (r%threshold >= r%fold_amplitude)
        if (switch) then
            call past_loss(map, run, scene%protocol, ctl, res, r%threshold_kind, r%fold_amplitude, r, switch_outcome, &
                           transmission, ended)
            r%branch_switch = branch_switch_code(switch_outcome)
            switch = switch_outcome /= switch_no_stairs
            if (switch) r%transmission_status = transmission_code(transmission, ended)
        end if
        ! the fold's fate (and, where no loss of stability below it was followed, where the chain transmits past it)
        if (test_fate .and. res%fold_index > 0 .and. .not. ieee_is_nan(r%fold_amplitude)) then
            call counted_fate(map, run, scene%protocol, res%states(:, res%fold_index), &
                              res%fold_amplitude*(1.0_wp + scene%protocol%fate_push), r, fate_outcome, fate_time, settled)
            r%fate = fold_fate_code(fate_outcome)
            r%fate_time = fate_time
            if (.not. switch) then
                r%branches = 1
                call transmission_after(map, run, scene%protocol, ctl, res%fold_amplitude, fate_outcome, settled, r, &
                                        transmission, ended)
                r%transmission_status = transmission_code(transmission, ended)
            end if
        end if
        call add_branch_cost(r, res)
        npts = min(res%n_points, size(r%branch, 2))
        r%points = npts
        do k = 1, npts
            r%branch(:, k) = [res%amplitude(k), res%umax(k), res%energy(k), res%max_multiplier(k), &
                              real(res%stable(k), wp), real(res%newton_iterations(k), wp), res%residual(k)]
        end do
        if (.not. keep_multipliers .or. res%n_points < 1) return
        samples = [1, nearest_point(res, 0.5_wp*r%fold_amplitude), res%fold_index, res%n_points]
        ! the fold alone (floquet_every = 0): its own multipliers only, no spectra computed for the samples
        if (scene%floquet_every == 0) samples = [0, 0, res%fold_index, 0]
        do s = 1, multiplier_samples
            if (samples(s) < 1) cycle
            call sample(samples(s), s)
        end do

    contains

        !> The multipliers of largest modulus at branch point i into sample s.
        subroutine sample(i, s)
            integer, intent(in) :: i, s
            real(wp), allocatable :: wr(:), wi(:)
            integer :: info, j, m
            integer, allocatable :: order(:)
            logical :: kept

            kept = .false.
            if (allocated(res%spectra)) then
                if (size(res%spectra) >= i) kept = allocated(res%spectra(i)%wr)
            end if
            call branch_multipliers(map, res, i, wr, wi, info)
            if (.not. kept) then                    ! computed afresh: one Jacobian and one eigenvalue call
                r%eigen_calls = r%eigen_calls + 1
                r%jacobians = r%jacobians + 1
                r%map_evaluations = r%map_evaluations + 1
            end if
            if (info /= 0) return
            order = largest_first(hypot(wr, wi))
            m = min(kept_multipliers, size(order))
            do j = 1, m
                r%multiplier_re(j, s) = wr(order(j))
                r%multiplier_im(j, s) = wi(order(j))
            end do
            r%multiplier_amplitude(s) = res%amplitude(i)
        end subroutine sample

    end subroutine trace_fold

    !> After a branch continued on the half-period map G: `map` made P again, the fold's residual taken as P's
    !> (|P(x) - x| <= (1 + |dG/dx|) |G(x) - x|: the periodic state's, not G's), and the multipliers kept with the
    !> branch and their largest moduli squared (P's multipliers at a fixed point of G are the squares of G's).
    subroutine back_to_period(map, res)
        !> The map (G on entry, P on exit).
        type(period_map), intent(inout) :: map
        !> The branch.
        type(continuation_result), intent(inout) :: res
        real(wp), allocatable :: px(:)
        integer :: status, i
        logical :: ok

        call set_half_period(map, .false., ok)
        ! G's real multiplier through -1 is P's through +1 (mu_P = mu_G^2) where the branch does not turn: a branch
        ! point of P at which the half-period symmetry breaks, not a period doubling of the state
        if (res%instability_type == crossing_period_doubling) res%instability_type = crossing_fold
        res%max_multiplier(1:res%n_points) = res%max_multiplier(1:res%n_points)**2
        if (allocated(res%spectra)) then
            do i = 1, min(res%n_points, size(res%spectra))
                if (allocated(res%spectra(i)%wr)) call square_multipliers(res%spectra(i)%wr, res%spectra(i)%wi)
            end do
        end if
        if (res%fold_index < 1) return
        allocate (px(map%dim))
        call map%apply(res%states(:, res%fold_index), res%fold_amplitude, px, status)
        res%stats%map_evaluations = res%stats%map_evaluations + 1
        if (status == map_ok) res%fold_residual = maxval(abs(px - res%states(:, res%fold_index)))
    end subroutine back_to_period

    !> The squares of the complex numbers wr + i wi, in place.
    pure subroutine square_multipliers(wr, wi)
        !> Real and imaginary parts.
        real(wp), intent(inout) :: wr(:), wi(:)
        real(wp), allocatable :: re(:)

        re = wr**2 - wi**2
        wi = 2.0_wp*wr*wi
        wr = re
    end subroutine square_multipliers

    !> The branch point whose amplitude is nearest `a` among those before the fold with multipliers (any, when none
    !> has them; 0 when there is no point).
    pure function nearest_point(res, a) result(i)
        !> The branch.
        type(continuation_result), intent(in) :: res
        !> The amplitude.
        real(wp), intent(in) :: a
        integer :: i, last

        i = 0
        if (ieee_is_nan(a) .or. res%n_points < 1) return
        last = res%n_points
        if (res%fold_index > 0) last = res%fold_index
        if (any(res%stable(1:last) /= -1)) then       ! prefer a point whose multipliers the continuation kept
            i = minloc(abs(res%amplitude(1:last) - a), dim=1, mask=res%stable(1:last) /= -1)
        else
            i = minloc(abs(res%amplitude(1:last) - a), dim=1)
        end if
    end function nearest_point

    !> Indices of x in order of decreasing value (a stable insertion sort: a handful of hundreds of values).
    pure function largest_first(x) result(order)
        !> The values.
        real(wp), intent(in) :: x(:)
        integer, allocatable :: order(:)
        integer :: i, j, key

        order = [(i, i=1, size(x))]
        do i = 2, size(x)
            key = order(i)
            j = i - 1
            do while (j >= 1)
                if (x(order(j)) >= x(key)) exit
                order(j + 1) = order(j)
                j = j - 1
            end do
            order(j + 1) = key
        end do
    end function largest_first

    !> The continuation statuses as "code name: meaning" clauses (the `/status` codes attribute).
    pure function fold_status_codes() result(text)
        character(len=:), allocatable :: text

        text = int_str(cont_fold_found) // " " // continuation_status_name(cont_fold_found) // ": the fold was " &
            // "found and located; " // int_str(cont_no_fold) // " " // continuation_status_name(cont_no_fold) &
            // ": no fold below amplitude_max (NaN); " // int_str(cont_newton_failed) // " " &
            // continuation_status_name(cont_newton_failed) // ": Newton-shooting failed at the start; " &
            // int_str(cont_step_too_small) // " " // continuation_status_name(cont_step_too_small) &
            // ": the step fell below its minimum before a fold; " // int_str(cont_max_points) // " " &
            // continuation_status_name(cont_max_points) // ": continuation_points reached before a fold; " &
            // int_str(fold_map_failed) // " map_failed: the one-period map could not be set up"
    end function fold_status_codes

    !> The instability types as "code name" clauses (the `codes` attributes of /instability_type, /threshold_kind).
    pure function instability_type_codes() result(text)
        character(len=:), allocatable :: text

        text = int_str(crossing_none) // " " // crossing_name(crossing_none) // ": stable up to the fold; " &
            // int_str(crossing_fold) // " " // crossing_name(crossing_fold) // ": a real multiplier through +1 (the " &
            // "fold itself, or a branch point where no fold is near); " &
            // int_str(crossing_period_doubling) // " " // crossing_name(crossing_period_doubling) &
            // ": a real multiplier through -1; " // int_str(crossing_torus) // " " // crossing_name(crossing_torus) &
            // ": a complex pair leaves the unit circle"
    end function instability_type_codes

end module supratrans_fold_line
