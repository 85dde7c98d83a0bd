"""load_model reads a PRBDM from a fit.json, a model JSON or a URDF and says what it read; the
truth comparisons the commands write are library calls returning the same records."""

from __future__ import annotations

import json

import numpy as np
import pytest
from paths import ROOT

import prbdm_pin as pp
from prbdm_pin.cli import main
from prbdm_pin.errors import BeamInputError
from prbdm_pin.options.choices import LINK_FLOOR_FRACTION

BEAM = str(ROOT / "examples" / "beams" / "uniform-narrow.json")
OTHER = str(ROOT / "examples" / "beams" / "tapered.json")


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    """A 2R fit against the 1D beam truth and its model JSON and URDF exports (hub, actuator)."""
    d = tmp_path_factory.mktemp("model_source")
    assert main(["fit", BEAM, "--joints", "2", "--truth-model", "beam", "--objective", "eigen",
                 "--stiffness", "joint", "--starts", "2", "--cache-dir", str(d / "cache"),
                 "--out", str(d / "fit"), "-q"]) == 0
    fit = d / "fit" / "fit.json"
    assert main(["export", str(fit), "--format", "json", "--hub", "5:0.1", "--actuator",
                 "0:0.3", "--out", str(d / "plant.json"), "-q"]) == 0
    assert main(["export", str(fit), "--format", "urdf", "--actuator", "0:0.3",
                 "--out", str(d / "plant.urdf"), "-q"]) == 0
    return d


def test_each_kind_says_what_it_carried(files):
    fit = pp.load_model(files / "fit" / "fit.json")
    assert fit.kind == "fit" and fit.fit is not None and fit.actuators == ()
    assert fit.fit.truth_request == pp.TruthRequest(model="beam", modes=2)
    assert fit.model.beam is not None and not fit.beam_given
    plant = pp.load_model(files / "plant.json")
    assert plant.kind == "model" and plant.fit is None and plant.model.hub is not None
    assert [(a.x_start_m, a.x_end_m) for a in plant.actuators] == [(0.0, 0.3)]
    urdf = pp.load_model(str(files / "plant.urdf"))
    assert urdf.kind == "urdf" and urdf.model.beam is None and len(urdf.actuators) == 1
    for other in (plant, urdf):  # the exports record the truth the fit was measured against
        assert np.array_equal(other.omega_truth_rad_s, fit.omega_truth_rad_s)
        assert np.allclose(other.model.lengths_m, fit.model.lengths_m, rtol=0, atol=0)


def test_a_fit_takes_the_beam_given_and_refuses_another(files):
    path = files / "fit" / "fit.json"
    beam = pp.load_beam(BEAM)
    for given in (BEAM, beam):
        got = pp.load_model(path, given)
        assert got.beam_given and got.model.beam.fingerprint() == beam.fingerprint()
    with pytest.raises(BeamInputError, match=r"^--beam .*: is not the beam"):
        pp.load_model(path, OTHER)
    with pytest.raises(BeamInputError, match=r"^beam 'tapered.*': is not the beam"):
        pp.load_model(path, pp.load_beam(OTHER))


def test_other_files_are_refused_naming_what_they_are(files, tmp_path):
    with pytest.raises(BeamInputError, match="not found"):
        pp.load_model(tmp_path / "none.json")
    with pytest.raises(BeamInputError, match="is a beam file"):
        pp.load_model(BEAM)
    bad = tmp_path / "bad.json"
    d = json.loads((files / "plant.json").read_text())
    bad.write_text(json.dumps({**d, "omega_truth_rad_s": ["a"]}))
    with pytest.raises(BeamInputError, match="omega_truth_rad_s"):
        pp.load_model(bad)


def test_the_truth_comparison_is_the_one_the_command_writes(files):
    fit_json = files / "fit" / "fit.json"
    out = files / "sim"
    assert main(["simulate", str(fit_json), "--duration", "0.01", "--compare-truth",
                 "--cache-dir", str(files / "cache"), "--out", str(out), "-q"]) == 0
    loaded = pp.load_model(fit_json)
    cmp = pp.compare_truth(loaded.model, loaded.fit.truth_request, 0.02, files / "cache")
    written = json.loads((out / "truth_comparison.json").read_text())
    # the file adds what made it (versions, the fit's seed) to the comparison's own record
    assert written.pop("seed") == loaded.fit.seed and "prbdm_pin" in written.pop("versions")
    assert json.dumps(cmp.to_dict("fit.json"), indent=2) == json.dumps(written, indent=2)
    with pytest.raises(BeamInputError, match="no beam"):
        pp.compare_truth(pp.load_model(files / "plant.urdf").model,
                         pp.TruthRequest(model="beam", modes=2))
    with pytest.raises(BeamInputError, match="request.model = 'solid'"):
        pp.compare_truth(loaded.model, pp.TruthRequest(model="solid", modes=2))


def test_the_plant_comparison_is_the_one_the_command_writes(files):
    fit_json = files / "fit" / "fit.json"
    out = files / "lin"
    assert main(["linearize", str(fit_json), "--inputs", "hub_torque,strain[0]", "--outputs",
                 "hub_angle,tip_z", "--hub", "5:0.1", "--actuator", "0:0.3", "--compare-truth",
                 "--cache-dir", str(files / "cache"), "--out", str(out), "-q"]) == 0
    loaded = pp.load_model(fit_json)
    model = pp.build_model(loaded.model.beam, loaded.model.lengths_m,
                           loaded.model.stiffness_Nm_per_rad, hub=pp.Hub(5.0, 0.1),
                           min_fraction=LINK_FLOOR_FRACTION)
    acts = (pp.StrainActuator(0.0, 0.3),)
    lin = pp.linearize(model, inputs=("hub_torque", "strain[0]"),
                       outputs=("hub_angle", "tip_z"), damping_ratio=0.02, damping="modal",
                       actuators=acts)
    cmp = pp.compare_truth_plant(lin, model, loaded.fit.truth_request, acts, 0.02,
                                 files / "cache")
    written = json.loads((out / "comparison.json").read_text())
    # the file adds what made it (versions, the fit's seed) to the comparison's own record
    assert written.pop("seed") == loaded.fit.seed and "prbdm_pin" in written.pop("versions")
    assert json.dumps(cmp.to_dict("fit.json"), indent=2) == json.dumps(written, indent=2)
    with pytest.raises(BeamInputError, match="has no modal plant"):
        pp.compare_truth_plant(lin, model, pp.TruthRequest(model="solid"), acts)
