"""The model a command reads: a URDF, a model JSON or a fit.json.

A model JSON comes from ``prbdm export``, a fit.json with the beam it was fitted to; each is
refused with a message naming the file.
"""

from __future__ import annotations

from pathlib import Path

from ..errors import BeamInputError


def load_model(path: str, beam_path: str | None = None):
    """Load a PrbdmModel from a URDF, a model JSON (export) or a fit.json (with its beam)."""
    return load_model_and_fit(path, beam_path)[0]


def load_model_and_fit(path: str, beam_path: str | None = None):
    """:func:`load_model`, and the ``FitResult`` when ``path`` is a fit.json (else None)."""
    from ..files.beam_file import load_beam
    from ..io.jsonfile import read_json
    from ..io.record_checks import LINK_FLOOR_FRACTION, file_kind
    from ..model.prbdm_model import build_model, load_urdf

    p = Path(path)
    if not p.is_file():
        raise BeamInputError(f"MODEL {path!r}: not found")
    if p.suffix.lower() == ".urdf":
        return load_urdf(p), None
    d = read_json(p, "MODEL")
    kind = file_kind(d)
    if kind == "model":
        from ..files.export import read_model_json

        return read_model_json(p), None
    if kind == "beam":
        raise BeamInputError(f"MODEL {path!r}: is a beam file, not a fit.json or model: run "
                             f"`prbdm fit {path} --joints N --out DIR` first and pass "
                             "DIR/fit.json")
    if kind != "fit":
        what = f"a {kind} file" if kind != "unknown" else (
            f"a JSON object with keys {sorted(d)[:8]}" if isinstance(d, dict)
            else f"a JSON {type(d).__name__}")
        raise BeamInputError(f"MODEL {path!r}: is {what}, not a fit.json, a model JSON "
                             "(prbdm export --format json) or a URDF")
    from ..files.fit_file import fit_beam
    from ..fitting.results import FitResult

    what = f"MODEL {path!r}"
    beam = load_beam(beam_path) if beam_path is not None else fit_beam(d, what)
    if beam is None:
        raise BeamInputError(f"{what}: this fit.json carries no beam; give --beam "
                             "BEAM.json (the beam it was fitted to)")
    fp = d.get("beam_fingerprint")
    if isinstance(fp, str) and fp and fp != beam.fingerprint():
        if beam_path is None:  # the beam stored in the file: the file itself was edited
            raise BeamInputError(f"{what}: its beam does not match its beam_fingerprint = "
                                 f"{fp!r} (the beam stored in it has {beam.fingerprint()!r})")
        raise BeamInputError(f"--beam {beam_path!r}: is not the beam {path!r} was fitted to "
                             f"({d.get('beam_name')!r:.60})")
    fit = FitResult.from_dict(d, beam=beam, what=what)
    model = build_model(beam, fit.lengths_m, fit.stiffness_Nm_per_rad,
                        min_fraction=LINK_FLOOR_FRACTION)
    return model, fit


def file_actuators(path: str | Path) -> tuple:
    """Return the strain actuators a model file records.

    These are a model JSON's ``actuators`` or the record of a URDF export; none for a fit.json.
    """
    from ..files.export import read_export_record, read_plant_json
    from ..io.jsonfile import read_json
    from ..io.record_checks import file_kind

    p = Path(path)
    if p.suffix.lower() == ".urdf":
        rec = read_export_record(p.read_text(encoding="utf-8"))
        return () if rec is None else rec.actuators()
    if file_kind(read_json(p, "MODEL")) == "model":
        return read_plant_json(p)[1]
    return ()
