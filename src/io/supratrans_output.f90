!> What every output file holds besides its scene's results: the root attributes (code, version, scene, input file,
!> creation time), `/provenance` (where the file comes from: the build, the compiler, the machine, the namelist text
!> as read) and `/parameters` (every input parameter, `write_parameters`). Each scene writes its own results beside
!> them (the timeseries: `supratrans_scene_timeseries`).
module supratrans_output
    use, intrinsic :: iso_fortran_env, only: compiler_version, compiler_options
    !$ use omp_lib, only: omp_get_max_threads
    use supratrans_kinds, only: wp, supratrans_version
    use supratrans_strings, only: text_or
    use supratrans_config, only: input_config
    use supratrans_invocation, only: invocation_type
    use supratrans_host, only: timestamp, build_commit, build_dirty, commit_source, host_name, executable_path, &
                               working_directory
    use supratrans_hdf5, only: h5_file, h5_write, h5_write_attr, h5_create_group
    use supratrans_parameters, only: write_parameters
    implicit none
    private

    public :: write_root, write_provenance, write_parameters

contains

    !> Root attributes shared by every scene (code, version, scene, description, input file, creation time) and the
    !> `/provenance` group.
    subroutine write_root(file, cfg, scene, description, inv)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Scene name.
        character(len=*), intent(in) :: scene
        !> One-line description of the file's contents.
        character(len=*), intent(in) :: description
        !> How the engine was invoked (a merge records its parts); default: computed here.
        type(invocation_type), intent(in), optional :: inv

        call h5_write_attr(file, "/", "code", "supratrans")
        call h5_write_attr(file, "/", "version", supratrans_version)
        call h5_write_attr(file, "/", "scene", scene)
        call h5_write_attr(file, "/", "description", description)
        call h5_write_attr(file, "/", "input_file", cfg%source)
        call h5_write_attr(file, "/", "created", timestamp())
        call h5_write_attr(file, "/", "reference", &
            "J. E. Macias-Diaz and A. Puri, An energy-based computational method in the analysis of the " // &
            "transmission of energy in a chain of coupled oscillators")
        call write_provenance(file, cfg, inv)
    end subroutine write_root

    !> Write `/provenance`: attributes `version`, `git_commit` and `git_dirty` (of the build: `build_commit`,
    !> `build_dirty`), `git_commit_source` (fixed at build or read at run time: `commit_source`), `compiler`,
    !> `compiler_options`, `omp_max_threads`, `host`, `executable`, `working_directory`, `started`, `input_file`,
    !> and the dataset `/provenance/namelist`, the input file's text exactly as read.
    subroutine write_provenance(file, cfg, inv)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The input (its source, text and start time).
        type(input_config), intent(in) :: cfg
        !> How the engine was invoked: a merge records its parts (default: computed here).
        type(invocation_type), intent(in), optional :: inv
        character(len=*), parameter :: g = "/provenance"
        integer :: threads

        threads = 1
        !$ threads = omp_get_max_threads()
        call h5_create_group(file, g, "Where this file comes from: code, build, machine, input")
        call h5_write_attr(file, g, "version", supratrans_version)
        call h5_write_attr(file, g, "git_commit", build_commit())
        call h5_write_attr(file, g, "git_dirty", build_dirty())
        call h5_write_attr(file, g, "git_commit_source", commit_source())
        call h5_write_attr(file, g, "compiler", compiler_version())
        call h5_write_attr(file, g, "compiler_options", compiler_options())
        call h5_write_attr(file, g, "omp_max_threads", threads)
        call h5_write_attr(file, g, "host", host_name())
        call h5_write_attr(file, g, "executable", executable_path())
        call h5_write_attr(file, g, "working_directory", working_directory())
        call h5_write_attr(file, g, "started", text_or(cfg%started, "unknown"))
        call h5_write_attr(file, g, "input_file", text_or(cfg%source, "unknown"))
        call h5_write(file, g // "/namelist", text_or(cfg%text, ""), "1", "The namelist file exactly as " &
            // "read (empty for a configuration built in code)")
        if (.not. present(inv)) return
        if (allocated(inv%merge_record)) then
            ! a merged file: where, when and how long each slice ran (its part file's record)
            call h5_write(file, g // "/parts", inv%merge_record, "1", "Merged from part files, one line per part, " &
                // "tab-separated: slice, host, start, end, wall time (s), OpenMP threads, git commit")
            call h5_write_attr(file, g, "slices_wall_time_s", max(inv%merge_wall_time, 0.0_wp))
        end if
    end subroutine write_provenance

end module supratrans_output
