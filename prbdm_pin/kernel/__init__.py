"""A compiled kernel of a serial chain's dynamics (numba): the fast path beside Pinocchio.

``chain_kernel(pin_model, tip_frame_id)`` reads a :class:`ChainKernel` (arrays) from any serial
chain the package builds (planar, spatial, a hub, a free bus); ``kernel.new_data()`` is its
workspace. The functions ``mass_matrix`` (CRBA), ``bias_forces`` (RNEA with a = 0, weight
included), ``forward_dynamics`` (Cholesky of M), ``tip_position`` and ``tip_force_torque``
(J^T f) evaluate it; the compiled functions themselves (for use inside other numba code, as
the ``"compiled"`` integrator does) are in :mod:`.dynamics`, on ``kernel.arrays()`` and
``data.arrays()``. Pinocchio stays the reference (the tests compare against ``pin.crba``,
``pin.rnea``, ``pin.aba`` and the frame Jacobian) and the engine of every public model.

The compiled functions are cached (``numba.njit(cache=True)``, in ``__pycache__``): the first
call in a fresh tree compiles them (10-20 s of CPU), later processes load them. numba checks a
cached function against its own source only: after editing :mod:`.dynamics`, delete the
``*.nbi``/``*.nbc`` files of its callers (``prbdm_pin/simulation/__pycache__``) too.
"""

from .api import bias_forces, forward_dynamics, mass_matrix, tip_force_torque, tip_position
from .build import ChainKernel, KernelData, chain_kernel

__all__ = ["ChainKernel", "KernelData", "chain_kernel", "mass_matrix", "bias_forces",
           "forward_dynamics", "tip_position", "tip_force_torque"]
