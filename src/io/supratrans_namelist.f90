!> The namelist syntax: a small tokenizer and parser that checks a namelist file against the key table of the
!> schema (`key_table` of `supratrans_schema`) and gives the values of each key as text.
!>
!> Syntax: `&group ... /` (or `&end`), `key = value`, `key = v1, v2, ...` (lists), separators are commas, blanks and
!> newlines, strings in '...' or "..." (the quote doubled inside), `!` comments, logicals `.true.`, `.false.`,
!> `T`, `F`, integers, reals with `e` or `d` exponents. Names and paths may also be given unquoted when they hold no
!> blank, comma, slash or quote. Rejected with a clear message: repeat counts (`3*0.0`), null values
!> (`a = 1, , 3`), subscripts (`probes(2) = 5`), a group or key given twice, and any text outside the groups other
!> than `!` comments. Group names, key names and the values of name keys are case-insensitive (kept lower case).
!>
!> Error messages (status `err_input`), one line each:
!>
!> * `<file>: line <l>: <syntax problem>`, `<file>: line <l>: &<group>: <syntax problem>`;
!> * `<file>: unknown group &<group> (known: &chain, ...)`, `<file>: group &<group> is given twice`;
!> * `<file>: &<group>: unknown key '<key>' (known: ...)`, `... key '<key>' expects an integer, got '<value>'`.
module supratrans_namelist
    use supratrans_kinds, only: name_len, path_len
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_strings, only: int_str, find_name
    use supratrans_keys, only: key_spec, kt_integer, kt_real, kt_logical, kt_name, kt_path, group_len, key_len, &
        input_error, joined
    use supratrans_schema, only: key_table
    implicit none
    private

    public :: parse_namelist

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
    type, public :: string_t
        !> The characters.
        character(len=:), allocatable :: s
    end type string_t

    !> The values given for one key, as text.
    type, public :: string_list
        !> One string per value: integers and reals as written, logicals `.true.`/`.false.`, names in lower case,
        !> paths as written.
        type(string_t), allocatable :: items(:)
    end type string_list

    !> The checked contents of a namelist file, before conversion.
    type, public :: parsed_input
        !> Number of values given for each entry of `key_table` (0 when the key is absent).
        integer, allocatable :: n_values(:)
        !> The values given for each entry of `key_table` (no items when absent).
        type(string_list), allocatable :: values(:)
    end type parsed_input

