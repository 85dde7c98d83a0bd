"""Sensor outputs at rest: the root reaction and the strain of a tip-loaded cantilever chain
against its statics, the slope and twist against differences of point positions, the station
outputs' rows against central differences, and the refusals of bad stations and names.

References: Newton-Euler of the whole member (what it exerts on its support: F,
r_tip x F + m, and the weight of the beam's analytic mass rho t A); the moment of the tip force
about each deformed joint over E I (beam theory's strain M t / (2 E I)); the rigid link's point
positions; central differences (tests/central_differences.py)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from central_differences import central_difference
from paths import ROOT
from tolerances import EPS

from prbdm_pin import Hub, build_model
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.model.load_outputs import load_output_values
from prbdm_pin.model.names import split_name
from prbdm_pin.model.outputs import (
    check_output_stations,
    output_maps,
    output_values,
    parse_outputs,
)

BEAM = load_beam(ROOT / "examples/beams/uniform-narrow.json")  # L = 1 m, t = 10 mm
LENGTHS = np.array([0.2, 0.3, 0.3, 0.2])  # joints at 0.2, 0.5, 0.8 m
SPRINGS = np.array([1000.0, 800.0, 500.0])
REACTION = ("root_force_x", "root_force_y", "root_force_z", "root_moment_x", "root_moment_y",
            "root_moment_z")


def _model(axes="y", hub=None):
    k = SPRINGS if axes == "y" else np.repeat(SPRINGS, len(axes))
    return build_model(BEAM, LENGTHS, k, axes=axes, hub=hub)


@pytest.mark.parametrize("axes", ["y", "xyz"])
def test_root_reaction_of_a_tip_loaded_cantilever_is_the_load(axes):
    model = _model(axes)
    F = np.array([0.0, 0.0, 40.0]) if axes == "y" else np.array([8.0, -15.0, 40.0])
    m = None if axes == "y" else np.array([1.5, -2.0, 0.7])
    q, tip = model.static_deflection(F, tip_moment_Nm=m)
    assert np.abs(q).max() > 0.01  # a deflection that turns the lever arms visibly
    parsed = parse_outputs(REACTION, model.n_springs, False)
    z = np.zeros(q.size)
    loads = {"tip_force": F, "tip_moment": np.zeros(3) if m is None else m}
    R = load_output_values(model, q, z, z, parsed, loads)
    # the member passes the load on to its support: F and its moment about the root
    ref = np.concatenate([F, np.cross(tip, F) + loads["tip_moment"]])
    # at rest and weightless the inertial part is an exact 0: what is left is the cross product
    # of the tip position and F, a few roundings of |tip| |F|
    assert np.abs(R - ref).max() <= 8 * EPS * np.linalg.norm(tip) * np.linalg.norm(F)


def test_root_force_under_gravity_carries_the_beams_weight():
    model = _model("xyz")
    g = np.array([0.0, -3.0, -9.81])
    q = np.random.default_rng(1).normal(size=model.pin_model.nv) * 0.2  # any pose: at rest
    parsed = parse_outputs(REACTION[:3], model.n_springs, False)
    z = np.zeros(q.size)
    R = load_output_values(model, q, z, z, parsed, {}, g)
    mass = 2.0 * 0.025 * BEAM.length_m * BEAM.thickness_m * BEAM.material.rho_kg_m3  # rho t A
    # the links' masses sum to the beam's (quadrature of a linear width: a few roundings)
    # the member's weight, passed on to its support
    assert np.abs(R - mass * g).max() <= 50 * EPS * mass * np.linalg.norm(g)


@pytest.mark.parametrize(("axes", "beam"), [("y", "uniform-narrow"), ("xyz", "uniform-narrow"),
                                           ("y", "tapered-linear")])
def test_strain_is_the_tip_forces_moment_over_EI(axes, beam):
    """At each joint the strain is the moment of the tip force about the deformed joint over
    the local E I(x) (a tapered member's changes along it), times t / 2."""
    b = load_beam(ROOT / f"examples/beams/{beam}.json")
    lengths = LENGTHS * b.length_m
    k = SPRINGS * (b.root_EI_Nm2 / BEAM.root_EI_Nm2)
    model = build_model(b, lengths, k if axes == "y" else np.repeat(k, 3), axes=axes)
    Fz = 40.0 * (b.root_EI_Nm2 / BEAM.root_EI_Nm2)  # a deflection of the same few degrees
    q, tip = model.static_deflection(np.array([0.0, 0.0, Fz]))
    data = model.new_data()  # the deformed joints: the lever arms of the tip force
    pin.framesForwardKinematics(model.pin_model, data, q)
    xj = np.array([data.oMf[model.pin_model.getFrameId(f"link_{j}")].translation[0]
                   for j in range(1, LENGTHS.size)])
    stations = np.cumsum(lengths)[:-1]
    names = [f"strain@{float(x)!r}" for x in stations]
    eps = output_values(model, q, names, load_N=np.array([0.0, 0.0, Fz]))
    EI = b.material.E_Pa * b.area_moment_at(stations)
    ref = Fz * (tip[0] - xj) * b.thickness_m / (2.0 * EI) * 1e6
    assert np.all(ref > 0.0)  # tip_z > 0: positive strain (the sign convention)
    # the springs hold the moment of F about the joints to the statics solver's tolerance
    # (its residual, rtol 1e-10 of the spring torques)
    assert np.abs(eps - ref).max() <= 1e-9 * np.abs(ref).max()


def test_strain_gain_at_the_straight_pose_is_beam_theory_everywhere():
    """The moment of a tip force F_z on the straight member is F_z (L - x) at every station,
    so the strain per newton is (L - x) t / (2 E I(x)) 1e6, between the joints too."""
    model = _model()
    x = np.array([0.0, 0.07, 0.2, 0.33, 0.5, 0.61, 0.8, 0.93, 1.0])
    names = [f"strain@{v:g}" for v in x]
    parsed = parse_outputs(names, model.n_springs, False)
    z = np.zeros(3)
    h = 1e-3  # N: small, so that the lever arms are the straight member's
    q1, _ = model.static_deflection(np.array([0.0, 0.0, h]))
    eps = load_output_values(model, q1, z, z, parsed, {"tip_force": np.array([0, 0, h])})
    EI = BEAM.material.E_Pa * BEAM.area_moment_at(x)
    ref = h * (BEAM.length_m - x) * BEAM.thickness_m / (2.0 * EI) * 1e6
    # a 1 mN load turns the joints by ~1e-6 rad: the lever arms shorten by q^2/2 ~ 1e-12
    assert np.abs(eps - ref).max() <= 1e-9 * np.abs(ref).max()


def test_strain_under_the_weight_is_the_chord_of_the_beams_moment():
    """Under its own weight w per length the beam's moment is w (L - x)^2 / 2, a parabola; the
    chain carries it exactly at the root, the joints and the tip (each link's weight at its own
    centre) and linearly between, so at a link's midpoint it reads the chord, w l^2 / 8 above
    the parabola (the claim of prbdm_pin.model.strain)."""
    from prbdm_pin import statics

    model = _model()
    g = 0.01  # m/s^2: a light weight keeps the lever arms the straight member's (q ~ 1e-6)
    eq = statics(model, gravity_m_s2=[0.0, 0.0, -g])
    ends = np.concatenate([[0.0], np.cumsum(LENGTHS)])
    mid = 0.5 * (ends[:-1] + ends[1:])
    names = [f"strain@{x:.12g}" for x in np.concatenate([ends, mid])]
    eps = output_values(model, eq.q_rad, names, gravity_m_s2=[0.0, 0.0, -g])
    w = BEAM.material.rho_kg_m3 * BEAM.thickness_m * 0.05 * g  # N/m: rho t (2 b) g
    L = BEAM.length_m
    M = w * (L - np.concatenate([ends, mid])) ** 2 / 2.0
    M[ends.size:] += w * LENGTHS**2 / 8.0  # the chord's excess at the midpoints
    ref = -M * BEAM.thickness_m / (2.0 * BEAM.material.E_Pa * BEAM.area_moment_at(0.5)) * 1e6
    # the statics' Newton tolerance (rtol 1e-10) and the lever arms' change O(q^2) ~ 1e-12
    assert np.abs(eps - ref).max() <= 1e-9 * np.abs(ref).max()


def test_root_reaction_on_a_turned_hub_is_in_the_hubs_frame():
    """The straight member on a hub turned by theta: its weight m g acts at L/2 from the root
    along the hub's x axis, a tip force F at L; in the hub's frame (R_y(theta)^T)."""
    r = 0.1
    model = _model(hub=Hub(5.0, r))
    theta = 0.7
    q = np.array([theta, 0.0, 0.0, 0.0])
    c, s = np.cos(theta), np.sin(theta)
    Rt = np.array([[c, 0.0, -s], [0.0, 1.0, 0.0], [s, 0.0, c]])  # hub from world
    g = np.array([0.0, 0.0, -9.81])
    F = np.array([1.0, 2.0, 3.0])
    parsed = parse_outputs(REACTION, model.n_springs, True)
    z = np.zeros(4)
    R = load_output_values(model, q, z, z, parsed, {"tip_force": F}, g)
    weight = BEAM.mass_kg * (Rt @ g)
    L = BEAM.length_m
    ref = np.concatenate([weight + Rt @ F, np.cross([L / 2, 0.0, 0.0], weight)
                          + np.cross([L, 0.0, 0.0], Rt @ F)])
    # sums of a few link terms of the weight's and the load's scale: a few roundings
    assert np.abs(R - ref).max() <= 64 * EPS * (np.abs(weight).max() + np.abs(F).max()) * L


@pytest.mark.parametrize("kind", ["spatial", "hub"])
def test_slope_and_twist_agree_with_point_positions(kind):
    model = _model("xyz") if kind == "spatial" else _model(hub=Hub(5.0, 0.05))
    q = np.random.default_rng(2).normal(size=model.pin_model.nv) * 0.25
    for x in (0.1, 0.35, 0.65, 0.9):  # inside links 0..3
        dx, w = 0.04, 0.02
        names = [f"slope@{x:g}", f"twist@{x:g}"] + [
            f"point_{c}@{xx:g}:{yy:g}" for xx, yy in ((x - dx, 0), (x + dx, 0), (x, w), (x, -w))
            for c in "xyz"]
        v = output_values(model, q, names)
        p = v[2:].reshape(4, 3)
        undeformed = np.array([[x - dx, 0, 0], [x + dx, 0, 0], [x, w, 0], [x, -w, 0]])
        if kind == "hub":
            undeformed[:, 0] += 0.05
        p = p + undeformed  # positions
        axis = (p[1] - p[0]) / np.linalg.norm(p[1] - p[0])  # the link's x axis, world
        across = (p[2] - p[3]) / np.linalg.norm(p[2] - p[3])  # its y axis
        slope_ref = np.arcsin(-axis[2])
        twist_ref = np.arctan2(across[2], np.cross(axis, across)[2])  # atan2(R_zy, R_zz)
        # points 2 dx and 2 w apart on a ~1 m chain: the difference loses |p| / (2 w) = 25 of
        # the positions' few roundings
        assert abs(v[0] - slope_ref) <= 500 * EPS
        assert abs(v[1] - twist_ref) <= 500 * EPS
        if kind == "hub":
            assert abs(v[1]) <= 500 * EPS  # a planar chain does not twist


@pytest.mark.parametrize("kind", ["planar", "spatial", "hub"])
def test_station_rows_match_central_differences(kind):
    model = {"planar": lambda: _model(), "spatial": lambda: _model("xyz"),
             "hub": lambda: _model(hub=Hub(5.0, 0.05))}[kind]()
    q = np.random.default_rng(3).normal(size=model.pin_model.nv) * 0.3
    names = ["slope@0.35", "twist@0.5", "slope@0.5", "point_x@0.9:0.015", "point_y@0.2:-0.02",
             "point_z@1:0.025", "point_z@0.5:0.01"]  # 0.5 is a joint: the two links' mean
    Cq, Cv = output_maps(model, q, names)
    # values of order 1 m or 1 rad, each a few roundings
    fd, err = central_difference(lambda x: output_values(model, x, names), q, 1e-4, 8 * EPS)
    assert not np.any(Cv)
    assert np.all(np.abs(Cq - fd) <= err)  # the difference's own error bound


def test_station_names_parse_and_bad_ones_are_refused_by_name():
    assert split_name("strain@0.25", "o") == ("strain", (0.25,))
    assert split_name("point_z@1e-1:-0.01", "o") == ("point_z", (0.1, -0.01))
    assert split_name("q[2]", "o") == ("q", 2)
    model = _model()
    cases = [
        (["tip_z", "strain@1.5"], r"outputs\[1\] = 'strain@1.5': station x = 1.5 m is off the "
                                  r"member, which spans \[0, 1\] m"),
        (["slope@-0.1"], r"outputs\[0\] = 'slope@-0.1': station x = -0.1 m is off"),
        (["point_z@0.5:0.03"], r"outputs\[0\] = 'point_z@0.5:0.03': point y = 0.03 m is off "
                               r"the planform, whose half-width at x = 0.5 m is 0.025 m"),
    ]
    for names, msg in cases:
        with pytest.raises(BeamInputError, match=msg):
            check_output_stations(model, names)
    for names, msg in [(["point_z@0.5"], r"outputs\[0\] = 'point_z@0.5': point_z takes the "
                                         r"station X:Y"),
                       (["strain@0.1:0.2"], r"outputs\[0\] = 'strain@0.1:0.2': strain takes"),
                       (["tip@0.5"], r"outputs\[0\] = 'tip@0.5': unknown"),
                       (["strain@abc"], r"outputs\[0\] = 'strain@abc': must be a name")]:
        with pytest.raises(BeamInputError, match=msg):
            parse_outputs(names, 3, False)


def test_a_model_without_its_beam_has_no_strain_or_points(tmp_path):
    from prbdm_pin.files.urdf_file import load_urdf

    model = _model()
    model.write_urdf(tmp_path / "chain.urdf")
    bare = load_urdf(tmp_path / "chain.urdf")
    check_output_stations(bare, ["slope@0.3", "twist@1"])  # the links suffice
    q = np.array([0.1, -0.2, 0.3])
    # a planar chain's slope is the sum of the joint angles inboard (0.3 m: joint 0; 0.6 m:
    # joints 0 and 1), its twist 0: through the rotation matrices, a few roundings of 1 rad
    assert np.allclose(output_values(bare, q, ["slope@0.3", "slope@0.6", "twist@1"]),
                       [0.1, -0.1, 0.0], rtol=0.0, atol=8 * EPS)
    with pytest.raises(BeamInputError, match=r"outputs\[0\] = 'strain@0.3': this model "
                                             "carries no beam"):
        check_output_stations(bare, ["strain@0.3"])
    with pytest.raises(BeamInputError, match=r"outputs\[1\] = 'point_x@0.3:0': this model "
                                             "carries no beam"):
        check_output_stations(bare, ["slope@0.3", "point_x@0.3:0"])


def test_an_input_whose_load_is_unknown_is_refused_not_dropped():
    """The root reaction subtracts the applied loads: an input it has no resultant for (one
    added to the plant later) must stop it, not be taken as no load."""
    from prbdm_pin.model.reaction import applied_wrench_columns, check_load_inputs

    model = _model()
    parsed = (("tip_force_z", "tip_force_z", None), ("joint_torque[0]", "joint_torque", 0),
              ("line_load_z", "line_load_z", None))
    with pytest.raises(BeamInputError, match=r"inputs\[2\] = 'line_load_z': the root reaction "
                                             "and the strain do not know"):
        check_load_inputs(parsed)
    cols = applied_wrench_columns(model, np.zeros(3), parsed[:2])
    tip = model.tip_position(np.zeros(3))
    # a unit z force at the tip (L, 0, 0): (0, 0, 1) and L e_x x e_z = -L e_y; a joint torque
    # is internal (none): exact products of 0, 1 and L
    assert np.array_equal(cols[:, 0], [0.0, 0.0, 1.0, 0.0, -tip[0], 0.0])
    assert np.array_equal(cols[:, 1], np.zeros(6))
