"""Rules every Fortran source must keep so that each way of building it works: the CMake build with the Ninja
generator runs every source through the C preprocessor (`gfortran -cpp -E`) for its dependency scan, where a `/*`
anywhere, even in a `!` comment, opens a C comment that never ends and stops the build ("unterminated comment").
And the house rule of the library (issue 21): one module a file, named after it. No rule on a file's length: a module
is split where it has a seam, never to reach a number of lines (issue 40).
"""
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def fortran_sources():
    """Every Fortran source a build compiles: src/, app/ and the tests (pFUnit's .pf and their translations)."""
    paths = []
    for folder in ("src", "app", "test"):
        for pattern in ("*.f90", "*.F90", "*.pf"):
            paths += sorted((ROOT / folder).rglob(pattern))
    return paths


def test_the_sources_are_found():
    names = {p.name for p in fortran_sources()}
    assert "supratrans_scene_workprec.f90" in names and "test_continuation.pf" in names


def test_no_source_opens_a_c_comment():
    found = []
    for path in fortran_sources():
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if "/*" in line:
                found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert not found, "'/*' breaks the preprocessed (CMake + Ninja) build:\n" + "\n".join(found)


def test_every_library_module_is_one_file_named_after_it():
    """One module (or submodule) a file of src/, the file named after it."""
    problems = []
    for path in sorted((ROOT / "src").rglob("*.f90")):
        lines = path.read_text(encoding="utf-8").splitlines()
        # "module NAME" or "submodule(PARENT) NAME": the name is the second word
        names = [line.split()[1] for line in lines if line.startswith(("module ", "submodule("))]
        if names != [path.stem]:
            problems.append(f"{path.relative_to(ROOT)}: units {names}")
    assert len(list((ROOT / "src").rglob("*.f90"))) > 50
    assert not problems, "\n".join(problems)


def code_part(line):
    """A Fortran line without its `!` comment (a `!` inside a string literal is kept)."""
    quote = None
    for i, ch in enumerate(line):
        if quote:
            if ch == quote:
                quote = None
        elif ch in "'\"":
            quote = ch
        elif ch == "!":
            return line[:i]
    return line


def test_only_physics_and_io_name_a_potential():
    """The on-site potential is a type (src/physics/potentials/, issue 40): outside src/physics/ and src/io/ no code
    names a particular potential (identifier or name) or tests which one a chain has; they call the type."""
    import re
    names = re.compile(r"(sine|klein)[-_ ]?gordon", re.IGNORECASE)
    tests = re.compile(r"%potential\s*(==|/=|\.eq\.|\.ne\.)|case\s*\(.*%potential\s*\)|potential\s*(==|/=)\s*\d",
                       re.IGNORECASE)
    found = []
    sources = sorted(p for p in (ROOT / "src").rglob("*") if p.suffix in (".f90", ".F90", ".c"))
    for path in sources:
        if path.relative_to(ROOT).parts[1] in ("physics", "io"):
            continue
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            code = code_part(line) if path.suffix != ".c" else line
            if names.search(code) or tests.search(code):
                found.append(f"{path.relative_to(ROOT)}:{number}: {line.strip()}")
    assert len(sources) > 50
    assert not found, "a potential named or tested outside src/physics and src/io:\n" + "\n".join(found)


def test_the_potential_check_sees_a_violation(tmp_path):
    """The check above is not vacuous: it flags a line that tests a potential and passes its comment-only form."""
    import re
    tests = re.compile(r"%potential\s*(==|/=|\.eq\.|\.ne\.)", re.IGNORECASE)
    assert tests.search(code_part("        if (run%chain%potential == sine_gordon) then"))
    assert not tests.search(code_part("        x = 1  ! if (run%chain%potential == sine_gordon)"))
    assert code_part("        s = 'a!b' ! c") == "        s = 'a!b' "
