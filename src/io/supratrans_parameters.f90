!> The `/parameters` group of every output file, written from the schema: one attribute per key of `key_table`
!> (under its `attribute` name), the values derived from them (`derived_table`), and `/parameters/schema`, the
!> table itself (name, key, type, units, default, allowed values, description of each attribute).
!>
!> Attributes: reals and integers as numbers (lists as arrays, empty when a list is not set), logicals as 0/1,
!> names and paths as strings, a list of names as one string "a, b". An unset list with an `unset` key in the
!> table (`potentials`) stores the value that stands for it (the &chain potential).
module supratrans_parameters
    use supratrans_kinds, only: wp
    use supratrans_error, only: fatal_error, err_io
    use supratrans_config, only: input_config
    use supratrans_keys, only: key_value, kt_integer, kt_real, kt_logical
    use supratrans_schema, only: key_table, derived_table, get_key, choice_names
    use supratrans_chain, only: band_gap_edge, decay_rate, threshold_as, critical_dt
    use supratrans_hdf5, only: h5_file, h5_create_group, h5_write_attr, h5_write
    implicit none
    private

    public :: write_parameters, key_attribute_text

    !> The group written.
    character(len=*), parameter :: group = "/parameters"
    !> Names of the value types `kt_integer`, `kt_real`, `kt_logical`, `kt_name`, `kt_path` (in that order).
    character(len=*), parameter :: type_names(*) = [character(len=7) :: "integer", "real", "logical", "name", "path"]

contains

    !> Write `/parameters`: every key of the input, the derived linear theory of the base run, and the schema.
    subroutine write_parameters(file, cfg)
        !> Open output file.
        type(h5_file), intent(inout) :: file
        !> The input.
        type(input_config), intent(in) :: cfg
        integer :: ik, id

        call h5_create_group(file, group, "Input parameters of the run (namelist names), and derived linear theory")
        do ik = 1, size(key_table)
            call write_key(file, cfg, ik)
        end do
        do id = 1, size(derived_table)
            call write_derived(file, cfg, id)
        end do
        call write_schema_table(file)
    end subroutine write_parameters

    !> One key as an attribute of `/parameters`.
    subroutine write_key(file, cfg, ik)
        type(h5_file), intent(inout) :: file
        type(input_config), intent(in) :: cfg
        integer, intent(in) :: ik
        type(key_value) :: v
        real(wp), allocatable :: reals(:)
        integer, allocatable :: ints(:)
        character(len=:), allocatable :: name

        name = trim(key_table(ik)%attribute)
        associate (spec => key_table(ik))
            v = get_key(cfg, ik)
            if (v%n == 0 .and. spec%unset > 0) v = get_key(cfg, spec%unset)
            ! a list as an array (empty when unset), a scalar key as a scalar
            select case (spec%value_type)
            case (kt_real)
                reals = [real(wp) ::]
                if (v%n > 0) reals = v%reals(1:v%n)
                if (spec%max_values > 1) call h5_write_attr(file, group, name, reals)
                if (spec%max_values == 1) call h5_write_attr(file, group, name, reals(1))
            case (kt_integer)
                ints = [integer ::]
                if (v%n > 0) ints = v%ints(1:v%n)
                if (spec%max_values > 1) call h5_write_attr(file, group, name, ints)
                if (spec%max_values == 1) call h5_write_attr(file, group, name, ints(1))
            case (kt_logical)
                call h5_write_attr(file, group, name, v%flag)
            case default
                call h5_write_attr(file, group, name, key_attribute_text(ik, v))
            end select
        end associate
    end subroutine write_key

    !> The text stored for a name or path key: the names joined by ", " (numbers of choices as their names).
    pure function key_attribute_text(ik, v) result(text)
        !> Index in `key_table`.
        integer, intent(in) :: ik
        !> The key's value.
        type(key_value), intent(in) :: v
        character(len=:), allocatable :: text
        integer :: i

        text = ""
        associate (names => choice_names(key_table(ik)%choices))
            do i = 1, v%n
                if (i > 1) text = text // ", "
                if (key_table(ik)%ids) then
                    if (v%ints(i) >= 1 .and. v%ints(i) <= size(names)) then
                        text = text // trim(names(v%ints(i)))
                    else
                        text = text // "unknown"
                    end if
                else
                    text = text // trim(v%texts(i))
                end if
            end do
        end associate
    end function key_attribute_text

    !> One derived value as an attribute of `/parameters`.
    subroutine write_derived(file, cfg, id)
        type(h5_file), intent(inout) :: file
        type(input_config), intent(in) :: cfg
        integer, intent(in) :: id
        real(wp) :: x
        character(len=:), allocatable :: name

        name = trim(derived_table(id)%name)
        associate (chain => cfg%run%chain, omega => cfg%run%drive%omega)
            select case (name)
            case ("band_gap_edge")
                x = band_gap_edge(chain)
            case ("lambda")
                x = decay_rate(chain, omega)
            case ("threshold_As")
                x = threshold_as(chain, omega)
            case ("critical_dt")
                x = critical_dt(chain)
            case default
                if (.not. allocated(file%error)) call fatal_error(file%error, &
                    "/parameters: no value for the derived parameter '" // name // "'", err_io)
                return
            end select
            call h5_write_attr(file, group, name, x)
        end associate
    end subroutine write_derived

    !> `/parameters/schema`: one row per attribute of `/parameters` (the keys, then the derived values).
    subroutine write_schema_table(file)
        type(h5_file), intent(inout) :: file
        character(len=*), parameter :: g = group // "/schema", dims = "parameter"
        integer, parameter :: nk = size(key_table), n = nk + size(derived_table)
        ! on the heap, not the stack (some hundred kB: a run under `ulimit -s 64` used to end in SIGSEGV here)
        character(len=len(key_table%description)), allocatable :: key(:), kind(:), default(:), allowed(:)
        integer :: i

        allocate (key(n), kind(n), default(n), allowed(n))
        key = ""
        kind = "real (derived)"
        default = ""
        allowed = ""
        do i = 1, nk
            key(i) = "&" // trim(key_table(i)%group) // " " // key_table(i)%key
            kind(i) = type_names(key_table(i)%value_type)
            if (key_table(i)%max_values > 1) kind(i) = trim(kind(i)) // " list"
            default(i) = key_table(i)%default_text
            allowed(i) = key_table(i)%range_text
        end do
        call h5_create_group(file, g, "The schema of the attributes of /parameters, one row each (src/io/schema.toml)")
        call h5_write(file, g // "/name", [character(len=len(key)) :: key_table%attribute, derived_table%name], "1", &
            "Attribute of /parameters", dims)
        call h5_write(file, g // "/key", key, "1", "The namelist group and key it comes from (empty for a derived value)", &
            dims)
        call h5_write(file, g // "/type", kind, "1", &
            "Value type: integer, real, logical, name (stored as text), path (text); lists are arrays", dims)
        call h5_write(file, g // "/units", [character(len=len(key)) :: key_table%units, derived_table%units], "1", &
            "Units of the value", dims)
        call h5_write(file, g // "/default", default, "1", "Default of the key", dims)
        call h5_write(file, g // "/allowed", allowed, "1", "Values allowed: range, choices, and the rules checked between keys", &
            dims)
        call h5_write(file, g // "/description", [key_table%description, derived_table%description], "1", "What it is", dims)
    end subroutine write_schema_table

end module supratrans_parameters
