"""Modal gains of the Kirchhoff plate truth: against the 1D beam on a narrow strip, the width-
averaged slope against finite differences, the modal statics against the plate's static solve."""


import numpy as np
import pytest
from paths import BEAMS
from scipy.integrate import quad

from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.truth import compute_truth
from prbdm_pin.truth.plant import truth_modal_gains
from prbdm_pin.truth.plant.plate_fields import line_average_matrix, probe_matrix
from prbdm_pin.truth.plate import plate_modes
from prbdm_pin.truth.plate_static import plate_static

ACTUATORS = ((0.1234, 0.4567), (0.0, 1.0), (0.3, 0.95))


@pytest.fixture(scope="module")
def plate_truth(narrow):
    return compute_truth(narrow, modes=5, static=False, error_tol_pct=None)


@pytest.fixture(scope="module")
def plate_gains(narrow, plate_truth):
    return truth_modal_gains(plate_truth, narrow, ACTUATORS)


def test_narrow_plate_strip_gains_match_the_beam(narrow, plate_gains):
    beam_truth = compute_truth(narrow, model="beam", modes=5, static=False, error_tol_pct=None)
    gb = truth_modal_gains(beam_truth, narrow, ACTUATORS)
    gp = plate_gains
    # the plate/beam gap of this strip: frequencies 0.3-0.4 %; gains measured within 0.17 % (tip)
    # and 1.3 % of each actuator's largest gain (strain, mode 5)
    np.testing.assert_allclose(gp.omega_rad_s, gb.omega_rad_s, rtol=1e-2)
    np.testing.assert_allclose(gp.tip_z_per_sqrt_kg, gb.tip_z_per_sqrt_kg, rtol=0.005)
    np.testing.assert_allclose(gp.tip_force_per_sqrt_kg, gb.tip_force_per_sqrt_kg, rtol=0.005)
    scale = np.abs(gb.strain_per_sqrt_kg_m).max(axis=1, keepdims=True)
    assert np.all(np.abs(gp.strain_per_sqrt_kg_m - gb.strain_per_sqrt_kg_m) < 0.02 * scale)


def _width_average(basis, phi, x, w):
    return line_average_matrix(basis, x, w) @ phi


@pytest.mark.parametrize("name", ["uniform-narrow", "tapered"])
def test_width_averaged_slope_is_the_derivative_of_the_width_average(name):
    beam = load_beam(BEAMS / f"{name}.json")
    pm = plate_modes(beam, 0, 8)
    L = beam.length_m
    h = 1e-5 * L
    worst = 0.0
    for x in (0.05 * L, 0.4567 * L, 0.5 * L, 0.9 * L):  # inside elements and on mesh lines
        w = float(beam.half_width_at(x))
        slope = line_average_matrix(pm.basis, x, w, d_dx=True) @ pm.phi
        fd = (_width_average(pm.basis, pm.phi, x + h, float(beam.half_width_at(x + h)))
              - _width_average(pm.basis, pm.phi, x - h, float(beam.half_width_at(x - h)))) / (2 * h)
        # Leibniz: d/dx of the average over |y| <= w(x) also moves its ends and its divisor
        dw = float(beam.half_width_at(x + h) - beam.half_width_at(x - h)) / (2 * h)
        edges = probe_matrix(pm.basis, np.array([x, x]), np.array([-w, w])) @ pm.phi
        fd -= dw / w * (edges.mean(axis=0) - _width_average(pm.basis, pm.phi, x, w))
        worst = max(worst, float(np.abs(slope - fd).max() / np.abs(slope).max()))
    assert worst < 1e-6  # measured 9e-9 (both)


def test_plate_modal_statics_match_the_plate_static_solve(narrow):
    truth = compute_truth(narrow, modes=10, n_computed=40, static=False, error_tol_pct=None)
    g = truth_modal_gains(truth, narrow)
    ref = plate_static(narrow, tip_force_N=np.array([0.0, 0.0, 1.0])).tip_displacement_m[2]
    # ten bending modes: the tail of sum c_k b_k / omega_k^2, measured 4.1e-5
    assert g.static_tip_z_m(1.0) == pytest.approx(ref, rel=2e-4)
    assert ref > 0.0


def test_positive_moment_bends_the_plate_tip_down(plate_gains):
    for i in range(len(ACTUATORS)):
        assert plate_gains.static_tip_z_m(0.0, np.eye(len(ACTUATORS))[i]) < 0.0


def test_tip_gain_is_the_truths_own_tip_node(narrow, plate_truth, plate_gains):
    nodes = plate_truth.modal.nodes_m
    tip = np.flatnonzero((nodes[:, 0] == narrow.length_m) & (nodes[:, 1] == 0.0))
    assert tip.size == 1
    stored = np.asarray(plate_truth.modal.node_uz)[plate_truth.mode_index, tip[0]]
    np.testing.assert_allclose(plate_gains.tip_z_per_sqrt_kg, np.abs(stored), rtol=1e-9)


@pytest.mark.parametrize("name", ["uniform-narrow", "tapered"])
def test_inertia_integrals(name):
    beam = load_beam(BEAMS / f"{name}.json")
    truth = compute_truth(beam, modes=3, static=False, error_tol_pct=None)
    g = truth_modal_gains(truth, beam)
    rho_t = beam.material.rho_kg_m3 * beam.thickness_m
    L = beam.length_m
    for k, got in enumerate((g.mass_kg, g.first_moment_kg_m, g.second_moment_kg_m2)):
        ref = quad(lambda x, k=k: rho_t * 2 * beam.half_width_at(x) * x**k, 0.0, L)[0]
        assert got == pytest.approx(ref, rel=1e-10)
    # (int rho t phi dA)^2 is the truth's z mass participation (from M and the rigid DOF vector)
    np.testing.assert_allclose(g.translation_sqrt_kg**2,
                               truth.modal.mpf_z[truth.mode_index], rtol=1e-8)


def test_stepped_strip_gains_match_the_beam_with_a_station_at_the_step():
    # at the width step x = 0.4 m the plate's average runs over the wider side's full width
    beam = load_beam(BEAMS / "stepped-narrow.json")
    actuators = ((0.4, 0.8), (0.1, 0.4), (0.0, 1.0))
    gp = truth_modal_gains(compute_truth(beam, modes=4, static=False, error_tol_pct=None),
                           beam, actuators)
    gb = truth_modal_gains(compute_truth(beam, model="beam", modes=4, static=False,
                                         error_tol_pct=None), beam, actuators)
    scale = np.abs(gb.strain_per_sqrt_kg_m).max(axis=1, keepdims=True)
    # measured within 1.0 % of each actuator's largest gain, tips within 0.17 %
    assert np.all(np.abs(gp.strain_per_sqrt_kg_m - gb.strain_per_sqrt_kg_m) < 0.02 * scale)
    np.testing.assert_allclose(gp.tip_z_per_sqrt_kg, gb.tip_z_per_sqrt_kg, rtol=0.005)
