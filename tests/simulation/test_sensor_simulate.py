"""simulate() records the root reaction: in a free vibration of a clamped chain it is the rate
of the member's momentum (linear, and angular about the fixed root point).

Reference: the links' momenta summed from Pinocchio's forward kinematics (m v_c and the
angular momentum about the world origin, I v of each body moved to the world), differentiated
along the trajectory by central differences; their truncation bounded by the difference of
two step sizes (as tests/central_differences.py does)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from paths import ROOT

from prbdm_pin import build_model, simulate
from prbdm_pin.files.beam_file import load_beam

BEAM = load_beam(ROOT / "examples/beams/uniform-narrow.json")
LENGTHS = np.array([0.2, 0.3, 0.3, 0.2])
SPRINGS = np.array([1000.0, 800.0, 500.0])
REACTION = ("root_force_x", "root_force_y", "root_force_z", "root_moment_x", "root_moment_y",
            "root_moment_z")


def _momenta(model, Q, V) -> np.ndarray:
    """(linear momentum, angular momentum about the origin) of the links, (s, 6)."""
    pm = model.pin_model
    data = pm.createData()
    out = np.zeros((len(Q), 6))
    for k, (q, v) in enumerate(zip(Q, V, strict=True)):
        pin.forwardKinematics(pm, data, q, v)
        for i in range(1, pm.njoints):  # link 0 is clamped: no momentum
            f = data.oMi[i].act(pm.inertias[i] * data.v[i])
            out[k] += np.concatenate([f.linear, f.angular])
    return out


@pytest.mark.parametrize("axes", ["y", "xyz"])
def test_free_vibration_root_reaction_is_the_momentum_rate(axes):
    k = SPRINGS if axes == "y" else np.repeat(SPRINGS, 3)
    model = build_model(BEAM, LENGTHS, k, axes=axes)
    F = np.array([0.0, 0.0, 40.0]) if axes == "y" else np.array([3.0, 5.0, 40.0])
    q0, _ = model.static_deflection(F)  # released from a tip load: no load, no weight, no damping
    h = 2e-5  # s, sample interval: ~1/500 of the highest period
    rtol = 1e-12
    run = simulate(model, 0.05, q0=q0, outputs=REACTION, output_dt_s=h, damping_ratio=0.0,
                   method="DOP853", rtol=rtol)
    P = _momenta(model, run.q_rad, run.v_rad_s)
    D1 = (P[4:-2] - P[2:-4]) / (2.0 * h)  # at samples 3 .. s-4
    D2 = (P[5:-1] - P[1:-5]) / (4.0 * h)
    R = run.output_values[3:-3]
    # the truncation of D1 is a third of |D1 - D2|; the integrator's error in P (rtol of it)
    # enters D1 divided by h
    noise = 2.0 * rtol * np.abs(P).max(axis=0) / h
    bound = np.abs(D1 - D2) + noise
    assert np.all(np.abs(R - D1) <= bound), (np.abs(R - D1) / bound).max(axis=0)
    # a vibration that shakes the root: the reaction is far from zero
    assert np.abs(R[:, 2]).max() > 10.0
