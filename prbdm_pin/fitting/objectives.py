"""Fit objectives of the paper (equations 16-19, 25-27) as pure functions over arrays.

Every function takes plain arrays (model quantities over the pose sweep and the truth) and returns
fractions or percentages; none builds a model. Errors are relative l2 norms:

- eigen error of pose i, two norms (``norm``):

  - ``"paper"`` (Eq. 16): ``||f - w_i|| / ||f||`` with ``f`` the first N truth frequencies and
    ``w_i`` the model's first N at pose i. Dominated by the highest mode: a 0.01 % loss can
    hide a 0.6 % error of the first mode;
  - ``"relative"``: ``sqrt(mean_k ((w_ik - f_k) / f_k)^2)``, the rms of the per-mode relative
    errors, each mode weighed equally;

  both are a weighted l2 norm ``||d (w_i - f)||`` with weights ``d_k`` (:func:`eigen_weights`);
  compared as omega (rad/s) by default, as omega^2 when ``squared`` (the paper's published
  code);
- per-mode errors (:func:`mode_errors_pct`): signed ``100 (w_ik / f_k - 1)`` in omega, whatever
  the norm; what a user of the model sees;
- tip-position error (Eq. 19): ``||p_truth - p_model|| / ||p_truth||`` (the paper's
  normalisation by the tip position, about L, which makes errors look small);
- tip-displacement error: ``||d_truth - d_model|| / ||d_truth||`` with ``d = p - p_undeformed``;
- the losses average the per-pose errors over the sweep (Eqs. 15a, 17, 18) and are in %;
- combined (Eq. 27): ``sqrt(eigen^2 + deflection^2)``.
"""

from __future__ import annotations

import numpy as np

from ..options.checks import check_choice
from ..options.choices import (
    DEFAULT_EIGEN_NORM,
    DEFLECTION_NORMS,
    EIGEN_NORMS,
    DeflectionNorm,
    EigenNorm,
)

__all__ = [
    "EIGEN_NORMS",
    "DEFAULT_EIGEN_NORM",
    "DEFLECTION_NORMS",
    "check_eigen_norm",
    "check_deflection_norm",
    "eigen_weights",
    "eigen_residuals",
    "eigen_errors",
    "mode_errors_pct",
    "worst_mode_error_pct",
    "eigen_loss_pct",
    "best_scale",
    "best_amplitude",
    "projected_eigen_residuals",
    "projected_eigen_errors",
    "tip_scale_m",
    "tip_errors",
    "tip_position_errors",
    "tip_displacement_errors",
    "combined_loss_pct",
    "scf_mean",
    "scf_deviation_pct",
    "knee_index",
]


def check_eigen_norm(norm: EigenNorm | str) -> EigenNorm:
    """Return ``norm`` as an :class:`EigenNorm` (its string is accepted).

    Anything else is a BeamInputError naming it.
    """
    return check_choice("eigen_norm", norm, EigenNorm)


def check_deflection_norm(norm: DeflectionNorm | str) -> DeflectionNorm:
    """Return ``norm`` as a :class:`DeflectionNorm` (its string is accepted).

    Anything else is a BeamInputError naming it.
    """
    return check_choice("deflection_norm", norm, DeflectionNorm)


def _truth(omega_truth: np.ndarray, squared: bool) -> np.ndarray:
    f = np.asarray(omega_truth, dtype=float).reshape(-1)
    return f**2 if squared else f


def _model(omega_model: np.ndarray, n_freq: int, squared: bool) -> np.ndarray:
    w = np.atleast_2d(np.asarray(omega_model, dtype=float))
    if w.shape[-1] < n_freq:
        raise ValueError(f"model has {w.shape[-1]} frequencies per pose: {n_freq} needed")
    w = w[..., :n_freq]
    return w**2 if squared else w


def eigen_weights(omega_truth_rad_s: np.ndarray, squared: bool = False,
                  norm: EigenNorm | str = EigenNorm.PAPER) -> np.ndarray:
    """Weights d_k of the eigen norm ``||d (w - f)||`` (see the module docstring), shape (N,).

    ``"paper"``: ``1 / ||f||`` for every mode (Eq. 16); ``"relative"``: ``1 / (f_k sqrt(N))``.
    ``f`` is the truth in omega (rad/s), or omega^2 when ``squared``; d is in its inverse unit.
    """
    f = _truth(omega_truth_rad_s, squared)
    if check_eigen_norm(norm) is EigenNorm.PAPER:
        return np.full(f.size, 1.0 / np.linalg.norm(f))
    return 1.0 / (f * np.sqrt(f.size))


def mode_errors_pct(omega_model_rad_s: np.ndarray, omega_truth_rad_s: np.ndarray) -> np.ndarray:
    """Signed per-mode errors ``100 (omega_model / omega_truth - 1)``, %, shape (m, N).

    Parameters
    ----------
    omega_model_rad_s : ndarray, shape (m, >= N) or (>= N,)
        Model natural frequencies at each pose, ascending, rad/s (the first N are used).
    omega_truth_rad_s : ndarray, shape (N,)
        Truth frequencies, rad/s.
    """
    f = _truth(omega_truth_rad_s, False)
    w = _model(omega_model_rad_s, f.size, False)
    return 100.0 * (w / f - 1.0)


