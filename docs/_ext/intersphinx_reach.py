"""Which projects the docs link to through intersphinx: those whose inventory can be had.

Sphinx's intersphinx logs an unreachable inventory as a plain warning (no type to suppress), so a
build with ``-W`` on a closed network would fail on it. The mapping therefore holds the projects
whose ``objects.inv`` is found, in this order: a local copy ``<name>.inv`` in the folder named by
``PRBDM_INTERSPHINX_DIR`` (an offline build with downloaded inventories), else the project's own
site when it answers; the others are left out, each with a note in the build log. Pinocchio is
not among them: its documentation is Doxygen, which writes no Sphinx inventory.
"""

from __future__ import annotations

import os
import urllib.error
import urllib.request
from collections.abc import Callable
from pathlib import Path

PROJECTS = {
    "python": "https://docs.python.org/3/",
    "numpy": "https://numpy.org/doc/stable/",
    "scipy": "https://docs.scipy.org/doc/scipy/",
    "matplotlib": "https://matplotlib.org/stable/",
    "control": "https://python-control.readthedocs.io/en/stable/",
    "pymoo": "https://pymoo.org/",
}


def reachable(url: str, timeout_s: float = 5.0) -> bool:
    """Return whether ``url`` answers a HEAD request within ``timeout_s`` seconds."""
    try:
        with urllib.request.urlopen(urllib.request.Request(url, method="HEAD"),
                                    timeout=timeout_s):
            return True
    except (urllib.error.URLError, OSError, ValueError):
        return False


def intersphinx_mapping(projects: dict[str, str] = PROJECTS, local_dir: str | None = None,
                        probe: Callable[[str], bool] = reachable
                        ) -> tuple[dict[str, tuple[str, str | None]], list[str]]:
    """Return Sphinx's ``intersphinx_mapping`` of the projects to be had, and the notes on the rest.

    ``local_dir`` defaults to the environment's ``PRBDM_INTERSPHINX_DIR``.
    """
    local_dir = os.environ.get("PRBDM_INTERSPHINX_DIR") if local_dir is None else local_dir
    mapping: dict[str, tuple[str, str | None]] = {}
    notes = []
    for name, url in projects.items():
        local = Path(local_dir) / f"{name}.inv" if local_dir else None
        if local is not None and local.is_file():
            mapping[name] = (url, str(local))
        elif probe(url + "objects.inv"):
            mapping[name] = (url, None)
        else:
            notes.append(f"intersphinx: {name}'s inventory ({url}objects.inv) cannot be "
                         "reached; its names are not linked in this build")
    return mapping, notes
