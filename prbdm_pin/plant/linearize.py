"""``linearize``: a PRBDM as a linear plant about its equilibrium.

The entry point of :mod:`prbdm_pin.plant`.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from scipy.linalg.lapack import dposv as _posv

from ..errors import BeamInputError, InputTypeError, SolveError
from ..model.inputs import (
    StrainActuator,
    check_corner_names,
    input_map,
    input_unit,
    parse_inputs,
)
from ..model.load_outputs import is_load_output
from ..model.loads import check_load
from ..model.outputs import (
    check_output_stations,
    output_maps,
    output_unit,
    output_values,
    parse_outputs,
)
from ..simulation.hub_damping import plant_damping
from .acceleration_outputs import load_rows, output_matrices
from .equilibrium import check_vector, equilibrium, gravity_model, static_terms
from .plant_layout import fast_linearize
from .spin import check_spin, spin_terms
from .state_space import LinearModel

__all__ = ["linearize"]


def _pose(model, q_eq) -> np.ndarray:
    nv = model.pin_model.nv
    try:
        q = np.array(q_eq, dtype=float)
    except (TypeError, ValueError):
        q = np.array([np.nan])
    if q.shape != (nv,) or not np.all(np.isfinite(q)):
        raise BeamInputError(f"q_eq = {q_eq!r}: must be {nv} finite joint angles (rad"
                             f"{', the hub angle first' if model.hub is not None else ''})")
    return q


def _actuators(actuators) -> tuple[StrainActuator, ...]:
    if isinstance(actuators, StrainActuator) or not isinstance(actuators, Sequence):
        raise BeamInputError(f"actuators = {actuators!r}: must be a sequence of StrainActuator")
    for i, a in enumerate(actuators):
        if not isinstance(a, StrainActuator):
            raise BeamInputError(f"actuators[{i}] = {a!r}: must be a StrainActuator")
    return tuple(actuators)


def _loads(model, loads) -> tuple:
    if isinstance(loads, (str, bytes)) or not isinstance(loads, Sequence):
        raise InputTypeError(f"loads = {loads!r:.60}: must be a sequence of DistributedLoad")
    for i, ld in enumerate(loads):
        check_load(model.lengths_m, ld, f"loads[{i}]")
    return tuple(loads)


def first_order(M: np.ndarray, K: np.ndarray, Cd: np.ndarray, Bq: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return A (2 nv, 2 nv), B (2 nv, m) of M dv' + C_d dv + K dq = B_q u (SI units).

    And X = M^-1 [K, C_d, B_q] (nv, 2 nv + m), which the outputs that read the acceleration
    need. SolveError unless M is positive definite.
    """
    nv, m = M.shape[0], Bq.shape[1]
    rhs = np.empty((nv, 2 * nv + m))
    rhs[:, :nv], rhs[:, nv:2 * nv], rhs[:, 2 * nv:] = K, Cd, Bq
    # the Cholesky factor is the check (M must be positive definite) and the solve, for the
    # three right-hand sides at once, in one LAPACK call (numpy's wrappers cost more than the
    # arithmetic for these small matrices)
    _, X, info = _posv(M, rhs, lower=0, overwrite_a=0, overwrite_b=1)
    if info != 0:  # info > 0: a leading minor is not positive, as numpy's Cholesky check
        raise SolveError(f"linearize: mass matrix not positive definite (LAPACK info {info})")
    A = np.zeros((2 * nv, 2 * nv))
    A[:nv, nv:] = np.eye(nv)
    A[nv:, :nv] = -X[:, :nv]
    A[nv:, nv:] = -X[:, nv:2 * nv]
    B = np.zeros((2 * nv, m))
    B[nv:] = X[:, 2 * nv:]
    return A, B, X


