!> The namelist syntax: a small parser (over the tokens of `supratrans_namelist_tokens`) that checks a namelist file
!> against the key table of the schema (`key_table` of `supratrans_schema`) and gives the values of each key, converted.
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
!> * `<file>: &<group>: unknown key '<key>' (known: ...)`, `... key '<key>' expects an integer, got '<value>'`,
!>   `<file>: &<group>: <key> = '<name>': unknown <potential|method> (known: ...)`.
module supratrans_namelist
    use supratrans_kinds, only: wp, name_len, path_len
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_strings, only: int_str, find_name, joined, lower
    use supratrans_keys, only: key_spec, key_value, kt_integer, kt_real, kt_logical, kt_name, kt_path, group_len, &
        key_len, input_error
    use supratrans_schema, only: key_table, choice_names, choice_noun
    use supratrans_namelist_tokens, only: token_t, tokenize, tk_eof, tk_group, tk_slash, tk_equals, tk_comma, &
        tk_string, tk_word, describe, fail_line, is_identifier, is_integer, is_real
    implicit none
    private

    public :: parse_namelist

    !> The checked contents of a namelist file.
    type, public :: parsed_input
        !> Number of values given for each entry of `key_table` (0 when the key is absent).
        integer, allocatable :: n_values(:)
        !> The values given for each entry of `key_table` (`n = 0` when absent): numbers converted, logicals, names
        !> in lower case (named choices as their numbers), paths as written.
        type(key_value), allocatable :: values(:)
        !> Number of groups in the file (0 for an empty or comments-only file).
        integer :: n_groups = 0
    end type parsed_input

contains

    ! Parser: groups, keys, value counts and value types against key_table

    !> Tokenize and check namelist text against `key_table`; gives the values of every key present, converted.
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
            parsed%n_groups = parsed%n_groups + 1
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
        character(len=:), allocatable :: key
        type(key_value) :: values
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
        ik = findloc(key_table%group == group .and. key_table%key == key, .true., 1)
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
        allocate (values%ints(0), values%reals(0), values%texts(0))
        do
            associate (tok => tokens(it))
                select case (tok%kind)
                case (tk_word, tk_string)
                    if (tok%kind == tk_word .and. tokens(it + 1)%kind == tk_equals) exit
                    nval = nval + 1
                    call check_value(key_table(ik), tok, path, nval, values, error)
                    if (allocated(error)) return
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
        values%n = nval
        parsed%values(ik) = values
    end subroutine parse_assignment

    !> Check value number `i` of a key against the key's type and append it to `v`: integers and reals converted,
    !> logicals, names in lower case (named choices as their numbers, looked up), paths as written.
    pure subroutine check_value(spec, tok, path, i, v, error)
        type(key_spec), intent(in) :: spec
        type(token_t), intent(in) :: tok
        character(len=*), intent(in) :: path
        integer, intent(in) :: i
        type(key_value), intent(inout) :: v
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: group, key, expected, name, label
        integer :: ival, ios
        real(wp) :: x

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
                    v%ints = [v%ints, ival]
                    return
                end if
                expected = "an integer in range"
            end if
        case (kt_real)
            expected = "a real number"
            if (tok%kind == tk_word .and. is_real(tok%text)) then
                read (tok%text, *, iostat=ios) x
                if (ios /= 0) call input_error(error, path, group, "key '" // key // "': cannot convert its value")
                v%reals = [v%reals, x]
                return
            end if
        case (kt_logical)
            expected = "a logical (.true. or .false.)"
            if (tok%kind == tk_word) then
                select case (lower(tok%text))
                case (".true.", ".t.", "t", "true")
                    v%flag = .true.
                    return
                case (".false.", ".f.", "f", "false")
                    v%flag = .false.
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
            name = lower(tok%text)
            if (.not. spec%ids) then
                v%texts = [character(len=path_len) :: v%texts, name]
                return
            end if
            ! a named choice, held as its number
            ival = find_name(choice_names(spec%choices), name)
            v%ints = [v%ints, ival]
            if (ival > 0) return
            label = key
            if (spec%max_values > 1) label = label // "(" // int_str(i) // ")"
            call input_error(error, path, group, label // " = '" // name // "': unknown " // choice_noun(spec%choices) &
                             // " (known: " // joined(choice_names(spec%choices), "") // ")")
            return
        case default
            if (len(tok%text) > path_len) then
                call input_error(error, path, group, "key '" // key // "': path longer than " // int_str(path_len) &
                          // " characters")
                return
            end if
            v%texts = [character(len=path_len) :: v%texts, tok%text]
            return
        end select
        call input_error(error, path, group, "key '" // key // "' expects " // expected // ", got " // describe(tok))
    end subroutine check_value

    ! Tables and messages

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

    !> Hint for an unknown key: the group it belongs to, or a close spelling; "" if neither.
    pure function key_hint(group, key) result(hint)
        character(len=*), intent(in) :: group, key
        character(len=:), allocatable :: hint
        integer :: i

        i = findloc(key_table%key == key, .true., 1)
        if (i > 0) then
            hint = "it belongs in &" // trim(key_table(i)%group) // "; "
        else
            hint = suggestion(key, group_keys(group), "'", "'")
        end if
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

end module supratrans_namelist
