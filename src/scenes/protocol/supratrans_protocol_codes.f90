!> The codes the fold protocol's outcomes are written as, in one place: /fold_fate (the fate's `fate_*`),
!> /transmission_status (the following's `follow_*`, with the continuation's status of the last branch followed)
!> and /branch_switch (the switch's `switch_*`), with the text of each dataset's `codes` attribute.
!>
!> The codes of the files are fixed (a file's meaning does not change with the code): /transmission_status shares
!> its values with the continuation's statuses (0 found, 1 .. 4 and 6 as /status says of a branch; `cont_*` of
!> `supratrans_continuation`), so the following's own outcomes that are not a branch's status are written as 7 (too
!> many branches) and 8 (a fate's watch failed); /fold_fate and /branch_switch have codes of their own, 0 where the
!> unit did not run. The units number their outcomes as they read (`supratrans_protocol_fate`,
!> `supratrans_protocol_follow`, `supratrans_protocol_switch`); only the functions here know the files' codes.
module supratrans_protocol_codes
    use supratrans_config, only: fold_protocol
    use supratrans_strings, only: int_str, real_str
    use supratrans_continuation, only: cont_fold_found, cont_no_fold, cont_newton_failed, cont_step_too_small, &
                                       cont_max_points, cont_unstable_start
    use supratrans_protocol_fate, only: fate_transmits, fate_localized, fate_failed
    use supratrans_protocol_follow, only: follow_at_push, follow_fold_transmits, follow_stairs_transmit, &
                                          follow_branch_ended, follow_too_many, follow_fate_failed
    use supratrans_protocol_switch, only: switch_supercritical, switch_subcritical, switch_side_unknown, &
                                          switch_not_found, switch_stairs, switch_no_stairs
    implicit none
    private

    public :: fold_fate_code, transmission_code, branch_switch_code, fate_codes, transmission_status_codes, &
              branch_switch_codes

    ! The codes of /fold_fate.
    !> /fold_fate: no fold, no fate (the record's default).
    integer, parameter, public :: fold_fate_none = 0
    !> /fold_fate: transmits.
    integer, parameter :: fold_fate_transmits = 1
    !> /fold_fate: localized.
    integer, parameter :: fold_fate_localized = 2
    !> /fold_fate: failed.
    integer, parameter :: fold_fate_failed = 3

    ! The codes of /transmission_status beside the continuation's statuses (`cont_*`).
    !> /transmission_status: no fold on the first branch, nothing followed (the record's default).
    integer, parameter :: transmission_none = -1
    !> /transmission_status: still localized past the folds of follow_branches branches.
    integer, parameter :: transmission_too_many = 7
    !> /transmission_status: the scheme failed while a fate was watched.
    integer, parameter :: transmission_fate_failed = 8

    ! The codes of /branch_switch.
    !> /branch_switch: no loss of stability below the fold (or no fate asked, or the stairs past it would start above
    !> the fold): the record's default.
    integer, parameter, public :: branch_switch_none = 0
    !> /branch_switch: supercritical.
    integer, parameter :: branch_switch_supercritical = 1
    !> /branch_switch: subcritical.
    integer, parameter :: branch_switch_subcritical = 2
    !> /branch_switch: the other branch was not found.
    integer, parameter :: branch_switch_failed = 3
    !> /branch_switch: stairs past a torus or a period doubling.
    integer, parameter :: branch_switch_stairs = 4
    !> /branch_switch: side unknown.
    integer, parameter :: branch_switch_side_unknown = 5

contains

    !> The /fold_fate code of a fate's outcome.
    pure integer function fold_fate_code(fate)
        !> `fate_transmits`, `fate_localized` or `fate_failed`.
        integer, intent(in) :: fate

        select case (fate)
        case (fate_transmits)
            fold_fate_code = fold_fate_transmits
        case (fate_localized)
            fold_fate_code = fold_fate_localized
        case (fate_failed)
            fold_fate_code = fold_fate_failed
        case default
            fold_fate_code = fold_fate_none
        end select
    end function fold_fate_code

    !> The /transmission_status code of where the chain transmits (the following's outcome): 0 (`cont_fold_found`)
    !> where it was found; the continuation's status of the last branch followed where that ended without a fold; 7,
    !> 8 for the following's own reasons.
    pure integer function transmission_code(outcome, ended)
        !> The outcome (`follow_*`).
        integer, intent(in) :: outcome
        !> With `follow_branch_ended`, the continuation's status of the last branch followed.
        integer, intent(in) :: ended

        select case (outcome)
        case (follow_at_push, follow_fold_transmits, follow_stairs_transmit)
            transmission_code = cont_fold_found
        case (follow_branch_ended)
            transmission_code = ended
        case (follow_too_many)
            transmission_code = transmission_too_many
        case (follow_fate_failed)
            transmission_code = transmission_fate_failed
        case default
            transmission_code = transmission_none
        end select
    end function transmission_code

    !> The /branch_switch code of the switch's outcome.
    pure integer function branch_switch_code(outcome)
        !> The outcome (`switch_*`).
        integer, intent(in) :: outcome

        select case (outcome)
        case (switch_supercritical)
            branch_switch_code = branch_switch_supercritical
        case (switch_subcritical)
            branch_switch_code = branch_switch_subcritical
        case (switch_side_unknown)
            branch_switch_code = branch_switch_side_unknown
        case (switch_not_found)
            branch_switch_code = branch_switch_failed
        case (switch_stairs)
            branch_switch_code = branch_switch_stairs
        case (switch_no_stairs)
            branch_switch_code = branch_switch_none
        case default
            branch_switch_code = branch_switch_none
        end select
    end function branch_switch_code

    !> The codes of /fold_fate as "code name: meaning" clauses (its `codes` attribute).
    pure function fate_codes(proto) result(text)
        !> The fold protocol (`fate_push`).
        type(fold_protocol), intent(in) :: proto
        character(len=:), allocatable :: text

        text = int_str(fold_fate_none) // " none: no fold; " // int_str(fold_fate_transmits) // " transmits: driven " &
            // "at A_f (1 + " // real_str(proto%fate_push, 3) // ") from the fold's state, an oscillator beyond the " &
            // "detector site passes the detector amplitude (the fold is the supratransmission threshold); " &
            // int_str(fold_fate_localized) // " localized: no transmission within /fold_fate_time (the chain " &
            // "settles on another state: the fold is not where transmission starts); " // int_str(fold_fate_failed) &
            // " failed: the scheme's implicit step did not converge"
    end function fate_codes

    !> The codes of /transmission_status as "code: meaning" clauses (its `codes` attribute).
    pure function transmission_status_codes(proto) result(text)
        !> The fold protocol (`max_branches`).
        type(fold_protocol), intent(in) :: proto
        character(len=:), allocatable :: text

        text = int_str(transmission_none) // ": no fold on the first branch (see /status); " &
            // int_str(cont_fold_found) // ": found; " &
            // int_str(cont_no_fold) // ", " // int_str(cont_newton_failed) // ", " // int_str(cont_step_too_small) &
            // ", " // int_str(cont_max_points) // ": the last branch followed ended as /status says of the first " &
            // "(no fold below amplitude_max, Newton-shooting failed from the settled state, step too small, " &
            // "points exhausted); " // int_str(cont_unstable_start) // ": the state found where the chain settled " &
            // "is unstable; " // int_str(transmission_too_many) // ": still localized past the folds of " &
            // int_str(proto%max_branches) // " branches; " // int_str(transmission_fate_failed) // ": the scheme " &
            // "failed while a fold's fate was watched"
    end function transmission_status_codes

    !> The codes of /branch_switch as "code name: meaning" clauses (its `codes` attribute).
    pure function branch_switch_codes(proto) result(text)
        !> The fold protocol (the stairs and their seed).
        type(fold_protocol), intent(in) :: proto
        character(len=:), allocatable :: text

        text = int_str(branch_switch_none) // " none: no branch point below the fold (or no fate asked); " &
            // int_str(branch_switch_supercritical) // " supercritical: the other branch leaves above the branch " &
            // "point and is followed (/transmission_fold is its fold, or a later one); " &
            // int_str(branch_switch_subcritical) // " subcritical: it leaves below; driven 1% past the branch " &
            // "point, the chain transmits (/transmission_fold is the branch point) or settles and is followed; " &
            // int_str(branch_switch_failed) // " failed: the other branch was not found; " &
            // int_str(branch_switch_stairs) // " stairs: past a torus or " &
            // "a period doubling below the fold (no branch of periodic states to switch to), the chain is driven " &
            // "from the loss's state (moved by " // real_str(proto%switch_seed, 3) // ") up in stairs of " &
            // real_str(proto%stair_height, 3) // " held " // real_str(proto%stair_time, 4) // " time units each; " &
            // "/transmission_fold is the first stair where it transmits (the one below it did not), or where " &
            // "none does below the fold, as past the fold from the last stair's state; " &
            // int_str(branch_switch_side_unknown) // " side unknown: the branch point is known only to its bracket " &
            // "(/instability_lower .. /instability_amplitude) and the other branch's first point lies inside it; " &
            // "the chain is driven 1% past the bracket's upper end, as past a subcritical one"
    end function branch_switch_codes

end module supratrans_protocol_codes
