!> supratrans: run the study a namelist file describes and write its HDF5 output (`supratrans --help`).
!> Exit status: 0 success, 2 bad input or command line, 3 a run failed fatally, 4 output could not be written,
!> 5 stopped by a signal (run the same command again to resume).
program main
    use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
    use supratrans_error, only: error_type
    use supratrans_cli, only: run_command, printable
    implicit none
    character(len=:), allocatable :: args(:), text
    type(error_type), allocatable :: error
    integer :: i, length, longest, status

    longest = 1
    do i = 1, command_argument_count()
        call get_command_argument(i, length=length)
        longest = max(longest, length)
    end do
    allocate (character(len=longest) :: args(command_argument_count()))
    do i = 1, size(args)
        call get_command_argument(i, args(i))
    end do
    call run_command(args, status, error, text)
    if (len(text) > 0) write (output_unit, "(a)") text
    if (allocated(error)) write (error_unit, "(a)") "error: " // printable(error%message)
    flush (error_unit)          ! the line reaches a redirected stderr whatever happens at exit
    deallocate (args, text)
    if (allocated(error)) deallocate (error)
    if (status /= 0) stop status, quiet=.true.
end program main
