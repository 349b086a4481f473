!> Reading one namelist file into a validated `input_config`, and validating configurations built in code.
!>
!> The input is a Fortran namelist file with the optional groups `&chain`, `&drive`, `&numerics`, `&record`,
!> `&scene` and `&output`; every key has the default of `supratrans_config` (paper Sec. 4). Keys are
!> case-insensitive; so are the names `potential`, `method` and `kind`. The file is read in three passes, so that
!> every mistake is reported as one line naming the file, the group and the key:
!>
!> 1. a small tokenizer and parser for namelist syntax checks group names, key names, value counts and value types
!>    against one table of (group, key, type) entries (`key_table`; a new key is one more entry there, one more
!>    variable in the group's NAMELIST statement below, and its check in `check_parameters`);
!> 2. each group is rewritten in canonical form and converted by a native namelist READ from an internal file;
!> 3. `validate_config` checks ranges and the physics: the band gap 0 < Omega < sqrt(1 + m^2), the paper's
!>    necessary stability condition (c^2 - m^2/4) dt^2 < 1 + (gamma/4 + beta) dt, and that the output file is
!>    not replaced by accident.
!>
!> Syntax: `&group ... /` (or `&end`), `key = value`, `key = v1, v2, ...` (lists), separators are commas, blanks and
!> newlines, strings in '...' or "..." (the quote doubled inside), `!` comments, logicals `.true.`, `.false.`,
!> `T`, `F`, integers, reals with `e` or `d` exponents. Names and paths may also be given unquoted when they hold no
!> blank, comma, slash or quote. Rejected with a clear message: repeat counts (`3*0.0`), null values
!> (`a = 1, , 3`), subscripts (`probes(2) = 5`), a group or key given twice, and any text outside the groups other
!> than `!` comments.
!>
!> Error messages (status `err_input`), one line each:
!>
!> * `<file>: cannot open file (<reason>)`, `<file>: cannot read file (<reason>)`;
!> * `<file>: line <l>: <syntax problem>`, `<file>: line <l>: &<group>: <syntax problem>`;
!> * `<file>: unknown group &<group> (known: &chain, ...)`, `<file>: group &<group> is given twice`;
!> * `<file>: &<group>: unknown key '<key>' (known: ...)`, `... key '<key>' expects an integer, got '<value>'`;
!> * `<file>: &<group>: <key> = <value>: <what is wrong>` for values out of range.
module supratrans_input
    use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
    use supratrans_kinds, only: wp, name_len, path_len
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_potential, only: sine_gordon, klein_gordon, potential_name, potential_from_name
    use supratrans_config, only: input_config, run_config, method_newton, method_linearized, method_rk4, method_rk8, &
        max_curve_values
    use supratrans_curves, only: curve_count, curve_run
    use supratrans_chain, only: band_gap_edge, stability_lhs, stability_rhs, stable_by_paper_condition, critical_dt
    use supratrans_strings, only: int_str, real_str, fixed4, text_fingerprint
    use supratrans_limits, only: check_limits
    use supratrans_system, only: path_kind, path_missing, path_directory, path_special, file_size
    implicit none
    private

    public :: read_input, read_input_text, validate_config, method_name, method_from_name

    !> Site whose u_n(t) is recorded when `&record` gives no `probes` (the paper's Fig. 1 shows u_60).
    integer, parameter, public :: default_probe = 60
    !> Largest namelist file read (bytes).
    integer, parameter :: max_input_bytes = 1048576
    !> Largest coupling c accepted (the stability condition needs dt < 1/c; c^2 must not overflow).
    real(wp), parameter :: max_coupling = 1.0e6_wp
    !> Longest line of a namelist file (characters).
    integer, parameter :: max_line_length = 2000
    !> Largest number of entries in the `probes` list.
    integer, parameter, public :: max_probes = 64

    !> Largest number of entries of the `methods` and `dt_smallest` lists of &scene.
    integer, parameter :: max_scene_methods = 8
    !> Largest number of entries of the `dts` list of &scene.
    integer, parameter :: max_scene_dts = 64

    !> Value type of a key: an integer.
    integer, parameter :: kt_integer = 1
    !> Value type of a key: a real number (integers are accepted).
    integer, parameter :: kt_real = 2
    !> Value type of a key: a logical (.true., .false., T, F).
    integer, parameter :: kt_logical = 3
    !> Value type of a key: a name, compared in lower case, at most `name_len` characters.
    integer, parameter :: kt_name = 4
    !> Value type of a key: a file path, kept as written, at most `path_len` characters.
    integer, parameter :: kt_path = 5

    !> Length of group names in `key_table`.
    integer, parameter :: group_len = 12
    !> Length of key names in `key_table`.
    integer, parameter :: key_len = 24

    !> One key of the input: the group it belongs to, its name, its value type, how many values it takes.
    type :: key_spec
        !> Group name, lower case, without the '&'.
        character(len=group_len) :: group
        !> Key name, lower case.
        character(len=key_len) :: key
        !> Value type: `kt_integer`, `kt_real`, `kt_logical`, `kt_name` or `kt_path`.
        integer :: type
        !> Largest number of values (1 for a scalar key).
        integer :: max_values
    end type key_spec

    !> Every key of the input, grouped; the order of the groups here is the order in which they are converted.
    type(key_spec), parameter :: key_table(*) = [ &
        key_spec("chain", "potential", kt_name, 1), &
        key_spec("chain", "c", kt_real, 1), &
        key_spec("chain", "m2", kt_real, 1), &
        key_spec("chain", "gamma", kt_real, 1), &
        key_spec("chain", "beta", kt_real, 1), &
        key_spec("chain", "n", kt_integer, 1), &
        key_spec("chain", "n0", kt_integer, 1), &
        key_spec("chain", "kappa", kt_real, 1), &
        key_spec("chain", "sigma", kt_real, 1), &
        key_spec("drive", "amplitude", kt_real, 1), &
        key_spec("drive", "omega", kt_real, 1), &
        key_spec("drive", "ramp_time", kt_real, 1), &
        key_spec("drive", "allow_outside_gap", kt_logical, 1), &
        key_spec("numerics", "method", kt_name, 1), &
        key_spec("numerics", "dt", kt_real, 1), &
        key_spec("numerics", "t_final", kt_real, 1), &
        key_spec("numerics", "newton_tol", kt_real, 1), &
        key_spec("numerics", "newton_max_iter", kt_integer, 1), &
        key_spec("numerics", "blowup_threshold", kt_real, 1), &
        key_spec("numerics", "allow_unstable", kt_logical, 1), &
        key_spec("record", "probes", kt_integer, max_probes), &
        key_spec("record", "probe_every", kt_integer, 1), &
        key_spec("record", "ledger_every", kt_integer, 1), &
        key_spec("scene", "kind", kt_name, 1), &
        key_spec("scene", "amplitude_min", kt_real, 1), &
        key_spec("scene", "amplitude_max", kt_real, 1), &
        key_spec("scene", "amplitude_step", kt_real, 1), &
        key_spec("scene", "omega_min", kt_real, 1), &
        key_spec("scene", "omega_max", kt_real, 1), &
        key_spec("scene", "omega_step", kt_real, 1), &
        key_spec("scene", "vary", kt_name, 1), &
        key_spec("scene", "values", kt_real, max_curve_values), &
        key_spec("scene", "potentials", kt_name, 2), &
        key_spec("scene", "coarse_step", kt_real, 1), &
        key_spec("scene", "resolution", kt_real, 1), &
        key_spec("scene", "methods", kt_name, max_scene_methods), &
        key_spec("scene", "dts", kt_real, max_scene_dts), &
        key_spec("scene", "dt_smallest", kt_real, max_scene_methods), &
        key_spec("scene", "amplitudes", kt_real, max_curve_values), &
        key_spec("scene", "c_values", kt_real, max_curve_values), &
        key_spec("scene", "repeats", kt_integer, 1), &
        key_spec("scene", "reference_dt", kt_real, 1), &
        key_spec("detect", "site", kt_integer, 1), &
        key_spec("detect", "amplitude", kt_real, 1), &
        key_spec("detect", "stop_when_decided", kt_logical, 1), &
        key_spec("output", "file", kt_path, 1), &
        key_spec("output", "overwrite", kt_logical, 1), &
        key_spec("output", "quiet", kt_logical, 1)]

    !> Scene kinds accepted by `&scene kind = ...`.
    character(len=*), parameter :: scene_kinds(*) = [character(len=name_len) :: "timeseries", "amplitude_sweep", "map", &
                                                     "bifurcation", "work_precision", "stability"]

    !> Parameters a scene may vary between its curves (`&scene vary = ...`).
    character(len=*), parameter :: vary_names(*) = [character(len=name_len) :: "none", "gamma", "beta", "m2"]

    !> Token kinds of the namelist tokenizer.
    integer, parameter :: tk_eof = 0, tk_group = 1, tk_slash = 2, tk_equals = 3, tk_comma = 4, &
                          tk_string = 5, tk_word = 6

    !> Characters that end an unquoted word.
    character(len=*), parameter :: word_stops = " " // achar(9) // achar(10) // achar(13) // "!&/=,'" // '"'

    !> One token of a namelist file.
    type :: token_t
        !> Token kind (`tk_*`).
        integer :: kind = tk_eof
        !> Line on which the token starts.
        integer :: line = 0
        !> Group name (lower case) for `tk_group`, contents for `tk_string`, the characters for `tk_word`.
        character(len=:), allocatable :: text
    end type token_t

    !> A string of any length, for arrays of strings.
    type :: string_t
        !> The characters.
        character(len=:), allocatable :: s
    end type string_t

    !> The checked contents of a namelist file, before conversion.
    type :: parsed_input
        !> Canonical namelist text of each group of `group_names()`; unallocated when the group is absent.
        type(string_t), allocatable :: group_text(:)
        !> Number of values given for each entry of `key_table` (0 when the key is absent).
        integer, allocatable :: n_values(:)
    end type parsed_input

contains

    !> Read the namelist file `path` into `cfg` and validate it (`validate_config`, output file check included).
    !>
    !> On failure `error` is allocated with status `err_input` and a one-line message naming the file, the group and
    !> the key. After a failed range check `cfg` still holds the values read; after a failure to read, the defaults.
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
    !> in messages and in `cfg%source`. The text and its fingerprint are kept in `cfg` (journals, part files).
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

        cfg%source = path
        cfg%text = text
        cfg%fingerprint = text_fingerprint(text)
        cfg%started = now_iso()
        cfg%run%record%probes = [default_probe]
        call check_line_lengths(text, path, error)
        if (allocated(error)) return
        call parse_namelist(text, path, parsed, error)
        if (allocated(error)) return
        if (count_groups_given(parsed) == 0) then
            call fatal_error(error, path // ": no namelist group in the file (an empty or comments-only input is " &
                             // "refused: write at least &output file = '...' /)", err_input)
            return
        end if
        call convert_groups(parsed, path, cfg, error)
        if (allocated(error)) return
        ! the default probe (the paper's site 60) moves to the last site of a shorter chain
        if (parsed%n_values(find_key("record", "probes")) == 0) cfg%run%record%probes = [min(default_probe, cfg%run%chain%n)]
        call validate_config(cfg, error, check_output)
    end subroutine read_input_text

    !> Refuse a line longer than `max_line_length` characters (no namelist needs one; the parser's work grows with
    !> the number of tokens of a line, so a megabyte-long line would take seconds).
    pure subroutine check_line_lengths(text, path, error)
        !> The namelist text.
        character(len=*), intent(in) :: text
        !> Its name, for messages.
        character(len=*), intent(in) :: path
        !> Allocated when a line is too long.
        type(error_type), allocatable, intent(out) :: error
        integer :: start, k, line

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

    !> The date and time now, ISO 8601 with the UTC offset ("2026-11-23T08:45:54+0000").
    function now_iso() result(stamp)
        character(len=:), allocatable :: stamp
        character(len=8) :: d
        character(len=10) :: t
        character(len=5) :: z

        call date_and_time(d, t, z)
        stamp = d(1:4) // "-" // d(5:6) // "-" // d(7:8) // "T" // t(1:2) // ":" // t(3:4) // ":" // t(5:6) // z
    end function now_iso

    !> Number of namelist groups present in a parsed input.
    pure function count_groups_given(parsed) result(n)
        !> The parsed input.
        type(parsed_input), intent(in) :: parsed
        integer :: n
        integer :: i

        n = 0
        if (.not. allocated(parsed%group_text)) return
        do i = 1, size(parsed%group_text)
            if (allocated(parsed%group_text(i)%s)) n = n + 1
        end do
    end function count_groups_given

    !> Check that a configuration is complete and within range: the checks of `read_input` after conversion.
    !>
    !> Meant also for configurations built or changed in code (scenes). Messages start with `cfg%source`, or with
    !> "configuration" when that is not set.
    subroutine validate_config(cfg, error, check_output)
        !> The configuration to check.
        type(input_config), intent(in) :: cfg
        !> Allocated when a check fails.
        type(error_type), allocatable, intent(out) :: error
        !> Check that the output file does not exist (unless `overwrite`) and that its directory does; default true.
        logical, intent(in), optional :: check_output
        character(len=:), allocatable :: where
        logical :: check_file

        where = "configuration"
        if (allocated(cfg%source)) then
            if (len(cfg%source) > 0) where = cfg%source
        end if
        call check_parameters(cfg, where, error)
        if (allocated(error)) return
        call check_limits(cfg, where, error)
        if (allocated(error)) return
        check_file = .true.
        if (present(check_output)) check_file = check_output
        if (check_file) call check_output_file(cfg, where, error)
    end subroutine validate_config

    !> Name of an integrator as written in `&numerics method = ...`; "unknown" for an unknown identifier.
    pure function method_name(id) result(name)
        !> Integrator identifier (`method_newton`, `method_linearized`, `method_rk4`).
        integer, intent(in) :: id
        character(len=:), allocatable :: name

        select case (id)
        case (method_newton)
            name = "newton"
        case (method_linearized)
            name = "linearized"
        case (method_rk4)
            name = "rk4"
        case (method_rk8)
            name = "rk8"
        case default
            name = "unknown"
        end select
    end function method_name

    !> Integrator identifier from its name ('newton', 'linearized' or 'rk4', lower case); 0 if unknown.
    pure function method_from_name(name) result(id)
        !> Name as written in the namelist.
        character(len=*), intent(in) :: name
        integer :: id

        select case (trim(adjustl(name)))
        case ("newton")
            id = method_newton
        case ("linearized")
            id = method_linearized
        case ("rk4")
            id = method_rk4
        case ("rk8")
            id = method_rk8
        case default
            id = 0
        end select
    end function method_from_name

    ! ---------------------------------------------------------------------------------------------------------------
    ! Reading the file
    ! ---------------------------------------------------------------------------------------------------------------

    !> The whole contents of a text file, newlines included.
    subroutine read_text_file(path, text, error)
        !> File to read.
        character(len=*), intent(in) :: path
        !> Its contents.
        character(len=:), allocatable, intent(out) :: text
        !> Allocated when the file cannot be opened or read.
        type(error_type), allocatable, intent(out) :: error
        integer :: unit, ios, nbytes
        logical :: exists
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
        !> The iomsg text.
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

    ! ---------------------------------------------------------------------------------------------------------------
    ! Tokenizer
    ! ---------------------------------------------------------------------------------------------------------------

    !> Split namelist text into tokens: `&name`, `/`, `=`, `,`, quoted strings and unquoted words; the last is `tk_eof`.
    pure subroutine tokenize(text, path, tokens, error)
        !> The file contents.
        character(len=*), intent(in) :: text
        !> File name for messages.
        character(len=*), intent(in) :: path
        !> The tokens, ending with one `tk_eof`.
        type(token_t), allocatable, intent(out) :: tokens(:)
        !> Allocated on a lexical error (unterminated string, '&' without a name).
        type(error_type), allocatable, intent(out) :: error
        integer :: i, j, n, line, ntok
        character :: ch
        character(len=:), allocatable :: s

        allocate (tokens(64))
        ntok = 0
        line = 1
        n = len(text)
        i = 1
        do while (i <= n)
            ch = text(i:i)
            select case (ch)
            case (achar(10))
                line = line + 1
                i = i + 1
            case (" ", achar(9), achar(13))
                i = i + 1
            case ("!")
                j = index(text(i:), achar(10))
                if (j == 0) then
                    i = n + 1
                else
                    i = i + j - 1
                end if
            case ("&")
                j = i + 1
                do while (j <= n)
                    if (.not. is_name_char(text(j:j))) exit
                    j = j + 1
                end do
                if (j == i + 1) then
                    call fail_line(error, path, line, "'&' must be followed by a group name, such as &chain")
                    return
                end if
                call push_token(tokens, ntok, tk_group, line, lower(text(i + 1:j - 1)))
                i = j
            case ("/")
                call push_token(tokens, ntok, tk_slash, line, "/")
                i = i + 1
            case ("=")
                call push_token(tokens, ntok, tk_equals, line, "=")
                i = i + 1
            case (",")
                call push_token(tokens, ntok, tk_comma, line, ",")
                i = i + 1
            case ("'", '"')
                s = ""
                j = i + 1
                do
                    if (j > n) exit
                    if (text(j:j) == achar(10)) exit
                    if (text(j:j) == ch) then
                        if (j < n) then
                            if (text(j + 1:j + 1) == ch) then
                                s = s // ch
                                j = j + 2
                                cycle
                            end if
                        end if
                        exit
                    end if
                    s = s // text(j:j)
                    j = j + 1
                end do
                if (j > n) then
                    call fail_line(error, path, line, "unterminated string " // ch // s)
                    return
                else if (text(j:j) /= ch) then
                    call fail_line(error, path, line, "unterminated string " // ch // s)
                    return
                end if
                call push_token(tokens, ntok, tk_string, line, s)
                i = j + 1
            case default
                j = i
                do while (j <= n)
                    if (index(word_stops, text(j:j)) > 0) exit
                    j = j + 1
                end do
                call push_token(tokens, ntok, tk_word, line, text(i:j - 1))
                i = j
            end select
        end do
        call push_token(tokens, ntok, tk_eof, line, "")
        tokens = tokens(1:ntok)
    end subroutine tokenize

    !> Append a token, growing the array as needed.
    pure subroutine push_token(tokens, ntok, kind, line, text)
        !> Token array (capacity >= ntok).
        type(token_t), allocatable, intent(inout) :: tokens(:)
        !> Number of tokens in use; incremented.
        integer, intent(inout) :: ntok
        !> Token kind.
        integer, intent(in) :: kind
        !> Line number.
        integer, intent(in) :: line
        !> Token text.
        character(len=*), intent(in) :: text
        type(token_t), allocatable :: grown(:)

        if (ntok == size(tokens)) then
            allocate (grown(2*size(tokens)))
            grown(1:ntok) = tokens(1:ntok)
            call move_alloc(grown, tokens)
        end if
        ntok = ntok + 1
        tokens(ntok)%kind = kind
        tokens(ntok)%line = line
        tokens(ntok)%text = text
    end subroutine push_token

    ! ---------------------------------------------------------------------------------------------------------------
    ! Parser: groups, keys, value counts and value types against key_table
    ! ---------------------------------------------------------------------------------------------------------------

    !> Tokenize and check namelist text; gives the canonical text of every group present.
    pure subroutine parse_namelist(text, path, parsed, error)
        !> The file contents.
        character(len=*), intent(in) :: text
        !> File name for messages.
        character(len=*), intent(in) :: path
        !> What the file gives, group by group.
        type(parsed_input), intent(out) :: parsed
        !> Allocated on the first problem found.
        type(error_type), allocatable, intent(out) :: error
        type(token_t), allocatable :: tokens(:)
        character(len=group_len) :: groups(count_groups())
        character(len=:), allocatable :: body
        integer :: it, ig

        call tokenize(text, path, tokens, error)
        if (allocated(error)) return
        groups = group_names()
        allocate (parsed%group_text(size(groups)))
        allocate (parsed%n_values(size(key_table)), source=0)
        it = 1
        do
            associate (tok => tokens(it))
                select case (tok%kind)
                case (tk_eof)
                    exit
                case (tk_group)
                    if (tok%text == "end") then
                        call fail_line(error, path, tok%line, "'&end' outside a group")
                        return
                    end if
                    ig = find_name(groups, tok%text)
                    if (ig == 0) then
                        call fatal_error(error, path // ": unknown group &" // tok%text // " (" &
                                         // suggestion(tok%text, groups, "&", "") // "known: " &
                                         // joined(groups, "&") // ")", err_input)
                        return
                    end if
                    if (allocated(parsed%group_text(ig)%s)) then
                        call fatal_error(error, path // ": group &" // trim(groups(ig)) // " is given twice", err_input)
                        return
                    end if
                case default
                    call fail_line(error, path, tok%line, "expected a group such as &chain, got " // describe(tok) &
                                   // " (outside &group ... / only ! comments are allowed)")
                    return
                end select
            end associate
            call parse_group(tokens, it, path, trim(groups(ig)), parsed, body, error)
            if (allocated(error)) return
            parsed%group_text(ig)%s = "&" // trim(groups(ig)) // " " // body // "/"
        end do
    end subroutine parse_namelist

    !> Check one group, from its `&name` token to its `/`; `it` ends on the token after the `/`.
    pure subroutine parse_group(tokens, it, path, group, parsed, body, error)
        !> All tokens of the file.
        type(token_t), intent(in) :: tokens(:)
        !> In: index of the `&group` token. Out: index of the token after the group.
        integer, intent(inout) :: it
        !> File name for messages.
        character(len=*), intent(in) :: path
        !> Group name.
        character(len=*), intent(in) :: group
        !> Value counts are recorded in `parsed%n_values`.
        type(parsed_input), intent(inout) :: parsed
        !> Canonical text of the group's assignments, `key = v1, v2, `.
        character(len=:), allocatable, intent(out) :: body
        !> Allocated on the first problem found.
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: item

        body = ""
        it = it + 1
        do
            associate (tok => tokens(it))
                select case (tok%kind)
                case (tk_slash)
                    it = it + 1
                    return
                case (tk_group)
                    if (tok%text == "end") then
                        it = it + 1
                        return
                    end if
                    call fail_line(error, path, tok%line, "&" // group // ": group not terminated by '/' before &" &
                                   // tok%text)
                    return
                case (tk_eof)
                    call fatal_error(error, path // ": &" // group // ": group not terminated by '/' at end of file", &
                                     err_input)
                    return
                case (tk_comma)
                    it = it + 1
                case (tk_word)
                    call parse_assignment(tokens, it, path, group, parsed, item, error)
                    if (allocated(error)) return
                    body = body // item
                case default
                    call fail_line(error, path, tok%line, "&" // group // ": expected a key, got " // describe(tok))
                    return
                end select
            end associate
        end do
    end subroutine parse_group

    !> Check one `key = value[, value...]`; `it` ends on the token after the last value.
    pure subroutine parse_assignment(tokens, it, path, group, parsed, item, error)
        !> All tokens of the file.
        type(token_t), intent(in) :: tokens(:)
        !> In: index of the key token. Out: index of the token after the values.
        integer, intent(inout) :: it
        !> File name for messages.
        character(len=*), intent(in) :: path
        !> Group name.
        character(len=*), intent(in) :: group
        !> The number of values is recorded in `parsed%n_values`.
        type(parsed_input), intent(inout) :: parsed
        !> Canonical text, `key = v1, v2, `.
        character(len=:), allocatable, intent(out) :: item
        !> Allocated on the first problem found.
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: key, values, canonical
        integer :: ik, nval, previous, line

        key = lower(tokens(it)%text)
        line = tokens(it)%line
        if (.not. is_identifier(key)) then
            if (index(key, "(") > 0) then
                call fail_line(error, path, line, "&" // group // ": subscripted key '" // tokens(it)%text &
                               // "' is not supported (give the whole list, key = v1, v2, ...)")
            else
                call fail_line(error, path, line, "&" // group // ": expected a key, got '" // tokens(it)%text // "'")
            end if
            return
        end if
        if (tokens(it + 1)%kind /= tk_equals) then
            call fail_line(error, path, line, "&" // group // ": expected '=' after '" // tokens(it)%text &
                           // "', got " // describe(tokens(it + 1)))
            return
        end if
        ik = find_key(group, key)
        if (ik == 0) then
            call fail(error, path, group, "unknown key '" // key // "' (" // key_hint(group, key) // "known: " &
                      // joined(group_keys(group), "") // ")")
            return
        end if
        if (parsed%n_values(ik) > 0) then
            call fail(error, path, group, "key '" // key // "' is given twice")
            return
        end if
        it = it + 2
        nval = 0
        previous = tk_equals
        values = ""
        do
            associate (tok => tokens(it))
                select case (tok%kind)
                case (tk_word, tk_string)
                    if (tok%kind == tk_word .and. tokens(it + 1)%kind == tk_equals) exit
                    call check_value(key_table(ik), tok, path, canonical, error)
                    if (allocated(error)) return
                    nval = nval + 1
                    if (nval > 1) values = values // ", "
                    values = values // canonical
                    previous = tk_word
                    it = it + 1
                case (tk_comma)
                    if (previous /= tk_word) then
                        call fail(error, path, group, "key '" // key // "': empty value before ',' on line " &
                                  // int_str(tok%line) // " (null values are not supported)")
                        return
                    end if
                    previous = tk_comma
                    it = it + 1
                case (tk_equals)
                    call fail_line(error, path, tok%line, "&" // group // ": key '" // key // "': unexpected '='")
                    return
                case default
                    exit
                end select
            end associate
        end do
        if (nval == 0) then
            call fail(error, path, group, "key '" // key // "' has no value")
            return
        end if
        if (nval > key_table(ik)%max_values) then
            if (key_table(ik)%max_values == 1) then
                call fail(error, path, group, "key '" // key // "' expects one value, got " // int_str(nval))
            else
                call fail(error, path, group, "key '" // key // "' takes at most " &
                          // int_str(key_table(ik)%max_values) // " values, got " // int_str(nval))
            end if
            return
        end if
        parsed%n_values(ik) = nval
        item = key // " = " // values // ", "
    end subroutine parse_assignment

    !> Check one value against the type of its key and give it in canonical namelist form.
    pure subroutine check_value(spec, tok, path, canonical, error)
        !> The key.
        type(key_spec), intent(in) :: spec
        !> The value token (`tk_word` or `tk_string`).
        type(token_t), intent(in) :: tok
        !> File name for messages.
        character(len=*), intent(in) :: path
        !> The value as it goes into the canonical namelist text.
        character(len=:), allocatable, intent(out) :: canonical
        !> Allocated when the value does not fit the key.
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: group, key, expected
        integer :: ival, ios

        group = trim(spec%group)
        key = trim(spec%key)
        if (tok%kind == tk_word .and. index(tok%text, "*") > 0 .and. spec%type /= kt_path) then
            call fail(error, path, group, "key '" // key // "': repeat counts like '" // tok%text &
                      // "' are not supported (write the values out)")
            return
        end if
        select case (spec%type)
        case (kt_integer)
            expected = "an integer"
            if (tok%kind == tk_word .and. is_integer(tok%text)) then
                read (tok%text, *, iostat=ios) ival
                if (ios == 0) then
                    canonical = tok%text
                    return
                end if
                expected = "an integer in range"
            end if
        case (kt_real)
            expected = "a real number"
            if (tok%kind == tk_word .and. is_real(tok%text)) then
                canonical = tok%text
                return
            end if
        case (kt_logical)
            expected = "a logical (.true. or .false.)"
            if (tok%kind == tk_word) then
                select case (lower(tok%text))
                case (".true.", ".t.", "t", "true")
                    canonical = ".true."
                    return
                case (".false.", ".f.", "f", "false")
                    canonical = ".false."
                    return
                case default
                    continue    ! not a logical: the message below
                end select
            end if
        case (kt_name)
            if (len(tok%text) > name_len) then
                call fail(error, path, group, "key '" // key // "': name longer than " // int_str(name_len) &
                          // " characters")
                return
            end if
            canonical = quoted(lower(tok%text))
            return
        case default
            if (len(tok%text) > path_len) then
                call fail(error, path, group, "key '" // key // "': path longer than " // int_str(path_len) &
                          // " characters")
                return
            end if
            canonical = quoted(tok%text)
            return
        end select
        call fail(error, path, group, "key '" // key // "' expects " // expected // ", got " // describe(tok))
    end subroutine check_value

    ! ---------------------------------------------------------------------------------------------------------------
    ! Conversion: one native namelist READ per group, from its canonical text
    ! ---------------------------------------------------------------------------------------------------------------

    !> Convert every group present into `cfg`, in the order of `key_table`.
    pure subroutine convert_groups(parsed, path, cfg, error)
        !> The checked groups.
        type(parsed_input), intent(in) :: parsed
        !> File name for messages.
        character(len=*), intent(in) :: path
        !> Configuration to fill (holds the defaults on entry).
        type(input_config), intent(inout) :: cfg
        !> Allocated when a conversion fails.
        type(error_type), allocatable, intent(out) :: error
        character(len=group_len) :: groups(count_groups())
        integer :: ig

        groups = group_names()
        do ig = 1, size(groups)
            if (.not. allocated(parsed%group_text(ig)%s)) cycle
            associate (text => parsed%group_text(ig)%s)
                select case (trim(groups(ig)))
                case ("chain")
                    call read_chain(text, path, cfg, error)
                case ("drive")
                    call read_drive(text, path, cfg, error)
                case ("numerics")
                    call read_numerics(text, path, cfg, error)
                case ("record")
                    call read_record(text, path, parsed%n_values(find_key("record", "probes")), cfg, error)
                case ("scene")
                    call read_scene(text, path, parsed%n_values(find_key("scene", "values")), &
                                    parsed%n_values(find_key("scene", "potentials")), cfg, error, &
                                    [parsed%n_values(find_key("scene", "methods")), &
                                     parsed%n_values(find_key("scene", "dts")), &
                                     parsed%n_values(find_key("scene", "dt_smallest")), &
                                     parsed%n_values(find_key("scene", "amplitudes")), &
                                     parsed%n_values(find_key("scene", "c_values"))])
                case ("detect")
                    call read_detect(text, path, cfg, error)
                case ("output")
                    call read_output(text, path, cfg, error)
                case default
                    call fail(error, path, trim(groups(ig)), "internal error: no reader for this group")
                end select
            end associate
            if (allocated(error)) return
        end do
    end subroutine convert_groups

    !> Convert `&chain`.
    pure subroutine read_chain(text, path, cfg, error)
        !> Canonical text of the group.
        character(len=*), intent(in) :: text
        !> File name for messages.
        character(len=*), intent(in) :: path
        !> Configuration to update.
        type(input_config), intent(inout) :: cfg
        !> Allocated when the conversion fails or the potential is unknown.
        type(error_type), allocatable, intent(out) :: error
        character(len=name_len) :: potential
        real(wp) :: c, m2, gamma, beta, kappa, sigma
        integer :: n, n0, ios, id
        character(len=512) :: msg
        namelist /chain/ potential, c, m2, gamma, beta, n, n0, kappa, sigma

        potential = potential_name(cfg%run%chain%potential)
        c = cfg%run%chain%c
        m2 = cfg%run%chain%m2
        gamma = cfg%run%chain%gamma
        beta = cfg%run%chain%beta
        n = cfg%run%chain%n
        n0 = cfg%run%chain%n0
        kappa = cfg%run%chain%kappa
        sigma = cfg%run%chain%sigma
        msg = ""
        read (text, nml=chain, iostat=ios, iomsg=msg)
        if (ios /= 0) then
            call fail(error, path, "chain", trim(msg))
            return
        end if
        id = potential_from_name(potential)
        if (id == 0) then
            call fail(error, path, "chain", "potential = '" // trim(potential) &
                      // "': unknown potential (known: sine-gordon, klein-gordon)")
            return
        end if
        cfg%run%chain%potential = id
        cfg%run%chain%c = c
        cfg%run%chain%m2 = m2
        cfg%run%chain%gamma = gamma
        cfg%run%chain%beta = beta
        cfg%run%chain%n = n
        cfg%run%chain%n0 = n0
        cfg%run%chain%kappa = kappa
        cfg%run%chain%sigma = sigma
    end subroutine read_chain

    !> Convert `&drive`.
    pure subroutine read_drive(text, path, cfg, error)
        !> Canonical text of the group.
        character(len=*), intent(in) :: text
        !> File name for messages.
        character(len=*), intent(in) :: path
        !> Configuration to update.
        type(input_config), intent(inout) :: cfg
        !> Allocated when the conversion fails.
        type(error_type), allocatable, intent(out) :: error
        real(wp) :: amplitude, omega, ramp_time
        logical :: allow_outside_gap
        integer :: ios
        character(len=512) :: msg
        namelist /drive/ amplitude, omega, ramp_time, allow_outside_gap

        amplitude = cfg%run%drive%amplitude
        omega = cfg%run%drive%omega
        ramp_time = cfg%run%drive%ramp_time
        allow_outside_gap = cfg%allow_outside_gap
        msg = ""
        read (text, nml=drive, iostat=ios, iomsg=msg)
        if (ios /= 0) then
            call fail(error, path, "drive", trim(msg))
            return
        end if
        cfg%run%drive%amplitude = amplitude
        cfg%run%drive%omega = omega
        cfg%run%drive%ramp_time = ramp_time
        cfg%allow_outside_gap = allow_outside_gap
    end subroutine read_drive

    !> Convert `&numerics`.
    pure subroutine read_numerics(text, path, cfg, error)
        !> Canonical text of the group.
        character(len=*), intent(in) :: text
        !> File name for messages.
        character(len=*), intent(in) :: path
        !> Configuration to update.
        type(input_config), intent(inout) :: cfg
        !> Allocated when the conversion fails or the method is unknown.
        type(error_type), allocatable, intent(out) :: error
        character(len=name_len) :: method
        real(wp) :: dt, t_final, newton_tol, blowup_threshold
        integer :: newton_max_iter, ios, id
        logical :: allow_unstable
        character(len=512) :: msg
        namelist /numerics/ method, dt, t_final, newton_tol, newton_max_iter, blowup_threshold, allow_unstable

        method = method_name(cfg%run%numerics%method)
        dt = cfg%run%numerics%dt
        t_final = cfg%run%numerics%t_final
        newton_tol = cfg%run%numerics%newton_tol
        newton_max_iter = cfg%run%numerics%newton_max_iter
        blowup_threshold = cfg%run%numerics%blowup_threshold
        allow_unstable = cfg%allow_unstable
        msg = ""
        read (text, nml=numerics, iostat=ios, iomsg=msg)
        if (ios /= 0) then
            call fail(error, path, "numerics", trim(msg))
            return
        end if
        id = method_from_name(method)
        if (id == 0) then
            call fail(error, path, "numerics", "method = '" // trim(method) &
                      // "': unknown method (known: newton, linearized, rk4, rk8)")
            return
        end if
        cfg%run%numerics%method = id
        cfg%run%numerics%dt = dt
        cfg%run%numerics%t_final = t_final
        cfg%run%numerics%newton_tol = newton_tol
        cfg%run%numerics%newton_max_iter = newton_max_iter
        cfg%run%numerics%blowup_threshold = blowup_threshold
        cfg%allow_unstable = allow_unstable
    end subroutine read_numerics

    !> Convert `&record`; a `probes` list replaces the default list.
    pure subroutine read_record(text, path, n_probes, cfg, error)
        !> Canonical text of the group.
        character(len=*), intent(in) :: text
        !> File name for messages.
        character(len=*), intent(in) :: path
        !> Number of `probes` values given (0: keep the current list).
        integer, intent(in) :: n_probes
        !> Configuration to update.
        type(input_config), intent(inout) :: cfg
        !> Allocated when the conversion fails.
        type(error_type), allocatable, intent(out) :: error
        integer :: probes(max_probes), probe_every, ledger_every, ios
        character(len=512) :: msg
        namelist /record/ probes, probe_every, ledger_every

        probes = 0
        probe_every = cfg%run%record%probe_every
        ledger_every = cfg%run%record%ledger_every
        msg = ""
        read (text, nml=record, iostat=ios, iomsg=msg)
        if (ios /= 0) then
            call fail(error, path, "record", trim(msg))
            return
        end if
        if (n_probes > 0) cfg%run%record%probes = probes(1:n_probes)
        cfg%run%record%probe_every = probe_every
        cfg%run%record%ledger_every = ledger_every
    end subroutine read_record

    !> Convert `&scene`; `values` and `potentials` lists replace the defaults.
    pure subroutine read_scene(text, path, n_values, n_potentials, cfg, error, n_lists)
        !> Canonical text of the group.
        character(len=*), intent(in) :: text
        !> File name for messages.
        character(len=*), intent(in) :: path
        !> Number of `values` given.
        integer, intent(in) :: n_values
        !> Number of `potentials` given.
        integer, intent(in) :: n_potentials
        !> Configuration to update.
        type(input_config), intent(inout) :: cfg
        !> Allocated when the conversion fails or a potential is unknown.
        type(error_type), allocatable, intent(out) :: error
        !> Number of values given for `methods`, `dts`, `dt_smallest`, `amplitudes`, `c_values`.
        integer, intent(in) :: n_lists(5)
        character(len=name_len) :: kind, vary, potentials(2), methods(max_scene_methods)
        real(wp) :: amplitude_min, amplitude_max, amplitude_step, omega_min, omega_max, omega_step, coarse_step, &
                    resolution, values(max_curve_values), dts(max_scene_dts), dt_smallest(max_scene_methods), &
                    amplitudes(max_curve_values), c_values(max_curve_values), reference_dt
        integer :: ios, i, repeats
        character(len=512) :: msg
        namelist /scene/ kind, amplitude_min, amplitude_max, amplitude_step, omega_min, omega_max, omega_step, vary, &
            values, potentials, coarse_step, resolution, methods, dts, dt_smallest, amplitudes, c_values, repeats, &
            reference_dt

        kind = cfg%scene%kind
        amplitude_min = cfg%scene%amplitude_min
        amplitude_max = cfg%scene%amplitude_max
        amplitude_step = cfg%scene%amplitude_step
        omega_min = cfg%scene%omega_min
        omega_max = cfg%scene%omega_max
        omega_step = cfg%scene%omega_step
        vary = cfg%scene%vary
        coarse_step = cfg%scene%coarse_step
        resolution = cfg%scene%resolution
        values = 0.0_wp
        potentials = ""
        methods = ""
        dts = 0.0_wp
        dt_smallest = 0.0_wp
        amplitudes = 0.0_wp
        c_values = 0.0_wp
        repeats = cfg%scene%repeats
        reference_dt = cfg%scene%reference_dt
        msg = ""
        read (text, nml=scene, iostat=ios, iomsg=msg)
        if (ios /= 0) then
            call fail(error, path, "scene", trim(msg))
            return
        end if
        cfg%scene%kind = kind
        cfg%scene%amplitude_min = amplitude_min
        cfg%scene%amplitude_max = amplitude_max
        cfg%scene%amplitude_step = amplitude_step
        cfg%scene%omega_min = omega_min
        cfg%scene%omega_max = omega_max
        cfg%scene%omega_step = omega_step
        cfg%scene%vary = vary
        cfg%scene%coarse_step = coarse_step
        cfg%scene%resolution = resolution
        cfg%scene%repeats = repeats
        cfg%scene%reference_dt = reference_dt
        if (n_values > 0) cfg%scene%values = values(1:n_values)
        if (n_lists(2) > 0) cfg%scene%dts = dts(1:n_lists(2))
        if (n_lists(3) > 0) cfg%scene%dt_smallest = dt_smallest(1:n_lists(3))
        if (n_lists(4) > 0) cfg%scene%amplitudes = amplitudes(1:n_lists(4))
        if (n_lists(5) > 0) cfg%scene%c_values = c_values(1:n_lists(5))
        if (n_lists(1) > 0) then
            allocate (cfg%scene%methods(n_lists(1)))
            do i = 1, n_lists(1)
                cfg%scene%methods(i) = method_from_name(methods(i))
                if (cfg%scene%methods(i) == 0) then
                    call fail(error, path, "scene", "methods(" // int_str(i) // ") = '" // trim(methods(i)) &
                              // "': unknown method (known: newton, linearized, rk4, rk8)")
                    return
                end if
            end do
        end if
        if (n_potentials > 0) then
            allocate (cfg%scene%potentials(n_potentials))
            do i = 1, n_potentials
                cfg%scene%potentials(i) = potential_from_name(potentials(i))
                if (cfg%scene%potentials(i) == 0) then
                    call fail(error, path, "scene", "potentials(" // int_str(i) // ") = '" // trim(potentials(i)) &
                              // "': unknown potential (known: sine-gordon, klein-gordon)")
                    return
                end if
            end do
        end if
    end subroutine read_scene

    !> Convert `&detect`.
    pure subroutine read_detect(text, path, cfg, error)
        !> Canonical text of the group.
        character(len=*), intent(in) :: text
        !> File name for messages.
        character(len=*), intent(in) :: path
        !> Configuration to update.
        type(input_config), intent(inout) :: cfg
        !> Allocated when the conversion fails.
        type(error_type), allocatable, intent(out) :: error
        integer :: site, ios
        real(wp) :: amplitude
        logical :: stop_when_decided
        character(len=512) :: msg
        namelist /detect/ site, amplitude, stop_when_decided

        site = cfg%run%detect%site
        amplitude = cfg%run%detect%amplitude
        stop_when_decided = cfg%run%detect%stop_when_decided
        msg = ""
        read (text, nml=detect, iostat=ios, iomsg=msg)
        if (ios /= 0) then
            call fail(error, path, "detect", trim(msg))
            return
        end if
        cfg%run%detect%site = site
        cfg%run%detect%amplitude = amplitude
        cfg%run%detect%stop_when_decided = stop_when_decided
    end subroutine read_detect

    !> Convert `&output`.
    pure subroutine read_output(text, path, cfg, error)
        !> Canonical text of the group.
        character(len=*), intent(in) :: text
        !> File name for messages.
        character(len=*), intent(in) :: path
        !> Configuration to update.
        type(input_config), intent(inout) :: cfg
        !> Allocated when the conversion fails.
        type(error_type), allocatable, intent(out) :: error
        character(len=path_len) :: file
        logical :: overwrite, quiet
        integer :: ios
        character(len=512) :: msg
        namelist /output/ file, overwrite, quiet

        file = cfg%output%file
        overwrite = cfg%output%overwrite
        quiet = cfg%output%quiet
        msg = ""
        read (text, nml=output, iostat=ios, iomsg=msg)
        if (ios /= 0) then
            call fail(error, path, "output", trim(msg))
            return
        end if
        cfg%output%file = file
        cfg%output%overwrite = overwrite
        cfg%output%quiet = quiet
    end subroutine read_output

    ! ---------------------------------------------------------------------------------------------------------------
    ! Validation
    ! ---------------------------------------------------------------------------------------------------------------

    !> Range and consistency checks of every parameter (everything of `validate_config` but the file system).
    pure subroutine check_parameters(cfg, where, error)
        !> The configuration.
        type(input_config), intent(in) :: cfg
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Allocated on the first failed check.
        type(error_type), allocatable, intent(out) :: error
        real(wp) :: edge
        integer :: i

        associate (ch => cfg%run%chain, dr => cfg%run%drive, nu => cfg%run%numerics, rec => cfg%run%record)
            ! &chain
            if (ch%potential /= sine_gordon .and. ch%potential /= klein_gordon) then
                call fail(error, where, "chain", "potential = " // int_str(ch%potential) &
                          // ": unknown potential (known: sine-gordon, klein-gordon)")
                return
            end if
            call check_real(where, "chain", "c", ch%c, .true., error)
            if (.not. allocated(error) .and. ch%c > max_coupling) then
                call fail(error, where, "chain", "c = " // real_str(ch%c, 6) // ": at most " // real_str(max_coupling) &
                          // " (the scheme needs dt < 1/c)")
            end if
            if (allocated(error)) return
            call check_real(where, "chain", "m2", ch%m2, .false., error, any_sign=.true.)
            if (allocated(error)) return
            if (.not. (1.0_wp + ch%m2 > 0.0_wp)) then
                call fail(error, where, "chain", "m2 = " // real_str(ch%m2) &
                          // ": need 1 + m2 > 0 (the band gap 0 < Omega < sqrt(1 + m^2) must not be empty)")
                return
            end if
            call check_real(where, "chain", "gamma", ch%gamma, .false., error)
            if (allocated(error)) return
            call check_real(where, "chain", "beta", ch%beta, .false., error)
            if (allocated(error)) return
            if (ch%n < 2) then
                call fail(error, where, "chain", "n = " // int_str(ch%n) // ": need N >= 2")
                return
            end if
            if (ch%n0 < 0 .or. ch%n0 > ch%n) then
                call fail(error, where, "chain", "n0 = " // int_str(ch%n0) // ": need 0 <= N0 <= N = " // int_str(ch%n))
                return
            end if
            call check_real(where, "chain", "kappa", ch%kappa, .false., error)
            if (allocated(error)) return
            call check_real(where, "chain", "sigma", ch%sigma, .true., error)
            if (allocated(error)) return

            ! &drive
            call check_real(where, "drive", "amplitude", dr%amplitude, .false., error)
            if (allocated(error)) return
            call check_real(where, "drive", "omega", dr%omega, .true., error)
            if (allocated(error)) return
            call check_real(where, "drive", "ramp_time", dr%ramp_time, .false., error)
            if (allocated(error)) return
            edge = band_gap_edge(ch)
            if (dr%omega >= edge .and. .not. cfg%allow_outside_gap .and. (trim(cfg%scene%kind) == "timeseries" &
                .or. trim(cfg%scene%kind) == "amplitude_sweep")) then
                call fail(error, where, "drive", "omega = " // real_str(dr%omega) // " is outside the band gap 0 < Omega < " &
                          // fixed4(edge) // " (set allow_outside_gap = .true. to run anyway)")
                return
            end if

            ! &numerics
            if (method_from_name(method_name(nu%method)) == 0) then
                call fail(error, where, "numerics", "method = " // int_str(nu%method) &
                          // ": unknown method (known: newton, linearized, rk4, rk8)")
                return
            end if
            call check_real(where, "numerics", "dt", nu%dt, .true., error)
            if (allocated(error)) return
            call check_real(where, "numerics", "t_final", nu%t_final, .true., error)
            if (allocated(error)) return
            if (nu%t_final < 2.0_wp*nu%dt) then
                call fail(error, where, "numerics", "t_final = " // real_str(nu%t_final) // ": must be >= 2 dt = " &
                          // real_str(2.0_wp*nu%dt))
                return
            end if
            call check_real(where, "numerics", "newton_tol", nu%newton_tol, .true., error)
            if (allocated(error)) return
            if (nu%newton_max_iter < 1) then
                call fail(error, where, "numerics", "newton_max_iter = " // int_str(nu%newton_max_iter) &
                          // ": must be >= 1")
                return
            end if
            call check_real(where, "numerics", "blowup_threshold", nu%blowup_threshold, .true., error)
            if (allocated(error)) return
            if (.not. stable_by_paper_condition(ch, nu%dt) .and. .not. cfg%allow_unstable) then
                call fail(error, where, "numerics", "dt = " // real_str(nu%dt) &
                          // " violates the paper's necessary stability condition" &
                          // " (c^2 - m^2/4) dt^2 < 1 + (gamma/4 + beta) dt: " &
                          // real_str(stability_lhs(ch, nu%dt), 6) // " >= " // real_str(stability_rhs(ch, nu%dt), 6) &
                          // " (it needs dt < " // real_str(critical_dt(ch), 6) &
                          // "; set allow_unstable = .true. to run anyway)")
                return
            end if

            ! &record
            if (allocated(rec%probes)) then
                if (size(rec%probes) > max_probes) then
                    call fail(error, where, "record", "probes: at most " // int_str(max_probes) // " sites, got " &
                              // int_str(size(rec%probes)))
                    return
                end if
                do i = 1, size(rec%probes)
                    if (rec%probes(i) < 1 .or. rec%probes(i) > ch%n) then
                        call fail(error, where, "record", "probes(" // int_str(i) // ") = " // int_str(rec%probes(i)) &
                                  // ": must be a site 1..N = " // int_str(ch%n))
                        return
                    end if
                    if (any(rec%probes(1:i - 1) == rec%probes(i))) then
                        call fail(error, where, "record", "probes(" // int_str(i) // ") = " // int_str(rec%probes(i)) &
                                  // ": site given twice")
                        return
                    end if
                end do
            end if
            if (rec%probe_every < 1) then
                call fail(error, where, "record", "probe_every = " // int_str(rec%probe_every) // ": must be >= 1")
                return
            end if
            if (rec%ledger_every < 1) then
                call fail(error, where, "record", "ledger_every = " // int_str(rec%ledger_every) // ": must be >= 1")
                return
            end if
        end associate

        ! &scene
        if (find_name(scene_kinds, trim(cfg%scene%kind)) == 0) then
            call fail(error, where, "scene", "kind = '" // trim(cfg%scene%kind) // "': unknown scene (known: " &
                      // joined(scene_kinds, "") // ")")
            return
        end if
        call check_scene(cfg, where, error)
        if (allocated(error)) return

        ! &detect
        if (cfg%run%detect%site < 0 .or. cfg%run%detect%site >= cfg%run%chain%n) then
            call fail(error, where, "detect", "site = " // int_str(cfg%run%detect%site) &
                      // ": need 0 (automatic) <= site < N = " // int_str(cfg%run%chain%n))
            return
        end if
        call check_real(where, "detect", "amplitude", cfg%run%detect%amplitude, .true., error)
        if (allocated(error)) return

        ! &output
        if (len_trim(cfg%output%file) == 0) then
            call fail(error, where, "output", "file = '': must name the output file")
            return
        end if
    end subroutine check_parameters

    !> Checks of the scene's axes and curves: each curve (potential, varied value) must be a valid chain, stable by
    !> the paper's condition, and (for scenes at one frequency) driven inside its band gap.
    pure subroutine check_scene(cfg, where, error)
        !> The configuration.
        type(input_config), intent(in) :: cfg
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Allocated on the first failed check.
        type(error_type), allocatable, intent(out) :: error
        type(run_config) :: run
        integer :: ic
        character(len=:), allocatable :: label

        associate (sc => cfg%scene)
            if (find_name(vary_names, trim(sc%vary)) == 0) then
                call fail(error, where, "scene", "vary = '" // trim(sc%vary) // "': unknown parameter (known: " &
                          // joined(vary_names, "") // ")")
                return
            end if
            if (trim(sc%vary) /= "none" .and. .not. allocated(sc%values)) then
                call fail(error, where, "scene", "vary = '" // trim(sc%vary) // "' needs a list of values")
                return
            end if
            if (trim(sc%vary) == "none" .and. allocated(sc%values)) then
                call fail(error, where, "scene", "values are given but vary = 'none' (say which parameter they set)")
                return
            end if
            if (trim(sc%kind) == "timeseries") return
            call check_real(where, "scene", "amplitude_min", sc%amplitude_min, .false., error)
            if (allocated(error)) return
            call check_real(where, "scene", "amplitude_step", sc%amplitude_step, .true., error)
            if (allocated(error)) return
            if (.not. (sc%amplitude_max >= sc%amplitude_min)) then
                call fail(error, where, "scene", "amplitude_max = " // real_str(sc%amplitude_max) &
                          // ": must be >= amplitude_min = " // real_str(sc%amplitude_min))
                return
            end if
            call check_real(where, "scene", "omega_min", sc%omega_min, .true., error)
            if (allocated(error)) return
            call check_real(where, "scene", "omega_step", sc%omega_step, .true., error)
            if (allocated(error)) return
            if (.not. (sc%omega_max >= sc%omega_min)) then
                call fail(error, where, "scene", "omega_max = " // real_str(sc%omega_max) &
                          // ": must be >= omega_min = " // real_str(sc%omega_min))
                return
            end if
            call check_real(where, "scene", "resolution", sc%resolution, .true., error)
            if (allocated(error)) return
            if (.not. (sc%coarse_step >= sc%resolution)) then
                call fail(error, where, "scene", "coarse_step = " // real_str(sc%coarse_step) &
                          // ": must be >= resolution = " // real_str(sc%resolution))
                return
            end if
        end associate

        do ic = 1, curve_count(cfg)
            run = curve_run(cfg, ic)
            label = "curve " // int_str(ic) // " (" // potential_name(run%chain%potential) // ", " &
                    // trim(cfg%scene%vary) // ")"
            if (run%chain%gamma < 0.0_wp .or. run%chain%beta < 0.0_wp .or. .not. (1.0_wp + run%chain%m2 > 0.0_wp)) then
                call fail(error, where, "scene", label // ": need gamma >= 0, beta >= 0 and 1 + m2 > 0")
                return
            end if
            if (.not. stable_by_paper_condition(run%chain, run%numerics%dt) .and. .not. cfg%allow_unstable) then
                call fail(error, where, "scene", label // ": dt = " // real_str(run%numerics%dt) &
                          // " violates the paper's necessary stability condition (it needs dt < " &
                          // real_str(critical_dt(run%chain), 6) // "; set allow_unstable = .true. to run anyway)")
                return
            end if
            if (trim(cfg%scene%kind) == "amplitude_sweep" .and. run%drive%omega >= band_gap_edge(run%chain) &
                .and. .not. cfg%allow_outside_gap) then
                call fail(error, where, "scene", label // ": omega = " // real_str(run%drive%omega) &
                          // " is outside its band gap 0 < Omega < " // fixed4(band_gap_edge(run%chain)) &
                          // " (set allow_outside_gap = .true. to run anyway)")
                return
            end if
        end do
    end subroutine check_scene

    !> Check that a real parameter is finite and positive (or non-negative, or of any sign).
    pure subroutine check_real(where, group, key, x, strict, error, any_sign)
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Group of the key.
        character(len=*), intent(in) :: group
        !> Key.
        character(len=*), intent(in) :: key
        !> Value.
        real(wp), intent(in) :: x
        !> True: must be > 0; false: must be >= 0.
        logical, intent(in) :: strict
        !> Allocated when the check fails.
        type(error_type), allocatable, intent(out) :: error
        !> Only finiteness is required (default false).
        logical, intent(in), optional :: any_sign

        if (.not. (abs(x) <= huge(x))) then
            call fail(error, where, group, key // " = " // real_str(x) // ": must be finite")
            return
        end if
        if (present(any_sign)) then
            if (any_sign) return
        end if
        if (strict .and. .not. (x > 0.0_wp)) then
            call fail(error, where, group, key // " = " // real_str(x) // ": must be > 0")
        else if (.not. (x >= 0.0_wp)) then
            call fail(error, where, group, key // " = " // real_str(x) // ": must be >= 0")
        end if
    end subroutine check_real

    !> The output file must not exist unless `overwrite`, and its directory must exist.
    subroutine check_output_file(cfg, where, error)
        !> The configuration.
        type(input_config), intent(in) :: cfg
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Allocated when the check fails.
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: file
        logical :: exists

        file = trim(cfg%output%file)
        if (path_kind(file) == path_directory) then
            call fail(error, where, "output", "file = '" // file // "' is a directory")
            return
        end if
        inquire (file=file, exist=exists)
        if (exists .and. .not. cfg%output%overwrite) then
            call fail(error, where, "output", "file '" // file // "' exists (set overwrite = .true. to replace it)")
        end if
    end subroutine check_output_file

    ! ---------------------------------------------------------------------------------------------------------------
    ! Tables, messages and strings
    ! ---------------------------------------------------------------------------------------------------------------

    !> Number of distinct groups in `key_table`.
    pure function count_groups() result(n)
        integer :: n
        integer :: i

        n = 0
        do i = 1, size(key_table)
            if (.not. any(key_table(1:i - 1)%group == key_table(i)%group)) n = n + 1
        end do
    end function count_groups

    !> Group names of `key_table`, in order of first appearance.
    pure function group_names() result(names)
        character(len=group_len) :: names(count_groups())
        integer :: i, n

        n = 0
        do i = 1, size(key_table)
            if (.not. any(key_table(1:i - 1)%group == key_table(i)%group)) then
                n = n + 1
                names(n) = key_table(i)%group
            end if
        end do
    end function group_names

    !> Keys of one group, in table order.
    pure function group_keys(group) result(keys)
        !> Group name.
        character(len=*), intent(in) :: group
        character(len=key_len), allocatable :: keys(:)

        keys = pack(key_table%key, key_table%group == group)
    end function group_keys

    !> Index in `key_table` of a key of a group; 0 if there is none.
    pure function find_key(group, key) result(ik)
        !> Group name.
        character(len=*), intent(in) :: group
        !> Key name.
        character(len=*), intent(in) :: key
        integer :: ik

        do ik = 1, size(key_table)
            if (key_table(ik)%group == group .and. key_table(ik)%key == key) return
        end do
        ik = 0
    end function find_key

    !> Index of `name` in `list` (trailing blanks ignored); 0 if absent.
    pure function find_name(list, name) result(i)
        !> Names.
        character(len=*), intent(in) :: list(:)
        !> Name to look for.
        character(len=*), intent(in) :: name
        integer :: i

        do i = 1, size(list)
            if (list(i) == name) return
        end do
        i = 0
    end function find_name

    !> Hint for an unknown key: the group it belongs to, or a close spelling; "" if neither.
    pure function key_hint(group, key) result(hint)
        !> Group in which the key was given.
        character(len=*), intent(in) :: group
        !> The unknown key.
        character(len=*), intent(in) :: key
        character(len=:), allocatable :: hint
        integer :: i

        do i = 1, size(key_table)
            if (key_table(i)%key == key) then
                hint = "it belongs in &" // trim(key_table(i)%group) // "; "
                return
            end if
        end do
        hint = suggestion(key, group_keys(group), "'", "'")
    end function key_hint

    !> "did you mean 'x'? " for the closest name within edit distance 2 (and less than the name's length); else "".
    pure function suggestion(name, names, prefix, suffix) result(hint)
        !> The misspelt name.
        character(len=*), intent(in) :: name
        !> Candidate names.
        character(len=*), intent(in) :: names(:)
        !> Text shown before the suggested name ("&" for groups, "'" for keys).
        character(len=*), intent(in) :: prefix
        !> Text shown after the suggested name.
        character(len=*), intent(in) :: suffix
        character(len=:), allocatable :: hint
        integer :: i, d, best, best_d

        best = 0
        best_d = huge(1)
        do i = 1, size(names)
            d = edit_distance(name, trim(names(i)))
            if (d < best_d) then
                best = i
                best_d = d
            end if
        end do
        hint = ""
        if (best > 0) then
            if (best_d <= 2 .and. best_d < len(name)) hint = "did you mean " // prefix // trim(names(best)) // suffix // "? "
        end if
    end function suggestion

    !> Levenshtein distance between two strings.
    pure function edit_distance(a, b) result(d)
        !> First string.
        character(len=*), intent(in) :: a
        !> Second string.
        character(len=*), intent(in) :: b
        integer :: d
        integer :: row(0:len(b)), diag, up, i, j

        row = [(j, j = 0, len(b))]
        do i = 1, len(a)
            diag = row(0)
            row(0) = i
            do j = 1, len(b)
                up = row(j)
                if (a(i:i) == b(j:j)) then
                    row(j) = diag
                else
                    row(j) = 1 + min(diag, up, row(j - 1))
                end if
                diag = up
            end do
        end do
        d = row(len(b))
    end function edit_distance

    !> Names joined by ", ", each with a prefix.
    pure function joined(names, prefix) result(s)
        !> Names (trailing blanks ignored).
        character(len=*), intent(in) :: names(:)
        !> Prefix of each name.
        character(len=*), intent(in) :: prefix
        character(len=:), allocatable :: s
        integer :: i

        s = ""
        do i = 1, size(names)
            if (i > 1) s = s // ", "
            s = s // prefix // trim(names(i))
        end do
    end function joined

    !> A token as quoted in messages.
    pure function describe(tok) result(s)
        !> The token.
        type(token_t), intent(in) :: tok
        character(len=:), allocatable :: s

        select case (tok%kind)
        case (tk_eof)
            s = "end of file"
        case (tk_group)
            s = "'&" // tok%text // "'"
        case (tk_string)
            s = "the string " // quoted(tok%text)
        case default
            s = "'" // tok%text // "'"
        end select
    end function describe

    !> Error `<path>: &<group>: <detail>`.
    pure subroutine fail(error, path, group, detail)
        !> The error to create.
        type(error_type), allocatable, intent(out) :: error
        !> File name.
        character(len=*), intent(in) :: path
        !> Group name.
        character(len=*), intent(in) :: group
        !> What is wrong.
        character(len=*), intent(in) :: detail

        call fatal_error(error, path // ": &" // group // ": " // detail, err_input)
    end subroutine fail

    !> Error `<path>: line <line>: <detail>` (syntax errors).
    pure subroutine fail_line(error, path, line, detail)
        !> The error to create.
        type(error_type), allocatable, intent(out) :: error
        !> File name.
        character(len=*), intent(in) :: path
        !> Line number.
        integer, intent(in) :: line
        !> What is wrong.
        character(len=*), intent(in) :: detail

        call fatal_error(error, path // ": line " // int_str(line) // ": " // detail, err_input)
    end subroutine fail_line

    !> True for a letter, digit or underscore.
    elemental function is_name_char(ch) result(ok)
        !> Character.
        character, intent(in) :: ch
        logical :: ok

        ok = (ch >= "a" .and. ch <= "z") .or. (ch >= "A" .and. ch <= "Z") .or. (ch >= "0" .and. ch <= "9") &
             .or. ch == "_"
    end function is_name_char

    !> True for a Fortran name: a letter followed by letters, digits and underscores.
    pure function is_identifier(s) result(ok)
        !> Candidate.
        character(len=*), intent(in) :: s
        logical :: ok
        integer :: i

        ok = len(s) > 0
        if (.not. ok) return
        ok = (s(1:1) >= "a" .and. s(1:1) <= "z") .or. (s(1:1) >= "A" .and. s(1:1) <= "Z")
        do i = 2, len(s)
            ok = ok .and. is_name_char(s(i:i))
        end do
    end function is_identifier

    !> Number of decimal digits at the start of `s`.
    pure function count_digits(s) result(n)
        !> String.
        character(len=*), intent(in) :: s
        integer :: n

        do n = 0, len(s) - 1
            if (s(n + 1:n + 1) < "0" .or. s(n + 1:n + 1) > "9") return
        end do
        n = len(s)
    end function count_digits

    !> True for an optionally signed string of decimal digits.
    pure function is_integer(s) result(ok)
        !> Candidate.
        character(len=*), intent(in) :: s
        logical :: ok
        integer :: i

        i = 1
        if (len(s) > 0) then
            if (s(1:1) == "+" .or. s(1:1) == "-") i = 2
        end if
        ok = len(s) >= i .and. count_digits(s(i:)) == len(s) - i + 1
    end function is_integer

    !> True for a real literal: [sign] (digits [. [digits]] | . digits) [(e|d) [sign] digits].
    pure function is_real(s) result(ok)
        !> Candidate.
        character(len=*), intent(in) :: s
        logical :: ok
        integer :: i, nint, nfrac, nexp

        ok = .false.
        i = 1
        if (len(s) == 0) return
        if (s(1:1) == "+" .or. s(1:1) == "-") i = 2
        nint = count_digits(s(i:))
        i = i + nint
        nfrac = 0
        if (i <= len(s)) then
            if (s(i:i) == ".") then
                nfrac = count_digits(s(i + 1:))
                i = i + 1 + nfrac
            end if
        end if
        if (nint + nfrac == 0) return
        if (i <= len(s)) then
            if (index("eEdD", s(i:i)) == 0) return
            i = i + 1
            if (i <= len(s)) then
                if (s(i:i) == "+" .or. s(i:i) == "-") i = i + 1
            end if
            nexp = count_digits(s(i:))
            if (nexp == 0) return
            i = i + nexp
        end if
        ok = i == len(s) + 1
    end function is_real

    !> Lower-case copy of an ASCII string.
    pure function lower(s) result(t)
        !> String.
        character(len=*), intent(in) :: s
        character(len=len(s)) :: t
        integer :: i

        t = s
        do i = 1, len(s)
            if (s(i:i) >= "A" .and. s(i:i) <= "Z") t(i:i) = achar(iachar(s(i:i)) + 32)
        end do
    end function lower

    !> A string between single quotes, inner quotes doubled (namelist form).
    pure function quoted(s) result(q)
        !> String.
        character(len=*), intent(in) :: s
        character(len=:), allocatable :: q
        integer :: i

        q = "'"
        do i = 1, len(s)
            if (s(i:i) == "'") then
                q = q // "''"
            else
                q = q // s(i:i)
            end if
        end do
        q = q // "'"
    end function quoted




end module supratrans_input
