!> The curves of a scene: one run configuration per (potential, value of the varied parameter), as in the paper's
!> figures (e.g. Fig. 2: gamma = 0, 0.01, 0.02, 0.03 for each of the two potentials).
module supratrans_curves
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp
    use supratrans_config, only: input_config, run_config
    implicit none
    private

    public :: curve_count, potential_count, value_count, curve_run, curve_indices, curve_value

contains

    !> Number of potentials of the scene (the &scene list, or the &chain potential alone).
    pure function potential_count(cfg) result(n)
        !> Validated input.
        type(input_config), intent(in) :: cfg
        integer :: n

        n = 1
        if (allocated(cfg%scene%potentials)) n = max(1, size(cfg%scene%potentials))
    end function potential_count

    !> Number of values of the varied parameter (1 when nothing varies).
    pure function value_count(cfg) result(n)
        !> Validated input.
        type(input_config), intent(in) :: cfg
        integer :: n

        n = 1
        if (trim(cfg%scene%vary) /= "none" .and. allocated(cfg%scene%values)) n = max(1, size(cfg%scene%values))
    end function value_count

    !> Number of curves: potentials x values.
    pure function curve_count(cfg) result(n)
        !> Validated input.
        type(input_config), intent(in) :: cfg
        integer :: n

        n = potential_count(cfg)*value_count(cfg)
    end function curve_count

    !> Potential index and value index of curve `icurve` (values vary fastest).
    pure subroutine curve_indices(cfg, icurve, ipot, ival)
        !> Validated input.
        type(input_config), intent(in) :: cfg
        !> Curve index, 1..curve_count.
        integer, intent(in) :: icurve
        !> Potential index and value index.
        integer, intent(out) :: ipot, ival

        ipot = (icurve - 1)/value_count(cfg) + 1
        ival = mod(icurve - 1, value_count(cfg)) + 1
    end subroutine curve_indices

    !> The run configuration of curve `icurve`: the base run with its potential and varied parameter set.
    pure function curve_run(cfg, icurve) result(run)
        !> Validated input.
        type(input_config), intent(in) :: cfg
        !> Curve index, 1..curve_count.
        integer, intent(in) :: icurve
        type(run_config) :: run
        integer :: ipot, ival
        real(wp) :: value

        run = cfg%run
        call curve_indices(cfg, icurve, ipot, ival)
        if (allocated(cfg%scene%potentials)) then
            if (size(cfg%scene%potentials) > 0) run%chain%potential = cfg%scene%potentials(ipot)
        end if
        if (trim(cfg%scene%vary) == "none" .or. .not. allocated(cfg%scene%values)) return
        value = cfg%scene%values(ival)
        select case (trim(cfg%scene%vary))
        case ("gamma")
            run%chain%gamma = value
        case ("beta")
            run%chain%beta = value
        case ("m2")
            run%chain%m2 = value
        case default
            continue                            ! 'none': validated by supratrans_input
        end select
    end function curve_run

    !> Value of the varied parameter (`&scene vary`) on curve `icurve`; NaN when nothing varies.
    function curve_value(cfg, icurve) result(value)
        !> Validated input.
        type(input_config), intent(in) :: cfg
        !> Curve index, 1..curve_count.
        integer, intent(in) :: icurve
        real(wp) :: value
        integer :: ipot, ival

        if (trim(cfg%scene%vary) == "none" .or. .not. allocated(cfg%scene%values)) then
            value = ieee_value(1.0_wp, ieee_quiet_nan)
        else
            call curve_indices(cfg, icurve, ipot, ival)
            value = cfg%scene%values(ival)
        end if
    end function curve_value

end module supratrans_curves
