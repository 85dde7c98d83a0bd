"""The spatial fit: lengths and the springs of every axis, matched to truth modes by kind.

References: a spatial chain taken as its own truth, its modes from one eigensolve of the whole
(M, K) pencil and labelled by where their kinetic energy sits (another algorithm than the fit's
per-axis blocks), which the fit must recover; the plate truth's labelled modes; the errors the
options and the command line must give.
"""

import json
import subprocess
import sys

import numpy as np
import pytest
from chain_truth import LABELS, self_target
from tolerances import EPS

from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.fit_file import load_fit, save_fit
from prbdm_pin.fitting.multistart import fit
from prbdm_pin.fitting.target import FitTarget, target_from_truth
from prbdm_pin.model.prbdm_model import build_model
from prbdm_pin.options.objects import FitOptions, ParetoOptions


def _self_target(beam, lengths, axes, scale):
    k = spatial_stiffness(beam, lengths, axes) * scale
    model = build_model(beam, lengths, k, axes=axes)
    return model, self_target(model)


def test_the_axes_do_not_couple_at_the_straight_pose(tapered):
    # the fit pairs modes by kind through the per-axis blocks of M(0): every product of
    # inertia that would couple them vanishes for a planform symmetric about x; the blocks
    # are sums of a few link terms, so their coupling is zero to the rounding of M's entries
    lengths = np.array([0.2, 0.3, 0.3, 0.2]) * tapered.length_m
    model = build_model(tapered, lengths, spatial_stiffness(tapered, lengths, "xyz"),
                        axes="xyz")
    M = model.mass_matrix()
    for a in "yzx":
        for b in "yzx":
            if a != b:
                block = M[np.ix_(model.axis_index(a), model.axis_index(b))]
                assert np.abs(block).max() <= 50 * EPS * np.abs(M).max()


@pytest.mark.parametrize("axes", ["xy", "yz", "xyz"])
def test_a_spatial_chain_taken_as_its_own_truth_is_matched(tapered, axes):
    lengths = np.array([0.25, 0.35, 0.25, 0.15]) * tapered.length_m
    rng = np.random.default_rng(3)
    scale = np.exp(rng.uniform(-0.4, 0.4, 3 * len(axes)))
    _, target = _self_target(tapered, lengths, axes, scale)
    r = fit(tapered, target, 3, axes=axes, stiffness="joint", starts=4, progress=False)
    assert r.axes == axes and r.stiffness_Nm_per_rad.size == 3 * len(axes)
    # an exact match exists (the target's own design): the solver's tolerance on the
    # relative residuals (least_squares' default ftol 1e-8) bounds the error
    assert r.worst_mode_error_pct < 1e-4
    kinds = [m["kind"] for m in r.modes]
    for a in axes:
        assert kinds.count(LABELS[a]) == 3
    truth = np.array([m["omega_truth_rad_s"] for m in r.modes])
    assert np.all(np.diff(truth) >= 0)
    rebuilt = build_model(tapered, r.lengths_m, r.stiffness_Nm_per_rad, axes=axes)
    w = np.sort(rebuilt.natural_frequencies())
    # the recorded model frequencies are the rebuilt model's (whole pencil, another solve);
    # the spread of the spectrum sets the eigensolver's relative accuracy
    model_w = np.sort([m["omega_model_rad_s"] for m in r.modes])
    assert np.allclose(model_w, w[: model_w.size], rtol=1e-9)


def test_fit_json_keeps_the_axes_and_the_modes(tapered, tmp_path):
    lengths = np.array([0.3, 0.4, 0.3]) * tapered.length_m
    _, target = _self_target(tapered, lengths, "xy", np.ones(4))
    r = fit(tapered, target, 2, axes="xy", stiffness="joint", starts=2, progress=False)
    path = save_fit(r, tmp_path / "fit.json", tapered)
    d = json.loads(path.read_text())
    assert d["axes"] == "xy" and d["options"]["axes"] == "xy"
    for rec in d["modes"]:
        assert set(rec) == {"kind", "omega_truth_rad_s", "omega_model_rad_s", "error_pct"}
    back = load_fit(path)
    assert back.axes == "xy" and back.modes == r.modes
    assert np.array_equal(back.stiffness_Nm_per_rad, r.stiffness_Nm_per_rad)


def test_a_chordwise_mode_in_the_band_is_named_not_matched(tapered):
    lengths = np.array([0.3, 0.4, 0.3]) * tapered.length_m
    _, t = _self_target(tapered, lengths, "xy", np.ones(4))
    # a chordwise mode between the chain's modes: no axis represents it
    w_mid = 0.5 * (t.all_omega_rad_s[0] + t.all_omega_rad_s[1])
    w = np.r_[t.all_omega_rad_s[0], w_mid, t.all_omega_rad_s[1:]]
    labels = (t.all_labels[0], "chordwise", *t.all_labels[1:])
    target = FitTarget(w[:1], np.zeros(3), all_omega_rad_s=w, all_labels=labels)
    r = fit(tapered, target, 2, axes="xy", stiffness="joint", starts=2, progress=False)
    chord = [m for m in r.modes if m["kind"] == "chordwise"]
    assert len(chord) == 1 and chord[0]["omega_model_rad_s"] is None
    assert chord[0]["error_pct"] is None
    assert any("chordwise" in note for note in r.warnings)
    assert r.worst_mode_error_pct < 1e-4  # the chordwise mode took no chain mode


