!> Thin, typed, self-describing HDF5 layer: every output file of supratrans is written through this module, which
!> gathers the public interface of `supratrans_h5_file` (the file's life cycle), `supratrans_h5_write` and
!> `supratrans_h5_read`.
!>
!> ## Files
!> A new output file is written as `<path>.tmp-XXXXXX` (`h5_create`: a fresh name, created exclusively, never through
!> a link) and renamed atomically to `<path>` by `h5_commit` (fsync, POSIX `rename`), so a file found under its final
!> name is complete. `h5_discard` closes and deletes the
!> temporary file after an error. An existing file is opened with `h5_open` (read-only or read-write) and closed
!> with `h5_close`.
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
!> Serial HDF5 is not thread-safe: every routine of this layer must be called from one thread only (outside
!> OpenMP parallel regions, or from one designated thread). The layer keeps no state of its own: `h5_create` and
!> `h5_open` initialise the library each time and switch off HDF5's automatic printing of error stacks; failures
!> are returned as an `error_type` with status `err_io` and a message naming the file and the object. No routine
!> stops the program.
module supratrans_hdf5
    use supratrans_h5_file, only: h5_file, h5_create, h5_commit, h5_discard, h5_open, h5_close, h5_exists, &
        h5_attr_exists
    use supratrans_h5_write, only: h5_write, h5_write_attr, h5_create_group
    use supratrans_h5_read, only: h5_read, h5_read_attr
    implicit none
    private

    public :: h5_file
    public :: h5_create, h5_commit, h5_discard, h5_open, h5_close
    public :: h5_write, h5_write_attr, h5_create_group
    public :: h5_exists, h5_attr_exists, h5_read, h5_read_attr

end module supratrans_hdf5
