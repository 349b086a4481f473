!> Writing HDF5 datasets, attributes and groups: every dataset with the string attributes `units` and
!> `description` (and `dimensions` when `dims` is given), every group with `description`.
!>
!> Object names are paths from the root group: "ledger/energy" and "/ledger/energy" are the same object; missing
!> intermediate groups are created. `h5_write` replaces an existing dataset of the same name (HDF5 does not reclaim
!> the space of the old one); `h5_write_attr` replaces an existing attribute. Arrays are stored as they are in
!> memory: h5py lists the Fortran dimensions reversed, so `dims` names them in C/h5py order ("probe, time" for a
!> Fortran array `a(ntime, nprobe)`). `real(wp)` is stored as IEEE 64-bit float, default integer as 32-bit signed
!> integer, `integer(i8)` as 64-bit, character as fixed-length, null-padded ASCII (trailing blanks of the elements
!> of a character array are padding and are not stored), logical attributes as integer 0 or 1.
module supratrans_h5_write
    use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_loc, c_char, c_null_char
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use hdf5, only: hid_t, hsize_t, h5dcreate_f, h5dopen_f, h5dwrite_f, h5screate_f, h5pset_create_inter_group_f, &
        h5tset_size_f, h5t_ieee_f64le, h5t_std_i64le, h5gcreate_f, h5oopen_f, h5ldelete_f, h5aexists_f, h5adelete_f, &
        h5acreate_f, h5awrite_f
    use supratrans_kinds, only: wp, i8
    use supratrans_error, only: error_type, fatal_error, err_io
    use supratrans_h5_file, only: h5_exists, real_mem_type, int_mem_type, int_file_type, i8_mem_type, disk_path, root_if_empty, &
        check, check_writable, check_dim_names, close_id, make_space, make_lcpl, make_string_type, h5_file
    implicit none
    private

    public :: h5_write, h5_write_attr, h5_create_group

    !> Write a dataset with the attributes `units` and `description` (and `dimensions` when `dims` is given):
    !> `call h5_write(file, name, data, units, description, error [, dims])`.
    !> `data`: `real(wp)` of rank 0 to 4, default integer of rank 0 to 3, `integer(i8)` of rank 0 or 1,
    !> character of rank 0 or 1. `dims` (arrays only): dimension names in C/h5py order, e.g. "probe, time".
    interface h5_write
        module procedure :: write_real_0d, write_real_1d, write_real_2d, write_real_3d, write_real_4d
        module procedure :: write_int_0d, write_int_1d, write_int_2d, write_int_3d, write_i8_0d, write_i8_1d
        module procedure :: write_char_0d, write_char_1d
    end interface h5_write

    !> Write an attribute `name` of the object `object` ("/" for the root group; a missing group is created):
    !> `call h5_write_attr(file, object, name, value, error)`. `value`: character scalar, `real(wp)` scalar or
    !> rank 1, default integer scalar or rank 1, `integer(i8)` scalar, logical scalar (stored as integer 0/1).
    interface h5_write_attr
        module procedure :: write_attr_char, write_attr_real_0d, write_attr_real_1d, write_attr_int_0d
        module procedure :: write_attr_int_1d, write_attr_i8_0d, write_attr_logical
    end interface h5_write_attr

