!> What the machine lets this process use: the memory available to it (MemAvailable, its cgroups' limits, ulimit -v
!> and -d) and the OpenMP threads it may run (bounded by the processors it may use). The figures the limits of a
!> configuration are checked against (`supratrans_limits`) and the bound the command line applies first.
module supratrans_resources
    use, intrinsic :: iso_c_binding, only: c_double, c_int
    use supratrans_kinds, only: wp, i8
    use supratrans_strings, only: int_str, real_str
    !$ use omp_lib, only: omp_get_max_threads, omp_set_num_threads
    use supratrans_system, only: usable_cpus
    implicit none
    private

    public :: available_memory_bytes, cgroup_memory_limit, bound_threads

    !> Most OpenMP threads per processor the process may use (`bound_threads`).
    integer, parameter, public :: max_threads_per_cpu = 4

    interface
        function c_memory_limit(kind) bind(c, name="supratrans_memory_limit") result(limit)
            import :: c_double, c_int
            integer(c_int), value :: kind
            real(c_double) :: limit
        end function c_memory_limit
        function c_address_space_used() bind(c, name="supratrans_address_space_used") result(used)
            import :: c_double
            real(c_double) :: used
        end function c_address_space_used
    end interface

contains

    !> Bound the number of OpenMP threads to `max_threads_per_cpu` x the processors this process may use
    !> (sched_getaffinity: taskset, cpusets, Slurm's --cpus-per-task): OMP_NUM_THREADS=100000 used to crash the
    !> program creating its threads. `message` is one line saying so when the number was lowered, "" otherwise.
    subroutine bound_threads(message)
        !> What was done, for stderr ("" when nothing was).
        character(len=:), allocatable, intent(out) :: message
        !$ integer :: asked, cpus

        message = ""
        !$ asked = omp_get_max_threads()
        !$ cpus = usable_cpus()
        !$ if (asked > max_threads_per_cpu*cpus) then
        !$     call omp_set_num_threads(max_threads_per_cpu*cpus)
        !$     message = "supratrans: " // int_str(asked) // " OpenMP threads asked (OMP_NUM_THREADS) for the " &
        !$         // int_str(cpus) // " processor(s) this process may use: running " &
        !$         // int_str(max_threads_per_cpu*cpus) // " (at most " // int_str(max_threads_per_cpu) // " a processor)"
        !$ end if
    end subroutine bound_threads

    !> Memory available to this process (bytes): the smallest of MemAvailable of /proc/meminfo, the memory limit of
    !> its cgroups (`cgroup_memory_limit`: Slurm's `--mem`, a container's limit), and what the address-space limit
    !> (ulimit -v) leaves beside what the process maps already, or the data limit (ulimit -d); 0 when none can be
    !> read. `source` names the one that binds, for messages.
    function available_memory_bytes(source) result(bytes)
        !> What gives the figure: "MemAvailable of /proc/meminfo", a cgroup file, "ulimit -v", "ulimit -d".
        character(len=:), allocatable, intent(out), optional :: source
        real(wp) :: bytes
        real(wp) :: limit, mapped
        integer :: unit, ios
        character(len=256) :: line
        character(len=:), allocatable :: what, file
        integer(i8) :: kib

        bytes = 0.0_wp
        what = ""
        open (newunit=unit, file="/proc/meminfo", status="old", action="read", iostat=ios)
        if (ios == 0) then
            do
                read (unit, "(a)", iostat=ios) line
                if (ios /= 0) exit
                if (index(line, "MemAvailable:") == 1) then
                    read (line(14:), *, iostat=ios) kib
                    if (ios == 0) bytes = 1024.0_wp*real(kib, wp)
                    if (ios == 0) what = "MemAvailable of /proc/meminfo"
                    exit
                end if
            end do
            close (unit)
        end if
        limit = cgroup_memory_limit(cgroup_root(), file)
        call take(limit, "the cgroup limit " // file)
        ! ulimit -v counts everything mapped: the libraries and thread stacks mapped already are not available
        mapped = max(real(c_address_space_used(), wp), 0.0_wp)
        limit = real(c_memory_limit(1_c_int), wp)
        if (limit > 0.0_wp) limit = max(limit - mapped, 1.0_wp)
        call take(limit, "ulimit -v, less the " // real_str(mapped/1.0e9_wp, 3) // " GB mapped already")
        call take(real(c_memory_limit(2_c_int), wp), "ulimit -d")
        if (present(source)) source = what

    contains

        subroutine take(candidate, name)
            real(wp), intent(in) :: candidate
            character(len=*), intent(in) :: name

            if (candidate > 0.0_wp .and. (bytes <= 0.0_wp .or. candidate < bytes)) then
                bytes = candidate
                what = name
            end if
        end subroutine take

    end function available_memory_bytes

    !> Where the cgroup files are read: "" (the root of this machine), or the directory the test-only variable
    !> SUPRATRANS_TEST_CGROUP_ROOT names (a fake tree holding proc/self/cgroup and sys/fs/cgroup/...).
    function cgroup_root() result(root)
        character(len=:), allocatable :: root
        character(len=4096) :: value
        integer :: ios

        root = ""
        call get_environment_variable("SUPRATRANS_TEST_CGROUP_ROOT", value, status=ios)
        if (ios == 0) root = trim(value)
    end function cgroup_root

    !> The memory limit of this process's cgroups, in bytes (0: none found): for each line of
    !> `<root>/proc/self/cgroup`, the cgroup v2 `memory.max` (line `0::PATH`, under `<root>/sys/fs/cgroup` or its
    !> `unified` mount) or the v1 `memory.limit_in_bytes` (the line whose controllers hold `memory`, under
    !> `<root>/sys/fs/cgroup/memory`) of PATH and of every parent up to the mount's root (a limit set on a parent,
    !> as Slurm sets it on the job above its steps, binds its children; inside a container PATH may not exist and the
    !> mount's root is the container's own cgroup). The smallest limit wins; "max" and v1's "unlimited" (2^63 rounded
    !> down to a page) are no limit.
    function cgroup_memory_limit(root, file) result(bytes)
        !> Root of the tree ("" for the machine's; a fake tree in tests).
        character(len=*), intent(in) :: root
        !> The file that gave the limit ("" when none).
        character(len=:), allocatable, intent(out) :: file
        real(wp) :: bytes
        integer :: unit, ios, k1, k2
        character(len=4096) :: line
        character(len=:), allocatable :: controllers, path

        bytes = 0.0_wp
        file = ""
        open (newunit=unit, file=root // "/proc/self/cgroup", status="old", action="read", iostat=ios)
        if (ios /= 0) return
        do
            read (unit, "(a)", iostat=ios) line
            if (ios /= 0) exit
            k1 = index(line, ":")
            if (k1 == 0) cycle
            k2 = k1 + index(line(k1 + 1:), ":")
            if (k2 == k1) cycle
            controllers = "," // line(k1 + 1:k2 - 1) // ","
            path = trim(line(k2 + 1:))
            if (line(1:k1 - 1) == "0" .and. controllers == ",,") then
                call walk(root // "/sys/fs/cgroup", "memory.max")
                call walk(root // "/sys/fs/cgroup/unified", "memory.max")
            else if (index(controllers, ",memory,") > 0) then
                call walk(root // "/sys/fs/cgroup/memory", "memory.limit_in_bytes")
            end if
        end do
        close (unit)

    contains

        !> Read `name` in the cgroup PATH under `mount` and in each of its parents.
        subroutine walk(mount, name)
            character(len=*), intent(in) :: mount, name
            character(len=:), allocatable :: dir
            integer :: k

            dir = path
            do
                if (len(dir) > 0) then
                    if (dir(len(dir):len(dir)) == "/") dir = dir(1:len(dir) - 1)
                end if
                call read_limit(mount // dir // "/" // name)
                if (len(dir) == 0) exit
                k = index(dir, "/", back=.true.)
                if (k == 0) exit
                dir = dir(1:k - 1)
            end do
        end subroutine walk

        subroutine read_limit(name)
            character(len=*), intent(in) :: name
            integer :: u, stat
            character(len=64) :: text
            real(wp) :: value

            open (newunit=u, file=name, status="old", action="read", iostat=stat)
            if (stat /= 0) return
            read (u, "(a)", iostat=stat) text
            close (u)
            if (stat /= 0) return
            if (verify(trim(adjustl(text)), "0123456789") /= 0 .or. len_trim(text) == 0) return   ! "max", junk
            read (text, *, iostat=stat) value
            if (stat /= 0 .or. .not. (value > 0.0_wp) .or. value >= 2.0_wp**62) return
            if (bytes <= 0.0_wp .or. value < bytes) then
                bytes = value
                file = name
            end if
        end subroutine read_limit

    end function cgroup_memory_limit

end module supratrans_resources
