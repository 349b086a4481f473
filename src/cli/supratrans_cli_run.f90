!> The run command (`supratrans FILE.nml [--slice I/N [--costs EARLIER.h5]]`, `supratrans_cli`): read the namelist,
!> make its scene, for a slice name its part file (or find it complete already), recognise an output a stopped run
!> finished already, validate, check the output's location and run the scene under the output's lock
!> (`supratrans_cli_output`).
module supratrans_cli_run
    use, intrinsic :: iso_fortran_env, only: error_unit
    use supratrans_strings, only: int_str, printable, text_fingerprint
    use supratrans_error, only: error_type, fatal_error, err_input, err_io
    use supratrans_config, only: input_config
    use supratrans_invocation, only: invocation_type
    use supratrans_progress, only: progress_every_setting
    use supratrans_system, only: path_kind, path_missing, remove_own_file, unlock_file, link_kind, path_regular, not_own_file
    use supratrans_hdf5, only: h5_file, h5_open, h5_close, h5_read, h5_read_attr, h5_attr_exists
    use supratrans_input, only: read_input
    use supratrans_validate, only: validate_config, input_warnings
    use supratrans_parts, only: part_set, read_parts, part_path
    use supratrans_scene, only: scene_type, new_scene
    use supratrans_cli_output, only: check_output_location, take_lock, with_lock, progress
    implicit none
    private

    public :: run_from_file, parse_slice

