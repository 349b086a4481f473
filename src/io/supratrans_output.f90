!> What every output file holds besides its scene's results: the root attributes (code, version, scene, input file,
!> creation time), `/provenance` (`write_provenance`) and `/parameters` (every input parameter, `write_parameters`).
!> Each scene writes its own results beside them (the timeseries: `supratrans_scene_timeseries`).
module supratrans_output
    use supratrans_kinds, only: supratrans_version
    use supratrans_config, only: input_config
    use supratrans_hdf5, only: h5_file, h5_write_attr
    use supratrans_parameters, only: write_parameters
    use supratrans_provenance, only: write_provenance, timestamp
    use supratrans_invocation, only: invocation_type
    implicit none
    private

    public :: write_parameters, write_root

contains

    !> Root attributes shared by every scene (code, version, scene, description, input file, creation time) and the
    !> `/provenance` group.
    subroutine write_root(file, cfg, scene, description, inv)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The validated input.
        type(input_config), intent(in) :: cfg
        !> Scene name.
        character(len=*), intent(in) :: scene
        !> One-line description of the file's contents.
        character(len=*), intent(in) :: description
        !> How the engine was invoked (a merge records its parts); default: computed here.
        type(invocation_type), intent(in), optional :: inv

        call h5_write_attr(file, "/", "code", "supratrans")
        call h5_write_attr(file, "/", "version", supratrans_version)
        call h5_write_attr(file, "/", "scene", scene)
        call h5_write_attr(file, "/", "description", description)
        call h5_write_attr(file, "/", "input_file", cfg%source)
        call h5_write_attr(file, "/", "created", timestamp())
        call h5_write_attr(file, "/", "reference", &
            "J. E. Macias-Diaz and A. Puri, An energy-based computational method in the analysis of the " // &
            "transmission of energy in a chain of coupled oscillators")
        call write_provenance(file, cfg, inv)
    end subroutine write_root

end module supratrans_output
