"""A PRBDM's tip response against its beam's finite-element truth: step and FRF.

:func:`compare_truth` computes (or finds in the cache) the truth a :class:`TruthRequest` asks for,
takes its modal superposition and measures the PRBDM linearised at the straight pose against it
(:func:`~prbdm_pin.simulation.response.dynamic_accuracy`); ``prbdm simulate --compare-truth``
writes what it returns (``truth_comparison.json``, ``truth_comparison.png``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

from ..errors import BeamInputError

if TYPE_CHECKING:
    from ..simulation.response import DynamicAccuracy, ModalTip
    from ..truth.request import TruthRequest
    from ..truth.result import TruthResult

__all__ = ["TRUTH_MODELS", "STEP_DURATION_S", "BAND_FACTOR", "TruthComparison",
           "compare_truth"]

# the truths whose modal superposition the comparison takes (truth_modal_tip)
TRUTH_MODELS = ("plate", "beam")
# the comparison's window (s) and band (a multiple of omega_n): the dynamic-accuracy metrics of
# the README
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
    >>> comparison = pp.compare_truth(model, result.truth_request)
    >>> isinstance(comparison, pp.TruthComparison), comparison.truth_model
    (True, 'beam')
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
        """Return the JSON form (SI units; errors as fractions); ``source`` names the model."""
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


def compare_truth(model, request: TruthRequest | None = None, damping_ratio: float = 0.02,
                  cache_dir=None) -> TruthComparison:
    """Step and FRF comparison of ``model`` (linearised, straight pose) with its beam's truth.

    Parameters
    ----------
    model : PrbdmModel
        The PRBDM; it must carry its beam (a model built on one, a fit.json's, a model JSON's).
    request : TruthRequest, optional
        The truth (its static solve included), a plate or beam truth; default the plate truth
        with as many modes as the model has joints. A fit's ``truth_request`` finds the very
        truth it was fitted to in the cache.
    damping_ratio : float
        Modal damping ratio of every mode on both sides (dimensionless, in (0, 1)).
    cache_dir : path, optional
        Truth cache folder (see ``compute_truth``).

    Returns
    -------
    TruthComparison
        The truth, its modal superposition (:func:`truth_modal_tip`) and the metrics of
        :func:`dynamic_accuracy` over the first ``STEP_DURATION_S`` (s) and the band
        [0, BAND_FACTOR * omega_n] (rad/s).

    Raises
    ------
    BeamInputError
        A model without its beam, or a request for another truth model.

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
    >>> comparison = pp.compare_truth(model, result.truth_request)
    >>> round(comparison.accuracy.frf_error, 2), round(comparison.accuracy.step_error, 2)
    (0.1, 0.1)
    """
    from ..model.checks import check_model

    check_model(model)
    from ..simulation.response import dynamic_accuracy, prbdm_modal_tip, truth_modal_tip
    from ..truth.request import TruthRequest

    if request is None:
        request = TruthRequest(modes=int(model.n_joints))
    if request.model not in TRUTH_MODELS:
        raise BeamInputError(f"request.model = {request.model!r}: must be one of "
                             f"{TRUTH_MODELS} (a truth with a modal superposition)")
    beam = model.beam
    if beam is None:
        raise BeamInputError("model: has no beam (a URDF does not carry it), so no truth")
    truth = request.compute(beam, cache_dir=cache_dir)
    ref = truth_modal_tip(truth, beam)
    acc = dynamic_accuracy(model, ref, damping_ratio=damping_ratio, duration_s=STEP_DURATION_S,
                           band_factor=BAND_FACTOR)
    return TruthComparison(request, truth, ref, prbdm_modal_tip(model), acc,
                           float(damping_ratio))
