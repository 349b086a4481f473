!> Writing HDF5 datasets, attributes and groups (the rules: `supratrans_hdf5`). One routine a type takes data of
!> every rank (assumed rank, `data(..)`: Fortran 2018 / TS 29113, in gfortran since 4.9, the one feature of the
!> code beyond Fortran 2008) and finds only the HDF5 types and the address of the data; one routine writes every
!> dataset (`write_dataset`) and one every attribute (`write_attr`). Each is a chain of HDF5 calls, each made only
!> while the previous ones succeeded, with one check at its end.
module supratrans_h5_write
    use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_loc, c_char, c_null_char
    use hdf5, only: hid_t, hsize_t, h5dcreate_f, h5dopen_f, h5dwrite_f, h5t_ieee_f64le, h5t_std_i64le, h5gcreate_f, &
        h5oopen_f, h5ldelete_f, h5aexists_f, h5adelete_f, h5acreate_f, h5awrite_f
    use supratrans_kinds, only: wp, i8
    use supratrans_h5_file, only: h5_file, h5_exists, real_mem_type, int_mem_type, int_file_type, i8_mem_type, &
        root_if_empty, fail, failed_call, check_writable, check_dim_names, close_id, make_space, make_lcpl, &
        make_string_type, remember_dims
    implicit none
    private

    public :: h5_write, h5_write_attr, h5_create_group

    !> Write a dataset with the attributes `units` and `description` (and `dimensions` when `dims` is given):
    !> `call h5_write(file, name, data, units, description [, dims])`; a failure sticks in `file`.
    !> `data`: `real(wp)`, default integer or `integer(i8)` of any rank, character of rank 0 or 1. `dims` (arrays
    !> only): dimension names in C/h5py order, e.g. "probe, time".
    interface h5_write
        module procedure :: write_real, write_int, write_i8, write_char_0d, write_char_1d
    end interface h5_write

    !> Write an attribute `name` of the object `object` ("/" for the root group; a missing group is created):
    !> `call h5_write_attr(file, object, name, value)` (a failure sticks in `file`). `value`: character scalar,
    !> `real(wp)`, default integer or `integer(i8)` scalar or array, logical scalar (stored as integer 0/1).
    interface h5_write_attr
        module procedure :: write_attr_char, write_attr_real, write_attr_int, write_attr_i8, write_attr_logical
    end interface h5_write_attr

