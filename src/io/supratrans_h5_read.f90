!> Reading HDF5 datasets and attributes back, as far as the program needs it: `merge` (the parts' attributes, task
!> indices, records and namelist), the `--check`/resume test of a finished output and the benchmark. The tests
!> read the other types through test/supratrans_h5_test.f90, built on `h5_shape` and `h5_read_into`.
!> Numeric types are converted by HDF5's rules; strings are read as this layer writes them, fixed-length (a
!> variable-length string, h5py's default, is refused as "not a fixed-length string"). Arrays come back in their
!> Fortran shape (the reverse of the h5py shape). Each routine is a chain of HDF5 calls, each made only while the
!> previous ones succeeded, with one check at its end.
module supratrans_h5_read
    use, intrinsic :: iso_c_binding, only: c_ptr, c_loc, c_char, c_null_char
    use hdf5, only: hid_t, hsize_t, size_t, h5dopen_f, h5dread_f, h5dget_space_f, h5dget_type_f, &
        h5sget_simple_extent_ndims_f, h5sget_simple_extent_dims_f, h5sget_simple_extent_npoints_f, &
        h5tget_size_f, h5tget_class_f, h5tis_variable_str_f, h5t_string_f, &
        h5aopen_by_name_f, h5aread_f, h5aget_space_f, h5aget_type_f
    use supratrans_kinds, only: wp
    use supratrans_error, only: error_type, fatal_error, err_io
    use supratrans_strings, only: int_str
    use supratrans_h5_file, only: h5_exists, h5_attr_exists, real_mem_type, int_mem_type, disk_path, &
        root_if_empty, check, close_id, h5_file, h5_mode_closed
    implicit none
    private

    public :: h5_read, h5_read_attr, h5_shape, h5_read_into, h5_read_strings

    !> Read a whole dataset: `call h5_read(file, name, data, error)`, converting numeric types. `data`: `real(wp)` or
    !> default integer allocatable of rank 1 or 2, deferred-length allocatable character scalar.
    interface h5_read
        module procedure :: read_real_1d, read_real_2d, read_int_1d, read_int_2d, read_char_0d
    end interface h5_read

    !> Read an attribute: `call h5_read_attr(file, object, name, value, error)`. `value`: deferred-length allocatable
    !> character, default integer or `real(wp)` scalar.
    interface h5_read_attr
        module procedure :: read_attr_char, read_attr_int_0d, read_attr_real_0d
    end interface h5_read_attr

    !> A list of strings (works around spurious gfortran warnings on local deferred-length character arrays).
    type :: string_array
        !> The strings.
        character(len=:), allocatable :: items(:)
    end type string_array

