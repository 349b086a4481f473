"""Tests of test/pf2f90.py, the translator of pFUnit .pf files, and of test/pf_runtime.f90."""

from __future__ import annotations

import re
import shutil
import subprocess
import textwrap
from pathlib import Path

import pytest

import pf2f90
from pf2f90 import PfError, convert, split_args

HERE = Path(__file__).resolve().parent


def pf(body: str, name: str = "test_x", uses: str = "    use funit\n") -> str:
    """A .pf module named ``name`` whose contains-part is ``body``."""
    return f"module {name}\n{uses}    implicit none\ncontains\n{textwrap.dedent(body)}end module {name}\n"


def translate(body: str, name: str = "test_x") -> tuple[str, pf2f90.TestModule]:
    return convert(f"{name}.pf", pf(body, name))


def calls(text: str) -> list[str]:
    """The generated statements that are not plain copies: calls joined over continuation lines."""
    out, current = [], ""
    for line in text.splitlines():
        s = line.strip()
        if current:
            current += s[1:] if s.startswith("&") else " " + s
        elif s.startswith("call assert"):
            current = s
        else:
            continue
        if current.endswith("&"):
            current = current[:-1].rstrip()
            continue
        out.append(current.replace("( ", "("))
        current = ""
    return out


# --------------------------------------------------------------------------- argument splitting


@pytest.mark.parametrize(
    "text, expected",
    [
        ("a, b", ["a", "b"]),
        ("f(x, y), g(z)", ["f(x, y)", "g(z)"]),
        ("a(b(c, d), e), [1, 2, 3]", ["a(b(c, d), e)", "[1, 2, 3]"]),
        ("x(1:2, :), (/ 1, 2 /)", ["x(1:2, :)", "(/ 1, 2 /)"]),
        ("'a, b', \"c, (d\"", ["'a, b'", '"c, (d"']),
        ("'it''s, ok', b", ["'it''s, ok'", "b"]),
        ('"say ""hi, there""", b', ['"say ""hi, there"""', "b"]),
        ("1.0_wp, x, message='m=(,)'", ["1.0_wp", "x", "message='m=(,)'"]),
        ("", []),
    ],
)
def test_split_args(text, expected):
    assert split_args(text) == expected


@pytest.mark.parametrize("text", ["f(a, b", "a), b", "'open, b", "[1, 2"])
def test_split_args_rejects_unbalanced(text):
    with pytest.raises(ValueError):
        split_args(text)


# --------------------------------------------------------------------------- each macro


@pytest.mark.parametrize(
    "macro, call",
    [
        ("@assertEqual(1.0_wp, x)", "call assertEqual(1.0_wp, x, location=LOC)"),
        ("@assertEqual(1.0_wp, x, 1e-12_wp)", "call assertEqual(1.0_wp, x, 1e-12_wp, location=LOC)"),
        ("@assertEqual(e, a, tolerance=t, message='m')",
         "call assertEqual(e, a, tolerance=t, message='m', location=LOC)"),
        ("@assertEqual(3, n, 'n')", "call assertEqual(3, n, 'n', location=LOC)"),
        ("@assertEqual('abc', s)", "call assertEqual('abc', s, location=LOC)"),
        ("@assertRelativelyEqual(e, a, 1e-8_wp)", "call assertRelativelyEqual(e, a, 1e-8_wp, location=LOC)"),
        ("@assertTrue(all(x > 0))", "call assertTrue(all(x > 0), location=LOC)"),
        ("@assertTrue(ok, 'why')", "call assertTrue(ok, 'why', location=LOC)"),
        ("@assertFalse(any(x < 0), message='m')", "call assertFalse(any(x < 0), message='m', location=LOC)"),
        ("@assertLessThan(a, b)", "call assertLessThan(a, b, location=LOC)"),
        ("@assertLessThanOrEqual(a, b, message='m')", "call assertLessThanOrEqual(a, b, message='m', location=LOC)"),
        ("@assertGreaterThan(a, b)", "call assertGreaterThan(a, b, location=LOC)"),
        ("@assertGreaterThanOrEqual(a, b, 'm')", "call assertGreaterThanOrEqual(a, b, 'm', location=LOC)"),
        ("@assertIsFinite(x(3))", "call assertIsFinite(x(3), location=LOC)"),
        ("@assertIsNaN(x)", "call assertIsNaN(x, location=LOC)"),
        ("@ASSERTEQUAL(1, n)", "call assertEqual(1, n, location=LOC)"),
        ("@assertEqual (1, n)", "call assertEqual(1, n, location=LOC)"),
    ],
)
def test_macro_translation(macro, call):
    text, _ = translate(f"    @test\n    subroutine t()\n        {macro}\n    end subroutine t\n")
    name = call.split("(")[0].split()[-1]
    loc = f"pf_source_location('test_x.pf', 7, '{name}')"
    assert calls(text) == [call.replace("LOC", loc)]
    lines = text.splitlines()
    k = next(i for i, line in enumerate(lines) if "call assert" in line)
    assert lines[k].startswith("    call ")  # indentation of the macro kept
    follow = next(line for line in lines[k:] if "pf_any_failed" in line)
    assert follow == "    if (pf_any_failed()) return"


