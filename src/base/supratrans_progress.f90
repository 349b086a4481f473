!> Progress lines on stderr, one rule for every long piece of work: the one run of a timeseries (`simulate`) and the
!> tasks of a scene (`run_tasks`).
!>
!> A `progress_clock`, a value its caller owns (no module state: any number of runs may keep one each), says when a
!> line is due (`progress_due`): once max(every, a tenth of the wall time elapsed) seconds have passed since the
!> last line, so that the number of lines grows only with the logarithm of the work's length; never when `every` is
!> 0 (a quiet output). The rule is a pure function of the times (`line_due`), and the caller reads the clock.
!> `progress_tail` writes the part every line shares: the fraction done, the wall time elapsed and the time left at
!> the rate so far, each with no more digits than it deserves (`duration_text`); what the work is (t of T, tasks
!> done of total and what they are called) is the caller's.
!>
!> The least interval comes from one place: `progress_every_default`, or the environment variable
!> SUPRATRANS_PROGRESS_EVERY (seconds, > 0), read by `progress_every_setting` once, by the command line beside the
!> configuration (into the invocation, `supratrans_invocation`), never deep inside a run.
!>
!> The texts are of fixed length (`trim` them): the engine formats its lines while other threads run tasks, where
!> gfortran's deferred-length results are not safe (see `supratrans_strings`).
module supratrans_progress
    use supratrans_kinds, only: wp, i8
    implicit none
    private

    public :: progress_every_setting, start_progress, line_due, progress_due, progress_tail, duration_text

    !> Least wall time (s) between two progress lines unless SUPRATRANS_PROGRESS_EVERY says otherwise: a 10 s run
    !> prints two (at 4 s and 8 s), a 100 s one some eight, an hour some forty.
    real(wp), parameter, public :: progress_every_default = 4.0_wp

    !> Length of the fixed-length texts of this module (`progress_tail`, `duration_text`).
    integer, parameter, public :: progress_text_len = 64

    !> When the last progress line of a piece of work was printed: the caller's own, started with `start_progress`.
    type, public :: progress_clock
        !> Least wall time (s) between two lines; 0: no lines.
        real(wp) :: every = 0.0_wp
        !> Wall time (s, since the work started) of the last line; 0 before the first.
        real(wp) :: last = 0.0_wp
    end type progress_clock

