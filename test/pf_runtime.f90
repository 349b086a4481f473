!> Minimal stand-in for the part of pFUnit's `funit` module that supratrans' tests use.
!>
!> `test/pf2f90.py` rewrites `use funit` in each `test/test_*.pf` into `use pf_runtime` and every
!> `@assertX(args)` macro into `call assertX(args, location=pf_source_location('file.pf', line))`
!> followed by `if (pf_any_failed()) return`, as pFUnit's own preprocessor does. The generic names
!> and dummy argument names below are pFUnit's, and every specific procedure mirrors one that
!> pFUnit provides, so a test that compiles against this module also compiles against pFUnit.
!> Where pFUnit forces `message=` to be passed by keyword (logical `assertEqual`, integer order
!> comparisons) an unusable optional dummy of a private type does the same here.
!>
!> Pass/fail rules are pFUnit's:
!>
!> - `assertEqual(expected, actual[, tolerance])` on reals passes where `actual == expected` or
!>   `abs(actual - expected) <= tolerance` (tolerance 0 when absent; NaN never passes).
!> - `assertRelativelyEqual(expected, actual, tolerance)` passes where
!>   `abs(actual - expected) <= tolerance*abs(expected)`; a zero `expected` is a failure.
!> - `assertLessThan(lhs, rhs[, tolerance])` passes where `lhs < rhs + tolerance`; likewise
!>   `<=` for `assertLessThanOrEqual`, `lhs > rhs - tolerance` for `assertGreaterThan` and
!>   `lhs >= rhs - tolerance` for `assertGreaterThanOrEqual`.
!> - A scalar expected value (or lhs) is compared with every element of an array actual value.
!> - Character values are compared after removing leading and trailing blanks and tabs.
!>
!> The module also keeps the state of the running test and the counts that the generated driver
!> `test/pf_driver.f90` reports (test-only code: module state is deliberate here).
module pf_runtime
    use, intrinsic :: iso_fortran_env, only: real32, real64, int32, int64, output_unit, error_unit
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite, ieee_is_nan
    implicit none
    private

    public :: assertEqual, assertRelativelyEqual
    public :: assertTrue, assertFalse
    public :: assertLessThan, assertLessThanOrEqual, assertGreaterThan, assertGreaterThanOrEqual
    public :: assertIsFinite, assertIsNaN
    public :: pf_source_location, pf_test_procedure
    public :: pf_start_test, pf_any_failed, anyExceptions
    public :: pf_driver_init, pf_run_test, pf_driver_finish

    !> Where an assertion stands in its `.pf` file (pFUnit's `SourceLocation`).
    type :: pf_source_location
        !> Base name of the `.pf` file.
        character(len=256) :: file = ""
        !> Line of the assertion in that file.
        integer :: line = 0
    end type pf_source_location

    !> Unusable type: an optional dummy of this type forces the arguments after it to be passed
    !> by keyword, as pFUnit's `KeywordEnforcer` does.
    type :: pf_keyword_enforcer
    end type pf_keyword_enforcer

    abstract interface
        !> A test, `@before` or `@after` procedure of a test module.
        subroutine pf_test_procedure()
        end subroutine pf_test_procedure
    end interface

    !> Comparison operators of the order assertions.
    integer, parameter :: op_lt = 1, op_le = 2, op_gt = 3, op_ge = 4

    !> `module::test` name of the running test.
    character(len=:), allocatable :: current_name
    !> Number of failed assertions in the running test.
    integer :: current_failures = 0
    !> Description of the first failed assertion of the running test.
    character(len=:), allocatable :: first_failure
    !> Only tests whose lower-case `module::test` name contains this text run (unallocated: all).
    character(len=:), allocatable :: test_filter
    !> Tests run so far that passed and that failed.
    integer :: n_passed = 0, n_failed = 0

    !> pFUnit's `assertEqual`: see the specific procedures for the supported types.
    interface assertEqual
        module procedure assert_equal_r64s_r64s
        module procedure assert_equal_r64s_r64s_tol64
        module procedure assert_equal_r64s_r64s_tol32
        module procedure assert_equal_i32s_r64s
        module procedure assert_equal_i32s_r64s_tol64
        module procedure assert_equal_i32s_r64s_tol32
        module procedure assert_equal_r64s_r64v
        module procedure assert_equal_r64s_r64v_tol64
        module procedure assert_equal_r64s_r64v_tol32
        module procedure assert_equal_r64v_r64v
        module procedure assert_equal_r64v_r64v_tol64
        module procedure assert_equal_r64v_r64v_tol32
        module procedure assert_equal_i32s_r64v
        module procedure assert_equal_i32s_r64v_tol64
        module procedure assert_equal_i32s_r64v_tol32
        module procedure assert_equal_i32v_r64v
        module procedure assert_equal_i32v_r64v_tol64
        module procedure assert_equal_i32v_r64v_tol32
        module procedure assert_equal_i32s_i32s
        module procedure assert_equal_i32s_i32v
        module procedure assert_equal_i32v_i32v
        module procedure assert_equal_i32s_i64s
        module procedure assert_equal_i64s_i64s
        module procedure assert_equal_i32s_i64v
        module procedure assert_equal_i32v_i64v
        module procedure assert_equal_i64s_i64v
        module procedure assert_equal_i64v_i64v
        module procedure assert_equal_ls_ls
        module procedure assert_equal_ls_lv
        module procedure assert_equal_lv_lv
        module procedure assert_equal_c_c
    end interface assertEqual

    !> pFUnit's `assertRelativelyEqual`: see the specific procedures for the supported types.
    interface assertRelativelyEqual
        module procedure assert_rel_equal_r64s_r64s_tol64
        module procedure assert_rel_equal_r64s_r64s_tol32
        module procedure assert_rel_equal_r64s_r64v_tol64
        module procedure assert_rel_equal_r64s_r64v_tol32
        module procedure assert_rel_equal_r64v_r64v_tol64
        module procedure assert_rel_equal_r64v_r64v_tol32
    end interface assertRelativelyEqual

    !> pFUnit's `assertLessThan`: see the specific procedures for the supported types.
    interface assertLessThan
        module procedure assert_less_than_r64s_r64s
        module procedure assert_less_than_r64s_r64s_tol64
        module procedure assert_less_than_r64s_r64v
        module procedure assert_less_than_r64s_r64v_tol64
        module procedure assert_less_than_r64v_r64v
        module procedure assert_less_than_r64v_r64v_tol64
        module procedure assert_less_than_i32s_i32s
        module procedure assert_less_than_i32s_i32v
        module procedure assert_less_than_i32v_i32v
        module procedure assert_less_than_i64s_i64s
    end interface assertLessThan

    !> pFUnit's `assertLessThanOrEqual`: see the specific procedures for the supported types.
    interface assertLessThanOrEqual
        module procedure assert_less_equal_r64s_r64s
        module procedure assert_less_equal_r64s_r64s_tol64
        module procedure assert_less_equal_r64s_r64v
        module procedure assert_less_equal_r64s_r64v_tol64
        module procedure assert_less_equal_r64v_r64v
        module procedure assert_less_equal_r64v_r64v_tol64
        module procedure assert_less_equal_i32s_i32s
        module procedure assert_less_equal_i32s_i32v
        module procedure assert_less_equal_i32v_i32v
        module procedure assert_less_equal_i64s_i64s
    end interface assertLessThanOrEqual

    !> pFUnit's `assertGreaterThan`: see the specific procedures for the supported types.
    interface assertGreaterThan
        module procedure assert_greater_than_r64s_r64s
        module procedure assert_greater_than_r64s_r64s_tol64
        module procedure assert_greater_than_r64s_r64v
        module procedure assert_greater_than_r64s_r64v_tol64
        module procedure assert_greater_than_r64v_r64v
        module procedure assert_greater_than_r64v_r64v_tol64
        module procedure assert_greater_than_i32s_i32s
        module procedure assert_greater_than_i32s_i32v
        module procedure assert_greater_than_i32v_i32v
        module procedure assert_greater_than_i64s_i64s
    end interface assertGreaterThan

    !> pFUnit's `assertGreaterThanOrEqual`: see the specific procedures for the supported types.
    interface assertGreaterThanOrEqual
        module procedure assert_greater_equal_r64s_r64s
        module procedure assert_greater_equal_r64s_r64s_tol64
        module procedure assert_greater_equal_r64s_r64v
        module procedure assert_greater_equal_r64s_r64v_tol64
        module procedure assert_greater_equal_r64v_r64v
        module procedure assert_greater_equal_r64v_r64v_tol64
        module procedure assert_greater_equal_i32s_i32s
        module procedure assert_greater_equal_i32s_i32v
        module procedure assert_greater_equal_i32v_i32v
        module procedure assert_greater_equal_i64s_i64s
    end interface assertGreaterThanOrEqual

    !> pFUnit's `assertIsFinite`: see the specific procedures for the supported types.
    interface assertIsFinite
        module procedure assert_is_finite_r64
        module procedure assert_is_finite_r32
    end interface assertIsFinite

    !> pFUnit's `assertIsNaN`: see the specific procedures for the supported types.
    interface assertIsNaN
        module procedure assert_is_nan_r64
        module procedure assert_is_nan_r32
    end interface assertIsNaN

    !> pFUnit's `assertTrue`: see the specific procedures for the supported types.
    interface assertTrue
        module procedure assert_true_s
        module procedure assert_true_v
    end interface assertTrue

    !> pFUnit's `assertFalse`: see the specific procedures for the supported types.
    interface assertFalse
        module procedure assert_false_s
        module procedure assert_false_v
    end interface assertFalse

contains

    !> Start a test: forget the failures of the previous one.
    subroutine pf_start_test(name)
        !> `module::test` name of the test.
        character(len=*), intent(in) :: name

        current_name = name
        current_failures = 0
        first_failure = ""
    end subroutine pf_start_test

    !> Whether an assertion of the running test has failed.
    logical function pf_any_failed()
        pf_any_failed = current_failures > 0
    end function pf_any_failed

    !> pFUnit's name of `pf_any_failed`, for helper procedures written in pFUnit style.
    logical function anyExceptions()
        anyExceptions = current_failures > 0
    end function anyExceptions

    !> Read the optional test filter (first command-line argument) and reset the counts.
    subroutine pf_driver_init()
        integer :: length, status

        n_passed = 0
        n_failed = 0
        if (allocated(test_filter)) deallocate(test_filter)
        call get_command_argument(1, length=length, status=status)
        if (status == 0 .and. length > 0) then
            allocate(character(len=length) :: test_filter)
            call get_command_argument(1, test_filter)
            test_filter = to_lower(trim(test_filter))
        end if
    end subroutine pf_driver_init

    !> Run one test unless the filter excludes it: `before`, then, if `before` did not fail, the
    !> test and `after` (also when the test failed), as pFUnit's `TestCase%runBare` does; count it
    !> and print one `FAIL` line when it failed.
    subroutine pf_run_test(module_name, test_name, test, before, after)
        !> Name of the test module.
        character(len=*), intent(in) :: module_name
        !> Name of the test procedure.
        character(len=*), intent(in) :: test_name
        !> The test procedure.
        procedure(pf_test_procedure) :: test
        !> The module's `@before` procedure, if any.
        procedure(pf_test_procedure), optional :: before
        !> The module's `@after` procedure, if any.
        procedure(pf_test_procedure), optional :: after

        character(len=:), allocatable :: name

        name = module_name // "::" // test_name
        if (allocated(test_filter)) then
            if (index(to_lower(name), test_filter) == 0) return
        end if
        call pf_start_test(name)
        if (present(before)) call before()
        if (.not. pf_any_failed()) then
            call test()
            if (present(after)) call after()
        end if
        if (pf_any_failed()) then
            n_failed = n_failed + 1
            if (current_failures > 1) then
                write(output_unit, "(a, i0, a)") "FAIL " // name // first_failure // " (and ", &
                    current_failures - 1, " more)"
            else
                write(output_unit, "(a)") "FAIL " // name // first_failure
            end if
            flush(output_unit)
        else
            n_passed = n_passed + 1
        end if
    end subroutine pf_run_test

    !> Print the closing line `fortran: N passed, M failed`; stop with an error if M > 0.
    subroutine pf_driver_finish()
        if (allocated(test_filter)) then
            if (n_passed + n_failed == 0) then
                write(error_unit, "(a)") 'pf_driver: no test name contains "' // test_filter // '"'
            end if
        end if
        write(output_unit, "(a, i0, a, i0, a)") "fortran: ", n_passed, " passed, ", n_failed, " failed"
        flush(output_unit)
        if (n_failed > 0) error stop 1
    end subroutine pf_driver_finish

    !> Record a failed assertion of the running test.
    subroutine record_failure(text, message, location)
        !> What failed, e.g. `assertEqual: expected 1.0 but found 1.1`.
        character(len=*), intent(in) :: text
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is.
        type(pf_source_location), intent(in), optional :: location

        current_failures = current_failures + 1
        if (current_failures > 1) return
        first_failure = ""
        if (present(location)) then
            first_failure = " (" // trim(location%file) // ":" // int_to_str(int(location%line, int64)) // ")"
        end if
        first_failure = first_failure // ": " // text
        if (present(message)) then
            if (len_trim(message) > 0) first_failure = first_failure // " -- " // trim(message)
        end if
    end subroutine record_failure

    !> Record a failure when the sizes of the expected and actual arrays differ.
    logical function sizes_differ(name, n_expected, n_actual, message, location)
        !> Name of the assertion.
        character(len=*), intent(in) :: name
        !> Size of the expected value (or lhs).
        integer, intent(in) :: n_expected
        !> Size of the actual value (or rhs).
        integer, intent(in) :: n_actual
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is.
        type(pf_source_location), intent(in), optional :: location

        sizes_differ = n_expected /= n_actual
        if (sizes_differ) then
            call record_failure(name // ": arrays not conformable: expected size " &
                // int_to_str(int(n_expected, int64)) // " but found size " &
                // int_to_str(int(n_actual, int64)), message, location)
        end if
    end function sizes_differ

    !> Text ` at index i` for array assertions, empty for scalars.
    function index_text(is_array, i) result(text)
        !> Whether the assertion is on arrays.
        logical, intent(in) :: is_array
        !> Index of the first failing element.
        integer, intent(in) :: i
        character(len=:), allocatable :: text

        text = ""
        if (is_array) text = " at index " // int_to_str(int(i, int64))
    end function index_text

    !> Check of `assertTrue` and `assertFalse`.
    subroutine check_condition(condition, name, message, location)
        !> Whether the assertion holds.
        logical, intent(in) :: condition
        !> Name of the assertion.
        character(len=*), intent(in) :: name
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is.
        type(pf_source_location), intent(in), optional :: location

        if (condition) return
        if (name == "assertTrue") then
            call record_failure("assertTrue: condition is .false.", message, location)
        else
            call record_failure("assertFalse: condition is .true.", message, location)
        end if
    end subroutine check_condition

    !> Check of `assertEqual` on reals: element i passes if equal or within `tolerance`.
    subroutine check_equal_real(expected, actual, tolerance, has_tolerance, is_array, message, location)
        !> Expected values (a scalar is spread to the size of `actual`).
        real(real64), intent(in) :: expected(:)
        !> Actual values.
        real(real64), intent(in) :: actual(:)
        !> Absolute tolerance (0 when the user gave none).
        real(real64), intent(in) :: tolerance
        !> Whether the user gave a tolerance (only changes the message).
        logical, intent(in) :: has_tolerance
        !> Whether the actual value is an array (only changes the message).
        logical, intent(in) :: is_array
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is.
        type(pf_source_location), intent(in), optional :: location

        character(len=:), allocatable :: detail
        integer :: i

        if (sizes_differ("assertEqual", size(expected), size(actual), message, location)) return
        do i = 1, size(actual)
            if (same_real(expected(i), actual(i))) cycle
            if (abs(actual(i) - expected(i)) <= tolerance) cycle
            detail = "difference " // real_to_str(actual(i) - expected(i))
            if (has_tolerance) detail = detail // ", tolerance " // real_to_str(tolerance)
            call record_failure("assertEqual: expected " // real_to_str(expected(i)) // " but found " &
                // real_to_str(actual(i)) // index_text(is_array, i) // " (" // detail // ")", message, location)
            return
        end do
    end subroutine check_equal_real

    !> Check of `assertRelativelyEqual`: element i passes if
    !> `abs(actual(i) - expected(i)) <= tolerance*abs(expected(i))`.
    subroutine check_relatively_equal(expected, actual, tolerance, is_array, message, location)
        !> Expected values (a scalar is spread to the size of `actual`).
        real(real64), intent(in) :: expected(:)
        !> Actual values.
        real(real64), intent(in) :: actual(:)
        !> Relative tolerance.
        real(real64), intent(in) :: tolerance
        !> Whether the actual value is an array (only changes the message).
        logical, intent(in) :: is_array
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is.
        type(pf_source_location), intent(in), optional :: location

        integer :: i

        if (sizes_differ("assertRelativelyEqual", size(expected), size(actual), message, location)) return
        do i = 1, size(actual)
            if (abs(expected(i)) <= 0.0_real64) then
                call record_failure("assertRelativelyEqual: expected value is zero" // index_text(is_array, i) &
                    // ", relative difference undefined", message, location)
                return
            end if
        end do
        do i = 1, size(actual)
            if (abs(actual(i) - expected(i)) <= tolerance*abs(expected(i))) cycle
            call record_failure("assertRelativelyEqual: expected " // real_to_str(expected(i)) // " but found " &
                // real_to_str(actual(i)) // index_text(is_array, i) // " (relative difference " &
                // real_to_str((actual(i) - expected(i))/expected(i)) // ", tolerance " &
                // real_to_str(tolerance) // ")", message, location)
            return
        end do
    end subroutine check_relatively_equal

    !> Check of the order assertions on reals, with pFUnit's tolerance rule.
    subroutine check_order_real(op, lhs, rhs, tolerance, is_array, message, location)
        !> One of `op_lt`, `op_le`, `op_gt`, `op_ge`.
        integer, intent(in) :: op
        !> Left-hand values (a scalar is spread to the size of `rhs`).
        real(real64), intent(in) :: lhs(:)
        !> Right-hand values.
        real(real64), intent(in) :: rhs(:)
        !> Tolerance (0 when the user gave none).
        real(real64), intent(in) :: tolerance
        !> Whether `rhs` is an array (only changes the message).
        logical, intent(in) :: is_array
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is.
        type(pf_source_location), intent(in), optional :: location

        character(len=:), allocatable :: detail
        logical :: holds
        integer :: i

        if (sizes_differ(order_name(op), size(lhs), size(rhs), message, location)) return
        do i = 1, size(rhs)
            select case (op)
            case (op_lt)
                holds = lhs(i) < rhs(i) + tolerance
            case (op_le)
                holds = lhs(i) <= rhs(i) + tolerance
            case (op_gt)
                holds = lhs(i) > rhs(i) - tolerance
            case default
                holds = lhs(i) >= rhs(i) - tolerance
            end select
            if (holds) cycle
            detail = ""
            if (tolerance > 0.0_real64) detail = " (tolerance " // real_to_str(tolerance) // ")"
            call record_failure(order_name(op) // ": " // real_to_str(lhs(i)) // " is not " // order_words(op) &
                // " " // real_to_str(rhs(i)) // index_text(is_array, i) // detail, message, location)
            return
        end do
    end subroutine check_order_real

    !> Check of the order assertions on integers.
    subroutine check_order_int(op, lhs, rhs, is_array, message, location)
        !> One of `op_lt`, `op_le`, `op_gt`, `op_ge`.
        integer, intent(in) :: op
        !> Left-hand values (a scalar is spread to the size of `rhs`).
        integer(int64), intent(in) :: lhs(:)
        !> Right-hand values.
        integer(int64), intent(in) :: rhs(:)
        !> Whether `rhs` is an array (only changes the message).
        logical, intent(in) :: is_array
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is.
        type(pf_source_location), intent(in), optional :: location

        logical :: holds
        integer :: i

        if (sizes_differ(order_name(op), size(lhs), size(rhs), message, location)) return
        do i = 1, size(rhs)
            select case (op)
            case (op_lt)
                holds = lhs(i) < rhs(i)
            case (op_le)
                holds = lhs(i) <= rhs(i)
            case (op_gt)
                holds = lhs(i) > rhs(i)
            case default
                holds = lhs(i) >= rhs(i)
            end select
            if (holds) cycle
            call record_failure(order_name(op) // ": " // int_to_str(lhs(i)) // " is not " // order_words(op) &
                // " " // int_to_str(rhs(i)) // index_text(is_array, i), message, location)
            return
        end do
    end subroutine check_order_int

    !> pFUnit name of an order assertion.
    function order_name(op) result(name)
        !> One of `op_lt`, `op_le`, `op_gt`, `op_ge`.
        integer, intent(in) :: op
        character(len=:), allocatable :: name

        select case (op)
        case (op_lt)
            name = "assertLessThan"
        case (op_le)
            name = "assertLessThanOrEqual"
        case (op_gt)
            name = "assertGreaterThan"
        case default
            name = "assertGreaterThanOrEqual"
        end select
    end function order_name

    !> The relation an order assertion asks for, in words.
    function order_words(op) result(words)
        !> One of `op_lt`, `op_le`, `op_gt`, `op_ge`.
        integer, intent(in) :: op
        character(len=:), allocatable :: words

        select case (op)
        case (op_lt)
            words = "less than"
        case (op_le)
            words = "less than or equal to"
        case (op_gt)
            words = "greater than"
        case default
            words = "greater than or equal to"
        end select
    end function order_words

    !> Check of `assertEqual` on integers.
    subroutine check_equal_int(expected, actual, is_array, message, location)
        !> Expected values (a scalar is spread to the size of `actual`).
        integer(int64), intent(in) :: expected(:)
        !> Actual values.
        integer(int64), intent(in) :: actual(:)
        !> Whether the actual value is an array (only changes the message).
        logical, intent(in) :: is_array
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is.
        type(pf_source_location), intent(in), optional :: location

        integer :: i

        if (sizes_differ("assertEqual", size(expected), size(actual), message, location)) return
        do i = 1, size(actual)
            if (expected(i) == actual(i)) cycle
            call record_failure("assertEqual: expected " // int_to_str(expected(i)) // " but found " &
                // int_to_str(actual(i)) // index_text(is_array, i), message, location)
            return
        end do
    end subroutine check_equal_int

    !> Check of `assertEqual` on logicals (`.eqv.`).
    subroutine check_equal_logical(expected, actual, is_array, message, location)
        !> Expected values (a scalar is spread to the size of `actual`).
        logical, intent(in) :: expected(:)
        !> Actual values.
        logical, intent(in) :: actual(:)
        !> Whether the actual value is an array (only changes the message).
        logical, intent(in) :: is_array
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is.
        type(pf_source_location), intent(in), optional :: location

        integer :: i

        if (sizes_differ("assertEqual", size(expected), size(actual), message, location)) return
        do i = 1, size(actual)
            if (expected(i) .eqv. actual(i)) cycle
            call record_failure("assertEqual: expected " // logical_to_str(expected(i)) // " but found " &
                // logical_to_str(actual(i)) // index_text(is_array, i), message, location)
            return
        end do
    end subroutine check_equal_logical

    !> Check of `assertEqual` on character values, ignoring leading and trailing blanks and tabs.
    subroutine check_equal_string(expected, found, message, location)
        !> Expected text.
        character(len=*), intent(in) :: expected
        !> Actual text.
        character(len=*), intent(in) :: found
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is.
        type(pf_source_location), intent(in), optional :: location

        character(len=:), allocatable :: e, f
        integer :: i

        e = strip_blanks(expected)
        f = strip_blanks(found)
        if (len(e) == len(f)) then
            if (e == f) return
        end if
        do i = 1, min(len(e), len(f))
            if (e(i:i) /= f(i:i)) exit
        end do
        call record_failure('assertEqual: expected "' // e // '" but found "' // f &
            // '" (first difference at character ' // int_to_str(int(i, int64)) // ")", message, location)
    end subroutine check_equal_string

    !> Check of `assertIsFinite`.
    subroutine check_is_finite(x, message, location)
        !> The value.
        real(real64), intent(in) :: x
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is.
        type(pf_source_location), intent(in), optional :: location

        if (ieee_is_finite(x)) return
        call record_failure("assertIsFinite: " // real_to_str(x) // " is not finite", message, location)
    end subroutine check_is_finite

    !> Check of `assertIsNaN`.
    subroutine check_is_nan(x, message, location)
        !> The value.
        real(real64), intent(in) :: x
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is.
        type(pf_source_location), intent(in), optional :: location

        if (ieee_is_nan(x)) return
        call record_failure("assertIsNaN: " // real_to_str(x) // " is not NaN", message, location)
    end subroutine check_is_nan

    !> Whether two reals are equal (infinities of the same sign included, NaN excluded), without
    !> comparing reals with `==` (which `-Wcompare-reals` flags).
    elemental logical function same_real(x, y)
        !> First value.
        real(real64), intent(in) :: x
        !> Second value.
        real(real64), intent(in) :: y

        same_real = .not. (ieee_is_nan(x) .or. ieee_is_nan(y) .or. x < y .or. x > y)
    end function same_real

    !> Shortest decimal text (up to 17 significant digits) that reads back as `x`.
    function real_to_str(x) result(text)
        !> The value.
        real(real64), intent(in) :: x
        character(len=:), allocatable :: text

        character(len=48) :: buffer
        character(len=16) :: form
        character(len=:), allocatable :: digits
        real(real64) :: y
        integer :: n, e_pos, exponent, iostat
        logical :: negative

        if (ieee_is_nan(x)) then
            text = "NaN"
            return
        else if (.not. ieee_is_finite(x)) then
            text = merge("-Infinity", "+Infinity", x < 0.0_real64)
            return
        end if
        do n = 1, 17
            write(form, "(a, i0, a)") "(es48.", n - 1, "e4)"
            write(buffer, form) x
            read(buffer, *, iostat=iostat) y
            if (iostat == 0 .and. same_real(x, y)) exit
        end do
        buffer = adjustl(buffer)
        negative = buffer(1:1) == "-"
        if (negative) buffer = buffer(2:)
        e_pos = index(buffer, "E")
        read(buffer(e_pos + 1:), *) exponent
        ! Significant digits without the decimal point, trailing zeros dropped.
        digits = buffer(1:1) // buffer(3:e_pos - 1)
        do while (len(digits) > 1)
            if (digits(len(digits):len(digits)) /= "0") exit
            digits = digits(1:len(digits) - 1)
        end do
        if (exponent >= 0 .and. exponent <= 6) then
            if (len(digits) <= exponent + 1) then
                text = digits // repeat("0", exponent + 1 - len(digits)) // ".0"
            else
                text = digits(1:exponent + 1) // "." // digits(exponent + 2:)
            end if
        else if (exponent < 0 .and. exponent >= -4) then
            text = "0." // repeat("0", -exponent - 1) // digits
        else if (len(digits) == 1) then
            text = digits // ".0e" // int_to_str(int(exponent, int64))
        else
            text = digits(1:1) // "." // digits(2:) // "e" // int_to_str(int(exponent, int64))
        end if
        if (negative) text = "-" // text
    end function real_to_str

    !> Decimal text of an integer.
    function int_to_str(i) result(text)
        !> The value.
        integer(int64), intent(in) :: i
        character(len=:), allocatable :: text

        character(len=24) :: buffer

        write(buffer, "(i0)") i
        text = trim(buffer)
    end function int_to_str

    !> `.true.` or `.false.`.
    function logical_to_str(l) result(text)
        !> The value.
        logical, intent(in) :: l
        character(len=:), allocatable :: text

        if (l) then
            text = ".true."
        else
            text = ".false."
        end if
    end function logical_to_str

    !> `s` without leading and trailing blanks and tabs (pFUnit's `trimAll`).
    function strip_blanks(s) result(stripped)
        !> The text.
        character(len=*), intent(in) :: s
        character(len=:), allocatable :: stripped

        integer :: first, last

        first = 1
        do while (first <= len(s))
            if (s(first:first) /= " " .and. s(first:first) /= achar(9)) exit
            first = first + 1
        end do
        last = len(s)
        do while (last >= first)
            if (s(last:last) /= " " .and. s(last:last) /= achar(9)) exit
            last = last - 1
        end do
        stripped = s(first:last)
    end function strip_blanks

    !> `s` in lower case (ASCII).
    function to_lower(s) result(lower)
        !> The text.
        character(len=*), intent(in) :: s
        character(len=len(s)) :: lower

        integer :: i, code

        do i = 1, len(s)
            code = iachar(s(i:i))
            if (code >= iachar("A") .and. code <= iachar("Z")) then
                lower(i:i) = achar(code + iachar("a") - iachar("A"))
            else
                lower(i:i) = s(i:i)
            end if
        end do
    end function to_lower

    ! ------------------------------------------------------------------------------------------
    ! Specific procedures of the generic assertions: one per supported combination of types,
    ! kinds and ranks, each converting its arguments for one of the checks above.
    ! ------------------------------------------------------------------------------------------

    !> assertEqual(expected: real64, actual: real64) without tolerance.
    subroutine assert_equal_r64s_r64s(expected, actual, message, location)
        real(real64), intent(in) :: expected
        real(real64), intent(in) :: actual
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real([expected], [actual], 0.0_real64, .false., .false., message, location)
    end subroutine assert_equal_r64s_r64s

    !> assertEqual(expected: real64, actual: real64, tolerance: real64).
    subroutine assert_equal_r64s_r64s_tol64(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected
        real(real64), intent(in) :: actual
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real([expected], [actual], tolerance, .true., .false., message, location)
    end subroutine assert_equal_r64s_r64s_tol64

    !> assertEqual(expected: real64, actual: real64, tolerance: real32).
    subroutine assert_equal_r64s_r64s_tol32(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected
        real(real64), intent(in) :: actual
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real([expected], [actual], real(tolerance, real64), .true., .false., &
            message, location)
    end subroutine assert_equal_r64s_r64s_tol32

    !> assertEqual(expected: int32, actual: real64) without tolerance.
    subroutine assert_equal_i32s_r64s(expected, actual, message, location)
        integer(int32), intent(in) :: expected
        real(real64), intent(in) :: actual
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real([real(expected, real64)], [actual], 0.0_real64, .false., .false., &
            message, location)
    end subroutine assert_equal_i32s_r64s

    !> assertEqual(expected: int32, actual: real64, tolerance: real64).
    subroutine assert_equal_i32s_r64s_tol64(expected, actual, tolerance, message, location)
        integer(int32), intent(in) :: expected
        real(real64), intent(in) :: actual
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real([real(expected, real64)], [actual], tolerance, .true., .false., &
            message, location)
    end subroutine assert_equal_i32s_r64s_tol64

    !> assertEqual(expected: int32, actual: real64, tolerance: real32).
    subroutine assert_equal_i32s_r64s_tol32(expected, actual, tolerance, message, location)
        integer(int32), intent(in) :: expected
        real(real64), intent(in) :: actual
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real([real(expected, real64)], [actual], real(tolerance, real64), .true., &
            .false., message, location)
    end subroutine assert_equal_i32s_r64s_tol32

    !> assertEqual(expected: real64, actual: real64(:)) without tolerance.
    subroutine assert_equal_r64s_r64v(expected, actual, message, location)
        real(real64), intent(in) :: expected
        real(real64), intent(in) :: actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(spread(expected, 1, size(actual)), actual, 0.0_real64, .false., &
            .true., message, location)
    end subroutine assert_equal_r64s_r64v

    !> assertEqual(expected: real64, actual: real64(:), tolerance: real64).
    subroutine assert_equal_r64s_r64v_tol64(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected
        real(real64), intent(in) :: actual(:)
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(spread(expected, 1, size(actual)), actual, tolerance, .true., .true., &
            message, location)
    end subroutine assert_equal_r64s_r64v_tol64

    !> assertEqual(expected: real64, actual: real64(:), tolerance: real32).
    subroutine assert_equal_r64s_r64v_tol32(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected
        real(real64), intent(in) :: actual(:)
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(spread(expected, 1, size(actual)), actual, real(tolerance, real64), &
            .true., .true., message, location)
    end subroutine assert_equal_r64s_r64v_tol32

    !> assertEqual(expected: real64(:), actual: real64(:)) without tolerance.
    subroutine assert_equal_r64v_r64v(expected, actual, message, location)
        real(real64), intent(in) :: expected(:)
        real(real64), intent(in) :: actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(expected, actual, 0.0_real64, .false., .true., message, location)
    end subroutine assert_equal_r64v_r64v

    !> assertEqual(expected: real64(:), actual: real64(:), tolerance: real64).
    subroutine assert_equal_r64v_r64v_tol64(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected(:)
        real(real64), intent(in) :: actual(:)
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(expected, actual, tolerance, .true., .true., message, location)
    end subroutine assert_equal_r64v_r64v_tol64

    !> assertEqual(expected: real64(:), actual: real64(:), tolerance: real32).
    subroutine assert_equal_r64v_r64v_tol32(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected(:)
        real(real64), intent(in) :: actual(:)
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(expected, actual, real(tolerance, real64), .true., .true., message, &
            location)
    end subroutine assert_equal_r64v_r64v_tol32

    !> assertEqual(expected: int32, actual: real64(:)) without tolerance.
    subroutine assert_equal_i32s_r64v(expected, actual, message, location)
        integer(int32), intent(in) :: expected
        real(real64), intent(in) :: actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(spread(real(expected, real64), 1, size(actual)), actual, 0.0_real64, &
            .false., .true., message, location)
    end subroutine assert_equal_i32s_r64v

    !> assertEqual(expected: int32, actual: real64(:), tolerance: real64).
    subroutine assert_equal_i32s_r64v_tol64(expected, actual, tolerance, message, location)
        integer(int32), intent(in) :: expected
        real(real64), intent(in) :: actual(:)
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(spread(real(expected, real64), 1, size(actual)), actual, tolerance, &
            .true., .true., message, location)
    end subroutine assert_equal_i32s_r64v_tol64

    !> assertEqual(expected: int32, actual: real64(:), tolerance: real32).
    subroutine assert_equal_i32s_r64v_tol32(expected, actual, tolerance, message, location)
        integer(int32), intent(in) :: expected
        real(real64), intent(in) :: actual(:)
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(spread(real(expected, real64), 1, size(actual)), actual, &
            real(tolerance, real64), .true., .true., message, location)
    end subroutine assert_equal_i32s_r64v_tol32

    !> assertEqual(expected: int32(:), actual: real64(:)) without tolerance.
    subroutine assert_equal_i32v_r64v(expected, actual, message, location)
        integer(int32), intent(in) :: expected(:)
        real(real64), intent(in) :: actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(real(expected, real64), actual, 0.0_real64, .false., .true., message, &
            location)
    end subroutine assert_equal_i32v_r64v

    !> assertEqual(expected: int32(:), actual: real64(:), tolerance: real64).
    subroutine assert_equal_i32v_r64v_tol64(expected, actual, tolerance, message, location)
        integer(int32), intent(in) :: expected(:)
        real(real64), intent(in) :: actual(:)
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(real(expected, real64), actual, tolerance, .true., .true., message, &
            location)
    end subroutine assert_equal_i32v_r64v_tol64

    !> assertEqual(expected: int32(:), actual: real64(:), tolerance: real32).
    subroutine assert_equal_i32v_r64v_tol32(expected, actual, tolerance, message, location)
        integer(int32), intent(in) :: expected(:)
        real(real64), intent(in) :: actual(:)
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(real(expected, real64), actual, real(tolerance, real64), .true., &
            .true., message, location)
    end subroutine assert_equal_i32v_r64v_tol32

    !> assertEqual(expected: int32, actual: int32).
    subroutine assert_equal_i32s_i32s(expected, actual, message, location)
        integer(int32), intent(in) :: expected
        integer(int32), intent(in) :: actual
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int([int(expected, int64)], [int(actual, int64)], .false., message, &
            location)
    end subroutine assert_equal_i32s_i32s

    !> assertEqual(expected: int32, actual: int32(:)).
    subroutine assert_equal_i32s_i32v(expected, actual, message, location)
        integer(int32), intent(in) :: expected
        integer(int32), intent(in) :: actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int(spread(int(expected, int64), 1, size(actual)), int(actual, int64), &
            .true., message, location)
    end subroutine assert_equal_i32s_i32v

    !> assertEqual(expected: int32(:), actual: int32(:)).
    subroutine assert_equal_i32v_i32v(expected, actual, message, location)
        integer(int32), intent(in) :: expected(:)
        integer(int32), intent(in) :: actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int(int(expected, int64), int(actual, int64), .true., message, location)
    end subroutine assert_equal_i32v_i32v

    !> assertEqual(expected: int32, actual: int64).
    subroutine assert_equal_i32s_i64s(expected, actual, message, location)
        integer(int32), intent(in) :: expected
        integer(int64), intent(in) :: actual
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int([int(expected, int64)], [actual], .false., message, location)
    end subroutine assert_equal_i32s_i64s

    !> assertEqual(expected: int64, actual: int64).
    subroutine assert_equal_i64s_i64s(expected, actual, message, location)
        integer(int64), intent(in) :: expected
        integer(int64), intent(in) :: actual
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int([expected], [actual], .false., message, location)
    end subroutine assert_equal_i64s_i64s

    !> assertEqual(expected: int32, actual: int64(:)).
    subroutine assert_equal_i32s_i64v(expected, actual, message, location)
        integer(int32), intent(in) :: expected
        integer(int64), intent(in) :: actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int(spread(int(expected, int64), 1, size(actual)), actual, .true., &
            message, location)
    end subroutine assert_equal_i32s_i64v

    !> assertEqual(expected: int32(:), actual: int64(:)).
    subroutine assert_equal_i32v_i64v(expected, actual, message, location)
        integer(int32), intent(in) :: expected(:)
        integer(int64), intent(in) :: actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int(int(expected, int64), actual, .true., message, location)
    end subroutine assert_equal_i32v_i64v

    !> assertEqual(expected: int64, actual: int64(:)).
    subroutine assert_equal_i64s_i64v(expected, actual, message, location)
        integer(int64), intent(in) :: expected
        integer(int64), intent(in) :: actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int(spread(expected, 1, size(actual)), actual, .true., message, location)
    end subroutine assert_equal_i64s_i64v

    !> assertEqual(expected: int64(:), actual: int64(:)).
    subroutine assert_equal_i64v_i64v(expected, actual, message, location)
        integer(int64), intent(in) :: expected(:)
        integer(int64), intent(in) :: actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int(expected, actual, .true., message, location)
    end subroutine assert_equal_i64v_i64v

    !> assertEqual(expected: logical, actual: logical); `message` only by keyword, as in pFUnit.
    subroutine assert_equal_ls_ls(expected, actual, unused, message, location)
        logical, intent(in) :: expected
        logical, intent(in) :: actual
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_equal_logical([expected], [actual], .false., message, location)
    end subroutine assert_equal_ls_ls

    !> assertEqual(expected: logical, actual: logical(:)); `message` only by keyword, as in pFUnit.
    subroutine assert_equal_ls_lv(expected, actual, unused, message, location)
        logical, intent(in) :: expected
        logical, intent(in) :: actual(:)
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_equal_logical(spread(expected, 1, size(actual)), actual, .true., message, &
            location)
    end subroutine assert_equal_ls_lv

    !> assertEqual(expected: logical(:), actual: logical(:)); `message` only by keyword, as in pFUnit.
    subroutine assert_equal_lv_lv(expected, actual, unused, message, location)
        logical, intent(in) :: expected(:)
        logical, intent(in) :: actual(:)
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_equal_logical(expected, actual, .true., message, location)
    end subroutine assert_equal_lv_lv

    !> assertEqual for character scalars; leading and trailing blanks and tabs are ignored (pFUnit's default).
    subroutine assert_equal_c_c(expected, found, message, location)
        character(len=*), intent(in) :: expected
        character(len=*), intent(in) :: found
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_string(expected, found, message, location)
    end subroutine assert_equal_c_c

    !> assertRelativelyEqual(expected: real64, actual: real64, tolerance: real64).
    subroutine assert_rel_equal_r64s_r64s_tol64(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected
        real(real64), intent(in) :: actual
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_relatively_equal([expected], [actual], tolerance, .false., message, location)
    end subroutine assert_rel_equal_r64s_r64s_tol64

    !> assertRelativelyEqual(expected: real64, actual: real64, tolerance: real32).
    subroutine assert_rel_equal_r64s_r64s_tol32(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected
        real(real64), intent(in) :: actual
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_relatively_equal([expected], [actual], real(tolerance, real64), .false., &
            message, location)
    end subroutine assert_rel_equal_r64s_r64s_tol32

    !> assertRelativelyEqual(expected: real64, actual: real64(:), tolerance: real64).
    subroutine assert_rel_equal_r64s_r64v_tol64(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected
        real(real64), intent(in) :: actual(:)
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_relatively_equal(spread(expected, 1, size(actual)), actual, tolerance, .true., &
            message, location)
    end subroutine assert_rel_equal_r64s_r64v_tol64

    !> assertRelativelyEqual(expected: real64, actual: real64(:), tolerance: real32).
    subroutine assert_rel_equal_r64s_r64v_tol32(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected
        real(real64), intent(in) :: actual(:)
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_relatively_equal(spread(expected, 1, size(actual)), actual, &
            real(tolerance, real64), .true., message, location)
    end subroutine assert_rel_equal_r64s_r64v_tol32

    !> assertRelativelyEqual(expected: real64(:), actual: real64(:), tolerance: real64).
    subroutine assert_rel_equal_r64v_r64v_tol64(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected(:)
        real(real64), intent(in) :: actual(:)
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_relatively_equal(expected, actual, tolerance, .true., message, location)
    end subroutine assert_rel_equal_r64v_r64v_tol64

    !> assertRelativelyEqual(expected: real64(:), actual: real64(:), tolerance: real32).
    subroutine assert_rel_equal_r64v_r64v_tol32(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected(:)
        real(real64), intent(in) :: actual(:)
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_relatively_equal(expected, actual, real(tolerance, real64), .true., message, &
            location)
    end subroutine assert_rel_equal_r64v_r64v_tol32

    !> assertLessThan(lhs: real64, rhs: real64).
    subroutine assert_less_than_r64s_r64s(lhs, rhs, message, location)
        real(real64), intent(in) :: lhs
        real(real64), intent(in) :: rhs
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_lt, [lhs], [rhs], 0.0_real64, .false., message, location)
    end subroutine assert_less_than_r64s_r64s

    !> assertLessThan(lhs: real64, rhs: real64, tolerance: real64).
    subroutine assert_less_than_r64s_r64s_tol64(lhs, rhs, tolerance, message, location)
        real(real64), intent(in) :: lhs
        real(real64), intent(in) :: rhs
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_lt, [lhs], [rhs], tolerance, .false., message, location)
    end subroutine assert_less_than_r64s_r64s_tol64

    !> assertLessThan(lhs: real64, rhs: real64(:)).
    subroutine assert_less_than_r64s_r64v(lhs, rhs, message, location)
        real(real64), intent(in) :: lhs
        real(real64), intent(in) :: rhs(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_lt, spread(lhs, 1, size(rhs)), rhs, 0.0_real64, .true., message, &
            location)
    end subroutine assert_less_than_r64s_r64v

    !> assertLessThan(lhs: real64, rhs: real64(:), tolerance: real64).
    subroutine assert_less_than_r64s_r64v_tol64(lhs, rhs, tolerance, message, location)
        real(real64), intent(in) :: lhs
        real(real64), intent(in) :: rhs(:)
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_lt, spread(lhs, 1, size(rhs)), rhs, tolerance, .true., message, &
            location)
    end subroutine assert_less_than_r64s_r64v_tol64

    !> assertLessThan(lhs: real64(:), rhs: real64(:)).
    subroutine assert_less_than_r64v_r64v(lhs, rhs, message, location)
        real(real64), intent(in) :: lhs(:)
        real(real64), intent(in) :: rhs(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_lt, lhs, rhs, 0.0_real64, .true., message, location)
    end subroutine assert_less_than_r64v_r64v

    !> assertLessThan(lhs: real64(:), rhs: real64(:), tolerance: real64).
    subroutine assert_less_than_r64v_r64v_tol64(lhs, rhs, tolerance, message, location)
        real(real64), intent(in) :: lhs(:)
        real(real64), intent(in) :: rhs(:)
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_lt, lhs, rhs, tolerance, .true., message, location)
    end subroutine assert_less_than_r64v_r64v_tol64

    !> assertLessThan(lhs: int32, rhs: int32); `message` only by keyword, as in pFUnit.
    subroutine assert_less_than_i32s_i32s(lhs, rhs, unused, message, location)
        integer(int32), intent(in) :: lhs
        integer(int32), intent(in) :: rhs
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(op_lt, [int(lhs, int64)], [int(rhs, int64)], .false., message, &
            location)
    end subroutine assert_less_than_i32s_i32s

    !> assertLessThan(lhs: int32, rhs: int32(:)); `message` only by keyword, as in pFUnit.
    subroutine assert_less_than_i32s_i32v(lhs, rhs, unused, message, location)
        integer(int32), intent(in) :: lhs
        integer(int32), intent(in) :: rhs(:)
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(op_lt, spread(int(lhs, int64), 1, size(rhs)), int(rhs, int64), .true., &
            message, location)
    end subroutine assert_less_than_i32s_i32v

    !> assertLessThan(lhs: int32(:), rhs: int32(:)); `message` only by keyword, as in pFUnit.
    subroutine assert_less_than_i32v_i32v(lhs, rhs, unused, message, location)
        integer(int32), intent(in) :: lhs(:)
        integer(int32), intent(in) :: rhs(:)
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(op_lt, int(lhs, int64), int(rhs, int64), .true., message, location)
    end subroutine assert_less_than_i32v_i32v

    !> assertLessThan(lhs: int64, rhs: int64); `message` only by keyword, as in pFUnit.
    subroutine assert_less_than_i64s_i64s(lhs, rhs, unused, message, location)
        integer(int64), intent(in) :: lhs
        integer(int64), intent(in) :: rhs
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(op_lt, [lhs], [rhs], .false., message, location)
    end subroutine assert_less_than_i64s_i64s

    !> assertLessThanOrEqual(lhs: real64, rhs: real64).
    subroutine assert_less_equal_r64s_r64s(lhs, rhs, message, location)
        real(real64), intent(in) :: lhs
        real(real64), intent(in) :: rhs
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_le, [lhs], [rhs], 0.0_real64, .false., message, location)
    end subroutine assert_less_equal_r64s_r64s

    !> assertLessThanOrEqual(lhs: real64, rhs: real64, tolerance: real64).
    subroutine assert_less_equal_r64s_r64s_tol64(lhs, rhs, tolerance, message, location)
        real(real64), intent(in) :: lhs
        real(real64), intent(in) :: rhs
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_le, [lhs], [rhs], tolerance, .false., message, location)
    end subroutine assert_less_equal_r64s_r64s_tol64

    !> assertLessThanOrEqual(lhs: real64, rhs: real64(:)).
    subroutine assert_less_equal_r64s_r64v(lhs, rhs, message, location)
        real(real64), intent(in) :: lhs
        real(real64), intent(in) :: rhs(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_le, spread(lhs, 1, size(rhs)), rhs, 0.0_real64, .true., message, &
            location)
    end subroutine assert_less_equal_r64s_r64v

    !> assertLessThanOrEqual(lhs: real64, rhs: real64(:), tolerance: real64).
    subroutine assert_less_equal_r64s_r64v_tol64(lhs, rhs, tolerance, message, location)
        real(real64), intent(in) :: lhs
        real(real64), intent(in) :: rhs(:)
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_le, spread(lhs, 1, size(rhs)), rhs, tolerance, .true., message, &
            location)
    end subroutine assert_less_equal_r64s_r64v_tol64

    !> assertLessThanOrEqual(lhs: real64(:), rhs: real64(:)).
    subroutine assert_less_equal_r64v_r64v(lhs, rhs, message, location)
        real(real64), intent(in) :: lhs(:)
        real(real64), intent(in) :: rhs(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_le, lhs, rhs, 0.0_real64, .true., message, location)
    end subroutine assert_less_equal_r64v_r64v

    !> assertLessThanOrEqual(lhs: real64(:), rhs: real64(:), tolerance: real64).
    subroutine assert_less_equal_r64v_r64v_tol64(lhs, rhs, tolerance, message, location)
        real(real64), intent(in) :: lhs(:)
        real(real64), intent(in) :: rhs(:)
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_le, lhs, rhs, tolerance, .true., message, location)
    end subroutine assert_less_equal_r64v_r64v_tol64

    !> assertLessThanOrEqual(lhs: int32, rhs: int32); `message` only by keyword, as in pFUnit.
    subroutine assert_less_equal_i32s_i32s(lhs, rhs, unused, message, location)
        integer(int32), intent(in) :: lhs
        integer(int32), intent(in) :: rhs
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(op_le, [int(lhs, int64)], [int(rhs, int64)], .false., message, &
            location)
    end subroutine assert_less_equal_i32s_i32s

    !> assertLessThanOrEqual(lhs: int32, rhs: int32(:)); `message` only by keyword, as in pFUnit.
    subroutine assert_less_equal_i32s_i32v(lhs, rhs, unused, message, location)
        integer(int32), intent(in) :: lhs
        integer(int32), intent(in) :: rhs(:)
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(op_le, spread(int(lhs, int64), 1, size(rhs)), int(rhs, int64), .true., &
            message, location)
    end subroutine assert_less_equal_i32s_i32v

    !> assertLessThanOrEqual(lhs: int32(:), rhs: int32(:)); `message` only by keyword, as in pFUnit.
    subroutine assert_less_equal_i32v_i32v(lhs, rhs, unused, message, location)
        integer(int32), intent(in) :: lhs(:)
        integer(int32), intent(in) :: rhs(:)
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(op_le, int(lhs, int64), int(rhs, int64), .true., message, location)
    end subroutine assert_less_equal_i32v_i32v

    !> assertLessThanOrEqual(lhs: int64, rhs: int64); `message` only by keyword, as in pFUnit.
    subroutine assert_less_equal_i64s_i64s(lhs, rhs, unused, message, location)
        integer(int64), intent(in) :: lhs
        integer(int64), intent(in) :: rhs
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(op_le, [lhs], [rhs], .false., message, location)
    end subroutine assert_less_equal_i64s_i64s

    !> assertGreaterThan(lhs: real64, rhs: real64).
    subroutine assert_greater_than_r64s_r64s(lhs, rhs, message, location)
        real(real64), intent(in) :: lhs
        real(real64), intent(in) :: rhs
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_gt, [lhs], [rhs], 0.0_real64, .false., message, location)
    end subroutine assert_greater_than_r64s_r64s

    !> assertGreaterThan(lhs: real64, rhs: real64, tolerance: real64).
    subroutine assert_greater_than_r64s_r64s_tol64(lhs, rhs, tolerance, message, location)
        real(real64), intent(in) :: lhs
        real(real64), intent(in) :: rhs
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_gt, [lhs], [rhs], tolerance, .false., message, location)
    end subroutine assert_greater_than_r64s_r64s_tol64

    !> assertGreaterThan(lhs: real64, rhs: real64(:)).
    subroutine assert_greater_than_r64s_r64v(lhs, rhs, message, location)
        real(real64), intent(in) :: lhs
        real(real64), intent(in) :: rhs(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_gt, spread(lhs, 1, size(rhs)), rhs, 0.0_real64, .true., message, &
            location)
    end subroutine assert_greater_than_r64s_r64v

    !> assertGreaterThan(lhs: real64, rhs: real64(:), tolerance: real64).
    subroutine assert_greater_than_r64s_r64v_tol64(lhs, rhs, tolerance, message, location)
        real(real64), intent(in) :: lhs
        real(real64), intent(in) :: rhs(:)
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_gt, spread(lhs, 1, size(rhs)), rhs, tolerance, .true., message, &
            location)
    end subroutine assert_greater_than_r64s_r64v_tol64

    !> assertGreaterThan(lhs: real64(:), rhs: real64(:)).
    subroutine assert_greater_than_r64v_r64v(lhs, rhs, message, location)
        real(real64), intent(in) :: lhs(:)
        real(real64), intent(in) :: rhs(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_gt, lhs, rhs, 0.0_real64, .true., message, location)
    end subroutine assert_greater_than_r64v_r64v

    !> assertGreaterThan(lhs: real64(:), rhs: real64(:), tolerance: real64).
    subroutine assert_greater_than_r64v_r64v_tol64(lhs, rhs, tolerance, message, location)
        real(real64), intent(in) :: lhs(:)
        real(real64), intent(in) :: rhs(:)
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_gt, lhs, rhs, tolerance, .true., message, location)
    end subroutine assert_greater_than_r64v_r64v_tol64

    !> assertGreaterThan(lhs: int32, rhs: int32); `message` only by keyword, as in pFUnit.
    subroutine assert_greater_than_i32s_i32s(lhs, rhs, unused, message, location)
        integer(int32), intent(in) :: lhs
        integer(int32), intent(in) :: rhs
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(op_gt, [int(lhs, int64)], [int(rhs, int64)], .false., message, &
            location)
    end subroutine assert_greater_than_i32s_i32s

    !> assertGreaterThan(lhs: int32, rhs: int32(:)); `message` only by keyword, as in pFUnit.
    subroutine assert_greater_than_i32s_i32v(lhs, rhs, unused, message, location)
        integer(int32), intent(in) :: lhs
        integer(int32), intent(in) :: rhs(:)
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(op_gt, spread(int(lhs, int64), 1, size(rhs)), int(rhs, int64), .true., &
            message, location)
    end subroutine assert_greater_than_i32s_i32v

    !> assertGreaterThan(lhs: int32(:), rhs: int32(:)); `message` only by keyword, as in pFUnit.
    subroutine assert_greater_than_i32v_i32v(lhs, rhs, unused, message, location)
        integer(int32), intent(in) :: lhs(:)
        integer(int32), intent(in) :: rhs(:)
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(op_gt, int(lhs, int64), int(rhs, int64), .true., message, location)
    end subroutine assert_greater_than_i32v_i32v

    !> assertGreaterThan(lhs: int64, rhs: int64); `message` only by keyword, as in pFUnit.
    subroutine assert_greater_than_i64s_i64s(lhs, rhs, unused, message, location)
        integer(int64), intent(in) :: lhs
        integer(int64), intent(in) :: rhs
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(op_gt, [lhs], [rhs], .false., message, location)
    end subroutine assert_greater_than_i64s_i64s

    !> assertGreaterThanOrEqual(lhs: real64, rhs: real64).
    subroutine assert_greater_equal_r64s_r64s(lhs, rhs, message, location)
        real(real64), intent(in) :: lhs
        real(real64), intent(in) :: rhs
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_ge, [lhs], [rhs], 0.0_real64, .false., message, location)
    end subroutine assert_greater_equal_r64s_r64s

    !> assertGreaterThanOrEqual(lhs: real64, rhs: real64, tolerance: real64).
    subroutine assert_greater_equal_r64s_r64s_tol64(lhs, rhs, tolerance, message, location)
        real(real64), intent(in) :: lhs
        real(real64), intent(in) :: rhs
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_ge, [lhs], [rhs], tolerance, .false., message, location)
    end subroutine assert_greater_equal_r64s_r64s_tol64

    !> assertGreaterThanOrEqual(lhs: real64, rhs: real64(:)).
    subroutine assert_greater_equal_r64s_r64v(lhs, rhs, message, location)
        real(real64), intent(in) :: lhs
        real(real64), intent(in) :: rhs(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_ge, spread(lhs, 1, size(rhs)), rhs, 0.0_real64, .true., message, &
            location)
    end subroutine assert_greater_equal_r64s_r64v

    !> assertGreaterThanOrEqual(lhs: real64, rhs: real64(:), tolerance: real64).
    subroutine assert_greater_equal_r64s_r64v_tol64(lhs, rhs, tolerance, message, location)
        real(real64), intent(in) :: lhs
        real(real64), intent(in) :: rhs(:)
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_ge, spread(lhs, 1, size(rhs)), rhs, tolerance, .true., message, &
            location)
    end subroutine assert_greater_equal_r64s_r64v_tol64

    !> assertGreaterThanOrEqual(lhs: real64(:), rhs: real64(:)).
    subroutine assert_greater_equal_r64v_r64v(lhs, rhs, message, location)
        real(real64), intent(in) :: lhs(:)
        real(real64), intent(in) :: rhs(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_ge, lhs, rhs, 0.0_real64, .true., message, location)
    end subroutine assert_greater_equal_r64v_r64v

    !> assertGreaterThanOrEqual(lhs: real64(:), rhs: real64(:), tolerance: real64).
    subroutine assert_greater_equal_r64v_r64v_tol64(lhs, rhs, tolerance, message, location)
        real(real64), intent(in) :: lhs(:)
        real(real64), intent(in) :: rhs(:)
        real(real64), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(op_ge, lhs, rhs, tolerance, .true., message, location)
    end subroutine assert_greater_equal_r64v_r64v_tol64

    !> assertGreaterThanOrEqual(lhs: int32, rhs: int32); `message` only by keyword, as in pFUnit.
    subroutine assert_greater_equal_i32s_i32s(lhs, rhs, unused, message, location)
        integer(int32), intent(in) :: lhs
        integer(int32), intent(in) :: rhs
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(op_ge, [int(lhs, int64)], [int(rhs, int64)], .false., message, &
            location)
    end subroutine assert_greater_equal_i32s_i32s

    !> assertGreaterThanOrEqual(lhs: int32, rhs: int32(:)); `message` only by keyword, as in pFUnit.
    subroutine assert_greater_equal_i32s_i32v(lhs, rhs, unused, message, location)
        integer(int32), intent(in) :: lhs
        integer(int32), intent(in) :: rhs(:)
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(op_ge, spread(int(lhs, int64), 1, size(rhs)), int(rhs, int64), .true., &
            message, location)
    end subroutine assert_greater_equal_i32s_i32v

    !> assertGreaterThanOrEqual(lhs: int32(:), rhs: int32(:)); `message` only by keyword, as in pFUnit.
    subroutine assert_greater_equal_i32v_i32v(lhs, rhs, unused, message, location)
        integer(int32), intent(in) :: lhs(:)
        integer(int32), intent(in) :: rhs(:)
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(op_ge, int(lhs, int64), int(rhs, int64), .true., message, location)
    end subroutine assert_greater_equal_i32v_i32v

    !> assertGreaterThanOrEqual(lhs: int64, rhs: int64); `message` only by keyword, as in pFUnit.
    subroutine assert_greater_equal_i64s_i64s(lhs, rhs, unused, message, location)
        integer(int64), intent(in) :: lhs
        integer(int64), intent(in) :: rhs
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(op_ge, [lhs], [rhs], .false., message, location)
    end subroutine assert_greater_equal_i64s_i64s

    !> assertIsFinite(x: real64).
    subroutine assert_is_finite_r64(x, message, location)
        real(real64), intent(in) :: x
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_is_finite(x, message, location)
    end subroutine assert_is_finite_r64

    !> assertIsFinite(x: real32).
    subroutine assert_is_finite_r32(x, message, location)
        real(real32), intent(in) :: x
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_is_finite(real(x, real64), message, location)
    end subroutine assert_is_finite_r32

    !> assertIsNaN(x: real64).
    subroutine assert_is_nan_r64(x, message, location)
        real(real64), intent(in) :: x
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_is_nan(x, message, location)
    end subroutine assert_is_nan_r64

    !> assertIsNaN(x: real32).
    subroutine assert_is_nan_r32(x, message, location)
        real(real32), intent(in) :: x
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_is_nan(real(x, real64), message, location)
    end subroutine assert_is_nan_r32

    !> assertTrue(condition: logical).
    subroutine assert_true_s(condition, message, location)
        logical, intent(in) :: condition
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_condition(condition, "assertTrue", message, location)
    end subroutine assert_true_s

    !> assertTrue(condition: logical(:)).
    subroutine assert_true_v(condition, message, location)
        logical, intent(in) :: condition(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_condition(all(condition), "assertTrue", message, location)
    end subroutine assert_true_v

    !> assertFalse(condition: logical).
    subroutine assert_false_s(condition, message, location)
        logical, intent(in) :: condition
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_condition(.not. condition, "assertFalse", message, location)
    end subroutine assert_false_s

    !> assertFalse(condition: logical(:)).
    subroutine assert_false_v(condition, message, location)
        logical, intent(in) :: condition(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_condition(.not. any(condition), "assertFalse", message, location)
    end subroutine assert_false_v

end module pf_runtime
