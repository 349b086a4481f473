!> The status codes of supratrans: one set, defined here once, for what a run, a task, a threshold search and its
!> certification ended as. The numbers are those the result datasets have always stored; each dataset's attribute
!> says which of the sets it holds (`run_status_codes`, `search_status_codes`, `certify_status_codes`).
!>
!> * tasks: -2 outside_gap (not run: the driving frequency lies outside the curve's band gap), -1 not_run (not
!>   computed (yet): partial files, a work_precision dt below the method's `dt_smallest`);
!> * runs: 0 ok, 1 diverged, 2 newton_failed, 3 solver_failed, 4 invalid (every scene that stores runs);
!> * threshold searches (bifurcation `/status`): 0 found, 1 at_lower_bound, 2 none_transmits, 3 run_failed,
!>   4 bad_arguments, and the task codes -2, -1;
!> * certification of a threshold at dt/2 (bifurcation `/certify/status`): -1 not checked, 0 unchanged, 1 moved by
!>   one grid point, 2 moved more, 3 unresolved, 4 a run failed.
module supratrans_status
    use supratrans_strings, only: int_str
    implicit none
    private

    public :: run_status_name, run_status_codes, search_status_name, search_status_codes, certify_status_codes

    !> Task not run: the driving frequency lies outside the curve's band gap, Omega >= sqrt(V''(0) + m^2).
    integer, parameter, public :: status_outside_gap = -2
    !> Task not computed (yet).
    integer, parameter, public :: status_not_run = -1

    !> Run: reached its final time (or was stopped early with its outcome decided).
    integer, parameter, public :: status_ok = 0
    !> Run: blew up (non-finite values or |u_n| above the blow-up threshold).
    integer, parameter, public :: status_diverged = 1
    !> Run: Newton's method did not converge within its iteration cap.
    integer, parameter, public :: status_newton_failed = 2
    !> Run: the linear solver failed (singular tridiagonal matrix) or produced non-finite values.
    integer, parameter, public :: status_solver_failed = 3
    !> Run: could not start, its description is not runnable (no step taken).
    integer, parameter, public :: status_invalid = 4

    !> Search: the threshold was found inside (a_min, a_max].
    integer, parameter, public :: search_found = 0
    !> Search: already a_min transmits; the threshold returned is a_min and the true one may lie below it.
    integer, parameter, public :: search_at_lower_bound = 1
    !> Search: no amplitude of [a_min, a_max] that the search asked transmits; the threshold is NaN.
    integer, parameter, public :: search_none = 2
    !> Search: a run failed before its verdict (e.g. it diverged); the threshold is NaN.
    integer, parameter, public :: search_failed = 3
    !> Search: invalid arguments (resolution <= 0, coarse_step < resolution, a_max < a_min, non-finite).
    integer, parameter, public :: search_bad_arguments = 4

    !> Certification: not checked (certify off, or no threshold to check).
    integer, parameter, public :: certify_not_checked = -1
    !> Certification: at dt/2 the threshold transmits and the grid point below it does not.
    integer, parameter, public :: certify_unchanged = 0
    !> Certification: at dt/2 the threshold moved by one grid point (not more than the resolution).
    integer, parameter, public :: certify_moved_within = 1
    !> Certification: at dt/2 the threshold moved by more than the resolution (flagged).
    integer, parameter, public :: certify_moved = 2
    !> Certification: no dt/2 threshold within one coarse step of the threshold (flagged).
    integer, parameter, public :: certify_unresolved = 3
    !> Certification: a dt/2 run failed before its verdict (flagged).
    integer, parameter, public :: certify_failed = 4

contains

    !> Name of a run status ("ok", "diverged", ...; "unknown" for another number).
    pure function run_status_name(status) result(name)
        !> Run status.
        integer, intent(in) :: status
        character(len=:), allocatable :: name

        select case (status)
        case (status_ok)
            name = "ok"
        case (status_diverged)
            name = "diverged"
        case (status_newton_failed)
            name = "newton_failed"
        case (status_solver_failed)
            name = "solver_failed"
        case (status_invalid)
            name = "invalid"
        case default
            name = "unknown"
        end select
    end function run_status_name

    !> The run status codes as "code name: meaning" clauses separated by "; " (the `status_codes` attributes), with
    !> the task codes -2 outside_gap and -1 not_run when asked for.
    pure function run_status_codes(outside_gap, not_run) result(text)
        !> Include -2 outside_gap.
        logical, intent(in) :: outside_gap
        !> Include -1 not_run.
        logical, intent(in) :: not_run
        character(len=:), allocatable :: text

        text = ""
        if (outside_gap) text = text // int_str(status_outside_gap) // " outside_gap: not run, the driving " &
                                // "frequency lies outside the band gap of the curve (Omega >= sqrt(V''(0) + m^2)); "
        if (not_run) text = text // int_str(status_not_run) // " not_run: not computed yet (partial file); "
        text = text // int_str(status_ok) // " " // run_status_name(status_ok) // ": the run reached T; " &
               // int_str(status_diverged) // " " // run_status_name(status_diverged) // ": blow-up, |u_n| above " &
               // "blowup_threshold or non-finite values; " &
               // int_str(status_newton_failed) // " " // run_status_name(status_newton_failed) // ": Newton did not " &
               // "converge within newton_max_iter; " &
               // int_str(status_solver_failed) // " " // run_status_name(status_solver_failed) // ": the tridiagonal " &
               // "solver failed"
    end function run_status_codes

    !> Name of a search status, as written to output files.
    pure function search_status_name(status) result(name)
        !> Search status.
        integer, intent(in) :: status
        character(len=:), allocatable :: name

        select case (status)
        case (search_found)
            name = "found"
        case (search_at_lower_bound)
            name = "at lower bound"
        case (search_none)
            name = "none transmits"
        case (search_failed)
            name = "run failed"
        case (search_bad_arguments)
            name = "bad arguments"
        case default
            name = "unknown"
        end select
    end function search_status_name

    !> The search status codes and their meaning, one "code: meaning" clause each, separated by "; ".
    pure function search_status_codes() result(text)
        character(len=:), allocatable :: text

        text = "0: found (smallest transmitting amplitude in (a_min, a_max]); " &
               // "1: at lower bound (a_min already transmits; the threshold may lie below it); " &
               // "2: none transmits (nothing in [a_min, a_max] the coarse scan asked transmits; NaN); " &
               // "3: run failed (a run diverged or its solver failed before a verdict; NaN); " &
               // "4: bad arguments (invalid search range or steps; NaN)"
    end function search_status_codes

    !> The certification status codes and their meaning, one "code: meaning" clause each, separated by "; ".
    pure function certify_status_codes() result(text)
        character(len=:), allocatable :: text

        text = "-1: not checked (certify off, or no threshold); 0: unchanged at dt/2; " &
               // "1: moved by one grid point at dt/2 (not more than the resolution); " &
               // "2: moved by more than the resolution at dt/2 (flagged); " &
               // "3: no dt/2 threshold within one coarse step (flagged); 4: a dt/2 run failed (flagged)"
    end function certify_status_codes

end module supratrans_status
