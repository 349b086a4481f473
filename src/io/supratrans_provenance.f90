!> Where an output file comes from: the `/provenance` group of every file (code version, git commit, compiler and
!> its flags, OpenMP threads, host, working directory, start time, the namelist file and its text as read).
!>
!> No shell and no `git` program: the commit is read from the repository's files. The repository is found by going
!> up from the directory of the executable (`/proc/self/exe`), then from the working directory, to the first
!> directory with a `.git` (a directory, or a file `gitdir: <path>` as in worktrees and submodules). Its `HEAD`
!> is either a commit or `ref: <name>`, looked up as a file in the git directory, in its common directory
!> (`commondir`, worktrees) and in `packed-refs`. Anything missing gives "unknown".
module supratrans_provenance
    use, intrinsic :: iso_c_binding, only: c_char, c_int, c_long, c_size_t, c_ptr, c_null_char, c_associated
    use, intrinsic :: iso_fortran_env, only: compiler_version, compiler_options
    !$ use omp_lib, only: omp_get_max_threads
    use supratrans_kinds, only: supratrans_version
    use supratrans_error, only: error_type
    use supratrans_strings, only: text_or
    use supratrans_config, only: input_config
    use supratrans_hdf5, only: h5_file, h5_create_group, h5_write_attr, h5_write
    implicit none
    private

    public :: write_provenance, timestamp, git_commit, find_commit, host_name, executable_path, working_directory

    !> Longest path read from the C library.
    integer, parameter :: max_path = 4096

    !> What is written for a fact that cannot be found.
    character(len=*), parameter :: unknown = "unknown"

    interface
        !> POSIX gethostname(2).
        function c_gethostname(name, length) bind(c, name="gethostname") result(stat)
            import :: c_char, c_int, c_size_t
            !> Buffer for the name.
            character(kind=c_char), intent(out) :: name(*)
            !> Size of the buffer.
            integer(c_size_t), value :: length
            integer(c_int) :: stat
        end function c_gethostname

        !> POSIX readlink(2): the target of a symbolic link (not null-terminated); the number of bytes, or -1.
        function c_readlink(path, buffer, length) bind(c, name="readlink") result(nbytes)
            import :: c_char, c_long, c_size_t
            !> Path of the link, null-terminated.
            character(kind=c_char), intent(in) :: path(*)
            !> Buffer for the target.
            character(kind=c_char), intent(out) :: buffer(*)
            !> Size of the buffer.
            integer(c_size_t), value :: length
            integer(c_long) :: nbytes
        end function c_readlink

        !> POSIX getcwd(3): the working directory, null-terminated; a null pointer on failure.
        function c_getcwd(buffer, length) bind(c, name="getcwd") result(p)
            import :: c_char, c_size_t, c_ptr
            !> Buffer for the path.
            character(kind=c_char), intent(out) :: buffer(*)
            !> Size of the buffer.
            integer(c_size_t), value :: length
            type(c_ptr) :: p
        end function c_getcwd
    end interface

