"""What made a file: the versions of the package and its numerics, and the random seed.

Every JSON the package writes carries ``"versions"`` (package name -> version) and ``"seed"``
(the seed of the fit or study that produced it; null where nothing random was drawn), so a
result can be traced to the code and the draw that made it.
"""

from __future__ import annotations

from typing import Any

from ..version import __version__

__all__ = ["package_versions", "provenance"]

_NUMERICS = ("pin", "numpy", "scipy", "pymoo", "scikit-fem")


def package_versions() -> tuple[tuple[str, str], ...]:
    """Return (name, version) of the package and the numerical packages its results depend on."""
    from importlib import metadata

    out = [("prbdm_pin", __version__)]  # this tree's version, installed or not
    for name in _NUMERICS:
        try:
            out.append((name, metadata.version(name)))
        except metadata.PackageNotFoundError:
            out.append((name, "unknown"))
    return tuple(out)


def provenance(seed: int | None = None) -> dict[str, Any]:
    """Return the ``versions`` and ``seed`` fields of a JSON file the package writes.

    Parameters
    ----------
    seed : int or None
        The seed of the random draw behind the file (a fit's multistart seed); None when the
        result involves no random draw (a truth, a linearisation, a static solve).

    Returns
    -------
    dict
        ``{"versions": {name: version}, "seed": seed}``.
    """
    return {"versions": dict(package_versions()), "seed": None if seed is None else int(seed)}
