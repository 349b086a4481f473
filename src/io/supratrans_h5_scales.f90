!> Finishing a new HDF5 file (`h5_commit`): its dimension scales attached, its image taken from memory and written
!> to the disk in one checked, atomic write. Use `supratrans_hdf5`, which gathers the public interface.
!>
!> ## Dimension scales
!> A dataset written with `dims = "curve, amplitude"` (names in C/h5py order) is remembered by the file; at commit,
!> each of its dimensions gets its name as label (`H5DSset_label`) and a dimension scale (`H5DSattach_scale`, the
!> HDF5 high-level library), so that h5py's `ds.dims[i][0]`, netCDF readers (h5netcdf, xarray) and HDFView find the
!> axis. The scale of a dimension named `d` of a dataset in group `G` is its coordinate dataset, the first of `G/d`,
!> then `d` in each parent group up to the root, then the same with the plural `ds` (so `method` finds `/methods`),
!> that is one-dimensional, of the dimension's length, and not the dataset itself (an axis such as `/amplitude`,
!> written with `dims = "amplitude"`, is its own scale). A dimension without a
!> coordinate (`curve`, `probe`, `point`, `task`, `failure`, `parameter`, ...) gets the index scale `/d` (0, 1, ...,
!> n - 1), created the first time, or `/d_index` where `/d` is something else (the two-dimensional `/dt` of
!> `work_precision`).
module supratrans_h5_scales
    use, intrinsic :: iso_c_binding, only: c_char, c_loc, c_ptr
    use hdf5, only: hid_t, hsize_t, size_t, h5fflush_f, h5f_scope_global_f, h5fget_file_image_f, h5dopen_f
    use h5ds, only: h5dsset_scale_f, h5dsis_scale_f, h5dsattach_scale_f, h5dsis_attached_f, h5dsset_label_f
    use supratrans_error, only: error_type
    use supratrans_strings, only: int_str
    use supratrans_system, only: write_bytes_atomic
    use supratrans_h5_file, only: h5_file, h5_mode_read, h5_mode_closed, h5_discard, h5_close, h5_exists, fail, &
        failed_call, close_id
    use supratrans_h5_write, only: h5_write
    use supratrans_h5_read, only: h5_shape
    implicit none
    private

    public :: h5_commit