contains

    ! ---------------------------------------------------------------------------------------------------------------
    ! Tokenizer
    ! ---------------------------------------------------------------------------------------------------------------

    !> Split namelist text into tokens: `&name`, `/`, `=`, `,`, quoted strings and unquoted words; the last is `tk_eof`.
    pure subroutine tokenize(text, path, tokens, error)
        character(len=*), intent(in) :: text, path
        type(token_t), allocatable, intent(out) :: tokens(:)
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
                i = merge(n + 1, i + j - 1, j == 0)
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
                do while (j <= n)       ! to the closing quote (a doubled quote stands for one) or the line's end
                    if (text(j:j) == achar(10)) exit
                    if (text(j:j) == ch) then
                        if (text(j:min(j + 1, n)) /= ch // ch) exit
                        j = j + 1
                    end if
                    s = s // text(j:j)
                    j = j + 1
                end do
                if (text(min(j, n):min(j, n)) /= ch .or. j > n) then
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
        type(token_t), allocatable, intent(inout) :: tokens(:)
        integer, intent(inout) :: ntok
        integer, intent(in) :: kind, line
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

    !> Tokenize and check namelist text against `key_table`; gives the values of every key present, as text.
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
        character(len=group_len), allocatable :: groups(:)
        logical, allocatable :: seen(:)
        integer :: it, ig

        call tokenize(text, path, tokens, error)
        if (allocated(error)) return
        groups = group_names()
        allocate (seen(size(groups)), source=.false.)
        allocate (parsed%n_values(size(key_table)), source=0)
        allocate (parsed%values(size(key_table)))
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
                    if (seen(ig)) then
                        call fatal_error(error, path // ": group &" // trim(groups(ig)) // " is given twice", err_input)
                        return
                    end if
                case default
                    call fail_line(error, path, tok%line, "expected a group such as &chain, got " // describe(tok) &
                                   // " (outside &group ... / only ! comments are allowed)")
                    return
                end select
            end associate
            seen(ig) = .true.
            call parse_group(tokens, it, path, trim(groups(ig)), parsed, error)
            if (allocated(error)) return
        end do
    end subroutine parse_namelist

    !> Check one group, from its `&name` token to its `/`; `it` ends on the token after the `/`.
    pure subroutine parse_group(tokens, it, path, group, parsed, error)
        type(token_t), intent(in) :: tokens(:)
        integer, intent(inout) :: it
        character(len=*), intent(in) :: path, group
        type(parsed_input), intent(inout) :: parsed
        type(error_type), allocatable, intent(out) :: error

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
                    call parse_assignment(tokens, it, path, group, parsed, error)
                    if (allocated(error)) return
                case default
                    call fail_line(error, path, tok%line, "&" // group // ": expected a key, got " // describe(tok))
                    return
                end select
            end associate
        end do
    end subroutine parse_group

    !> Check one `key = value[, value...]`; `it` ends on the token after the last value.
    pure subroutine parse_assignment(tokens, it, path, group, parsed, error)
        type(token_t), intent(in) :: tokens(:)
        integer, intent(inout) :: it
        character(len=*), intent(in) :: path, group
        type(parsed_input), intent(inout) :: parsed
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: key, canonical
        type(string_t), allocatable :: values(:)
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
            call input_error(error, path, group, "unknown key '" // key // "' (" // key_hint(group, key) // "known: " &
                      // joined(group_keys(group), "") // ")")
            return
        end if
        if (parsed%n_values(ik) > 0) then
            call input_error(error, path, group, "key '" // key // "' is given twice")
            return
        end if
        it = it + 2
        nval = 0
        previous = tk_equals
        allocate (values(0))
        do
            associate (tok => tokens(it))
                select case (tok%kind)
                case (tk_word, tk_string)
                    if (tok%kind == tk_word .and. tokens(it + 1)%kind == tk_equals) exit
                    call check_value(key_table(ik), tok, path, canonical, error)
                    if (allocated(error)) return
                    nval = nval + 1
                    values = [values, string_t(canonical)]
                    previous = tk_word
                    it = it + 1
                case (tk_comma)
                    if (previous /= tk_word) then
                        call input_error(error, path, group, "key '" // key // "': empty value before ',' on line " &
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
            call input_error(error, path, group, "key '" // key // "' has no value")
            return
        end if
        if (nval > key_table(ik)%max_values) then
            if (key_table(ik)%max_values == 1) then
                call input_error(error, path, group, "key '" // key // "' expects one value, got " // int_str(nval))
            else
                call input_error(error, path, group, "key '" // key // "' takes at most " &
                          // int_str(key_table(ik)%max_values) // " values, got " // int_str(nval))
            end if
            return
        end if
        parsed%n_values(ik) = nval
        call move_alloc(values, parsed%values(ik)%items)
    end subroutine parse_assignment

    !> Check one value against the type of its key and give it in canonical form: numbers as written, logicals
    !> `.true.`/`.false.`, names in lower case, paths as written.
    pure subroutine check_value(spec, tok, path, canonical, error)
        type(key_spec), intent(in) :: spec
        type(token_t), intent(in) :: tok
        character(len=*), intent(in) :: path
        character(len=:), allocatable, intent(out) :: canonical
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: group, key, expected
        integer :: ival, ios

        group = trim(spec%group)
        key = trim(spec%key)
        if (tok%kind == tk_word .and. index(tok%text, "*") > 0 .and. spec%value_type /= kt_path) then
            call input_error(error, path, group, "key '" // key // "': repeat counts like '" // tok%text &
                      // "' are not supported (write the values out)")
            return
        end if
        select case (spec%value_type)
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
                call input_error(error, path, group, "key '" // key // "': name longer than " // int_str(name_len) &
                          // " characters")
                return
            end if
            canonical = lower(tok%text)
            return
        case default
            if (len(tok%text) > path_len) then
                call input_error(error, path, group, "key '" // key // "': path longer than " // int_str(path_len) &
                          // " characters")
                return
            end if
            canonical = tok%text
            return
        end select
        call input_error(error, path, group, "key '" // key // "' expects " // expected // ", got " // describe(tok))
    end subroutine check_value

    ! ---------------------------------------------------------------------------------------------------------------
    ! Tables, messages and strings
    ! ---------------------------------------------------------------------------------------------------------------

    !> Group names of `key_table`, in order of first appearance.
    pure function group_names() result(names)
        character(len=group_len), allocatable :: names(:)
        integer :: i

        allocate (names(0))
        do i = 1, size(key_table)
            if (.not. any(names == key_table(i)%group)) names = [character(len=group_len) :: names, key_table(i)%group]
        end do
    end function group_names

    !> Keys of one group, in table order.
    pure function group_keys(group) result(keys)
        character(len=*), intent(in) :: group
        character(len=key_len), allocatable :: keys(:)

        keys = pack(key_table%key, key_table%group == group)
    end function group_keys

    !> Index in `key_table` of a key of a group; 0 if there is none.
    pure function find_key(group, key) result(ik)
        character(len=*), intent(in) :: group, key
        integer :: ik

        do ik = 1, size(key_table)
            if (key_table(ik)%group == group .and. key_table(ik)%key == key) return
        end do
        ik = 0
    end function find_key

    !> Hint for an unknown key: the group it belongs to, or a close spelling; "" if neither.
    pure function key_hint(group, key) result(hint)
        character(len=*), intent(in) :: group, key
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
        character(len=*), intent(in) :: name, names(:), prefix, suffix
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
        character(len=*), intent(in) :: a, b
        integer :: d, row(0:len(b)), diag, up, i, j

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

    !> A token as quoted in messages.
    pure function describe(tok) result(s)
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

    !> Error `<path>: line <line>: <detail>` (syntax errors).
    pure subroutine fail_line(error, path, line, detail)
        type(error_type), allocatable, intent(out) :: error
        character(len=*), intent(in) :: path
        integer, intent(in) :: line
        character(len=*), intent(in) :: detail

        call fatal_error(error, path // ": line " // int_str(line) // ": " // detail, err_input)
    end subroutine fail_line

    !> True for a letter, digit or underscore.
    elemental function is_name_char(ch) result(ok)
        character, intent(in) :: ch
        logical :: ok

        ok = (ch >= "a" .and. ch <= "z") .or. (ch >= "A" .and. ch <= "Z") .or. (ch >= "0" .and. ch <= "9") &
             .or. ch == "_"
    end function is_name_char

    !> True for a Fortran name: a letter followed by letters, digits and underscores.
    pure function is_identifier(s) result(ok)
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
        character(len=*), intent(in) :: s
        integer :: n

        do n = 0, len(s) - 1
            if (s(n + 1:n + 1) < "0" .or. s(n + 1:n + 1) > "9") return
        end do
        n = len(s)
    end function count_digits

    !> True for an optionally signed string of decimal digits.
    pure function is_integer(s) result(ok)
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

end module supratrans_namelist
