"""linearize() of a spatial chain: names refused by field, gravity balanced against
Pinocchio's generalized gravity and its tangent against central differences of it."""

import numpy as np
import pinocchio as pin
import pytest
from paths import ROOT

from prbdm_pin import build_model, linearize
from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.files.beam_file import load_beam

BEAM = load_beam(ROOT / "examples/beams/reference-random.json")
LENGTHS = np.array([0.15, 0.3, 0.2, 0.35]) * BEAM.length_m


def _model(axes="xyz"):
    return build_model(BEAM, LENGTHS, spatial_stiffness(BEAM, LENGTHS, axes), axes=axes)



def test_bad_names_and_actuators_are_refused_by_name(tmp_path):
    from prbdm_pin import StrainActuator
    from prbdm_pin.errors import BeamInputError
    from prbdm_pin.files.urdf_file import load_urdf

    planar = build_model(BEAM, LENGTHS, spatial_stiffness(BEAM, LENGTHS, "y"))
    planar.write_urdf(tmp_path / "chain.urdf")
    bare = load_urdf(tmp_path / "chain.urdf")  # no beam: no width, no corners
    assert bare.beam is None
    with pytest.raises(BeamInputError, match=r"inputs\[1\] = 'corner_force_z_left': this model "
                                             "carries no beam"):
        linearize(bare, inputs=("tip_force_z", "corner_force_z_left"))
    with pytest.raises(BeamInputError, match=r"outputs\[0\] = 'corner_z_right': this model "
                                             "carries no beam"):
        linearize(bare, outputs=("corner_z_right",))
    spatial = _model("xyz")
    with pytest.raises(BeamInputError, match=r"inputs\[0\] = 'corner_force_z': unknown"):
        linearize(spatial, inputs=("corner_force_z",))
    # every spring coordinate is a joint: 3 nodes x 3 axes = 9
    with pytest.raises(BeamInputError, match=r"outputs\[0\] = 'q\[9\]': index 9 out of range, "
                                             "this model has 9"):
        linearize(spatial, outputs=("q[9]",))
    with pytest.raises(BeamInputError, match="actuators: strain actuators act on the planar"):
        linearize(spatial, inputs=("strain[0]",),
                  actuators=[StrainActuator(0.1 * BEAM.length_m, 0.6 * BEAM.length_m)])


def test_gravity_on_a_spatial_chain_balances_the_chain():
    model = _model("xyz")
    g = np.array([0.0, -9.81, -9.81])  # sideways and down: every axis works
    lin = linearize(model, inputs=("tip_force_z",), outputs=("tip_y", "tip_twist"),
                    gravity_m_s2=g)
    pm = pin.Model(model.pin_model)
    pm.gravity = pin.Motion(np.concatenate([g, np.zeros(3)]))
    data = pm.createData()
    q = lin.q_eq
    r = model.stiffness_Nm_per_rad * q + pin.computeGeneralizedGravity(pm, data, q)
    # Newton to rtol 1e-10 of the spring torques
    assert np.abs(r).max() <= 1e-9 * np.abs(model.stiffness_Nm_per_rad * q).max()
    assert lin.y_eq[0] < 0.0  # the tip sags sideways under the y gravity
    # K_e = K + dg/dq against central differences of Pinocchio's generalized gravity
    h = 1e-6  # truncation h^2, rounding EPS |g| / h
    dg = np.column_stack([(pin.computeGeneralizedGravity(pm, data, q + h * e)
                           - pin.computeGeneralizedGravity(pm, data, q - h * e)) / (2 * h)
                          for e in np.eye(q.size)])
    K_e = np.diag(model.stiffness_Nm_per_rad) + dg
    np.testing.assert_allclose(lin.stiffness_Nm_per_rad, 0.5 * (K_e + K_e.T), rtol=1e-7,
                               atol=1e-7 * np.abs(dg).max())
