!> The HDF5 layer as the tests see it: everything of `supratrans_hdf5`, `h5_discard` and `h5_failed` (a file dropped
!> unwritten, whether an error stuck: only the tests ask), and `h5_read` and `h5_read_attr` extended by the types only
!> the tests read back (the program reads just what `merge`, `--check` and the benchmark need). Built on `h5_shape`
!> and `h5_read_into` of `supratrans_h5_read`, with its messages.
module supratrans_h5_test
    use, intrinsic :: iso_c_binding, only: c_loc
    use hdf5, only: hsize_t
    use supratrans_kinds, only: wp, i8
    use supratrans_error, only: error_type
    use supratrans_hdf5, only: h5_file, h5_create, h5_commit, h5_open, h5_close, h5_write, h5_write_attr, &
        h5_create_group, h5_exists, h5_attr_exists, h5_read, h5_read_attr
    use supratrans_h5_file, only: h5_discard, real_mem_type, int_mem_type, i8_mem_type
    use supratrans_h5_read, only: h5_shape, h5_read_into, h5_read_strings
    implicit none
    private

    public :: h5_file, h5_create, h5_commit, h5_discard, h5_failed, h5_open, h5_close
    public :: h5_write, h5_write_attr, h5_create_group
    public :: h5_exists, h5_attr_exists, h5_read, h5_read_attr

    !> `h5_read` of `supratrans_hdf5`, and `real(wp)` scalar or rank 3, default integer and `integer(i8)` scalar,
    !> `integer(i8)` rank 1, deferred-length character rank 1.
    interface h5_read
        module procedure :: read_real_0d, read_real_3d, read_int_0d, read_i8_0d, read_i8_1d, read_char_1d
    end interface h5_read

    !> `h5_read_attr` of `supratrans_hdf5`, and `real(wp)` scalar or rank 1, default integer rank 1, `integer(i8)`
    !> and logical scalar (non-zero is true).
    interface h5_read_attr
        module procedure :: read_attr_real_1d, read_attr_int_1d, read_attr_i8_0d, read_attr_logical
    end interface h5_read_attr

contains

    !> Whether an error stuck in the file (then every write does nothing and `h5_commit` refuses).
    pure logical function h5_failed(file)
        !> The file.
        type(h5_file), intent(in) :: file

        h5_failed = allocated(file%error)
    end function h5_failed

    subroutine read_real_0d(file, name, data, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: name
        real(wp), intent(out), target :: data
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        data = 0.0_wp
        call h5_shape(file, name, "", 0, dims, error)
        if (.not. allocated(error)) call h5_read_into(file, name, "", real_mem_type(), c_loc(data), error)
    end subroutine read_real_0d

    subroutine read_real_3d(file, name, data, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: name
        real(wp), allocatable, target, intent(out) :: data(:, :, :)
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        call h5_shape(file, name, "", 3, dims, error)
        if (allocated(error)) return
        allocate (data(dims(1), dims(2), dims(3)))
        if (size(data) > 0) call h5_read_into(file, name, "", real_mem_type(), c_loc(data), error)
    end subroutine read_real_3d

    subroutine read_int_0d(file, name, data, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: name
        integer, intent(out), target :: data
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        data = 0
        call h5_shape(file, name, "", 0, dims, error)
        if (.not. allocated(error)) call h5_read_into(file, name, "", int_mem_type(), c_loc(data), error)
    end subroutine read_int_0d

    subroutine read_i8_0d(file, name, data, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: name
        integer(i8), intent(out), target :: data
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        data = 0
        call h5_shape(file, name, "", 0, dims, error)
        if (.not. allocated(error)) call h5_read_into(file, name, "", i8_mem_type(), c_loc(data), error)
    end subroutine read_i8_0d

    subroutine read_i8_1d(file, name, data, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: name
        integer(i8), allocatable, target, intent(out) :: data(:)
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        call h5_shape(file, name, "", 1, dims, error)
        if (allocated(error)) return
        allocate (data(dims(1)))
        if (size(data) > 0) call h5_read_into(file, name, "", i8_mem_type(), c_loc(data), error)
    end subroutine read_i8_1d

    subroutine read_char_1d(file, name, data, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: name
        character(len=:), allocatable, intent(out) :: data(:)
        type(error_type), allocatable, intent(out) :: error

        call h5_read_strings(file, name, "", data, error)
    end subroutine read_char_1d

    subroutine read_attr_real_1d(file, object, name, value, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: object, name
        real(wp), allocatable, target, intent(out) :: value(:)
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        call h5_shape(file, object, name, 1, dims, error)
        if (allocated(error)) return
        allocate (value(dims(1)))
        if (size(value) > 0) call h5_read_into(file, object, name, real_mem_type(), c_loc(value), error)
    end subroutine read_attr_real_1d

    subroutine read_attr_int_1d(file, object, name, value, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: object, name
        integer, allocatable, target, intent(out) :: value(:)
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        call h5_shape(file, object, name, 1, dims, error)
        if (allocated(error)) return
        allocate (value(dims(1)))
        if (size(value) > 0) call h5_read_into(file, object, name, int_mem_type(), c_loc(value), error)
    end subroutine read_attr_int_1d

    subroutine read_attr_i8_0d(file, object, name, value, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: object, name
        integer(i8), intent(out), target :: value
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        value = 0
        call h5_shape(file, object, name, 0, dims, error)
        if (.not. allocated(error)) call h5_read_into(file, object, name, i8_mem_type(), c_loc(value), error)
    end subroutine read_attr_i8_0d

    subroutine read_attr_logical(file, object, name, value, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: object, name
        logical, intent(out) :: value
        type(error_type), allocatable, intent(out) :: error
        integer :: stored

        call h5_read_attr(file, object, name, stored, error)
        value = stored /= 0
    end subroutine read_attr_logical

end module supratrans_h5_test
