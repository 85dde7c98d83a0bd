"""The files of a spatial chain: the URDF and the model JSON read back as the same model (axes,
springs, sections, M); bad spatial files are refused naming the field or joint; and the planar
files are what they were before the spatial chain (goldens written by the planar-only code)."""

import json
import re
import warnings
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from paths import BEAMS, ROOT
from tolerances import EPS

from prbdm_pin.chain.spatial_stiffness import spatial_stiffness
from prbdm_pin.chain.stiffness import finite_segment_stiffness
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.files.export import (
    export_model,
    mjcf_text,
    model_dict,
    read_model_json,
    urdf_text,
)
from prbdm_pin.files.model_source import load_model
from prbdm_pin.files.urdf_file import load_urdf
from prbdm_pin.model.hub import Hub
from prbdm_pin.model.inputs import StrainActuator
from prbdm_pin.model.prbdm_model import build_model
from prbdm_pin.version import __version__

BEAM = load_beam(BEAMS / "tapered.json")
LENGTHS = np.array([0.12, 0.18, 0.16, 0.14])  # m, summing to the beam's 0.6 m
GOLDEN = ROOT / "tests" / "files" / "planar_golden"  # written by the planar-only code


@pytest.fixture(scope="module", params=["xy", "yz", "xyz"])
def chain(request):
    axes = request.param
    return build_model(BEAM, LENGTHS, spatial_stiffness(BEAM, LENGTHS, axes), axes=axes)


def _same_model(back, model):
    assert back.axes == model.axes and back.spring_axes == model.spring_axes
    # every number is written in full (repr) and read back: exact by construction (the
    # sections through Pinocchio's inertia algebra, a few roundings: 0 measured); slack 5 EPS
    np.testing.assert_allclose(back.stiffness_Nm_per_rad, model.stiffness_Nm_per_rad,
                               rtol=5 * EPS, atol=0.0)
    np.testing.assert_allclose(back.lengths_m, model.lengths_m, rtol=5 * EPS, atol=0.0)
    for name in ("mass_kg", "com_m", "inertia_com_kg_m2", "start_m", "end_m"):
        np.testing.assert_allclose(getattr(back.sections, name), getattr(model.sections, name),
                                   rtol=5 * EPS, atol=5 * EPS * np.abs(
                                       getattr(model.sections, name)).max())
    q = np.random.default_rng(3).normal(0.0, 0.3, model.n_springs)
    for pose in (np.zeros(model.n_springs), q):
        ref = model.mass_matrix(pose)
        # the same CRBA on the same numbers: exact here; slack 5 EPS of max |M|
        assert np.abs(back.mass_matrix(pose) - ref).max() <= 5 * EPS * np.abs(ref).max()


def test_the_urdf_reads_back_as_the_same_spatial_model(chain, tmp_path):
    path = export_model(chain, tmp_path / "chain.urdf", "urdf", 0.02)
    back = load_urdf(path)
    _same_model(back, chain)
    assert back.beam is None and back.hub is None
    # PrbdmModel.urdf (no record, no damping) reads back too; load_model tells it a URDF
    (tmp_path / "plain.urdf").write_text(chain.urdf)
    _same_model(load_model(tmp_path / "plain.urdf").model, chain)


def test_the_model_json_records_the_axes_and_reads_back(chain, tmp_path):
    path = export_model(chain, tmp_path / "chain.json", "json")
    d = json.loads(path.read_text())
    assert d["axes"] == chain.axes.value and d["n_joints"] == 3
    assert len(d["stiffness_Nm_per_rad"]) == chain.n_springs and len(d["links"]) == 4
    back = read_model_json(path)
    _same_model(back, chain)
    assert back.beam.fingerprint() == chain.beam.fingerprint()
    read = load_model(path)
    assert read.kind == "model" and read.model.axes == chain.axes


def _json(tmp_path, chain, **changes):
    d = json.loads(export_model(chain, tmp_path / "m.json", "json").read_text())
    d.update(changes)
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(d))
    return path


@pytest.mark.parametrize("value", ["xz", "zyx", "Y", 3, None])
def test_a_model_json_with_bad_axes_is_refused_naming_the_field(value, tmp_path):
    model = build_model(BEAM, LENGTHS, spatial_stiffness(BEAM, LENGTHS, "xy"), axes="xy")
    with pytest.raises(BeamInputError, match=r"bad\.json.*: axes = .*must be one of 'y', "
                                             r"'xy', 'yz', 'xyz'"):
        read_model_json(_json(tmp_path, model, axes=value))


def test_a_model_json_with_springs_for_other_axes_is_refused(chain, tmp_path):
    other = "xyz" if chain.axes.value != "xyz" else "xy"
    with pytest.raises(BeamInputError, match=r"stiffness_Nm_per_rad has shape"):
        read_model_json(_json(tmp_path, chain, axes=other))
    # without the key the file is the planar chain, whose 3 springs these are not
    d = json.loads(export_model(chain, tmp_path / "m.json", "json").read_text())
    del d["axes"]
    (tmp_path / "planar.json").write_text(json.dumps(d))
    with pytest.raises(BeamInputError, match=r"stiffness_Nm_per_rad has shape"):
        read_model_json(tmp_path / "planar.json")


def _edit_urdf(text, edit):
    root = ET.fromstring(text)
    edit(root)
    return ET.tostring(root, encoding="unicode")


def _drop_spring(name):
    def edit(root):
        (g,) = [g for g in root.iter("gazebo") if g.get("reference") == name]
        root.remove(g)
    return edit


def _give_mass(link):
    def edit(root):
        (el,) = [el for el in root.iter("link") if el.get("name") == link]
        el.find("inertial/mass").set("value", "0.01")
    return edit


