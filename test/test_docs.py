"""The README and docs/: the README stays short, every relative link (file and #anchor) resolves, and every file,
folder and module of the repository they name exists, so that a rename or a removal shows up here and not in a
reader's hands."""
import itertools
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PAGES = [ROOT / "README.md"] + sorted((ROOT / "docs").glob("*.md"))
#: Top-level folders whose files the pages name by their path from the repository root.
TOP = ("src/", "app/", "test/", "input/", "postprocess/", "docs/", ".ci/")
#: Layers of src/, named without `src/` in the tables of the README and docs/code.md.
LAYERS = ("base/", "physics/", "numerics/", "run/", "tasks/", "scenes/", "io/", "cli/", "steppers/", "lapack/",
          "continuation/")


def slug(heading):
    """GitHub's anchor of a Markdown heading: lower case, punctuation but '-' and '_' dropped, spaces as '-'."""
    text = re.sub(r"[`*]", "", heading.strip().lower())
    text = re.sub(r"[^\w\- ]", "", text)
    return text.replace(" ", "-")


def anchors(page):
    """The anchors of a page's headings."""
    return {slug(m.group(1)) for m in re.finditer(r"^#{1,6} +(.+?) *$", page.read_text(encoding="utf-8"), re.M)}


def links(page):
    """Relative link targets of a page: Markdown links and <img src>, without external addresses."""
    text = page.read_text(encoding="utf-8")
    found = re.findall(r"\]\(([^)\s]+)\)", text) + re.findall(r'<img src="([^"]+)"', text)
    return [t for t in found if not re.match(r"[a-z]+:", t)]


def expand(token):
    """`a{b,c}d` -> [abd, acd] (as a shell would)."""
    parts = re.split(r"(\{[^{}]*\})", token)
    choices = [p[1:-1].split(",") if p.startswith("{") else [p] for p in parts]
    return ["".join(c) for c in itertools.product(*choices)]


def code_spans(page):
    """The texts between backticks of a page, code blocks included line by line."""
    text = page.read_text(encoding="utf-8")
    spans = re.findall(r"`([^`\n]+)`", text)
    for block in re.findall(r"```[a-z]*\n(.*?)```", text, re.S):
        spans += block.split()
    return spans


def test_readme_is_short():
    lines = (ROOT / "README.md").read_text(encoding="utf-8").count("\n")
    assert lines <= 250, f"README.md has {lines} lines; move detail into docs/"


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_relative_links_resolve(page):
    bad = []
    for target in links(page):
        path, _, anchor = target.partition("#")
        dest = (page.parent / path).resolve() if path else page
        if not dest.exists():
            bad.append(f"{target}: no such file")
        elif anchor and dest.suffix == ".md" and anchor not in anchors(dest):
            bad.append(f"{target}: no heading with anchor #{anchor}")
    assert not bad, f"{page.name}: " + "; ".join(bad)


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_named_files_exist(page):
    """Paths from the root (`src/io/schema.toml`, `input/fig1_{sg,kg}_A{177,179}.nml`) and from src/
    (`physics/supratrans_chain.f90`) that a page names exist; generated and run-time files are not looked for."""
    bad = []
    for span in code_spans(page):
        for word in re.findall(r"[\w./{},*-]+", span):
            word = word.rstrip(".,")
            if word.startswith(TOP):
                candidates = [ROOT]
            elif word.startswith(LAYERS) and word.endswith((".f90", ".c", ".py", ".toml", "/")):
                candidates = [ROOT / "src", ROOT / "src" / "numerics"]
            else:
                continue
            if re.search(r"<|X\.|\bI\b|/N\b|api/|test_\*\.f90|pf_driver", word):
                continue                     # placeholders, generated and git-ignored files
            for path in expand(word):
                if not any(list(base.glob(path)) for base in candidates):
                    bad.append(path)
    assert not bad, f"{page.name} names files that do not exist: {sorted(set(bad))}"


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.name)
def test_named_modules_exist(page):
    modules = set()
    for source in (ROOT / "src").rglob("*.f90"):
        modules |= set(re.findall(r"^\s*module\s+(\w+)\s*$", source.read_text(encoding="utf-8"), re.M | re.I))
    bad = []
    for span in code_spans(page):
        for word in re.findall(r"\bsupratrans_[\w{},]+(?:\.\w+)?", span):
            for name in expand(word):
                if "." in name:          # a source file: supratrans_os.c
                    if not list((ROOT / "src").rglob(name)):
                        bad.append(name)
                elif name != "supratrans_post" and name.lower() not in modules:
                    bad.append(name)
    assert not bad, f"{page.name} names modules that do not exist: {sorted(set(bad))}"
