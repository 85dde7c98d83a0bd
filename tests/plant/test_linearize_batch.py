"""linearize_batch against each design's own linearize (Pinocchio's CRBA, one design's
eigensolve and solve): designs of other springs (one Pinocchio model) and of other lengths,
inputs and outputs of every kind the stacked path makes; bad batches."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from tolerances import EPS, eig_rtol

import prbdm_pin as pp
from prbdm_pin.errors import BeamInputError

BEAM = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.03, 0.02], thickness_m=[0.012, 0.006])
INPUTS = ("tip_force_z", "tip_force_x", "joint_torque[1]")
OUTPUTS = ("tip_z", "tip_x", "q[0]", "q_rate[2]", "spring_torque[1]", "tip_z_rate")


def _designs(n: int, count: int, seed: int, same_lengths: bool):
    rng = np.random.default_rng(seed)
    w = rng.uniform(0.5, 1.5, n + 1)
    base = pp.build_model(BEAM, w / w.sum(), rng.uniform(500.0, 5000.0, n))
    if same_lengths:
        return [base.with_stiffness(base.stiffness_Nm_per_rad * rng.uniform(0.5, 2.0, n))
                for _ in range(count)]
    out = []
    for _ in range(count):
        w = rng.uniform(0.5, 1.5, n + 1)
        out.append(pp.build_model(BEAM, w / w.sum(), rng.uniform(500.0, 5000.0, n)))
    return out


def _bound(lin: pp.LinearModel) -> float:
    # the damping matrix from two eigensolves of one pencil (eig_rtol of its spread, x11 for
    # the mass matrices' own roundings: tests/plant/test_frequencies_batch.py) and a solve of M
    # (10 n cond(M) EPS): relative to each matrix's largest entry
    M = lin.mass_kg_m2
    omega = lin.modal().omega_rad_s
    return 11 * eig_rtol(omega) + 10 * M.shape[0] * np.linalg.cond(M) * EPS


def _close(a: np.ndarray, b: np.ndarray, rtol: float) -> bool:
    return float(np.abs(a - b).max()) <= rtol * max(float(np.abs(b).max()), np.finfo(float).tiny)


@pytest.mark.parametrize("same_lengths", [True, False])
def test_each_design_matches_its_own_linearisation(same_lengths):
    models = _designs(3, 5, seed=int(same_lengths), same_lengths=same_lengths)
    plants = pp.linearize_batch(models, INPUTS, OUTPUTS, damping_ratio=0.03)
    for lin, m in zip(plants, models, strict=True):
        ref = pp.linearize(m, INPUTS, OUTPUTS, damping_ratio=0.03)
        rtol = _bound(ref)
        for name in ("A", "B", "C", "D", "mass_kg_m2", "damping_Nms_per_rad", "input_map",
                     "output_map_position", "output_map_rate", "y_eq"):
            assert _close(getattr(lin, name), getattr(ref, name), rtol), name
        assert np.array_equal(lin.stiffness_Nm_per_rad, ref.stiffness_Nm_per_rad)
        assert lin.state_names == ref.state_names and lin.output_units == ref.output_units
        assert np.allclose(lin.modal().omega_rad_s, m.natural_frequencies(),
                           rtol=11 * eig_rtol(m.natural_frequencies()), atol=0.0)


def test_a_load_or_another_damping_form_takes_each_designs_own_call():
    models = _designs(3, 2, seed=3, same_lengths=True)
    F = [0.0, 0.0, -5.0]
    plants = pp.linearize_batch(models, damping="stiffness", load_N=F)
    for lin, m in zip(plants, models, strict=True):
        # the deflected pose: the springs hold the load, J(q)^T F by Pinocchio's Jacobian
        d = m.new_data()
        J = pin.computeFrameJacobian(m.pin_model, d, lin.q_eq, m.tip_frame_id,
                                     pin.LOCAL_WORLD_ALIGNED)[:3]
        spring = m.stiffness_Nm_per_rad * lin.q_eq
        residual = np.abs(spring - J.T @ np.asarray(F)).max() / np.abs(spring).max()
        assert residual <= 1e-10  # the equilibrium solver's rtol (plant.equilibrium)
        assert lin.q_eq[0] != 0.0
        C = lin.damping_Nms_per_rad  # the stiffness form: beta K
        assert _close(C, C[0, 0] / m.stiffness_Nm_per_rad[0] * np.diag(m.stiffness_Nm_per_rad),
                      10 * EPS)  # one product per entry


def test_bad_batches_are_refused_naming_the_argument():
    three, two = _designs(3, 1, 1, True)[0], _designs(2, 1, 2, True)[0]
    with pytest.raises(BeamInputError, match=r"models\[1\]: 2 joints"):
        pp.linearize_batch([three, two])
    with pytest.raises(BeamInputError, match="the batch is empty"):
        pp.linearize_batch([])
    with pytest.raises(BeamInputError, match="outputs"):
        pp.linearize_batch([three, three], outputs=("tip_q",))
