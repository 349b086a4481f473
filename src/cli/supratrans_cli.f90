!> The command line: what `app/main.f90` calls. Everything is returned as a status and a message, so that tests can
!> drive it like the program does.
!>
!>     supratrans FILE.nml                  run the study a namelist describes, write its HDF5 output
!>     supratrans FILE.nml --slice I/N      run slice I of N of the scene's tasks, write a part file
!>     supratrans FILE.nml --slice I/N --costs EARLIER.h5   the same, slices dealt by the costs measured there
!>     supratrans merge [--partial] [-o OUT] [--overwrite] PART...   join part files into the scene's output
!>     supratrans --check FILE.nml          read and validate only
!>     supratrans --help | --version
!>
!> Before any work starts the output location is checked: a file name (no NUL, no trailing '/', short enough for the
!> temporary and journal names made from it), not a directory, not a symbolic link, FIFO or device, not the input
!> file itself, its directory made (mkdir(2), never a shell). Then the advisory lock `<output>.lock` is taken before
!> any file of the output is touched (scene, slice, merge and merge --partial alike): it keeps a second instance off
!> the same output while the first runs. The lock file is never deleted (an empty file; deleting a held lock file
!> would let a second instance lock a new file of the same name). On a file system that refuses locks (NFS without a
!> lock manager, Lustre without `-o flock`) the run stops and says so; `SUPRATRANS_NO_LOCK=1` runs without the lock
!> (and without HDF5's own file locking) for whoever is sure no two runs write one output. SIGTERM, SIGINT and
!> SIGUSR1 stop a scene cleanly (exit status 5): the tasks running finish and are journaled (a threshold search, or
!> the run of a sweep, map or hysteresis task, with `checkpoint_every` > 0 writes its mid-run checkpoint instead and
!> stops at once), a snapshot is written,
!> and the same command resumes. A timeseries (one run, no journal) stops within a time step and writes no output,
!> only its mid-run checkpoint (`supratrans_checkpoint`, unless `checkpoint_every` = 0), from which it resumes; a
!> merge catches them from its start and stops, writing nothing, unless it is writing the merged output already
!> (then it finishes). `--check` also asks access(2) whether the output's directory can be written.
module supratrans_cli
    use, intrinsic :: iso_fortran_env, only: error_unit, output_unit, int64
    use supratrans_kinds, only: wp, supratrans_version
    use supratrans_strings, only: int_str, printable, text_fingerprint
    use supratrans_error, only: error_type, fatal_error, err_input, err_io, err_interrupted
    use supratrans_config, only: input_config
    use supratrans_invocation, only: invocation_type
    use, intrinsic :: iso_c_binding, only: c_null_char
    use supratrans_system, only: make_directories, path_kind, path_directory, path_missing, same_file, lock_file, &
                                 unlock_file, remove_file, catch_stop_signals, link_kind, path_link, path_special, &
                                 lock_busy, lock_unsupported, remove_stale_temporaries, disable_hdf5_locking, &
                                 temp_extra, path_regular, ignore_file_size_signal, directory_writable, stop_signal
    use supratrans_hdf5, only: h5_file, h5_open, h5_close, h5_read, h5_read_attr, h5_attr_exists
    use supratrans_input, only: read_input, read_input_text
    use supratrans_validate, only: validate_config
    use supratrans_limits, only: bound_threads, run_memory_bytes
    use supratrans_journal, only: write_journal
    use supratrans_parts, only: part_set, read_parts, part_path, merged_path
    use supratrans_scene, only: scene_type, new_scene
    implicit none
    private

    public :: run_command, run_from_file, usage, printable

    !> Usage text of the program.
    character(len=*), parameter :: usage = "usage: supratrans FILE.nml [--slice I/N [--costs FILE]] | supratrans merge " &
        // "[--partial] " &
        // "[-o OUT] [--overwrite] PART... | supratrans merge --slices N FILE.nml | supratrans --check FILE.nml | " &
        // "supratrans --help | supratrans --version"

    !> The longer help of `--help`.
    character(len=*), parameter :: help_text = usage // new_line("a") // new_line("a") // &
        "  FILE.nml              run the study the namelist describes (input/ holds one per paper figure)" &
        // new_line("a") // &
        "  --slice I/N           run only slice I of N of the scene's tasks (largest-first by cost), write" // new_line("a") // &
        "                        <output stem>.part-I-of-N.h5; for Slurm job arrays (input/slurm/)" // new_line("a") // &
        "    --costs FILE        deal the slices by the task costs measured in FILE, an earlier output of" // new_line("a") // &
        "                        the same study (bifurcation: /cost/wall_time), not by the estimate" // new_line("a") // &
        "  merge PART...         join the part files of every slice into the scene's ordinary output" // new_line("a") // &
        "    --partial           accept missing slices: write <output>.partial.h5 from what is there" // new_line("a") // &
        "    -o OUT              output file (default: the parts' name without .part-I-of-N)" // new_line("a") // &
        "    --overwrite         replace an existing output file" // new_line("a") // &
        "    --slices N FILE.nml the parts of slices 1..N of that namelist's output" // new_line("a") // &
        "  --check FILE.nml...   read and validate namelists only (exit 0 if they would run; one file: its" &
        // new_line("a") // "                        output, overwrite and memory estimate on stdout, one 'key value' a" &
        // new_line("a") // "                        line; several: one line each, the worst status)" // new_line("a") // &
        "  --version             print the version" // new_line("a") // new_line("a") // &
        "Exit status: 0 success, 2 bad input or command line, 3 a run failed fatally, 4 output not written," &
        // new_line("a") // "5 stopped by a signal (run the same command again to resume)." // new_line("a") &
        // new_line("a") // "Environment: SUPRATRANS_NO_LOCK=1 runs without the output's lock, for file systems that " &
        // "refuse locks" // new_line("a") // "(NFS without a lock manager): then make sure no two runs write one output."

contains

    !> Run the command line `args` (without the program name): the status is the program's exit status, `error`
    !> its one-line message; `text` is what goes to standard output (help, version).
    subroutine run_command(args, status, error, text)
        !> The arguments.
        character(len=*), intent(in) :: args(:)
        !> Exit status.
        integer, intent(out) :: status
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Text for standard output (empty unless help or version).
        character(len=:), allocatable, intent(out) :: text
        character(len=:), allocatable :: file, output, parts(:), costs
        integer :: i, slice_index, slice_count, nparts, nchecked, worst
        logical :: check_only, partial, overwrite

        status = 0
        text = ""
        call ignore_file_size_signal()
        if (size(args) == 0) then
            call fail(usage)
            return
        end if
        select case (trim(args(1)))
        case ("--help", "-h")
            text = help_text
            return
        case ("--version", "-V")
            text = "supratrans " // supratrans_version
            return
        case default
            continue
        end select
        ! every command that may run something: at most max_threads_per_cpu threads a processor, said in one line
        call bound_threads(text)
        if (len(text) > 0) write (error_unit, "(a)") text
        text = ""
        select case (trim(args(1)))
        case ("merge")
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
            return
        case default
            continue    ! a namelist and its options, below
        end select

        file = ""
        nchecked = 0
        worst = 0
        check_only = .false.
        slice_index = 0
        slice_count = 0
        i = 1
        do while (i <= size(args))
            select case (trim(args(i)))
            case ("--check")
                check_only = .true.
            case ("--costs")
                if (i == size(args)) then
                    call fail("--costs needs a file, an earlier output of the same study")
                    return
                end if
                i = i + 1
                costs = trim(args(i))
            case ("--slice")
                if (i == size(args)) then
                    call fail("--slice needs I/N, e.g. --slice 3/16")
                    return
                end if
                i = i + 1
                call parse_slice(trim(args(i)), slice_index, slice_count, error)
                if (allocated(error)) then
                    status = error%stat
                    return
                end if
            case default
                if (args(i)(1:1) == "-" .and. len_trim(args(i)) > 1) then
                    call fail("unknown option '" // printable(trim(args(i))) // "' (see supratrans --help)")
                    return
                end if
                if (len(file) > 0 .and. .not. check_only) then
                    call fail("one namelist file at a time ('" // printable(file) // "' and '" &
                              // printable(trim(args(i))) // "'); see supratrans --help")
                    return
                end if
                if (len(file) > 0) then
                    ! --check FILE FILE ...: one line per file on standard output, the worst status
                    if (nchecked == 0) call check_one(file)
                    call check_one(trim(args(i)))
                    file = trim(args(i))
                    nchecked = nchecked + 1
                else
                    file = trim(args(i))
                end if
            end select
            i = i + 1
        end do
        if (len(file) == 0) then
            call fail(usage)
            return
        end if
        if (check_only .and. nchecked > 0) then
            status = worst
        else if (check_only) then
            call check_file(file, status, error, report=.true.)
        else if (allocated(costs) .and. slice_count == 0) then
            call fail("--costs applies with --slice I/N (it deals the slices)")
        else
            call run_from_file(file, status, error, slice_index, slice_count, costs)
        end if

    contains

        !> --check of one of several files: "ok FILE" or "error STATUS FILE: MESSAGE" on standard output.
        subroutine check_one(path)
            character(len=*), intent(in) :: path
            type(error_type), allocatable :: problem
            integer :: one

            call check_file(path, one, problem)
            if (allocated(problem)) then
                write (output_unit, "(a)") "error " // int_str(one) // " " // printable(path) // ": " &
                    // printable(problem%message)
            else
                write (output_unit, "(a)") "ok " // printable(path)
            end if
            worst = max(worst, one)
        end subroutine check_one

        subroutine fail(message)
            character(len=*), intent(in) :: message

            call fatal_error(error, message, err_input)
            status = err_input
        end subroutine fail

    end subroutine run_command

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

    !> Read "I/N" with 1 <= I <= N <= 100000.
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
            .and. index(text(k + 1:), "/") == 0) then
            read (text(1:k - 1), *, iostat=ios1) slice_index
            read (text(k + 1:), *, iostat=ios2) slice_count
        end if
        if (ios1 /= 0 .or. ios2 /= 0 .or. slice_count < 1 .or. slice_count > 100000 .or. slice_index < 1 &
            .or. slice_index > slice_count) then
            call fatal_error(error, "--slice " // printable(text) // ": expected I/N with 1 <= I <= N <= 100000, " &
                             // "e.g. --slice 3/16", err_input)
        end if
    end subroutine parse_slice

    !> `--check`: read and validate the namelist (output location included), run nothing, write nothing.
    subroutine check_file(path, status, error, report)
        !> Namelist file.
        character(len=*), intent(in) :: path
        !> Exit status.
        integer, intent(out) :: status
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Print the output, overwrite and memory estimate (`check_report`) when the file is fine; default false.
        logical, intent(in), optional :: report
        type(input_config) :: cfg

        status = 0
        call read_input(path, cfg, error)
        if (.not. allocated(error)) call check_output_location(cfg, error, create=.false.)
        if (.not. allocated(error)) call check_output_writable(cfg, error)
        if (allocated(error)) status = error%stat
        if (.not. allocated(error) .and. present(report)) then
            if (report) call check_report(cfg)
        end if
    end subroutine check_file

    !> What `--check` of one file says on stdout, one "key value" a line, for scripts (input/slurm/submit.sh): the
    !> output file (`output`), whether an existing one is replaced (`overwrite` 1/0), the scene (`scene`) and the
    !> memory one run needs (`memory_per_thread_bytes`: its state, and for a timeseries its records; a scene's
    !> threads each hold one run; with checkpoints on, the checkpoint's buffers too, `checkpoint_bytes`).
    subroutine check_report(cfg)
        !> The validated input.
        type(input_config), intent(in) :: cfg
        real(wp) :: bytes, checkpoint
        class(scene_type), allocatable :: scene
        type(error_type), allocatable :: error
        logical :: one_run

        one_run = .false.
        call new_scene(trim(cfg%scene%kind), scene, error)   ! validated: the kind is known
        if (.not. allocated(error)) one_run = scene%one_run()
        bytes = run_memory_bytes(cfg, one_run)   ! one run (a timeseries) holds its records too
        ! a mid-run checkpoint assembles the run's state (its levels and records, at most what the run holds) in one
        ! buffer and then the file's bytes in a second (supratrans_checkpoint); a resume reads it back the same way
        checkpoint = 0.0_wp
        if (cfg%output%checkpoint_every > 0.0_wp) checkpoint = 2.0_wp*bytes
        write (output_unit, "(a)") "output " // printable(trim(cfg%output%file))
        write (output_unit, "(a, i0)") "overwrite ", merge(1, 0, cfg%output%overwrite)
        write (output_unit, "(a)") "scene " // trim(cfg%scene%kind)
        write (output_unit, "(a, i0)") "memory_per_thread_bytes ", nint(min(bytes + checkpoint, 9.0e18_wp), int64)
        write (output_unit, "(a, i0)") "checkpoint_bytes ", nint(min(checkpoint, 9.0e18_wp), int64)
    end subroutine check_report

    !> `--check`: whether the output could be created where it is named: the nearest directory of its path that
    !> exists (the others would be made in it) must let this process create files, asked with access(2) W_OK | X_OK,
    !> which also sees a read-only mount. Nothing is created. Status 4 (as the run itself would end) when not.
    subroutine check_output_writable(cfg, error)
        !> The input.
        type(input_config), intent(in) :: cfg
        !> Error (status 4), allocated when the directory cannot be written.
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: file, dir, reason
        integer :: k

        file = trim(cfg%output%file)
        k = index(file, "/", back=.true.)
        dir = "."
        if (k == 1) dir = "/"
        if (k > 1) dir = file(1:k - 1)
        do while (path_kind(dir) == path_missing .and. dir /= "." .and. dir /= "/")
            k = index(dir, "/", back=.true.)
            if (k == 0) then
                dir = "."
            else if (k == 1) then
                dir = "/"
            else
                dir = dir(1:k - 1)
            end if
        end do
        if (path_kind(dir) /= path_directory) then
            call fatal_error(error, cfg%source // ": &output: file = '" // file // "': '" // dir // "' is not a " &
                             // "directory", err_io)
        else if (.not. directory_writable(dir, reason)) then
            call fatal_error(error, cfg%source // ": &output: file = '" // file // "': cannot create files in " &
                             // "directory '" // dir // "' (access(2) W_OK: " // reason // ")", err_io)
        end if
    end subroutine check_output_writable

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

        status = 0
        call read_input(path, cfg, error, check_output=.false.)
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
        call with_lock(cfg, inv, status, error)
    end subroutine run_from_file

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
            call remove_file(file // trim(stale(i)))
            call progress(cfg, "  deleted the stale " // file // trim(stale(i)) // " left by that run")
        end do
        call unlock_file(handle)
    end subroutine clean_finished

    !> Take the output's lock, (for a merge: write the joined records as the output's journal,) run the scene, release
    !> the lock. Nothing of the output is touched before the lock is held.
    subroutine with_lock(cfg, inv, status, error, set)
        !> The validated input.
        type(input_config), intent(inout) :: cfg
        !> How the engine is invoked (slice, merge).
        type(invocation_type), intent(in) :: inv
        !> Exit status.
        integer, intent(out) :: status
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> The records of a merge, handed to the scene as a complete journal.
        type(part_set), intent(in), optional :: set
        character(len=:), allocatable :: journal
        integer :: handle

        status = 0
        call take_lock(cfg, handle, error)
        if (allocated(error)) then
            status = error%stat
            return
        end if
        journal = trim(cfg%output%file) // ".journal"
        if (present(set)) then
            ! a merge that a signal stopped before this point: nothing of the output written yet, nothing to leave
            if (stop_signal() /= 0) call merge_stopped(error)
            if (.not. allocated(error)) call write_journal(journal, set%header, set%results, set%done, error)
        end if
        if (.not. allocated(error)) then
            call catch_stop_signals()
            call run_scene(cfg, inv, error)
        end if
        ! the journal a merge wrote is the parts' records: gone once used, or refused
        if (present(set) .and. inv%snapshot_only) call remove_file(journal)
        if (present(set) .and. allocated(error)) then
            if (error%stat == err_input) call remove_file(journal)
        end if
        call unlock_file(handle)
        if (allocated(error)) then
            status = error%stat
            return
        end if
        if (inv%slice_count == 0 .and. .not. inv%snapshot_only) call progress(cfg, "  wrote " // trim(cfg%output%file))
    end subroutine with_lock

    !> Take the lock `<output>.lock` (never through a link; the file stays when released), then delete the
    !> temporaries a killed run of this output left. With SUPRATRANS_NO_LOCK=1 no lock is taken (`handle` -1) and
    !> no temporary is deleted.
    subroutine take_lock(cfg, handle, error)
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Lock handle (negative: none held).
        integer, intent(out) :: handle
        !> Error, allocated when the lock cannot be had.
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: file, lock, reason
        character(len=8) :: knob
        integer :: ios, removed

        file = trim(cfg%output%file)
        lock = file // ".lock"
        handle = -1
        call get_environment_variable("SUPRATRANS_NO_LOCK", knob, status=ios)
        if (ios == 0 .and. trim(knob) /= "" .and. trim(knob) /= "0") then
            call disable_hdf5_locking()
            call progress(cfg, "supratrans: SUPRATRANS_NO_LOCK is set: " // file // " is written without a lock")
        else
            call lock_file(lock, handle, reason)
            if (handle == lock_busy) then
                call fatal_error(error, file // ": another supratrans is writing this output (lock " // lock &
                                 // " is held); wait for it to end", err_io)
            else if (handle == lock_unsupported) then
                call fatal_error(error, file // ": the file system refuses locks (flock on " // lock // ": " // reason &
                                 // "; NFS without a lock manager, or Lustre without -o flock?): write the output to a " &
                                 // "local directory, or set SUPRATRANS_NO_LOCK=1 if no other run writes this output", &
                                 err_io)
            else if (handle < 0) then
                call fatal_error(error, file // ": cannot write in its directory (lock file " // lock // ": " // reason &
                                 // ")", err_io)
            end if
            if (allocated(error)) return
            ! only under the lock: without it, a temporary may be another run's file being written
            call remove_stale_temporaries(file, removed)
            if (removed > 0) call progress(cfg, "supratrans: deleted " // int_str(removed) // " temporary file(s) of " &
                                           // file // " left by an interrupted run")
        end if
    end subroutine take_lock

    !> Run the scene of a validated input (`new_scene` makes it from &scene kind).
    subroutine run_scene(cfg, inv, error)
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> How the engine is invoked (slice, merge).
        type(invocation_type), intent(in) :: inv
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        class(scene_type), allocatable :: scene

        call new_scene(trim(cfg%scene%kind), scene, error)
        if (allocated(error)) then
            error%message = cfg%source // ": " // error%message
            return
        end if
        call scene%run(cfg, error, inv)
    end subroutine run_scene

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
        ! from the start: a merge stopped by a signal ends with status 5 and writes nothing (the parts stay, the same
        ! command merges them again); once the output is being written, the merge finishes it instead
        call catch_stop_signals()
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

    !> The error of a merge stopped by a signal before it wrote anything (status 5).
    subroutine merge_stopped(error)
        !> The error.
        type(error_type), allocatable, intent(out) :: error

        call fatal_error(error, "merge: stopped by signal " // int_str(stop_signal()) // " before it wrote anything: " &
                         // "nothing written, the parts are unchanged; run the same command again", err_interrupted)
    end subroutine merge_stopped

    !> The output location, checked before any work: a usable file name (`check_output_name`), not a directory, not
    !> a symbolic link (refused: never written through, never replaced), FIFO or device, nor its journal and partial
    !> snapshot, not the input itself, its directory made (mkdir(2), no shell).
    subroutine check_output_location(cfg, error, create)
        !> The input.
        type(input_config), intent(in) :: cfg
        !> Error, allocated when the output cannot be written there.
        type(error_type), allocatable, intent(out) :: error
        !> Create the missing directories (default true; `--check` writes nothing).
        logical, intent(in), optional :: create
        character(len=:), allocatable :: file
        type(error_type), allocatable :: cause
        integer :: k, i
        !> The files supratrans keeps beside the output (the lock is checked when it is taken).
        character(len=*), parameter :: companions(2) = [character(len=11) :: ".journal", ".partial.h5"]

        file = trim(cfg%output%file)
        call check_output_name(cfg, error)
        if (allocated(error)) return
        if (path_kind(file) == path_directory) then
            call fatal_error(error, cfg%source // ": &output: file = '" // file // "' is a directory", err_input)
            return
        end if
        select case (link_kind(file))
        case (path_link)
            call fatal_error(error, cfg%source // ": &output: file = '" // file // "' is a symbolic link: supratrans " &
                             // "never writes through a link nor replaces one; name the file it points to, or remove " &
                             // "the link", err_input)
            return
        case (path_special)
            call fatal_error(error, cfg%source // ": &output: file = '" // file // "' is a FIFO, device or socket, " &
                             // "not a regular file: supratrans replaces only regular files", err_input)
            return
        case default
            continue
        end select
        do i = 1, size(companions)
            if (any(link_kind(file // trim(companions(i))) == [path_link, path_special, path_directory])) then
                call fatal_error(error, file // trim(companions(i)) // ": is a symbolic link, FIFO, device or " &
                                 // "directory, not a file of supratrans: it is never written through nor replaced; " &
                                 // "remove it", err_io)
                return
            end if
        end do
        if (allocated(cfg%source)) then
            if (same_file(file, cfg%source)) then
                call fatal_error(error, cfg%source // ": &output: file = '" // file // "' is the input file itself", &
                                 err_input)
                return
            end if
        end if
        k = index(file, "/", back=.true.)
        if (k <= 1) return
        if (present(create)) then
            if (.not. create) return
        end if
        call make_directories(file(1:k - 1), cause)
        if (allocated(cause)) call fatal_error(error, cfg%source // ": &output: " // cause%message, err_io)
    end subroutine check_output_location

    !> The output's name must name a file that can be written together with its companions: no NUL character, not
    !> ending in '/', '.' or '..' (a directory), and its last component short enough for the longest name made from
    !> it (`<file>.partial.h5.tmp-XXXXXX`) to fit the 255 bytes a file name may have (4095 for the whole path), so that
    !> a name that would fail at the write is refused before the work.
    subroutine check_output_name(cfg, error)
        !> The input.
        type(input_config), intent(in) :: cfg
        !> Error (status 2), allocated when the name cannot be used.
        type(error_type), allocatable, intent(out) :: error
        !> Longest a name component may be (NAME_MAX of Linux file systems), and a whole path (PATH_MAX - 1).
        integer, parameter :: name_max = 255, path_max = 4095
        !> What supratrans appends to the output's name at most: `.partial.h5` and a temporary suffix.
        integer, parameter :: extra = len(".partial.h5") + temp_extra
        character(len=:), allocatable :: file, last
        integer :: k

        file = trim(cfg%output%file)
        if (index(file, c_null_char) > 0) then
            call fatal_error(error, cfg%source // ": &output: file = '" // printable(file) // "' holds a NUL " &
                             // "character", err_input)
            return
        end if
        k = index(file, "/", back=.true.)
        last = file(k + 1:)
        if (len(last) == 0 .or. last == "." .or. last == "..") then
            call fatal_error(error, cfg%source // ": &output: file = '" // file // "' names a directory, not a file " &
                             // "(give the file's name, e.g. '" // file(1:k) // "result.h5')", err_input)
            return
        end if
        if (len(last) + extra > name_max .or. len(file) + extra > path_max) then
            call fatal_error(error, cfg%source // ": &output: file = '" // file // "': name too long (" &
                             // int_str(len(last)) // " characters; at most " // int_str(name_max - extra) &
                             // ", as supratrans adds up to " // int_str(extra) // " for its journal and temporary files)", &
                             err_input)
        end if
    end subroutine check_output_name

    !> Print a progress line on stderr unless the output asks for quiet (control characters shown as '?').
    subroutine progress(cfg, line)
        !> Input (for the quiet flag).
        type(input_config), intent(in) :: cfg
        !> Text.
        character(len=*), intent(in) :: line

        if (.not. cfg%output%quiet) write (error_unit, "(a)") printable(line)
    end subroutine progress

end module supratrans_cli
