"""Model and result files from disk are validated at the boundary: beam, fit.json, model JSON, URDF.

Each bad file gives a BeamInputError (CLI: exit 2, one line) naming the field and the value,
never a traceback, a wrong model or a run that exhausts memory. Independent references: the
field names written in the tests, exit codes, Python's XML parser and MuJoCo for the files
written from a beam with a hostile name, and the frequencies of ``build_model`` for URDFs the
package writes.
"""

from __future__ import annotations

import copy
import json
import xml.etree.ElementTree as ET

import numpy as np
import pytest
from tolerances import EPS

from prbdm_pin.cli import main
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import beam_from_dict, load_beam
from prbdm_pin.files.export import mjcf_text, read_model_json, urdf_text, write_json
from prbdm_pin.files.fit_file import load_fit, save_fit
from prbdm_pin.files.urdf_file import load_urdf
from prbdm_pin.fitting import fit
from prbdm_pin.fitting.target import FitTarget
from prbdm_pin.member.geometry import Beam, beam_to_dict
from prbdm_pin.model.prbdm_model import build_model

BEAMS = "examples/beams"
TAPERED_OMEGA = np.array([87.0, 520.0])  # rad/s, a hand target near the 1D beam's


@pytest.fixture(scope="module")
def beam():
    return load_beam(f"{BEAMS}/tapered.json")


@pytest.fixture(scope="module")
def fit_dict(beam, tmp_path_factory):
    """A real 2R fit.json (with its beam), as a mapping."""
    r = fit(beam, FitTarget(TAPERED_OMEGA, beam.tip_force_N), 2, frequencies=2, starts=1, seed=0,
            progress=False)
    path = tmp_path_factory.mktemp("fit") / "fit.json"
    save_fit(r, path, beam)
    return json.loads(path.read_text())


def _write(tmp_path, d, name="fit.json"):
    p = tmp_path / name
    p.write_text(d if isinstance(d, str) else json.dumps(d))
    return p


def _cli_error(capsys, argv):
    """Run the CLI; assert exit 2 with one stderr line and return that line."""
    code = main(argv)
    err = capsys.readouterr().err.strip()
    assert code == 2, err
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    return err


# Beam files ----------------------------------------------------------------------------------


def test_beam_with_a_400_digit_integer_is_refused(tmp_path):
    d = json.loads(open(f"{BEAMS}/tapered.json").read())
    text = json.dumps(d).replace('"thickness": 0.005', '"thickness": ' + "9" * 400)
    assert "9" * 400 in text
    with pytest.raises(BeamInputError, match="beam file.*400 digits"):
        load_beam(_write(tmp_path, text, "beam.json"))


def test_beam_nested_100000_deep_is_refused(tmp_path):
    with pytest.raises(BeamInputError, match="nested deeper"):
        load_beam(_write(tmp_path, "[" * 100_000, "beam.json"))


def test_beam_with_200k_vertices_is_refused_before_any_work(tmp_path, capsys):
    n = 200_000
    x = np.linspace(0.0, 1.0, n).tolist()
    d = {"x": x, "half_width": [0.05] * n, "thickness": 0.01, "tip_force": [0, 0, -10]}
    p = _write(tmp_path, d, "beam.json")
    with pytest.raises(BeamInputError, match=r"x \(vertices\) = 200000.*max_vertices"):
        load_beam(p)
    err = _cli_error(capsys, ["fit", str(p), "--joints", "2", "--truth-model", "beam",
                              "--out", str(tmp_path / "o")])
    assert "PRBDM_MAX_VERTICES" in err
    assert not (tmp_path / "o" / "fit.json").exists()


