!> Working precision and the few constants shared by every module of supratrans.
module supratrans_kinds
    use, intrinsic :: iso_fortran_env, only: real64, int64
    implicit none
    private

    !> Working precision: IEEE double, the precision LAPACK `dgtsv` works in.
    integer, parameter, public :: wp = real64
    !> Kind of 64-bit integers (step counters of long sweeps).
    integer, parameter, public :: i8 = int64
    !> The number pi to working precision.
    real(wp), parameter, public :: pi = 3.141592653589793238462643383279502884_wp
    !> Length of fixed-size character variables (keys, names, file paths).
    integer, parameter, public :: name_len = 64
    !> Length of character variables that hold file paths.
    integer, parameter, public :: path_len = 512
    !> Version of the code, written into every output file.
    character(len=*), parameter, public :: supratrans_version = "0.1.0"

end module supratrans_kinds
