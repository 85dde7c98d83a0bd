"""``prbdm simulate --compare-truth``: a PRBDM's responses against its beam's truth.

The step and frequency responses against the finite-element truth (what
``truth_comparison.json`` and ``truth_comparison.png`` report).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import BeamInputError

if TYPE_CHECKING:
    from ..simulation.response import DynamicAccuracy, ModalTip
    from ..truth import TruthRequest, TruthResult

TRUTH_MODELS = ("plate", "beam")
# the comparison's window and band (the dynamic-accuracy metrics of the README)
STEP_DURATION_S = 1.0
BAND_FACTOR = 1.2


@dataclass(frozen=True, eq=False)
class TruthComparison:
    """A PRBDM against its beam's truth (what ``truth_comparison.json`` reports).

    Attributes
    ----------
    request : TruthRequest
        The truth asked for (``model`` is ``"plate"`` or ``"beam"``).
    truth : TruthResult
        The truth (selected modes, modal solution, linear static solve).
    superposed : ModalTip
        The truth's modal superposition (frequencies rad/s, tip gains).
    prbdm : ModalTip
        The PRBDM linearised at the straight pose.
    accuracy : DynamicAccuracy
        Errors (fractions, phase in rad) and the curves (m/N against s and rad/s).
    damping_ratio : float
        Modal damping ratio of every mode on both sides.
    """

    request: TruthRequest
    truth: TruthResult
    superposed: ModalTip
    prbdm: ModalTip
    accuracy: DynamicAccuracy
    damping_ratio: float

    @property
    def truth_model(self) -> str:
        """``"plate"`` or ``"beam"``."""
        return self.request.model

    @property
    def linear_static_compliance_m_per_N(self) -> float | None:
        """Tip z deflection per unit tip z force of the truth's linear static solve, m/N."""
        static = self.truth.static_linear
        if static is None or float(static.tip_force_N[2]) == 0.0:
            return None
        return float(static.tip_displacement_m[2] / static.tip_force_N[2])

    def to_dict(self, source: str) -> dict:
        """Return the JSON form; ``source`` names the model file."""
        acc, truth = self.accuracy, self.truth
        return {
            "truth": {
                "model": self.truth_model,
                "solver": truth.modal.model,
                "mesh_level": int(truth.mesh_level),
                "dofs": int(truth.modal.dofs),
                "selection": truth.selection,
                "request": self.request.to_dict(),
                "selected_omega_rad_s": [float(w) for w in truth.omega_rad_s],
                "superposed_modes": int(self.superposed.omega_rad_s.size),
                "superposed_omega_rad_s": [float(w) for w in self.superposed.omega_rad_s],
                "modal_masses": ("finite-element" if truth.modal.modal_mass_kg is not None
                                 else "beam mass per length"),
                "linear_static_compliance_m_per_N": self.linear_static_compliance_m_per_N,
                "warnings": list(truth.warnings),
                "version": truth.version,
            },
            "prbdm": {
                "source": source,
                "joints": int(self.prbdm.omega_rad_s.size),
                "omega_rad_s": [float(w) for w in self.prbdm.omega_rad_s],
                "linearised_at": "straight pose (q = 0)",
            },
            "damping_ratio": float(self.damping_ratio),
            "step_duration_s": float(acc.t_s[-1]),
            "step_error": acc.step_error,
            "band_rad_s": [0.0, float(acc.omega_band_rad_s[-1])],
            "frf_error": acc.frf_error,
            "frf_magnitude_error": acc.frf_magnitude_error,
            "frf_phase_error_rad": acc.frf_phase_error_rad,
            # H(0), the sum of the modal static compliances: each FRF's static limit, m/N
            "truth_frf_static_limit_m_per_N": float(acc.frf_truth_m_per_N[0].real),
            "prbdm_frf_static_limit_m_per_N": float(acc.frf_model_m_per_N[0].real),
        }


