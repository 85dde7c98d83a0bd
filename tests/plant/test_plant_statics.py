"""statics() and ``prbdm statics``: a PRBDM's equilibrium under a dead tip force, tip moment and
gravity.

References: the elastica of a uniform cantilever under an end moment (a circular arc of
curvature M / EI: x / L = sin(phi) / phi, z / L = (1 - cos(phi)) / phi, the full circle at
M = 2 pi EI / L), which a chain of equal links with half-length end links follows exactly at its
joints (a polygon inscribed in the arc); the small self-weight sag q L^4 / (8 EI); the static
balance K q + g(q) - J^T F - J_w^T M = 0 evaluated with Pinocchio's own gravity and frame
Jacobians at the returned pose.
"""

import json

import numpy as np
import pinocchio as pin
import pytest
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.cli import main
from prbdm_pin.errors import BeamInputError


def _polygon(beam, n):
    """n joints on equal links, the end links half as long, springs EI / link (the arc's)."""
    L = beam.length_m
    lengths = np.r_[0.5, np.ones(n - 1), 0.5] * L / n
    EI = beam.material.E_Pa * 2 * beam.half_width_m[0] * beam.thickness_m**3 / 12
    return pp.build_model(beam, lengths, np.full(n, EI / (L / n))), EI


def test_an_end_moment_rolls_the_chain_into_the_circle(narrow):
    model, EI = _polygon(narrow, 8)
    L = narrow.length_m
    full = pp.statics(model, tip_moment_Nm=[0.0, -2 * np.pi * EI / L, 0.0])
    # the polygon closes: the tip is back at the root (Newton's rtol 1e-10 on the torques)
    assert np.linalg.norm(full.tip_position_m) <= 1e-6 * L
    # every spring carries the moment (negative angles: the chain turns about -y)
    np.testing.assert_allclose(full.spring_torque_Nm, -2 * np.pi * EI / L, rtol=1e-9)


@pytest.mark.parametrize("phi", [np.pi / 2, np.pi])
def test_partial_arcs_are_the_elastica_s_circle(narrow, phi):
    model, EI = _polygon(narrow, 16)
    L = narrow.length_m
    eq = pp.statics(model, tip_moment_Nm=[0.0, -phi * EI / L, 0.0])
    ref = L * np.array([np.sin(phi) / phi, 0.0, (1 - np.cos(phi)) / phi])
    # the chord of an inscribed 16-gon: O(1 / n^2) of L (2.5e-3 measured at a half circle)
    assert np.linalg.norm(eq.tip_position_m - ref) <= 5e-3 * np.linalg.norm(ref)
    assert eq.tip_position_m[2] > 0.0  # a moment about -y rolls x towards +z


def test_self_weight_sag_is_the_cantilever_s(narrow):
    model, EI = _polygon(narrow, 10)
    L = narrow.length_m
    q = narrow.material.rho_kg_m3 * 2 * narrow.half_width_m[0] * narrow.thickness_m * 9.81
    eq = pp.statics(model, gravity_m_s2=[0.0, 0.0, -9.81])
    sag = q * L**4 / (8 * EI)
    assert sag < 0.01 * L  # small: the linear reference holds to (sag / L)^2
    # lumped link masses and the polygon: O(1 / n^2) (0.5 % measured at n = 10)
    assert eq.tip_displacement_m[2] == pytest.approx(-sag, rel=1e-2)


@pytest.mark.parametrize("axes", ["y", "xyz"])
def test_the_equilibrium_balances_pinocchio_s_terms(tapered, axes):
    lengths = np.array([0.2, 0.3, 0.3, 0.2]) * tapered.length_m
    model = pp.build_model(tapered, lengths, spatial_stiffness(tapered, lengths, axes),
                           axes=axes)
    F, M, g = np.array([0.0, 0.4, -3.0]), np.array([0.3, -0.5, 0.2]), np.array([0, -3, -9.81])
    eq = pp.statics(model, tip_force_N=F, tip_moment_Nm=M, gravity_m_s2=g)
    pm = pin.Model(model.pin_model)
    pm.gravity = pin.Motion(np.r_[g, 0.0, 0.0, 0.0])
    data = pm.createData()
    J = pin.computeFrameJacobian(pm, data, eq.q_rad, model.tip_frame_id,
                                 pin.LOCAL_WORLD_ALIGNED)
    r = eq.spring_torque_Nm + pin.computeGeneralizedGravity(pm, data, eq.q_rad) \
        - J[:3].T @ F - J[3:].T @ M
    # Newton's rtol 1e-10 of the spring torques
    assert np.abs(r).max() <= 1e-9 * np.abs(eq.spring_torque_Nm).max()
    assert np.abs(eq.q_rad).max() > 1e-3  # loaded
    p, R = model.tip_pose(eq.q_rad)
    assert np.array_equal(p, eq.tip_position_m) and np.array_equal(R, eq.tip_rotation)


def test_bad_loads_and_a_hub_are_refused_by_name(tapered):
    lengths = np.array([0.2, 0.3, 0.3, 0.2]) * tapered.length_m
    model = pp.build_model(tapered, lengths, spatial_stiffness(tapered, lengths, "y"))
    with pytest.raises(BeamInputError, match="tip_moment_Nm = .*3 finite numbers"):
        pp.statics(model, tip_moment_Nm=[0.0, np.nan, 0.0])
    with pytest.raises(BeamInputError, match="gravity_m_s2"):
        pp.statics(model, gravity_m_s2=[0.0, -9.81])
    hub = pp.build_model(tapered, lengths, model.stiffness_Nm_per_rad,
                         hub=pp.Hub(inertia_kg_m2=5.0, radius_m=0.1))
    with pytest.raises(BeamInputError, match="model: has a hub"):
        pp.statics(hub, tip_force_N=[0.0, 0.0, -1.0])


def test_the_command_writes_the_equilibrium_and_refuses_bad_options(narrow, tmp_path, capsys):
    model, EI = _polygon(narrow, 8)
    src = tmp_path / "model.json"
    pp.export_model(model, src, "json")
    M = -np.pi * EI / narrow.length_m
    out = tmp_path / "st"
    assert main(["statics", str(src), "--tip-moment", f"0,{float(M)!r},0", "--gravity", "0,0,-1",
                 "--out", str(out), "-q"]) == 0
    d = json.loads((out / "statics.json").read_text())
    eq = pp.statics(pp.load_model(src).model, tip_moment_Nm=[0, M, 0],
                    gravity_m_s2=[0, 0, -1])
    # the same solve on the model read back from its JSON (its numbers round-trip exactly):
    # a few roundings of L at most
    np.testing.assert_allclose(d["tip_position_m"], eq.tip_position_m, rtol=0.0,
                               atol=50 * EPS * narrow.length_m)
    np.testing.assert_allclose(d["q_rad"], eq.q_rad, rtol=1e-9)
    for args, text in ((["--tip-force", "1,2"], "--tip-force"),
                       (["--gravity", "0,0,nan"], "--gravity")):
        bad = tmp_path / "bad"
        assert main(["statics", str(src), *args, "--out", str(bad)]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and text in err[0], err
        assert not bad.exists()
