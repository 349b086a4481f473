!> The command line: `supratrans <file.nml>` reads and validates the namelist, runs its scene and writes the
!> output. Everything is returned as a status and a message, so that tests can drive it like the program does.
module supratrans_cli
    use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
    use supratrans_kinds, only: wp, supratrans_version
    use supratrans_strings, only: real_str
    use supratrans_error, only: error_type, fatal_error, err_input, err_io
    use supratrans_config, only: input_config
    use supratrans_system, only: make_directories
    use supratrans_input, only: read_input
    use supratrans_simulate, only: simulate
    use supratrans_result, only: run_result, status_name
    use supratrans_output, only: write_timeseries
    use supratrans_scene_sweep, only: run_amplitude_sweep
    use supratrans_scene_map, only: run_map
    use supratrans_scene_bifurcation, only: run_bifurcation
    use supratrans_scene_workprec, only: run_work_precision
    use supratrans_scene_stability, only: run_stability
    implicit none
    private

    public :: run_from_file, usage

    !> Usage text of the program.
    character(len=*), parameter :: usage = "usage: supratrans <input.nml>   (see README.md; input/ holds examples)"

contains

    !> Run the study described by namelist file `path`. Returns exit status 0 on success; otherwise the error's
    !> status (2 for bad input) and `error` holds the one-line message.
    subroutine run_from_file(path, status, error)
        !> Namelist file.
        character(len=*), intent(in) :: path
        !> Exit status for the program.
        integer, intent(out) :: status
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        type(input_config) :: cfg
        type(run_result) :: result

        status = 0
        call read_input(path, cfg, error)
        if (allocated(error)) then
            status = error%stat
            return
        end if
        call ensure_parent_directory(trim(cfg%output%file), error)
        if (allocated(error)) then
            status = error%stat
            return
        end if
        select case (trim(cfg%scene%kind))
        case ("timeseries")
            call progress(cfg, "supratrans " // supratrans_version // ": timeseries from " // path)
            call simulate(cfg%run, result)
            call progress(cfg, "  run ended: " // status_name(result%status) // " " // result%reason)
            call progress(cfg, "  verdict: " // trim(merge("transmitting    ", "not transmitting", result%transmitting)) &
                          // " (" // result%verdict_reason // "); energy injected " // real_str(result%ledger%injected, 6))
            call write_timeseries(cfg, result, error)
        case ("amplitude_sweep")
            call run_amplitude_sweep(cfg, error)
        case ("map")
            call run_map(cfg, error)
        case ("bifurcation")
            call run_bifurcation(cfg, error)
        case ("work_precision")
            call run_work_precision(cfg, error)
        case ("stability")
            call run_stability(cfg, error)
        case default
            call fatal_error(error, path // ": &scene: kind '" // trim(cfg%scene%kind) // "' is not implemented", err_input)
        end select
        if (allocated(error)) then
            status = error%stat
            return
        end if
        call progress(cfg, "  wrote " // trim(cfg%output%file))
    end subroutine run_from_file

    !> Create the directory part of an output path if it does not exist (like `mkdir -p`, through mkdir(2): no shell).
    subroutine ensure_parent_directory(file, error)
        !> Output file path.
        character(len=*), intent(in) :: file
        !> Error, allocated if the directory cannot be created.
        type(error_type), allocatable, intent(out) :: error
        type(error_type), allocatable :: cause
        integer :: k

        k = index(file, "/", back=.true.)
        if (k <= 1) return
        call make_directories(file(1:k - 1), cause)
        if (allocated(cause)) call fatal_error(error, file // ": " // cause%message, err_io)
    end subroutine ensure_parent_directory

    !> Print a progress line on stderr unless the output asks for quiet.
    subroutine progress(cfg, line)
        !> Input (for the quiet flag).
        type(input_config), intent(in) :: cfg
        !> Text.
        character(len=*), intent(in) :: line

        if (.not. cfg%output%quiet) write (error_unit, '(a)') line
    end subroutine progress

end module supratrans_cli
