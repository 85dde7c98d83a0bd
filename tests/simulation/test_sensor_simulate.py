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
    R = -run.output_values[3:-3]  # the support's push on the member: minus what it receives
    # the truncation of D1 is a third of |D1 - D2|; the integrator's error in P (rtol of it)
    # enters D1 divided by h
    noise = 2.0 * rtol * np.abs(P).max(axis=0) / h
    bound = np.abs(D1 - D2) + noise
    assert np.all(np.abs(R - D1) <= bound), (np.abs(R - D1) / bound).max(axis=0)
    # a vibration that shakes the root: the reaction is far from zero
    assert np.abs(R[:, 2]).max() > 10.0


def test_a_run_at_rest_under_a_tip_moment_and_gravity_records_them():
    """Held at its equilibrium, the member carries its weight to the root, and a pure moment
    about y bends it uniformly: the strain is -m_y t / (2 E I) at every station (beam theory),
    read at the root (the reaction), the joints (the springs), the tip (the load) and between."""
    from prbdm_pin import statics

    model = build_model(BEAM, LENGTHS, SPRINGS)
    m_y = 3.0  # N m
    eq = statics(model, tip_moment_Nm=[0.0, m_y, 0.0])
    x = np.array([0.0, 0.1, 0.2, 0.42, 0.5, 0.77, 0.8, 0.9, 1.0])
    outs = tuple(f"strain@{v:g}" for v in x) + ("root_force_z", "root_moment_y")
    run = simulate(model, 0.01, q0=eq.q_rad, inputs=("tip_moment_y",), u=np.array([m_y]),
                   outputs=outs, output_dt_s=0.001, damping_ratio=0.0)
    EI = BEAM.material.E_Pa * BEAM.area_moment_at(0.5)
    ref = -m_y * BEAM.thickness_m / (2.0 * EI) * 1e6
    strain = run.output_values[:, :x.size]
    # the equilibrium's Newton residual (rtol 1e-10 of the spring torques) is what the run
    # starts off by: it stays within a few times that
    assert np.abs(strain - ref).max() <= 1e-9 * abs(ref)
    assert np.abs(run.output_values[:, -1] - m_y).max() <= 1e-9 * m_y
    assert np.abs(run.output_values[:, -2]).max() <= 1e-9 * m_y / BEAM.length_m

    g = np.array([0.0, 0.0, -9.81])
    eq = statics(model, gravity_m_s2=g)
    run = simulate(model, 0.01, q0=eq.q_rad, outputs=("root_force_z", "root_force_x"),
                   output_dt_s=0.001, damping_ratio=0.0, gravity_m_s2=g)
    mass = 2.0 * 0.025 * BEAM.length_m * BEAM.thickness_m * BEAM.material.rho_kg_m3  # rho t A
    weight = mass * 9.81
    assert np.abs(run.output_values[:, 0] + weight).max() <= 1e-9 * weight
    assert np.abs(run.output_values[:, 1]).max() <= 1e-9 * weight
