"""Where a benchmark script's Markdown tables go: always to its ``--out`` file, and, when that is
the script's default, also to ``docs/benchmarks/<name>.md``, which the benchmarks page of the docs
includes. A run with another ``--out`` (a test, a variant study) leaves the docs alone."""

from __future__ import annotations

import os
from pathlib import Path

from prbdm_pin.io.atomic import atomic_write_text

ROOT = Path(__file__).resolve().parents[1]
DOCS_TABLES = ROOT / "docs" / "benchmarks"


def write_table(out: str | os.PathLike, text: str, default_out: str | os.PathLike,
                name: str, docs_tables: str | os.PathLike = DOCS_TABLES) -> list[Path]:
    """Write ``text`` to ``out``; when ``out`` is ``default_out``, to the docs table ``name`` too.

    Parameters
    ----------
    out, default_out : path
        The file the run was asked to write and the script's default for it.
    text : str
        The Markdown the script writes.
    name : str
        The docs table's name: ``docs/benchmarks/<name>.md``.
    docs_tables : path
        The docs tables' folder (default ``docs/benchmarks``).

    Returns
    -------
    list of Path
        The files written.
    """
    written = [atomic_write_text(out, text)]
    if Path(out).resolve() == Path(default_out).resolve():
        written.append(atomic_write_text(Path(docs_tables) / f"{name}.md", text))
    return written
