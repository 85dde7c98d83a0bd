"""A linearised PRBDM plant against the truth plant of the same hub and actuators.

:func:`compare_truth_plant` computes (or finds in the cache) the truth a :class:`TruthRequest`
asks for, builds its plant on the PRBDM's support (the clamped modal plant, or Likins' hybrid
coordinates on the PRBDM's hub) with the same strain actuators and damping, and compares the two
with :func:`~prbdm_pin.plant.comparison.compare_plant`; ``prbdm linearize --compare-truth`` and
``prbdm simulate --compare-truth`` of a plant write what it returns (``comparison.json``).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import BeamInputError

if TYPE_CHECKING:
    from ..truth.request import TruthRequest
    from ..truth.result import TruthResult
    from .comparison import PlantComparison

__all__ = ["PLANT_TRUTH_MODELS", "TruthPlantComparison", "compare_truth_plant"]

# truths whose modes the truth plant reads (``truth_modal_gains``)
PLANT_TRUTH_MODELS = ("plate", "plate-morley", "beam")


@dataclass(frozen=True, eq=False)
class TruthPlantComparison:
    """A PRBDM plant against its truth plant (what ``comparison.json`` reports).

    Attributes
    ----------
    request : TruthRequest
        The truth asked for.
    truth : TruthResult
        The truth the truth plant was built from.
    comparison : PlantComparison
        Per flexible mode and per (input, output) pair (frequencies rad/s, errors %).
    damping_ratio : float
        Modal damping ratio of every flexible mode of both plants.

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
    >>> report = pp.compare_truth_plant(pp.linearize(model), model, result.truth_request)
    >>> isinstance(report, pp.TruthPlantComparison), report.damping_ratio
    (True, 0.02)
    """

    request: TruthRequest
    truth: TruthResult
    comparison: PlantComparison
    damping_ratio: float

    def to_dict(self, source: str) -> dict[str, Any]:
        """Return the JSON form: what was compared with what, and the comparison.

        ``source`` names the model file; frequencies in rad/s, errors in %.
        """
        from .comparison_record import comparison_dict

        truth = self.truth
        return {
            "prbdm": {"source": source, "linearised_at": "straight pose (q = 0), unloaded"},
            "truth": {"model": truth.model, "request": self.request.to_dict(),
                      "mesh_level": int(truth.mesh_level),
                      "selected_omega_rad_s": [float(w) for w in truth.omega_rad_s]},
            "damping": {"ratio": float(self.damping_ratio),
                        "form": "modal on both sides: every flexible mode of the coupled plant "
                                "(hub-stiffened on a hub), the rigid-body mode undamped"},
            **comparison_dict(self.comparison),
        }


def compare_truth_plant(lin, model, request: TruthRequest, actuators: Sequence = (),
                        damping_ratio: float = 0.02, cache_dir=None) -> TruthPlantComparison:
    """Compare ``lin``, the linearised plant of ``model``, with the truth plant.

    Parameters
    ----------
    lin : LinearModel
        The PRBDM plant (``linearize(model, ..., damping="modal")``), unloaded at the straight
        pose.
    model : PrbdmModel
        The PRBDM, with its beam; on its hub (``model.hub``) the truth plant is on the same hub.
    request : TruthRequest
        The truth: a plate, Morley plate or beam truth (a fit's ``truth_request``).
    actuators : sequence of StrainActuator
        The strain actuators of ``lin``; the truth plant's patches span the same stations (m).
    damping_ratio : float
        Modal damping ratio of every flexible mode of the truth plant (dimensionless), as
        ``lin``'s.
    cache_dir : path, optional
        Truth cache folder (see ``compute_truth``).

    Returns
    -------
    TruthPlantComparison

    Raises
    ------
    BeamInputError
        A model without its beam, or a truth model with no modal plant.

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
    >>> lin = pp.linearize(model, damping_ratio=0.02)
    >>> report = pp.compare_truth_plant(lin, model, result.truth_request)
    >>> [round(m.frequency_error_pct, 3) for m in report.comparison.modes]
    [0.0, 0.0]
    """
    from ..model.checks import check_model
    from ..options.validate import check_type
    from .state_space import LinearModel

    check_type("lin", lin, LinearModel, "a prbdm_pin.LinearModel (linearize)")
    check_model(model)
    from ..truth.plant import clamped_model, hybrid_model
    from .comparison import compare_plant
    from .truth_loads import TIP_MOMENTS, with_truth_loads

    if request.model not in PLANT_TRUTH_MODELS:
        raise BeamInputError(f"request.model = {request.model!r}: has no modal plant; use one "
                             f"of {', '.join(PLANT_TRUTH_MODELS)}")
    beam = model.beam
    if beam is None:
        raise BeamInputError("model: has no beam (a URDF does not carry it), so no truth")
    truth = request.compute(beam, cache_dir=cache_dir)
    stations = [(a.x_start_m, a.x_end_m) for a in actuators]
    # a tip moment's modal column is an actuator's over (0, L) (:mod:`.truth_loads`)
    tip_column = None
    if any(n in TIP_MOMENTS for n in lin.input_names):
        tip_column = f"strain[{len(stations)}]"
        stations = [*stations, (0.0, float(beam.length_m))]
    hub = model.hub
    bus = getattr(model, "bus", None)
    if bus is not None:
        plant = _bus_truth(truth, beam, bus, stations, damping_ratio)
    elif hub is not None and hub.axis != "y":
        # the rotation about x or z does not move the strip along z: uncoupled at first order
        from ..truth.plant import truth_modal_gains
        from ..truth.plant.hub_axis import decoupled_hub_from_gains

        plant = decoupled_hub_from_gains(truth_modal_gains(truth, beam, stations), beam,
                                         hub.inertia_kg_m2, hub.radius_m, hub.axis,
                                         damping_ratio, damping="modal")
    elif hub is None:
        plant = clamped_model(truth, beam, stations, damping_ratio)
    else:
        plant = hybrid_model(truth, beam, hub.inertia_kg_m2, hub.radius_m, stations,
                             damping_ratio, damping="modal")
    plant = with_truth_loads(plant, beam, lin.input_names, tip_column)
    return TruthPlantComparison(request, truth, compare_plant(lin, plant), float(damping_ratio))


def _bus_truth(truth, beam, bus, stations, damping_ratio):
    """Return the truth on the PRBDM's free bus: the planar hybrid model (``truth.plant.bus``).

    It holds the bus's translation along z and its turn about y, so the bus's centre of mass
    must be its frame's origin, the root on the frame's x axis, and y a principal axis of its
    inertia (no product of inertia coupling the pitch with the roll or the yaw).
    """
    from ..truth.plant.bus import bus_model

    com, root, J = (np.asarray(a, dtype=float) for a in (bus.com_m, bus.root_m,
                                                         bus.inertia_kg_m2))
    if np.any(com) or np.any(root[1:]) or root[0] < 0.0 or J[0, 1] or J[1, 2]:
        raise BeamInputError(f"model: bus {bus!r}: the truth's bus plant is planar: it needs "
                             "the centre of mass at the bus frame's origin, the root at "
                             "(r >= 0, 0, 0) and y a principal axis of the inertia")
    return bus_model(truth, beam, bus.mass_kg, float(J[1, 1]), float(root[0]), stations,
                     damping_ratio)
