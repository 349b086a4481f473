!> Runs the independent tasks of a scene (one simulation, or one threshold search, each) on OpenMP threads, with a
!> journal that makes a killed scene resumable and progress on stderr.
!>
!> Every finished task appends one line `index v_1 ... v_m` to the journal (17 significant digits: an exact
!> round trip of IEEE doubles) and flushes it, so a scene killed at any moment (SIGKILL, a wall-time limit) loses at
!> most the tasks that were running. Started again, it reads the journal, checks that it belongs to the same input
!> (a fingerprint of the namelist file), keeps the complete lines, and runs only what is missing. Results are
!> stored by task index, whatever thread computed them, so they are identical for any thread count.
module supratrans_tasks
    use, intrinsic :: iso_fortran_env, only: error_unit, int64
    use supratrans_kinds, only: wp
    use supratrans_strings, only: int_str, fixed1
    use supratrans_error, only: error_type, fatal_error, err_io
    use supratrans_system, only: rename_file, remove_file
    !$ use omp_lib, only: omp_get_max_threads
    implicit none
    private

    public :: run_tasks, file_fingerprint

    !> A scene's list of tasks; the scene extends it with what its tasks need (read-only during the run).
    type, abstract, public :: task_list
    contains
        !> Compute task `index`, writing its results into `values`. Must be thread-safe (no shared mutable state).
        procedure(run_task_interface), deferred :: run
        !> Called now and then, serially, with the results so far (write a partial output); default: nothing.
        procedure :: snapshot => no_snapshot
    end type task_list

    abstract interface
        !> Compute one task.
        subroutine run_task_interface(self, index, values)
            import :: task_list, wp
            !> The task list.
            class(task_list), intent(in) :: self
            !> Task index.
            integer, intent(in) :: index
            !> The task's results.
            real(wp), intent(out) :: values(:)
        end subroutine run_task_interface
    end interface

    !> Seconds between two progress lines, and between two snapshots.
    real(wp), parameter :: progress_interval = 2.0_wp, snapshot_interval = 10.0_wp

