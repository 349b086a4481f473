!> Where an output file comes from: the `/provenance` group of every file (code version, the git commit it was built
!> from, compiler and its flags, OpenMP threads, host, working directory, start time, the namelist file and its text
!> as read).
!>
!> The commit and the dirty flag are fixed when the program is built (src/io/supratrans_build_info.c, given by
!> `sh .ci/with_commit fpm build` or by CMake), never read from `.git` when it runs: a run from another directory or
!> after a checkout records the commit its executable was built from, and a build without them records
!> "unknown (built without commit)".
module supratrans_provenance
    use, intrinsic :: iso_c_binding, only: c_char, c_int, c_long, c_size_t, c_ptr, c_null_char, c_associated
    use, intrinsic :: iso_fortran_env, only: compiler_version, compiler_options
    !$ use omp_lib, only: omp_get_max_threads
    use supratrans_kinds, only: wp, supratrans_version
    use supratrans_strings, only: text_or
    use supratrans_config, only: input_config
    use supratrans_invocation, only: invocation_type
    use supratrans_hdf5, only: h5_file, h5_create_group, h5_write_attr, h5_write
    implicit none
    private

    public :: write_provenance, timestamp, build_commit, build_dirty, host_name, executable_path, working_directory

    !> Longest path read from the C library.
    integer, parameter :: max_path = 4096

    !> What is written for a fact that cannot be found.
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

        !> Whether the tree built from had uncommitted changes: 1 yes, 0 no, -1 not known.
        function c_build_dirty() bind(c, name="supratrans_build_dirty") result(flag)
            import :: c_int
            integer(c_int) :: flag
        end function c_build_dirty
    end interface

contains

    !> Write `/provenance`: attributes `version`, `git_commit` and `git_dirty` (of the build: `build_commit`,
    !> `build_dirty`), `compiler`, `compiler_options`, `omp_max_threads`, `host`, `executable`, `working_directory`,
    !> `started`, `input_file`, and the dataset `/provenance/namelist`, the input file's text exactly as read.
    subroutine write_provenance(file, cfg, inv)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The input (its source, text and start time).
        type(input_config), intent(in) :: cfg
        !> How the engine was invoked: a merge records its parts (default: computed here).
        type(invocation_type), intent(in), optional :: inv
        character(len=*), parameter :: g = "/provenance"
        character(len=:), allocatable :: text
        integer :: threads

        threads = 1
        !$ threads = omp_get_max_threads()
        call h5_create_group(file, g, "Where this file comes from: code, build, machine, input")
        call h5_write_attr(file, g, "version", supratrans_version)
        call h5_write_attr(file, g, "git_commit", build_commit())
        call h5_write_attr(file, g, "git_dirty", build_dirty())
        call h5_write_attr(file, g, "compiler", compiler_version())
        call h5_write_attr(file, g, "compiler_options", compiler_options())
        call h5_write_attr(file, g, "omp_max_threads", threads)
        call h5_write_attr(file, g, "host", host_name())
        call h5_write_attr(file, g, "executable", executable_path())
        call h5_write_attr(file, g, "working_directory", working_directory())
        call h5_write_attr(file, g, "started", text_or(cfg%started, unknown))
        call h5_write_attr(file, g, "input_file", text_or(cfg%source, unknown))
        text = ""
        if (allocated(cfg%text)) text = cfg%text
        call h5_write(file, g // "/namelist", text, "1", "The namelist file exactly as " &
            // "read (empty for a configuration built in code)")
        if (.not. present(inv)) return
        if (allocated(inv%merge_record)) then
            ! a merged file: where, when and how long each slice ran (its part file's record)
            call h5_write(file, g // "/parts", inv%merge_record, "1", "Merged from part files, one line per part, " &
                // "tab-separated: slice, host, start, end, wall time (s), OpenMP threads, git commit")
            call h5_write_attr(file, g, "slices_wall_time_s", max(inv%merge_wall_time, 0.0_wp))
        end if
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

    !> The git commit the program was built from (40 or 64 hexadecimal digits), fixed at build time; `no_commit`
    !> when the build was given none.
    function build_commit() result(commit)
        character(len=:), allocatable :: commit
        character(kind=c_char) :: buffer(80)

        buffer = c_null_char
        call c_build_commit(buffer, int(size(buffer), c_int))
        commit = from_c(buffer, size(buffer))
        if (.not. is_commit_id(commit)) commit = no_commit
    end function build_commit

    !> Whether the tree the program was built from had uncommitted changes (`git status` not empty): 1 yes, 0 no,
    !> -1 when the build was given no commit.
    function build_dirty() result(flag)
        integer :: flag

        flag = -1
        if (build_commit() == no_commit) return
        flag = int(c_build_dirty())
        if (flag /= 0 .and. flag /= 1) flag = -1
    end function build_dirty

    !> Whether a string is a git object id: 40 (SHA-1) or 64 (SHA-256) lower-case hexadecimal digits.
    pure function is_commit_id(s) result(ok)
        character(len=*), intent(in) :: s
        logical :: ok

        ok = (len(s) == 40 .or. len(s) == 64) .and. verify(s, "0123456789abcdef") == 0
    end function is_commit_id

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

end module supratrans_provenance
