"""The damping an export carries: the form asked, the form written, and the ratios it gives.

Three forms (:data:`~prbdm_pin.options.choices.EXPORT_DAMPING_FORMS`):

- ``"stiffness"``: C = beta K, beta = 2 xi_1 / omega_1 (diagonal: every format carries it);
- ``"modal"``: every mode its own ratio; only JSON records it (URDF and MJCF joint damping is
  diagonal, and this C is not);
- ``"modal_fit"``: the diagonal joint damping c >= 0 fitted by least squares to the per-mode
  ratios (:mod:`prbdm_pin.simulation.modal_fit`), with the ratios it achieves (from the damped
  chain's complex eigenvalues) and each mode's error against the asked ratio; a mode that
  misses by more than :data:`MODAL_FIT_WARN_PCT` % of its asked ratio is warned about.

URDF and MJCF default to ``"modal_fit"`` when given ratios that differ between modes (a
calibrated model's), to ``"stiffness"`` otherwise; asked for ``"modal"`` with one ratio for every
mode they write the stiffness form and warn, with ratios that differ the fitted form and warn.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..simulation.modal_fit import modal_fit_damping
from .export_plant import stiffness_form

__all__ = ["MODAL_FIT_WARN_PCT", "ExportDamping", "default_form", "export_damping"]

# A fitted mode whose achieved ratio is off its asked one by more than this share of it, %, is
# warned about: the calibrations this serves fit a ratio to a few % standard error, so a 10 %
# miss is a model visibly off its data
MODAL_FIT_WARN_PCT = 10.0
# ... and a mode asked for no damping, by more than this absolute ratio
MODAL_FIT_WARN_ABS = 1e-4


@dataclass(frozen=True, eq=False)
class ExportDamping:
    """The damping fields of an export record (see :class:`~.export_record.ExportRecord`)."""

    requested: str
    form: str
    ratio: np.ndarray
    beta_s: float | None
    joint_damping_Nms_per_rad: np.ndarray
    modal_ratios: np.ndarray
    ratio_errors: np.ndarray | None
    notes: tuple


def default_form(fmt: str, xi: np.ndarray) -> str:
    """Return the damping form a file of ``fmt`` gets when none is asked.

    JSON the modal form; URDF and MJCF the stiffness form for one ratio, the fitted diagonal
    form for ratios that differ between modes.
    """
    if fmt == "json":
        return "modal"
    return "modal_fit" if np.any(xi != xi[0]) else "stiffness"


def _misses(xi: np.ndarray, err: np.ndarray) -> list[int]:
    bound = np.maximum(0.01 * MODAL_FIT_WARN_PCT * xi, MODAL_FIT_WARN_ABS)
    return [int(i) for i in np.flatnonzero(np.abs(err) > bound)]


def export_damping(model, M: np.ndarray, fmt: str, requested: str, xi: np.ndarray,
                   omega_hub: np.ndarray | None) -> ExportDamping:
    """Compute the damping a file of ``fmt`` carries for the ``requested`` form and ratios ``xi``.

    ``M`` is the mass matrix at the straight pose (kg m^2; with the hub's row and column for a
    hub model), ``omega_hub`` the hub model's flexible frequencies (rad/s) or None.
    """
    n = xi.size
    if not np.any(xi > 0.0):
        return ExportDamping("none", "none", xi, None, np.zeros(n), np.zeros(n), None, ())
    if requested == "modal" and fmt == "json":
        return ExportDamping(requested, "modal", xi, None, np.zeros(n), xi, None, ())
    uniform = not np.any(xi != xi[0])
    if requested == "stiffness" or (requested == "modal" and uniform):
        beta, c, ratios = stiffness_form(model, M, xi, omega_hub)
        notes = () if requested == "stiffness" else (
            f"modal damping (every mode {xi[0]:g}) cannot be carried by a diagonal joint "
            f"damping: wrote the stiffness form C = beta K (beta = {beta:.6g} s), whose "
            "modal ratios are " + " ".join(f"{x:.4g}" for x in ratios),)
        return ExportDamping(requested, "stiffness", xi, beta, c, ratios, None, notes)
    hub = omega_hub is not None
    fit = modal_fit_damping(M, model.stiffness_Nm_per_rad, xi, n_free=int(hub))
    c = fit.joint_damping_Nms_per_rad[int(hub):]
    notes = []
    if requested == "modal":
        notes.append("per-mode damping cannot be carried exactly by a diagonal joint damping: "
                     "wrote the diagonal damping fitted to the ratios (modal_fit)")
    bad = _misses(xi, fit.ratio_errors)
    if bad:
        notes.append(
            "modal_fit: " + ", ".join(
                f"mode {i + 1} gets {fit.achieved_ratios[i]:.4g} for {xi[i]:.4g}" for i in bad)
            + f" (off by more than {MODAL_FIT_WARN_PCT:g} % of the asked ratio; a diagonal "
            "joint damping c >= 0 carries no closer fit in least squares; the stiffness form "
            "gives mode 1 its ratio exactly and the higher modes more)")
    return ExportDamping(requested, "modal_fit", xi, None, c, fit.achieved_ratios,
                         fit.ratio_errors, tuple(notes))