def test_use_funit_rewritten_and_annotations_commented():
    text, module = translate(
        """\
        @before
        subroutine set_up()
        end subroutine set_up
        @after
        subroutine tear_down()  ! comment allowed here
        end subroutine tear_down
        @test
        subroutine test_a()
        end subroutine test_a
        @test()
        ! a comment between annotation and subroutine
        subroutine test_b
        end subroutine test_b
        subroutine helper()
        end subroutine helper
        """
    )
    assert "    use pf_runtime" in text.splitlines()
    assert "use funit" not in text
    assert "! @test" in text and "! @before" in text and "! @after" in text
    assert not any(line.lstrip().startswith("@") for line in text.splitlines())
    assert text.startswith(pf2f90.MARKER)
    assert (module.name, module.tests, module.before, module.after) == ("test_x", ["test_a", "test_b"], "set_up",
                                                                        "tear_down")


def test_continued_directive_is_rejected_as_pfunit_does():
    """pFUnit 4.14 reads a directive from one physical line: a continued one is refused, not joined."""
    with pytest.raises(PfError, match=r"continued with '&'"):
        translate("    @test\n    subroutine t()\n        @assertEqual(1.0_wp, &\n            x)\n"
                  "    end subroutine t\n")


def test_directive_longer_than_pfunit_allows_is_rejected():
    with pytest.raises(PfError, match=r"longer than 124"):
        translate("    @test\n    subroutine t()\n        @assertTrue(ok, '" + "x" * 120 + "')\n    end subroutine t\n")


def test_ordinary_continuation_lines_copied_unchanged():
    body = """\
    @test
    subroutine t()
        character(len=*), parameter :: s = 'not @a directive &
            &@assertTrue(.false.)'
        real :: x(2) = [1.0, &
        @2.0]
    end subroutine t
    """
    text, _ = convert("test_x.pf", pf(body))
    for line in textwrap.dedent(body).splitlines()[2:6]:
        assert line in text
    assert "call assert" not in text


def test_long_call_is_wrapped_within_132_columns():
    long_message = "x" * 90
    text, _ = translate(f"    @test\n    subroutine t()\n        @assertTrue(ok, '{long_message}')\n"
                        "    end subroutine t\n")
    assert max(len(line) for line in text.splitlines()) <= 132
    assert calls(text) == [f"call assertTrue(ok, '{long_message}', location=pf_source_location('test_x.pf', 7, 'assertTrue'))"]


def test_driver_runs_every_test_with_before_and_after():
    _, m1 = translate("    @before\n    subroutine s()\n    end subroutine s\n"
                      "    @test\n    subroutine t()\n    end subroutine t\n", name="test_a")
    _, m2 = translate("    @test\n    subroutine t()\n    end subroutine t\n", name="test_b")
    driver = pf2f90.driver_source([m1, m2])
    assert "use test_a, only: b1 => s" in driver
    assert "use test_a, only: t1 => t" in driver
    assert "use test_b, only: t2 => t" in driver
    assert "call pf_run_test('test_a', 't', t1, before=b1)" in driver
    assert "call pf_run_test('test_b', 't', t2)" in driver


# --------------------------------------------------------------------------- errors


