"""Mode pairing by shape (MAC) in a spatial fit's result.

References: Pinocchio's point Jacobians for the chain's deflection and twist at the tip; an
exact field linear across the width and along the span for the truth's slices; Saint-Venant's
clamped-free torsion sines and the Euler-Bernoulli cantilever shapes for the plate truth's
modes on the uniform strip; a spatial chain taken as its own truth (its modes from one
eigensolve of the whole pencil) for the pairing, with two of its torsion shapes exchanged.
"""

from types import SimpleNamespace

import numpy as np
import pytest
from chain_truth import self_target
from reference import BETA_L
from tolerances import EPS

from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.errors import BeamInputError
from prbdm_pin.fitting.mode_shapes import (
    ModeShapes,
    chain_shapes,
    mac_matrix,
    pair_by_mac,
    pair_modes,
    pairing_notes,
    truth_mode_shapes,
)
from prbdm_pin.fitting.multistart import fit
from prbdm_pin.fitting.spatial_design import SpatialDesign
from prbdm_pin.fitting.spatial_target import select_spatial
from prbdm_pin.fitting.target import target_from_truth
from prbdm_pin.model.prbdm_model import build_model
from prbdm_pin.options.objects import FitOptions


def _chain(beam, axes="xyz"):
    lengths = np.array([0.25, 0.35, 0.25, 0.15]) * beam.length_m
    return build_model(beam, lengths, spatial_stiffness(beam, lengths, axes), axes=axes)


def test_the_chain_shapes_at_the_tip_are_pinocchio_s_point_kinematics(tapered):
    model = _chain(tapered)
    phi = np.random.default_rng(1).normal(size=(model.n_springs, 4))
    tip = np.array([tapered.length_m])
    w = chain_shapes(model.lengths_m, model.axis_index("y"), phi, tip, "y")[0]
    theta = chain_shapes(model.lengths_m, model.axis_index("x"), phi, tip, "x")[0]
    Jz = {p: model.point_kinematics(p)[1][2] for p in ("tip", "tip_corner_left",
                                                        "tip_corner_right")}
    half = tapered.half_width_m[-1]
    # sums of a few products of lengths and coordinates: a few roundings
    np.testing.assert_allclose(w, Jz["tip"] @ phi, rtol=0.0, atol=50 * EPS * np.abs(w).max())
    twist = (Jz["tip_corner_left"] - Jz["tip_corner_right"]) @ phi / (2 * half)
    np.testing.assert_allclose(theta, twist, rtol=0.0, atol=50 * EPS * np.abs(theta).max()
                               * tapered.length_m / half)


def test_the_truth_slices_recover_a_field_linear_in_x_and_y():
    x, y = np.meshgrid(np.linspace(0.0, 1.0, 49), np.linspace(-0.1, 0.1, 5))
    nodes = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])
    a, b = np.array([[0.0, 2.0], [1.0, -3.0]]), np.array([[0.5, 1.0], [-2.0, 4.0]])
    uz = np.array([a[k, 0] + a[k, 1] * nodes[:, 0] + (b[k, 0] + b[k, 1] * nodes[:, 0])
                   * nodes[:, 1] for k in range(2)])
    s = truth_mode_shapes(SimpleNamespace(nodes_m=nodes, node_uz=uz))
    xs = s.stations_m
    assert xs.size >= 20
    for k in range(2):
        # least squares on a few dozen nodes of order-one values: rounding only
        np.testing.assert_allclose(s.deflection[k], a[k, 0] + a[k, 1] * xs, atol=1e3 * EPS)
        np.testing.assert_allclose(s.twist[k], b[k, 0] + b[k, 1] * xs, atol=1e4 * EPS)
    # no width: no twist to read (the 1D beam)
    assert truth_mode_shapes(SimpleNamespace(nodes_m=nodes * [1, 0, 0], node_uz=uz)) is None


def test_the_plate_strip_s_shapes_are_the_closed_forms(narrow, truth_of):
    truth = truth_of(narrow, model="plate", mesh_level=1, modes=2, static=False)
    s = truth_mode_shapes(truth.modal)
    x = s.stations_m / narrow.length_m
    labels = np.array(truth.labels)
    twist = s.twist[labels == "torsion"][:2]
    sines = np.array([np.sin((2 * k - 1) * np.pi * x / 2) for k in (1, 2)])
    bend = s.deflection[labels == "bending"][:2]
    bl = BETA_L[:2, None] * x
    sigma = (np.cosh(BETA_L[:2]) + np.cos(BETA_L[:2])) / (np.sinh(BETA_L[:2]) + np.sin(BETA_L[:2]))
    eb = np.cosh(bl) - np.cos(bl) - sigma[:, None] * (np.sinh(bl) - np.sin(bl))
    # the plate's clamp restrains warping near the root (width / length = 1/20 of the span):
    # the shapes agree to a few 1e-3 in MAC; the other modes are near orthogonal
    np.testing.assert_allclose(np.diag(mac_matrix(twist.T, sines.T)), 1.0, atol=5e-3)
    np.testing.assert_allclose(np.diag(mac_matrix(bend.T, eb.T)), 1.0, atol=5e-3)
    # a symmetric strip separates the kinds: a bending mode does not twist the section, a
    # torsion mode does not move the axis (the mesh's rounding, relative to the other part)
    half = narrow.half_width_m[0]
    assert np.abs(s.twist[labels == "bending"][:2]).max() * half \
        <= 1e-9 * np.abs(bend).max()
    assert np.abs(s.deflection[labels == "torsion"][:2]).max() \
        <= 1e-9 * np.abs(twist).max() * half


