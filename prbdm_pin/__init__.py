"""prbdm_pin: pseudo-rigid-body dynamic models (PRBDM) of compliant cantilevers on Pinocchio.

The public API is re-exported here and imported lazily, so ``import prbdm_pin`` stays cheap and
optional dependencies load only when used.
"""

from __future__ import annotations

import importlib
from typing import Any

from .version import __version__

_EXPORTS = {
    # beam input
    "Material": "member.material",
    "Beam": "member.geometry",
    "load_beam": "files.beam_file",
    "save_beam": "files.beam_file",
    "load_schema": "schemas",
    "random_beam": "member.random_beams",
    "beam_from_dict": "files.beam_file",
    "RoundSection": "member.round_section",
    "SectionTable": "member.section_table",
    "SectionProperties": "member.section_law",
    "round_beam": "member.section_member",
    "table_beam": "member.section_member",
    "section_properties": "member.section_law",
    # errors
    "BeamInputError": "errors",
    "InputTypeError": "errors",
    "SolveError": "errors",
    "TruthError": "errors",
    # sections, layout, stiffness
    "LinkSections": "chain.sections",
    "link_sections": "chain.sections",
    "validate_lengths": "chain.layout",
    "sample_lengths": "chain.layout",
    "repair_lengths": "chain.layout",
    "pose_sweep": "chain.stiffness",
    "paper_stiffness": "chain.stiffness",
    "finite_segment_stiffness": "chain.stiffness",
    "spatial_stiffness": "chain.spatial_stiffness",
    # model sensitivities
    "model_gradient": "chain.chain_derivatives",
    "ModelGradient": "chain.chain_derivatives",
    # model
    "PrbdmModel": "model.prbdm_model",
    "build_model": "model.prbdm_model",
    "load_urdf": "files.urdf_file",
    "load_model": "files.model_source",
    "ModelFile": "files.model_source",
    # the linear plant
    "Hub": "model.hub",
    "FreeBus": "model.supports",
    "LightHubWarning": "model.hub_check",
    "StrainActuator": "model.inputs",
    "DistributedLoad": "model.loads",
    "fit_strain_actuators": "plant.actuator_fit",
    "linearize": "plant.linearize",
    "frequencies_batch": "plant.batch_frequencies",
    "linearize_batch": "plant.batch_linearize",
    "statics": "plant.statics",
    "spinning_frequencies": "plant.spin",
    "gyroscopic_frequencies": "plant.spin",
    "StaticEquilibrium": "plant.statics",
    "LinearModel": "plant.state_space",
    "ModalData": "plant.state_space",
    "compare_plant": "plant.comparison",
    "PlantComparison": "plant.comparison",
    "compare_truth_plant": "plant.comparison_truth",
    "TruthPlantComparison": "plant.comparison_truth",
    # truth
    "TruthRequest": "truth",
    "TruthResult": "truth",
    "compute_truth": "truth",
    "beam_gravity_modal": "truth.beam_gravity",
    "beam_gravity_static": "truth.beam_gravity",
    "beam_self_weight_buckling": "truth.beam_gravity",
    "elastica_gravity_modes": "truth.elastica_modes",
    "SectionLaws": "truth.timoshenko_sections",
    "shear_coefficient": "truth.timoshenko_sections",
    "rectangle_section_laws": "truth.timoshenko_sections",
    "timoshenko_modal": "truth.beam_timoshenko",
    "timoshenko_static": "truth.beam_timoshenko",
    "beam_timoshenko_modal": "truth.beam_timoshenko",
    "beam_timoshenko_static": "truth.beam_timoshenko",
    "TimoshenkoModes": "truth.beam_timoshenko",
    "TimoshenkoStatic": "truth.beam_timoshenko",
    "timoshenko_criterion": "truth.timoshenko_criterion",
    "TimoshenkoCriterion": "truth.timoshenko_criterion",
    "tube_solid_modes": "truth.tube_solid",
    "round_solid_modes": "truth.tube_solid",
    "TubeModes": "truth.tube_solid",
    # design sensitivities
    "Design": "member.design",
    "truth_gradient": "truth.compute_derivatives",
    "TruthGradient": "truth.compute_derivatives",
    "elastica_gradient": "truth.elastica_derivatives",
    "ElasticaGradient": "truth.elastica_derivatives",
    # fitting
    "FitTarget": "fitting.target",
    "LoadCase": "fitting.load_case",
    "target_from_truth": "fitting.target",
    "gravity_target": "fitting.gravity_target",
    "FitOptions": "options.objects",
    "ParetoOptions": "options.objects",
    "SimulationOptions": "options.simulation",
    "Objective": "options.choices",
    "StiffnessKind": "options.choices",
    "EigenNorm": "options.choices",
    "DeflectionNorm": "options.choices",
    "Axes": "options.choices",
    "fit": "fitting",
    "fit_pareto": "fitting",
    "fit_sweep": "fitting",
    "SweepResult": "fitting",
    "fit_derivative": "fitting",
    "FitDerivative": "fitting",
    "fit_design_gradient": "fitting",
    "FitDesignGradient": "fitting",
    # co-design through truth -> fit -> model
    "codesign_point": "fitting.codesign",
    "CodesignPoint": "fitting.codesign",
    "FitResult": "fitting.results",
    "ParetoResult": "fitting.pareto_result",
    "with_point_gains": "fitting.spatial_gains",
    "spatial_load_target": "fitting.spatial_deflection",
    "corner_static": "truth.corner_static",
    "load_fit": "files.fit_file",
    "save_fit": "files.fit_file",
    # simulation and exports
    "simulate": "simulation",
    "Trajectory": "simulation",
    "simulate_batch": "simulation.batch",
    "TrajectoryBatch": "simulation.trajectory_batch",
    "Exponential": "options.integrators",
    "Gauss": "options.integrators",
    "Trapezoidal": "options.integrators",
    "ScipyIVP": "options.integrators",
    "Compiled": "options.integrators",
    "Auto": "options.integrators",
    "StiffnessSchedule": "simulation",
    "Controller": "simulation",
    "StateFeedback": "simulation",
    "trajectory_gradient": "simulation.sensitivity",
    "TrajectoryGradient": "simulation.sensitivity",
    "TrajectoryCost": "simulation.trajectory_cost",
    "QuadraticCost": "simulation.trajectory_cost",
    "BaseMotion": "simulation.base_motion",
    "dynamic_accuracy": "simulation.response",
    "compare_truth": "plant.truth_comparison",
    "TruthComparison": "plant.truth_comparison",
    "fit_joint_damping": "simulation.modal_fit",
    "ModalFitDamping": "simulation.modal_fit",
    "export_model": "files.export",
    "read_model_json": "files.export",
    "read_plant_json": "files.export",
    "link_meshes": "files.export_geometry",
    "LinkMesh": "files.link_mesh",
    "planform_link_mesh": "files.link_mesh",
    "round_link_mesh": "files.link_mesh",
    # the compiled kernel of a chain's dynamics
    "ChainKernel": "kernel",
    "chain_kernel": "kernel",
    # calibration to measurements
    "calibrate": "fitting.calibrate",
    "CalibrationResult": "fitting.calibrate",
    "read_ring_down": "fitting.calibration_data",
    "RingDown": "fitting.calibration_data",
    "read_calibration_data": "fitting.calibration_measured",
    "DrivenTrajectory": "fitting.calibration_measured",
    "FrequencyResponse": "fitting.calibration_measured",
    "write_calibration": "files.calibration_file",
    "plot_calibration": "files.calibration_file",
    # batch studies
    "run_batch": "batch",
    "BatchSpec": "batch",
    "FitSettings": "batch",
    # seeing a model: mode shapes, animations, ParaView files, meshcat
    "ChainModes": "views.chain_geometry",
    "chain_modes": "views.chain_geometry",
    "TruthShapes": "views.modes",
    "plot_mode_shapes": "views.modes",
    "animate_response": "views.animate",
    "write_model_modes_vtu": "views.vtu_model",
    "write_trajectory_vtu": "views.vtu_model",
    "open_meshcat": "views.meshcat_view",
}

__all__ = ["__version__", *_EXPORTS]


def __getattr__(name: str) -> Any:
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'prbdm_pin' has no attribute {name!r}")
    return getattr(importlib.import_module(f".{module}", __name__), name)


def __dir__() -> list[str]:
    return sorted(__all__)
