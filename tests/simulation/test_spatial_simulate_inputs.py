"""A time response driven by the tip moment and the corner forces (dead loads on the tip link).

References: the chain's own 3D statics (Newton on the exact tangent, a different algorithm from
the integrator) for the state a damped response settles in under large loads; linearize's
state-space step response for a small load (second order in the amplitude); central
differences of the inputs' generalized force for the Jacobians the exponential integrator's
linearisation takes (the pose-dependent columns' load stiffness and B(q) K of a feedback).
"""

import numpy as np
import pytest
import scipy.linalg

import prbdm_pin as pp
from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.errors import BeamInputError
from prbdm_pin.model.prbdm_model import build_model
from prbdm_pin.simulation.inputs import input_force
from prbdm_pin.simulation.system import generalised_force


@pytest.fixture(scope="module")
def chain(tapered):
    lengths = np.array([0.2, 0.3, 0.3, 0.2]) * tapered.length_m
    return build_model(tapered, lengths, spatial_stiffness(tapered, lengths, "xyz"), axes="xyz")


def _settle(model, inputs, u):
    """A response damped at 0.9 of critical for 25 / (0.9 omega_1): exp(-25) ~ 1e-11 is left."""
    T = 25.0 / (0.9 * model.natural_frequencies()[0])
    r = pp.simulate(model, T, inputs=inputs, u=u, damping_ratio=0.9, output_dt_s=T / 20)
    return r.q_rad[-1]


def test_a_large_corner_force_settles_in_the_static_equilibrium(chain):
    k_min = chain.stiffness_Nm_per_rad[chain.axis_index("y")].min()
    F = 0.3 * k_min / chain.beam.length_m  # bends the root 0.13 rad and twists the tip
    q_s = chain.static_deflection(np.array([0.0, 0.0, -F]), point="tip_corner_left")[0]
    assert np.abs(q_s[chain.axis_index("x")]).max() > 1e-3
    q = _settle(chain, ("corner_force_z_left",), [-F])
    # the decay left (1e-11) and the integrator's rtol 1e-9 over the settling
    assert np.abs(q - q_s).max() <= 1e-8 * np.abs(q_s).max()


def test_a_large_tip_moment_with_a_tip_force_settles_in_the_static_equilibrium(chain):
    F = 0.3 * chain.stiffness_Nm_per_rad[chain.axis_index("y")].min() / chain.beam.length_m
    Mx = 0.3 * chain.stiffness_Nm_per_rad[chain.axis_index("x")].min()
    q_s = chain.static_deflection(np.array([0.0, 0.0, -F]),
                                  tip_moment_Nm=np.array([Mx, 0.0, 0.0]))[0]
    assert np.abs(q_s[chain.axis_index("x")]).max() > 0.1  # a large twist
    q = _settle(chain, ("tip_moment_x", "tip_force_z"), [Mx, -F])
    assert np.abs(q - q_s).max() <= 1e-8 * np.abs(q_s).max()  # as above


@pytest.mark.parametrize("name", ["tip_moment_x", "corner_force_z_right"])
def test_a_small_step_is_the_linear_model_s_step_response(chain, name):
    lin = pp.linearize(chain, inputs=(name,), outputs=("tip_twist", "corner_z_right"),
                       damping_ratio=0.0)
    u = 1e-4 * chain.stiffness_Nm_per_rad[chain.axis_index("x")].min()  # twist ~1e-4 rad
    if name.startswith("corner"):
        u /= chain.beam.half_width_m[-1]
    T = 0.05
    r = pp.simulate(chain, T, inputs=(name,), u=[u], outputs=("tip_twist", "corner_z_right"),
                    damping_ratio=0.0, output_dt_s=T / 50)
    A, b = lin.A, lin.B[:, 0] * u
    I = np.eye(A.shape[0])
    y = np.array([lin.C @ np.linalg.solve(A, (scipy.linalg.expm(A * t) - I) @ b)
                  for t in r.t_s])
    # second order in the amplitude (1e-4) and the integrator's rtol 1e-9
    assert np.abs(r.output_values - y).max() <= 1e-3 * np.abs(y).max()


