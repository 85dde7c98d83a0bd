"""A planar chain in gravity: its sag, its frequencies about the sag, its tips under the loads.

What a fit in gravity compares with the truth in the same gravity
(:mod:`prbdm_pin.fitting.gravity_target`). The sag q_g balances the springs against the weight,
K q_g + g(q_g) = 0 (:func:`prbdm_pin.plant.equilibrium.equilibrium`); about it the chain
vibrates with the stiffness K + dg/dq (q_g) (the Hessian of the gravity potential, Pinocchio's
``computeGeneralizedGravityDerivatives``: a hanging chain is stiffened, a standing one softened)
and the mass matrix M(q_g). A load case is the equilibrium under its dead tip force plus the
weight.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.linalg

from ..errors import SolveError
from ..plant.equilibrium import equilibrium, gravity_model, static_terms
from ..truth.self_weight import check_gravity

__all__ = ["ChainInGravity", "chain_in_gravity"]


class ChainInGravity(NamedTuple):
    """A chain evaluated in gravity.

    Attributes
    ----------
    sag_rad : ndarray (n,)
        The equilibrium under its weight alone, rad.
    omega_rad_s : ndarray (n,)
        Its natural frequencies about that pose, ascending, rad/s.
    tip_positions_m : ndarray (k, 3)
        Its tip under each dead tip force plus the weight, m, world.
    sag_tip_m : ndarray (3,)
        Its tip at the sag, m, world.
    """

    sag_rad: np.ndarray
    omega_rad_s: np.ndarray
    tip_positions_m: np.ndarray
    sag_tip_m: np.ndarray


def chain_in_gravity(model, gravity_m_s2, tip_forces_N=()) -> ChainInGravity:
    """Evaluate a clamped planar PRBDM in gravity.

    Parameters
    ----------
    model : PrbdmModel
        Clamped, planar (joints about y).
    gravity_m_s2 : array_like (3,)
        Gravity, m/s^2, world (g_y = 0).
    tip_forces_N : sequence of array_like (3,)
        Dead tip forces, N, world: one load case each, under the weight as well.

    Returns
    -------
    ChainInGravity

    Raises
    ------
    SolveError
        No equilibrium, or a chain that buckles under its weight (K + dg/dq not positive
        definite at the sag).
    """
    g = check_gravity(gravity_m_s2)
    pm_g = gravity_model(model, g)
    zero = np.zeros(3)
    q, _ = equilibrium(model, zero, pm_g)
    data_g = None if pm_g is None else pm_g.createData()
    _, H = static_terms(model, q, zero, pm_g, data_g)
    H = 0.5 * (H + H.T)  # a Hessian: symmetric up to rounding
    lam = scipy.linalg.eigh(H, model.mass_matrix(q), eigvals_only=True)
    if not lam[0] > 0.0:
        raise SolveError(f"the chain buckles under its weight in gravity {g.tolist()} m/s^2 "
                         f"(lowest omega^2 {lam[0]:.3g} (rad/s)^2 about its sag)")
    tips = [model.tip_position(equilibrium(model, np.asarray(F, dtype=float), pm_g)[0])
            for F in tip_forces_N]
    return ChainInGravity(q, np.sqrt(lam), np.array(tips).reshape(-1, 3),
                          model.tip_position(q))
