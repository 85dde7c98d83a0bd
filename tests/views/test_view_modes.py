"""The mode-shape figure and the model's VTU against an independent computation of the modes.

The reference (tests/chain_modes_reference.py) solves the pencil of Pinocchio's CRBA and the
springs with scipy.linalg.eigh and moves the chain's points by hand; the package goes through
its own eigensolver and Pinocchio's frame Jacobians.
"""

from __future__ import annotations

import meshio
import numpy as np
import pytest
from chain_modes_reference import reference_modes, same_up_to_sign
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.views.modes import TruthShapes, plot_mode_shapes
from prbdm_pin.views.plots import new_figure
from prbdm_pin.views.vtu_model import write_model_modes_vtu

LENGTHS = np.array([0.25, 0.2, 0.15])
# two eigensolvers' unit-normalised mode shapes differ by about EPS lambda_max / (nearest
# gap of lambda = omega^2): 1.03 on the planar chain, 7.5 on the xy chain and 104 on the xyz
# chain (its in-plane and torsion modes are close); times a few for the Jacobian products and
# the normalisation (measured: 1.2, 1.2 and 80 EPS)
SHAPE_TOL = 1000 * EPS


@pytest.fixture(scope="module", params=["y", "xy", "xyz"])
def chain(request, tapered):
    lengths = LENGTHS * tapered.length_m / LENGTHS.sum()
    if request.param == "y":
        k = pp.finite_segment_stiffness(tapered, lengths)
    else:
        k = pp.spatial_stiffness(tapered, lengths, request.param)
    return pp.build_model(tapered, lengths, k, axes=request.param)


def _unit(y):
    return y / np.max(np.abs(y))


def test_the_drawn_model_curves_are_the_modes_computed_independently(chain):
    omega, x, disp, twist = reference_modes(chain)
    n = omega.size
    fig = plot_mode_shapes(chain)
    axes = fig.axes
    assert len(axes) == min(n, 6)
    for k, ax in enumerate(axes):
        line = ax.lines[0]
        assert line.get_label().endswith("R PRBDM")
        xd, yd = (np.asarray(a, dtype=float) for a in line.get_data())
        assert np.array_equal(xd, x)  # the stations: sums of the link lengths, exact
        # a torsion panel draws the twist, an in-plane one the y displacement, a bending one
        # the deflection w (which panel is which kind: the next test)
        label = ax.get_ylabel()
        ref = _unit(twist[k] if "twist" in label else
                    disp[k, :, 1] if "in-plane" in label else disp[k, :, 2])
        np.testing.assert_allclose(yd, same_up_to_sign(yd, ref), rtol=0, atol=SHAPE_TOL)
        # the frequency in the title, Hz
        assert f"{omega[k] / (2 * np.pi):.4g} Hz" in ax.get_title()
        assert ax.get_xlabel() == "x along the span (m)"
        assert "(-)" in ax.get_ylabel()


def test_a_torsion_mode_is_drawn_as_twist_and_a_bending_mode_as_deflection(tapered):
    lengths = LENGTHS * tapered.length_m / LENGTHS.sum()
    model = pp.build_model(tapered, lengths, pp.spatial_stiffness(tapered, lengths, "xy"),
                           axes="xy")
    _, _, disp, twist = reference_modes(model)
    fig = plot_mode_shapes(model)
    for k, ax in enumerate(fig.axes):
        # a mode of the xy chain either bends (w, no twist) or twists (no w): the two blocks
        # of the straight chain's mass matrix do not couple (the links' COM on the axis)
        torsion = np.max(np.abs(twist[k])) > np.max(np.abs(disp[k, :, 2])) / model.lengths_m.sum()
        assert ("twist" in ax.get_ylabel()) == torsion, ax.get_title()
        assert ("torsion" in ax.get_title()) == torsion


def test_the_truth_is_drawn_on_the_same_scale_with_its_error_in_the_title(tapered):
    lengths = LENGTHS * tapered.length_m / LENGTHS.sum()
    model = pp.build_model(tapered, lengths, pp.finite_segment_stiffness(tapered, lengths))
    omega, x, disp, _ = reference_modes(model)
    # a "truth": the chain's own first two shapes sampled finer, with the sign flipped on
    # mode 2 and a scale of 7, and frequencies 2 % above
    xs = np.linspace(0.0, x[-1], 30)
    defl = np.array([-7.0 * (1 - 2 * (k == 1)) * np.interp(xs, x, disp[k, :, 2])
                     for k in range(2)])
    truth = TruthShapes(omega[:2] * 1.02, xs, defl)
    fig = plot_mode_shapes(model, 2, truth)
    for ax in fig.axes:
        model_line, truth_line = ax.lines[0], ax.lines[1]
        assert truth_line.get_label() == "truth"
        yt = np.asarray(truth_line.get_ydata(), dtype=float)
        ym = np.interp(xs, *model_line.get_data())
        # scaled to a unit largest magnitude and signed as the chain's: on the chain's curve
        np.testing.assert_allclose(yt, ym, rtol=0, atol=SHAPE_TOL)
        err = 100.0 * (1 / 1.02 - 1)
        assert f"error {err:+.2f} %" in ax.get_title()


