!> Part files of a sliced scene and their merge.
!>
!> `supratrans FILE.nml --slice I/N` runs the tasks the largest-first assignment by estimated cost deals to slice I
!> (`supratrans_tasks::slice_owners`; equal costs: task t to slice mod(t - 1, N) + 1) and writes the part file
!> `<output stem>.part-I-of-N.h5`: group `/part` with the task records of the slice (`task`, `values`, exactly as
!> the journal holds them), the journal header (tasks, values per task, fingerprint of the input), I, N, the code
!> version, the namelist text, the part format (`part_format`) and `checksum`: the CRC-32 of all of these
!> (`part_checksum`; the values by their bits), so that a bit flipped anywhere in what the part says is seen.
!> `supratrans merge PART...` proves each part whole before it uses it: its checksum, the fingerprint recomputed
!> from the namelist text it holds (and named by its journal header, whose own checksum holds), counts within the
!> limits (checked before anything is allocated), and its task indices within the scene's, each once, in order.
!> It then checks that the parts belong together (same fingerprint, version, N and header; the assignment is a
!> function of these), that no task is in two parts and that every slice 1..N is there exactly once, and hands
!> the joined records to the scene as a complete journal: the scene
!> writes its ordinary output from them, computing nothing (a part whose fields are not the scene's is refused, see
!> `supratrans_tasks`), so the merged file is the single-machine file by construction. Anything else is refused
!> with one line naming the part and the reason (status 2).
module supratrans_parts
    use, intrinsic :: iso_fortran_env, only: int64
    use hdf5, only: hid_t, hsize_t, h5dopen_f, h5dget_space_f, h5sget_simple_extent_ndims_f, &
                    h5sget_simple_extent_dims_f, h5dclose_f, h5sclose_f
    use supratrans_kinds, only: wp, supratrans_version
    use supratrans_strings, only: int_str, text_or, text_fingerprint, printable
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_config, only: input_config
    use supratrans_system, only: path_kind, path_regular
    use supratrans_limits, only: max_tasks
    use supratrans_journal, only: crc32, header_checked, max_fields, split_words
    use supratrans_hdf5, only: h5_file, h5_create, h5_commit, h5_open, h5_close, h5_write, &
                               h5_write_attr, h5_create_group, h5_read, h5_read_attr, h5_exists, h5_attr_exists
    implicit none
    private

    public :: write_part, part_path, merged_path, part_set, read_parts, part_checksum

    !> The format of the part files written (1: before they had a checksum; 2: before they recorded where and
    !> when the slice ran).
    character(len=*), parameter, public :: part_format = "3"
    !> Most slices (as `--slice` accepts).
    integer, parameter :: max_slices = 100000

    !> What `read_parts` gathers from a complete set of parts.
    type, public :: part_set
        !> The namelist text of the study (as the slices read it).
        character(len=:), allocatable :: text
        !> Path of the namelist the slices were run from.
        character(len=:), allocatable :: source
        !> Fingerprint of that text.
        character(len=:), allocatable :: fingerprint
        !> Journal header of the whole scene.
        character(len=:), allocatable :: header
        !> Number of slices N.
        integer :: slice_count = 0
        !> Task records, (values, tasks), and which tasks they hold.
        real(wp), allocatable :: results(:, :)
        !> Which tasks the parts hold.
        logical, allocatable :: done(:)
        !> The first part file (named when the scene refuses the records).
        character(len=:), allocatable :: first
        !> One line per part, in slice order: slice, host, start, end, wall time (s), threads, commit.
        character(len=:), allocatable :: record
        !> The summed wall time of the parts' slices (s).
        real(wp) :: wall_time = 0.0_wp
    end type part_set

    !> Where and when a slice ran, as its part file records it (attributes of /part).
    type, public :: part_run
        !> Host name.
        character(len=:), allocatable :: host
        !> Start and end of the invocation that finished the slice (ISO 8601).
        character(len=:), allocatable :: started, ended
        !> The commit the program was built from.
        character(len=:), allocatable :: commit
        !> Wall time of that invocation (s).
        real(wp) :: wall_time = 0.0_wp
        !> OpenMP threads.
        integer :: threads = 1
    end type part_run

