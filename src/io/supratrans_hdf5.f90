!> Thin, typed, self-describing HDF5 layer: every output file of supratrans is written through this module.
!>
!> ## Files
!> A new output file is written as `<path>.tmp` (`h5_create`) and renamed atomically to `<path>` by `h5_commit`
!> (POSIX `rename`), so a file found under its final name is complete. `h5_discard` closes and deletes the
!> temporary file after an error. An existing file is opened with `h5_open`, read-only or read-write. To resume a
!> killed run, open its left-over `<path>.tmp` read-write with `final_path = <path>`: `h5_commit` then renames it
!> when the resumed run is complete. `h5_close` closes without renaming (a temporary file stays `<path>.tmp`).
!>
!> ## Objects and self-description
!> Object names are paths from the root group: "ledger/energy" and "/ledger/energy" are the same object; missing
!> intermediate groups are created. Every dataset carries the string attributes `units` and `description`;
!> arrays written with the optional `dims` argument also carry `dimensions`, the comma-separated names of the
!> dimensions in C/h5py order (see below). `h5_write` replaces an existing dataset of the same name (HDF5 does not
!> reclaim the space of the old one); `h5_write_attr` replaces an existing attribute.
!>
!> ## Dimension order
!> Arrays are stored as they are in memory, without transposition. HDF5 describes dataspaces in C (row-major)
!> order, so C, Python/h5py and h5dump list the Fortran dimensions reversed: a Fortran array `a(ntime, nprobe)`
!> appears in h5py as `d` of shape `(nprobe, ntime)` with `d[j-1, i-1] == a(i, j)`. Name the dimensions in that
!> C/h5py order: `dims = "probe, time"`. Reading back with this module restores the Fortran shape.
!> Extendable datasets (`h5_create_extendable`) grow along the last, slowest Fortran dimension, which is the first
!> h5py dimension: a ledger of rows `row(nvalue)` is `(nvalue, nrow)` in Fortran and `(nrow, nvalue)` in h5py.
!>
!> ## Types
!> `real(wp)` is stored as IEEE 64-bit float, default integer as 32-bit signed integer, `integer(i8)` as 64-bit
!> signed integer, character as fixed-length, null-padded ASCII string (h5py returns `bytes`; trailing blanks of
!> the elements of a character array are padding and are not stored). Logical attributes are stored under their
!> own name as 32-bit integer 0 (false) or 1 (true); reading one back gives `.true.` for any non-zero value.
!> Reading converts between numeric types by HDF5's rules, and reads fixed- and variable-length strings (so
!> strings written by h5py can be read too).
!>
!> ## Threads and errors
!> Serial HDF5 is not thread-safe: every routine of this module must be called from one thread only (outside
!> OpenMP parallel regions, or from one designated thread). The library is initialised lazily by `h5_create` and
!> `h5_open`, which also switch off HDF5's automatic printing of error stacks; failures are returned as an
!> `error_type` with status `err_io` and a message naming the file and the object. No routine stops the program.
module supratrans_hdf5
    use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_loc, c_f_pointer, c_associated, c_char, c_int, &
        c_size_t, c_null_char
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use hdf5, only: hid_t, hsize_t, size_t, h5open_f, h5eset_auto_f, h5kind_to_type, h5_real_kind, h5_integer_kind, &
        h5fcreate_f, h5fopen_f, h5fclose_f, h5fflush_f, h5f_acc_trunc_f, h5f_acc_rdonly_f, h5f_acc_rdwr_f, &
        h5f_scope_global_f, h5dcreate_f, h5dopen_f, h5dclose_f, h5dwrite_f, h5dread_f, h5dget_space_f, &
        h5dget_type_f, h5dset_extent_f, h5dvlen_reclaim_f, h5screate_f, h5screate_simple_f, h5sclose_f, &
        h5sget_simple_extent_ndims_f, h5sget_simple_extent_dims_f, h5sget_simple_extent_npoints_f, &
        h5sselect_hyperslab_f, h5s_scalar_f, h5s_unlimited_f, h5s_select_set_f, h5pcreate_f, h5pclose_f, &
        h5pset_chunk_f, h5pset_fill_value_f, h5pset_create_inter_group_f, h5p_dataset_create_f, &
        h5p_link_create_f, h5p_default_f, h5tcopy_f, h5tclose_f, h5tset_size_f, h5tget_size_f, h5tset_strpad_f, &
        h5tget_strpad_f, h5tget_class_f, h5tis_variable_str_f, h5tget_cset_f, h5tset_cset_f, h5t_c_s1, &
        h5t_string, h5t_string_f, h5t_str_nullpad_f, h5t_str_spacepad_f, h5t_ieee_f64le, h5t_std_i32le, &
        h5t_std_i64le, h5gcreate_f, h5gclose_f, h5oopen_f, h5lexists_f, h5ldelete_f, h5aexists_f, &
        h5aexists_by_name_f, h5adelete_f, h5acreate_f, h5aopen_by_name_f, h5aclose_f, h5awrite_f, h5aread_f, &
        h5aget_space_f, h5aget_type_f, h5iget_type_f, h5i_file_f, h5i_group_f, h5i_dataset_f, h5i_datatype_f, &
        h5i_dataspace_f, h5i_attr_f, h5i_genprop_lst_f
    use supratrans_kinds, only: wp, i8
    use supratrans_error, only: error_type, fatal_error, err_io
    implicit none
    private

    public :: h5_file
    public :: h5_create, h5_commit, h5_discard, h5_open, h5_close, h5_flush, h5_is_open
    public :: h5_write, h5_write_attr, h5_create_group
    public :: h5_create_extendable, h5_append, h5_write_at, h5_extent
    public :: h5_exists, h5_attr_exists, h5_read, h5_read_attr

    !> File state: not open.
    integer, parameter, public :: h5_mode_closed = 0
    !> File state: an existing file open read-only (`h5_open` with `writable = .false.`).
    integer, parameter, public :: h5_mode_read = 1
    !> File state: an existing file open read-write (`h5_open` with `writable = .true.`).
    integer, parameter, public :: h5_mode_readwrite = 2
    !> File state: a new file being written as `<path>.tmp` (`h5_create`); `h5_discard` deletes it.
    integer, parameter, public :: h5_mode_create = 3

    !> An HDF5 file handle: the HDF5 identifier, the final path, the temporary path and the state.
    !> Obtain one from `h5_create` or `h5_open`; do not set its components.
    type :: h5_file
        !> HDF5 file identifier (negative when closed).
        integer(hid_t) :: id = -1
        !> Final path of the file.
        character(len=:), allocatable :: path
        !> Path of the file on disk while it is written (`<path>.tmp`); empty when the file is written in place.
        character(len=:), allocatable :: tmp_path
        !> State: `h5_mode_closed`, `h5_mode_read`, `h5_mode_readwrite` or `h5_mode_create`.
        integer :: mode = h5_mode_closed
    end type h5_file

    !> Write a dataset with the attributes `units` and `description` (and `dimensions` when `dims` is given):
    !> `call h5_write(file, name, data, units, description, error [, dims])`.
    !> `data`: `real(wp)` of rank 0 to 3, default integer of rank 0 to 2, `integer(i8)` of rank 0 or 1,
    !> character of rank 0 or 1. `dims` (arrays only): dimension names in C/h5py order, e.g. "probe, time".
    interface h5_write
        module procedure :: write_real_0d, write_real_1d, write_real_2d, write_real_3d
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

    !> Append to an extendable dataset (`h5_create_extendable`): `call h5_append(file, name, values, error)`.
    !> 1-D dataset: appends the value(s); 2-D dataset of rows `(row_size, n)`: appends one row of `row_size` values.
    !> `values`: `real(wp)` or default integer, scalar or rank 1. Call `h5_flush` to make the data durable.
    interface h5_append
        module procedure :: append_real_0d, append_real_1d, append_int_0d, append_int_1d
    end interface h5_append

    !> Write at position `index` (1-based, along the extendable dimension) of an extendable dataset, extending it
    !> when `index` lies beyond its end: `call h5_write_at(file, name, index, values, error)`. Unwritten entries read
    !> as NaN (real) or 0 (integer). `values`: as for `h5_append`.
    interface h5_write_at
        module procedure :: write_at_real_0d, write_at_real_1d, write_at_int_0d, write_at_int_1d
    end interface h5_write_at

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

    interface
        !> C library `rename`: atomic replacement of `new_path` by `old_path` on POSIX file systems.
        function c_rename(old_path, new_path) bind(c, name="rename") result(stat)
            import :: c_char, c_int
            !> Existing path, null-terminated.
            character(kind=c_char), intent(in) :: old_path(*)
            !> New path, null-terminated.
            character(kind=c_char), intent(in) :: new_path(*)
            integer(c_int) :: stat
        end function c_rename

        !> C library `remove`: delete a file.
        function c_remove(path) bind(c, name="remove") result(stat)
            import :: c_char, c_int
            !> Path, null-terminated.
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int) :: stat
        end function c_remove

        !> C library `strlen`: length of a null-terminated string.
        function c_strlen(str) bind(c, name="strlen") result(length)
            import :: c_ptr, c_size_t
            !> Address of the string.
            type(c_ptr), value, intent(in) :: str
            integer(c_size_t) :: length
        end function c_strlen
    end interface

    !> A list of strings (works around spurious gfortran warnings on local deferred-length character arrays).
    type :: string_array
        !> The strings.
        character(len=:), allocatable :: items(:)
    end type string_array

    !> Default number of elements in a chunk of an extendable dataset (64 KiB of `real(wp)`).
    integer, parameter :: default_chunk_elements = 8192

