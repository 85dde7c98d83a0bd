"""The stated rule that picks an integrator for a scene: ``default_integrator``.

``simulate``'s default integrator, :class:`~prbdm_pin.options.integrators.Auto`, is replaced by
what this rule picks once the system is assembled. It compares two cost estimates read from the
linearised equations at the start, both measured by ``scripts/bench_compiled.py`` and
``scripts/bench_default_rule.py`` (docs/benchmarks.md; CPU per simulated second, 1R-8R strips,
step loads and releases, undamped, 2 % modal and 2 % stiffness-form damping):

- the compiled DOP853 (``"compiled"``) is explicit: ~20-26 us per step whatever n, and its
  step is held by the stiffest eigenvalues lambda of the first-order system. An oscillating
  mode holds h |lambda| ~ 1 while it is excited (accuracy, at rtol 1e-6; the step grows as
  rtol^(1/8)) and ~4.5 once it has decayed (DOP853's stability along the imaginary axis); a
  real (overdamped) one h |lambda| ~ 6 (stability on the negative real axis). Undamped, its
  steps are ~omega_max T (measured 0.86-0.99 omega_max T for 2R-8R); 2 % modal damping lets
  the step grow after ~ln(0.1 / tolerance) / (zeta omega_max) (3R 480, 5R 828, 8R 1,703 steps
  per s against 506, 955, 1,975 estimated); the stiffness form's overdamped top modes hold
  it at |lambda| / 6 (8R 6,722 against 7,154);
- the exponential integrator (``"exponential"``) propagates every linear mode exactly: from
  rest it keeps its nominal step T1/10 (85-116 steps per s, ~220 us each, 19-23 ms per
  simulated second for 1R-8R, error below 2e-5 % of the peak); on a release its step
  control takes small steps on the higher modes the bent start carries (3R-8R undamped
  0.05-0.08 % off at 10-60 times the compiled cost; 2 % modal damping 0.014-0.035 % off),
  except where damping makes the top modes overdamped (the stiffness form on 5R and 8R:
  0.002-0.003 % off at ~1.7-2.5 times its cost from rest).

With omega_1 the lowest flexible frequency and T the duration, one exponential step costing
about 25 compiled steps' worth per 1/omega_1 of simulated time (undamped, the measured crossover
omega_max / omega_1 ~ 25: the 3R, ratio 18, is as cheap either way, the 5R, ratio 56, three
times cheaper exponential), the rule picks the compiled scheme when its estimated steps are at
most ``STIFFNESS_RATIO_MAX`` omega_1 T from rest, ``RELEASE_COST`` times that on a release
that the exponential integrator follows to the tolerance.
"""

from __future__ import annotations

import math

import numpy as np

from ..chain.eigen import eig_scaled
from ..options.integrators import Auto, Compiled, Exponential, Integrator, ScipyIVP
from .system import System, mass_matrix, static_angle_rad, weight_angle_rad

__all__ = ["default_integrator", "compiled_steps", "stiffness_ratio", "STIFFNESS_RATIO_MAX",
           "RELEASE_COST"]

# compiled steps per omega_1 T above which the exponential integrator is cheaper from rest (its
# ~220 us step against the compiled ~20 us, T1/10 against h omega_max ~ 1: bench_compiled)
STIFFNESS_RATIO_MAX = 25.0
# an overdamped release costs the exponential integrator 1.7-2.5 times its cost from rest
RELEASE_COST = 2.5
# h |lambda| of the compiled DOP853 (rtol 1e-6) while a mode is excited (accuracy), once it has
# decayed (stability along the imaginary axis) and on a real eigenvalue (along the real axis):
# fitted on the measured steps (the module docstring)
H_ACCURACY, H_IMAGINARY, H_REAL = 1.0, 4.5, 6.0
# the largest tip error relative to the peak the exponential integrator reached, measured: from
# rest (1.6e-5 % on the 8R) and on an overdamped release (0.0034 %, the 8R)
EXPONENTIAL_REST_ERROR, EXPONENTIAL_RELEASE_ERROR = 1e-6, 1e-4
# the largest static joint angle of an undamped step load (the load's torque over the springs)
# at which the exponential integrator is trusted from rest: its linearised step control meets
# 2e-7 of the peak at 3e-4 rad (the strip's 0.5 N, bench_default_rule.py) but 1.1-2.1e-3 at
# 0.06-0.14 rad (2500 N on the reference random beam's 3R-8R, bench_mujoco_accuracy.py), the
# error growing as about the angle^1.8: 1e-4 near 0.011 rad, halved for margin. With damping
# it met 1e-4 at 0.1 rad (6e-5 and 9e-5 on the damped 5R and 8R there).
LINEAR_ANGLE_RAD = 0.005


