"""The measures of a slew study (``scripts/ccd_slew.py``).

The hub inertia that stiffens the truth's first mode by a given ratio, the open-loop FRF errors
of a PRBDM slew plant against the
truth's, the closed-loop response's settling and residual vibration, and each strain actuator
map of a PRBDM on a hub (``MAPS``: virtual work, fitted to the truth's modal gains, fitted to
its strain -> tip z residues).
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import brentq

from ..model.inputs import StrainActuator, virtual_work_map
from ..simulation.response import relative_l2
from . import slew
from .actuator_fit import fitted_weights

__all__ = ["MAPS", "PAIRS", "PAIR_NAMES", "hub_inertia_for_stiffening", "patch_actuators",
           "frf_errors", "slew_metrics"]

MAPS = ("virtual-work", "fitted", "fitted-tip_z")
PAIRS = [(i, o) for i in range(2) for o in range(4)]
PAIR_NAMES = [f"{slew.INPUTS[i].split('[')[0]}->{slew.OUTPUTS[o]}" for i, o in PAIRS]


def hub_inertia_for_stiffening(gains, radius_m: float, ratio: float) -> float:
    """Return the hub inertia J_h (kg m^2) that stiffens the truth's first mode by ``ratio``.

    At J_h the truth's first hub-stiffened mode is ``ratio`` times its first clamped mode
    (brentq on log J_h; omega_1 falls monotonically to the clamped value).
    """
    from ..truth.plant import hub_frequencies_rad_s, hybrid_matrices

    def gap(log_j: float) -> float:
        M, K, _, _ = hybrid_matrices(gains, float(np.exp(log_j)), radius_m)
        return hub_frequencies_rad_s(M, K)[1] / gains.omega_rad_s[0] - ratio
    j_beam = gains.second_moment_kg_m2 + gains.mass_kg * radius_m**2
    lo, hi = np.log(j_beam) - 20.0, np.log(j_beam) + 20.0
    return float(np.exp(brentq(gap, lo, hi, xtol=1e-12)))


def patch_actuators(model, gains, stations, kind: str) -> tuple[StrainActuator, ...]:
    """Return the patches ``stations`` ((x_a, x_b), m) as actuators of ``model``.

    ``kind`` is the map (``MAPS``); ``gains``: the truth's modal gains of the stations followed
    by the ``profile_stations`` (see ``fitted_weights``).
    """
    if kind == "virtual-work":
        # written out as weights: a patch between joints gets the map's zero input, which the
        # study compares with the fitted maps (an unweighted one is refused: it would drive
        # nothing)
        return tuple(StrainActuator(a, b, joint_weights=tuple(virtual_work_map(
            model.lengths_m, a, b))) for a, b in stations)
    W = fitted_weights(model, gains, "tip_z" if kind == "fitted-tip_z" else "modal")
    return tuple(StrainActuator(a, b, joint_weights=tuple(w))
                 for (a, b), w in zip(stations, W, strict=True))


def frf_errors(lin, truth: slew.SlewPlant, n: int, start_frac: float) -> np.ndarray:
    """Return the relative L2 FRF error of each input/output pair (``PAIRS``).

    Of a PRBDM ``LinearModel`` against the truth's slew plant over
    [start_frac omega_1, 1.2 omega_n] (linear grid).
    """
    w_t = truth.frequencies_rad_s
    w = np.linspace(start_frac * w_t[0], 1.2 * w_t[min(n, w_t.size) - 1], 4000)
    eye = np.eye(truth.A.shape[0])
    H_t = np.array([truth.C @ np.linalg.solve(1j * wi * eye - truth.A, truth.B) for wi in w])
    H_p = lin.frequency_response(w)
    return np.array([relative_l2(H_p[:, o, i], H_t[:, o, i]) for i, o in PAIRS])


def slew_metrics(resp: slew.SlewResponse, angle_rad: float, wc: float,
                 residual_per_wc: float) -> dict:
    """Return the closed-loop measures of a slew.

    Settling times (2 % band, s), the peak residual tip vibration after ``residual_per_wc``
    / omega_c (m), the peak tip vibration (m), the cost and the largest pole real part.
    """
    w = resp.tip_vibration_m
    late = resp.t_s >= residual_per_wc / wc
    return {"settle_hub_s": slew.settling_time_s(resp.t_s, resp.hub_angle_rad, angle_rad,
                                                 0.02 * angle_rad),
            "settle_tip_s": slew.settling_time_s(resp.t_s, w, 0.0, 0.02 * np.abs(w).max()),
            "residual_tip_m": float(np.abs(w[late]).max()), "peak_tip_m": float(np.abs(w).max()),
            "cost": resp.cost, "max_pole": resp.max_real_pole_rad_s}
