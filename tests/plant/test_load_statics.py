"""statics() and ``prbdm statics`` under follower tip moments and distributed loads.

References (tests/cantilever_loads.py, none from the package): the end moment's circle (the
full circle at M = 2 pi EI / L; a half circle's tip at 2 L / pi; partial arcs x / L =
sin(phi) / phi, z / L = (1 - cos(phi)) / phi) and the chain's own polygon of it, worked out in
closed form (the arc scaled by (theta / 2) cot(theta / 2), theta = phi / n); Euler-Bernoulli's
tip deflection under a uniform load over part of the span and the sag q L^4 / (8 EI); the
elastica under self weight by shooting; the static balance evaluated with the follower
moment's generalized force from central differences of the tip rotation.
"""

import json

import numpy as np
import pinocchio as pin
import pytest
from cantilever_loads import (
    arc_tip,
    elastica_self_weight,
    equal_lengths,
    partial_load_tip,
    polygon_arc_tip,
    strip_properties,
)

import prbdm_pin as pp
from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.cli import main
from prbdm_pin.errors import BeamInputError, SolveError

# the equilibrium's Newton stops at 1e-10 of the spring torques (plant.equilibrium's rtol): a
# joint angle, and so a tip position over L, is good to about that times the condition of K
# against the load stiffness (1 for a pure moment on the planar chain)
NEWTON = 1e-9


def _polygon(beam, n, axes="y"):
    """Equal links with half-length end links; springs E I / h (the package's finite-segment
    rule gives exactly that on a uniform strip); a spatial chain's z springs the same, its
    torsion springs G J / h from the package's spatial rule."""
    L, EI, _ = strip_properties(beam)
    lengths = equal_lengths(L, n)
    k = spatial_stiffness(beam, lengths, axes) if axes != "y" else np.full(n, EI * n / L)
    if axes != "y":
        k = k.reshape(n, len(axes))
        k[:, 0] = k[:, 1] = EI * n / L  # isotropic bending: the circle in either plane
        k = k.ravel()
    return pp.build_model(beam, lengths, k, axes=axes, min_fraction=0.5 / n)


@pytest.mark.parametrize("axes, moment", [("y", [0.0, -1.0, 0.0]), ("xyz", [0.0, -1.0, 0.0]),
                                          ("xyz", [0.0, 0.0, 1.0])])
def test_a_follower_end_moment_closes_the_polygon(narrow, axes, moment):
    n = 8
    model = _polygon(narrow, n, axes)
    L, EI, _ = strip_properties(narrow)
    eq = pp.statics(model, tip_moment_follower_Nm=2 * np.pi * EI / L * np.array(moment))
    # the polygon closes: the tip is back at the root (the 2 pi turn is n joint angles each
    # good to NEWTON)
    assert np.linalg.norm(eq.tip_position_m) <= 1e-6 * L
    # every bending spring carries the moment
    bend = model.axis_index("y" if moment[1] else "z")
    np.testing.assert_allclose(np.abs(eq.spring_torque_Nm[bend]), 2 * np.pi * EI / L,
                               rtol=NEWTON)


@pytest.mark.parametrize("phi", [np.pi / 3, np.pi / 2, np.pi])
def test_partial_arcs_are_the_polygon_s_and_near_the_circle(narrow, phi):
    n = 16
    model = _polygon(narrow, n, "xyz")
    L, EI, _ = strip_properties(narrow)
    eq = pp.statics(model, tip_moment_follower_Nm=[0.0, -phi * EI / L, 0.0])
    tip = eq.tip_position_m[[0, 2]]
    # the chain's own polygon in closed form: to the solver's precision
    assert np.abs(tip - polygon_arc_tip(L, n, phi)).max() <= NEWTON * L
    # the continuum's arc: off by the polygon's factor (theta / 2) cot(theta / 2), theta^2 / 12
    # to first order (3.2e-3 at a half circle of a 16-gon)
    theta = phi / n
    shrink = 1.0 - 0.5 * theta / np.tan(0.5 * theta)
    ref = arc_tip(L, phi)
    assert np.linalg.norm(tip - ref) <= (shrink + NEWTON) * np.linalg.norm(ref)
    if phi == np.pi:
        # the half circle's tip at 2 L / pi: within 0.5 % (0.32 % measured)
        assert abs(np.linalg.norm(tip) / (2 * L / np.pi) - 1.0) <= 5e-3


