"""Objectives (Eqs. 16-19, 25-27) against hand-computed values, including closed-form 1R models."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq
from tolerances import EPS

from prbdm_pin.fitting import objectives as ob
from prbdm_pin.fitting.evaluate import evaluate
from prbdm_pin.fitting.problem import make_problem
from prbdm_pin.fitting.target import FitTarget
from prbdm_pin.member.geometry import Beam
from prbdm_pin.member.material import Material
from prbdm_pin.options.objects import FitOptions


def test_eigen_errors_hand_values():
    truth = np.array([1.0, 2.0])
    model = np.array([[1.0, 2.0, 9.0], [1.0, 2.2, 9.0], [0.9, 2.0, 9.0]])
    # hand values: each side a handful of roundings of decimal inputs (<= 4.3 EPS measured);
    # kept: the tests' 1e-14, 1e-13, 1e-12 as 50, 500, 5000 EPS
    e = ob.eigen_errors(model, truth)
    assert e == pytest.approx([0.0, 0.2 / math.sqrt(5.0), 0.1 / math.sqrt(5.0)], rel=50 * EPS)
    assert ob.eigen_loss_pct(model, truth) == pytest.approx(100 * 0.3 / math.sqrt(5) / 3)
    # omega^2: |4.84 - 4| / sqrt(1 + 16)
    e2 = ob.eigen_errors(model[:2], truth, squared=True)
    assert e2 == pytest.approx([0.0, 0.84 / math.sqrt(17.0)], rel=50 * EPS)


def test_best_scale_is_the_exact_one_dimensional_least_squares():
    truth = np.array([3.0, 7.0, 11.0])
    w = np.array([[1.0, 2.0, 4.0], [3.0, 7.0, 11.0]]) / 2.0
    # hand values: as in test_eigen_errors_hand_values (kept bounds)
    k = ob.best_scale(w, truth)
    # sqrt(k) = f.w / w.w
    assert k[1] == pytest.approx(4.0, rel=50 * EPS)
    assert math.sqrt(k[0]) == pytest.approx((3 + 14 + 44) / (1 + 4 + 16) * 2.0, rel=50 * EPS)
    e = ob.projected_eigen_errors(w, truth)
    assert e[1] == pytest.approx(0.0, abs=1e-15)
    # no other factor does better
    for c in np.linspace(0.5, 2.0, 31):
        assert e[0] <= ob.eigen_errors(w[:1] * math.sqrt(c * k[0]), truth)[0] + 1e-15
    # squared: k = f^2.w^2 / w^2.w^2
    k2 = ob.best_scale(w, truth, squared=True)
    f2, w2 = truth**2, w[0] ** 2
    assert k2[0] == pytest.approx(f2 @ w2 / (w2 @ w2), rel=50 * EPS)


def test_relative_norm_hand_values():
    truth = np.array([1.0, 2.0, 4.0])
    model = np.array([[1.1, 2.0, 3.6, 50.0], [1.0, 2.0, 4.0, 9.0]])
    # hand values: as in test_eigen_errors_hand_values (kept bounds)
    # sqrt(mean_k ((w_k - t_k) / t_k)^2): the 10 % errors of modes 1 and 3 count equally
    assert ob.eigen_errors(model, truth, norm="relative") == pytest.approx(
        [math.sqrt((0.01 + 0.0 + 0.01) / 3.0), 0.0], rel=50 * EPS)
    assert ob.eigen_loss_pct(model, truth, norm="relative") == pytest.approx(
        100 * math.sqrt(0.02 / 3.0) / 2, rel=50 * EPS)
    # Eq. 16 weighs mode 3's 0.4 rad/s above mode 1's 0.1 rad/s
    assert ob.eigen_errors(model, truth)[0] == pytest.approx(
        math.sqrt(0.1**2 + 0.4**2) / math.sqrt(21.0), rel=50 * EPS)
    # omega^2: ((1.21 - 1) / 1, 0, (12.96 - 16) / 16)
    e2 = ob.eigen_errors(model[:1], truth, squared=True, norm="relative")[0]
    assert e2 == pytest.approx(math.sqrt((0.21**2 + 0.19**2) / 3.0), rel=50 * EPS)
    # signed per-mode errors in omega, whatever the norm
    pm = ob.mode_errors_pct(model, truth)
    assert pm == pytest.approx(np.array([[10.0, 0.0, -10.0], [0.0, 0.0, 0.0]]), abs=1e-12)
    assert ob.worst_mode_error_pct(pm) == pytest.approx(10.0, rel=5000 * EPS)
    with pytest.raises(ValueError, match="eigen_norm"):
        ob.eigen_errors(model, truth, norm="l1")


@pytest.mark.parametrize("squared", [False, True])
def test_relative_best_scale_is_its_own_closed_form(squared):
    from scipy.optimize import minimize_scalar

    truth = np.array([3.0, 7.0, 11.0])
    w = np.array([[1.0, 2.0, 4.0], [1.5, 3.5, 5.5]])
    # hand values: as in test_eigen_errors_hand_values (kept bounds)
    k = ob.best_scale(w, truth, squared=squared, norm="relative")
    # the second pose is the truth scaled by 1/2 in omega: k = 4 exactly
    assert k[1] == pytest.approx(4.0, rel=500 * EPS)
    # the first against a bounded scalar minimisation of the hand-written relative rms
    p = 2 if squared else 1

    def rms(kk):
        return math.sqrt(np.mean((((math.sqrt(kk) * w[0]) ** p - truth**p) / truth**p) ** 2))

    ref = minimize_scalar(rms, bounds=(0.1, 100.0), method="bounded",
                          options={"xatol": 1e-12}).x
    assert k[0] == pytest.approx(ref, rel=1e-6)
    # ... and it differs from the Eq. 16 optimum
    assert abs(k[0] / ob.best_scale(w, truth, squared=squared)[0] - 1) > 1e-3
    e = ob.projected_eigen_errors(w, truth, squared=squared, norm="relative")
    assert e[0] == pytest.approx(rms(k[0]), rel=5000 * EPS) and e[1] == pytest.approx(0, abs=1e-14)


def test_tip_errors_hand_values():
    truth = np.array([0.9, 0.0, -0.4])
    disp = truth - np.array([1.0, 0.0, 0.0])
    model = np.array([[0.9, 0.0, -0.4], [0.93, 0.0, -0.36]])
    # hand values: as in test_eigen_errors_hand_values (kept bounds)
    pos = ob.tip_position_errors(model, truth)
    assert pos == pytest.approx([0.0, 0.05 / math.sqrt(0.97)], rel=500 * EPS)
    d = ob.tip_displacement_errors(model, truth, disp)
    assert d == pytest.approx([0.0, 0.05 / math.sqrt(0.17)], rel=500 * EPS)


def test_scf_statistics_and_knee():
    k = np.array([1.0, 2.0, 3.0])
    assert ob.scf_mean(k) == 2.0
    assert ob.scf_deviation_pct(k) == pytest.approx([-50.0, 0.0, 50.0])
    F = np.array([[0.1, 9.0], [1.0, 1.5], [3.0, 0.2]])
    assert ob.knee_index(F) == 1
    assert ob.combined_loss_pct(3.0, 4.0) == pytest.approx(5.0)


# --- closed-form 1R models ----------------------------------------------------------------------
B_M, T_M, L_M = 0.05, 0.01, 1.0
MAT = Material()


def _uniform_beam(force=(0.0, 0.0, -100.0)) -> Beam:
    return Beam([0.0, L_M], [B_M / 2, B_M / 2], T_M, MAT, np.array(force))


def _link_inertia_about_joint(ell: float) -> float:
    # rigid rectangular link of length ell, hinged at one end, rotating about y:
    # m ell^2 / 3 (along x) + m t^2 / 12 (through the thickness)
    m = MAT.rho_kg_m3 * B_M * T_M * ell
    return m * ell**2 / 3.0 + m * T_M**2 / 12.0


@pytest.mark.parametrize("a", [0.3, 0.5])
def test_1r_frequency_closed_form(a):
    beam = _uniform_beam()
    ell = L_M - a
    EI = MAT.E_Pa * B_M * T_M**3 / 12.0
    # finite-segment stiffness of 1R: the one spring spans the whole beam (from the clamp to the
    # tip: the end links count from the clamp and to the tip), E / int_0^L dx/I = EI / L
    K = EI / L_M
    omega = math.sqrt(K / _link_inertia_about_joint(ell))
    truth = FitTarget([1.1 * omega], beam.tip_force_N)
    prob = make_problem(beam, truth, 1, FitOptions(stiffness="joint", eigen_norm="paper"))
    for s in (1.0, 2.5):
        ev = evaluate(prob, np.array([a, ell]), np.array([s]), deflection=False)
        assert ev.omega_model_rad_s[0, 0] == pytest.approx(math.sqrt(s) * omega, rel=1e-10)
        assert ev.eigen_loss_pct == pytest.approx(
            100 * abs(math.sqrt(s) - 1.1) / 1.1, rel=1e-9)


@pytest.mark.parametrize("P", [50.0, 400.0])
def test_1r_deflection_closed_form(P):
    beam = _uniform_beam((0.0, 0.0, -P))
    a, ell = 0.25, 0.75
    EI = MAT.E_Pa * B_M * T_M**3 / 12.0
    K = 0.3 * EI / L_M  # a soft spring (the finite-segment 1R spring is EI / L): large rotation
    # equilibrium of a rigid link under a transverse dead load: K theta = P ell cos(theta)
    theta = brentq(lambda th: K * th - P * ell * math.cos(th), 0.0, math.pi / 2)
    tip = np.array([a + ell * math.cos(theta), 0.0, -ell * math.sin(theta)])
    truth_tip = tip + np.array([0.01, 0.0, -0.02])
    disp = truth_tip - np.array([L_M, 0.0, 0.0])
    target = FitTarget([10.0], beam.tip_force_N, truth_tip, disp)
    prob = make_problem(beam, target, 1, FitOptions(stiffness="joint", eigen_norm="paper"))
    ev = evaluate(prob, np.array([a, ell]), np.array([0.3]), deflection=True)
    assert ev.tip_position_m[0] == pytest.approx(tip, abs=1e-9)
    assert ev.deflection_loss_pct == pytest.approx(
        100 * math.hypot(0.01, 0.02) / np.linalg.norm(truth_tip), rel=1e-6)
    assert ev.displacement_loss_pct == pytest.approx(
        100 * math.hypot(0.01, 0.02) / np.linalg.norm(disp), rel=1e-6)
