!> The factory of steppers: the integrator of a method id (`method_*` of `supratrans_config`). A new method is one
!> stepper module (extending `stepper`) and one name: its id in `supratrans_config`, its case here, its name in the
!> input schema.
module supratrans_steppers
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_strings, only: int_str
    use supratrans_config, only: method_newton, method_linearized, method_rk4, method_rk8, method_avf4, method_avf8
    use supratrans_stepper, only: stepper
    use supratrans_stepper_newton, only: newton_stepper
    use supratrans_stepper_linearized, only: linearized_stepper
    use supratrans_stepper_rk4, only: rk4_stepper
    use supratrans_stepper_rk8, only: rk8_stepper
    use supratrans_stepper_avf, only: avf_stepper
    implicit none
    private

    public :: new_stepper

contains

    !> Allocate the stepper of method `method` (not yet initialised: call its `init`). An unknown id allocates
    !> nothing and returns an error.
    subroutine new_stepper(method, integrator, error)
        !> Method identifier (`method_newton`, `method_linearized`, `method_rk4`, `method_rk8`, `method_avf4`,
        !> `method_avf8`).
        integer, intent(in) :: method
        !> The stepper, allocated with the method's type.
        class(stepper), allocatable, intent(out) :: integrator
        !> Error, allocated when the method is unknown.
        type(error_type), allocatable, intent(out) :: error

        select case (method)
        case (method_newton)
            allocate (newton_stepper :: integrator)
        case (method_linearized)
            allocate (linearized_stepper :: integrator)
        case (method_rk4)
            allocate (rk4_stepper :: integrator)
        case (method_rk8)
            allocate (rk8_stepper :: integrator)
        case (method_avf4, method_avf8)
            allocate (avf_stepper :: integrator)   ! its init reads the number of Gauss nodes from the method
        case default
            call fatal_error(error, "unknown method identifier " // int_str(method), err_input)
        end select
    end subroutine new_stepper

end module supratrans_steppers