def test_a_follower_moment_balances_the_tip_rotation_s_virtual_work(tapered):
    # a bent and twisted spatial chain: follower moments about all three tip axes; the balance
    # K q = J_l^T M_f with J_l from central differences of the tip rotation (omega in the tip
    # frame), not the package's map
    lengths = np.array([0.2, 0.3, 0.3, 0.2]) * tapered.length_m
    model = pp.build_model(tapered, lengths, spatial_stiffness(tapered, lengths, "xyz"),
                           axes="xyz")
    Mf = np.array([40.0, -200.0, 150.0])  # N m: joint angles up to 0.4 rad
    eq = pp.statics(model, tip_moment_follower_Nm=Mf)
    q, data, h = eq.q_rad, model.new_data(), 1e-5

    def rotation(qq):
        pin.framesForwardKinematics(model.pin_model, data, qq)
        return data.oMf[model.tip_frame_id].rotation.copy()

    R = rotation(q)
    J = np.empty((3, q.size))
    for j in range(q.size):
        e = np.zeros(q.size)
        e[j] = h
        W = R.T @ (rotation(q + e) - rotation(q - e)) / (2 * h)
        J[:, j] = [W[2, 1], W[0, 2], W[1, 0]]
    r = eq.spring_torque_Nm - J.T @ Mf
    # Newton's 1e-10 and the differences' h^2 ~ 1e-10 of the torques
    assert np.abs(r).max() <= 1e-8 * np.abs(eq.spring_torque_Nm).max()
    assert np.abs(eq.q_rad).max() > 0.05  # well bent
    # the dead moment equal to the follower one in world axes at this pose (R M_f) has the
    # same equilibrium: found by the dead-moment statics (the spatial chain's exact tangent
    # and load stepping), to both solvers' precision
    dead = pp.statics(model, tip_moment_Nm=R @ Mf)
    assert np.abs(dead.q_rad - q).max() <= NEWTON * np.abs(q).max()
    # while the dead moment of the follower's components in world axes bends otherwise: the
    # tip turned, and the follower moment with it
    other = pp.statics(model, tip_moment_Nm=Mf)
    assert np.abs(other.q_rad - q).max() > 1e-2


@pytest.mark.parametrize("span", [(0.0, 1.0), (0.3, 1.0), (0.0, 0.45), (0.25, 0.7)])
def test_a_small_load_over_part_of_the_span_deflects_the_tip_as_the_beam(narrow, span):
    L, EI, _ = strip_properties(narrow)
    a, b = span[0] * L, span[1] * L
    q = 1e-3 * EI / L**3  # sag ~ 1e-4 L: the linear theory holds to (sag / L) ~ 1e-4
    ref = partial_load_tip(L, EI, q, a, b)
    err = {}
    for n in (10, 20):
        lengths = equal_lengths(L, n)
        model = pp.build_model(narrow, lengths,
                               pp.finite_segment_stiffness(narrow, lengths, min_fraction=0.5 / n),
                               min_fraction=0.5 / n)
        eq = pp.statics(model, distributed_N_m=[0.0, 0.0, -q],
                        distributed_load=pp.DistributedLoad(a, b))
        err[n] = -eq.tip_displacement_m[2] / ref - 1.0
    # the chain's discretisation (its springs sample the beam's curvature at the joints): second
    # order in 1 / n, -1 / (2 n^2) for the whole span; 3.99 to 4.01 measured for the ratio
    # (the linear theory's 1e-4 and Newton's 1e-10 are below its last digit)
    assert 3.9 <= err[10] / err[20] <= 4.1
    # 1.0e-3 (span ends at joints) to 4.3e-3 ([0, 0.45 L], ending inside a link) at n = 20
    assert abs(err[20]) <= 5e-3


def test_the_5r_sag_of_a_uniform_strip(narrow):
    # 5R: equal links with half-length end links, the package's finite-segment springs
    n = 5
    L, EI, rhoA = strip_properties(narrow)
    lengths = equal_lengths(L, n)
    model = pp.build_model(narrow, lengths, pp.finite_segment_stiffness(narrow, lengths))
    q = rhoA * 9.81
    sag = q * L**4 / (8 * EI)
    assert sag < 1e-2 * L  # small: the linear reference holds to (sag / L)^2
    for eq in (pp.statics(model, distributed_N_m=[0.0, 0.0, -q]),
               pp.statics(model, gravity_m_s2=[0.0, 0.0, -9.81])):
        # within 3 % (2.0 % measured: the chain's -1 / (2 n^2))
        assert abs(-eq.tip_displacement_m[2] / sag - 1.0) <= 0.03


