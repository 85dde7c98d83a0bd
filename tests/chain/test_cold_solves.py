"""A process that solves a few chains does not load numba; one that solves many does, and the
frequencies on both sides of the switch equal the generalised problem K phi = w^2 M phi solved
by scipy (Cholesky of M, another algorithm). Run in a fresh interpreter: the test session has
loaded numba already."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pinocchio as pin
import scipy.linalg as sla
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.chain.eigen import COLD_SOLVES

ROOT = Path(__file__).resolve().parents[2]
BEAM = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
LENGTHS = [0.1, 0.2, 0.2, 0.2, 0.2, 0.1]
K = [4000.0, 3000.0, 2500.0, 1500.0, 900.0]
Q = [0.05, -0.02, 0.1, 0.0, 0.03]

_SCRIPT = f"""
import json, sys
import numpy as np
import prbdm_pin as pp
from prbdm_pin.chain.eigen import COLD_SOLVES
model = pp.build_model(pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01),
                       {LENGTHS}, {K})
q = np.array({Q})
out = {{"cold": model.natural_frequencies(q).tolist(), "cold_numba": "numba" in sys.modules}}
for _ in range(COLD_SOLVES + 1):
    w = model.natural_frequencies(q)
out.update(warm=w.tolist(), warm_numba="numba" in sys.modules)
print(json.dumps(out))
"""


def test_numba_loads_only_after_many_solves_and_both_paths_agree():
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])))
    proc = subprocess.run([sys.executable, "-c", _SCRIPT], capture_output=True, text=True,
                          env=env, check=True)
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    assert not out["cold_numba"]  # one solve: LAPACK's path, numba not imported
    assert out["warm_numba"]  # past COLD_SOLVES: the compiled solve, numba loaded
    assert COLD_SOLVES <= 10_000  # a long loop pays at most ~0.1 s on LAPACK's path
    model = pp.build_model(BEAM, LENGTHS, K)
    M = pin.crba(model.pin_model, model.pin_model.createData(), np.array(Q))
    ref = np.sqrt(sla.eigh(np.diag(K), M, eigvals_only=True))
    # the reference's lowest w is good to n EPS (w_max / w_min)^2 / 2 (the unscaled solve),
    # either path's highest to about EPS cond(S M S): bound n EPS (w_max / w_min)^2
    tol = len(K) * EPS * (ref[-1] / ref[0]) ** 2
    np.testing.assert_allclose(out["cold"], ref, rtol=tol)
    np.testing.assert_allclose(out["warm"], ref, rtol=tol)
