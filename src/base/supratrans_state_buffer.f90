!> A byte buffer for the state of a running task (a mid-run checkpoint): numbers are stored with their exact bits
!> (IEEE doubles and 64-bit integers copied byte for byte, so a state read back is bit-identical), texts with their
!> length. Values are appended with `put_*` and read back in the same order with `get_*`; a read past the end or of
!> a size that does not match leaves `ok` false (and the value zero), so a damaged state is found, never used.
!> The checksum of a checkpoint file is `crc32_bytes` (zlib's CRC-32, table-driven: a state of many megabytes).
!> The buffer is an argument, never module state: any number of tasks fill their own at once.
module supratrans_state_buffer
    use, intrinsic :: iso_fortran_env, only: int64
    use supratrans_kinds, only: wp
    implicit none
    private

    public :: put_int, put_real, put_reals, put_reals2, put_ints, put_text, put_logical, put_buffer
    public :: get_int, get_real, get_reals, get_reals2, get_ints, get_text, get_logical
    public :: crc32_bytes

    !> The bytes of a saved state: `bytes(1:used)` written, `bytes(pos:used)` not read yet.
    type, public :: state_buffer
        !> The bytes (grown by doubling).
        character(len=1), allocatable :: bytes(:)
        !> Bytes written.
        integer(int64) :: used = 0
        !> Next byte to read.
        integer(int64) :: pos = 1
        !> No read has gone past the end or met a size other than the one expected.
        logical :: ok = .true.
        !> Something asked to save a state it cannot save (a stepper without `save_levels`): no checkpoint.
        logical :: unsupported = .false.
    end type state_buffer

contains

    !> Make room for `extra` more bytes.
    pure subroutine reserve(buf, extra)
        type(state_buffer), intent(inout) :: buf
        integer(int64), intent(in) :: extra
        character(len=1), allocatable :: grown(:)
        integer(int64) :: need

        need = buf%used + extra
        if (.not. allocated(buf%bytes)) allocate (buf%bytes(max(need, 4096_int64)))
        if (need <= size(buf%bytes, kind=int64)) return
        allocate (grown(max(need, 2*size(buf%bytes, kind=int64))))
        grown(1:buf%used) = buf%bytes(1:buf%used)
        call move_alloc(grown, buf%bytes)
    end subroutine reserve

    !> Append raw bytes.
    pure subroutine put_raw(buf, bytes)
        type(state_buffer), intent(inout) :: buf
        character(len=1), intent(in) :: bytes(:)

        call reserve(buf, size(bytes, kind=int64))
        buf%bytes(buf%used + 1:buf%used + size(bytes, kind=int64)) = bytes
        buf%used = buf%used + size(bytes, kind=int64)
    end subroutine put_raw

    !> Whether `n` more bytes can be read (else `ok` becomes false).
    pure subroutine check_read(buf, n)
        type(state_buffer), intent(inout) :: buf
        integer(int64), intent(in) :: n

        if (.not. (buf%ok .and. n >= 0 .and. buf%pos + n - 1 <= buf%used)) buf%ok = .false.
    end subroutine check_read

    !> Append a 64-bit integer (a count, an index, a status).
    pure subroutine put_int(buf, value)
        !> The buffer.
        type(state_buffer), intent(inout) :: buf
        !> The value.
        integer(int64), intent(in) :: value

        call put_raw(buf, transfer(value, [" "], 8))
    end subroutine put_int

    !> Append a real with its exact bits.
    pure subroutine put_real(buf, value)
        !> The buffer.
        type(state_buffer), intent(inout) :: buf
        !> The value.
        real(wp), intent(in) :: value

        call put_raw(buf, transfer(value, [" "], 8))
    end subroutine put_real

    !> Append a logical (as the integer 0 or 1).
    pure subroutine put_logical(buf, value)
        !> The buffer.
        type(state_buffer), intent(inout) :: buf
        !> The value.
        logical, intent(in) :: value

        call put_int(buf, merge(1_int64, 0_int64, value))
    end subroutine put_logical

    !> Append a real array: its size, then its values with their exact bits.
    pure subroutine put_reals(buf, values)
        !> The buffer.
        type(state_buffer), intent(inout) :: buf
        !> The values.
        real(wp), intent(in) :: values(:)

        call put_int(buf, size(values, kind=int64))
        if (size(values) > 0) call put_raw(buf, transfer(values, [" "], 8*size(values)))
    end subroutine put_reals

    !> Append a rank-2 real array: its two extents, then its values (column-major) with their exact bits.
    pure subroutine put_reals2(buf, values)
        !> The buffer.
        type(state_buffer), intent(inout) :: buf
        !> The values.
        real(wp), intent(in) :: values(:, :)

        call put_int(buf, size(values, 1, kind=int64))
        call put_int(buf, size(values, 2, kind=int64))
        if (size(values) > 0) call put_raw(buf, transfer(values, [" "], 8*size(values)))
    end subroutine put_reals2

    !> Append an integer array (default kind): its size, then its values as 64-bit integers.
    pure subroutine put_ints(buf, values)
        !> The buffer.
        type(state_buffer), intent(inout) :: buf
        !> The values.
        integer, intent(in) :: values(:)
        integer :: i

        call put_int(buf, size(values, kind=int64))
        do i = 1, size(values)
            call put_int(buf, int(values(i), int64))
        end do
    end subroutine put_ints

    !> Append a text: its length, then its characters.
    pure subroutine put_text(buf, text)
        !> The buffer.
        type(state_buffer), intent(inout) :: buf
        !> The text.
        character(len=*), intent(in) :: text

        call put_int(buf, len(text, kind=int64))
        if (len(text) > 0) call put_raw(buf, transfer(text, [" "], len(text)))
    end subroutine put_text

    !> Append the bytes written to another buffer: their count, then the bytes.
    pure subroutine put_buffer(buf, other)
        !> The buffer.
        type(state_buffer), intent(inout) :: buf
        !> The buffer whose bytes are appended.
        type(state_buffer), intent(in) :: other

        call put_int(buf, other%used)
        if (other%used > 0) call put_raw(buf, other%bytes(1:other%used))
    end subroutine put_buffer

    !> Read a 64-bit integer (0 when past the end).
    pure subroutine get_int(buf, value)
        !> The buffer.
        type(state_buffer), intent(inout) :: buf
        !> The value.
        integer(int64), intent(out) :: value

        value = 0
        call check_read(buf, 8_int64)
        if (.not. buf%ok) return
        value = transfer(buf%bytes(buf%pos:buf%pos + 7), value)
        buf%pos = buf%pos + 8
    end subroutine get_int

    !> Read a real (0 when past the end).
    pure subroutine get_real(buf, value)
        !> The buffer.
        type(state_buffer), intent(inout) :: buf
        !> The value.
        real(wp), intent(out) :: value

        value = 0.0_wp
        call check_read(buf, 8_int64)
        if (.not. buf%ok) return
        value = transfer(buf%bytes(buf%pos:buf%pos + 7), value)
        buf%pos = buf%pos + 8
    end subroutine get_real

    !> Read a logical.
    pure subroutine get_logical(buf, value)
        !> The buffer.
        type(state_buffer), intent(inout) :: buf
        !> The value.
        logical, intent(out) :: value
        integer(int64) :: i

        call get_int(buf, i)
        if (i /= 0 .and. i /= 1) buf%ok = .false.
        value = i == 1
    end subroutine get_logical

    !> Read a real array of the size of `values` (a stored size that differs leaves `ok` false).
    pure subroutine get_reals(buf, values)
        !> The buffer.
        type(state_buffer), intent(inout) :: buf
        !> The values (their size is the one expected).
        real(wp), intent(out) :: values(:)
        integer(int64) :: n

        values = 0.0_wp
        call get_int(buf, n)
        if (n /= size(values, kind=int64)) buf%ok = .false.
        call check_read(buf, 8*n)
        if (.not. buf%ok) return
        if (n > 0) values = transfer(buf%bytes(buf%pos:buf%pos + 8*n - 1), values, size(values))
        buf%pos = buf%pos + 8*n
    end subroutine get_reals

    !> Read a rank-2 real array of the shape of `values`.
    pure subroutine get_reals2(buf, values)
        !> The buffer.
        type(state_buffer), intent(inout) :: buf
        !> The values (their shape is the one expected).
        real(wp), intent(out) :: values(:, :)
        integer(int64) :: n1, n2

        values = 0.0_wp
        call get_int(buf, n1)
        call get_int(buf, n2)
        if (n1 /= size(values, 1, kind=int64) .or. n2 /= size(values, 2, kind=int64)) buf%ok = .false.
        call check_read(buf, 8*n1*n2)
        if (.not. buf%ok) return
        if (n1*n2 > 0) values = reshape(transfer(buf%bytes(buf%pos:buf%pos + 8*n1*n2 - 1), 0.0_wp, &
                                                 int(n1*n2)), shape(values))
        buf%pos = buf%pos + 8*n1*n2
    end subroutine get_reals2

    !> Read an integer array of the size of `values`.
    pure subroutine get_ints(buf, values)
        !> The buffer.
        type(state_buffer), intent(inout) :: buf
        !> The values (their size is the one expected).
        integer, intent(out) :: values(:)
        integer(int64) :: n, v
        integer :: i

        values = 0
        call get_int(buf, n)
        if (n /= size(values, kind=int64)) buf%ok = .false.
        if (.not. buf%ok) return
        do i = 1, size(values)
            call get_int(buf, v)
            if (v < -huge(0) .or. v > huge(0)) buf%ok = .false.
            if (buf%ok) values(i) = int(v)
        end do
    end subroutine get_ints

    !> Read a text.
    pure subroutine get_text(buf, text)
        !> The buffer.
        type(state_buffer), intent(inout) :: buf
        !> The text ("" when past the end).
        character(len=:), allocatable, intent(out) :: text
        integer(int64) :: n
        integer(int64) :: i

        text = ""
        call get_int(buf, n)
        if (n > huge(0)) buf%ok = .false.
        call check_read(buf, n)
        if (.not. buf%ok) return
        deallocate (text)
        allocate (character(len=n) :: text)
        do i = 1, n
            text(i:i) = buf%bytes(buf%pos + i - 1)
        end do
        buf%pos = buf%pos + n
    end subroutine get_text

    !> CRC-32 (zlib's: polynomial 0xEDB88320 reflected, initial and final XOR 0xFFFFFFFF) of bytes, table-driven.
    pure function crc32_bytes(bytes) result(crc)
        !> The bytes.
        character(len=1), intent(in) :: bytes(:)
        integer(int64) :: crc
        integer(int64), parameter :: poly = int(z'EDB88320', int64), mask = int(z'FFFFFFFF', int64)
        integer(int64) :: table(0:255), c
        integer(int64) :: i
        integer :: j, bit

        do j = 0, 255
            c = int(j, int64)
            do bit = 1, 8
                if (iand(c, 1_int64) /= 0) then
                    c = ieor(shiftr(c, 1), poly)
                else
                    c = shiftr(c, 1)
                end if
            end do
            table(j) = c
        end do
        crc = mask
        do i = 1, size(bytes, kind=int64)
            crc = ieor(table(iand(ieor(crc, int(ichar(bytes(i)), int64)), 255_int64)), shiftr(crc, 8))
        end do
        crc = ieor(crc, mask)
    end function crc32_bytes

end module supratrans_state_buffer
