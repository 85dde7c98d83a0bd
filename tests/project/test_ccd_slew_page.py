"""The co-design page is what scripts/ccd_slew_page.py writes from the study's files, its tables
are narrow, and the numbers in its tables are the CSV values (rounded as printed).

References: the CSV files scripts/ccd_slew.py wrote into docs/ccd_slew/, read here with the
csv module, and the page in the repository (a rerun of the writer must reproduce it)."""

from __future__ import annotations

import csv
import importlib.util
import re
import shutil
import sys

from paths import ROOT

FOLDER = ROOT / "docs" / "ccd_slew"
FILES = ("summary.json", "open_loop.csv", "closed_loop.csv", "codesign.csv")


def _writer():
    spec = importlib.util.spec_from_file_location("ccd_slew_page",
                                                  ROOT / "scripts" / "ccd_slew_page.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module
    spec.loader.exec_module(module)
    return module


def _tables(text: str) -> list[list[list[str]]]:
    """Every Markdown table of ``text``: rows of cells, the separator row left out."""
    tables, rows = [], []
    for line in text.splitlines() + [""]:
        if line.startswith("|"):
            if not re.fullmatch(r"\|(---\|)+", line):
                rows.append([c.strip() for c in line.strip("|").split("|")])
        elif rows:
            tables.append(rows)
            rows = []
    return tables


def _written(tmp_path) -> str:
    for name in FILES:
        shutil.copy(FOLDER / name, tmp_path / name)
    page = _writer().write_page(tmp_path)
    assert (tmp_path / "ccd_slew_maps.png").stat().st_size > 0
    return page.read_text(encoding="utf-8")


def test_the_page_in_the_repository_is_the_writer_s(tmp_path):
    assert _written(tmp_path) == (FOLDER / "ccd_slew.md").read_text(encoding="utf-8")


def test_tables_are_narrow_and_every_figure_exists(tmp_path):
    text = _written(tmp_path)
    tables = _tables(text)
    assert len(tables) >= 5
    assert max(len(t[0]) for t in tables) <= 7  # the old page had 12 and 20 columns
    for name in re.findall(r"```\{figure\} (\S+)", text):
        assert (FOLDER / name).is_file(), name


def test_the_sweep_table_holds_the_csv_costs(tmp_path):
    text = _written(tmp_path)
    with open(FOLDER / "codesign.csv", newline="", encoding="utf-8") as f:
        sweep = list(csv.DictReader(f))
    table = next(t for t in _tables(text) if t[0][0] == "start (L)")
    cols = ["truth_designed", "5R on truth", "5R fitted on truth", "5R fitted-tip_z on truth"]
    assert len(table) - 1 == len(sweep)
    for row, want in zip(table[1:], sweep, strict=True):
        assert row[0] == want["start_frac"]
        got = [float(c.strip("*")) for c in row[1:]]
        assert got == [float(f"{float(want[c]):.4g}") for c in cols]
    # the bold cell of each column is the column's minimum in the CSV
    for k, c in enumerate(cols):
        best = min(range(len(sweep)), key=lambda i, c=c: float(sweep[i][c]))
        assert table[1 + best][1 + k].startswith("**")
