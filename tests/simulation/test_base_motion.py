"""simulate(..., base_motion=): a clamp moved by a prescribed motion, against independent paths.

References: a constant base acceleration a is gravity g = -a on the fixed clamp (the package's
gravity: Pinocchio's weight terms, not the base-motion force); a base turning at a constant rate
is a hub spinning at that rate held by a huge inertia (the hub model; the error falls as 1 / J);
a small sinusoidal translation against the chain's linear response by modal superposition (its
own M and K, the base's inertial load from the links' masses and centres of mass by hand);
samples of a quadratic motion through the cubic spline equal the motion itself.
"""

import numpy as np
import pytest
import scipy.linalg
from paths import ROOT
from tolerances import EPS

from prbdm_pin import (
    BeamInputError,
    Hub,
    InputTypeError,
    build_model,
    simulate,
    spatial_stiffness,
)
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.simulation.base_motion import BaseMotion, world_tip_positions

BEAM = load_beam(ROOT / "examples/beams/reference-random.json")
LENGTHS = np.array([0.15, 0.3, 0.2, 0.35]) * BEAM.length_m
SPRINGS = np.array([400.0, 150.0, 60.0])
ACCEL = np.array([1.5, 0.0, -3.0])  # m/s^2


def _constant_acceleration(a):
    z3 = np.zeros(3)
    return BaseMotion(lambda t: np.r_[0.5 * a * t * t, z3], lambda t: np.r_[a * t, z3],
                      lambda t: np.r_[a, z3])


@pytest.mark.parametrize("method,kw,tol", [
    # both runs take the same steps (the same integrator, the forces equal up to roundings,
    # which the steps carry: 2e-14 and 1e-12 of the swing measured)
    ("DOP853", dict(rtol=1e-11), 1e-11),
    ("exponential", {}, 1e-10),
])
def test_constant_acceleration_equals_gravity(method, kw, tol):
    model = build_model(BEAM, LENGTHS, SPRINGS)
    T = 2.0 * 2 * np.pi / model.natural_frequencies()[0]
    moved = simulate(model, T, base_motion=_constant_acceleration(ACCEL), damping_ratio=0.02,
                     method=method, output_dt_s=T / 20, **kw)
    held = simulate(model, T, gravity_m_s2=-ACCEL, damping_ratio=0.02, method=method,
                    output_dt_s=T / 20, **kw)
    swing = np.abs(held.q_rad).max()
    assert swing > 0.05
    assert np.abs(moved.q_rad - held.q_rad).max() <= tol * swing
    # the samples of the motion, through the cubic spline (exact on a quadratic)
    t = np.linspace(0.0, T, 7)
    sampled = BaseMotion.from_samples(t, 0.5 * np.outer(t * t, ACCEL))
    again = simulate(model, T, base_motion=sampled, damping_ratio=0.02, method=method,
                     output_dt_s=T / 20, **kw)
    assert np.abs(again.q_rad - held.q_rad).max() <= tol * swing


def test_constant_acceleration_equals_gravity_on_a_spatial_chain(tapered):
    lengths = np.array([0.3, 0.4, 0.3]) * tapered.length_m
    model = build_model(tapered, lengths, spatial_stiffness(tapered, lengths, "xyz"),
                        axes="xyz")
    a = np.array([1.0, -2.0, -3.0])  # m/s^2: every bending and the twist's coupling
    T = 3.0 * 2 * np.pi / model.natural_frequencies()[0]
    kw = dict(method="DOP853", rtol=1e-11, output_dt_s=T / 10)
    moved = simulate(model, T, base_motion=_constant_acceleration(a), **kw)
    held = simulate(model, T, gravity_m_s2=-a, **kw)
    swing = np.abs(held.q_rad).max()
    assert swing > 1e-3
    # the same steps on both sides: roundings carried (1e-15 of the swing measured)
    assert np.abs(moved.q_rad - held.q_rad).max() <= 1e-11 * swing


def _spin(omega, r):
    """The clamp on a hub of radius r turning about y at omega: (x, z) = r (cos, -sin)."""
    def pose(t):
        th = omega * t
        return np.r_[r * np.cos(th), 0.0, -r * np.sin(th), 0.0, th, 0.0]

    def rate(t):
        th = omega * t
        return np.r_[-r * omega * np.sin(th), 0.0, -r * omega * np.cos(th), 0.0, omega, 0.0]

    def accel(t):
        th = omega * t
        w2 = r * omega * omega
        return np.r_[-w2 * np.cos(th), 0.0, w2 * np.sin(th), 0.0, 0.0, 0.0]

    return BaseMotion(pose, rate, accel)


def test_constant_rate_rotation_equals_a_hub_held_at_that_rate():
    omega, r = 3.0, 0.2  # rad/s, m: the centrifugal stiffening shows (omega ~ 0.5 omega_1)
    model = build_model(BEAM, LENGTHS, SPRINGS)
    T = 1.0
    kw = dict(damping_ratio=0.0, method="DOP853", rtol=1e-11, output_dt_s=T / 20)
    q0 = np.array([0.03, -0.02, 0.05])  # bent at the start: it swings under the spin
    moved = simulate(model, T, q0=q0, base_motion=_spin(omega, r), **kw)
    errs = []
    for J in (1e8, 1e10):
        hub = build_model(BEAM, LENGTHS, SPRINGS, hub=Hub(J, r))
        held = simulate(hub, T, q0=np.r_[0.0, q0], v0=np.r_[omega, 0.0, 0.0, 0.0], **kw)
        assert np.abs(held.v_rad_s[:, 0] - omega).max() < 1e3 / J  # it keeps its rate
        errs.append(np.abs(moved.q_rad - held.q_rad[:, 1:]).max())
    swing = np.abs(moved.q_rad).max()
    assert swing > 0.01
    # the hub's finite inertia is the only difference: the error is 1.34 kg m^2 rad / J
    # (measured from J = 1e4 to 1e12: exactly 1 / J down to DOP853's rtol 1e-11), 2e-9 of the
    # swing at J = 1e10
    assert errs[1] <= 1e-8 * swing
    assert errs[0] / errs[1] == pytest.approx(100.0, rel=0.05)