def test_the_plate_truths_torsion_modes_are_matched(narrow, truth_of):
    truth = truth_of(narrow, model="plate", mesh_level=1, modes=2, static=False)
    target = target_from_truth(truth, narrow.tip_force_N)
    r = fit(narrow, target, 2, axes="xy", stiffness="joint", starts=4, progress=False)
    matched = [m for m in r.modes if m["omega_model_rad_s"] is not None]
    assert [m["kind"] for m in matched].count("torsion") == 2
    # two bending and two torsion frequencies against a 2-joint chain's 3 n unknowns: an
    # exact match (the solver's tolerance, as above)
    assert max(abs(m["error_pct"]) for m in matched) < 1e-4
    bend = [m["omega_truth_rad_s"] for m in matched if m["kind"] == "bending"]
    assert np.allclose(bend, truth.omega_rad_s[:2])


def test_a_planar_fit_records_its_modes(narrow, truth_of):
    truth = truth_of(narrow, model="beam", modes=2)
    r = fit(narrow, target_from_truth(truth, narrow.tip_force_N), 2, stiffness="joint",
            starts=2, progress=False)
    assert r.axes == "y" and [m["kind"] for m in r.modes] == ["bending", "bending"]
    for m, w, e in zip(r.modes, r.omega_export_rad_s, r.omega_export_errors_pct, strict=True):
        # the same two roundings on both sides (a ratio, less one, in %): 100 EPS each
        assert m["omega_model_rad_s"] == w and m["error_pct"] == pytest.approx(e, abs=400 * EPS)


def test_a_truth_without_torsion_modes_is_refused(narrow):
    w = np.array([10.0, 60.0, 170.0])
    target = FitTarget(w, np.zeros(3), all_omega_rad_s=w, all_labels=("bending",) * 3,
                       source="beam")
    with pytest.raises(BeamInputError, match=r"axes = 'xy'.*0 torsion mode"):
        fit(narrow, target, 2, axes="xy", stiffness="joint", progress=False)
    with pytest.raises(BeamInputError, match="all_omega_rad_s|every truth mode"):
        fit(narrow, FitTarget(w, np.zeros(3)), 2, axes="xy", stiffness="joint",
            progress=False)
    with pytest.raises(BeamInputError, match="frequencies = 3"):
        fit(narrow, target, 2, axes="yz", stiffness="joint", frequencies=3, progress=False)


@pytest.mark.parametrize("change, field", [
    ({"squared": True}, "squared"),
    ({"joint_sweep": True}, "joint_sweep"), ({"axes": "xz"}, "axes"),
])
def test_options_a_spatial_fit_does_not_have_are_refused(change, field):
    kw = {"axes": "xy", "stiffness": "joint", **change}
    with pytest.raises(BeamInputError, match=f"^{field} = "):
        FitOptions(**kw)


def test_a_spatial_pareto_front_takes_no_squared_frequencies():
    with pytest.raises(BeamInputError, match="squared = True"):
        ParetoOptions(axes="xyz", stiffness="joint", squared=True)


@pytest.mark.parametrize("args, text", [
    (["--axes", "xz"], "--axes: invalid choice"),
    (["--axes", "xy", "--objective", "combined"], "--truth-model plate or solid"),
])
def test_the_command_line_refuses_bad_axes_in_one_line(narrow, tmp_path, args, text):
    from paths import BEAMS

    p = subprocess.run([sys.executable, "-m", "prbdm_pin", "fit",
                        str(BEAMS / "uniform-narrow.json"), "--joints", "2", "--truth-model",
                        "beam", "--out", str(tmp_path / "o"), *args],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 2
    assert text in p.stderr and "Traceback" not in p.stderr
    assert not (tmp_path / "o").exists()


def test_a_paper_style_spatial_fit_has_one_factor_per_axis(tapered, tmp_path):
    # a chain whose springs are Eq. 14's closed form times one factor per axis: the paper
    # parametrisation can represent it exactly, so the fit recovers its frequencies
    from prbdm_pin.chain.sections import link_sections
    from prbdm_pin.chain.spatial_stiffness import paper_axis_unit_stiffness

    lengths = np.array([0.3, 0.4, 0.3]) * tapered.length_m
    mass = link_sections(tapered, lengths).mass_kg
    k = np.stack([f * paper_axis_unit_stiffness(tapered, lengths, mass, a)
                  for a, f in (("y", 1.7), ("x", 0.6))], axis=1).reshape(-1)
    target = self_target(build_model(tapered, lengths, k, axes="xy"))
    r = fit(tapered, target, 2, axes="xy", stiffness="paper", starts=4, progress=False)
    assert r.stiffness == "paper" and r.factors.size == 2
    # an exact match exists (the solver's tolerance on the relative residuals)
    assert r.worst_mode_error_pct < 1e-4
    assert np.allclose(np.sort(r.factors), [0.6, 1.7], rtol=1e-5)
    back = load_fit(save_fit(r, tmp_path / "fit.json", tapered))
    assert np.array_equal(back.factors, r.factors)


@pytest.mark.parametrize("command", [
    ["pareto", "--axes", "xy"],  # a front needs the 3D tip truth: not from the 1D beam
    ["batch", "--beams", "2", "--axes", "xy", "--objective", "combined"],
])
def test_what_a_spatial_command_does_not_do_is_refused_before_any_work(tmp_path, command):
    from paths import BEAMS

    beam = [] if command[0] == "batch" else [str(BEAMS / "uniform-narrow.json")]
    p = subprocess.run([sys.executable, "-m", "prbdm_pin", command[0], *beam, "--joints", "2",
                        "--truth-model", "beam", *command[1:], "--out", str(tmp_path / "o")],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert "axes" in p.stderr and len(p.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()
