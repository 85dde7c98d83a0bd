"""The stated rule that picks an integrator for a scene: ``default_integrator``.

Measured by ``scripts/bench_compiled.py`` (docs/benchmarks/bench_compiled.md): the compiled
DOP853 (``"compiled"``) is an explicit scheme, so its step is held near h omega_max ~ 1.2-1.4
(the stiffest mode's stability and accuracy) and its cost grows as omega_max T, at about
12 dynamics evaluations of ~1 us per step; the exponential integrator propagates every linear
mode exactly, so from rest under a step load it keeps its nominal step T1/10 (cost ~ omega_1 T,
at ~150 us of Python per step), but a release from a bent pose drives its step control to its
smallest steps (10-50 times the compiled run's cost). Equating the two from rest gives the
crossover omega_max / omega_1 ~ 26: the 3R chain (ratio 18) is cheaper compiled, the 5R
(ratio 56) and 8R under a step load cheaper exponential.
"""

from __future__ import annotations

import numpy as np

from ..chain.eigen import eig_scaled
from ..options.integrators import Compiled, Exponential, Integrator
from .system import System, mass_matrix

__all__ = ["default_integrator", "STIFFNESS_RATIO_MAX", "COMPILED_RTOL"]

# omega_max / omega_1 above which a run from rest is cheaper exponential (the cost model above)
STIFFNESS_RATIO_MAX = 25.0
# reaches 0.01 % of the peak tip motion on every case of the benchmark (where the stability
# limit, not the tolerance, sets the step)
COMPILED_RTOL = 1e-6


def stiffness_ratio(system: System, q: np.ndarray) -> float:
    """Return omega_max / omega_1 of the sprung coordinates linearised at ``q`` (rad).

    A coordinate without a spring (a hub, a free bus) is eliminated (its rigid mode left out):
    the flexible modes are those of the mass's Schur complement over the sprung coordinates.
    """
    M = mass_matrix(system.pin_model, system.data, q)
    k = np.asarray(system.springs(q), dtype=float)
    flex = k > 0.0
    if not np.all(flex):
        rigid = ~flex
        M = M[np.ix_(flex, flex)] - M[np.ix_(flex, rigid)] @ np.linalg.solve(
            M[np.ix_(rigid, rigid)], M[np.ix_(rigid, flex)])
    w = eig_scaled(M, 1.0 / np.sqrt(k[flex]))
    return float(w[-1] / w[0])


def default_integrator(system: System, y0: np.ndarray) -> Integrator:
    """Return the integrator the rule picks for ``system`` from the state ``y0`` = (q, v).

    The rule (what ``scripts/bench_compiled.py`` measured):

    1. A scene the compiled kernel cannot serve (plant inputs or a base motion, a stiffness
       schedule, a tip force that varies in time): ``Exponential()``, the default today.
    2. A run that does not start from rest (a release from a bent pose, an initial velocity):
       ``Compiled(rtol=COMPILED_RTOL)``; the exponential integrator's step control takes its
       smallest steps on the higher modes such a start carries.
    3. From rest (a step load, the weight): ``Compiled(rtol=COMPILED_RTOL)`` when the chain's
       stiffness ratio omega_max / omega_1 at the start is at most ``STIFFNESS_RATIO_MAX``
       (25), ``Exponential()`` above it, where the explicit scheme's stiffest-mode steps cost
       more than the exponential integrator's T1/10.

    Parameters
    ----------
    system : System
        The assembled equations of motion (``system.assemble_system``).
    y0 : ndarray (2n,)
        Initial joint angles (rad) and velocities (rad/s).

    Returns
    -------
    Integrator
    """
    if system.inputs is not None or system.schedule is not None or (
            system.tip_force_N is not None and not system.constant_force):
        return Exponential()
    n = y0.size // 2
    if np.any(y0):
        return Compiled(rtol=COMPILED_RTOL)
    if stiffness_ratio(system, y0[:n]) <= STIFFNESS_RATIO_MAX:
        return Compiled(rtol=COMPILED_RTOL)
    return Exponential()
