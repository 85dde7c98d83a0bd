"""``linearize_batch``: the linear plants of many designs about their unloaded straight pose.

For planar clamped designs with modal damping, what :func:`prbdm_pin.linearize` computes per
design is computed over the stack: the mass matrices in closed form
(:func:`prbdm_pin.chain.planar_batch.batch_mass`, checked against Pinocchio's CRBA in the
tests), the modal damping from one stacked eigensolve
(:func:`prbdm_pin.simulation.damping.spring_modal_damping`) and X = M^-1 [K, C_d, B_q] from
one stacked solve (``first_order``'s system, stacked). The input and output maps and the
outputs' values at the pose are :func:`prbdm_pin.linearize`'s own, computed once per Pinocchio
model (designs made by ``with_stiffness`` share theirs; a row of ``spring_torque`` reads the
springs and is made per design). A load, gravity, a pose, a spin, another damping form, the
outputs that read the acceleration, hubs, buses and spatial chains loop over
:func:`prbdm_pin.linearize`.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

import numpy as np

from ..chain.planar_batch import batch_mass, design_links
from ..errors import SolveError
from ..model.designs import check_designs
from ..model.inputs import StrainActuator, input_map
from ..model.load_outputs import is_load_output
from ..model.outputs import output_maps, output_values, parse_outputs
from ..simulation.damping import damping_ratios, spring_modal_damping
from .acceleration_outputs import output_matrices
from .linearize import linearize
from .state_space import LinearModel

__all__ = ["linearize_batch"]


def linearize_batch(
    models,
    inputs: Sequence[str] = ("tip_force_z",),
    outputs: Sequence[str] = ("tip_z",),
    damping_ratio: float | np.ndarray = 0.02,
    damping: str = "modal",
    actuators: Sequence[StrainActuator] = (),
    **options,
) -> list[LinearModel]:
    """Linearise B designs with the same inputs, outputs and damping.

    Parameters
    ----------
    models : sequence of PrbdmModel
        The designs: one joint count and support (``models[i]`` is refused otherwise).
    inputs, outputs, damping_ratio, damping, actuators
        As :func:`prbdm_pin.linearize` takes them, for every design.
    **options
        :func:`prbdm_pin.linearize`'s other arguments (``q_eq``, ``load_N``,
        ``gravity_m_s2``, ``loads``, ``spin_rad_s``): the designs are then looped through it.

    Returns
    -------
    list of LinearModel
        Entry b is ``linearize(models[b], inputs, outputs, ...)``.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> base = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> models = [base.with_stiffness(base.stiffness_Nm_per_rad * s) for s in (1.0, 2.0)]
    >>> plants = pp.linearize_batch(models, inputs=("tip_force_z",), outputs=("tip_z",))
    >>> one = pp.linearize(models[1], inputs=("tip_force_z",), outputs=("tip_z",))
    >>> len(plants), bool(np.allclose(plants[1].A, one.A, rtol=1e-12, atol=0.0))
    (2, True)
    """
    models = check_designs(models)
    kw = dict(inputs=inputs, outputs=outputs, damping_ratio=damping_ratio, damping=damping,
              actuators=actuators, **options)
    first = linearize(models[0], **kw)  # checks every argument as a single design's call
    links = None
    if not options and damping == "modal" and len(models) > 1 and not any(
            is_load_output(b) for _, b, _ in parse_outputs(first.output_names,
                                                             models[0].n_springs, False)):
        links = design_links(models)
    if links is None:
        return [first] + [linearize(m, **kw) for m in models[1:]]
    return _stacked(models, links, first, damping_ratio, tuple(actuators))


def _stacked(models, links, first: LinearModel, damping_ratio, acts) -> list[LinearModel]:
    B, nv = len(models), int(models[0].pin_model.nv)
    q = np.zeros(nv)
    M = batch_mass(links, np.zeros((B, nv)))
    k = np.array([m.stiffness_Nm_per_rad for m in models], dtype=float)
    Cd = spring_modal_damping(M, k, damping_ratios(damping_ratio, nv))
    ins, outs = first.input_names, first.output_names
    springs_read = any(name.startswith("spring_torque") for name in outs)
    maps: dict[int, tuple] = {}
    rows = []
    for m in models:
        key = id(m.pin_model)  # alive through the call: the models hold them
        if key not in maps:
            maps[key] = (input_map(m, q, ins, acts), *output_maps(m, q, outs),
                         output_values(m, q, outs, np.zeros(3), None))
        Bq, Cq, Cv, y = maps[key]
        if springs_read:
            Cq = output_maps(m, q, outs)[0]
        rows.append((Bq, Cq, Cv, y))
    Bq = np.array([r[0] for r in rows])
    K = k[:, :, None] * np.eye(nv)
    try:
        np.linalg.cholesky(M)  # the check: every M positive definite
        X = np.linalg.solve(M, np.concatenate([K, Cd, Bq], axis=2))
    except np.linalg.LinAlgError as exc:
        raise SolveError(f"linearize_batch: a mass matrix is not positive definite ({exc})"
                         ) from None
    A = np.zeros((B, 2 * nv, 2 * nv))
    A[:, :nv, nv:] = np.eye(nv)
    A[:, nv:, :nv] = -X[:, :, :nv]
    A[:, nv:, nv:] = -X[:, :, nv:2 * nv]
    Bs = np.zeros((B, 2 * nv, Bq.shape[2]))
    Bs[:, nv:] = X[:, :, 2 * nv:]
    p, m_in = len(outs), len(ins)
    Ca, Du = np.zeros((p, nv)), np.zeros((p, m_in))  # no output reads the acceleration here
    out = []
    for b in range(B):
        Bq_b, Cq, Cv, y = rows[b]
        C, D = output_matrices(Cq, Cv, Ca, Du, X[b])
        fields = dict(A=A[b], B=Bs[b], C=C, D=D, q_eq=q.copy(), u_eq=np.zeros(m_in),
                      y_eq=y.copy(), mass_kg_m2=M[b], stiffness_Nm_per_rad=K[b],
                      damping_Nms_per_rad=Cd[b], input_map=Bq_b.copy(),
                      output_map_position=Cq.copy(), output_map_rate=Cv.copy(),
                      output_map_acceleration=Ca.copy(), output_map_input=Du.copy())
        for a in fields.values():
            a.setflags(write=False)
        # the first design's plant gives the names, units and the rest, the same for all
        out.append(dataclasses.replace(first, **fields))
    return out