def test_small_sinusoidal_translation_matches_the_modal_response():
    model = build_model(BEAM, LENGTHS, SPRINGS)
    M, K = model.mass_matrix(), model.stiffness_matrix()
    s = model.sections
    joints = np.cumsum(LENGTHS)[:-1]
    # generalised force per unit base z-acceleration: each link's -m a_z at its COM, through
    # dz_i/dq_j = -(x_i - x_j) for the joints j at or before link i
    d = np.array([np.sum(s.mass_kg[j:] * (s.com_m[j:, 0] - joints[j - 1]))
                  for j in range(1, joints.size + 1)])
    w2, Phi = scipy.linalg.eigh(K, M)
    w = np.sqrt(w2)
    amp, Om = 1e-4, 0.6 * w[0]  # m, rad/s: linear (angles ~1e-4 rad) and below mode 1
    T = 3.0 * 2 * np.pi / w[0]
    z3 = np.zeros(3)
    motion = BaseMotion(lambda t: np.r_[0.0, 0.0, amp * np.sin(Om * t), z3],
                        lambda t: np.r_[0.0, 0.0, amp * Om * np.cos(Om * t), z3],
                        lambda t: np.r_[0.0, 0.0, -amp * Om**2 * np.sin(Om * t), z3])
    r = simulate(model, T, base_motion=motion, damping_ratio=0.0, method="DOP853", rtol=1e-11,
                 output_dt_s=T / 60)
    t = r.t_s[:, None]
    f = Phi.T @ d * (-amp * Om**2)  # modal force amplitude of sin(Om t) (M q'' + K q = d a_z)
    eta = f / (w2 - Om**2) * (np.sin(Om * t) - Om / w * np.sin(w * t))  # from rest
    ref = eta @ Phi.T
    swing = np.abs(ref).max()
    assert swing > 1e-5
    # the motion's nonlinearity, quadratic in the amplitude (2.7e-6, 2.7e-8, 2.7e-10 of the
    # swing measured at 1e-3, 1e-4, 1e-5 m), above DOP853's rtol 1e-11
    assert np.abs(r.q_rad - ref).max() <= 1e-7 * swing


def test_world_tip_is_the_base_frame_tip_moved_with_the_base():
    model = build_model(BEAM, LENGTHS, SPRINGS)
    motion = _spin(2.0, 0.0)
    r = simulate(model, 0.4, base_motion=motion, method="DOP853", output_dt_s=0.1)
    tip_w = world_tip_positions(model, motion, r.t_s, r.q_rad)
    for t, local, world in zip(r.t_s, r.tip_position_m, tip_w, strict=True):
        th = 2.0 * t  # pitch about y, the base at the origin
        Ry = np.array([[np.cos(th), 0, np.sin(th)], [0, 1, 0], [-np.sin(th), 0, np.cos(th)]])
        # rotations of ~1 m positions: roundings (kept: 1e-13)
        np.testing.assert_allclose(world, Ry @ local, rtol=0, atol=500 * EPS)


def test_bad_base_motion_is_refused():
    model = build_model(BEAM, LENGTHS, SPRINGS)
    t = np.linspace(0.0, 1.0, 5)
    p = np.zeros((5, 3))
    with pytest.raises(BeamInputError, match=r"t_s\[2\]"):
        BaseMotion.from_samples([0.0, 0.5, 0.5, 0.7, 1.0], p)
    with pytest.raises(BeamInputError, match="position_m"):
        BaseMotion.from_samples(t, np.zeros((5, 2)))
    with pytest.raises(BeamInputError, match="angles_rad"):
        BaseMotion.from_samples(t, p, np.full((5, 3), np.nan))
    with pytest.raises(BeamInputError, match="at least 2"):
        BaseMotion.from_samples([0.0], np.zeros((1, 3)))
    with pytest.raises(InputTypeError, match="pose"):
        BaseMotion(3.0, np.zeros, np.zeros)
    with pytest.raises(BeamInputError, match="6 finite"):
        BaseMotion(lambda t: np.zeros(5), lambda t: np.zeros(6), lambda t: np.zeros(6))
    short = BaseMotion.from_samples(t, p)
    with pytest.raises(BeamInputError, match="cover the run"):
        simulate(model, 2.0, base_motion=short)
    with pytest.raises(InputTypeError, match="base_motion"):
        simulate(model, 0.5, base_motion=np.zeros(6))
    with pytest.raises(BeamInputError, match="gauss"):
        simulate(model, 0.5, base_motion=short, method="gauss")
    hub = build_model(BEAM, LENGTHS, SPRINGS, hub=Hub(100.0))
    with pytest.raises(BeamInputError, match="hub"):
        simulate(hub, 0.5, base_motion=short)
