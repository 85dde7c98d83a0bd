"""Reliability probe: bad CLI and API input, tampered caches, killed runs, signals.

Each module in ``scripts/probe_cases/`` defines ``cases()``, a list of ``(category, name, fn)``;
``fn()`` returns None when the package behaved (a clear BeamInputError / exit 2 naming the
field, a refused cache entry, a folder left whole ...) and raises AssertionError saying what
went wrong otherwise. The table of tried / passed per category goes to
``results/reliability_probe.md``; failures are listed below it.

    python scripts/reliability_probe.py [--only AREA ...]
"""

from __future__ import annotations

import argparse
import importlib.util
import os
import sys
import tempfile
import time
import traceback
from collections import Counter
from pathlib import Path

for var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(var, "1")

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent


def _modules(only: list[str] | None):
    for path in sorted((HERE / "probe_cases").glob("*.py")):
        if path.stem.startswith("_") or (only and path.stem not in only):
            continue
        spec = importlib.util.spec_from_file_location(f"probe_cases.{path.stem}", path)
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
        yield path.stem, mod


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--only", nargs="*", help="case modules to run (file stems)")
    ap.add_argument("--out", default=str(ROOT / "results" / "reliability_probe.md"))
    args = ap.parse_args(argv)
    tried, passed, failures = Counter(), Counter(), []
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory(prefix="prbdm-probe-") as scratch:
        os.environ["PRBDM_CACHE"] = str(Path(scratch) / "cache")
        for stem, mod in _modules(args.only):
            for category, name, fn in mod.cases():
                tried[category] += 1
                try:
                    fn()
                except AssertionError as exc:
                    failures.append((category, name, str(exc) or "assertion failed"))
                except Exception as exc:  # noqa: BLE001 - an unexpected exception is a failure
                    where = traceback.format_exc(limit=-1).strip().splitlines()[-2]
                    failures.append((category, name, f"{type(exc).__name__}: {exc} [{where}]"))
                else:
                    passed[category] += 1
                ok = not failures or failures[-1][:2] != (category, name)
                print(f"{stem}: {category}: {name}: {'ok' if ok else 'FAIL'}", flush=True)
    lines = ["# Reliability probe", "",
             f"`python scripts/reliability_probe.py` ({time.perf_counter() - t0:.0f} s)", "",
             "| category | tried | passed |", "|---|---:|---:|"]
    for cat in sorted(tried):
        lines.append(f"| {cat} | {tried[cat]} | {passed[cat]} |")
    lines.append(f"| **total** | {sum(tried.values())} | {sum(passed.values())} |")
    if failures:
        lines += ["", "## Failures", ""]
        lines += [f"- {c}: {n}: {why}" for c, n, why in failures]
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text("\n".join(lines) + "\n", encoding="utf-8")
    print("\n".join(lines))
    return 0 if not failures else 1


if __name__ == "__main__":
    sys.exit(main())