@pytest.mark.parametrize(
    "body, line, message",
    [
        ("    @test\n    subroutine t()\n        @assertFoo(1)\n    end subroutine t\n", 7,
         "unknown directive @assertFoo"),
        ("    @test\n    subroutine t()\n        @assertNotEqual(1, 2)\n    end subroutine t\n", 7, "does not support"),
        ("    @disable\n", 5, "does not support"),
        ("    @test\n    subroutine t()\n        @assertEqual(1)\n    end subroutine t\n", 7, "at least 2"),
        ("    @test\n    subroutine t()\n        @assertTrue(a, b, c)\n    end subroutine t\n", 7, "at most 2"),
        ("    @test\n    subroutine t()\n        @assertTrue(x, msg='m')\n    end subroutine t\n", 7,
         "unknown keyword"),
        ("    @test\n    subroutine t()\n        @assertTrue(message='m', x)\n    end subroutine t\n", 7, "positional"),
        ("    @test\n    subroutine t()\n        @assertTrue(f(x)\n    end subroutine t\n", 7, "unbalanced"),
        ("    @test\n    subroutine t()\n        @assertTrue(x) ! why\n    end subroutine t\n", 7, "comment after"),
        ("    @test\n    subroutine t()\n        @assertTrue(x) y\n    end subroutine t\n", 7,
         "after the argument list"),
        ("    @test\n    function f()\n    end function f\n", 6, "expected 'subroutine name()'"),
        ("    @test\n    subroutine t(this)\n    end subroutine t\n", 6, "no arguments"),
        ("    @test\n", 6, "expected 'subroutine name()' after @test of line 5"),
        ("    @test\n    subroutine t()\n    end subroutine t\n    @test\n    subroutine t()\n    end subroutine t\n",
         9, "defined twice"),
    ],
)
def test_errors_name_file_and_line(body, line, message):
    with pytest.raises(PfError) as info:
        convert("test_x.pf", pf(body))
    assert str(info.value).startswith(f"test_x.pf:{line}: ")
    assert message in str(info.value)


@pytest.mark.parametrize(
    "name, source, pattern",
    [
        ("test_x.pf", "module test_x ! tests\n    use funit\ncontains\nend module test_x\n", "comment on the module line"),
        ("test_x.pf", "module test_x\n    use pfunit\ncontains\nend module test_x\n", "only 'use funit'"),
        ("test_x.pf", "module test_x\n    use funit\ncontains\n    subroutine t()\n        @assertTrue(x, &\n",
         r"^test_x\.pf:5: @-directive continued"),
        ("test_x.pf", "module test_x\ncontains\n    @test\n", r"^test_x\.pf:3: @test without a following subroutine"),
        ("test_y.pf", pf(""), r"^test_y\.pf:1: module test_x must be named like its file"),
        ("test_x.pf", pf("    @test\n    subroutine t()\n        @assertTrue(.true.)\n    end subroutine t\n", uses=""),
         "no 'use funit'"),
        ("test_x.pf", pf("", uses="    use funit, only: assertTrue\n"), "no only-list"),
    ],
)
def test_module_errors(name, source, pattern):
    """The module line, `use funit`, and directives cut off by the end of the file."""
    with pytest.raises(PfError, match=pattern):
        convert(name, source)


def test_command_line_reports_errors_and_writes_nothing(tmp_path, capsys):
    bad = tmp_path / "test_bad.pf"
    bad.write_text(pf("    @test\n    subroutine t()\n        @assertWhat(1)\n    end subroutine t\n", name="test_bad"))
    out = tmp_path / "gen"
    assert pf2f90.main(["-o", str(out), str(bad)]) == 1
    assert f"{bad}:7: unknown directive @assertWhat" in capsys.readouterr().err
    assert not out.exists()


def test_stale_generated_files_are_deleted(tmp_path):
    out = tmp_path / "gen"
    out.mkdir()
    (out / "test_old.f90").write_text(pf2f90.MARKER + " from test_old.pf\n")
    (out / "handwritten.f90").write_text("module handwritten\nend module handwritten\n")
    src = tmp_path / "test_new.pf"
    src.write_text(pf("    @test\n    subroutine t()\n    end subroutine t\n", name="test_new"))
    assert pf2f90.main(["-o", str(out), str(src)]) == 0
    assert sorted(p.name for p in out.iterdir()) == ["handwritten.f90", "pf_driver.f90", "test_new.f90"]