contains

    !> Write `/provenance`: attributes `version`, `git_commit`, `git_ref`, `git_repository`, `compiler`,
    !> `compiler_options`, `omp_max_threads`, `host`, `executable`, `working_directory`, `started`, `input_file`,
    !> and the dataset `/provenance/namelist`, the input file's text exactly as read.
    subroutine write_provenance(file, cfg, error)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The input (its source, text and start time).
        type(input_config), intent(in) :: cfg
        !> Error, allocated on failure.
        type(error_type), allocatable, intent(out) :: error
        character(len=*), parameter :: g = "/provenance"
        character(len=:), allocatable :: commit, ref, repository, text
        integer :: threads

        threads = 1
        !$ threads = omp_get_max_threads()
        call git_commit(commit, ref, repository)
        call h5_create_group(file, g, "Where this file comes from: code, build, machine, input", error)
        if (.not. allocated(error)) call h5_write_attr(file, g, "version", supratrans_version, error)
        if (.not. allocated(error)) call h5_write_attr(file, g, "git_commit", commit, error)
        if (.not. allocated(error)) call h5_write_attr(file, g, "git_ref", ref, error)
        if (.not. allocated(error)) call h5_write_attr(file, g, "git_repository", repository, error)
        if (.not. allocated(error)) call h5_write_attr(file, g, "compiler", compiler_version(), error)
        if (.not. allocated(error)) call h5_write_attr(file, g, "compiler_options", compiler_options(), error)
        if (.not. allocated(error)) call h5_write_attr(file, g, "omp_max_threads", threads, error)
        if (.not. allocated(error)) call h5_write_attr(file, g, "host", host_name(), error)
        if (.not. allocated(error)) call h5_write_attr(file, g, "executable", executable_path(), error)
        if (.not. allocated(error)) call h5_write_attr(file, g, "working_directory", working_directory(), error)
        if (.not. allocated(error)) call h5_write_attr(file, g, "started", text_or(cfg%started, unknown), error)
        if (.not. allocated(error)) call h5_write_attr(file, g, "input_file", text_or(cfg%source, unknown), error)
        text = ""
        if (allocated(cfg%text)) text = cfg%text
        if (.not. allocated(error)) call h5_write(file, g // "/namelist", text, "1", "The namelist file exactly as " &
            // "read (empty for a configuration built in code)", error)
    end subroutine write_provenance

    !> Current local date and time, ISO 8601.
    function timestamp() result(stamp)
        character(len=:), allocatable :: stamp
        character(len=8) :: date
        character(len=10) :: time
        character(len=5) :: zone

        call date_and_time(date, time, zone)
        stamp = date(1:4) // "-" // date(5:6) // "-" // date(7:8) // "T" // time(1:2) // ":" // time(3:4) // ":" &
                // time(5:6) // zone
    end function timestamp

    !> The commit of the checkout the program runs from: found from the executable's directory, else from the
    !> working directory; "unknown" (all three) when neither is in a git repository.
    subroutine git_commit(commit, ref, repository)
        !> Commit id (hexadecimal), or "unknown".
        character(len=:), allocatable, intent(out) :: commit
        !> What HEAD names ("refs/heads/main"), "HEAD" for a detached HEAD, or "unknown".
        character(len=:), allocatable, intent(out) :: ref
        !> The directory holding `.git`, or "unknown".
        character(len=:), allocatable, intent(out) :: repository
        character(len=:), allocatable :: exe
        integer :: k

        exe = executable_path()
        k = index(exe, "/", back=.true.)
        if (k > 1) then
            call find_commit(exe(1:k - 1), commit, ref, repository)
            if (commit /= unknown) return
        end if
        call find_commit(working_directory(), commit, ref, repository)
    end subroutine git_commit

    !> The commit of the git repository that holds directory `start` (an absolute path): the first directory up
    !> from `start` with a `.git`, its HEAD resolved through the ref files and `packed-refs`.
    subroutine find_commit(start, commit, ref, repository)
        !> Absolute path of a directory.
        character(len=*), intent(in) :: start
        !> Commit id, or "unknown".
        character(len=:), allocatable, intent(out) :: commit
        !> What HEAD names, "HEAD" when detached, or "unknown".
        character(len=:), allocatable, intent(out) :: ref
        !> The directory holding `.git`, or "unknown".
        character(len=:), allocatable, intent(out) :: repository
        character(len=:), allocatable :: dir, gitdir, common, head, line
        logical :: ok
        integer :: k

        commit = unknown
        ref = unknown
        repository = unknown
        if (len(start) == 0) return
        if (start(1:1) /= "/") return
        dir = strip_slashes(start)
        do
            call read_first_line(dir // "/.git/HEAD", head, ok)
            if (ok) then
                gitdir = dir // "/.git"
                exit
            end if
            call read_first_line(dir // "/.git", line, ok)
            if (ok .and. index(line, "gitdir:") == 1) then
                gitdir = absolute(dir, adjustl_trim(line(8:)))
                call read_first_line(gitdir // "/HEAD", head, ok)
                if (ok) exit
            end if
            if (len(dir) == 0) return
            k = index(dir, "/", back=.true.)
            dir = dir(1:k - 1)
        end do
        repository = dir
        if (len(repository) == 0) repository = "/"
        common = gitdir
        call read_first_line(gitdir // "/commondir", line, ok)
        if (ok) common = absolute(gitdir, adjustl_trim(line))
        if (index(head, "ref:") == 1) then
            ref = adjustl_trim(head(5:))
            commit = resolve_ref(gitdir, common, ref)
        else if (is_commit_id(head)) then
            ref = "HEAD"
            commit = head
        end if
    end subroutine find_commit

    !> The commit a ref names: the file `<gitdir>/<ref>` or `<common>/<ref>`, else its line in `packed-refs`.
    function resolve_ref(gitdir, common, ref) result(commit)
        !> The git directory.
        character(len=*), intent(in) :: gitdir
        !> The common git directory (the same as `gitdir` outside worktrees).
        character(len=*), intent(in) :: common
        !> The ref ("refs/heads/main").
        character(len=*), intent(in) :: ref
        character(len=:), allocatable :: commit

        commit = loose_ref(gitdir // "/" // ref)
        if (commit == unknown) commit = loose_ref(common // "/" // ref)
        if (commit == unknown) commit = packed_ref(gitdir // "/packed-refs", ref)
        if (commit == unknown) commit = packed_ref(common // "/packed-refs", ref)
    end function resolve_ref

    !> The commit id held by a ref file; "unknown" if it holds none.
    function loose_ref(path) result(commit)
        !> The ref file.
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: commit
        character(len=:), allocatable :: line
        logical :: ok

        commit = unknown
        call read_first_line(path, line, ok)
        if (ok .and. is_commit_id(line)) commit = line
    end function loose_ref

    !> The commit id of `ref` in a `packed-refs` file (lines `<id> <ref>`); "unknown" if it is not there.
    function packed_ref(path, ref) result(commit)
        !> The packed-refs file.
        character(len=*), intent(in) :: path
        !> The ref.
        character(len=*), intent(in) :: ref
        character(len=:), allocatable :: commit
        character(len=:), allocatable :: text, line
        logical :: ok
        integer :: k, next

        commit = unknown
        call read_file(path, text, ok)
        if (.not. ok) return
        k = 1
        do while (k <= len(text))
            next = index(text(k:), new_line("a"))
            if (next == 0) then
                line = text(k:)
                k = len(text) + 1
            else
                line = text(k:k + next - 2)
                k = k + next
            end if
            next = index(line, " ")
            if (next < 2) cycle
            if (trim(line(next + 1:)) == ref .and. is_commit_id(line(1:next - 1))) then
                commit = line(1:next - 1)
                return
            end if
        end do
    end function packed_ref

    !> Whether a string is a git object id: 40 (SHA-1) or 64 (SHA-256) lower-case hexadecimal digits.
    pure function is_commit_id(s) result(ok)
        !> Candidate.
        character(len=*), intent(in) :: s
        logical :: ok

        ok = (len(s) == 40 .or. len(s) == 64) .and. verify(s, "0123456789abcdef") == 0
    end function is_commit_id

    !> `path` if absolute, else `dir/path`.
    pure function absolute(dir, path) result(full)
        !> Directory that a relative path is relative to.
        character(len=*), intent(in) :: dir
        !> The path.
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: full

        if (len(path) > 0) then
            if (path(1:1) == "/") then
                full = strip_slashes(path)
                return
            end if
        end if
        full = dir // "/" // strip_slashes(path)
    end function absolute

    !> A path without trailing slashes ("/" becomes "").
    pure function strip_slashes(path) result(s)
        !> The path.
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: s
        integer :: n

        n = len_trim(path)
        do while (n > 0)
            if (path(n:n) /= "/") exit
            n = n - 1
        end do
        s = path(1:n)
    end function strip_slashes

    !> A string without leading and trailing blanks.
    pure function adjustl_trim(s) result(t)
        !> The string.
        character(len=*), intent(in) :: s
        character(len=:), allocatable :: t

        t = trim(adjustl(s))
    end function adjustl_trim

    !> The first line of a small text file, without its newline and trailing blanks; `ok` false if unreadable.
    subroutine read_first_line(path, line, ok)
        !> The file.
        character(len=*), intent(in) :: path
        !> Its first line.
        character(len=:), allocatable, intent(out) :: line
        !> Whether the file could be read.
        logical, intent(out) :: ok
        character(len=:), allocatable :: text
        integer :: k

        call read_file(path, text, ok)
        line = ""
        if (.not. ok) return
        k = index(text, new_line("a"))
        if (k > 0) text = text(1:k - 1)
        line = trim(text)
        if (len(line) > 0) then
            if (line(len(line):len(line)) == achar(13)) line = line(1:len(line) - 1)
        end if
    end subroutine read_first_line

    !> The whole of a regular file (at most 16 MiB); `ok` false if it is missing, a directory or unreadable.
    subroutine read_file(path, text, ok)
        !> The file.
        character(len=*), intent(in) :: path
        !> Its contents.
        character(len=:), allocatable, intent(out) :: text
        !> Whether the file could be read.
        logical, intent(out) :: ok
        integer :: unit, ios, nbytes
        logical :: exists

        ok = .false.
        text = ""
        inquire (file=path, exist=exists)
        if (.not. exists) return
        inquire (file=path // "/.", exist=exists)
        if (exists) return                                  ! a directory
        open (newunit=unit, file=path, status="old", access="stream", form="unformatted", action="read", iostat=ios)
        if (ios /= 0) return
        inquire (unit=unit, size=nbytes)
        if (nbytes < 0 .or. nbytes > 16*1024*1024) then
            close (unit)
            return
        end if
        deallocate (text)
        allocate (character(len=nbytes) :: text)
        if (nbytes > 0) read (unit, iostat=ios) text
        close (unit)
        ok = ios == 0
    end subroutine read_file

    !> The host name (gethostname); "unknown" on failure.
    function host_name() result(name)
        character(len=:), allocatable :: name
        character(kind=c_char) :: buffer(256)

        buffer = c_null_char
        if (c_gethostname(buffer, int(size(buffer) - 1, c_size_t)) /= 0) then
            name = unknown
            return
        end if
        name = from_c(buffer, size(buffer))
        if (len(name) == 0) name = unknown
    end function host_name

    !> Absolute path of the running executable (the target of /proc/self/exe); "unknown" where there is none.
    function executable_path() result(path)
        character(len=:), allocatable :: path
        character(kind=c_char) :: buffer(max_path)
        integer(c_long) :: n

        n = c_readlink("/proc/self/exe" // c_null_char, buffer, int(size(buffer), c_size_t))
        if (n <= 0 .or. n >= size(buffer)) then
            path = unknown
            return
        end if
        path = from_c(buffer, int(n))
    end function executable_path

    !> The working directory (getcwd); "unknown" on failure.
    function working_directory() result(path)
        character(len=:), allocatable :: path
        character(kind=c_char) :: buffer(max_path)

        buffer = c_null_char
        if (.not. c_associated(c_getcwd(buffer, int(size(buffer), c_size_t)))) then
            path = unknown
            return
        end if
        path = from_c(buffer, size(buffer))
    end function working_directory

    !> The first `n` characters of a C buffer, up to its first null character.
    pure function from_c(buffer, n) result(s)
        !> The buffer.
        character(kind=c_char), intent(in) :: buffer(:)
        !> Largest number of characters.
        integer, intent(in) :: n
        character(len=:), allocatable :: s
        integer :: i, m

        m = min(n, size(buffer))
        do i = 1, m
            if (buffer(i) == c_null_char) then
                m = i - 1
                exit
            end if
        end do
        allocate (character(len=m) :: s)
        do i = 1, m
            s(i:i) = buffer(i)
        end do
    end function from_c

end module supratrans_provenance
