"""The scenes are one abstract type made by one factory: no Fortran source but the factory
(src/scenes/supratrans_scene_factory.f90) selects on a scene's name, and the factory has one case for each name of
the schema's scene choices. A comparison like `kind == "timeseries"` or `case ("map")` elsewhere would bring back
what `scene_type` replaced: a scene's behaviour spread over the command line, validation and limits."""
import re
import tomllib
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
FACTORY = ROOT / "src" / "scenes" / "supratrans_scene_factory.f90"


def scene_names():
    """The names of `&scene kind` (the schema's choices named "scene")."""
    schema = tomllib.loads((ROOT / "src" / "io" / "schema.toml").read_text(encoding="utf-8"))
    (choice,) = [c for c in schema["choices"] if c["name"] == "scene"]
    return choice["values"]


def selections(text, names):
    """The lines of a Fortran text that compare a string with one of `names` or select a case on one."""
    alternatives = "|".join(re.escape(n) for n in names)
    pattern = re.compile(rf"""(==|/=|\.eq\.|\.ne\.)\s*["']({alternatives})["']|["']({alternatives})["']\s*(==|/=)"""
                         rf"""|case\s*\(\s*["']({alternatives})["']""", re.I)
    lines = []
    for number, line in enumerate(text.splitlines(), 1):
        code = line.split("!", 1)[0]
        if pattern.search(code):
            lines.append(f"{number}: {line.strip()}")
    return lines


def test_only_the_factory_selects_on_a_scene_name():
    names = scene_names()
    found = {}
    for path in sorted((ROOT / "src").rglob("*.f90")) + sorted((ROOT / "app").rglob("*.f90")):
        if path == FACTORY:
            continue
        hits = selections(path.read_text(encoding="utf-8"), names)
        if hits:
            found[str(path.relative_to(ROOT))] = hits
    assert not found, f"selections on a scene's name outside the factory: {found}"


def test_the_factory_has_one_case_per_scene_name():
    text = FACTORY.read_text(encoding="utf-8")
    cases = re.findall(r"""case\s*\(\s*["']([a-z_]+)["']\s*\)""", text)
    assert sorted(cases) == sorted(scene_names())


def test_the_pattern_finds_a_selection():
    """The check above could fail: the pattern sees the forms the code used before the factory."""
    names = ["timeseries", "map"]
    assert selections('if (trim(cfg%scene%kind) == "timeseries") then', names)
    assert selections("        case ('map')", names)
    assert selections('if (kind /= "timeseries" .and. threads > 1) x = 1', names)
    assert not selections('call write_root(file, cfg, "map", "text")', names)
    assert not selections('! kind == "map" in a comment', names)
