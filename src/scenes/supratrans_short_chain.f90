!> The short chain of fold lines (`shortest_chain`, issue 25 point 6; `supratrans_fold_line` re-exports it).
!>
!> The periodic state is localized at the driven end: at small amplitude it decays as e^{-lambda' n}, lambda' the
!> scheme's own decay rate (NOTES.md: cosh lambda' = 1 + ((V''(0) + m^2) cos(Omega dt) - (2 sin(Omega dt / 2) / dt)^2) / (2
!> c^2)). Beyond the core, what matters is the absorber: the state radiates its odd harmonics (3 Omega, 5 Omega, ... in
!> the phonon band), and whatever the absorber reflects moves A_f (by 2e-5 at Omega = 0.9 and 1e-3 .. 4e-2 at 0.7 ..
!> 0.5 with the paper's absorber, N - N0 = 50, sigma = 3; by up to 0.2 below Omega = 0.3, where the lowest odd harmonic
!> in the band sits near its edge with a long wavelength: docs/continuation_reference.md). The tanh absorber's reflection of a
!> wave of wavenumber q is about exp(-pi sigma q / 2), whatever its width or kappa. The short chain has N0 = the
!> smallest integer >= `short_decay` / lambda' (at least `short_n0_min`) and a smooth absorber with sigma =
!> `short_sigma_q` / q (q of the lowest odd harmonic in the band, `harmonic_wavenumber`), kept within
!> `short_sigma_min` .. `short_sigma_max`, over `short_width_per_sigma` sigma sites (kappa as given): &scene keys
!> (`short_chain_params`). A fold line uses it when its input says &scene chain = 'short'; the record says which
!> chain each task used. (sigma q = 3.4: the reflection R <~ exp(-pi sigma q / 2) ~ 5e-3, measured |A_f -
!> A_f(reference)| <= 0.3 R; sigma_max 20, N - N0 = 200: near Omega = 1/k, k odd, an odd harmonic sits at the band
!> edge and no affordable absorber takes it, docs/continuation_reference.md.)
module supratrans_short_chain
    use supratrans_kinds, only: wp
    use supratrans_error, only: error_type
    use supratrans_config, only: chain_params, short_chain_params
    use supratrans_chain, only: gap_squared
    use supratrans_namelist, only: parse_namelist, parsed_input
    use supratrans_schema, only: key_table
    implicit none
    private

    public :: shortest_chain, chain_length_given, any_key_given, old_short_chain_rule, scheme_decay_rate, &
        harmonic_wavenumber

