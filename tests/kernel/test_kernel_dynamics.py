"""The compiled kernel against Pinocchio at random states: CRBA (pin.crba), bias forces
(pin.rnea with a = 0), forward dynamics (pin.aba), the tip frame's position (oMf) and J^T f
(computeFrameJacobian, LOCAL_WORLD_ALIGNED), gravity on, on planar, spatial, hub and free-bus
chains; and the models and arguments it refuses."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from kernel_models import bus, hub, planar, spatial
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.errors import BeamInputError, InputTypeError
from prbdm_pin.kernel import (
    bias_forces,
    chain_kernel,
    forward_dynamics,
    mass_matrix,
    tip_force_torque,
    tip_position,
)

CASES = ["1R", "5R", "8R", "xyz", "xy", "hub-x", "hub-y", "hub-z", "bus"]
GRAVITY = np.array([0.4, -1.2, -9.81])  # m/s^2: every component, so every axis carries weight


def _model(beam, case):
    if case.endswith("R"):
        return planar(beam, int(case[:-1]))
    if case.startswith("hub"):
        return hub(beam, case[-1])
    return bus(beam) if case == "bus" else spatial(beam, case)


@pytest.fixture(scope="module", params=CASES)
def chain(request, narrow):
    m = _model(narrow, request.param)
    pm = pin.Model(m.pin_model)
    pm.gravity = pin.Motion(np.concatenate([GRAVITY, np.zeros(3)]))
    k = chain_kernel(pm, m.tip_frame_id)
    return pm, pm.createData(), m.tip_frame_id, k, k.new_data()


def _states(n, count=4, seed=7):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        yield rng.uniform(-1.0, 1.0, n), rng.uniform(-3.0, 3.0, n), rng.uniform(-2.0, 2.0, n)


def _rel(a, b):
    return float(np.abs(a - b).max() / np.abs(b).max())


# Each entry of M, h and J^T f is a sum over the n bodies (or joints) of products of a few
# roundings each, evaluated in another order (world frame here, joint frames in Pinocchio): about
# n EPS of the largest entry, with 10x for the constants that figure drops.
def _sum_tol(n):
    return 10 * n * EPS


def test_mass_matrix_is_pinocchios_crba(chain):
    pm, d, _, k, kd = chain
    for q, _, _ in _states(pm.nv):
        M = pin.crba(pm, d, q)
        M = np.triu(M) + np.triu(M, 1).T
        assert _rel(mass_matrix(k, kd, q), M) <= _sum_tol(pm.nv)


def test_bias_forces_are_pinocchios_rnea_at_zero_acceleration(chain):
    pm, d, _, k, kd = chain
    for q, v, _ in _states(pm.nv):
        h = pin.rnea(pm, d, q, v, np.zeros(pm.nv))
        assert _rel(bias_forces(k, kd, q, v), h) <= _sum_tol(pm.nv)


def test_forward_dynamics_is_pinocchios_aba(chain):
    pm, d, _, k, kd = chain
    for q, v, tau in _states(pm.nv):
        a = pin.aba(pm, d, q, v, tau)
        M = pin.crba(pm, d, q)
        M = np.triu(M) + np.triu(M, 1).T
        h = pin.rnea(pm, d, q, v, np.zeros(pm.nv))
        mine = forward_dynamics(k, kd, q, v, tau).copy()
        # backward error: the kernel's a satisfies Pinocchio's M a + h = tau to the roundings
        # of a backward-stable Cholesky solve and of the products, n EPS of the terms' sizes
        scale = np.abs(M).max() * np.abs(mine).max() + np.abs(h).max() + np.abs(tau).max()
        assert np.abs(M @ mine + h - tau).max() <= _sum_tol(pm.nv) * scale
        # forward error against ABA: those roundings amplified by cond(M) (up to 2e4 on the
        # spatial chain, whose twist inertia is small)
        assert _rel(mine, a) <= _sum_tol(pm.nv) * np.linalg.cond(M)


def test_tip_position_and_force_are_pinocchios_frame(chain):
    pm, d, fid, k, kd = chain
    rng = np.random.default_rng(3)
    for q, _, _ in _states(pm.nv):
        pin.framesForwardKinematics(pm, d, q)
        p = d.oMf[fid].translation
        # a chain of n rotations and offsets: n EPS of the reach (the tip's distance, >= 0.5 m)
        assert np.abs(tip_position(k, kd, q) - p).max() <= _sum_tol(pm.nv) * np.abs(p).max()
        f = rng.uniform(-1.0, 1.0, 3)
        J = pin.computeFrameJacobian(pm, d, q, fid, pin.LOCAL_WORLD_ALIGNED)[:3]
        assert _rel(tip_force_torque(k, kd, q, f), J.T @ f) <= _sum_tol(pm.nv)


def test_the_kernel_keeps_the_models_gravity_and_tip(chain):
    pm, _, fid, k, _ = chain
    assert np.array_equal(k.gravity_m_s2, GRAVITY)
    assert k.tip_joint == pm.frames[fid].parentJoint - 1 and k.n == pm.nv


def test_a_model_that_is_not_a_one_axis_chain_is_refused_by_name():
    pm = pin.Model()
    pm.name = "ball"
    pm.addJoint(0, pin.JointModelSpherical(), pin.SE3.Identity(), "ball_joint")
    with pytest.raises(BeamInputError, match="ball"):
        chain_kernel(pm, 0)
    free = pin.buildSampleModelHumanoidRandom()
    with pytest.raises(BeamInputError, match="pin_model"):
        chain_kernel(free, 0)


def test_bad_arguments_are_refused_by_name(narrow):
    m = planar(narrow, 2)
    with pytest.raises(InputTypeError, match="pin_model"):
        chain_kernel("model.urdf", 0)
    with pytest.raises(InputTypeError, match="tip_frame_id"):
        chain_kernel(m.pin_model, 1.5)
    with pytest.raises(BeamInputError, match="tip_frame_id"):
        chain_kernel(m.pin_model, 10_000)
    with pytest.raises(BeamInputError, match="tip_frame_id"):
        chain_kernel(m.pin_model, 0)  # the universe frame
    k = chain_kernel(m.pin_model, m.tip_frame_id)
    with pytest.raises(BeamInputError, match="q ="):
        mass_matrix(k, k.new_data(), np.zeros(3))
    with pytest.raises(BeamInputError, match="v ="):
        bias_forces(k, k.new_data(), np.zeros(2), [0.0, np.nan])
    with pytest.raises(BeamInputError, match="force_N"):
        tip_force_torque(k, k.new_data(), np.zeros(2), [1.0, 0.0])


def test_the_public_name_reads_the_same_kernel(narrow):
    m = planar(narrow, 3)
    assert pp.chain_kernel(m.pin_model, m.tip_frame_id).n == 3
