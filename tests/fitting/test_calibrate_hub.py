"""calibrate on a hub of known inertia: E and rho apart. The coupled modes' derivatives and the
problem's Jacobian against central differences; the noiseless ring-down of the scaled 1D beam
truth on the hub (``hub_ring_down_truth``: its own hybrid coordinates and eigen solve) recovered
to the first-order image of the chain's frequency errors; noisy ring-downs within their standard
errors; the refusals (a hub that decouples, damping[k] beyond the flexible modes, J_h <= 0)."""

import numpy as np
import pytest
import scipy.linalg as sla
from central_differences import central_difference
from hub_ring_down_truth import hub_ring_down, hub_truth
from tolerances import EPS

import prbdm_pin as pp
from prbdm_pin.bench.run import finite_segment_chain
from prbdm_pin.commands.plant_options import with_hub
from prbdm_pin.errors import BeamInputError
from prbdm_pin.fitting.calibrate import calibrate
from prbdm_pin.fitting.calibration_data import ring_down
from prbdm_pin.fitting.calibration_hub import HubProblem, hub_matrices
from prbdm_pin.model.hub import Hub

S_E, S_RHO, ZETA = 1.07, 0.93, np.array([0.012, 0.006])
J_H, RADIUS = 0.5, 0.05  # kg m^2, m: a third of the strip's own inertia about the axis
PARAMS = "E,rho,damping[0],damping[1]"
# the calibrated model on the light hub warns that a chain fitted to the clamped truth errs
# there; these chains are fine finite-segment ones (their error is measured below)
pytestmark = pytest.mark.filterwarnings("ignore::prbdm_pin.model.hub_check.LightHubWarning")


def _on_hub(model, hub):
    return with_hub(model, hub)


@pytest.fixture(scope="module")
def chain(narrow):
    # 40 segments: its hub frequencies are within 6e-5 and 4e-4 of the truth's (measured below)
    return _on_hub(finite_segment_chain(narrow, 40), Hub(J_H, RADIUS))


@pytest.fixture(scope="module")
def truth(narrow):
    return hub_truth(narrow, S_E, S_RHO, J_H, RADIUS)


def _ring(truth, T=10.0):
    M, K, Cq = truth
    q0, v0 = np.zeros(M.shape[0]), np.zeros(M.shape[0])
    q0[1], q0[2], v0[2] = 0.05, 0.01, 0.3  # clamped-mode coordinates (sqrt(kg) m, per s)
    t = np.arange(int(T * 250)) / 250.0  # 250 Hz
    return t, hub_ring_down(M, K, Cq, ZETA, t, q0, v0)


def _problem(chain, names, channels=("tip_z", "hub_angle", "tip_z_rate"), n=300):
    K, Mb, Mh, Cq, Cv = hub_matrices(chain, channels)
    t = np.arange(n) / 250.0
    return HubProblem(names, t, np.ones(n * len(channels)), np.array([1.0, 10.0, 0.01]), K,
                      Mb, Mh, Cq, Cv, np.full(2, 0.02), (0,))


def test_mass_splits_into_the_beam_s_scaled_part_and_the_hub(chain, narrow):
    K, Mb, Mh, _, _ = hub_matrices(chain, ("tip_z",))
    # the hub row of K is zero (no spring) and the hub's own inertia sits alone in M_hub
    assert not np.any(K[0]) and Mh[0, 0] == J_H and np.count_nonzero(Mh) == 1
    # M_beam[0, 0] is the straight strip's inertia about the axis (y): rho t int 2 w ((r + x)^2
    # + t^2 / 12) dx, the second term the section's own through the thickness
    w, L = narrow.half_width_at(0.0), narrow.length_m
    t = narrow.uniform_thickness_m("test")
    J_b = narrow.material.rho_kg_m3 * t * 2 * w * (((RADIUS + L) ** 3 - RADIUS**3) / 3
                                                  + L * t**2 / 12)
    # exact for rigid links of a uniform strip (their inertias sum to the strip's): 50 EPS
    # of the sum over 41 links, each computed from its own closed form
    np.testing.assert_allclose(Mb[0, 0], J_b, rtol=50 * EPS * 41)


def test_mode_derivatives_are_central_differences(chain):
    prob = _problem(chain, ("E", "rho"))
    x = np.array([1.1, 0.9])
    w, cq, cv, dw, dcq, dcv = prob.modes(*x, derivatives=True)
    lam = np.linalg.eigvals(np.linalg.solve(prob.M_beam * x[1] + prob.M_hub,
                                            prob.K_beam * x[0])).real
    lam = np.sort(lam[lam > 1e-6 * lam.max()])
    # an eigenvector's rounding ~ EPS lambda_max / gap (Davis-Kahan), x 10 for what that drops
    rel = 10 * EPS * lam.max() / np.diff(lam).min()
    for f, d in ((lambda v: prob.modes(*v)[0], dw.T),
                 (lambda v: prob.modes(*v)[1], np.moveaxis(dcq, 0, -1)),
                 (lambda v: prob.modes(*v)[2], np.moveaxis(dcv, 0, -1))):
        noise = rel * np.abs(f(x)).max()
        D, bound = central_difference(f, x, 1e-4 * x, noise)
        np.testing.assert_array_less(np.abs(d - D), bound + noise)


