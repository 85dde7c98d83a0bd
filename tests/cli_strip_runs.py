"""Shared pieces of the ``prbdm simulate`` tests on the uniform strip: a 3-link model written as
JSON (finite-segment springs, so its dynamics are the beam's, not a fit's) and the tip height read
back from a run's ``trajectory.csv``."""

from __future__ import annotations

import numpy as np

import prbdm_pin as pp

BEAM = "examples/beams/uniform-narrow.json"


def strip_model_json(tmp_path):
    """Write the 2R strip model (links L/4, L/2, L/4) to ``tmp_path/m.json``; return the path."""
    beam = pp.load_beam(BEAM)
    lengths = np.array([0.25, 0.5, 0.25]) * beam.length_m
    model = pp.build_model(beam, lengths, pp.finite_segment_stiffness(beam, lengths))
    path = tmp_path / "m.json"
    pp.export_model(model, str(path), "json")
    return path


def tip_z(folder):
    """The ``tip_z_m`` column of ``folder/trajectory.csv``, m."""
    head = (folder / "trajectory.csv").read_text().splitlines()[0].split(",")
    return np.loadtxt(folder / "trajectory.csv", delimiter=",", skiprows=1)[
        :, head.index("tip_z_m")]
