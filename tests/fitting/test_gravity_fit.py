"""A fit in gravity against the truth in that gravity, checked in MuJoCo.

The fitted chain's frequencies about its sag are compared with the 1D beam truth's (prestressed
by the weight: Rayleigh-Ritz-checked in tests/truth/test_truth_gravity.py); the exported MJCF,
loaded in MuJoCo, carries the gravity, settles where the package's statics put the chain, and
about that pose vibrates (MuJoCo's forces, differentiated by central differences) at the
frequencies the fit reports.
"""

from __future__ import annotations

import numpy as np
import pytest

import prbdm_pin as pp
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.export import mjcf_text, urdf_text
from prbdm_pin.fitting.gravity_chain import chain_in_gravity
from prbdm_pin.fitting.gravity_target import gravity_target
from prbdm_pin.fitting.result import EXACT_MATCH_PCT
from prbdm_pin.model.prbdm_model import build_model

mujoco = pytest.importorskip("mujoco")

# hanging, standing (both through the prestress) and horizontal (the sag)
GRAVITIES = {"hanging": [300.0, 0.0, 0.0], "standing": [-300.0, 0.0, 0.0],
             "horizontal": [0.0, 0.0, -9.81]}


@pytest.fixture(scope="module", params=sorted(GRAVITIES))
def gravity_fit(request, narrow):
    g = GRAVITIES[request.param]
    target = gravity_target(narrow, g, modes=3)
    result = pp.fit(narrow, target, 3, stiffness="joint", objective="eigen", starts=4,
                    progress=False)
    model = build_model(narrow, result.lengths_m, result.stiffness_Nm_per_rad)
    return np.array(g), target, result, model


def _mujoco(model, g, damping_ratio=0.0):
    m = mujoco.MjModel.from_xml_string(mjcf_text(model, damping_ratio, gravity_m_s2=g))
    return m, mujoco.MjData(m)


def _mj_frequencies(m, d, q):
    """Frequencies (rad/s) about pose q: MuJoCo's net joint force differentiated centrally."""
    n = m.nv

    def force(qq):
        d.qpos[:] = qq
        d.qvel[:] = 0.0
        mujoco.mj_forward(m, d)
        return d.qfrc_passive - d.qfrc_bias  # springs minus gravity (no velocity terms)

    h = 1e-6  # rad: truncation h^2 ~ 1e-12, rounding EPS |f| / h ~ 1e-10 relative
    H = np.column_stack([-(force(q + h * e) - force(q - h * e)) / (2 * h) for e in np.eye(n)])
    d.qpos[:] = q
    mujoco.mj_forward(m, d)
    M = np.zeros((n, n))
    mujoco.mj_fullM(m, d, M)
    import scipy.linalg

    return np.sqrt(scipy.linalg.eigh(0.5 * (H + H.T), M, eigvals_only=True))


def test_the_fit_matches_the_truth_in_gravity(gravity_fit, narrow):
    g, target, result, _ = gravity_fit
    assert result.gravity_m_s2.tolist() == g.tolist()
    # a joint fit of n frequencies with n joints matches them (the fit's exact-match level)
    assert result.eigen_loss_pct < EXACT_MATCH_PCT
    np.testing.assert_allclose(result.omega_model_rad_s[0], target.omega_truth_rad_s,
                               rtol=EXACT_MATCH_PCT / 100)
    # the truth in gravity differs from the unloaded one where the weight prestresses
    unloaded = pp.compute_truth(narrow, model="beam", modes=3, static=False)
    moved = np.abs(target.omega_truth_rad_s[0] / unloaded.omega_rad_s[0] - 1)
    assert (moved > 1e-3) == (g[0] != 0.0)


def test_mujoco_settles_where_the_statics_put_it(gravity_fit):
    g, _, _, model = gravity_fit
    zeta = 0.1  # mode 1; mode k gets 0.1 omega_k / omega_1 (the highest 1.75: RK4 stays stable)
    m, d = _mujoco(model, g, damping_ratio=zeta)
    # the MJCF carries the gravity the model was fitted in
    assert m.opt.gravity.tolist() == g.tolist()
    w1 = pp.statics(model, gravity_m_s2=g)
    d.qpos[:] = 0.05  # rad: released bent, so even the axial cases settle from afar
    # mode 1 decays slowest, as e^(-zeta omega_1 t) (the over-damped ones as e^(-omega_1 t /
    # (2 zeta))): 30 / (zeta omega_1) s leaves e^-30 of the start
    for _ in range(int(30.0 / (zeta * result_omega1(model, g)) / m.opt.timestep)):
        mujoco.mj_step(m, d)
    q_ref = np.asarray(w1.q_rad)
    # an RK4 fixed point is the equilibrium; the statics' Newton stops at 1e-10 relative; the
    # release's 0.05 rad decays to e^-30 of it (2e-15 rad)
    np.testing.assert_allclose(d.qpos, q_ref, rtol=1e-8,
                               atol=1e-8 * max(np.abs(q_ref).max(), 0.05))


def result_omega1(model, g):
    return float(chain_in_gravity(model, g).omega_rad_s[0])


