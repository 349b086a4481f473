!> The curves of a scene: one run configuration per (potential, value of the varied parameter), as in the paper's
!> figures (e.g. Fig. 2: gamma = 0, 0.01, 0.02, 0.03 for each of the two potentials).
module supratrans_curves
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp
    use supratrans_config, only: input_config, run_config, vary_none, vary_gamma, vary_beta, vary_m2, vary_choices
    use supratrans_potential, only: potential_name
    use supratrans_chain, only: band_gap_edge
    use supratrans_hdf5, only: h5_file, h5_write, h5_write_attr, h5_create_group
    implicit none
    private

    public :: curve_count, curve_run, curve_indices, write_curves

contains

    !> Whether the curves differ in a parameter (`vary` is not 'none' and `values` are given).
    pure logical function varies(cfg)
        !> Validated input.
        type(input_config), intent(in) :: cfg

        varies = cfg%scene%vary /= vary_none .and. allocated(cfg%scene%values)
    end function varies

    !> Number of values of the varied parameter (1 when nothing varies).
    pure integer function value_count(cfg)
        !> Validated input.
        type(input_config), intent(in) :: cfg

        value_count = 1
        if (varies(cfg)) value_count = max(1, size(cfg%scene%values))
    end function value_count

    !> Number of curves: potentials (the &scene list, or the &chain potential alone) x values.
    pure integer function curve_count(cfg)
        !> Validated input.
        type(input_config), intent(in) :: cfg

        curve_count = value_count(cfg)
        if (allocated(cfg%scene%potentials)) curve_count = max(1, size(cfg%scene%potentials))*value_count(cfg)
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

        run = cfg%run
        call curve_indices(cfg, icurve, ipot, ival)
        if (allocated(cfg%scene%potentials)) then
            if (size(cfg%scene%potentials) > 0) run%chain%potential = cfg%scene%potentials(ipot)
        end if
        if (.not. varies(cfg)) return
        select case (cfg%scene%vary)
        case (vary_gamma)
            run%chain%gamma = cfg%scene%values(ival)
        case (vary_beta)
            run%chain%beta = cfg%scene%values(ival)
        case (vary_m2)
            run%chain%m2 = cfg%scene%values(ival)
        case default
            continue                            ! vary_none: validated by supratrans_input
        end select
    end function curve_run

    !> Write `/curves`, the same in every scene: the group's attribute `vary`, and per curve its potential, the value
    !> of the varied parameter (in the units of that parameter: gamma and beta 1/time, m2 1/time^2; "1" and NaN when
    !> nothing varies), gamma, beta, m^2 and the band-gap edge sqrt(V''(0) + m^2). A scene adds its own per-curve
    !> datasets (`threshold_As`, `screen_dt`) after this.
    subroutine write_curves(file, cfg, runs)
        !> Open output file (a failure sticks in it).
        type(h5_file), intent(inout) :: file
        !> Validated input.
        type(input_config), intent(in) :: cfg
        !> The run configuration of each curve (`curve_run`).
        type(run_config), intent(in) :: runs(:)
        character(len=:), allocatable :: names(:)
        real(wp) :: values(size(runs)), edge(size(runs)), gamma(size(runs)), beta(size(runs)), m2(size(runs))
        character(len=:), allocatable :: value_units
        integer :: ic, ipot, ival

        ! the names' width: 16 (that of the files before the longer names), or the longest name's
        ic = 16
        do ipot = 1, size(runs)
            ic = max(ic, len(potential_name(runs(ipot)%chain%potential)))
        end do
        allocate (character(len=ic) :: names(size(runs)))
        do ic = 1, size(runs)
            names(ic) = potential_name(runs(ic)%chain%potential)
            values(ic) = ieee_value(1.0_wp, ieee_quiet_nan)       ! the value of the varied parameter, NaN if none
            call curve_indices(cfg, ic, ipot, ival)
            if (varies(cfg)) values(ic) = cfg%scene%values(ival)
            edge(ic) = band_gap_edge(runs(ic)%chain)
            gamma(ic) = runs(ic)%chain%gamma
            beta(ic) = runs(ic)%chain%beta
            m2(ic) = runs(ic)%chain%m2
        end do
        select case (cfg%scene%vary)
        case (vary_gamma, vary_beta)
            value_units = "1/time"
        case (vary_m2)
            value_units = "1/time^2"
        case default
            value_units = "1"
        end select
        call h5_create_group(file, "/curves", "One entry per curve: a potential and a value of the varied " &
                             // "parameter (attribute vary), the values fastest")
        call h5_write_attr(file, "/curves", "vary", trim(vary_choices(cfg%scene%vary)))
        call h5_write(file, "/curves/potential", names, "1", "On-site potential of each curve", dims="curve")
        call h5_write(file, "/curves/value", values, value_units, "Value of the varied parameter (attribute vary " &
                      // "of /curves) of each curve; NaN when vary = 'none'", dims="curve")
        call h5_write(file, "/curves/gamma", gamma, "1/time", "External damping gamma of each curve", &
                      dims="curve")
        call h5_write(file, "/curves/beta", beta, "1/time", "Internal damping beta of each curve", &
                      dims="curve")
        call h5_write(file, "/curves/m2", m2, "1/time^2", &
                      "Mass term m^2 of each curve (negative: imaginary mass)", dims="curve")
        call h5_write(file, "/curves/band_gap_edge", edge, "1/time", "Upper edge sqrt(V''(0) + m^2) of the band gap of " &
                      // "each curve", dims="curve")
    end subroutine write_curves

end module supratrans_curves
