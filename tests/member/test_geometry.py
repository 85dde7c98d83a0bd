"""Beam input: every invalid field raises BeamInputError naming field and value; JSON; random."""

import json
import math

import numpy as np
import pytest
from paths import BEAMS

from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.beam_file import beam_from_dict, load_beam, save_beam
from prbdm_pin.member.geometry import Beam, beam_to_dict
from prbdm_pin.member.random_beams import random_beam
from prbdm_pin.model.prbdm_model import build_model


def good():
    return {
        "name": "t", "length": 1.0, "x": [0.0, 0.4, 1.0], "half_width": [0.1, 0.08, 0.05],
        "thickness": 0.01, "material": {"name": "steel", "E": 205e9, "rho": 7850.0, "nu": 0.28},
        "tip_force": [0.0, 0.0, -100.0],
    }


def _set(d, path, value):
    d = json.loads(json.dumps(d))
    target = d
    for key in path[:-1]:
        target = target[key]
    if value is _DELETE:
        del target[path[-1]]
    else:
        target[path[-1]] = value
    return d


_DELETE = object()

CASES = [
    (("x", 0), 0.1, r"x\[0\] = 0\.1"),
    (("x", 1), 1.0, r"x\[2\] = 1\.0 m: a width step at the tip"),
    (("x", 1), 0.0, r"x\[1\] = 0\.0 m: a width step at the root"),
    (("x", 1), 1.2, r"x\[2\] = 1\.0 m: must not decrease \(x\[1\] = 1\.2 m\)"),
    (("length",), 1.2, r"length = 1\.2"),
    (("half_width", 1), 0.0, r"half_width\[1\] = 0\.0"),
    (("half_width", 2), -0.01, r"half_width\[2\] = -0\.01"),
    (("x", 1), math.nan, r"x\[1\] = nan"),
    (("x", 2), math.inf, r"x\[2\] = inf"),
    (("half_width", 0), math.nan, r"half_width\[0\] = nan"),
    (("half_width", 0), -math.inf, r"half_width\[0\] = -inf"),
    (("thickness",), math.nan, r"thickness = nan"),
    (("thickness",), math.inf, r"thickness = inf"),
    (("thickness",), 0.0, r"thickness = 0\.0"),
    (("thickness",), -0.01, r"thickness = -0\.01"),
    (("material", "E"), math.nan, r"material\.E = nan"),
    (("material", "E"), -1.0, r"material\.E = -1\.0"),
    (("material", "rho"), math.inf, r"material\.rho = inf"),
    (("material", "nu"), 0.5, r"material\.nu = 0\.5"),
    (("material", "nu"), math.nan, r"material\.nu = nan"),
    (("tip_force", 2), math.nan, r"tip_force\[2\] = nan"),
    (("tip_force",), [1.0, 2.0], r"tip_force has 2 entries"),
    (("length",), math.nan, r"length = nan"),
    (("thickness",), "thin", r"thickness = 'thin'"),
    (("x",), "0 1", r"x = '0 1'"),
    (("x", 1), "0.4", r"x\[1\] = '0\.4'"),
    (("half_width", 0), True, r"half_width\[0\] = True"),
    (("material",), "steel", r"material = 'steel'"),
    (("material", "E"), "205e9", r"material\.E = '205e9'"),
    (("name",), 3, r"name = 3"),
    (("half_width",), [0.1, 0.1], r"half_width has 2 entries"),
    (("bogus",), 1, r"unknown key\(s\) \['bogus'\]"),
    (("material", "G"), 1, r"unknown key\(s\) in material \['G'\]"),
    (("x",), _DELETE, r"missing key\(s\) \['x'\]"),
    (("half_width",), _DELETE, r"missing key\(s\) \['half_width'\]"),
    (("thickness",), _DELETE, r"missing key\(s\) \['thickness'\]"),
]


@pytest.mark.parametrize("path, value, pattern", CASES)
def test_every_invalid_field_is_named(path, value, pattern):
    with pytest.raises(BeamInputError, match=pattern):
        beam_from_dict(_set(good(), path, value))


def test_non_finite_json_constants_are_rejected(tmp_path):
    p = tmp_path / "b.json"
    p.write_text(json.dumps(good()).replace("0.01,", "NaN,", 1))
    with pytest.raises(BeamInputError, match="NaN"):
        load_beam(p)


def test_missing_or_malformed_file(tmp_path):
    with pytest.raises(BeamInputError, match="not found"):
        load_beam(tmp_path / "none.json")
    (tmp_path / "bad.json").write_text("{")
    with pytest.raises(BeamInputError, match="not valid JSON"):
        load_beam(tmp_path / "bad.json")


BEAM = Beam([0.0, 1.0], [0.05, 0.05], 0.01)


@pytest.mark.parametrize(
    "lengths, stiffness, pattern",
    [
        ([1.0], [], r"lengths = \[1\.0\]: needs at least 2 links \(n >= 1"),
        ([0.5, 0.6], [1.0], r"lengths sum to 1\.1"),
        ([0.99, 0.01], [1.0], r"lengths\[0\] = 0\.99"),
        ([0.5, float("nan")], [1.0], r"lengths\[1\] = nan"),
        ([0.5, 0.5], [1.0, 2.0], r"stiffness has shape \(2,\): needs 1 value"),
        ([0.5, 0.5], [0.0], r"stiffness\[0\] = 0\.0"),
        ([0.5, 0.5], [-3.0], r"stiffness\[0\] = -3\.0"),
        ([0.5, 0.5], [float("nan")], r"stiffness\[0\] = nan"),
        ([0.5, 0.5], [[1.0]], r"stiffness has shape \(1, 1\)"),
        ([0.5, 0.5], "stiff", r"stiffness = 'stiff'"),
    ],
)
def test_model_inputs_are_named(lengths, stiffness, pattern):
    with pytest.raises(BeamInputError, match=pattern):
        build_model(BEAM, lengths, stiffness)


def test_shipped_beams_load_and_round_trip(tmp_path):
    for path in sorted(BEAMS.glob("*.json")):
        beam = load_beam(path)
        out = save_beam(beam, tmp_path / path.name)
        again = load_beam(out)
        assert beam_to_dict(again) == beam_to_dict(beam)
        assert again.fingerprint() == beam.fingerprint()
        raw = json.loads(path.read_text())
        np.testing.assert_array_equal(again.x_m, raw["x"])
        np.testing.assert_array_equal(again.half_width_m, raw["half_width"])


def test_random_beam_reproducible_and_floored():
    a = random_beam(np.random.default_rng(42), p=10)
    b = random_beam(np.random.default_rng(42), p=10)
    c = random_beam(np.random.default_rng(43), p=10)
    assert beam_to_dict(a) == beam_to_dict(b)
    assert beam_to_dict(a) != beam_to_dict(c)
    assert a.x_m.size == 12 and a.x_m[0] == 0.0 and a.x_m[-1] == 1.0
    assert np.all(np.diff(a.x_m) > 0)
    assert np.all(a.half_width_m <= 0.5)
    floor = 0.3
    many = [random_beam(np.random.default_rng(s), p=10, min_half_width_m=floor) for s in range(5)]
    w = np.concatenate([m.half_width_m for m in many])
    assert w.min() == floor  # draws under the floor (60 % of U(0, 0.5)) are lifted to it
    assert np.all(w >= floor)
