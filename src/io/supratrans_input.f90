!> Reading one namelist file into a validated `input_config`.
!>
!> The input is a Fortran namelist file with the optional groups `&chain`, `&drive`, `&numerics`, `&record`,
!> `&scene`, `&detect` and `&output`; every key has the default of the schema (src/io/schema.toml, the paper's
!> Sec. 4). The file is read in three passes, so that every mistake is reported as one line naming the file, the
!> group and the key:
!>
!> 1. `parse_namelist` (`supratrans_namelist`) checks the syntax, group names, key names, value counts and value
!>    types against the key table of the schema, and gives each key's values converted to its type (names of
!>    choices held as numbers, potential and method, looked up);
!> 2. `set_key` stores each key given, in the order of the table;
!> 3. `validate_config` (`supratrans_validate`) checks the ranges, the rules between keys, and that the output file
!>    is not replaced by accident.
!>
!> Error messages (status `err_input`), one line each, besides those of the parser and of the validation:
!> `<file>: cannot open file (<reason>)`, `<file>: cannot read file (<reason>)`.
module supratrans_input
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_strings, only: int_str, text_fingerprint
    use supratrans_system, only: path_kind, path_missing, path_directory, path_special, file_size
    use supratrans_config, only: input_config, default_probes
    use supratrans_schema, only: key_table, set_key, key_record_probes
    use supratrans_namelist, only: parse_namelist, parsed_input
    use supratrans_validate, only: validate_config
    use supratrans_host, only: timestamp
    implicit none
    private

    public :: read_input, read_input_text

    !> Largest namelist file read (bytes).
    integer, parameter :: max_input_bytes = 1048576
    !> Longest line of a namelist file (characters).
    integer, parameter :: max_line_length = 2000

contains

    !> Read the namelist file `path` into `cfg` and validate it (`validate_config`, output file check included).
    !>
    !> On failure `error` is allocated with status `err_input` and a one-line message naming the file, the group and
    !> the key. After a failed range check `cfg` still holds the values read; after a failure to read, the defaults.
    !> `cfg%text` keeps the file's text and `cfg%started` the time it was read (provenance of the output).
    subroutine read_input(path, cfg, error, check_output)
        !> Path of the namelist file; recorded in `cfg%source` and used in messages.
        character(len=*), intent(in) :: path
        !> The configuration read.
        type(input_config), intent(out) :: cfg
        !> Allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Check the output file too (`validate_config`); default true.
        logical, intent(in), optional :: check_output
        character(len=:), allocatable :: text

        cfg%source = path
        call read_text_file(path, text, error)
        if (allocated(error)) return
        call read_input_text(text, path, cfg, error, check_output)
    end subroutine read_input

    !> Read a namelist text (as `read_input` reads a file's contents) into `cfg` and validate it; `path` names it
    !> in messages and in `cfg%source`. The text, its fingerprint and the time are kept in `cfg` (journals, part
    !> files, provenance).
    subroutine read_input_text(text, path, cfg, error, check_output)
        !> The namelist text.
        character(len=*), intent(in) :: text
        !> Where it came from (for messages).
        character(len=*), intent(in) :: path
        !> The configuration read.
        type(input_config), intent(out) :: cfg
        !> Allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        !> Check the output file too (`validate_config`); default true.
        logical, intent(in), optional :: check_output
        type(parsed_input) :: parsed
        integer :: ik

        cfg%source = path
        cfg%started = timestamp()
        cfg%text = text
        cfg%fingerprint = text_fingerprint(text)
        cfg%run%record%probes = default_probes
        call check_line_lengths(text, path, error)
        if (allocated(error)) return
        call parse_namelist(text, path, parsed, error)
        if (allocated(error)) return
        if (parsed%n_groups == 0) then
            call fatal_error(error, path // ": no namelist group in the file (an empty or comments-only input is " &
                             // "refused: write at least &output file = '...' /)", err_input)
            return
        end if
        do ik = 1, size(key_table)
            if (parsed%n_values(ik) > 0) call set_key(cfg, ik, parsed%values(ik))
        end do
        ! the default probe (the paper's site 60) moves to the last site of a shorter chain
        if (parsed%n_values(key_record_probes) == 0) cfg%run%record%probes = min(default_probes, cfg%run%chain%n)
        call validate_config(cfg, error, check_output)
    end subroutine read_input_text

    !> Refuse a line longer than `max_line_length` characters (no namelist needs one; the parser's work grows with
    !> the number of tokens of a line, so a megabyte-long line would take seconds).
    pure subroutine check_line_lengths(text, path, error)
        character(len=*), intent(in) :: text, path
        type(error_type), allocatable, intent(out) :: error
        integer :: start, k, line

        if (len(text) == 0) return
        start = 1
        line = 1
        do
            k = index(text(start:), new_line("a"))
            if (k == 0) k = len(text) - start + 2
            if (k - 1 > max_line_length) then
                call fatal_error(error, path // ": line " // int_str(line) // " is " // int_str(k - 1) &
                                 // " characters long (at most " // int_str(max_line_length) // ")", err_input)
                return
            end if
            start = start + k
            line = line + 1
            if (start > len(text)) exit
        end do
    end subroutine check_line_lengths

    !> The whole contents of a text file, newlines included.
    subroutine read_text_file(path, text, error)
        character(len=*), intent(in) :: path
        character(len=:), allocatable, intent(out) :: text
        type(error_type), allocatable, intent(out) :: error
        integer :: unit, ios, nbytes
        character(len=512) :: msg

        select case (path_kind(path))
        case (path_missing)
            call fatal_error(error, path // ": cannot open file (No such file or directory)", err_input)
            return
        case (path_directory)
            call fatal_error(error, path // ": is a directory, not a namelist file", err_input)
            return
        case (path_special)
            call fatal_error(error, path // ": not a regular file (a FIFO, device or socket): give a namelist file", &
                             err_input)
            return
        case default
            continue    ! a regular file
        end select
        if (file_size(path) > max_input_bytes) then
            call fatal_error(error, path // ": " // int_str(int(file_size(path)/1024)) // " KiB is too large for a " &
                             // "namelist file (limit 1024 KiB)", err_input)
            return
        end if
        msg = ""
        open (newunit=unit, file=path, status="old", access="stream", form="unformatted", action="read", &
              iostat=ios, iomsg=msg)
        if (ios /= 0) then
            call fatal_error(error, path // ": cannot open file (" // os_reason(msg) // ")", err_input)
            return
        end if
        inquire (unit=unit, size=nbytes)
        if (nbytes < 0) then
            close (unit)
            call fatal_error(error, path // ": cannot read file (size unknown)", err_input)
            return
        end if
        allocate (character(len=nbytes) :: text)
        ios = 0
        if (nbytes > 0) read (unit, iostat=ios, iomsg=msg) text
        close (unit)
        if (ios /= 0) then
            call fatal_error(error, path // ": cannot read file (" // os_reason(msg) // ")", err_input)
        end if
    end subroutine read_text_file

    !> The operating system's part of a gfortran I/O message ("Cannot open file 'x': Permission denied").
    pure function os_reason(msg) result(reason)
        character(len=*), intent(in) :: msg
        character(len=:), allocatable :: reason
        integer :: k

        k = index(msg, ": ", back=.true.)
        if (k > 0) then
            reason = trim(msg(k + 2:))
        else
            reason = trim(msg)
        end if
        if (len(reason) == 0) reason = "unknown reason"
    end function os_reason

end module supratrans_input

