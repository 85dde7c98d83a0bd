"""Fuzz the file readers: beam JSON, fit.json, model JSON (and MODEL), URDF.

Mutations of valid files (fields dropped, retyped, negated, NaN-ified, made huge or tiny, nested
deep, given control characters; text truncated or overwritten with random bytes) must give
either a result that passes the validators (a Beam that round-trips and renders as XML, a
model with positive lengths and masses whose frequencies are finite and positive, or a
SolveError from the eigensolver refusing an ill-conditioned chain) or a BeamInputError whose
message names a field of the file (or what is wrong with the file as a whole). Never another
exception type. The default suite runs a few dozen examples per reader; ``-m stress`` many more.
"""

from __future__ import annotations

import copy
import json
import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from tolerances import EPS

from prbdm_pin.errors import BeamInputError, SolveError
from prbdm_pin.files.beam_file import beam_from_dict, load_beam
from prbdm_pin.files.export import read_model_json, write_json
from prbdm_pin.files.fit_file import load_fit, save_fit
from prbdm_pin.files.model_source import load_model
from prbdm_pin.files.urdf_file import load_urdf
from prbdm_pin.fitting import fit
from prbdm_pin.fitting.target import FitTarget
from prbdm_pin.member.geometry import beam_to_dict
from prbdm_pin.model.prbdm_model import build_model

BEAMS = Path("examples/beams")
# what a message may name when the file as a whole is wrong, not one field
FILE_LEVEL = ("not valid JSON", "not UTF-8", "nested deeper", "digits", "must be finite",
              "must be a JSON object", "not valid XML", "root element", "Pinocchio cannot parse",
              "is a ", "format must be", "missing", "unknown key")

