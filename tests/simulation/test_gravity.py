"""simulate() under gravity: the weight through Pinocchio's dynamics.

References: the static equilibrium under the same gravity (Newton on the balance
K q + g(q) = 0, another algorithm) for where a damped response settles; conservation of the
spring, kinetic and gravitational energy (Pinocchio's potential energy of the bodies, not the
generalized gravity the dynamics use) for an undamped one.
"""

import numpy as np
import pinocchio as pin
import pytest
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.cli import main


def _chain(beam, axes):
    lengths = np.array([0.2, 0.3, 0.3, 0.2]) * beam.length_m
    return pp.build_model(beam, lengths, spatial_stiffness(beam, lengths, axes), axes=axes)


@pytest.mark.parametrize("axes, method", [("y", "exponential"), ("y", "trapezoidal"),
                                          ("y", "Radau"), ("xyz", "exponential"),
                                          ("xyz", "DOP853")])
def test_a_damped_member_settles_in_its_sag(tapered, axes, method):
    model = _chain(tapered, axes)
    g = np.array([0.0, -4.0, -9.81]) if axes == "xyz" else np.array([0.0, 0.0, -9.81])
    eq = pp.statics(model, gravity_m_s2=g)
    assert np.abs(eq.q_rad).max() > 1e-4  # it sags
    # 0.9 of critical for 25 / (0.9 omega_1): exp(-25) ~ 1e-11 of the sag is left
    T = 25.0 / (0.9 * model.natural_frequencies()[0])
    r = pp.simulate(model, T, gravity_m_s2=g, damping_ratio=0.9, output_dt_s=T / 10,
                    method=method)
    # the decay left (1e-11) and the integrators' rtol 1e-9 (2e-13 measured: the error
    # shrinks with the motion)
    tol = 1e-8
    assert np.abs(r.q_rad[-1] - eq.q_rad).max() <= tol * np.abs(eq.q_rad).max()
    np.testing.assert_allclose(r.tip_position_m[-1], eq.tip_position_m, rtol=0.0,
                               atol=tol * np.abs(eq.tip_displacement_m).max())


def test_an_undamped_fall_keeps_its_energy(tapered):
    model = _chain(tapered, "xyz")
    g = np.array([0.0, -4.0, -9.81])
    T = 4 * np.pi / model.natural_frequencies()[0]
    r = pp.simulate(model, T, gravity_m_s2=g, damping_ratio=0.0, output_dt_s=T / 40,
                    method="DOP853", rtol=1e-11, atol=50 * EPS)  # rad: the angles' rounding
    pm = pin.Model(model.pin_model)
    pm.gravity = pin.Motion(np.r_[g, 0.0, 0.0, 0.0])
    data = pm.createData()
    k = model.stiffness_Nm_per_rad
    E = np.array([pin.computeKineticEnergy(pm, data, q, v) + 0.5 * np.sum(k * q * q)
                  + pin.computePotentialEnergy(pm, data, q)
                  for q, v in zip(r.q_rad, r.v_rad_s, strict=True)])
    swing = max(pin.computeKineticEnergy(pm, data, q, v) for q, v in
                zip(r.q_rad, r.v_rad_s, strict=True))
    assert swing > 0.0
    # DOP853 at rtol 1e-11 over two periods (9e-15 of the energy exchanged measured)
    assert np.abs(E - E[0]).max() <= 1e-9 * swing


def test_the_command_takes_gravity_and_refuses_it_badly(tapered, tmp_path, capsys):
    model = _chain(tapered, "y")
    src = tmp_path / "model.json"
    pp.export_model(model, src, "json")
    out = tmp_path / "sim"
    assert main(["simulate", str(src), "--duration", "0.05", "--gravity", "0,0,-9.81",
                 "--out", str(out), "-q"]) == 0
    assert (out / "trajectory.csv").exists()
    for args, text in ((["--gravity", "0,-9.81"], "--gravity"),
                       (["--gravity", "0,0,-9.81", "--compare-truth"], "--compare-truth")):
        bad = tmp_path / "bad"
        assert main(["simulate", str(src), "--duration", "0.05", *args, "--out",
                     str(bad)]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and text in err[0], err
        assert not bad.exists()