def stiffness_ratio(system: System, q: np.ndarray) -> float:
    """Return omega_max / omega_1 of the sprung coordinates linearised at ``q`` (rad).

    A coordinate without a spring (a hub, a free bus) is eliminated (its rigid mode left out):
    the flexible modes are those of the mass's Schur complement over the sprung coordinates.
    """
    w = _flexible_frequencies(system, q)
    return float(w[-1] / w[0])


def _flexible_frequencies(system: System, q: np.ndarray, M: np.ndarray | None = None
                          ) -> np.ndarray:
    M = mass_matrix(system.pin_model, system.data, q) if M is None else M
    k = np.asarray(system.springs(q), dtype=float)
    flex = k > 0.0
    if not np.all(flex):
        rigid = ~flex
        M = M[np.ix_(flex, flex)] - M[np.ix_(flex, rigid)] @ np.linalg.solve(
            M[np.ix_(rigid, rigid)], M[np.ix_(rigid, flex)])
    # one solve per run: LAPACK's, since the compiled solve's first load costs ~0.25 s (a run
    # the rule gives the exponential integrator then loads no numba at all)
    return eig_scaled(M, 1.0 / np.sqrt(k[flex]), compiled=False)


def _eigenvalues(system: System, q: np.ndarray, M: np.ndarray) -> np.ndarray:
    """Eigenvalues (1/s) of the first-order system [[0, I], [-M^-1 K, -M^-1 C]] at ``q``."""
    n = M.shape[0]
    C = system.damping_Nms_per_rad
    KC = np.hstack((np.diag(np.asarray(system.springs(q), dtype=float)),
                    np.zeros((n, n)) if C is None else C))
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, KC)]])
    return np.linalg.eigvals(A)


def compiled_steps(system: System, q: np.ndarray, duration_s: float,
                   tolerance: float = 1e-4) -> float:
    """Return the estimated steps of ``Compiled(rtol=tolerance / 100)`` over ``duration_s``.

    Parameters
    ----------
    system : System
        The assembled equations of motion.
    q : ndarray (n,)
        The start pose, rad, where the equations are linearised.
    duration_s : float
        Simulated time, s.
    tolerance : float
        The accuracy asked (fraction of the peak tip motion).

    Returns
    -------
    float
        The largest over the eigenvalues lambda of: |lambda| t / H_ACCURACY (scaled by the
        order-8 law (tolerance / 1e-4)^(-1/8)) over the ``t`` an oscillating mode takes to
        decay by ``ln(0.1 / tolerance)`` e-folds, plus |lambda| / H_IMAGINARY over the rest;
        |lambda| T / H_REAL for a real one.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> from prbdm_pin.simulation.default_rule import compiled_steps
    >>> from prbdm_pin.simulation.system import assemble_system
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.5, 0.5], [2500.0])
    >>> sy = assemble_system(model, np.zeros(1), damping_ratios=np.zeros(1), damping="modal",
    ...                      schedule=None, tip_force_N=None, constant_force=True,
    ...                      damping_pose=None, inputs=None)
    >>> w = float(np.sqrt(2500.0 / model.mass_matrix()[0, 0]))  # rad/s, the 1R's frequency
    >>> bool(abs(compiled_steps(sy, np.zeros(1), 1.0) - w) < 1e-9 * w)  # undamped: omega T
    True
    """
    return _steps(_eigenvalues(system, q, mass_matrix(system.pin_model, system.data, q)),
                  duration_s, tolerance)


def _steps(lam: np.ndarray, duration_s: float, tolerance: float) -> float:
    h_acc = H_ACCURACY * (tolerance / 1e-4) ** 0.125
    folds = math.log(0.1 / tolerance)
    steps = 0.0
    for z in lam:
        r = abs(z)
        if r == 0.0:
            continue
        sigma = -z.real
        if abs(z.imag) <= 1e-9 * r:  # a real eigenvalue: an overdamped mode
            steps = max(steps, r * duration_s / H_REAL)
            continue
        t_d = duration_s if sigma <= 0.0 else min(duration_s, folds / sigma)
        steps = max(steps, r * t_d / h_acc + r * (duration_s - t_d) / H_IMAGINARY)
    return steps


def _overdamped(lam: np.ndarray) -> bool:
    """Whether the stiffest mode is overdamped (a real eigenvalue beyond omega_max)."""
    real = np.abs(lam.imag) <= 1e-9 * np.abs(lam)
    w_max = float(np.max(np.abs(lam.imag)))
    return bool(np.any(real & (np.abs(lam) >= w_max) & (np.abs(lam) > 0.0)))


