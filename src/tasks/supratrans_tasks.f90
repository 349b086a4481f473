!> Runs the independent tasks of a scene (one simulation, or one threshold search, each) on OpenMP threads, with a
!> journal that makes a killed scene resumable and progress on stderr.
!>
!> Every finished task appends one checksummed line to the journal (`supratrans_journal`) and flushes it, so a scene
!> killed at any moment (SIGKILL, a wall-time limit) loses at most the tasks that were running. Started again, it
!> reads the journal, checks that it belongs to the same input (a fingerprint of the namelist text), keeps the lines
!> that prove whole, and runs only what is missing. Results are stored by task index, whatever thread computed them,
!> so they are identical for any thread count. A scene can be split into slices (`--slice I/N`, one per job of a
!> Slurm array), each writing a part file that `merge` joins (`supratrans_parts`): the tasks are dealt to the slices
!> largest-first by their estimated cost (`slice_owners`), so that the slices of an array end together. Within a
!> process the tasks are handed to the threads in the same order, largest first (`run_order`), so that the threads
!> end together too.
module supratrans_tasks
    use, intrinsic :: iso_fortran_env, only: error_unit, int64
    use supratrans_kinds, only: wp
    use supratrans_strings, only: int_str, real_str, int_fixed, text_fingerprint, printable
    use supratrans_progress, only: progress_clock, start_progress, progress_due, progress_tail, progress_every_default
    use supratrans_error, only: error_type, fatal_error, err_io, err_interrupted, err_input
    use supratrans_config, only: input_config, run_config, method_newton, method_linearized, method_rk4, method_rk8, &
                                 method_avf4, method_avf8
    use supratrans_system, only: remove_own_file, stop_signal, out_of_memory
    use supratrans_invocation, only: invocation_type, engine_only
    use supratrans_journal, only: journal_header, read_journal, write_journal, append_journal_line, record_binding
    use supratrans_parts, only: write_part, part_run
    use supratrans_task_list, only: task_list
    use supratrans_host, only: timestamp, host_name, build_commit
    !$ use omp_lib, only: omp_get_max_threads
    implicit none
    private

    public :: run_tasks, file_fingerprint, text_fingerprint, input_fingerprint, engine_only, slice_owners, slice_text, run_work
    public :: slice_costs, task_list, run_order

    !> Seconds between two snapshots (the progress lines: `supratrans_progress`, at the invocation's interval).
    real(wp), parameter :: snapshot_interval = 10.0_wp

contains

    !> The costs that deal the slices: the measured ones of `inv%slice_costs` (`--costs`) when given, else the
    !> estimates (`cost`). Every slice of an array computes the same ones (the same file, the same input).
    subroutine slice_costs(tasks, ntask, inv, costs, error)
        !> The tasks.
        class(task_list), intent(in) :: tasks
        !> Number of tasks.
        integer, intent(in) :: ntask
        !> The invocation (its `slice_costs` file, if any).
        type(invocation_type), intent(in) :: inv
        !> Cost of each task.
        real(wp), allocatable, intent(out) :: costs(:)
        !> Error: the file is unreadable, of another study, or lacks costs.
        type(error_type), allocatable, intent(out) :: error
        integer :: i

        if (.not. allocated(inv%slice_costs)) then
            costs = [(tasks%cost(i), i = 1, ntask)]
            return
        end if
        call tasks%measured_costs(inv%slice_costs, costs, error)
        if (allocated(error)) return
        if (size(costs) /= ntask) then
            call fatal_error(error, "--costs " // printable(inv%slice_costs) // ": " // int_str(size(costs)) &
                             // " task costs, but the scene has " // int_str(ntask) // " tasks (another study)", &
                             err_input)
        else if (.not. all(costs >= 0.0_wp .and. costs <= huge(1.0_wp))) then
            call fatal_error(error, "--costs " // printable(inv%slice_costs) // ": " // int_str(count(.not. (costs &
                             >= 0.0_wp .and. costs <= huge(1.0_wp)))) // " task(s) without a measured cost (an " &
                             // "incomplete output? use a complete one, or no --costs)", err_input)
        end if
    end subroutine slice_costs

    !> Estimated work of one run, for task costs: oscillators N x time steps T/dt x the method's work per step
    !> relative to a Newton step (measured by the benchmark on the paper-default run: a Newton step of about two
    !> iterations 1, a linearized step 0.35, a classical Runge-Kutta step 0.6, an 8th-order one 1.6; avf4 4, avf8 10).
    pure function run_work(run) result(work)
        !> The run.
        type(run_config), intent(in) :: run
        real(wp) :: work
        real(wp) :: per_step

        select case (run%numerics%method)
        case (method_newton)
            per_step = 1.0_wp
        case (method_linearized)
            per_step = 0.35_wp
        case (method_rk4)
            per_step = 0.6_wp
        case (method_rk8)
            per_step = 1.6_wp
        case (method_avf4)      ! from the work-precision run at A = 1.9 (docs/method.md): 2.5x an rk8 step
            per_step = 4.0_wp
        case (method_avf8)      ! there 6x an rk8 step
            per_step = 10.0_wp
        case default
            per_step = 1.0_wp
        end select
        work = real(max(run%chain%n, 1), wp)*max(run%numerics%t_final/run%numerics%dt, 1.0_wp)*per_step
    end function run_work

    !> Which slice of `slice_count` each task belongs to: a deterministic largest-first (LPT) assignment. The costs,
    !> rounded to 9 significant digits relative to the largest (so that the last bits of an estimate cannot change
    !> the assignment), are taken in decreasing order (ties: lower task index first), each to the slice with the
    !> least cost so far (ties: lower slice index). With equal costs this deals the tasks round-robin, task t to
    !> slice mod(t - 1, N) + 1. Negative or non-finite costs count as 0. A binary heap of the slices' loads makes it
    !> O(ntask log ntask).
    pure function slice_owners(costs, slice_count) result(owner)
        !> Estimated cost of each task.
        real(wp), intent(in) :: costs(:)
        !> Number of slices N (>= 1).
        integer, intent(in) :: slice_count
        integer :: owner(size(costs))
        integer(int64), allocatable :: key(:), load(:)
        integer, allocatable :: order(:), heap(:)
        integer :: i, t, n

        n = size(costs)
        key = cost_keys(costs)
        order = sorted_by_key(key)
        allocate (load(slice_count), heap(slice_count))
        load = 0
        heap = [(i, i = 1, slice_count)]       ! equal loads: a valid heap in slice order
        do i = 1, n
            t = order(i)
            owner(t) = heap(1)
            load(heap(1)) = load(heap(1)) + key(t)
            call sift_down(heap, load)
        end do

    end function slice_owners

    !> The order in which a process runs its tasks: largest estimated cost first (the keys of `slice_owners`; ties:
    !> lower task index first), so that the longest tasks do not start last and leave one thread working alone at
    !> the end (with equal costs: the tasks in index order). Results do not depend on it: each is stored by index.
    pure function run_order(costs) result(order)
        !> Estimated (or measured) cost of each task.
        real(wp), intent(in) :: costs(:)
        integer, allocatable :: order(:)

        order = sorted_by_key(cost_keys(costs))
    end function run_order

    !> Costs as integer keys: rounded to 9 significant digits relative to the largest, so that the last bits of an
    !> estimate move no task; negative or non-finite costs count as 0.
    pure function cost_keys(costs) result(key)
        !> The costs.
        real(wp), intent(in) :: costs(:)
        integer(int64) :: key(size(costs))
        real(wp) :: top
        integer :: i

        top = 0.0_wp
        do i = 1, size(costs)
            if (costs(i) > top .and. costs(i) <= huge(1.0_wp)) top = costs(i)
        end do
        do i = 1, size(costs)
            key(i) = 0
            if (top > 0.0_wp .and. costs(i) > 0.0_wp .and. costs(i) <= huge(1.0_wp)) then
                key(i) = nint(1.0e9_wp*costs(i)/top, int64)
            end if
        end do
    end function cost_keys

    !> Restore the heap order of `heap` (slices, least load first; ties: lower index) after its top grew.
    pure subroutine sift_down(heap, load)
        !> The slices, a binary heap but for its top.
        integer, intent(inout) :: heap(:)
        !> Load of each slice.
        integer(int64), intent(in) :: load(:)
        integer :: j, c, swap, n

        n = size(heap)
        j = 1
        do
            c = 2*j
            if (c > n) exit
            if (c < n) then
                if (before(heap(c + 1), heap(c))) c = c + 1
            end if
            if (.not. before(heap(c), heap(j))) exit
            swap = heap(j)
            heap(j) = heap(c)
            heap(c) = swap
            j = c
        end do

    contains

        pure logical function before(a, b)
            integer, intent(in) :: a, b

            before = load(a) < load(b) .or. (load(a) == load(b) .and. a < b)
        end function before

    end subroutine sift_down

    !> The task indices ordered by decreasing key, equal keys by increasing index (a stable merge sort).
    pure function sorted_by_key(key) result(order)
        !> The keys.
        integer(int64), intent(in) :: key(:)
        integer, allocatable :: order(:)
        integer, allocatable :: work(:)
        integer :: n, width, lo, mid, hi, i, j, k

        n = size(key)
        order = [(i, i = 1, n)]
        allocate (work(n))
        width = 1
        do while (width < n)
            lo = 1
            do while (lo <= n)
                mid = min(lo + width - 1, n)
                hi = min(lo + 2*width - 1, n)
                i = lo
                j = mid + 1
                do k = lo, hi
                    if (j > hi) then
                        work(k) = order(i)
                        i = i + 1
                    else if (i > mid) then
                        work(k) = order(j)
                        j = j + 1
                    else if (key(order(j)) > key(order(i))) then
                        work(k) = order(j)
                        j = j + 1
                    else
                        work(k) = order(i)
                        i = i + 1
                    end if
                end do
                lo = hi + 1
            end do
            order = work
            width = 2*width
        end do
    end function sorted_by_key

    !> Run tasks 1..ntask (those not already in the journal), in parallel over OpenMP threads. Unless `quiet`, a
    !> progress line goes to stderr after a task is journaled when one is due (`supratrans_progress`, at the interval
    !> `inv%progress_every`), and after the last: "  12/40 runs", then the fraction done, the wall time elapsed and
    !> the time left at the rate so far (`progress_tail`), the tasks weighed by their costs (those that deal the
    !> slices): the largest run first, so that a count of tasks would foretell the rest at the rate of the costliest.
    !> A task that runs long prints nothing while it runs.
    !>
    !> With `inv` given, its options apply: `--slice I/N` (`inv%slice_count` > 0) runs only the tasks
    !> `slice_owners` deals to slice I by their costs (`tasks%cost`, or with `--costs FILE` the costs measured in
    !> that earlier output, `tasks%measured_costs`) and, once they are all done, writes the part
    !> file `cfg%output%file` for `merge`
    !> (then deletes the slice's journal and partial snapshot); `inv%snapshot_only` computes nothing and writes the
    !> partial snapshot of what the journal holds. A stop signal (SIGTERM, SIGINT, SIGUSR1: see
    !> `supratrans_system`) hands out no new task: the tasks running finish and are journaled (or, if they
    !> checkpoint, stop at their checkpoint and are not: `finished`), a snapshot is
    !> written, and `error` says so with status `err_interrupted`.
    subroutine run_tasks(tasks, ntask, fields, journal, fingerprint, label, quiet, results, done, error, cfg, inv)
        !> The tasks.
        class(task_list), intent(in) :: tasks
        !> Number of tasks.
        integer, intent(in) :: ntask
        !> Names of the fields of a task's record (`values` holds them in this order; the journal names them).
        character(len=*), intent(in) :: fields(:)
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
        !> Which tasks are done (all, unless an error occurred or only a slice was asked).
        logical, allocatable, intent(out) :: done(:)
        !> Error, allocated on failure (journal unreadable or from another input, or unwritable; interrupted).
        type(error_type), allocatable, intent(out) :: error
        !> The input, for the text a part file keeps.
        type(input_config), intent(in), optional :: cfg
        !> How the engine was invoked (slice, costs, snapshot only, merge); default: the whole scene.
        type(invocation_type), intent(in), optional :: inv
        character(len=:), allocatable :: header
        real(wp), allocatable :: values(:)
        logical, allocatable :: mine(:)
        integer :: nvalues, i, ndone_start, ndone, ntodo, ios, threads, dropped, slice_index, slice_count
        integer(int64) :: clock_start, clock_rate, clock_now, binding
        real(wp) :: last_snapshot, elapsed, every, work_start, work_done, work_total
        real(wp), allocatable :: weights(:)
        logical :: snapshot_only, write_failed, written, merging, lost, due
        type(progress_clock) :: clock
        real(wp), allocatable :: costs(:)
        integer, allocatable :: order(:)
        integer :: stop_after, k
        type(part_run) :: run_record
        character(len=16) :: knob

        nvalues = size(fields)
        slice_index = 0
        slice_count = 0
        snapshot_only = .false.
        every = progress_every_default
        if (present(inv)) then
            slice_index = inv%slice_index
            slice_count = inv%slice_count
            snapshot_only = inv%snapshot_only
            every = inv%progress_every
        end if
        allocate (results(nvalues, ntask), stat=ios)
        if (ios == 0) allocate (done(ntask), stat=ios)
        if (ios == 0) allocate (mine(ntask), stat=ios)
        if (ios /= 0) then
            call fatal_error(error, journal // ": cannot allocate " // real_str(8.0_wp*real(nvalues + 1, wp) &
                             *real(ntask, wp)/1.0e9_wp, 3) // " GB for the results of " // int_str(ntask) // " " &
                             // label // " (more memory, or fewer tasks)", err_input)
            return
        end if
        results = 0.0_wp
        done = .false.
        mine = .true.
        if (slice_count > 0 .and. present(inv)) then
            call slice_costs(tasks, ntask, inv, costs, error)
            if (allocated(error)) return
            mine = slice_owners(costs, slice_count) == slice_index
        else
            costs = [(tasks%cost(i), i = 1, ntask)]
        end if
        order = run_order(costs)
        ! the progress lines weigh the tasks by their costs: run largest first, the first ones done are not a
        ! fair sample of the rest (a task of cost 0, or with all costs 0, weighs 1 in 10^9 of the largest)
        weights = real(max(cost_keys(costs), 1_int64), wp)
        header = journal_header(ntask, fields, fingerprint)
        call read_journal(journal, header, results, done, dropped, error)
        merging = .false.
        if (present(inv)) merging = allocated(inv%merge_part)
        if (merging .and. present(cfg)) then
            ! the records of merged parts: the scene's own, every one (or, merge --partial, the ones there)
            if (allocated(error)) then
                call fatal_error(error, inv%merge_part // ": its records do not fit the scene '" // trim(cfg%scene%kind) &
                                 // "' of its namelist (fields or task count of another version of supratrans: the " &
                                 // "parts' journal header is not " // header // ")", err_input)
                return
            end if
            if (.not. snapshot_only .and. (dropped > 0 .or. .not. all(done))) then
                call fatal_error(error, inv%merge_part // ": " // int_str(count(.not. done)) // " of " &
                                 // int_str(ntask) // " task records missing or damaged: merge computes nothing", &
                                 err_input)
                return
            end if
        end if
        if (allocated(error)) return
        if (snapshot_only) then
            call tasks%snapshot(results, done)
            return
        end if
        ! rewritten with the whole lines only (a new file, renamed over the old one only once it is complete)
        call write_journal(journal, header, results, done, error)
        if (allocated(error)) return
        binding = record_binding(header)      ! (not the deferred-length header itself in the parallel region)

        ! fault injection for the tests: SUPRATRANS_STOP_AFTER=k acts as a stop signal once k tasks are journaled
        stop_after = huge(1)
        call get_environment_variable("SUPRATRANS_STOP_AFTER", knob, status=ios)
        if (ios == 0) read (knob, *, iostat=ios) stop_after
        if (ios /= 0) stop_after = huge(1)
        ntodo = count(mine)
        ndone_start = count(done .and. mine)
        ndone = ndone_start
        work_total = sum(weights, mask=mine)
        work_start = sum(weights, mask=done .and. mine)
        work_done = work_start
        threads = 1
        !$ threads = omp_get_max_threads()
        call system_clock(clock_start, clock_rate)
        run_record%started = timestamp()
        clock = start_progress(every, quiet)
        last_snapshot = 0.0_wp
        write_failed = .false.
        if (.not. quiet .and. merging .and. ndone_start == ntodo) then
            ! a merge runs nothing: its records are the parts'
            write (error_unit, "(a)") "  merged " // int_str(ndone_start) // " " // label // " from the parts' " &
                // "records (none run here)"
        else if (.not. quiet) then
            write (error_unit, "(a)") "  " // int_str(ntodo) // " " // label // slice_text(slice_index, slice_count, &
                ntodo, ntask) // ", " // int_str(ndone_start) // " already done (journal " // printable(journal) // "), " &
                // int_str(threads) // " thread(s)"
            if (dropped > 0) write (error_unit, "(a)") "  " // int_str(dropped) // " journal line(s) failed their " &
                // "checksum (cut short or altered): those tasks are computed again"
            flush (error_unit)
        end if

        !$omp parallel do schedule(dynamic, 1) default(shared) private(k, i, values, clock_now, elapsed, written, lost, due)
        do k = 1, ntask
            i = order(k)
            if (done(i) .or. .not. mine(i)) cycle
            if (stop_signal() /= 0 .or. ndone - ndone_start >= stop_after .or. write_failed .or. out_of_memory()) cycle
            allocate (values(nvalues))
            call tasks%run(i, values)
            ! a run that could not allocate its arrays (this task's or another thread's) is no result: not journaled
            lost = out_of_memory()
            ! a task stopped at its checkpoint by a signal is no result either: a rerun resumes it
            if (.not. lost) lost = .not. tasks%finished(values)
            !$omp critical (supratrans_tasks_journal)
            if (.not. lost) then
                results(:, i) = values
                done(i) = .true.
                ndone = ndone + 1
                work_done = work_done + weights(i)
                if (.not. write_failed) then
                    call append_journal_line(journal, binding, i, values, written)
                    write_failed = .not. written
                end if
            end if
            call system_clock(clock_now)
            elapsed = real(clock_now - clock_start, wp)/real(clock_rate, wp)
            due = .false.
            if (.not. lost) call progress_due(clock, elapsed, due, final=ndone == ntodo)
            if (due) then
                write (error_unit, "(a)") "  " // trim(int_fixed(ndone)) // "/" // trim(int_fixed(ntodo)) // " " &
                    // label // trim(progress_tail(work_start, merge(work_total, work_done, ndone == ntodo), &
                                                   work_total, elapsed))
                flush (error_unit)
            end if
            if (elapsed - last_snapshot >= snapshot_interval .and. ndone < ntodo) then
                last_snapshot = elapsed
                call tasks%snapshot(results, done)
            end if
            !$omp end critical (supratrans_tasks_journal)
            deallocate (values)
        end do
        !$omp end parallel do
        if (write_failed) then
            call fatal_error(error, journal // ": cannot write the journal (disk full?); run again to resume from " &
                             // "the lines it holds", err_io)
            return
        end if
        if (out_of_memory()) then
            call tasks%snapshot(results, done)
            call fatal_error(error, journal // ": a run could not allocate its arrays (out of memory) after " &
                             // int_str(count(done .and. mine)) // " of " // int_str(ntodo) // " " // label &
                             // "; run again with fewer threads (OMP_NUM_THREADS) or more memory: it resumes", err_input)
            return
        end if
        if (count(done .and. mine) < ntodo) then
            call tasks%snapshot(results, done)
            call fatal_error(error, journal // ": stopped by signal " // int_str(max(stop_signal(), 0)) // " after " &
                             // int_str(count(done .and. mine)) // " of " // int_str(ntodo) // " " // label &
                             // "; run the same command again to resume", err_interrupted)
            return
        end if
        if (slice_count > 0 .and. present(cfg)) then
            call system_clock(clock_now)
            run_record%wall_time = real(clock_now - clock_start, wp)/real(clock_rate, wp)
            run_record%ended = timestamp()
            run_record%host = host_name()
            run_record%commit = build_commit()
            run_record%threads = threads
            call write_part(trim(cfg%output%file), cfg, slice_index, slice_count, header, results, done, mine, &
                            run_record, error)
            if (allocated(error)) return
            call remove_own_file(journal)
            call remove_own_file(trim(cfg%output%file) // ".partial.h5")
            if (.not. quiet) write (error_unit, "(a)") "  wrote part " // printable(trim(cfg%output%file)) &
                // slice_text(slice_index, slice_count, ntodo, ntask)
        end if
    end subroutine run_tasks

    !> The fingerprint that ties a journal to its input: that of the namelist text read, or of the file `source`,
    !> or "none" for a configuration built in code.
    function input_fingerprint(cfg) result(text)
        !> The input.
        type(input_config), intent(in) :: cfg
        character(len=:), allocatable :: text

        text = "none"
        if (allocated(cfg%fingerprint)) then
            text = cfg%fingerprint
        else if (allocated(cfg%source)) then
            text = file_fingerprint(cfg%source)
        end if
    end function input_fingerprint

    !> " (slice I of N: k of ntask tasks)", or "" when not sliced.
    pure function slice_text(slice_index, slice_count, nslice, ntask) result(text)
        !> Slice index I.
        integer, intent(in) :: slice_index
        !> Number of slices N (0: not sliced).
        integer, intent(in) :: slice_count
        !> Number of tasks of the slice (those dealt to it), and of the scene.
        integer, intent(in) :: nslice, ntask
        character(len=:), allocatable :: text

        text = ""
        if (slice_count > 0) text = " (slice " // int_str(slice_index) // " of " // int_str(slice_count) // ": " &
            // int_str(nslice) // " of " // int_str(ntask) // " tasks)"
    end function slice_text

    !> A fingerprint of a file's bytes (`text_fingerprint` of its contents; of "" if it cannot be read).
    function file_fingerprint(path) result(hash_text)
        !> File to fingerprint.
        character(len=*), intent(in) :: path
        character(len=:), allocatable :: hash_text
        integer :: unit, ios, n
        character(len=:), allocatable :: bytes

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
        hash_text = text_fingerprint(bytes)
    end function file_fingerprint

end module supratrans_tasks