contains

    ! The typed reads of `h5_read` and `h5_read_attr`: file, path, (attribute name,) data, error.

    subroutine read_real_1d(file, name, data, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: name
        real(wp), allocatable, target, intent(out) :: data(:)
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        call h5_shape(file, name, "", 1, dims, error)
        if (allocated(error)) return
        allocate (data(dims(1)))
        if (size(data) > 0) call h5_read_into(file, name, "", real_mem_type(), c_loc(data), error)
    end subroutine read_real_1d

    subroutine read_real_2d(file, name, data, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: name
        real(wp), allocatable, target, intent(out) :: data(:, :)
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        call h5_shape(file, name, "", 2, dims, error)
        if (allocated(error)) return
        allocate (data(dims(1), dims(2)))
        if (size(data) > 0) call h5_read_into(file, name, "", real_mem_type(), c_loc(data), error)
    end subroutine read_real_2d

    subroutine read_int_1d(file, name, data, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: name
        integer, allocatable, target, intent(out) :: data(:)
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        call h5_shape(file, name, "", 1, dims, error)
        if (allocated(error)) return
        allocate (data(dims(1)))
        if (size(data) > 0) call h5_read_into(file, name, "", int_mem_type(), c_loc(data), error)
    end subroutine read_int_1d

    subroutine read_int_2d(file, name, data, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: name
        integer, allocatable, target, intent(out) :: data(:, :)
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        call h5_shape(file, name, "", 2, dims, error)
        if (allocated(error)) return
        allocate (data(dims(1), dims(2)))
        if (size(data) > 0) call h5_read_into(file, name, "", int_mem_type(), c_loc(data), error)
    end subroutine read_int_2d

    subroutine read_char_0d(file, name, data, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: name
        character(len=:), allocatable, intent(out) :: data
        type(error_type), allocatable, intent(out) :: error

        call read_one_string(file, name, "", data, error)
    end subroutine read_char_0d

    subroutine read_attr_char(file, object, name, value, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: object, name
        character(len=:), allocatable, intent(out) :: value
        type(error_type), allocatable, intent(out) :: error

        call read_one_string(file, object, name, value, error)
    end subroutine read_attr_char

    subroutine read_attr_int_0d(file, object, name, value, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: object, name
        integer, intent(out), target :: value
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        value = 0
        call h5_shape(file, object, name, 0, dims, error)
        if (.not. allocated(error)) call h5_read_into(file, object, name, int_mem_type(), c_loc(value), error)
    end subroutine read_attr_int_0d

    subroutine read_attr_real_0d(file, object, name, value, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: object, name
        real(wp), intent(out), target :: value
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: dims(:)

        value = 0.0_wp
        call h5_shape(file, object, name, 0, dims, error)
        if (.not. allocated(error)) call h5_read_into(file, object, name, real_mem_type(), c_loc(value), error)
    end subroutine read_attr_real_0d

    !> Read the one string of dataset `object` (`attr` empty) or of its attribute `attr`, without padding.
    subroutine read_one_string(file, object, attr, value, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: object, attr
        character(len=:), allocatable, intent(out) :: value
        type(error_type), allocatable, intent(out) :: error
        type(string_array) :: values

        call h5_read_strings(file, object, attr, values%items, error)
        if (allocated(error)) return
        if (size(values%items) /= 1) then
            call fatal_error(error, disk_path(file)//": "//what(object, attr)//" holds "// &
                int_str(size(values%items))//" strings, expected one", err_io)
            return
        end if
        value = values%items(1)
    end subroutine read_one_string

    !> The dimensions (Fortran order) of dataset `object` (`attr` empty) or of its attribute `attr`, checked to be of
    !> rank `rank` (negative: any; 0 accepts a scalar or any shape of one element, then `dims` may be non-empty).
    subroutine h5_shape(file, object, attr, rank, dims, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset, or of the attribute's object.
        character(len=*), intent(in) :: object
        !> Name of the attribute; empty for the dataset.
        character(len=*), intent(in) :: attr
        !> Expected rank; negative to accept any.
        integer, intent(in) :: rank
        !> Dimensions in Fortran order.
        integer(hsize_t), allocatable, intent(out) :: dims(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hid_t) :: id, space
        integer(hsize_t), allocatable :: maxdims(:)
        integer :: hdferr, n

        allocate (dims(0))
        call open_object(file, object, attr, id, error)
        if (allocated(error)) return
        call get_space(id, len(attr) > 0, space, hdferr)
        if (hdferr >= 0) call h5sget_simple_extent_ndims_f(space, n, hdferr)
        if (hdferr >= 0) then
            deallocate (dims)
            allocate (dims(n), maxdims(n))
            if (n > 0) call h5sget_simple_extent_dims_f(space, dims, maxdims, hdferr)
        end if
        call close_id(space)
        call close_id(id)
        call check(hdferr, file, "get the dimensions of"//of_attr(attr), object, "h5sget_simple_extent_dims_f", error)
        if (allocated(error) .or. rank < 0) return
        if (rank == 0 .and. product(dims) /= 1) then
            call fatal_error(error, disk_path(file)//": "//what(object, attr)//" holds "// &
                int_str(int(product(dims)))//" values, expected a scalar", err_io)
        else if (rank > 0 .and. size(dims) /= rank) then
            call fatal_error(error, disk_path(file)//": "//what(object, attr)//" has rank "//int_str(size(dims))// &
                ", expected "//int_str(rank), err_io)
        end if
    end subroutine h5_shape

    !> Read the whole dataset `object` (`attr` empty) or its attribute `attr` into the memory at `buf` (sized by the
    !> caller, of type `mem_type`).
    subroutine h5_read_into(file, object, attr, mem_type, buf, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset, or of the attribute's object.
        character(len=*), intent(in) :: object
        !> Name of the attribute; empty for the dataset.
        character(len=*), intent(in) :: attr
        !> Datatype in memory.
        integer(hid_t), intent(in) :: mem_type
        !> Address of the destination.
        type(c_ptr), intent(in) :: buf
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hid_t) :: id
        type(c_ptr) :: dest
        integer :: hdferr

        dest = buf
        call open_object(file, object, attr, id, error)
        if (allocated(error)) return
        call read_raw(id, len(attr) > 0, mem_type, dest, hdferr)
        call close_id(id)
        call check(hdferr, file, "read"//of_attr(attr), object, "h5dread_f/h5aread_f", error)
    end subroutine h5_read_into

    !> Read the strings (fixed-length) of dataset `object` (`attr` empty) or of its attribute `attr`.
    subroutine h5_read_strings(file, object, attr, values, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset, or of the attribute's object.
        character(len=*), intent(in) :: object
        !> Name of the attribute; empty for the dataset.
        character(len=*), intent(in) :: attr
        !> The strings without padding, blank-padded to the longest.
        character(len=:), allocatable, intent(out) :: values(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hid_t) :: id
        integer :: hdferr

        allocate (character(len=0) :: values(0))
        call open_object(file, object, attr, id, error)
        if (allocated(error)) return
        call read_string_values(id, len(attr) > 0, values, hdferr)
        call close_id(id)
        if (hdferr == -2) then
            call fatal_error(error, disk_path(file)//": cannot read"//of_attr(attr)//" '"//object//"' as text: "// &
                "not a fixed-length string", err_io)
        else
            call check(hdferr, file, "read"//of_attr(attr), object, "h5dread_f/h5aread_f", error)
        end if
    end subroutine h5_read_strings

    !> " attribute 'NAME' of" for messages ("read attribute 'x' of '/y'"); " dataset" for a dataset.
    pure function of_attr(attr) result(s)
        character(len=*), intent(in) :: attr
        character(len=:), allocatable :: s

        s = " dataset"
        if (len(attr) > 0) s = " attribute '"//attr//"' of"
    end function of_attr

    !> "dataset 'OBJECT'" or "attribute 'ATTR' of 'OBJECT'", for messages.
    pure function what(object, attr) result(s)
        character(len=*), intent(in) :: object, attr
        character(len=:), allocatable :: s

        s = "dataset '"//object//"'"
        if (len(attr) > 0) s = "attribute '"//attr//"' of '"//object//"'"
    end function what

    !> Open dataset `object` (`attr` empty) or its attribute `attr`, with a clear error if it is missing.
    subroutine open_object(file, object, attr, id, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: object, attr
        integer(hid_t), intent(out) :: id
        type(error_type), allocatable, intent(out) :: error
        integer :: hdferr
        logical :: exists

        id = -1
        if (file%mode == h5_mode_closed) then
            call fatal_error(error, disk_path(file)//": file is not open, cannot read"//of_attr(attr)//" '"//object//"'", &
                err_io)
            return
        end if
        if (len(attr) == 0) then
            exists = h5_exists(file, object)
        else
            exists = h5_attr_exists(file, object, attr)
        end if
        if (.not. exists) then
            call fatal_error(error, disk_path(file)//": no "//what(object, attr), err_io)
            return
        end if
        if (len(attr) == 0) then
            call h5dopen_f(file%id, object, id, hdferr)
        else
            call h5aopen_by_name_f(file%id, root_if_empty(object), attr, id, hdferr)
        end if
        call check(hdferr, file, "open"//of_attr(attr), object, "h5dopen_f/h5aopen_by_name_f", error)
        if (allocated(error)) id = -1
    end subroutine open_object

    !> Read all strings of an open dataset or attribute (fixed length), each to its first null. Status -2: not a
    !> fixed-length string type.
    subroutine read_string_values(id, is_attr, values, hdferr)
        integer(hid_t), intent(in) :: id
        logical, intent(in) :: is_attr
        character(len=:), allocatable, intent(inout) :: values(:)
        integer, intent(out) :: hdferr
        integer(hid_t) :: file_type, space
        integer(hsize_t) :: npoints
        integer(size_t) :: width
        integer :: type_class, n, i, k
        integer, allocatable :: lengths(:)
        logical :: variable
        character(kind=c_char, len=1), allocatable, target :: chars(:, :)
        type(c_ptr) :: buf

        file_type = -1
        space = -1
        if (is_attr) then
            call h5aget_type_f(id, file_type, hdferr)
        else
            call h5dget_type_f(id, file_type, hdferr)
        end if
        if (hdferr >= 0) call h5tget_class_f(file_type, type_class, hdferr)
        if (hdferr >= 0 .and. type_class /= h5t_string_f) hdferr = -2
        if (hdferr >= 0) call h5tis_variable_str_f(file_type, variable, hdferr)
        if (hdferr >= 0 .and. variable) hdferr = -2    ! only fixed-length strings (what this layer writes)
        if (hdferr >= 0) call get_space(id, is_attr, space, hdferr)
        if (hdferr >= 0) call h5sget_simple_extent_npoints_f(space, npoints, hdferr)
        if (hdferr >= 0) call h5tget_size_f(file_type, width, hdferr)
        if (hdferr >= 0) then
            ! the raw characters, read with the file's own type: one column a string
            n = int(npoints)
            allocate (chars(int(width), max(n, 1)), source=c_null_char)
            buf = c_loc(chars)
            if (n > 0) call read_raw(id, is_attr, file_type, buf, hdferr)
        end if
        if (hdferr >= 0) then
            allocate (lengths(n))
            do i = 1, n
                lengths(i) = findloc([chars(:, i), c_null_char], c_null_char, 1) - 1
            end do
            deallocate (values)
            allocate (character(len=maxval([0, lengths])) :: values(n))
            values = ""
            do i = 1, n
                do k = 1, lengths(i)
                    values(i) (k:k) = chars(k, i)
                end do
            end do
        end if
        call close_id(space)
        call close_id(file_type)
    end subroutine read_string_values

    !> The dataspace of an open dataset or attribute.
    subroutine get_space(id, is_attr, space, hdferr)
        integer(hid_t), intent(in) :: id
        logical, intent(in) :: is_attr
        integer(hid_t), intent(out) :: space
        integer, intent(out) :: hdferr

        space = -1
        if (is_attr) then
            call h5aget_space_f(id, space, hdferr)
        else
            call h5dget_space_f(id, space, hdferr)
        end if
    end subroutine get_space

    !> Read a whole dataset or attribute into `buf`.
    subroutine read_raw(id, is_attr, mem_type, buf, hdferr)
        integer(hid_t), intent(in) :: id, mem_type
        logical, intent(in) :: is_attr
        type(c_ptr), intent(inout) :: buf
        integer, intent(out) :: hdferr

        if (is_attr) then
            call h5aread_f(id, mem_type, buf, hdferr)
        else
            call h5dread_f(id, mem_type, buf, hdferr)
        end if
    end subroutine read_raw

end module supratrans_h5_read
