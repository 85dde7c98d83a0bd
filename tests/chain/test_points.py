"""Named points on the tip link: positions against the rigid-body formula, Jacobians against
central differences."""

import numpy as np
import pytest
from tolerances import EPS

from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.errors import BeamInputError
from prbdm_pin.model.prbdm_model import build_model


@pytest.fixture(scope="module")
def chain(tapered):
    lengths = np.array([0.2, 0.3, 0.3, 0.2]) * tapered.length_m
    return build_model(tapered, lengths, spatial_stiffness(tapered, lengths, "xyz"),
                       axes="xyz")


@pytest.mark.parametrize("point, side", [("tip", 0.0), ("tip_corner_left", 1.0),
                                         ("tip_corner_right", -1.0)])
def test_a_point_is_the_tip_plus_its_rotated_offset(chain, tapered, point, side):
    q = np.random.default_rng(4).normal(size=chain.n_springs) * 0.4
    p, J = chain.point_kinematics(point, q)
    tip, R = chain.tip_pose(q)
    w = tapered.half_width_m[-1]
    # the same rigid-body placement two ways: rounding of a 3x3 product on ~L-sized numbers
    assert np.abs(p - (tip + R[:, 1] * side * w)).max() <= 50 * EPS * tapered.length_m
    h = 1e-6
    fd = np.array([(chain.point_kinematics(point, q + h * e)[0]
                    - chain.point_kinematics(point, q - h * e)[0]) / (2 * h)
                   for e in np.eye(q.size)]).T
    # central differences: truncation ~h^2 |d3p| ~ 1e-12 L, rounding ~EPS L / h ~ 1e-10 L
    assert np.abs(J - fd).max() <= 1e-8 * tapered.length_m


def test_at_the_straight_pose_a_twist_moves_the_corners_apart(chain, tapered):
    _, J_left = chain.point_kinematics("tip_corner_left")
    _, J_right = chain.point_kinematics("tip_corner_right")
    x = chain.axis_index("x")
    w = tapered.half_width_m[-1]
    # a unit twist at any node lifts the left corner by w and lowers the right one by w
    assert np.allclose(J_left[2, x], w) and np.allclose(J_right[2, x], -w)


def test_an_unknown_point_is_refused(chain):
    with pytest.raises(BeamInputError, match="point = 'corner'"):
        chain.point_kinematics("corner")
