"""LQG design, closed loop and the slew problem against closed forms and an ODE solver."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp, trapezoid
from tolerances import EPS

from prbdm_pin.errors import BeamInputError
from prbdm_pin.plant.lqg import closed_loop, initial_response, lqg_compensator, quadratic_cost
from prbdm_pin.plant.slew import (
    SlewDesign,
    SlewPlant,
    settling_time_s,
    slew_controller,
    slew_scales,
)

J = 2.5  # kg m^2


def _double_integrator():
    A = np.array([[0.0, 1.0], [0.0, 0.0]])
    B = np.array([[0.0], [1.0 / J]])
    C = np.eye(2)
    return A, B, C


def test_lqr_gain_of_a_double_integrator_is_the_closed_form():
    # J theta'' = tau, cost q theta^2 + rho tau^2: K = [k1, sqrt(2 J k1)] with k1 = sqrt(q / rho)
    # (no rate weight), poles at (q / (rho J^2))^(1/4) with damping 1 / sqrt 2
    A, B, C = _double_integrator()
    q, rho = 4.0, 0.01
    comp = lqg_compensator(A, B, C, np.diag([q, 0.0]), np.array([[rho]]), np.eye(1),
                           np.eye(2))
    k1 = np.sqrt(q / rho)
    np.testing.assert_allclose(comp.state_gain, [[k1, np.sqrt(2.0 * J * k1)]],
                               rtol=1e-9)
    wn = (q / (rho * J**2)) ** 0.25
    np.testing.assert_allclose(np.abs(comp.regulator_poles), wn, rtol=1e-9)
    np.testing.assert_allclose(-comp.regulator_poles.real / wn, 1.0 / np.sqrt(2.0), rtol=1e-9)


def test_kalman_gain_of_a_scalar_system_is_the_closed_form():
    # x' = a x + b (u + w), y = x + v: P = (a + sqrt(a^2 + b^2 W / V)) V, L = P / V
    a, b, W, V = -0.7, 2.0, 3.0, 0.5
    comp = lqg_compensator(np.array([[a]]), np.array([[b]]), np.eye(1), np.eye(1),
                           np.eye(1), np.array([[W]]), np.array([[V]]))
    np.testing.assert_allclose(comp.estimator_gain, [[a + np.sqrt(a**2 + b**2 * W / V)]],
                               rtol=1e-9)


def _loop():
    A, B, C = _double_integrator()
    comp = lqg_compensator(A, B, C, np.diag([4.0, 0.0]), np.array([[0.01]]), np.eye(1),
                           1e-2 * np.eye(2))
    return A, B, C, comp


def test_initial_response_matches_an_ode_solver_and_the_cost_its_quadrature():
    A, B, C, comp = _loop()
    A_cl = closed_loop(A, B, C, comp)
    x0 = np.array([-0.1, 0.0, 0.0, 0.0])
    t = np.linspace(0.0, 60.0, 60001)
    X = initial_response(A_cl, x0, t)
    # the integrator's request: 4500 EPS (1e-12) relative, 4.5 EPS absolute (1e-15)
    ref = solve_ivp(lambda _t, x: A_cl @ x, (0.0, 60.0), x0, t_eval=t, method="DOP853",
                    rtol=4500 * EPS, atol=4.5 * EPS)
    np.testing.assert_allclose(X, ref.y.T, atol=1e-10)
    Q_cl = np.diag([1.0, 0.3, 0.0, 0.0])
    integrand = np.einsum("ti,ij,tj->t", X, Q_cl, X)
    assert X[-1] @ X[-1] < 1e-20  # the quadrature's tail is nothing
    assert quadratic_cost(A_cl, Q_cl, x0) == pytest.approx(trapezoid(integrand, t), rel=1e-6)


def test_an_unstable_loop_costs_inf_and_bad_shapes_are_refused():
    A, B, C, comp = _loop()
    assert quadratic_cost(closed_loop(A, -B, C, comp), np.eye(4), np.ones(4)) == np.inf
    with pytest.raises(BeamInputError, match="compensator"):
        closed_loop(A, np.hstack([B, B]), C, comp)
    with pytest.raises(BeamInputError, match="Q"):
        lqg_compensator(A, B, C, np.eye(3), np.eye(1), np.eye(1), np.eye(2))
    with pytest.raises(BeamInputError, match="t_s"):
        initial_response(A, np.ones(2), np.array([0.0, 1.0, 3.0]))


def test_slew_weights_put_a_rigid_hub_at_the_bandwidth_with_damping_1_over_sqrt2():
    # a rigid hub (no flexible state) and a strain actuator with no effect: the slew's scales
    # make the LQR's rigid poles omega_c e^(+-3i pi/4) whatever J and the slew angle
    A, B1, _ = _double_integrator()
    B = np.hstack([B1, np.zeros((2, 1))])
    C = np.array([[1.0, 0.0], [0.0, 1.0], [-1.1, 0.0], [0.0, -1.1]])
    plant = SlewPlant(A, B, C, np.zeros((1, 1)), J, 1.1, np.array([40.0]))
    design = SlewDesign(angle_rad=0.3, bandwidth_ratio=0.25, vibration_weight=0.0)
    scales = slew_scales(plant, design)
    assert scales.omega_c_rad_s == pytest.approx(10.0)
    poles = slew_controller(plant, design, scales).regulator_poles
    np.testing.assert_allclose(np.abs(poles), 10.0, rtol=1e-9)
    np.testing.assert_allclose(-poles.real / 10.0, 1.0 / np.sqrt(2.0), rtol=1e-9)


def test_settling_time_of_a_decaying_exponential():
    t = np.linspace(0.0, 10.0, 100001)
    ts = settling_time_s(t, 1.0 + np.exp(-t), 1.0, 0.02)
    assert ts == pytest.approx(np.log(50.0), abs=2e-4)
    assert settling_time_s(t, np.cos(t), 0.0, 0.02) == np.inf
    assert settling_time_s(t, np.zeros_like(t), 0.0, 0.02) == 0.0
