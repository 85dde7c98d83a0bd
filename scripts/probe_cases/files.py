"""Probe cases: the model and result files the package reads (beam, fit.json, model JSON, URDF).

Each case hands a broken, hostile or oversized file to a reader (in process) or to the CLI (in a
subprocess) and expects a BeamInputError / exit 2 naming the field, quickly, with no file
written; a few check that valid files the package writes still load unchanged.
"""

from __future__ import annotations

import atexit
import copy
import functools
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import xml.etree.ElementTree as ET
from pathlib import Path

from probe_cases._common import BEAMS, ROOT, expect_exit2

if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

import numpy as np  # noqa: E402

FILES = "3 model and result files"
WORK = "4 unbounded work"
SILENT = "5 silent wrong answers"
TAPERED = BEAMS / "tapered.json"


@functools.cache
def _tmp() -> Path:
    d = Path(tempfile.mkdtemp(prefix="prbdm-probe-files-"))
    atexit.register(shutil.rmtree, d, ignore_errors=True)
    return d


_counter = iter(range(10**9))


def _file(content, suffix=".json") -> Path:
    p = _tmp() / f"case{next(_counter)}{suffix}"
    if isinstance(content, bytes):
        p.write_bytes(content)
    elif isinstance(content, str):
        p.write_text(content, encoding="utf-8")
    else:
        p.write_text(json.dumps(content), encoding="utf-8")
    return p


def _cli(*args, timeout=120):
    # the package's own entry point (python -m prbdm_pin), this checkout first on the path
    env = {**os.environ, "PYTHONPATH": os.pathsep.join(
        [str(ROOT)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p])}
    t0 = time.perf_counter()
    proc = subprocess.run([sys.executable, "-m", "prbdm_pin", *map(str, args)],
                          capture_output=True, text=True, timeout=timeout, cwd=ROOT, env=env)
    proc.wall_s = time.perf_counter() - t0
    return proc


def _refused(fn, *names, where=None):
    """``fn()`` must raise BeamInputError whose message names every one of ``names``."""
    from prbdm_pin.errors import BeamInputError

    try:
        out = fn()
    except BeamInputError as exc:
        msg = str(exc)
        for n in names:
            assert n in msg, f"{n!r} not named in {msg!r}"
        return msg
    raise AssertionError(f"accepted{'' if where is None else ' ' + where}: returned {out!r:.120}")


@functools.cache
def _beam_doc() -> dict:
    return json.loads(TAPERED.read_text())


@functools.cache
def _fit_doc() -> dict:
    from prbdm_pin.files.beam_file import load_beam
    from prbdm_pin.files.fit_file import save_fit
    from prbdm_pin.fitting import fit
    from prbdm_pin.fitting.target import FitTarget

    beam = load_beam(TAPERED)
    r = fit(beam, FitTarget(np.array([87.0, 520.0]), beam.tip_force_N), 2, frequencies=2, starts=1,
            seed=0,
            progress=False)
    p = _tmp() / "valid-fit.json"
    save_fit(r, p, beam)
    return json.loads(p.read_text())


def _fit(**changes) -> dict:
    d = copy.deepcopy(_fit_doc())
    for k, v in changes.items():
        if v is KeyError:
            d.pop(k, None)
        else:
            d[k] = v
    return d


@functools.cache
def _model():
    from prbdm_pin.files.beam_file import load_beam
    from prbdm_pin.model.prbdm_model import build_model

    return build_model(load_beam(TAPERED), [0.2, 0.25, 0.15], [1200.0, 1100.0])


@functools.cache
def _model_doc() -> dict:
    from prbdm_pin.files.export import write_json

    p = _tmp() / "valid-model.json"
    write_json(_model(), p)
    return json.loads(p.read_text())


def _urdf_root():
    return ET.fromstring(_model().urdf)


def _named(root, tag, name):
    return [e for e in root.findall(tag) if e.get("name") == name][0]


def _urdf(root) -> Path:
    return _file(ET.tostring(root, encoding="unicode"), ".urdf")


def _load_fit(d):
    from prbdm_pin.files.fit_file import load_fit

    return lambda: load_fit(_file(d))


def _load_model(d):
    from prbdm_pin.files.model_source import load_model

    return lambda: load_model(str(_file(d)))


def _load_urdf(p):
    from prbdm_pin.files.urdf_file import load_urdf

    return lambda: load_urdf(p)


def _simulate(p, *extra):
    return _cli("simulate", p, "--duration", "0.01", "--out", _tmp() / f"sim{next(_counter)}",
                *extra)


