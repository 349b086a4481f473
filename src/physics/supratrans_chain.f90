!> The chain model of the paper: absorbing-end damping profile, boundary drive, linear theory and the
!> necessary stability condition.
!>
!> The linear theory lives here, in one place, from V''(0) of the potential (`potential_stiffness`) and m^2: the
!> on-site stiffness at rest K = V''(0) + m^2 (`gap_squared`), the band gap 0 < Omega < sqrt(K), the phonon band's
!> top sqrt(K + 4 c^2), the decay rate lambda = arccosh(1 + (K - Omega^2)/(2 c^2)) and A_s = 4 arctan(lambda c /
!> Omega) (the sine-Gordon continuum's kink formula, used as the reference for every potential).
!>
!> Absorber (paper Sec. 3.1, misprint corrected, see README): for N0 < n <= N,
!> gamma'(n) = kappa [1 + tanh((2n - N0 - N) / (2 sigma))], a smooth ramp from 0 to 2 kappa centred at (N0 + N)/2;
!> gamma'(n) = 0 otherwise. The damping of site n is alpha_n = gamma + gamma'(n).
module supratrans_chain
    use supratrans_kinds, only: wp
    use supratrans_config, only: chain_params, drive_params, run_config
    use supratrans_potential, only: potential_stiffness
    implicit none
    private

    public :: absorber_profile, damping_profile, drive_psi, ramp_factor, stair_amplitude, stair_slope, stair_level, &
              stair_count, stair_start

    !> Amplitude profile of the drive (`drive_params%profile`): the ramp A r(t) of every scene but hysteresis.
    integer, parameter, public :: profile_ramp = 0
    !> Amplitude profile of the hysteresis scene: stairs up from a_0 to a_K and down again (`stair_amplitude`).
    integer, parameter, public :: profile_stairs = 1
    public :: band_gap_edge, phonon_band_top, decay_rate, threshold_as, gap_squared, onsite_stiffness
    public :: stability_lhs, stability_rhs, stable_by_paper_condition, critical_dt, detector_site

contains

    !> Absorber gamma'(n) of the paper at site n (smooth profile).
    elemental function absorber_profile(chain, n) result(gp)
        !> Chain parameters (kappa, sigma, N0, N).
        type(chain_params), intent(in) :: chain
        !> Site index, 1 <= n <= N.
        integer, intent(in) :: n
        real(wp) :: gp

        if (n > chain%n0 .and. n <= chain%n) then
            gp = chain%kappa*(1.0_wp + tanh(real(2*n - chain%n0 - chain%n, wp)/(2.0_wp*chain%sigma)))
        else
            gp = 0.0_wp
        end if
    end function absorber_profile

    !> Site damping alpha_n = gamma + gamma'(n) for n = 1..N.
    pure function damping_profile(chain) result(alpha)
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        real(wp) :: alpha(chain%n)
        integer :: n

        do n = 1, chain%n
            alpha(n) = chain%gamma + absorber_profile(chain, n)
        end do
    end function damping_profile

    !> Ramp r(t) = min(t / ramp_time, 1) of the drive amplitude (1 when ramp_time = 0).
    elemental function ramp_factor(drive, t) result(r)
        !> Drive parameters.
        type(drive_params), intent(in) :: drive
        !> Time t >= 0.
        real(wp), intent(in) :: t
        real(wp) :: r

        if (drive%ramp_time > 0.0_wp) then
            r = min(max(t, 0.0_wp)/drive%ramp_time, 1.0_wp)
        else
            r = 1.0_wp
        end if
    end function ramp_factor

    !> Boundary value u_0(t) = psi(t) = A r(t) sin(Omega t) (profile_ramp, the default), or A(t) sin(Omega t) with
    !> A(t) the stairs of `stair_amplitude` (profile_stairs).
    elemental function drive_psi(drive, t) result(psi)
        !> Drive parameters.
        type(drive_params), intent(in) :: drive
        !> Time t.
        real(wp), intent(in) :: t
        real(wp) :: psi

        if (drive%profile == profile_ramp) then
            psi = drive%amplitude*ramp_factor(drive, t)*sin(drive%omega*t)
        else
            psi = stair_amplitude(drive, t)*sin(drive%omega*t)
        end if
    end function drive_psi

    !> Number of stairs 2K + 1 of the stair profile: levels a_0, a_1, .., a_K, a_{K-1}, .., a_0.
    elemental function stair_count(drive) result(n)
        !> Drive parameters (stair_top = K).
        type(drive_params), intent(in) :: drive
        integer :: n

        n = 2*drive%stair_top + 1
    end function stair_count

    !> Level of stair j (0-based, 0 .. 2K): a_i = a_0 + i stair_height with i = min(j, 2K - j) (up, then down).
    elemental function stair_level(drive, j) result(a)
        !> Drive parameters.
        type(drive_params), intent(in) :: drive
        !> Stair index, 0 .. 2K (clamped to that range).
        integer, intent(in) :: j
        real(wp) :: a
        integer :: jj

        jj = max(0, min(j, 2*drive%stair_top))
        a = drive%stair_low + real(min(jj, 2*drive%stair_top - jj), wp)*drive%stair_height
    end function stair_level

    !> Start time of stair j: ramp_time + j stair_time (stair 0 starts when the ramp from rest reaches a_0).
    elemental function stair_start(drive, j) result(t)
        !> Drive parameters.
        type(drive_params), intent(in) :: drive
        !> Stair index, 0 .. 2K + 1 (2K + 1: the end of the last stair).
        integer, intent(in) :: j
        real(wp) :: t

        t = drive%ramp_time + real(j, wp)*drive%stair_time
    end function stair_start

    !> The stair profile A(t) of the hysteresis scene, continuous and piecewise linear: from rest a linear ramp to
    !> a_0 over [0, ramp_time]; then stair j (j = 0 .. 2K) on [ramp_time + j T_s, ramp_time + (j + 1) T_s), T_s =
    !> stair_time, whose first stair_ramp (for j >= 1) is the linear ramp from the level of stair j - 1 to its own
    !> level `stair_level(j)`; after the last stair the bottom level a_0 is held.
    elemental function stair_amplitude(drive, t) result(a)
        !> Drive parameters (profile_stairs).
        type(drive_params), intent(in) :: drive
        !> Time t.
        real(wp), intent(in) :: t
        real(wp) :: a
        real(wp) :: s, tau
        integer :: j

        if (t < drive%ramp_time) then
            a = drive%stair_low*max(t, 0.0_wp)/drive%ramp_time
            return
        end if
        s = t - drive%ramp_time
        j = int(min(s/drive%stair_time, real(2*drive%stair_top + 1, wp)))
        tau = s - real(j, wp)*drive%stair_time
        a = stair_level(drive, j)
        if (j >= 1 .and. j <= 2*drive%stair_top .and. tau < drive%stair_ramp) then
            a = stair_level(drive, j - 1) + (a - stair_level(drive, j - 1))*(tau/drive%stair_ramp)
        end if
    end function stair_amplitude

    !> Slope A'(t) of the stair profile on the piece that holds `t_side` (a time inside the current step, which
    !> chooses the side at a kink: the profile's pieces are linear, so the slope of the piece holding t_side is
    !> exact for every time of a step that crosses no kink).
    elemental function stair_slope(drive, t_side) result(da)
        !> Drive parameters (profile_stairs).
        type(drive_params), intent(in) :: drive
        !> A time inside the current step.
        real(wp), intent(in) :: t_side
        real(wp) :: da
        real(wp) :: s, tau
        integer :: j

        da = 0.0_wp
        if (t_side < drive%ramp_time) then
            if (t_side >= 0.0_wp) da = drive%stair_low/drive%ramp_time
            return
        end if
        s = t_side - drive%ramp_time
        j = int(min(s/drive%stair_time, real(2*drive%stair_top + 1, wp)))
        tau = s - real(j, wp)*drive%stair_time
        if (j >= 1 .and. j <= 2*drive%stair_top .and. tau < drive%stair_ramp) then
            da = (stair_level(drive, j) - stair_level(drive, j - 1))/drive%stair_ramp
        end if
    end function stair_slope

    !> V''(0), the on-site potential's stiffness at rest (1 for sine-Gordon and Klein-Gordon).
    elemental function onsite_stiffness(chain) result(k)
        !> Chain parameters (potential and its parameters).
        type(chain_params), intent(in) :: chain
        real(wp) :: k

        k = potential_stiffness(chain)
    end function onsite_stiffness

    !> The on-site stiffness at rest K = V''(0) + m^2: the square of the band gap's edge.
    elemental function gap_squared(chain) result(k)
        !> Chain parameters (potential, m^2).
        type(chain_params), intent(in) :: chain
        real(wp) :: k

        k = onsite_stiffness(chain) + chain%m2
    end function gap_squared

    !> Upper edge of the forbidden band gap, sqrt(V''(0) + m^2): the gap is 0 < Omega < sqrt(V''(0) + m^2).
    elemental function band_gap_edge(chain) result(w)
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        real(wp) :: w

        w = sqrt(max(gap_squared(chain), 0.0_wp))
    end function band_gap_edge

    !> Top of the phonon band, sqrt(V''(0) + m^2 + 4 c^2).
    elemental function phonon_band_top(chain) result(w)
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        real(wp) :: w

        w = sqrt(max(gap_squared(chain) + 4.0_wp*chain%c**2, 0.0_wp))
    end function phonon_band_top

    !> Decay rate lambda = arccosh(1 + (V''(0) + m^2 - Omega^2)/(2 c^2)) of the evanescent wave
    !> A sin(Omega t) e^{-lambda n}.
    elemental function decay_rate(chain, omega) result(lambda)
        !> Chain parameters (c, m^2, potential).
        type(chain_params), intent(in) :: chain
        !> Driving frequency Omega.
        real(wp), intent(in) :: omega
        real(wp) :: lambda

        lambda = acosh(1.0_wp + (chain%m2 + onsite_stiffness(chain) - omega**2)/(2.0_wp*chain%c**2))
    end function decay_rate

    !> Continuum-limit supratransmission threshold A_s = 4 arctan(lambda c / Omega) (massless, undamped; the
    !> sine-Gordon continuum's formula, with this potential's lambda).
    elemental function threshold_as(chain, omega) result(as)
        !> Chain parameters (c, m^2).
        type(chain_params), intent(in) :: chain
        !> Driving frequency Omega.
        real(wp), intent(in) :: omega
        real(wp) :: as

        as = 4.0_wp*atan(decay_rate(chain, omega)*chain%c/omega)
    end function threshold_as

    !> Left side of the paper's necessary stability condition, (c^2 - m^2/4) dt^2.
    elemental function stability_lhs(chain, dt) result(lhs)
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        !> Time step.
        real(wp), intent(in) :: dt
        real(wp) :: lhs

        lhs = (chain%c**2 - chain%m2/4.0_wp)*dt**2
    end function stability_lhs

    !> Right side of the condition, 1 + (alpha/4 + beta) dt, with the smallest damping alpha = gamma (the
    !> absorber only relaxes it), so that the condition holds at every site.
    elemental function stability_rhs(chain, dt) result(rhs)
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        !> Time step.
        real(wp), intent(in) :: dt
        real(wp) :: rhs

        rhs = 1.0_wp + (chain%gamma/4.0_wp + chain%beta)*dt
    end function stability_rhs

    !> True when the paper's necessary condition (c^2 - m^2/4) dt^2 < 1 + (alpha/4 + beta) dt holds.
    elemental function stable_by_paper_condition(chain, dt) result(ok)
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        !> Time step.
        real(wp), intent(in) :: dt
        logical :: ok

        ok = stability_lhs(chain, dt) < stability_rhs(chain, dt)
    end function stable_by_paper_condition

    !> Largest dt that satisfies the paper's condition (root of (c^2 - m^2/4) dt^2 = 1 + (gamma/4 + beta) dt);
    !> huge() when the condition holds for every dt.
    elemental function critical_dt(chain) result(dt)
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        real(wp) :: dt, q, p

        q = chain%c**2 - chain%m2/4.0_wp
        p = chain%gamma/4.0_wp + chain%beta
        if (q <= 0.0_wp) then
            dt = huge(1.0_wp)
        else
            dt = (p + sqrt(p*p + 4.0_wp*q))/(2.0_wp*q)
        end if
    end function critical_dt

    !> Detector site n_d of a run: the configured one, or min(N0 - 10, max(20, ceiling(3/lambda))) from linear
    !> theory (the evanescent wave A e^{-lambda n} has decayed to 5% of A there), kept inside 1..N-1.
    pure function detector_site(run) result(nd)
        !> Run configuration.
        type(run_config), intent(in) :: run
        integer :: nd
        real(wp) :: lambda

        if (run%detect%site > 0) then
            nd = run%detect%site
        else
            lambda = decay_rate(run%chain, min(run%drive%omega, 0.999999_wp*sqrt(gap_squared(run%chain))))
            nd = min(run%chain%n0 - 10, max(20, ceiling(min(3.0_wp/max(lambda, 1.0e-6_wp), 1.0e6_wp))))
        end if
        nd = max(1, min(nd, run%chain%n - 1))
    end function detector_site

end module supratrans_chain
