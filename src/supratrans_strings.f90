!> Text formatting of numbers for messages and progress lines (shortest exact decimal forms).
module supratrans_strings
    use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
    use supratrans_kinds, only: wp
    implicit none
    private

    public :: int_str, real_str, fixed4, fixed1

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


    !> Shortest decimal form of a real that reads back to the same value ("0.3", "1.0", "200.0", "1.0e-10"),
    !> or rounded to at most `digits` significant digits.
    pure function real_str(x, digits) result(s)
        !> Value.
        real(wp), intent(in) :: x
        !> Largest number of significant digits (default: as many as needed, at most 17).
        integer, intent(in), optional :: digits
        character(len=:), allocatable :: s
        character(len=64) :: buf
        character(len=:), allocatable :: mant, sig
        real(wp) :: y
        integer :: d, dmax, e, k, ios

        if (ieee_is_nan(x)) then
            s = "NaN"
            return
        else if (abs(x) > huge(x)) then
            s = merge("Infinity ", "-Infinity", x > 0.0_wp)
            s = trim(s)
            return
        else if (.not. (abs(x) > 0.0_wp)) then
            s = "0.0"
            return
        end if
        dmax = 17
        if (present(digits)) dmax = max(1, min(digits, 17))
        do d = 1, dmax
            write (buf, "(es40." // int_str(d - 1) // "e3)") x
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
            s = s // sig(1:1) // "." // sig(2:) // "e" // int_str(e)
        end if
    end function real_str


    !> A real with one decimal (progress lines: seconds).
    pure function fixed1(x) result(s)
        !> Value.
        real(wp), intent(in) :: x
        character(len=:), allocatable :: s
        character(len=32) :: buf

        write (buf, '(f0.1)') x
        s = trim(adjustl(buf))
        if (s(1:1) == ".") s = "0" // s
        if (s(1:2) == "-.") s = "-0" // s(2:)
    end function fixed1

end module supratrans_strings
