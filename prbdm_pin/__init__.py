"""prbdm_pin: pseudo-rigid-body dynamic models (PRBDM) of compliant cantilevers on Pinocchio.

The public API is re-exported here and imported lazily, so ``import prbdm_pin`` stays cheap and
optional dependencies load only when used.
"""

from __future__ import annotations

import importlib
from typing import Any

__version__ = "0.1.0"

_EXPORTS = {
    # beam input
    "Material": "material",
    "Beam": "geometry",
    "load_beam": "beam_file",
    "save_beam": "beam_file",
    "random_beam": "random_beams",
    "beam_from_dict": "beam_file",
    # errors
    "BeamInputError": "errors",
    "InputTypeError": "errors",
    "SolveError": "errors",
    "TruthError": "errors",
    # sections, layout, stiffness
    "LinkSections": "sections",
    "link_sections": "sections",
    "validate_lengths": "layout",
    "sample_lengths": "layout",
    "repair_lengths": "layout",
    "pose_sweep": "stiffness",
    "paper_stiffness": "stiffness",
    "finite_segment_stiffness": "stiffness",
    # model sensitivities
    "model_gradient": "chain_gradient",
    "ModelGradient": "chain_gradient",
    # model
    "PrbdmModel": "model",
    "build_model": "model",
    "load_urdf": "model",
    # the linear plant
    "Hub": "plant.hub",
    "LightHubWarning": "plant.hub_check",
    "StrainActuator": "plant.inputs",
    "fit_strain_actuators": "plant.actuator_fit",
    "linearize": "plant.linearize",
    "LinearModel": "plant.state_space",
    "ModalData": "plant.state_space",
    "compare_plant": "plant.comparison",
    "PlantComparison": "plant.comparison",
    # truth
    "TruthResult": "truth",
    "compute_truth": "truth",
    # design sensitivities
    "Design": "design",
    "truth_gradient": "truth.gradient",
    "TruthGradient": "truth.gradient",
    "elastica_gradient": "truth.elastica_gradient",
    "ElasticaGradient": "truth.elastica_gradient",
    # fitting
    "FitTarget": "target",
    "LoadCase": "target",
    "target_from_truth": "target",
    "FitOptions": "options",
    "ParetoOptions": "options",
    "SimulationOptions": "options",
    "Objective": "choices",
    "StiffnessKind": "choices",
    "EigenNorm": "choices",
    "DeflectionNorm": "choices",
    "fit": "fitting",
    "fit_pareto": "fitting",
    "fit_sweep": "fitting",
    "SweepResult": "fitting",
    "fit_derivative": "fitting",
    "FitDerivative": "fitting",
    "fit_design_gradient": "fitting",
    "FitDesignGradient": "fitting",
    # co-design through truth -> fit -> model
    "codesign_point": "codesign",
    "CodesignPoint": "codesign",
    "FitResult": "results",
    "ParetoResult": "pareto_result",
    "load_fit": "fit_file",
    "save_fit": "fit_file",
    # simulation and exports
    "simulate": "simulation",
    "Trajectory": "simulation",
    "StiffnessSchedule": "simulation",
    "Controller": "simulation",
    "StateFeedback": "simulation",
    "dynamic_accuracy": "response",
    "export_model": "export",
    "read_model_json": "export",
    "read_plant_json": "export",
    # batch studies
    "run_batch": "batch",
    "BatchSpec": "batch",
    "FitSettings": "batch",
}

__all__ = ["__version__", *_EXPORTS]


def __getattr__(name: str) -> Any:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'prbdm_pin' has no attribute {name!r}")
    return getattr(importlib.import_module(f".{module}", __name__), name)


def __dir__() -> list[str]:
    return sorted(__all__)