def test_axes_given_are_drawn_into_and_their_figure_returned(chain):
    fig = new_figure((8, 3))
    axes = fig.subplots(1, 2)
    out = plot_mode_shapes(chain, 2, axes=axes)
    assert out is fig
    assert all(len(ax.lines) >= 1 for ax in axes)


def test_the_vtu_holds_the_modes_displacement_vectors_and_twists(chain, tmp_path):
    omega, x, disp, twist = reference_modes(chain)
    path = write_model_modes_vtu(chain, tmp_path / "model.vtu")
    mesh = meshio.read(path)
    assert np.array_equal(mesh.points, np.column_stack([x, 0 * x, 0 * x]))
    lines = mesh.cells_dict["line"]
    assert lines.tolist() == [[i, i + 1] for i in range(x.size - 1)]
    for k in range(omega.size):
        u = mesh.point_data[f"displacement_mode_{k + 1}"]
        t = mesh.point_data[f"twist_mode_{k + 1}"]
        # one sign for both fields of a mode
        sign = 1.0 if np.sum(u * disp[k]) + np.sum(t * twist[k]) >= 0 else -1.0
        # mass-normalised entries: at most ~1/sqrt(smallest link mass) m per unit; the bound
        # is SHAPE_TOL relative to the largest entry
        scale = max(np.max(np.abs(disp[k])), np.max(np.abs(twist[k])))
        np.testing.assert_allclose(u, sign * disp[k], rtol=0, atol=SHAPE_TOL * scale)
        np.testing.assert_allclose(t, sign * twist[k], rtol=0, atol=SHAPE_TOL * scale)


def test_bad_input_is_refused_by_name(chain, tmp_path):
    with pytest.raises(pp.BeamInputError, match="path"):
        write_model_modes_vtu(chain, tmp_path / "model.txt")
    with pytest.raises(pp.BeamInputError, match="n_modes = 0"):
        plot_mode_shapes(chain, 0)
    with pytest.raises(pp.InputTypeError, match="model"):
        plot_mode_shapes("chain")
    with pytest.raises(pp.BeamInputError, match="path"):
        plot_mode_shapes(chain, 1, path=tmp_path / "f.jpg")
    assert list(tmp_path.iterdir()) == []


def test_the_vtu_series_holds_each_frames_displacement_and_twist(tapered, tmp_path):
    import xml.etree.ElementTree as ET

    from prbdm_pin.simulation.trajectory import Trajectory
    from prbdm_pin.views.vtu_model import write_trajectory_vtu

    lengths = LENGTHS * tapered.length_m / LENGTHS.sum()
    model = pp.build_model(tapered, lengths, pp.spatial_stiffness(tapered, lengths, "xy"),
                           axes="xy")
    # coordinates node-major (y, x) per node: frame 0 bends only, frame 1 twists only
    bend = np.array([0.1, 0.0, 0.2, 0.0])
    twist = np.array([0.0, 0.3, 0.0, -0.1])
    q = np.array([bend, twist])
    tr = Trajectory(np.array([0.0, 0.5]), q, np.zeros_like(q), np.zeros((2, 3)), 2, "by hand",
                    0.0)
    pvd = write_trajectory_vtu(model, tr, tmp_path, frames=2)
    files = [d.get("file") for d in ET.parse(pvd).getroot().iter("DataSet")]
    f0, f1 = (meshio.read(tmp_path / f) for f in files)
    x = np.r_[0.0, np.cumsum(lengths)]  # root, nodes, tip
    # bending by hand: phi_i = th_1 + ... + th_i; the point after link i moves by
    # l_i (cos phi_i - 1, 0, -sin phi_i) on top of the earlier links' motion
    phi = np.cumsum(bend[0::2])
    step = np.zeros((x.size, 3))
    step[2:, 0] = np.cumsum(lengths[1:] * (np.cos(phi) - 1.0))
    step[2:, 2] = np.cumsum(-lengths[1:] * np.sin(phi))
    # forward kinematics through Pinocchio's products against sums of sines: a few EPS of
    # the span
    np.testing.assert_allclose(f0.point_data["displacement"], step, rtol=0,
                               atol=10 * EPS * x[-1])
    np.testing.assert_allclose(f0.point_data["twist"], 0.0, rtol=0, atol=10 * EPS)
    # twisting moves no point of the axis; each link's twist is the sum of the node twists
    # before it (rotations about one axis add)
    np.testing.assert_allclose(f1.point_data["displacement"], 0.0, rtol=0,
                               atol=10 * EPS * x[-1])
    np.testing.assert_allclose(f1.point_data["twist"],
                               np.r_[0.0, np.cumsum(twist[1::2]), twist[1::2].sum()],
                               rtol=0, atol=10 * EPS)