def test_check_names_stale_missing_and_orphaned_files_and_writes_nothing(tmp_path, capsys):
    src = tmp_path / "test_new.pf"
    src.write_text(pf("    @test\n    subroutine t()\n    end subroutine t\n", name="test_new"))
    out = tmp_path / "gen"
    assert pf2f90.main(["-o", str(out), "--check", str(src)]) == 1  # nothing translated yet
    err = capsys.readouterr().err
    assert "test_new.f90: missing" in err and "pf_driver.f90: missing" in err
    assert f"run `{pf2f90.REGENERATE}`" in err
    assert not out.exists()

    assert pf2f90.main(["-o", str(out), str(src)]) == 0
    assert pf2f90.main(["-o", str(out), "--check", str(src)]) == 0
    fresh = {p.name: p.read_text() for p in out.iterdir()}

    src.write_text(pf("    @test\n    subroutine u()\n    end subroutine u\n", name="test_new"))  # edited .pf
    (out / "test_old.f90").write_text(pf2f90.MARKER + " from test_old.pf\n")  # its .pf deleted
    (out / "handwritten.f90").write_text("module handwritten\nend module handwritten\n")
    capsys.readouterr()
    assert pf2f90.main(["-o", str(out), "--check", str(src)]) == 1
    err = capsys.readouterr().err
    assert "test_new.f90: differs" in err and "pf_driver.f90: differs" in err
    assert "test_old.f90: generated from a .pf file that no longer exists" in err
    assert "handwritten" not in err
    assert fresh == {p.name: p.read_text() for p in out.iterdir() if p.name in fresh}  # --check wrote nothing

    assert pf2f90.main(["-o", str(out), str(src)]) == 0
    assert pf2f90.main(["-o", str(out), "--check", str(src)]) == 0


def test_defaults_translate_every_pf_file_next_to_the_runtime():
    """Without -o, the inputs are test/*.pf and the output is test/ (the committed translation)."""
    outputs, modules, errors = pf2f90.translate_all(sorted(str(p) for p in HERE.glob("*.pf")))
    assert not errors
    assert sorted(outputs) == sorted([p.stem + ".f90" for p in HERE.glob("*.pf")] + ["pf_driver.f90"])
    assert sum(len(m.tests) for m in modules) > 0


# --------------------------------------------------------------------------- end to end

END_TO_END = """\
module test_e2e
    use funit
    use, intrinsic :: iso_fortran_env, only: real64
    implicit none
    integer, parameter :: wp = real64
    integer :: calls = 0
contains
    @before
    subroutine set_up()
        calls = calls + 1
    end subroutine set_up

    @test
    subroutine test_passes()
        real(wp) :: x(3) = [1.0_wp, 2.0_wp, 3.0_wp]
        @assertEqual(1.0_wp, x(1) + 1.0e-13_wp, tolerance=1.0e-12_wp)
        @assertEqual([1.0_wp, 2.0_wp, 3.0_wp], x)
        @assertRelativelyEqual(100.0_wp, 100.5_wp, 1.0e-2_wp)
        @assertEqual(1, calls, 'before ran once')
        @assertEqual('abc', '  abc ')
        @assertLessThan(x(1), x(2))
        @assertIsFinite(x(3))
        @assertTrue(all(x > 0), message='positive')
        @assertFalse(.false.)
    end subroutine test_passes

    @test
    subroutine test_fails()
        @assertEqual(1.0_wp, 1.1_wp, 1.0e-3_wp, 'the message')
        @assertTrue(.false., 'not reached: the test returns after its first failure')
    end subroutine test_fails

    @test
    subroutine test_also_passes()
        @assertGreaterThanOrEqual(2, 2)
    end subroutine test_also_passes
end module test_e2e
"""