FAST = settings(max_examples=30, deadline=None,
                suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
STRESS = settings(max_examples=600, deadline=None,
                  suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

SPECIAL = [0, -1, 1, 2, -0.0, 1e308, -1e308, 5e-324, 1e-300, 1e300, 10**29, 0.5, 64, 65, 1000]
LEAF = st.one_of(
    st.none(), st.booleans(), st.sampled_from(SPECIAL),
    st.floats(allow_nan=False, allow_infinity=False, width=64),
    st.integers(-(10**40), 10**40),
    st.text(alphabet=st.sampled_from("ab\u0000\u0001\t<&\"'\ud7ff\udc80"), max_size=6),
    st.lists(st.floats(-10, 10, allow_nan=False), max_size=4),
    st.just({}), st.just([[]]), st.just("nan"),
)
OPS = ("drop", "set", "negate", "null", "wrap", "deep", "ctrl", "scale")


def _keys(doc) -> set[str]:
    out = set()
    if isinstance(doc, dict):
        for k, v in doc.items():
            out.add(k)
            out |= _keys(v)
    elif isinstance(doc, list):
        for v in doc[:3]:
            out |= _keys(v)
    return out


def _paths(doc, prefix=()) -> list[tuple]:
    out = [prefix] if prefix else []
    if isinstance(doc, dict):
        for k, v in doc.items():
            out += _paths(v, prefix + (k,))
    elif isinstance(doc, list):
        for i, v in enumerate(doc[:4]):
            out += _paths(v, prefix + (i,))
    return out


def _mutate(doc, path, op, leaf):
    d = copy.deepcopy(doc)
    parent = d
    for p in path[:-1]:
        parent = parent[p]
    key = path[-1]
    v = parent[key]
    if op == "drop":
        del parent[key]
    elif op == "set":
        parent[key] = leaf
    elif op == "negate" and isinstance(v, (int, float)) and not isinstance(v, bool):
        parent[key] = -v
    elif op == "null":
        parent[key] = None
    elif op == "wrap":
        parent[key] = [v]
    elif op == "deep":
        parent[key] = json.loads("[" * 70 + "1" + "]" * 70)
    elif op == "ctrl":
        parent[key] = f"{v}\u0000" if isinstance(v, str) else "\u0001"
    elif op == "scale" and isinstance(v, (int, float)) and not isinstance(v, bool):
        parent[key] = v * 1e-12
    else:
        parent[key] = leaf
    return d


TEXT_OPS = st.one_of(
    st.tuples(st.just("truncate"), st.floats(0, 1)),
    st.tuples(st.just("bytes"), st.binary(min_size=1, max_size=40)),
    st.tuples(st.just("splice"), st.binary(min_size=1, max_size=8)),
)


def _text_mutation(text: str, op) -> bytes:
    raw = text.encode()
    kind, arg = op
    if kind == "truncate":
        return raw[: int(arg * len(raw))]
    if kind == "bytes":
        return arg
    mid = len(raw) // 2
    return raw[:mid] + arg + raw[mid:]


def _names_a_field(msg: str, names: set[str]) -> bool:
    if any(s in msg for s in FILE_LEVEL):
        return True
    return any(re.search(rf"(?<![A-Za-z_]){re.escape(n)}(?![A-Za-z_])", msg) for n in names)


def _check_frequencies(model) -> None:
    assert np.all(np.asarray(model.lengths_m) > 0)
    assert np.all(np.asarray(model.sections.mass_kg) > 0)
    try:
        w = model.natural_frequencies()
    except SolveError:
        return  # the eigensolver refused an ill-conditioned chain, by name
    assert np.all(np.isfinite(w)) and np.all(w > 0), w


# Fixtures: valid files -------------------------------------------------------------------------


@pytest.fixture(scope="module")
def beam_doc():
    return json.loads((BEAMS / "tapered.json").read_text())


@pytest.fixture(scope="module")
def fit_doc(tmp_path_factory):
    beam = load_beam(BEAMS / "tapered.json")
    r = fit(beam, FitTarget(np.array([87.0, 520.0]), beam.tip_force_N), 2, frequencies=2, starts=1,
            seed=0, progress=False)
    p = tmp_path_factory.mktemp("fit") / "fit.json"
    save_fit(r, p, beam)
    return json.loads(p.read_text())


@pytest.fixture(scope="module")
def model_doc(tmp_path_factory):
    beam = load_beam(BEAMS / "tapered.json")
    p = tmp_path_factory.mktemp("mj") / "model.json"
    write_json(build_model(beam, [0.2, 0.25, 0.15], [1200.0, 1100.0]), p)
    return json.loads(p.read_text())


@pytest.fixture(scope="module")
def urdf_doc():
    beam = load_beam(BEAMS / "tapered.json")
    return build_model(beam, [0.2, 0.25, 0.15], [1200.0, 1100.0]).urdf


@pytest.fixture(scope="module")
def scratch(tmp_path_factory):
    return tmp_path_factory.mktemp("fuzz")


def _write(scratch: Path, name: str, content) -> Path:
    p = scratch / name
    if isinstance(content, bytes):
        p.write_bytes(content)
    else:
        p.write_text(json.dumps(content), encoding="utf-8")
    return p


# Readers -------------------------------------------------------------------------------------


def _read_beam(p: Path, names: set[str]) -> None:
    try:
        beam = load_beam(p)
    except BeamInputError as exc:
        assert _names_a_field(str(exc), names), str(exc)
        return
    again = beam_from_dict(beam_to_dict(beam))
    assert again.fingerprint() == beam.fingerprint()
    L = beam.length_m
    urdf = build_model(beam, [L / 3, L / 3, L / 3], [1.0, 1.0]).urdf
    assert ET.fromstring(urdf).get("name") == f"prbdm_{beam.name}"


def _read_fit(p: Path, names: set[str]) -> None:
    for reader in (load_fit, lambda q: load_model(str(q)).model):
        try:
            out = reader(p)
        except BeamInputError as exc:
            assert _names_a_field(str(exc), names), str(exc)
            continue
        if hasattr(out, "pin_model"):
            _check_frequencies(out)
        else:
            assert 1 <= out.joints <= 64 and out.lengths_m.size == out.joints + 1
            assert np.all(out.lengths_m > 0) and np.all(out.stiffness_Nm_per_rad > 0)


def _read_model(p: Path, names: set[str]) -> None:
    for reader in (read_model_json, lambda q: load_model(str(q)).model):
        try:
            model = reader(p)
        except BeamInputError as exc:
            assert _names_a_field(str(exc), names), str(exc)
            continue
        _check_frequencies(model)


URDF_NAMES = {"joint", "link", "springStiffness", "revolute", "tip", "placement", "frame",
              "robot", "stiffness", "UTF-8", "XML", "mass", "inertia", "joints"}


def _read_urdf(p: Path) -> None:
    try:
        model = load_urdf(p)
    except BeamInputError as exc:
        assert _names_a_field(str(exc), URDF_NAMES), str(exc)
        return
    _check_frequencies(model)


# JSON mutations ----------------------------------------------------------------------------------


def _json_case(data, doc):
    paths = _paths(doc)
    n_mut = data.draw(st.integers(1, 3))
    d = doc
    for _ in range(n_mut):
        paths = _paths(d) or [()]
        path = data.draw(st.sampled_from(paths))
        if not path:
            break
        d = _mutate(d, path, data.draw(st.sampled_from(OPS)), data.draw(LEAF))
    if data.draw(st.integers(0, 9)) == 0:
        return _text_mutation(json.dumps(d), data.draw(TEXT_OPS))
    return d


def _fuzz_beam(data, beam_doc, scratch):
    case = _json_case(data, beam_doc)
    _read_beam(_write(scratch, "beam.json", case), _keys(beam_doc) | {"vertices"})


def _fuzz_fit(data, fit_doc, scratch):
    case = _json_case(data, fit_doc)
    _read_fit(_write(scratch, "fit.json", case), _keys(fit_doc))


def _fuzz_model(data, model_doc, scratch):
    case = _json_case(data, model_doc)
    _read_model(_write(scratch, "model.json", case), _keys(model_doc))


# URDF mutations ----------------------------------------------------------------------------------

URDF_VALUES = st.one_of(
    st.sampled_from(["0", "-1", "nan", "inf", "-inf", "1e400", "", " ", "abc", "1e-320",
                     "-0.953 0 0", "0 0 0", "1 2", "0.1 0.1 0.1", "continuous", "prismatic",
                     "fixed", "floating", "world", "tip", "link_1", "joint_1", "1e300"]),
    st.floats(allow_nan=True, allow_infinity=True).map(repr),
    st.text(alphabet=st.sampled_from("0123456789.-e "), max_size=8),
)


def _fuzz_urdf(data, urdf_doc, scratch):
    root = ET.fromstring(urdf_doc)
    for _ in range(data.draw(st.integers(1, 3))):
        elements = list(root.iter())
        el = data.draw(st.sampled_from(elements))
        op = data.draw(st.sampled_from(["attr", "remove", "text", "duplicate"]))
        if op == "attr" and el.attrib:
            el.set(data.draw(st.sampled_from(sorted(el.attrib))), data.draw(URDF_VALUES))
        elif op == "remove" and el is not root:
            parent = next(p for p in root.iter() if el in list(p))
            parent.remove(el)
        elif op == "duplicate" and el is not root:
            parent = next(p for p in root.iter() if el in list(p))
            parent.append(copy.deepcopy(el))
        else:
            el.text = data.draw(URDF_VALUES)
    text = ET.tostring(root, encoding="unicode")
    raw = (_text_mutation(text, data.draw(TEXT_OPS)) if data.draw(st.integers(0, 7)) == 0
           else text.encode())
    _read_urdf(_write(scratch, "model.urdf", raw))


# Tests -------------------------------------------------------------------------------------------


@FAST
@given(data=st.data())
def test_fuzz_beam_reader(data, beam_doc, scratch):
    _fuzz_beam(data, beam_doc, scratch)


@FAST
@given(data=st.data())
def test_fuzz_fit_reader(data, fit_doc, scratch):
    _fuzz_fit(data, fit_doc, scratch)


@FAST
@given(data=st.data())
def test_fuzz_model_json_reader(data, model_doc, scratch):
    _fuzz_model(data, model_doc, scratch)


@FAST
@given(data=st.data())
def test_fuzz_urdf_reader(data, urdf_doc, scratch):
    _fuzz_urdf(data, urdf_doc, scratch)


@pytest.mark.stress
@STRESS
@given(data=st.data())
def test_fuzz_beam_reader_stress(data, beam_doc, scratch):
    _fuzz_beam(data, beam_doc, scratch)


@pytest.mark.stress
@STRESS
@given(data=st.data())
def test_fuzz_fit_reader_stress(data, fit_doc, scratch):
    _fuzz_fit(data, fit_doc, scratch)


@pytest.mark.stress
@STRESS
@given(data=st.data())
def test_fuzz_model_json_reader_stress(data, model_doc, scratch):
    _fuzz_model(data, model_doc, scratch)


@pytest.mark.stress
@STRESS
@given(data=st.data())
def test_fuzz_urdf_reader_stress(data, urdf_doc, scratch):
    _fuzz_urdf(data, urdf_doc, scratch)


def _hostile_beams(doc):
    yield "deep", ("[" * 100_000).encode()
    yield "digits", json.dumps(doc).replace('"thickness": 0.005', '"thickness": ' + "9" * 400)
    for char in ("\u0000", "\u0001", "\udc80"):
        yield f"name {char!r}", {**doc, "name": f"a{char}"}
        yield f"material {char!r}", {**doc, "material": {**doc["material"], "name": char}}
    yield "vertices", {**doc, "x": np.linspace(0, 0.6, 200_000).tolist(),
                       "half_width": [0.05] * 200_000}
    yield "NaN", json.dumps(doc).replace('"thickness": 0.005', '"thickness": NaN')


def test_hostile_beam_corpus(beam_doc, scratch):
    """Inputs of the issue through the same property: a clean refusal naming the problem."""
    for name, case in _hostile_beams(beam_doc):
        p = _write(scratch, "beam.json", case.encode() if isinstance(case, str) else case)
        with pytest.raises(BeamInputError) as info:
            load_beam(p)
        assert _names_a_field(str(info.value), _keys(beam_doc) | {"vertices"}), name


def test_the_valid_files_themselves_pass(beam_doc, fit_doc, model_doc, urdf_doc, scratch):
    """The unmutated files load, so a fuzz run exercises more than the refusals."""
    assert load_beam(_write(scratch, "b.json", beam_doc)).name == beam_doc["name"]
    assert load_fit(_write(scratch, "f.json", fit_doc)).joints == 2
    m = read_model_json(_write(scratch, "m.json", model_doc))
    u = load_urdf(_write(scratch, "m.urdf", urdf_doc.encode()))
    # both files write every number in full: one chain (exact here); kept: the test's 1e-12
    np.testing.assert_allclose(u.natural_frequencies(), m.natural_frequencies(),
                               rtol=5000 * EPS)
    assert math.isclose(float(np.sum(m.lengths_m)), 0.6, rel_tol=1e-12)
