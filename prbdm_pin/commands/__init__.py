"""One module per ``prbdm`` subcommand (see ``prbdm_pin.cli``)."""

import argparse


def add_common(parser: argparse.ArgumentParser) -> None:
    """Options every command shares."""
    parser.add_argument("-q", "--quiet", action="store_true", help="no progress bars or summaries")