def test_pairing_is_the_permutation_of_largest_mac():
    rng = np.random.default_rng(0)
    a = rng.normal(size=(30, 4))
    perm = np.array([2, 0, 3, 1])
    cols, mac = pair_by_mac(a, a[:, np.argsort(perm)] * [2.0, -1.0, 0.5, 3.0])
    assert np.array_equal(cols, perm) and np.allclose(mac, 1.0, rtol=0.0, atol=50 * EPS)


def _design(model, target, joints):
    o = FitOptions(axes=model.axes.value, stiffness="joint")
    sel = select_spatial(target, o.axes, joints, o.frequencies)
    return SpatialDesign(model.beam, sel, joints, o)


def test_a_weak_resemblance_keeps_the_rank():
    """Only a MAC of at least MAC_WARN moves a pair; noise between poor pairs does not."""
    e = np.eye(6)
    # truth 0 resembles model 1 faintly (MAC 0.3 > its rank's 0.1): not enough to move it
    truth = np.column_stack([np.sqrt(0.1) * e[0] + np.sqrt(0.3) * e[1] + np.sqrt(0.6) * e[5],
                             e[4]])  # truth 1 resembles no model mode
    cols, mac = pair_by_mac(truth, e[:, :3])
    assert np.array_equal(cols, [0, 1])
    np.testing.assert_allclose(mac, [0.1, 0.0], atol=50 * EPS)
    # at MAC 0.9 with model 1, truth 0 takes it and truth 1 another
    truth[:, 0] = np.sqrt(0.1) * e[0] + np.sqrt(0.9) * e[1]
    cols, mac = pair_by_mac(truth, e[:, :3])
    assert cols[0] == 1 and cols[1] != 1 and mac[0] == pytest.approx(0.9, abs=50 * EPS)


def test_a_chain_pairs_with_itself_by_rank_and_exchanged_shapes_are_caught(tapered):
    model = _chain(tapered, "xy")
    target = self_target(model, shapes=True)
    d = _design(model, target, 3)
    w, mac, moved = pair_modes(d, model, target.mode_shapes)
    # the chain's own modes: its per-axis blocks against its whole pencil (two eigensolves)
    np.testing.assert_allclose(w, d.sel.omega_truth_rad_s, rtol=1e-9)
    np.testing.assert_allclose(mac, 1.0, rtol=0.0, atol=1e-9)
    assert not moved.any()
    # the truth's first two torsion shapes exchanged: each is paired with the other's mode
    tors = np.flatnonzero(d.sel.axis == "x")[:2]
    twist = target.mode_shapes.twist.copy()
    twist[d.sel.index[tors]] = twist[d.sel.index[tors[::-1]]]
    shapes = ModeShapes(target.mode_shapes.stations_m, target.mode_shapes.deflection, twist)
    w2, mac2, moved2 = pair_modes(d, model, shapes)
    # the same per-axis eigensolve on the same model, permuted
    np.testing.assert_array_equal(w2[tors], w[tors[::-1]])
    assert np.array_equal(np.flatnonzero(moved2), tors)
    notes = pairing_notes(d.sel, w2, moved2, mac2)
    assert len(notes) == 1 and f"truth mode {d.sel.index[tors[0]] + 1} (torsion" in notes[0]


def test_a_fit_reports_its_pairs_by_shape(tapered):
    model = _chain(tapered, "xy")
    target = self_target(model, shapes=True)
    r = fit(tapered, target, 3, axes="xy", stiffness="joint", starts=2, progress=False)
    matched = [m for m in r.modes if m["omega_model_rad_s"] is not None]
    assert len(matched) == 6 and all(0.0 < m["mac"] <= 1.0 + 1e-12 for m in matched)
    d = _design(model, target, 3)
    rebuilt = build_model(tapered, r.lengths_m, r.stiffness_Nm_per_rad, axes="xy")
    w, mac, moved = pair_modes(d, rebuilt, target.mode_shapes)
    # the record is the pairing of the fitted chain (same design, rebuilt: one rounding)
    np.testing.assert_allclose([m["mac"] for m in matched], mac, rtol=1e-9)
    np.testing.assert_allclose([m["omega_model_rad_s"] for m in matched], w, rtol=1e-9)


def test_bad_shapes_are_refused_by_name():
    with pytest.raises(BeamInputError, match=r"mode_shapes.twist: must be finite"):
        ModeShapes(np.arange(3.0), np.zeros((2, 3)), np.full((2, 3), np.nan))
    with pytest.raises(BeamInputError, match=r"mode_shapes.deflection: must be finite, one row"):
        ModeShapes(np.arange(3.0), np.zeros((2, 4)), np.zeros((2, 3)))


def test_a_plate_target_carries_shapes_and_the_1d_beam_none(narrow, truth_of):
    plate = target_from_truth(truth_of(narrow, model="plate", mesh_level=1, modes=2,
                                       static=False), narrow.tip_force_N)
    assert plate.mode_shapes.deflection.shape[0] == plate.all_omega_rad_s.size
    beam = target_from_truth(truth_of(narrow, model="beam", modes=2), narrow.tip_force_N)
    assert beam.mode_shapes is None