def worst_mode_error_pct(errors_pct: np.ndarray) -> float:
    """Return the largest ``|error|`` over poses and modes of :func:`mode_errors_pct`'s table, %."""
    e = np.asarray(errors_pct, dtype=float)
    return float(np.max(np.abs(e))) if e.size else float("nan")


def eigen_residuals(
    omega_model_rad_s: np.ndarray, omega_truth_rad_s: np.ndarray, squared: bool = False,
    norm: EigenNorm | str = EigenNorm.PAPER, weights: np.ndarray | None = None,
) -> np.ndarray:
    """Compute the weighted per-mode residuals ``d (w - f)`` of every pose, dimensionless.

    Shape (..., m, N) for model frequencies (rad/s) of shape (..., m, >= N); their norm over
    the modes is :func:`eigen_errors`. ``weights``: ``eigen_weights(omega_truth_rad_s,
    squared, norm)`` when already computed (a fit's inner loop).
    """
    f = _truth(omega_truth_rad_s, squared)
    w = _model(omega_model_rad_s, f.size, squared)
    if weights is None:
        weights = eigen_weights(omega_truth_rad_s, squared, norm)
    return (w - f) * weights


def eigen_errors(
    omega_model_rad_s: np.ndarray, omega_truth_rad_s: np.ndarray, squared: bool = False,
    norm: EigenNorm | str = EigenNorm.PAPER,
) -> np.ndarray:
    """Relative eigen error of every pose (equation 16 or the per-mode rms), as a fraction.

    Parameters
    ----------
    omega_model_rad_s : ndarray, shape (m, >= N) or (>= N,)
        Model natural frequencies at each pose, ascending, rad/s (only the first N are used).
    omega_truth_rad_s : ndarray, shape (N,)
        Truth frequencies, ascending, rad/s.
    squared : bool
        Compare omega^2 instead of omega.
    norm : EigenNorm or str
        Eq. 16's l2 norm, or the rms of the per-mode relative errors.

    Returns
    -------
    ndarray, shape (m,)
    """
    return np.linalg.norm(eigen_residuals(omega_model_rad_s, omega_truth_rad_s, squared, norm),
                          axis=-1)


def eigen_loss_pct(
    omega_model_rad_s: np.ndarray, omega_truth_rad_s: np.ndarray, squared: bool = False,
    norm: EigenNorm | str = EigenNorm.PAPER,
) -> float:
    """Eigen loss (equations 15a, 17): the per-pose error averaged over the poses, in %."""
    return float(100.0 * np.mean(eigen_errors(omega_model_rad_s, omega_truth_rad_s, squared,
                                              norm)))


def best_scale(
    omega_unit_rad_s: np.ndarray, omega_truth_rad_s: np.ndarray, squared: bool = False,
    norm: EigenNorm | str = EigenNorm.PAPER,
) -> np.ndarray:
    """Each pose's optimal stiffness factor k_i given its frequencies at k = 1 (var. projection).

    Scaling every spring by k scales every omega^2 by k (M does not depend on K), so pose i's
    model frequencies are ``sqrt(k_i) w_i``. Its error ``||f - sqrt(k_i) w_i||`` is a 1-D linear
    least-squares problem in ``sqrt(k_i)`` (in ``k_i`` when comparing omega^2), solved exactly.
    With the norm's weights d (:func:`eigen_weights`), ``sqrt(k_i) = sum d^2 f w_i / sum d^2
    w_i^2``: for ``"paper"`` (equal weights) ``f.w_i / w_i.w_i``; for ``"relative"``
    (d_k proportional to 1/f_k) ``sum r_k / sum r_k^2`` with ``r_k = w_ik / f_k`` (w, f squared
    when comparing omega^2, and then the result is k_i itself).

    Parameters
    ----------
    omega_unit_rad_s : ndarray, shape (m, >= N)
        Model frequencies with stiffness factor 1 at each pose, rad/s.
    omega_truth_rad_s : ndarray, shape (N,)
    squared : bool
    norm : EigenNorm or str

    Returns
    -------
    ndarray, shape (m,)
        The optimal k_i (dimensionless, > 0).
    """
    c = best_amplitude(omega_unit_rad_s, omega_truth_rad_s, squared, norm)
    return c if squared else c**2


def best_amplitude(omega_unit_rad_s: np.ndarray, omega_truth_rad_s: np.ndarray,
                   squared: bool = False, norm: EigenNorm | str = EigenNorm.PAPER) -> np.ndarray:
    """Compute the optimal multiplier of each pose's (squared) frequencies, dimensionless.

    The multiplier is sqrt(k_i) (k_i when ``squared``), shape (..., m) for
    ``omega_unit_rad_s`` of shape (..., m, >= N) (a stack of designs has a leading axis).
    """
    f = _truth(omega_truth_rad_s, squared)
    w = _model(omega_unit_rad_s, f.size, squared)
    d2 = eigen_weights(omega_truth_rad_s, squared, norm) ** 2
    return ((w * d2) @ f) / np.einsum("...ij,...ij->...i", w * d2, w)


