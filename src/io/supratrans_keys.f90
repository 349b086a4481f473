!> The types of the input schema (src/io/schema.toml): one namelist key (`key_spec`), one value derived from the
!> keys (`derived_spec`), and the value of a key in a configuration (`key_value`), whatever its type.
!>
!> The table itself, `key_table` of `supratrans_schema`, is generated from schema.toml; the reader, the range checks
!> and the `/parameters` writer loop over it, so that none of them names a key.
module supratrans_keys
    use supratrans_kinds, only: wp, path_len
    use supratrans_error, only: error_type, fatal_error, err_input
    implicit none
    private

    public :: set_list, list_value, input_error

    !> Value type of a key: an integer.
    integer, parameter, public :: kt_integer = 1
    !> Value type of a key: a real number (integers are accepted).
    integer, parameter, public :: kt_real = 2
    !> Value type of a key: a logical (.true., .false., T, F).
    integer, parameter, public :: kt_logical = 3
    !> Value type of a key: a name, compared in lower case, at most `name_len` characters.
    integer, parameter, public :: kt_name = 4
    !> Value type of a key: a file path, kept as written, at most `path_len` characters.
    integer, parameter, public :: kt_path = 5

    !> Length of group names.
    integer, parameter, public :: group_len = 12
    !> Length of key names.
    integer, parameter, public :: key_len = 24
    !> Length of `/parameters` attribute names.
    integer, parameter :: attribute_len = 32
    !> Length of units.
    integer, parameter :: units_len = 16
    !> Length of the text of a bound.
    integer, parameter :: bound_len = 16
    !> Length of descriptions and other texts of the table.
    integer, parameter :: text_len = 200
    !> Length of the list of scenes that use a key.
    integer, parameter :: scenes_len = 120

    !> One key of the input: where it is given, its type and count, its range, how it is stored and what it is. The
    !> table gives the first eight components in order (group, key, type, attribute, units, default, range,
    !> description), the others by name.
    type, public :: key_spec
        !> Group name, lower case, without the '&'.
        character(len=group_len) :: group = ""
        !> Key name, lower case.
        character(len=key_len) :: key = ""
        !> Value type: `kt_integer`, `kt_real`, `kt_logical`, `kt_name` or `kt_path`.
        integer :: value_type = kt_real
        !> Name of the attribute of `/parameters` that stores the key.
        character(len=attribute_len) :: attribute = ""
        !> Units of the value ("1" for counts, flags, names and dimensionless numbers).
        character(len=units_len) :: units = "1"
        !> The default, as the documentation shows it.
        character(len=text_len) :: default_text = ""
        !> The values allowed, in words (bounds, choices and the rules checked elsewhere).
        character(len=text_len) :: range_text = ""
        !> What the key is.
        character(len=text_len) :: description = ""
        !> Largest number of values (1 for a scalar key).
        integer :: max_values = 1
        !> Choice set of the allowed names (`choice_*` of `supratrans_schema`); 0 for any value.
        integer :: choices = 0
        !> The configuration holds the number of the choice, not its name.
        logical :: ids = .false.
        !> Lower bound of each value as messages show it, with its relation: "> 0", ">= 1"; blank for none.
        character(len=bound_len) :: lower = ""
        !> Upper bound, as `lower`: "<= 100"; blank for none.
        character(len=bound_len) :: upper = ""
        !> Replaces "must be >= <min>" in the message of a value out of range (blank: the default text).
        character(len=text_len) :: message = ""
        !> For a list: index of the key whose value an unset list stands for (0: none; stored empty).
        integer :: unset = 0
        !> For a key of &scene: the scenes that use it, "map, bifurcation" (blank: every scene).
        character(len=scenes_len) :: scenes = ""
    end type key_spec

    !> A value derived from the keys that `/parameters` stores next to them (linear theory of the base run).
    type, public :: derived_spec
        !> Attribute name.
        character(len=attribute_len) :: name = ""
        !> Units.
        character(len=units_len) :: units = "1"
        !> What it is.
        character(len=text_len) :: description = ""
    end type derived_spec

    !> The value of one key, whatever its type: `n` values in the component of the key's type.
    type, public :: key_value
        !> Number of values; 0 for a list that is not set.
        integer :: n = 0
        !> Values of a real key.
        real(wp), allocatable :: reals(:)
        !> Values of an integer key, or the numbers of named choices held as numbers.
        integer, allocatable :: ints(:)
        !> Value of a logical key.
        logical :: flag = .false.
        !> Values of a name or path key (blank-padded).
        character(len=path_len), allocatable :: texts(:)
    end type key_value

    !> Set a list key of a configuration from a `key_value` (unset, deallocated, when it holds no value):
    !> `call set_list(list, v)` for a `real(wp)` or default-integer allocatable list.
    interface set_list
        module procedure :: set_real_list, set_int_list
    end interface set_list

    !> The `key_value` of a list key of a configuration (`n = 0` when the list is not set): `v = list_value(list)`
    !> for a `real(wp)` or default-integer allocatable list.
    interface list_value
        module procedure :: real_list_value, int_list_value
    end interface list_value

contains

    pure subroutine set_real_list(list, v)
        real(wp), allocatable, intent(out) :: list(:)
        type(key_value), intent(in) :: v

        if (v%n > 0) list = v%reals(1:v%n)
    end subroutine set_real_list

    pure subroutine set_int_list(list, v)
        integer, allocatable, intent(out) :: list(:)
        type(key_value), intent(in) :: v

        if (v%n > 0) list = v%ints(1:v%n)
    end subroutine set_int_list

    pure type(key_value) function real_list_value(list) result(v)
        real(wp), allocatable, intent(in) :: list(:)

        if (allocated(list)) v = key_value(size(list), reals=list)
    end function real_list_value

    pure type(key_value) function int_list_value(list) result(v)
        integer, allocatable, intent(in) :: list(:)

        if (allocated(list)) v = key_value(size(list), ints=list)
    end function int_list_value

    !> The input error `<where>: &<group>: <detail>` (status `err_input`): one line naming the file, group and key.
    pure subroutine input_error(error, where, group, detail)
        !> The error to create.
        type(error_type), allocatable, intent(out) :: error
        !> The namelist file (or "configuration").
        character(len=*), intent(in) :: where
        !> Group name.
        character(len=*), intent(in) :: group
        !> What is wrong, starting with the key.
        character(len=*), intent(in) :: detail

        call fatal_error(error, where // ": &" // group // ": " // detail, err_input)
    end subroutine input_error

end module supratrans_keys
