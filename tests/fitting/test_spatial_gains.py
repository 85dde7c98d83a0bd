"""The spatial fit's modal-gain term: amplitudes at the tip points, against a chain taken as its
own truth (its modes from one eigensolve of the whole pencil, read through the point Jacobians)
and the plate truth's own amplitudes."""

import subprocess
import sys

import numpy as np
import pytest
from chain_truth import self_target

from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.errors import BeamInputError
from prbdm_pin.fitting.multistart import fit
from prbdm_pin.fitting.spatial_gains import with_point_gains
from prbdm_pin.fitting.target import FitTarget, target_from_truth
from prbdm_pin.model.prbdm_model import build_model


def _self_target(beam, lengths, scale):
    k = spatial_stiffness(beam, lengths, "xy") * scale
    return self_target(build_model(beam, lengths, k, axes="xy"), gains=True)


def test_a_chain_taken_as_its_own_truth_is_matched_in_amplitude_too(tapered):
    lengths = np.array([0.3, 0.45, 0.25]) * tapered.length_m
    target = _self_target(tapered, lengths, np.exp([0.2, -0.3, 0.1, 0.25]))
    r = fit(tapered, target, 2, axes="xy", stiffness="joint", starts=4, progress=False,
            gain_points=("tip_corner_left", "tip"), gain_modes=2)
    # an exact design exists (the target's own): the solver's tolerance on relative residuals
    assert r.worst_mode_error_pct < 1e-4
    assert len(r.gains) == 4 * 2
    assert max(abs(g["error_pct"]) for g in r.gains) < 1e-4
    # a torsion mode does not move the tip centre (an antisymmetric shape): its amplitude there
    # is the rounding of a sum over the chain's coordinates
    tips = [g for g in r.gains if g["kind"] == "torsion" and g["point"] == "tip"]
    assert all(abs(g["model_per_sqrt_kg"]) < 1e-9 for g in tips)


def test_the_first_modes_of_the_plate_are_matched_at_the_corner(narrow, truth_of):
    truth = truth_of(narrow, model="plate", mesh_level=1, modes=2, static=False)
    target = with_point_gains(target_from_truth(truth, narrow.tip_force_N), truth, narrow)
    r = fit(narrow, target, 2, axes="xy", stiffness="joint", starts=6, progress=False,
            gain_points=("tip_corner_left",), gain_modes=1)
    first = list(r.gains)
    assert [g["kind"] for g in first] == ["bending", "torsion"]
    # 2 lengths and 4 springs against 4 frequencies and 2 amplitudes: an exact match (the
    # solver's tolerance)
    assert r.worst_mode_error_pct < 1e-3
    assert max(abs(g["error_pct"]) for g in first) < 1e-3
    # the truth side is the plate's own amplitude at the corner (the same number, carried)
    corner = dict(target.point_gains)["tip_corner_left"]
    for g in first:
        k = int(np.argmin(np.abs(target.all_omega_rad_s - g["omega_truth_rad_s"])))
        assert abs(g["truth_per_sqrt_kg"]) == abs(corner[k])


def test_gains_need_a_target_with_them_and_a_truth_with_width(narrow, truth_of):
    w = np.array([10.0, 30.0, 60.0, 90.0])
    target = FitTarget(w[:1], np.zeros(3), all_omega_rad_s=w,
                       all_labels=("bending", "torsion", "bending", "torsion"))
    with pytest.raises(BeamInputError, match="gain_points = .*no truth amplitude"):
        fit(narrow, target, 2, axes="xy", stiffness="joint", progress=False,
            gain_points=("tip_corner_left",))
    beam_truth = truth_of(narrow, model="beam", modes=2)
    # the 1D beam has a tip (a planar fit's gain point) but no corners
    with pytest.raises(BeamInputError, match="no tip corners"):
        with_point_gains(target_from_truth(beam_truth, narrow.tip_force_N), beam_truth, narrow,
                         ("tip", "tip_corner_left"))


def test_the_command_line_refuses_gains_without_a_plate_truth(tmp_path):
    from paths import BEAMS

    p = subprocess.run([sys.executable, "-m", "prbdm_pin", "fit",
                        str(BEAMS / "uniform-narrow.json"), "--joints", "2", "--axes", "xy",
                        "--truth-model", "beam", "--gain-points", "tip_corner_left",
                        "--out", str(tmp_path / "o")], capture_output=True, text=True,
                       timeout=120)
    assert p.returncode == 2 and "Traceback" not in p.stderr
    assert len(p.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "o").exists()