def _rename(old, new):
    def edit(root):
        for el in root.iter():
            if el.get("name") == old:
                el.set("name", new)
            if el.get("reference") == old:
                el.set("reference", new)
    return edit


@pytest.mark.parametrize("edit, needle", [
    (_drop_spring("joint_2_z"), r"joint 'joint_2_z': no <gazebo reference=\.\.\.>"
                                r"<springStiffness>"),
    (_drop_spring("joint_3_x"), r"joint 'joint_3_x': no <gazebo"),
    (_give_mass("link_2_y"), r"the link after joint 'joint_2_y': mass = 0\.01 kg: a link "
                             "between two joints of one node must be massless"),
    (_rename("joint_2_z", "joint_2_q"), r"joint 'joint_2_q': expected 'joint_2_z'"),
    (_rename("joint_1_z", "joint_1_q"), r"joints joint_1_y, joint_1_q, joint_1_x: a spatial "
                                        "node has"),
], ids=["spring-z", "spring-x", "mass", "name", "node-1"])
def test_a_bad_spatial_urdf_is_refused_naming_the_joint(edit, needle, tmp_path):
    model = build_model(BEAM, LENGTHS, spatial_stiffness(BEAM, LENGTHS, "xyz"), axes="xyz")
    path = tmp_path / "bad.urdf"
    path.write_text(_edit_urdf(model.urdf, edit))
    with pytest.raises(BeamInputError, match=r"urdf file '.*bad\.urdf': " + needle):
        load_urdf(path)


def test_a_spatial_export_refuses_the_planar_plant(chain, tmp_path):
    with pytest.raises(BeamInputError, match=r"actuators: .*planar chain only .*axes = "):
        export_model(chain, tmp_path / "m.xml", "mjcf", actuators=(StrainActuator(0.1, 0.3),))
    with pytest.raises(BeamInputError, match=r"inputs: .*planar chain only"):
        mjcf_text(chain, inputs=["tip_force_z"])


def test_the_export_command_carries_a_spatial_model_through_files(tmp_path, capsys):
    from prbdm_pin.cli import main

    model = build_model(BEAM, LENGTHS, spatial_stiffness(BEAM, LENGTHS, "xyz"), axes="xyz")
    src = export_model(model, tmp_path / "m.json", "json")
    for fmt, name in (("urdf", "m.urdf"), ("mjcf", "m.xml"), ("json", "again.json")):
        assert main(["export", str(src), "--format", fmt, "--out", str(tmp_path / name),
                     "-q"]) == 0
    _same_model(load_urdf(tmp_path / "m.urdf"), model)
    _same_model(read_model_json(tmp_path / "again.json"), model)
    assert main(["export", str(tmp_path / "m.urdf"), "--format", "mjcf", "--out",
                 str(tmp_path / "u.xml"), "-q"]) == 0
    hinges = [[(j.get("name"), j.get("axis"), j.get("stiffness"))
               for j in ET.parse(tmp_path / name).getroot().iter("joint")]
              for name in ("u.xml", "m.xml")]
    assert hinges[0] == hinges[1] and len(hinges[0]) == 9  # springs as written, exactly
    capsys.readouterr()
    assert main(["export", str(src), "--format", "mjcf", "--hub", "5:0.1", "--out",
                 str(tmp_path / "h.xml")]) == 2
    assert "--hub: a hub carries the planar chain only" in capsys.readouterr().err


# --- the planar files are unchanged ---------------------------------------------------------

RECORD = re.compile(r"[ ]*<!-- prbdm_pin export record .*?-->\n", re.S)


def _stable(text):
    """The text less what a machine's eigen-solve or the release sets: the export record (its
    frequencies are an eigen-solve's last bits) and the version."""
    return RECORD.sub("", text).replace(f"prbdm_pin {__version__}", "prbdm_pin VERSION")


def test_the_planar_files_are_the_planar_code_s_byte_for_byte():
    """Goldens written by the code before the spatial chain (the same models, damping 0, a
    given MuJoCo step, the record and version set aside): the URDF, the export URDF and MJCF
    with and without a hub and actuators, and the model JSON's model fields."""
    k = finite_segment_stiffness(BEAM, LENGTHS)
    model = build_model(BEAM, LENGTHS, k)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a heavy hub: no light-hub warning
        hub = build_model(BEAM, LENGTHS, k, hub=Hub(50.0, 0.1))
    acts = (StrainActuator(0.03, 0.27),)
    # the texts without a mesh folder (no geometry, no MJCF tip body): the goldens hold no
    # geometry, which export_model adds as files beside these (test_export_geometry.py)
    texts = {
        "tapered_3R.urdf": model.urdf,
        "tapered_3R_hub.urdf": _stable(urdf_text(hub, 0.0, actuators=acts)),
        "tapered_3R.xml": _stable(mjcf_text(model, 0.0, 1e-4,
                                            inputs=["joint_torque[1]", "tip_force_z"])),
        "tapered_3R_hub.xml": _stable(mjcf_text(hub, 0.0, 1e-4, actuators=acts)),
    }
    assert _stable(urdf_text(model, 0.0)) == model.urdf
    for name, text in texts.items():
        assert text == (GOLDEN / name).read_text(), name
    d = model_dict(model, 0.0)
    assert "axes" not in d  # a planar file is as before: no axes key, read as "y"
    fields = ["format", "beam", "n_joints", "lengths_m", "stiffness_Nm_per_rad", "hub",
              "actuators", "links"]
    assert json.dumps({f: d[f] for f in fields}, indent=2) + "\n" == \
        (GOLDEN / "tapered_3R.json").read_text()
