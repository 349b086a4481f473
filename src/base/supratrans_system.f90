!> Operating-system calls on paths, made directly through the C library: no path or input ever reaches a shell.
!>
!> `make_directories` is `mkdir -p` done one component at a time with POSIX `mkdir(2)`; `rename_file` is
!> `rename(2)` (atomic within one file system); `remove_file` is `unlink(2)`; `path_kind` is `stat(2)`;
!> `lock_file` an advisory `flock(2)`; `catch_stop_signals`/`stop_signal` turn SIGTERM, SIGINT and SIGUSR1 into a
!> flag that long work polls (the one process-wide state of the program: a signal can only set a flag); the C side
!> is `supratrans_os.c`. Errors come back as values.
!>
!> Files on a shared machine: a file is created only under a fresh name nobody can guess (`temp_name`,
!> `<final>.tmp-XXXXXX`) with `O_CREAT | O_EXCL | O_NOFOLLOW` (or HDF5's `H5F_ACC_EXCL`, the same flags), written,
!> fsync'ed and renamed onto its final name (`write_file_atomic`, `commit_file`), so that no link or file planted under
!> a predictable name is ever written through. `remove_stale_temporaries` deletes what a killed run left, only regular
!> files of this user, and only under the output's lock.
module supratrans_system
    use, intrinsic :: iso_c_binding, only: c_char, c_int, c_long_long, c_null_char, c_double
    use supratrans_error, only: error_type, fatal_error, err_io
    use supratrans_kinds, only: wp
    implicit none
    private

    public :: make_directories, rename_file, remove_file, is_directory, path_kind, file_size
    public :: lock_file, unlock_file, catch_stop_signals, ignore_file_size_signal, stop_signal, same_file, append_bytes, link_kind
    public :: temp_name, write_file_atomic, write_bytes_atomic, commit_file, remove_stale_temporaries, os_error_text, &
        disable_hdf5_locking
    public :: directory_writable, usable_cpus, note_out_of_memory, out_of_memory, thread_cpu_seconds
    public :: not_own_file, remove_own_file, foreign_checkpoint

    !> `path_kind`: nothing at that path.
    integer, parameter, public :: path_missing = 0
    !> `path_kind`: a regular file.
    integer, parameter, public :: path_regular = 1
    !> `path_kind`: a directory.
    integer, parameter, public :: path_directory = 2
    !> `path_kind`: something else (a FIFO, a device, a socket).
    integer, parameter, public :: path_special = 3
    !> `link_kind`: a symbolic link (dangling or not).
    integer, parameter, public :: path_link = 4
    !> Suffix of the temporary file of `<final>` before its six random characters: `<final>.tmp-XXXXXX`.
    character(len=*), parameter, public :: temp_suffix = ".tmp-"
    !> How many characters a temporary name adds to its final name (`.tmp-XXXXXX`).
    integer, parameter, public :: temp_extra = len(temp_suffix) + 6
    !> `lock_file`: another process holds the lock.
    integer, parameter, public :: lock_busy = -1
    !> `lock_file`: the lock file cannot be opened (no permission, or a link or other non-file at its path).
    integer, parameter, public :: lock_cannot_open = -2
    !> `lock_file`: the file system refuses locks (ENOLCK: NFS without a lock manager; EOPNOTSUPP, ENOSYS).
    integer, parameter, public :: lock_unsupported = -3

    interface
        !> POSIX mkdir(2).
        function c_mkdir(path, mode) bind(c, name="mkdir") result(stat)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int), value :: mode
            integer(c_int) :: stat
        end function c_mkdir
        !> C rename(3).
        function c_rename(old, new) bind(c, name="rename") result(stat)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: old(*), new(*)
            integer(c_int) :: stat
        end function c_rename
        !> POSIX unlink(2).
        function c_unlink(path) bind(c, name="unlink") result(stat)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int) :: stat
        end function c_unlink
        function c_path_kind(path) bind(c, name="supratrans_path_kind") result(kind)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int) :: kind
        end function c_path_kind
        function c_file_size(path) bind(c, name="supratrans_file_size") result(bytes)
            import :: c_char, c_long_long
            character(kind=c_char), intent(in) :: path(*)
            integer(c_long_long) :: bytes
        end function c_file_size
        function c_lock(path, err) bind(c, name="supratrans_lock") result(fd)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int), intent(out) :: err
            integer(c_int) :: fd
        end function c_lock
        function c_link_kind(path) bind(c, name="supratrans_link_kind") result(kind)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int) :: kind
        end function c_link_kind
        subroutine c_strerror(err, buf, size) bind(c, name="supratrans_strerror")
            import :: c_char, c_int
            integer(c_int), value :: err
            character(kind=c_char), intent(out) :: buf(*)
            integer(c_int), value :: size
        end subroutine c_strerror
        subroutine c_hdf5_no_file_locking() bind(c, name="supratrans_hdf5_no_file_locking")
        end subroutine c_hdf5_no_file_locking
        function c_temp_name(final, buf, size) bind(c, name="supratrans_temp_name") result(stat)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: final(*)
            character(kind=c_char), intent(out) :: buf(*)
            integer(c_int), value :: size
            integer(c_int) :: stat
        end function c_temp_name
        function c_write_file_atomic(final, bytes, length) bind(c, name="supratrans_write_file_atomic") result(err)
            import :: c_char, c_int, c_long_long
            character(kind=c_char), intent(in) :: final(*), bytes(*)
            integer(c_long_long), value :: length
            integer(c_int) :: err
        end function c_write_file_atomic
        function c_commit_file(tmp, final) bind(c, name="supratrans_commit_file") result(err)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: tmp(*), final(*)
            integer(c_int) :: err
        end function c_commit_file
        function c_remove_stale(dir, prefix) bind(c, name="supratrans_remove_stale") result(removed)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: dir(*), prefix(*)
            integer(c_int) :: removed
        end function c_remove_stale
        subroutine c_unlock(fd) bind(c, name="supratrans_unlock")
            import :: c_int
            integer(c_int), value :: fd
        end subroutine c_unlock
        subroutine c_unlock_remove(fd, path) bind(c, name="supratrans_unlock_remove")
            import :: c_char, c_int
            integer(c_int), value :: fd
            character(kind=c_char), intent(in) :: path(*)
        end subroutine c_unlock_remove
        subroutine c_catch_stop_signals() bind(c, name="supratrans_catch_stop_signals")
        end subroutine c_catch_stop_signals
        subroutine c_ignore_file_size_signal() bind(c, name="supratrans_ignore_file_size_signal")
        end subroutine c_ignore_file_size_signal
        function c_stop_signal() bind(c, name="supratrans_stop_signal") result(sig)
            import :: c_int
            integer(c_int) :: sig
        end function c_stop_signal
        function c_append_bytes(path, bytes, length) bind(c, name="supratrans_append_bytes") result(err)
            import :: c_char, c_int, c_long_long
            character(kind=c_char), intent(in) :: path(*), bytes(*)
            integer(c_long_long), value :: length
            integer(c_int) :: err
        end function c_append_bytes
        function c_directory_writable(path) bind(c, name="supratrans_directory_writable") result(err)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int) :: err
        end function c_directory_writable
        subroutine c_note_out_of_memory() bind(c, name="supratrans_note_out_of_memory")
        end subroutine c_note_out_of_memory
        function c_out_of_memory() bind(c, name="supratrans_out_of_memory") result(yes)
            import :: c_int
            integer(c_int) :: yes
        end function c_out_of_memory
        function c_usable_cpus() bind(c, name="supratrans_usable_cpus") result(n)
            import :: c_int
            integer(c_int) :: n
        end function c_usable_cpus
        function c_thread_cpu_seconds() bind(c, name="supratrans_thread_cpu_seconds") result(seconds)
            import :: c_double
            real(c_double) :: seconds
        end function c_thread_cpu_seconds
        function c_own_file(path, uid, mode) bind(c, name="supratrans_own_file") result(kind)
            import :: c_char, c_int, c_long_long
            character(kind=c_char), intent(in) :: path(*)
            integer(c_long_long), intent(out) :: uid
            integer(c_int), intent(out) :: mode
            integer(c_int) :: kind
        end function c_own_file
        function c_foreign_entry(dir, prefix, buf, size) bind(c, name="supratrans_foreign_entry") result(kind)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: dir(*), prefix(*)
            character(kind=c_char), intent(out) :: buf(*)
            integer(c_int), value :: size
            integer(c_int) :: kind
        end function c_foreign_entry
        function c_same_file(a, b) bind(c, name="supratrans_same_file") result(same)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: a(*), b(*)
            integer(c_int) :: same
        end function c_same_file
    end interface

    !> Permissions asked of a new directory (rwxrwxrwx, reduced by the process umask).
    integer(c_int), parameter :: directory_mode = int(o'777', c_int)

