!> supratrans <input.nml>: run the study a namelist file describes and write its HDF5 output.
!> Exit status: 0 success, 2 bad input, 3 a run failed fatally, 4 output could not be written.
program main
    use, intrinsic :: iso_fortran_env, only: error_unit
    use supratrans_error, only: error_type
    use supratrans_cli, only: run_from_file, usage
    implicit none
    character(len=:), allocatable :: path
    type(error_type), allocatable :: error
    integer :: length, status

    if (command_argument_count() /= 1) then
        write (error_unit, '(a)') usage
        stop 2, quiet=.true.
    end if
    call get_command_argument(1, length=length)
    allocate (character(len=length) :: path)
    call get_command_argument(1, path)
    call run_from_file(path, status, error)
    if (allocated(error)) write (error_unit, '(a)') "error: " // error%message
    if (status /= 0) stop status, quiet=.true.
end program main