def _export(p, fmt="urdf"):
    return _cli("export", p, "--format", fmt, "--out", _tmp() / f"exp{next(_counter)}.{fmt}")


# Category 3: model and result files ---------------------------------------------------------


def _fit_cases():
    out = []
    for label, lengths, field in [
        ("NaN (null) length", [None, 0.3, 0.3], "lengths_m[0]"),
        ("negative length", [0.3, -0.012, 0.312], "lengths_m[1]"),
        ("zero lengths [1, 0, 0]", [0.6, 0.0, 0.0], "lengths_m[1]"),
        ("empty lengths", [], "lengths_m"),
        ("lengths not summing to L", [0.2, 0.2, 0.3], "lengths_m sum"),
        ("lengths a string", "0.2,0.2,0.2", "lengths_m"),
    ]:
        out.append((FILES, f"fit.json {label}",
                    lambda ln=lengths, f=field: _refused(_load_fit(_fit(lengths_m=ln)), f)))
    text = json.dumps(_fit_doc())
    out += [
        (FILES, "fit.json truncated (was JSONDecodeError)",
         lambda: _refused(_load_fit(text[: len(text) // 2]), "not valid JSON")),
        (FILES, "fit.json not UTF-8",
         lambda: _refused(_load_fit(b"\xff" + text.encode()), "not UTF-8")),
        (FILES, "fit.json missing fields (was TypeError)",
         lambda: _refused(_load_fit({"lengths_m": [0.3, 0.3], "joints": 1}), "missing field")),
        (FILES, "fit.json as a list (was AttributeError)",
         lambda: _refused(_load_fit([_fit_doc()]), "JSON object")),
        (FILES, "fit.json versions a list (was AttributeError)",
         lambda: _refused(_load_fit(_fit(versions=[["numpy", "2"]])), "versions")),
        (FILES, "fit.json lengths [1, 0, 0] through simulate (was a Pinocchio RuntimeError)",
         lambda: expect_exit2(_simulate(_file(_fit(lengths_m=[0.6, 0.0, 0.0]))),
                              "lengths_m[1]")),
        (FILES, "beam JSON as MODEL of simulate (was 'missing 37 positional arguments')",
         lambda: expect_exit2(_simulate(TAPERED), "is a beam file")),
        (FILES, "beam JSON as MODEL of export",
         lambda: expect_exit2(_export(TAPERED), "prbdm fit")),
        (FILES, "truth.json as MODEL",
         lambda: _refused(_load_model({"omega_rad_s": [1.0], "dofs": 3}), "truth file")),
        (FILES, "batch.json as MODEL",
         lambda: _refused(_load_model({"settings": {}, "shard": [0, 1]}), "batch file")),
        (FILES, "a JSON list as MODEL", lambda: _refused(_load_model([1, 2]), "JSON list")),
        (FILES, "the valid fit.json loads and rebuilds its model",
         lambda: _valid_fit_loads()),
    ]
    # every field retyped, every required field dropped
    for key, value in _fit_doc().items():
        if key == "beam":
            continue
        bad = 5 if isinstance(value, str) else "x!"
        out.append((FILES, f"fit.json {key} retyped",
                    lambda k=key, b=bad: _refused(_load_fit(_fit(**{k: b})), k)))
    from dataclasses import MISSING, fields

    from prbdm_pin.fitting.results import FitResult

    for f in fields(FitResult):
        if f.default is MISSING and f.default_factory is MISSING:
            out.append((FILES, f"fit.json without {f.name}",
                        lambda k=f.name: _refused(_load_fit(_fit(**{k: KeyError})), k)))
    return out


def _valid_fit_loads():
    from prbdm_pin.files.model_source import load_model

    loaded = load_model(str(_file(_fit_doc())))
    model, fit = loaded.model, loaded.fit
    assert fit.joints == 2 and np.all(np.isfinite(model.natural_frequencies()))


def _model_json_cases():
    from prbdm_pin.files.export import read_model_json

    def rd(d):
        return lambda: read_model_json(_file(d))

    doc = _model_doc()
    out = [
        (FILES, "model JSON negative length",
         lambda: _refused(rd({**doc, "lengths_m": [0.8, -0.2, 0.0]}), "lengths_m[1]")),
        (FILES, "model JSON null length",
         lambda: _refused(rd({**doc, "lengths_m": [0.2, None, 0.15]}), "lengths_m[1]")),
        (FILES, "model JSON zero spring",
         lambda: _refused(rd({**doc, "stiffness_Nm_per_rad": [1.0, 0.0]}),
                          "stiffness_Nm_per_rad[1]")),
        (FILES, "model JSON n_joints inconsistent",
         lambda: _refused(rd({**doc, "n_joints": 5}), "n_joints")),
        (FILES, "model JSON truncated",
         lambda: _refused(rd(json.dumps(doc)[:-9]), "not valid JSON")),
        (FILES, "model JSON bad beam",
         lambda: _refused(rd({**doc, "beam": {**doc["beam"], "thickness": "thin"}}),
                          "beam: thickness")),
        (FILES, "model JSON round trip", lambda: _model_json_round_trip()),
    ]
    return out


def _model_json_round_trip():
    from prbdm_pin.files.export import read_model_json

    m = read_model_json(_file(_model_doc()))
    np.testing.assert_allclose(m.natural_frequencies(), _model().natural_frequencies(),
                               rtol=1e-12)


def _urdf_cases():
    out = []

    def no_joints():
        root = _urdf_root()
        for j in root.findall("joint"):
            root.remove(j)
        return _urdf(root)

    def joint_x(name, value):
        root = _urdf_root()
        _named(root, "joint", name).find("origin").set("xyz", f"{value} 0 0")
        return _urdf(root)

    def link_attr(link, tag, attr, value):
        root = _urdf_root()
        _named(root, "link", link).find("inertial").find(tag).set(attr, value)
        return _urdf(root)

    def joint_type(kind):
        root = _urdf_root()
        _named(root, "joint", "joint_1").set("type", kind)
        return _urdf(root)

    out += [
        (FILES, "URDF with no joints (was IndexError)",
         lambda: _refused(_load_urdf(no_joints()), "revolute joints")),
        (FILES, "URDF negative link length -0.953 m (was accepted)",
         lambda: _refused(_load_urdf(joint_x("joint_2", -0.953)), "joint_2", "-0.953")),
        (FILES, "URDF tip at a negative length",
         lambda: _refused(_load_urdf(joint_x("tip_joint", -0.1)), "tip_joint")),
        (FILES, "URDF zero masses (were accepted)",
         lambda: _refused(_load_urdf(_zero_masses()), "mass = 0.0")),
        (FILES, "URDF not XML",
         lambda: _refused(_load_urdf(_file("robot, not XML", ".urdf")), "not valid XML")),
        (FILES, "URDF not UTF-8",
         lambda: _refused(_load_urdf(_file(_model().urdf.encode("utf-16"), ".urdf")),
                          "not UTF-8")),
        (FILES, "URDF through simulate, no joints",
         lambda: expect_exit2(_simulate(no_joints()), "revolute joints")),
        (FILES, "URDFs the package writes load unchanged", lambda: _own_urdfs_load()),
    ]
    for kind in ("continuous", "prismatic", "floating", "planar"):
        out.append((FILES, f"URDF {kind} joint",
                    lambda k=kind: _refused(_load_urdf(joint_type(k)), "joint_1", k)))
    for link in ("link_0", "link_1", "link_2"):
        for value in ("0", "-1", "nan", "inf"):
            out.append((FILES, f"URDF {link} mass {value}",
                        lambda lk=link, v=value: _refused(
                            _load_urdf(link_attr(lk, "mass", "value", v)), lk, "mass")))
        for key in ("ixx", "iyy", "izz"):
            for value in ("0", "nan"):
                out.append((FILES, f"URDF {link} {key} {value}",
                            lambda lk=link, k=key, v=value: _refused(
                                _load_urdf(link_attr(lk, "inertia", k, v)), lk, k)))
    for value in ("nan", "0", "-5", "inf"):
        out.append((FILES, f"URDF springStiffness {value}",
                    lambda v=value: _refused(_load_urdf(_file(_model().urdf.replace(
                        "<springStiffness>1100.0<", f"<springStiffness>{v}<"), ".urdf")),
                        "springStiffness of joint_2")))
    for value in ("nan", "-0.2", "0"):
        out.append((FILES, f"URDF joint_1 origin x {value}",
                    lambda v=value: _refused(_load_urdf(joint_x("joint_1", v)), "joint_1")))
    return out


def _zero_masses():
    root = _urdf_root()
    for link in root.findall("link"):
        inertial = link.find("inertial")
        if inertial is not None:
            inertial.find("mass").set("value", "0")
    return _urdf(root)


def _own_urdfs_load():
    from prbdm_pin.files.export import urdf_text
    from prbdm_pin.files.urdf_file import load_urdf

    m = _model()
    w = m.natural_frequencies()
    for text in (m.urdf, urdf_text(m, 0.05, omega_truth_rad_s=w)):
        back = load_urdf(_file(text, ".urdf"))
        np.testing.assert_allclose(back.natural_frequencies(), w, rtol=1e-12)
    templates = sorted((ROOT / "urdf_templates").glob("*.tmpl"))
    assert len(templates) == 5, templates  # robot, link, joint, spring, hub


# Category 4: unbounded work -----------------------------------------------------------------


def _fit_with_links(n):
    return _fit(joints=n, lengths_m=[0.6 / (n + 1)] * (n + 1), stiffness_Nm_per_rad=[1e3] * n,
                stiffness_per_pose_Nm_per_rad=[[1e3] * n], poses_rad=[[0.0] * n],
                factors=[1.0], min_fraction=0.5 / (n + 1))


def _quick_exit2(proc, field, limit_s=30.0):
    expect_exit2(proc, field)
    assert proc.wall_s < limit_s, f"took {proc.wall_s:.1f} s"


def _work_cases():
    out = [
        (WORK, "fit.json with 1000 links through simulate (was > 6 GB)",
         lambda: _quick_exit2(_simulate(_file(_fit_with_links(1000))), "max_joints")),
        (WORK, "fit.json with 1000 links through export",
         lambda: _quick_exit2(_export(_file(_fit_with_links(1000)), "mjcf"), "max_joints")),
        (WORK, "200k-vertex beam through fit (was LinAlgError)",
         lambda: _quick_exit2(_cli("fit", _file(_vertices(200_000)), "--joints", "2",
                                   "--truth-model", "beam", "--out", _tmp() / "v"),
                              "max_vertices")),
        (WORK, "400-digit integer in a beam (was OverflowError)",
         lambda: _quick_exit2(_cli("fit", _file(_digits(400)), "--joints", "2",
                                   "--truth-model", "beam", "--out", _tmp() / "d"), "digits")),
        (WORK, "[ x 100000 as a beam (was RecursionError)",
         lambda: _quick_exit2(_cli("truth", _file("[" * 100_000), "--model", "beam",
                                   "--out", _tmp() / "r"), "nested deeper")),
        (WORK, "model JSON with 1000 links",
         lambda: _refused(_read_model_json({**_model_doc(), "lengths_m": [0.6 / 1001] * 1001,
                                            "stiffness_Nm_per_rad": [1.0] * 1000}),
                          "max_joints")),
        (WORK, "URDF with 200 joints", lambda: _refused(_load_urdf(_long_urdf(200)),
                                                        "max_joints")),
        (WORK, "PRBDM_MAX_JOINTS raises the cap for a 100-link URDF",
         lambda: _raised_cap()),
    ]
    for n in (65, 100, 10**6):
        out.append((WORK, f"fit.json joints = {n}",
                    lambda k=n: _refused(_load_fit(_fit(joints=k)), "joints", "max_joints")))
    for n in (10_001, 50_000):
        out.append((WORK, f"beam with {n} vertices",
                    lambda k=n: _refused(_load_beam(_vertices(k)), "max_vertices")))
    for digits in (31, 100, 4000):
        out.append((WORK, f"{digits}-digit integer in a beam",
                    lambda k=digits: _refused(_load_beam(_digits(k)), "digits")))
    for depth in (65, 1000, 100_000):
        out.append((WORK, f"beam nested {depth} deep",
                    lambda k=depth: _refused(_load_beam("[" * k), "nested deeper")))
        out.append((WORK, f"fit.json nested {depth} deep",
                    lambda k=depth: _refused(_load_fit("[" * k), "nested deeper")))
    return out


def _read_model_json(d):
    from prbdm_pin.files.export import read_model_json

    return lambda: read_model_json(_file(d))


def _load_beam(content):
    from prbdm_pin.files.beam_file import load_beam

    return lambda: load_beam(_file(content))


def _vertices(n):
    return {"x": np.linspace(0.0, 0.6, n).tolist(), "half_width": [0.05] * n,
            "thickness": 0.005, "tip_force": [0, 0, -10]}


def _digits(n):
    return json.dumps(_beam_doc()).replace('"thickness": 0.005', '"thickness": ' + "9" * n)


def _long_urdf(n):
    """A URDF of n joints, written by a model built with the joint cap raised to n."""
    from prbdm_pin.files.beam_file import load_beam
    from prbdm_pin.model.prbdm_model import build_model

    beam = load_beam(TAPERED)
    old = os.environ.get("PRBDM_MAX_JOINTS")
    os.environ["PRBDM_MAX_JOINTS"] = str(max(n, 64))
    try:
        m = build_model(beam, np.full(n + 1, beam.length_m / (n + 1)), np.full(n, 100.0),
                        min_fraction=0.5 / (n + 1))
        return _file(m.urdf, ".urdf")
    finally:
        if old is None:
            del os.environ["PRBDM_MAX_JOINTS"]
        else:
            os.environ["PRBDM_MAX_JOINTS"] = old


def _raised_cap():
    p = _long_urdf(100)
    old = os.environ.get("PRBDM_MAX_JOINTS")
    os.environ["PRBDM_MAX_JOINTS"] = "100"
    try:
        from prbdm_pin.files.urdf_file import load_urdf

        assert load_urdf(p).n_joints == 100
    finally:
        if old is None:
            del os.environ["PRBDM_MAX_JOINTS"]
        else:
            os.environ["PRBDM_MAX_JOINTS"] = old


# Category 5: silent wrong answers -----------------------------------------------------------


def _silent_cases():
    out = [
        (SILENT, "beam name with \\u0000 through fit (was exit 0 and unparsable URDF/MJCF)",
         lambda: _ctrl_name_cli()),
        (SILENT, 'fit.json "joints": "two" (was accepted)',
         lambda: _refused(_load_fit(_fit(joints="two")), "joints = 'two'")),
        (SILENT, "negative length reported as the length, not 'min_fraction = -0.05'",
         lambda: _no_min_fraction(_refused(_load_model(_fit(lengths_m=[0.66, -0.06, 0.0])),
                                           "lengths_m[1] = -0.06"))),
        (SILENT, "fit.json min_fraction negative",
         lambda: _refused(_load_fit(_fit(min_fraction=-0.05)), "min_fraction = -0.05")),
        (SILENT, "link floor from the beam, not from the file's min_fraction",
         lambda: _refused(_load_fit(_fit(lengths_m=[1e-9, 0.3, 0.3 - 1e-9],
                                         min_fraction=1e-10)), "lengths_m[0]")),
        (SILENT, "fingerprint mismatch names the --beam given (was '--beam None')",
         lambda: _fingerprint_mismatch()),
        (SILENT, "XML special characters in a beam name: URDF and MJCF parse",
         lambda: _special_name()),
    ]
    for field in ("name", "description", "material.name"):
        for code in list(range(0, 9)) + [11, 12] + list(range(14, 32)) + [0xDC80]:
            out.append((SILENT, f"beam {field} with U+{code:04X}",
                        lambda f=field, c=code: _refused(_load_beam(_ctrl(f, chr(c))),
                                                         f, "control characters")))
    return out


def _ctrl(field, char):
    d = copy.deepcopy(_beam_doc())
    if field == "material.name":
        d["material"]["name"] = f"steel{char}"
    else:
        d[field] = f"beam{char}"
    return d


def _ctrl_name_cli():
    out = _tmp() / "ctrl"
    expect_exit2(_cli("fit", _file(_ctrl("name", "\u0000")), "--joints", "2",
                      "--truth-model", "beam", "--out", out), "name")
    assert not (out / "model.urdf").exists(), "model.urdf written"


def _no_min_fraction(msg):
    assert "min_fraction" not in msg, msg


def _fingerprint_mismatch():
    d = {k: v for k, v in _fit_doc().items() if k != "beam"}
    proc = _simulate(_file(d), "--beam", BEAMS / "uniform-narrow.json")
    expect_exit2(proc, "uniform-narrow.json")
    assert "None" not in proc.stderr, proc.stderr


def _special_name():
    import mujoco

    from prbdm_pin.files.beam_file import beam_from_dict
    from prbdm_pin.files.export import mjcf_text, urdf_text
    from prbdm_pin.model.prbdm_model import build_model

    name = 'a<b>&"c\'d'
    beam = beam_from_dict({**_beam_doc(), "name": name})
    m = build_model(beam, [0.2, 0.25, 0.15], [1200.0, 1100.0])
    assert ET.fromstring(urdf_text(m)).get("name") == f"prbdm_{name}"
    p = _file(mjcf_text(m), ".xml")
    assert mujoco.MjModel.from_xml_path(str(p)).njnt == 2


def cases():
    """(category, name, fn) for every case of this module."""
    return _fit_cases() + _model_json_cases() + _urdf_cases() + _work_cases() + _silent_cases()
