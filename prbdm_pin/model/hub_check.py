"""A warning for a hub so light that the model leaves the regime it was fitted in.

A PRBDM is fitted to the clamped truth. On a hub, its modes move toward those of the pinned-free
beam as the hub's inertia J_h falls against the member's own inertia about the hub axis J_beam
(with no hub, J_h = 0, the root turns freely: mode 1 of a uniform strip rises from beta L = 1.875
to 3.927, 4.4 times the frequency). The chain's links and springs were chosen for the clamped
modes, so its error on the hub's modes grows with how far the hub moves them.

The estimate: the first flexible frequency of the model on its hub against the same chain
clamped (both from the model itself, two small eigensolves), as a shift
``100 (omega_hub / omega_clamped - 1)`` %. Measured on 3R and 5R joint fits of the uniform
strip against the 1D truth's hybrid plant (``truth.plant.hybrid``), mode 1's error with the
hub is 2-4 % of that shift: J_h = 10 J_beam moves mode 1 by 4.8 % (error 0.09 %), J_h = J_beam
by 41 % (0.9 %), J_h = J_beam / 10 by 210 % (9 %). A shift above ``LIGHT_HUB_SHIFT_PCT``
(25 %, J_h below about 2 J_beam) therefore puts mode 1's expected error near the 1 % beyond
which a fit warns of its exported model (``fitting.result.EXPORT_WARN_PCT``): a
:class:`LightHubWarning` says so, with the shift and the inertia ratio.
"""

from __future__ import annotations

import warnings

import numpy as np

__all__ = ["LightHubWarning", "LIGHT_HUB_SHIFT_PCT", "hub_shift", "warn_light_hub"]

# mode 1's shift on the hub beyond which its expected error reaches ~1 % (2-4 % of the shift)
LIGHT_HUB_SHIFT_PCT = 25.0


class LightHubWarning(UserWarning):
    """A hub light enough that a model fitted to the clamped truth loses accuracy on it.

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> issubclass(pp.LightHubWarning, UserWarning)
    True
    """


def hub_shift(model) -> tuple[float, float, float, float]:
    """Return how far the hub moves mode 1 of ``model`` (a PrbdmModel with a hub).

    Returns
    -------
    shift_pct : float
        100 (omega_hub / omega_clamped - 1), %: mode 1 on the hub against the chain clamped.
    omega_clamped, omega_hub : float
        The two first flexible frequencies, rad/s.
    inertia_ratio : float
        J_h / J_beam: the hub's inertia over the chain's own about the hub axis.
    """
    from ..chain.eigen import eig_scaled
    from .hub import hub_frequencies

    M = model.mass_matrix()
    k = model.stiffness_Nm_per_rad
    w_hub = float(hub_frequencies(M, k)[1])
    w_clamped = float(eig_scaled(M[1:, 1:], 1.0 / np.sqrt(k))[0])
    J_h = model.hub.inertia_kg_m2
    J_beam = float(M[0, 0]) - J_h
    return 100.0 * (w_hub / w_clamped - 1.0), w_clamped, w_hub, J_h / J_beam


def warn_light_hub(model, stacklevel: int = 3) -> None:
    """Warn (:class:`LightHubWarning`) when the hub moves mode 1 by more than 25 %.

    See the module notes for the estimate and the threshold ``LIGHT_HUB_SHIFT_PCT``.
    """
    shift, w_c, w_h, ratio = hub_shift(model)
    if shift <= LIGHT_HUB_SHIFT_PCT:
        return
    warnings.warn(
        f"hub inertia_kg_m2 = {model.hub.inertia_kg_m2:g} is {ratio:.3g} times the member's "
        f"inertia about the hub axis: it moves mode 1 from {w_c:.6g} rad/s (clamped) to "
        f"{w_h:.6g} rad/s (+{shift:.3g} %), toward the pinned-free beam, where a model fitted "
        f"to the clamped truth errs by about 2-4 % of that shift (about {0.03 * shift:.2g} % "
        "on mode 1); compare with the hub truth (prbdm linearize --compare-truth, "
        "prbdm_pin.compare_plant), or use a heavier hub",
        LightHubWarning, stacklevel=stacklevel)
