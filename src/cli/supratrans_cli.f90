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
!>
!> This module reads the command line and hands each command to its module: `supratrans_cli_run` (a namelist, a
!> slice), `supratrans_cli_merge`, `supratrans_cli_check`; what they share about the output (its location, its lock,
!> the scene run under it) is `supratrans_cli_output`.
module supratrans_cli
    use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
    use supratrans_kinds, only: supratrans_version
    use supratrans_strings, only: int_str, printable
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_system, only: ignore_file_size_signal
    use supratrans_resources, only: bound_threads
    use supratrans_cli_run, only: run_from_file, parse_slice
    use supratrans_cli_merge, only: merge_command
    use supratrans_cli_check, only: check_file
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
        "                        the same study (bifurcation: /cost/cpu_time), not by the estimate" // new_line("a") // &
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
        character(len=:), allocatable :: file, costs, slice_text
        integer :: i, slice_index, slice_count, nchecked, worst
        logical :: check_only

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
            call merge_command(args, status, error)
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
                if (slice_count > 0) then
                    ! one slice per run: the last of several used to be taken silently
                    call fail("--slice given twice ('" // printable(slice_text) // "' and '" &
                              // printable(trim(args(i + 1))) // "'): one run computes one slice")
                    return
                end if
                i = i + 1
                slice_text = trim(args(i))
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

end module supratrans_cli
