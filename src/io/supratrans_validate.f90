!> Checking a configuration before any work starts: the ranges of the schema, then the rules that involve several
!> keys, then the output file.
!>
!> 1. `check_keys`: every key against its row of `key_table` (list length, finite reals, bounds, allowed names);
!>    nothing key-specific is written here, so a new key with a range is checked by its row alone;
!> 2. `check_rules`: the hand-written rules between keys: 0 <= N0 <= N (naming N0 as the default when it was not
!>    given), Omega inside the band gap 0 < Omega < sqrt(V''(0) + m^2), T >= 2 dt, the paper's necessary stability
!>    condition (c^2 - m^2/4) dt^2 < 1 + (gamma/4 + beta) dt, probes within 1..N, the scene's axes and curves, the
!>    detector site, a named output file, continuation_step <= continuation_step_max (refused, never clamped);
!> 3. `check_limits` (`supratrans_limits`, then the scene's own), and the scene's `check_input`: every check the
!>    run's task making would make, so that `--check` refuses what the run would, before anything is created;
!> 4. `check_output_file`: the output file is not replaced by accident.
!>
!> `input_warnings` gives the lines said about keys a scene does not use (`&drive omega` on a frequency axis).
!>
!> Every failure is one line (status `err_input`): `<file>: &<group>: <key> = <value>: <what is wrong>`.
module supratrans_validate
    use supratrans_kinds, only: wp
    use supratrans_limits, only: check_limits
    use supratrans_system, only: path_kind, path_directory, link_kind, path_missing
    use supratrans_error, only: error_type
    use supratrans_config, only: input_config, run_config, method_avf4, method_avf8, vary_none, vary_choices
    use supratrans_potential, only: potential_name, potential_takes, potential_ids, potential_names
    use supratrans_chain, only: band_gap_edge, gap_squared, onsite_stiffness, stability_lhs, stability_rhs, &
                                stable_by_paper_condition, critical_dt
    use supratrans_curves, only: curve_count, curve_run
    use supratrans_strings, only: int_str, real_str, fixed4, joined, find_name
    use supratrans_keys, only: key_spec, key_value, kt_integer, kt_real, kt_name, input_error
    use supratrans_schema, only: key_table, get_key, choice_names, choice_noun
    use supratrans_scene, only: scene_type, new_scene
    use supratrans_namelist, only: parse_namelist, parsed_input
    implicit none
    private

    public :: validate_config, input_warnings

contains

    !> Check that a configuration is complete and within range: the checks `read_input` makes after conversion.
    !>
    !> Meant also for configurations built or changed in code (scenes). Messages start with `cfg%source`, or with
    !> "configuration" when that is not set.
    subroutine validate_config(cfg, error, check_output)
        !> The configuration to check.
        type(input_config), intent(in) :: cfg
        !> Allocated when a check fails.
        type(error_type), allocatable, intent(out) :: error
        !> Check that the output file does not exist (unless `overwrite`); default true.
        logical, intent(in), optional :: check_output
        character(len=:), allocatable :: where
        logical :: check_file
        class(scene_type), allocatable :: scene

        where = "configuration"
        if (allocated(cfg%source)) then
            if (len(cfg%source) > 0) where = cfg%source
        end if
        call check_keys(cfg, where, error)
        if (allocated(error)) return
        ! the kind is one of the schema's choices now: its scene answers the questions that depend on it
        call new_scene(trim(cfg%scene%kind), scene, error)
        if (allocated(error)) return
        call check_rules(cfg, scene, where, error)
        if (allocated(error)) return
        call check_limits(cfg, scene, where, error)
        if (allocated(error)) return
        call scene%check_input(cfg, where, error)
        if (allocated(error)) return
        check_file = .true.
        if (present(check_output)) check_file = check_output
        if (check_file) call check_output_file(cfg, where, error)
    end subroutine validate_config

    !> Every key against its row of `key_table`: at most `max_values` values, each finite (reals), within its
    !> bounds (numbers) and among its choices (names).
    pure subroutine check_keys(cfg, where, error)
        !> The configuration.
        type(input_config), intent(in) :: cfg
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Allocated on the first failed check.
        type(error_type), allocatable, intent(out) :: error
        type(key_value) :: v
        character(len=:), allocatable :: label
        integer :: ik, i

        do ik = 1, size(key_table)
            associate (spec => key_table(ik))
                v = get_key(cfg, ik)
                if (v%n > spec%max_values) then
                    call input_error(error, where, trim(spec%group), trim(spec%key) // ": at most " &
                                     // int_str(spec%max_values) // " values, got " // int_str(v%n))
                    return
                end if
                do i = 1, v%n
                    label = trim(spec%key)
                    if (spec%max_values > 1) label = label // "(" // int_str(i) // ")"
                    select case (spec%value_type)
                    case (kt_real)
                        call check_number(spec, where, label, v%reals(i), real_str(v%reals(i)), error)
                    case (kt_integer)
                        call check_number(spec, where, label, real(v%ints(i), wp), int_str(v%ints(i)), error)
                    case (kt_name)
                        if (spec%ids) then
                            call check_choice(spec, where, label, v%ints(i), "", error)
                        else
                            call check_choice(spec, where, label, 0, trim(v%texts(i)), error)
                        end if
                    case default
                        continue    ! logicals: no range
                    end select
                    if (allocated(error)) return
                end do
            end associate
        end do
    end subroutine check_keys

    !> A number against the bounds of its key: finite, then `min`, then `max`.
    pure subroutine check_number(spec, where, label, x, shown, error)
        !> The key.
        type(key_spec), intent(in) :: spec
        !> Prefix of messages.
        character(len=*), intent(in) :: where
        !> The key (with the index of the value in a list).
        character(len=*), intent(in) :: label
        !> The value.
        real(wp), intent(in) :: x
        !> The value as messages show it.
        character(len=*), intent(in) :: shown
        !> Allocated when the value is out of range.
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: problem

        problem = ""
        if (.not. (abs(x) <= huge(x))) then
            problem = "must be finite"
        else if (.not. meets(x, spec%lower)) then
            problem = "must be " // trim(spec%lower)
        else if (.not. meets(x, spec%upper)) then
            problem = "must be " // trim(spec%upper)
        end if
        if (len(problem) == 0) return
        if (len_trim(spec%message) > 0 .and. problem /= "must be finite") problem = trim(spec%message)
        call input_error(error, where, trim(spec%group), label // " = " // shown // ": " // problem)
    end subroutine check_number

    !> Whether `x` meets a bound of the key table ("> 0", "<= 100": the relation, a blank, the number); a blank
    !> bound is met by every value.
    pure logical function meets(x, bound)
        !> The value.
        real(wp), intent(in) :: x
        !> The bound.
        character(len=*), intent(in) :: bound
        real(wp) :: limit

        meets = .true.
        if (len_trim(bound) == 0) return
        read (bound(index(bound, " ") + 1:), *) limit
        meets = (bound(1:1) == ">" .and. x > limit) .or. (bound(1:1) == "<" .and. x < limit) &
                .or. (bound(2:2) == "=" .and. x == limit)
    end function meets

    !> A name (or the number of a named choice) against the choices of its key.
    pure subroutine check_choice(spec, where, label, id, name, error)
        !> The key.
        type(key_spec), intent(in) :: spec
        !> Prefix of messages.
        character(len=*), intent(in) :: where
        !> The key (with the index of the value in a list).
        character(len=*), intent(in) :: label
        !> Number of the choice (keys with `ids`).
        integer, intent(in) :: id
        !> The name (other keys).
        character(len=*), intent(in) :: name
        !> Allocated when the value is not among the choices.
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: shown

        if (spec%choices == 0) return
        associate (names => choice_names(spec%choices))
            if (spec%ids) then
                if (id >= 1 .and. id <= size(names)) return
                shown = int_str(id)
            else
                if (find_name(names, name) > 0) return
                shown = "'" // name // "'"
            end if
            call input_error(error, where, trim(spec%group), label // " = " // shown // ": unknown " &
                             // choice_noun(spec%choices) // " (known: " // joined(names, "") // ")")
        end associate
    end subroutine check_choice

    !> The rules between keys (after `check_keys`: every value is in its own range).
    pure subroutine check_rules(cfg, scene, where, error)
        !> The configuration.
        type(input_config), intent(in) :: cfg
        !> Its scene.
        class(scene_type), intent(in) :: scene
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Allocated on the first failed check.
        type(error_type), allocatable, intent(out) :: error
        real(wp) :: edge
        integer :: i

        associate (ch => cfg%run%chain, dr => cfg%run%drive, nu => cfg%run%numerics, rec => cfg%run%record)
            if (ch%n0 < 0 .or. ch%n0 > ch%n) then
                if (key_given(cfg, "chain", "n0")) then
                    call input_error(error, where, "chain", "n0 = " // int_str(ch%n0) // ": need 0 <= N0 <= N = " &
                                     // int_str(ch%n))
                else
                    call input_error(error, where, "chain", "n0 = " // int_str(ch%n0) // " (the default, not given): " &
                                     // "need 0 <= N0 <= N = " // int_str(ch%n) // "; give n0 (the absorber's start) " &
                                     // "with n")
                end if
                return
            end if
            if (ch%eta /= 0.0_wp .and. .not. run_takes(cfg, "eta")) then     ! eta = 0 changes nothing
                call input_error(error, where, "chain", "eta = " // real_str(ch%eta) // " is a parameter of no " &
                                 // "potential of this run: only " // takers("eta") // " take" // " it (&chain " &
                                 // "potential, &scene potentials); remove eta or choose such a potential")
                return
            end if
            if (.not. (gap_squared(ch) > 0.0_wp)) then
                call input_error(error, where, "chain", "m2 = " // real_str(ch%m2) // ": need V''(0) + m2 > 0 (V''(0) = " &
                                 // real_str(onsite_stiffness(ch)) // " for " // potential_name(ch%potential) &
                                 // "): the band gap 0 < Omega^2 < V''(0) + m2 must not be empty")
                return
            end if
            edge = band_gap_edge(ch)
            if (dr%omega >= edge .and. .not. cfg%allow_outside_gap .and. scene%gap_rule()) then
                call input_error(error, where, "drive", "omega = " // real_str(dr%omega) &
                                 // " is outside the band gap 0 < Omega < " // fixed4(edge) &
                                 // " (set allow_outside_gap = .true. to run anyway)")
                return
            end if
            if (nu%t_final < 2.0_wp*nu%dt) then
                call input_error(error, where, "numerics", "t_final = " // real_str(nu%t_final) &
                                 // ": must be >= 2 dt = " // real_str(2.0_wp*nu%dt))
                return
            end if
            if (.not. stable_by_paper_condition(ch, nu%dt) .and. .not. cfg%allow_unstable &
                .and. .not. a_stable(nu%method)) then
                call input_error(error, where, "numerics", "dt = " // real_str(nu%dt) &
                                 // " violates the paper's necessary stability condition" &
                                 // " (c^2 - m^2/4) dt^2 < 1 + (gamma/4 + beta) dt: " &
                                 // real_str(stability_lhs(ch, nu%dt), 6) // " >= " &
                                 // real_str(stability_rhs(ch, nu%dt), 6) // " (it needs dt < " &
                                 // real_str(critical_dt(ch), 6) // "; set allow_unstable = .true. to run anyway)")
                return
            end if
            if (allocated(rec%probes)) then
                do i = 1, size(rec%probes)
                    if (rec%probes(i) < 1 .or. rec%probes(i) > ch%n) then
                        call input_error(error, where, "record", "probes(" // int_str(i) // ") = " &
                                         // int_str(rec%probes(i)) // ": must be a site 1..N = " // int_str(ch%n))
                        return
                    end if
                    if (any(rec%probes(1:i - 1) == rec%probes(i))) then
                        call input_error(error, where, "record", "probes(" // int_str(i) // ") = " &
                                         // int_str(rec%probes(i)) // ": site given twice")
                        return
                    end if
                end do
            end if
        end associate

        call check_scene(cfg, scene, where, error)
        if (allocated(error)) return

        if (cfg%run%detect%site < 0 .or. cfg%run%detect%site >= cfg%run%chain%n) then
            call input_error(error, where, "detect", "site = " // int_str(cfg%run%detect%site) &
                             // ": need 0 (automatic) <= site < N = " // int_str(cfg%run%chain%n))
            return
        end if
        if (len_trim(cfg%output%file) == 0) then
            call input_error(error, where, "output", "file = '': must name the output file")
            return
        end if
    end subroutine check_rules

    !> The scene's rules: `values` go with `vary`; the axes are ordered; each curve (potential, varied value) is a
    !> valid chain, stable by the paper's condition, and (scenes whose `gap_rule` holds) driven inside its band gap.
    pure subroutine check_scene(cfg, scene, where, error)
        !> The configuration.
        type(input_config), intent(in) :: cfg
        !> Its scene.
        class(scene_type), intent(in) :: scene
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Allocated on the first failed check.
        type(error_type), allocatable, intent(out) :: error
        type(run_config) :: run
        integer :: ic
        character(len=:), allocatable :: label

        associate (sc => cfg%scene)
            if (sc%vary /= vary_none .and. .not. allocated(sc%values)) then
                call input_error(error, where, "scene", "vary = '" // trim(vary_choices(sc%vary)) &
                                 // "' needs a list of values")
                return
            end if
            if (sc%vary == vary_none .and. allocated(sc%values)) then
                call input_error(error, where, "scene", &
                                 "values are given but vary = 'none' (say which parameter they set)")
                return
            end if
            if (.not. (sc%continuation_step <= sc%continuation_step_max)) then
                call input_error(error, where, "scene", "continuation_step = " // real_str(sc%continuation_step) &
                                 // ": must be <= continuation_step_max = " // real_str(sc%continuation_step_max) &
                                 // default_note(cfg, "continuation_step_max") // " (it is not clamped)")
                return
            end if
            if (scene%one_run()) return
            if (.not. (sc%amplitude_max >= sc%amplitude_min)) then
                call input_error(error, where, "scene", "amplitude_max = " // real_str(sc%amplitude_max) &
                                 // ": must be >= amplitude_min = " // real_str(sc%amplitude_min))
                return
            end if
            if (.not. (sc%omega_max >= sc%omega_min)) then
                call input_error(error, where, "scene", "omega_max = " // real_str(sc%omega_max) &
                                 // ": must be >= omega_min = " // real_str(sc%omega_min))
                return
            end if
            if (.not. (sc%coarse_step >= sc%resolution)) then
                call input_error(error, where, "scene", "coarse_step = " // real_str(sc%coarse_step) &
                                 // ": must be >= resolution = " // real_str(sc%resolution))
                return
            end if
            if (sc%screen_dt > 0.0_wp .and. .not. (sc%screen_dt >= cfg%run%numerics%dt &
                                                   .and. sc%screen_dt <= cfg%run%numerics%t_final/2.0_wp)) then
                call input_error(error, where, "scene", "screen_dt = " // real_str(sc%screen_dt) &
                                 // ": must be 0 (the &numerics dt) or between dt = " // real_str(cfg%run%numerics%dt) &
                                 // " and t_final/2 = " // real_str(cfg%run%numerics%t_final/2.0_wp))
                return
            end if
        end associate

        do ic = 1, curve_count(cfg)
            run = curve_run(cfg, ic)
            label = "curve " // int_str(ic) // " (" // potential_name(run%chain%potential) // ", " &
                    // trim(vary_choices(cfg%scene%vary)) // ")"
            if (run%chain%gamma < 0.0_wp .or. run%chain%beta < 0.0_wp .or. .not. (gap_squared(run%chain) > 0.0_wp)) then
                call input_error(error, where, "scene", label // ": need gamma >= 0, beta >= 0 and V''(0) + m2 > 0")
                return
            end if
            if (.not. stable_by_paper_condition(run%chain, run%numerics%dt) .and. .not. cfg%allow_unstable &
                .and. .not. a_stable(run%numerics%method)) then
                call input_error(error, where, "scene", label // ": dt = " // real_str(run%numerics%dt) &
                                 // " violates the paper's necessary stability condition (it needs dt < " &
                                 // real_str(critical_dt(run%chain), 6) &
                                 // "; set allow_unstable = .true. to run anyway)")
                return
            end if
            if (scene%gap_rule() .and. run%drive%omega >= band_gap_edge(run%chain) .and. .not. cfg%allow_outside_gap) then
                call input_error(error, where, "scene", label // ": omega = " // real_str(run%drive%omega) &
                                 // " is outside its band gap 0 < Omega < " // fixed4(band_gap_edge(run%chain)) &
                                 // " (set allow_outside_gap = .true. to run anyway)")
                return
            end if
        end do
    end subroutine check_scene

    !> Lines to print before a run (and by `--check`), one per key given that the scene does not use: today
    !> `&drive omega` given to a scene over a frequency axis (map, bifurcation, continuation, hysteresis), which runs
    !> omega_min .. omega_max by omega_step instead. Empty when there is nothing to say.
    function input_warnings(cfg) result(lines)
        !> The validated configuration.
        type(input_config), intent(in) :: cfg
        character(len=:), allocatable :: lines(:)
        character(len=:), allocatable :: where, text
        integer :: n
        class(scene_type), allocatable :: scene
        type(error_type), allocatable :: error

        allocate (character(len=0) :: lines(0))
        where = "configuration"
        if (allocated(cfg%source)) then
            if (len(cfg%source) > 0) where = cfg%source
        end if
        call new_scene(trim(cfg%scene%kind), scene, error)
        if (allocated(error)) return
        if (scene%frequency_axis()) then
            if (.not. key_given(cfg, "drive", "omega") .or. .not. allocated(cfg%text)) return
            n = int(min((cfg%scene%omega_max - cfg%scene%omega_min)/cfg%scene%omega_step + 1.0e-9_wp, 1.0e7_wp)) + 1
            text = "warning: " // where // ": &drive: omega = " // real_str(cfg%run%drive%omega) // " is not used by " &
                   // "&scene kind = '" // trim(cfg%scene%kind) // "', which runs omega_min .. omega_max by omega_step (" &
                   // real_str(cfg%scene%omega_min) // " .. " // real_str(cfg%scene%omega_max) // " by " &
                   // real_str(cfg%scene%omega_step) // ": " // int_str(n) // trim(merge(" frequency  ", " frequencies", &
                   n == 1)) // "); set those for one frequency"
            deallocate (lines)
            allocate (character(len=len(text)) :: lines(1))
            lines(1) = text
        end if
    end function input_warnings

    !> Whether a potential of the run (&chain potential, or one of &scene potentials) takes the &chain key `key`.
    pure logical function run_takes(cfg, key) result(takes)
        !> The input.
        type(input_config), intent(in) :: cfg
        !> The key (e.g. 'eta').
        character(len=*), intent(in) :: key

        takes = potential_takes(cfg%run%chain%potential, key)
        if (allocated(cfg%scene%potentials)) takes = takes .or. any(potential_takes(cfg%scene%potentials, key))
    end function run_takes

    !> The names of the potentials that take the &chain key `key`, quoted and joined ("'a', 'b'").
    pure function takers(key) result(text)
        !> The key.
        character(len=*), intent(in) :: key
        character(len=:), allocatable :: text
        integer :: i

        text = ""
        do i = 1, size(potential_ids)
            if (.not. potential_takes(potential_ids(i), key)) cycle
            if (len(text) > 0) text = text // ", "
            text = text // "'" // trim(potential_names(i)) // "'"
        end do
    end function takers

    !> Whether the namelist text of `cfg` gives `group` `key` (true for a configuration built in code: no text).
    pure logical function key_given(cfg, group, key) result(given)
        !> The configuration.
        type(input_config), intent(in) :: cfg
        !> The key's group and name.
        character(len=*), intent(in) :: group, key
        type(parsed_input) :: parsed
        type(error_type), allocatable :: error
        integer :: ik

        given = .true.
        if (.not. allocated(cfg%text)) return
        if (len_trim(cfg%text) == 0) return
        call parse_namelist(cfg%text, "input", parsed, error)
        if (allocated(error)) return
        do ik = 1, size(key_table)
            if (trim(key_table(ik)%group) == group .and. trim(key_table(ik)%key) == key) then
                given = parsed%n_values(ik) > 0
                return
            end if
        end do
    end function key_given

    !> " (the default)" when `&scene` `key` is not given in the namelist text, else empty.
    pure function default_note(cfg, key) result(note)
        !> The configuration.
        type(input_config), intent(in) :: cfg
        !> The &scene key.
        character(len=*), intent(in) :: key
        character(len=:), allocatable :: note

        note = ""
        if (.not. key_given(cfg, "scene", key)) note = " (the default)"
    end function default_note

    !> Nothing may be at the output's path (a file, a link, a FIFO) unless `overwrite`.
    subroutine check_output_file(cfg, where, error)
        !> The configuration.
        type(input_config), intent(in) :: cfg
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Allocated when the check fails.
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: file

        file = trim(cfg%output%file)
        if (path_kind(file) == path_directory) then
            call input_error(error, where, "output", "file = '" // file // "' is a directory")
            return
        end if
        ! anything at that path counts (lstat): a FIFO, a device, a dangling symbolic link are not replaced either
        if (link_kind(file) /= path_missing .and. .not. cfg%output%overwrite) then
            call input_error(error, where, "output", "file '" // file // "' exists (set overwrite = .true. to replace it)")
        end if
    end subroutine check_output_file

    !> Whether a method is A-stable on the linear chain, so that the paper's necessary condition on dt (a bound of
    !> its explicit-in-V' scheme) does not apply: the energy-preserving Gauss collocation avf4/avf8. Its dt is
    !> limited by the convergence of its stage iteration instead, which a run reports as its status.
    pure logical function a_stable(method)
        !> The &numerics method (named constant of supratrans_config).
        integer, intent(in) :: method

        a_stable = method == method_avf4 .or. method == method_avf8
    end function a_stable

end module supratrans_validate
