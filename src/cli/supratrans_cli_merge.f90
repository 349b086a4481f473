!> The merge command (`supratrans merge ...`, `supratrans_cli`): the part files of a scene's slices (named, or
!> those of slices 1..N of a namelist's output) read and checked against their namelist, and joined into the scene's
!> output by the scene itself, under the output's lock (`supratrans_cli_output`). A signal from its start stops it
!> with nothing written, unless it is writing the merged output already (then it finishes).
module supratrans_cli_merge
    use supratrans_strings, only: int_str, printable
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_config, only: input_config
    use supratrans_invocation, only: invocation_type
    use supratrans_progress, only: progress_every_setting
    use supratrans_system, only: path_kind, path_missing, stop_signal
    use supratrans_input, only: read_input, read_input_text
    use supratrans_validate, only: validate_config
    use supratrans_parts, only: part_set, read_parts, part_path, merged_path
    use supratrans_cli_run, only: parse_slice
    use supratrans_cli_output, only: check_output_location, with_lock, merge_stopped, progress
    implicit none
    private

    public :: merge_command

contains

    !> `supratrans merge [--partial] [-o OUT] [--overwrite] PART...` and `supratrans merge --slices N FILE.nml`: the
    !> options read, the part files named (or those of slices 1..N of the namelist's output) joined into the scene's
    !> output (`merge_parts`).
    subroutine merge_command(args, status, error)
        !> The arguments (the first is `merge`).
        character(len=*), intent(in) :: args(:)
        !> Exit status.
        integer, intent(out) :: status
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: output, parts(:)
        integer :: i, slice_index, slice_count, nparts
        logical :: partial, overwrite

        status = 0
        partial = .false.
        overwrite = .false.
        output = ""
        nparts = 0
        slice_count = 0
        allocate (character(len=len(args)) :: parts(size(args)))
        i = 2
        do while (i <= size(args))
            select case (trim(args(i)))
            case ("--partial")
                partial = .true.
            case ("--overwrite")
                overwrite = .true.
            case ("--slices")
                if (i == size(args)) then
                    call fail("merge: --slices needs the number of slices N")
                    return
                end if
                i = i + 1
                call parse_slice("1/" // trim(args(i)), slice_index, slice_count, error)
                if (allocated(error)) then
                    call fail("merge: --slices " // printable(trim(args(i))) // ": expected a number of slices " &
                              // "from 1 to 100000")
                    return
                end if
            case ("-o")
                if (i == size(args)) then
                    call fail("merge: -o needs a file name")
                    return
                end if
                i = i + 1
                output = trim(args(i))
            case default
                if (args(i)(1:1) == "-") then
                    call fail("merge: unknown option '" // printable(trim(args(i))) // "' (see supratrans --help)")
                    return
                end if
                nparts = nparts + 1
                parts(nparts) = args(i)
            end select
            i = i + 1
        end do
        if (nparts == 0) then
            call fail("merge: no part files given (supratrans merge out/x.part-*.h5)")
            return
        end if
        if (slice_count > 0) then
            ! merge --slices N FILE.nml: the parts of that namelist's output
            if (nparts /= 1) then
                call fail("merge --slices N takes one namelist file")
                return
            end if
            call parts_of_namelist(trim(parts(1)), slice_count, partial, parts, error)
            if (allocated(error)) then
                status = error%stat
                return
            end if
            nparts = size(parts)
        end if
        call merge_parts(parts(1:nparts), partial, output, overwrite, status, error)

    contains

        subroutine fail(message)
            character(len=*), intent(in) :: message

            call fatal_error(error, message, err_input)
            status = err_input
        end subroutine fail

    end subroutine merge_command

    !> The part files of slices 1..N of the output a namelist names. Those missing are named all at once (with the
    !> `--slice I/N` that makes each); with `partial`, they are left out (an error only when none is there).
    subroutine parts_of_namelist(path, slice_count, partial, parts, error)
        !> Namelist file.
        character(len=*), intent(in) :: path
        !> Number of slices N.
        integer, intent(in) :: slice_count
        !> Leave the missing parts out (merge --partial).
        logical, intent(in) :: partial
        !> The part files.
        character(len=:), allocatable, intent(out) :: parts(:)
        !> Error, allocated when the namelist cannot be read or parts are missing.
        type(error_type), allocatable, intent(out) :: error
        type(input_config) :: cfg
        character(len=:), allocatable :: missing, first, kept(:)
        logical, allocatable :: there(:)
        integer :: i, nmissing

        call read_input(path, cfg, error, check_output=.false.)
        if (allocated(error)) return
        allocate (character(len=len_trim(cfg%output%file) + 32) :: parts(slice_count))
        allocate (there(slice_count))
        missing = ""
        nmissing = 0
        do i = 1, slice_count
            parts(i) = part_path(trim(cfg%output%file), i, slice_count)
            there(i) = path_kind(trim(parts(i))) /= path_missing
            if (.not. there(i)) then
                nmissing = nmissing + 1
                if (nmissing == 1) first = trim(parts(i))
                if (nmissing <= 20) missing = missing // merge(", ", "  ", nmissing > 1) // int_str(i)
            end if
        end do
        if (nmissing > 20) missing = missing // ", ... (" // int_str(nmissing) // " in all)"
        if (nmissing == slice_count) then
            call fatal_error(error, "merge: no part of " // path // " is there (" // first // " and the other " &
                             // int_str(slice_count - 1) // "): run its slices first (--slice I/" &
                             // int_str(slice_count) // ")", err_input)
        else if (nmissing > 0 .and. .not. partial) then
            call fatal_error(error, "merge: " // int_str(nmissing) // " of " // int_str(slice_count) // " parts of " &
                             // path // " missing: slice(s) " // missing(3:) // " (e.g. " // first // "); run each" &
                             // " with --slice I/" // int_str(slice_count) // ", or merge --partial to look at " &
                             // "what is there", err_input)
        else if (nmissing > 0) then
            ! (a loop: gfortran's pack of a deferred-length character array loses the strings)
            allocate (character(len=len(parts)) :: kept(slice_count - nmissing))
            nmissing = 0
            do i = 1, slice_count
                if (.not. there(i)) cycle
                nmissing = nmissing + 1
                kept(nmissing) = parts(i)
            end do
            call move_alloc(kept, parts)
        end if
    end subroutine parts_of_namelist

    !> Join part files into the scene's output (see `supratrans_parts`).
    subroutine merge_parts(paths, partial, output, overwrite, status, error)
        !> The part files.
        character(len=*), intent(in) :: paths(:)
        !> Accept missing slices and write a partial snapshot.
        logical, intent(in) :: partial
        !> Output file ("" for the parts' own name).
        character(len=*), intent(in) :: output
        !> Replace an existing output.
        logical, intent(in) :: overwrite
        !> Exit status.
        integer, intent(out) :: status
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        type(part_set) :: set
        type(input_config) :: cfg
        type(invocation_type) :: inv

        status = 0
        ! the stop signals are caught from the program's start (supratrans_os.c, before main): a merge stopped by a
        ! signal ends with status 5 and writes nothing (the parts stay, the same command merges them again); once the
        ! output is being written, the merge finishes it instead
        call read_parts(paths, partial, set, error)
        if (.not. allocated(error)) call read_input_text(set%text, set%source, cfg, error, check_output=.false.)
        if (allocated(error)) then
            status = error%stat
            return
        end if
        if (cfg%fingerprint /= set%fingerprint) then
            call fatal_error(error, set%first // ": its namelist text has the fingerprint " // cfg%fingerprint &
                             // ", not the " // set%fingerprint // " the part was made for (edited?)", err_input)
            status = error%stat
            return
        end if
        inv%merge_part = set%first
        inv%progress_every = progress_every_setting()     ! SUPRATRANS_PROGRESS_EVERY, read once, with the input
        inv%merge_record = set%record
        inv%merge_wall_time = set%wall_time
        cfg%output%file = output
        if (len(output) == 0) cfg%output%file = merged_path(trim(paths(1)))
        if (overwrite) cfg%output%overwrite = .true.
        inv%snapshot_only = partial
        if (.not. partial) call validate_config(cfg, error)
        if (.not. allocated(error)) call check_output_location(cfg, error)
        if (allocated(error)) then
            status = error%stat
            return
        end if
        if (stop_signal() /= 0) then
            call merge_stopped(error)
            status = error%stat
            return
        end if
        call progress(cfg, "supratrans merge: " // int_str(count(set%done)) // " of " // int_str(size(set%done)) &
                      // " tasks from " // int_str(size(paths)) // " part(s) of " // int_str(set%slice_count) &
                      // " -> " // trim(cfg%output%file) // trim(merge(".partial.h5", "           ", partial)))
        call with_lock(cfg, inv, status, error, set)
    end subroutine merge_parts

end module supratrans_cli_merge