def linearize(
    model,
    inputs: Sequence[str] = ("tip_force_z",),
    outputs: Sequence[str] = ("tip_z",),
    q_eq: np.ndarray | None = None,
    load_N: np.ndarray | None = None,
    damping_ratio: float | np.ndarray = 0.02,
    damping: str = "modal",
    actuators: Sequence[StrainActuator] = (),
    gravity_m_s2: np.ndarray | None = None,
    loads: Sequence = (),
    spin_rad_s: float | None = None,
    compiled: bool = True,
) -> LinearModel:
    """Linearise ``model`` about an equilibrium.

    Parameters
    ----------
    model : PrbdmModel
        The chain: planar (with or without hub) or spatial (``axes`` ``"xy"``, ``"yz"``,
        ``"xyz"``: linearised through Pinocchio's general kinematics and the exact tangent
        stiffness of :mod:`prbdm_pin.chain.spatial_tangent`).
    inputs : sequence of str
        ``tip_force_z``, ``tip_force_x``, ``tip_force_y`` (N, world, at the tip centre),
        ``tip_moment_x`` (N m, about world x at the tip: a torque on the twist),
        ``tip_moment_y``, ``tip_moment_z`` (N m, dead, about world y and z at the tip),
        ``corner_force_z_left``, ``corner_force_z_right`` (N, world z at the tip corners, +/- the
        tip half-width along the tip link's y axis; a planar chain feels their bending part
        only), ``joint_torque[j]`` (N m, spring coordinate j from the root, 0-based: beam joint
        j of a planar chain, the ``spring_axes`` order of a spatial one), ``strain[i]`` (N m,
        the moment of ``actuators[i]``; planar chains), ``hub_torque`` (N m, hub models);
        ``tip_moment_follower_x``, ``_y``, ``_z`` (N m, about the tip link's own axes),
        ``distributed_force_x``, ``_y``, ``_z`` (N/m, world, uniform over the whole beam;
        ``distributed_force_z[i]``: over ``loads[i]``), ``base_accel_x``, ``_y``, ``_z``
        (m/s^2, a translating base's acceleration: the inertial load -m a on every link;
        the states and outputs are then measured in the base frame, relative to the base);
        see :mod:`prbdm_pin.model.loads`.
    outputs : sequence of str
        ``tip_z``, ``tip_z_rate``, ``tip_x``, ``tip_y`` (m, m/s), ``tip_twist`` (rad, the tip
        section's rotation about the tip link's own axis), ``corner_z_left``,
        ``corner_z_right`` (m, z of the tip corners), ``q[j]``, ``q_rate[j]``,
        ``spring_torque[j]`` (every spring coordinate), ``hub_angle``, ``hub_rate``;
        ``slope@X``, ``twist@X`` (rad), ``point_x@X:Y``, ``point_y@X:Y``, ``point_z@X:Y`` (m),
        ``strain@X`` (microstrain) at station X m from the root (and Y m across);
        ``root_force_x|y|z`` (N), ``root_moment_x|y|z`` (N m), the member's wrench on its
        support (see :mod:`prbdm_pin.model.outputs`); on a free bus also
        ``bus_attitude_x|y|z``, ``bus_rate_x|y|z``, ``bus_position_x|y|z``
        (:mod:`prbdm_pin.model.bus_outputs`). Corner, strain and point signals need the
        model's beam (its width, E I). The root reaction and the strain near the root read
        the acceleration: their C and D carry it (:mod:`prbdm_pin.plant.acceleration_outputs`).
    q_eq : array_like (nv,), optional
        Pose to linearise about, rad, taken as given; default: the equilibrium under
        ``load_N`` and gravity (a hub held at angle 0 by a trim torque).
    load_N : array_like (3,), optional
        Dead tip force, N, world (default none), at the tip centre. Its load stiffness enters
        K_e = K - d(J^T F)/dq (+ dg/dq under gravity).
    damping_ratio : float or array (n,)
        Damping ratio of each flexible mode (``"modal"``; ``"modal_fit"``, the diagonal joint
        damping fitted to them), of the lowest (``"stiffness"``), or per joint (``"eq5c"``, no
        hub); dimensionless.
    damping : str
        Damping form, see :mod:`prbdm_pin.simulation.hub_damping`.
    actuators : sequence of StrainActuator
        The strain actuators ``strain[i]`` refers to.
    gravity_m_s2 : array_like (3,), optional
        Gravity, m/s^2, world; default none.
    loads : sequence of DistributedLoad
        The spans (and profiles) ``distributed_force_z[i]`` (and ``_x``, ``_y``) refer to.
    spin_rad_s : float, optional
        Hub models: linearise about the steady spin of the hub at this rate, rad/s, about its
        axis (default none: at rest). The states are then deviations from the spinning motion
        (the hub angle less Omega t, the hub rate less Omega); the centrifugal stiffness dh/dq
        enters ``stiffness_Nm_per_rad`` and the gyroscopic dh/dv ``damping_Nms_per_rad``, both
        from Pinocchio's RNEA derivatives (:mod:`prbdm_pin.plant.spin`). The unloaded straight
        pose is the relative equilibrium for every hub axis; ``load_N`` and ``gravity_m_s2``
        along the hub axis give a coned one (solved with the centrifugal terms), and off it
        they are refused (no steady equilibrium). ``lin.modal()`` solves (K_e, M) and so
        leaves the gyroscopic term G out: zero at the straight pose, not at a coned one
        (Omega dM_hh/dq couples the flapping rates to the hub's); ``lin.A`` carries it, and
        :func:`prbdm_pin.plant.spin.gyroscopic_frequencies` gives the undamped frequencies
        with it. The root reaction and the strain (which read the acceleration) are refused
        with a spin.
    compiled : bool
        True (default): the common planar plant (tip forces and joint torques in; tips, angles,
        rates and spring torques out; modal damping) in one compiled call, the same plant to
        rounding. False: the numpy path only, which loads no numba; a caller that linearises
        once per process (``prbdm linearize``) saves numba's load, about 0.25 s of CPU, for
        some 0.1 ms of arithmetic.

    Returns
    -------
    LinearModel

    Raises
    ------
    BeamInputError
        Naming a bad argument. SolveError when no equilibrium is found or M is singular.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> lin = pp.linearize(model, inputs=("tip_force_z",), outputs=("tip_z",))
    >>> lin.A.shape, lin.B.shape, lin.C.shape
    ((4, 4), (4, 1), (1, 4))
    >>> bool(np.allclose(lin.modal().omega_rad_s, model.natural_frequencies()))
    True
    """
    from ..model.prbdm_model import PrbdmModel

    if not isinstance(model, PrbdmModel):
        raise InputTypeError(f"model = {model!r}: must be a PrbdmModel")
    if not isinstance(compiled, bool):
        raise InputTypeError(f"compiled = {compiled!r}: must be True or False")
    if (compiled and q_eq is None and gravity_m_s2 is None and spin_rad_s is None
            and isinstance(damping, str) and damping == "modal"
            and isinstance(actuators, tuple) and not actuators
            and isinstance(loads, tuple) and not loads
            and model.bus is None and model.hub is None and not model.axes.spatial):
        # the common plant: one compiled call (:mod:`.plant_layout`); None: the general path
        lin = fast_linearize(model, inputs, outputs, load_N, damping_ratio)
        if lin is not None:
            return lin
    acts = _actuators(actuators)
    if acts and model.axes.spatial:
        # a patch's moment pair is defined on the bending joints of the planar chain
        raise BeamInputError(f"actuators: strain actuators act on the planar chain's bending "
                             f"joints (axes 'y'); this model has axes {model.axes.value!r}")
    if model.bus is not None:  # six rigid coordinates: :mod:`.bus_linearize`
        from .bus_linearize import linearize_bus

        return linearize_bus(model, inputs, outputs, q_eq, load_N, damping_ratio, damping,
                             acts, gravity_m_s2)
    hub = model.hub is not None
    # names first: refused before any work, and a bare string is not taken letter by letter;
    # joint_torque[j] and q[j] index every spring coordinate (n_joints on the planar chain)
    lds = _loads(model, loads)
    in_names = tuple(n for n, _, _ in parse_inputs(inputs, model.n_springs, len(acts), hub,
                                                   len(lds)))
    out_names = tuple(n for n, _, _ in parse_outputs(outputs, model.n_springs, hub))
    check_corner_names(model, in_names, "inputs")
    check_corner_names(model, out_names, "outputs")
    check_output_stations(model, out_names)
    F = check_vector("load_N", load_N, "N")
    F = np.zeros(3) if F is None else F
    g = check_vector("gravity_m_s2", gravity_m_s2, "m/s^2")
    spin = check_spin(model, spin_rad_s, F, g)
    if spin and any(is_load_output(b) for _, b, _ in parse_outputs(out_names, model.n_springs,
                                                                   hub)):
        raise BeamInputError("outputs: the root reaction and the strain read the acceleration "
                             "of a plant at rest; not with spin_rad_s")
    pm_g = gravity_model(model, g)
    terms = None
    if q_eq is None:
        q, trim = equilibrium(model, F, pm_g, spin_rad_s=spin)
    else:
        q = _pose(model, q_eq)
        terms = static_terms(model, q, F, pm_g, None if pm_g is None else pm_g.createData())
        trim = float(terms[0][0]) if hub else 0.0
    Bq = input_map(model, q, in_names, acts, lds)
    Cq, Cv = output_maps(model, q, out_names)
    # the root reaction and the strain read the acceleration and the inputs too
    Lq, Lv, Ca, Du = load_rows(model, q, out_names, in_names, len(acts), F, g, lds)
    Cq, Cv = Cq + Lq, Cv + Lv
    M = model.mass_matrix(q)
    if terms is None:  # at the equilibrium's pose (given poses reuse the trim's terms)
        terms = static_terms(model, q, F, pm_g, None if pm_g is None else pm_g.createData())
    K = 0.5 * (terms[1] + terms[1].T)
    Cd = plant_damping(model, M, damping_ratio, damping)
    G = None
    if spin:
        h, dh_dq, G = spin_terms(model, q, spin)
        K = K + 0.5 * (dh_dq + dh_dq.T)  # -Omega^2/2 d2M_hh/dq2: symmetric but for roundings
        Cd = Cd + G
        trim += float(h[0])  # the hub torque that holds the rate at this pose
        G.setflags(write=False)
    A, B, X = first_order(M, K, Cd, Bq)
    coords = (["hub"] if hub else []) + [f"q[{j}]" for j in range(model.n_springs)]
    states = tuple(coords + [f"{c}_rate" if c == "hub" else c.replace("q[", "q_rate[")
                             for c in coords])
    nominal = {"tip_force_z": F[2], "tip_force_x": F[0], "tip_force_y": F[1], "hub_torque": trim}
    u_eq = np.array([nominal.get(name, 0.0) for name in in_names])
    for a in (A, B, Cq, Cv, M, K, Cd, Bq, q, u_eq, Ca, Du):
        a.setflags(write=False)
    Cfull, D = output_matrices(Cq, Cv, Ca, Du, X)
    y_eq = output_values(model, q, out_names, F, g)
    for a in (Cfull, D, y_eq):
        a.setflags(write=False)
    return LinearModel(
        A=A, B=B, C=Cfull, D=D, state_names=states, input_names=in_names,
        output_names=out_names, input_units=tuple(input_unit(s) for s in in_names),
        output_units=tuple(output_unit(s) for s in out_names), q_eq=q, u_eq=u_eq, y_eq=y_eq,
        mass_kg_m2=M, stiffness_Nm_per_rad=K, damping_Nms_per_rad=Cd, input_map=Bq,
        output_map_position=Cq, output_map_rate=Cv, hub=hub, spin_rad_s=spin,
        gyroscopic_Nms_per_rad=G, output_map_acceleration=Ca, output_map_input=Du,
    )