contains

    !> Default snapshot: nothing.
    subroutine no_snapshot(self, results, done)
        !> The task list.
        class(task_list), intent(in) :: self
        !> Results so far, (values, tasks).
        real(wp), intent(in) :: results(:, :)
        !> Which tasks are done.
        logical, intent(in) :: done(:)
    end subroutine no_snapshot

    !> Run tasks 1..ntask (those not already in the journal), in parallel over OpenMP threads.
    subroutine run_tasks(tasks, ntask, nvalues, journal, fingerprint, label, quiet, results, done, error)
        !> The tasks.
        class(task_list), intent(in) :: tasks
        !> Number of tasks.
        integer, intent(in) :: ntask
        !> Number of values each task produces.
        integer, intent(in) :: nvalues
        !> Journal file (created, or resumed from).
        character(len=*), intent(in) :: journal
        !> Identifies the input the journal belongs to.
        character(len=*), intent(in) :: fingerprint
        !> What the progress lines call the tasks (e.g. "runs").
        character(len=*), intent(in) :: label
        !> No progress lines.
        logical, intent(in) :: quiet
        !> Results, (nvalues, ntask).
        real(wp), allocatable, intent(out) :: results(:, :)
        !> Which tasks are done (all, unless an error occurred).
        logical, allocatable, intent(out) :: done(:)
        !> Error, allocated on failure (journal unreadable or from another input, or unwritable).
        type(error_type), allocatable, intent(out) :: error
        character(len=:), allocatable :: header
        real(wp), allocatable :: values(:)
        integer :: unit, i, ndone_start, ndone, ios, threads
        integer(int64) :: clock_start, clock_rate, clock_now
        real(wp) :: last_progress, last_snapshot, elapsed

        allocate (results(nvalues, ntask), done(ntask))
        results = 0.0_wp
        done = .false.
        header = "supratrans-journal 1 " // int_str(ntask) // " " // int_str(nvalues) // " " // fingerprint
        call read_journal(journal, header, results, done, error)
        if (allocated(error)) return
        call write_journal(journal, header, results, done, error)
        if (allocated(error)) return
        open (newunit=unit, file=journal, status="old", position="append", action="write", iostat=ios)
        if (ios /= 0) then
            call fatal_error(error, journal // ": cannot append to the journal", err_io)
            return
        end if

        ndone_start = count(done)
        ndone = ndone_start
        threads = 1
        !$ threads = omp_get_max_threads()
        call system_clock(clock_start, clock_rate)
        last_progress = 0.0_wp
        last_snapshot = 0.0_wp
        if (.not. quiet) then
            write (error_unit, '(a)') "  " // int_str(ntask) // " " // label // ", " // int_str(ndone_start) &
                // " already done (journal " // journal // "), " // int_str(threads) // " thread(s)"
            flush (error_unit)
        end if

        !$omp parallel do schedule(dynamic, 1) default(shared) private(i, values, clock_now, elapsed)
        do i = 1, ntask
            if (done(i)) cycle
            allocate (values(nvalues))
            call tasks%run(i, values)
            !$omp critical (supratrans_tasks_journal)
            results(:, i) = values
            done(i) = .true.
            ndone = ndone + 1
            write (unit, '(i0, *(1x, es25.17e3))') i, values
            flush (unit)
            call system_clock(clock_now)
            elapsed = real(clock_now - clock_start, wp)/real(clock_rate, wp)
            if (.not. quiet .and. (elapsed - last_progress >= progress_interval .or. ndone == ntask)) then
                last_progress = elapsed
                write (error_unit, '(a)') "  " // int_str(ndone) // "/" // int_str(ntask) // " " // label &
                    // ", elapsed " // fixed1(elapsed) // " s, remaining ~" &
                    // fixed1(elapsed/real(ndone - ndone_start, wp)*real(ntask - ndone, wp)) // " s"
                flush (error_unit)
            end if
            if (elapsed - last_snapshot >= snapshot_interval .and. ndone < ntask) then
                last_snapshot = elapsed
                call tasks%snapshot(results, done)
            end if
            !$omp end critical (supratrans_tasks_journal)
            deallocate (values)
        end do
        !$omp end parallel do
        close (unit)
    end subroutine run_tasks

    !> Read the complete lines of an existing journal into `results`/`done`; nothing if there is no journal.
    subroutine read_journal(journal, header, results, done, error)
        character(len=*), intent(in) :: journal, header
        real(wp), intent(inout) :: results(:, :)
        logical, intent(inout) :: done(:)
        type(error_type), allocatable, intent(out) :: error
        logical :: exists
        integer :: unit, ios, index
        character(len=:), allocatable :: line
        real(wp), allocatable :: values(:)

        inquire (file=journal, exist=exists)
        if (.not. exists) return
        open (newunit=unit, file=journal, status="old", action="read", iostat=ios)
        if (ios /= 0) then
            call fatal_error(error, journal // ": cannot read the journal of an earlier run", err_io)
            return
        end if
        call read_line(unit, line, ios)
        if (ios /= 0 .or. line /= header) then
            close (unit)
            call fatal_error(error, journal // ": journal of a different input or scene (delete it to start afresh," &
                             // " or restore the input it was made with)", err_io)
            return
        end if
        allocate (values(size(results, 1)))
        do
            call read_line(unit, line, ios)
            if (ios /= 0) exit
            read (line, *, iostat=ios) index, values
            if (ios /= 0) exit                       ! a line cut short by a kill: ignore it and what follows
            if (index < 1 .or. index > size(done)) exit
            results(:, index) = values
            done(index) = .true.
        end do
        close (unit)
    end subroutine read_journal

    !> (Re)write the journal with its header and the complete lines (atomically: temporary file, then rename).
    subroutine write_journal(journal, header, results, done, error)
        character(len=*), intent(in) :: journal, header
        real(wp), intent(in) :: results(:, :)
        logical, intent(in) :: done(:)
        type(error_type), allocatable, intent(out) :: error
        integer :: unit, ios, i

        open (newunit=unit, file=journal // ".new", status="replace", action="write", iostat=ios)
        if (ios /= 0) then
            call fatal_error(error, journal // ": cannot write the journal", err_io)
            return
        end if
        write (unit, '(a)') header
        do i = 1, size(done)
            if (done(i)) write (unit, '(i0, *(1x, es25.17e3))') i, results(:, i)
        end do
        close (unit)
        call rename_file(journal // ".new", journal, error)
    end subroutine write_journal

    !> Read one whole line of any length.
    subroutine read_line(unit, line, ios)
        integer, intent(in) :: unit
        character(len=:), allocatable, intent(out) :: line
        integer, intent(out) :: ios
        character(len=4096) :: buffer
        integer :: size_read

        line = ""
        do
            read (unit, '(a)', advance="no", iostat=ios, size=size_read) buffer
            line = line // buffer(1:size_read)
            if (ios /= 0) exit
        end do
        if (is_iostat_eor(ios)) ios = 0
    end subroutine read_line

    !> A fingerprint of a file's bytes (two polynomial hashes modulo the prime 2^31 - 1, in hexadecimal), to tie
    !> a journal to its input. Integer arithmetic never overflows: every intermediate is below 2^38.
    function file_fingerprint(path) result(hash_text)
        !> File to fingerprint.
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: hash_text
        integer(int64), parameter :: modulus = 2147483647_int64
        integer :: unit, ios, n, i
        integer(int64) :: h1, h2
        character(len=:), allocatable :: bytes
        character(len=17) :: buf

        h1 = 1_int64
        h2 = 7_int64
        bytes = ""
        open (newunit=unit, file=path, access="stream", form="unformatted", status="old", action="read", iostat=ios)
        if (ios == 0) then
            inquire (unit=unit, size=n)
            deallocate (bytes)
            allocate (character(len=max(n, 0)) :: bytes)
            if (n > 0) read (unit, iostat=ios) bytes
            if (ios /= 0) bytes = ""
            close (unit)
        end if
        do i = 1, len(bytes)
            h1 = mod(h1*31_int64 + int(ichar(bytes(i:i)), int64), modulus)
            h2 = mod(h2*131_int64 + int(ichar(bytes(i:i)), int64), modulus)
        end do
        write (buf, '(z8.8, "-", z8.8)') h1, h2
        hash_text = buf
    end function file_fingerprint

end module supratrans_tasks
