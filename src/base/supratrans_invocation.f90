!> How the engine is invoked, apart from the physics it computes: the command line's slice and cost options and
!> what `merge` hands a scene, and the interval of the progress lines. The configuration (`input_config`, the
!> namelist) says what to compute; this says which part of it this process runs and how its output (and its progress
!> on stderr) is made, and is passed beside the configuration (scenes' `run`, `supratrans_tasks::run_tasks`, the root
!> of an output file). Defaults: the whole scene, computed here.
module supratrans_invocation
    use supratrans_kinds, only: wp
    use supratrans_progress, only: progress_every_default
    implicit none
    private

    public :: engine_only

    !> The invocation options of one run of the engine.
    type, public :: invocation_type
        !> Run only slice slice_index of slice_count of the scene's tasks (command line --slice I/N; 0: all).
        integer :: slice_index = 0
        !> Number of slices the scene's tasks are split into (0: not sliced).
        integer :: slice_count = 0
        !> An earlier output of the same study whose measured per-task costs deal the slices (--costs FILE;
        !> unallocated: the estimate).
        character(len=:), allocatable :: slice_costs
        !> Compute nothing: write the partial snapshot of what the journal holds (merge --partial).
        logical :: snapshot_only = .false.
        !> For `merge`: the first part file, whose records the scene receives as its journal; the scene then computes
        !> nothing and refuses records that are not its own (unallocated: not a merge).
        character(len=:), allocatable :: merge_part
        !> For `merge`: one line per part (slice, host, start, end, wall time s, threads, commit), written to
        !> /provenance/parts of the merged file.
        character(len=:), allocatable :: merge_record
        !> For `merge`: the summed wall time (s) of the slices, the merged file's cost in place of the merge's own
        !> (< 0: not a merge).
        real(wp) :: merge_wall_time = -1.0_wp
        !> Least wall time (s) between two progress lines on stderr (`supratrans_progress`): the command line's
        !> `progress_every_setting` (SUPRATRANS_PROGRESS_EVERY), read once with the configuration; an output's
        !> `quiet` prints none.
        real(wp) :: progress_every = progress_every_default
    end type invocation_type

contains

    !> Whether this invocation's output is written by the engine alone (a slice's part file, or a snapshot): a
    !> scene returns right after `run_tasks` when this is true.
    pure function engine_only(inv) result(yes)
        !> The invocation.
        type(invocation_type), intent(in) :: inv
        logical :: yes

        yes = inv%slice_count > 0 .or. inv%snapshot_only
    end function engine_only

end module supratrans_invocation