@pytest.mark.parametrize("names, x", [
    (("E", "rho", "damping[0]", "damping[1]"), [1.1, 0.9, 0.015, 0.007]),
    (("rho", "rayleigh_alpha", "rayleigh_beta"), [1.05, 0.8, 3e-5]),
])
def test_the_parameter_jacobian_is_central_differences(chain, names, x):
    prob = _problem(chain, names)
    x = np.array(x)
    B, c, dy = prob.model_jacobian(x)
    # each value's rounding: EPS of the phase omega t (omega up to mode 2's ~ 400 rad/s) times
    # its size, plus the frequencies' own rounding carried by the phase over the record. That
    # rounding is the pencil's (a 41 x 41 chain whose highest mode is far above these): it is
    # measured here as the spread between this solve and an unsymmetric one of the same pencil
    # (the BLAS kernel sets it: 1e-12 relative on some, less on others)
    sE, sR = prob.scales(x)
    w = prob.modes(sE, sR)[0]
    lam = np.linalg.eigvals(np.linalg.solve(prob.M_beam * sR + prob.M_hub, prob.K_beam * sE))
    other = np.sqrt(np.sort(lam.real[lam.real > 1e-6 * lam.real.max()]))[:w.size - 1]
    dw = np.abs(w[1:] - other).max()  # w[0] is the hub's rigid mode, set to 0 exactly
    noise = np.abs(B @ c).max() * prob.t.max() * (4 * EPS * w.max() + 2 * dw)
    D, bound = central_difference(lambda v: prob.basis(v) @ c, x, 1e-4 * x, noise)
    np.testing.assert_array_less(np.abs(dy - D), bound + noise)


def test_noiseless_ring_down_gives_the_truth_to_the_chain_s_model_form_error(chain, truth,
                                                                              narrow):
    t, y = _ring(truth)
    r = calibrate(chain, ring_down(t, y, ["tip_z_m", "hub_angle_rad"]), PARAMS)
    got = np.log([r.E_scale / S_E, r.rho_scale / S_RHO])
    # the chain's frequency errors e_k = ln(omega_chain / omega_truth) at the true scales map to
    # scale errors -A^-1 e (first order), A = d ln omega_{1,2} / d ln(s_E, s_rho) of the truth:
    # 1/2 for s_E (K alone scales), central differences of the truth for s_rho
    M, K, _ = truth

    def w_truth(M, K):
        return np.sqrt(sla.eigh(K, M, eigvals_only=True)[1:3])

    h = 0.01
    up, down = (hub_truth(narrow, S_E, S_RHO * np.exp(s), J_H, RADIUS) for s in (h, -h))
    A = np.column_stack([[0.5, 0.5], (np.log(w_truth(*up[:2])) - np.log(w_truth(*down[:2])))
                         / (2 * h)])
    scaled = pp.linearize(
        _on_hub(finite_segment_chain(_scaled(narrow), 40), Hub(J_H, RADIUS)),
        inputs=("hub_torque",), outputs=("tip_z",), damping_ratio=0.0)
    w_chain = np.sqrt(sla.eigh(scaled.stiffness_Nm_per_rad, scaled.mass_kg_m2,
                               eigvals_only=True)[1:3])
    e = np.log(w_chain / w_truth(M, K))
    want = -np.linalg.solve(A, e)
    assert np.all(np.abs(want) > 1e-4), want  # the model-form error shows: 3e-4 and 1.2e-3
    # second order: |A^-1| |e|^2 ~ 1e-6; the shapes' share (the amplitudes between channels)
    # measured at 1 % of it; the central difference's truncation (h^2) below 1e-4 of A
    np.testing.assert_allclose(got, want, rtol=0.05)
    np.testing.assert_allclose(r.damping_ratio, ZETA, rtol=1e-3)  # the same model-form error
    assert r.model.hub == chain.hub


def _scaled(beam):
    import dataclasses

    mat = dataclasses.replace(beam.material, E_Pa=beam.material.E_Pa * S_E,
                              rho_kg_m3=beam.material.rho_kg_m3 * S_RHO)
    return dataclasses.replace(beam, material=mat)