contains

    !> The scheme's own decay rate lambda' of the small-amplitude periodic state at drive frequency Omega with time
    !> step dt (NOTES.md); 0 when Omega is not in the chain's band gap (no decay).
    pure real(wp) function scheme_decay_rate(chain, omega, dt) result(lambda)
        !> The chain (c, m^2).
        type(chain_params), intent(in) :: chain
        !> Driving frequency Omega.
        real(wp), intent(in) :: omega
        !> Time step (the one used: the drive period over a whole number of steps).
        real(wp), intent(in) :: dt
        real(wp) :: arg

        arg = (gap_squared(chain)*cos(omega*dt) - (2.0_wp*sin(0.5_wp*omega*dt)/dt)**2)/(2.0_wp*chain%c**2)
        lambda = 0.0_wp
        if (arg > 0.0_wp) lambda = acosh(1.0_wp + arg)
    end function scheme_decay_rate

    !> The short chain of a fold line at drive frequency Omega (see the module's documentation): N0 and N and the
    !> absorber's sigma of `chain` replaced; left as it is where Omega is outside the band gap.
    pure subroutine shortest_chain(chain, omega, dt, short)
        !> The chain (n, n0, sigma changed).
        type(chain_params), intent(inout) :: chain
        !> Driving frequency Omega.
        real(wp), intent(in) :: omega
        !> The configured time step (adjusted to the period over M = ceiling(T / dt) steps, as the period map does).
        real(wp), intent(in) :: dt
        !> The short chain's constants (&scene short_*).
        type(short_chain_params), intent(in) :: short
        real(wp) :: period, lambda, q
        integer :: m

        if (.not. (omega > 0.0_wp)) return
        period = 2.0_wp*acos(-1.0_wp)/omega
        m = max(1, ceiling((period/dt)*(1.0_wp - 1.0e-12_wp)))
        lambda = scheme_decay_rate(chain, omega, period/real(m, wp))
        if (.not. (lambda > 0.0_wp)) return
        chain%n0 = max(short%n0_min, ceiling(short%decay/lambda))
        q = harmonic_wavenumber(chain, omega, short%band_edge_margin)
        chain%sigma = short%sigma_min
        if (q >= 0.0_wp) chain%sigma = short%sigma_max           ! a harmonic at the band edge: the cap
        if (q > 0.0_wp) chain%sigma = min(short%sigma_max, max(short%sigma_min, short%sigma_q/q))
        chain%n = chain%n0 + ceiling(short%width_per_sigma*chain%sigma)
    end subroutine shortest_chain

    !> The wavenumber q (per site) of the lowest odd harmonic k Omega (k = 3, 5, ...) of the drive at or inside the
    !> chain's phonon band, from the linear dispersion (k Omega)^2 = V''(0) + m^2 + 4 c^2 sin^2(q / 2): 0 for a harmonic
    !> within `margin` of the lower edge (below it or above: long, slow and not absorbed by any affordable
    !> ramp, and the scheme's own band edge differs from the continuum's by O(dt^2)); -1 when the lowest odd harmonic
    !> above the gap lies beyond the band (no odd harmonic radiates).
    pure real(wp) function harmonic_wavenumber(chain, omega, margin) result(q)
        !> The chain (c, m^2).
        type(chain_params), intent(in) :: chain
        !> Driving frequency Omega (inside the gap).
        real(wp), intent(in) :: omega
        !> Relative distance in Omega^2 from the lower band edge within which a harmonic counts as at the edge
        !> (&scene short_edge_margin).
        real(wp), intent(in) :: margin
        real(wp) :: w2, edge, k

        q = -1.0_wp
        edge = gap_squared(chain)
        ! the smallest odd k >= 3 with (k Omega)^2 > edge (1 - margin), in reals (no loop, no overflow)
        k = sqrt(max(edge*(1.0_wp - margin), 0.0_wp))/omega
        k = max(3.0_wp, 2.0_wp*real(floor((k - 1.0_wp)/2.0_wp), wp) + 3.0_wp)
        if ((k*omega)**2 <= edge*(1.0_wp - margin)) k = k + 2.0_wp
        w2 = (k*omega)**2
        if (w2 >= edge + 4.0_wp*chain%c**2) return
        q = 0.0_wp
        if (w2 > edge*(1.0_wp + margin)) q = 2.0_wp*asin(sqrt(w2 - edge)/(2.0_wp*chain%c))
    end function harmonic_wavenumber

    !> Whether a namelist text gives the chain's length or absorber (n, n0 or sigma in &chain); also true when the
    !> text is empty or cannot be read (then the chain is taken as given).
    pure logical function chain_length_given(text) result(given)
        !> The namelist text (`input_config%text`).
        character(len=*), intent(in) :: text

        given = any_key_given(text, "chain", [character(len=5) :: "n", "n0", "sigma"])
    end function chain_length_given

    !> Whether a namelist text gives any of `keys` in `group`; true when the text is empty or cannot be read.
    pure logical function any_key_given(text, group, keys) result(given)
        !> The namelist text (`input_config%text`).
        character(len=*), intent(in) :: text
        !> The group, without '&'.
        character(len=*), intent(in) :: group
        !> The keys (blank-padded).
        character(len=*), intent(in) :: keys(:)
        type(parsed_input) :: parsed
        type(error_type), allocatable :: error
        integer :: ik

        given = .true.
        if (len_trim(text) == 0) return
        call parse_namelist(text, "input", parsed, error)
        if (allocated(error)) return
        given = .false.
        do ik = 1, size(key_table)
            if (trim(key_table(ik)%group) /= group) cycle
            if (.not. any(keys == key_table(ik)%key)) cycle
            if (parsed%n_values(ik) > 0) given = .true.
        end do
    end function any_key_given

    !> The one line that refuses an input written for the old rule (before &scene chain), when the continuation
    !> scene picked the short chain by itself where &chain gives none of n, n0, sigma: such a text, with no &scene
    !> chain either, names the new spelling; empty otherwise.
    pure function old_short_chain_rule(text) result(message)
        !> The namelist text (`input_config%text`).
        character(len=*), intent(in) :: text
        character(len=:), allocatable :: message

        message = ""
        if (chain_length_given(text) .or. any_key_given(text, "scene", [character(len=5) :: "chain"])) return
        message = "&scene: chain: &chain gives none of n, n0, sigma, which used to pick the short chain of each Omega: " &
                  // "say chain = 'short' for that (the old behaviour) or chain = 'input' for the &chain as given " &
                  // "(N = 200)"
    end function old_short_chain_rule

end module supratrans_short_chain
