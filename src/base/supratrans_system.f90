!> Operating-system calls on paths, made directly through the C library: no path or input ever reaches a shell.
!>
!> `make_directories` is `mkdir -p` done one component at a time with POSIX `mkdir(2)`; `rename_file` is
!> `rename(2)` (atomic within one file system); `remove_file` is `unlink(2)`. Errors come back as values.
module supratrans_system
    use, intrinsic :: iso_c_binding, only: c_char, c_int, c_null_char
    use supratrans_error, only: error_type, fatal_error, err_io
    implicit none
    private

    public :: make_directories, rename_file, remove_file, is_directory

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

end module supratrans_system
