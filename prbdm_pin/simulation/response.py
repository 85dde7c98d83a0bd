"""Dynamic accuracy of a PRBDM against a modal truth: tip step response and tip FRF.

Both sides are written as a modal superposition of the tip z displacement under a tip z force:
mode k (frequency omega_k, mass-normalised shape phi_k) contributes the gain
g_k = phi_k(tip)^2 (m/N per (rad/s)^2), so that::

    H(omega) = sum_k g_k / (omega_k^2 - omega^2 + 2 i xi_k omega_k omega)        (FRF, m/N)
    u(t) / F = sum_k g_k / omega_k^2 (1 - e^(-xi_k omega_k t) (cos omega_dk t
               + xi_k / sqrt(1 - xi_k^2) sin omega_dk t))                           (step, m/N)

For the PRBDM, g_k = (J_z phi_k)^2 with J_z the tip Jacobian's z row (the model linearised at
a pose). For a finite-element truth, the centreline shapes are mass-normalised with the beam's
mass per length mu(x) = rho 2 w(x) t: m_k = int mu phi_k^2 dx (exact for the 1D beam truth;
for plate modes it assumes the section moves rigidly, which ``centerline_modal_tip`` checks
against the truth's own z mass participation). ``euler_bernoulli_modal_tip`` is the closed form
of a uniform cantilever.

Metrics: relative L2 error of the tip displacement over the first second (step), and relative L2
error of the complex FRF over [0, 1.2 omega_N] (plus its magnitude and phase errors).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from ..errors import BeamInputError
from ..member.section_law import section_properties
from ..model.checks import check_model
from ..options.validate import check_type
from .damping import damping_ratios

__all__ = [
    "ModalTip",
    "DynamicAccuracy",
    "prbdm_modal_tip",
    "centerline_modal_tip",
    "truth_modal_tip",
    "euler_bernoulli_modal_tip",
    "modal_frf",
    "modal_step_response",
    "relative_l2",
    "dynamic_accuracy",
]


@dataclass(frozen=True, eq=False)
class ModalTip:
    """Modal data of the tip z response to a tip z force.

    Attributes
    ----------
    omega_rad_s : ndarray, shape (k,)
        Natural frequencies, rad/s.
    tip_gain_m_per_N : ndarray, shape (k,)
        phi_k(tip)^2 for mass-normalised shapes (m/N times (rad/s)^2): mode k's static tip
        compliance is tip_gain / omega_k^2 (m/N).
    mass_participation_check : float
        Largest relative difference between the z mass participation recomputed from the
        normalised shapes and the truth's own (NaN where not checked).
    """

    omega_rad_s: np.ndarray
    tip_gain_m_per_N: np.ndarray
    mass_participation_check: float = float("nan")

    @property
    def static_compliance_m_per_N(self) -> float:
        """Tip z static compliance of the retained modes, m/N."""
        return float(np.sum(self.tip_gain_m_per_N / self.omega_rad_s**2))


@dataclass(frozen=True, eq=False)
class DynamicAccuracy:
    """PRBDM versus truth over the first ``duration_s`` and the band [0, band_rad_s].

    Attributes
    ----------
    step_error : float
        Relative L2 error of the tip z displacement under a step tip force (fraction).
    frf_error : float
        Relative L2 error of the complex tip FRF over the band (fraction).
    frf_magnitude_error, frf_phase_error_rad : float
        Relative L2 error of ``|H|`` and RMS phase difference over the band.
    t_s, step_model_m_per_N, step_truth_m_per_N : ndarray
    omega_band_rad_s : ndarray
    frf_model_m_per_N, frf_truth_m_per_N : ndarray (complex)
    """

    step_error: float
    frf_error: float
    frf_magnitude_error: float
    frf_phase_error_rad: float
    t_s: np.ndarray
    step_model_m_per_N: np.ndarray
    step_truth_m_per_N: np.ndarray
    omega_band_rad_s: np.ndarray
    frf_model_m_per_N: np.ndarray
    frf_truth_m_per_N: np.ndarray


def prbdm_modal_tip(model, q: np.ndarray | None = None) -> ModalTip:
    """Linearise the PRBDM at pose ``q`` (rad, default straight): frequencies and tip gains."""
    omega, phi = model.modes(q)
    jz = model.tip_jacobian(q)[2]
    return ModalTip(np.asarray(omega, dtype=float), (jz @ phi) ** 2)


def centerline_modal_tip(modal, beam, indices: np.ndarray | None = None) -> ModalTip:
    """Truth modes (a ``ModalSolution``) normalised with the beam's mass per length.

    Parameters
    ----------
    modal : ModalSolution
        Needs ``omega_rad_s``, ``centerline_x_m`` (reaching the tip) and ``centerline_uz``.
    beam : Beam
    indices : array of int, optional
        Modes to keep (e.g. ``TruthResult.mode_index``); default all.
    """
    idx = np.arange(len(modal.omega_rad_s)) if indices is None else np.asarray(indices, int)
    x = np.asarray(modal.centerline_x_m, dtype=float)
    order = np.argsort(x)
    x = x[order]
    if abs(x[-1] - beam.length_m) > 1e-9 * beam.length_m:
        raise BeamInputError(f"centerline_x_m ends at {x[-1]} m: must reach the tip "
                             f"({beam.length_m} m)")
    modal_mass = getattr(modal, "modal_mass_kg", None)
    if modal_mass is not None:
        # exact: the finite-element modal mass phi^T M phi at the stored shapes' scale
        tip = np.asarray(modal.centerline_uz, dtype=float)[:, order][idx, -1]
        gains = tip**2 / np.asarray(modal_mass, dtype=float)[idx]
        return ModalTip(np.asarray(modal.omega_rad_s, dtype=float)[idx], gains, float("nan"))
    # No modal mass: normalise the centreline shapes with the section mass, which assumes each
    # section moves rigidly (true for beam-like modes only); refine by linear interpolation so
    # the quadrature of mu phi^2 is accurate
    xf = np.union1d(np.linspace(0.0, beam.length_m, 4001), x)
    mu = section_properties(beam, xf).rhoA_kg_m
    gains, checks = [], []
    for k in idx:
        phi = np.interp(xf, x, np.asarray(modal.centerline_uz[k], dtype=float)[order])
        m_k = np.trapezoid(mu * phi**2, xf)
        if m_k == 0.0:
            # no z motion on the axis (the 1D truth's torsion and in-plane modes): a tip z
            # force at the axis does not excite it
            gains.append(0.0)
            continue
        gains.append(phi[-1] ** 2 / m_k)
        mpf = np.trapezoid(mu * phi, xf) ** 2 / m_k
        ref = float(np.asarray(modal.mpf_z)[k])
        if ref > 1e-3 * beam.mass_kg:
            checks.append(abs(mpf / ref - 1.0))
    check = max(checks) if checks else float("nan")
    return ModalTip(np.asarray(modal.omega_rad_s, dtype=float)[idx], np.array(gains), check)


def truth_modal_tip(truth, beam) -> ModalTip:
    """Build the modal tip of a ``TruthResult``: every computed mode up to the highest selected.

    Bending, torsion and chordwise modes below the last selected frequency all respond to a tip
    force, so all of them are superposed (with the finite-element modal masses where the truth
    has them); the FRF band of :func:`dynamic_accuracy` then ends at 1.2 times the last selected
    frequency.

    Parameters
    ----------
    truth : TruthResult
        From ``prbdm_pin.truth.compute_truth`` (any model).
    beam : Beam
        The beam it was computed for (mass per length where the truth has no modal masses).

    Returns
    -------
    ModalTip
        Frequencies in rad/s, tip gains in m/N times (rad/s)^2.
    """
    modes = np.arange(int(np.max(truth.mode_index)) + 1)
    return centerline_modal_tip(truth.modal, beam, modes)


def euler_bernoulli_modal_tip(beam, n_modes: int) -> ModalTip:
    """Closed-form modes of a uniform Euler-Bernoulli cantilever (uses the root section).

    beta_k L solves cos(x) cosh(x) = -1; omega_k = (beta_k L)^2 sqrt(E I / (mu L^4)); with
    shapes normalised to int phi^2 = L the tip value is 2 in magnitude, so g_k = 4 / (mu L).
    """
    L = beam.length_m
    mu = float(section_properties(beam, 0.0).rhoA_kg_m)
    EI = beam.root_EI_Nm2
    roots = []
    for k in range(1, n_modes + 1):
        lo, hi = (k - 0.5) * np.pi - 0.5, (k - 0.5) * np.pi + 0.5
        roots.append(brentq(lambda x: np.cos(x) + 1.0 / np.cosh(x), lo, hi, xtol=1e-15))
    bl = np.array(roots)
    omega = bl**2 * np.sqrt(EI / (mu * L**4))
    return ModalTip(omega, np.full(n_modes, 4.0 / (mu * L)))


def modal_frf(tip: ModalTip, omega_rad_s: np.ndarray, damping_ratio: float | np.ndarray = 0.02
              ) -> np.ndarray:
    """Tip z displacement per unit tip z force, complex, m/N, at frequencies ``omega_rad_s``."""
    xi = damping_ratios(damping_ratio, tip.omega_rad_s.size)
    w = np.asarray(omega_rad_s, dtype=float)[:, None]
    wk = tip.omega_rad_s[None, :]
    return np.sum(tip.tip_gain_m_per_N / (wk**2 - w**2 + 2j * xi * wk * w), axis=1)


def modal_step_response(tip: ModalTip, t_s: np.ndarray, damping_ratio: float | np.ndarray = 0.02
                        ) -> np.ndarray:
    """Tip z displacement per unit step tip z force at times ``t_s`` (from rest), m/N."""
    xi = damping_ratios(damping_ratio, tip.omega_rad_s.size)
    if np.any(xi >= 1.0):
        raise BeamInputError("damping_ratio: the step response needs xi < 1 (underdamped)")
    t = np.asarray(t_s, dtype=float)[:, None]
    wk = tip.omega_rad_s[None, :]
    wd = wk * np.sqrt(1.0 - xi**2)
    decay = np.exp(-xi * wk * t) * (np.cos(wd * t) + xi / np.sqrt(1.0 - xi**2) * np.sin(wd * t))
    return np.sum(tip.tip_gain_m_per_N / wk**2 * (1.0 - decay), axis=1)


def relative_l2(a: np.ndarray, ref: np.ndarray) -> float:
    """Compute ||a - ref|| / ||ref|| (complex allowed)."""
    return float(np.linalg.norm(np.asarray(a) - ref) / np.linalg.norm(ref))


def dynamic_accuracy(
    model,
    truth: ModalTip,
    damping_ratio: float = 0.02,
    duration_s: float = 1.0,
    band_factor: float = 1.2,
    samples: int = 2001,
    simulate_step: bool = False,
) -> DynamicAccuracy:
    """Step-response and FRF errors of ``model`` (linearised, straight pose) against ``truth``.

    The band is [0, band_factor * omega_N] with omega_N the highest truth frequency given. With
    ``simulate_step`` the PRBDM step response is integrated with :func:`prbdm_pin.simulate` under
    a small force (linear regime) instead of its modal superposition. Both sides use the same
    modal damping ratio for every mode.

    Parameters
    ----------
    model : PrbdmModel
        The PRBDM, linearised at the straight pose.
    truth : ModalTip
        The truth's modal tip (:func:`truth_modal_tip`): frequencies in rad/s.
    damping_ratio : float
        Modal damping ratio of every mode, dimensionless.
    duration_s : float
        Length of the step response compared, s.
    band_factor : float
        The FRF band ends at this multiple of the highest truth frequency.
    samples : int
        Number of time samples and of band frequencies.
    simulate_step : bool
        Integrate the PRBDM step response with :func:`prbdm_pin.simulate`.

    Returns
    -------
    DynamicAccuracy
        The errors (fractions; phase in rad) and the curves compared (m/N).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01,
    ...                tip_force_N=[0.0, 0.0, -100.0])
    >>> truth = pp.compute_truth(beam, model="beam", modes=2)
    >>> target = pp.target_from_truth(truth, beam.tip_force_N)
    >>> result = pp.fit(beam, target, 2, objective="eigen", stiffness="joint", starts=1,
    ...                 progress=False)
    >>> model = pp.build_model(beam, result.lengths_m, result.stiffness_Nm_per_rad)
    >>> from prbdm_pin.simulation.response import truth_modal_tip
    >>> acc = pp.dynamic_accuracy(model, truth_modal_tip(truth, beam), damping_ratio=0.02)
    >>> round(acc.frf_error, 2), acc.t_s.shape == acc.step_model_m_per_N.shape
    (0.1, True)
    """
    check_model(model)
    check_type("truth", truth, ModalTip, "a prbdm_pin.response.ModalTip (truth_modal_tip)")
    t = np.linspace(0.0, duration_s, samples)
    mine = prbdm_modal_tip(model)
    u_truth = modal_step_response(truth, t, damping_ratio)
    if simulate_step:
        from . import simulate

        force = 1e-6 * model.n_joints * float(np.min(model.stiffness_Nm_per_rad)) / \
            float(np.sum(model.lengths_m))
        tr = simulate(model, duration_s, tip_force=[0.0, 0.0, force], damping_ratio=damping_ratio,
                      output_dt_s=duration_s / (samples - 1))
        u_model = tr.tip_displacement_m[:, 2] / force
        u_model = np.interp(t, tr.t_s, u_model)
    else:
        u_model = modal_step_response(mine, t, damping_ratio)
    w = np.linspace(0.0, band_factor * float(truth.omega_rad_s.max()), samples)
    h_truth = modal_frf(truth, w, damping_ratio)
    h_model = modal_frf(mine, w, damping_ratio)
    phase = np.angle(h_model / h_truth)
    return DynamicAccuracy(
        step_error=relative_l2(u_model, u_truth),
        frf_error=relative_l2(h_model, h_truth),
        frf_magnitude_error=relative_l2(np.abs(h_model), np.abs(h_truth)),
        frf_phase_error_rad=float(np.sqrt(np.mean(phase**2))),
        t_s=t, step_model_m_per_N=u_model, step_truth_m_per_N=u_truth,
        omega_band_rad_s=w, frf_model_m_per_N=h_model, frf_truth_m_per_N=h_truth,
    )
