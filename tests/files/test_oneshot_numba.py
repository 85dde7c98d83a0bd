"""What a one-shot command computes once (an export's frequency record, the default integrator's
rule, ``prbdm linearize``'s plant) goes through LAPACK and loads no numba in a fresh process;
its frequencies equal the generalised problem K phi = w^2 M phi solved by scipy (Cholesky of M,
another algorithm), and so do the compiled one-chain solve's. The fresh interpreter is needed:
the test session has loaded numba already."""

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
from prbdm_pin.chain.eigen import eig_scaled

ROOT = Path(__file__).resolve().parents[2]
BEAM = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
LENGTHS = [0.1, 0.2, 0.2, 0.2, 0.2, 0.1]
K = [4000.0, 3000.0, 2500.0, 1500.0, 900.0]

_SCRIPT = f"""
import json, sys
from pathlib import Path
import numpy as np
import prbdm_pin as pp
from prbdm_pin.files.export_record import read_export_record
model = pp.build_model(pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01),
                       {LENGTHS}, {K})
path = pp.export_model(model, Path(sys.argv[1]) / "model.urdf", "urdf")
record = read_export_record(path.read_text())
out = {{"record": record.natural_frequencies_rad_s.tolist(),
       "export_numba": "numba" in sys.modules}}
# undamped, from rest, stiffness ratio above 25: the rule gives the exponential integrator
run = pp.simulate(model, 0.01, tip_force=np.array([0.0, 0.0, -1.0]), damping_ratio=0.0)
out.update(method=run.method, simulate_numba="numba" in sys.modules)
# prbdm linearize: one plant a command, by the numpy path
json_path = pp.export_model(model, Path(sys.argv[1]) / "model.json", "json")
from prbdm_pin.cli import main
folder = Path(sys.argv[1]) / "lin"
rc = main(["linearize", str(json_path), "--out", str(folder), "-q"])
A = np.load(folder / "linear_model.npz")["A"]
out.update(linearize_rc=rc, linearize_numba="numba" in sys.modules,
           stiffness_block=(-A[A.shape[0] // 2:, :A.shape[0] // 2]).tolist())
print(json.dumps(out))
"""


def _reference() -> np.ndarray:
    model = pp.build_model(BEAM, LENGTHS, K)
    M = pin.crba(model.pin_model, model.pin_model.createData(), np.zeros(len(K)))
    return M, np.sqrt(sla.eigh(np.diag(K), M, eigvals_only=True))


def test_export_the_rule_and_linearize_load_no_numba_and_their_frequencies_are_right(
        tmp_path):
    env = dict(os.environ, PYTHONPATH=os.pathsep.join(
        filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])))
    proc = subprocess.run([sys.executable, "-c", _SCRIPT, str(tmp_path)], capture_output=True,
                          text=True,
                          env=env, check=True)
    out = json.loads(proc.stdout.strip().splitlines()[-1])
    assert not out["export_numba"]
    assert out["method"] == "exponential" and not out["simulate_numba"]
    _, ref = _reference()
    # the reference's lowest w is good to n EPS (w_max / w_min)^2 / 2 (the unscaled solve),
    # LAPACK's highest to about EPS cond(S M S): bound n EPS (w_max / w_min)^2; the record
    # holds repr(float), exact
    tol = len(K) * EPS * (ref[-1] / ref[0]) ** 2
    np.testing.assert_allclose(out["record"], ref, rtol=tol)
    # prbdm linearize: the unloaded plant's M^-1 K block has the eigenvalues w^2, within
    # the same bound (the block's eigenvalues by LAPACK's nonsymmetric solver: cond of the
    # eigenvector basis, that of M^-1/2, is below (w_max / w_min)^2 here)
    assert out["linearize_rc"] == 0 and not out["linearize_numba"]
    w2 = np.sort(np.linalg.eigvals(np.array(out["stiffness_block"])).real)
    np.testing.assert_allclose(np.sqrt(w2), ref, rtol=tol)


def test_both_paths_of_eig_scaled_equal_the_generalised_problem():
    M, ref = _reference()
    s = 1.0 / np.sqrt(np.asarray(K))
    tol = len(K) * EPS * (ref[-1] / ref[0]) ** 2  # as above
    for compiled in (True, False):
        np.testing.assert_allclose(eig_scaled(M, s, compiled=compiled), ref, rtol=tol)
        np.testing.assert_allclose(eig_scaled(M[None], s[None], compiled=compiled)[0], ref,
                                   rtol=tol)
