"""The common plant's short path: what depends on the model alone, cached, and one compiled call.

:func:`prbdm_pin.linearize` of a plain planar chain (no hub, bus or spatial axes; no gravity,
spin, actuators, distributed loads or given pose; ``"modal"`` damping) whose inputs are tip
forces or joint torques and whose outputs are the tip's coordinates, its vertical rate, joint
angles, rates or spring torques goes through here. The names' parsing and checks, the units,
the state names and the selections that turn the tip Jacobian into B_q, C_q, C_v and y_eq
depend on the model and the names only: :func:`plant_layout` builds them once per model and
names (in the model's cache, as its workspace and scalings are). Each call then costs
Pinocchio's CRBA and frame Jacobian, the equilibrium (the straight pose when unloaded) and
one compiled call (:mod:`.plant_kernel`). Anything else, and any call the kernel's guard
refuses, takes the general path, which also raises every error.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import pinocchio as pin

from ..chain.eigen import COND_LIMIT
from ..chain.planar_statics_fast import static_deflection_straight
from ..model.inputs import input_unit, parse_inputs
from ..model.outputs import output_unit, parse_outputs
from ..simulation.damping import damping_ratios
from .equilibrium import check_vector
from .state_space import LinearModel

__all__ = ["PlantLayout", "plant_layout", "fast_linearize"]

# the inputs and outputs read from the tip's linear Jacobian (row: x 0, y 1, z 2)
_TIP_INPUTS = {"tip_force_x": 0, "tip_force_y": 1, "tip_force_z": 2}
_TIP_OUTPUTS = {"tip_x": 0, "tip_y": 1, "tip_z": 2}
_FIXED_OUTPUTS = ("q", "q_rate", "spring_torque")
# 1 / mu below this could overflow: the general path checks it (chain.eigen._SAFE_INVERSE)
_SAFE_INVERSE = 2.0 / np.finfo(float).max
_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
_KERNEL = None
_MAX_RATIOS = 16  # scalar damping ratios kept per layout


@dataclass(frozen=True, eq=False)
class PlantLayout:
    """What the short path's plant takes from the model and the names alone (read-only arrays).

    Attributes
    ----------
    input_names, output_names, input_units, output_units, state_names : tuple of str
    b_sel, b_fixed : ndarray (m, 3), (n, m)
        B_q = J^T b_sel^T + b_fixed (J the tip's linear Jacobian, m/rad).
    cq_sel, cq_fixed, cv_sel, cv_fixed : ndarray (p, 3), (p, n), (p, 3), (p, n)
        C_q = cq_sel J + cq_fixed, C_v = cv_sel J + cv_fixed; y_eq = cq_sel p + cq_fixed q.
    u_sel : ndarray (m, 3)
        u_eq = u_sel F, F the dead tip force (N).
    zeros_pn, zeros_pm : ndarray (p, n), (p, m)
        The acceleration map C_a, the direct map D_u and D (no output here reads either).
    lengths_m : ndarray (n+1,)
        The links' lengths, m (the load stiffness's lever arms).
    ratios : dict
        Checked damping ratios (n,) of the scalar ratios seen, by value.
    """

    input_names: tuple[str, ...]
    output_names: tuple[str, ...]
    input_units: tuple[str, ...]
    output_units: tuple[str, ...]
    state_names: tuple[str, ...]
    b_sel: np.ndarray
    b_fixed: np.ndarray
    cq_sel: np.ndarray
    cq_fixed: np.ndarray
    cv_sel: np.ndarray
    cv_fixed: np.ndarray
    u_sel: np.ndarray
    zeros_pn: np.ndarray
    zeros_pm: np.ndarray
    lengths_m: np.ndarray
    ratios: dict = field(default_factory=dict)


def _layout(model, inputs, outputs) -> PlantLayout | None:
    n = model.n_springs
    ins = parse_inputs(inputs, n, 0, False, 0)
    outs = parse_outputs(outputs, n, False)
    m, p = len(ins), len(outs)
    b_sel, b_fixed, u_sel = np.zeros((m, 3)), np.zeros((n, m)), np.zeros((m, 3))
    for c, (_, base, idx) in enumerate(ins):
        if base in _TIP_INPUTS:
            b_sel[c, _TIP_INPUTS[base]] = 1.0
            u_sel[c, _TIP_INPUTS[base]] = 1.0  # the load's component is the nominal input
        elif base == "joint_torque":
            b_fixed[idx, c] = 1.0
        else:
            return None
    cq_sel, cq_fixed = np.zeros((p, 3)), np.zeros((p, n))
    cv_sel, cv_fixed = np.zeros((p, 3)), np.zeros((p, n))
    for r, (_, base, idx) in enumerate(outs):
        if base in _TIP_OUTPUTS:
            cq_sel[r, _TIP_OUTPUTS[base]] = 1.0
        elif base == "tip_z_rate":
            cv_sel[r, 2] = 1.0
        elif base == "q":
            cq_fixed[r, idx] = 1.0
        elif base == "q_rate":
            cv_fixed[r, idx] = 1.0
        elif base == "spring_torque":
            cq_fixed[r, idx] = model.stiffness_Nm_per_rad[idx]
        else:
            return None
    coords = [f"q[{j}]" for j in range(n)]
    arrays = (b_sel, b_fixed, cq_sel, cq_fixed, cv_sel, cv_fixed, u_sel, np.zeros((p, n)),
              np.zeros((p, m)), np.array(model.lengths_m, dtype=float))
    for a in arrays:
        a.setflags(write=False)
    in_names = tuple(s for s, _, _ in ins)
    out_names = tuple(s for s, _, _ in outs)
    return PlantLayout(in_names, out_names, tuple(input_unit(s) for s in in_names),
                       tuple(output_unit(s) for s in out_names),
                       tuple(coords + [c.replace("q[", "q_rate[") for c in coords]), *arrays)


def plant_layout(model, inputs, outputs) -> PlantLayout | None:
    """Return the short path's layout of ``model`` for these names, or None (general path).

    Built once per model and names and kept in the model's cache; None for names the short
    path does not cover, names that are neither a list nor hashable, or names the checks refuse
    (the general path then raises the error).

    Examples
    --------
    >>> import prbdm_pin as pp
    >>> from prbdm_pin.plant.plant_layout import plant_layout
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> plant_layout(model, ("tip_force_z",), ("tip_z", "q[1]")).state_names
    ('q[0]', 'q[1]', 'q_rate[0]', 'q_rate[1]')
    """
    # a list of names is as common as a tuple: the same key (a bare string stays one, and
    # the checks refuse it)
    key = ("plant_layout", tuple(inputs) if type(inputs) is list else inputs,
           tuple(outputs) if type(outputs) is list else outputs)
    try:
        found = model._cache.get(key, False)
    except TypeError:  # names that are not hashable: not a key
        return None
    if found is False:
        try:
            found = _layout(model, inputs, outputs)
        except (ValueError, TypeError):  # refused names: the general path says why
            return None
        model._cache[key] = found
    return found


def fast_linearize(model, inputs, outputs, load_N, damping_ratio) -> LinearModel | None:
    """Return :func:`prbdm_pin.linearize` of a plain planar chain, or None (the general path).

    The caller has checked that the model and the other options are those of the short path
    (see the module notes). ``load_N`` (N, world, or None) and ``damping_ratio`` (scalar or
    one per mode) as :func:`prbdm_pin.linearize` takes them.
    """
    global _KERNEL
    lay = plant_layout(model, inputs, outputs)
    if lay is None:
        return None
    n, m, p = model.n_springs, lay.b_sel.shape[0], lay.cq_sel.shape[0]
    if load_N is None:
        F = np.zeros(3)
        q = np.zeros(n)
    else:
        F = check_vector("load_N", load_N, "N")
        # the general path's equilibrium (the planar statics from the straight pose), its
        # plain descent compiled
        q = static_deflection_straight(lay.lengths_m, model.stiffness_Nm_per_rad, F)
    # a scalar ratio's checked broadcast, kept with the layout (the check costs as much as the
    # kernel's arithmetic); a float is a safe key, its checked vector read-only
    xi = lay.ratios.get(damping_ratio) if type(damping_ratio) is float else None
    if xi is None:
        xi = damping_ratios(damping_ratio, n)
        if type(damping_ratio) is float and len(lay.ratios) < _MAX_RATIOS:
            xi.setflags(write=False)
            lay.ratios[damping_ratio] = xi
    pm, data = model.pin_model, model.default_data
    M = pin.crba(pm, data, q)
    J = pin.computeFrameJacobian(pm, data, q, model.tip_frame_id, _LWA)[:3].reshape(3, n)
    tip = pin.updateFramePlacement(pm, data, model.tip_frame_id).translation
    if _KERNEL is None:  # numba is imported on first use, not with the package
        from .plant_kernel import assemble_plant_entry

        _KERNEL = assemble_plant_entry()
    A, B, C = np.empty((2 * n, 2 * n)), np.empty((2 * n, m)), np.empty((p, 2 * n))
    K, Cd, Bq = np.empty((n, n)), np.empty((n, n)), np.empty((n, m))
    y, u = np.empty(p), np.empty(m)
    if not _KERNEL(M, model.stiffness_Nm_per_rad, xi, lay.lengths_m, J, tip, q, F, lay.b_sel,
                   lay.b_fixed, lay.cq_sel, lay.cq_fixed, lay.cv_sel, lay.cv_fixed, lay.u_sel,
                   COND_LIMIT, _SAFE_INVERSE, A, B, C, K, Cd, Bq, y, u):
        return None
    for a in (A, B, C, K, Cd, Bq, y, u, M, q):
        a.setflags(write=False)
    # no output reads the acceleration: C = [C_q, C_v], whose halves are read-only views
    Cq, Cv = C[:, :n], C[:, n:]
    # the frozen dataclass's __init__ sets its 24 fields one object.__setattr__ at a time
    # (a fifth of this call); it has no __post_init__, so its instance dict is filled at once
    lin = object.__new__(LinearModel)
    lin.__dict__.update(
        A=A, B=B, C=C, D=lay.zeros_pm, state_names=lay.state_names,
        input_names=lay.input_names, output_names=lay.output_names,
        input_units=lay.input_units, output_units=lay.output_units, q_eq=q, u_eq=u, y_eq=y,
        mass_kg_m2=M, stiffness_Nm_per_rad=K, damping_Nms_per_rad=Cd, input_map=Bq,
        output_map_position=Cq, output_map_rate=Cv, hub=False, spin_rad_s=0.0,
        gyroscopic_Nms_per_rad=None, output_map_acceleration=lay.zeros_pn,
        output_map_input=lay.zeros_pm, n_free=0,
    )
    return lin
