!> The exact radiation condition of the linear chain per harmonic: beyond a site where the motion is linear, the
!> harmonic w of u_n = Re(U_n e^{i w t}) obeys U_{n+1} = z U_n with z a root of the linear dispersion relation
!>
!>     -w^2 - (c^2 + i beta w)(z + 1/z - 2) + i alpha w + kappa0 = 0,     kappa0 = m^2 + V''(0),
!>
!> the root with |z| < 1 (the wave decays away from the drive), or for an undamped harmonic in the phonon band (|z| =
!> 1 for both roots) the outgoing one: the limit of the decaying root as the damping tends to 0+.
module supratrans_radiation
    use supratrans_kinds, only: wp
    implicit none
    private

    public :: radiation_root

    !> Relative damping added to choose between two roots on the unit circle (the limit alpha -> 0+).
    real(wp), parameter :: damping_probe = 1.0e-7_wp

contains

    !> The decaying (or outgoing) root z of the dispersion relation at frequency w.
    pure function radiation_root(w, c, beta, alpha, kappa0) result(z)
        !> Frequency of the harmonic.
        real(wp), intent(in) :: w
        !> Coupling c.
        real(wp), intent(in) :: c
        !> Coupling damping beta.
        real(wp), intent(in) :: beta
        !> On-site damping alpha at the closure.
        real(wp), intent(in) :: alpha
        !> Linear on-site stiffness m^2 + V''(0).
        real(wp), intent(in) :: kappa0
        complex(wp) :: z
        complex(wp) :: r(2), probe(2)
        integer :: i

        r = roots(alpha)
        if (abs(abs(r(1)) - abs(r(2))) > 1.0e-12_wp) then
            i = minloc(abs(r), 1)
        else                                              ! both on the unit circle: the limit alpha -> 0+
            probe = roots(alpha + damping_probe*max(w, 1.0_wp))
            i = minloc(abs(r - probe(minloc(abs(probe), 1))), 1)
        end if
        z = r(i)

    contains

        !> Both roots of z^2 - (2 + q) z + 1 = 0, q = (-w^2 + i a w + kappa0) / (c^2 + i beta w).
        pure function roots(a) result(zz)
            real(wp), intent(in) :: a
            complex(wp) :: zz(2)
            complex(wp) :: q, s

            q = cmplx(-w*w + kappa0, a*w, wp)/cmplx(c*c, beta*w, wp)
            s = sqrt((2.0_wp + q)**2 - 4.0_wp)
            zz(1) = 0.5_wp*((2.0_wp + q) + s)
            zz(2) = 0.5_wp*((2.0_wp + q) - s)
        end function roots

    end function radiation_root

end module supratrans_radiation