def _nearly_linear(system: System, q: np.ndarray) -> bool:
    """Whether a step from rest at ``q`` stays where the exponential integrator is trusted.

    Damped, or the static joint angle of the load and the weight at most ``LINEAR_ANGLE_RAD``.
    """
    if system.damping_Nms_per_rad is not None:
        return True
    k = system.springs(q)
    angle = max(static_angle_rad(system.tau_external(q, 0.0), k), weight_angle_rad(system, q))
    return angle <= LINEAR_ANGLE_RAD


def default_integrator(system: System, y0: np.ndarray, duration_s: float = 1.0,
                       auto: Auto | None = None, spinning: bool = False) -> Integrator:
    """Return the integrator the rule picks for ``system`` from the state ``y0`` = (q, v).

    The rule (what ``scripts/bench_compiled.py`` and ``scripts/bench_default_rule.py``
    measured; the module docstring has the numbers):

    1. A scene the compiled kernel cannot serve (plant inputs or a base motion, a stiffness
       schedule, a tip force that varies in time): ``Exponential()``; on a spinning hub,
       which the exponential integrator refuses, scipy's ``DOP853`` at ``tolerance / 100``.
    2. From rest (a step load, the weight), when ``tolerance`` >= 1e-6 (the exponential
       integrator's error from rest stays below 2e-7 of the peak): ``Exponential()`` if the
       compiled scheme's estimated steps (:func:`compiled_steps`) exceed
       ``STIFFNESS_RATIO_MAX`` (25) omega_1 T (undamped: omega_max / omega_1 > 25; with 2 %
       modal damping the 8R; with 2 % stiffness-form damping the 8R), and the run is damped or
       the load's static joint angle is at most ``LINEAR_ANGLE_RAD`` (0.005 rad: an undamped
       large step load, 0.06-0.14 rad, took the exponential integrator 0.1-0.2 % off).
    3. A release or an initial velocity whose stiffest mode is overdamped (stiffness-form
       damping on 5R and more joints), when ``tolerance`` >= 1e-4: ``Exponential()`` if the
       estimated steps exceed ``RELEASE_COST`` (2.5) times 25 omega_1 T (the 8R).
    4. Otherwise ``Compiled(rtol=tolerance / 100)``: reaches the tolerance on every measured
       case (rtol 1e-6: at most 4e-5 % of the peak), where the exponential integrator's step
       control, on an undamped or lightly damped release, misses 0.01 % at 2-60 times the cost.

    Parameters
    ----------
    system : System
        The assembled equations of motion (``system.assemble_system``).
    y0 : ndarray (2n,)
        Initial joint angles (rad) and velocities (rad/s).
    duration_s : float
        Simulated time, s.
    auto : Auto, optional
        The accuracy asked (default ``Auto()``: 0.01 % of the peak tip motion).
    spinning : bool
        The run starts from a hub's steady spin (``simulate(spin_rad_s=...)``).

    Returns
    -------
    Integrator

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> from prbdm_pin.simulation.default_rule import default_integrator
    >>> from prbdm_pin.simulation.system import assemble_system
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> sy = assemble_system(model, np.zeros(2), damping_ratios=np.zeros(2), damping="modal",
    ...                      schedule=None, tip_force_N=None, constant_force=True,
    ...                      damping_pose=None, inputs=None)
    >>> default_integrator(sy, np.array([0.01, 0.0, 0.0, 0.0]))  # a release of a 2R
    Compiled(rtol=1e-06, atol=None)
    """
    tol = (auto or Auto()).tolerance
    rtol = tol / 100.0
    if system.inputs is not None or system.schedule is not None or (
            system.tip_force_N is not None and not system.constant_force):
        return ScipyIVP("DOP853", rtol=rtol) if spinning else Exponential()
    n = y0.size // 2
    q = y0[:n]
    release = bool(np.any(y0))
    if release and (tol < EXPONENTIAL_RELEASE_ERROR or spinning
                    or system.damping_Nms_per_rad is None):
        return Compiled(rtol=rtol)  # only an overdamped release is the exponential one's
    M = mass_matrix(system.pin_model, system.data, q)
    budget = STIFFNESS_RATIO_MAX * float(_flexible_frequencies(system, q, M)[0]) * duration_s
    if release:
        lam = _eigenvalues(system, q, M)
        if _overdamped(lam) and _steps(lam, duration_s, tol) > RELEASE_COST * budget:
            return Exponential()
    elif tol >= EXPONENTIAL_REST_ERROR and _nearly_linear(system, q) and _steps(
            _eigenvalues(system, q, M), duration_s, tol) > budget:
        return Exponential()
    return Compiled(rtol=rtol)
