"""What a simulation takes in and records besides its state: the plant inputs and outputs.

``plant_signals`` checks the named inputs and outputs of a run before any work (and makes the
system's input force), and ``recorded`` evaluates the outputs along the samples: the strain and
the root reaction from each sample's acceleration and applied loads, a free bus's own outputs.
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError, InputTypeError
from ..model.bus_outputs import bus_output_samples, bus_output_unit, parse_bus_outputs
from ..model.inputs import StrainActuator, check_corner_names, parse_inputs, strain_map
from ..model.load_outputs import is_load_output
from ..model.loads import check_load
from ..model.outputs import check_output_stations, output_samples, output_unit, parse_outputs
from ..model.reaction import check_load_inputs
from ..options.integrators import Integrator
from .inputs import input_force
from .load_samples import sample_accelerations, sample_loads

__all__ = ["plant_signals", "recorded"]


def plant_signals(model, inputs, u, actuators, outputs, integrator: Integrator, loads=()):
    """Check the plant inputs and outputs before any work.

    Returns (a maker of the system's InputForce or None, the output names).
    """
    acts = tuple(actuators) if isinstance(actuators, (list, tuple)) else actuators
    if not isinstance(acts, tuple) or not all(isinstance(a, StrainActuator) for a in acts):
        raise BeamInputError(f"actuators = {actuators!r:.80}: must be a sequence of "
                             "StrainActuator")
    hub = model.hub is not None
    n_springs = int(getattr(model, "n_springs", model.n_joints))  # spatial: per axis and node
    out_names, loads_read = (), False
    bus = getattr(model, "bus", None) is not None
    if bus and not (isinstance(outputs, (list, tuple)) and len(outputs) == 0):
        out_names = parse_bus_outputs(outputs, n_springs)
        check_corner_names(model.member, out_names, "outputs")
    elif not (isinstance(outputs, (list, tuple)) and len(outputs) == 0):
        parsed_out = parse_outputs(outputs, n_springs, hub)
        out_names = tuple(n for n, _, _ in parsed_out)
        check_corner_names(model, out_names, "outputs")
        check_output_stations(model, out_names)
        loads_read = any(is_load_output(b) for _, b, _ in parsed_out)
    if isinstance(inputs, (list, tuple)) and len(inputs) == 0:
        if u is not None:
            raise BeamInputError("u: given without inputs; name the inputs it drives")
        return None, out_names
    lds = check_loads(model, loads)
    parsed_in = parse_inputs(inputs, n_springs, len(acts), hub, len(lds))
    names = tuple(n for n, _, _ in parsed_in)
    check_corner_names(model, names, "inputs")
    if loads_read:  # the root reaction and the strain must know every input's load
        check_load_inputs(parsed_in)
    if not integrator.takes_inputs:
        raise BeamInputError(f"inputs: method {integrator.method!r} takes a tip force only; "
                             "use 'auto' (default), 'exponential', 'trapezoidal' or a "
                             "solve_ivp method")
    if acts and getattr(getattr(model, "axes", None), "spatial", False):
        raise BeamInputError(f"actuators: strain actuators act on the planar chain's bending "
                             f"joints; this model has axes {model.axes.value!r}")
    for i, a in enumerate(acts):
        strain_map(model.lengths_m, a, f"actuators[{i}]")
    return (lambda tip_terms: input_force(model, names, u, acts, tip_terms, lds)), out_names


def check_loads(model, loads) -> tuple:
    """Check the DistributedLoad spans against the model's beam (naming ``loads[i]``)."""
    if isinstance(loads, (str, bytes)) or not isinstance(loads, (list, tuple)):
        raise InputTypeError(f"loads = {loads!r:.80}: must be a sequence of DistributedLoad")
    for i, ld in enumerate(loads):
        check_load(model.lengths_m, ld, f"loads[{i}]")
    return tuple(loads)


def recorded(model, system, out_names, t, Q, V, tip, force, gravity, spans=()) -> tuple:
    """(input names, units, values, output names, units, values) of the samples.

    The root reaction and the strain read the samples' accelerations and applied loads (the
    tip force ``force`` of time, N, and the inputs, the distributed ones over ``spans``) under
    the gravity (m/s^2, world).
    """
    f = system.inputs
    if f is None:
        U, in_names, in_units = np.zeros((len(t), 0)), (), ()
    else:
        U = np.array([f.values(ti, q, v) for ti, q, v in zip(t, Q, V, strict=True)])
        U = U.reshape(len(t), len(f.names))
        in_names, in_units = f.names, f.units
    if not out_names:
        Y = np.zeros((len(t), 0))
    elif getattr(model, "bus", None) is not None:
        Y = bus_output_samples(model, Q, V, tip, out_names)
        return (in_names, in_units, U, out_names, tuple(bus_output_unit(s) for s in out_names),
                Y)
    else:
        A = loads = None
        if any(is_load_output(b) for _, b, _ in parse_outputs(out_names, model.n_springs,
                                                              model.hub is not None)):
            A = sample_accelerations(system, t, Q, V)
            loads = sample_loads(model, system, force, t, U, spans)
        Y = output_samples(model, Q, V, tip, out_names, A, loads, gravity)
    return (in_names, in_units, U, out_names, tuple(output_unit(s) for s in out_names), Y)