contains

    !> Finish a new file: refuse if an error stuck (it is returned, nothing is written), else attach the dimension
    !> scales, take the file's image and write it atomically under its path (`write_bytes_atomic`: a fresh
    !> temporary, every write checked, fsync, rename). A file opened by `h5_open` is just closed.
    subroutine h5_commit(file, error)
        !> The file; closed on return, its stuck error (if any) moved to `error`.
        type(h5_file), intent(inout) :: file
        !> Error, allocated on failure (the stuck error, or the commit's own).
        type(error_type), allocatable, intent(out) :: error
        character(kind=c_char, len=1), allocatable, target :: image(:)
        integer(size_t) :: size

        if (file%mode == h5_mode_read .and. .not. allocated(file%error)) then
            call h5_close(file, error)
            return
        end if
        if (file%mode == h5_mode_closed) call fail(file, "file is not open, cannot commit '/'")
        call attach_scales(file)
        if (.not. allocated(file%error)) call file_image(file, image, size)
        call h5_discard(file)
        if (allocated(file%error)) then
            call move_alloc(file%error, error)
            return
        end if
        call write_bytes_atomic(file%path, image(1:size), error)
    end subroutine h5_commit

    !> The image of an open file built in memory (`size` bytes of `image`); a failure sticks in `file`.
    subroutine file_image(file, image, size)
        type(h5_file), intent(inout) :: file
        character(kind=c_char, len=1), allocatable, target, intent(out) :: image(:)
        integer(size_t), intent(out) :: size
        type(c_ptr) :: buf
        integer :: hdferr, stat

        ! the size of the image first, then the image
        allocate (image(1))
        buf = c_loc(image)
        size = 0
        call h5fflush_f(file%id, h5f_scope_global_f, hdferr)
        if (hdferr >= 0) call h5fget_file_image_f(file%id, buf, 0_size_t, hdferr, size)
        if (hdferr >= 0) then
            deallocate (image)
            allocate (image(max(size, 1_size_t)), stat=stat)
            if (stat /= 0) then
                call fail(file, "cannot allocate "//int_str(int(min(size, 2000000000_size_t)))// &
                    " bytes for the file's image (out of memory)")
                return
            end if
            buf = c_loc(image)
            call h5fget_file_image_f(file%id, buf, size, hdferr)
        end if
        if (hdferr < 0) call fail(file, failed_call("take the image of", "/", "h5fflush_f/h5fget_file_image_f"))
    end subroutine file_image

    !> Label every remembered dimension with its name and attach its coordinate dataset as dimension scale (see
    !> the module's documentation for how a name finds its dataset). A failure sticks in `file`.
    subroutine attach_scales(file)
        type(h5_file), intent(inout) :: file
        character(len=:), allocatable :: line, name, names
        integer :: first, last, tab

        if (.not. allocated(file%dim_table)) return
        first = 1
        do while (first <= len(file%dim_table) .and. .not. allocated(file%error))
            last = index(file%dim_table(first:), achar(10)) + first - 1
            line = file%dim_table(first:last - 1)
            first = last + 1
            tab = index(line, achar(9))
            name = line(1:tab - 1)
            names = line(tab + 1:)
            call attach_dataset_scales(file, name, names)
        end do
    end subroutine attach_scales

    !> Label the dimensions of dataset `name` and attach their scales.
    subroutine attach_dataset_scales(file, name, names)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: name, names
        type(error_type), allocatable :: error
        integer(hsize_t), allocatable :: shape(:)
        integer(hid_t) :: dset, scale
        character(len=:), allocatable :: rest, dim, scale_path
        integer :: rank, j, comma, hdferr, idx
        logical :: attached, is_scale

        call h5_shape(file, name, "", -1, shape, error)
        if (allocated(error)) then
            call move_alloc(error, file%error)      ! attach_scales runs only while no error stuck
            return
        end if
        call h5dopen_f(file%id, name, dset, hdferr)
        rank = size(shape)
        rest = names
        j = 0
        do while (len(rest) > 0 .and. hdferr >= 0)
            comma = index(rest, ",")
            if (comma == 0) comma = len(rest) + 1
            dim = trim(adjustl(rest(1:comma - 1)))
            rest = rest(min(comma + 1, len(rest) + 1):)
            j = j + 1
            if (j > rank) exit
            idx = j                                 ! h5ds*_f take the C index + 1 (measured with h5py, HDF5 1.10)
            call h5dsset_label_f(dset, idx, dim, hdferr)
            if (hdferr < 0) exit
            if (rank == 1 .and. (base_name(name) == dim .or. base_name(name) == dim//"s")) then
                ! an axis written with its own name (/amplitude, /probes/time, /methods): it is the scale itself
                call h5dsis_scale_f(dset, is_scale, hdferr)
                if (hdferr >= 0 .and. .not. is_scale) call h5dsset_scale_f(dset, hdferr, dim)
                cycle
            end if
            call find_scale(file, name, dim, shape(rank - j + 1), scale_path)   ! shape is in Fortran order
            if (len(scale_path) == 0) call index_scale(file, dim, shape(rank - j + 1), scale_path)
            if (len(scale_path) == 0) cycle
            call h5dopen_f(file%id, scale_path, scale, hdferr)
            if (hdferr < 0) exit
            call h5dsis_scale_f(scale, is_scale, hdferr)
            if (hdferr >= 0 .and. .not. is_scale) call h5dsset_scale_f(scale, hdferr, dim)
            if (hdferr >= 0) call h5dsis_attached_f(dset, scale, idx, attached, hdferr)
            if (hdferr >= 0 .and. .not. attached) call h5dsattach_scale_f(dset, scale, idx, hdferr)
            call close_id(scale)
        end do
        call close_id(dset)
        if (hdferr < 0) call fail(file, failed_call("attach the dimension scales of", name, "h5dsattach_scale_f"))
    end subroutine attach_dataset_scales

    !> The coordinate dataset of dimension `dim` (of length `length`) of dataset `name`: the first of `G/dim` for
    !> `G` the dataset's group and each parent up to the root, then the same with `dim//"s"`, that is a rank-1
    !> dataset of that length and not `name` itself; empty if there is none.
    subroutine find_scale(file, name, dim, length, path)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: name, dim
        integer(hsize_t), intent(in) :: length
        character(len=:), allocatable, intent(out) :: path
        character(len=:), allocatable :: group, candidate, own
        integer :: plural, slash

        own = "/"//strip_slashes(name)
        do plural = 0, 1
            group = own(1:index(own, "/", back=.true.) - 1)
            do
                candidate = group//"/"//dim
                if (plural == 1) candidate = candidate//"s"
                if (candidate /= own .and. length_of(file, candidate) == length) then
                    path = candidate
                    return
                end if
                if (len(group) == 0) exit
                slash = index(group, "/", back=.true.)
                group = group(1:slash - 1)
            end do
        end do
        path = ""
    end subroutine find_scale

    !> The index scale of dimension `dim` (of length `length`) that has no coordinate dataset: the dataset `/<dim>`
    !> holding 0, 1, ..., length - 1, created the first time (netCDF readers such as xarray want every dimension of a
    !> dataset to have a scale, or none); `/<dim>_index` where `/<dim>` is something else (the two-dimensional `/dt`
    !> of `work_precision`). Empty when both are taken: the dimension then keeps only its label.
    subroutine index_scale(file, dim, length, path)
        type(h5_file), intent(inout) :: file
        character(len=*), intent(in) :: dim
        integer(hsize_t), intent(in) :: length
        character(len=:), allocatable, intent(out) :: path
        integer :: i

        path = ""
        if (len_trim(dim) == 0 .or. index(dim, "/") > 0) return
        if (.not. h5_exists(file, "/"//dim)) then
            path = "/"//dim
        else if (.not. h5_exists(file, "/"//dim//"_index")) then
            path = "/"//dim//"_index"
        else
            if (length_of(file, "/"//dim//"_index") == length) path = "/"//dim//"_index"   ! made for another dataset
            return
        end if
        call h5_write(file, path, [(i, i=0, int(length) - 1)], "1", "Index of the "//dim//" dimension, "// &
                      "0-based (it has no coordinate of its own): the dimension scale of every dataset with that dimension")
        if (allocated(file%error)) path = ""
    end subroutine index_scale

    !> The length of the rank-1 dataset `path`; -1 if there is none.
    function length_of(file, path) result(length)
        type(h5_file), intent(in) :: file
        character(len=*), intent(in) :: path
        integer(hsize_t) :: length
        integer(hsize_t), allocatable :: shape(:)
        type(error_type), allocatable :: error

        length = -1
        if (.not. h5_exists(file, path)) return
        call h5_shape(file, path, "", 1, shape, error)
        if (.not. allocated(error)) length = shape(1)
    end function length_of

    !> The last component of a path ("time" for "/probes/time").
    pure function base_name(path) result(name)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: name

        name = path(index(path, "/", back=.true.) + 1:)
    end function base_name

    !> A path without leading and trailing slashes.
    pure function strip_slashes(path) result(stripped)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: stripped
        integer :: first, last

        first = verify(path, "/")
        last = verify(path, "/ ", back=.true.)
        if (first == 0) then
            stripped = ""
        else
            stripped = path(first:last)
        end if
    end function strip_slashes
end module supratrans_h5_scales
