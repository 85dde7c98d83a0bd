"""The plant side of an export.

The strain actuators and inputs a file carries, and the stiffness-form damping of a model with or
without a hub.

With a hub the damping is :func:`prbdm_pin.simulation.hub_damping.plant_damping`'s stiffness form
(beta = 2 xi_1 / omega_1 from the lowest flexible frequency of the hub model, the hub joint
undamped), so that an MJCF, ``linearize(..., damping="stiffness")`` and a simulation of the
plant agree.
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError
from ..simulation.damping import modal_ratios, stiffness_damping_coefficient

__all__ = ["MJCF_INPUTS", "stiffness_form", "plant_inputs", "mujoco_name"]

# the inputs the MJCF export writes as MuJoCo actuators (the bases of their names)
MJCF_INPUTS = ("hub_torque", "joint_torque", "strain", "tip_force_z", "tip_force_x")


def mujoco_name(input_name: str) -> str:
    """Return the MuJoCo actuator (and tendon) name of an input.

    ``strain[0]`` -> ``strain_0``, ``joint_torque[2]`` -> ``joint_torque_2``; names without an
    index are kept.
    """
    return input_name.replace("[", "_").replace("]", "")


def stiffness_form(model, M: np.ndarray, xi: np.ndarray, omega_hub: np.ndarray | None):
    """Compute the stiffness form C = beta K of ``model`` with mode 1's ratio ``xi[0]``.

    Parameters
    ----------
    model : PrbdmModel
        The exported model, with or without a hub.
    M : ndarray, shape (n, n) or (n+1, n+1)
        Mass matrix at the straight pose, kg m^2.
    xi : ndarray
        Damping ratios; mode 1's is used.
    omega_hub : ndarray or None
        The hub model's flexible frequencies, rad/s (None without a hub).

    Returns
    -------
    beta : float
        The stiffness-proportional coefficient, s.
    c : ndarray, shape (n,)
        The beam joints' damping beta K_jj, N m s/rad.
    ratios : ndarray
        The damping ratio it gives each (flexible) mode.
    """
    k = np.asarray(model.stiffness_Nm_per_rad, dtype=float)
    if omega_hub is None:
        K = model.stiffness_matrix()
        beta = stiffness_damping_coefficient(M, K, xi)
        c = beta * k
        return beta, c, modal_ratios(M, K, np.diag(c))
    from ..model.hub import hub_modes
    from ..simulation.hub_damping import plant_damping

    # the plant's own stiffness form, so that the file, linearize and simulate agree
    C = plant_damping(model, M, xi, "stiffness")
    omega, Phi = hub_modes(M, k)
    flex = Phi[:, 1:]
    ratios = np.einsum("ik,ij,jk->k", flex, C, flex) / (2.0 * omega[1:])
    return 2.0 * float(xi[0]) / float(omega_hub[0]), np.diag(C)[1:].copy(), ratios


def plant_inputs(model, fmt: str, actuators, inputs
                 ) -> tuple[np.ndarray, tuple, tuple[str, ...]]:
    """Check a plant's strain actuators and the inputs a file of ``fmt`` drives.

    Actuators must lie on the beam, with one joint weight per joint when they have weights.

    Returns
    -------
    spans : ndarray, shape (k, 2)
        The actuators' [x_start_m, x_end_m], m.
    weights : tuple
        Each actuator's joint weights (a tuple, or None for the virtual-work map).
    names : tuple of str
        The input names.
    """
    from ..model.inputs import StrainActuator, parse_inputs, strain_map

    if isinstance(actuators, (str, bytes)) or not hasattr(actuators, "__len__"):
        raise BeamInputError(f"actuators = {actuators!r:.60}: must be a sequence of "
                             "StrainActuator")
    if model.axes.spatial and (len(actuators) or (inputs is not None and len(inputs))):
        what = "actuators" if len(actuators) else "inputs"
        raise BeamInputError(f"{what}: the strain actuators and the MJCF inputs are defined on "
                             f"the planar chain only (axes='y'); this model has axes = "
                             f"{model.axes.value!r}")
    for i, a in enumerate(actuators):
        if not isinstance(a, StrainActuator):
            raise BeamInputError(f"actuators[{i}] = {a!r:.60}: must be a StrainActuator")
        strain_map(model.lengths_m, a, f"actuators[{i}]")
    spans = np.array([[a.x_start_m, a.x_end_m] for a in actuators], dtype=float).reshape(-1, 2)
    weights = tuple(a.joint_weights for a in actuators)
    hub = model.hub is not None
    if inputs is None:
        if fmt != "mjcf":
            return spans, weights, ()
        inputs = (("hub_torque",) if hub else ()) + tuple(
            f"strain[{i}]" for i in range(len(actuators)))
    elif fmt != "mjcf" and len(inputs):
        raise BeamInputError(f"inputs = {list(inputs)!r}: a {fmt} file carries no actuators "
                             "(only the MJCF does)")
    if not len(inputs):
        return spans, weights, ()
    parsed = parse_inputs(tuple(inputs), model.n_joints, len(actuators), hub)
    for i, (name, base, _) in enumerate(parsed):
        if base not in MJCF_INPUTS:  # the plant's other inputs have no MuJoCo transmission here
            raise BeamInputError(f"inputs[{i}] = {name!r}: not an MJCF input; one of "
                                 f"{', '.join(MJCF_INPUTS)}")
    return spans, weights, tuple(name for name, _, _ in parsed)