contains

    !> Part file of slice `slice_index` of `slice_count` for the output `file`: `<stem>.part-I-of-N.h5`, where
    !> `<stem>` is `file` without a final `.h5`.
    pure function part_path(file, slice_index, slice_count) result(path)
        !> The scene's output file.
        character(len=*), intent(in) :: file
        !> Slice I.
        integer, intent(in) :: slice_index
        !> Number of slices N.
        integer, intent(in) :: slice_count
        character(len=:), allocatable :: path

        path = stem(file) // ".part-" // int_str(slice_index) // "-of-" // int_str(slice_count) // ".h5"
    end function part_path

    !> The output a part file merges into: `x.part-I-of-N.h5` -> `x.h5`.
    pure function merged_path(part) result(path)
        !> A part file.
        character(len=*), intent(in) :: part
        character(len=:), allocatable :: path
        integer :: k

        k = index(part, ".part-", back=.true.)
        if (k > 0) then
            path = part(1:k - 1) // ".h5"
        else
            path = stem(part) // ".merged.h5"
        end if
    end function merged_path

    !> A file name without a final `.h5`.
    pure function stem(file) result(text)
        character(len=*), intent(in) :: file
        character(len=:), allocatable :: text
        integer :: n

        n = len_trim(file)
        text = file(1:n)
        if (n > 3) then
            if (file(n - 2:n) == ".h5") text = file(1:n - 3)
        end if
    end function stem

    !> Write the part file of a finished slice (atomically: `<path>.tmp-XXXXXX`, then renamed).
    subroutine write_part(path, cfg, slice_index, slice_count, header, results, done, mine, run, error)
        !> Part file.
        character(len=*), intent(in) :: path
        !> The input (its namelist text, source and scene).
        type(input_config), intent(in) :: cfg
        !> Slice I.
        integer, intent(in) :: slice_index
        !> Number of slices N.
        integer, intent(in) :: slice_count
        !> Journal header of the whole scene.
        character(len=*), intent(in) :: header
        !> Results of every task (only those of the slice are meaningful).
        real(wp), intent(in) :: results(:, :)
        !> Which tasks are done.
        logical, intent(in) :: done(:)
        !> Which tasks belong to the slice.
        logical, intent(in) :: mine(:)
        !> Where and when the slice ran.
        type(part_run), intent(in) :: run
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        type(h5_file) :: file
        integer, allocatable :: tasks(:)
        real(wp), allocatable :: records(:, :)
        integer :: i
        character(len=8) :: hex

        tasks = pack([(i, i = 1, size(done))], done .and. mine)
        allocate (records(size(results, 1), size(tasks)))
        do i = 1, size(tasks)
            records(:, i) = results(:, tasks(i))
        end do
        call h5_create(file, path, .true.)
        call h5_write_attr(file, "/", "code", "supratrans")
        call h5_write_attr(file, "/", "version", supratrans_version)
        call h5_write_attr(file, "/", "scene", trim(cfg%scene%kind))
        call h5_write_attr(file, "/", "description", "Part " // int_str(slice_index) // " of " &
                           // int_str(slice_count) // " of a sliced scene: join the parts with `supratrans merge`")
        call h5_create_group(file, "part", "Task records of one slice (supratrans FILE.nml --slice I/N)")
        call h5_write_attr(file, "part", "slice_index", slice_index)
        call h5_write_attr(file, "part", "slice_count", slice_count)
        call h5_write_attr(file, "part", "tasks_total", size(done))
        call h5_write_attr(file, "part", "tasks_in_slice", count(mine))
        call h5_write_attr(file, "part", "journal_header", header)
        call h5_write_attr(file, "part", "fingerprint", text_or(cfg%fingerprint, "none"))
        call h5_write_attr(file, "part", "input_file", text_or(cfg%source, "configuration"))
        call h5_write(file, "part/task", tasks, "1", "task index of each record")
        call h5_write(file, "part/values", records, "mixed", "the task records, exactly as the " &
                      // "journal holds them (values, task)")
        call h5_write(file, "part/namelist", text_or(cfg%text, ""), "", "the namelist text as read")
        call h5_write_attr(file, "part", "part_format", part_format)
        call h5_write_attr(file, "part", "host", run%host)
        call h5_write_attr(file, "part", "started", run%started)
        call h5_write_attr(file, "part", "ended", run%ended)
        call h5_write_attr(file, "part", "wall_time_s", run%wall_time)
        call h5_write_attr(file, "part", "threads", run%threads)
        call h5_write_attr(file, "part", "git_commit", run%commit)
        write (hex, "(z8.8)") part_checksum(supratrans_version, trim(cfg%scene%kind), slice_index, slice_count, &
                                            size(done), count(mine), header, text_or(cfg%fingerprint, "none"), &
                                            text_or(cfg%source, "configuration"), text_or(cfg%text, ""), tasks, &
                                            records, run_line(run))
        call h5_write_attr(file, "part", "checksum", hex)
        call h5_commit(file, error)
    end subroutine write_part

    !> The checksum of a part file: the CRC-32 (`crc32`) of its format, version, scene, I, N, task counts, journal
    !> header, fingerprint, input name and namelist text, one per line, then of one line per record: the task index
    !> and the 64 bits of each value in hexadecimal (so that any change of a value, a NaN's payload included, is
    !> seen), then of the line of where and when the slice ran (`run_line`).
    pure function part_checksum(version, scene, slice_index, slice_count, ntask, nslice, header, fingerprint, source, &
                                text, tasks, values, run) result(crc)
        !> Code version that wrote the part.
        character(len=*), intent(in) :: version
        !> Scene kind.
        character(len=*), intent(in) :: scene
        !> Slice I and number of slices N.
        integer, intent(in) :: slice_index, slice_count
        !> Tasks of the scene and of the slice.
        integer, intent(in) :: ntask, nslice
        !> Journal header of the scene.
        character(len=*), intent(in) :: header
        !> Fingerprint of the input.
        character(len=*), intent(in) :: fingerprint
        !> Name of the input file.
        character(len=*), intent(in) :: source
        !> Namelist text.
        character(len=*), intent(in) :: text
        !> Task index of each record.
        integer, intent(in) :: tasks(:)
        !> The records, (values, records).
        real(wp), intent(in) :: values(:, :)
        !> Where and when the slice ran (`run_line`).
        character(len=*), intent(in) :: run
        integer(int64) :: crc
        character(len=:), allocatable :: line
        character(len=17) :: word
        character(len=1), parameter :: lf = achar(10)
        integer :: i, j

        crc = crc32("supratrans-part " // part_format // lf // version // lf // scene // lf // int_str(slice_index) &
                    // lf // int_str(slice_count) // lf // int_str(ntask) // lf // int_str(nslice) // lf // header // lf &
                    // fingerprint // lf // source // lf)
        crc = crc32(text // lf, crc)
        do i = 1, size(tasks)
            line = int_str(tasks(i))
            do j = 1, size(values, 1)
                write (word, "(1x, z16.16)") transfer(values(j, i), 0_int64)
                line = line // word
            end do
            crc = crc32(line // lf, crc)
        end do
        crc = crc32(run // lf, crc)
    end function part_checksum

    !> Where and when a slice ran, one line: host, start, end, wall time (s, 17 significant digits: its bits),
    !> threads, commit, separated by tabs.
    pure function run_line(run) result(line)
        !> The slice's run.
        type(part_run), intent(in) :: run
        character(len=:), allocatable :: line
        character(len=32) :: wall
        character(len=1), parameter :: tab = achar(9)

        write (wall, "(es24.16e3)") run%wall_time
        line = run%host // tab // run%started // tab // run%ended // tab // trim(adjustl(wall)) // tab &
               // int_str(run%threads) // tab // run%commit
    end function run_line

    !> The dimensions (Fortran order, as the HDF5 Fortran API gives them) of a dataset, without reading it; `ok`
    !> false if they cannot be had.
    subroutine dataset_dims(file, name, dims, ok)
        !> The file (open).
        type(h5_file), intent(in) :: file
        !> Path of the dataset.
        character(len=*), intent(in) :: name
        !> Its dimensions.
        integer(hsize_t), allocatable, intent(out) :: dims(:)
        !> Whether they could be read.
        logical, intent(out) :: ok
        integer(hid_t) :: dset, space
        integer(hsize_t), allocatable :: maxdims(:)
        integer :: rank, hdferr, ignored

        ok = .false.
        allocate (dims(0))
        if (.not. h5_exists(file, name)) return
        call h5dopen_f(file%id, name, dset, hdferr)
        if (hdferr < 0) return
        call h5dget_space_f(dset, space, hdferr)
        if (hdferr >= 0) then
            call h5sget_simple_extent_ndims_f(space, rank, hdferr)
            if (hdferr >= 0 .and. rank >= 0 .and. rank <= 32) then
                deallocate (dims)
                allocate (dims(rank), maxdims(rank))
                call h5sget_simple_extent_dims_f(space, dims, maxdims, hdferr)
                ok = hdferr >= 0
            end if
            call h5sclose_f(space, ignored)
        end if
        call h5dclose_f(dset, ignored)
    end subroutine dataset_dims

    !> Read and check one part file (see the module's description); `error` (status `err_input`) names it and says
    !> what is wrong.
    subroutine read_one_part(file, where, version, slice_index, slice_count, ntask, header, fingerprint, source, &
                             text, tasks, values, run, error)
        !> The part file (open).
        type(h5_file), intent(in) :: file
        !> Its name, for messages.
        character(len=*), intent(in) :: where
        !> What it holds: code version, slice I of N, tasks of the scene, journal header, fingerprint, input name,
        !> namelist text, task indices and records.
        character(len=:), allocatable, intent(out) :: version, header, fingerprint, source, text
        !> Slice I, number of slices N, tasks of the scene.
        integer, intent(out) :: slice_index, slice_count, ntask
        !> Task index of each record.
        integer, allocatable, intent(out) :: tasks(:)
        !> The records, (values, records).
        real(wp), allocatable, intent(out) :: values(:, :)
        !> Where and when the slice ran.
        type(part_run), intent(out) :: run
        !> Error, allocated when the part is refused.
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: scene, format, stored, hwords(:)
        character(len=8) :: hex
        integer(hsize_t), allocatable :: tdims(:), vdims(:)
        type(error_type), allocatable :: cause
        integer :: nslice, nfields, i
        logical :: ok

        if (.not. h5_attr_exists(file, "part", "part_format") .or. .not. h5_attr_exists(file, "part", "checksum")) then
            call fatal_error(error, where // ": part file of an older supratrans, without a checksum (the part format " &
                             // "changed): delete it and run its slice again", err_input)
            return
        end if
        call h5_read_attr(file, "part", "part_format", format, cause)
        if (.not. allocated(cause)) call h5_read_attr(file, "part", "checksum", stored, cause)
        if (.not. allocated(cause)) call h5_read_attr(file, "/", "version", version, cause)
        if (.not. allocated(cause)) call h5_read_attr(file, "/", "scene", scene, cause)
        if (.not. allocated(cause)) call h5_read_attr(file, "part", "slice_index", slice_index, cause)
        if (.not. allocated(cause)) call h5_read_attr(file, "part", "slice_count", slice_count, cause)
        if (.not. allocated(cause)) call h5_read_attr(file, "part", "tasks_total", ntask, cause)
        if (.not. allocated(cause)) call h5_read_attr(file, "part", "tasks_in_slice", nslice, cause)
        if (.not. allocated(cause)) call h5_read_attr(file, "part", "journal_header", header, cause)
        if (.not. allocated(cause)) call h5_read_attr(file, "part", "fingerprint", fingerprint, cause)
        if (.not. allocated(cause)) call h5_read_attr(file, "part", "input_file", source, cause)
        if (.not. allocated(cause) .and. format == part_format) then
            call h5_read_attr(file, "part", "host", run%host, cause)
            if (.not. allocated(cause)) call h5_read_attr(file, "part", "started", run%started, cause)
            if (.not. allocated(cause)) call h5_read_attr(file, "part", "ended", run%ended, cause)
            if (.not. allocated(cause)) call h5_read_attr(file, "part", "wall_time_s", run%wall_time, cause)
            if (.not. allocated(cause)) call h5_read_attr(file, "part", "threads", run%threads, cause)
            if (.not. allocated(cause)) call h5_read_attr(file, "part", "git_commit", run%commit, cause)
        end if
        if (allocated(cause)) then
            call fatal_error(error, where // ": damaged part file (" // cause%message // ")", err_input)
            return
        end if
        if (format /= part_format) then
            call fatal_error(error, where // ": part file of format " // printable(format) // ", this supratrans reads " &
                             // part_format // " (the part format changed): delete it and run its slice again", &
                             err_input)
            return
        end if
        ! counts first, so that nothing is allocated from a damaged one
        if (slice_count < 1 .or. slice_count > max_slices .or. slice_index < 1 .or. slice_index > slice_count) then
            call fatal_error(error, where // ": damaged part file (slice " // int_str(slice_index) // " of " &
                             // int_str(slice_count) // ": not 1 <= I <= N <= " // int_str(max_slices) // ")", err_input)
            return
        end if
        if (ntask < 1 .or. real(ntask, wp) > max_tasks) then
            call fatal_error(error, where // ": damaged part file (tasks_total = " // int_str(ntask) // ", not within " &
                             // "1.." // int_str(int(max_tasks)) // ", the limit of a scene)", err_input)
            return
        end if
        if (nslice < 0 .or. nslice > ntask) then
            call fatal_error(error, where // ": damaged part file (tasks_in_slice = " // int_str(nslice) // ", not " &
                             // "within 0.." // int_str(ntask) // ", the tasks of the scene)", err_input)
            return
        end if
        call split_words(header, hwords)
        nfields = size(hwords) - 5
        if (.not. header_checked(header)) then
            call fatal_error(error, where // ": damaged part file (its journal header fails its checksum)", err_input)
            return
        end if
        if (nfields < 1 .or. nfields > max_fields) then
            call fatal_error(error, where // ": damaged part file (its journal header names " // int_str(nfields) &
                             // " fields, not 1.." // int_str(max_fields) // ")", err_input)
            return
        end if
        call dataset_dims(file, "part/task", tdims, ok)
        if (ok) call dataset_dims(file, "part/values", vdims, ok)
        if (ok) ok = size(tdims) == 1 .and. size(vdims) == 2
        if (ok) ok = tdims(1) == nslice .and. vdims(1) == nfields .and. vdims(2) == nslice
        if (.not. ok) then
            call fatal_error(error, where // ": damaged part file (part/task or part/values is not of " &
                             // int_str(nslice) // " records of " // int_str(nfields) // " values)", err_input)
            return
        end if
        call h5_read(file, "part/task", tasks, cause)
        if (.not. allocated(cause)) call h5_read(file, "part/values", values, cause)
        if (.not. allocated(cause)) call h5_read(file, "part/namelist", text, cause)
        if (allocated(cause)) then
            call fatal_error(error, where // ": damaged part file (" // cause%message // ")", err_input)
            return
        end if
        write (hex, "(z8.8)") part_checksum(version, scene, slice_index, slice_count, ntask, nslice, header, &
                                            fingerprint, source, text, tasks, values, run_line(run))
        if (stored /= hex) then
            call fatal_error(error, where // ": damaged part file (its checksum " // printable(stored) // " is not " &
                             // "that of its content, " // hex // ": altered since it was written)", err_input)
            return
        end if
        if (text_fingerprint(text) /= fingerprint .or. hwords(4) /= fingerprint .or. hwords(3) /= int_str(ntask)) then
            call fatal_error(error, where // ": its namelist text has the fingerprint " // text_fingerprint(text) &
                             // ", not the " // printable(fingerprint) // " the part was made for (edited?)", err_input)
            return
        end if
        do i = 1, nslice
            if (tasks(i) < 1 .or. tasks(i) > ntask .or. tasks(i) <= merge(tasks(max(i - 1, 1)), 0, i > 1)) then
                call fatal_error(error, where // ": record " // int_str(i) // " holds task " // int_str(tasks(i)) &
                                 // ": the tasks of slice " // int_str(slice_index) // " of " // int_str(slice_count) &
                                 // " must be within 1.." // int_str(ntask) // ", each exactly once, in increasing " &
                                 // "order", err_input)
                return
            end if
        end do
    end subroutine read_one_part

    !> Read and check a set of part files. Refused with one line naming the file and the reason (status
    !> `err_input`): a file that is not a part, a part that fails its checks (`read_one_part`), parts of another
    !> input, version or slice count, a slice given twice, a missing slice (unless `partial`: its tasks stay missing).
    subroutine read_parts(paths, partial, set, error)
        !> The part files.
        character(len=*), intent(in) :: paths(:)
        !> Accept missing slices (a look at an unfinished study).
        logical, intent(in) :: partial
        !> What the parts hold.
        type(part_set), intent(out) :: set
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        type(h5_file) :: file
        character(len=:), allocatable :: version, header, fingerprint, where, first, source, text
        integer, allocatable :: tasks(:), given(:)
        real(wp), allocatable :: values(:, :)
        integer :: ip, slice_index, slice_count, ntask, i, stat
        type(error_type), allocatable :: cause
        type(part_run) :: run
        type(part_run), allocatable :: runs(:)

        do ip = 1, size(paths)
            where = trim(paths(ip))
            if (path_kind(where) /= path_regular) then
                call fatal_error(error, where // ": no such part file", err_input)
                return
            end if
            call h5_open(file, where, cause)
            if (allocated(cause)) then
                call fatal_error(error, where // ": not an HDF5 file (a part file of supratrans --slice is)", err_input)
                return
            end if
            read_one: block
                if (.not. h5_exists(file, "part")) then
                    if (index(where, ".partial.h5") > 0) then
                        call fatal_error(error, where // ": a partial snapshot, not a part: its slice was interrupted" &
                                         // " (run that slice again: it resumes from its journal)", err_input)
                    else
                        call fatal_error(error, where // ": not a part file (no /part group)", err_input)
                    end if
                    exit read_one
                end if
                call read_one_part(file, where, version, slice_index, slice_count, ntask, header, fingerprint, source, &
                                   text, tasks, values, run, error)
                if (allocated(error)) exit read_one
                if (version /= supratrans_version) then
                    call fatal_error(error, where // ": made by supratrans " // printable(version) // ", this is " &
                                     // supratrans_version // ": run every slice with one version", err_input)
                    exit read_one
                end if
                if (ip == 1) then
                    first = where
                    set%first = where
                    set%header = header
                    set%fingerprint = fingerprint
                    set%slice_count = slice_count
                    set%text = text
                    set%source = source
                    allocate (set%results(size(values, 1), ntask), stat=stat)
                    if (stat == 0) allocate (set%done(ntask), stat=stat)
                    if (stat == 0) allocate (given(slice_count), stat=stat)
                    if (stat /= 0) then
                        call fatal_error(error, where // ": " // int_str(ntask) // " tasks of " &
                                         // int_str(size(values, 1)) // " values do not fit in memory", err_input)
                        exit read_one
                    end if
                    set%results = 0.0_wp
                    set%done = .false.
                    given = 0
                else if (fingerprint /= set%fingerprint .or. header /= set%header) then
                    call fatal_error(error, where // ": belongs to another input or scene than " // first &
                                     // " (fingerprint " // fingerprint // " vs " // set%fingerprint // ")", err_input)
                    exit read_one
                else if (slice_count /= set%slice_count) then
                    call fatal_error(error, where // ": slice " // int_str(slice_index) // " of " &
                                     // int_str(slice_count) // ", but " // first // " is of " &
                                     // int_str(set%slice_count), err_input)
                    exit read_one
                end if
                if (given(slice_index) > 0) then
                    call fatal_error(error, where // ": slice " // int_str(slice_index) // " of " &
                                     // int_str(slice_count) // " given twice (also " // trim(paths(given(slice_index))) &
                                     // ")", err_input)
                    exit read_one
                end if
                given(slice_index) = ip
                if (.not. allocated(runs)) allocate (runs(slice_count))
                runs(slice_index) = run
                do i = 1, size(tasks)
                    if (set%done(tasks(i))) then
                        call fatal_error(error, where // ": task " // int_str(tasks(i)) // " is also in another part" &
                                         // " (the slices' tasks are disjoint by construction: a part of another " &
                                         // "assignment?)", err_input)
                        exit read_one
                    end if
                    set%results(:, tasks(i)) = values(:, i)
                    set%done(tasks(i)) = .true.
                end do
            end block read_one
            call h5_close(file, cause)
            if (allocated(error)) return
        end do
        if (.not. allocated(given)) then
            call fatal_error(error, "merge: no part files given", err_input)
            return
        end if
        set%record = ""
        set%wall_time = 0.0_wp
        do i = 1, size(given)
            if (given(i) == 0) cycle
            set%record = set%record // int_str(i) // achar(9) // run_line(runs(i)) // achar(10)
            set%wall_time = set%wall_time + runs(i)%wall_time
        end do
        if (.not. partial .and. any(given == 0)) then
            i = findloc(given, 0, dim=1)
            call fatal_error(error, first // ": slice " // int_str(i) // " of " // int_str(set%slice_count) &
                             // " is missing (" // int_str(count(given == 0)) // " missing in all): run it with " &
                             // "--slice " // int_str(i) // "/" // int_str(set%slice_count) &
                             // ", or merge --partial to look at what is there", err_input)
        end if
    end subroutine read_parts

end module supratrans_parts
