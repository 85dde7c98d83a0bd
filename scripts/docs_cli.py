"""Write docs/cli.md, the command-line reference, from the argparse parsers of ``prbdm``.

Every subcommand gets its usage, its description, one table row per argument (the invocation
``--help`` prints, the parser's default, the help text as ``--help`` expands it) and its epilog
(examples and notes) verbatim. ``tests/project/test_docs_cli.py`` regenerates the page in memory and
fails when the committed one differs, so an option cannot be added without its entry.

usage: python scripts/docs_cli.py [--out docs/cli.md]
"""

from __future__ import annotations

import argparse
import re
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from prbdm_pin.cli import build_parser  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402

DEFAULT_OUT = ROOT / "docs" / "cli.md"
# usage lines wrap at a fixed width, not at the terminal's, so the page does not depend on it
WIDTH = 96
# CommonMark lets a backslash escape any ASCII punctuation; these would otherwise start markup
# (emphasis, links, HTML, MyST roles and dollar math) or end a table cell
_MARKUP = re.compile(r"([\\*_\[\]<>$|{}~^#])")
_CODE_SPAN = re.compile(r"(`[^`]*`)")

HEADER = """\
# Command-line reference

<!-- written by `python scripts/docs_cli.py` from the parsers of `prbdm`; do not edit by hand -->

Every stage of the package is a subcommand of `prbdm` (also `python -m prbdm_pin`). This page is
generated from the command's own parsers, so it lists exactly what `prbdm COMMAND --help` prints:
each command's usage, its arguments with their defaults, and its examples. Options are checked
before any work starts; bad input gives one line naming the option and exit code 2 (see
[bad input, caps and the truth cache](guide/robustness.md)). The user guide explains what the
options mean: [truth models](guide/truth_models.md), [fitting](guide/fitting.md),
[simulation and exports](guide/simulation.md), [the plant](guide/plant.md),
[sensitivities](guide/sensitivities.md) and [batch studies](guide/batch.md).
"""


def _subparsers(parser: argparse.ArgumentParser) -> argparse._SubParsersAction:
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            return action
    raise ValueError(f"{parser.prog} has no subcommands")


def _formatter(parser: argparse.ArgumentParser) -> argparse.HelpFormatter:
    return parser.formatter_class(prog=parser.prog, width=WIDTH)


def _escape(text: str) -> str:
    """``text`` as Markdown that shows it literally, inline code spans kept as code."""
    parts = _CODE_SPAN.split(" ".join(text.split()))
    return "".join(p if p.startswith("`") and p.endswith("`") and len(p) > 1
                   else _MARKUP.sub(r"\\\1", p) for p in parts)


def _usage(parser: argparse.ArgumentParser) -> str:
    formatter = _formatter(parser)
    formatter.add_usage(parser.usage, parser._actions, parser._mutually_exclusive_groups)
    return formatter.format_help().strip()


def _default(action: argparse.Action) -> str:
    if action.required or action.default in (None, argparse.SUPPRESS, []):
        return ""
    if action.nargs == 0:  # flags: their default is the absence of the flag
        return ""
    return f"`{action.default}`"


def _argument_rows(parser: argparse.ArgumentParser) -> list[str]:
    formatter = _formatter(parser)
    rows = ["| argument | default | description |", "|---|---|---|"]
    for action in parser._actions:
        if action.help == argparse.SUPPRESS or isinstance(action, argparse._HelpAction):
            continue
        invocation = f"`{formatter._format_action_invocation(action)}`"
        if action.required and action.option_strings:
            invocation += " (required)"
        text = formatter._expand_help(action) if action.help else ""
        if action.choices is not None and not action.option_strings and not text:
            text = "one of " + ", ".join(str(c) for c in action.choices)
        rows.append(f"| {invocation} | {_default(action)} | {_escape(text)} |")
    return rows


def _command_section(name: str, parser: argparse.ArgumentParser) -> list[str]:
    lines = [f"## prbdm {name}", ""]
    if parser.description:
        lines += [_escape(parser.description), ""]
    lines += ["```text", _usage(parser), "```", ""]
    lines += _argument_rows(parser) + [""]
    if parser.epilog:
        lines += ["```text", parser.epilog.strip("\n"), "```", ""]
    return lines


def cli_page() -> str:
    """The Markdown of docs/cli.md, built from the parsers of ``prbdm``.

    Returns
    -------
    str
        The page, ending with one newline.
    """
    parser = build_parser()
    sub = _subparsers(parser)
    helps = {a.dest: a.help for a in sub._choices_actions}
    lines = HEADER.splitlines() + ["", "```text", _usage(parser), "```", ""]
    lines += ["| command | does |", "|---|---|"]
    for name in sub.choices:
        lines.append(f"| [`prbdm {name}`](#prbdm-{name}) | {_escape(helps.get(name) or '')} |")
    lines.append("")
    for name, command in sub.choices.items():
        lines += _command_section(name, command)
    return "\n".join(lines).rstrip("\n") + "\n"


def main() -> None:
    """Write the command-line reference page."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(DEFAULT_OUT), help="page to write (default docs/cli.md)")
    args = ap.parse_args()
    print(f"wrote {atomic_write_text(args.out, cli_page())}")


if __name__ == "__main__":
    main()
