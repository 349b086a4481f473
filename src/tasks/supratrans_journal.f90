!> The journal of a scene: one line per finished task, each proven whole, unaltered and of this input.
!>
!> The first line is the header `supratrans-journal 4 <tasks> <fingerprint of the input> <name_1> ... <name_m> *<crc>`:
!> the names of the m fields of a task's record, in the order the lines hold them, and the CRC-32 (IEEE 802.3
!> polynomial, as zlib computes it) of everything before the ` *`, in 8 hexadecimal digits. Every other line is
!> `<task> <v_1> ... <v_m> *<crc>`: the task index, its m values with 17 significant digits (an exact round trip of
!> IEEE doubles) and the CRC-32 of the header line, a newline and everything of the line before the ` *`: a record
!> is bound to its header, hence to the input's fingerprint, the task count and the order of the fields, so that a
!> line copied from another input's journal fails its check. A line is accepted only if its checksum matches and
!> it holds exactly m + 1 numbers that read without error; any other line (cut short by a kill, altered on disk,
!> garbage, another journal's) is dropped and its task computed again. A header that fails its checksum (two field
!> names swapped, an edited task count) is refused, as is the journal of format 3 that supratrans wrote before the
!> records were bound to their header. Records are read by name: a journal that holds the fields in another order is
!> read in the reader's order; one that lacks a field the reader needs, or has one it does not know, is refused, as
!> is one of another input. An empty journal is no journal (the run starts afresh).
module supratrans_journal
    use, intrinsic :: iso_fortran_env, only: int64
    use supratrans_kinds, only: wp
    use supratrans_strings, only: int_str
    use supratrans_error, only: error_type, fatal_error, err_io
    use supratrans_system, only: file_size, append_bytes, write_file_atomic, not_own_file
    implicit none
    private

    public :: split_words
    public :: journal_header, journal_line, parse_journal_line, read_journal, write_journal, append_journal_line, crc32, &
              header_checked, record_binding

    !> The format of the journals written (3: records not bound to the header, which had no checksum).
    character(len=*), parameter, public :: journal_format = "4"

    !> Longest journal line accepted (a task has at most a few dozen values, a fold line's about a thousand).
    integer, parameter :: max_line = 65536
    !> Most values a task's record may have: its line (index, 26 characters a value, checksum) fits `max_line`.
    integer, parameter, public :: max_fields = (max_line - 64)/26

contains

    !> The header line of a journal of `ntask` tasks whose records have the fields `fields`, for the input
    !> `fingerprint`.
    pure function journal_header(ntask, fields, fingerprint) result(header)
        !> Number of tasks of the scene.
        integer, intent(in) :: ntask
        !> Names of a record's fields (no blanks inside a name), in the order of the values.
        character(len=*), intent(in) :: fields(:)
        !> Fingerprint of the input.
        character(len=*), intent(in) :: fingerprint
        character(len=:), allocatable :: header
        integer :: i

        character(len=8) :: hex

        header = "supratrans-journal " // journal_format // " " // int_str(ntask) // " " // fingerprint
        do i = 1, size(fields)
            header = header // " " // trim(fields(i))
        end do
        write (hex, "(z8.8)") crc32(header)
        header = header // " *" // hex
    end function journal_header

    !> Whether a header line's checksum matches (`journal_header` wrote it, and it is unaltered).
    pure function header_checked(line) result(ok)
        !> The header line.
        character(len=*), intent(in) :: line
        logical :: ok
        integer :: star, ios
        integer(int64) :: stored

        ok = .false.
        star = index_of_mark(line)
        if (star < 3 .or. len(line) - star /= 8) return
        if (verify(line(star + 1:), "0123456789ABCDEF") /= 0) return
        read (line(star + 1:), "(z8)", iostat=ios) stored
        if (ios /= 0) return
        ok = stored == crc32(line(1:star - 2))
    end function header_checked

    !> Match a journal's header against the one expected: same version, tasks and fingerprint, and the same field
    !> names in any order (checksums apart). `column(i)` is the position in the journal's lines of the expected
    !> field i. The caller checks the header's checksum (`header_checked`).
    pure subroutine match_header(line, expected, column, same_input, ok)
        !> The header read.
        character(len=*), intent(in) :: line
        !> The header expected (`journal_header`).
        character(len=*), intent(in) :: expected
        !> Column of each expected field in the journal (allocated when `ok`).
        integer, allocatable, intent(out) :: column(:)
        !> The version, task count and fingerprint agree.
        logical, intent(out) :: same_input
        !> The fields agree too (as a set).
        logical, intent(out) :: ok
        character(len=:), allocatable :: got(:), want(:)
        integer :: i, j

        ok = .false.
        call split_words(line(1:max(0, index_of_mark(line) - 2)), got)
        call split_words(expected(1:max(0, index_of_mark(expected) - 2)), want)
        same_input = size(got) >= 4 .and. size(want) >= 4
        if (same_input) same_input = all(got(1:4) == want(1:4))
        if (.not. same_input .or. size(got) /= size(want)) return
        allocate (column(size(want) - 4))
        do i = 5, size(want)
            column(i - 4) = 0
            do j = 5, size(got)
                if (got(j) == want(i)) column(i - 4) = j - 4
            end do
            if (column(i - 4) == 0) return
        end do
        ok = .true.
    end subroutine match_header

    !> The blank-separated words of a line.
    pure subroutine split_words(line, words)
        !> The line.
        character(len=*), intent(in) :: line
        !> Its words (padded to the longest).
        character(len=:), allocatable, intent(out) :: words(:)
        integer :: i, n, start, longest, pass

        do pass = 1, 2
            n = 0
            longest = 1
            i = 1
            do while (i <= len(line))
                if (line(i:i) == " ") then
                    i = i + 1
                    cycle
                end if
                start = i
                do while (i <= len(line))
                    if (line(i:i) == " ") exit
                    i = i + 1
                end do
                n = n + 1
                longest = max(longest, i - start)
                if (pass == 2) words(n) = line(start:i - 1)
            end do
            if (pass == 1) allocate (character(len=longest) :: words(n))
        end do
    end subroutine split_words

    !> The journal line of task `index` with its `values`, its checksum binding it to the journal's `header`
    !> (thread-safe: fixed-length buffers).
    function journal_line(index, values, header) result(line)
        !> Task index.
        integer, intent(in) :: index
        !> The task's values.
        real(wp), intent(in) :: values(:)
        !> The header line of the journal (`journal_header`).
        character(len=*), intent(in) :: header
        character(len=:), allocatable :: line

        line = bound_line(index, values, record_binding(header))
    end function journal_line

    !> What binds the records of a journal to its `header`: the CRC-32 of the header line and a newline, from which
    !> each record's checksum starts.
    pure function record_binding(header) result(binding)
        !> The header line of the journal (`journal_header`).
        character(len=*), intent(in) :: header
        integer(int64) :: binding

        binding = crc32(header // new_line("a"))
    end function record_binding

    !> `journal_line` with the header's `record_binding` (thread-safe: fixed-length buffers).
    function bound_line(index, values, binding) result(line)
        !> Task index.
        integer, intent(in) :: index
        !> The task's values.
        real(wp), intent(in) :: values(:)
        !> `record_binding` of the journal's header.
        integer(int64), intent(in) :: binding
        character(len=:), allocatable :: line
        character(len=32 + 26*size(values)) :: buffer
        character(len=8) :: hex

        write (buffer, "(i0, *(1x, es25.17e3))") index, values
        write (hex, "(z8.8)") crc32(trim(buffer), binding)
        line = trim(buffer) // " *" // hex
    end function bound_line

    !> Read one journal line: `ok` only when its checksum (bound to `header`) matches and it holds exactly
    !> `size(values)` + 1 numbers.
    subroutine parse_journal_line(line, header, ntask, task, values, ok)
        !> The line (without its newline).
        character(len=*), intent(in) :: line
        !> The header line of the journal it was read from.
        character(len=*), intent(in) :: header
        !> Number of tasks (valid indices are 1..ntask).
        integer, intent(in) :: ntask
        !> Task index read.
        integer, intent(out) :: task
        !> Values read.
        real(wp), intent(out) :: values(:)
        !> Whether the line is whole and unaltered.
        logical, intent(out) :: ok
        integer :: star, ios, ntokens, i
        integer(int64) :: stored
        logical :: in_token

        ok = .false.
        task = 0
        values = 0.0_wp
        star = index_of_mark(line)
        if (star < 3 .or. len(line) - star /= 8) return
        read (line(star + 1:), "(z8)", iostat=ios) stored
        if (ios /= 0) return
        if (stored /= crc32(line(1:star - 2), crc32(header // new_line("a")))) return
        ntokens = 0
        in_token = .false.
        do i = 1, star - 2
            if (line(i:i) /= " " .neqv. in_token) then
                in_token = .not. in_token
                if (in_token) ntokens = ntokens + 1
            end if
        end do
        if (ntokens /= size(values) + 1) return
        read (line(1:star - 2), *, iostat=ios) task, values
        if (ios /= 0) return
        ok = task >= 1 .and. task <= ntask
    end subroutine parse_journal_line

    !> Position of the checksum mark `*` in a line, 0 if none.
    pure function index_of_mark(line) result(k)
        character(len=*), intent(in) :: line
        integer :: k

        k = index(line, " *", back=.true.)
        if (k > 0) k = k + 1
    end function index_of_mark

    !> Read the whole lines of an existing journal into `results`/`done`; nothing if there is no journal or it is
    !> empty. `dropped` counts the lines that failed their check.
    subroutine read_journal(journal, header, results, done, dropped, error)
        !> Journal file.
        character(len=*), intent(in) :: journal
        !> The header it must have.
        character(len=*), intent(in) :: header
        !> Results, (values, tasks): filled for the tasks found.
        real(wp), intent(inout) :: results(:, :)
        !> Which tasks were found.
        logical, intent(inout) :: done(:)
        !> Lines dropped (cut short or altered).
        integer, intent(out) :: dropped
        !> Error: unreadable, or the journal of another input.
        type(error_type), allocatable, intent(out) :: error
        logical :: exists, ok, same_input
        integer :: unit, ios, task
        integer, allocatable :: column(:)
        character(len=:), allocatable :: line, got
        real(wp), allocatable :: values(:)
        character(len=:), allocatable :: words(:)

        dropped = 0
        inquire (file=journal, exist=exists)
        if (.not. exists) return
        ! a checksum finds damage, not forgery: only a journal of this user's, writable by nobody else, is resumed from
        if (len(not_own_file(journal)) > 0) then
            call fatal_error(error, journal // ": " // not_own_file(journal), err_io)
            return
        end if
        if (file_size(journal) == 0) return
        open (newunit=unit, file=journal, status="old", action="read", iostat=ios)
        if (ios /= 0) then
            call fatal_error(error, journal // ": cannot read the journal of an earlier run", err_io)
            return
        end if
        call read_line(unit, got, ios)
        ok = .false.
        same_input = .false.
        if (ios == 0) call split_words(got, words)
        if (ios == 0 .and. index(got, "supratrans-journal ") == 1 .and. size(words) >= 2) then
            if (words(2) /= journal_format) then
                close (unit)
                call fatal_error(error, journal // ": journal in the format " // trim(words(2)) // " of an older " &
                                 // "supratrans (the format changed: records are now bound to their input; this one " &
                                 // "writes " // journal_format // "): delete it to start afresh", err_io)
                return
            end if
            if (.not. header_checked(got)) then
                close (unit)
                call fatal_error(error, journal // ": the journal's header fails its checksum (altered: its fields or " &
                                 // "task count cannot be trusted); delete it to start afresh", err_io)
                return
            end if
        end if
        if (ios == 0) call match_header(got, header, column, same_input, ok)
        if (.not. ok) then
            close (unit)
            if (same_input) then
                call fatal_error(error, journal // ": journal of another version of supratrans (its records have " &
                                 // "other fields; delete it to start afresh)", err_io)
            else if (ios == 0 .and. index(got, "supratrans-journal ") == 1) then
                call fatal_error(error, journal // ": journal of a different input or scene (delete it to start " &
                                 // "afresh, or restore the input it was made with)", err_io)
            else
                call fatal_error(error, journal // ": not a supratrans journal, or its header is damaged (delete it " &
                                 // "to start afresh)", err_io)
            end if
            return
        end if
        allocate (values(size(results, 1)))
        do
            call read_line(unit, line, ios)
            if (ios /= 0) exit
            call parse_journal_line(line, got, size(done), task, values, ok)
            if (.not. ok) then
                dropped = dropped + 1
                cycle
            end if
            results(:, task) = values(column)
            done(task) = .true.
        end do
        close (unit)
    end subroutine read_journal

    !> (Re)write a journal with its header and the lines of the tasks done (atomically, never through a link: a fresh
    !> temporary file created exclusively, fsync, rename; see `write_file_atomic`).
    subroutine write_journal(journal, header, results, done, error)
        !> Journal file.
        character(len=*), intent(in) :: journal
        !> Header line.
        character(len=*), intent(in) :: header
        !> Results, (values, tasks).
        real(wp), intent(in) :: results(:, :)
        !> Which tasks are done.
        logical, intent(in) :: done(:)
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: text
        integer :: i
        type(error_type), allocatable :: cause

        text = header // new_line("a")
        do i = 1, size(done)
            if (done(i)) text = text // journal_line(i, results(:, i), header) // new_line("a")
        end do
        call write_file_atomic(journal, text, cause)
        if (allocated(cause)) call fatal_error(error, cause%message // "; the journal there is kept", err_io)
    end subroutine write_journal

    !> Append one task's line to a journal (write(2), never through a link: a full disk is reported, `ok` false).
    subroutine append_journal_line(journal, binding, index, values, ok)
        !> Journal file.
        character(len=*), intent(in) :: journal
        !> `record_binding` of its header line.
        integer(int64), intent(in) :: binding
        !> Task index.
        integer, intent(in) :: index
        !> The task's values.
        real(wp), intent(in) :: values(:)
        !> Whether the line was written whole.
        logical, intent(out) :: ok

        call append_bytes(journal, bound_line(index, values, binding) // new_line("a"), ok)
    end subroutine append_journal_line

    !> Read one whole line (up to `max_line` characters; a longer one is cut and will fail its checksum).
    subroutine read_line(unit, line, ios)
        integer, intent(in) :: unit
        character(len=:), allocatable, intent(out) :: line
        integer, intent(out) :: ios
        character(len=4096) :: buffer
        integer :: size_read

        line = ""
        do
            read (unit, "(a)", advance="no", iostat=ios, size=size_read) buffer
            if (len(line) < max_line) line = line // buffer(1:size_read)
            if (ios /= 0) exit
        end do
        if (is_iostat_eor(ios)) ios = 0
    end subroutine read_line

    !> CRC-32 (polynomial 0xEDB88320, reflected, initial and final XOR 0xFFFFFFFF: zlib's crc32) of a string;
    !> with `previous`, the CRC-32 of the bytes `previous` was the CRC of followed by `text` (zlib's crc32(crc, ...)).
    pure function crc32(text, previous) result(crc)
        !> Bytes to check.
        character(len=*), intent(in) :: text
        !> CRC-32 of the bytes before `text` (default: none).
        integer(int64), intent(in), optional :: previous
        integer(int64) :: crc
        integer(int64), parameter :: poly = int(z'EDB88320', int64), mask = int(z'FFFFFFFF', int64)
        integer :: i, bit

        crc = mask
        if (present(previous)) crc = ieor(iand(previous, mask), mask)
        do i = 1, len(text)
            crc = ieor(crc, int(ichar(text(i:i)), int64))
            do bit = 1, 8
                if (iand(crc, 1_int64) /= 0) then
                    crc = ieor(shiftr(crc, 1), poly)
                else
                    crc = shiftr(crc, 1)
                end if
            end do
        end do
        crc = ieor(crc, mask)
    end function crc32

end module supratrans_journal
