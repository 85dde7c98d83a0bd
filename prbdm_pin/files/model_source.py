"""A PRBDM read from whichever file holds one: a URDF, a model JSON or a fit.json.

:func:`load_model` tells the three apart (a beam file, a truth file or any other JSON is refused
with a message naming the file and what it is) and returns a :class:`ModelFile`: the model and
what else the file carried, the fit record, the strain actuators and the truth frequencies an
earlier export recorded. A model JSON comes from ``prbdm export``, a fit.json with the beam it
was fitted to (the one it carries, or one given).
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from ..errors import BeamInputError

if TYPE_CHECKING:
    import numpy as np

    from ..fitting.results import FitResult
    from ..member.geometry import Beam
    from ..model.prbdm_model import PrbdmModel

__all__ = ["ModelFile", "load_model", "MODEL_KINDS"]

# "urdf": a URDF export (or PrbdmModel.urdf); "model": a model JSON (prbdm export --format
# json); "fit": a fit.json
MODEL_KINDS = ("urdf", "model", "fit")


@dataclass(frozen=True, eq=False)
class ModelFile:
    """A model file as read by :func:`load_model`.

    Attributes
    ----------
    path : Path
        The file.
    kind : {"urdf", "model", "fit"}
        A URDF, a model JSON or a fit.json.
    model : PrbdmModel
        The PRBDM (link lengths in m, springs in N m/rad), on its hub when a model JSON or URDF
        records one; a URDF's has no beam.
    fit : FitResult or None
        The fit record of a fit.json (its ``truth_request`` names the truth it was fitted to).
    actuators : tuple of StrainActuator
        The strain actuators a model JSON or a URDF export records (spans in m, with the joint
        weights they were exported with); none for a fit.json.
    omega_truth_rad_s : ndarray or None
        The truth frequencies the file knows, rad/s: a fit.json's ``omega_truth_rad_s``, or those
        an export recorded (model JSON field, URDF comment); None when it knows none.
    beam_given : bool
        The model's beam is the one passed to :func:`load_model`, not the one the file carries.
    gravity_m_s2 : ndarray (3,) or None
        The gravity the model was fitted in, m/s^2, world: a fit.json's ``gravity_m_s2``, a
        model JSON's, or the one a URDF's comment states; None for a model fitted without.
    modal_damping_ratio : ndarray (n,) or None
        The per-mode damping ratios a model JSON records in the modal form (a calibration's
        fitted ratios: ``prbdm calibrate``), or those a model JSON's or URDF's ``modal_fit``
        damping was fitted to, mode 1 first; None otherwise.

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> import tempfile
    >>> from pathlib import Path
    >>> folder = Path(tempfile.mkdtemp())
    >>> source = pp.load_model(model.write_urdf(folder / "model.urdf"))
    >>> isinstance(source, pp.ModelFile), source.fit is None
    (True, True)
    """

    path: Path
    kind: str
    model: PrbdmModel
    fit: FitResult | None
    actuators: tuple
    omega_truth_rad_s: np.ndarray | None
    beam_given: bool = False
    gravity_m_s2: np.ndarray | None = None
    modal_damping_ratio: np.ndarray | None = None


def load_model(path: str | os.PathLike, beam: Beam | str | os.PathLike | None = None
               ) -> ModelFile:
    """Read a PRBDM from a URDF, a model JSON (export) or a fit.json (with its beam).

    Parameters
    ----------
    path : str or path-like
        The file; a ``.urdf`` suffix reads as URDF, anything else as JSON.
    beam : Beam, str or path-like, optional
        For a fit.json: the beam it was fitted to (a Beam or a beam JSON file) instead of the
        one it carries; refused when its fingerprint is not the fit's. Ignored for the other
        kinds, which carry their own.

    Returns
    -------
    ModelFile
        The model and what the file carried beside it.

    Raises
    ------
    BeamInputError
        A missing file, a file of another kind (a beam, a truth, ...), a fit.json without a
        beam, a beam that is not the fit's, or a malformed file (naming the field).

    Examples
    --------
    >>> import numpy as np
    >>> import prbdm_pin as pp
    >>> beam = pp.Beam(x_m=[0.0, 1.0], half_width_m=[0.025, 0.025], thickness_m=0.01)
    >>> model = pp.build_model(beam, [0.2, 0.5, 0.3], [2500.0, 1200.0])
    >>> import tempfile
    >>> from pathlib import Path
    >>> folder = Path(tempfile.mkdtemp())
    >>> path = model.write_urdf(folder / "model.urdf")
    >>> source = pp.load_model(path)
    >>> source.kind, source.model.n_joints
    ('urdf', 2)
    """
    from ..io.jsonfile import read_json
    from ..io.record_checks import file_kind
    from ..options.validate import check_path
    from .urdf_file import load_urdf

    p = Path(check_path("path", path))
    if not p.is_file():
        raise BeamInputError(f"MODEL {str(path)!r}: not found")
    if p.suffix.lower() == ".urdf":
        from .export import read_export_record
        from .export_comment import read_gravity_comment

        model = load_urdf(p)
        text = p.read_text(encoding="utf-8")
        rec = read_export_record(text)
        return ModelFile(p, "urdf", model, None, () if rec is None else rec.actuators(),
                         None if rec is None else rec.omega_truth_rad_s,
                         gravity_m_s2=_gravity(str(path), read_gravity_comment(text)),
                         modal_damping_ratio=_fitted_damping(str(path), rec, model.n_springs))
    d = read_json(p, "MODEL")
    kind = file_kind(d)
    if kind == "model":
        from .export import read_plant_json

        model, actuators = read_plant_json(p)
        return ModelFile(p, "model", model, None, tuple(actuators),
                         _recorded_frequencies(str(path), d.get("omega_truth_rad_s")),
                         gravity_m_s2=_gravity(str(path), d.get("gravity_m_s2")),
                         modal_damping_ratio=_modal_damping(str(path), d.get("damping"),
                                                            model.n_springs))
    if kind == "beam":
        raise BeamInputError(f"MODEL {str(path)!r}: is a beam file, not a fit.json or model: "
                             f"run `prbdm fit {path} --joints N --out DIR` first and pass "
                             "DIR/fit.json")
    if kind != "fit":
        what = f"a {kind} file" if kind != "unknown" else (
            f"a JSON object with keys {sorted(d)[:8]}" if isinstance(d, dict)
            else f"a JSON {type(d).__name__}")
        raise BeamInputError(f"MODEL {str(path)!r}: is {what}, not a fit.json, a model JSON "
                             "(prbdm export --format json) or a URDF")
    return _fit_model(p, str(path), d, beam)


def _recorded_frequencies(path: str, value) -> np.ndarray | None:
    """Return a model JSON's ``omega_truth_rad_s`` as a float array (rad/s), None when null.

    Its range is checked where it is used (an export's per-mode errors).
    """
    import numpy as np

    if value is None:
        return None
    try:
        return np.asarray(value, dtype=float)
    except (TypeError, ValueError):
        raise BeamInputError(f"MODEL {path!r}: omega_truth_rad_s = {value!r:.60}: must be a "
                             "list of numbers (rad/s) or null") from None


def _fit_model(p: Path, path: str, d: dict, beam) -> ModelFile:
    """Read the model of a fit.json mapping ``d``, on ``beam`` or on the beam it carries."""
    from ..fitting.results import FitResult
    from ..io.record_checks import LINK_FLOOR_FRACTION
    from ..member.geometry import Beam
    from ..model.prbdm_model import build_model
    from .beam_file import load_beam
    from .fit_file import fit_beam

    what = f"MODEL {path!r}"
    if beam is None:
        used = fit_beam(d, what)
        label = None
    elif isinstance(beam, Beam):
        used, label = beam, f"beam {beam.name!r}"
    else:
        used, label = load_beam(beam), f"--beam {str(beam)!r}"
    if used is None:
        raise BeamInputError(f"{what}: this fit.json carries no beam; give --beam "
                             "BEAM.json (the beam it was fitted to)")
    fp = d.get("beam_fingerprint")
    if isinstance(fp, str) and fp and fp != used.fingerprint():
        if label is None:  # the beam stored in the file: the file itself was edited
            raise BeamInputError(f"{what}: its beam does not match its beam_fingerprint = "
                                 f"{fp!r} (the beam stored in it has {used.fingerprint()!r})")
        raise BeamInputError(f"{label}: is not the beam {path!r} was fitted to "
                             f"({d.get('beam_name')!r:.60})")
    fit = FitResult.from_dict(d, beam=used, what=what)
    model = build_model(used, fit.lengths_m, fit.stiffness_Nm_per_rad,
                        min_fraction=LINK_FLOOR_FRACTION, axes=fit.axes)
    return ModelFile(p, "fit", model, fit, (), fit.omega_truth_rad_s, label is not None,
                     gravity_m_s2=_gravity(path, fit.gravity_m_s2))


def _gravity(path: str, value) -> np.ndarray | None:
    """Return a recorded gravity (m/s^2, (3,)) checked, None for none or a zero vector."""
    from ..truth.self_weight import check_gravity

    if value is None:
        return None
    g = check_gravity(value, f"MODEL {path!r}: gravity_m_s2", planar=False)
    return g if g.any() else None


def _fitted_damping(path: str, rec, n: int) -> np.ndarray | None:
    """Return the per-mode ratios a URDF export's ``modal_fit`` damping was fitted to, or None."""
    if rec is None or rec.damping_form != "modal_fit":
        return None
    return _modal_damping(path, {"form": "modal_fit", "ratio": rec.damping_ratio.tolist()}, n)


def _modal_damping(path: str, record, n: int) -> np.ndarray | None:
    """Return the per-mode ratios of a model JSON's modal or modal_fit ``damping`` record.

    None without one, or with one ratio for every mode.
    """
    import numpy as np

    # the modal form's ratios, or those a modal_fit damping was fitted to
    if not isinstance(record, dict) or record.get("form") not in ("modal", "modal_fit"):
        return None
    try:
        z = np.asarray(record.get("ratio"), dtype=float).reshape(-1)
    except (TypeError, ValueError):
        z = np.array([np.nan])
    if z.size == 1:  # one ratio for every mode: what the package assumes anyway
        return None
    if z.size != n or not np.all((z >= 0.0) & (z < 1.0)):
        raise BeamInputError(f"MODEL {path!r}: damping.ratio = {record.get('ratio')!r}: must "
                             f"be {n} ratios in [0, 1), one per mode")
    return z
