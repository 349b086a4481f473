!> The curves of a scene: one run configuration per (potential, value of the varied parameter), as in the paper's
!> figures (e.g. Fig. 2: gamma = 0, 0.01, 0.02, 0.03 for each of the two potentials). The varied parameter (&scene
!> vary) is any numeric key of &chain, &drive or &numerics (`vary_keys` of the schema: the choice set is generated
!> from the key table), set through the schema's `set_key`, so that no key is named here.
module supratrans_curves
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp
    use supratrans_config, only: input_config, run_config, vary_none, vary_choices
    use supratrans_keys, only: key_value, kt_integer
    use supratrans_strings, only: int_str, real_str
    use supratrans_schema, only: key_table, vary_keys, get_key, set_key
    use supratrans_potential, only: potential_name
    use supratrans_chain, only: band_gap_edge
    use supratrans_hdf5, only: h5_file
    use supratrans_output_rows, only: write_row, write_row_group, write_row_attr, shared_curves, &
        shared_curves_potential, shared_curves_value, shared_curves_gamma, shared_curves_beta, shared_curves_m2, &
        shared_curves_band_gap_edge
    implicit none
    private

    public :: curve_count, curve_run, curve_indices, write_curves, varied_key, curve_label

contains

    !> Whether the curves differ in a parameter (`vary` is not 'none' and `values` are given).
    pure logical function varies(cfg)
        !> Validated input.
        type(input_config), intent(in) :: cfg

        varies = cfg%scene%vary /= vary_none .and. allocated(cfg%scene%values)
    end function varies

    !> Index in `key_table` of the varied key; 0 when nothing varies.
    pure integer function varied_key(cfg)
        !> Validated input.
        type(input_config), intent(in) :: cfg

        varied_key = 0
        if (cfg%scene%vary >= 1 .and. cfg%scene%vary <= size(vary_keys)) varied_key = vary_keys(cfg%scene%vary)
    end function varied_key

    !> "curve 2 (sine-gordon, n = 100)": a curve as messages name it.
    pure function curve_label(cfg, icurve) result(label)
        !> Validated input.
        type(input_config), intent(in) :: cfg
        !> Curve index, 1..curve_count.
        integer, intent(in) :: icurve
        character(len=:), allocatable :: label
        type(run_config) :: run
        integer :: ipot, ival, ik

        run = curve_run(cfg, icurve)
        call curve_indices(cfg, icurve, ipot, ival)
        label = "curve " // int_str(icurve) // " (" // potential_name(run%chain%potential)
        ik = varied_key(cfg)
        if (varies(cfg) .and. ik > 0) then
            label = label // ", " // trim(vary_choices(cfg%scene%vary)) // " = "
            if (key_table(ik)%value_type == kt_integer) then
                label = label // int_str(nint(cfg%scene%values(ival)))
            else
                label = label // real_str(cfg%scene%values(ival))
            end if
        end if
        label = label // ")"
    end function curve_label

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
        type(input_config) :: curve
        type(key_value) :: v
        integer :: ipot, ival, ik

        run = cfg%run
        call curve_indices(cfg, icurve, ipot, ival)
        if (allocated(cfg%scene%potentials)) then
            if (size(cfg%scene%potentials) > 0) run%chain%potential = cfg%scene%potentials(ipot)
        end if
        ik = varied_key(cfg)
        if (.not. varies(cfg) .or. ik == 0) return
        ! the value set through the key table, as the namelist reader sets it (an integer key: the nearest integer;
        ! validation refuses a value that is not whole)
        curve%run = run
        v = get_key(curve, ik)
        if (key_table(ik)%value_type == kt_integer) then
            v%ints(1) = nint(cfg%scene%values(ival))
        else
            v%reals(1) = cfg%scene%values(ival)
        end if
        call set_key(curve, ik, v)
        run = curve%run
    end function curve_run

    !> Write `/curves`, the same in every scene: the group's attribute `vary`, and per curve its potential, the value
    !> of the varied parameter (in the units of its key; "1" and NaN when nothing varies), gamma, beta, m^2 and the
    !> band-gap edge sqrt(V''(0) + m^2), by the rows every curve table shares (`shared_curves_*` of
    !> `supratrans_output_rows`, the same in each table). A scene adds its own per-curve datasets (`threshold_As`,
    !> `screen_dt`) after this.
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
        value_units = "1"
        if (varied_key(cfg) > 0) value_units = trim(key_table(varied_key(cfg))%units)
        call write_row_group(file, shared_curves)
        call write_row_attr(file, shared_curves, "vary", trim(vary_choices(cfg%scene%vary)))
        call write_row(file, shared_curves_potential, names)
        call write_row(file, shared_curves_value, values, units=value_units)
        call write_row(file, shared_curves_gamma, gamma)
        call write_row(file, shared_curves_beta, beta)
        call write_row(file, shared_curves_m2, m2)
        call write_row(file, shared_curves_band_gap_edge, edge)
    end subroutine write_curves

end module supratrans_curves