def test_the_large_sag_under_self_weight_is_the_elastica_s(narrow):
    L, EI, rhoA = strip_properties(narrow)
    q = 3.0 * EI / L**3  # q L^3 / EI = 3: the tip drops by a third of L
    ref = elastica_self_weight(L, EI, q)
    err = {}
    for n in (8, 16):
        lengths = equal_lengths(L, n)
        model = pp.build_model(narrow, lengths, np.full(n, EI * n / L), min_fraction=0.5 / n)
        dist = pp.statics(model, distributed_N_m=[0.0, 0.0, -q])
        grav = pp.statics(model, gravity_m_s2=[0.0, 0.0, -q / rhoA])
        # the weight of a uniform strip is the uniform load (links' centres of mass at their
        # middles): the same equilibrium to Newton's precision
        assert np.abs(dist.q_rad - grav.q_rad).max() <= NEWTON * np.abs(grav.q_rad).max()
        err[n] = np.linalg.norm(dist.tip_position_m[[0, 2]] - ref) / L
    # second order in 1 / n (2.8e-3 and 7.1e-4 of L measured): the ratio near 4 shows the error
    # is the discretisation's, and it is small at n = 16
    assert 3.5 <= err[8] / err[16] <= 4.5
    assert err[16] <= 1e-3


def test_a_heavy_strip_hangs_as_the_elastica_after_the_load_is_stepped_up(narrow):
    # q L^3 / EI = 100: the strip hangs nearly down; the whole load in one Newton solve from
    # the straight pose finds no equilibrium, so statics steps it up in tenths
    L, EI, _ = strip_properties(narrow)
    q = 100.0 * EI / L**3
    ref = elastica_self_weight(L, EI, q)
    err = {}
    for n in (8, 16):
        model = pp.build_model(narrow, equal_lengths(L, n), np.full(n, EI * n / L),
                               min_fraction=0.5 / n)
        eq = pp.statics(model, distributed_N_m=[0.0, 0.0, -q])
        err[n] = np.linalg.norm(eq.tip_position_m[[0, 2]] - ref) / L
    # second order in 1 / n (2.2e-2 and 5.3e-3 of L measured)
    assert 3.5 <= err[8] / err[16] <= 4.5
    assert err[16] <= 1e-2
    assert ref[1] < -0.9 * L  # hanging


def test_bad_loads_are_refused_by_name(tapered):
    lengths = np.array([0.2, 0.3, 0.3, 0.2]) * tapered.length_m
    model = pp.build_model(tapered, lengths, spatial_stiffness(tapered, lengths, "y"))
    with pytest.raises(BeamInputError, match="tip_moment_follower_Nm = .*3 finite numbers"):
        pp.statics(model, tip_moment_follower_Nm=[0.0, np.inf, 0.0])
    with pytest.raises(BeamInputError, match="distributed_N_m"):
        pp.statics(model, distributed_N_m=[0.0, -1.0])
    with pytest.raises(BeamInputError, match="distributed_load x_end_m = .*must lie on the beam"):
        pp.statics(model, distributed_N_m=[0.0, 0.0, -1.0],
                   distributed_load=pp.DistributedLoad(0.1, 5.0))
    # beyond what stepping finds: a SolveError naming the loads
    with pytest.raises(SolveError, match="distributed load .*stepped up in tenths"):
        pp.statics(model, distributed_N_m=[0.0, 0.0, -1e9])


def test_the_command_takes_the_new_loads_and_refuses_them_badly(narrow, tmp_path, capsys):
    model = _polygon(narrow, 8)
    L, EI, _ = strip_properties(narrow)
    src = tmp_path / "model.json"
    pp.export_model(model, src, "json")
    M = -np.pi * EI / L
    out = tmp_path / "st"
    assert main(["statics", str(src), "--tip-moment-follower", f"0,{float(M)!r},0",
                 "--distributed-load", "0,0,-3", "--distributed-span", f"{0.2 * L!r}:{L!r}",
                 "--out", str(out), "-q"]) == 0
    d = json.loads((out / "statics.json").read_text())
    eq = pp.statics(pp.load_model(src).model, tip_moment_follower_Nm=[0, M, 0],
                    distributed_N_m=[0, 0, -3], distributed_load=pp.DistributedLoad(0.2 * L, L))
    # the same solve on the model read back from its JSON (numbers round-trip exactly)
    np.testing.assert_array_equal(d["q_rad"], eq.q_rad)
    assert d["distributed_span_m"] == [0.2 * L, L]
    assert d["tip_moment_follower_Nm"] == [0.0, M, 0.0]
    for args, text in ((["--tip-moment-follower", "1,2"], "--tip-moment-follower"),
                       (["--distributed-load", "0,0,x"], "--distributed-load"),
                       (["--distributed-load", "0,0,-1", "--distributed-span", "0.5"],
                        "--distributed-span"),
                       (["--distributed-load", "0,0,-1", "--distributed-span", "0:9"],
                        "--distributed-span")):
        bad = tmp_path / "bad"
        assert main(["statics", str(src), *args, "--out", str(bad)]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and text in err[0], err
        assert not bad.exists()
