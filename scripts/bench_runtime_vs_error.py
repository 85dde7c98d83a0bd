"""Error against cost benchmark: a thin wrapper of ``prbdm bench`` (see prbdm_pin/bench/).

usage: python scripts/bench_runtime_vs_error.py [--quick] [--out results/bench]
"""

import os

for _v in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_v] = "1"  # pin BLAS to one thread before numpy is imported

import sys  # noqa: E402
from pathlib import Path  # noqa: E402

from prbdm_pin.cli import main  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]

if __name__ == "__main__":
    argv = sys.argv[1:]
    if "--out" not in argv:
        argv += ["--out", str(ROOT / "results" / "bench")]
    raise SystemExit(main(["bench", *argv]))
