!> The HDF5 file of supratrans: its handle (`h5_file`), its life cycle, and the helpers the reading and writing
!> modules share (types, identifiers, errors). Use `supratrans_hdf5`, which gathers the public interface and
!> documents the layer. A new file is built in memory (HDF5's core driver, no backing store), so that HDF5 never
!> writes to the disk itself: a full disk cannot fail inside the library (which used to leave it in a state that
!> crashed at exit); `h5_commit` (`supratrans_h5_scales`) writes the image.
module supratrans_h5_file
    use hdf5, only: hid_t, hsize_t, size_t, h5open_f, h5eset_auto_f, h5kind_to_type, h5_real_kind, h5_integer_kind, &
        h5fcreate_f, h5fopen_f, h5fclose_f, h5f_acc_trunc_f, h5f_acc_rdonly_f, &
        h5dclose_f, h5screate_f, h5screate_simple_f, h5sclose_f, h5s_scalar_f, h5pcreate_f, h5pclose_f, &
        h5pset_create_inter_group_f, h5p_link_create_f, h5p_file_access_f, h5pset_fapl_core_f, &
        h5tcopy_f, h5tclose_f, h5tset_size_f, h5tset_strpad_f, h5t_c_s1, &
        h5t_str_nullpad_f, h5t_std_i32le, h5t_std_i64le, h5gclose_f, h5lexists_f, h5aexists_by_name_f, h5aclose_f, &
        h5iget_type_f, h5i_file_f, h5i_group_f, h5i_dataset_f, h5i_datatype_f, h5i_dataspace_f, h5i_attr_f, &
        h5i_genprop_lst_f
    use supratrans_kinds, only: wp, i8
    use supratrans_error, only: error_type, fatal_error, err_io
    use supratrans_strings, only: int_str
    use supratrans_system, only: temp_name, link_kind, path_missing, path_regular
    implicit none
    private

    public :: h5_create, h5_open, h5_close, h5_discard, h5_exists, h5_attr_exists, fail, &
        real_mem_type, int_mem_type, int_file_type, i8_mem_type, disk_path, root_if_empty, check, failed_call, &
        check_writable, check_dim_names, close_id, make_space, make_lcpl, make_string_type, remember_dims

    !> File state: not open.
    integer, parameter, public :: h5_mode_closed = 0
    !> File state: an existing file open read-only (`h5_open`).
    integer, parameter, public :: h5_mode_read = 1
    !> File state: a new file being built in memory (`h5_create`); `h5_commit` writes it to the disk.
    integer, parameter, public :: h5_mode_create = 3
    !> Growth of the in-memory image of a new file (bytes).
    integer(size_t), parameter :: core_increment = 1048576_size_t

    !> An HDF5 file handle: the HDF5 identifier, the final path, the state and the first error (which sticks).
    !> Obtain one from `h5_create` or `h5_open`; do not set its components.
    type, public :: h5_file
        !> HDF5 file identifier (negative when closed).
        integer(hid_t) :: id = -1
        !> Final path of the file.
        character(len=:), allocatable :: path
        !> State: `h5_mode_closed`, `h5_mode_read` or `h5_mode_create`.
        integer :: mode = h5_mode_closed
        !> The first error of `h5_create` or of a write; allocated, it makes every later write do nothing and
        !> `h5_commit` refuse.
        type(error_type), allocatable :: error
        !> Datasets written with dimension names, one line each: `<dataset><TAB><names>` (scales attached at commit).
        character(len=:), allocatable :: dim_table
    end type h5_file

contains

    !> Create a new file, built in memory until `h5_commit` writes it under `path`. Refused (the error sticks in
    !> `file`) if anything is at `path` and `overwrite` is false (a dangling link or a FIFO included); with
    !> `overwrite`, an existing regular file `path` is replaced at commit, anything else (a link, a FIFO, a device,
    !> a directory) is refused. `file` must not hold an open file (it is reset, not closed).
    subroutine h5_create(file, path, overwrite)
        !> The new file handle; its `error` is allocated on failure.
        type(h5_file), intent(out) :: file
        !> Final path of the file.
        character(len=*), intent(in) :: path
        !> Whether an existing file `path` may be replaced.
        logical, intent(in) :: overwrite
        integer(hid_t) :: fapl
        integer :: hdferr, kind

        file%path = path
        file%dim_table = ""
        kind = link_kind(path)
        if (kind /= path_missing .and. .not. overwrite) then
            call fatal_error(file%error, path//": output file exists (set overwrite = .true. to replace it)", err_io)
            return
        end if
        if (kind /= path_missing .and. kind /= path_regular) then
            call fatal_error(file%error, path//": exists and is not a regular file (a symbolic link, FIFO, device "// &
                "or directory): supratrans replaces only regular files; remove it or choose another output file", err_io)
            return
        end if
        fapl = -1
        call init_library(hdferr)
        if (hdferr >= 0) call h5pcreate_f(h5p_file_access_f, fapl, hdferr)
        if (hdferr >= 0) call h5pset_fapl_core_f(fapl, core_increment, .false., hdferr)
        ! the in-memory file is named like a temporary (random, never on disk): two files built at once for one path
        ! do not collide in HDF5's table of open files
        if (hdferr >= 0) call h5fcreate_f(temp_name(path), h5f_acc_trunc_f, file%id, hdferr, access_prp=fapl)
        call close_id(fapl)
        if (hdferr < 0) then
            file%id = -1
            call fatal_error(file%error, path//": cannot create an HDF5 file in memory (h5open_f/h5fcreate_f failed: "// &
                "out of memory?)", err_io)
            return
        end if
        file%mode = h5_mode_create
    end subroutine h5_create

    !> Open an existing file read-only. `file` must not hold an open file (it is reset, not closed).
    subroutine h5_open(file, path, error)
        !> The file handle.
        type(h5_file), intent(out) :: file
        !> Path of the file to open.
        character(len=*), intent(in) :: path
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        logical :: exists
        integer :: hdferr

        file%path = path
        file%dim_table = ""
        inquire (file=path, exist=exists)
        if (.not. exists) then
            call fatal_error(error, path//": file not found", err_io)
            return
        end if
        call init_library(hdferr)
        if (hdferr >= 0) call h5fopen_f(path, h5f_acc_rdonly_f, file%id, hdferr)
        if (hdferr < 0) then
            file%id = -1
            call fatal_error(error, path//": cannot open as HDF5 file (h5open_f/h5fopen_f failed: not HDF5, or "// &
                "locked?)", err_io)
            return
        end if
        file%mode = h5_mode_read
    end subroutine h5_open

    !> Close a file opened by `h5_open` (a new file is closed without being written: use `h5_commit`).
    !> Closing a closed file does nothing.
    subroutine h5_close(file, error)
        !> The file; closed on return.
        type(h5_file), intent(inout) :: file
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer :: hdferr

        hdferr = 0
        if (file%mode /= h5_mode_closed) call h5fclose_f(file%id, hdferr)
        call check(hdferr, file, "close", "/", "h5fclose_f", error)
        file%id = -1
        file%mode = h5_mode_closed
    end subroutine h5_close

    !> Close the file, ignoring errors, without writing anything (use on error). The stuck error stays in `file`.
    subroutine h5_discard(file)
        !> The file; closed on return.
        type(h5_file), intent(inout) :: file

        if (file%mode /= h5_mode_closed) call close_id(file%id)
        file%id = -1
        file%mode = h5_mode_closed
    end subroutine h5_discard

    !> Remember that dataset `name` has the dimensions `dims` (C/h5py order), for `attach_scales` at commit.
    pure subroutine remember_dims(file, name, dims)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, dims

        if (.not. allocated(file%dim_table)) file%dim_table = ""
        file%dim_table = file%dim_table//name//achar(9)//dims//achar(10)
    end subroutine remember_dims

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

    !> Initialise the HDF5 library and its Fortran interface (`h5open_f`, which may be called again: the module
    !> keeps no "initialised" flag) and switch off HDF5's automatic printing of error stacks.
    subroutine init_library(hdferr)
        integer, intent(out) :: hdferr

        call h5open_f(hdferr)
        if (hdferr >= 0) call h5eset_auto_f(0, hdferr)
    end subroutine init_library

    !> Memory type of `real(wp)`.
    integer(hid_t) function real_mem_type()
        real_mem_type = h5kind_to_type(wp, h5_real_kind)
    end function real_mem_type

    !> Memory type of default integers.
    integer(hid_t) function int_mem_type()
        int_mem_type = h5kind_to_type(kind(0), h5_integer_kind)
    end function int_mem_type

    !> File type of default integers (little-endian, of their size).
    integer(hid_t) function int_file_type()
        int_file_type = merge(h5t_std_i64le, h5t_std_i32le, storage_size(0) == 64)
    end function int_file_type

    !> Memory type of `integer(i8)`.
    integer(hid_t) function i8_mem_type()
        i8_mem_type = h5kind_to_type(i8, h5_integer_kind)
    end function i8_mem_type

    !> The path of the file (for messages).
    pure function disk_path(file) result(path)
        type(h5_file), intent(in) :: file
        character(len=:), allocatable :: path

        path = "(no file)"
        if (allocated(file%path)) path = file%path
    end function disk_path

    !> "/" for an empty object path, else the path.
    pure function root_if_empty(object) result(path)
        character(len=*), intent(in) :: object
        character(len=:), allocatable :: path

        path = object
        if (len_trim(object) == 0) path = "/"
    end function root_if_empty

    !> Stick the error "<file>: <message>" (status `err_io`) in the file, unless an earlier one stuck.
    subroutine fail(file, message)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: message

        if (.not. allocated(file%error)) call fatal_error(file%error, disk_path(file)//": "//message, err_io)
    end subroutine fail

    !> "cannot <action> '<object>' (<routine> failed)": the message of a failed HDF5 call.
    pure function failed_call(action, object, routine) result(text)
        character(len=*), intent(in) :: action, object, routine
        character(len=:), allocatable :: text

        text = "cannot "//action//" '"//object//"' ("//routine//" failed)"
    end function failed_call

    !> Turn a negative HDF5 status into an `err_io` error "<file>: cannot <action> '<object>' (<routine> failed)".
    subroutine check(hdferr, file, action, object, routine, error)
        integer, intent(in) :: hdferr
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: action, object, routine
        type(error_type), allocatable, intent(out) :: error

        if (hdferr < 0) call fatal_error(error, disk_path(file)//": "//failed_call(action, object, routine), err_io)
    end subroutine check

    !> Stick an error in the file unless it is open for writing.
    subroutine check_writable(file, action, object)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: action, object

        if (file%mode == h5_mode_closed) call fail(file, "file is not open, cannot "//action//" '"//object//"'")
        if (file%mode == h5_mode_read) call fail(file, "file is open read-only, cannot "//action//" '"//object//"'")
    end subroutine check_writable

    !> Stick an error in the file unless `names` holds `rank` comma-separated dimension names.
    subroutine check_dim_names(file, name, names, rank)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, names
        integer, intent(in) :: rank
        integer :: n, k

        n = 1 + count([(names(k:k) == ",", k = 1, len(names))])
        if (n /= rank .or. len_trim(names) == 0) call fail(file, "dims = '"//names//"' names "//int_str(n)// &
            " dimensions, dataset '"//name//"' has rank "//int_str(rank))
    end subroutine check_dim_names

    !> Close any HDF5 identifier (file, group, dataset, datatype, dataspace, attribute, property list) and set it to
    !> -1; negative identifiers are ignored. Never pass a predefined datatype.
    subroutine close_id(id)
        integer(hid_t), intent(inout) :: id
        integer :: id_type, hdferr

        if (id < 0) return
        call h5iget_type_f(id, id_type, hdferr)
        if (hdferr >= 0) then
            if (id_type == h5i_dataset_f) call h5dclose_f(id, hdferr)
            if (id_type == h5i_group_f) call h5gclose_f(id, hdferr)
            if (id_type == h5i_datatype_f) call h5tclose_f(id, hdferr)
            if (id_type == h5i_dataspace_f) call h5sclose_f(id, hdferr)
            if (id_type == h5i_attr_f) call h5aclose_f(id, hdferr)
            if (id_type == h5i_genprop_lst_f) call h5pclose_f(id, hdferr)
            if (id_type == h5i_file_f) call h5fclose_f(id, hdferr)
        end if
        id = -1
    end subroutine close_id

    !> Create a scalar dataspace (`dims` empty) or a simple one (`dims` in Fortran order).
    subroutine make_space(dims, space, hdferr)
        integer(hsize_t), intent(in) :: dims(:)
        integer(hid_t), intent(out) :: space
        integer, intent(out) :: hdferr

        if (size(dims) == 0) then
            call h5screate_f(h5s_scalar_f, space, hdferr)
        else
            call h5screate_simple_f(size(dims), dims, space, hdferr)
        end if
    end subroutine make_space

    !> Create a link-creation property list that creates missing intermediate groups.
    subroutine make_lcpl(lcpl, hdferr)
        integer(hid_t), intent(out) :: lcpl
        integer, intent(out) :: hdferr

        call h5pcreate_f(h5p_link_create_f, lcpl, hdferr)
        if (hdferr >= 0) call h5pset_create_inter_group_f(lcpl, 1, hdferr)
    end subroutine make_lcpl

    !> Create a fixed-length, null-padded ASCII string type of `length` characters (at least 1).
    subroutine make_string_type(length, type_id, hdferr)
        integer, intent(in) :: length
        integer(hid_t), intent(out) :: type_id
        integer, intent(out) :: hdferr

        call h5tcopy_f(h5t_c_s1, type_id, hdferr)
        if (hdferr >= 0) call h5tset_size_f(type_id, int(max(length, 1), size_t), hdferr)
        if (hdferr >= 0) call h5tset_strpad_f(type_id, h5t_str_nullpad_f, hdferr)
    end subroutine make_string_type

end module supratrans_h5_file