def build_end_to_end(tmp_path: Path, source: str = END_TO_END, name: str = "test_e2e") -> Path:
    """Translate ``source`` (the module ``name``), compile it with the runtime and a driver; the executable."""
    gfortran = shutil.which("gfortran")
    if gfortran is None:
        pytest.skip("gfortran not installed")
    (tmp_path / f"{name}.pf").write_text(source)
    gen = tmp_path / "generated"
    assert pf2f90.main(["-o", str(gen), str(tmp_path / f"{name}.pf")]) == 0
    exe = tmp_path / "driver"
    sources = [HERE / "pf_runtime.f90", gen / f"{name}.f90", gen / "pf_driver.f90"]
    build = subprocess.run(
        [gfortran, "-std=f2008", "-Wall", "-Wextra", "-Werror", "-fcheck=all", "-g",
         "-J", str(tmp_path), *map(str, sources), "-o", str(exe)],
        capture_output=True, text=True,
    )
    assert build.returncode == 0, build.stderr
    return exe


#: A test's time as the driver prints it: `    0.012 s  module::test`.
TIME_LINE = re.compile(r"^ *([0-9]+\.[0-9]{3}) s  (\S+)$")


def untimed(stdout: str) -> tuple[list[str], list[tuple[str, float]], list[tuple[str, float]]]:
    """The driver's output without its times: the other lines, then (name, seconds) of each test as it ran, then
    those of the list of the slowest (after its heading `slowest K of N tests (wall clock):`)."""
    lines, ran, slowest = [], [], []
    in_slowest = False
    for line in stdout.strip().splitlines():
        match = TIME_LINE.match(line)
        if re.fullmatch(r"slowest [0-9]+ of [0-9]+ tests \(wall clock\):", line):
            in_slowest = True
        elif match:
            (slowest if in_slowest else ran).append((match[2], float(match[1])))
        else:
            lines.append(line)
            in_slowest = False
    return lines, ran, slowest


@pytest.mark.slow
def test_end_to_end(tmp_path):
    exe = build_end_to_end(tmp_path)
    run = subprocess.run([str(exe)], capture_output=True, text=True, cwd=tmp_path, timeout=60)
    lines, ran, slowest = untimed(run.stdout)
    # each test's time, in the order they ran, and then all three again, slowest first, before the closing line
    assert [name for name, _ in ran] == ["test_e2e::test_passes", "test_e2e::test_fails", "test_e2e::test_also_passes"]
    assert sorted(slowest) == sorted(ran)
    assert [t for _, t in slowest] == sorted((t for _, t in ran), reverse=True)
    assert run.stdout.strip().splitlines()[-5] == "slowest 3 of 3 tests (wall clock):"
    assert lines[-1] == "fortran: 2 passed, 1 failed"
    assert run.returncode != 0
    fails = [line for line in lines if line.startswith("FAIL")]
    assert fails == [
        "FAIL test_e2e::test_fails (test_e2e.pf:29): assertEqual: expected 1.0 but found 1.1 "
        "(difference 0.10000000000000009, tolerance 0.001) -- the message"
    ]

    selected = subprocess.run([str(exe), "PASSES"], capture_output=True, text=True, cwd=tmp_path, timeout=60)
    assert selected.stdout.strip().splitlines()[-1] == "fortran: 2 passed, 0 failed"
    assert [name for name, _ in untimed(selected.stdout)[1]] == ["test_e2e::test_passes", "test_e2e::test_also_passes"]
    assert selected.returncode == 0


def with_set_up(name: str, set_up: str, test: str) -> str:
    """A module whose @before does ``set_up`` (line 7), whose one test does ``test`` (line 17) and whose
    @after prints ``tear-down ran``."""
    return f"""\
module {name}
    use funit
    implicit none
contains
    @before
    subroutine set_up()
        {set_up}
    end subroutine set_up

    @after
    subroutine tear_down()
        write(*, '(a)') 'tear-down ran'
    end subroutine tear_down

    @test
    subroutine test_it()
        {test}
    end subroutine test_it
end module {name}
"""


