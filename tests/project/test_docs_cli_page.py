"""docs/cli.md is generated on each docs build by sphinx-argparse from ``build_parser``, through
docs/_ext/cli_docs.py, which hands it every help text, description and epilog as literal
reStructuredText. Checked here against docutils itself: what the page's parser renders from each
text is the text ``prbdm COMMAND --help`` prints (markup characters, option names, inline code,
the epilogs' lines), and the parser behind ``prbdm`` is left as it was."""

from __future__ import annotations

import argparse
import importlib.util
import textwrap

from docutils import nodes
from docutils.core import publish_doctree
from paths import ROOT

from prbdm_pin.cli import build_parser


def _cli_docs():
    spec = importlib.util.spec_from_file_location("cli_docs",
                                                  ROOT / "docs" / "_ext" / "cli_docs.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def _commands(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


def _rendered(rst: str) -> nodes.document:
    # docutils' own reader, quiet: a markup error fails the assertion below, not a print
    return publish_doctree(rst, settings_overrides={"report_level": 5, "halt_level": 5})


def _text(doc: nodes.document) -> str:
    return " ".join(doc.astext().split())


def test_help_texts_render_as_help_prints_them():
    docs_parser, plain = _cli_docs().build_docs_parser(), build_parser()
    docs_commands, commands = _commands(docs_parser), _commands(plain)
    assert docs_commands.keys() == commands.keys() and len(commands) >= 12
    checked = 0
    for name, parser in commands.items():
        docs_actions = {a.dest: a for a in docs_commands[name]._actions}
        for action in parser._actions:
            if not action.help or action.help == argparse.SUPPRESS:
                continue
            # argparse's expansion of the original (what --help prints) ...
            expected = parser._get_formatter()._expand_help(action)
            # ... against docutils' rendering of the page's text, after the same % expansion
            # sphinx-argparse applies
            rendered = _rendered(docs_actions[action.dest].help % {})
            # (a `code` span of --help is shown as code, without its backticks)
            assert _text(rendered) == " ".join(expected.replace("`", "").split()), \
                (name, action.dest)
            # nothing in a help text becomes markup other than inline code
            assert not list(rendered.findall(nodes.problematic)), (name, action.dest)
            assert not list(rendered.findall(nodes.emphasis)), (name, action.dest)
            checked += 1
    assert checked > 150


def test_epilogs_are_literal_blocks_line_for_line():
    docs_commands, commands = _commands(_cli_docs().build_docs_parser()), _commands(build_parser())
    raw = [n for n, p in commands.items()
           if issubclass(p.formatter_class, argparse.RawDescriptionHelpFormatter) and p.epilog]
    assert len(raw) >= 10
    for name in raw:
        blocks = list(_rendered(docs_commands[name].epilog).findall(nodes.literal_block))
        assert len(blocks) == 1, name
        assert blocks[0].astext() == textwrap.dedent(commands[name].epilog).strip("\n"), name


def test_markup_characters_and_options_are_shown_literally():
    literal = _cli_docs()._literal_help
    text = "a*b, |x|, x_1 [a] <b> `prbdm fit --out DIR`, --stiffness joint (-q), well-known"
    doc = _rendered(literal(text))
    assert _text(doc) == text.replace("`", "")
    codes = [n.astext() for n in doc.findall(nodes.literal)]
    assert codes == ["prbdm fit --out DIR", "--stiffness", "-q"]


def test_prbdm_parser_is_unchanged_by_the_docs_parser():
    before = build_parser().format_help()
    _cli_docs().build_docs_parser()
    assert build_parser().format_help() == before
