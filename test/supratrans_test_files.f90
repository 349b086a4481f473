!> Small helpers the tests share for their files: a unique path under /tmp, whether a file exists, deleting one, and
!> an error's message for an assertion's message.
module supratrans_test_files
    use supratrans_kinds, only: wp, i8
    use supratrans_error, only: error_type
    implicit none
    private

    public :: unique_tmp, path_exists, delete_file, error_text

contains

    !> A path under /tmp that no other test (nor a run of the same test) uses: `/tmp/<prefix><16 hex digits>`.
    function unique_tmp(prefix) result(path)
        !> The start of the file's name, e.g. "supratrans_test_map_".
        character(len=*), intent(in) :: prefix
        character(len=:), allocatable :: path
        character(len=16) :: tag
        real(wp) :: r
        integer(i8) :: count

        call random_seed()
        call random_number(r)
        call system_clock(count)
        write (tag, "(z0.8, z0.8)") int(r*2.0_wp**31, i8), int(modulo(count, 2_i8**31), i8)
        path = "/tmp/" // prefix // trim(tag)
    end function unique_tmp

    !> Whether a file exists.
    function path_exists(path) result(exists)
        !> The file.
        character(len=*), intent(in) :: path
        logical :: exists

        inquire (file=path, exist=exists)
    end function path_exists

    !> Delete a file if it exists (a test's cleanup: a file that cannot be deleted is left, silently).
    subroutine delete_file(path)
        !> The file.
        character(len=*), intent(in) :: path
        integer :: unit, stat

        if (.not. path_exists(path)) return
        open (newunit=unit, file=path, status="old", iostat=stat)
        if (stat == 0) close (unit, status="delete", iostat=stat)
    end subroutine delete_file

    !> The message of an error, for assertion messages ("no error" when there is none).
    function error_text(error) result(text)
        !> The error.
        type(error_type), allocatable, intent(in) :: error
        character(len=:), allocatable :: text

        if (allocated(error)) then
            text = error%message
        else
            text = "no error"
        end if
    end function error_text

end module supratrans_test_files
