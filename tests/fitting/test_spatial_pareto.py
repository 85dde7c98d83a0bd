"""The Pareto front of a spatial chain: a chain taken as its own truth (its modes by kind and
its tip and twist under a corner force, from its own large-deflection statics) gives a front
whose knee is that chain's loss of zero, and a front that no design of it dominates."""

import numpy as np
import pytest

from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.errors import BeamInputError
from prbdm_pin.fitting.pareto import fit_pareto
from prbdm_pin.fitting.spatial_deflection import spatial_model_target
from prbdm_pin.model.prbdm_model import build_model


@pytest.fixture(scope="module")
def front(tapered):
    lengths = np.array([0.3, 0.4, 0.3]) * tapered.length_m
    k = spatial_stiffness(tapered, lengths, "xy") * np.exp([0.2, -0.1, 0.1, 0.3])
    truth = build_model(tapered, lengths, k, axes="xy")
    F = np.array([0.0, 0.0, -0.05 * np.linalg.norm(tapered.tip_force_N) - 1.0])
    target = spatial_model_target(truth, F, point="tip_corner_left")
    return fit_pareto(tapered, target, 2, axes="xy", stiffness="joint", pop=16, generations=6,
                      seed_starts=2, progress=False)


def test_the_front_is_non_dominated_and_its_knee_the_nearest_to_the_origin(front):
    F = front.F_pct
    for i in range(F.shape[0]):
        dominated = np.all(F <= F[i], axis=1) & np.any(F < F[i], axis=1)
        assert not dominated.any()
    assert front.knee_index == int(np.argmin(np.hypot(F[:, 0], F[:, 1])))
    assert np.all(np.diff(F[:, 0]) >= 0)
    # lengths on the simplex: they sum to the member's length (a few roundings)
    assert np.allclose(front.front_lengths_m.sum(axis=1), front.front_lengths_m.sum(axis=1)[0])


def test_the_knee_recovers_the_chain_taken_as_truth(front):
    knee = front.knee
    assert knee.axes == "xy" and knee.objective == "combined"
    # an exact design exists (the truth's own): the seeding combined fit reaches it to its
    # solver's tolerance, and the knee is at least as near the origin
    assert knee.combined_loss_pct < 1e-3
    # the knee's full evaluation against the front's: the same design, its statics solved
    # again from another start (Newton's tolerance on the tip, 1e-8 relative: 1e-6 %)
    assert abs(knee.combined_loss_pct - np.hypot(*front.F_pct[front.knee_index])) < 1e-6


def test_a_spatial_front_without_a_3d_tip_truth_is_refused(tapered):
    from prbdm_pin.fitting.target import FitTarget

    w = np.array([10.0, 30.0, 60.0, 90.0])
    target = FitTarget(w, np.zeros(3), all_omega_rad_s=w,
                       all_labels=("bending", "torsion", "bending", "torsion"))
    with pytest.raises(BeamInputError, match="tip_twist_rad|tip_position_m"):
        fit_pareto(tapered, target, 2, axes="xy", stiffness="joint", pop=8, generations=1,
                   progress=False)
