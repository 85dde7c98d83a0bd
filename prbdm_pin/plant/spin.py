"""A hub model in steady spin: the relative equilibrium and the spin terms of its linearisation.

The hub turns at the constant rate Omega (rad/s) about its axis; the state of the linear plant
is the deviation from that motion: the hub angle less Omega t, the hub rate less Omega, and the
beam joints with their rates. Writing the equations of motion as M(q) a + h(q, v) + K q = tau,
with h the Coriolis and centrifugal terms (Pinocchio's RNEA at a = 0 and no gravity, which the
statics carry), a steady spin v = (Omega, 0, ..., 0), a = 0 needs K q + h(q, v) = tau_u on the
beam joints; the hub's row is the torque that holds the rate (0 when no energy flows: a free hub
with no torque keeps spinning at the relative equilibrium). Linearised about it::

    M dv' + (C_d + dh/dv) dv + (K_e + dh/dq) dq = B_q u

dh/dq and dh/dv come from ``pinocchio.computeRNEADerivatives`` at (q_eq, (Omega, 0...), 0):
dh/dq is -Omega^2 / 2 d^2 M_hh / dq^2 on the beam joints (the hub angle is cyclic: M does not
depend on it), the centrifugal stiffening (or softening, a negative term in the plane of
rotation); dh/dv is Omega (dM_ih/dq_j - dM_jh/dq_i), the gyroscopic (Coriolis) coupling
(skew; on the hub's row and column Omega dM_hh/dq_j, zero at the straight pose where M_hh is
stationary, not at a coned one).

When is the straight pose the relative equilibrium? The beam joints turn about y and the beam
lies along x. Centrifugal forces act away from the hub axis through the origin: on the straight
beam (in the xz-plane, on the x axis) they lie along x for a hub about y or z and vanish for a
hub about x (the beam on the axis), so they exert no moment about any beam joint: h(0, v) = 0
and the unloaded straight pose is the relative equilibrium for every hub axis. A dead tip load
or gravity turns with the world, not with the hub, so the loaded spinning beam has no steady
relative equilibrium in general (the load's direction in the hub frame goes round once a turn):
:func:`check_spin` refuses them, unless they lie along the hub axis, where a turn leaves them
as they are (a rotor about z under gravity or a tip lift along z: the beam cones). Then the
relative equilibrium solves K q + g(q) - J^T F + h(q, (Omega, 0...)) = 0 on the beam joints
(:func:`prbdm_pin.plant.equilibrium.equilibrium`, Newton with the tangent K_e + dh/dq).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from ..chain.eigen import generalized_eigh
from ..errors import BeamInputError, InputTypeError
from ..model.hub import schur_mass
from ..options.checks import check_bool, check_float

__all__ = ["check_spin", "gyroscopic_frequencies", "spin_terms", "spinning_frequencies"]


def check_spin(model, spin_rad_s, load_N: np.ndarray | None, gravity_m_s2: np.ndarray | None
               ) -> float:
    """Return ``spin_rad_s`` (rad/s) checked for ``model``: a finite float, 0.0 for None.

    A spin needs a hub, and a dead tip load or gravity only along the hub axis (module notes).

    Raises
    ------
    BeamInputError
        Naming ``spin_rad_s`` (not finite, no hub, a load or gravity off the hub axis).
    """
    w = check_float("spin_rad_s", spin_rad_s, optional=True, unit="rad/s")
    if w is None or w == 0.0:
        return 0.0
    if model.hub is None:
        raise BeamInputError(f"spin_rad_s = {w!r}: needs a hub to spin (build the model with "
                             "hub=Hub(...))")
    off_axis = [i for i, a in enumerate("xyz") if a != model.hub.axis]
    for name, v in (("load_N", load_N), ("gravity_m_s2", gravity_m_s2)):
        if v is not None and np.any(np.asarray(v)[off_axis]):
            raise BeamInputError(f"spin_rad_s = {w!r} with {name} = {np.asarray(v).tolist()}: "
                                 "a dead load or gravity off the hub axis "
                                 f"({model.hub.axis}) turns relative to the spinning hub, so "
                                 "the beam has no steady equilibrium under it; give it along "
                                 "the hub axis, or none")
    return float(w)


def spin_terms(model, q: np.ndarray, spin_rad_s: float
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return h, dh/dq and dh/dv of ``model`` at pose ``q`` (rad) spinning at ``spin_rad_s``.

    h = RNEA(q, (Omega, 0, ...), 0) without gravity: the Coriolis and centrifugal generalized
    forces, N m, shape (nv,); dh/dq, N m/rad, and dh/dv, N m s/rad, shape (nv, nv), from
    ``pinocchio.computeRNEADerivatives`` (dh/dq's hub row and column set to their exact 0).
    """
    pm = model.pin_model
    if np.any(pm.gravity.vector):  # a user's gravity: the statics carry the weight, not h
        pm = pin.Model(pm)
        pm.gravity = pin.Motion.Zero()
    data = pm.createData()
    q = np.asarray(q, dtype=float)
    v = np.zeros(pm.nv)
    v[0] = spin_rad_s
    a = np.zeros(pm.nv)
    h = np.array(pin.rnea(pm, data, q, v, a))
    dq, dv, _ = pin.computeRNEADerivatives(pm, data, q, v, a)
    dq = np.array(dq)
    # the hub angle is cyclic (M and h do not depend on it) and h_hub = 1/2 dM_hh/dq_hub
    # Omega^2 = 0, so the hub's row and column of dh/dq are exactly zero; RNEA leaves roundings
    # there, which would hide the plant's rigid mode (K e_hub = 0) from its modal view
    dq[0, :] = 0.0
    dq[:, 0] = 0.0
    return h, dq, np.array(dv)


