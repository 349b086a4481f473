!> Reading HDF5 datasets and attributes back (what `merge`, the `--check`/resume test of a finished output and the
!> benchmark need, and the Fortran tests), converting numeric types by HDF5's rules. Strings are read as this layer
!> writes them, fixed-length; a variable-length string (h5py's default) is refused as "not a fixed-length string".
!> Arrays come back in their Fortran shape (the reverse of the h5py shape); a logical attribute is true for any
!> non-zero value.
module supratrans_h5_read
    use, intrinsic :: iso_c_binding, only: c_ptr, c_loc, c_char, c_null_char
    use hdf5, only: hid_t, hsize_t, size_t, h5dopen_f, h5dread_f, h5dget_space_f, h5dget_type_f, &
        h5sget_simple_extent_ndims_f, h5sget_simple_extent_dims_f, h5sget_simple_extent_npoints_f, &
        h5tget_size_f, h5tget_strpad_f, h5tget_class_f, h5tis_variable_str_f, h5t_string_f, h5t_str_spacepad_f, &
        h5aopen_by_name_f, h5aread_f, h5aget_space_f, h5aget_type_f
    use supratrans_kinds, only: wp, i8
    use supratrans_error, only: error_type, fatal_error, err_io
    use supratrans_strings, only: int_str
    use supratrans_h5_file, only: h5_exists, h5_attr_exists, real_mem_type, int_mem_type, i8_mem_type, disk_path, &
        root_if_empty, check, check_open, close_id, h5_file
    implicit none
    private

    public :: h5_read, h5_read_attr

    !> Read a whole dataset: `call h5_read(file, name, data, error)`, converting numeric types.
    !> `data`: `real(wp)` scalar or allocatable of rank 1 to 3, default integer scalar or allocatable of rank 1 or 2,
    !> `integer(i8)` scalar or allocatable rank 1, deferred-length allocatable character scalar or rank 1.
    interface h5_read
        module procedure :: read_real_0d, read_real_1d, read_real_2d, read_real_3d
        module procedure :: read_int_0d, read_int_1d, read_int_2d, read_i8_0d, read_i8_1d
        module procedure :: read_char_0d, read_char_1d
    end interface h5_read

    !> Read an attribute: `call h5_read_attr(file, object, name, value, error)`. `value`: deferred-length
    !> allocatable character, `real(wp)` scalar or allocatable rank 1, default integer scalar or allocatable rank 1,
    !> `integer(i8)` scalar, logical scalar.
    interface h5_read_attr
        module procedure :: read_attr_char, read_attr_real_0d, read_attr_real_1d, read_attr_int_0d
        module procedure :: read_attr_int_1d, read_attr_i8_0d, read_attr_logical
    end interface h5_read_attr

    !> A list of strings (works around spurious gfortran warnings on local deferred-length character arrays).
    type :: string_array
        !> The strings.
        character(len=:), allocatable :: items(:)
    end type string_array

contains

    !> Read a `real(wp)` scalar (a scalar dataset or one with a single element).
    subroutine read_real_0d(file, name, data, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The value.
        real(wp), intent(out), target :: data
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        data = 0.0_wp
        call query_dataset(file, name, 0, dims, error)
        if (allocated(error)) return
        call read_dataset(file, name, real_mem_type(), c_loc(data), error)
    end subroutine read_real_0d

    !> Read a `real(wp)` rank-1 dataset.
    subroutine read_real_1d(file, name, data, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The values.
        real(wp), allocatable, target, intent(out) :: data(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        call query_dataset(file, name, 1, dims, error)
        if (allocated(error)) return
        allocate (data(dims(1)))
        if (size(data) > 0) call read_dataset(file, name, real_mem_type(), c_loc(data), error)
    end subroutine read_real_1d

    !> Read a `real(wp)` rank-2 dataset (Fortran shape, the reverse of the h5py shape).
    subroutine read_real_2d(file, name, data, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The values.
        real(wp), allocatable, target, intent(out) :: data(:, :)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        call query_dataset(file, name, 2, dims, error)
        if (allocated(error)) return
        allocate (data(dims(1), dims(2)))
        if (size(data) > 0) call read_dataset(file, name, real_mem_type(), c_loc(data), error)
    end subroutine read_real_2d

    !> Read a `real(wp)` rank-3 dataset (Fortran shape, the reverse of the h5py shape).
    subroutine read_real_3d(file, name, data, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The values.
        real(wp), allocatable, target, intent(out) :: data(:, :, :)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        call query_dataset(file, name, 3, dims, error)
        if (allocated(error)) return
        allocate (data(dims(1), dims(2), dims(3)))
        if (size(data) > 0) call read_dataset(file, name, real_mem_type(), c_loc(data), error)
    end subroutine read_real_3d

    !> Read a default-integer scalar.
    subroutine read_int_0d(file, name, data, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The value.
        integer, intent(out), target :: data
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        data = 0
        call query_dataset(file, name, 0, dims, error)
        if (allocated(error)) return
        call read_dataset(file, name, int_mem_type(), c_loc(data), error)
    end subroutine read_int_0d

    !> Read a default-integer rank-1 dataset.
    subroutine read_int_1d(file, name, data, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The values.
        integer, allocatable, target, intent(out) :: data(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        call query_dataset(file, name, 1, dims, error)
        if (allocated(error)) return
        allocate (data(dims(1)))
        if (size(data) > 0) call read_dataset(file, name, int_mem_type(), c_loc(data), error)
    end subroutine read_int_1d

    !> Read a default-integer rank-2 dataset (Fortran shape).
    subroutine read_int_2d(file, name, data, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The values.
        integer, allocatable, target, intent(out) :: data(:, :)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        call query_dataset(file, name, 2, dims, error)
        if (allocated(error)) return
        allocate (data(dims(1), dims(2)))
        if (size(data) > 0) call read_dataset(file, name, int_mem_type(), c_loc(data), error)
    end subroutine read_int_2d

    !> Read an `integer(i8)` scalar.
    subroutine read_i8_0d(file, name, data, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The value.
        integer(i8), intent(out), target :: data
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        data = 0
        call query_dataset(file, name, 0, dims, error)
        if (allocated(error)) return
        call read_dataset(file, name, i8_mem_type(), c_loc(data), error)
    end subroutine read_i8_0d

    !> Read an `integer(i8)` rank-1 dataset.
    subroutine read_i8_1d(file, name, data, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The values.
        integer(i8), allocatable, target, intent(out) :: data(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        call query_dataset(file, name, 1, dims, error)
        if (allocated(error)) return
        allocate (data(dims(1)))
        if (size(data) > 0) call read_dataset(file, name, i8_mem_type(), c_loc(data), error)
    end subroutine read_i8_1d

    !> Read a string dataset (fixed or variable length) holding one string.
    subroutine read_char_0d(file, name, data, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The string, without padding.
        character(len=:), allocatable, intent(out) :: data
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        type(string_array) :: values

        call read_strings(file, name, "", values%items, error)
        if (allocated(error)) return
        if (size(values%items) /= 1) then
            call fatal_error(error, disk_path(file)//": dataset '"//name//"' holds "//int_str(size(values%items))// &
                " strings, expected one", err_io)
            return
        end if
        data = values%items(1)
    end subroutine read_char_0d

    !> Read a string dataset (fixed or variable length) into an array, each element blank-padded.
    subroutine read_char_1d(file, name, data, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The strings; their length is that of the longest one.
        character(len=:), allocatable, intent(out) :: data(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error

        call read_strings(file, name, "", data, error)
    end subroutine read_char_1d

    !> Read a string attribute (fixed or variable length) holding one string.
    subroutine read_attr_char(file, object, name, value, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> The string, without padding.
        character(len=:), allocatable, intent(out) :: value
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        type(string_array) :: values

        call read_strings(file, object, name, values%items, error)
        if (allocated(error)) return
        if (size(values%items) /= 1) then
            call fatal_error(error, disk_path(file)//": attribute '"//name//"' of '"//object//"' holds "// &
                int_str(size(values%items))//" strings, expected one", err_io)
            return
        end if
        value = values%items(1)
    end subroutine read_attr_char

    !> Read a `real(wp)` scalar attribute.
    subroutine read_attr_real_0d(file, object, name, value, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> The value.
        real(wp), intent(out), target :: value
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        value = 0.0_wp
        call query_attr(file, object, name, 0, dims, error)
        if (allocated(error)) return
        call read_attr(file, object, name, real_mem_type(), c_loc(value), error)
    end subroutine read_attr_real_0d

    !> Read a `real(wp)` rank-1 attribute.
    subroutine read_attr_real_1d(file, object, name, value, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> The values.
        real(wp), allocatable, target, intent(out) :: value(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        call query_attr(file, object, name, 1, dims, error)
        if (allocated(error)) return
        allocate (value(dims(1)))
        if (size(value) > 0) call read_attr(file, object, name, real_mem_type(), c_loc(value), error)
    end subroutine read_attr_real_1d

    !> Read a default-integer scalar attribute.
    subroutine read_attr_int_0d(file, object, name, value, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> The value.
        integer, intent(out), target :: value
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        value = 0
        call query_attr(file, object, name, 0, dims, error)
        if (allocated(error)) return
        call read_attr(file, object, name, int_mem_type(), c_loc(value), error)
    end subroutine read_attr_int_0d

    !> Read a default-integer rank-1 attribute.
    subroutine read_attr_int_1d(file, object, name, value, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> The values.
        integer, allocatable, target, intent(out) :: value(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        call query_attr(file, object, name, 1, dims, error)
        if (allocated(error)) return
        allocate (value(dims(1)))
        if (size(value) > 0) call read_attr(file, object, name, int_mem_type(), c_loc(value), error)
    end subroutine read_attr_int_1d

    !> Read an `integer(i8)` scalar attribute.
    subroutine read_attr_i8_0d(file, object, name, value, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> The value.
        integer(i8), intent(out), target :: value
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        value = 0
        call query_attr(file, object, name, 0, dims, error)
        if (allocated(error)) return
        call read_attr(file, object, name, i8_mem_type(), c_loc(value), error)
    end subroutine read_attr_i8_0d

    !> Read a logical attribute (an integer attribute; non-zero is true).
    subroutine read_attr_logical(file, object, name, value, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> The value.
        logical, intent(out) :: value
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer :: stored

        call read_attr_int_0d(file, object, name, stored, error)
        value = stored /= 0
    end subroutine read_attr_logical

    !> Read the whole dataset `name` into the memory at `buf` (sized by the caller).
    subroutine read_dataset(file, name, mem_type, buf, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> Datatype in memory.
        integer(hid_t), intent(in) :: mem_type
        !> Address of the destination.
        type(c_ptr), intent(in) :: buf
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hid_t) :: dset
        type(c_ptr) :: dest
        integer :: hdferr

        dest = buf
        call h5dopen_f(file%id, name, dset, hdferr)
        call check(hdferr, file, "open dataset", name, "h5dopen_f", error)
        if (allocated(error)) return
        call h5dread_f(dset, mem_type, dest, hdferr)
        call check(hdferr, file, "read dataset", name, "h5dread_f", error)
        call close_id(dset)
    end subroutine read_dataset

    !> Read the whole attribute `name` of `object` into the memory at `buf` (sized by the caller).
    subroutine read_attr(file, object, name, mem_type, buf, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the object.
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> Datatype in memory.
        integer(hid_t), intent(in) :: mem_type
        !> Address of the destination.
        type(c_ptr), intent(in) :: buf
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hid_t) :: attr
        type(c_ptr) :: dest
        integer :: hdferr

        dest = buf
        call open_attr(file, object, name, attr, error)
        if (allocated(error)) return
        call h5aread_f(attr, mem_type, dest, hdferr)
        call check(hdferr, file, "read attribute '"//name//"' of", object, "h5aread_f", error)
        call close_id(attr)
    end subroutine read_attr

    !> Read the strings of dataset `object` (when `attr_name` is empty) or of its attribute `attr_name`.
    subroutine read_strings(file, object, attr_name, values, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset or of the attribute's object.
        character(len=*), intent(in) :: object
        !> Name of the attribute; empty to read the dataset.
        character(len=*), intent(in) :: attr_name
        !> The strings, blank-padded to the longest.
        character(len=:), allocatable, intent(out) :: values(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hid_t) :: id
        integer :: hdferr
        logical :: is_attr
        character(len=:), allocatable :: what

        is_attr = len(attr_name) > 0
        id = -1
        if (is_attr) then
            what = "read attribute '"//attr_name//"' of"
            call open_attr(file, object, attr_name, id, error)
            if (allocated(error)) return
        else
            what = "read dataset"
            call check_open(file, what, object, error)
            if (allocated(error)) return
            if (.not. h5_exists(file, object)) then
                call fatal_error(error, disk_path(file)//": no dataset '"//object//"'", err_io)
                return
            end if
            call h5dopen_f(file%id, object, id, hdferr)
            call check(hdferr, file, "open dataset", object, "h5dopen_f", error)
            if (allocated(error)) return
        end if
        call read_string_values(id, is_attr, values, hdferr)
        if (hdferr == -2) then
            call fatal_error(error, disk_path(file)//": cannot "//what//" '"//object//"' as text: not a fixed-length "// &
                "string", err_io)
        else
            call check(hdferr, file, what, object, "h5dread_f/h5aread_f", error)
        end if
        call close_id(id)
    end subroutine read_strings

    !> Read all strings of an open dataset or attribute (fixed length). Status -2: not a fixed-length string type.
    subroutine read_string_values(id, is_attr, values, hdferr)
        !> The dataset or attribute.
        integer(hid_t), intent(in) :: id
        !> Whether `id` is an attribute.
        logical, intent(in) :: is_attr
        !> The strings without padding, blank-padded to the longest.
        character(len=:), allocatable, intent(out) :: values(:)
        !> HDF5 status; -2 if the datatype is not a fixed-length string.
        integer, intent(out) :: hdferr
        integer(hid_t) :: file_type, space
        integer(hsize_t) :: npoints
        integer(size_t) :: width
        integer :: type_class, pad, n, i, k
        integer, allocatable :: lengths(:)
        logical :: variable
        character(kind=c_char, len=1), allocatable, target :: chars(:)
        type(c_ptr) :: buf

        file_type = -1
        space = -1
        allocate (character(len=0) :: values(0))
        body: block
            if (is_attr) then
                call h5aget_type_f(id, file_type, hdferr)
            else
                call h5dget_type_f(id, file_type, hdferr)
            end if
            if (hdferr < 0) exit body
            call h5tget_class_f(file_type, type_class, hdferr)
            if (hdferr < 0) exit body
            if (type_class /= h5t_string_f) then
                hdferr = -2
                exit body
            end if
            if (is_attr) then
                call h5aget_space_f(id, space, hdferr)
            else
                call h5dget_space_f(id, space, hdferr)
            end if
            if (hdferr < 0) exit body
            call h5sget_simple_extent_npoints_f(space, npoints, hdferr)
            if (hdferr < 0) exit body
            n = int(npoints)
            call h5tis_variable_str_f(file_type, variable, hdferr)
            if (hdferr < 0) exit body
            allocate (lengths(n))
            if (variable) then
                hdferr = -2                     ! only fixed-length strings (what this layer writes) are read
                exit body
            else
                ! Fixed-length strings: read the raw characters with the file's own type, strip the padding.
                call h5tget_size_f(file_type, width, hdferr)
                if (hdferr < 0) exit body
                call h5tget_strpad_f(file_type, pad, hdferr)
                if (hdferr < 0) exit body
                allocate (chars(max(int(width)*n, 1)))
                chars = c_null_char
                buf = c_loc(chars)
                if (n > 0) then
                    call read_raw(id, is_attr, file_type, buf, hdferr)
                    if (hdferr < 0) exit body
                end if
                do i = 1, n
                    lengths(i) = 0
                    do k = 1, int(width)
                        if (chars((i - 1)*int(width) + k) == c_null_char) exit
                        lengths(i) = k
                    end do
                end do
                deallocate (values)
                allocate (character(len=maxval([0, lengths])) :: values(n))
                do i = 1, n
                    values(i) = ""
                    do k = 1, lengths(i)
                        values(i) (k:k) = chars((i - 1)*int(width) + k)
                    end do
                    if (pad == h5t_str_spacepad_f) values(i) = trim(values(i))
                end do
            end if
        end block body
        call close_id(space)
        call close_id(file_type)
    end subroutine read_string_values

    !> Read a whole dataset or attribute into `buf`.
    subroutine read_raw(id, is_attr, mem_type, buf, hdferr)
        !> The dataset or attribute.
        integer(hid_t), intent(in) :: id
        !> Whether `id` is an attribute.
        logical, intent(in) :: is_attr
        !> Datatype in memory.
        integer(hid_t), intent(in) :: mem_type
        !> Address of the destination.
        type(c_ptr), intent(inout) :: buf
        !> HDF5 status.
        integer, intent(out) :: hdferr

        if (is_attr) then
            call h5aread_f(id, mem_type, buf, hdferr)
        else
            call h5dread_f(id, mem_type, buf, hdferr)
        end if
    end subroutine read_raw

    !> Open dataset `name` and return its dimensions (Fortran order); check the rank unless `rank < 0`.
    !> Rank 0 accepts a scalar dataspace or a simple one with one element (then `dims` is empty).
    subroutine query_dataset(file, name, rank, dims, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> Expected rank; negative to accept any.
        integer, intent(in) :: rank
        !> Dimensions in Fortran order.
        integer(hsize_t), allocatable, intent(out) :: dims(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hid_t) :: dset, space
        integer :: hdferr

        call check_open(file, "read dataset", name, error)
        if (allocated(error)) return
        if (.not. h5_exists(file, name)) then
            call fatal_error(error, disk_path(file)//": no dataset '"//name//"'", err_io)
            return
        end if
        dset = -1
        space = -1
        body: block
            call h5dopen_f(file%id, name, dset, hdferr)
            call check(hdferr, file, "open dataset", name, "h5dopen_f", error)
            if (allocated(error)) exit body
            call h5dget_space_f(dset, space, hdferr)
            call check(hdferr, file, "get dataspace of", name, "h5dget_space_f", error)
            if (allocated(error)) exit body
            call space_dims(space, dims, hdferr)
            call check(hdferr, file, "get dimensions of", name, "h5sget_simple_extent_dims_f", error)
            if (allocated(error)) exit body
            call check_rank(file, "dataset '"//name//"'", rank, dims, error)
        end block body
        call close_id(space)
        call close_id(dset)
    end subroutine query_dataset

    !> Dimensions of a dataspace in Fortran order (empty for a scalar).
    subroutine space_dims(space, dims, hdferr)
        !> The dataspace.
        integer(hid_t), intent(in) :: space
        !> Dimensions in Fortran order.
        integer(hsize_t), allocatable, intent(out) :: dims(:)
        !> HDF5 status.
        integer, intent(out) :: hdferr
        integer(hsize_t), allocatable :: maxdims(:)
        integer :: rank

        call h5sget_simple_extent_ndims_f(space, rank, hdferr)
        if (hdferr < 0) return
        allocate (dims(rank), maxdims(rank))
        if (rank > 0) then
            call h5sget_simple_extent_dims_f(space, dims, maxdims, hdferr)
            if (hdferr >= 0) hdferr = 0
        end if
    end subroutine space_dims

    !> Error unless `dims` has the rank `rank` (negative: any); for rank 0, one element in any shape is accepted.
    subroutine check_rank(file, what, rank, dims, error)
        !> The file.
        type(h5_file), intent(in) :: file
        !> Description of the object, e.g. "dataset 'x'".
        character(len=*), intent(in) :: what
        !> Expected rank.
        integer, intent(in) :: rank
        !> Actual dimensions.
        integer(hsize_t), intent(in) :: dims(:)
        !> Error, allocated on a mismatch.
        type(error_type), allocatable, intent(out) :: error

        if (rank < 0) return
        if (rank == 0) then
            if (product(dims) /= 1) then
                call fatal_error(error, disk_path(file)//": "//what//" holds "//int_str(int(product(dims)))// &
                    " values, expected a scalar", err_io)
            end if
        else if (size(dims) /= rank) then
            call fatal_error(error, disk_path(file)//": "//what//" has rank "//int_str(size(dims))//", expected "// &
                int_str(rank), err_io)
        end if
    end subroutine check_rank

    !> Return the dimensions of attribute `name` of `object` (Fortran order) and check its rank.
    subroutine query_attr(file, object, name, rank, dims, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the object.
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> Expected rank; negative to accept any.
        integer, intent(in) :: rank
        !> Dimensions in Fortran order.
        integer(hsize_t), allocatable, intent(out) :: dims(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hid_t) :: attr, space
        integer :: hdferr

        call open_attr(file, object, name, attr, error)
        if (allocated(error)) return
        space = -1
        body: block
            call h5aget_space_f(attr, space, hdferr)
            call check(hdferr, file, "get dataspace of attribute '"//name//"' of", object, "h5aget_space_f", error)
            if (allocated(error)) exit body
            call space_dims(space, dims, hdferr)
            call check(hdferr, file, "get dimensions of attribute '"//name//"' of", object, &
                "h5sget_simple_extent_dims_f", error)
            if (allocated(error)) exit body
            call check_rank(file, "attribute '"//name//"' of '"//object//"'", rank, dims, error)
        end block body
        call close_id(space)
        call close_id(attr)
    end subroutine query_attr

    !> Open attribute `name` of `object`, with a clear error if the object or the attribute is missing.
    subroutine open_attr(file, object, name, attr, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the object.
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        !> The attribute; -1 on failure.
        integer(hid_t), intent(out) :: attr
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer :: hdferr

        attr = -1
        call check_open(file, "read attribute '"//name//"' of", object, error)
        if (allocated(error)) return
        if (.not. h5_attr_exists(file, object, name)) then
            call fatal_error(error, disk_path(file)//": no attribute '"//name//"' of '"//object//"'", err_io)
            return
        end if
        call h5aopen_by_name_f(file%id, root_if_empty(object), name, attr, hdferr)
        call check(hdferr, file, "open attribute '"//name//"' of", object, "h5aopen_by_name_f", error)
        if (allocated(error)) attr = -1
    end subroutine open_attr

end module supratrans_h5_read