def test_vertex_cap_can_be_raised(tmp_path, monkeypatch):
    d = {"x": np.linspace(0.0, 1.0, 300).tolist(), "half_width": [0.05] * 300,
         "thickness": 0.01}
    p = _write(tmp_path, d, "beam.json")
    monkeypatch.setenv("PRBDM_MAX_VERTICES", "200")
    with pytest.raises(BeamInputError, match="max_vertices = 200"):
        load_beam(p)
    monkeypatch.setenv("PRBDM_MAX_VERTICES", "300")
    assert load_beam(p).x_m.size == 300


@pytest.mark.parametrize("field", ["name", "description", "material.name"])
@pytest.mark.parametrize("char", ["\u0000", "\u0001"])
def test_beam_names_with_control_characters_are_refused(tmp_path, field, char, capsys):
    d = json.loads(open(f"{BEAMS}/tapered.json").read())
    if field == "material.name":
        d.setdefault("material", {})["name"] = f"steel{char}x"
    else:
        d[field] = f"beam{char}x"
    p = _write(tmp_path, d, "beam.json")
    with pytest.raises(BeamInputError, match=f"{field} = .*control characters"):
        load_beam(p)
    err = _cli_error(capsys, ["fit", str(p), "--joints", "2", "--truth-model", "beam",
                              "--out", str(tmp_path / "o")])
    assert field in err
    assert not (tmp_path / "o" / "model.urdf").exists()


def test_api_beam_with_a_control_character_in_its_name_is_refused(beam):
    with pytest.raises(BeamInputError, match="name = .*control characters"):
        Beam(beam.x_m, beam.half_width_m, beam.thickness_m, name="a\u0001b")


def test_xml_special_characters_in_a_name_survive_urdf_and_mjcf(beam, tmp_path):
    import mujoco

    name = 'a<b>&"c\'d'
    b = beam_from_dict({**beam_to_dict(beam), "name": name})
    model = build_model(b, [0.2, 0.2, 0.2], [1000.0, 900.0])
    urdf = urdf_text(model)
    assert ET.fromstring(urdf).get("name") == f"prbdm_{name}"
    mjcf = mjcf_text(model)
    assert ET.fromstring(mjcf).get("model") == f"prbdm_{name}"
    (tmp_path / "m.xml").write_text(mjcf)
    assert mujoco.MjModel.from_xml_path(str(tmp_path / "m.xml")).njnt == 2
    (tmp_path / "m.urdf").write_text(urdf)
    # the URDF writes every number in full, so the reloaded chain is this one (exact here);
    # kept: the test's 1e-12
    np.testing.assert_allclose(load_urdf(tmp_path / "m.urdf").natural_frequencies(),
                               model.natural_frequencies(), rtol=5000 * EPS)


@pytest.mark.parametrize("name", ["\t", "a\nb", "c\r\nd", " x "])
def test_whitespace_in_a_name_survives_urdf_and_mjcf(beam, tmp_path, name):
    # an XML parser normalises a tab or newline in an attribute to a space unless written
    # as a character reference
    b = beam_from_dict({**beam_to_dict(beam), "name": name})
    model = build_model(b, [0.2, 0.2, 0.2], [1000.0, 900.0])
    assert ET.fromstring(urdf_text(model)).get("name") == f"prbdm_{name}"
    assert ET.fromstring(mjcf_text(model)).get("model") == f"prbdm_{name}"
    (tmp_path / "m.urdf").write_text(urdf_text(model))
    assert load_urdf(tmp_path / "m.urdf").pin_model.name == f"prbdm_{name}"


# fit.json ------------------------------------------------------------------------------------


def _bad(fit_dict, **changes):
    d = copy.deepcopy(fit_dict)
    for k, v in changes.items():
        if v is KeyError:
            d.pop(k)
        else:
            d[k] = v
    return d


