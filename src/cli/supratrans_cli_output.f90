!> What every command that writes an output shares (`supratrans_cli`): the output's location checked before any
!> work (a file name: no NUL, no trailing '/', short enough for the temporary and journal names made from it; not a
!> directory, not a symbolic link, FIFO or device, not the input file itself; its directory made with mkdir(2),
!> never a shell), the advisory lock `<output>.lock` taken before any file of the output is touched (removed by its
!> holder as the run ends, while still held; `SUPRATRANS_NO_LOCK=1` runs without it), and the scene run under that
!> lock (`with_lock`), for a merge after the parts' records are written as the output's journal.
module supratrans_cli_output
    use, intrinsic :: iso_fortran_env, only: error_unit
    use, intrinsic :: iso_c_binding, only: c_null_char
    use supratrans_strings, only: int_str, printable
    use supratrans_error, only: error_type, fatal_error, err_input, err_io, err_interrupted
    use supratrans_config, only: input_config
    use supratrans_invocation, only: invocation_type
    use supratrans_system, only: make_directories, path_kind, path_directory, same_file, lock_file, unlock_file, &
                                 catch_stop_signals, link_kind, path_link, path_special, lock_busy, &
                                 lock_unsupported, remove_stale_temporaries, disable_hdf5_locking, temp_extra, stop_signal, &
                                 not_own_file, remove_own_file, foreign_checkpoint
    use supratrans_journal, only: write_journal
    use supratrans_parts, only: part_set
    use supratrans_scene, only: scene_type, new_scene
    implicit none
    private

    public :: check_output_location, take_lock, with_lock, merge_stopped, progress

contains

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
        call check_own_files(file, error)
        if (allocated(error)) return
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

    !> The files of the output `file` that a run resumes from or deletes (its journal, partial snapshot and
    !> checkpoints) must be this user's own: regular files owned by the running user and writable by nobody else
    !> (`not_own_file`). In a folder others can write (0777 without the sticky bit) another user's file there is
    !> refused with one line, status 4, and left as it is: it used to be deleted, or a forged journal resumed from.
    subroutine check_own_files(file, error)
        !> The output file.
        character(len=*), intent(in) :: file
        !> Error (status 4), allocated for the first file that is not this user's own.
        type(error_type), allocatable, intent(out) :: error
        character(len=*), parameter :: kept(2) = [character(len=11) :: ".journal", ".partial.h5"]
        character(len=:), allocatable :: why
        integer :: i

        do i = 1, size(kept)
            why = not_own_file(file // trim(kept(i)))
            if (len(why) > 0) then
                call fatal_error(error, file // trim(kept(i)) // ": " // why, err_io)
                return
            end if
        end do
        why = foreign_checkpoint(file)
        if (len(why) > 0) call fatal_error(error, why, err_io)
    end subroutine check_own_files

    !> Take the lock `<output>.lock` (never through a link; its holder removes it when released), then delete the
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
            call check_own_files(file, error)
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
            if (.not. allocated(error)) call check_own_files(file, error)
            if (allocated(error)) then
                call unlock_file(handle)
                handle = -1
                return
            end if
            ! only under the lock: without it, a temporary may be another run's file being written
            call remove_stale_temporaries(file, removed)
            if (removed > 0) call progress(cfg, "supratrans: deleted " // int_str(removed) // " temporary file(s) of " &
                                           // file // " left by an interrupted run")
        end if
    end subroutine take_lock

    !> Take the output's lock, (for a merge: write the joined records as the output's journal,) run the scene, release
    !> the lock and remove its file. Nothing of the output is touched before the lock is held.
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
        ! caught before the lock file exists: a stop signal as the lock is taken sets the flag (the scene then stops
        ! at once, exit 5, and the lock's file is removed) instead of ending the process with the file left behind
        call catch_stop_signals()
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
        if (.not. allocated(error)) call run_scene(cfg, inv, error)
        ! the journal a merge wrote is the parts' records: gone once used, or refused
        if (present(set) .and. inv%snapshot_only) call remove_own_file(journal)
        if (present(set) .and. allocated(error)) then
            if (error%stat == err_input) call remove_own_file(journal)
        end if
        call unlock_file(handle, trim(cfg%output%file) // ".lock")   ! removed as the lock ends
        if (allocated(error)) then
            status = error%stat
            return
        end if
        if (inv%slice_count == 0 .and. .not. inv%snapshot_only) call progress(cfg, "  wrote " // trim(cfg%output%file))
    end subroutine with_lock

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

    !> The error of a merge stopped by a signal before it wrote anything (status 5).
    subroutine merge_stopped(error)
        !> The error.
        type(error_type), allocatable, intent(out) :: error

        call fatal_error(error, "merge: stopped by signal " // int_str(stop_signal()) // " before it wrote anything: " &
                         // "nothing written, the parts are unchanged; run the same command again", err_interrupted)
    end subroutine merge_stopped

    !> Print a progress line on stderr unless the output asks for quiet (control characters shown as '?').
    subroutine progress(cfg, line)
        !> Input (for the quiet flag).
        type(input_config), intent(in) :: cfg
        !> Text.
        character(len=*), intent(in) :: line

        if (.not. cfg%output%quiet) write (error_unit, "(a)") printable(line)
    end subroutine progress

end module supratrans_cli_output
