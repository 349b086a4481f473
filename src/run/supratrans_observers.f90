!> The observers of the run engine: what watches the time loop of every method (`supratrans_simulate`) and fills
!> the run record (`supratrans_result`).
!>
!> An observer sees the stepper at the start of the run (the initial levels), after every step (the newest level),
!> and at the end. It reads the state only through the stepper's interface (displacement, max |u_n|, the energy
!> bookkeeping), so it works for every method; after a step it may ask the loop to halt. The engine's list, in
!> the order it calls them (`standard_observers`):
!>
!> 1. blow-up: max |u_n| above `blowup_threshold`, or not finite, ends the run (`run_diverged`);
!> 2. ledger: the stepper's energy bookkeeping brought up to the step, E evaluated and recorded every
!>    `ledger_every` steps, at the start, and at the end;
!> 3. ramp: the energy injected up to the end of the drive's ramp;
!> 4. probes: u_n at the probe sites every `probe_every` levels (and at t = 0);
!> 5. detector: the transmission verdict (|u_n| beyond the detector site n_d above `detect_amplitude`);
!> 6. early stop: end the run as soon as its verdict is decided, if `stop_when_decided`.
!>
!> A run asked only for its verdict (threshold searches) gets 1, 5 and 6 alone: no energy bookkeeping, no ramp
!> energy, no probes (its ledger and records stay empty); 1 and 5 are then one observer (`verdict_observer`),
!> whose two maxima come from one pass over the chain (`verdict_measures`).
module supratrans_observers
    use supratrans_kinds, only: wp, i8
    use supratrans_config, only: run_config, detect_params
    use supratrans_chain, only: detector_site
    use supratrans_ledger, only: ledger_close
    use supratrans_stepper, only: stepper
    use supratrans_result, only: run_result, run_ok, record_ledger, record_probes, observe_ramp, check_blowup, &
                                 observe_detector, observe_early_stop, close_verdict
    implicit none
    private

    public :: standard_observers

    !> Something that watches the time loop.
    type, abstract, public :: run_observer
    contains
        !> At the start, after the stepper's `init` (the initial levels are set).
        procedure :: start => observer_no_start
        !> Instead of `start`, when the run resumes from a checkpoint (stepper and record restored): set up what
        !> the observer needs without recording anything (the observers keep no state of their own).
        procedure :: resume => observer_no_resume
        !> After every step that succeeded; `halt` ends the run after this step.
        procedure(observer_step), deferred :: after_step
        !> At the end of the run (`result%steps` and `result%t_end` set).
        procedure :: finish => observer_no_finish
    end type run_observer

    abstract interface
        !> Watch one step.
        subroutine observer_step(self, integrator, result, halt)
            import :: run_observer, stepper, run_result
            !> The observer.
            class(run_observer), intent(inout) :: self
            !> The stepper, after its step.
            class(stepper), intent(in) :: integrator
            !> The run's record.
            type(run_result), intent(inout) :: result
            !> Set to true to end the run after this step.
            logical, intent(out) :: halt
        end subroutine observer_step
    end interface

    !> An entry of the list of observers.
    type, public :: observer_item
        !> The observer.
        class(run_observer), allocatable :: item
    end type observer_item

    !> Blow-up: a new level with max |u_n| above the threshold (or not finite) ends the run.
    type, extends(run_observer) :: blowup_observer
        !> The blow-up threshold.
        real(wp) :: threshold = 0.0_wp
    contains
        procedure :: after_step => blowup_after_step
    end type blowup_observer

    !> The energy ledger: the stepper's bookkeeping after every step, E and the balance every `every` steps.
    type, extends(run_observer) :: ledger_observer
        !> Evaluate E and record the ledger every this many steps.
        integer :: every = 1
    contains
        procedure :: start => ledger_start
        procedure :: after_step => ledger_after_step
        procedure :: finish => ledger_finish
    end type ledger_observer

    !> The energy injected by the end of the drive's ramp.
    type, extends(run_observer) :: ramp_observer
        !> End of the ramp.
        real(wp) :: ramp_time = 0.0_wp
    contains
        procedure :: after_step => ramp_after_step
    end type ramp_observer

    !> Probe samples every `every` levels.
    type, extends(run_observer) :: probe_observer
        !> Sample every this many levels.
        integer :: every = 1
        !> Work: one sample, u_n at each probe site (allocated once per run).
        real(wp), allocatable :: sample(:)
    contains
        procedure :: start => probe_start
        procedure :: resume => probe_resume
        procedure :: after_step => probe_after_step
    end type probe_observer

    !> The transmission detector and the verdict.
    type, extends(run_observer) :: detector_observer
        !> Detector parameters.
        type(detect_params) :: detect
        !> Detector site n_d.
        integer :: site = 1
    contains
        procedure :: start => detector_start
        procedure :: after_step => detector_after_step
        procedure :: finish => detector_finish
    end type detector_observer

    !> Blow-up check and detector in one (a verdict-only run, where they follow each other): both maxima of the
    !> new level from one pass (`verdict_measures`), then the blow-up check, then, unless it halts, the detector.
    type, extends(detector_observer) :: verdict_observer
        !> The blow-up threshold.
        real(wp) :: threshold = 0.0_wp
    contains
        procedure :: after_step => verdict_after_step
    end type verdict_observer

    !> Early stop once the verdict is decided.
    type, extends(run_observer) :: early_stop_observer
        !> Detector parameters (`stop_when_decided`).
        type(detect_params) :: detect
    contains
        procedure :: after_step => early_stop_after_step
    end type early_stop_observer

