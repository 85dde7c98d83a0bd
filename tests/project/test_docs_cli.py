"""docs/cli.md is the command-line reference generated from the parsers of ``prbdm`` by
scripts/docs_cli.py: the committed page must be what the parsers give today, so an option added
or changed without regenerating the page fails here."""

from __future__ import annotations

import argparse
import importlib.util

from paths import ROOT

from prbdm_pin.cli import build_parser

REGENERATE = "run `python scripts/docs_cli.py` and commit docs/cli.md"


def _module():
    spec = importlib.util.spec_from_file_location("docs_cli", ROOT / "scripts" / "docs_cli.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _commands() -> dict[str, argparse.ArgumentParser]:
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices)


def _section(page: str, name: str) -> str:
    start = page.index(f"\n## prbdm {name}\n")
    end = page.find("\n## ", start + 1)
    return page[start:] if end < 0 else page[start:end]


def test_committed_page_is_up_to_date():
    committed = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    assert committed == _module().cli_page(), f"docs/cli.md is out of date: {REGENERATE}"


def test_every_option_of_every_command_is_on_its_section():
    # independent of the generator: the option strings and help words `--help` itself prints
    page = (ROOT / "docs" / "cli.md").read_text(encoding="utf-8")
    commands = _commands()
    assert len(commands) >= 9
    for name, parser in commands.items():
        section = _section(page, name)
        help_text = parser.format_help()
        for action in parser._actions:
            if isinstance(action, argparse._HelpAction):  # every command has -h; not listed
                continue
            for option in action.option_strings:
                assert option in help_text
                assert f"`{option}" in section or f", {option}" in section, \
                    f"prbdm {name} {option} is missing from docs/cli.md: {REGENERATE}"
            if action.help and action.help != argparse.SUPPRESS:
                first = action.help.split()[0].strip("(`")
                assert first in section, f"prbdm {name}: help of {action.dest} not on the page"
        if parser.epilog:
            assert parser.epilog.strip().splitlines()[0] in section


def test_a_new_option_changes_the_page(monkeypatch):
    mod = _module()
    before = mod.cli_page()

    def with_extra_option():
        parser = build_parser()
        sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        sub.choices["fit"].add_argument("--brand-new", type=float, default=3.5,
                                        help="an option with 50%% more help")
        return parser

    monkeypatch.setattr(mod, "build_parser", with_extra_option)
    after = mod.cli_page()
    assert after != before
    assert "| `--brand-new BRAND_NEW` | `3.5` | an option with 50% more help |" \
        in _section(after, "fit")


def test_page_does_not_depend_on_the_terminal_width(monkeypatch):
    mod = _module()
    monkeypatch.setenv("COLUMNS", "200")
    wide = mod.cli_page()
    monkeypatch.setenv("COLUMNS", "40")
    assert mod.cli_page() == wide


def test_markup_in_help_text_is_shown_literally():
    mod = _module()
    assert mod._escape("half_width[1], $PRBDM_CACHE, a|b, `prbdm fit --out_dir`") == \
        r"half\_width\[1\], \$PRBDM\_CACHE, a\|b, `prbdm fit --out_dir`"
