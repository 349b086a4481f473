!> Mid-run checkpoints: the complete state of a running task, written so that a killed or preempted task resumes
!> where it stopped and ends bit-identical to an uninterrupted one.
!>
!> A task (one timeseries run, or one threshold search of many runs) opens a `checkpoint_session` with its file
!> (`<output>.checkpoint` for a timeseries, `<output>.checkpoint-<task>` for a task of a scene) and a binding text
!> (the input's fingerprint and the task). The run engine (`simulate`, given the session) then writes, every
!> `checkpoint_every` seconds of wall time and at once when a stop signal (SIGTERM, SIGINT, SIGUSR1) arrives:
!> the records of the task's runs that have finished (a search's verdicts so far: its progress) and the state of
!> the run in progress (its record as it stands: ledger sums, verdict, probes and ledger series; the stepper's step
!> index, work counters and time levels, `save_levels`). The observers keep no state of their own (it lives in the
!> record), and no method draws random numbers, so that is everything a step reads.
!>
!> A task resumed from its checkpoint replays: each `simulate` of a finished run returns its saved record without
!> computing it (the search, a deterministic function of its verdicts, asks the same questions in the same order),
!> then the run in progress continues from its saved step. A session that was interrupted answers every further
!> `simulate` at once with an interrupted record, so the task's code needs no change to stop: it ends quickly with
!> a result that its caller discards (`interrupted`).
!>
!> File: the line `supratrans-checkpoint 1`, then (`supratrans_state_buffer`) the binding text, the finished runs'
!> records, the run in progress, and the CRC-32 of every byte before it. Written like every file of supratrans: a
!> fresh temporary created with `O_CREAT | O_EXCL | O_NOFOLLOW`, fsync, rename. A checkpoint whose checksum fails
!> (cut short, altered), of another input or task, or that does not fit the run is ignored with one line
!> (`note`) and the task starts afresh: never used.
module supratrans_checkpoint
    use, intrinsic :: iso_fortran_env, only: int64
    use supratrans_kinds, only: wp, i8
    use supratrans_error, only: error_type
    use supratrans_system, only: write_bytes_atomic, remove_own_file, link_kind, path_regular, path_missing, &
                                 remove_stale_temporaries, not_own_file
    use supratrans_state_buffer, only: state_buffer, put_int, put_text, put_logical, put_buffer, get_int, get_text, &
                                       get_logical, crc32_bytes
    use supratrans_result, only: run_result, load_result
    implicit none
    private

    public :: open_session, checkpoint_due, write_checkpoint, close_session, session_active

    !> First line of a checkpoint file (its format).
    character(len=*), parameter, public :: checkpoint_magic = "supratrans-checkpoint 1" // achar(10)
    !> Steps between two looks at the wall clock (a stop signal is looked for at every step).
    integer(i8), parameter, public :: clock_stride = 256

    !> The checkpoint of one running task: its file, what it is bound to, the finished runs' records and the state
    !> read back from an earlier checkpoint.
    type, public :: checkpoint_session
        !> Checkpoint file (unallocated: checkpoints off).
        character(len=:), allocatable :: path
        !> Binding text: the input's fingerprint and the task (a checkpoint with another one is ignored).
        character(len=:), allocatable :: binding
        !> Seconds of wall time between two checkpoints (> 0).
        real(wp) :: every = 0.0_wp
        !> Clock count of the last checkpoint (or of the session's start).
        integer(int64) :: last_clock = 0
        !> Clock counts per second.
        integer(int64) :: clock_rate = 1
        !> Records of the task's finished runs, in order (`save_result`); a replay reads them from `log%pos`.
        type(state_buffer) :: log
        !> Keep the records of the finished runs (a task of several runs: a search); false for a task of one run
        !> (a timeseries), whose record would only be copied.
        logical :: log_runs = .true.
        !> Number of records in `log`.
        integer(i8) :: nlog = 0
        !> Records already handed back by the replay.
        integer(i8) :: replayed = 0
        !> The run in progress read back (its record, counters and levels), for the first run after the replay.
        type(state_buffer) :: pending
        !> `pending` holds a state to resume from.
        logical :: has_pending = .false.
        !> A stop signal arrived and the checkpoint was written (or could not be): the task stops.
        logical :: interrupted = .false.
        !> Checkpoints written by this session.
        integer :: written = 0
        !> The task resumed from a checkpoint (its finished runs and step).
        logical :: resumed = .false.
        !> One line for the log: why an existing checkpoint was ignored, or why one could not be written ("" none).
        character(len=240) :: note = ""
    end type checkpoint_session

contains

    !> Whether checkpoints are on for this session.
    pure function session_active(session) result(yes)
        !> The session.
        type(checkpoint_session), intent(in) :: session
        logical :: yes

        yes = allocated(session%path)
    end function session_active

    !> Start the checkpoints of a task: file `path`, binding text `binding`, every `every` seconds (<= 0: off, the
    !> session stays inactive). An existing checkpoint of the same binding is read back (the task then replays it);
    !> one that fails its checks is ignored and `note` says why.
    subroutine open_session(session, path, binding, every)
        !> The session (reset).
        type(checkpoint_session), intent(out) :: session
        !> Checkpoint file.
        character(len=*), intent(in) :: path
        !> Binding text (fingerprint of the input, task).
        character(len=*), intent(in) :: binding
        !> Seconds between checkpoints (<= 0: no checkpoints).
        real(wp), intent(in) :: every

        integer :: removed

        if (.not. (every > 0.0_wp)) return
        ! the temporary of a checkpoint whose writing was killed (the task runs under the output's lock)
        call remove_stale_temporaries(path, removed)
        session%path = path
        session%binding = binding
        session%every = every
        call system_clock(session%last_clock, session%clock_rate)
        call read_checkpoint(session)
    end subroutine open_session

    !> Read an existing checkpoint into the session (nothing if there is none; a note if it is refused).
    subroutine read_checkpoint(session)
        type(checkpoint_session), intent(inout) :: session
        type(state_buffer) :: buf
        type(run_result) :: scratch
        integer :: unit, ios
        integer(int64) :: n, stored, k
        character(len=:), allocatable :: bound
        character(len=len(checkpoint_magic)) :: head

        if (link_kind(session%path) == path_missing) return
        if (link_kind(session%path) /= path_regular) then
            session%note = "ignored: not a regular file (a link is never followed)"
            return
        end if
        if (len(not_own_file(session%path)) > 0) then
            ! another user's (planted since the run began): neither read, nor replaced, nor deleted; no checkpoints
            session%note = "ignored and kept (not this user's own file, or writable by others); this task runs " &
                           // "without checkpoints"
            deallocate (session%path)
            return
        end if
        open (newunit=unit, file=session%path, access="stream", form="unformatted", status="old", action="read", &
              iostat=ios)
        if (ios /= 0) then
            session%note = "ignored: cannot be read"
            return
        end if
        inquire (unit=unit, size=n)
        if (n < len(checkpoint_magic) + 8) then
            close (unit)
            session%note = "ignored: cut short"
            return
        end if
        allocate (buf%bytes(n), stat=ios)
        if (ios == 0) read (unit, iostat=ios) buf%bytes
        close (unit)
        if (ios /= 0) then
            session%note = "ignored: cannot be read"
            return
        end if
        buf%used = n
        do k = 1, len(checkpoint_magic)
            head(k:k) = buf%bytes(k)
        end do
        if (head /= checkpoint_magic) then
            session%note = "ignored: not a supratrans checkpoint of this version"
            return
        end if
        stored = transfer(buf%bytes(n - 7:n), stored)
        if (stored /= crc32_bytes(buf%bytes(1:n - 8))) then
            session%note = "ignored: fails its checksum (cut short or altered)"
            return
        end if
        buf%used = n - 8
        buf%pos = len(checkpoint_magic) + 1
        call get_text(buf, bound)
        if (.not. buf%ok .or. bound /= session%binding) then
            session%note = "ignored: written for another input or task"
            return
        end if
        call get_int(buf, session%nlog)
        call get_int(buf, n)
        if (.not. buf%ok .or. n < 0 .or. n > buf%used - buf%pos + 1 .or. session%nlog < 0) then
            session%note = "ignored: damaged"
            session%nlog = 0
            return
        end if
        allocate (session%log%bytes(max(n, 1_int64)))
        session%log%bytes(1:n) = buf%bytes(buf%pos:buf%pos + n - 1)
        session%log%used = n
        buf%pos = buf%pos + n
        ! every finished run's record must read back whole
        do k = 1, session%nlog
            call load_result(scratch, session%log, fresh=.true.)
        end do
        call get_logical(buf, session%has_pending)
        if (session%has_pending) then
            call get_int(buf, n)
            if (buf%ok .and. n >= 0 .and. n <= buf%used - buf%pos + 1) then
                allocate (session%pending%bytes(max(n, 1_int64)))
                session%pending%bytes(1:n) = buf%bytes(buf%pos:buf%pos + n - 1)
                session%pending%used = n
                buf%pos = buf%pos + n
            else
                buf%ok = .false.
            end if
        end if
        if (.not. buf%ok .or. .not. session%log%ok .or. buf%pos /= buf%used + 1) then
            session%note = "ignored: damaged"
            session%nlog = 0
            session%has_pending = .false.
            session%log = state_buffer()
            session%pending = state_buffer()
            return
        end if
        session%log%pos = 1
        session%resumed = session%nlog > 0 .or. session%has_pending
    end subroutine read_checkpoint

    !> Whether a periodic checkpoint is due (`every` seconds since the last one); call every `clock_stride` steps.
    function checkpoint_due(session) result(due)
        !> The session.
        type(checkpoint_session), intent(in) :: session
        logical :: due
        integer(int64) :: now

        call system_clock(now)
        due = real(now - session%last_clock, wp) >= session%every*real(session%clock_rate, wp)
    end function checkpoint_due

    !> Write the checkpoint: the finished runs' records and `flight`, the state of the run in progress (its record,
    !> counters and levels; `has_flight` false between runs). A failure to write leaves the earlier checkpoint and
    !> says so in `note`.
    subroutine write_checkpoint(session, flight, has_flight)
        !> The session.
        type(checkpoint_session), intent(inout) :: session
        !> The run in progress.
        type(state_buffer), intent(in) :: flight
        !> Whether a run is in progress.
        logical, intent(in) :: has_flight
        type(state_buffer) :: buf
        type(error_type), allocatable :: error
        integer(int64) :: k, crc

        allocate (buf%bytes(session%log%used + flight%used + len(session%binding) + 256))
        do k = 1, len(checkpoint_magic)
            buf%bytes(k) = checkpoint_magic(k:k)
        end do
        buf%used = len(checkpoint_magic)
        call put_text(buf, session%binding)
        call put_int(buf, session%nlog)
        call put_buffer(buf, session%log)
        call put_logical(buf, has_flight)
        if (has_flight) call put_buffer(buf, flight)
        crc = crc32_bytes(buf%bytes(1:buf%used))
        call put_int(buf, crc)
        call write_bytes_atomic(session%path, buf%bytes(1:buf%used), error)
        if (allocated(error)) then
            session%note = "could not be written (the earlier one, if any, is kept): " // error%message
        else
            session%written = session%written + 1
        end if
        call system_clock(session%last_clock)
    end subroutine write_checkpoint

    !> The task finished: delete its checkpoint (nothing when checkpoints are off).
    subroutine close_session(session)
        !> The session.
        type(checkpoint_session), intent(inout) :: session

        if (allocated(session%path)) call remove_own_file(session%path)
    end subroutine close_session

end module supratrans_checkpoint
