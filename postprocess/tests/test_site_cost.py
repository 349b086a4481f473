"""The site-step cost chart (`scaling.py --site-cost`, issue 24 point 3): the benchmark's CSV is read, checked and
drawn (cost against N with the 1.2x line, bandwidth against the triad's), nothing is run, and a bad file is one line
with exit status 2."""
from __future__ import annotations

from pathlib import Path

import pytest

from supratrans_post import scaling
from supratrans_post.reader import PlotError

pytest.importorskip("matplotlib")

HEADER = ",".join(scaling.SITE_COST_COLUMNS)


def write_csv(path: Path, rows: list[tuple[float, ...]], header: str = HEADER) -> Path:
    path.write_text(header + "\n" + "".join(",".join(f"{v:.6e}" for v in r) + "\n" for r in rows))
    return path


#: Three points in the benchmark's order, N descending in the file to check the sort.
ROWS = [(1.0e5, 12.0, 1.5, 220.0, 18.3, 20.0), (1.0e3, 10.0, 1.5, 220.0, 22.0, 20.0),
        (1.0e4, 10.5, 1.5, 220.0, 21.0, 20.0)]


def test_rows_read_sorted_and_tabled(tmp_path):
    rows = scaling.read_site_cost(write_csv(tmp_path / "s.csv", ROWS))
    assert [r["n"] for r in rows] == [1.0e3, 1.0e4, 1.0e5]
    table = scaling.site_cost_table(rows)
    assert len(table) == 2 + 3
    # the cost relative to the smallest N: 12/10 at N = 1e5, and the bandwidth share 18.3/20
    assert "| 100000 | 12.00 | 1.200 |" in table[-1] and table[-1].endswith("| 0.92 |")


def test_chart_holds_the_data(tmp_path):
    rows = scaling.read_site_cost(write_csv(tmp_path / "s.csv", ROWS))
    fig = scaling.draw_site_cost(rows)
    cost, bandwidth = fig.axes[:2]
    x, y = cost.lines[0].get_data()
    assert list(x) == [1.0e3, 1.0e4, 1.0e5] and list(y) == [10.0, 10.5, 12.0]
    assert cost.lines[1].get_ydata()[0] == pytest.approx(12.0)     # the goal line, 1.2 x the smallest N's cost
    assert list(bandwidth.lines[0].get_ydata()) == [22.0, 21.0, 18.3]
    assert list(bandwidth.lines[1].get_ydata()) == [20.0, 20.0, 20.0]


@pytest.mark.parametrize("text", ["", "n,cost\n1,2\n", HEADER + "\n", HEADER + "\n1000,10,1.5,220,22\n",
                                  HEADER + "\n1000,ten,1.5,220,22,20\n", HEADER + "\n1000,-1,1.5,220,22,20\n",
                                  HEADER + "\n1000,nan,1.5,220,22,20\n"])
def test_bad_files_are_refused(tmp_path, text):
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(PlotError):
        scaling.read_site_cost(path)


def test_main_draws_without_running(tmp_path, call_main, monkeypatch):
    """--site-cost runs nothing (no executable is asked for): the table, and the image where -o says."""
    monkeypatch.setattr(scaling, "executable", lambda: pytest.fail("--site-cost must not build or run"))
    csv = write_csv(tmp_path / "s.csv", ROWS)
    proc = call_main(scaling.main, "--site-cost", csv, "-o", tmp_path / "out" / "site_cost.png")
    assert proc.returncode == 0, proc.stderr
    assert proc.stdout.splitlines()[0].startswith("| N | ns per site-step |")
    assert (tmp_path / "out" / "site_cost.png").read_bytes()[:4] == b"\x89PNG"
    proc = call_main(scaling.main, "--site-cost", tmp_path / "missing.csv", "-o", tmp_path / "m.png")
    assert proc.returncode == 2 and proc.stderr.strip().startswith("error: ")
    assert len(proc.stderr.strip().splitlines()) == 1 and not (tmp_path / "m.png").exists()


def test_committed_data_is_readable():
    """The benchmark's committed output (postprocess/data/site_cost.csv) is a valid table from N = 10^3 on."""
    rows = scaling.read_site_cost(Path(__file__).resolve().parents[1] / "data" / "site_cost.csv")
    assert rows[0]["n"] == 1000 and len(rows) >= 4
