!> What the paper's two finite-difference schemes (Sec. 3.1) share: the scheme's matrices, the time levels, the
!> driven end and the discrete energy ledger of Sec. 3.2 (`supratrans_ledger`). `newton` and `linearized` extend
!> it with their step.
!>
!> The chain starts at rest, u^0 = u^1 = 0 (phi = varphi = 0), and the driven end follows u_0^k = psi(t_k): two
!> initial levels, and step k (k = 1 .. M-1) computes u^{k+1} from u^k and u^{k-1} (and earlier levels for
!> Newton's predictor). The levels are the columns of u(0:N+1, L), rotated after every step; the end cells hold
!> the boundary values u_0 = psi(t) and u_{N+1} = 0. The ledger sums dt (P_k - D_k) over the steps; E_k lives on the
!> half level t_{k+1/2}.
module supratrans_stepper_leapfrog
    use supratrans_kinds, only: wp, i8
    use supratrans_strings, only: int_fixed, real_fixed
    use supratrans_config, only: run_config, drive_params
    use supratrans_chain, only: drive_psi
    use supratrans_scheme, only: scheme_type, scheme_init
    use supratrans_ledger, only: ledger_type, stored_energy, step_powers, ledger_add_step
    use supratrans_stepper, only: stepper
    use supratrans_state_buffer, only: state_buffer, put_reals2, put_ints, get_reals2, get_ints
    implicit none
    private

    public :: leapfrog_init, leapfrog_max_abs_u, leapfrog_verdict_measures, leapfrog_load_levels

    !> A two-level scheme of the paper: the levels u^{k-2}, u^{k-1}, u^k, u^{k+1} and the scheme's matrices.
    type, abstract, extends(stepper), public :: leapfrog_stepper
        !> The scheme's matrices A, B, C (eq. DiscreteMainDiscr).
        type(scheme_type) :: scheme
        !> The drive psi(t) of the end u_0.
        type(drive_params) :: drive
        !> External damping gamma, internal damping beta, mass term m^2 (for the ledger).
        real(wp) :: gamma = 0.0_wp, beta = 0.0_wp, m2 = 0.0_wp
        !> Time levels u(0:N+1, L), L = `levels` >= 4: column `col(j)` holds level k+1-j (j = 1 .. L-1, k the
        !> newest), column `col(L)` is free for the next level; `ic`, `io`, `io2`, `inew` name col(1), col(2),
        !> col(3) and col(L). Levels before t = 0 are the chain at rest.
        real(wp), allocatable :: u(:, :)
        !> Number of stored levels L (4: enough for the schemes; Newton keeps more for its predictor).
        integer :: levels = 4
        !> Columns of the levels k, k-1, ..., and (last) of the next level.
        integer, allocatable :: col(:)
        !> Columns of the levels k-2, k-1, k and of the next level.
        integer :: io2 = 3, io = 2, ic = 1, inew = 4
    contains
        !> Stored energy E_k of the newest two levels.
        procedure :: stored_energy => leapfrog_energy
        !> Add dt (P_k - D_k) of the last step to the ledger.
        procedure :: account => leapfrog_account
        !> u_n of the newest level (back = 0) or the one before (back = 1).
        procedure :: displacement => leapfrog_displacement
        !> max |u_n| over sites first..N of the newest level.
        procedure :: max_abs_u => leapfrog_max_abs_u
        !> max |u_n| over the whole chain and over sites first..N in one pass.
        procedure :: verdict_measures => leapfrog_verdict_measures
        !> Start the next step: the new level's boundary cells; returns its time.
        procedure :: begin_step
        !> End a successful step: rotate the levels, count it.
        procedure :: end_step
        !> Checkpoint: the stored levels and their column order.
        procedure :: save_levels => leapfrog_save_levels
        !> Restore them.
        procedure :: load_levels => leapfrog_load_levels
    end type leapfrog_stepper

contains

    !> Set up the scheme and the two initial levels (at rest, the driven end at psi(0) and psi(dt)).
    subroutine leapfrog_init(self, run, levels)
        !> The stepper.
        class(leapfrog_stepper), intent(inout) :: self
        !> Validated run configuration.
        type(run_config), intent(in) :: run
        !> Levels to store (default 4, at least 4).
        integer, intent(in), optional :: levels
        integer :: n, j, stat

        n = run%chain%n
        self%n = n
        if (allocated(self%reason)) deallocate (self%reason)
        self%dt = run%numerics%dt
        self%order = 2
        self%initial_levels = 2
        self%energy_offset = 0.5_wp
        self%steps = 0
        self%newton_iterations = 0
        self%newton_max_iterations = 0
        self%tridiagonal_solves = 0
        self%rhs_evaluations = 0
        self%drive = run%drive
        self%gamma = run%chain%gamma
        self%beta = run%chain%beta
        self%m2 = run%chain%m2
        call scheme_init(self%scheme, run%chain, self%dt)
        self%levels = 4
        if (present(levels)) self%levels = max(4, levels)
        if (allocated(self%u)) deallocate (self%u)
        allocate (self%u(0:n + 1, self%levels), source=0.0_wp, stat=stat)
        if (stat /= 0) then
            self%reason = "cannot allocate " // trim(real_fixed(8.0_wp*real(n + 2, wp)*real(self%levels, wp) &
                                                                /1.0e9_wp, 3)) // " GB for the " &
                          // trim(int_fixed(self%levels)) // " time levels of " // trim(int_fixed(n)) // " oscillators"
            return
        end if
        self%col = [(j, j=1, self%levels)]
        call name_columns(self)
        ! levels 0 and 1: at rest, boundary from the drive
        self%u(0, self%io) = drive_psi(self%drive, 0.0_wp)
        self%u(0, self%ic) = drive_psi(self%drive, self%dt)
    end subroutine leapfrog_init

    !> Set the boundary cells of the next level u^{k+1} (k = steps + 1) and return its time t_{k+1}.
    function begin_step(self) result(t_new)
        !> The stepper.
        class(leapfrog_stepper), intent(inout) :: self
        real(wp) :: t_new

        t_new = real(self%steps + 2_i8, wp)*self%dt
        self%u(0, self%inew) = drive_psi(self%drive, t_new)
        self%u(self%n + 1, self%inew) = 0.0_wp
    end function begin_step

    !> After a successful step: rotate the levels (k+1 -> k, k -> k-1, ...; the oldest column becomes free), and
    !> count the step.
    subroutine end_step(self)
        !> The stepper.
        class(leapfrog_stepper), intent(inout) :: self
        integer :: free

        free = self%col(self%levels - 1)                      ! the oldest level is dropped
        self%col(2:self%levels - 1) = self%col(1:self%levels - 2)
        self%col(1) = self%inew
        self%col(self%levels) = free
        call name_columns(self)
        self%steps = self%steps + 1
    end subroutine end_step

    !> Append the stored levels u(0:N+1, L) and the order of their columns to a checkpoint's buffer.
    pure subroutine leapfrog_save_levels(self, buf)
        !> The stepper.
        class(leapfrog_stepper), intent(in) :: self
        !> The state so far.
        type(state_buffer), intent(inout) :: buf

        call put_reals2(buf, self%u)
        call put_ints(buf, self%col)
    end subroutine leapfrog_save_levels

    !> Restore the levels and their column order (after `init` of the same run: same N and number of levels).
    pure subroutine leapfrog_load_levels(self, buf)
        !> The stepper.
        class(leapfrog_stepper), intent(inout) :: self
        !> The saved state.
        type(state_buffer), intent(inout) :: buf
        integer :: j

        call get_reals2(buf, self%u)
        call get_ints(buf, self%col)
        ! the columns must be a permutation of 1..L
        do j = 1, self%levels
            if (count(self%col == j) /= 1) buf%ok = .false.
        end do
        if (buf%ok) call name_columns(self)
    end subroutine leapfrog_load_levels

    !> Set `ic`, `io`, `io2`, `inew` from `col`.
    pure subroutine name_columns(self)
        !> The stepper.
        class(leapfrog_stepper), intent(inout) :: self

        self%ic = self%col(1)
        self%io = self%col(2)
        self%io2 = self%col(3)
        self%inew = self%col(self%levels)
    end subroutine name_columns

    !> Stored energy E_k from the newest level (k+1) and the one before (k).
    pure function leapfrog_energy(self) result(e)
        !> The stepper.
        class(leapfrog_stepper), intent(in) :: self
        real(wp) :: e

        e = stored_energy(self%scheme, self%m2, self%u(:, self%ic), self%u(:, self%io))
    end function leapfrog_energy

    !> Add the powers of the last step (levels k-1, k, k+1) times dt to the ledger.
    pure subroutine leapfrog_account(self, ledger)
        !> The stepper.
        class(leapfrog_stepper), intent(in) :: self
        !> The ledger.
        type(ledger_type), intent(inout) :: ledger
        real(wp) :: p_in, d_gamma, d_beta, d_abs

        call step_powers(self%scheme, self%gamma, self%beta, self%u(:, self%io2), self%u(:, self%io), &
                         self%u(:, self%ic), p_in, d_gamma, d_beta, d_abs)
        call ledger_add_step(ledger, self%dt, p_in, d_gamma, d_beta, d_abs)
    end subroutine leapfrog_account

    !> u_n of the newest level (back = 0) or the one before (back = 1): the level's end cells are psi and 0.
    pure function leapfrog_displacement(self, site, back) result(u)
        !> The stepper.
        class(leapfrog_stepper), intent(in) :: self
        !> Site n.
        integer, intent(in) :: site
        !> 0 the newest level, 1 the one before.
        integer, intent(in) :: back
        real(wp) :: u

        u = 0.0_wp
        if (site < 0 .or. site > self%n + 1) return
        if (back == 0) then
            u = self%u(site, self%ic)
        else
            u = self%u(site, self%io)
        end if
    end function leapfrog_displacement

    !> max |u_n| over sites first..N of the newest level.
    pure function leapfrog_max_abs_u(self, first) result(umax)
        !> The stepper.
        class(leapfrog_stepper), intent(in) :: self
        !> First site.
        integer, intent(in) :: first
        real(wp) :: umax

        umax = max_abs_nan(self%u(first:self%n, self%ic))
    end function leapfrog_max_abs_u

    !> max |u_n| of the newest level over the whole chain (the blow-up measure, NaN carried as in `max_abs_nan`)
    !> and over sites first..N, in one pass (a threshold search's run watches both every step).
    pure subroutine leapfrog_verdict_measures(self, first, blowup, beyond)
        !> The stepper.
        class(leapfrog_stepper), intent(in) :: self
        !> First site of the second range.
        integer, intent(in) :: first
        !> max |u_n| over 1..N.
        real(wp), intent(out) :: blowup
        !> max |u_n| over first..N.
        real(wp), intent(out) :: beyond
        real(wp) :: below

        below = max_abs_nan(self%u(1:min(first - 1, self%n), self%ic))
        beyond = max_abs_nan(self%u(max(first, 1):self%n, self%ic))
        blowup = max(below, beyond)
        if (below /= below) blowup = below
        if (beyond /= beyond) blowup = beyond
    end subroutine leapfrog_verdict_measures

    !> max |x_n| in one vectorised pass; NaN (which a SIMD max may drop) is carried by the sum of x_n*0 instead.
    pure function max_abs_nan(x) result(umax)
        !> The values.
        real(wp), intent(in), contiguous :: x(:)
        real(wp) :: umax
        integer :: n
        real(wp) :: nan_probe

        umax = 0.0_wp
        nan_probe = 0.0_wp
        !$omp simd reduction(max: umax) reduction(+: nan_probe)
        do n = 1, size(x)
            umax = max(umax, abs(x(n)))
            nan_probe = nan_probe + 0.0_wp*x(n)
        end do
        if (nan_probe /= nan_probe) umax = nan_probe
    end function max_abs_nan

end module supratrans_stepper_leapfrog