@pytest.mark.parametrize("lengths, field", [
    ([None, 0.3, 0.3], r"lengths_m\[0\] = nan: must be finite"),
    ([0.3, -0.012, 0.312], r"lengths_m\[1\] = -0.012: must be > 0"),
    ([0.6, 0.0, 0.0], r"lengths_m\[1\] = 0.0: must be > 0"),
    ([], r"lengths_m has 0 values"),
    ("0.2 0.2 0.2", r"lengths_m = '0.2 0.2 0.2'"),
    ([0.2, 0.2, 0.3], r"lengths_m sum to 0.7.* beam length 0.6"),
    ([0.2, 0.2, 0.1, 0.1], r"lengths_m has 4 values: joints = 2 needs 3"),
])
def test_fit_json_bad_lengths_are_refused(fit_dict, tmp_path, lengths, field):
    p = _write(tmp_path, _bad(fit_dict, lengths_m=lengths))
    with pytest.raises(BeamInputError, match=field):
        load_fit(p)


def test_negative_length_names_the_length_not_a_derived_min_fraction(fit_dict, tmp_path,
                                                                     capsys):
    lengths = [0.953, -0.353, 0.0]  # sums to L = 0.6
    err = _cli_error(capsys, ["simulate", str(_write(tmp_path, _bad(fit_dict, lengths_m=lengths))),
                              "--duration", "0.01", "--out", str(tmp_path / "o")])
    assert "lengths_m[1] = -0.353" in err and "min_fraction" not in err


def test_fit_json_lengths_1_0_0_through_simulate_and_export(fit_dict, tmp_path, capsys):
    p = _write(tmp_path, _bad(fit_dict, lengths_m=[0.6, 0.0, 0.0]))
    for argv in (["simulate", str(p), "--duration", "0.01", "--out", str(tmp_path / "s")],
                 ["export", str(p), "--format", "urdf", "--out", str(tmp_path / "m.urdf")]):
        assert "lengths_m[1] = 0.0" in _cli_error(capsys, argv)


def test_link_floor_comes_from_the_beam_not_the_file(fit_dict, tmp_path):
    # the file claims a tiny min_fraction: the floor is 1e-5 of the beam's 0.6 m all the same
    d = _bad(fit_dict, lengths_m=[1e-9, 0.3, 0.3 - 1e-9], min_fraction=1e-10)
    with pytest.raises(BeamInputError, match=r"lengths_m\[0\] = 1e-09 m: shorter than 1e-05"):
        load_fit(_write(tmp_path, d))


@pytest.mark.parametrize("min_fraction", [-0.05, 0.0, 0.5, "0.02", None])
def test_fit_json_min_fraction_out_of_range_is_refused(fit_dict, tmp_path, min_fraction):
    with pytest.raises(BeamInputError, match="min_fraction = "):
        load_fit(_write(tmp_path, _bad(fit_dict, min_fraction=min_fraction)))


