"""The trajectory gradient's compiled stage (``sensitivity_kernel``, ``sensitivity_stations``)
against Pinocchio and central differences at one state.

The closed loop's torque and tip terms against Pinocchio's frame Jacobian and placement; df/dx
and every design column of df/dp (springs, beta, dampers, gain, stations: by the planar closed
forms and by the general kernel's residual) and the tip height's station derivative against
central differences of Pinocchio's ABA (and frame placement) on
models rebuilt by ``build_model`` with the parameter moved. The whole-run gradients are checked
against differences of re-simulated runs in test_trajectory_gradient.py.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from central_differences import central_difference
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.simulation.sensitivity_field import Chain, Field, FieldDesign, station_variants
from prbdm_pin.simulation.sensitivity_stations import MovedChains

# a tapered strip: the links' masses and inertias move non-linearly with the stations
BEAM = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.03, 0.02], thickness_m=0.01)
L0 = np.array([0.2, 0.3, 0.25, 0.25])
K0 = np.array([2500.0, 1200.0, 800.0])
Q = np.array([0.3, -0.5, 0.8])
V = np.array([1.5, -2.0, 3.0])
F = np.array([1.5, 0.0, -2.0])
B = np.array([[1.0], [0.0], [0.0]])  # joint_torque[0]
GAIN = np.array([[20.0, 5.0, -3.0, 2.0, 0.5, 0.1]])
X_REF = np.array([0.01, 0.0, -0.02, 0.0, 0.1, 0.0])
BETA, C = 1e-3, np.array([0.05, 0.02, 0.01])
# the field's own station difference (h = EPS^(1/3) of the beam): truncation (h / l_min)^2 / 6
# with l_min = 0.2 m is 1.5e-10, rounding EPS^(2/3) 4e-11, both relative to the accelerations'
# terms; 1e-8 of the largest term leaves a margin for the conditioning of M^-1 (about 50 here)
FIELD_REL = 1e-8


def _tau(model, q, v, k, beta, c, gain):
    """The closed loop's torque from Pinocchio's tip Jacobian, and the tip height."""
    data = model.pin_model.createData()
    pin.framesForwardKinematics(model.pin_model, data, q)
    J = pin.computeFrameJacobian(model.pin_model, data, q, model.tip_frame_id,
                                 pin.LOCAL_WORLD_ALIGNED)[:3]
    x = np.concatenate((q, v))
    u = -gain @ (x - X_REF)
    tau = -k * (q + beta * v) - c * v + J.T @ F + B @ u
    return tau, float(data.oMf[model.tip_frame_id].translation[2]), J


def _accel(L, k=K0, beta=BETA, c=C, gain=GAIN, q=Q, v=V):
    model = pp.build_model(BEAM, L, k, min_fraction=0.1)
    tau = _tau(model, q, v, k, beta, c, gain)[0]
    return pin.aba(model.pin_model, model.pin_model.createData(), q, v, tau)


def _field(groups):
    model = pp.build_model(BEAM, L0, K0)
    design = FieldDesign(K0, BETA, C, GAIN, X_REF,
                         lambda t, q, v: -GAIN @ (np.concatenate((q, v)) - X_REF),
                         groups, 3, 1)
    variants = station_variants(model, K0, lambda m: B) if "stations" in groups else []
    return model, Field(Chain(model, B), variants, design, F)


def test_closed_loop_torque_and_tip_match_pinocchio():
    model, field = _field(())
    x = np.concatenate((Q, V))
    a, u, z, dz = field.value(0.0, x)
    tau_ref, z_ref, J = _tau(model, Q, V, K0, BETA, C, GAIN)
    # sums of a few terms up to |k q| ~ 1e3 N m: a few roundings of the largest
    assert np.allclose(field.tau, tau_ref, rtol=0.0, atol=16 * EPS * 1e3)
    assert abs(z - z_ref) <= 16 * EPS  # n terms of order 1 m
    assert np.allclose(dz, J[2], rtol=0.0, atol=16 * EPS)
    data = model.pin_model.createData()
    pin.framesForwardKinematics(model.pin_model, data, Q)
    assert abs(field.tip_x() - data.oMf[model.tip_frame_id].translation[0]) <= 16 * EPS


def test_state_jacobian_matches_central_differences_of_aba():
    _, field = _field(())
    A = field.state_jacobian(0.0, np.concatenate((Q, V)))

    def f(x):
        return _accel(L0, q=x[:3], v=x[3:])

    # noise: ABA's rounding, a few EPS of its largest term (|a| up to 1e5 rad/s^2 here)
    a0 = np.abs(f(np.concatenate((Q, V)))).max()
    fd, bound = central_difference(f, np.concatenate((Q, V)), 1e-5, 64 * EPS * a0)
    assert np.all(np.abs(A - fd) <= bound)


@pytest.mark.parametrize("stations", ["planar", "kernel"])
def test_design_columns_match_central_differences_of_rebuilt_models(stations):
    groups = ("springs", "stations", "beta", "dampers", "gain")
    model, field = _field(groups)
    assert type(field.stations).__name__ == "PlanarMovedChains"  # build_model's chains
    if stations == "kernel":  # the general kernel's residual, for chains the closed forms omit
        moved = [ch for lo, hi, _ in field.variants for ch in (lo, hi)]
        field.stations = MovedChains([(ch.pm, ch.tip_frame, ch.b0) for ch in moved],
                                     field.two_h)
    x = np.concatenate((Q, V))
    a, u, z = field.sensitivity_stage(0.0, x)
    P = field.d.size
    dS, dg = np.empty((6, P)), np.empty(P)
    # S = 0: S' is df/dp; dl/dz = 1 and no other partials: the gradient rate is dz/dp
    field.stage_rates(x, np.zeros((6, P)), np.zeros(6), np.zeros(1), 1.0, dS, dg)
    Fp, s = dS[3:], field.d.slices
    a0 = np.abs(a).max()
    noise = 64 * EPS * a0  # ABA's rounding, as above
    fd, bound = central_difference(lambda k: _accel(L0, k=k), K0, 1e-4 * K0, noise)
    assert np.all(np.abs(Fp[:, s["springs"]] - fd) <= bound)
    fd, bound = central_difference(lambda b: _accel(L0, beta=b[0]), [BETA], [1e-5], noise)
    assert np.all(np.abs(Fp[:, s["beta"]] - fd) <= bound)
    fd, bound = central_difference(lambda c: _accel(L0, c=c), C, [1e-3] * 3, noise)
    assert np.all(np.abs(Fp[:, s["dampers"]] - fd) <= bound)
    fd, bound = central_difference(lambda g: _accel(L0, gain=g.reshape(1, 6)), GAIN.ravel(),
                                   [1e-2] * 6, noise)
    assert np.all(np.abs(Fp[:, s["gain"]] - fd) <= bound)

    def at_stations(st):
        return _accel(np.diff(np.concatenate(([0.0], st, [1.0]))))

    stations = np.cumsum(L0)[:-1]
    fd, bound = central_difference(at_stations, stations, 1e-4, noise)
    assert np.all(np.abs(Fp[:, s["stations"]] - fd) <= bound + FIELD_REL * a0)

    def tip_z(st):
        m = pp.build_model(BEAM, np.diff(np.concatenate(([0.0], st, [1.0]))), K0)
        return np.array([_tau(m, Q, V, K0, BETA, C, GAIN)[1]])

    fd, bound = central_difference(tip_z, stations, 1e-4, 16 * EPS)
    # the field's own difference of the tip height: 1e-10 of the 1 m chain (FIELD_REL's terms)
    assert np.all(np.abs(dg[s["stations"]] - fd[0]) <= bound[0] + FIELD_REL)
    assert np.all(dg[:s["stations"].start] == 0.0)  # structural: z does not see the springs
