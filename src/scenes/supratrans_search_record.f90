!> The result of one threshold search of the bifurcation scene, as a typed record, and its serialisation by name
!> (the journal and the part files store a task's record as named values: `search_fields` lists the names).
module supratrans_search_record
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    use supratrans_kinds, only: wp, i8
    use supratrans_status, only: certify_not_checked, certify_unchanged, certify_moved_within, certify_moved, &
                                 certify_unresolved, certify_failed, certify_status_codes
    implicit none
    private

    public :: search_fields, to_values, from_values
    !> The certification statuses (`supratrans_status`) and their codes text.
    public :: certify_not_checked, certify_unchanged, certify_moved_within, certify_moved, certify_unresolved, &
              certify_failed, certify_status_codes

    !> One threshold search: what it found, what it cost, how screening and certification went.
    type, public :: search_record
        !> The threshold (smallest transmitting grid amplitude); NaN when none.
        real(wp) :: threshold = 0.0_wp
        !> Continuum-limit threshold A_s of the curve's chain at this frequency; NaN outside the gap.
        real(wp) :: threshold_as = 0.0_wp
        !> Search status (`supratrans_threshold` codes, or the scene's -2 outside gap, -1 pending).
        integer :: status = 0
        !> Simulations run (screening + confirming).
        integer :: runs = 0
        !> Time steps of those simulations.
        integer(i8) :: steps = 0_i8
        !> Wall-clock time of the search (s).
        real(wp) :: wall_time = 0.0_wp
        !> Simulations run by the screening method.
        integer :: runs_screened = 0
        !> Simulations run by the scene's method.
        integer :: runs_confirmed = 0
        !> Of the screening runs, the quiet ones with a margin below `screen_margin` (the scene's method ran too).
        integer :: runs_doubtful = 0
        !> Time steps of the screening runs.
        integer(i8) :: steps_screened = 0_i8
        !> Time steps of the scene method's runs.
        integer(i8) :: steps_confirmed = 0_i8
        !> Threshold of the screening search alone (its bracket bisected); NaN when none (or not screened).
        real(wp) :: screen_threshold = 0.0_wp
        !> Lowest amplitude of the confirmation band; NaN when not screened.
        real(wp) :: band_low = 0.0_wp
        !> Highest amplitude of the confirmation band; NaN when not screened.
        real(wp) :: band_high = 0.0_wp
        !> Hybrid searches run (0 when not screened).
        integer :: rounds = 0
        !> Amplitudes that both methods answered, with different verdicts.
        integer :: disagreements = 0
        !> Largest distance between the threshold and such an amplitude (0 when none).
        real(wp) :: farthest_disagreement = 0.0_wp
        !> Threshold found again at dt/2 near the threshold (certify); NaN when not checked or not found.
        real(wp) :: certified_threshold = 0.0_wp
        !> Certification status (`certify_*`).
        integer :: certify_status = certify_not_checked
        !> Simulations (at dt/2) run by the certification.
        integer :: certify_runs = 0
        !> Their time steps.
        integer(i8) :: certify_steps = 0_i8
        !> Processor time of the search's thread (s): its cost on any machine, shared or not (`--costs` deals by it).
        real(wp) :: cpu_time = 0.0_wp
        !> Margin of the verdict at the grid point just below the threshold (quiet, run to T by the scene's method
        !> where screening confirmed it): 1 - max|u_n|/a beyond the detector site; NaN unless a threshold was found
        !> above amplitude_min. Small: that run nearly transmitted, the threshold is a thin verdict.
        real(wp) :: margin_below = 0.0_wp
    end type search_record

    !> Names of the record's fields, in the order of `to_values` (the journal header lists them).
    character(len=*), parameter :: search_fields(*) = [character(len=21) :: "threshold", "threshold_as", "status", &
        "runs", "steps", "wall_time", "runs_screened", "runs_confirmed", "runs_doubtful", "steps_screened", &
        "steps_confirmed", "screen_threshold", "band_low", "band_high", "rounds", "disagreements", "farthest_disagreement", &
        "certified_threshold", "certify_status", "certify_runs", "certify_steps", "cpu_time", "margin_below"]

contains

    !> The record as values in the order of `search_fields` (integers exactly representable).
    pure function to_values(r) result(values)
        !> The record.
        type(search_record), intent(in) :: r
        real(wp) :: values(size(search_fields))

        values = [r%threshold, r%threshold_as, real(r%status, wp), real(r%runs, wp), real(r%steps, wp), r%wall_time, &
                  real(r%runs_screened, wp), real(r%runs_confirmed, wp), real(r%runs_doubtful, wp), &
                  real(r%steps_screened, wp), real(r%steps_confirmed, wp), r%screen_threshold, r%band_low, r%band_high, &
                  real(r%rounds, wp), real(r%disagreements, wp), r%farthest_disagreement, r%certified_threshold, &
                  real(r%certify_status, wp), real(r%certify_runs, wp), real(r%certify_steps, wp), r%cpu_time, &
                  r%margin_below]
    end function to_values

    !> The record from values in the order of `search_fields`.
    pure function from_values(values) result(r)
        !> The values.
        real(wp), intent(in) :: values(:)
        type(search_record) :: r

        r%threshold = values(1)
        r%threshold_as = values(2)
        r%status = nint(values(3))
        r%runs = nint(values(4))
        r%steps = nint(values(5), i8)
        r%wall_time = values(6)
        r%runs_screened = nint(values(7))
        r%runs_confirmed = nint(values(8))
        r%runs_doubtful = nint(values(9))
        r%steps_screened = nint(values(10), i8)
        r%steps_confirmed = nint(values(11), i8)
        r%screen_threshold = values(12)
        r%band_low = values(13)
        r%band_high = values(14)
        r%rounds = nint(values(15))
        r%disagreements = nint(values(16))
        r%farthest_disagreement = values(17)
        r%certified_threshold = values(18)
        r%certify_status = nint(values(19))
        r%certify_runs = nint(values(20))
        r%certify_steps = nint(values(21), i8)
        r%cpu_time = values(22)
        r%margin_below = values(23)
    end function from_values


end module supratrans_search_record