contains

    !> Run the study described by namelist file `path` (or slice `slice_index` of `slice_count` of it). Returns exit
    !> status 0 on success; otherwise the error's status (2 for bad input) and `error` holds the one-line message.
    subroutine run_from_file(path, status, error, slice_index, slice_count, costs)
        !> Namelist file.
        character(len=*), intent(in) :: path
        !> Exit status for the program.
        integer, intent(out) :: status
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Run only slice `slice_index` of `slice_count` (default: the whole scene).
        integer, intent(in), optional :: slice_index, slice_count
        !> With a slice: deal the slices by the task costs measured in this earlier output (`--costs`).
        character(len=*), intent(in), optional :: costs
        type(input_config) :: cfg
        type(invocation_type) :: inv
        type(part_set) :: done_part
        type(error_type), allocatable :: cause
        class(scene_type), allocatable :: scene
        character(len=:), allocatable :: warnings(:)
        integer :: i

        status = 0
        call read_input(path, cfg, error, check_output=.false.)
        inv%progress_every = progress_every_setting()     ! SUPRATRANS_PROGRESS_EVERY, read once, with the input
        if (.not. allocated(error)) call new_scene(trim(cfg%scene%kind), scene, error)
        if (allocated(error)) then
            status = error%stat
            return
        end if
        if (present(slice_index) .and. present(slice_count)) then
            if (slice_count > 0) then
                if (scene%one_run()) then
                    call fatal_error(error, path // ": &scene kind = '" // trim(cfg%scene%kind) // "' is one run: " &
                                     // "--slice applies to amplitude_sweep, map, bifurcation, work_precision and " &
                                     // "stability", err_input)
                    status = error%stat
                    return
                end if
                if (.not. cfg%output%overwrite .and. path_kind(trim(cfg%output%file)) /= path_missing) then
                    ! the merge would refuse it at the end: refused before the slice's work
                    call fatal_error(error, trim(cfg%output%file) // ": output file exists (set overwrite = .true. " &
                                     // "to replace it): the merge of the slices would be refused", err_input)
                    status = error%stat
                    return
                end if
                inv%slice_index = slice_index
                inv%slice_count = slice_count
                if (present(costs)) inv%slice_costs = costs
                cfg%output%file = part_path(trim(cfg%output%file), slice_index, slice_count)
                if (path_kind(trim(cfg%output%file)) /= path_missing) then
                    ! a part found under the slice's name is trusted as done only if it is this user's own file
                    if (len(not_own_file(trim(cfg%output%file))) > 0) then
                        call fatal_error(error, trim(cfg%output%file) // ": " // not_own_file(trim(cfg%output%file)), &
                                         err_io)
                        status = error%stat
                        return
                    end if
                    call read_parts([character(len=len_trim(cfg%output%file)) :: trim(cfg%output%file)], .true., &
                                    done_part, cause)
                    if (.not. allocated(cause)) then
                        if (done_part%fingerprint == cfg%fingerprint) then
                            call progress(cfg, "supratrans: " // trim(cfg%output%file) // " is complete already " &
                                          // "(slice " // int_str(slice_index) // "/" // int_str(slice_count) // ")")
                            call clean_finished(cfg, status, error)
                            return
                        end if
                    end if
                end if
            end if
        end if
        if (finished_by_earlier_run(cfg)) then
            call progress(cfg, "supratrans: " // trim(cfg%output%file) // " is complete already (written from this " &
                          // "input by a run stopped before it deleted its journal)")
            call clean_finished(cfg, status, error)
            return
        end if
        call validate_config(cfg, error)
        if (.not. allocated(error)) call check_output_location(cfg, error)
        if (allocated(error)) then
            status = error%stat
            return
        end if
        warnings = input_warnings(cfg)   ! what --check says too (a key the scene does not use)
        do i = 1, size(warnings)
            write (error_unit, "(a)") printable(trim(warnings(i)))
        end do
        call with_lock(cfg, inv, status, error)
    end subroutine run_from_file

    !> Read "I/N" with 1 <= I <= N <= 100000, both decimal numbers without leading zeros ("08/09" is refused: a
    !> shell or a script could read it as octal).
    subroutine parse_slice(text, slice_index, slice_count, error)
        !> The argument of --slice.
        character(len=*), intent(in) :: text
        !> Slice I.
        integer, intent(out) :: slice_index
        !> Number of slices N.
        integer, intent(out) :: slice_count
        !> Error, allocated when the text is not I/N.
        type(error_type), allocatable, intent(out) :: error
        integer :: k, ios1, ios2

        slice_index = 0
        slice_count = 0
        k = index(text, "/")
        ios1 = 1
        ios2 = 1
        ! exactly one '/' (list-directed input would read "3/3" as 3: a '/' ends its list)
        if (k > 1 .and. k < len(text) .and. verify(text, "0123456789/") == 0 .and. len(text) <= 13 &
            .and. index(text(k + 1:), "/") == 0 .and. text(1:1) /= "0" .and. text(k + 1:k + 1) /= "0") then
            read (text(1:k - 1), *, iostat=ios1) slice_index
            read (text(k + 1:), *, iostat=ios2) slice_count
        end if
        if (ios1 /= 0 .or. ios2 /= 0 .or. slice_count < 1 .or. slice_count > 100000 .or. slice_index < 1 &
            .or. slice_index > slice_count) then
            call fatal_error(error, "--slice " // printable(text) // ": expected I/N with 1 <= I <= N <= 100000, " &
                             // "decimal without leading zeros, e.g. --slice 3/16", err_input)
        end if
    end subroutine parse_slice

    !> Whether the output is the finished result of this very input while its journal is still there (a run killed
    !> after it renamed its output into place and before it deleted the journal): the output is a regular HDF5 file
    !> whose `/provenance/namelist` has this input's fingerprint and that is not marked `complete = 0`, and the
    !> journal's header names this input's fingerprint. Without `overwrite` only (with it, the run starts afresh).
    function finished_by_earlier_run(cfg) result(yes)
        !> The input read.
        type(input_config), intent(in) :: cfg
        logical :: yes
        character(len=:), allocatable :: file, text, header
        type(h5_file) :: h5
        type(error_type), allocatable :: cause
        integer :: complete, unit, ios
        character(len=4096) :: line

        yes = .false.
        file = trim(cfg%output%file)
        if (cfg%output%overwrite .or. .not. allocated(cfg%fingerprint)) return
        if (link_kind(file) /= path_regular .or. link_kind(file // ".journal") /= path_regular) return
        open (newunit=unit, file=file // ".journal", status="old", action="read", iostat=ios)
        if (ios /= 0) return
        line = ""
        read (unit, "(a)", iostat=ios) line
        close (unit)
        header = trim(line) // " "
        if (ios /= 0 .or. index(header, "supratrans-journal ") /= 1) return
        if (index(header, " " // cfg%fingerprint // " ") == 0) return
        call h5_open(h5, file, cause)
        if (allocated(cause)) return
        call h5_read(h5, "provenance/namelist", text, cause)
        if (.not. allocated(cause)) then
            yes = text_fingerprint(text) == cfg%fingerprint
            if (yes .and. h5_attr_exists(h5, "/", "complete")) then
                call h5_read_attr(h5, "/", "complete", complete, cause)
                yes = .not. allocated(cause)
                if (yes) yes = complete /= 0
            end if
        end if
        call h5_close(h5, cause)
    end function finished_by_earlier_run

    !> Under the output's lock, delete what a run stopped after finishing left beside its output: the journal and
    !> the partial snapshot (regular files only), with a line saying so.
    subroutine clean_finished(cfg, status, error)
        !> The input.
        type(input_config), intent(in) :: cfg
        !> Exit status (0, or that of the lock's error).
        integer, intent(out) :: status
        !> Error, allocated when the lock cannot be had.
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: file
        integer :: handle, i
        character(len=*), parameter :: stale(2) = [character(len=11) :: ".journal", ".partial.h5"]

        status = 0
        file = trim(cfg%output%file)
        if (all([(link_kind(file // trim(stale(i))) /= path_regular, i = 1, size(stale))])) return
        call take_lock(cfg, handle, error)
        if (allocated(error)) then
            status = error%stat
            return
        end if
        do i = 1, size(stale)
            if (link_kind(file // trim(stale(i))) /= path_regular) cycle
            call remove_own_file(file // trim(stale(i)))
            call progress(cfg, "  deleted the stale " // file // trim(stale(i)) // " left by that run")
        end do
        call unlock_file(handle, file // ".lock")
    end subroutine clean_finished

end module supratrans_cli_run
