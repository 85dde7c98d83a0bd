"""The parser sphinx-argparse documents on docs/cli.md: ``prbdm``'s own, its help texts shown
literally.

sphinx-argparse parses descriptions, help texts and epilogs as reStructuredText. The commands'
epilogs are preformatted (``RawDescriptionHelpFormatter``: example command lines with
continuations, notes), and help texts hold characters that reStructuredText reads as markup
(``*``, ``|``, a backslash, ``$``), so each is given to it as literal text: epilogs and
descriptions as literal blocks, help texts with their markup characters escaped and inline
```code``` kept as code. The parser ``prbdm --help`` prints is not changed.
"""

from __future__ import annotations

import argparse
import re
import textwrap

from prbdm_pin.cli import build_parser

# reStructuredText inline markup starts or ends at these; a backslash shows them literally
_MARKUP = re.compile(r"([\\*|_`<>\[\]])")
# inline code, and option names (Sphinx's smart quotes would turn a "--" in prose into a dash)
_CODE_SPAN = re.compile(r"(`[^`]+`|(?<![\w`-])--?[A-Za-z][\w-]*)")


def _literal_help(text: str) -> str:
    """One-paragraph help as reStructuredText that shows it as ``--help`` does."""
    parts = _CODE_SPAN.split(" ".join(text.split()))
    return "".join(_code(p) if i % 2 else _MARKUP.sub(r"\\\1", p) for i, p in enumerate(parts))


def _code(span: str) -> str:
    """An inline code span or an option name as reStructuredText inline literal."""
    return f"``{span.strip('`')}``"


def _literal_block(text: str) -> str:
    """Preformatted text (an epilog) as a reStructuredText literal block, kept line for line."""
    return "::\n\n" + textwrap.indent(textwrap.dedent(text).strip("\n"), "    ")


def _subparsers(parser: argparse.ArgumentParser):
    return [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]


def _literal(parser: argparse.ArgumentParser) -> None:
    raw = issubclass(parser.formatter_class, argparse.RawDescriptionHelpFormatter)
    if parser.epilog:
        parser.epilog = _literal_block(parser.epilog) if raw else _literal_help(parser.epilog)
    if parser.description:
        parser.description = (_literal_block(parser.description) if raw and
                              "\n" in parser.description.strip()
                              else _literal_help(parser.description))
    for action in parser._actions:
        if action.help and action.help != argparse.SUPPRESS:
            # argparse's own %-expansion first (%(default)s, %%), as --help prints it
            params = dict(vars(action), prog=parser.prog)
            for name in list(params):
                if hasattr(params[name], "__name__"):
                    params[name] = params[name].__name__
            if params.get("choices") is not None:
                params["choices"] = ", ".join(map(str, params["choices"]))
            try:
                text = action.help % params
            except (KeyError, TypeError, ValueError):  # not a %-template: shown as written
                text = action.help
            action.help = _literal_help(text).replace("%", "%%")
    for sub in _subparsers(parser):
        for choice in sub._choices_actions:
            if choice.help:
                choice.help = _literal_help(choice.help)
        for child in sub.choices.values():
            _literal(child)


def build_docs_parser() -> argparse.ArgumentParser:
    """``prbdm_pin.cli.build_parser()`` with its texts made literal for reStructuredText."""
    parser = build_parser()
    _literal(parser)
    return parser