def test_mujoco_vibrates_at_the_fit_s_frequencies_about_the_sag(gravity_fit):
    g, target, result, model = gravity_fit
    m, d = _mujoco(model, g)
    q = np.asarray(pp.statics(model, gravity_m_s2=g).q_rad)
    w = _mj_frequencies(m, d, q)
    # central differences: 1e-10 relative on the stiffness; the eigensolve adds rounding
    np.testing.assert_allclose(w, result.omega_model_rad_s[0], rtol=1e-7)
    np.testing.assert_allclose(w, target.omega_truth_rad_s, rtol=EXACT_MATCH_PCT / 100 + 1e-7)


def test_the_combined_fit_in_gravity_moves_its_tip_to_the_truth_s(narrow):
    # the tip term works in gravity: the combined fit's tip under the load and the weight is
    # nearer the elastica's than the eigen-only fit's, and its frequencies stay near
    target = gravity_target(narrow, [0.0, 0.0, -9.81], modes=2)
    runs = {o: pp.fit(narrow, target, 2, stiffness="joint", objective=o, starts=2,
                      progress=False) for o in ("eigen", "combined")}
    assert runs["combined"].deflection_loss_pct < 0.5 * runs["eigen"].deflection_loss_pct
    assert runs["combined"].combined_loss_pct < runs["eigen"].combined_loss_pct


def test_fit_json_records_the_gravity_and_only_then(gravity_fit, narrow, tmp_path):
    g, _, result, _ = gravity_fit
    path = pp.save_fit(result, tmp_path / "fit.json", narrow)
    back = pp.load_fit(path)
    # written in full (repr) and read back: exact by construction
    assert back.gravity_m_s2.tolist() == g.tolist()
    t = pp.FitTarget([10.0, 60.0, 170.0], narrow.tip_force_N)
    plain = pp.fit(narrow, t, 2, stiffness="joint", starts=2, progress=False)
    assert "gravity_m_s2" not in plain.to_dict()  # a fit without gravity keeps its keys
    assert plain.gravity_m_s2 is None


def test_the_urdf_states_the_fit_s_gravity(gravity_fit):
    g, _, result, model = gravity_fit
    text = urdf_text(model, gravity_m_s2=result.gravity_m_s2)
    assert "gravity_m_s2: " + " ".join(repr(float(v)) for v in g) in text
    assert "consumer must set this gravity" in text and "No gravity" not in text
    plain = urdf_text(model)
    assert "fitted without gravity" in plain and "No gravity" in plain


def test_a_fit_in_gravity_refuses_what_it_does_not_take(narrow):
    target = gravity_target(narrow, [0.0, 0.0, -9.81], modes=2)
    for kw, name in (({"stiffness": "paper"}, "stiffness"), ({"axes": "xy"}, "axes"),
                     ({"stiffness": "joint", "joint_sweep": True}, "joint_sweep")):
        with pytest.raises(BeamInputError, match=name):
            pp.fit(narrow, target, 2, progress=False, **kw)
    with pytest.raises(BeamInputError, match="extra_loads"):
        pp.fit(narrow, target, 2, stiffness="joint", extra_loads=(2.0,), progress=False)
    with pytest.raises(BeamInputError, match="gravity_m_s2.*above"):
        gravity_target(narrow, [0.0, 0.0, -2000.0])
    with pytest.raises(BeamInputError, match="gravity_m_s2.*above"):
        mjcf_text(build_model(narrow, [0.25] * 4, [800.0] * 3), gravity_m_s2=[0, 0, 1e4])
    with pytest.raises(BeamInputError, match="g_y must be 0"):
        pp.FitTarget([10.0], narrow.tip_force_N, gravity_m_s2=[0.0, 9.81, 0.0])


def test_a_fit_about_a_large_sag_matches_the_truth_about_it():
    # a 2 mm steel strip sags 0.13 L under 1 g: the chain's frequencies about its own sag
    # against the truth's about its sag (tests/truth/test_truth_sag_modes.py checks those)
    floppy = pp.Beam(np.array([0.0, 1.0]), np.array([0.025, 0.025]), 0.002,
                     pp.Material("steel", 205e9, 7850.0, 0.28))
    target = gravity_target(floppy, [0.0, 0.0, -9.81], modes=2)
    straight = gravity_target(floppy, [0.0, 0.0, -9.81e-3], modes=2)
    assert abs(target.omega_truth_rad_s[0] / straight.omega_truth_rad_s[0] - 1) > 1e-3
    result = pp.fit(floppy, target, 2, stiffness="joint", starts=2, progress=False)
    # 2 frequencies, 2 joints: the fit's exact-match level
    np.testing.assert_allclose(result.omega_model_rad_s[0], target.omega_truth_rad_s,
                               rtol=EXACT_MATCH_PCT / 100)


def test_a_weight_along_the_member_without_a_tip_force_has_no_tip_case(narrow):
    unloaded = narrow.with_tip_force(np.zeros(3))
    target = gravity_target(unloaded, [300.0, 0.0, 0.0], modes=2)
    assert not target.has_static  # the inextensible member hangs straight
    with pytest.raises(BeamInputError, match="no tip deflection"):
        pp.fit(unloaded, target, 2, stiffness="joint", objective="combined", progress=False)
