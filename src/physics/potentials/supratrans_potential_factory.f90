!> The factory of the potentials (`new_potential`): the one place that names every member of the catalog.
submodule(supratrans_potential) supratrans_potential_factory
    use supratrans_potential_sine_gordon, only: sine_gordon_potential
    use supratrans_potential_klein_gordon, only: klein_gordon_potential
    use supratrans_potential_double_sine_gordon, only: double_sine_gordon_potential
    implicit none

contains

    !> The potential of a chain, with its parameters; unallocated for an unknown identifier.
    pure module subroutine new_potential(chain, potential)
        !> Chain parameters.
        type(chain_params), intent(in) :: chain
        !> The potential (reallocated).
        class(potential_type), allocatable, intent(inout) :: potential

        if (allocated(potential)) deallocate (potential)
        select case (chain%potential)
        case (sine_gordon)
            allocate (potential, source=sine_gordon_potential())
        case (klein_gordon)
            allocate (potential, source=klein_gordon_potential())
        case (double_sine_gordon)
            allocate (potential, source=double_sine_gordon_potential(eta=chain%eta))
        case default
            return          ! not in the catalog: left unallocated (`check_potential` says why)
        end select
    end subroutine new_potential

end submodule supratrans_potential_factory
