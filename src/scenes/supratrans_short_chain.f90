!> The short chain of fold lines (`shortest_chain`, issue 25 point 6; `supratrans_fold_line` re-exports it).
!>
!> The periodic state is localized at the driven end: at small amplitude it decays as e^{-lambda' n}, lambda' the
!> scheme's own decay rate (NOTES.md: cosh lambda' = 1 + ((V''(0) + m^2) cos(Omega dt) - (2 sin(Omega dt / 2) / dt)^2) / (2
!> c^2)). Beyond the core, what matters is the absorber: the state radiates its odd harmonics (3 Omega, 5 Omega, ... in
!> the phonon band), and whatever the absorber reflects moves A_f (by 2e-5 at Omega = 0.9 and 1e-3 .. 4e-2 at 0.7 ..
!> 0.5 with the paper's absorber, N - N0 = 50, sigma = 3; by up to 0.2 below Omega = 0.3, where the lowest odd harmonic
!> in the band sits near its edge with a long wavelength: docs/continuation_reference.md). The tanh absorber's reflection of a
!> wave of wavenumber q is about exp(-pi sigma q / 2), whatever its width or kappa. The short chain has N0 = the
!> smallest integer >= `short_chain_decay` / lambda' (at least `short_n0_min`) and a smooth absorber with sigma =
!> `short_absorber_sigma_q` / q (q of the lowest odd harmonic in the band, `harmonic_wavenumber`), kept within
!> `short_absorber_sigma` .. `short_absorber_sigma_max`, over `short_width_per_sigma` sigma sites (kappa as given). A
!> fold line uses it when its input gives none of n, n0, sigma in &chain; the record says which chain each task used.
module supratrans_short_chain
    use supratrans_kinds, only: wp
    use supratrans_error, only: error_type
    use supratrans_config, only: chain_params
    use supratrans_chain, only: gap_squared
    use supratrans_namelist, only: parse_namelist, parsed_input
    use supratrans_schema, only: key_table
    implicit none
    private

    public :: shortest_chain, chain_length_given, scheme_decay_rate, harmonic_wavenumber

    !> Sites N - N0 of the short chain's absorber per unit of its sigma (the tanh ramp reaches 2 kappa within it).
    integer, parameter, public :: short_width_per_sigma = 10
    !> Least sigma of the short chain's absorber ramp (the paper's is 3).
    real(wp), parameter, public :: short_absorber_sigma = 6.0_wp
    !> Largest sigma of the short chain's absorber (N - N0 = 200): near Omega = 1/k, k odd, an odd harmonic sits at
    !> the band edge and no affordable absorber takes it (docs/continuation_reference.md).
    real(wp), parameter, public :: short_absorber_sigma_max = 20.0_wp
    !> sigma q of the short chain's absorber, q the wavenumber of the lowest odd harmonic of the drive in the phonon
    !> band: its reflection R <~ exp(-pi sigma q / 2) ~ 5e-3 (measured: |A_f - A_f(reference)| <= 0.3 R).
    real(wp), parameter, public :: short_absorber_sigma_q = 3.4_wp
    !> Relative distance in Omega^2 from the lower band edge within which a harmonic counts as at the edge.
    real(wp), parameter, public :: band_edge_margin = 1.0e-2_wp
    !> lambda' N0 of the short chain: the linear state is down by e^{-7} ~ 1e-3 where the absorber starts.
    real(wp), parameter, public :: short_chain_decay = 7.0_wp
    !> Fewest sites N0 before the short chain's absorber.
    integer, parameter, public :: short_n0_min = 20

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
    pure subroutine shortest_chain(chain, omega, dt)
        !> The chain (n, n0, sigma changed).
        type(chain_params), intent(inout) :: chain
        !> Driving frequency Omega.
        real(wp), intent(in) :: omega
        !> The configured time step (adjusted to the period over M = ceiling(T / dt) steps, as the period map does).
        real(wp), intent(in) :: dt
        real(wp) :: period, lambda, q
        integer :: m

        if (.not. (omega > 0.0_wp)) return
        period = 2.0_wp*acos(-1.0_wp)/omega
        m = max(1, ceiling((period/dt)*(1.0_wp - 1.0e-12_wp)))
        lambda = scheme_decay_rate(chain, omega, period/real(m, wp))
        if (.not. (lambda > 0.0_wp)) return
        chain%n0 = max(short_n0_min, ceiling(short_chain_decay/lambda))
        q = harmonic_wavenumber(chain, omega)
        chain%sigma = short_absorber_sigma
        if (q >= 0.0_wp) chain%sigma = short_absorber_sigma_max           ! a harmonic at the band edge: the cap
        if (q > 0.0_wp) chain%sigma = min(short_absorber_sigma_max, max(short_absorber_sigma, short_absorber_sigma_q/q))
        chain%n = chain%n0 + ceiling(short_width_per_sigma*chain%sigma)
    end subroutine shortest_chain

    !> The wavenumber q (per site) of the lowest odd harmonic k Omega (k = 3, 5, ...) of the drive at or inside the
    !> chain's phonon band, from the linear dispersion (k Omega)^2 = V''(0) + m^2 + 4 c^2 sin^2(q / 2): 0 for a harmonic
    !> within `band_edge_margin` of the lower edge (below it or above: long, slow and not absorbed by any affordable
    !> ramp, and the scheme's own band edge differs from the continuum's by O(dt^2)); -1 when the lowest odd harmonic
    !> above the gap lies beyond the band (no odd harmonic radiates).
    pure real(wp) function harmonic_wavenumber(chain, omega) result(q)
        !> The chain (c, m^2).
        type(chain_params), intent(in) :: chain
        !> Driving frequency Omega (inside the gap).
        real(wp), intent(in) :: omega
        real(wp) :: w2, edge, k

        q = -1.0_wp
        edge = gap_squared(chain)
        ! the smallest odd k >= 3 with (k Omega)^2 > edge (1 - band_edge_margin), in reals (no loop, no overflow)
        k = sqrt(max(edge*(1.0_wp - band_edge_margin), 0.0_wp))/omega
        k = max(3.0_wp, 2.0_wp*real(floor((k - 1.0_wp)/2.0_wp), wp) + 3.0_wp)
        if ((k*omega)**2 <= edge*(1.0_wp - band_edge_margin)) k = k + 2.0_wp
        w2 = (k*omega)**2
        if (w2 >= edge + 4.0_wp*chain%c**2) return
        q = 0.0_wp
        if (w2 > edge*(1.0_wp + band_edge_margin)) q = 2.0_wp*asin(sqrt(w2 - edge)/(2.0_wp*chain%c))
    end function harmonic_wavenumber

    !> Whether a namelist text gives the chain's length or absorber (n, n0 or sigma in &chain); also true when the
    !> text is empty or cannot be read (then the chain is taken as given).
    pure logical function chain_length_given(text) result(given)
        !> The namelist text (`input_config%text`).
        character(len=*), intent(in) :: text
        type(parsed_input) :: parsed
        type(error_type), allocatable :: error
        integer :: ik

        given = .true.
        if (len_trim(text) == 0) return
        call parse_namelist(text, "input", parsed, error)
        if (allocated(error)) return
        given = .false.
        do ik = 1, size(key_table)
            if (trim(key_table(ik)%group) /= "chain") cycle
            select case (trim(key_table(ik)%key))
            case ("n", "n0", "sigma")
                if (parsed%n_values(ik) > 0) given = .true.
            case default
                continue                 ! the other keys of &chain do not set the chain's length or absorber
            end select
        end do
    end function chain_length_given

end module supratrans_short_chain