contains

    !> Create a group (and missing intermediate groups) with the attribute `description`; if the group exists,
    !> only its description is (re)written.
    subroutine h5_create_group(file, name, description)
        !> The file (writable).
        type(h5_file), intent(inout) :: file
        !> Path of the group.
        character(len=*), intent(in) :: name
        !> What the group holds.
        character(len=*), intent(in) :: description

        call write_attr_char(file, name, "description", description)
    end subroutine h5_create_group

    ! The typed datasets of `h5_write`: data, units, description and (arrays) the dimension names.

    subroutine write_real(file, name, data, units, description, dims)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description
        real(wp), intent(in), target, contiguous :: data(..)
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, real_mem_type(), h5t_ieee_f64le, shape(data, hsize_t), buf, units, description, dims)
    end subroutine write_real

    subroutine write_int(file, name, data, units, description, dims)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description
        integer, intent(in), target, contiguous :: data(..)
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, int_mem_type(), int_file_type(), shape(data, hsize_t), buf, units, description, dims)
    end subroutine write_int

    subroutine write_i8(file, name, data, units, description, dims)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description
        integer(i8), intent(in), target, contiguous :: data(..)
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, i8_mem_type(), h5t_std_i64le, shape(data, hsize_t), buf, units, description, dims)
    end subroutine write_i8

    subroutine write_char_0d(file, name, data, units, description)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, data, units, description

        call write_strings(file, name, [data], .false., units, description)
    end subroutine write_char_0d

    subroutine write_char_1d(file, name, data, units, description, dims)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description, data(:)
        character(len=*), intent(in), optional :: dims

        call write_strings(file, name, data, .true., units, description, dims)
    end subroutine write_char_1d

    ! The typed attributes of `h5_write_attr`: object, attribute name, value.

    subroutine write_attr_char(file, object, name, value)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: object, name, value
        character(kind=c_char, len=1), allocatable, target :: chars(:)
        integer(hid_t) :: string_type
        integer :: hdferr
        type(c_ptr) :: buf      ! c_loc of a character array stored first (see `write_strings`)

        call c_chars([value], .false., chars)
        call make_string_type(len(value), string_type, hdferr)
        buf = c_loc(chars)
        call write_attr(file, object, name, string_type, string_type, [integer(hsize_t) ::], buf, hdferr)
        call close_id(string_type)
    end subroutine write_attr_char

    subroutine write_attr_real(file, object, name, value)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: object, name
        real(wp), intent(in), target, contiguous :: value(..)
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(value) > 0) buf = c_loc(value)
        call write_attr(file, object, name, real_mem_type(), h5t_ieee_f64le, shape(value, hsize_t), buf, 0)
    end subroutine write_attr_real

    subroutine write_attr_int(file, object, name, value)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: object, name
        integer, intent(in), target, contiguous :: value(..)
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(value) > 0) buf = c_loc(value)
        call write_attr(file, object, name, int_mem_type(), int_file_type(), shape(value, hsize_t), buf, 0)
    end subroutine write_attr_int

    subroutine write_attr_i8(file, object, name, value)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: object, name
        integer(i8), intent(in), target, contiguous :: value(..)
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(value) > 0) buf = c_loc(value)
        call write_attr(file, object, name, i8_mem_type(), h5t_std_i64le, shape(value, hsize_t), buf, 0)
    end subroutine write_attr_i8

    subroutine write_attr_logical(file, object, name, value)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: object, name
        logical, intent(in) :: value

        call write_attr_int(file, object, name, merge(1, 0, value))
    end subroutine write_attr_logical

    !> The characters of strings, each in `max(len(data), 1)` bytes, null-padded (with `trim_each`, the trailing
    !> blanks of each string are padding too): the buffer of a fixed-length string dataset or attribute.
    pure subroutine c_chars(data, trim_each, chars)
        character(len=*), intent(in) :: data(:)
        logical, intent(in) :: trim_each
        character(kind=c_char, len=1), allocatable, intent(out) :: chars(:)
        integer :: width, i, k, n

        width = max(len(data), 1)
        allocate (chars(width*max(size(data), 1)))
        chars = c_null_char
        do i = 1, size(data)
            n = len(data(i))
            if (trim_each) n = len_trim(data(i))
            do k = 1, n
                chars((i - 1)*width + k) = data(i) (k:k)
            end do
        end do
    end subroutine c_chars

    !> Write the attribute `name` of the object `object` (a missing object is created as a group, with
    !> intermediate groups; an existing attribute is replaced) from `buf`; `hdferr` is the status of making its types
    !> (negative: nothing written).
    subroutine write_attr(file, object, name, mem_type, file_type, dims, buf, hdferr)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: object, name
        integer(hid_t), intent(in) :: mem_type, file_type
        integer(hsize_t), intent(in) :: dims(:)
        type(c_ptr), intent(in) :: buf
        integer, intent(in) :: hdferr
        integer(hid_t) :: obj, lcpl, space, attr
        integer :: status
        logical :: exists

        call check_writable(file, "write to", object)
        if (len_trim(name) == 0) call fail(file, "empty attribute name for '"//object//"'")
        if (allocated(file%error)) return
        obj = -1
        lcpl = -1
        space = -1
        attr = -1
        status = hdferr
        if (status >= 0 .and. h5_exists(file, object)) then
            call h5oopen_f(file%id, root_if_empty(object), obj, status)
        else if (status >= 0) then
            call make_lcpl(lcpl, status)
            if (status >= 0) call h5gcreate_f(file%id, object, obj, status, lcpl_id=lcpl)
        end if
        if (status >= 0) call h5aexists_f(obj, name, exists, status)
        if (status >= 0 .and. exists) call h5adelete_f(obj, name, status)
        if (status >= 0) call make_space(dims, space, status)
        if (status >= 0) call h5acreate_f(obj, name, file_type, space, attr, status)
        if (status >= 0 .and. product(dims) > 0) call h5awrite_f(attr, mem_type, buf, status)
        call close_id(attr)
        call close_id(space)
        call close_id(obj)
        call close_id(lcpl)
        if (status < 0) call fail(file, failed_call("write attribute '"//name//"' of", object, "h5awrite_f"))
    end subroutine write_attr

    !> Create dataset `name` (replacing an existing dataset), write it from `buf` and describe it: the attributes
    !> `units`, `description` and, with `dim_names`, `dimensions` (and the dimensions remembered for the scales).
    subroutine write_dataset(file, name, mem_type, file_type, dims, buf, units, description, dim_names)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description
        integer(hid_t), intent(in) :: mem_type, file_type
        integer(hsize_t), intent(in) :: dims(:)
        type(c_ptr), intent(in) :: buf
        character(len=*), intent(in), optional :: dim_names
        integer(hid_t) :: space, lcpl, dset
        integer :: status

        call check_writable(file, "write dataset", name)
        if (present(dim_names)) call check_dim_names(file, name, dim_names, size(dims))
        if (allocated(file%error)) return
        if (h5_exists(file, name)) call remove_dataset(file, name)
        if (allocated(file%error)) return
        space = -1
        lcpl = -1
        dset = -1
        call make_space(dims, space, status)
        if (status >= 0) call make_lcpl(lcpl, status)
        if (status >= 0) call h5dcreate_f(file%id, name, file_type, space, dset, status, lcpl_id=lcpl)
        if (status >= 0 .and. product(dims) > 0) call h5dwrite_f(dset, mem_type, buf, status)
        call close_id(dset)
        call close_id(lcpl)
        call close_id(space)
        if (status < 0) call fail(file, failed_call("write dataset", name, "h5dcreate_f/h5dwrite_f"))
        call write_attr_char(file, name, "units", units)
        call write_attr_char(file, name, "description", description)
        if (.not. present(dim_names)) return
        call write_attr_char(file, name, "dimensions", dim_names)
        if (.not. allocated(file%error)) call remember_dims(file, name, dim_names)
    end subroutine write_dataset

    !> Remove the existing object `name`, which must be a dataset (`h5_write` replaces a dataset, nothing else).
    subroutine remove_dataset(file, name)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name
        integer(hid_t) :: dset
        integer :: hdferr

        call h5dopen_f(file%id, name, dset, hdferr)
        if (hdferr < 0) then
            call fail(file, "cannot write dataset '"//name//"': an object of that name exists and is not a dataset")
            return
        end if
        call close_id(dset)
        call h5ldelete_f(file%id, name, hdferr)
        if (hdferr < 0) call fail(file, failed_call("replace dataset", name, "h5ldelete_f"))
    end subroutine remove_dataset

    !> Write strings as a fixed-length string dataset: scalar (`array` false, one string, stored as given) or rank 1
    !> (trailing blanks of each element dropped).
    subroutine write_strings(file, name, data, array, units, description, dim_names)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description, data(:)
        logical, intent(in) :: array
        character(len=*), intent(in), optional :: dim_names
        character(kind=c_char, len=1), allocatable, target :: chars(:)
        integer(hsize_t), allocatable :: dims(:)
        integer(hid_t) :: string_type
        integer :: hdferr
        ! c_loc of a character array is stored first: passed directly, gfortran 12 adds a spurious hidden length.
        type(c_ptr) :: buf

        call c_chars(data, array, chars)
        allocate (dims(0))
        if (array) dims = [int(size(data), hsize_t)]
        call make_string_type(len(data), string_type, hdferr)
        if (hdferr < 0) call fail(file, failed_call("create string type for", name, "h5tset_size_f"))
        buf = c_loc(chars)
        call write_dataset(file, name, string_type, string_type, dims, buf, units, description, dim_names)
        call close_id(string_type)
    end subroutine write_strings

end module supratrans_h5_write
