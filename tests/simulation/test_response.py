"""Modal superposition of the tip response: closed forms, beam truth, PRBDM vs simulation."""

import numpy as np
import pytest
from paths import ROOT
from tolerances import EPS

from prbdm_pin.chain.stiffness import finite_segment_stiffness
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.model.prbdm_model import build_model
from prbdm_pin.simulation.response import (
    centerline_modal_tip,
    dynamic_accuracy,
    euler_bernoulli_modal_tip,
    modal_frf,
    modal_step_response,
    prbdm_modal_tip,
)
from prbdm_pin.truth.beam import beam_modal


@pytest.fixture(scope="module")
def beam():
    return load_beam("examples/beams/uniform-narrow.json")


def test_euler_bernoulli_closed_form(beam):
    eb = euler_bernoulli_modal_tip(beam, 30)
    EI, L = beam.root_EI_Nm2, beam.length_m
    # sum of modal static compliances converges to L^3 / (3 E I) (1/k^4 tail)
    assert eb.static_compliance_m_per_N == pytest.approx(L**3 / (3 * EI), rel=1e-5)
    mu = beam.mass_kg / L
    # the same closed form either side: a few roundings (1.2 EPS measured); kept: the test's
    # 1e-12
    assert eb.omega_rad_s[0] == pytest.approx(1.875104068711961**2 * np.sqrt(EI / (mu * L**4)),
                                              rel=5000 * EPS)


def test_beam_truth_normalisation_matches_closed_form(beam):
    modal = beam_modal(beam, n_modes=5, n_elements=200)
    tip = centerline_modal_tip(modal, beam)
    eb = euler_bernoulli_modal_tip(beam, 5)
    np.testing.assert_allclose(tip.omega_rad_s, eb.omega_rad_s, rtol=1e-6)
    np.testing.assert_allclose(tip.tip_gain_m_per_N, eb.tip_gain_m_per_N, rtol=1e-3)
    # int mu phi dx of the higher modes is a small difference of large parts, so the linear
    # interpolation between the 201 nodal values shows there at the 1e-3 level
    assert tip.mass_participation_check < 3e-3


def test_step_and_frf_limits(beam):
    eb = euler_bernoulli_modal_tip(beam, 5)
    t = np.linspace(0.0, 60.0, 20001)
    u = modal_step_response(eb, t, 0.05)
    assert u[0] == 0.0
    assert u[-1] == pytest.approx(eb.static_compliance_m_per_N, rel=1e-9)
    h0 = modal_frf(eb, [0.0], 0.05)[0]
    # the FRF at 0 is the sum of the modal compliances (exact here); kept: the test's 1e-12
    assert h0.real == pytest.approx(eb.static_compliance_m_per_N, rel=5000 * EPS)
    # at resonance of an isolated mode the phase lags by about 90 degrees
    h1 = modal_frf(eb, [eb.omega_rad_s[0]], 0.05)[0]
    assert np.angle(h1) == pytest.approx(-np.pi / 2, abs=0.01)


def test_prbdm_simulation_matches_its_modal_superposition(beam):
    lengths = np.array([1, 2, 2, 2, 1]) / 8.0
    model = build_model(beam, lengths, finite_segment_stiffness(beam, lengths))
    mine = prbdm_modal_tip(model)
    acc_sim = dynamic_accuracy(model, mine, damping_ratio=0.05, duration_s=0.5, samples=501,
                               simulate_step=True)
    # the integrated (nonlinear, small-load) response equals the linear modal superposition
    assert acc_sim.step_error < 2e-3
    assert acc_sim.frf_error == 0.0


def test_finer_prbdm_approaches_euler_bernoulli(beam):
    """The finite-segment chain converges to the beam: both errors shrink with more links."""
    step, frf = [], []
    for n in (4, 8, 16):
        lengths = np.r_[0.5, np.ones(n - 1), 0.5] / n
        model = build_model(beam, lengths, finite_segment_stiffness(beam, lengths))
        acc = dynamic_accuracy(model, euler_bernoulli_modal_tip(beam, 3), damping_ratio=0.02)
        step.append(acc.step_error)
        frf.append(acc.frf_error)
    assert step[0] > step[1] > step[2]
    assert frf[0] > frf[1] > frf[2]


@pytest.mark.slow
def test_plate_modal_superposition_static_limit_matches_the_static_solve():
    """The exact (modal-mass) plate superposition's static compliance sum(gain / omega^2) equals
    an independent solve, the plate's linear static tip deflection (truncation < 0.1 %)."""

    from prbdm_pin.files.beam_file import load_beam
    from prbdm_pin.simulation.response import centerline_modal_tip
    from prbdm_pin.truth import compute_truth

    beam = load_beam(ROOT / "examples/beams/reference-random.json")
    truth = compute_truth(beam, modes=5)
    tip = centerline_modal_tip(truth.modal, beam)
    compliance = float(np.sum(tip.tip_gain_m_per_N / tip.omega_rad_s**2))
    static = -truth.static_linear.tip_displacement_m[2] / -beam.tip_force_N[2]
    assert compliance == pytest.approx(static, rel=1e-3)


def test_truth_modal_tip_superposes_every_mode_below_the_last_selected(beam):
    """uniform-narrow's plate truth selects bending modes 1-5, which skip a torsion mode: the
    superposition keeps it (no tip gain: its node line is the axis), and its static limit is
    an independent linear solve of the plate less the Euler-Bernoulli share of modes 6, 7, ..."""
    from prbdm_pin.simulation.response import truth_modal_tip
    from prbdm_pin.truth import compute_truth
    from prbdm_pin.truth.plate_static import plate_static

    truth = compute_truth(beam, modes=5)
    tip = truth_modal_tip(truth, beam)
    assert truth.labels[4] == "torsion" and list(truth.mode_index) == [0, 1, 2, 3, 5]
    np.testing.assert_array_equal(tip.omega_rad_s, truth.modal.omega_rad_s[:6])
    assert tip.tip_gain_m_per_N[4] < 1e-12 * tip.tip_gain_m_per_N.max()
    # roots of cos(x) cosh(x) = -1; mode k carries 12 / (beta_k L)^4 of L^3 / (3 E I)
    beta_l = np.array([1.8751040687120, 4.6940911329742, 7.8547574382376, 10.995540734875,
                       14.137168391046])
    tail = 1.0 - float(np.sum(12.0 / beta_l**4))
    static = plate_static(beam)
    compliance = float(static.tip_displacement_m[2] / beam.tip_force_N[2])
    # measured 8e-7 from the beam tail (3.2e-4): the strip's plate modes are beam-like
    assert tip.static_compliance_m_per_N / compliance - 1.0 == pytest.approx(-tail, abs=1e-5)
