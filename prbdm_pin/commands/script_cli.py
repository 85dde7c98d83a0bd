"""The command line of the example scripts: ``--quick`` and ``--out``, handled as ``prbdm`` does.

Every ``examples/*.py`` script ends with ``raise SystemExit(run_example(__doc__, OUT, main))``.
``--out`` goes through the check of the commands' ``--out`` (``commands.checks.writable_dir``)
before ``main`` runs, so a file, a path under a file, a folder in ``/proc``, ``/sys`` or
``/dev`` or one that cannot be written is refused before any computation and nothing is created.
A refusal (there or later, a :class:`~prbdm_pin.errors.BeamInputError`) is one line on stderr
and exit code 2; a solve that fails is one line and exit code 1; Ctrl-C exit code 130, as for
``prbdm``.
"""

from __future__ import annotations

import os
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

from ..io.paths import writable_dir
from .checks import CliParser, run_reported

__all__ = ["example_parser", "run_example"]


def example_parser(doc: str, default_out: str | os.PathLike, quick_help: str,
                   prog: str | None = None) -> CliParser:
    """Return the parser of an example script: ``--quick`` and ``--out`` (one-line errors)."""
    # sphinx-gallery runs a script with an empty __doc__
    p = CliParser(prog=prog or Path(sys.argv[0]).name,
                  description=doc.splitlines()[0] if doc else None)
    p.add_argument("--quick", action="store_true", help=quick_help)
    p.add_argument("--out", default=str(default_out), help=f"output folder (default {default_out})")
    return p


def run_example(doc: str, default_out: str | os.PathLike, main: Callable[[bool, Path], object],
                quick_help: str = "1D beam truth, seconds", argv: Sequence[str] | None = None,
                prog: str | None = None) -> int:
    """Parse the script's arguments, check ``--out``, run ``main(quick, out)``; the exit code.

    Parameters
    ----------
    doc : str
        The script's docstring (its first line is the description).
    default_out : path
        The folder ``--out`` defaults to.
    main : callable
        ``main(quick, out)`` of the script.
    quick_help : str
        What ``--quick`` does.
    argv : sequence of str, optional
        The arguments (default ``sys.argv[1:]``).
    prog : str, optional
        The script's name in messages (default the file name).

    Returns
    -------
    int
        0, 2 (a bad option or input: one line on stderr), 1 (a solve that failed) or 130.
    """
    parser = example_parser(doc, default_out, quick_help, prog)
    args = parser.parse_args(argv)
    def work() -> None:
        out = writable_dir(args.out, "--out")  # creates nothing: refused before any work
        main(args.quick, out)

    return run_reported(parser.prog, work)
