!> Part files of a sliced scene and their merge.
!>
!> `supratrans FILE.nml --slice I/N` runs the tasks t of the scene with mod(t - 1, N) + 1 = I (interleaved, so that
!> the expensive tasks of a frequency axis spread over the slices) and writes the part file
!> `<output stem>.part-I-of-N.h5`: group `/part` with the task records of the slice (`task`, `values`, exactly as
!> the journal holds them), the journal header (tasks, values per task, fingerprint of the input), I, N, the code
!> version and the namelist text. `supratrans merge PART...` checks that the parts belong together (same
!> fingerprint, version, N and header), that every slice 1..N is there exactly once, and hands the joined records to
!> the scene as a complete journal: the scene then writes its ordinary output from them, computing nothing, so the
!> merged file is the single-machine file by construction.
module supratrans_parts
    use supratrans_kinds, only: wp, supratrans_version
    use supratrans_strings, only: int_str, text_or
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_config, only: input_config
    use supratrans_system, only: path_kind, path_regular
    use supratrans_hdf5, only: h5_file, h5_create, h5_commit, h5_open, h5_close, h5_write, &
                               h5_write_attr, h5_create_group, h5_read, h5_read_attr, h5_exists
    implicit none
    private

    public :: write_part, part_path, merged_path, part_set, read_parts

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
    end type part_set

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
    subroutine write_part(path, cfg, slice_index, slice_count, header, results, done, mine, error)
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
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        type(h5_file) :: file
        integer, allocatable :: tasks(:)
        real(wp), allocatable :: records(:, :)
        integer :: i

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
        call h5_commit(file, error)
    end subroutine write_part

    !> Read and check a set of part files. Refused with one line naming the file and the reason (status
    !> `err_input`): a file that is not a part, parts of another input, version or slice count, a slice given twice,
    !> a missing slice (unless `partial`: its tasks stay missing), a part that does not hold all its tasks.
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
        character(len=:), allocatable :: version, header, fingerprint, where, first
        integer, allocatable :: tasks(:), given(:)
        real(wp), allocatable :: values(:, :)
        integer :: ip, slice_index, slice_count, ntask, nslice, i
        type(error_type), allocatable :: cause

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
                call h5_read_attr(file, "/", "version", version, cause)
                if (.not. allocated(cause)) call h5_read_attr(file, "part", "slice_index", slice_index, cause)
                if (.not. allocated(cause)) call h5_read_attr(file, "part", "slice_count", slice_count, cause)
                if (.not. allocated(cause)) call h5_read_attr(file, "part", "tasks_total", ntask, cause)
                if (.not. allocated(cause)) call h5_read_attr(file, "part", "tasks_in_slice", nslice, cause)
                if (.not. allocated(cause)) call h5_read_attr(file, "part", "journal_header", header, cause)
                if (.not. allocated(cause)) call h5_read_attr(file, "part", "fingerprint", fingerprint, cause)
                if (.not. allocated(cause)) call h5_read(file, "part/task", tasks, cause)
                if (.not. allocated(cause)) call h5_read(file, "part/values", values, cause)
                if (allocated(cause)) then
                    call fatal_error(error, where // ": damaged part file (" // cause%message // ")", err_input)
                    exit read_one
                end if
                if (version /= supratrans_version) then
                    call fatal_error(error, where // ": made by supratrans " // version // ", this is " &
                                     // supratrans_version // ": run every slice with one version", err_input)
                    exit read_one
                end if
                if (ip == 1) then
                    first = where
                    set%header = header
                    set%fingerprint = fingerprint
                    set%slice_count = slice_count
                    call h5_read(file, "part/namelist", set%text, cause)
                    if (.not. allocated(cause)) call h5_read_attr(file, "part", "input_file", set%source, cause)
                    if (allocated(cause)) then
                        call fatal_error(error, where // ": damaged part file (" // cause%message // ")", err_input)
                        exit read_one
                    end if
                    allocate (set%results(size(values, 1), ntask), set%done(ntask), given(slice_count))
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
                if (slice_index < 1 .or. slice_index > slice_count .or. size(values, 1) /= size(set%results, 1) &
                    .or. ntask /= size(set%done) .or. size(values, 2) /= size(tasks)) then
                    call fatal_error(error, where // ": damaged part file (inconsistent sizes)", err_input)
                    exit read_one
                end if
                if (given(slice_index) > 0) then
                    call fatal_error(error, where // ": slice " // int_str(slice_index) // " of " &
                                     // int_str(slice_count) // " given twice (also " // trim(paths(given(slice_index))) &
                                     // ")", err_input)
                    exit read_one
                end if
                given(slice_index) = ip
                if (size(tasks) /= nslice .or. any(tasks < 1 .or. tasks > ntask) .or. &
                    any(mod(tasks - 1, slice_count) + 1 /= slice_index)) then
                    call fatal_error(error, where // ": incomplete part (" // int_str(size(tasks)) // " of " &
                                     // int_str(nslice) // " tasks): run slice " // int_str(slice_index) // "/" &
                                     // int_str(slice_count) // " again", err_input)
                    exit read_one
                end if
                do i = 1, size(tasks)
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
        if (.not. partial .and. any(given == 0)) then
            i = findloc(given, 0, dim=1)
            call fatal_error(error, first // ": slice " // int_str(i) // " of " // int_str(set%slice_count) &
                             // " is missing (" // int_str(count(given == 0)) // " missing in all): run it with " &
                             // "--slice " // int_str(i) // "/" // int_str(set%slice_count) &
                             // ", or merge --partial to look at what is there", err_input)
        end if
    end subroutine read_parts

end module supratrans_parts
