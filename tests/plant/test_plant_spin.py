"""A hub model in steady spin: its linearisation against central differences of the nonlinear
dynamics (pin.aba), its centrifugal stiffness against the closed form -Omega^2/2 d2M_hh/dq2
(second differences of CRBA), its frequencies against the rotating Euler-Bernoulli cantilever
(tests/rotating_beam.py, itself checked against Hodges & Rutkowski's table), and a nonlinear
simulation from the spinning state oscillating at the linear plant's frequency."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
import scipy.optimize as so
from central_differences import central_difference
from paths import BEAMS
from rotating_beam import rotating_beam_frequencies, southwell_coefficients
from tolerances import EPS

from prbdm_pin import BeamInputError, Hub, beam_from_dict, build_model, linearize, simulate
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.io.record_checks import LINK_FLOOR_FRACTION
from prbdm_pin.plant.spin import gyroscopic_frequencies, spinning_frequencies

PANEL = load_beam(BEAMS / "reference-random.json")
LENGTHS = np.array([0.15, 0.3, 0.2, 0.35]) * PANEL.length_m
SPRINGS = np.array([400.0, 150.0, 60.0])

STRIP = load_beam(BEAMS / "uniform-narrow.json")  # L = 1 m, 50 mm x 10 mm steel
EI = 205e9 * 0.05 * 0.01**3 / 12.0  # N m^2, about y (the chain's bending axis)
RHO_A = 7850.0 * 0.05 * 0.01  # kg/m


def _segments(n: int) -> tuple[np.ndarray, np.ndarray]:
    """n joints at the centres of n equal segments (half links at the ends), springs EI / l."""
    l = STRIP.length_m / n
    return l * np.array([0.5] + [1.0] * (n - 1) + [0.5]), np.full(n, EI / l)


def test_reference_reproduces_the_published_rotating_cantilever():
    # Hodges & Rutkowski (1981), uniform cantilever, r = 0, out of plane, units of
    # sqrt(EI / (rho A L^4)), given to 4 decimals: half a unit of the last, plus the reference's
    # own discretisation (60 against 120 elements: 5e-7)
    for spin, table in ((1.0, (3.6816, 22.1810, 61.8418)), (12.0, (13.1702, 37.6031, 79.6145))):
        got = rotating_beam_frequencies(1.0, 1.0, 1.0, spin, 0.0, "out")
        np.testing.assert_allclose(got, table, rtol=0.0, atol=0.5e-4 + 1e-6)
    # Southwell's first coefficient 1.193 out of plane, K_in = K_out - 1 (the -M term exactly;
    # a few roundings of the modal sums)
    k_out, k_in = southwell_coefficients(0.0, "out"), southwell_coefficients(0.0, "in")
    assert k_out[0] == pytest.approx(1.193, abs=5e-4)  # the literature's 4 digits
    np.testing.assert_allclose(k_out - k_in, 1.0, rtol=1000 * EPS)


@pytest.mark.parametrize("axis", ["x", "y", "z"])
def test_spin_stiffness_is_minus_half_omega_squared_hessian_of_hub_inertia(axis):
    model = build_model(PANEL, LENGTHS, SPRINGS, hub=Hub(50.0, 0.1, axis))
    spin = 30.0
    lin = linearize(model, inputs=("hub_torque",), outputs=("hub_angle",), spin_rad_s=spin)
    Ks = lin.stiffness_Nm_per_rad - model.stiffness_matrix()
    nv = model.pin_model.nv

    def m00(q):
        return model.mass_matrix(q)[0, 0]

    def hessian(h):
        H = np.zeros((nv, nv))
        for i in range(nv):
            for j in range(nv):
                e, f = np.eye(nv)[i] * h, np.eye(nv)[j] * h
                H[i, j] = (m00(e + f) - m00(e - f) - m00(f - e) + m00(-e - f)) / (4 * h * h)
        return H

    h = 1e-3
    H1, H2 = hessian(h), hessian(2 * h)
    # second differences: truncation c h^2, bounded by |H(h) - H(2h)| (= 3 c h^2), and the
    # rounding of four values of M_hh of size M_hh over 4 h^2 (8 roundings each, CRBA sums)
    bound = np.abs(H1 - H2) + 4 * 8 * EPS * m00(np.zeros(nv)) / (4 * h * h)
    closed = -0.5 * spin**2 * H1
    assert np.all(np.abs(Ks - closed) <= 0.5 * spin**2 * bound + 1e-9 * np.abs(Ks).max())
    assert not np.any(Ks[0]) and not np.any(Ks[:, 0])  # the hub angle is cyclic
    # the gyroscopic term: the hub's row of M (M_hh included) is even in every joint angle
    # about the straight pose, so stationary there, and dh/dv is zero
    base = linearize(model, inputs=("hub_torque",), outputs=("hub_angle",))
    np.testing.assert_array_equal(lin.damping_Nms_per_rad, base.damping_Nms_per_rad)


@pytest.mark.parametrize("axis", ["x", "y", "z"])
def test_state_matrix_is_the_jacobian_of_the_nonlinear_spinning_dynamics(axis):
    model = build_model(PANEL, LENGTHS, SPRINGS, hub=Hub(50.0, 0.1, axis))
    spin, nv = 12.0, model.pin_model.nv
    lin = linearize(model, inputs=("hub_torque", "joint_torque[1]"), outputs=("hub_angle",),
                    spin_rad_s=spin, damping_ratio=0.03)
    K, Cd = model.stiffness_matrix(), lin.damping_Nms_per_rad
    pm, data = model.pin_model, model.pin_model.createData()
    v_eq = np.zeros(nv)
    v_eq[0] = spin

    def f(z):  # z = [q, v - v_eq, u]: the nonlinear state derivative, springs and damping
        q, dv, u = z[:nv], z[nv:2 * nv], z[2 * nv:]
        tau = -K @ q - Cd @ dv
        tau[0] += u[0]
        tau[2] += u[1]
        return np.concatenate([dv, pin.aba(pm, data, q, v_eq + dv, tau)])

    z0 = np.zeros(2 * nv + 2)
    scale = np.abs(f(z0 + 1e-3)).max()
    # steps 1e-5: truncation bounded by the Richardson term; each aba value rounds to a few
    # hundred EPS of the largest acceleration (O(n) recursions of 6-vectors)
    D, bound = central_difference(f, z0, 1e-5, 300 * EPS * scale)
    J = np.hstack([lin.A, lin.B])
    assert np.all(np.abs(J - D) <= bound + 1e-9 * np.abs(J).max())
    assert lin.u_eq[0] == 0.0  # a free hub needs no torque to keep spinning unloaded


CONE_G, CONE_F = np.array([0.0, 0.0, -9.81]), np.array([0.0, 0.0, 2.0])


def _coned(spin: float, damping_ratio: float):
    # a rotor about z under gravity and a tip lift along z (the hub axis: both turn with it):
    # the beam cones, the spin stiffening pulling it back toward the plane of rotation
    # a light hub (5 kg m^2, a quarter of the panel's inertia about z): the coning moves
    # inertia off the hub axis, and the hub's rate answers (gyroscopic coupling)
    model = build_model(PANEL, LENGTHS, SPRINGS, hub=Hub(5.0, 0.1, "z"))
    lin = linearize(model, inputs=("hub_torque", "tip_force_z"), outputs=("tip_z",),
                    load_N=CONE_F, gravity_m_s2=CONE_G, spin_rad_s=spin,
                    damping_ratio=damping_ratio)
    return model, lin


@pytest.mark.parametrize("spin", [4.0, 15.0])
def test_coned_relative_equilibrium_and_its_jacobian(spin):
    model, lin = _coned(spin, 0.02)
    q_eq, nv = lin.q_eq, model.pin_model.nv
    at_rest = linearize(model, outputs=("tip_z",), load_N=CONE_F, gravity_m_s2=CONE_G).q_eq
    assert np.all(np.abs(q_eq[1:]) < np.abs(at_rest[1:]))  # the spin cones it less
    pm = pin.Model(model.pin_model)
    pm.gravity = pin.Motion(np.concatenate([CONE_G, np.zeros(3)]))
    data = pm.createData()
    # the plant's own damping at this pose (lin's damping holds it plus the gyroscopic G)
    Cd = linearize(model, inputs=("hub_torque",), outputs=("tip_z",), q_eq=q_eq,
                   damping_ratio=0.02).damping_Nms_per_rad
    K = model.stiffness_matrix()
    v_eq = np.zeros(nv)
    v_eq[0] = spin

    def torque(q, dv, u):
        J = pin.computeFrameJacobian(pm, data, q, model.tip_frame_id,
                                     pin.LOCAL_WORLD_ALIGNED)[:3]
        tau = -K @ q - Cd @ dv + J.T @ (CONE_F + np.array([0.0, 0.0, u[1]]))
        tau[0] += lin.u_eq[0] + u[0]
        return tau

    # the definition by ABA: at rest in the spinning frame (no acceleration) with the trim;
    # the Newton solve's rtol 1e-10 of the spring torques, as generalized forces M a
    a0 = pin.aba(pm, data, q_eq, v_eq, torque(q_eq, np.zeros(nv), np.zeros(2)))
    assert np.abs(model.mass_matrix(q_eq) @ a0).max() < 1e-9 * np.abs(K @ q_eq).max()

    def f(z):
        q, dv, u = z[:nv], z[nv:2 * nv], z[2 * nv:]
        return np.concatenate([dv, pin.aba(pm, data, q, v_eq + dv, torque(q, dv, u))])

    z0 = np.concatenate([q_eq, np.zeros(nv + 2)])
    scale = np.abs(f(z0 + 1e-3)).max()
    # as at the straight pose: Richardson-bounded truncation, ABA's roundings
    D, bound = central_difference(f, z0, 1e-5, 300 * EPS * scale)
    J = np.hstack([lin.A, lin.B])
    assert np.all(np.abs(J - D) <= bound + 1e-9 * np.abs(J).max())
    # the gyroscopic coupling at the coned pose: skew, Omega dM_hh/dq_j on the hub's row
    # (central differences of CRBA, step 1e-6: truncation 1e-12 of M_hh'', roundings
    # EPS M_hh / 1e-6 = 1e-8 relative)
    G = lin.gyroscopic_Nms_per_rad
    # skew: RNEA's two triangles are separate sums, a rounding apart
    np.testing.assert_allclose(G, -G.T, rtol=0.0, atol=10 * EPS * np.abs(G).max())
    dM = [(model.mass_matrix(q_eq + e)[0, 0] - model.mass_matrix(q_eq - e)[0, 0]) / 2e-6
          for e in np.eye(nv)[1:] * 1e-6]
    np.testing.assert_allclose(G[0, 1:], spin * np.array(dM), rtol=1e-6)


@pytest.mark.parametrize("spin", [4.0, 15.0])
def test_coned_rotor_oscillates_at_its_gyroscopic_frequency(spin):
    model, lin = _coned(spin, 0.0)
    w = gyroscopic_frequencies(lin)
    w_modal = lin.modal().omega_rad_s[1:]  # without G: 4.5 % (4 rad/s), 0.18 % (15) off
    # mode 1 of the undamped gyroscopic plant as the start: the real part of its complex
    # eigenvector, positions and rates, at 1e-5 rad
    lam, V = np.linalg.eig(lin.A)
    vec = V[:, np.argmin(np.abs(lam - 1j * w[0]))]
    nv = model.pin_model.nv
    vec = 1e-5 * vec / np.abs(vec[1:nv]).max()
    period = 2 * np.pi / w[0]
    tr = simulate(model, 10 * period, q0=lin.q_eq + vec[:nv].real, v0=vec[nv:].real,
                  spin_rad_s=spin, tip_force=CONE_F, gravity_m_s2=CONE_G, damping_ratio=0.0,
                  output_dt_s=period / 64, method="gauss")
    t, x = tr.t_s, tr.q_rad[:, 1]

    def misfit(om):
        A = np.column_stack([np.cos(om * t), np.sin(om * t), np.ones_like(t)])
        return np.linalg.lstsq(A, x, rcond=None)[1][0]

    best = so.minimize_scalar(misfit, bounds=(0.95 * w[0], 1.05 * w[0]), method="bounded",
                              options={"xatol": 1e-9 * w[0]}).x
    # the Gauss steps' phase error and the fit over ten periods: measured 5e-6 (4 rad/s) and
    # 1.8e-4 (15 rad/s, the hub turning 15 rad/s within each step); the frequency without G
    # is further off than that
    assert best == pytest.approx(w[0], rel=5e-4)
    assert abs(best / w_modal[0] - 1.0) > 1e-3


def _strip_model(n: int, axis: str):
    lengths, k = _segments(n)
    return build_model(STRIP, lengths, k, hub=Hub(1e3, 0.0, axis),
                       min_fraction=LINK_FLOOR_FRACTION)


@pytest.mark.parametrize("axis,plane", [("z", "out"), ("y", "in")])
def test_fine_chain_converges_to_the_rotating_cantilever(axis, plane):
    # hub about z: the beam sweeps the xy-plane and bends out of it (flapping); about y: it
    # bends in its plane of rotation (lead-lag). The hub held at the rate, as the reference.
    w0 = rotating_beam_frequencies(1.0, EI, RHO_A, 0.0)
    spin = float(w0[0])
    ref = rotating_beam_frequencies(1.0, EI, RHO_A, spin, 0.0, plane)
    err = {n: np.abs(spinning_frequencies(_strip_model(n, axis), spin, hub_free=False)[:3]
                     / ref - 1.0) for n in (10, 20)}
    # the equal-segment chain's error is O(1/n^2): halving the segments divides it by ~4
    # (4.0-4.3 measured over the three modes, both planes)
    np.testing.assert_array_less(2.8 * err[20], err[10])
    # measured 0.09-0.34 % at n = 20; the chain at rest errs by 0.06-0.29 % (its own
    # discretisation), so the spin adds at most ~0.1 %
    np.testing.assert_array_less(err[20], 0.004)
    # the chain's Southwell coefficient of mode 1 at this spin: 1.18 flapping, 0.18 lead-lag
    # (1.193 and 0.193 at Omega -> 0); the chain's discretisation shifts it by 0.0030 in both
    # planes at n = 20
    m = _strip_model(20, axis)
    w2 = spinning_frequencies(m, spin, hub_free=False, squared=True)[0]
    w2_0 = spinning_frequencies(m, 0.0, hub_free=False, squared=True)[0]
    k_ref_at_spin = (ref[0] ** 2 - w0[0] ** 2) / spin**2
    assert (w2 - w2_0) / spin**2 == pytest.approx(k_ref_at_spin, abs=0.005)


def test_epps_chandra_strip_within_the_experiment_scatter():
    # Epps & Chandra's rotating aluminium strip (the unswept case; dimensions and measured
    # frequencies as GXBeam.jl's test/examples/rotating.jl gives them): 37.5 in from a hub
    # radius of 2.5 in, 1 in x 0.063 in, E = 1.06e7 psi, rho = 2.51e-4 lbf s^2/in^4, flapping
    # (hub about z) at 0, 500 and 750 rpm; modes 1-3, Hz
    inch, lbf = 0.0254, 4.4482216152605
    E, rho = 1.06e7 * lbf / inch**2, 2.51e-4 * lbf / inch**4
    L, w, h, r = 37.5 * inch, 1.0 * inch, 0.063 * inch, 2.5 * inch
    beam = beam_from_dict({"name": "epps-chandra", "length": L, "x": [0.0, L],
                           "half_width": [w / 2, w / 2], "thickness": h,
                           "material": {"name": "aluminium", "E": E, "rho": rho, "nu": 0.325}})
    EIs = E * w * h**3 / 12.0
    n = 20
    l = L / n
    model = build_model(beam, l * np.array([0.5] + [1.0] * (n - 1) + [0.5]), np.full(n, EIs / l),
                        hub=Hub(1e3, r, "z"), min_fraction=LINK_FLOOR_FRACTION)
    measured = {0: (1.4, 10.3, 27.7), 500: (10.2, 25.2, 47.0), 750: (14.8, 36.1, 62.9)}
    for rpm, f_exp in measured.items():
        spin = rpm * 2 * np.pi / 60
        f = spinning_frequencies(model, spin, hub_free=False)[:3] / (2 * np.pi)
        ref = rotating_beam_frequencies(L, EIs, rho * w * h, spin, r, "out") / (2 * np.pi)
        # the chain against the beam theory: its 20-segment discretisation, O(1/n^2) (3.7-3.8
        # times smaller than at n = 10), growing with the centrifugal share of the stiffness:
        # 0.06-0.33 % at rest, up to 1.07 % at 750 rpm (Omega = 8.4 omega_1)
        np.testing.assert_allclose(f, ref, rtol=0.012)
        # the experiment: its mode 1 at rest reads 1.4 to 1.8 Hz over the four tip sweeps that
        # share this straight root, a scatter of +-12 %; beam theory and chain are within 10 %
        # of every measurement (measured -9.6 to +6.3 %)
        np.testing.assert_array_less(np.abs(f / np.array(f_exp) - 1.0), 0.12)


def test_spin_about_the_beam_axis_softens_by_omega_squared():
    # the beam on the spin axis, bending in z: the centrifugal push on the lateral deflection
    # alone, omega^2 = omega_0^2 - Omega^2 for a string of point masses. A link pitched by
    # theta has inertia about x I_xx cos^2 + I_zz sin^2, whose spin stiffness -Omega^2 (I_zz -
    # I_xx) falls short of the mass term I_yy by m t^2 / 6: at most 2 t^2 / (l^2 + t^2) of a
    # link's rotational inertia (l the shortest link), so of a mode's mass-normalised 1
    m = _strip_model(8, "x")
    spin, t = 20.0, 0.01
    got = spinning_frequencies(m, spin, squared=True)
    ref = spinning_frequencies(m, 0.0, squared=True) - spin**2
    l_min = float(m.lengths_m.min())
    np.testing.assert_array_less(ref - 100 * EPS * ref.max(), got)  # the shortfall softens less
    np.testing.assert_array_less(got - ref, 2 * t**2 / (l_min**2 + t**2) * spin**2)
    # mode 1, nearly all translation: within 1e-4 of Omega^2 (measured 8e-5)
    assert got[0] - ref[0] < 1e-4 * spin**2


@pytest.mark.parametrize("axis", ["y", "z"])
def test_free_hub_simulation_oscillates_at_the_spinning_frequency(axis):
    lengths, k = _segments(3)
    model = build_model(STRIP, lengths, k, hub=Hub(10.0, 0.1, axis))
    spin = float(spinning_frequencies(model, 0.0)[0])
    w = spinning_frequencies(model, spin)  # hub free, as simulate has it
    lin = linearize(model, inputs=("hub_torque",), outputs=("hub_angle",), spin_rad_s=spin,
                    damping_ratio=0.0)
    # the undamped plant's eigenvalues: +-i omega of every flexible mode (another solver)
    ev = np.sort(np.abs(np.linalg.eigvals(lin.A).imag))[2::2]
    np.testing.assert_allclose(ev, w, rtol=5000 * EPS * (w[-1] / w[0]) ** 2)
    phi = lin.modal().shapes[:, 1]
    period = 2 * np.pi / w[0]
    tr = simulate(model, 10 * period, q0=1e-5 * phi / np.abs(phi[1:]).max(), spin_rad_s=spin,
                  damping_ratio=0.0, output_dt_s=period / 64, method="gauss")
    t, x = tr.t_s, tr.q_rad[:, 1]

    def misfit(om):
        A = np.column_stack([np.cos(om * t), np.sin(om * t), np.ones_like(t)])
        return np.linalg.lstsq(A, x, rcond=None)[1][0]

    best = so.minimize_scalar(misfit, bounds=(0.98 * w[0], 1.02 * w[0]), method="bounded",
                              options={"xatol": 1e-9 * w[0]}).x
    # amplitude 1e-5 rad: the nonlinear shift is O(1e-10); the Gauss steps' phase error over
    # ten periods and the fit's resolution: 1e-5 measured 1e-6
    assert best == pytest.approx(w[0], rel=1e-5)
    # the hub keeps its mean rate: the angle grows as Omega t (the mode's hub part oscillates
    # at 1e-5 of a radian)
    np.testing.assert_allclose(tr.q_rad[:, 0], spin * t, atol=1e-4)


def test_spin_refusals():
    clamped = build_model(PANEL, LENGTHS, SPRINGS)
    hub = build_model(PANEL, LENGTHS, SPRINGS, hub=Hub(50.0, 0.1, "z"))
    with pytest.raises(BeamInputError, match="spin_rad_s.*needs a hub"):
        linearize(clamped, spin_rad_s=3.0)
    with pytest.raises(BeamInputError, match="spin_rad_s.*load_N.*off the hub axis"):
        linearize(hub, spin_rad_s=3.0, load_N=[1.0, 0.0, -1.0])
    with pytest.raises(BeamInputError, match="spin_rad_s.*gravity.*off the hub axis"):
        linearize(hub, spin_rad_s=3.0, gravity_m_s2=[0.0, -9.81, 0.0])
    with pytest.raises(BeamInputError, match="spin_rad_s"):
        linearize(hub, spin_rad_s=float("nan"))
    with pytest.raises(BeamInputError, match="has no hub"):
        spinning_frequencies(clamped, 3.0)
    with pytest.raises(BeamInputError, match="not linearised about a spin"):
        gyroscopic_frequencies(linearize(hub))
    with pytest.raises(BeamInputError, match="spin_rad_s.*needs a hub"):
        simulate(clamped, 0.01, spin_rad_s=3.0, method="gauss")
    with pytest.raises(BeamInputError, match="spin_rad_s = 3.0: the exponential integrator"):
        simulate(hub, 0.01, spin_rad_s=3.0, method="exponential")
