"""The ``prbdm`` command line.

Each subcommand lives in ``prbdm_pin/commands/<name>.py`` and exposes ``add_parser(subparsers)``
(which sets ``func`` on its parser) and the function it runs. This module only wires them together
and turns input errors into one clear line and exit code 2.
"""

from __future__ import annotations

import argparse
import contextlib
import importlib
import io
import json
import os
import sys

from .commands.checks import CliParser, one_line, run_reported
from .version import __version__

# Order is the order of `prbdm --help`.
COMMANDS = ("truth", "sensitivity", "fit", "pareto", "simulate", "linearize", "statics", "export",
            "calibrate", "view", "batch", "batch_report", "bench")


def _pin_threads() -> None:
    # A threaded BLAS made small eigensolves ~60x slower on 2 cores: one thread unless told.
    for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
        os.environ.setdefault(var, "1")


def build_parser() -> argparse.ArgumentParser:
    """Build the argument parser with every available subcommand."""
    # subparsers take the parser class of their parent: every error of every command is one line
    parser = CliParser(
        prog="prbdm",
        description="Pseudo-rigid-body dynamic models of compliant cantilevers on Pinocchio.",
        epilog="Run `prbdm COMMAND --help` for a command's options and examples.",
    )
    parser.add_argument("--version", action="version", version=f"prbdm_pin {__version__}")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in COMMANDS:
        try:
            module = importlib.import_module(f".commands.{name}", __package__)
        except ModuleNotFoundError as exc:
            if exc.name == f"{__package__}.commands.{name}":
                continue
            raise
        module.add_parser(sub)
    from .commands.json_summary import add_json_option

    for command in {id(p): p for p in sub.choices.values()}.values():
        add_json_option(command)
    return parser


def main(argv: list[str] | None = None) -> int:
    """Entry point of ``prbdm``; returns the exit code."""
    _pin_threads()
    parser = build_parser()
    args, unknown = parser.parse_known_args(argv)
    if unknown:
        # reported by the command's own parser, so that the line names the command
        prog = f"prbdm {args.command}" if getattr(args, "command", None) else "prbdm"
        parser.exit(2, f"{prog}: error: unrecognized arguments: {one_line(' '.join(unknown))}\n")
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    prog = f"prbdm {args.command}"
    if not getattr(args, "json", False):
        return run_reported(prog, lambda: args.func(args))
    # --json: stdout holds the JSON object only; what the command says goes to stderr
    from .commands.json_summary import json_summary

    err = io.StringIO()
    with contextlib.redirect_stdout(sys.stderr), contextlib.redirect_stderr(err):
        rc = run_reported(prog, lambda: args.func(args))
    text = err.getvalue()
    sys.stderr.write(text)
    error = next((line.split("error: ", 1)[-1].split("failed: ", 1)[-1]
                  for line in text.splitlines()
                  if line.startswith(f"{prog}: error:") or line.startswith(f"{prog}: failed:")),
                 None)
    print(json.dumps(json_summary(args.command, args, rc, error), indent=2))
    return rc

if __name__ == "__main__":  # ``python -m prbdm_pin.cli``, as ``python -m prbdm_pin``
    raise SystemExit(main())
