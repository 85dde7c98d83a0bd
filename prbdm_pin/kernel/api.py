"""The kernel's functions in Pinocchio's style, f(kernel, data, ...), returning workspace arrays.

Each checks the sizes of its vectors (a BeamInputError naming the argument), runs the compiled
function (:mod:`.dynamics`, numba, imported on the first call so ``import prbdm_pin`` stays
fast) and returns the array of ``data`` it wrote (as ``pin.crba`` returns ``data.M``): copy it
to keep it past the next call.
"""

from __future__ import annotations

import numpy as np

from ..errors import BeamInputError
from .build import ChainKernel, KernelData

__all__ = ["mass_matrix", "bias_forces", "forward_dynamics", "tip_position", "tip_force_torque"]


def _vector(name: str, value, n: int) -> np.ndarray:
    a = np.ascontiguousarray(value, dtype=float)
    if a.shape != (n,) or not np.all(np.isfinite(a)):
        raise BeamInputError(f"{name} = {np.asarray(value).tolist()!r:.80}: must be {n} finite "
                             "numbers")
    return a


def _posed(kernel: ChainKernel, data: KernelData, q):
    from . import dynamics

    dynamics.kinematics(kernel.joint_type, kernel.joint_axis, kernel.parent_rotation,
                        kernel.parent_translation_m, _vector("q", q, kernel.n), data.rotation,
                        data.origin_m, data.motion_subspace)
    dynamics.body_inertias(kernel.mass_kg, kernel.com_m, kernel.inertia_kg_m2, data.rotation,
                           data.origin_m, data.first_moment_kg_m, data.inertia_origin_kg_m2)
    return dynamics


def mass_matrix(kernel: ChainKernel, data: KernelData, q) -> np.ndarray:
    """Return the joint-space mass matrix M(q) (n, n) by CRBA, SI (kg m^2 for revolute joints).

    Parameters
    ----------
    kernel : ChainKernel
    data : KernelData
        Its workspace (``kernel.new_data()``); the result is ``data.mass_matrix``.
    q : array_like (n,)
        Joint coordinates, rad (m for a prismatic joint).

    Returns
    -------
    ndarray (n, n)

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> from prbdm_pin.kernel import mass_matrix
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> kernel = pp.chain_kernel(model.pin_model, model.tip_frame_id)
    >>> M = mass_matrix(kernel, kernel.new_data(), np.zeros(2))
    >>> bool(np.allclose(M, M.T)), M.shape
    (True, (2, 2))
    """
    k, d = kernel, data
    _posed(k, d, q).crba(k.mass_kg, d.motion_subspace, d.first_moment_kg_m,
                         d.inertia_origin_kg_m2, d.composite_mass_kg,
                         d.composite_first_moment_kg_m, d.composite_inertia_kg_m2, d.force,
                         d.mass_matrix)
    return d.mass_matrix


def bias_forces(kernel: ChainKernel, data: KernelData, q, v) -> np.ndarray:
    """Return h(q, v) (n,): Coriolis, centrifugal and weight terms by RNEA with a = 0, N m.

    Parameters
    ----------
    kernel : ChainKernel
    data : KernelData
        The result is ``data.bias``.
    q, v : array_like (n,)
        Joint coordinates (rad) and velocities (rad/s).

    Returns
    -------
    ndarray (n,)

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> from prbdm_pin.kernel import bias_forces
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> kernel = pp.chain_kernel(model.pin_model, model.tip_frame_id)
    >>> bias_forces(kernel, kernel.new_data(), np.zeros(2), np.zeros(2)).tolist()  # at rest
    [0.0, 0.0]
    """
    k, d = kernel, data
    _posed(k, d, q).rnea_bias(k.mass_kg, k.gravity_m_s2, d.motion_subspace, d.first_moment_kg_m,
                              d.inertia_origin_kg_m2, _vector("v", v, k.n), d.velocity,
                              d.acceleration, d.force, d.bias)
    return d.bias


def forward_dynamics(kernel: ChainKernel, data: KernelData, q, v, tau) -> np.ndarray:
    """Return the joint accelerations a = M(q)^-1 (tau - h(q, v)) (n,), rad/s^2.

    Parameters
    ----------
    kernel : ChainKernel
    data : KernelData
        The result is ``data.acceleration_joint``.
    q, v : array_like (n,)
        Joint coordinates (rad) and velocities (rad/s).
    tau : array_like (n,)
        Joint torques, N m.

    Returns
    -------
    ndarray (n,)

    Raises
    ------
    BeamInputError
        When M(q) is not positive definite (a chain with a massless end).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> from prbdm_pin.kernel import forward_dynamics, mass_matrix
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> kernel = pp.chain_kernel(model.pin_model, model.tip_frame_id)
    >>> data = kernel.new_data()
    >>> a = forward_dynamics(kernel, data, np.zeros(2), np.zeros(2), [1.0, 0.0]).copy()
    >>> bool(np.allclose(mass_matrix(kernel, data, np.zeros(2)) @ a, [1.0, 0.0]))
    True
    """
    from . import dynamics

    n = kernel.n
    ok = dynamics.forward_dynamics(kernel.arrays(), data.arrays(), _vector("q", q, n),
                                   _vector("v", v, n), _vector("tau", tau, n))
    if not ok:
        raise BeamInputError(f"kernel {kernel.model_name!r}: the mass matrix is not positive "
                             "definite at this q")
    return data.acceleration_joint


def tip_position(kernel: ChainKernel, data: KernelData, q) -> np.ndarray:
    """Return the tip frame's world position (3,), m, at ``q``.

    Parameters
    ----------
    kernel : ChainKernel
    data : KernelData
    q : array_like (n,)
        Joint coordinates, rad.

    Returns
    -------
    ndarray (3,)
        A fresh array.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> from prbdm_pin.kernel import tip_position
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> kernel = pp.chain_kernel(model.pin_model, model.tip_frame_id)
    >>> tip_position(kernel, kernel.new_data(), np.zeros(2)).round(6).tolist()  # m, straight
    [1.0, 0.0, 0.0]
    """
    out = np.empty(3)
    _posed(kernel, data, q).tip_position(kernel.tip_joint, kernel.tip_translation_m,
                                         data.rotation, data.origin_m, out)
    return out


def tip_force_torque(kernel: ChainKernel, data: KernelData, q, force_N) -> np.ndarray:
    """Return J(q)^T f (n,), N m: the joint torques of a world force ``force_N`` at the tip.

    Parameters
    ----------
    kernel : ChainKernel
    data : KernelData
        The result is ``data.torque``.
    q : array_like (n,)
        Joint coordinates, rad.
    force_N : array_like (3,)
        World force at the tip, N.

    Returns
    -------
    ndarray (n,)

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> from prbdm_pin.kernel import tip_force_torque
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> kernel = pp.chain_kernel(model.pin_model, model.tip_frame_id)
    >>> tau = tip_force_torque(kernel, kernel.new_data(), np.zeros(2), [0.0, 0.0, -1.0])
    >>> tau.round(6).tolist()  # N m: -1 N at 0.8 m and 0.3 m from the joints, about y
    [0.8, 0.3]
    """
    out = data.torque
    out[:] = 0.0
    _posed(kernel, data, q).tip_force_torque(kernel.tip_joint, kernel.tip_translation_m,
                                             data.rotation, data.origin_m,
                                             data.motion_subspace,
                                             _vector("force_N", force_N, 3), out)
    return out
