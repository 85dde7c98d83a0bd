"""``--json``: every command's summary as one JSON object on stdout, for scripts.

With ``--json`` the human summary a command prints goes to stderr instead, and stdout holds
only ``{"command", "exit_code", "versions", "out", "files", "summary"}``: the files the command
wrote (relative to ``out``), and from its main record (``fit.json``, ``truth.json``,
``statics.json``, ``linear_model.json``, ...) the top-level numbers, strings and short numeric
lists, per-mode errors included. A command refused once its options parsed (exit 2) or whose
solve failed (exit 1) still prints the object, with ``"error"`` the line it wrote to stderr;
an option the parser itself refuses is one line on stderr, exit 2, as without ``--json``.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

__all__ = ["add_json_option", "json_summary", "RECORD_FILES"]

# the file whose top-level fields summarise each command's result (None: the files only)
RECORD_FILES = {
    "truth": "truth.json", "sensitivity": "sensitivity.json", "fit": "fit.json",
    "pareto": "fit.json", "simulate": None, "linearize": "linear_model.json",
    "statics": "statics.json", "calibrate": "calibration.json", "batch": None,
    "batch-report": None, "bench": "results.json",
}
_MAX_LIST = 64  # longer lists (trajectories, matrices) stay in the files


def add_json_option(parser) -> None:
    """Add ``--json`` to a command's parser."""
    parser.add_argument("--json", action="store_true",
                        help="print a JSON summary on stdout (the files written and the key "
                             "numbers of the result); the human summary goes to stderr")


def _short(value: Any) -> bool:
    if value is None or isinstance(value, (bool, int, float, str)):
        return True
    return (isinstance(value, list) and len(value) <= _MAX_LIST
            and all(isinstance(v, (int, float)) or v is None for v in value))


def _record_summary(path: Path) -> dict[str, Any]:
    try:
        doc = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    if not isinstance(doc, dict):
        return {}
    return {k: v for k, v in doc.items() if k not in ("versions", "seed") and _short(v)}


def _export_summary(path: Path) -> dict[str, Any]:
    if path.suffix == ".json":
        return _record_summary(path)
    from ..files.export_record import read_export_record

    try:
        rec = read_export_record(path.read_text(encoding="utf-8"))
    except (OSError, ValueError):
        return {}
    return {} if rec is None else {k: v for k, v in rec.to_dict().items() if _short(v)}


def json_summary(command: str, args: Any, exit_code: int, error: str | None = None
                 ) -> dict[str, Any]:
    """Return the ``--json`` object of a finished command.

    Parameters
    ----------
    command : str
        The subcommand as typed (``"fit"``, ``"batch-report"``).
    args : argparse.Namespace
        Its parsed arguments (``out`` is read).
    exit_code : int
        What the command returned.
    error : str, optional
        The one-line error of a refused or failed command.

    Returns
    -------
    dict
        JSON-ready.
    """
    from ..io.provenance import provenance

    out = getattr(args, "out", None)
    doc: dict[str, Any] = {"command": command, "exit_code": int(exit_code),
                           **provenance(), "out": out, "files": [], "summary": {}}
    doc.pop("seed")
    if error is not None:
        doc["error"] = error
    if exit_code != 0 or out is None:
        return doc
    p = Path(out)
    if p.is_file():
        doc["files"] = [p.name]
        doc["summary"] = _export_summary(p)
    elif p.is_dir():
        doc["files"] = sorted(f.name for f in p.iterdir() if f.is_file())
        name = RECORD_FILES.get(command)
        if name is not None and (p / name).is_file():
            doc["summary"] = _record_summary(p / name)
            seed = json.loads((p / name).read_text(encoding="utf-8")).get("seed")
            doc["seed"] = seed if isinstance(seed, int) else None
    doc["out"] = os.fspath(p)
    return doc