def projected_eigen_residuals(
    omega_unit_rad_s: np.ndarray, omega_truth_rad_s: np.ndarray, squared: bool = False,
    norm: EigenNorm | str = EigenNorm.PAPER,
) -> np.ndarray:
    """Compute the weighted residuals ``d (c_i w_i - f)`` at each pose's optimal factor.

    The factor is :func:`best_amplitude`'s; dimensionless, shape (..., m, N): the variable
    projection's residual vector, whose norm over the modes is :func:`projected_eigen_errors`.
    """
    f = _truth(omega_truth_rad_s, squared)
    w = _model(omega_unit_rad_s, f.size, squared)
    c = best_amplitude(omega_unit_rad_s, omega_truth_rad_s, squared, norm)
    d = eigen_weights(omega_truth_rad_s, squared, norm)
    return (w * c[..., None] - f) * d


def projected_eigen_errors(
    omega_unit_rad_s: np.ndarray, omega_truth_rad_s: np.ndarray, squared: bool = False,
    norm: EigenNorm | str = EigenNorm.PAPER,
) -> np.ndarray:
    """Per-pose eigen error (fraction) at each pose's optimal factor (see :func:`best_scale`).

    Equals the sine of the angle between the weighted truth vector and the pose's weighted
    model vector.
    """
    return np.linalg.norm(projected_eigen_residuals(omega_unit_rad_s, omega_truth_rad_s,
                                                    squared, norm), axis=-1)


def tip_scale_m(tip_truth_m: np.ndarray, tip_displacement_truth_m: np.ndarray,
                norm: DeflectionNorm | str = DeflectionNorm.POSITION) -> float:
    """Return what a tip error is divided by, m.

    The truth tip position's length (``"position"``, Eq. 19) or the truth tip displacement's
    (``"displacement"``).
    """
    if check_deflection_norm(norm) is DeflectionNorm.POSITION:
        v = tip_truth_m
    else:
        v = tip_displacement_truth_m
    return float(np.linalg.norm(np.asarray(v, dtype=float).reshape(3)))


def tip_errors(tip_model_m: np.ndarray, tip_truth_m: np.ndarray, scale_m: float) -> np.ndarray:
    """Compute ``||p_model - p_truth|| / scale_m`` of each model tip, as a fraction.

    ``tip_model_m`` has m' rows or is one (3,) vector, m; ``scale_m`` comes from
    :func:`tip_scale_m`.
    """
    p = np.atleast_2d(np.asarray(tip_model_m, dtype=float))
    t = np.asarray(tip_truth_m, dtype=float).reshape(3)
    return np.linalg.norm(p - t, axis=1) / scale_m


def tip_position_errors(tip_model_m: np.ndarray, tip_truth_m: np.ndarray) -> np.ndarray:
    """Relative tip-position error (equation 19) of each model tip, as a fraction.

    Parameters
    ----------
    tip_model_m : ndarray, shape (m, 3) or (3,)
        Model tip positions under the load case, m.
    tip_truth_m : ndarray, shape (3,)
        Truth tip position, m.
    """
    return tip_errors(tip_model_m, tip_truth_m, tip_scale_m(tip_truth_m, tip_truth_m))


def tip_displacement_errors(
    tip_model_m: np.ndarray, tip_truth_m: np.ndarray, tip_displacement_truth_m: np.ndarray
) -> np.ndarray:
    """Tip-position error normalised by the truth tip displacement, as a fraction.

    The undeformed tip is ``tip_truth_m - tip_displacement_truth_m``; the error is
    ``||p_model - p_truth|| / ||d_truth||``: unlike Eq. 19 it is not diluted by the beam length.
    """
    return tip_errors(tip_model_m, tip_truth_m,
                      tip_scale_m(tip_truth_m, tip_displacement_truth_m,
                                  DeflectionNorm.DISPLACEMENT))


def combined_loss_pct(eigen_pct: float | np.ndarray, deflection_pct: float | np.ndarray):
    """Return the combined loss of equation 27, ``sqrt(eigen^2 + deflection^2)``, %."""
    return np.hypot(eigen_pct, deflection_pct)


def scf_mean(k: np.ndarray) -> float:
    """Mean stiffness correction factor over the poses (equation 25; the sum has m terms)."""
    return float(np.mean(np.asarray(k, dtype=float)))


def scf_deviation_pct(k: np.ndarray) -> np.ndarray:
    """Each pose's SCF deviation from the mean, P_i of equation 26, in %."""
    k = np.asarray(k, dtype=float)
    m = np.mean(k)
    return (k - m) / m * 100.0


def knee_index(F: np.ndarray) -> int:
    """Index of the Pareto point nearest the origin (equation 27) among rows (eigen, deflection)."""
    F = np.atleast_2d(np.asarray(F, dtype=float))
    return int(np.argmin(np.hypot(F[:, 0], F[:, 1])))
