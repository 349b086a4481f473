!> The factory of scenes: the one place that maps the name of a kind (&scene kind) to the module that implements
!> it. A new scene is a module extending `scene_type` and one line here (and its name in the schema's choices).
!>
!> A submodule of `supratrans_scene`: the modules that validate an input call `new_scene` through its interface
!> there, while the scene modules below, which use those modules, are compiled before this one.
submodule(supratrans_scene) supratrans_scene_factory
    use supratrans_error, only: fatal_error, err_input
    use supratrans_config, only: scene_choices
    use supratrans_scene_timeseries, only: timeseries_scene
    use supratrans_scene_sweep, only: sweep_scene
    use supratrans_scene_map, only: map_scene
    use supratrans_scene_bifurcation, only: bifurcation_scene
    use supratrans_scene_workprec, only: workprec_scene
    use supratrans_scene_stability, only: stability_scene
    use supratrans_scene_continuation, only: continuation_scene
    use supratrans_scene_hysteresis, only: hysteresis_scene
    implicit none

contains

    !> The scene of kind `kind`; an error of status `err_input` naming the known kinds when there is none.
    module procedure new_scene
        character(len=:), allocatable :: known
        integer :: i

        select case (kind)
        case ("timeseries")
            allocate (timeseries_scene :: scene)
        case ("amplitude_sweep")
            allocate (sweep_scene :: scene)
        case ("map")
            allocate (map_scene :: scene)
        case ("bifurcation")
            allocate (bifurcation_scene :: scene)
        case ("work_precision")
            allocate (workprec_scene :: scene)
        case ("stability")
            allocate (stability_scene :: scene)
        case ("continuation")
            allocate (continuation_scene :: scene)
        case ("hysteresis")
            allocate (hysteresis_scene :: scene)
        case default
            known = trim(scene_choices(1))
            do i = 2, size(scene_choices)
                known = known // ", " // trim(scene_choices(i))
            end do
            call fatal_error(error, "&scene: kind = '" // kind // "': unknown scene (known: " // known // ")", err_input)
        end select
    end procedure new_scene

end submodule supratrans_scene_factory
