"""Run the examples in full mode and, with ``--write-docs``, copy their figures onto the example
pages (``docs/examples/figures/NAME.png``).

The examples write only under their ``--out``; the figures on the example pages change only
through this script and its explicit flag. Without ``--write-docs`` the figures stay under
``--out`` for a look first.

usage: python scripts/docs_example_figures.py [--write-docs] [--out results/examples]
                                              [NAME ...]
"""

from __future__ import annotations

import argparse
import importlib.util
import shutil
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

FIGURES = ROOT / "docs" / "examples" / "figures"


def _main_of(name: str):
    spec = importlib.util.spec_from_file_location(f"example_{name}",
                                                  ROOT / "examples" / f"{name}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.main


def main(argv: list[str] | None = None) -> int:
    names = sorted(p.stem for p in (ROOT / "examples").glob("*.py"))
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("names", nargs="*", metavar="NAME", help=f"examples (default all: {names})")
    ap.add_argument("--out", default=str(ROOT / "results" / "examples"),
                    help="parent of each example's --out")
    ap.add_argument("--write-docs", action="store_true",
                    help="copy each figure to docs/examples/figures/NAME.png")
    args = ap.parse_args(argv)
    unknown = sorted(set(args.names) - set(names))
    if unknown:
        ap.error(f"NAME = {unknown}: not an example (one of {names})")
    for name in args.names or names:
        res = _main_of(name)(quick=False, out=Path(args.out) / name)
        figure = Path(res["figure"])
        if args.write_docs:
            shutil.copyfile(figure, FIGURES / f"{name}.png")
            print(f"{name}: {figure} -> {FIGURES / (name + '.png')}")
        else:
            print(f"{name}: {figure}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