contains

    !> Create a group (and missing intermediate groups) with the attribute `description`; if the group exists,
    !> only its description is (re)written.
    subroutine h5_create_group(file, name, description, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the group.
        character(len=*), intent(in) :: name
        !> What the group holds.
        character(len=*), intent(in) :: description
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hid_t) :: obj
        integer :: hdferr

        call open_or_create_group(file, name, obj, error)
        if (allocated(error)) return
        call put_string_attr(obj, "description", description, hdferr)
        call check(hdferr, file, "write attribute 'description' of group", name, "h5awrite_f", error)
        call close_id(obj)
    end subroutine h5_create_group

    !> Write a `real(wp)` scalar dataset.
    subroutine write_real_0d(file, name, data, units, description, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The value.
        real(wp), intent(in), target :: data
        !> Units ("1" for dimensionless).
        character(len=*), intent(in) :: units
        !> What the value is.
        character(len=*), intent(in) :: description
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error

        call write_dataset(file, name, real_mem_type(), h5t_ieee_f64le, [integer(hsize_t) ::], c_loc(data), units, &
            description, error)
    end subroutine write_real_0d

    !> Write a `real(wp)` rank-1 dataset.
    subroutine write_real_1d(file, name, data, units, description, error, dims)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The values.
        real(wp), intent(in), target, contiguous :: data(:)
        !> Units ("1" for dimensionless).
        character(len=*), intent(in) :: units
        !> What the values are.
        character(len=*), intent(in) :: description
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Name of the dimension, stored as attribute `dimensions`.
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, real_mem_type(), h5t_ieee_f64le, shape(data, kind=hsize_t), &
            buf, units, description, error, dims)
    end subroutine write_real_1d

    !> Write a `real(wp)` rank-2 dataset (h5py sees the dimensions reversed).
    subroutine write_real_2d(file, name, data, units, description, error, dims)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The values.
        real(wp), intent(in), target, contiguous :: data(:, :)
        !> Units ("1" for dimensionless).
        character(len=*), intent(in) :: units
        !> What the values are.
        character(len=*), intent(in) :: description
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Names of the dimensions in C/h5py order, e.g. "probe, time"; stored as attribute `dimensions`.
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, real_mem_type(), h5t_ieee_f64le, shape(data, kind=hsize_t), &
            buf, units, description, error, dims)
    end subroutine write_real_2d

    !> Write a `real(wp)` rank-3 dataset (h5py sees the dimensions reversed).
    subroutine write_real_3d(file, name, data, units, description, error, dims)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The values.
        real(wp), intent(in), target, contiguous :: data(:, :, :)
        !> Units ("1" for dimensionless).
        character(len=*), intent(in) :: units
        !> What the values are.
        character(len=*), intent(in) :: description
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Names of the dimensions in C/h5py order; stored as attribute `dimensions`.
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, real_mem_type(), h5t_ieee_f64le, shape(data, kind=hsize_t), &
            buf, units, description, error, dims)
    end subroutine write_real_3d

    !> Write a `real(wp)` rank-4 dataset (h5py sees the dimensions reversed).
    subroutine write_real_4d(file, name, data, units, description, error, dims)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The values.
        real(wp), intent(in), target, contiguous :: data(:, :, :, :)
        !> Units ("1" for dimensionless).
        character(len=*), intent(in) :: units
        !> What the values are.
        character(len=*), intent(in) :: description
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Names of the dimensions in C/h5py order; stored as attribute `dimensions`.
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, real_mem_type(), h5t_ieee_f64le, shape(data, kind=hsize_t), &
            buf, units, description, error, dims)
    end subroutine write_real_4d

    !> Write a default-integer scalar dataset.
    subroutine write_int_0d(file, name, data, units, description, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The value.
        integer, intent(in), target :: data
        !> Units ("1" for counts and flags).
        character(len=*), intent(in) :: units
        !> What the value is.
        character(len=*), intent(in) :: description
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error

        call write_dataset(file, name, int_mem_type(), int_file_type(), [integer(hsize_t) ::], c_loc(data), units, &
            description, error)
    end subroutine write_int_0d

    !> Write a default-integer rank-1 dataset.
    subroutine write_int_1d(file, name, data, units, description, error, dims)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The values.
        integer, intent(in), target, contiguous :: data(:)
        !> Units ("1" for counts and flags).
        character(len=*), intent(in) :: units
        !> What the values are.
        character(len=*), intent(in) :: description
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Name of the dimension, stored as attribute `dimensions`.
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, int_mem_type(), int_file_type(), shape(data, kind=hsize_t), &
            buf, units, description, error, dims)
    end subroutine write_int_1d

    !> Write a default-integer rank-2 dataset (h5py sees the dimensions reversed).
    subroutine write_int_2d(file, name, data, units, description, error, dims)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The values.
        integer, intent(in), target, contiguous :: data(:, :)
        !> Units ("1" for counts and flags).
        character(len=*), intent(in) :: units
        !> What the values are.
        character(len=*), intent(in) :: description
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Names of the dimensions in C/h5py order; stored as attribute `dimensions`.
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, int_mem_type(), int_file_type(), shape(data, kind=hsize_t), &
            buf, units, description, error, dims)
    end subroutine write_int_2d

    !> Write a default-integer rank-3 dataset.
    subroutine write_int_3d(file, name, data, units, description, error, dims)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The values.
        integer, intent(in), target, contiguous :: data(:, :, :)
        !> Units ("1" for counts and flags).
        character(len=*), intent(in) :: units
        !> What the values are.
        character(len=*), intent(in) :: description
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Names of the dimensions in C/h5py order; stored as attribute `dimensions`.
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, int_mem_type(), int_file_type(), shape(data, kind=hsize_t), &
            buf, units, description, error, dims)
    end subroutine write_int_3d

    !> Write an `integer(i8)` scalar dataset.
    subroutine write_i8_0d(file, name, data, units, description, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The value.
        integer(i8), intent(in), target :: data
        !> Units ("1" for counts).
        character(len=*), intent(in) :: units
        !> What the value is.
        character(len=*), intent(in) :: description
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error

        call write_dataset(file, name, i8_mem_type(), h5t_std_i64le, [integer(hsize_t) ::], c_loc(data), units, &
            description, error)
    end subroutine write_i8_0d

    !> Write an `integer(i8)` rank-1 dataset.
    subroutine write_i8_1d(file, name, data, units, description, error, dims)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The values.
        integer(i8), intent(in), target, contiguous :: data(:)
        !> Units ("1" for counts).
        character(len=*), intent(in) :: units
        !> What the values are.
        character(len=*), intent(in) :: description
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Name of the dimension, stored as attribute `dimensions`.
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, i8_mem_type(), h5t_std_i64le, shape(data, kind=hsize_t), buf, units, &
            description, error, dims)
    end subroutine write_i8_1d

    !> Write a character scalar as a fixed-length string dataset.
    subroutine write_char_0d(file, name, data, units, description, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The string (stored as given, trailing blanks included).
        character(len=*), intent(in) :: data
        !> Units ("1" or "" for text).
        character(len=*), intent(in) :: units
        !> What the string is.
        character(len=*), intent(in) :: description
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error

        call write_strings(file, name, [data], .false., units, description, error)
    end subroutine write_char_0d

    !> Write a character array as a rank-1 fixed-length string dataset (trailing blanks are not stored).
    subroutine write_char_1d(file, name, data, units, description, error, dims)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The strings.
        character(len=*), intent(in) :: data(:)
        !> Units ("1" or "" for text).
        character(len=*), intent(in) :: units
        !> What the strings are.
        character(len=*), intent(in) :: description
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Name of the dimension, stored as attribute `dimensions`.
        character(len=*), intent(in), optional :: dims

        call write_strings(file, name, data, .true., units, description, error, dims)
    end subroutine write_char_1d

    !> Write a string attribute.
    subroutine write_attr_char(file, object, name, value, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> The value.
        character(len=*), intent(in) :: value
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hid_t) :: obj
        integer :: hdferr

        call open_attr_owner(file, object, name, obj, error)
        if (allocated(error)) return
        call put_string_attr(obj, name, value, hdferr)
        call check(hdferr, file, "write attribute '"//name//"' of", object, "h5awrite_f", error)
        call close_id(obj)
    end subroutine write_attr_char

    !> Write a `real(wp)` scalar attribute.
    subroutine write_attr_real_0d(file, object, name, value, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> The value.
        real(wp), intent(in), target :: value
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error

        call write_attr(file, object, name, real_mem_type(), h5t_ieee_f64le, [integer(hsize_t) ::], c_loc(value), &
            error)
    end subroutine write_attr_real_0d

    !> Write a `real(wp)` rank-1 attribute.
    subroutine write_attr_real_1d(file, object, name, value, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> The values.
        real(wp), intent(in), target, contiguous :: value(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(value) > 0) buf = c_loc(value)
        call write_attr(file, object, name, real_mem_type(), h5t_ieee_f64le, shape(value, kind=hsize_t), &
            buf, error)
    end subroutine write_attr_real_1d

    !> Write a default-integer scalar attribute.
    subroutine write_attr_int_0d(file, object, name, value, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> The value.
        integer, intent(in), target :: value
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error

        call write_attr(file, object, name, int_mem_type(), int_file_type(), [integer(hsize_t) ::], c_loc(value), &
            error)
    end subroutine write_attr_int_0d

    !> Write a default-integer rank-1 attribute.
    subroutine write_attr_int_1d(file, object, name, value, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> The values.
        integer, intent(in), target, contiguous :: value(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(value) > 0) buf = c_loc(value)
        call write_attr(file, object, name, int_mem_type(), int_file_type(), shape(value, kind=hsize_t), &
            buf, error)
    end subroutine write_attr_int_1d

    !> Write an `integer(i8)` scalar attribute.
    subroutine write_attr_i8_0d(file, object, name, value, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> The value.
        integer(i8), intent(in), target :: value
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error

        call write_attr(file, object, name, i8_mem_type(), h5t_std_i64le, [integer(hsize_t) ::], c_loc(value), error)
    end subroutine write_attr_i8_0d

    !> Write a logical attribute, stored as 32-bit integer 0 (false) or 1 (true).
    subroutine write_attr_logical(file, object, name, value, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> The value.
        logical, intent(in) :: value
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error

        call write_attr_int_0d(file, object, name, merge(1, 0, value), error)
    end subroutine write_attr_logical

    !> Create or replace an attribute of the object `obj` and write it from `buf`.
    subroutine put_attr(obj, name, mem_type, file_type, dims, buf, hdferr)
        !> The object (group, dataset).
        integer(hid_t), intent(in) :: obj
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> Datatype of the data in memory.
        integer(hid_t), intent(in) :: mem_type
        !> Datatype in the file.
        integer(hid_t), intent(in) :: file_type
        !> Dimensions in Fortran order; empty for a scalar.
        integer(hsize_t), intent(in) :: dims(:)
        !> Address of the data (may be null when there are no elements).
        type(c_ptr), intent(in) :: buf
        !> HDF5 status.
        integer, intent(out) :: hdferr
        integer(hid_t) :: space, attr
        logical :: exists

        space = -1
        attr = -1
        body: block
            call h5aexists_f(obj, name, exists, hdferr)
            if (hdferr < 0) exit body
            if (exists) then
                call h5adelete_f(obj, name, hdferr)
                if (hdferr < 0) exit body
            end if
            call make_space(dims, space, hdferr)
            if (hdferr < 0) exit body
            call h5acreate_f(obj, name, file_type, space, attr, hdferr)
            if (hdferr < 0) exit body
            if (product(dims) > 0) call h5awrite_f(attr, mem_type, buf, hdferr)
        end block body
        call close_id(attr)
        call close_id(space)
    end subroutine put_attr

    !> Create or replace a scalar string attribute of the object `obj`.
    subroutine put_string_attr(obj, name, value, hdferr)
        !> The object (group, dataset).
        integer(hid_t), intent(in) :: obj
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> The string.
        character(len=*), intent(in) :: value
        !> HDF5 status.
        integer, intent(out) :: hdferr
        character(kind=c_char, len=1), allocatable, target :: chars(:)
        integer(hid_t) :: string_type
        integer :: k
        type(c_ptr) :: buf

        allocate (chars(max(len(value), 1)))
        chars = c_null_char
        do k = 1, len(value)
            chars(k) = value(k:k)
        end do
        call make_string_type(len(value), string_type, hdferr)
        buf = c_loc(chars)
        if (hdferr >= 0) call put_attr(obj, name, string_type, string_type, [integer(hsize_t) ::], buf, hdferr)
        call close_id(string_type)
    end subroutine put_string_attr

    !> Write the attributes `units`, `description` and (if present) `dimensions` of a dataset.
    subroutine describe_object(obj, units, description, hdferr, dim_names)
        !> The dataset.
        integer(hid_t), intent(in) :: obj
        !> Units.
        character(len=*), intent(in) :: units
        !> Description.
        character(len=*), intent(in) :: description
        !> HDF5 status.
        integer, intent(out) :: hdferr
        !> Dimension names in C/h5py order.
        character(len=*), intent(in), optional :: dim_names

        call put_string_attr(obj, "units", units, hdferr)
        if (hdferr < 0) return
        call put_string_attr(obj, "description", description, hdferr)
        if (hdferr < 0) return
        if (present(dim_names)) call put_string_attr(obj, "dimensions", dim_names, hdferr)
    end subroutine describe_object

    !> Open the object `object`, creating it as a group (with intermediate groups) if it does not exist.
    subroutine open_or_create_group(file, object, obj, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> The open object; -1 on failure.
        integer(hid_t), intent(out) :: obj
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hid_t) :: lcpl
        integer :: hdferr

        obj = -1
        call check_writable(file, "write to", object, error)
        if (allocated(error)) return
        if (h5_exists(file, object)) then
            call h5oopen_f(file%id, root_if_empty(object), obj, hdferr)
            call check(hdferr, file, "open object", object, "h5oopen_f", error)
        else
            call make_lcpl(lcpl, hdferr)
            call check(hdferr, file, "create link properties for", object, "h5pset_create_inter_group_f", error)
            if (.not. allocated(error)) then
                call h5gcreate_f(file%id, object, obj, hdferr, lcpl_id=lcpl)
                call check(hdferr, file, "create group", object, "h5gcreate_f", error)
            end if
            call close_id(lcpl)
        end if
        if (allocated(error)) obj = -1
    end subroutine open_or_create_group

    !> Open the owner of an attribute (creating a missing group) and check the attribute name.
    subroutine open_attr_owner(file, object, name, obj, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> The open object.
        integer(hid_t), intent(out) :: obj
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error

        obj = -1
        if (len_trim(name) == 0) then
            call fatal_error(error, disk_path(file)//": empty attribute name for '"//object//"'", err_io)
            return
        end if
        call open_or_create_group(file, object, obj, error)
    end subroutine open_attr_owner

    !> Write a numeric attribute of the object `object`.
    subroutine write_attr(file, object, name, mem_type, file_type, dims, buf, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> Datatype in memory.
        integer(hid_t), intent(in) :: mem_type
        !> Datatype in the file.
        integer(hid_t), intent(in) :: file_type
        !> Dimensions; empty for a scalar.
        integer(hsize_t), intent(in) :: dims(:)
        !> Address of the data.
        type(c_ptr), intent(in) :: buf
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hid_t) :: obj
        integer :: hdferr

        call open_attr_owner(file, object, name, obj, error)
        if (allocated(error)) return
        call put_attr(obj, name, mem_type, file_type, dims, buf, hdferr)
        call check(hdferr, file, "write attribute '"//name//"' of", object, "h5awrite_f", error)
        call close_id(obj)
    end subroutine write_attr

    !> Prepare writing dataset `name`: check the file and the dimension names, unlink an existing dataset.
    subroutine prepare_dataset(file, name, rank, dim_names, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> Rank of the dataset.
        integer, intent(in) :: rank
        !> Dimension names in C/h5py order.
        character(len=*), intent(in), optional :: dim_names
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hid_t) :: dset
        integer :: hdferr

        call check_writable(file, "write dataset", name, error)
        if (allocated(error)) return
        if (present(dim_names)) then
            call check_dim_names(file, name, dim_names, rank, error)
            if (allocated(error)) return
        end if
        if (.not. h5_exists(file, name)) return
        call h5dopen_f(file%id, name, dset, hdferr)
        if (hdferr < 0) then
            call fatal_error(error, disk_path(file)//": cannot write dataset '"//name// &
                "': an object of that name exists and is not a dataset", err_io)
            return
        end if
        call close_id(dset)
        call h5ldelete_f(file%id, name, hdferr)
        call check(hdferr, file, "replace dataset", name, "h5ldelete_f", error)
    end subroutine prepare_dataset

    !> Create dataset `name` (replacing an existing one), write it from `buf` and describe it.
    subroutine write_dataset(file, name, mem_type, file_type, dims, buf, units, description, error, dim_names)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> Datatype in memory.
        integer(hid_t), intent(in) :: mem_type
        !> Datatype in the file.
        integer(hid_t), intent(in) :: file_type
        !> Dimensions in Fortran order; empty for a scalar.
        integer(hsize_t), intent(in) :: dims(:)
        !> Address of the data (may be null when there are no elements).
        type(c_ptr), intent(in) :: buf
        !> Units.
        character(len=*), intent(in) :: units
        !> Description.
        character(len=*), intent(in) :: description
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Dimension names in C/h5py order.
        character(len=*), intent(in), optional :: dim_names
        integer(hid_t) :: space, lcpl, dset
        integer :: hdferr

        call prepare_dataset(file, name, size(dims), dim_names, error)
        if (allocated(error)) return
        space = -1
        lcpl = -1
        dset = -1
        body: block
            call make_space(dims, space, hdferr)
            call check(hdferr, file, "create dataspace of", name, "h5screate_f", error)
            if (allocated(error)) exit body
            call make_lcpl(lcpl, hdferr)
            call check(hdferr, file, "create link properties for", name, "h5pset_create_inter_group_f", error)
            if (allocated(error)) exit body
            call h5dcreate_f(file%id, name, file_type, space, dset, hdferr, lcpl_id=lcpl)
            call check(hdferr, file, "create dataset", name, "h5dcreate_f", error)
            if (allocated(error)) exit body
            if (product(dims) > 0) then
                call h5dwrite_f(dset, mem_type, buf, hdferr)
                call check(hdferr, file, "write dataset", name, "h5dwrite_f", error)
                if (allocated(error)) exit body
            end if
            call describe_object(dset, units, description, hdferr, dim_names)
            call check(hdferr, file, "write attributes of dataset", name, "h5awrite_f", error)
        end block body
        call close_id(dset)
        call close_id(lcpl)
        call close_id(space)
    end subroutine write_dataset

    !> Write strings as a fixed-length string dataset: scalar (`array` false, one string) or rank 1.
    subroutine write_strings(file, name, data, array, units, description, error, dim_names)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The strings.
        character(len=*), intent(in) :: data(:)
        !> Rank-1 dataset (trailing blanks dropped) or scalar (string stored as given).
        logical, intent(in) :: array
        !> Units.
        character(len=*), intent(in) :: units
        !> Description.
        character(len=*), intent(in) :: description
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Dimension name.
        character(len=*), intent(in), optional :: dim_names
        character(kind=c_char, len=1), allocatable, target :: chars(:)
        integer(hsize_t), allocatable :: dims(:)
        integer(hid_t) :: string_type
        integer :: hdferr, width, i, k, n
        ! c_loc of a character array is stored first: passed directly, gfortran 12 adds a spurious hidden length.
        type(c_ptr) :: buf

        width = max(len(data), 1)
        allocate (chars(width*max(size(data), 1)))
        chars = c_null_char
        do i = 1, size(data)
            n = len(data(i))
            if (array) n = len_trim(data(i))
            do k = 1, n
                chars((i - 1)*width + k) = data(i) (k:k)
            end do
        end do
        if (array) then
            dims = [int(size(data), hsize_t)]
        else
            allocate (dims(0))
        end if
        call make_string_type(width, string_type, hdferr)
        call check(hdferr, file, "create string type for", name, "h5tset_size_f", error)
        if (.not. allocated(error)) then
            buf = c_loc(chars)
            call write_dataset(file, name, string_type, string_type, dims, buf, units, description, error, &
                dim_names)
        end if
        call close_id(string_type)
    end subroutine write_strings

end module supratrans_h5_write
