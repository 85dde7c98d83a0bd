"""URDF round trip: Pinocchio's parser and an independent ElementTree reading agree."""

import shutil
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from prbdm_pin.errors import BeamInputError
from prbdm_pin.geometry import load_beam
from prbdm_pin.model import build_model, load_urdf

ROOT = Path(__file__).resolve().parent.parent
BEAM = load_beam(ROOT / "examples" / "beams" / "reference-random.json")
LENGTHS = np.array([0.07, 0.2, 0.23, 0.18, 0.32])
STIFFNESS = np.array([1234.5, 987.25, 1.0 / 3.0, 42.0])


@pytest.fixture(scope="module")
def model():
    return build_model(BEAM, LENGTHS, STIFFNESS)


@pytest.fixture()
def urdf_path(model, tmp_path):
    return model.write_urdf(tmp_path / "chain.urdf")


def test_pinocchio_file_parser_gives_the_same_bodies(model, urdf_path):
    parsed = pin.buildModelFromUrdf(str(urdf_path))
    s = model.sections
    assert parsed.nq == 4 and parsed.njoints == 5
    for i in range(5):
        inertia = parsed.inertias[i]
        assert inertia.mass == s.mass_kg[i]
        # appending a body to a joint sums inertias (lever = sum m c / sum m): equal to rounding
        np.testing.assert_allclose(inertia.lever, s.com_m[i] - [s.start_m[i], 0, 0], rtol=1e-14,
                                   atol=0)
        np.testing.assert_allclose(inertia.inertia, s.inertia_com_kg_m2[i], rtol=1e-14, atol=0)
    for j in range(1, 5):
        assert parsed.joints[j].shortname() == "JointModelRY"
        np.testing.assert_array_equal(parsed.jointPlacements[j].translation, [LENGTHS[j - 1], 0, 0])
    tip = parsed.frames[parsed.getFrameId("tip")]
    assert tip.parentJoint == 4
    np.testing.assert_array_equal(tip.placement.translation, [LENGTHS[4], 0, 0])
    parsed.gravity = pin.Motion.Zero()
    assert parsed == model.pin_model


def test_elementtree_reading_agrees(model, urdf_path):
    root = ET.parse(urdf_path).getroot()
    links = {el.get("name"): el for el in root.findall("link")}
    joints = {el.get("name"): el for el in root.findall("joint")}
    s = model.sections
    for i in range(5):
        inertial = links[f"link_{i}"].find("inertial")
        assert float(inertial.find("mass").get("value")) == s.mass_kg[i]
        xyz = [float(v) for v in inertial.find("origin").get("xyz").split()]
        assert xyz[0] + s.start_m[i] == pytest.approx(s.com_m[i, 0], abs=1e-15)
        I = inertial.find("inertia")
        got = np.array([[float(I.get(f"i{a}{b}" if a <= b else f"i{b}{a}")) for b in "xyz"]
                        for a in "xyz"])
        np.testing.assert_array_equal(got, s.inertia_com_kg_m2[i])
    springs = {g.get("reference"): g for g in root.findall("gazebo")}
    for j in range(1, 5):
        joint = joints[f"joint_{j}"]
        assert joint.get("type") == "revolute"
        assert joint.find("axis").get("xyz") == "0 1 0"
        assert joint.find("limit") is not None
        assert float(joint.find("origin").get("xyz").split()[0]) == LENGTHS[j - 1]
        g = springs[f"joint_{j}"]
        assert float(g.find("springStiffness").text) == STIFFNESS[j - 1]
        assert float(g.find("springReference").text) == 0.0
    assert joints["clamp"].get("type") == "fixed"
    assert joints["clamp"].find("parent").get("link") == "world"


def test_load_urdf_round_trip(model, urdf_path):
    loaded = load_urdf(urdf_path)
    assert loaded.beam is None
    np.testing.assert_array_equal(loaded.stiffness_Nm_per_rad, STIFFNESS)
    np.testing.assert_allclose(loaded.lengths_m, LENGTHS, rtol=0, atol=0)
    assert loaded.pin_model == model.pin_model
    q = np.array([0.1, 0.4, -0.2, 0.3])
    np.testing.assert_array_equal(loaded.natural_frequencies(q), model.natural_frequencies(q))
    np.testing.assert_array_equal(loaded.sections.mass_kg, model.sections.mass_kg)
    assert loaded.urdf == model.urdf


def test_load_urdf_rejects_missing_springs(model, tmp_path):
    p = tmp_path / "nospring.urdf"
    text = model.urdf.replace('<gazebo reference="joint_3">', '<gazebo reference="other">')
    p.write_text(text)
    with pytest.raises(BeamInputError, match="joint_3"):
        load_urdf(p)
    p.write_text(model.urdf.replace("<springStiffness>42.0<", "<springStiffness>-1<"))
    with pytest.raises(BeamInputError, match="springStiffness of joint_4 = -1.0"):
        load_urdf(p)


@pytest.mark.slow
def test_installed_package_finds_templates(tmp_path):
    """Install the project (no deps) into a folder and render a URDF from the installed copy."""
    target = tmp_path / "site"
    # build from a copy so the checkout gets no build/ or egg-info folders
    src = tmp_path / "src"
    shutil.copytree(ROOT, src, ignore=shutil.ignore_patterns(
        ".git", "build", "dist", "results", ".*cache*", "*.egg-info", "__pycache__", ".hypothesis"))
    r = subprocess.run(
        [sys.executable, "-m", "pip", "install", "--no-deps", "--quiet",
         "--target", str(target), str(src)],
        capture_output=True, text=True, timeout=600,
    )
    assert r.returncode == 0, r.stderr
    code = (
        "import importlib.resources as r, prbdm_pin, numpy as np\n"
        "from prbdm_pin.model import build_model\n"
        "from prbdm_pin.geometry import Beam\n"
        "files = r.files('prbdm_pin.urdf_templates')\n"
        "names = sorted(p.name for p in files.iterdir() if p.name.endswith('.tmpl'))\n"
        "print(prbdm_pin.__file__)\n"
        "print(','.join(names))\n"
        "m = build_model(Beam([0.0, 1.0], [0.05, 0.05], 0.01), [0.5, 0.5], [10.0])\n"
        "print('springStiffness>10.0<' in m.urdf)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         cwd=tmp_path, env={"PYTHONPATH": str(target), "PATH": ""}, timeout=300)
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert lines[0].startswith(str(target))
    assert lines[1] == "joint.urdf.tmpl,link.urdf.tmpl,robot.urdf.tmpl,spring.urdf.tmpl"
    assert lines[2] == "True"
