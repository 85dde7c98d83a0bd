"""``prbdm fit --truth TRUTH.json``: a bad truth file is one line naming the field, exit 2."""

import json
import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from paths import ROOT

from prbdm_pin.cli import main
from prbdm_pin.errors import BeamInputError
from prbdm_pin.files.truth_file import read_truth_file, truth_file_from_dict

BEAM = str(ROOT / "examples" / "beams" / "uniform-narrow.json")
OMEGA = [10.0, 60.0, 170.0]
GOOD = {"omega_rad_s": OMEGA, "tip_position_m": [0.9, 0.0, -0.3],
        "tip_displacement_m": [-0.1, 0.0, -0.3], "mac": [1.0, 0.99, 0.98]}


def _run(tmp_path, capsys, text: str | bytes) -> str:
    path = tmp_path / "truth.json"
    (path.write_bytes if isinstance(text, bytes) else path.write_text)(text)
    rc = main(["fit", BEAM, "--joints", "2", "--truth", str(path), "--out",
               str(tmp_path / "fit"), "-q"])
    err = capsys.readouterr().err.strip()
    assert rc == 2, err
    assert len(err.splitlines()) == 1 and "Traceback" not in err, err
    assert not (tmp_path / "fit" / "fit.json").exists()
    return err


def _with(**changes):
    d = dict(GOOD)
    for k, v in changes.items():
        if v is ...:
            d.pop(k)
        else:
            d[k] = v
    return json.dumps(d)


@pytest.mark.parametrize("text, field", [
    ("[1, 2, 3]", "must be a JSON object"),
    (_with(omega_rad_s=...), "omega_rad_s: missing"),
    (_with(omega_rad_s="fast"), "omega_rad_s"),
    (_with(omega_rad_s=[]), "omega_rad_s"),
    (_with(omega_rad_s=[10.0, -60.0, 170.0]), "omega_rad_s[1]"),
    (_with(omega_rad_s=[0.0, 60.0, 170.0]), "omega_rad_s[0]"),
    (_with(omega_rad_s=[10.0, "60", 170.0]), "omega_rad_s[1]"),
    (_with(omega_rad_s=[60.0, 10.0, 170.0]), "omega_rad_s[1]"),
    ('{"omega_rad_s": [10.0, NaN, 170.0]}', "NaN"),
    ('{"omega_rad_s": [10.0, 1e999, 170.0]}', "omega_rad_s[1]"),
    (_with(tip_position_m=[0.9, 0.0]), "tip_position_m"),
    (_with(tip_position_m=[0.9, None, 0.0]), "tip_position_m[1]"),
    (_with(tip_displacement_m={"x": 1}), "tip_displacement_m"),
    (_with(mac=[1.0, 1.0]), "mac"),
    (_with(mac=[1.0, 1.5, 1.0]), "mac[1]"),
    (_with(mac=[1.0, -0.1, 1.0]), "mac[1]"),
    (_with(static_theory_gap_pct="small"), "static_theory_gap_pct"),
    (_with(beam_fingerprint=5), "beam_fingerprint"),
    (_with(beam_fingerprint="abc"), "beam_fingerprint"),
    (_with(tip_positon_m=[0.9, 0.0, -0.3]), "tip_positon_m"),
    (_with(mode_index=[0, 1]), "mode_index"),
    (_with(mode_index=[0, 1, 2], all_omega_rad_s=[10.0, 60.0]), "mode_index[2]"),
    (_with(mode_index=[0, 1, 3], all_omega_rad_s=[10.0, 11.0, 60.0, 170.0]), "omega_rad_s[1]"),
    (_with(labels=["bending", "bending"]), "labels"),
    (_with(labels=["bending", 3, "bending"]), "labels[1]"),
    (_with(mpf_z_fraction=[0.5, 0.2, 7.0]), "mpf_z_fraction[2]"),
    (_with(error_estimate_pct=[0.1, 0.1]), "error_estimate_pct"),
    (_with(mesh_level=-1), "mesh_level"),
    (_with(warnings="none"), "warnings"),
    (_with(beam="a\u0000b"), "beam"),
    ('{"omega_rad_s": [10.0, 60.0', "not valid JSON"),
    (b'{"omega_rad_s": [10.0], "beam": "\xff\xfe"}', "not UTF-8"),
    ("[" * 100_000, "nested deeper"),
    ('{"omega_rad_s": [1' + "0" * 400 + "]}", "digits"),
])
def test_a_bad_truth_file_is_one_line_naming_the_field(tmp_path, capsys, text, field):
    err = _run(tmp_path, capsys, text)
    assert field in err and "truth file" in err, err


def test_a_missing_truth_file_names_the_file(tmp_path, capsys):
    rc = main(["fit", BEAM, "--joints", "2", "--truth", str(tmp_path / "nope.json"),
               "--out", str(tmp_path / "fit"), "-q"])
    err = capsys.readouterr().err
    assert rc == 2 and "nope.json" in err and "not found" in err


def test_the_truth_command_output_is_read_back_exactly(tmp_path):
    out = tmp_path / "truth"
    assert main(["truth", BEAM, "--model", "beam", "--modes", "3", "--out", str(out), "-q"]) == 0
    doc = json.loads((out / "truth.json").read_text())
    t = read_truth_file(out / "truth.json")
    assert t.omega_rad_s.tolist() == doc["omega_rad_s"]
    assert t.tip_position_m.tolist() == doc["tip_position_m"]
    assert t.tip_displacement_m.tolist() == doc["tip_displacement_m"]
    assert t.mac.tolist() == doc["mac"] and t.beam_fingerprint == doc["beam_fingerprint"]
    assert t.static_theory_gap_pct == doc["static_theory_gap_pct"]


_values = st.one_of(
    st.none(), st.booleans(), st.integers(-3, 5), st.floats(allow_nan=True),
    st.text(max_size=4), st.lists(st.floats(-1e3, 1e3), max_size=5),
    st.lists(st.integers(-1, 4), max_size=4), st.lists(st.text(max_size=3), max_size=4),
)
_keys = st.sampled_from(["omega_rad_s", "tip_position_m", "tip_displacement_m", "mac",
                         "static_theory_gap_pct", "beam_fingerprint", "mode_index",
                         "all_omega_rad_s", "labels", "mpf_z_fraction", "mesh_level", "extra"])


@settings(max_examples=60, deadline=None)
@given(st.dictionaries(_keys, _values, max_size=6),
       st.lists(st.floats(0.1, 1e4), min_size=1, max_size=4))
def test_fuzz_a_truth_mapping_is_valid_or_refused_naming_a_field(d, omega):
    d = {"omega_rad_s": sorted(omega), **d}
    try:
        t = truth_file_from_dict(d)
    except BeamInputError as exc:
        assert any(k in str(exc) for k in d) or "JSON object" in str(exc), str(exc)
        return
    w = t.omega_rad_s
    assert w.ndim == 1 and w.size >= 1 and np.all(np.isfinite(w)) and np.all(w > 0)
    assert np.all(np.diff(w) >= 0)
    for v in (t.tip_position_m, t.tip_displacement_m):
        assert v is None or (v.shape == (3,) and np.all(np.isfinite(v)))
    assert t.mac is None or (t.mac.shape == w.shape and np.all((t.mac >= 0) & (t.mac <= 1 + 1e-9)))
    assert t.static_theory_gap_pct is None or math.isfinite(t.static_theory_gap_pct)
