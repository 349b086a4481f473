!> Thin, typed, self-describing HDF5 layer: every output file of supratrans is written through this module, which
!> gathers the public interface of `supratrans_h5_file` (the file object and its life cycle), `supratrans_h5_write`,
!> `supratrans_h5_scales` (the commit, with the dimension scales) and `supratrans_h5_read`.
!>
!> ## A writer is a sequence of writes with one check at the end
!>
!>     call h5_create(file, path, overwrite)
!>     call write_root(file, cfg, "map", "...")
!>     call h5_write(file, "/omega", omegas, "1/time", "Driving frequency Omega", dims="omega")
!>     call h5_write(file, "/energy/injected", injected, "energy", "...", dims="curve, omega, amplitude")
!>     call h5_commit(file, error)
!>
!> The first error (of `h5_create` or of any write) sticks in the file (`file%error`); every later write does
!> nothing, and `h5_commit` returns that error and writes nothing. A new file is built in memory and `h5_commit`
!> writes it in one checked write to a fresh `<path>.tmp-XXXXXX` (created with `O_CREAT | O_EXCL | O_NOFOLLOW`),
!> fsyncs it and renames it onto `path`: a file found under its final name is complete, a full disk or a file size
!> limit is one error naming the file and the system's reason ("No space left on device"), and nothing is left
!> behind.
!>
!> ## Objects and self-description
!> Object names are paths from the root group: "ledger/energy" and "/ledger/energy" are the same object; missing
!> intermediate groups are created. Every dataset carries the string attributes `units` and `description`;
!> arrays written with the optional `dims` argument also carry `dimensions`, the comma-separated names of the
!> dimensions in C/h5py order, and at commit each dimension its name as label and, where the file holds a
!> coordinate dataset of that name, that dataset as HDF5 dimension scale, else an index scale (see
!> `supratrans_h5_scales`).
!> `h5_write` replaces an existing dataset of the same name; `h5_write_attr` replaces an existing attribute.
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
!> Reading (`h5_open`, `h5_read`, `h5_read_attr`, `h5_close`; each read returns its own error) converts between
!> numeric types by HDF5's rules and reads fixed-length strings; it reads the types the program reads back (merge,
!> `--check`, the benchmark), the tests more (test/supratrans_h5_test.f90).
!>
!> ## Threads and errors
!> Serial HDF5 is not thread-safe: every routine of this layer must be called from one thread only (outside
!> OpenMP parallel regions, or from one designated thread). The layer keeps no state of its own: `h5_create` and
!> `h5_open` initialise the library each time and switch off HDF5's automatic printing of error stacks; failures
!> are `error_type`s with status `err_io` and a message naming the file and the object. No routine stops the
!> program.
module supratrans_hdf5
    use supratrans_h5_file, only: h5_file, h5_create, h5_open, h5_close, h5_exists, h5_attr_exists
    use supratrans_h5_scales, only: h5_commit
    use supratrans_h5_write, only: h5_write, h5_write_attr, h5_create_group
    use supratrans_h5_read, only: h5_read, h5_read_attr
    implicit none
    private

    public :: h5_file
    public :: h5_create, h5_commit, h5_open, h5_close
    public :: h5_write, h5_write_attr, h5_create_group
    public :: h5_exists, h5_attr_exists, h5_read, h5_read_attr

end module supratrans_hdf5