contains

    ! ------------------------------------------------------------------------------------------------------------
    ! Files
    ! ------------------------------------------------------------------------------------------------------------

    !> Create a new file: it is written as `<path>.tmp` (truncated if it exists) until `h5_commit` renames it.
    !> Fails if `path` exists and `overwrite` is false; with `overwrite`, an existing `path` is replaced at commit.
    !> A left-over `<path>.tmp` of a killed run is truncated: to resume it, use `h5_open` with `final_path`.
    !> `file` must not hold an open file (it is reset, not closed).
    subroutine h5_create(file, path, overwrite, error)
        !> The new file handle.
        type(h5_file), intent(out) :: file
        !> Final path of the file.
        character(len=*), intent(in) :: path
        !> Whether an existing file `path` may be replaced.
        logical, intent(in) :: overwrite
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        logical :: exists
        integer :: hdferr
        integer(c_int) :: stat

        file%path = path
        file%tmp_path = path//".tmp"
        inquire (file=path, exist=exists)
        if (exists .and. .not. overwrite) then
            call fatal_error(error, path//": output file exists (set overwrite = .true. to replace it)", err_io)
            return
        end if
        call init_library(hdferr)
        if (hdferr < 0) then
            call fatal_error(error, path//": cannot initialise the HDF5 library", err_io)
            return
        end if
        call h5fcreate_f(file%tmp_path, h5f_acc_trunc_f, file%id, hdferr)
        if (hdferr < 0) then
            file%id = -1
            stat = c_remove(file%tmp_path//c_null_char)
            call fatal_error(error, file%tmp_path//": cannot create HDF5 file (h5fcreate_f failed: disk full, or no "// &
                "permission to write there?)", err_io)
            return
        end if
        file%mode = h5_mode_create
    end subroutine h5_create

    !> Open an existing file, read-only or read-write. With `final_path`, the file (normally a left-over
    !> `<final_path>.tmp`) is treated as the temporary file of `final_path`: `h5_commit` renames it.
    !> `file` must not hold an open file (it is reset, not closed).
    subroutine h5_open(file, path, writable, error, final_path)
        !> The file handle.
        type(h5_file), intent(out) :: file
        !> Path of the file to open.
        character(len=*), intent(in) :: path
        !> Open read-write (true) or read-only (false).
        logical, intent(in) :: writable
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Final path for `h5_commit` (requires `writable`).
        character(len=*), intent(in), optional :: final_path
        logical :: exists
        integer :: hdferr, flags

        if (present(final_path)) then
            if (.not. writable) then
                call fatal_error(error, path//": final_path requires opening the file writable", err_io)
                return
            end if
            file%path = final_path
            file%tmp_path = path
        else
            file%path = path
            file%tmp_path = ""
        end if
        inquire (file=path, exist=exists)
        if (.not. exists) then
            call fatal_error(error, path//": file not found", err_io)
            return
        end if
        call init_library(hdferr)
        if (hdferr < 0) then
            call fatal_error(error, path//": cannot initialise the HDF5 library", err_io)
            return
        end if
        if (writable) then
            flags = h5f_acc_rdwr_f
        else
            flags = h5f_acc_rdonly_f
        end if
        call h5fopen_f(path, flags, file%id, hdferr)
        if (hdferr < 0) then
            file%id = -1
            call fatal_error(error, path//": cannot open as HDF5 file (h5fopen_f failed: not HDF5, or locked?)", &
                err_io)
            return
        end if
        if (writable) then
            file%mode = h5_mode_readwrite
        else
            file%mode = h5_mode_read
        end if
    end subroutine h5_open

    !> Whether the file is open.
    pure function h5_is_open(file) result(is_open)
        !> The file.
        type(h5_file), intent(in) :: file
        logical :: is_open

        is_open = file%mode /= h5_mode_closed
    end function h5_is_open

    !> Flush all buffers of the file to disk (after appending the results of a run).
    subroutine h5_flush(file, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer :: hdferr

        call check_open(file, "flush", "/", error)
        if (allocated(error)) return
        call h5fflush_f(file%id, h5f_scope_global_f, hdferr)
        call check(hdferr, file, "flush", "/", "h5fflush_f", error)
    end subroutine h5_flush

    !> Close the file. A file being written as `<path>.tmp` is not renamed (see `h5_commit`).
    !> Closing a closed file does nothing.
    subroutine h5_close(file, error)
        !> The file; closed on return.
        type(h5_file), intent(inout) :: file
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer :: hdferr

        if (file%mode == h5_mode_closed) return
        call h5fclose_f(file%id, hdferr)
        call check(hdferr, file, "close", "/", "h5fclose_f", error)
        file%id = -1
        file%mode = h5_mode_closed
    end subroutine h5_close

    !> Flush and close the file, then rename `<path>.tmp` atomically to `<path>` (replacing an existing file).
    !> A file opened in place (no temporary path) is just flushed and closed.
    subroutine h5_commit(file, error)
        !> The file; closed on return (on failure too, its temporary file then deleted).
        type(h5_file), intent(inout) :: file
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer :: hdferr, mode
        integer(c_int) :: stat

        call check_open(file, "commit", "/", error)
        if (allocated(error)) return
        mode = file%mode
        if (mode /= h5_mode_read) then
            call h5fflush_f(file%id, h5f_scope_global_f, hdferr)
            call check(hdferr, file, "flush", "/", "h5fflush_f", error)
            if (allocated(error)) then
                ! disk full or I/O error: close what can be closed and delete the temporary file, so that nothing
                ! half-written stays behind and no exit handler meets an open file
                error%message = error%message//" (disk full?)"
                call h5_discard(file)
                return
            end if
        end if
        call h5fclose_f(file%id, hdferr)
        file%id = -1
        file%mode = h5_mode_closed
        call check(hdferr, file, "close", "/", "h5fclose_f", error)
        if (allocated(error)) then
            if (mode == h5_mode_create) stat = c_remove(file%tmp_path//c_null_char)
            return
        end if
        if (mode == h5_mode_read .or. len(file%tmp_path) == 0) return
        if (c_rename(file%tmp_path//c_null_char, file%path//c_null_char) /= 0) then
            call fatal_error(error, file%tmp_path//": cannot rename to "//file%path, err_io)
            if (mode == h5_mode_create) stat = c_remove(file%tmp_path//c_null_char)
        end if
    end subroutine h5_commit

    !> Close the file, ignoring errors, and delete the temporary file of a file created by `h5_create`
    !> (use on error). A file opened by `h5_open` is only closed, never deleted.
    subroutine h5_discard(file)
        !> The file; closed on return.
        type(h5_file), intent(inout) :: file
        integer :: hdferr
        integer(c_int) :: stat

        if (file%mode == h5_mode_closed) return
        call h5fclose_f(file%id, hdferr)
        if (file%mode == h5_mode_create) stat = c_remove(file%tmp_path//c_null_char)
        file%id = -1
        file%mode = h5_mode_closed
    end subroutine h5_discard

    ! ------------------------------------------------------------------------------------------------------------
    ! Groups, existence, extents
    ! ------------------------------------------------------------------------------------------------------------

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

    !> Whether the object `name` exists; each level of a nested path is checked. "/" always exists in an open file.
    function h5_exists(file, name) result(exists)
        !> The file (open; false if closed).
        type(h5_file), intent(in) :: file
        !> Path of the object.
        character(len=*), intent(in) :: name
        logical :: exists
        integer :: k, last, hdferr

        exists = .false.
        if (file%mode == h5_mode_closed) return
        last = len_trim(name)
        do while (last > 0)
            if (name(last:last) /= "/") exit
            last = last - 1
        end do
        if (last == 0) then
            exists = .true.
            return
        end if
        do k = 2, last + 1
            if (k <= last) then
                if (name(k:k) /= "/" .or. name(k - 1:k - 1) == "/") cycle
            end if
            call h5lexists_f(file%id, name(1:k - 1), exists, hdferr)
            if (hdferr < 0) exists = .false.
            if (.not. exists) return
        end do
    end function h5_exists

    !> Whether the object `object` exists and has an attribute `name`.
    function h5_attr_exists(file, object, name) result(exists)
        !> The file (open; false if closed).
        type(h5_file), intent(in) :: file
        !> Path of the object ("/" for the root group).
        character(len=*), intent(in) :: object
        !> Name of the attribute.
        character(len=*), intent(in) :: name
        logical :: exists
        integer :: hdferr

        exists = h5_exists(file, object)
        if (.not. exists) return
        call h5aexists_by_name_f(file%id, root_if_empty(object), name, exists, hdferr)
        if (hdferr < 0) exists = .false.
    end function h5_attr_exists

    !> Current dimensions of a dataset, in Fortran order (the last one is the number of rows of an extendable
    !> dataset); size 0 for a scalar dataset.
    subroutine h5_extent(file, name, dims, error)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> Dimensions in Fortran order.
        integer, allocatable, intent(out) :: dims(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hsize_t), allocatable :: hdims(:)

        call query_dataset(file, name, -1, hdims, error)
        if (allocated(error)) return
        dims = int(hdims)
    end subroutine h5_extent

    ! ------------------------------------------------------------------------------------------------------------
    ! Writing datasets
    ! ------------------------------------------------------------------------------------------------------------

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

    ! ------------------------------------------------------------------------------------------------------------
    ! Writing attributes
    ! ------------------------------------------------------------------------------------------------------------

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

    ! ------------------------------------------------------------------------------------------------------------
    ! Extendable datasets
    ! ------------------------------------------------------------------------------------------------------------

    !> Create an extendable, chunked dataset of zero length that grows along its last (Fortran) dimension:
    !> 1-D of values when `row_size == 0`, else 2-D of rows, shape `(row_size, 0)` in Fortran, `(0, row_size)` in h5py.
    !> If the dataset exists with the same row size (a resumed run), it is left as it is.
    subroutine h5_create_extendable(file, name, row_size, units, description, error, dims, chunk_rows, integer_data)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> Number of values per row; 0 for a 1-D dataset.
        integer, intent(in) :: row_size
        !> Units ("1" for dimensionless).
        character(len=*), intent(in) :: units
        !> What the values are.
        character(len=*), intent(in) :: description
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Names of the dimensions in C/h5py order, e.g. "run, quantity"; stored as attribute `dimensions`.
        character(len=*), intent(in), optional :: dims
        !> Rows (or values of a 1-D dataset) per chunk; default about 8192 values per chunk.
        integer, intent(in), optional :: chunk_rows
        !> Store default integers instead of `real(wp)` values (default false).
        logical, intent(in), optional :: integer_data
        integer(hsize_t), allocatable :: cur(:), maxdims(:), chunk(:)
        integer(hid_t) :: space, dcpl, lcpl, dset, mem_type, file_type
        integer, allocatable :: existing(:)
        integer :: hdferr, rows, rank
        logical :: integers
        real(wp), target :: real_fill
        integer, target :: int_fill
        type(c_ptr) :: fill

        call check_writable(file, "create dataset", name, error)
        if (allocated(error)) return
        if (row_size < 0) then
            call fatal_error(error, disk_path(file)//": negative row size for dataset '"//name//"'", err_io)
            return
        end if
        rank = merge(1, 2, row_size == 0)
        if (present(dims)) then
            call check_dim_names(file, name, dims, rank, error)
            if (allocated(error)) return
        end if
        if (h5_exists(file, name)) then
            call h5_extent(file, name, existing, error)
            if (allocated(error)) return
            if (size(existing) /= rank .or. (rank == 2 .and. existing(1) /= row_size)) then
                call fatal_error(error, disk_path(file)//": dataset '"//name// &
                    "' exists with another shape than the requested extendable dataset", err_io)
            end if
            return
        end if

        integers = .false.
        if (present(integer_data)) integers = integer_data
        rows = max(1, default_chunk_elements/max(1, row_size))
        if (present(chunk_rows)) rows = max(1, chunk_rows)
        allocate (cur(rank), maxdims(rank), chunk(rank))
        if (rank == 1) then
            cur(:) = [0_hsize_t]
            maxdims(:) = [h5s_unlimited_f]
            chunk(:) = [int(rows, hsize_t)]
        else
            cur(:) = [int(row_size, hsize_t), 0_hsize_t]
            maxdims(:) = [int(row_size, hsize_t), h5s_unlimited_f]
            chunk(:) = [int(row_size, hsize_t), int(rows, hsize_t)]
        end if
        if (integers) then
            mem_type = int_mem_type()
            file_type = int_file_type()
            int_fill = 0
            fill = c_loc(int_fill)
        else
            mem_type = real_mem_type()
            file_type = h5t_ieee_f64le
            real_fill = ieee_value(real_fill, ieee_quiet_nan)
            fill = c_loc(real_fill)
        end if

        space = -1
        dcpl = -1
        lcpl = -1
        dset = -1
        body: block
            call h5screate_simple_f(rank, cur, space, hdferr, maxdims)
            call check(hdferr, file, "create dataspace of", name, "h5screate_simple_f", error)
            if (allocated(error)) exit body
            call h5pcreate_f(h5p_dataset_create_f, dcpl, hdferr)
            call check(hdferr, file, "create properties of", name, "h5pcreate_f", error)
            if (allocated(error)) exit body
            call h5pset_chunk_f(dcpl, rank, chunk, hdferr)
            call check(hdferr, file, "set chunks of", name, "h5pset_chunk_f", error)
            if (allocated(error)) exit body
            call h5pset_fill_value_f(dcpl, mem_type, fill, hdferr)
            call check(hdferr, file, "set fill value of", name, "h5pset_fill_value_f", error)
            if (allocated(error)) exit body
            call make_lcpl(lcpl, hdferr)
            call check(hdferr, file, "create link properties for", name, "h5pset_create_inter_group_f", error)
            if (allocated(error)) exit body
            call h5dcreate_f(file%id, name, file_type, space, dset, hdferr, dcpl_id=dcpl, lcpl_id=lcpl)
            call check(hdferr, file, "create dataset", name, "h5dcreate_f", error)
            if (allocated(error)) exit body
            call describe_object(dset, units, description, hdferr, dims)
            call check(hdferr, file, "write attributes of dataset", name, "h5awrite_f", error)
        end block body
        call close_id(dset)
        call close_id(lcpl)
        call close_id(dcpl)
        call close_id(space)
    end subroutine h5_create_extendable

    !> Append `real(wp)` value to a 1-D extendable dataset.
    subroutine append_real_0d(file, name, values, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The value.
        real(wp), intent(in), target :: values
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error

        call write_rows(file, name, .true., 0, real_mem_type(), 1, c_loc(values), error)
    end subroutine append_real_0d

    !> Append `real(wp)` values to a 1-D extendable dataset, or one row to a 2-D one.
    subroutine append_real_1d(file, name, values, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The values or the row.
        real(wp), intent(in), target, contiguous :: values(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(values) > 0) buf = c_loc(values)
        call write_rows(file, name, .true., 0, real_mem_type(), size(values), buf, error)
    end subroutine append_real_1d

    !> Append a default-integer value to a 1-D extendable dataset.
    subroutine append_int_0d(file, name, values, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The value.
        integer, intent(in), target :: values
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error

        call write_rows(file, name, .true., 0, int_mem_type(), 1, c_loc(values), error)
    end subroutine append_int_0d

    !> Append default-integer values to a 1-D extendable dataset, or one row to a 2-D one.
    subroutine append_int_1d(file, name, values, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> The values or the row.
        integer, intent(in), target, contiguous :: values(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(values) > 0) buf = c_loc(values)
        call write_rows(file, name, .true., 0, int_mem_type(), size(values), buf, error)
    end subroutine append_int_1d

    !> Write a `real(wp)` value at position `index` of a 1-D extendable dataset.
    subroutine write_at_real_0d(file, name, index, values, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> Position, 1-based.
        integer, intent(in) :: index
        !> The value.
        real(wp), intent(in), target :: values
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error

        call write_rows(file, name, .false., index, real_mem_type(), 1, c_loc(values), error)
    end subroutine write_at_real_0d

    !> Write `real(wp)` values from position `index` of a 1-D extendable dataset, or row `index` of a 2-D one.
    subroutine write_at_real_1d(file, name, index, values, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> Position or row, 1-based.
        integer, intent(in) :: index
        !> The values or the row.
        real(wp), intent(in), target, contiguous :: values(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(values) > 0) buf = c_loc(values)
        call write_rows(file, name, .false., index, real_mem_type(), size(values), buf, &
            error)
    end subroutine write_at_real_1d

    !> Write a default-integer value at position `index` of a 1-D extendable dataset.
    subroutine write_at_int_0d(file, name, index, values, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> Position, 1-based.
        integer, intent(in) :: index
        !> The value.
        integer, intent(in), target :: values
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error

        call write_rows(file, name, .false., index, int_mem_type(), 1, c_loc(values), error)
    end subroutine write_at_int_0d

    !> Write default-integer values from position `index` of a 1-D extendable dataset, or row `index` of a 2-D one.
    subroutine write_at_int_1d(file, name, index, values, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> Position or row, 1-based.
        integer, intent(in) :: index
        !> The values or the row.
        integer, intent(in), target, contiguous :: values(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        type(c_ptr) :: buf

        buf = c_null_ptr
        if (size(values) > 0) buf = c_loc(values)
        call write_rows(file, name, .false., index, int_mem_type(), size(values), buf, error)
    end subroutine write_at_int_1d

    ! ------------------------------------------------------------------------------------------------------------
    ! Reading datasets
    ! ------------------------------------------------------------------------------------------------------------

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
            call fatal_error(error, disk_path(file)//": dataset '"//name//"' holds "//itoa(size(values%items))// &
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

    ! ------------------------------------------------------------------------------------------------------------
    ! Reading attributes
    ! ------------------------------------------------------------------------------------------------------------

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
                itoa(size(values%items))//" strings, expected one", err_io)
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

    ! ------------------------------------------------------------------------------------------------------------
    ! Private helpers
    ! ------------------------------------------------------------------------------------------------------------

    !> Initialise HDF5 once (h5open_f) and switch off its automatic printing of error stacks.
    subroutine init_library(hdferr)
        !> HDF5 status, negative on failure.
        integer, intent(out) :: hdferr
        !> Whether HDF5 has been initialised: the only mutable module state (HDF5 must be initialised once).
        logical, save :: initialized = .false.

        hdferr = 0
        if (initialized) return
        call h5open_f(hdferr)
        if (hdferr < 0) return
        call h5eset_auto_f(0, hdferr)
        if (hdferr < 0) return
        initialized = .true.
    end subroutine init_library

    !> Memory type of `real(wp)`.
    function real_mem_type() result(type_id)
        integer(hid_t) :: type_id

        type_id = h5kind_to_type(wp, h5_real_kind)
    end function real_mem_type

    !> Memory type of default integers.
    function int_mem_type() result(type_id)
        integer(hid_t) :: type_id

        type_id = h5kind_to_type(kind(0), h5_integer_kind)
    end function int_mem_type

    !> File type of default integers (little-endian, of their size).
    function int_file_type() result(type_id)
        integer(hid_t) :: type_id

        if (storage_size(0) == 64) then
            type_id = h5t_std_i64le
        else
            type_id = h5t_std_i32le
        end if
    end function int_file_type

    !> Memory type of `integer(i8)`.
    function i8_mem_type() result(type_id)
        integer(hid_t) :: type_id

        type_id = h5kind_to_type(i8, h5_integer_kind)
    end function i8_mem_type

    !> Decimal representation of an integer.
    pure function itoa(i) result(text)
        !> The integer.
        integer, intent(in) :: i
        character(len=:), allocatable :: text
        character(len=24) :: buffer

        write (buffer, "(i0)") i
        text = trim(buffer)
    end function itoa

    !> The path of the file on disk (the temporary path while it is written).
    pure function disk_path(file) result(path)
        !> The file.
        type(h5_file), intent(in) :: file
        character(len=:), allocatable :: path

        path = "(no file)"
        if (allocated(file%path)) path = file%path
        if (allocated(file%tmp_path)) then
            if (len(file%tmp_path) > 0) path = file%tmp_path
        end if
    end function disk_path

    !> "/" for an empty object path, else the path.
    pure function root_if_empty(object) result(path)
        !> Path of an object.
        character(len=*), intent(in) :: object
        character(len=:), allocatable :: path

        if (len_trim(object) == 0) then
            path = "/"
        else
            path = object
        end if
    end function root_if_empty

    !> Turn a negative HDF5 status into an `err_io` error "<file>: cannot <action> '<object>' (<routine> failed)".
    subroutine check(hdferr, file, action, object, routine, error)
        !> HDF5 status.
        integer, intent(in) :: hdferr
        !> The file.
        type(h5_file), intent(in) :: file
        !> What was attempted, e.g. "create dataset".
        character(len=*), intent(in) :: action
        !> The object concerned.
        character(len=*), intent(in) :: object
        !> The HDF5 routine that failed.
        character(len=*), intent(in) :: routine
        !> Error, allocated if `hdferr < 0`.
        type(error_type), allocatable, intent(out) :: error

        if (hdferr < 0) then
            call fatal_error(error, disk_path(file)//": cannot "//action//" '"//object//"' ("//routine//" failed)", &
                err_io)
        end if
    end subroutine check

    !> Error unless the file is open.
    subroutine check_open(file, action, object, error)
        !> The file.
        type(h5_file), intent(in) :: file
        !> What is attempted.
        character(len=*), intent(in) :: action
        !> The object concerned.
        character(len=*), intent(in) :: object
        !> Error, allocated if the file is closed.
        type(error_type), allocatable, intent(out) :: error

        if (file%mode == h5_mode_closed) then
            call fatal_error(error, disk_path(file)//": file is not open, cannot "//action//" '"//object//"'", err_io)
        end if
    end subroutine check_open

    !> Error unless the file is open for writing.
    subroutine check_writable(file, action, object, error)
        !> The file.
        type(h5_file), intent(in) :: file
        !> What is attempted.
        character(len=*), intent(in) :: action
        !> The object concerned.
        character(len=*), intent(in) :: object
        !> Error, allocated if the file is closed or read-only.
        type(error_type), allocatable, intent(out) :: error

        call check_open(file, action, object, error)
        if (allocated(error)) return
        if (file%mode == h5_mode_read) then
            call fatal_error(error, disk_path(file)//": file is open read-only, cannot "//action//" '"//object//"'", &
                err_io)
        end if
    end subroutine check_writable

    !> Error unless `names` holds `rank` comma-separated dimension names.
    subroutine check_dim_names(file, name, names, rank, error)
        !> The file.
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> Comma-separated dimension names.
        character(len=*), intent(in) :: names
        !> Rank of the dataset.
        integer, intent(in) :: rank
        !> Error, allocated on a mismatch.
        type(error_type), allocatable, intent(out) :: error
        integer :: count, k

        count = 1
        do k = 1, len(names)
            if (names(k:k) == ",") count = count + 1
        end do
        if (count /= rank .or. len_trim(names) == 0) then
            call fatal_error(error, disk_path(file)//": dims = '"//names//"' names "//itoa(count)// &
                " dimensions, dataset '"//name//"' has rank "//itoa(rank), err_io)
        end if
    end subroutine check_dim_names

    !> Close any HDF5 identifier (file, group, dataset, datatype, dataspace, attribute, property list) and set it to
    !> -1; negative identifiers are ignored. Never pass a predefined datatype.
    subroutine close_id(id)
        !> The identifier.
        integer(hid_t), intent(inout) :: id
        integer :: id_type, hdferr

        if (id < 0) return
        call h5iget_type_f(id, id_type, hdferr)
        if (hdferr >= 0) then
            if (id_type == h5i_dataset_f) then
                call h5dclose_f(id, hdferr)
            else if (id_type == h5i_group_f) then
                call h5gclose_f(id, hdferr)
            else if (id_type == h5i_datatype_f) then
                call h5tclose_f(id, hdferr)
            else if (id_type == h5i_dataspace_f) then
                call h5sclose_f(id, hdferr)
            else if (id_type == h5i_attr_f) then
                call h5aclose_f(id, hdferr)
            else if (id_type == h5i_genprop_lst_f) then
                call h5pclose_f(id, hdferr)
            else if (id_type == h5i_file_f) then
                call h5fclose_f(id, hdferr)
            end if
        end if
        id = -1
    end subroutine close_id

    !> Create a scalar dataspace (no dimensions) or a simple one.
    subroutine make_space(dims, space, hdferr)
        !> Dimensions in Fortran order; empty for a scalar.
        integer(hsize_t), intent(in) :: dims(:)
        !> The dataspace.
        integer(hid_t), intent(out) :: space
        !> HDF5 status.
        integer, intent(out) :: hdferr

        if (size(dims) == 0) then
            call h5screate_f(h5s_scalar_f, space, hdferr)
        else
            call h5screate_simple_f(size(dims), dims, space, hdferr)
        end if
    end subroutine make_space

    !> Create a link-creation property list that creates missing intermediate groups.
    subroutine make_lcpl(lcpl, hdferr)
        !> The property list.
        integer(hid_t), intent(out) :: lcpl
        !> HDF5 status.
        integer, intent(out) :: hdferr

        call h5pcreate_f(h5p_link_create_f, lcpl, hdferr)
        if (hdferr < 0) return
        call h5pset_create_inter_group_f(lcpl, 1, hdferr)
    end subroutine make_lcpl

    !> Create a fixed-length, null-padded ASCII string type of `length` characters (at least 1).
    subroutine make_string_type(length, type_id, hdferr)
        !> Number of characters.
        integer, intent(in) :: length
        !> The datatype.
        integer(hid_t), intent(out) :: type_id
        !> HDF5 status.
        integer, intent(out) :: hdferr

        call h5tcopy_f(h5t_c_s1, type_id, hdferr)
        if (hdferr < 0) return
        call h5tset_size_f(type_id, int(max(length, 1), size_t), hdferr)
        if (hdferr < 0) return
        call h5tset_strpad_f(type_id, h5t_str_nullpad_f, hdferr)
    end subroutine make_string_type

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
                call fatal_error(error, disk_path(file)//": "//what//" holds "//itoa(int(product(dims)))// &
                    " values, expected a scalar", err_io)
            end if
        else if (size(dims) /= rank) then
            call fatal_error(error, disk_path(file)//": "//what//" has rank "//itoa(size(dims))//", expected "// &
                itoa(rank), err_io)
        end if
    end subroutine check_rank

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
            call fatal_error(error, disk_path(file)//": cannot "//what//" '"//object//"' as text: not a string", err_io)
        else
            call check(hdferr, file, what, object, "h5dread_f/h5aread_f", error)
        end if
        call close_id(id)
    end subroutine read_strings

    !> Read all strings of an open dataset or attribute, fixed or variable length. Status -2: not a string type.
    subroutine read_string_values(id, is_attr, values, hdferr)
        !> The dataset or attribute.
        integer(hid_t), intent(in) :: id
        !> Whether `id` is an attribute.
        logical, intent(in) :: is_attr
        !> The strings without padding, blank-padded to the longest.
        character(len=:), allocatable, intent(out) :: values(:)
        !> HDF5 status; -2 if the datatype is not a string.
        integer, intent(out) :: hdferr
        integer(hid_t) :: file_type, mem_type, space
        integer(hsize_t) :: npoints
        integer(size_t) :: width
        integer :: type_class, pad, cset, n, i, k
        integer, allocatable :: lengths(:)
        logical :: variable
        type(c_ptr), allocatable, target :: pointers(:)
        character(kind=c_char, len=1), allocatable, target :: chars(:)
        character(kind=c_char, len=1), pointer :: cstring(:)
        type(c_ptr) :: buf

        file_type = -1
        mem_type = -1
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
                ! Variable-length strings (e.g. written by h5py): read C pointers, copy, let HDF5 free them.
                call h5tcopy_f(h5t_string, mem_type, hdferr)
                if (hdferr < 0) exit body
                call h5tget_cset_f(file_type, cset, hdferr)
                if (hdferr < 0) exit body
                call h5tset_cset_f(mem_type, cset, hdferr)
                if (hdferr < 0) exit body
                allocate (pointers(max(n, 1)))
                buf = c_loc(pointers)
                if (n > 0) then
                    call read_raw(id, is_attr, mem_type, buf, hdferr)
                    if (hdferr < 0) exit body
                end if
                lengths = 0
                do i = 1, n
                    if (c_associated(pointers(i))) lengths(i) = int(c_strlen(pointers(i)))
                end do
                deallocate (values)
                allocate (character(len=maxval([0, lengths])) :: values(n))
                do i = 1, n
                    values(i) = ""
                    if (lengths(i) == 0) cycle
                    call c_f_pointer(pointers(i), cstring, [lengths(i)])
                    do k = 1, lengths(i)
                        values(i) (k:k) = cstring(k)
                    end do
                end do
                if (n > 0) call h5dvlen_reclaim_f(mem_type, space, h5p_default_f, buf, hdferr)
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
        call close_id(mem_type)
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

    !> Write `nvalues` values at the end or at `index` (1-based) along the extendable dimension of dataset `name`.
    subroutine write_rows(file, name, append, index, mem_type, nvalues, buf, error)
        !> The file (writable).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> Append after the last row (then `index` is ignored).
        logical, intent(in) :: append
        !> Position (1-D) or row (2-D), 1-based.
        integer, intent(in) :: index
        !> Datatype in memory.
        integer(hid_t), intent(in) :: mem_type
        !> Number of values.
        integer, intent(in) :: nvalues
        !> Address of the values.
        type(c_ptr), intent(in) :: buf
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer(hid_t) :: dset, space, mem_space
        integer(hsize_t), allocatable :: dims(:), start(:), count(:), new_dims(:)
        integer :: hdferr, rank

        call check_writable(file, "append to dataset", name, error)
        if (allocated(error)) return
        if (.not. append .and. index < 1) then
            call fatal_error(error, disk_path(file)//": index "//itoa(index)//" < 1 for dataset '"//name//"'", err_io)
            return
        end if
        if (nvalues == 0) return
        if (.not. h5_exists(file, name)) then
            call fatal_error(error, disk_path(file)//": no dataset '"//name//"' to append to", err_io)
            return
        end if
        dset = -1
        space = -1
        mem_space = -1
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
            rank = size(dims)
            allocate (start(rank), count(rank), new_dims(rank))
            if (rank == 1) then
                start(1) = dims(1)
                if (.not. append) start(1) = int(index - 1, hsize_t)
                count(1) = int(nvalues, hsize_t)
            else if (rank == 2) then
                if (int(nvalues, hsize_t) /= dims(1)) then
                    call fatal_error(error, disk_path(file)//": row of "//itoa(nvalues)//" values for dataset '"// &
                        name//"' of rows of "//itoa(int(dims(1)))//" values", err_io)
                    exit body
                end if
                start(1) = 0
                start(2) = dims(2)
                if (.not. append) start(2) = int(index - 1, hsize_t)
                count(1) = dims(1)
                count(2) = 1
            else
                call fatal_error(error, disk_path(file)//": dataset '"//name//"' is not a 1-D or 2-D dataset", err_io)
                exit body
            end if
            new_dims(:) = max(dims, start + count)
            if (any(new_dims /= dims)) then
                call h5dset_extent_f(dset, new_dims, hdferr)
                call check(hdferr, file, "extend dataset (is it extendable?)", name, "h5dset_extent_f", error)
                if (allocated(error)) exit body
                call close_id(space)
                call h5dget_space_f(dset, space, hdferr)
                call check(hdferr, file, "get dataspace of", name, "h5dget_space_f", error)
                if (allocated(error)) exit body
            end if
            call h5sselect_hyperslab_f(space, h5s_select_set_f, start, count, hdferr)
            call check(hdferr, file, "select rows of", name, "h5sselect_hyperslab_f", error)
            if (allocated(error)) exit body
            call h5screate_simple_f(1, [int(nvalues, hsize_t)], mem_space, hdferr)
            call check(hdferr, file, "create memory dataspace for", name, "h5screate_simple_f", error)
            if (allocated(error)) exit body
            call h5dwrite_f(dset, mem_type, buf, hdferr, mem_space_id=mem_space, file_space_id=space)
            call check(hdferr, file, "write rows of", name, "h5dwrite_f", error)
        end block body
        call close_id(mem_space)
        call close_id(space)
        call close_id(dset)
    end subroutine write_rows

end module supratrans_hdf5
