!> Facts about the running program that its outputs, journals and part files record: the git commit it was built
!> from, the host, the executable, the working directory and the local time.
!>
!> The commit and the dirty flag are fixed when the program is built where the build gives them
!> (`supratrans_build_info.c`, given by `sh .ci/with_commit fpm build` or by CMake): a run from another directory or
!> after a checkout records the commit its executable was built from. A plain `fpm build` gives none: the commit is
!> then read when the program runs from the `.git` of the source tree the program was built in (never the working
!> directory's), recorded with `commit_source` saying so and the dirty flag -1 (not known); a program with neither
!> (a copy without `.git`, an installed program built with plain fpm) records "unknown (built without commit)".
module supratrans_host
    use, intrinsic :: iso_c_binding, only: c_char, c_int, c_long, c_size_t, c_ptr, c_null_char, c_associated
    implicit none
    private

    public :: timestamp, build_commit, build_dirty, commit_source, host_name, executable_path, working_directory

    !> Longest path read from the C library.
    integer, parameter :: max_path = 4096

    !> What is given for a fact that cannot be found.
    character(len=*), parameter :: unknown = "unknown"

    !> The commit of a program built without one (plain `fpm build`, a copy without `.git`).
    character(len=*), parameter, public :: no_commit = "unknown (built without commit)"

    interface
        !> POSIX gethostname(2).
        function c_gethostname(name, length) bind(c, name="gethostname") result(stat)
            import :: c_char, c_int, c_size_t
            character(kind=c_char), intent(out) :: name(*)
            !> Size of the buffer.
            integer(c_size_t), value :: length
            integer(c_int) :: stat
        end function c_gethostname

        !> POSIX readlink(2): the target of a symbolic link (not null-terminated); the number of bytes, or -1.
        function c_readlink(path, buffer, length) bind(c, name="readlink") result(nbytes)
            import :: c_char, c_long, c_size_t
            character(kind=c_char), intent(in) :: path(*)
            character(kind=c_char), intent(out) :: buffer(*)
            !> Size of the buffer.
            integer(c_size_t), value :: length
            integer(c_long) :: nbytes
        end function c_readlink

        !> POSIX getcwd(3): the working directory, null-terminated; a null pointer on failure.
        function c_getcwd(buffer, length) bind(c, name="getcwd") result(p)
            import :: c_char, c_size_t, c_ptr
            character(kind=c_char), intent(out) :: buffer(*)
            !> Size of the buffer.
            integer(c_size_t), value :: length
            type(c_ptr) :: p
        end function c_getcwd

        !> The commit id fixed at build time (supratrans_build_info.c), null-terminated; empty if none was given.
        subroutine c_build_commit(buffer, length) bind(c, name="supratrans_build_commit")
            import :: c_char, c_int
            character(kind=c_char), intent(out) :: buffer(*)
            !> Size of the buffer.
            integer(c_int), value :: length
        end subroutine c_build_commit

        !> The commit HEAD names now in the `.git` of the source tree the program was built in, and that `.git`
        !> (both null-terminated): 0 when HEAD is older than the executable, 1 when it moved after the executable
        !> was written, -1 when there is none.
        function c_runtime_commit(commit, csize, gitdir, gsize) bind(c, name="supratrans_runtime_commit") &
            result(state)
            import :: c_char, c_int
            character(kind=c_char), intent(out) :: commit(*)
            !> Size of `commit`.
            integer(c_int), value :: csize
            character(kind=c_char), intent(out) :: gitdir(*)
            !> Size of `gitdir`.
            integer(c_int), value :: gsize
            integer(c_int) :: state
        end function c_runtime_commit

        !> Whether the tree built from had uncommitted changes: 1 yes, 0 no, -1 not known.
        function c_build_dirty() bind(c, name="supratrans_build_dirty") result(flag)
            import :: c_int
            integer(c_int) :: flag
        end function c_build_dirty
    end interface

contains

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

    !> The git commit of the program (40 or 64 hexadecimal digits): the one fixed at build time, else the one read
    !> at run time from the `.git` of the source tree it was built in (`commit_source` says which); `no_commit`
    !> when there is neither.
    function build_commit() result(commit)
        character(len=:), allocatable :: commit
        character(len=:), allocatable :: gitdir
        integer :: state

        commit = fixed_commit()
        if (commit /= no_commit) return
        call runtime_commit(commit, gitdir, state)
        if (state < 0) commit = no_commit
    end function build_commit

    !> Where `build_commit` comes from, as `/provenance` records it (attribute `git_commit_source`): "fixed at
    !> build", "read at run time from <.git>: HEAD when the program ran, not necessarily the build's; dirty flag not
    !> known" (with ", and HEAD moved after the executable was written" when its files are newer than the
    !> executable), or "none".
    function commit_source() result(text)
        character(len=:), allocatable :: text
        character(len=:), allocatable :: commit, gitdir
        integer :: state

        text = "fixed at build"
        if (fixed_commit() /= no_commit) return
        call runtime_commit(commit, gitdir, state)
        text = "none"
        if (state < 0) return
        text = "read at run time from " // gitdir // ": HEAD when the program ran, not necessarily the build's; " &
               // "dirty flag not known"
        if (state == 1) text = text // "; HEAD moved after the executable was written"
    end function commit_source

    !> The commit fixed at build time (`supratrans_build_info.c`), or `no_commit`.
    function fixed_commit() result(commit)
        character(len=:), allocatable :: commit
        character(kind=c_char) :: buffer(80)

        buffer = c_null_char
        call c_build_commit(buffer, int(size(buffer), c_int))
        commit = from_c(buffer, size(buffer))
        if (.not. object_id(commit)) commit = no_commit
    end function fixed_commit

    !> The commit read now from the `.git` of the source tree (`supratrans_build_info.c`), the `.git` it was read
    !> from, and `state`: 0 read, 1 read but HEAD moved after the executable was written, -1 none.
    subroutine runtime_commit(commit, gitdir, state)
        !> The commit (empty when none).
        character(len=:), allocatable, intent(out) :: commit
        !> The git directory read.
        character(len=:), allocatable, intent(out) :: gitdir
        !> 0, 1 or -1 as above.
        integer, intent(out) :: state
        character(kind=c_char) :: cbuf(80), gbuf(max_path)

        cbuf = c_null_char
        gbuf = c_null_char
        state = int(c_runtime_commit(cbuf, int(size(cbuf), c_int), gbuf, int(size(gbuf), c_int)))
        commit = from_c(cbuf, size(cbuf))
        gitdir = from_c(gbuf, size(gbuf))
        if (state < 0 .or. .not. object_id(commit)) then
            state = -1
            commit = ""
        end if
    end subroutine runtime_commit

    !> Whether `text` is a git object id: 40 (SHA-1) or 64 (SHA-256) lower-case hexadecimal digits.
    pure logical function object_id(text)
        !> The text.
        character(len=*), intent(in) :: text

        object_id = (len(text) == 40 .or. len(text) == 64) .and. verify(text, "0123456789abcdef") == 0
    end function object_id

    !> Whether the tree the program was built from had uncommitted changes (`git status` not empty): 1 yes, 0 no,
    !> -1 when not known (no commit fixed at build: a commit read at run time comes without its dirty flag).
    function build_dirty() result(flag)
        integer :: flag

        flag = -1
        if (fixed_commit() == no_commit) return
        flag = int(c_build_dirty())
        if (flag /= 0 .and. flag /= 1) flag = -1
    end function build_dirty

    !> The host name (gethostname); "unknown" on failure.
    function host_name() result(name)
        character(len=:), allocatable :: name
        character(kind=c_char) :: buffer(256)

        buffer = c_null_char
        name = unknown
        if (c_gethostname(buffer, int(size(buffer) - 1, c_size_t)) /= 0) return
        name = from_c(buffer, size(buffer))
        if (len(name) == 0) name = unknown
    end function host_name

    !> Absolute path of the running executable (the target of /proc/self/exe); "unknown" where there is none.
    function executable_path() result(path)
        character(len=:), allocatable :: path
        character(kind=c_char) :: buffer(max_path)
        integer(c_long) :: n

        n = c_readlink("/proc/self/exe" // c_null_char, buffer, int(size(buffer), c_size_t))
        path = unknown
        if (n > 0 .and. n < size(buffer)) path = from_c(buffer, int(n))
    end function executable_path

    !> The working directory (getcwd); "unknown" on failure.
    function working_directory() result(path)
        character(len=:), allocatable :: path
        character(kind=c_char) :: buffer(max_path)

        buffer = c_null_char
        path = unknown
        if (c_associated(c_getcwd(buffer, int(size(buffer), c_size_t)))) path = from_c(buffer, size(buffer))
    end function working_directory

    !> The first `n` characters of a C buffer, up to its first null character.
    pure function from_c(buffer, n) result(s)
        character(kind=c_char), intent(in) :: buffer(:)
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

end module supratrans_host