def spinning_frequencies(model, spin_rad_s: float, hub_free: bool = True,
                         squared: bool = False) -> np.ndarray:
    """Return the flexible frequencies of a hub model spinning unloaded at ``spin_rad_s``.

    Parameters
    ----------
    model : PrbdmModel
        With a hub (any axis), at its straight pose (the relative equilibrium).
    spin_rad_s : float
        The hub's steady rate, rad/s (0: the model at rest).
    hub_free : bool
        True: the hub turns freely about the steady spin (no torque deviation), as
        :func:`prbdm_pin.linearize` models it; the rigid mode is left out (the Schur complement
        of the hub, :func:`prbdm_pin.model.hub.schur_mass`). False: the hub held at the constant
        rate (a prescribed rotation, as the rotating-beam literature's Southwell coefficients
        assume).
    squared : bool
        Return omega^2 (rad^2/s^2, negative for a mode the spin made unstable) instead of
        omega (rad/s; such a mode then reads 0).

    Returns
    -------
    ndarray, shape (n,)
        Ascending. The stiffness is K - Omega^2 / 2 d^2 M_hh / dq^2 (RNEA derivatives); the
        gyroscopic term dh/dv vanishes at the straight pose (the hub's row of M, M_hh
        included, is even in every joint angle there, so stationary), so the undamped modes
        of (K, M) are the linear plant's.

    Raises
    ------
    BeamInputError
        ``model`` without a hub, a ``spin_rad_s`` that is not finite.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> hub_model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0],
    ...                           hub=pp.Hub(inertia_kg_m2=50.0))
    >>> still = pp.spinning_frequencies(hub_model, 0.0, hub_free=False)
    >>> spun = pp.spinning_frequencies(hub_model, 10.0, hub_free=False)
    >>> bool(np.all(spun > still))  # centrifugal stiffening
    True
    """
    from ..model.prbdm_model import PrbdmModel

    if not isinstance(model, PrbdmModel):
        raise InputTypeError(f"model = {model!r:.60}: must be a PrbdmModel")
    if model.hub is None:
        raise BeamInputError("model: has no hub; spinning_frequencies needs a hub model "
                             "(build_model(..., hub=Hub(...)))")
    w = check_float("spin_rad_s", spin_rad_s, unit="rad/s")
    free = check_bool("hub_free", hub_free)
    q = np.zeros(model.pin_model.nv)
    M = model.mass_matrix(q)
    K = model.stiffness_matrix()
    if w:
        dh_dq = spin_terms(model, q, w)[1]
        K = K + 0.5 * (dh_dq + dh_dq.T)
    Mf = schur_mass(M) if free else M[1:, 1:]
    w2 = generalized_eigh(K[1:, 1:], Mf, "spinning frequencies", vectors=False)
    return w2 if check_bool("squared", squared) else np.sqrt(np.clip(w2, 0.0, None))


def gyroscopic_frequencies(lin) -> np.ndarray:
    """Return the undamped flexible frequencies of a linearised spinning plant, rad/s.

    The eigenvalues +-i omega of M q'' + G q' + K_e q = 0 (``lin`` from
    :func:`prbdm_pin.linearize` with ``spin_rad_s``; G its ``gyroscopic_Nms_per_rad``),
    ascending, one per pair, the rigid mode's zeros left out. At the straight pose G = 0 and
    they are ``lin.modal()``'s; at a coned pose G couples the hub to the flapping.

    Raises
    ------
    BeamInputError
        ``lin`` not linearised about a spin (InputTypeError: not a LinearModel).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> hub_model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0],
    ...                           hub=pp.Hub(inertia_kg_m2=50.0))
    >>> lin = pp.linearize(hub_model, inputs=("hub_torque",), outputs=("hub_angle",),
    ...                    spin_rad_s=5.0)
    >>> pp.gyroscopic_frequencies(lin).round(1)
    array([ 59.8, 321.3])
    """
    from .state_space import LinearModel

    if not isinstance(lin, LinearModel):
        raise InputTypeError(f"lin = {lin!r:.60}: must be a prbdm_pin.LinearModel (linearize)")
    G = lin.gyroscopic_Nms_per_rad
    if G is None:
        raise BeamInputError("lin: not linearised about a spin (linearize(..., spin_rad_s=...))")
    M, K = lin.mass_kg_m2, lin.stiffness_Nm_per_rad
    n = M.shape[0]
    X = np.linalg.solve(M, np.hstack([K, G]))
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-X[:, :n], -X[:, n:]]])
    lam = np.linalg.eigvals(A)
    # a gyroscopic conservative system: purely imaginary pairs (and the rigid mode's zeros)
    w = np.sort(np.abs(lam.imag[lam.imag > 0.0]))
    if lin.hub:
        w = w[w > 1e-9 * max(float(w.max(initial=0.0)), 1e-300)]
    return w
