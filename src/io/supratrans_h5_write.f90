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
!>
!> Each typed routine of the generic interfaces only finds the HDF5 types and the address of its data; one
!> routine writes every dataset (`write_dataset`) and one every attribute (`write_attr`).
module supratrans_h5_write
    use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_loc, c_char, c_null_char
    use hdf5, only: hid_t, hsize_t, h5dcreate_f, h5dopen_f, h5dwrite_f, h5t_ieee_f64le, h5t_std_i64le, h5gcreate_f, &
        h5oopen_f, h5ldelete_f, h5aexists_f, h5adelete_f, h5acreate_f, h5awrite_f
    use supratrans_kinds, only: wp, i8
    use supratrans_error, only: error_type, fatal_error, err_io
    use supratrans_h5_file, only: h5_file, h5_exists, real_mem_type, int_mem_type, int_file_type, i8_mem_type, &
        disk_path, root_if_empty, check, check_writable, check_dim_names, close_id, make_space, make_lcpl, &
        make_string_type, stick, remember_dims
    implicit none
    private

    public :: h5_write, h5_write_attr, h5_create_group

    !> Write a dataset with the attributes `units` and `description` (and `dimensions` when `dims` is given):
    !> `call h5_write(file, name, data, units, description [, dims])`; a failure sticks in `file`.
    !> `data`: `real(wp)` of rank 0 to 4, default integer of rank 0 to 3, `integer(i8)` of rank 0 or 1,
    !> character of rank 0 or 1. `dims` (arrays only): dimension names in C/h5py order, e.g. "probe, time".
    interface h5_write
        module procedure :: write_real_0d, write_real_1d, write_real_2d, write_real_3d, write_real_4d
        module procedure :: write_int_0d, write_int_1d, write_int_2d, write_int_3d, write_i8_0d, write_i8_1d
        module procedure :: write_char_0d, write_char_1d
    end interface h5_write

    !> Write an attribute `name` of the object `object` ("/" for the root group; a missing group is created):
    !> `call h5_write_attr(file, object, name, value)` (a failure sticks in `file`). `value`: character scalar,
    !> `real(wp)` scalar or rank 1, default integer scalar or rank 1, `integer(i8)` scalar, logical scalar (stored
    !> as integer 0/1).
    interface h5_write_attr
        module procedure :: write_attr_char, write_attr_real_0d, write_attr_real_1d, write_attr_int_0d
        module procedure :: write_attr_int_1d, write_attr_i8_0d, write_attr_logical
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
        type(error_type), allocatable :: error
        integer(hid_t) :: obj
        integer :: hdferr

        if (allocated(file%error)) return
        call open_or_create_group(file, name, obj, error)
        if (.not. allocated(error)) then
            call put_string_attr(obj, "description", description, hdferr)
            call check(hdferr, file, "write attribute 'description' of group", name, "h5awrite_f", error)
            call close_id(obj)
        end if
        call stick(file, error)
    end subroutine h5_create_group

    ! The typed datasets of `h5_write`: data, units, description and (arrays) the dimension names.

    subroutine write_real_0d(file, name, data, units, description)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description
        real(wp), intent(in), target :: data

        call write_dataset(file, name, real_mem_type(), h5t_ieee_f64le, [integer(hsize_t) ::], c_loc(data), units, &
            description)
    end subroutine write_real_0d

    subroutine write_real_1d(file, name, data, units, description, dims)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description
        real(wp), intent(in), target, contiguous :: data(:)
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, real_mem_type(), h5t_ieee_f64le, shape(data, hsize_t), buf, units, description, dims)
    end subroutine write_real_1d

    subroutine write_real_2d(file, name, data, units, description, dims)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description
        real(wp), intent(in), target, contiguous :: data(:, :)
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, real_mem_type(), h5t_ieee_f64le, shape(data, hsize_t), buf, units, description, dims)
    end subroutine write_real_2d

    subroutine write_real_3d(file, name, data, units, description, dims)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description
        real(wp), intent(in), target, contiguous :: data(:, :, :)
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, real_mem_type(), h5t_ieee_f64le, shape(data, hsize_t), buf, units, description, dims)
    end subroutine write_real_3d

    subroutine write_real_4d(file, name, data, units, description, dims)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description
        real(wp), intent(in), target, contiguous :: data(:, :, :, :)
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, real_mem_type(), h5t_ieee_f64le, shape(data, hsize_t), buf, units, description, dims)
    end subroutine write_real_4d

    subroutine write_int_0d(file, name, data, units, description)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description
        integer, intent(in), target :: data

        call write_dataset(file, name, int_mem_type(), int_file_type(), [integer(hsize_t) ::], c_loc(data), units, &
            description)
    end subroutine write_int_0d

    subroutine write_int_1d(file, name, data, units, description, dims)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description
        integer, intent(in), target, contiguous :: data(:)
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, int_mem_type(), int_file_type(), shape(data, hsize_t), buf, units, description, dims)
    end subroutine write_int_1d

    subroutine write_int_2d(file, name, data, units, description, dims)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description
        integer, intent(in), target, contiguous :: data(:, :)
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, int_mem_type(), int_file_type(), shape(data, hsize_t), buf, units, description, dims)
    end subroutine write_int_2d

    subroutine write_int_3d(file, name, data, units, description, dims)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description
        integer, intent(in), target, contiguous :: data(:, :, :)
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, int_mem_type(), int_file_type(), shape(data, hsize_t), buf, units, description, dims)
    end subroutine write_int_3d

    subroutine write_i8_0d(file, name, data, units, description)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description
        integer(i8), intent(in), target :: data

        call write_dataset(file, name, i8_mem_type(), h5t_std_i64le, [integer(hsize_t) ::], c_loc(data), units, &
            description)
    end subroutine write_i8_0d

    subroutine write_i8_1d(file, name, data, units, description, dims)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description
        integer(i8), intent(in), target, contiguous :: data(:)
        character(len=*), intent(in), optional :: dims
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(data) > 0) buf = c_loc(data)
        call write_dataset(file, name, i8_mem_type(), h5t_std_i64le, shape(data, hsize_t), buf, units, description, dims)
    end subroutine write_i8_1d

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
        type(c_ptr) :: buf

        call c_chars(value, chars)
        call make_string_type(len(value), string_type, hdferr)
        buf = c_loc(chars)
        if (hdferr < 0) then
            call write_failed(file, hdferr, object, name)
        else
            call write_attr(file, object, name, string_type, string_type, [integer(hsize_t) ::], buf)
        end if
        call close_id(string_type)
    end subroutine write_attr_char

    subroutine write_attr_real_0d(file, object, name, value)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: object, name
        real(wp), intent(in), target :: value

        call write_attr(file, object, name, real_mem_type(), h5t_ieee_f64le, [integer(hsize_t) ::], c_loc(value))
    end subroutine write_attr_real_0d

    subroutine write_attr_real_1d(file, object, name, value)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: object, name
        real(wp), intent(in), target, contiguous :: value(:)
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(value) > 0) buf = c_loc(value)
        call write_attr(file, object, name, real_mem_type(), h5t_ieee_f64le, shape(value, hsize_t), buf)
    end subroutine write_attr_real_1d

    subroutine write_attr_int_0d(file, object, name, value)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: object, name
        integer, intent(in), target :: value

        call write_attr(file, object, name, int_mem_type(), int_file_type(), [integer(hsize_t) ::], c_loc(value))
    end subroutine write_attr_int_0d

    subroutine write_attr_int_1d(file, object, name, value)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: object, name
        integer, intent(in), target, contiguous :: value(:)
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(value) > 0) buf = c_loc(value)
        call write_attr(file, object, name, int_mem_type(), int_file_type(), shape(value, hsize_t), buf)
    end subroutine write_attr_int_1d

    subroutine write_attr_i8_0d(file, object, name, value)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: object, name
        integer(i8), intent(in), target :: value

        call write_attr(file, object, name, i8_mem_type(), h5t_std_i64le, [integer(hsize_t) ::], c_loc(value))
    end subroutine write_attr_i8_0d

    subroutine write_attr_logical(file, object, name, value)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: object, name
        logical, intent(in) :: value

        call write_attr_int_0d(file, object, name, merge(1, 0, value))
    end subroutine write_attr_logical

    !> The characters of a string, null-terminated buffer of at least one character.
    pure subroutine c_chars(value, chars)
        character(len=*), intent(in) :: value
        character(kind=c_char, len=1), allocatable, intent(out) :: chars(:)
        integer :: k

        allocate (chars(max(len(value), 1)))
        chars = c_null_char
        do k = 1, len(value)
            chars(k) = value(k:k)
        end do
    end subroutine c_chars

    !> Create or replace an attribute of the open object `obj` and write it from `buf`.
    subroutine put_attr(obj, name, mem_type, file_type, dims, buf, hdferr)
        integer(hid_t), intent(in) :: obj, mem_type, file_type
        character(len=*), intent(in) :: name
        integer(hsize_t), intent(in) :: dims(:)
        type(c_ptr), intent(in) :: buf
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

    !> Create or replace a scalar string attribute of the open object `obj`.
    subroutine put_string_attr(obj, name, value, hdferr)
        integer(hid_t), intent(in) :: obj
        character(len=*), intent(in) :: name, value
        integer, intent(out) :: hdferr
        character(kind=c_char, len=1), allocatable, target :: chars(:)
        integer(hid_t) :: string_type
        type(c_ptr) :: buf

        call c_chars(value, chars)
        call make_string_type(len(value), string_type, hdferr)
        buf = c_loc(chars)
        if (hdferr >= 0) call put_attr(obj, name, string_type, string_type, [integer(hsize_t) ::], buf, hdferr)
        call close_id(string_type)
    end subroutine put_string_attr

    !> Open the object `object`, creating it as a group (with intermediate groups) if it does not exist.
    subroutine open_or_create_group(file, object, obj, error)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: object
        integer(hid_t), intent(out) :: obj
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

    !> Stick the error of a failed attribute write in the file.
    subroutine write_failed(file, hdferr, object, name)
        type(h5_file), intent(inout) :: file
        integer, intent(in) :: hdferr
        character(len=*), intent(in) :: object, name
        type(error_type), allocatable :: error

        call check(hdferr, file, "write attribute '"//name//"' of", object, "h5awrite_f", error)
        call stick(file, error)
    end subroutine write_failed

    !> Write the attribute `name` of the object `object` (a missing group is created) from `buf`.
    subroutine write_attr(file, object, name, mem_type, file_type, dims, buf)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: object, name
        integer(hid_t), intent(in) :: mem_type, file_type
        integer(hsize_t), intent(in) :: dims(:)
        type(c_ptr), intent(in) :: buf
        type(error_type), allocatable :: error
        integer(hid_t) :: obj
        integer :: hdferr

        if (allocated(file%error)) return
        if (len_trim(name) == 0) then
            call fatal_error(error, disk_path(file)//": empty attribute name for '"//object//"'", err_io)
        else
            call open_or_create_group(file, object, obj, error)
        end if
        if (.not. allocated(error)) then
            call put_attr(obj, name, mem_type, file_type, dims, buf, hdferr)
            call close_id(obj)
            if (hdferr < 0) call write_failed(file, hdferr, object, name)
        end if
        call stick(file, error)
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
        type(error_type), allocatable :: error
        integer(hid_t) :: space, lcpl, dset
        integer :: hdferr

        if (allocated(file%error)) return
        space = -1
        lcpl = -1
        dset = -1
        body: block
            call check_writable(file, "write dataset", name, error)
            if (allocated(error)) exit body
            if (present(dim_names)) call check_dim_names(file, name, dim_names, size(dims), error)
            if (allocated(error)) exit body
            if (h5_exists(file, name)) then
                call h5dopen_f(file%id, name, dset, hdferr)
                if (hdferr < 0) then
                    call fatal_error(error, disk_path(file)//": cannot write dataset '"//name// &
                        "': an object of that name exists and is not a dataset", err_io)
                    exit body
                end if
                call close_id(dset)
                call h5ldelete_f(file%id, name, hdferr)
                call check(hdferr, file, "replace dataset", name, "h5ldelete_f", error)
                if (allocated(error)) exit body
            end if
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
            call put_string_attr(dset, "units", units, hdferr)
            if (hdferr >= 0) call put_string_attr(dset, "description", description, hdferr)
            if (hdferr >= 0 .and. present(dim_names)) call put_string_attr(dset, "dimensions", dim_names, hdferr)
            call check(hdferr, file, "write attributes of dataset", name, "h5awrite_f", error)
            if (allocated(error)) exit body
            if (present(dim_names)) call remember_dims(file, name, dim_names)
        end block body
        call close_id(dset)
        call close_id(lcpl)
        call close_id(space)
        call stick(file, error)
    end subroutine write_dataset

    !> Write strings as a fixed-length string dataset: scalar (`array` false, one string, stored as given) or rank 1
    !> (trailing blanks of each element dropped).
    subroutine write_strings(file, name, data, array, units, description, dim_names)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, units, description, data(:)
        logical, intent(in) :: array
        character(len=*), intent(in), optional :: dim_names
        character(kind=c_char, len=1), allocatable, target :: chars(:)
        integer(hsize_t), allocatable :: dims(:)
        type(error_type), allocatable :: error
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
        call stick(file, error)
        if (.not. allocated(file%error)) then
            buf = c_loc(chars)
            call write_dataset(file, name, string_type, string_type, dims, buf, units, description, dim_names)
        end if
        call close_id(string_type)
    end subroutine write_strings

end module supratrans_h5_write
