"""The PRBDM plant against the truth of the same plant: a 3R joint fit of the 1D truth, put on a
hub, against the truth's hybrid-coordinates hub model (a different model built from the clamped
finite-element modes)."""

from __future__ import annotations

import numpy as np

import prbdm_pin as pp
from prbdm_pin.truth.plant import hybrid_model


def test_hub_stiffened_frequencies_of_the_prbdm_match_the_truths_hybrid_model():
    beam = pp.load_beam("examples/beams/uniform-narrow.json")
    truth = pp.compute_truth(beam, model="beam", modes=6, static=False, error_tol_pct=None)
    target = pp.FitTarget(truth.omega_rad_s, beam.tip_force_N)
    r = pp.fit(beam, target, 3, stiffness="joint", starts=4, seed=0, loss_tol_pct=1e-7,
               progress=False)
    hub = pp.Hub(inertia_kg_m2=5.0, radius_m=0.1)
    model = pp.build_model(beam, r.lengths_m, r.stiffness_Nm_per_rad, hub=hub)
    lin = pp.linearize(model, inputs=("hub_torque",), outputs=("hub_angle",))
    w_prbdm = np.sort(lin.modal().omega_rad_s)
    w_truth = hybrid_model(truth, beam, 5.0, 0.1).frequencies_rad_s
    assert w_prbdm[0] == 0.0 and w_truth[0] == 0.0
    # the hub stiffens the flexible modes: both models must see it, and agree on it
    assert np.all(w_truth[1:4] > truth.omega_rad_s[:3] * 1.001)
    assert np.allclose(w_prbdm[1:4], w_truth[1:4], rtol=1e-2)
