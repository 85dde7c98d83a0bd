"""Progress bars: shown on a terminal, silent in a log file or a pipe.

Every long computation of the package (fit starts, NSGA-II generations, a simulation, a batch, a
benchmark, a design sweep) draws its bar through :func:`progress_bar`. tqdm's ``disable=None``
turns the bar off when its stream is not a terminal, so a job's log holds no carriage-return
redraws; ``enabled=False`` (the commands' ``--quiet``, the API's ``progress=False``) turns it off
everywhere.
"""

from __future__ import annotations

from collections.abc import Iterable
from typing import Any

__all__ = ["progress_bar"]


def progress_bar(total: float | None = None, *, enabled: bool = True, desc: str = "",
                 unit: str = "it", iterable: Iterable | None = None, **kwargs: Any):
    """Return a tqdm bar that draws only on a terminal.

    Parameters
    ----------
    total : float, optional
        The amount of work (in ``unit``); taken from ``iterable`` when that has a length.
    enabled : bool
        False silences the bar wherever it would draw.
    desc, unit : str
        The bar's label and the unit of its count.
    iterable : iterable, optional
        Wrapped, as ``tqdm(iterable)`` does.
    **kwargs
        Passed to tqdm (``initial``, ``leave``, ``bar_format``, ``file``, ...).

    Returns
    -------
    tqdm.tqdm
        The bar; a disabled one takes ``update`` and ``close`` as no-ops, so callers need not
        test ``enabled``.
    """
    from tqdm.auto import tqdm

    return tqdm(iterable, total=total, desc=desc, unit=unit,
                disable=None if enabled else True, dynamic_ncols=True, **kwargs)
