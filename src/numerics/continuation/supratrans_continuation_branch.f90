!> The branch of a continuation (`supratrans_continuation`) as it is recorded in its `continuation_result`: the arrays
!> allocated, a point appended or inserted (its state, tangent, measures, and multipliers with the stability verdict
!> where they were computed), the march's stop recorded, the arrays trimmed at the end; and the multipliers of a
!> computed branch's point, for the record of the spectrum. No state of its own.
module supratrans_continuation_branch
    use supratrans_kinds, only: wp
    use supratrans_fixed_point_map, only: fixed_point_map, map_ok
    use supratrans_floquet, only: floquet_multipliers, largest_modulus, is_stable
    use supratrans_continuation_types, only: continuation_result, point_spectrum, cont_fold_found, wall_clock
    use supratrans_continuation_corrector, only: branch_point
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    implicit none
    private

    public :: branch_multipliers, allocate_branch, record_point, keep_spectrum, update_tangent, set_stop, finish

contains

    !> The Floquet multipliers at branch point `i` of a computed branch: those kept from the continuation where they
    !> were computed, else from its stored state (one Jacobian evaluation and one `dgeev`): for the record of the
    !> spectrum at a few amplitudes. `info` /= 0 when the map or LAPACK failed.
    subroutine branch_multipliers(map, res, i, wr, wi, info)
        !> The map the branch was computed with.
        class(fixed_point_map), intent(inout) :: map
        !> The branch.
        type(continuation_result), intent(in) :: res
        !> The branch point, 1 .. res%n_points.
        integer, intent(in) :: i
        !> Real parts of the multipliers.
        real(wp), allocatable, intent(out) :: wr(:)
        !> Imaginary parts of the multipliers.
        real(wp), allocatable, intent(out) :: wi(:)
        !> 0 on success.
        integer, intent(out) :: info
        real(wp), allocatable :: px(:), jac(:, :)
        integer :: status

        info = 1
        if (i < 1 .or. i > res%n_points) return
        if (allocated(res%spectra)) then
            if (size(res%spectra) >= i) then
                if (allocated(res%spectra(i)%wr)) then
                    ! computed during the continuation, from the same state: the same multipliers, bit for bit
                    wr = res%spectra(i)%wr
                    wi = res%spectra(i)%wi
                    info = 0
                    return
                end if
            end if
        end if
        allocate (px(map%dim), jac(map%dim, map%dim))
        call map%apply(res%states(:, i), res%amplitude(i), px, status, jac=jac)
        if (status /= map_ok) return
        call floquet_multipliers(jac, wr, wi, info)
    end subroutine branch_multipliers

    !> Allocate the branch arrays of `res` for `capacity` points of dimension `d` (no multipliers: max NaN, stable -1).
    subroutine allocate_branch(res, d, capacity)
        !> The result (its arrays not yet allocated).
        type(continuation_result), intent(inout) :: res
        !> Dimension d of the state x, and the most points.
        integer, intent(in) :: d, capacity
        real(wp) :: nan

        nan = ieee_value(1.0_wp, ieee_quiet_nan)
        allocate (res%amplitude(capacity), res%arclength(capacity), res%umax(capacity), res%energy(capacity), &
                  res%max_multiplier(capacity), res%residual(capacity), res%tangent_amplitude(capacity))
        allocate (res%stable(capacity), res%newton_iterations(capacity), res%exact_tangent(capacity))
        allocate (res%states(d, capacity), res%tangents(d + 1, capacity), res%spectra(capacity))
        res%max_multiplier = nan
        res%stable = -1
    end subroutine allocate_branch

    !> Append a point to the branch arrays (with its multipliers when `have_mult`), or insert it at `position`.
    subroutine record_point(map, res, pt, wr, wi, have_mult, position)
        !> The map (its `measures` of the point's orbit).
        class(fixed_point_map), intent(inout) :: map
        !> The branch.
        type(continuation_result), intent(inout) :: res
        !> The point.
        type(branch_point), intent(in) :: pt
        !> Its multipliers (read only when `have_mult`).
        real(wp), intent(in) :: wr(:), wi(:)
        !> Whether wr, wi are the point's multipliers.
        logical, intent(in) :: have_mult
        !> Where to insert it (default: appended).
        integer, intent(in), optional :: position
        integer :: i, d, n, k

        d = size(pt%y) - 1
        res%n_points = res%n_points + 1
        n = res%n_points
        i = n
        if (present(position)) i = position
        if (i < n) then
            res%amplitude(i + 1:n) = res%amplitude(i:n - 1)
            res%arclength(i + 1:n) = res%arclength(i:n - 1)
            res%umax(i + 1:n) = res%umax(i:n - 1)
            res%energy(i + 1:n) = res%energy(i:n - 1)
            res%max_multiplier(i + 1:n) = res%max_multiplier(i:n - 1)
            res%stable(i + 1:n) = res%stable(i:n - 1)
            res%newton_iterations(i + 1:n) = res%newton_iterations(i:n - 1)
            res%residual(i + 1:n) = res%residual(i:n - 1)
            res%tangent_amplitude(i + 1:n) = res%tangent_amplitude(i:n - 1)
            res%exact_tangent(i + 1:n) = res%exact_tangent(i:n - 1)
            res%states(:, i + 1:n) = res%states(:, i:n - 1)
            res%tangents(:, i + 1:n) = res%tangents(:, i:n - 1)
            do k = n, i + 1, -1
                call move_spectrum(res%spectra(k - 1), res%spectra(k))
            end do
        end if
        res%amplitude(i) = pt%y(d + 1)
        res%arclength(i) = pt%s
        call map%measures(pt%y(1:d), pt%y(d + 1), res%umax(i), res%energy(i))
        res%newton_iterations(i) = pt%iterations
        res%residual(i) = pt%residual
        res%tangent_amplitude(i) = pt%t(d + 1)
        res%exact_tangent(i) = merge(1, 0, pt%exact)
        res%states(:, i) = pt%y(1:d)
        res%tangents(:, i) = pt%t
        res%max_multiplier(i) = ieee_value(1.0_wp, ieee_quiet_nan)
        res%stable(i) = -1
        if (allocated(res%spectra(i)%wr)) deallocate (res%spectra(i)%wr, res%spectra(i)%wi)
        if (have_mult) call keep_spectrum(res, i, wr, wi)
    end subroutine record_point

    !> Keep the multipliers of recorded point `i` (and its largest modulus and stability verdict).
    subroutine keep_spectrum(res, i, wr, wi)
        !> The branch.
        type(continuation_result), intent(inout) :: res
        !> The recorded point.
        integer, intent(in) :: i
        !> Its multipliers.
        real(wp), intent(in) :: wr(:), wi(:)

        res%spectra(i)%wr = wr
        res%spectra(i)%wi = wi
        res%max_multiplier(i) = largest_modulus(wr, wi)
        res%stable(i) = merge(1, 0, is_stable(wr, wi, res%crossing_tol))
    end subroutine keep_spectrum

    !> Move a kept spectrum from one point's slot to another's.
    subroutine move_spectrum(from, to)
        type(point_spectrum), intent(inout) :: from, to

        if (allocated(to%wr)) deallocate (to%wr, to%wi)
        if (allocated(from%wr)) then
            call move_alloc(from%wr, to%wr)
            call move_alloc(from%wi, to%wi)
        end if
    end subroutine move_spectrum

    !> Replace the recorded tangent of point `i` by the exact one of `pt`.
    subroutine update_tangent(res, i, pt)
        !> The branch.
        type(continuation_result), intent(inout) :: res
        !> The recorded point.
        integer, intent(in) :: i
        !> The same point with its exact tangent.
        type(branch_point), intent(in) :: pt

        res%tangents(:, i) = pt%t
        res%tangent_amplitude(i) = pt%t(size(pt%t))
        res%exact_tangent(i) = 1
    end subroutine update_tangent

    !> Stop reason and status: a located fold makes the status `cont_fold_found` whatever ended the march.
    subroutine set_stop(res, reason)
        !> The result.
        type(continuation_result), intent(inout) :: res
        !> Why the march ended (`cont_*`).
        integer, intent(in) :: reason

        res%stop_reason = reason
        res%status = reason
        if (res%fold_index > 0) res%status = cont_fold_found
    end subroutine set_stop

    !> Trim the branch arrays to n_points and record the total time.
    subroutine finish(res, t_start)
        !> The result.
        type(continuation_result), intent(inout) :: res
        !> `wall_clock` at the start of the continuation.
        real(wp), intent(in) :: t_start
        integer :: n

        n = res%n_points
        res%amplitude = res%amplitude(1:n)
        res%arclength = res%arclength(1:n)
        res%umax = res%umax(1:n)
        res%energy = res%energy(1:n)
        res%max_multiplier = res%max_multiplier(1:n)
        res%residual = res%residual(1:n)
        res%tangent_amplitude = res%tangent_amplitude(1:n)
        res%exact_tangent = res%exact_tangent(1:n)
        res%stable = res%stable(1:n)
        res%newton_iterations = res%newton_iterations(1:n)
        res%states = res%states(:, 1:n)
        res%tangents = res%tangents(:, 1:n)
        res%spectra = res%spectra(1:n)
        res%stats%time_total = wall_clock() - t_start
    end subroutine finish

end module supratrans_continuation_branch
