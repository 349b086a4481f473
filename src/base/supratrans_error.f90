!> Errors travel as values: a routine that can fail takes an allocatable `error_type`, allocated only on failure.
!> Library code never stops the program; the application prints the message and chooses the exit status.
module supratrans_error
    implicit none
    private

    public :: error_type, fatal_error

    !> Error codes: the exit status the application gives for each class of error.
    integer, parameter, public :: err_input = 2     !< bad input: namelist, file, parameter out of range
    integer, parameter, public :: err_runtime = 3   !< a run failed (divergence, Newton failure) where that is fatal
    integer, parameter, public :: err_io = 4        !< reading or writing an output file failed
    integer, parameter, public :: err_interrupted = 5  !< stopped by a signal (SIGTERM, SIGINT, SIGUSR1); run again to resume

    !> An error: a code (the exit status) and a one-line message that names what is wrong.
    type :: error_type
        !> Exit status class (`err_input`, `err_runtime`, `err_io`).
        integer :: stat = err_input
        !> One-line human-readable message.
        character(len=:), allocatable :: message
    end type error_type

contains

    !> Allocate `error` with a message and an optional status (default `err_input`).
    pure subroutine fatal_error(error, message, stat)
        !> The error to create; allocated on return.
        type(error_type), allocatable, intent(out) :: error
        !> What went wrong, in one line.
        character(len=*), intent(in) :: message
        !> Status class; default `err_input`.
        integer, intent(in), optional :: stat

        allocate (error)
        error%message = message
        if (present(stat)) error%stat = stat
    end subroutine fatal_error

end module supratrans_error
