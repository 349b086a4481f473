!> What the explicit Runge-Kutta steppers (`rk4`, `rk8`) share: the state of the method-of-lines system
!> (`supratrans_mol`), its work arrays, the energy bookkeeping (the cumulative energies integrated as four extra ODE
!> components; H evaluated on the time level itself) and the observers' view of the state.
!>
!> The chain starts at rest at t = 0: one initial level, and step s (s = 1 .. M) goes from t_{s-1} to t_s. A
!> concrete method sets `stages` and `order` in its `init` (through `rk_init`) and advances `y` in its `step`.
module supratrans_stepper_rk
    use supratrans_kinds, only: wp
    use supratrans_strings, only: int_fixed, real_fixed
    use supratrans_config, only: run_config, chain_params, drive_params
    use supratrans_chain, only: damping_profile, drive_psi
    use supratrans_mol, only: chain_energy, ledger_from_state, mol_energy_components
    use supratrans_potential, only: potential_type, new_potential
    use supratrans_ledger, only: ledger_type
    use supratrans_stepper, only: stepper
    use supratrans_state_buffer, only: state_buffer, put_reals, get_reals
    implicit none
    private

    public :: rk_init

    !> An explicit Runge-Kutta method on the method-of-lines system.
    type, abstract, extends(stepper), public :: rk_stepper
        !> Chain parameters.
        type(chain_params) :: chain
        !> On-site potential V of the chain.
        class(potential_type), allocatable :: potential
        !> Drive parameters.
        type(drive_params) :: drive
        !> Stages (right-hand sides) of one step.
        integer :: stages = 0
        !> Site damping alpha_n, size N.
        real(wp), allocatable :: alpha(:)
        !> State (u_1..u_N, v_1..v_N, injected, dissipated by gamma, beta, absorber), size 2N + 4.
        real(wp), allocatable :: y(:)
        !> Work: stage state, size 2N + 4.
        real(wp), allocatable :: ys(:)
        !> Work: stage derivatives, (2N + 4, stages).
        real(wp), allocatable :: k(:, :)
    contains
        !> Continuous energy H of the newest level.
        procedure :: stored_energy => rk_energy
        !> Copy the integrated cumulative energies into the ledger.
        procedure :: account => rk_account
        !> u_n of the newest level.
        procedure :: displacement => rk_displacement
        !> max |u_n| over sites first..N of the newest level.
        procedure :: max_abs_u => rk_max_abs_u
        !> max |u_n|, or huge() when a velocity is not finite.
        procedure :: blowup_measure => rk_blowup_measure
        !> Count a step of the method taken.
        procedure :: end_step => rk_end_step
        !> Checkpoint: the state y (the stages are work).
        procedure :: save_levels => rk_save_levels
        !> Restore it.
        procedure :: load_levels => rk_load_levels
    end type rk_stepper

