!> The lexical level of the namelist syntax (`supratrans_namelist` is the parser): the tokens of a namelist text
!> (`&group`, `/`, `=`, `,`, quoted strings, unquoted words, with their lines), how messages quote them, and the
!> tests of literals (names, integers, reals) the parser applies to the words.
module supratrans_namelist_tokens
    use supratrans_error, only: error_type, fatal_error, err_input
    use supratrans_strings, only: int_str, lower
    implicit none
    private

    public :: tokenize, describe, fail_line, is_identifier, is_integer, is_real

    !> Token kinds of the namelist tokenizer.
    integer, parameter, public :: tk_eof = 0, tk_group = 1, tk_slash = 2, tk_equals = 3, tk_comma = 4, &
                          tk_string = 5, tk_word = 6

    !> The characters of a name: digits (the first ten), letters, underscore.
    character(len=*), parameter :: name_chars = "0123456789abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ_"
    !> Characters that end an unquoted word.
    character(len=*), parameter :: word_stops = " " // achar(9) // achar(10) // achar(13) // "!&/=,'" // '"'

    !> One token of a namelist file.
    type, public :: token_t
        !> Token kind (`tk_*`).
        integer :: kind = tk_eof
        !> Line on which the token starts.
        integer :: line = 0
        !> Group name (lower case) for `tk_group`, contents for `tk_string`, the characters for `tk_word`.
        character(len=:), allocatable :: text
    end type token_t

contains

    !> Split namelist text into tokens: `&name`, `/`, `=`, `,`, quoted strings and unquoted words; the last is `tk_eof`.
    pure subroutine tokenize(text, path, tokens, error)
        !> The file contents, and the file name for messages.
        character(len=*), intent(in) :: text, path
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
                i = merge(n + 1, i + j - 1, j == 0)
            case ("&")
                j = verify(text(i + 1:), name_chars)       ! the end of the name
                j = merge(n + 1, i + j, j == 0)
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
                j = scan(text(i:), word_stops)             ! the end of the word
                j = merge(n + 1, i + j - 1, j == 0)
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

    !> True for a Fortran name: a letter followed by letters, digits and underscores.
    pure function is_identifier(s) result(ok)
        character(len=*), intent(in) :: s
        logical :: ok

        ok = .false.
        if (len(s) > 0) ok = verify(s(1:1), name_chars(11:62)) == 0 .and. verify(s, name_chars) == 0
    end function is_identifier

    !> True for an optionally signed string of decimal digits.
    pure logical function is_integer(s)
        character(len=*), intent(in) :: s

        is_integer = len(s) > signed(s) .and. verify(s(signed(s) + 1:), name_chars(1:10)) == 0
    end function is_integer

    !> True for a real literal: [sign] (digits [. [digits]] | . digits) [(e|d) [sign] digits].
    pure logical function is_real(s)
        character(len=*), intent(in) :: s
        integer :: first, e, k

        first = signed(s) + 1
        e = scan(s, "eEdD")
        if (e == 0) e = len(s) + 1
        is_real = verify(s(first:e - 1), name_chars(1:10) // ".") == 0 .and. scan(s(first:e - 1), name_chars(1:10)) > 0 &
                  .and. count([(s(k:k) == ".", k = first, e - 1)]) <= 1
        if (e <= len(s)) is_real = is_real .and. is_integer(s(e + 1:))
    end function is_real

    !> 1 when `s` starts with a sign, else 0.
    pure integer function signed(s)
        character(len=*), intent(in) :: s

        signed = 0
        if (len(s) > 0) signed = merge(1, 0, s(1:1) == "+" .or. s(1:1) == "-")
    end function signed

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

end module supratrans_namelist_tokens