contains

    !> Whether `path` names an existing directory.
    function is_directory(path) result(yes)
        !> Path to test.
        character(len=*), intent(in) :: path
        logical :: yes

        inquire (file=path // "/.", exist=yes)
    end function is_directory

    !> Create directory `path` and every missing parent (like `mkdir -p`), through mkdir(2).
    subroutine make_directories(path, error)
        !> Directory to create.
        character(len=*), intent(in) :: path
        !> Error, allocated if a component cannot be created or is not a directory.
        type(error_type), allocatable, intent(out) :: error
        integer :: k, stat

        if (len_trim(path) == 0) return
        if (index(path, c_null_char) > 0) then
            call fatal_error(error, "directory name holds a NUL character", err_io)
            return
        end if
        do k = 2, len_trim(path) + 1
            if (k <= len_trim(path)) then
                if (path(k:k) /= "/") cycle
            end if
            if (path(k - 1:k - 1) == "/" .or. is_directory(path(1:k - 1))) cycle
            stat = c_mkdir(path(1:k - 1) // c_null_char, directory_mode)
            if (stat /= 0 .and. .not. is_directory(path(1:k - 1))) then
                call fatal_error(error, "cannot create directory '" // path(1:k - 1) // "'", err_io)
                return
            end if
        end do
    end subroutine make_directories

    !> Rename a file (atomic on one file system).
    subroutine rename_file(from, to, error)
        !> Existing file.
        character(len=*), intent(in) :: from
        !> New name.
        character(len=*), intent(in) :: to
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error

        if (c_rename(from // c_null_char, to // c_null_char) /= 0) then
            call fatal_error(error, from // ": cannot rename to " // to, err_io)
        end if
    end subroutine rename_file

    !> Delete a file if it exists (nothing if it does not).
    subroutine remove_file(path)
        !> File to delete.
        character(len=*), intent(in) :: path
        integer(c_int) :: stat

        stat = c_unlink(path // c_null_char)
    end subroutine remove_file

    !> Kind of a path (`stat(2)`, links followed): `path_missing`, `path_regular`, `path_directory`, `path_special`.
    function path_kind(path) result(kind)
        !> Path to examine.
        character(len=*), intent(in) :: path
        integer :: kind

        kind = int(c_path_kind(path // c_null_char))
    end function path_kind

    !> Size in bytes of a file (-1 if unknown).
    function file_size(path) result(bytes)
        !> File.
        character(len=*), intent(in) :: path
        integer(c_long_long) :: bytes

        bytes = c_file_size(path // c_null_char)
    end function file_size

    !> Kind of a path itself (`lstat(2)`: a symbolic link is not followed): `path_missing`, `path_regular`,
    !> `path_directory`, `path_special` or `path_link`.
    function link_kind(path) result(kind)
        !> Path to examine.
        character(len=*), intent(in) :: path
        integer :: kind

        kind = int(c_link_kind(path // c_null_char))
    end function link_kind

    !> Take an exclusive advisory lock on `path` (created if missing, never through a symbolic link) without waiting:
    !> `handle` >= 0 holds it (the kernel releases it when the process ends, also by a crash or a kill);
    !> `lock_busy`: another process holds it; `lock_cannot_open`: the lock file cannot be created or is not a
    !> regular file; `lock_unsupported`: the file system refuses locks. `reason` says why for the last two.
    !> A lock counts only once `path` still names the file locked (its holder may have removed it in between:
    !> `unlock_file` with `path`); else the name is opened again, so that two processes never each hold a lock of
    !> the same name.
    subroutine lock_file(path, handle, reason)
        !> Lock file.
        character(len=*), intent(in) :: path
        !> Lock handle, or `lock_busy`, `lock_cannot_open`, `lock_unsupported`.
        integer, intent(out) :: handle
        !> The system's words for the failure (strerror), empty otherwise.
        character(len=:), allocatable, intent(out) :: reason
        integer(c_int) :: err

        handle = int(c_lock(path // c_null_char, err))
        reason = ""
        if (err /= 0) reason = os_error_text(int(err))
        if (handle /= lock_cannot_open) return
        select case (link_kind(path))
        case (path_link)
            reason = "it is a symbolic link, which is never followed"
        case (path_directory, path_special)
            reason = "it is not a regular file"
        case default
            continue
        end select
    end subroutine lock_file

    !> Release a lock taken by `lock_file` (nothing for a negative handle). Given `path`, the lock file is removed
    !> first, while still held, and only if that name still refers to the file this process locked (same device and
    !> inode); without it the file stays.
    subroutine unlock_file(handle, path)
        !> Lock handle.
        integer, intent(in) :: handle
        !> The lock file `handle` was taken on: remove it.
        character(len=*), intent(in), optional :: path

        if (handle < 0) return
        if (present(path)) then
            call c_unlock_remove(int(handle, c_int), path // c_null_char)
        else
            call c_unlock(int(handle, c_int))
        end if
    end subroutine unlock_file

    !> The system's text for an `errno` value (strerror), e.g. "No space left on device".
    function os_error_text(err) result(text)
        !> The errno value.
        integer, intent(in) :: err
        character(len=:), allocatable :: text
        character(kind=c_char, len=256) :: buffer

        buffer = ""
        call c_strerror(int(err, c_int), buffer, int(len(buffer), c_int))
        text = buffer(1:max(index(buffer, c_null_char) - 1, 0))
    end function os_error_text

    !> Switch HDF5's own file locking off for this process (HDF5_USE_FILE_LOCKING=FALSE, unless set): the
    !> documented no-lock override, for file systems that refuse locks.
    subroutine disable_hdf5_locking()
        call c_hdf5_no_file_locking()
    end subroutine disable_hdf5_locking

    !> A fresh candidate name for a temporary file of `final`: `<final>.tmp-XXXXXX`, six random letters or digits.
    !> Take it only by creating it exclusively (`O_EXCL`, or HDF5's `H5F_ACC_EXCL`) and retry when it is taken.
    function temp_name(final) result(name)
        !> The final name of the file.
        character(len=*), intent(in) :: final
        character(len=:), allocatable :: name
        character(kind=c_char, len=len(final) + temp_extra + 1) :: buffer

        if (c_temp_name(final // c_null_char, buffer, int(len(buffer), c_int)) /= 0) then
            name = final // temp_suffix // "XXXXXX"
        else
            name = buffer(1:len(final) + temp_extra)
        end if
    end function temp_name

    !> Write `bytes` as the new contents of `final`, atomically and never through a link: a fresh temporary file
    !> (`temp_name`, created with `O_CREAT | O_EXCL | O_NOFOLLOW`), every write checked, fsync, rename onto `final`.
    !> Nothing is left behind on failure, and `final` is then unchanged.
    subroutine write_file_atomic(final, bytes, error)
        !> The file.
        character(len=*), intent(in) :: final
        !> Its new contents.
        character(len=*), intent(in) :: bytes
        !> Error, allocated on failure (the message names the file and the system's reason).
        type(error_type), allocatable, intent(out) :: error
        integer :: err

        if (index(final, c_null_char) > 0) then
            call fatal_error(error, "file name holds a NUL character", err_io)
            return
        end if
        err = int(c_write_file_atomic(final // c_null_char, bytes, int(len(bytes), c_long_long)))
        if (err /= 0) call fatal_error(error, final // ": cannot write (" // os_error_text(err) // ")", err_io)
    end subroutine write_file_atomic

    !> Write the bytes `bytes` as the new contents of `final`, atomically, as `write_file_atomic` does (a fresh
    !> temporary created exclusively, every write checked, fsync, rename; nothing left behind on failure).
    subroutine write_bytes_atomic(final, bytes, error)
        !> The file.
        character(len=*), intent(in) :: final
        !> Its new contents (an HDF5 file's image).
        character(kind=c_char, len=1), intent(in) :: bytes(:)
        !> Error, allocated on failure (the message names the file and the system's reason, e.g. "No space left on
        !> device").
        type(error_type), allocatable, intent(out) :: error
        integer :: err

        if (index(final, c_null_char) > 0) then
            call fatal_error(error, "file name holds a NUL character", err_io)
            return
        end if
        err = int(c_write_file_atomic(final // c_null_char, bytes, int(size(bytes), c_long_long)))
        if (err /= 0) call fatal_error(error, final // ": cannot write (" // os_error_text(err) // ")", err_io)
    end subroutine write_bytes_atomic

    !> Give a finished temporary file its final name: fsync it, rename(2) it onto `final` (replacing `final` itself,
    !> never the target of a link there), fsync the directory.
    subroutine commit_file(tmp, final, error)
        !> The temporary file, written and closed.
        character(len=*), intent(in) :: tmp
        !> Its final name.
        character(len=*), intent(in) :: final
        !> Error, allocated on failure (`tmp` is then left for the caller to delete).
        type(error_type), allocatable, intent(out) :: error
        integer :: err

        err = int(c_commit_file(tmp // c_null_char, final // c_null_char))
        if (err /= 0) call fatal_error(error, tmp // ": cannot rename to " // final // " (" // os_error_text(err) &
                                       // ")", err_io)
    end subroutine commit_file

    !> Delete the temporary files a killed run left for the output `file` (`<file>.tmp-XXXXXX`,
    !> `<file>.journal.tmp-XXXXXX`, `<file>.partial.h5.tmp-XXXXXX`): only regular files owned by this user, never
    !> through a link. Call only while holding the output's lock. `removed` counts them.
    subroutine remove_stale_temporaries(file, removed)
        !> The output file.
        character(len=*), intent(in) :: file
        !> How many were deleted.
        integer, intent(out) :: removed
        character(len=*), parameter :: owned(3) = [character(len=12) :: "", ".journal", ".partial.h5"]
        character(len=:), allocatable :: dir, base
        integer :: k, i

        k = index(file, "/", back=.true.)
        if (k == 0) then
            dir = "."
        else if (k == 1) then
            dir = "/"
        else
            dir = file(1:k - 1)
        end if
        base = file(k + 1:)
        removed = 0
        do i = 1, size(owned)
            removed = removed + int(c_remove_stale(dir // c_null_char, base // trim(owned(i)) // temp_suffix &
                                                   // c_null_char))
        end do
    end subroutine remove_stale_temporaries

    !> From now on SIGTERM, SIGINT and SIGUSR1 set the stop flag (`stop_signal`) instead of ending the process.
    subroutine catch_stop_signals()
        call c_catch_stop_signals()
    end subroutine catch_stop_signals

    !> From now on a write beyond the file size limit (`ulimit -f`) fails with EFBIG, reported like a full disk,
    !> instead of SIGXFSZ ending the process.
    subroutine ignore_file_size_signal()
        call c_ignore_file_size_signal()
    end subroutine ignore_file_size_signal

    !> The signal number that asked the program to stop, 0 if none arrived.
    function stop_signal() result(sig)
        integer :: sig

        sig = int(c_stop_signal())
    end function stop_signal

    !> Append `bytes` to the journal `path` (created if missing; never through a symbolic link, never anything but a
    !> regular file) through write(2) and close(2), whose every failure (a full disk, an I/O error) is reported: `ok`
    !> false then.
    subroutine append_bytes(path, bytes, ok)
        !> File.
        character(len=*), intent(in) :: path
        !> What to write.
        character(len=*), intent(in) :: bytes
        !> Whether every byte was written and the file closed without error.
        logical, intent(out) :: ok

        ok = c_append_bytes(path // c_null_char, bytes, int(len(bytes), c_long_long)) == 0
    end subroutine append_bytes

    !> Whether two paths name the same existing file (same device and inode).
    function same_file(a, b) result(same)
        !> First path.
        character(len=*), intent(in) :: a
        !> Second path.
        character(len=*), intent(in) :: b
        logical :: same

        same = c_same_file(a // c_null_char, b // c_null_char) == 1
    end function same_file

    !> Whether this process may create files in the directory `path` (access(2) with W_OK | X_OK, which also
    !> reports a read-only mount); `reason` is the system's words when not (e.g. "Read-only file system").
    function directory_writable(path, reason) result(yes)
        !> Directory.
        character(len=*), intent(in) :: path
        !> Why not (strerror), empty when writable.
        character(len=:), allocatable, intent(out) :: reason
        logical :: yes
        integer :: err

        err = int(c_directory_writable(path // c_null_char))
        yes = err == 0
        reason = ""
        if (.not. yes) reason = os_error_text(err)
    end function directory_writable

    !> Note that a run could not allocate its arrays (safe from any thread: a flag that is only ever set). The task
    !> loop and the timeseries scene stop with one line instead of recording such a run.
    subroutine note_out_of_memory()
        call c_note_out_of_memory()
    end subroutine note_out_of_memory

    !> Whether a run of this process could not allocate its arrays (`note_out_of_memory`).
    function out_of_memory() result(yes)
        logical :: yes

        yes = c_out_of_memory() /= 0
    end function out_of_memory

    !> Processors this process may run on (sched_getaffinity(2): taskset, cpusets, Slurm's --cpus-per-task), at
    !> least 1.
    function usable_cpus() result(n)
        integer :: n

        n = max(1, int(c_usable_cpus()))
    end function usable_cpus

    !> Processor time of the calling thread so far (s): differences of two calls on one thread are what the work
    !> between them cost, unlike wall time also on a machine that other processes share; -1 where the clock is
    !> not available.
    function thread_cpu_seconds() result(seconds)
        real(wp) :: seconds

        seconds = real(c_thread_cpu_seconds(), wp)
    end function thread_cpu_seconds

    !> Why `path` is not a file of this user that supratrans may resume from or delete, "" when it is (or when
    !> nothing is there): it must be a regular file (a link is not followed) owned by the running user and writable
    !> by nobody else. A checksum finds damage, not forgery: a journal, snapshot, part or checkpoint that another user
    !> wrote, or could have altered, is never trusted nor removed.
    function not_own_file(path) result(reason)
        !> The file.
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: reason
        integer(c_long_long) :: uid
        integer(c_int) :: mode

        reason = own_file_reason(int(c_own_file(path // c_null_char, uid, mode)), uid, mode)
    end function not_own_file

    !> The words of `not_own_file` for the code of `supratrans_own_file` (owner `uid`, permission bits `mode`).
    function own_file_reason(kind, uid, mode) result(reason)
        !> 0 missing, 1 own, 2 not a regular file, 3 another user's, 4 writable by group or others.
        integer, intent(in) :: kind
        !> Its owner.
        integer(c_long_long), intent(in) :: uid
        !> Its permission bits.
        integer(c_int), intent(in) :: mode
        character(len=:), allocatable :: reason
        character(len=24) :: text

        select case (kind)
        case (2)
            reason = "not a regular file (a symbolic link, FIFO, device or directory): never read nor removed"
        case (3)
            write (text, "(i0)") uid
            reason = "belongs to another user (uid " // trim(text) // "): supratrans neither resumes from nor " &
                     // "deletes a file it did not write; its owner may delete it, or write the output elsewhere"
        case (4)
            write (text, "(o4.4)") mode
            reason = "writable by group or others (mode " // trim(text) // "): anyone may have altered it, and " &
                     // "supratrans writes its files rw-r--r--; if it is yours and unaltered, chmod go-w it, else " &
                     // "delete it"
        case default
            reason = ""
        end select
    end function own_file_reason

    !> Delete `path` only if it is this user's own file (`not_own_file` is ""): a file planted under one of the
    !> output's names by someone else, or a link, is left as it is.
    subroutine remove_own_file(path)
        !> The file.
        character(len=*), intent(in) :: path

        if (len(not_own_file(path)) == 0) call remove_file(path)
    end subroutine remove_own_file

    !> The first checkpoint of the output `file` (`<file>.checkpoint`, `<file>.checkpoint-<task>`) that is not this
    !> user's own (`not_own_file`): `<name>: <why>`, or "" when there is none.
    function foreign_checkpoint(file) result(text)
        !> The output file.
        character(len=*), intent(in) :: file
        character(len=:), allocatable :: text
        character(kind=c_char, len=4096) :: buffer
        character(len=:), allocatable :: dir
        integer :: k, kind

        k = index(file, "/", back=.true.)
        if (k == 0) then
            dir = "."
        else if (k == 1) then
            dir = "/"
        else
            dir = file(1:k - 1)
        end if
        buffer = ""
        kind = int(c_foreign_entry(dir // c_null_char, file(k + 1:) // ".checkpoint" // c_null_char, buffer, &
                                   int(len(buffer), c_int)))
        text = ""
        if (kind == 0) return
        text = buffer(1:max(index(buffer, c_null_char) - 1, 0))
        if (k > 0) text = file(1:k) // text
        text = text // ": " // not_own_file(text)
    end function foreign_checkpoint

end module supratrans_system
