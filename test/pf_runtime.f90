!> Minimal stand-in for the part of pFUnit's `funit` module that supratrans' tests use.
!>
!> `test/pf2f90.py` rewrites `use funit` in each `test/test_*.pf` into `use pf_runtime` and every
!> `@assertX(args)` macro into `call assertX(args, location=pf_source_location('file.pf', line, 'assertX'))`
!> followed by `if (pf_any_failed()) return`, as pFUnit's own preprocessor does. The generic names
!> and dummy argument names below are pFUnit's, and every specific procedure mirrors one that
!> pFUnit provides, so a test that compiles against this module also compiles against pFUnit.
!> Where pFUnit forces `message=` to be passed by keyword (logical `assertEqual`, integer order
!> comparisons) an unusable optional dummy of a private type does the same here.
!>
!> Layout: a generic core of checks on rank-1 arrays of one kind (`check_*`: real64, int64,
!> logical, character), each reporting the first failing element, and thin typed front-ends,
!> the specific procedures of the generic names, that only convert their arguments (kind, scalar
!> or array) for a check. The four order assertions share their front-ends: which relation to
!> check is the assertion named in the location that their @-macro passes.
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

    !> Where an assertion stands in its `.pf` file, and which it is (pFUnit's `SourceLocation`,
    !> plus the assertion's name).
    type :: pf_source_location
        !> Base name of the `.pf` file.
        character(len=256) :: file = ""
        !> Line of the assertion in that file.
        integer :: line = 0
        !> Name of the @-macro, e.g. `assertLessThan`: it tells the order assertions, which share
        !> their specific procedures, which relation to check.
        character(len=32) :: assertion = ""
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

    !> The order assertions (`op_lt`, `op_le`, `op_gt`, `op_ge` index them), and their relations in words.
    character(len=*), parameter :: order_names(4) = [character(len=24) :: "assertLessThan", &
        "assertLessThanOrEqual", "assertGreaterThan", "assertGreaterThanOrEqual"]
    character(len=*), parameter :: order_words(4) = [character(len=24) :: "less than", &
        "less than or equal to", "greater than", "greater than or equal to"]
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
    !> The tests run so far (`module::test`) and their wall-clock times in seconds, for the slowest ten
    !> that `pf_driver_finish` lists (reporting only: no test asserts on a time).
    character(len=160), allocatable :: timed_names(:)
    real(real64), allocatable :: timed_seconds(:)
    !> How many entries of `timed_names` and `timed_seconds` are filled.
    integer :: n_timed = 0
    !> How many of the slowest tests `pf_driver_finish` lists.
    integer, parameter :: n_slowest = 10

    !> pFUnit's `assertEqual`: real64 actual values with real64 or int32 expected ones (tolerance
    !> absent, real64 or real32), int32 and int64, logical, character.
    interface assertEqual
        module procedure eq_r64s_r64s, eq_r64s_r64s_t64, eq_r64s_r64s_t32, eq_r64s_r64v, eq_r64s_r64v_t64
        module procedure eq_r64s_r64v_t32, eq_r64v_r64v, eq_r64v_r64v_t64, eq_r64v_r64v_t32
        module procedure eq_i32s_r64s, eq_i32s_r64s_t64, eq_i32s_r64s_t32, eq_i32s_r64v, eq_i32s_r64v_t64
        module procedure eq_i32s_r64v_t32, eq_i32v_r64v, eq_i32v_r64v_t64, eq_i32v_r64v_t32
        module procedure eq_i32s_i32s, eq_i32s_i32v, eq_i32v_i32v, eq_i32s_i64s, eq_i32s_i64v, eq_i32v_i64v
        module procedure eq_i64s_i64s, eq_i64s_i64v, eq_i64v_i64v, eq_ls_ls, eq_ls_lv, eq_lv_lv, eq_c_c
    end interface assertEqual

    !> pFUnit's `assertRelativelyEqual` on real64 values (tolerance real64 or real32).
    interface assertRelativelyEqual
        module procedure rel_r64s_r64s_t64, rel_r64s_r64s_t32, rel_r64s_r64v_t64, rel_r64s_r64v_t32
        module procedure rel_r64v_r64v_t64, rel_r64v_r64v_t32
    end interface assertRelativelyEqual

    !> pFUnit's `assertLessThan` on real64 (tolerance optional), int32 and int64 values.
    interface assertLessThan
        module procedure order_r64s_r64s, order_r64s_r64s_t64, order_r64s_r64v, order_r64s_r64v_t64
        module procedure order_r64v_r64v, order_r64v_r64v_t64, order_i32s_i32s, order_i32s_i32v
        module procedure order_i32v_i32v, order_i64s_i64s
    end interface assertLessThan

    !> pFUnit's `assertLessThanOrEqual`: the same specific procedures as `assertLessThan`.
    interface assertLessThanOrEqual
        module procedure order_r64s_r64s, order_r64s_r64s_t64, order_r64s_r64v, order_r64s_r64v_t64
        module procedure order_r64v_r64v, order_r64v_r64v_t64, order_i32s_i32s, order_i32s_i32v
        module procedure order_i32v_i32v, order_i64s_i64s
    end interface assertLessThanOrEqual

    !> pFUnit's `assertGreaterThan`: the same specific procedures as `assertLessThan`.
    interface assertGreaterThan
        module procedure order_r64s_r64s, order_r64s_r64s_t64, order_r64s_r64v, order_r64s_r64v_t64
        module procedure order_r64v_r64v, order_r64v_r64v_t64, order_i32s_i32s, order_i32s_i32v
        module procedure order_i32v_i32v, order_i64s_i64s
    end interface assertGreaterThan

    !> pFUnit's `assertGreaterThanOrEqual`: the same specific procedures as `assertLessThan`.
    interface assertGreaterThanOrEqual
        module procedure order_r64s_r64s, order_r64s_r64s_t64, order_r64s_r64v, order_r64s_r64v_t64
        module procedure order_r64v_r64v, order_r64v_r64v_t64, order_i32s_i32s, order_i32s_i32v
        module procedure order_i32v_i32v, order_i64s_i64s
    end interface assertGreaterThanOrEqual

    !> pFUnit's `assertIsFinite` on a real64 or real32 scalar.
    interface assertIsFinite
        module procedure is_finite_r64, is_finite_r32
    end interface assertIsFinite

    !> pFUnit's `assertIsNaN` on a real64 or real32 scalar.
    interface assertIsNaN
        module procedure is_nan_r64, is_nan_r32
    end interface assertIsNaN

    !> pFUnit's `assertTrue` on a logical scalar or array (all elements).
    interface assertTrue
        module procedure true_s, true_v
    end interface assertTrue

    !> pFUnit's `assertFalse` on a logical scalar or array (no element true).
    interface assertFalse
        module procedure false_s, false_v
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
        n_timed = 0
        if (allocated(test_filter)) deallocate(test_filter)
        call get_command_argument(1, length=length, status=status)
        if (status == 0 .and. length > 0) then
            allocate(character(len=length) :: test_filter)
            call get_command_argument(1, test_filter)
            test_filter = to_lower(trim(test_filter))
        end if
    end subroutine pf_driver_init

    !> Run one test unless the filter excludes it: `before`, then, if `before` did not fail, the
    !> test and `after` (also when the test failed), as pFUnit's `TestCase%runBare` does; count it,
    !> print one `FAIL` line when it failed, and one line with its wall-clock time (`before` and
    !> `after` included), e.g. `    0.012 s  test_rk4::test_order`.
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
        integer(int64) :: start, finish, rate

        name = module_name // "::" // test_name
        if (allocated(test_filter)) then
            if (index(to_lower(name), test_filter) == 0) return
        end if
        call system_clock(start, rate)
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
        call system_clock(finish)
        call record_time(name, real(finish - start, real64) / real(max(rate, 1_int64), real64))
    end subroutine pf_run_test

    !> Print a test's time as `    0.012 s  module::test` and keep it for the list of the slowest.
    subroutine record_time(name, seconds)
        !> `module::test` name of the test.
        character(len=*), intent(in) :: name
        !> Its wall-clock time in seconds.
        real(real64), intent(in) :: seconds

        character(len=160), allocatable :: names(:)
        real(real64), allocatable :: times(:)

        call print_time(name, seconds)
        if (.not. allocated(timed_names)) then
            allocate(timed_names(256), timed_seconds(256))
        else if (n_timed == size(timed_names)) then
            allocate(names(2 * n_timed), times(2 * n_timed))
            names(:n_timed) = timed_names(:n_timed)
            times(:n_timed) = timed_seconds(:n_timed)
            call move_alloc(names, timed_names)
            call move_alloc(times, timed_seconds)
        end if
        n_timed = n_timed + 1
        timed_names(n_timed) = name
        timed_seconds(n_timed) = seconds
    end subroutine record_time

    !> One line: the time in seconds, right-aligned, then the name.
    subroutine print_time(name, seconds)
        !> `module::test` name of the test.
        character(len=*), intent(in) :: name
        !> Its wall-clock time in seconds.
        real(real64), intent(in) :: seconds

        write(output_unit, "(f9.3, a)") seconds, " s  " // trim(name)
        flush(output_unit)
    end subroutine print_time

    !> Print the `n_slowest` slowest tests run, slowest first (ties in the order they ran).
    subroutine print_slowest()
        logical, allocatable :: listed(:)
        integer :: k, i, pick

        if (n_timed == 0) return
        allocate(listed(n_timed), source=.false.)
        write(output_unit, "(a, i0, a, i0, a)") "slowest ", min(n_slowest, n_timed), " of ", n_timed, &
            " tests (wall clock):"
        do k = 1, min(n_slowest, n_timed)
            pick = 0
            do i = 1, n_timed
                if (listed(i)) cycle
                if (pick == 0) then
                    pick = i
                else if (timed_seconds(i) > timed_seconds(pick)) then
                    pick = i
                end if
            end do
            listed(pick) = .true.
            call print_time(timed_names(pick), timed_seconds(pick))
        end do
    end subroutine print_slowest

    !> Print the slowest ten tests and the closing line `fortran: N passed, M failed`; stop with an
    !> error if M > 0.
    subroutine pf_driver_finish()
        if (allocated(test_filter)) then
            if (n_passed + n_failed == 0) then
                write(error_unit, "(a)") 'pf_driver: no test name contains "' // test_filter // '"'
            end if
        end if
        call print_slowest()
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


    ! ------------------------------------------------------------------------------------------
    ! The generic core: checks on rank-1 arrays of one kind. A scalar expected value (or lhs) comes
    ! spread to the size of the actual value; `is_array` (the actual value is an array) only adds
    ! ` at index i` to the message. Each check records at most one failure, its first element.
    ! ------------------------------------------------------------------------------------------

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

    !> Record the failure of element `i`: `name: what[ at index i]detail`.
    subroutine fail_element(name, what, is_array, i, detail, message, location)
        !> Name of the assertion.
        character(len=*), intent(in) :: name
        !> What failed, e.g. `expected 1.0 but found 1.1`.
        character(len=*), intent(in) :: what
        !> Whether the assertion is on arrays (then the index is given).
        logical, intent(in) :: is_array
        !> Index of the failing element.
        integer, intent(in) :: i
        !> Text after the index, e.g. ` (tolerance 0.1)`.
        character(len=*), intent(in) :: detail
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is.
        type(pf_source_location), intent(in), optional :: location

        if (is_array) then
            call record_failure(name // ": " // what // " at index " // int_to_str(int(i, int64)) // detail, &
                message, location)
        else
            call record_failure(name // ": " // what // detail, message, location)
        end if
    end subroutine fail_element

    !> Check of `assertEqual` on reals: element i passes if equal or within `tolerance` (0 if absent).
    subroutine check_equal_real(expected, actual, is_array, message, location, tolerance)
        !> Expected and actual values.
        real(real64), intent(in) :: expected(:), actual(:)
        !> Whether the actual value is an array.
        logical, intent(in) :: is_array
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is.
        type(pf_source_location), intent(in), optional :: location
        !> Absolute tolerance.
        real(real64), intent(in), optional :: tolerance

        character(len=:), allocatable :: detail
        real(real64) :: tol
        integer :: i

        if (sizes_differ("assertEqual", size(expected), size(actual), message, location)) return
        tol = 0.0_real64
        if (present(tolerance)) tol = tolerance
        i = findloc(within(expected, actual, tol), .false., dim=1)
        if (i == 0) return
        detail = " (difference " // real_to_str(actual(i) - expected(i))
        if (present(tolerance)) detail = detail // ", tolerance " // real_to_str(tolerance)
        call fail_element("assertEqual", "expected " // real_to_str(expected(i)) // " but found " &
            // real_to_str(actual(i)), is_array, i, detail // ")", message, location)
    end subroutine check_equal_real

    !> Check of `assertRelativelyEqual`: element i passes if
    !> `abs(actual(i) - expected(i)) <= tolerance*abs(expected(i))`; a zero expected value fails.
    subroutine check_relatively_equal(expected, actual, is_array, message, location, tolerance)
        !> Expected and actual values.
        real(real64), intent(in) :: expected(:), actual(:)
        !> Whether the actual value is an array.
        logical, intent(in) :: is_array
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is.
        type(pf_source_location), intent(in), optional :: location
        !> Relative tolerance.
        real(real64), intent(in) :: tolerance

        integer :: i

        if (sizes_differ("assertRelativelyEqual", size(expected), size(actual), message, location)) return
        i = findloc(abs(expected) <= 0.0_real64, .true., dim=1)
        if (i > 0) then
            call fail_element("assertRelativelyEqual", "expected value is zero", is_array, i, &
                ", relative difference undefined", message, location)
            return
        end if
        i = findloc(abs(actual - expected) <= tolerance*abs(expected), .false., dim=1)
        if (i == 0) return
        call fail_element("assertRelativelyEqual", "expected " // real_to_str(expected(i)) // " but found " &
            // real_to_str(actual(i)), is_array, i, " (relative difference " &
            // real_to_str((actual(i) - expected(i))/expected(i)) // ", tolerance " // real_to_str(tolerance) &
            // ")", message, location)
    end subroutine check_relatively_equal

    !> Check of `assertEqual` on integers.
    subroutine check_equal_int(expected, actual, is_array, message, location)
        !> Expected and actual values.
        integer(int64), intent(in) :: expected(:), actual(:)
        !> Whether the actual value is an array.
        logical, intent(in) :: is_array
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is.
        type(pf_source_location), intent(in), optional :: location

        integer :: i

        if (sizes_differ("assertEqual", size(expected), size(actual), message, location)) return
        i = findloc(expected == actual, .false., dim=1)
        if (i == 0) return
        call fail_element("assertEqual", "expected " // int_to_str(expected(i)) // " but found " &
            // int_to_str(actual(i)), is_array, i, "", message, location)
    end subroutine check_equal_int

    !> Check of `assertEqual` on logicals (`.eqv.`).
    subroutine check_equal_logical(expected, actual, is_array, message, location)
        !> Expected and actual values.
        logical, intent(in) :: expected(:), actual(:)
        !> Whether the actual value is an array.
        logical, intent(in) :: is_array
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is.
        type(pf_source_location), intent(in), optional :: location

        integer :: i

        if (sizes_differ("assertEqual", size(expected), size(actual), message, location)) return
        i = findloc(expected .eqv. actual, .false., dim=1)
        if (i == 0) return
        call fail_element("assertEqual", "expected " // logical_to_str(expected(i)) // " but found " &
            // logical_to_str(actual(i)), is_array, i, "", message, location)
    end subroutine check_equal_logical

    !> Check of the order assertion that `location` names on reals, with pFUnit's tolerance rule
    !> (`lhs < rhs + tolerance` for `assertLessThan`, ..., `lhs >= rhs - tolerance`; 0 if absent).
    subroutine check_order_real(lhs, rhs, is_array, message, location, tolerance)
        !> Left-hand and right-hand values.
        real(real64), intent(in) :: lhs(:), rhs(:)
        !> Whether `rhs` is an array.
        logical, intent(in) :: is_array
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is, and which.
        type(pf_source_location), intent(in), optional :: location
        !> Tolerance.
        real(real64), intent(in), optional :: tolerance

        character(len=:), allocatable :: detail
        real(real64) :: tol
        real(real64) :: bound(size(rhs))
        integer :: op, i

        call order_of(location, message, op)
        if (op == 0) return
        if (sizes_differ(trim(order_names(op)), size(lhs), size(rhs), message, location)) return
        tol = 0.0_real64
        if (present(tolerance)) tol = tolerance
        bound = rhs + merge(tol, -tol, op <= op_le)
        i = findloc(relation_holds(op, lhs < bound, same_real(lhs, bound), lhs > bound), .false., dim=1)
        if (i == 0) return
        detail = ""
        if (tol > 0.0_real64) detail = " (tolerance " // real_to_str(tol) // ")"
        call fail_element(trim(order_names(op)), real_to_str(lhs(i)) // " is not " // trim(order_words(op)) &
            // " " // real_to_str(rhs(i)), is_array, i, detail, message, location)
    end subroutine check_order_real

    !> Check of the order assertion that `location` names on integers.
    subroutine check_order_int(lhs, rhs, is_array, message, location)
        !> Left-hand and right-hand values.
        integer(int64), intent(in) :: lhs(:), rhs(:)
        !> Whether `rhs` is an array.
        logical, intent(in) :: is_array
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> Where the assertion is, and which.
        type(pf_source_location), intent(in), optional :: location

        integer :: op, i

        call order_of(location, message, op)
        if (op == 0) return
        if (sizes_differ(trim(order_names(op)), size(lhs), size(rhs), message, location)) return
        i = findloc(relation_holds(op, lhs < rhs, lhs == rhs, lhs > rhs), .false., dim=1)
        if (i == 0) return
        call fail_element(trim(order_names(op)), int_to_str(lhs(i)) // " is not " // trim(order_words(op)) &
            // " " // int_to_str(rhs(i)), is_array, i, "", message, location)
    end subroutine check_order_int

    !> Which order assertion `location` names (`op_lt`, ..., `op_ge`); 0, after recording a failure,
    !> when it names none (a direct call: the relation comes only with the @-macro's location).
    subroutine order_of(location, message, op)
        !> Where the assertion is, and which.
        type(pf_source_location), intent(in), optional :: location
        !> The user's message, if any.
        character(len=*), intent(in), optional :: message
        !> The order assertion, or 0.
        integer, intent(out) :: op

        op = 0
        if (present(location)) op = findloc(order_names, location%assertion, dim=1)
        if (op > 0) return
        call record_failure("assertLessThan and its kin run only from their @-macros, whose location names " &
            // "the relation to check", message, location)
    end subroutine order_of

    !> Whether the relation of order assertion `op` holds between two values that compare as given
    !> (all three false: unordered, a NaN, which fails every relation).
    elemental logical function relation_holds(op, less, equal, greater)
        !> One of `op_lt`, `op_le`, `op_gt`, `op_ge`.
        integer, intent(in) :: op
        !> Whether lhs < rhs, lhs == rhs, lhs > rhs.
        logical, intent(in) :: less, equal, greater

        select case (op)
        case (op_lt)
            relation_holds = less
        case (op_le)
            relation_holds = less .or. equal
        case (op_gt)
            relation_holds = greater
        case default
            relation_holds = greater .or. equal
        end select
    end function relation_holds

    !> Whether `actual` equals `expected` (see `same_real`) or lies within `tolerance` of it.
    elemental logical function within(expected, actual, tolerance)
        !> Expected value.
        real(real64), intent(in) :: expected
        !> Actual value.
        real(real64), intent(in) :: actual
        !> Absolute tolerance.
        real(real64), intent(in) :: tolerance

        within = same_real(expected, actual)
        if (.not. within) within = abs(actual - expected) <= tolerance
    end function within

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
    ! Thin typed front-ends: the specific procedures of the generic assertions, one per pFUnit
    ! signature (kinds; scalar s or array v; tolerance absent, t64 or t32), each converting its
    ! arguments for one check of the core.
    ! ------------------------------------------------------------------------------------------

    subroutine true_s(condition, message, location)
        logical, intent(in) :: condition
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (.not. condition) call record_failure("assertTrue: condition is .false.", message, location)
    end subroutine true_s

    subroutine true_v(condition, message, location)
        logical, intent(in) :: condition(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call true_s(all(condition), message, location)
    end subroutine true_v

    subroutine false_s(condition, message, location)
        logical, intent(in) :: condition
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (condition) call record_failure("assertFalse: condition is .true.", message, location)
    end subroutine false_s

    subroutine false_v(condition, message, location)
        logical, intent(in) :: condition(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call false_s(any(condition), message, location)
    end subroutine false_v

    subroutine is_finite_r64(x, message, location)
        real(real64), intent(in) :: x
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (.not. ieee_is_finite(x)) call record_failure("assertIsFinite: " // real_to_str(x) // " is not finite", &
            message, location)
    end subroutine is_finite_r64

    subroutine is_finite_r32(x, message, location)
        real(real32), intent(in) :: x
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call is_finite_r64(real(x, real64), message, location)
    end subroutine is_finite_r32

    subroutine is_nan_r64(x, message, location)
        real(real64), intent(in) :: x
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (.not. ieee_is_nan(x)) call record_failure("assertIsNaN: " // real_to_str(x) // " is not NaN", &
            message, location)
    end subroutine is_nan_r64

    subroutine is_nan_r32(x, message, location)
        real(real32), intent(in) :: x
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call is_nan_r64(real(x, real64), message, location)
    end subroutine is_nan_r32

    !> Character scalars, compared without leading and trailing blanks and tabs (pFUnit's default).
    subroutine eq_c_c(expected, found, message, location)
        character(len=*), intent(in) :: expected, found
        character(len=*), intent(in), optional :: message
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
    end subroutine eq_c_c

    subroutine eq_r64s_r64s(expected, actual, message, location)
        real(real64), intent(in) :: expected, actual
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real([expected], [actual], .false., message, location)
    end subroutine eq_r64s_r64s

    subroutine eq_r64s_r64s_t64(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected, actual, tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real([expected], [actual], .false., message, location, tolerance)
    end subroutine eq_r64s_r64s_t64

    subroutine eq_r64s_r64s_t32(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected, actual
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real([expected], [actual], .false., message, location, real(tolerance, real64))
    end subroutine eq_r64s_r64s_t32

    subroutine eq_r64s_r64v(expected, actual, message, location)
        real(real64), intent(in) :: expected, actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(spread(expected, 1, size(actual)), actual, .true., message, location)
    end subroutine eq_r64s_r64v

    subroutine eq_r64s_r64v_t64(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected, actual(:), tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(spread(expected, 1, size(actual)), actual, .true., message, location, tolerance)
    end subroutine eq_r64s_r64v_t64

    subroutine eq_r64s_r64v_t32(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected, actual(:)
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(spread(expected, 1, size(actual)), actual, .true., &
            message, location, real(tolerance, real64))
    end subroutine eq_r64s_r64v_t32

    subroutine eq_r64v_r64v(expected, actual, message, location)
        real(real64), intent(in) :: expected(:), actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(expected, actual, .true., message, location)
    end subroutine eq_r64v_r64v

    subroutine eq_r64v_r64v_t64(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected(:), actual(:), tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(expected, actual, .true., message, location, tolerance)
    end subroutine eq_r64v_r64v_t64

    subroutine eq_r64v_r64v_t32(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected(:), actual(:)
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(expected, actual, .true., message, location, real(tolerance, real64))
    end subroutine eq_r64v_r64v_t32

    subroutine eq_i32s_r64s(expected, actual, message, location)
        integer(int32), intent(in) :: expected
        real(real64), intent(in) :: actual
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real([real(expected, real64)], [actual], .false., message, location)
    end subroutine eq_i32s_r64s

    subroutine eq_i32s_r64s_t64(expected, actual, tolerance, message, location)
        integer(int32), intent(in) :: expected
        real(real64), intent(in) :: actual, tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real([real(expected, real64)], [actual], .false., message, location, tolerance)
    end subroutine eq_i32s_r64s_t64

    subroutine eq_i32s_r64s_t32(expected, actual, tolerance, message, location)
        integer(int32), intent(in) :: expected
        real(real64), intent(in) :: actual
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real([real(expected, real64)], [actual], .false., message, location, real(tolerance, real64))
    end subroutine eq_i32s_r64s_t32

    subroutine eq_i32s_r64v(expected, actual, message, location)
        integer(int32), intent(in) :: expected
        real(real64), intent(in) :: actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(spread(real(expected, real64), 1, size(actual)), actual, .true., message, location)
    end subroutine eq_i32s_r64v

    subroutine eq_i32s_r64v_t64(expected, actual, tolerance, message, location)
        integer(int32), intent(in) :: expected
        real(real64), intent(in) :: actual(:), tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(spread(real(expected, real64), 1, size(actual)), actual, .true., &
            message, location, tolerance)
    end subroutine eq_i32s_r64v_t64

    subroutine eq_i32s_r64v_t32(expected, actual, tolerance, message, location)
        integer(int32), intent(in) :: expected
        real(real64), intent(in) :: actual(:)
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(spread(real(expected, real64), 1, size(actual)), actual, .true., &
            message, location, real(tolerance, real64))
    end subroutine eq_i32s_r64v_t32

    subroutine eq_i32v_r64v(expected, actual, message, location)
        integer(int32), intent(in) :: expected(:)
        real(real64), intent(in) :: actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(real(expected, real64), actual, .true., message, location)
    end subroutine eq_i32v_r64v

    subroutine eq_i32v_r64v_t64(expected, actual, tolerance, message, location)
        integer(int32), intent(in) :: expected(:)
        real(real64), intent(in) :: actual(:), tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(real(expected, real64), actual, .true., message, location, tolerance)
    end subroutine eq_i32v_r64v_t64

    subroutine eq_i32v_r64v_t32(expected, actual, tolerance, message, location)
        integer(int32), intent(in) :: expected(:)
        real(real64), intent(in) :: actual(:)
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_real(real(expected, real64), actual, .true., message, location, real(tolerance, real64))
    end subroutine eq_i32v_r64v_t32

    subroutine eq_i32s_i32s(expected, actual, message, location)
        integer(int32), intent(in) :: expected, actual
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int([int(expected, int64)], [int(actual, int64)], .false., message, location)
    end subroutine eq_i32s_i32s

    subroutine eq_i32s_i32v(expected, actual, message, location)
        integer(int32), intent(in) :: expected, actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int(spread(int(expected, int64), 1, size(actual)), int(actual, int64), .true., &
            message, location)
    end subroutine eq_i32s_i32v

    subroutine eq_i32v_i32v(expected, actual, message, location)
        integer(int32), intent(in) :: expected(:), actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int(int(expected, int64), int(actual, int64), .true., message, location)
    end subroutine eq_i32v_i32v

    subroutine eq_i32s_i64s(expected, actual, message, location)
        integer(int32), intent(in) :: expected
        integer(int64), intent(in) :: actual
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int([int(expected, int64)], [actual], .false., message, location)
    end subroutine eq_i32s_i64s

    subroutine eq_i32s_i64v(expected, actual, message, location)
        integer(int32), intent(in) :: expected
        integer(int64), intent(in) :: actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int(spread(int(expected, int64), 1, size(actual)), actual, .true., message, location)
    end subroutine eq_i32s_i64v

    subroutine eq_i32v_i64v(expected, actual, message, location)
        integer(int32), intent(in) :: expected(:)
        integer(int64), intent(in) :: actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int(int(expected, int64), actual, .true., message, location)
    end subroutine eq_i32v_i64v

    subroutine eq_i64s_i64s(expected, actual, message, location)
        integer(int64), intent(in) :: expected, actual
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int([expected], [actual], .false., message, location)
    end subroutine eq_i64s_i64s

    subroutine eq_i64s_i64v(expected, actual, message, location)
        integer(int64), intent(in) :: expected, actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int(spread(expected, 1, size(actual)), actual, .true., message, location)
    end subroutine eq_i64s_i64v

    subroutine eq_i64v_i64v(expected, actual, message, location)
        integer(int64), intent(in) :: expected(:), actual(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_equal_int(expected, actual, .true., message, location)
    end subroutine eq_i64v_i64v

    subroutine eq_ls_ls(expected, actual, unused, message, location)
        logical, intent(in) :: expected, actual
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_equal_logical([expected], [actual], .false., message, location)
    end subroutine eq_ls_ls

    subroutine eq_ls_lv(expected, actual, unused, message, location)
        logical, intent(in) :: expected, actual(:)
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_equal_logical(spread(expected, 1, size(actual)), actual, .true., message, location)
    end subroutine eq_ls_lv

    subroutine eq_lv_lv(expected, actual, unused, message, location)
        logical, intent(in) :: expected(:), actual(:)
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_equal_logical(expected, actual, .true., message, location)
    end subroutine eq_lv_lv

    subroutine rel_r64s_r64s_t64(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected, actual, tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_relatively_equal([expected], [actual], .false., message, location, tolerance)
    end subroutine rel_r64s_r64s_t64

    subroutine rel_r64s_r64s_t32(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected, actual
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_relatively_equal([expected], [actual], .false., message, location, real(tolerance, real64))
    end subroutine rel_r64s_r64s_t32

    subroutine rel_r64s_r64v_t64(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected, actual(:), tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_relatively_equal(spread(expected, 1, size(actual)), actual, .true., message, location, tolerance)
    end subroutine rel_r64s_r64v_t64

    subroutine rel_r64s_r64v_t32(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected, actual(:)
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_relatively_equal(spread(expected, 1, size(actual)), actual, .true., &
            message, location, real(tolerance, real64))
    end subroutine rel_r64s_r64v_t32

    subroutine rel_r64v_r64v_t64(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected(:), actual(:), tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_relatively_equal(expected, actual, .true., message, location, tolerance)
    end subroutine rel_r64v_r64v_t64

    subroutine rel_r64v_r64v_t32(expected, actual, tolerance, message, location)
        real(real64), intent(in) :: expected(:), actual(:)
        real(real32), intent(in) :: tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_relatively_equal(expected, actual, .true., message, location, real(tolerance, real64))
    end subroutine rel_r64v_r64v_t32

    subroutine order_r64s_r64s(lhs, rhs, message, location)
        real(real64), intent(in) :: lhs, rhs
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real([lhs], [rhs], .false., message, location)
    end subroutine order_r64s_r64s

    subroutine order_r64s_r64s_t64(lhs, rhs, tolerance, message, location)
        real(real64), intent(in) :: lhs, rhs, tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real([lhs], [rhs], .false., message, location, tolerance)
    end subroutine order_r64s_r64s_t64

    subroutine order_r64s_r64v(lhs, rhs, message, location)
        real(real64), intent(in) :: lhs, rhs(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(spread(lhs, 1, size(rhs)), rhs, .true., message, location)
    end subroutine order_r64s_r64v

    subroutine order_r64s_r64v_t64(lhs, rhs, tolerance, message, location)
        real(real64), intent(in) :: lhs, rhs(:), tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(spread(lhs, 1, size(rhs)), rhs, .true., message, location, tolerance)
    end subroutine order_r64s_r64v_t64

    subroutine order_r64v_r64v(lhs, rhs, message, location)
        real(real64), intent(in) :: lhs(:), rhs(:)
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(lhs, rhs, .true., message, location)
    end subroutine order_r64v_r64v

    subroutine order_r64v_r64v_t64(lhs, rhs, tolerance, message, location)
        real(real64), intent(in) :: lhs(:), rhs(:), tolerance
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        call check_order_real(lhs, rhs, .true., message, location, tolerance)
    end subroutine order_r64v_r64v_t64

    subroutine order_i32s_i32s(lhs, rhs, unused, message, location)
        integer(int32), intent(in) :: lhs, rhs
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int([int(lhs, int64)], [int(rhs, int64)], .false., message, location)
    end subroutine order_i32s_i32s

    subroutine order_i32s_i32v(lhs, rhs, unused, message, location)
        integer(int32), intent(in) :: lhs, rhs(:)
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(spread(int(lhs, int64), 1, size(rhs)), int(rhs, int64), .true., message, location)
    end subroutine order_i32s_i32v

    subroutine order_i32v_i32v(lhs, rhs, unused, message, location)
        integer(int32), intent(in) :: lhs(:), rhs(:)
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int(int(lhs, int64), int(rhs, int64), .true., message, location)
    end subroutine order_i32v_i32v

    subroutine order_i64s_i64s(lhs, rhs, unused, message, location)
        integer(int64), intent(in) :: lhs, rhs
        class(pf_keyword_enforcer), intent(in), optional :: unused
        character(len=*), intent(in), optional :: message
        type(pf_source_location), intent(in), optional :: location

        if (present(unused)) continue
        call check_order_int([lhs], [rhs], .false., message, location)
    end subroutine order_i64s_i64s

end module pf_runtime
