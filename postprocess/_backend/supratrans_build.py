"""The build backend of postprocess/ (PEP 517 and PEP 660): a wheel of the packages named in pyproject.toml, with
the metadata and console scripts of its [project] table, made with the standard library alone.

Why not setuptools: building a wheel with it needs the package `wheel` as well (setuptools < 70.1), which a machine
without network or with an old setuptools may not have; this backend needs nothing, so `pip install ./postprocess`
works offline, with or without build isolation. It supports only what pyproject.toml uses: name, version,
description, license (text), requires-python, dependencies, scripts, and [tool.supratrans-build] packages (every
.py file below each package). `pip install -e` gets a wheel holding a .pth file that puts this folder on sys.path.
"""
from __future__ import annotations

import base64
import hashlib
import io
import os
import re
import tarfile
import zipfile
from pathlib import Path

try:
    import tomllib
except ModuleNotFoundError:  # Python < 3.11
    import tomli as tomllib  # type: ignore[no-redef]

#: The folder of pyproject.toml (pip runs the hooks there).
HERE = Path.cwd()
#: Fixed time stamp of the archive members (1980-01-01, the earliest a zip file knows): the same wheel every time.
STAMP = (1980, 1, 1, 0, 0, 0)


def _project() -> dict:
    """The [project] table of pyproject.toml, and the packages of [tool.supratrans-build]."""
    data = tomllib.loads((HERE / "pyproject.toml").read_text())
    project = dict(data["project"])
    project["packages"] = data.get("tool", {}).get("supratrans-build", {}).get("packages", [])
    return project


def _names(project: dict) -> tuple[str, str]:
    """(file name stem of the distribution 'supratrans_post', its version)."""
    return re.sub(r"[-_.]+", "_", project["name"]).lower(), str(project["version"])


def _metadata(project: dict) -> str:
    """The METADATA file (core metadata 2.1)."""
    lines = ["Metadata-Version: 2.1", f"Name: {project['name']}", f"Version: {project['version']}"]
    if "description" in project:
        lines.append(f"Summary: {project['description']}")
    if "text" in project.get("license", {}):
        lines.append(f"License: {project['license']['text']}")
    if "requires-python" in project:
        lines.append(f"Requires-Python: {project['requires-python']}")
    lines += [f"Requires-Dist: {d}" for d in project.get("dependencies", [])]
    return "\n".join(lines) + "\n"


def _dist_info(project: dict) -> dict[str, str]:
    """The files of the .dist-info folder except RECORD, by name."""
    scripts = project.get("scripts", {})
    files = {"METADATA": _metadata(project),
             "WHEEL": "Wheel-Version: 1.0\nGenerator: supratrans_build\nRoot-Is-Purelib: true\nTag: py3-none-any\n"}
    if scripts:
        files["entry_points.txt"] = "[console_scripts]\n" + "".join(f"{k} = {v}\n" for k, v in scripts.items())
    return files


def _sources(project: dict) -> list[Path]:
    """Every .py file of the packages, relative to this folder, sorted."""
    out = []
    for pkg in project["packages"]:
        out += [p.relative_to(HERE) for p in (HERE / pkg.replace(".", "/")).rglob("*.py")
                if "__pycache__" not in p.parts]
    return sorted(out)


def _write_wheel(folder: str, payload: dict[str, bytes]) -> str:
    """Write the wheel of `payload` (archive name -> content, .dist-info added) into `folder`; its file name."""
    project = _project()
    stem, version = _names(project)
    info = f"{stem}-{version}.dist-info"
    files = dict(payload)
    files.update({f"{info}/{k}": v.encode() for k, v in _dist_info(project).items()})
    record = []
    for name, data in files.items():
        digest = base64.urlsafe_b64encode(hashlib.sha256(data).digest()).rstrip(b"=").decode()
        record.append(f"{name},sha256={digest},{len(data)}")
    record.append(f"{info}/RECORD,,")
    files[f"{info}/RECORD"] = ("\n".join(record) + "\n").encode()
    wheel = f"{stem}-{version}-py3-none-any.whl"
    with zipfile.ZipFile(Path(folder) / wheel, "w", zipfile.ZIP_DEFLATED) as zf:
        for name, data in files.items():
            member = zipfile.ZipInfo(name, STAMP)
            member.external_attr = 0o644 << 16
            member.compress_type = zipfile.ZIP_DEFLATED
            zf.writestr(member, data)
    return wheel


# ------------------------------------------------------------------------------------------------ PEP 517 hooks


def get_requires_for_build_wheel(config_settings=None) -> list[str]:
    """Nothing is needed to build."""
    return []


def get_requires_for_build_sdist(config_settings=None) -> list[str]:
    """Nothing is needed to build."""
    return []


def get_requires_for_build_editable(config_settings=None) -> list[str]:
    """Nothing is needed to build."""
    return []


def prepare_metadata_for_build_wheel(metadata_directory: str, config_settings=None) -> str:
    """The .dist-info folder of the wheel, for pip to read the dependencies before building."""
    project = _project()
    stem, version = _names(project)
    info = Path(metadata_directory) / f"{stem}-{version}.dist-info"
    info.mkdir(parents=True, exist_ok=True)
    for name, text in _dist_info(project).items():
        (info / name).write_text(text)
    return info.name


prepare_metadata_for_build_editable = prepare_metadata_for_build_wheel


def build_wheel(wheel_directory: str, config_settings=None, metadata_directory=None) -> str:
    """The wheel: the packages' .py files and the .dist-info."""
    return _write_wheel(wheel_directory, {p.as_posix(): (HERE / p).read_bytes() for p in _sources(_project())})


def build_editable(wheel_directory: str, config_settings=None, metadata_directory=None) -> str:
    """An editable wheel: a .pth file that puts this folder on sys.path (the packages are imported from here)."""
    stem, _ = _names(_project())
    return _write_wheel(wheel_directory, {f"{stem}.pth": (str(HERE.resolve()) + os.linesep).encode()})


def build_sdist(sdist_directory: str, config_settings=None) -> str:
    """A source archive: pyproject.toml, the backend, requirements.txt and the packages."""
    project = _project()
    stem, version = _names(project)
    base = f"{stem}-{version}"
    files = [Path("pyproject.toml"), Path("_backend/supratrans_build.py"), *_sources(project)]
    if (HERE / "requirements.txt").is_file():
        files.append(Path("requirements.txt"))
    pkg_info = _metadata(project).encode()
    name = f"{base}.tar.gz"
    with tarfile.open(Path(sdist_directory) / name, "w:gz", format=tarfile.PAX_FORMAT) as tf:
        for rel, data in [(Path("PKG-INFO"), pkg_info)] + [(p, (HERE / p).read_bytes()) for p in files]:
            member = tarfile.TarInfo(f"{base}/{rel.as_posix()}")
            member.size, member.mode, member.mtime = len(data), 0o644, 315532800
            tf.addfile(member, io.BytesIO(data))
    return name
