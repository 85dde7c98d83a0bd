"""Figures a report can use: drawn into given axes (their figure returned), units and legends on
every axes, one Bode axes pair per input/output pair, PDF and SVG by the suffix.

The Bode magnitudes are compared with the plant's response computed by another algorithm: the
eigendecomposition A = V diag(lambda) V^-1, H(j w) = C V diag(1 / (j w - lambda)) V^-1 B + D
(the package solves (j w I - A) X = B at each frequency).
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.views.bode import plot_bode
from prbdm_pin.views.plots import new_figure, plot_pareto, plot_planform, plot_scf

LENGTHS = np.array([0.25, 0.2, 0.15])


@pytest.fixture(scope="module")
def model(tapered):
    lengths = LENGTHS * tapered.length_m / LENGTHS.sum()
    return pp.build_model(tapered, lengths, pp.finite_segment_stiffness(tapered, lengths))


def _labelled(ax) -> None:
    """Every axes names its quantities with units (a parenthesis) and has a legend."""
    assert "(" in ax.get_xlabel() and "(" in ax.get_ylabel(), (ax.get_xlabel(),
                                                               ax.get_ylabel())
    assert ax.get_legend() is not None


def test_planform_scf_and_pareto_draw_into_the_given_axes(tapered, model):
    fig = new_figure((12, 4))
    axes = fig.subplots(1, 3)
    assert plot_planform(tapered, model.lengths_m, ax=axes[0]) is fig
    scf = SimpleNamespace(poses_rad=np.array([[0.0], [0.1], [0.2]]),
                          factors=np.array([1.0, 1.01, 1.03]), scf_mean=1.013,
                          export_pose_rad=np.array([0.1]),
                          scf_deviation_pct=np.array([-1.3, -0.3, 1.7]), joints=3)
    assert plot_scf(scf, ax=axes[1]) is fig
    front = SimpleNamespace(F_pct=np.array([[0.1, 2.0], [0.5, 1.0], [2.0, 0.2]]), joints=3,
                            knee_index=1, deflection_norm="linf")
    assert plot_pareto(front, ax=axes[2]) is fig
    for ax in axes:
        assert ax.lines or ax.collections
        _labelled(ax)


@pytest.mark.parametrize("suffix, head", [(".pdf", b"%PDF"), (".svg", b"<?xml")])
def test_figures_are_written_as_pdf_and_svg_by_the_suffix(tapered, model, tmp_path, suffix,
                                                          head):
    path = tmp_path / f"planform{suffix}"
    plot_planform(tapered, model.lengths_m, path)
    assert path.read_bytes().startswith(head)


def test_another_suffix_is_refused_by_name_before_anything_is_written(tapered, model,
                                                                       tmp_path):
    with pytest.raises(pp.BeamInputError, match="planform.jpg"):
        plot_planform(tapered, model.lengths_m, tmp_path / "planform.jpg")
    assert list(tmp_path.iterdir()) == []


def _eig_response(lin, w: np.ndarray) -> np.ndarray:
    lam, V = np.linalg.eig(lin.A)
    left = lin.C @ V
    right = np.linalg.solve(V, lin.B)
    return np.array([left @ np.diag(1.0 / (1j * wi - lam)) @ right + lin.D for wi in w])


def test_the_bode_figure_has_one_axes_pair_per_pair_with_its_units(model):
    lin = pp.linearize(model, inputs=("tip_force_z", "joint_torque[0]"),
                       outputs=("tip_z", "q[1]"))
    fig = plot_bode(lin)
    axes = fig.axes
    assert len(axes) == 2 * 4  # 2 inputs x 2 outputs, a magnitude and a phase each
    mags = axes[0::2]
    units = {("tip_force_z", "tip_z"): "(m/N)", ("tip_force_z", "q[1]"): "(rad/N)",
             ("joint_torque[0]", "tip_z"): "(m/(N m))", ("joint_torque[0]", "q[1]"): "(rad/(N m))"}
    seen = set()
    ref_w = None
    for mag, ph in zip(mags, axes[1::2], strict=True):
        pair = next(p for p in units if mag.get_title().startswith(f"{p[0]} (")
                    and f"-> {p[1]} (" in mag.get_title())
        seen.add(pair)
        assert mag.get_ylabel() == f"|H| {units[pair]}"
        assert ph.get_ylabel() == "phase (deg)" and ph.get_xlabel() == "omega (rad/s)"
        assert mag.get_legend() is not None and ph.get_legend() is not None
        w, h = (np.asarray(a, dtype=float) for a in mag.lines[0].get_data())
        ref_w = w
        i, j = lin.output_names.index(pair[1]), lin.input_names.index(pair[0])
        ref = np.abs(_eig_response(lin, w)[:, i, j])
        # eig's response is off by about cond(V) EPS relative (V: the damped modes'
        # eigenvectors, cond 852 here) times the few terms each entry sums; measured
        # 3.5e-13 (1560 EPS), bound 1e4 EPS
        np.testing.assert_allclose(h, ref, rtol=1e4 * EPS)
    assert seen == set(units)
    assert ref_w[0] < ref_w[-1]
    # the title counts the states (2 nv) and the coordinates (nv)
    assert f"{lin.A.shape[0]} states ({len(lin.q_eq)} coordinates" in fig._suptitle.get_text()


def test_the_bode_figure_draws_into_given_axes(model):
    lin = pp.linearize(model)
    fig = new_figure((4, 4))
    axes = fig.subplots(2, 1)
    assert plot_bode(lin, axes=axes) is fig
    assert axes[0].get_ylabel() == "|H| (m/N)"


def test_the_response_draws_into_given_axes_with_a_labelled_line_per_joint(model, tmp_path):
    from prbdm_pin.simulation.trajectory import Trajectory
    from prbdm_pin.views.response_plot import plot_response

    t = np.linspace(0.0, 0.1, 20)
    q = np.outer(np.sin(40 * t), [0.01, 0.02])
    tip = np.array([model.tip_position(row) for row in q])
    tr = Trajectory(t, q, np.zeros_like(q), tip, 20, "by hand", 0.0)
    fig = new_figure((6, 5))
    axes = fig.subplots(2, 1)
    assert plot_response(model, tr, [0, 0, -1], 0.02, tmp_path / "r.svg", axes=axes) is fig
    for ax in axes:
        assert ax.get_legend() is not None and "(" in ax.get_ylabel()
    assert [line.get_label() for line in axes[1].lines] == ["joint 1", "joint 2"]
    assert axes[1].get_xlabel() == "t (s)"
    # the tip's z line: its drawn data are the tip z from the straight pose in mm
    z = axes[0].lines[0].get_ydata()
    np.testing.assert_array_equal(z, (tip[:, 2] - model.tip_position()[2]) * 1e3)
    assert (tmp_path / "r.svg").read_bytes().startswith(b"<?xml")


def _pair(inp: str, out: str, w: np.ndarray):
    h = 1.0 / (100.0 ** 2 - w ** 2 + 2j * 0.02 * 100.0 * w)
    return SimpleNamespace(input_name=inp, output_name=out, omega_rad_s=w, frf_truth=h,
                           frf_prbdm=1.01 * h, frf_error_pct=1.0)


def test_the_plant_comparisons_draw_into_given_axes_with_units():
    from prbdm_pin.plant.comparison_plot import plot_plant_comparison
    from prbdm_pin.plant.truth_comparison_plot import plot_truth_comparison

    w = np.linspace(10.0, 300.0, 50)
    cmp = SimpleNamespace(pairs=[_pair("tip_force_z", "tip_z", w),
                                 _pair("hub_torque", "hub_angle", w)],
                          truth_omega_rad_s=np.array([100.0]), band_rad_s=(10.0, 300.0),
                          modes=[])
    fig = new_figure((8, 5))
    axes = fig.subplots(2, 2)
    assert plot_plant_comparison(cmp, axes=axes) is fig
    assert axes[0, 0].get_ylabel() == "|H| (m/N)"
    assert axes[0, 1].get_ylabel() == "|H| (rad/(N m))"
    for ax in axes.ravel():
        assert ax.get_legend() is not None and "(" in ax.get_ylabel()
    t = np.linspace(0.0, 0.1, 20)
    acc = SimpleNamespace(t_s=t, step_truth_m_per_N=t, step_model_m_per_N=t, omega_band_rad_s=w,
                          frf_truth_m_per_N=cmp.pairs[0].frf_truth,
                          frf_model_m_per_N=cmp.pairs[0].frf_prbdm, step_error=0.01,
                          frf_error=0.01)
    tc = SimpleNamespace(accuracy=acc, truth_model="plate",
                         prbdm=SimpleNamespace(omega_rad_s=np.ones(3)), damping_ratio=0.02)
    fig2 = new_figure((5, 8))
    axes2 = fig2.subplots(3, 1)
    assert plot_truth_comparison(tc, axes=axes2) is fig2
    for ax in axes2:
        _labelled(ax)


def test_the_sensitivity_bars_draw_into_a_given_axes():
    from prbdm_pin.commands.sensitivity import plot_sensitivity

    g = SimpleNamespace(relative_d_omega=np.array([[0.5, -0.5], [0.4, -0.6]]),
                        omega_rad_s=np.array([10.0, 60.0]), names=("thickness", "rho"),
                        model="beam")
    fig = new_figure((5, 3))
    ax = fig.subplots()
    assert plot_sensitivity(g, title="strip", ax=ax) is fig
    assert len(ax.patches) == 4  # 2 modes x 2 variables
    _labelled(ax)
