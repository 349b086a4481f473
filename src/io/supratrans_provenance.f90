!> How an output file was made: the `/provenance` group every output file carries.
!>
!> Code version; the git commit of the checkout the program was built in (found from the executable's own path,
!> /proc/self/exe, by walking up to a `.git` directory and reading HEAD and the ref it names, loose or packed: no
!> shell, no git needed; "unknown" when the program does not sit in a checkout); the compiler and its options
!> (`compiler_version()`, `compiler_options()`); the OpenMP threads; the host; the start of the run; the input
!> file's path and the namelist text exactly as read.
module supratrans_provenance
    use, intrinsic :: iso_fortran_env, only: compiler_version, compiler_options
    use supratrans_kinds, only: supratrans_version
    use supratrans_strings, only: text_or
    use supratrans_error, only: error_type
    use supratrans_config, only: input_config
    use supratrans_system, only: host_name, is_directory
    use supratrans_hdf5, only: h5_file, h5_write_attr, h5_create_group, h5_write
    !$ use omp_lib, only: omp_get_max_threads
    implicit none
    private

    public :: write_provenance, git_commit

contains

    !> Write `/provenance` into an open output file.
    subroutine write_provenance(file, cfg, started, error)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The input.
        type(input_config), intent(in) :: cfg
        !> When the run started (ISO 8601).
        character(len=*), intent(in) :: started
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        integer :: threads

        threads = 1
        !$ threads = omp_get_max_threads()
        call h5_create_group(file, "/provenance", "How this file was made: code, build, machine, input", error)
        if (.not. allocated(error)) call h5_write_attr(file, "/provenance", "code_version", supratrans_version, error)
        if (.not. allocated(error)) call h5_write_attr(file, "/provenance", "git_commit", git_commit(), error)
        if (.not. allocated(error)) call h5_write_attr(file, "/provenance", "compiler_version", compiler_version(), error)
        if (.not. allocated(error)) call h5_write_attr(file, "/provenance", "compiler_options", compiler_options(), error)
        if (.not. allocated(error)) call h5_write_attr(file, "/provenance", "openmp_threads", threads, error)
        if (.not. allocated(error)) call h5_write_attr(file, "/provenance", "host", host_name(), error)
        if (.not. allocated(error)) call h5_write_attr(file, "/provenance", "started", started, error)
        if (.not. allocated(error)) call h5_write_attr(file, "/provenance", "input_file", text_or(cfg%source, &
                                                                                                  "(built in code)"), error)
        if (.not. allocated(error)) call h5_write(file, "/provenance/namelist", text_or(cfg%text, "(built in code)"), &
                                                  "", "The namelist text exactly as read", error)
    end subroutine write_provenance

    !> The commit of the git checkout the executable lies in ("unknown" if none): HEAD, followed through one ref
    !> (loose file or packed-refs); a detached HEAD is the commit itself.
    function git_commit() result(commit)
        character(len=:), allocatable :: commit
        character(len=4096) :: exe
        character(len=:), allocatable :: dir, head, ref
        integer :: length, status, k

        commit = "unknown"
        call get_executable(exe, length, status)
        if (status /= 0) return
        dir = exe(1:length)
        do
            k = index(dir, "/", back=.true.)
            if (k <= 1) return
            dir = dir(1:k - 1)
            if (is_directory(dir // "/.git")) exit
        end do
        head = first_line(dir // "/.git/HEAD")
        if (len(head) == 0) return
        if (index(head, "ref: ") /= 1) then
            if (is_hex(head)) commit = head
            return
        end if
        ref = head(6:)
        commit = first_line(dir // "/.git/" // ref)
        if (len(commit) == 0) commit = packed_ref(dir // "/.git/packed-refs", ref)
        if (.not. is_hex(commit)) commit = "unknown"
    end function git_commit

    !> The path of the running executable (readlink of /proc/self/exe).
    subroutine get_executable(path, length, status)
        character(len=*), intent(out) :: path
        integer, intent(out) :: length, status
        interface
            function c_readlink(link, buf, size) bind(c, name="readlink") result(n)
                use, intrinsic :: iso_c_binding, only: c_char, c_size_t, c_long
                character(kind=c_char), intent(in) :: link(*)
                character(kind=c_char), intent(out) :: buf(*)
                integer(c_size_t), value :: size
                integer(c_long) :: n
            end function c_readlink
        end interface
        character(len=1) :: buf(4096)
        integer :: n, i

        path = ""
        n = int(c_readlink("/proc/self/exe" // achar(0), buf, int(size(buf), kind=8)))
        status = merge(0, 1, n > 0 .and. n < size(buf))
        length = max(n, 0)
        do i = 1, length
            path(i:i) = buf(i)
        end do
    end subroutine get_executable

    !> First line of a small text file ("" if it cannot be read).
    function first_line(path) result(line)
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: line
        character(len=512) :: buffer
        integer :: unit, ios

        line = ""
        open (newunit=unit, file=path, status="old", action="read", iostat=ios)
        if (ios /= 0) return
        read (unit, "(a)", iostat=ios) buffer
        close (unit)
        if (ios == 0) line = trim(buffer)
    end function first_line

    !> The commit of `ref` in a packed-refs file ("" if absent).
    function packed_ref(path, ref) result(commit)
        character(len=*), intent(in) :: path, ref
        character(len=:), allocatable :: commit
        character(len=512) :: buffer
        integer :: unit, ios, k

        commit = ""
        open (newunit=unit, file=path, status="old", action="read", iostat=ios)
        if (ios /= 0) return
        do
            read (unit, "(a)", iostat=ios) buffer
            if (ios /= 0) exit
            k = index(buffer, " ")
            if (k > 1) then
                if (trim(buffer(k + 1:)) == ref) then
                    commit = buffer(1:k - 1)
                    exit
                end if
            end if
        end do
        close (unit)
    end function packed_ref

    !> Whether a text is a 40- or 64-digit hexadecimal object name.
    pure function is_hex(text) result(yes)
        character(len=*), intent(in) :: text
        logical :: yes

        yes = (len(text) == 40 .or. len(text) == 64) .and. verify(text, "0123456789abcdef") == 0
    end function is_hex

end module supratrans_provenance
