"""Simulating a spatial chain: Pinocchio's general path, against independent references.

References: the linear modal solution q(t) = Phi cos(Omega t) Phi^T M q0 of a small release
(the nonlinear terms are second order in the amplitude), and the planar chain's own closed-form
path for a load that bends the spatial chain in the plane only.
"""

import numpy as np
import pytest
import scipy.linalg
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.model.prbdm_model import build_model


@pytest.fixture(scope="module")
def chains(tapered):
    lengths = np.array([0.2, 0.3, 0.3, 0.2]) * tapered.length_m
    return {a: build_model(tapered, lengths, spatial_stiffness(tapered, lengths, a), axes=a)
            for a in ("y", "xy", "xyz")}


@pytest.mark.parametrize("axes", ["xy", "xyz"])
def test_a_small_twist_release_follows_the_linear_modes(chains, axes):
    m = chains[axes]
    amp = 1e-5  # rad: the nonlinear terms are ~amp^2 relative
    q0 = np.zeros(m.n_springs)
    q0[m.axis_index("x")] = amp * np.array([1.0, -0.5, 0.25])
    M = m.mass_matrix()
    w2, phi = scipy.linalg.eigh(m.stiffness_matrix(), M)
    T = 2 * np.pi / np.sqrt(w2[0])
    t = np.linspace(0.0, 2 * T, 41)
    r = pp.simulate(m, 2 * T, q0=q0, method="DOP853", rtol=1e-11, atol=1e-11 * amp,
                    damping_ratio=0.0,
                    output_dt_s=t[1] - t[0])
    ref = (phi * np.cos(np.outer(r.t_s, np.sqrt(w2)))[:, None, :] * (phi.T @ M @ q0)).sum(-1)
    # DOP853 at rtol 1e-11 and the amplitude's second-order terms (1e-5) set the bound
    assert np.abs(r.q_rad - ref).max() <= 1e-4 * amp


def test_an_out_of_plane_load_on_a_spatial_chain_is_the_planar_response(chains):
    F = np.array([0.0, 0.0, -0.2])
    kw = {"tip_force": F, "method": "DOP853", "rtol": 1e-10, "atol": 1e-14,
          "output_dt_s": 1e-3}
    planar = pp.simulate(chains["y"], 0.05, **kw)
    spatial = pp.simulate(chains["xyz"], 0.05, **kw)
    # two paths (closed-form planar kinematics; Pinocchio's frames) at the integrator's rtol
    scale = np.abs(planar.tip_position_m - planar.tip_position_m[0]).max()
    assert np.array_equal(spatial.t_s, planar.t_s)
    assert np.abs(spatial.tip_position_m - planar.tip_position_m).max() <= 1e-7 * scale
    # no torque reaches the twist and in-plane joints: they stay at the rounding of the
    # bending terms, accumulated over the integrator's steps (thousands: 5000 EPS)
    q = spatial.q_rad
    for a in "xz":
        assert np.abs(q[:, chains["xyz"].axis_index(a)]).max() <= 5000 * EPS * np.abs(q).max()


def test_linearize_of_a_spatial_chain_has_its_frequencies(chains):
    lin = pp.linearize(chains["xy"], damping_ratio=0.0)
    # the undamped state space's eigenvalues against the chain's own eigensolver: both carry
    # the rounding of M^-1 K, relative ~EPS cond(M) (kept loose: 1e-9)
    np.testing.assert_allclose(lin.modal().omega_rad_s, chains["xy"].natural_frequencies(),
                               rtol=1e-9)