def test_fit_json_truncated_or_not_json(fit_dict, tmp_path):
    text = json.dumps(fit_dict)
    with pytest.raises(BeamInputError, match="fit.json .*not valid JSON"):
        load_fit(_write(tmp_path, text[: len(text) // 2]))
    with pytest.raises(BeamInputError, match="fit.json .*not UTF-8"):
        p = tmp_path / "fit.json"
        p.write_bytes(b"\xff\xfe" + text.encode())
        load_fit(p)
    with pytest.raises(BeamInputError, match="fit.json .*not found"):
        load_fit(tmp_path / "none.json")


def test_fit_json_as_a_list_or_with_versions_a_list(fit_dict, tmp_path):
    with pytest.raises(BeamInputError, match="must be a JSON object, got list"):
        load_fit(_write(tmp_path, [fit_dict]))
    with pytest.raises(BeamInputError, match="versions: must be a JSON object, got list"):
        load_fit(_write(tmp_path, _bad(fit_dict, versions=[["numpy", "2"]])))


def test_fit_json_missing_fields_are_named(fit_dict, tmp_path):
    with pytest.raises(BeamInputError, match=r"missing field\(s\) \['scf_mean'\]"):
        load_fit(_write(tmp_path, _bad(fit_dict, scf_mean=KeyError)))


@pytest.mark.parametrize("field, value, message", [
    ("joints", "two", r"joints = 'two': must be an integer"),
    ("joints", 3, r"lengths_m has 3 values: joints = 3 needs 4"),
    ("joints", 0, r"joints = 0: must be >= 1"),
    ("frequencies", 3, r"frequencies = 3: must be <= 2"),
    ("stiffness_Nm_per_rad", [1000.0], r"stiffness_Nm_per_rad has shape \(1,\): expected \(2\)"),
    ("stiffness_Nm_per_rad", [1000.0, -1.0], r"stiffness_Nm_per_rad\[1\] = -1.0: must be > 0"),
    ("stiffness_Nm_per_rad", [1000.0, None], r"stiffness_Nm_per_rad\[1\] = nan"),
    ("stiffness_per_pose_Nm_per_rad", [[1.0, 2.0]], r"stiffness_per_pose_Nm_per_rad has shape"),
    ("poses_rad", [[0.1]], r"poses_rad has shape \(1, 1\): expected \(k, 2\)"),
    ("factors", [1.0], r"factors has shape"),
    ("omega_truth_rad_s", [87.0, -1.0], r"omega_truth_rad_s\[1\] = -1.0: must be > 0"),
    ("objective", "best", r"objective = 'best': must be one of"),
    ("stiffness", 1, r"stiffness = 1: must be one of"),
    ("squared", "no", r"squared = 'no': must be true or false"),
    ("seed", -1, r"seed = -1: must be >= 0"),
    ("eigen_loss_pct", "low", r"eigen_loss_pct = 'low': must be a number"),
    ("warnings", "none", r"warnings = 'none': must be a list"),
    ("beam_name", "a\u0000", r"beam_name = .*control characters"),
    ("truth_request", [1, 2], r"truth_request"),
])
def test_fit_json_field_types_and_shapes(fit_dict, tmp_path, field, value, message):
    with pytest.raises(BeamInputError, match=message):
        load_fit(_write(tmp_path, _bad(fit_dict, **{field: value})))


def test_fit_json_with_1000_links_is_refused_before_any_work(fit_dict, tmp_path, capsys):
    n = 1000
    d = _bad(fit_dict, joints=n, lengths_m=[0.6 / (n + 1)] * (n + 1),
             stiffness_Nm_per_rad=[1e3] * n, stiffness_per_pose_Nm_per_rad=[[1e3] * n],
             poses_rad=[[0.0] * n], factors=[1.0], min_fraction=1e-4)
    p = _write(tmp_path, d)
    with pytest.raises(BeamInputError, match="joints = 1000: exceeds the cap max_joints = 64"):
        load_fit(p)
    for argv in (["simulate", str(p), "--duration", "0.01", "--out", str(tmp_path / "s")],
                 ["export", str(p), "--format", "mjcf", "--out", str(tmp_path / "m.xml")]):
        assert "max_joints" in _cli_error(capsys, argv)


def test_fit_json_embedded_beam_is_validated(fit_dict, tmp_path):
    d = copy.deepcopy(fit_dict)
    d["beam"]["thickness"] = -1
    with pytest.raises(BeamInputError, match="fit.json .*beam: thickness = -1"):
        load_fit(_write(tmp_path, d))


def test_embedded_beams_are_capped_but_beams_built_in_code_are_not(fit_dict, model_json,
                                                                    tmp_path, monkeypatch):
    d = copy.deepcopy(fit_dict)
    d["beam"]["x"] = np.linspace(0.0, 0.6, 12).tolist()
    d["beam"]["half_width"] = [0.05] * 12
    d["beam"].pop("length", None)
    m = {**model_json, "beam": d["beam"]}
    monkeypatch.setenv("PRBDM_MAX_VERTICES", "10")
    with pytest.raises(BeamInputError, match=r"beam: x \(vertices\) = 12: exceeds the cap"):
        load_fit(_write(tmp_path, d))
    with pytest.raises(BeamInputError, match=r"beam: x \(vertices\) = 12: exceeds the cap"):
        read_model_json(_write(tmp_path, m, "model.json"))
    assert beam_from_dict(d["beam"]).x_m.size == 12


def test_valid_fit_json_with_and_without_its_beam_round_trips(fit_dict, beam, tmp_path):
    r = load_fit(_write(tmp_path, fit_dict))
    np.testing.assert_array_equal(r.lengths_m, fit_dict["lengths_m"])
    assert r.joints == 2 and r.versions == tuple(fit_dict["versions"].items())
    d = {k: v for k, v in fit_dict.items() if k not in ("beam", "min_fraction")}
    back = load_fit(_write(tmp_path, d, "old.json"))
    np.testing.assert_array_equal(back.stiffness_Nm_per_rad, fit_dict["stiffness_Nm_per_rad"])
    # the beam given explicitly decides the length the links must sum to
    other = beam_from_dict({**beam_to_dict(beam), "x": [0.0, 1.2], "half_width": [0.05, 0.03],
                            "length": 1.2})
    with pytest.raises(BeamInputError, match="beam length 1.2"):
        load_fit(_write(tmp_path, d, "old.json"), beam=other)


def test_fingerprint_mismatch_names_the_beam_given(fit_dict, tmp_path, capsys):
    d = {k: v for k, v in fit_dict.items() if k != "beam"}
    p = _write(tmp_path, d)
    err = _cli_error(capsys, ["simulate", str(p), "--beam", f"{BEAMS}/uniform-narrow.json",
                              "--duration", "0.01", "--out", str(tmp_path / "o")])
    assert "uniform-narrow.json" in err and "None" not in err
    d = copy.deepcopy(fit_dict)
    d["beam"]["thickness"] = 0.006
    err = _cli_error(capsys, ["simulate", str(_write(tmp_path, d)), "--duration", "0.01",
                              "--out", str(tmp_path / "o")])
    assert "its beam" in err and "--beam None" not in err


# MODEL of another kind; model JSON ---------------------------------------------------------


@pytest.mark.parametrize("command", ["simulate", "export"])
def test_beam_json_as_model_says_run_fit_first(command, tmp_path, capsys):
    extra = (["--duration", "0.01", "--out", str(tmp_path / "o")] if command == "simulate"
             else ["--format", "urdf", "--out", str(tmp_path / "m.urdf")])
    err = _cli_error(capsys, [command, f"{BEAMS}/tapered.json", *extra])
    assert "is a beam file" in err and "prbdm fit" in err
    assert "positional" not in err


@pytest.mark.parametrize("doc, kind", [
    ({"omega_rad_s": [1.0], "dofs": 10, "beam": "b"}, "a truth file"),
    ({"settings": {}, "shard": [0, 1], "seed": 0}, "a batch file"),
    ([1, 2, 3], "a JSON list"),
    ({"hello": 1}, "keys ['hello']"),
])
def test_other_json_as_model_is_named(doc, kind, tmp_path, capsys):
    p = _write(tmp_path, doc, "x.json")
    err = _cli_error(capsys, ["export", str(p), "--format", "urdf",
                              "--out", str(tmp_path / "m.urdf")])
    assert kind in err


@pytest.fixture(scope="module")
def model_json(beam, tmp_path_factory):
    p = tmp_path_factory.mktemp("mj") / "model.json"
    write_json(build_model(beam, [0.2, 0.25, 0.15], [1200.0, 1100.0]), p)
    return json.loads(p.read_text())


@pytest.mark.parametrize("change, message", [
    ({"lengths_m": [0.8, -0.2, 0.0]}, r"lengths_m\[1\] = -0.2: must be > 0"),
    ({"lengths_m": [0.2, None, 0.15]}, r"lengths_m\[1\] = nan: must be finite"),
    ({"stiffness_Nm_per_rad": [1.0, 0.0]}, r"stiffness_Nm_per_rad\[1\] = 0.0"),
    ({"stiffness_Nm_per_rad": "stiff"}, r"stiffness_Nm_per_rad = 'stiff'"),
    ({"n_joints": 3}, r"n_joints = 3"),
    ({"format": "other/1"}, r"format = 'other/1'"),
    ({"lengths_m": [0.6 / 101] * 101, "stiffness_Nm_per_rad": [1.0] * 100},
     r"max_joints = 64"),
])
def test_model_json_fields(model_json, tmp_path, change, message):
    with pytest.raises(BeamInputError, match=message):
        read_model_json(_write(tmp_path, {**model_json, **change}, "model.json"))


def test_model_json_round_trips_and_a_truncated_one_is_refused(model_json, tmp_path, beam):
    m = read_model_json(_write(tmp_path, model_json, "model.json"))
    ref = build_model(beam, [0.2, 0.25, 0.15], [1200.0, 1100.0])
    # the file's chain is this one (exact here); kept: the test's 1e-12
    np.testing.assert_allclose(m.natural_frequencies(), ref.natural_frequencies(),
                               rtol=5000 * EPS)
    text = json.dumps(model_json)
    with pytest.raises(BeamInputError, match="model file .*not valid JSON"):
        read_model_json(_write(tmp_path, text[:-10], "model.json"))


# URDF ----------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def urdf(beam):
    return build_model(beam, [0.2, 0.25, 0.15], [1200.0, 1100.0]).urdf


def _urdf_file(tmp_path, text):
    p = tmp_path / "m.urdf"
    p.write_bytes(text if isinstance(text, bytes) else text.encode())
    return p


def _strip_joints(urdf):
    root = ET.fromstring(urdf)
    for j in root.findall("joint"):
        root.remove(j)
    return ET.tostring(root, encoding="unicode")


def test_urdf_with_no_joints(urdf, tmp_path):
    with pytest.raises(BeamInputError, match="0 revolute joints"):
        load_urdf(_urdf_file(tmp_path, _strip_joints(urdf)))


def test_urdf_with_a_negative_link_length(urdf, tmp_path):
    root = ET.fromstring(urdf)
    j2 = [j for j in root.findall("joint") if j.get("name") == "joint_2"][0]
    j2.find("origin").set("xyz", "-0.953 0 0")
    with pytest.raises(BeamInputError, match=r"joint 'joint_2' origin x = -0.953 m"):
        load_urdf(_urdf_file(tmp_path, ET.tostring(root, encoding="unicode")))


@pytest.mark.parametrize("link", ["link_0", "link_1", "link_2"])
@pytest.mark.parametrize("value", ["0", "-1", "nan", "inf", "heavy"])
def test_urdf_link_masses(urdf, tmp_path, link, value):
    root = ET.fromstring(urdf)
    lk = [e for e in root.findall("link") if e.get("name") == link][0]
    lk.find("inertial").find("mass").set("value", value)
    text = ET.tostring(root, encoding="unicode")
    with pytest.raises(BeamInputError, match=f"link '{link}' mass = "):
        load_urdf(_urdf_file(tmp_path, text))


@pytest.mark.parametrize("key, value", [("ixx", "0"), ("iyy", "-1e-3"), ("izz", "nan"),
                                        ("ixy", "inf")])
def test_urdf_inertias(urdf, tmp_path, key, value):
    root = ET.fromstring(urdf)
    lk = [e for e in root.findall("link") if e.get("name") == "link_1"][0]
    lk.find("inertial").find("inertia").set(key, value)
    with pytest.raises(BeamInputError, match=f"link 'link_1' inertia {key} = "):
        load_urdf(_urdf_file(tmp_path, ET.tostring(root, encoding="unicode")))


def test_urdf_missing_inertial_means_a_massless_link(urdf, tmp_path):
    root = ET.fromstring(urdf)
    lk = [e for e in root.findall("link") if e.get("name") == "link_1"][0]
    lk.remove(lk.find("inertial"))
    with pytest.raises(BeamInputError, match="link_1 mass = 0.0 kg"):
        load_urdf(_urdf_file(tmp_path, ET.tostring(root, encoding="unicode")))


@pytest.mark.parametrize("kind", ["continuous", "prismatic", "floating", "planar"])
def test_urdf_non_revolute_joints(urdf, tmp_path, kind):
    root = ET.fromstring(urdf)
    [j for j in root.findall("joint") if j.get("name") == "joint_1"][0].set("type", kind)
    with pytest.raises(BeamInputError, match=f"joint 'joint_1' type = '{kind}'"):
        load_urdf(_urdf_file(tmp_path, ET.tostring(root, encoding="unicode")))


@pytest.mark.parametrize("value", ["nan", "0", "-5", "inf"])
def test_urdf_spring_stiffness(urdf, tmp_path, value):
    text = urdf.replace("<springStiffness>1100.0<", f"<springStiffness>{value}<")
    assert text != urdf
    with pytest.raises(BeamInputError, match="springStiffness of joint_2"):
        load_urdf(_urdf_file(tmp_path, text))


def test_urdf_not_xml_not_utf8_oversized_and_over_the_joint_cap(urdf, tmp_path, monkeypatch):
    with pytest.raises(BeamInputError, match="not valid XML"):
        load_urdf(_urdf_file(tmp_path, urdf[: len(urdf) // 2]))
    with pytest.raises(BeamInputError, match="not UTF-8"):
        load_urdf(_urdf_file(tmp_path, urdf.encode("utf-16")))
    with pytest.raises(BeamInputError, match="root element <mujoco>"):
        load_urdf(_urdf_file(tmp_path, "<mujoco/>"))
    p = _urdf_file(tmp_path, urdf)
    monkeypatch.setenv("PRBDM_MAX_FILE_BYTES", "1000")
    with pytest.raises(BeamInputError, match="max_file_bytes = 1000"):
        load_urdf(p)
    monkeypatch.delenv("PRBDM_MAX_FILE_BYTES")
    monkeypatch.setenv("PRBDM_MAX_JOINTS", "1")
    with pytest.raises(BeamInputError, match="revolute joints = 2: exceeds the cap max_joints"):
        load_urdf(p)
    with pytest.raises(BeamInputError, match="not found"):
        load_urdf(tmp_path / "none.urdf")


def test_urdf_cli_errors_are_one_line(urdf, tmp_path, capsys):
    p = _urdf_file(tmp_path, _strip_joints(urdf))
    err = _cli_error(capsys, ["simulate", str(p), "--duration", "0.01",
                              "--out", str(tmp_path / "o")])
    assert "revolute joints" in err


def test_urdfs_the_package_writes_load_unchanged(beam, tmp_path):
    model = build_model(beam, [0.2, 0.25, 0.15], [1200.0, 1100.0])
    w = model.natural_frequencies()
    for text in (model.urdf, urdf_text(model, 0.05, omega_truth_rad_s=w * 1.01)):
        back = load_urdf(_urdf_file(tmp_path, text))
        # every number written in full: the same chain (exact here); kept: the tests' 1e-12
        # and 1e-15 m
        np.testing.assert_allclose(back.natural_frequencies(), w, rtol=5000 * EPS)
        np.testing.assert_allclose(back.lengths_m, model.lengths_m, rtol=0, atol=5 * EPS)
    # a fine 33-link reference chain with half links at the ends (under the 64-joint cap)
    L = beam.length_m
    lengths = np.r_[L / 64, np.full(31, L / 32), L / 64]
    fine = build_model(beam, lengths, np.full(32, 500.0), min_fraction=1 / 128)
    back = load_urdf(_urdf_file(tmp_path, fine.urdf))
    np.testing.assert_allclose(back.natural_frequencies(), fine.natural_frequencies(),
                               rtol=1e-10)