def comparison_request(model, fitted, truth_model: str | None = None,
                       quiet: bool = True) -> TruthRequest:
    """Return the truth request ``--compare-truth`` asks for.

    With no ``truth_model`` (or the fit's own model), the request recorded in the fit
    (``fitted.truth_request``: model, selection, mesh level, ...) when it is a plate or beam truth,
    so the comparison finds the fit's truth in the cache; otherwise ``truth_model`` (default
    plate) at ``prbdm fit``'s defaults with n = joints modes.
    """
    from ..truth import TruthRequest

    # an unknown truth_model passes through: compare_truth refuses it
    recorded = getattr(fitted, "truth_request", None)
    if recorded is not None and truth_model in (None, recorded.model):
        if recorded.model in TRUTH_MODELS:
            return recorded
        if not quiet:
            print(f"note: the fit's {recorded.model} truth has no modal superposition here; "
                  "comparing with the plate truth", file=sys.stderr)
    return TruthRequest(model=truth_model or "plate", modes=int(model.n_joints))


def compare_truth(model, request: TruthRequest, damping_ratio: float, cache_dir,
                  quiet: bool = True) -> TruthComparison:
    """Step and FRF comparison of ``model`` (linearised, straight pose) with its beam's truth.

    The truth is ``request.compute(beam, cache_dir)`` (static solve included; see
    :func:`comparison_request`), so a model fitted by ``prbdm fit`` finds the very truth it was
    fitted to in the cache. Its modal superposition is :func:`truth_modal_tip`; the metrics are
    :func:`dynamic_accuracy` over the first ``STEP_DURATION_S`` (s) and the band
    [0, BAND_FACTOR * omega_n] (rad/s).
    """
    from ..simulation.response import dynamic_accuracy, prbdm_modal_tip, truth_modal_tip

    if request.model not in TRUTH_MODELS:
        raise BeamInputError(f"--truth-model = {request.model!r}: must be one of {TRUTH_MODELS}")
    beam = model.beam
    truth = request.compute(beam, cache_dir=cache_dir)
    if not quiet:
        for note in truth.warnings:
            print(f"truth warning: {note}", file=sys.stderr)
    ref = truth_modal_tip(truth, beam)
    acc = dynamic_accuracy(model, ref, damping_ratio=damping_ratio, duration_s=STEP_DURATION_S,
                           band_factor=BAND_FACTOR)
    return TruthComparison(request, truth, ref, prbdm_modal_tip(model), acc,
                           float(damping_ratio))


def comparison_figure(cmp: TruthComparison, plt):
    """Draw the step response and the FRF magnitude and phase of both sides (pyplot ``plt``).

    Returns the figure; the command writes and closes it.
    """
    import numpy as np

    acc, name = cmp.accuracy, cmp.truth_model
    mine = f"{cmp.prbdm.omega_rad_s.size}R PRBDM"
    fig, ax = plt.subplots(3, 1, figsize=(7, 8))
    ax[0].plot(acc.t_s, acc.step_truth_m_per_N * 1e6, label=f"{name} truth")
    ax[0].plot(acc.t_s, acc.step_model_m_per_N * 1e6, "--", label=mine)
    ax[0].set_xlabel("t (s)")
    ax[0].set_ylabel("tip z / F, unit step (um/N)")
    ax[0].legend()
    w = acc.omega_band_rad_s
    ax[1].semilogy(w, np.abs(acc.frf_truth_m_per_N), label=f"{name} truth")
    ax[1].semilogy(w, np.abs(acc.frf_model_m_per_N), "--", label=mine)
    ax[1].set_ylabel("|H| (m/N)")
    ax[2].plot(w, np.degrees(np.angle(acc.frf_truth_m_per_N)))
    ax[2].plot(w, np.degrees(np.angle(acc.frf_model_m_per_N)), "--")
    ax[2].set_xlabel("omega (rad/s)")
    ax[2].set_ylabel("phase (deg)")
    fig.suptitle(f"{name} truth, zeta = {cmp.damping_ratio}: step error "
                 f"{acc.step_error:.1%}, FRF error {acc.frf_error:.1%}")
    fig.tight_layout()
    return fig
