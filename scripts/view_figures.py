"""The figures of the guide's page on viewing a model (docs/guide/viewing.md), by ``prbdm view``.

Fits a 3-node spatial chain (axes xy: bending and torsion) of the tapered beam to its plate truth
(eigen objective, joint springs; the truth cached in the output folder), then runs ``prbdm view``
on the fit: the mode shapes beside the truth's and the release from the static pose under the
beam's tip force, 40 frames. Copies ``modes.png`` and ``response.gif`` into ``--out`` and writes
``view_figures.md``: the commands run and the modes' frequencies and errors, as the page quotes
them.

usage: python scripts/view_figures.py [--out docs/guide/viewing]
"""

from __future__ import annotations

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")

import argparse  # noqa: E402
import json  # noqa: E402
import shutil  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
from pathlib import Path  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from prbdm_pin.cli import main as prbdm  # noqa: E402
from prbdm_pin.io.atomic import atomic_write_text  # noqa: E402

BEAM = ROOT / "examples" / "beams" / "tapered.json"
FIT_OPTIONS = ("--joints", "3", "--axes", "xy", "--objective", "eigen", "--stiffness", "joint",
               "--starts", "2")


def run(out: Path) -> None:
    """Fit, view, and copy the figures and the table into ``out``."""
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        fit = ["fit", str(BEAM), *FIT_OPTIONS, "--cache-dir", str(work / "cache"),
               "--out", str(work / "fit"), "-q"]
        view = ["view", str(work / "fit" / "fit.json"), "--frames", "40",
                "--cache-dir", str(work / "cache"), "--out", str(work / "view"), "-q"]
        for argv in (fit, view):
            rc = prbdm([*argv])
            if rc:
                raise SystemExit(rc)
        out.mkdir(parents=True, exist_ok=True)
        for name in ("modes.png", "response.gif"):
            shutil.copyfile(work / "view" / name, out / name)
        d = json.loads((work / "fit" / "fit.json").read_text())
    rows = ["| model mode | kind | model (rad/s) | truth (rad/s) | error (%) |",
            "|---|---|---|---|---|"]
    matched = sorted((r for r in d["modes"] if r["omega_model_rad_s"] is not None),
                     key=lambda r: r["omega_model_rad_s"])
    for k, r in enumerate(matched):
        rows.append(f"| {k + 1} | {r['kind']} | {r['omega_model_rad_s']:.6g} | "
                    f"{r['omega_truth_rad_s']:.6g} | {r['error_pct']:+.3g} |")
    text = ("<!-- written by scripts/view_figures.py: do not edit -->\n\n"
            f"```text\nprbdm fit {BEAM.relative_to(ROOT)} {' '.join(FIT_OPTIONS)} --out fit\n"
            "prbdm view fit/fit.json --frames 40 --out view\n```\n\n"
            + "\n".join(rows) + "\n")
    atomic_write_text(out / "view_figures.md", text)
    print(f"wrote {out}/modes.png, response.gif, view_figures.md")


if __name__ == "__main__":
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default=str(ROOT / "docs" / "guide" / "viewing"))
    run(Path(p.parse_args().out))
