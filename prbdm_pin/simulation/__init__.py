"""Time response of a PRBDM through Pinocchio.

The model carries joint springs, damping, a tip force and the plant's inputs (open loop or in
closed loop).

Equations of motion (relative joint angles q, rad; the hub angle first on a hub model):

    M(q) a + h(q, v) + K q + C v = J(q)^T F(t) + B(q) u(t, q, v)

with h the Coriolis/centrifugal terms and the weight (``gravity_m_s2``; none by default), K the
diagonal joint stiffness (zero for the hub), C a damping matrix (``prbdm_pin.simulation.damping``;
``prbdm_pin.simulation.hub_damping`` with a hub), J the world-aligned linear Jacobian of the tip
point and B the inputs' map (``inputs``: torques, strain
actuators, hub torque, tip forces, driven by a constant, a function of time, a controller or a
state-feedback gain).

``simulate`` (``driver``) checks the inputs, assembles the system (``system``: mass, springs,
damping frozen at one pose, tip force; ``schedule``: pose-dependent springs), starts the
integrator's stepper on it and runs that under the one shared loop (``loop``: steps, samples,
the step cap, progress). The integrators are values (``prbdm_pin.options.integrators``),
``simulate(model, 1.0, integrator=Gauss(dt_s=1e-3))``, or spelled by name,
``simulate(model, 1.0, method="gauss", dt_s=1e-3)``; one stepper module each:

- ``Auto`` (default, ``"auto"``, ``default_rule``): not a scheme but the stated rule that picks
  one per problem once the system is assembled, from the linearised equations at the start
  (stiffness, damping, start, the accuracy asked ``Auto(tolerance=1e-4)``, 0.01 % of the peak
  tip motion). Estimating the compiled DOP853's steps from the eigenvalues lambda of the
  first-order system (h |lambda| ~ 1 while a mode rings, ~4.5 once it has decayed, ~6 on an
  overdamped one) against the exponential integrator's T1/10 (one of its steps costs about 25
  compiled ones per 1/omega_1): ``Exponential()`` from rest when the compiled steps exceed
  25 omega_1 T (undamped: omega_max / omega_1 > 25, the 5R and up; with 2 % modal damping the
  8R), and on an overdamped release when they exceed 2.5 times that (2 % stiffness-form
  damping, the 8R); ``Compiled(rtol=tolerance / 100)`` otherwise: every undamped or lightly
  damped release, where the exponential integrator misses 0.01 % at 2-60 times the cost, and
  the chains up to 3R. A scene the kernel cannot serve (plant inputs, a base motion, a
  schedule, a time-varying force) gets ``Exponential()`` (scipy's DOP853 on a spinning hub).
  Measured on 1R-8R strips (``scripts/bench_default_rule.py``): within 0.01 % of the peak on
  every case, at 0.92-1.12 times the cheaper of the two from 2R up (1R: up to 1.31, the
  rule's ~0.1 ms on a 2 ms run).
  ``run.method`` and ``run.integrator`` record the integrator used.
- ``Exponential`` (``"exponential"``, ``exponential``): the exponential Rosenbrock
  method exprb32 with step-size control; every linear mode, however stiff, keeps its exact
  frequency and damping. Nominal step: lowest natural period at ``q0`` / 10. Not symplectic.
  ``Exponential(order=4)``: exprb43 (``exponential_rb43``), the cheaper one at tight
  tolerances (0.01 % of the peak on releases and step loads at ``step_rtol=3e-5``).
- ``Gauss`` (``"gauss"``, ``gauss``): 2-stage Gauss-Legendre, fixed step (period / 40), fourth
  order, symplectic: long undamped runs at large amplitude. A motion that swings the stiffest
  mode (a release from a bent pose) needs ``dt_s`` of at most 2 / omega_max.
- ``Trapezoidal`` (``"trapezoidal"``, ``newmark``): Newmark's average-acceleration rule, fixed
  step (period / 100), second order.
- ``ScipyIVP`` (``ivp``): a ``scipy.integrate`` solver, ``"DOP853"``, ``"RK45"``, ``"Radau"``, ...
- ``Compiled`` (``"compiled"``, ``compiled``): scipy's DOP853 (same steps, same accuracy for the
  same tolerances) run whole inside the compiled chain kernel (:mod:`prbdm_pin.kernel`, numba):
  10-15 times cheaper than ``"DOP853"``; constant springs, frozen damping, a constant tip force,
  gravity; no plant inputs, stiffness schedule, base motion or time-varying force.

Each module's docstring gives the scheme, its accuracy as measured and its limits; the
``Trajectory`` (``trajectory``) holds the samples, the tip positions and the integrator.
"""

from ..options.choices import FIXED_STEP_METHODS, IVP_METHODS
from ..options.integrators import (
    Auto,
    Compiled,
    Exponential,
    Gauss,
    Integrator,
    ScipyIVP,
    Trapezoidal,
)
from .driver import simulate
from .gauss import gauss_frequency_ratio
from .inputs import Controller, StateFeedback
from .schedule import StiffnessSchedule
from .system import mechanical_energy
from .trajectory import Trajectory

__all__ = [
    "Trajectory",
    "StiffnessSchedule",
    "Controller",
    "StateFeedback",
    "simulate",
    "Integrator",
    "Exponential",
    "Gauss",
    "Trapezoidal",
    "ScipyIVP",
    "Compiled",
    "Auto",
    "mechanical_energy",
    "gauss_frequency_ratio",
    "FIXED_STEP_METHODS",
    "IVP_METHODS",
]
