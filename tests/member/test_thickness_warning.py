"""The Kirchhoff-range warning: a plate truth of a beam too thick for plate theory says so and
points to the 3D solid; the estimate it quotes is checked against the 3D solid truth."""

from __future__ import annotations

import json

import numpy as np
import pytest
from paths import BEAMS

from prbdm_pin.cli import main
from prbdm_pin.files.beam_file import load_beam, save_beam
from prbdm_pin.member.geometry import Beam
from prbdm_pin.truth import compute_truth


def test_thick_beam_warns_in_the_plate_truth_and_the_cli(tmp_path, capsys):
    beam = Beam([0.0, 0.6], [0.05, 0.02], 0.7)  # 0.7 m thick, 0.6 m long, 40 mm at the tip
    notes = beam.kirchhoff_warnings(3)
    assert len(notes) == 2
    assert "1.17 L" in notes[0] and "far more than 10 %" in notes[0]
    assert "narrowest width 0.04 m" in notes[1]
    assert all("--model solid" in n for n in notes)
    path = tmp_path / "thick.json"
    save_beam(beam, path)
    rc = main(["truth", str(path), "--modes", "2", "--no-static", "--out", str(tmp_path / "t"),
               "-q"])
    assert rc == 0
    stored = json.loads((tmp_path / "t" / "truth.json").read_text())["warnings"]
    assert any("past Kirchhoff plate theory" in w and "--model solid" in w for w in stored)
    # the 1D beam truth is no plate: no such warning there
    beam_truth = compute_truth(beam, model="beam", modes=2, static=False)
    assert not any("Kirchhoff" in w for w in beam_truth.warnings)


@pytest.mark.parametrize("name", ["uniform-narrow", "reference-random", "square-plate",
                                  "stepped-narrow"])
def test_shipped_beams_are_thin_plates(name):
    # t = 10 mm (5 mm) on 1 m: the estimate for mode 8 is below 1 %
    assert load_beam(BEAMS / f"{name}.json").kirchhoff_warnings(8) == ()


@pytest.mark.slow
def test_estimate_against_the_solid():
    # t = L / 15: the solid's frequencies drop below the plate's by about the estimate
    beam = Beam([0.0, 0.3], [0.025, 0.025], 0.02)
    notes = beam.kirchhoff_warnings(3)
    assert len(notes) == 1 and "about 4.7 %" in notes[0]
    plate = np.asarray(compute_truth(beam, model="plate", modes=3, static=False).omega_rad_s)
    solid = np.asarray(compute_truth(beam, model="solid", modes=3, static=False).omega_rad_s)
    gap = 100 * (solid / plate - 1)  # measured -0.58, -2.29, -5.00 %
    beta = np.array([1.8751040687, 4.6940911330, 7.8547574382])
    G = beam.material.G_Pa
    est = -100 * 0.5 * (beta * 0.02 / 0.3) ** 2 / 12 * (1 + beam.material.E_Pa / (5 / 6 * G))
    # modes 2 and 3, where shear dominates the plate's few tenths of a percent Poisson offset
    ratio = gap[1:] / est[1:]
    assert np.all((ratio > 0.7) & (ratio < 1.5)), (gap, est)