@pytest.mark.slow
@pytest.mark.parametrize(
    "name, set_up, test, ran, fail",
    [
        ("test_setup", "@assertTrue(.false., 'set-up fails')", "write(*, '(a)') 'test ran'", [],
         "FAIL test_setup::test_it (test_setup.pf:7): assertTrue: condition is .false. -- set-up fails"),
        ("test_teardown", "continue", "@assertTrue(.false., 'the test fails')", ["tear-down ran"],
         "FAIL test_teardown::test_it (test_teardown.pf:17): assertTrue: condition is .false. -- the test fails"),
    ],
)
def test_after_runs_only_when_before_passed(tmp_path, name, set_up, test, ran, fail):
    """As pFUnit's TestCase%runBare: a failed @before skips the test and @after; a failed test does not skip @after."""
    exe = build_end_to_end(tmp_path, with_set_up(name, set_up, test), name)
    run = subprocess.run([str(exe)], capture_output=True, text=True, cwd=tmp_path, timeout=60)
    assert untimed(run.stdout)[0] == [*ran, fail, "fortran: 0 passed, 1 failed"]
    assert run.returncode != 0


ORDER = """\
module test_order
    use funit
    implicit none
contains
    @test
    subroutine test_lt_equal()
        @assertLessThan(1, 1)
    end subroutine test_lt_equal

    @test
    subroutine test_le_equal()
        @assertLessThanOrEqual(1.0d0, [1.0d0, 0.5d0], 0.6d0)
    end subroutine test_le_equal

    @test
    subroutine test_gt_equal()
        @assertGreaterThan([1.0d0, 2.0d0], [1.0d0, 1.0d0])
    end subroutine test_gt_equal

    @test
    subroutine test_ge_equal()
        @assertGreaterThanOrEqual(1, [1, 2], message='ge')
    end subroutine test_ge_equal

    @test
    subroutine test_direct_call()
        call assertLessThan(1, 2)
    end subroutine test_direct_call
end module test_order
"""


@pytest.mark.slow
def test_order_assertions_take_their_relation_from_the_location(tmp_path):
    """The four order assertions share their specific procedures: each checks its own relation, and a
    call without the location that the @-macro passes fails instead of checking an arbitrary one."""
    exe = build_end_to_end(tmp_path, ORDER, "test_order")
    run = subprocess.run([str(exe)], capture_output=True, text=True, cwd=tmp_path, timeout=60)
    assert untimed(run.stdout)[0] == [
        "FAIL test_order::test_lt_equal (test_order.pf:7): assertLessThan: 1 is not less than 1",
        "FAIL test_order::test_gt_equal (test_order.pf:17): assertGreaterThan: 1.0 is not greater than 1.0 at index 1",
        "FAIL test_order::test_ge_equal (test_order.pf:22): assertGreaterThanOrEqual: 1 is not greater than or equal "
        "to 2 at index 2 -- ge",
        "FAIL test_order::test_direct_call: assertLessThan and its kin run only from their @-macros, whose location "
        "names the relation to check",
        "fortran: 1 passed, 4 failed",
    ]


def test_no_input_gives_an_empty_driver(tmp_path):
    assert pf2f90.main(["-o", str(tmp_path)]) == 0
    driver = (tmp_path / "pf_driver.f90").read_text()
    assert "call pf_driver_init()\n    call pf_driver_finish()" in driver


def test_warns_when_output_cannot_see_the_runtime(tmp_path, capsys):
    (tmp_path / "pf_runtime.f90").write_text("module pf_runtime\nend module pf_runtime\n")
    assert pf2f90.main(["-o", str(tmp_path / "generated")]) == 0
    assert "fpm will not let" in capsys.readouterr().err


def test_cmake_builds_every_shared_test_module():
    """The CMake/pFUnit build links each test against ``supratrans_test_lib``: every test/*.f90 that is neither a
    translation of a .pf (test_*.f90, pf_driver.f90) nor the stand-in runtime must be in it, or the tests that use
    it fail to compile there (``fpm test`` finds them by itself, so only this check sees one missing)."""
    cmake = (HERE.parent / "CMakeLists.txt").read_text()
    start = cmake.index("set(shared_test_modules")
    listed = set(cmake[start:cmake.index(")", start)].split()[1:])
    generated = {f"{p.stem}.f90" for p in HERE.glob("test_*.pf")} | {"pf_driver.f90", "pf_runtime.f90"}
    shared = {f"test/{p.name}" for p in HERE.glob("*.f90") if p.name not in generated}
    assert shared, "no shared test module found"
    assert listed == shared, f"CMakeLists.txt lists {sorted(listed)}, test/ has {sorted(shared)}"
