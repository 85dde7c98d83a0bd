"""The shipped JSON Schemas accept every file the package writes, refuse what its readers refuse."""

from __future__ import annotations

import json

import numpy as np
import pytest
from jsonschema import Draft202012Validator
from paths import BEAMS
from referencing import Registry, Resource

from prbdm_pin.cli import main as prbdm
from prbdm_pin.files.beam_file import load_beam, save_beam
from prbdm_pin.schemas import SCHEMA_NAMES, load_schema

_REGISTRY = Registry().with_resources(
    (load_schema(n)["$id"], Resource.from_contents(load_schema(n))) for n in SCHEMA_NAMES)


def _errors(name: str, doc) -> list[str]:
    v = Draft202012Validator(load_schema(name), registry=_REGISTRY)
    return [f"{'/'.join(map(str, e.absolute_path))}: {e.message}" for e in v.iter_errors(doc)]


def test_schemas_are_valid_draft_2020_12():
    for name in SCHEMA_NAMES:
        Draft202012Validator.check_schema(load_schema(name))
    with pytest.raises(ValueError, match="name = 'urdf'"):
        load_schema("urdf")


@pytest.mark.parametrize("path", sorted(BEAMS.glob("*.json")), ids=lambda p: p.stem)
def test_every_shipped_beam_and_its_rewrite_is_valid(path, tmp_path):
    assert _errors("beam", json.loads(path.read_text())) == []
    save_beam(load_beam(path), tmp_path / "b.json")  # what the package writes back
    assert _errors("beam", json.loads((tmp_path / "b.json").read_text())) == []


def test_a_thickness_law_is_valid(tmp_path):
    from prbdm_pin.files.beam_file import beam_from_dict

    d = json.loads((BEAMS / "tapered.json").read_text())
    d["thickness"] = [0.005, 0.002]
    save_beam(beam_from_dict(d), tmp_path / "law.json")
    assert _errors("beam", json.loads((tmp_path / "law.json").read_text())) == []


@pytest.mark.parametrize("edit, field", [
    (lambda d: d.pop("x"), "x"),
    (lambda d: d.update(thickness=-0.005), "thickness"),
    (lambda d: d.update(colour="red"), "colour"),
    (lambda d: d.update(section={"kind": "round", "outer_diameter": [0.02, 0.01]}), "section"),
    (lambda d: d["material"].update(nu=0.7), "nu"),
])
def test_schema_refuses_what_the_reader_refuses(edit, field):
    from prbdm_pin.errors import BeamInputError
    from prbdm_pin.files.beam_file import beam_from_dict

    d = json.loads((BEAMS / "tapered.json").read_text())
    edit(d)
    assert _errors("beam", d) != []
    with pytest.raises((BeamInputError, TypeError)):
        beam_from_dict(d)


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    out = tmp_path_factory.mktemp("written")
    beam = str(BEAMS / "uniform-narrow.json")
    common = ["--truth-model", "beam", "--stiffness", "joint", "--starts", "2", "-q",
              "--cache-dir", str(out / "cache")]
    assert prbdm(["fit", beam, "--joints", "3", "--objective", "combined", *common,
                  "--out", str(out / "planar")]) == 0
    assert prbdm(["fit", beam, "--joints", "2", "--axes", "xy", "--objective", "eigen", *common,
                  "--out", str(out / "spatial")]) == 0
    for fit, extra, name in (("planar", [], "m1"), ("planar", ["--hub", "0.5:0.1"], "m2"),
                             ("spatial", [], "m3")):
        assert prbdm(["export", str(out / fit / "fit.json"), "--format", "json", *extra,
                      "--out", str(out / f"{name}.json")]) == 0
    return out


def test_fit_json_of_planar_and_spatial_fits_is_valid(written):
    for fit in ("planar", "spatial"):
        doc = json.loads((written / fit / "fit.json").read_text())
        assert _errors("fit", doc) == []
        # the schema is not vacuous: the per-mode record it requires holds every fitted mode
        # (a spatial fit's also lists the truth modes of kinds the chain lacks)
        assert len(doc["modes"]) >= len(doc["omega_truth_rad_s"]) > 0


def test_model_json_exports_are_valid(written):
    for name in ("m1", "m2", "m3"):
        doc = json.loads((written / f"{name}.json").read_text())
        assert _errors("model", doc) == []
    bad = json.loads((written / "m1.json").read_text())
    bad["links"][0]["mass_kg"] = -1.0
    assert any("mass_kg" in e for e in _errors("model", bad))
    bad["links"][0]["mass_kg"] = float(np.float64(1.0))
    del bad["stiffness_Nm_per_rad"]
    assert any("stiffness_Nm_per_rad" in e for e in _errors("model", bad))
