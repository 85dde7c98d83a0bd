"""Fit objectives of the paper (Eqs. 16-19, 25-27) as pure functions over arrays.

Every function takes plain arrays (model quantities over the pose sweep and the truth) and returns
fractions or percentages; none builds a model. Errors are relative l2 norms:

- eigen error of pose i (Eq. 16): ``||f - w_i|| / ||f||`` with ``f`` the first N truth
  frequencies and ``w_i`` the model's first N at pose i; compared as omega (rad/s) by default,
  as omega^2 when ``squared`` (the paper's published code);
- tip-position error (Eq. 19): ``||p_truth - p_model|| / ||p_truth||`` (the paper's
  normalisation by the tip position, about L, which makes errors look small);
- tip-displacement error: ``||d_truth - d_model|| / ||d_truth||`` with ``d = p - p_undeformed``;
- the losses average the per-pose errors over the sweep (Eqs. 15a, 17, 18) and are in %;
- combined (Eq. 27): ``sqrt(eigen^2 + deflection^2)``.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "eigen_errors",
    "eigen_loss_pct",
    "best_scale",
    "projected_eigen_errors",
    "tip_position_errors",
    "tip_displacement_errors",
    "combined_loss_pct",
    "scf_mean",
    "scf_deviation_pct",
    "knee_index",
]


def _truth(omega_truth: np.ndarray, squared: bool) -> np.ndarray:
    f = np.asarray(omega_truth, dtype=float).reshape(-1)
    return f**2 if squared else f


def _model(omega_model: np.ndarray, n_freq: int, squared: bool) -> np.ndarray:
    w = np.atleast_2d(np.asarray(omega_model, dtype=float))
    if w.shape[1] < n_freq:
        raise ValueError(f"model has {w.shape[1]} frequencies per pose: {n_freq} needed")
    w = w[:, :n_freq]
    return w**2 if squared else w


def eigen_errors(
    omega_model_rad_s: np.ndarray, omega_truth_rad_s: np.ndarray, squared: bool = False
) -> np.ndarray:
    """Relative l2 eigen error of every pose (Eq. 16), as a fraction.

    Parameters
    ----------
    omega_model_rad_s : ndarray, shape (m, >= N) or (>= N,)
        Model natural frequencies at each pose, ascending, rad/s (only the first N are used).
    omega_truth_rad_s : ndarray, shape (N,)
        Truth frequencies, ascending, rad/s.
    squared : bool
        Compare omega^2 instead of omega.

    Returns
    -------
    ndarray, shape (m,)
    """
    f = _truth(omega_truth_rad_s, squared)
    w = _model(omega_model_rad_s, f.size, squared)
    return np.linalg.norm(w - f, axis=1) / np.linalg.norm(f)


def eigen_loss_pct(
    omega_model_rad_s: np.ndarray, omega_truth_rad_s: np.ndarray, squared: bool = False
) -> float:
    """Eigen loss (Eqs. 15a, 17): the per-pose error of Eq. 16 averaged over the poses, in %."""
    return float(100.0 * np.mean(eigen_errors(omega_model_rad_s, omega_truth_rad_s, squared)))


def best_scale(
    omega_unit_rad_s: np.ndarray, omega_truth_rad_s: np.ndarray, squared: bool = False
) -> np.ndarray:
    """Each pose's optimal stiffness factor k_i given its frequencies at k = 1 (var. projection).

    Scaling every spring by k scales every omega^2 by k (M does not depend on K), so pose i's
    model frequencies are ``sqrt(k_i) w_i``. Its error ``||f - sqrt(k_i) w_i||`` is a 1-D linear
    least-squares problem in ``sqrt(k_i)`` (in ``k_i`` when comparing omega^2), solved exactly:
    ``sqrt(k_i) = f.w_i / w_i.w_i`` (``k_i = f^2.w_i^2 / w_i^2.w_i^2``).

    Parameters
    ----------
    omega_unit_rad_s : ndarray, shape (m, >= N)
        Model frequencies with stiffness factor 1 at each pose, rad/s.
    omega_truth_rad_s : ndarray, shape (N,)
    squared : bool

    Returns
    -------
    ndarray, shape (m,)
        The optimal k_i (dimensionless, > 0).
    """
    f = _truth(omega_truth_rad_s, squared)
    w = _model(omega_unit_rad_s, f.size, squared)
    c = (w @ f) / np.einsum("ij,ij->i", w, w)
    return c if squared else c**2


def projected_eigen_errors(
    omega_unit_rad_s: np.ndarray, omega_truth_rad_s: np.ndarray, squared: bool = False
) -> np.ndarray:
    """Per-pose eigen error (fraction) at each pose's optimal factor (see :func:`best_scale`).

    Equals the sine of the angle between the truth vector and the pose's model vector.
    """
    f = _truth(omega_truth_rad_s, squared)
    w = _model(omega_unit_rad_s, f.size, squared)
    c = (w @ f) / np.einsum("ij,ij->i", w, w)
    return np.linalg.norm(w * c[:, None] - f, axis=1) / np.linalg.norm(f)


def tip_position_errors(tip_model_m: np.ndarray, tip_truth_m: np.ndarray) -> np.ndarray:
    """Relative tip-position error (Eq. 19) of each model tip, as a fraction.

    Parameters
    ----------
    tip_model_m : ndarray, shape (m, 3) or (3,)
        Model tip positions under the load case, m.
    tip_truth_m : ndarray, shape (3,)
        Truth tip position, m.
    """
    p = np.atleast_2d(np.asarray(tip_model_m, dtype=float))
    t = np.asarray(tip_truth_m, dtype=float).reshape(3)
    return np.linalg.norm(p - t, axis=1) / np.linalg.norm(t)


def tip_displacement_errors(
    tip_model_m: np.ndarray, tip_truth_m: np.ndarray, tip_displacement_truth_m: np.ndarray
) -> np.ndarray:
    """Tip-position error normalised by the truth tip displacement, as a fraction.

    The undeformed tip is ``tip_truth_m - tip_displacement_truth_m``; the error is
    ``||p_model - p_truth|| / ||d_truth||``: unlike Eq. 19 it is not diluted by the beam length.
    """
    p = np.atleast_2d(np.asarray(tip_model_m, dtype=float))
    t = np.asarray(tip_truth_m, dtype=float).reshape(3)
    d = np.asarray(tip_displacement_truth_m, dtype=float).reshape(3)
    return np.linalg.norm(p - t, axis=1) / np.linalg.norm(d)


def combined_loss_pct(eigen_pct: float | np.ndarray, deflection_pct: float | np.ndarray):
    """Combined loss of Eq. 27, ``sqrt(eigen^2 + deflection^2)`` (inputs and output in %)."""
    return np.hypot(eigen_pct, deflection_pct)


def scf_mean(k: np.ndarray) -> float:
    """Mean stiffness correction factor over the poses (Eq. 25; the sum has m terms)."""
    return float(np.mean(np.asarray(k, dtype=float)))


def scf_deviation_pct(k: np.ndarray) -> np.ndarray:
    """Each pose's SCF deviation from the mean, P_i of Eq. 26, in %."""
    k = np.asarray(k, dtype=float)
    m = np.mean(k)
    return (k - m) / m * 100.0


def knee_index(F: np.ndarray) -> int:
    """Index of the Pareto point closest to the origin (Eq. 27) among rows (eigen, deflection)."""
    F = np.atleast_2d(np.asarray(F, dtype=float))
    return int(np.argmin(np.hypot(F[:, 0], F[:, 1])))
