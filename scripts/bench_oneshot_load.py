"""What a one-shot process pays to load the compiled code: numba's import, its typing and target
registries (set up once, at the first cached function loaded), each further cached function,
and a first ``simulate`` through the compiled integrator against one through the exponential
integrator (which loads no numba).

Each figure is CPU time (``time.process_time``) in a fresh interpreter on this checkout, BLAS on
one thread, the least over ``--repeats`` processes. The scene of the simulations: the 3R
equal-link chain of ``uniform-narrow.json`` under a -0.5 N tip step, 1 s (``prbdm simulate``'s
scene in ``bench_revisions.py``). Writes a Markdown table to ``--out`` (default
results/bench_oneshot_load.md, then also docs/benchmarks/bench_oneshot_load.md).

usage: python scripts/bench_oneshot_load.py [--repeats 5] [--out FILE]
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "scripts"))  # the scripts' shared helpers
DEFAULT_OUT = ROOT / "results" / "bench_oneshot_load.md"

_SET_UP = """
import json, sys, time
import numpy as np
import scipy.linalg, pinocchio
import prbdm_pin as pp
from prbdm_pin.chain.stiffness import finite_segment_stiffness
beam = pp.load_beam("examples/beams/uniform-narrow.json")
lengths = np.full(4, 0.25) * beam.length_m
model = pp.build_model(beam, lengths, finite_segment_stiffness(beam, lengths))
force = np.array([0.0, 0.0, -0.5])
out = {}
def timed(key, fn):
    c = time.process_time()
    r = fn()
    out[key] = time.process_time() - c
    return r
"""
# the loads in the order a process meets them
_LOADS = _SET_UP + """
import importlib
timed("import numba", lambda: importlib.import_module("numba"))
timed("first cached function (chain.small_eigen): numba's registries",
      lambda: importlib.import_module("prbdm_pin.chain.small_eigen"))
timed("a further cached function (chain.planar_mass_kernel)",
      lambda: importlib.import_module("prbdm_pin.chain.planar_mass_kernel"))
timed("first simulate, compiled (its modules, scipy.integrate, cache loads, run)",
      lambda: pp.simulate(model, 1.0, tip_force=force, integrator=pp.Compiled()))
timed("second simulate, compiled (the run)",
      lambda: pp.simulate(model, 1.0, tip_force=force, integrator=pp.Compiled()))
print(json.dumps(out))
"""
_EXPONENTIAL = _SET_UP + """
timed("first simulate, exponential (no numba)",
      lambda: pp.simulate(model, 1.0, tip_force=force, integrator=pp.Exponential()))
timed("second simulate, exponential (the run)",
      lambda: pp.simulate(model, 1.0, tip_force=force, integrator=pp.Exponential()))
assert "numba" not in sys.modules
print(json.dumps(out))
"""
_AUTO = _SET_UP + """
trajectory = timed("first simulate, default (Auto) in a fresh process",
                   lambda: pp.simulate(model, 1.0, tip_force=force))
out["default picks"] = trajectory.method
print(json.dumps(out))
"""


def run(code: str) -> dict:
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MKL_NUM_THREADS="1")
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(ROOT), env.get("PYTHONPATH")]))
    proc = subprocess.run([sys.executable, "-c", code], env=env, cwd=ROOT, check=True,
                          capture_output=True, text=True)
    return json.loads(proc.stdout.strip().splitlines()[-1])


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--out", default=str(DEFAULT_OUT))
    a = ap.parse_args()
    from docs_tables import write_table

    load = os.getloadavg()[0]
    best: dict = {}
    for _ in range(a.repeats):
        for code in (_LOADS, _EXPONENTIAL, _AUTO):
            for key, value in run(code).items():
                if isinstance(value, float):
                    best[key] = min(best.get(key, value), value)
                else:
                    best[key] = value
    picks = best.pop("default picks")
    lines = [
        "# What a one-shot process pays for the compiled code (scripts/bench_oneshot_load.py)",
        "",
        f"CPU ms, least over {a.repeats} fresh processes, BLAS on one thread; load average "
        f"{load:.2f} at the start. Scene: 3R chain of uniform-narrow.json, -0.5 N tip step, "
        f"1 s; the default picks `{picks}` on it.",
        "",
        "| step | CPU (ms) |",
        "|---|---:|",
        *(f"| {k} | {1e3 * v:.1f} |" for k, v in best.items()),
        "",
    ]
    text = "\n".join(lines)
    print(text)
    for f in write_table(a.out, text, DEFAULT_OUT, "bench_oneshot_load"):
        print(f"wrote {f}")


if __name__ == "__main__":
    main()
