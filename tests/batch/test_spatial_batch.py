"""A batch of spatial fits: every record carries its axes and the kind of each matched mode,
and its springs rebuild a chain whose own eigensolve gives the recorded truth frequencies."""

import json

import numpy as np
import scipy.linalg

from prbdm_pin.batch import BatchSpec, FitSettings, LocalPool, run_batch
from prbdm_pin.member.random_beams import random_beam
from prbdm_pin.model.prbdm_model import build_model
from prbdm_pin.options.objects import FitOptions


def test_a_spatial_batch_records_axes_and_kinds(tmp_path):
    settings = FitSettings(joints=2, options=FitOptions(axes="xy", stiffness="joint", starts=2),
                           truth_model="beam", cache_dir=str(tmp_path / "cache"))
    summary = run_batch(BatchSpec(seed=5, settings=settings, n_beams=2), tmp_path / "out",
                        backend=LocalPool(1), progress=False)
    assert (summary.n_ok, summary.n_failed) == (2, 0)
    for line in (tmp_path / "out" / "results.jsonl").read_text().splitlines():
        rec = json.loads(line)
        assert rec["axes"] == "xy"
        assert sorted(rec["mode_kinds"]) == ["bending", "bending", "torsion", "torsion"]
        beam = random_beam(np.random.default_rng(np.random.SeedSequence(5, spawn_key=(
            rec["beam_index"],))))
        model = build_model(beam, rec["lengths_m"], rec["stiffness_Nm_per_rad"], axes="xy")
        w = np.sqrt(scipy.linalg.eigh(np.diag(model.stiffness_Nm_per_rad),
                                      model.mass_matrix(), eigvals_only=True))
        # the whole pencil's four frequencies, ascending, against the recorded truth ones:
        # the fit matched them to its solver's tolerance (1e-8 relative residuals)
        assert np.allclose(w, np.sort(rec["omega_truth_rad_s"]), rtol=1e-6)
