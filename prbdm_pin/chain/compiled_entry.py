"""A compiled function's entry point, called without numba's dispatcher.

For a kernel of one explicit signature, the dispatcher's type resolution of each call costs
about as much as the loops of a short chain (1-2 us for a handful of arrays); the entry point
skips it. It unboxes without checking types, so a caller passes exactly the signature's
types: float64 arrays of its dimensions, C-contiguous where it says so, floats and ints.
Reading the entry point does not import numba.
"""

from __future__ import annotations

__all__ = ["entry_point"]


def entry_point(kernel):
    """Return ``kernel``'s compiled entry point for its one signature, or the kernel.

    Parameters
    ----------
    kernel : numba dispatcher
        Compiled with one explicit signature.

    Returns
    -------
    callable
        The entry point; the dispatcher itself under a numba without one (it then checks).
    """
    try:
        return kernel.overloads[kernel.signatures[0]].entry_point
    except (AttributeError, IndexError, KeyError):
        return kernel
