!> Operating-system calls on paths, made directly through the C library: no path or input ever reaches a shell.
!>
!> `make_directories` is `mkdir -p` done one component at a time with POSIX `mkdir(2)`; `rename_file` is
!> `rename(2)` (atomic within one file system); `remove_file` is `unlink(2)`; `path_kind` is `stat(2)`;
!> `lock_file` an advisory `flock(2)`; `catch_stop_signals`/`stop_signal` turn SIGTERM, SIGINT and SIGUSR1 into a
!> flag that long work polls (the one process-wide state of the program: a signal can only set a flag); the C side
!> is `supratrans_os.c`. Errors come back as values.
module supratrans_system
    use, intrinsic :: iso_c_binding, only: c_char, c_int, c_long_long, c_null_char
    use supratrans_error, only: error_type, fatal_error, err_io
    implicit none
    private

    public :: make_directories, rename_file, remove_file, is_directory, path_kind, file_size
    public :: lock_file, unlock_file, catch_stop_signals, stop_signal, same_file, write_bytes

    !> `path_kind`: nothing at that path.
    integer, parameter, public :: path_missing = 0
    !> `path_kind`: a regular file.
    integer, parameter, public :: path_regular = 1
    !> `path_kind`: a directory.
    integer, parameter, public :: path_directory = 2
    !> `path_kind`: something else (a FIFO, a device, a socket).
    integer, parameter, public :: path_special = 3

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
        function c_lock(path) bind(c, name="supratrans_lock") result(fd)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int) :: fd
        end function c_lock
        subroutine c_unlock(fd) bind(c, name="supratrans_unlock")
            import :: c_int
            integer(c_int), value :: fd
        end subroutine c_unlock
        subroutine c_catch_stop_signals() bind(c, name="supratrans_catch_stop_signals")
        end subroutine c_catch_stop_signals
        function c_stop_signal() bind(c, name="supratrans_stop_signal") result(sig)
            import :: c_int
            integer(c_int) :: sig
        end function c_stop_signal
        function c_write_bytes(path, bytes, length, append) bind(c, name="supratrans_write_bytes") result(stat)
            import :: c_char, c_int, c_long_long
            character(kind=c_char), intent(in) :: path(*), bytes(*)
            integer(c_long_long), value :: length
            integer(c_int), value :: append
            integer(c_int) :: stat
        end function c_write_bytes
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

    !> Take an exclusive advisory lock on `path` (created if missing) without waiting: `handle` >= 0 holds it (the
    !> kernel releases it when the process ends, also by a crash or a kill), -1 another process holds it, -2 the
    !> lock file cannot be created.
    subroutine lock_file(path, handle)
        !> Lock file.
        character(len=*), intent(in) :: path
        !> Lock handle, or -1 / -2.
        integer, intent(out) :: handle

        handle = int(c_lock(path // c_null_char))
    end subroutine lock_file

    !> Release a lock taken by `lock_file` (nothing for a negative handle).
    subroutine unlock_file(handle)
        !> Lock handle.
        integer, intent(in) :: handle

        if (handle >= 0) call c_unlock(int(handle, c_int))
    end subroutine unlock_file

    !> From now on SIGTERM, SIGINT and SIGUSR1 set the stop flag (`stop_signal`) instead of ending the process.
    subroutine catch_stop_signals()
        call c_catch_stop_signals()
    end subroutine catch_stop_signals

    !> The signal number that asked the program to stop, 0 if none arrived.
    function stop_signal() result(sig)
        integer :: sig

        sig = int(c_stop_signal())
    end function stop_signal

    !> Write `bytes` to `path` (created if missing), appended or replacing its contents, through write(2) and
    !> close(2), whose every failure (a full disk, an I/O error) is reported: `ok` false then.
    subroutine write_bytes(path, bytes, append, ok)
        !> File.
        character(len=*), intent(in) :: path
        !> What to write.
        character(len=*), intent(in) :: bytes
        !> Append (true) or replace (false).
        logical, intent(in) :: append
        !> Whether every byte was written and the file closed without error.
        logical, intent(out) :: ok

        ok = c_write_bytes(path // c_null_char, bytes, int(len(bytes), c_long_long), merge(1_c_int, 0_c_int, append)) == 0
    end subroutine write_bytes

    !> Whether two paths name the same existing file (same device and inode).
    function same_file(a, b) result(same)
        !> First path.
        character(len=*), intent(in) :: a
        !> Second path.
        character(len=*), intent(in) :: b
        logical :: same

        same = c_same_file(a // c_null_char, b // c_null_char) == 1
    end function same_file

end module supratrans_system