def test_the_inputs_jacobians_under_feedback_are_their_central_differences(chain):
    """d tau / dq and d tau / dv of a state feedback through the pose-dependent columns.

    tau(q, v) = B_0 u + J_tip(q)^T F(u) + B_p(q) u_p with u = -K x: the exponential
    integrator's linearisation takes these Jacobians (load stiffness and B(q) K).
    """
    names = ("corner_force_z_left", "tip_moment_x", "tip_force_z")
    nv = chain.pin_model.nv
    rng = np.random.default_rng(7)
    K = rng.normal(size=(3, 2 * nv)) * np.concatenate([chain.stiffness_Nm_per_rad] * 2)
    pm = chain.pin_model
    tip_terms = generalised_force(pm, pm.createData(), int(chain.tip_frame_id), None)[2]
    f = input_force(chain, names, pp.StateFeedback(K, u_ref=[2.0, 0.3, -1.0]), (), tip_terms)
    q = rng.uniform(-0.3, 0.3, nv)  # a bent, twisted pose: B(q) differs from B(0)
    v = rng.uniform(-1.0, 1.0, nv)
    dq, dv = f.jacobians(0.0, q, v)
    h = 1e-6  # central differences: truncation h^2, rounding EPS |tau| / h
    cd_q = np.column_stack([(f.torque(0.0, q + h * e, v) - f.torque(0.0, q - h * e, v)) / (2 * h)
                            for e in np.eye(nv)])
    cd_v = np.column_stack([(f.torque(0.0, q, v + h * e) - f.torque(0.0, q, v - h * e)) / (2 * h)
                            for e in np.eye(nv)])
    # the load stiffness inside is a forward difference (step 1e-7: error ~1e-7 relative)
    np.testing.assert_allclose(dq, cd_q, rtol=0.0, atol=1e-6 * np.abs(cd_q).max())
    np.testing.assert_allclose(dv, cd_v, rtol=0.0, atol=1e-8 * np.abs(cd_v).max())


def test_corner_signals_need_the_beam(chain, tmp_path):
    from prbdm_pin.files.urdf_file import load_urdf

    chain.write_urdf(tmp_path / "chain.urdf")
    bare = load_urdf(tmp_path / "chain.urdf")  # a URDF carries no width: no corners
    with pytest.raises(BeamInputError, match=r"inputs\[1\] = 'corner_force_z_left': this "
                                             "model carries no beam"):
        pp.simulate(bare, 0.01, inputs=("tip_moment_x", "corner_force_z_left"), u=[0.0, 1.0])
    with pytest.raises(BeamInputError, match=r"outputs\[0\] = 'corner_z_left': this model "
                                             "carries no beam"):
        pp.simulate(bare, 0.01, outputs=("corner_z_left",))


def test_a_tip_moment_about_y_rolls_the_chain_as_the_statics(tapered):
    """A large dead moment about -y (joint angles up to 0.5 rad) settles where
    the statics put it; the linear model's static gain is the compliance sum."""
    lengths = np.array([0.2, 0.3, 0.3, 0.2]) * tapered.length_m
    k = spatial_stiffness(tapered, lengths, "y")
    planar = build_model(tapered, lengths, k)
    M = -0.5 * float(np.min(k))  # joint angles ~0.5 rad at the softest joint
    q_s = pp.statics(planar, tip_moment_Nm=[0.0, M, 0.0]).q_rad
    # a dead moment on a chain of y joints: each carries it, q_j = M / k_j (exactly)
    np.testing.assert_allclose(q_s, M / k, rtol=1e-9)
    q = _settle(planar, ("tip_moment_y",), [M])
    assert np.abs(q - q_s).max() <= 1e-8 * np.abs(q_s).max()  # as above
    lin = pp.linearize(planar, inputs=("tip_moment_y", "tip_moment_z"), outputs=("q[0]",))
    dc = -lin.C @ np.linalg.solve(lin.A, lin.B)
    # a solve of cond ~ the spring spread: 1e-9; the moment about z does not reach a y joint
    # (its column of B is exactly zero)
    assert dc[0, 0] == pytest.approx(1.0 / k[0], rel=1e-9) and dc[0, 1] == 0.0