def test_noisy_ring_downs_lie_within_their_standard_errors(chain, truth, narrow):
    t, clean = _ring(truth, T=4.0)  # mode 1 decays in 0.8 s: the rest of 10 s is noise
    want = np.r_[narrow.material.E_Pa * S_E, narrow.material.rho_kg_m3 * S_RHO, ZETA]
    for seed in range(3):
        y = clean + 0.02 * np.abs(clean).max(axis=0) \
            * np.random.default_rng(seed).standard_normal(clean.shape)
        r = calibrate(chain, ring_down(t, y, ["tip_z_m", "hub_angle_rad"]), PARAMS)
        # 3 sigma: a miss has probability 0.3 % per parameter if the standard errors are
        # right and the model-form error (previous test: 0.1 and 0.2 of E's and rho's standard
        # errors here) is below them; the 50-trial coverage is scripts/bench_calibrate_hub.py's.
        # damping[1] is left out: mode 2 is weak here (it decays in 0.5 s), and its errors
        # spread 1.04 to 1.38 times its linearised standard error over the benchmark's 50
        # seeds, so 3 of them is no 0.3 % event for it
        np.testing.assert_array_less(np.abs(r.values - want)[:3], 3 * r.std_errors[:3])


def test_a_hub_that_does_not_couple_refuses_e_with_rho(narrow, truth):
    t, y = _ring(truth, T=2.0)
    about_z = _on_hub(finite_segment_chain(narrow, 8), Hub(J_H, RADIUS, "z"))
    with pytest.raises(BeamInputError, match=r"E, rho not determined.*J_b = .*J_h = 0.5 "
                                             r"kg m\^2"):
        calibrate(about_z, ring_down(t, y[:, :1], ["tip_z_m"]), PARAMS)


def test_a_hub_far_heavier_than_the_beam_refuses_e_with_rho(narrow):
    J_heavy = 5e6  # kg m^2: 3.3e6 times the strip's own inertia about the axis
    M, K, Cq = hub_truth(narrow, S_E, S_RHO, J_heavy, RADIUS)
    t, y = _ring((M, K, Cq), T=2.0)
    heavy = _on_hub(finite_segment_chain(narrow, 12), Hub(J_heavy, RADIUS))
    # the condition the message gives (1.31e8 here) is past 1 / sqrt(EPS) = 6.71e7
    with pytest.raises(BeamInputError, match=r"E, rho not determined .*condition \S+ > "
                                             r"6.71e\+07.*J_b = 1.514 kg m\^2.*J_h = 5e\+06"):
        calibrate(heavy, ring_down(t, y[:, :1], ["tip_z_m"]), PARAMS)


def test_damping_beyond_the_flexible_modes_and_a_zero_hub_are_refused(narrow, truth):
    t, y = _ring(truth, T=1.0)
    small = _on_hub(finite_segment_chain(narrow, 3), Hub(J_H, RADIUS))
    with pytest.raises(BeamInputError, match=r"damping\[3\] is flexible mode 4's; the model "
                                             r"on its hub has 3 flexible modes"):
        calibrate(small, ring_down(t, y, ["tip_z_m", "hub_angle_rad"]), "E,rho,damping[3]")
    with pytest.raises(BeamInputError, match=r"n_modes = 4: must be an integer in \[1, 3\]"):
        calibrate(small, ring_down(t, y, ["tip_z_m", "hub_angle_rad"]), "E,rho", n_modes=4)
    with pytest.raises(BeamInputError, match=r"Hub inertia_kg_m2 = 0.0: must be a finite "
                                             r"number > 0"):
        Hub(0.0, RADIUS)


def test_an_offset_on_the_hub_s_angle_channel_is_refused_as_its_rest_angle(chain, truth):
    t, y = _ring(truth, T=1.0)
    # the rest angle a reads Cq_h a in tip z: a constant, as the offset is
    with pytest.raises(BeamInputError, match=r"offset\[tip_z_m\] not determined.*rest angle"):
        calibrate(chain, ring_down(t, y[:, :1], ["tip_z_m"]), "E,offset[tip_z_m]")



def test_rho_alone_is_rho_on_a_hub_not_its_ratio_to_e(chain, narrow):
    # E as the model's: the grid runs along s_rho alone
    t, clean = _ring(hub_truth(narrow, 1.0, S_RHO, J_H, RADIUS), T=3.0)
    y = clean + 0.02 * np.abs(clean).max(axis=0) \
        * np.random.default_rng(8).standard_normal(clean.shape)
    r = calibrate(chain, ring_down(t, y, ["tip_z_m", "hub_angle_rad"]), "rho,damping[0]")
    # one seed, 3 sigma (0.3 %); the chain's model-form error is a fraction of it (above)
    want = narrow.material.rho_kg_m3 * S_RHO
    assert abs(r.values[0] - want) <= 3 * r.std_errors[0], (r.values[0], want)
    assert r.model.beam.material.E_Pa == narrow.material.E_Pa
