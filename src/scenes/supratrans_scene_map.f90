!> Scene `map` (paper Fig. 11): the total energy injected into the chain over a grid of driving frequency x
!> amplitude, for each curve (normally the two potentials, undamped and massless), with the continuum-limit
!> threshold A_s(Omega) for comparison.
!>
!> The map is the amplitude sweep of `supratrans_scene_sweep` over a second axis, the frequency
!> omega_min..omega_max by omega_step (`axis_grid`, handed to the axis base as its frequency axis): it uses that
!> module's task list, file, summary, partial file and per-run datasets (a `grid_scene`, on the axis base
!> `supratrans_axis_scene`), and adds only its axes (`/omega`, `/threshold_As`). A (curve, frequency) outside the curve's
!> band gap, Omega >= sqrt(V''(0) + m^2), is not run (unless allow_outside_gap): its entries are NaN with status
!> `status_outside_gap` (-2) and its A_s is NaN.
!>
!> The per-run datasets are Fortran arrays (namp, nomega, ncurve), which h5py reads as (ncurve, nomega, namp):
!> `d[ic-1, iw-1, ia-1]` for curve ic, frequency iw, amplitude ia (attribute `dimensions` = "curve, omega,
!> amplitude"); `/threshold_As` is (ncurve, nomega) in h5py.
module supratrans_scene_map
    use supratrans_kinds, only: wp
    use supratrans_error, only: error_type
    use supratrans_invocation, only: invocation_type
    use supratrans_scene, only: scene_budget, scene_tasks, scene_plan
    use supratrans_curves, only: curve_count
    use supratrans_limits, only: axis_points, check_axis, check_tasks, sci
    use supratrans_config, only: input_config
    use supratrans_hdf5, only: h5_file
    use supratrans_output_rows, only: write_row, map_omega, map_threshold_as
    use supratrans_chain, only: band_gap_edge, threshold_as
    use supratrans_scene_sweep, only: grid_scene, sweep_tasks, init_sweep_tasks, make_grid_tasks, write_common_axes, &
                                      axis_grid
    use, intrinsic :: ieee_arithmetic, only: ieee_value, ieee_quiet_nan
    implicit none
    private

    public :: run_map

    !> The tasks of a map: those of a sweep with a frequency axis; only the axes written differ.
    type, extends(sweep_tasks), public :: map_tasks
    contains
        !> Write `/amplitude`, `/curves/...`, `/omega` and `/threshold_As`.
        procedure :: write_axes => map_write_axes
    end type map_tasks

    !> The scene `map`: one full run per (curve, frequency, amplitude).
    type, extends(grid_scene), public :: map_scene
    contains
        !> Its tasks: curves x frequencies x amplitudes.
        procedure :: make_tasks => map_make_tasks
        !> Its axes, tasks, work and memory against the limits.
        procedure :: check_limits => map_scene_limits
        procedure :: plan => map_scene_plan
    end type map_scene

contains

    !> Run the scene `map` described by `cfg` and write `cfg%output%file` (layout in README.md, "Output"): for each
    !> curve, each frequency of the &scene axis omega_min..omega_max by omega_step inside the curve's band gap, and
    !> each amplitude of amplitude_min..amplitude_max by amplitude_step, one full run. Resumes from
    !> `<file>.journal` if a killed map left one. The scene's `run` (`supratrans_scene`), under the name the tests
    !> call.
    subroutine run_map(cfg, error, inv)
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Error, allocated on failure (bad configuration, journal of another input, unwritable files). Runs that
        !> diverge or whose Newton fails are not errors: they are recorded with their status.
        type(error_type), allocatable, intent(out) :: error
        !> How the engine is invoked (a slice, a merge: `supratrans_invocation`); default: the whole scene.
        type(invocation_type), intent(in), optional :: inv
        type(map_scene) :: scene

        call scene%run(cfg, error, inv)
    end subroutine run_map

    !> The tasks of the map: a sweep's over the frequency axis, with the map's axes.
    subroutine map_make_tasks(self, cfg, tasks, error)
        !> The scene.
        class(map_scene), intent(in) :: self
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Its tasks (`make_grid_tasks`).
        type(scene_tasks), intent(inout) :: tasks
        !> Error, allocated when the configuration is not valid or makes too many runs.
        type(error_type), allocatable, intent(out) :: error
        class(sweep_tasks), allocatable :: list

        allocate (map_tasks :: list)
        call init_sweep_tasks(list, cfg, tasks%inv, "map", "Total energy injected vs driving frequency and " &
                              // "amplitude: one full run (0..T) per curve, frequency and amplitude (paper Fig. 11)", &
                              axis_grid(cfg%scene%omega_min, cfg%scene%omega_max, cfg%scene%omega_step), .true., error)
        if (allocated(error)) return
        call make_grid_tasks(list, tasks, error)
    end subroutine map_make_tasks

    !> The axes of the map: those shared with the sweep, `/omega` and `/threshold_As` (ncurve, nomega in h5py).
    subroutine map_write_axes(self, file)
        !> The task list.
        class(map_tasks), intent(in) :: self
        !> Open output file (a failure sticks in it).
        type(h5_file), intent(inout) :: file
        real(wp) :: as(size(self%omegas), size(self%runs))
        integer :: ic, iw

        call write_common_axes(self, file)
        do ic = 1, size(self%runs)
            do iw = 1, size(self%omegas)
                if (self%omegas(iw) < band_gap_edge(self%runs(ic)%chain)) then
                    as(iw, ic) = threshold_as(self%runs(ic)%chain, self%omegas(iw))
                else
                    as(iw, ic) = ieee_value(as(iw, ic), ieee_quiet_nan)
                end if
            end do
        end do
        call write_row(file, map_omega, self%omegas)
        call write_row(file, map_threshold_as, as)
    end subroutine map_write_axes

    !> The amplitude and frequency axes, then the runs (curves x frequencies x amplitudes) and their work.
    pure subroutine map_scene_limits(self, cfg, where, budget, error)
        !> The scene.
        class(map_scene), intent(in) :: self
        !> The configuration (values already within their ranges and rules).
        type(input_config), intent(in) :: cfg
        !> Prefix of messages (the file name).
        character(len=*), intent(in) :: where
        !> Threads and memory of the machine.
        type(scene_budget), intent(in) :: budget
        !> Allocated when a limit is exceeded.
        type(error_type), allocatable, intent(out) :: error
        real(wp) :: namp, nomega
        type(scene_plan) :: p

        associate (sc => cfg%scene)
            namp = axis_points(sc%amplitude_min, sc%amplitude_max, sc%amplitude_step)
            call check_axis(namp, "amplitude_step = " // sci(sc%amplitude_step) // " makes " // sci(namp) &
                            // " amplitudes", where, error)
            if (allocated(error)) return
            nomega = axis_points(sc%omega_min, sc%omega_max, sc%omega_step)
            call check_axis(nomega, "omega_step = " // sci(sc%omega_step) // " makes " // sci(nomega) // " frequencies", &
                            where, error)
            if (allocated(error)) return
            p = map_scene_plan(self, cfg)
            call check_tasks(cfg, p%tasks, p%runs_per_task, p%steps, p%noun, where, error)
        end associate
    end subroutine map_scene_limits

    !> The runs: curves x frequencies x amplitudes, each of t_final/dt steps.
    pure function map_scene_plan(self, cfg) result(p)
        !> The scene.
        class(map_scene), intent(in) :: self
        !> The configuration (values within their ranges).
        type(input_config), intent(in) :: cfg
        type(scene_plan) :: p

        associate (sc => cfg%scene)
            p%tasks = real(curve_count(cfg), wp)*axis_points(sc%omega_min, sc%omega_max, sc%omega_step) &
                      *axis_points(sc%amplitude_min, sc%amplitude_max, sc%amplitude_step)
        end associate
        p%noun = "runs"
        p%steps = cfg%run%numerics%t_final/cfg%run%numerics%dt
    end function map_scene_plan

end module supratrans_scene_map
