!> Set-up and checkpoint of the steppers `avf4` and `avf8` (a submodule of `supratrans_stepper_avf`, whose
!> interface declares these procedures): a run's tableau (`supratrans_avf_tableau`) and work arrays, and the state
!> a checkpoint saves. Cold code, apart from the stage iteration of the module, which stays one compilation unit.
submodule(supratrans_stepper_avf) supratrans_stepper_avf_setup
    use supratrans_config, only: method_avf8
    use supratrans_stepper_rk, only: rk_init
    use supratrans_avf_tableau, only: avf_make_tableau, avf4_stages, avf8_stages
    use supratrans_state_buffer, only: put_reals, put_reals2, get_reals, get_reals2
    implicit none

contains

    !> Set up a run: the chain at rest, the method of `run%numerics%method` (avf4 or avf8), work arrays.
    module subroutine avf_init(self, run)
        !> The stepper.
        class(avf_stepper), intent(inout) :: self
        !> Validated run configuration.
        type(run_config), intent(in) :: run
        integer :: s, n, st

        s = avf4_stages
        if (run%numerics%method == method_avf8) s = avf8_stages
        n = run%chain%n
        call rk_init(self, run, s, 2*s)
        if (allocated(self%reason)) return
        ! the averaging rule: the potential's number of nodes (exact for a polynomial V')
        call avf_make_tableau(s, self%potential%averaging_nodes(s), self%tab)
        self%wh = transpose(self%tab%w)/self%dt
        self%mwh = -self%wh
        self%mqw = -transpose(self%tab%qw)
        self%lagc = transpose(self%tab%lag(:, 1:s))
        self%tinc = transpose(self%tab%tin)
        self%tbc = transpose(self%tab%tb)
        self%extc = transpose(self%tab%ext)
        self%tol = run%numerics%newton_tol
        self%max_iter = run%numerics%newton_max_iter
        if (allocated(self%uu)) deallocate (self%uu)
        if (allocated(self%vv)) deallocate (self%vv)
        if (allocated(self%rbase)) deallocate (self%rbase)
        if (allocated(self%sigq)) deallocate (self%sigq)
        if (allocated(self%fqq)) deallocate (self%fqq)
        if (allocated(self%rr)) deallocate (self%rr)
        if (allocated(self%prev)) deallocate (self%prev)
        if (allocated(self%winv)) deallocate (self%winv)
        if (allocated(self%cfac)) deallocate (self%cfac)
        if (allocated(self%rho)) deallocate (self%rho)
        if (allocated(self%sig)) deallocate (self%sig)
        if (allocated(self%fq)) deallocate (self%fq)
        if (allocated(self%psi_s)) deallocate (self%psi_s)
        if (allocated(self%dpsi_s)) deallocate (self%dpsi_s)
        allocate (self%uu(n, s), stat=st)
        if (st == 0) allocate (self%vv(n, s), stat=st)
        if (st == 0) allocate (self%rbase(n, s), stat=st)
        if (st == 0) allocate (self%sigq(n, self%tab%nq), stat=st)
        if (st == 0) allocate (self%fqq(n, self%tab%nq), stat=st)
        if (st == 0) allocate (self%rr(n, s), stat=st)
        if (st == 0) allocate (self%prev(n, s), stat=st)
        if (st == 0) allocate (self%winv(n, s), stat=st)
        if (st == 0) allocate (self%cfac(n, s), stat=st)
        if (st == 0) allocate (self%rho(n, s), stat=st)
        if (st == 0) allocate (self%sig(n), stat=st)
        if (st == 0) allocate (self%fq(n), stat=st)
        if (st == 0) allocate (self%psi_s(s), stat=st)
        if (st == 0) allocate (self%dpsi_s(s), stat=st)
        if (st /= 0) self%reason = "cannot allocate the collocation work arrays of " // trim(int_fixed(n)) &
                                   // " oscillators"
    end subroutine avf_init

    !> Append the state y (u, v, the integrated energies) and the previous step's stage increments Z (the
    !> predictor's start, so that a resumed run iterates from the same guess and gives the same bits).
    pure module subroutine avf_save_levels(self, buf)
        !> The stepper.
        class(avf_stepper), intent(in) :: self
        !> The state so far.
        type(state_buffer), intent(inout) :: buf

        call put_reals(buf, self%y)
        call put_reals2(buf, self%prev)
    end subroutine avf_save_levels

    !> Restore y and the previous increments (after `init` of the same run).
    pure module subroutine avf_load_levels(self, buf)
        !> The stepper.
        class(avf_stepper), intent(inout) :: self
        !> The saved state.
        type(state_buffer), intent(inout) :: buf

        call get_reals(buf, self%y)
        call get_reals2(buf, self%prev)
    end subroutine avf_load_levels

end submodule supratrans_stepper_avf_setup
