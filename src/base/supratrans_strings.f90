!> Text for messages and progress lines: numbers in their shortest exact decimal forms, names joined, looked up and
!> lower-cased, texts made printable.
!>
!> gfortran 12 keeps the length of a deferred-length function result in a static variable of the caller, so two
!> OpenMP threads calling `int_str` / `real_str` at once can corrupt each other's strings. Code that runs inside
!> threads (the observers of a run) uses the fixed-length forms `int_fixed` / `real_fixed` with `trim`.
module supratrans_strings
    use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
    use supratrans_kinds, only: wp, i8
    implicit none
    private

    public :: int_str, real_str, fixed4, fixed1, int_fixed, real_fixed, text_fingerprint, text_or, printable, find_name
    public :: joined, lower

contains

    !> Integer in decimal, no blanks.
    pure function int_str(i) result(s)
        !> Integer.
        integer, intent(in) :: i
        character(len=:), allocatable :: s
        character(len=24) :: buf

        write (buf, "(i0)") i
        s = trim(buf)
    end function int_str


    !> Real with 4 decimals and a leading zero, e.g. "1.0000" (band-gap edges).
    pure function fixed4(x) result(s)
        !> Value.
        real(wp), intent(in) :: x
        character(len=:), allocatable :: s
        character(len=64) :: buf

        write (buf, "(f0.4)") x
        s = trim(adjustl(buf))
        if (s(1:1) == ".") then
            s = "0" // s
        else if (s(1:min(2, len(s))) == "-.") then
            s = "-0" // s(2:)
        end if
    end function fixed4


    !> Shortest decimal form of a real that reads back to the same value, or rounded to at most `digits`
    !> significant digits (deferred length: for code outside OpenMP threads; see `real_fixed`).
    pure function real_str(x, digits) result(s)
        !> Value.
        real(wp), intent(in) :: x
        !> Largest number of significant digits (default: as many as needed, at most 17).
        integer, intent(in), optional :: digits
        character(len=:), allocatable :: s

        s = trim(real_fixed(x, digits))
    end function real_str

    !> Shortest decimal form of a real that reads back to the same value ("0.3", "1.0", "200.0", "1.0e-10"),
    !> or rounded to at most `digits` significant digits, in a fixed-length result (thread-safe; `trim` it).
    pure function real_fixed(x, digits) result(res)
        !> Value.
        real(wp), intent(in) :: x
        !> Largest number of significant digits (default: as many as needed, at most 17).
        integer, intent(in), optional :: digits
        character(len=48) :: res
        character(len=:), allocatable :: s
        character(len=64) :: buf
        character(len=:), allocatable :: mant, sig
        real(wp) :: y
        integer :: d, dmax, e, k, ios

        if (ieee_is_nan(x)) then
            res = "NaN"
            return
        else if (abs(x) > huge(x)) then
            s = merge("Infinity ", "-Infinity", x > 0.0_wp)
            res = trim(s)
            return
        else if (.not. (abs(x) > 0.0_wp)) then
            res = "0.0"
            return
        end if
        dmax = 17
        if (present(digits)) dmax = max(1, min(digits, 17))
        do d = 1, dmax
            write (buf, "(es40." // trim(int_fixed(d - 1)) // "e3)") x
            read (buf, *, iostat=ios) y
            if (ios == 0 .and. .not. (abs(y - x) > 0.0_wp)) exit
        end do
        buf = adjustl(buf)
        k = index(buf, "E")
        mant = buf(1:k - 1)
        read (buf(k + 1:), *) e
        s = ""
        if (mant(1:1) == "-") then
            s = "-"
            mant = mant(2:)
        end if
        sig = mant(1:1) // mant(3:)
        do while (len(sig) > 1)
            if (sig(len(sig):len(sig)) /= "0") exit
            sig = sig(1:len(sig) - 1)
        end do
        if (e >= -4 .and. e < 6) then
            if (e >= 0) then
                if (len(sig) < e + 2) sig = sig // repeat("0", e + 2 - len(sig))
                s = s // sig(1:e + 1) // "." // sig(e + 2:)
            else
                s = s // "0." // repeat("0", -e - 1) // sig
            end if
        else
            if (len(sig) == 1) sig = sig // "0"
            s = s // sig(1:1) // "." // sig(2:) // "e" // trim(int_fixed(e))
        end if
        res = s
    end function real_fixed

    !> Integer in decimal, left-adjusted in a fixed-length result (thread-safe; `trim` it).
    pure function int_fixed(i) result(s)
        !> Integer.
        integer, intent(in) :: i
        character(len=24) :: s

        write (s, "(i0)") i
    end function int_fixed



    !> A real with one decimal (progress lines: seconds).
    pure function fixed1(x) result(s)
        !> Value.
        real(wp), intent(in) :: x
        character(len=:), allocatable :: s
        character(len=32) :: buf

        write (buf, "(f0.1)") x
        s = trim(adjustl(buf))
        if (s(1:1) == ".") s = "0" // s
        if (s(1:2) == "-.") s = "-0" // s(2:)
    end function fixed1

    !> A fingerprint of a text (two polynomial hashes modulo the prime 2^31 - 1, in hexadecimal), to tie a journal
    !> or a part file to its input. Integer arithmetic never overflows: every intermediate is below 2^38.
    pure function text_fingerprint(bytes) result(hash_text)
        !> The text.
        character(len=*), intent(in) :: bytes
        character(len=:), allocatable :: hash_text
        integer(i8), parameter :: modulus = 2147483647_i8
        integer(i8) :: h1, h2
        integer :: i
        character(len=17) :: buf

        h1 = 1_i8
        h2 = 7_i8
        do i = 1, len(bytes)
            h1 = mod(h1*31_i8 + int(ichar(bytes(i:i)), i8), modulus)
            h2 = mod(h2*131_i8 + int(ichar(bytes(i:i)), i8), modulus)
        end do
        write (buf, '(z8.8, "-", z8.8)') h1, h2
        hash_text = buf
    end function text_fingerprint

    !> An allocatable text, or `default` when it is unallocated or empty.
    pure function text_or(text, default) result(value)
        !> The text.
        character(len=:), allocatable, intent(in) :: text
        !> What to give instead.
        character(len=*), intent(in) :: default
        character(len=:), allocatable :: value

        value = default
        if (allocated(text)) then
            if (len(text) > 0) value = text
        end if
    end function text_or

    !> A text with every character outside printable ASCII (control characters such as ESC, NUL, and bytes above
    !> 126) shown as '?': what every line the program prints goes through, so that a name read from a namelist or
    !> the command line cannot drive the terminal.
    pure function printable(text) result(shown)
        !> The text.
        character(len=*), intent(in) :: text
        character(len=len(text)) :: shown
        integer :: i

        shown = text
        do i = 1, len(text)
            if (iachar(text(i:i)) < 32 .or. iachar(text(i:i)) > 126) shown(i:i) = "?"
        end do
    end function printable

    !> Index of `name` in `list` (trailing blanks ignored): the number of a named choice, of a group; 0 if absent.
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

    !> Names joined by ", ", each with a prefix ("&chain, &drive").
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

    !> Lower-case copy of an ASCII string.
    pure function lower(s) result(t)
        !> The string.
        character(len=*), intent(in) :: s
        character(len=len(s)) :: t
        integer :: i

        t = s
        do i = 1, len(s)
            if (s(i:i) >= "A" .and. s(i:i) <= "Z") t(i:i) = achar(iachar(s(i:i)) + 32)
        end do
    end function lower

end module supratrans_strings
