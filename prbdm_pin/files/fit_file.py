"""``fit.json``: a :class:`~prbdm_pin.fitting.results.FitResult` with the beam it was fitted to.

The file is written atomically and read back validated.
"""

from __future__ import annotations

import os
from typing import Any

from ..fitting.results import FitResult
from ..io.atomic import atomic_write_json

__all__ = ["fit_beam", "load_fit", "save_fit"]


def save_fit(result: FitResult, path: str | os.PathLike, beam=None):
    """Write ``fit.json`` atomically.

    The file keeps the fit's truth record (``result.truth_request``: a target made by
    :func:`prbdm_pin.target_from_truth` from a :func:`prbdm_pin.compute_truth` result carries
    it), so ``prbdm simulate/linearize --compare-truth`` find the same truth, as for a
    ``prbdm fit`` folder.

    Parameters
    ----------
    result : FitResult
        The fit (lengths in m, springs in N m/rad, losses in %).
    path : str or path-like
        The file to write.
    beam : Beam, optional
        The beam it was fitted to; with it the file alone rebuilds the model
        (``prbdm simulate fit.json``, ``prbdm export fit.json``).

    Returns
    -------
    pathlib.Path
        The file written.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> EI = beam.material.E_Pa * 0.05 * 0.01**3 / 12  # N m^2
    >>> rho_A = beam.material.rho_kg_m3 * 0.05 * 0.01  # kg/m
    >>> w = np.array([1.8751041, 4.6940911])**2 * np.sqrt(EI / rho_A)  # rad/s, L = 1 m
    >>> target = pp.FitTarget(omega_truth_rad_s=w, tip_force_N=[0.0, 0.0, -1.0])
    >>> result = pp.fit(beam, target, 2, objective="eigen", stiffness="joint", starts=1,
    ...                 progress=False)
    >>> import tempfile
    >>> from pathlib import Path
    >>> folder = Path(tempfile.mkdtemp())
    >>> path = pp.save_fit(result, folder / "fit.json", beam=beam)
    >>> again = pp.load_fit(path)
    >>> bool(np.array_equal(again.lengths_m, result.lengths_m))
    True
    """
    from ..io.paths import check_out_file
    from ..member.geometry import Beam, beam_to_dict
    from ..options.validate import check_type

    check_type("result", result, FitResult, "a prbdm_pin.FitResult (fit, fit_pareto().knee)")
    check_out_file("path", path)
    d = result.to_dict()
    if beam is not None:
        check_type("beam", beam, Beam, "a prbdm_pin.Beam or None")
        d["beam"] = beam_to_dict(beam)
    return atomic_write_json(path, d)


def fit_beam(d: dict[str, Any], what: str = "fit.json"):
    """Return the Beam embedded in a fit.json mapping, or None when it has none."""
    from ..errors import BeamInputError
    from .beam_file import beam_from_dict

    b = d.get("beam") if isinstance(d, dict) else None
    if b is None:
        return None
    try:
        return beam_from_dict(b, check_caps=True)
    except BeamInputError as exc:
        raise BeamInputError(f"{what}: beam: {exc}") from None


def load_fit(path: str | os.PathLike, beam=None) -> FitResult:
    """Read a ``fit.json`` written by :meth:`FitResult.save` or :func:`save_fit`.

    Every field is validated (:func:`prbdm_pin.io.record_checks.fit_kwargs`); the link lengths must
    sum to the length of ``beam`` (a Beam), else of the beam embedded in the file, when there
    is one.

    Parameters
    ----------
    path : str or path-like
        The ``fit.json`` file.
    beam : Beam, optional
        The beam the fit was made for; its length L (m) checks the link lengths.

    Returns
    -------
    FitResult
        The fit (lengths in m, springs in N m/rad, losses in %).

    Raises
    ------
    BeamInputError
        Naming the file, the field and the value.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> EI = beam.material.E_Pa * 0.05 * 0.01**3 / 12  # N m^2
    >>> rho_A = beam.material.rho_kg_m3 * 0.05 * 0.01  # kg/m
    >>> w = np.array([1.8751041, 4.6940911])**2 * np.sqrt(EI / rho_A)  # rad/s, L = 1 m
    >>> target = pp.FitTarget(omega_truth_rad_s=w, tip_force_N=[0.0, 0.0, -1.0])
    >>> result = pp.fit(beam, target, 2, objective="eigen", stiffness="joint", starts=1,
    ...                 progress=False)
    >>> import tempfile
    >>> from pathlib import Path
    >>> folder = Path(tempfile.mkdtemp())
    >>> again = pp.load_fit(pp.save_fit(result, folder / "fit.json", beam=beam))
    >>> again.joints, again.objective
    (2, 'eigen')
    """
    from ..io.jsonfile import read_json
    from ..member.geometry import Beam
    from ..options.validate import check_type

    if beam is not None:
        check_type("beam", beam, Beam, "a prbdm_pin.Beam or None")
    d = read_json(path, "fit.json")
    what = f"fit.json {str(path)!r}"
    if beam is None:
        beam = fit_beam(d, what)
    return FitResult.from_dict(d, beam=beam, what=what)