contains

    !> Set up a run of a method with `stages` stages and classical order `order`: the chain at rest, work arrays.
    subroutine rk_init(self, run, stages, order)
        !> The stepper.
        class(rk_stepper), intent(inout) :: self
        !> Validated run configuration.
        type(run_config), intent(in) :: run
        !> Stages of one step.
        integer, intent(in) :: stages
        !> Classical order.
        integer, intent(in) :: order
        integer :: n, s1, s2

        n = run%chain%n
        if (allocated(self%reason)) deallocate (self%reason)
        self%n = n
        self%dt = run%numerics%dt
        self%order = order
        self%initial_levels = 1
        self%energy_offset = 0.0_wp
        self%steps = 0
        self%newton_iterations = 0
        self%newton_max_iterations = 0
        self%tridiagonal_solves = 0
        self%rhs_evaluations = 0
        self%chain = run%chain
        call new_potential(run%chain, self%potential)
        self%drive = run%drive
        self%stages = stages
        ! work arrays, allocated once; the chain starts at rest
        self%alpha = damping_profile(run%chain)
        if (allocated(self%y)) deallocate (self%y)
        if (allocated(self%ys)) deallocate (self%ys)
        if (allocated(self%k)) deallocate (self%k)
        allocate (self%y(2*n + mol_energy_components), source=0.0_wp, stat=s1)
        allocate (self%ys(2*n + mol_energy_components), stat=s2)
        if (s2 == 0) allocate (self%k(2*n + mol_energy_components, stages), stat=s2)
        if (s1 /= 0 .or. s2 /= 0) self%reason = "cannot allocate " // trim(real_fixed(8.0_wp*real(2*n, wp) &
            *real(stages + 2, wp)/1.0e9_wp, 3)) // " GB for the " // trim(int_fixed(stages)) // " stages of " &
            // trim(int_fixed(n)) // " oscillators"
    end subroutine rk_init

    !> After a step: count it and its right-hand sides.
    pure subroutine rk_end_step(self)
        !> The stepper.
        class(rk_stepper), intent(inout) :: self

        self%steps = self%steps + 1
        self%rhs_evaluations = self%rhs_evaluations + self%stages
    end subroutine rk_end_step

    !> Append the state y (u, v and the integrated energies) to a checkpoint's buffer.
    pure subroutine rk_save_levels(self, buf)
        !> The stepper.
        class(rk_stepper), intent(in) :: self
        !> The state so far.
        type(state_buffer), intent(inout) :: buf

        call put_reals(buf, self%y)
    end subroutine rk_save_levels

    !> Restore the state y (after `init` of the same run).
    pure subroutine rk_load_levels(self, buf)
        !> The stepper.
        class(rk_stepper), intent(inout) :: self
        !> The saved state.
        type(state_buffer), intent(inout) :: buf

        call get_reals(buf, self%y)
    end subroutine rk_load_levels

    !> Continuous energy H of the newest level, u_0 = psi(t).
    pure function rk_energy(self) result(e)
        !> The stepper.
        class(rk_stepper), intent(in) :: self
        real(wp) :: e

        e = chain_energy(self%chain, self%potential, drive_psi(self%drive, self%level_time()), self%y)
    end function rk_energy

    !> Copy the integrated cumulative energies into the ledger.
    pure subroutine rk_account(self, ledger)
        !> The stepper.
        class(rk_stepper), intent(in) :: self
        !> The ledger.
        type(ledger_type), intent(inout) :: ledger

        call ledger_from_state(ledger, self%y(2*self%n + 1:))
    end subroutine rk_account

    !> u_n of the newest level (`back` must be 0): site 0 the drive psi(t), 1..N the chain, else 0.
    pure function rk_displacement(self, site, back) result(u)
        !> The stepper.
        class(rk_stepper), intent(in) :: self
        !> Site n.
        integer, intent(in) :: site
        !> 0 (a one-step method keeps only the newest level).
        integer, intent(in) :: back
        real(wp) :: u

        u = 0.0_wp
        if (back /= 0) return
        if (site >= 1 .and. site <= self%n) then
            u = self%y(site)
        else if (site == 0) then
            u = drive_psi(self%drive, self%level_time())
        end if
    end function rk_displacement

    !> max |u_n| over sites first..N of the newest level.
    pure function rk_max_abs_u(self, first) result(umax)
        !> The stepper.
        class(rk_stepper), intent(in) :: self
        !> First site.
        integer, intent(in) :: first
        real(wp) :: umax

        umax = maxval(abs(self%y(first:self%n)))
    end function rk_max_abs_u

    !> max |u_n| of the newest level, huge() when a velocity is not finite (a blow-up seen in v first).
    pure function rk_blowup_measure(self) result(umax)
        !> The stepper.
        class(rk_stepper), intent(in) :: self
        real(wp) :: umax

        umax = maxval(abs(self%y(1:self%n)))
        if (.not. (maxval(abs(self%y(self%n + 1:2*self%n))) <= huge(1.0_wp))) umax = huge(1.0_wp)   ! non-finite velocity
    end function rk_blowup_measure

end module supratrans_stepper_rk
