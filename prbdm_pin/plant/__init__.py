"""The fitted PRBDM as a control co-design plant: inputs, outputs and a linear state-space model.

``hub`` (a rotating rigid hub at the root), ``inputs`` (tip forces, joint torques, strain
actuators, hub torque), ``outputs`` (tip motion, joint angles and rates, spring torques, hub
angle), ``equilibrium`` (the pose under a dead tip load and gravity, and its stiffness),
``damping`` (damping that leaves the hub's rigid mode undamped), ``linearize`` (the entry
point) and ``state_space`` (``LinearModel`` and its modal view); ``second_order`` (any plant of
the package as M, C_d, K with its rigid-body and flexible parts), ``comparison`` (a PRBDM plant
against the truth of the same plant, with ``comparison_metrics``, ``comparison_record`` (JSON,
summary) and ``comparison_plot`` (Bode figure)); ``comparison_truth`` (the truth plant a request
asks for, compared); ``truth_comparison`` (the tip step response and FRF against the truth's
modal superposition, with ``truth_comparison_plot``); ``actuator_fit`` (strain actuator maps
fitted to the truth's modal gains). Nothing is imported here, so that
:mod:`prbdm_pin.model.prbdm_model` can use :mod:`.hub` without loading the rest;
``fit_strain_actuators`` loads on first use.
"""

import importlib
from typing import Any

__all__ = ["fit_strain_actuators"]


def __getattr__(name: str) -> Any:
    if name == "fit_strain_actuators":
        return importlib.import_module(".actuator_fit", __name__).fit_strain_actuators
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
