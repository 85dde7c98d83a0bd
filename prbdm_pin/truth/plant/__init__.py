"""The finite-element truth as a control plant: modal gains and a hub in hybrid coordinates.

``truth_modal_gains`` (``gains``): per selected clamped mode of a plate or 1D beam truth, the
generalised force of a tip force and of full-width strain actuators (moment pairs) and the tip z
output. ``hybrid_model`` (``hybrid``): the truth on a rotating rigid hub (Likins' hybrid
coordinates) as M, K and a state space with the PRBDM plant's input and output names.
``clamped_model`` (``clamped``): the clamped truth's selected modes as a state space with the
same names, the truth side of a PRBDM plant without a hub. ``bus_model`` (``bus``): the truth on a
free-floating rigid bus (hybrid coordinates with the bus's translation and rotation).

A subpackage on purpose: the truth's code digest (``truth.digest``) covers ``truth/*.py`` and
what it imports, and these modules only read a truth, so adding them leaves every truth's cache
key as it was.
"""

from .bus import BUS_OUTPUT_NAMES, BusModel, bus_from_gains, bus_input_names, bus_model
from .clamped import (
    CLAMPED_OUTPUT_NAMES,
    ClampedModel,
    clamped_from_gains,
    clamped_input_names,
    clamped_model,
)
from .gains import ModalGains, check_actuators, truth_modal_gains
from .hybrid import (
    DAMPING_KINDS,
    OUTPUT_NAMES,
    HybridModel,
    hub_frequencies_rad_s,
    hub_modal_damping,
    hybrid_from_gains,
    hybrid_matrices,
    hybrid_model,
    input_names,
)

__all__ = [
    "ModalGains",
    "truth_modal_gains",
    "check_actuators",
    "HybridModel",
    "hybrid_model",
    "hybrid_from_gains",
    "hybrid_matrices",
    "hub_frequencies_rad_s",
    "hub_modal_damping",
    "input_names",
    "DAMPING_KINDS",
    "OUTPUT_NAMES",
    "ClampedModel",
    "clamped_model",
    "clamped_from_gains",
    "clamped_input_names",
    "CLAMPED_OUTPUT_NAMES",
    "BusModel",
    "bus_model",
    "bus_from_gains",
    "bus_input_names",
    "BUS_OUTPUT_NAMES",
]