contains

    !> The interval of the progress lines: SUPRATRANS_PROGRESS_EVERY (seconds, a finite number > 0) when set, else
    !> `progress_every_default`. Read once, where the command line reads the configuration.
    function progress_every_setting() result(every)
        real(wp) :: every
        character(len=64) :: text
        integer :: ios, stat
        real(wp) :: value

        every = progress_every_default
        call get_environment_variable("SUPRATRANS_PROGRESS_EVERY", text, status=stat)
        if (stat /= 0 .or. len_trim(text) == 0) return
        read (text, *, iostat=ios) value
        if (ios == 0) then
            if (value > 0.0_wp .and. value <= huge(1.0_wp)) every = value
        end if
    end function progress_every_setting

    !> The clock of a piece of work that starts now: lines every `every` seconds at least, none when `quiet` (or
    !> `every` <= 0).
    pure function start_progress(every, quiet) result(clock)
        !> Least wall time (s) between two lines (`progress_every_setting`).
        real(wp), intent(in) :: every
        !> The output is quiet: no lines.
        logical, intent(in) :: quiet
        type(progress_clock) :: clock

        clock%every = 0.0_wp
        if (.not. quiet .and. every > 0.0_wp) clock%every = every
    end function start_progress

    !> The rule: a line is due at `elapsed` when lines are on (`every` > 0) and max(`every`, `elapsed`/10)
    !> seconds have passed since the last, at `last`.
    pure function line_due(every, last, elapsed) result(due)
        !> Least wall time (s) between two lines (0: none).
        real(wp), intent(in) :: every
        !> Wall time (s) of the last line (0: none yet).
        real(wp), intent(in) :: last
        !> Wall time (s) elapsed since the work started.
        real(wp), intent(in) :: elapsed
        logical :: due

        due = .false.
        if (every > 0.0_wp) due = elapsed - last >= max(every, 0.1_wp*elapsed)
    end function line_due

    !> Whether a line is due at `elapsed` (`line_due`; with `final`, the work's last line, whenever lines are on);
    !> when it is, the clock records it.
    pure subroutine progress_due(clock, elapsed, due, final)
        !> The work's clock.
        type(progress_clock), intent(inout) :: clock
        !> Wall time (s) elapsed since the work started.
        real(wp), intent(in) :: elapsed
        !> A line is due now.
        logical, intent(out) :: due
        !> The work is done: its last line is due (default false).
        logical, intent(in), optional :: final

        due = line_due(clock%every, clock%last, elapsed)
        if (present(final)) due = due .or. (final .and. clock%every > 0.0_wp)
        if (due) clock%last = elapsed
    end subroutine progress_due

    !> The part every progress line shares, after what the work is: " (35%), 4.2 s elapsed, about 7.5 s left".
    !> `done` of `total` is the work done (simulated time, tasks), of which `done_before` was done before this
    !> process started (a resumed run or scene): the time left is `elapsed` times the work left over the work done
    !> here, shown only while there is work left and some was done here. The percentage is floored, so that 100% is
    !> said only of work that is done.
    pure function progress_tail(done_before, done, total, elapsed) result(text)
        !> Work done before this process started.
        real(wp), intent(in) :: done_before
        !> Work done.
        real(wp), intent(in) :: done
        !> All the work.
        real(wp), intent(in) :: total
        !> Wall time (s) elapsed in this process.
        real(wp), intent(in) :: elapsed
        character(len=progress_text_len) :: text
        real(wp) :: fraction
        character(len=8) :: percent

        fraction = 1.0_wp
        if (total > 0.0_wp) fraction = min(max(done/total, 0.0_wp), 1.0_wp)
        write (percent, "(i0)") int(100.0_wp*fraction)
        text = " (" // trim(percent) // "%), " // trim(duration_text(elapsed)) // " elapsed"
        if (done > done_before .and. done < total) text = trim(text) // ", about " &
            // trim(duration_text(elapsed*(total - done)/(done - done_before))) // " left"
    end function progress_tail

    !> A duration for a person, with the two digits an estimate deserves: "0.3 s", "7.5 s", "42 s", "2.4 min",
    !> "42 min", "3.1 h", "30 h", "2.5 days" (seconds below a minute, minutes below an hour, hours below two days).
    pure function duration_text(seconds) result(text)
        !> Seconds (a negative or NaN value is shown as 0).
        real(wp), intent(in) :: seconds
        character(len=progress_text_len) :: text
        real(wp) :: s

        s = 0.0_wp
        if (seconds > 0.0_wp) s = min(seconds, 1.0e12_wp)
        if (s < 59.5_wp) then
            text = trim(two_digits(s)) // " s"
        else if (s < 59.5_wp*60.0_wp) then
            text = trim(two_digits(s/60.0_wp)) // " min"
        else if (s < 47.5_wp*3600.0_wp) then
            text = trim(two_digits(s/3600.0_wp)) // " h"
        else
            text = trim(two_digits(s/86400.0_wp)) // " days"
        end if
    end function duration_text

    !> A value >= 0 with one decimal below 9.95, else rounded to a whole number ("0.3", "9.9", "10", "42").
    pure function two_digits(x) result(text)
        !> Value (>= 0, at most 1e12).
        real(wp), intent(in) :: x
        character(len=24) :: text
        character(len=24) :: buf

        if (x < 9.95_wp) then
            write (buf, "(f0.1)") x
            text = adjustl(buf)
            if (text(1:1) == ".") text = "0" // text
        else
            write (buf, "(i0)") nint(x, i8)
            text = adjustl(buf)
        end if
    end function two_digits

end module supratrans_progress
