"""planar_mass_matrices refuses points of another design or pose count (its compiled sum
indexes them), and sums the points it is given: the mass matrix at the given points' poses
equals Pinocchio's CRBA there."""

from __future__ import annotations

import numpy as np
import pytest
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.chain.pin_dynamics import mass_matrices
from prbdm_pin.chain.planar_mass import chain_points, planar_mass_matrices

BEAM = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)


def test_points_of_other_poses_are_refused_and_given_points_are_used():
    lengths = np.array([0.2, 0.3, 0.3, 0.2])
    model = pp.build_model(BEAM, lengths, np.ones(3))
    s = model.sections
    args = (lengths, s.mass_kg, s.com_m[:, 0] - s.start_m, s.inertia_com_kg_m2[:, 1, 1])
    Q = np.array([[0.1, -0.2, 0.3], [0.5, 0.4, -0.6]])
    points = chain_points(lengths[None], args[2][None], Q)
    with pytest.raises(ValueError, match="points of shapes"):
        planar_mass_matrices(*args, Q[:1], points)
    M = planar_mass_matrices(*args, Q, points)
    ref = mass_matrices(model.pin_model, model.new_data(), Q)
    # two sums of a few products over 3 links: a few roundings of the largest entry (measured
    # 2 EPS); bound 50 EPS
    assert np.max(np.abs(M - ref)) <= 50 * EPS * np.max(np.abs(ref))