contains

    !> The engine's observers of a run, in the order they are called.
    subroutine standard_observers(run, verdict_only, observers)
        !> Validated run configuration.
        type(run_config), intent(in) :: run
        !> Only the verdict is wanted: blow-up, detector and early stop alone.
        logical, intent(in) :: verdict_only
        !> The observers.
        type(observer_item), allocatable, intent(out) :: observers(:)

        if (verdict_only) then
            allocate (observers(2))
            allocate (observers(1)%item, source=verdict_observer(detect=run%detect, site=detector_site(run), &
                                                                 threshold=run%numerics%blowup_threshold))
        else
            allocate (observers(6))
            ! first the blow-up check, last the detector and the early stop (it may end the run after the others)
            allocate (observers(1)%item, source=blowup_observer(threshold=run%numerics%blowup_threshold))
            allocate (observers(2)%item, source=ledger_observer(every=run%record%ledger_every))
            allocate (observers(3)%item, source=ramp_observer(ramp_time=run%drive%ramp_time))
            allocate (observers(4)%item, source=probe_observer(every=run%record%probe_every))
            allocate (observers(5)%item, source=detector_observer(detect=run%detect, site=detector_site(run)))
        end if
        allocate (observers(size(observers))%item, source=early_stop_observer(detect=run%detect))
    end subroutine standard_observers

    !> Default start: nothing.
    subroutine observer_no_start(self, integrator, result)
        !> The observer.
        class(run_observer), intent(inout) :: self
        !> The stepper, initialised.
        class(stepper), intent(in) :: integrator
        !> The run's record.
        type(run_result), intent(inout) :: result
    end subroutine observer_no_start

    !> Default resume: nothing.
    subroutine observer_no_resume(self, integrator, result)
        !> The observer.
        class(run_observer), intent(inout) :: self
        !> The stepper, restored.
        class(stepper), intent(in) :: integrator
        !> The run's record, restored.
        type(run_result), intent(inout) :: result
    end subroutine observer_no_resume

    !> Resume: the work array of a sample (the samples taken are in the record).
    subroutine probe_resume(self, integrator, result)
        !> The observer.
        class(probe_observer), intent(inout) :: self
        !> The stepper, restored.
        class(stepper), intent(in) :: integrator
        !> The run's record, restored.
        type(run_result), intent(inout) :: result

        if (allocated(self%sample)) deallocate (self%sample)
        allocate (self%sample(size(result%probes)))
    end subroutine probe_resume

    !> Default finish: nothing.
    subroutine observer_no_finish(self, integrator, result)
        !> The observer.
        class(run_observer), intent(inout) :: self
        !> The stepper at the end of the run.
        class(stepper), intent(in) :: integrator
        !> The run's record.
        type(run_result), intent(inout) :: result
    end subroutine observer_no_finish

    !> Blow-up check of the new level.
    subroutine blowup_after_step(self, integrator, result, halt)
        !> The observer.
        class(blowup_observer), intent(inout) :: self
        !> The stepper.
        class(stepper), intent(in) :: integrator
        !> The run's record.
        type(run_result), intent(inout) :: result
        !> True when the run blew up.
        logical, intent(out) :: halt

        call check_blowup(result, integrator%blowup_measure(), self%threshold, integrator%level_time(), halt)
    end subroutine blowup_after_step

    !> First evaluation of the stored energy (E_0 of the balance) and the first ledger record.
    subroutine ledger_start(self, integrator, result)
        !> The observer.
        class(ledger_observer), intent(inout) :: self
        !> The stepper.
        class(stepper), intent(in) :: integrator
        !> The run's record.
        type(run_result), intent(inout) :: result

        call ledger_close(result%ledger, integrator%stored_energy())
        call record_ledger(result, integrator%energy_time())
    end subroutine ledger_start

    !> The step's energies into the ledger; every `every` steps E, the balance residual and a record.
    subroutine ledger_after_step(self, integrator, result, halt)
        !> The observer.
        class(ledger_observer), intent(inout) :: self
        !> The stepper.
        class(stepper), intent(in) :: integrator
        !> The run's record.
        type(run_result), intent(inout) :: result
        !> Always false.
        logical, intent(out) :: halt

        halt = .false.
        call integrator%account(result%ledger)
        if (mod(integrator%steps, int(self%every, i8)) == 0) then
            call ledger_close(result%ledger, integrator%stored_energy())
            call record_ledger(result, integrator%energy_time())
        end if
    end subroutine ledger_after_step

    !> Close the ledger on the last step of a run that ended normally between two records.
    subroutine ledger_finish(self, integrator, result)
        !> The observer.
        class(ledger_observer), intent(inout) :: self
        !> The stepper.
        class(stepper), intent(in) :: integrator
        !> The run's record.
        type(run_result), intent(inout) :: result

        if (result%status == run_ok .and. mod(result%steps, int(self%every, i8)) /= 0 .and. result%steps > 0) then
            call ledger_close(result%ledger, integrator%stored_energy())
            call record_ledger(result, integrator%energy_time())
        end if
    end subroutine ledger_finish

    !> Energy injected by the end of the ramp.
    subroutine ramp_after_step(self, integrator, result, halt)
        !> The observer.
        class(ramp_observer), intent(inout) :: self
        !> The stepper.
        class(stepper), intent(in) :: integrator
        !> The run's record.
        type(run_result), intent(inout) :: result
        !> Always false.
        logical, intent(out) :: halt

        halt = .false.
        call observe_ramp(result, integrator%energy_time(), self%ramp_time)
    end subroutine ramp_after_step

    !> Samples of the initial levels t_j = j dt, j = 0 .. initial_levels - 1, that fall on the sampling interval.
    subroutine probe_start(self, integrator, result)
        !> The observer.
        class(probe_observer), intent(inout) :: self
        !> The stepper.
        class(stepper), intent(in) :: integrator
        !> The run's record.
        type(run_result), intent(inout) :: result
        integer :: j

        if (allocated(self%sample)) deallocate (self%sample)
        allocate (self%sample(size(result%probes)))
        do j = 0, integrator%initial_levels - 1
            if (mod(j, self%every) /= 0) cycle
            call take_sample(self, integrator, result, integrator%initial_levels - 1 - j, real(j, wp)*integrator%dt)
        end do
    end subroutine probe_start

    !> A sample of the new level when its index is a multiple of `every`.
    subroutine probe_after_step(self, integrator, result, halt)
        !> The observer.
        class(probe_observer), intent(inout) :: self
        !> The stepper.
        class(stepper), intent(in) :: integrator
        !> The run's record.
        type(run_result), intent(inout) :: result
        !> Always false.
        logical, intent(out) :: halt
        integer(i8) :: level

        halt = .false.
        level = integrator%steps + (integrator%initial_levels - 1)
        if (mod(level, int(self%every, i8)) == 0) call take_sample(self, integrator, result, 0, integrator%level_time())
    end subroutine probe_after_step

    !> Record u_n at the probe sites of level `back` (0 the newest) at time t.
    subroutine take_sample(self, integrator, result, back, t)
        !> The observer.
        class(probe_observer), intent(inout) :: self
        !> The stepper.
        class(stepper), intent(in) :: integrator
        !> The run's record.
        type(run_result), intent(inout) :: result
        !> Which level.
        integer, intent(in) :: back
        !> Its time.
        real(wp), intent(in) :: t
        integer :: j

        do j = 1, size(self%sample)
            self%sample(j) = integrator%displacement(result%probes(j), back)
        end do
        call record_probes(result, t, self%sample)
    end subroutine take_sample

    !> The detector site of the run.
    subroutine detector_start(self, integrator, result)
        !> The observer.
        class(detector_observer), intent(inout) :: self
        !> The stepper.
        class(stepper), intent(in) :: integrator
        !> The run's record.
        type(run_result), intent(inout) :: result

        result%detect_site = self%site
    end subroutine detector_start

    !> The detector on the new level.
    subroutine detector_after_step(self, integrator, result, halt)
        !> The observer.
        class(detector_observer), intent(inout) :: self
        !> The stepper.
        class(stepper), intent(in) :: integrator
        !> The run's record.
        type(run_result), intent(inout) :: result
        !> Always false (`early_stop_observer` halts).
        logical, intent(out) :: halt

        halt = .false.
        call observe_detector(result, self%detect, self%site, integrator%max_abs_u(self%site + 1), &
                              integrator%level_time())
    end subroutine detector_after_step

    !> Blow-up check, then (unless it halts) the detector, from one pass over the new level.
    subroutine verdict_after_step(self, integrator, result, halt)
        !> The observer.
        class(verdict_observer), intent(inout) :: self
        !> The stepper.
        class(stepper), intent(in) :: integrator
        !> The run's record.
        type(run_result), intent(inout) :: result
        !> True when the run blew up (`early_stop_observer` halts on the verdict).
        logical, intent(out) :: halt
        real(wp) :: blowup, beyond

        call integrator%verdict_measures(self%site + 1, blowup, beyond)
        call check_blowup(result, blowup, self%threshold, integrator%level_time(), halt)
        if (halt) return
        call observe_detector(result, self%detect, self%site, beyond, integrator%level_time())
    end subroutine verdict_after_step

    !> The verdict of a run that never transmitted.
    subroutine detector_finish(self, integrator, result)
        !> The observer.
        class(detector_observer), intent(inout) :: self
        !> The stepper.
        class(stepper), intent(in) :: integrator
        !> The run's record.
        type(run_result), intent(inout) :: result

        call close_verdict(result, self%detect)
    end subroutine detector_finish

    !> End the run once its verdict is decided, if asked to.
    subroutine early_stop_after_step(self, integrator, result, halt)
        !> The observer.
        class(early_stop_observer), intent(inout) :: self
        !> The stepper.
        class(stepper), intent(in) :: integrator
        !> The run's record.
        type(run_result), intent(inout) :: result
        !> True when the run should stop now.
        logical, intent(out) :: halt

        call observe_early_stop(result, self%detect, halt)
    end subroutine early_stop_after_step

end module supratrans_observers
