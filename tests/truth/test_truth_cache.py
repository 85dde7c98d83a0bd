"""The truth cache runs no code and serves nothing it cannot verify.

Every refused entry must be a miss with a TruthCacheWarning naming it, and the truth then served
must equal an independent computation without any cache.
"""

import dataclasses
import json
import os
import pickle
import shutil
import subprocess
import sys
import textwrap
import zipfile
from pathlib import Path

import numpy as np
import pytest
from paths import ROOT

from prbdm_pin.files.beam_file import load_beam
from prbdm_pin.truth import cache, compute_truth
from prbdm_pin.truth.cache import TruthCacheWarning
from prbdm_pin.truth.digest import TRUTH_MODULES, digest_of, truth_modules

BEAMS = ROOT / "examples" / "beams"
ARGS = {"model": "beam", "modes": 3, "static": False}


def _fresh(name="tapered.json"):
    return compute_truth(load_beam(BEAMS / name), **ARGS)


def _only_entry(d: Path) -> Path:
    entries = list(d.glob("truth-*.npz"))
    assert len(entries) == 1, entries
    return entries[0]


def _assert_equal(a, b, path="result"):
    """Field-by-field equality of two truth dataclasses (arrays bitwise, timings excepted)."""
    if dataclasses.is_dataclass(a):
        assert type(a) is type(b), path
        for f in dataclasses.fields(a):
            if f.name != "timings":
                _assert_equal(getattr(a, f.name), getattr(b, f.name), f"{path}.{f.name}")
    elif isinstance(a, np.ndarray):
        assert a.dtype == b.dtype and a.shape == b.shape, path
        np.testing.assert_array_equal(a, b, err_msg=path)
    else:
        assert a == b, (path, a, b)


class _Marker:
    """Unpickling this creates the file ``path`` (a stand-in for arbitrary code)."""

    def __init__(self, path):
        self.path = str(path)

    def __reduce__(self):
        return (Path.touch, (Path(self.path),))


def test_hit_returns_every_field_of_the_stored_truth_read_only(tmp_path):
    beam = load_beam(BEAMS / "tapered.json")
    first = compute_truth(beam, model="beam", modes=3, static=True, cache_dir=tmp_path)
    entry = _only_entry(tmp_path)
    assert not list(tmp_path.glob("*.pkl")) and not list(tmp_path.glob(".truth-*"))
    with zipfile.ZipFile(entry) as zf:  # data only: .npy members, no pickled object arrays
        assert all(i.filename.endswith(".npy") for i in zf.infolist())
    with np.load(entry, allow_pickle=False) as npz:
        meta = json.loads(npz["__meta__"].tobytes())
    assert meta["key"] in entry.name and meta["beam_fingerprint"] == beam.fingerprint()
    assert len(meta["checksum"]) == 64
    again = compute_truth(beam, model="beam", modes=3, static=True, cache_dir=tmp_path)
    _assert_equal(first, again)
    assert not again.omega_rad_s.flags.writeable and not again.modal.node_uz.flags.writeable


def _key_of(tmp_path) -> str:
    compute_truth(load_beam(BEAMS / "tapered.json"), **ARGS, cache_dir=tmp_path)
    return _only_entry(tmp_path).name[len("truth-"):-len(".npz")]


def test_a_pickle_in_the_cache_folder_is_never_executed(tmp_path):
    key = _key_of(tmp_path)
    marker = tmp_path / "executed"
    evil = pickle.dumps(_Marker(marker))
    (tmp_path / f"truth-{key}.pkl").write_bytes(evil)  # the previous format's name
    (tmp_path / f"truth-{key}.npz").write_bytes(evil)  # the current name
    with pytest.warns(TruthCacheWarning, match=f"truth-{key}.npz"):
        got = compute_truth(load_beam(BEAMS / "tapered.json"), **ARGS, cache_dir=tmp_path)
    assert not marker.exists()
    _assert_equal(got, _fresh())


def test_an_npz_with_a_pickled_object_array_is_never_executed(tmp_path):
    key = _key_of(tmp_path)
    entry = tmp_path / f"truth-{key}.npz"
    marker = tmp_path / "executed"
    with np.load(entry, allow_pickle=False) as npz:
        arrays = dict(npz)
    arrays["omega_rad_s"] = np.array([_Marker(marker)], dtype=object)
    with open(entry, "wb") as fh:
        np.savez(fh, **arrays)
    with pytest.warns(TruthCacheWarning, match="refused"):
        got = compute_truth(load_beam(BEAMS / "tapered.json"), **ARGS, cache_dir=tmp_path)
    assert not marker.exists()
    _assert_equal(got, _fresh())


def _rewrite(entry: Path, arrays=None, meta=None):
    with np.load(entry, allow_pickle=False) as npz:
        old = dict(npz)
    m = json.loads(old.pop("__meta__").tobytes())
    m = meta(m) if meta else m
    new = arrays(old) if arrays else old
    blob = np.frombuffer(json.dumps(m).encode(), dtype=np.uint8)
    with open(entry, "wb") as fh:
        np.savez(fh, __meta__=blob, **new)


def test_an_entry_edited_in_place_is_recomputed_not_served(tmp_path):
    key = _key_of(tmp_path)
    fresh = _fresh()

    def scaled(a):
        a["omega_rad_s"] = a["omega_rad_s"] * 1.37
        a["modal.omega_rad_s"] = a["modal.omega_rad_s"] * 1.37
        return a

    _rewrite(tmp_path / f"truth-{key}.npz", arrays=scaled)
    with pytest.warns(TruthCacheWarning, match="checksum"):
        got = compute_truth(load_beam(BEAMS / "tapered.json"), **ARGS, cache_dir=tmp_path)
    np.testing.assert_array_equal(got.omega_rad_s, fresh.omega_rad_s)
    _assert_equal(got, fresh)
    # the recomputed truth replaced the edited entry: the next call is a clean hit
    import warnings

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        _assert_equal(compute_truth(load_beam(BEAMS / "tapered.json"), **ARGS,
                                    cache_dir=tmp_path), fresh)


def test_edited_metadata_is_recomputed_not_served(tmp_path):
    key = _key_of(tmp_path)

    def edit(m):
        m["result"]["warnings"] = ["all is well"]
        m["result"]["modal"]["dofs"] = 7
        return m

    _rewrite(tmp_path / f"truth-{key}.npz", meta=edit)
    with pytest.warns(TruthCacheWarning, match="checksum"):
        got = compute_truth(load_beam(BEAMS / "tapered.json"), **ARGS, cache_dir=tmp_path)
    _assert_equal(got, _fresh())


def test_a_forged_entry_with_a_valid_checksum_but_wrong_types_is_refused(tmp_path):
    key = _key_of(tmp_path)
    entry = tmp_path / f"truth-{key}.npz"

    def forge(a):
        a["omega_rad_s"] = np.array(["1", "2", "3"])
        return a

    def fix_checksum(m):
        with np.load(entry, allow_pickle=False) as npz:
            arrays = {k: npz[k] for k in npz.files if k != "__meta__"}
        m["checksum"] = cache.entry_checksum(m, forge(arrays))
        return m

    _rewrite(entry, arrays=forge, meta=fix_checksum)
    with pytest.warns(TruthCacheWarning, match="omega_rad_s"):
        got = compute_truth(load_beam(BEAMS / "tapered.json"), **ARGS, cache_dir=tmp_path)
    _assert_equal(got, _fresh())


def test_another_beams_entry_copied_under_this_key_is_recomputed(tmp_path):
    other = tmp_path / "other"
    compute_truth(load_beam(BEAMS / "uniform-narrow.json"), **ARGS, cache_dir=other)
    key = _key_of(tmp_path)
    shutil.copyfile(_only_entry(other), tmp_path / f"truth-{key}.npz")
    with pytest.warns(TruthCacheWarning, match="key"):
        got = compute_truth(load_beam(BEAMS / "tapered.json"), **ARGS, cache_dir=tmp_path)
    _assert_equal(got, _fresh())
    assert not np.allclose(got.omega_rad_s, _fresh("uniform-narrow.json").omega_rad_s)


def test_an_entry_of_another_beam_with_this_key_written_in_is_recomputed(tmp_path):
    # the key field edited to match (checksum recomputed): the fingerprint still differs
    other = tmp_path / "other"
    compute_truth(load_beam(BEAMS / "uniform-narrow.json"), **ARGS, cache_dir=other)
    key = _key_of(tmp_path)
    entry = tmp_path / f"truth-{key}.npz"
    shutil.copyfile(_only_entry(other), entry)

    def rekey(m):
        m["key"] = key
        with np.load(entry, allow_pickle=False) as npz:
            arrays = {k: npz[k] for k in npz.files if k != "__meta__"}
            m["checksum"] = cache.entry_checksum(m, arrays)
        return m

    _rewrite(entry, meta=rekey)
    with pytest.warns(TruthCacheWarning, match="fingerprint"):
        got = compute_truth(load_beam(BEAMS / "tapered.json"), **ARGS, cache_dir=tmp_path)
    _assert_equal(got, _fresh())


@pytest.mark.parametrize("damage", ["truncated", "empty", "garbage", "compressed", "json"])
def test_a_damaged_entry_is_recomputed(tmp_path, damage):
    key = _key_of(tmp_path)
    entry = tmp_path / f"truth-{key}.npz"
    data = entry.read_bytes()
    if damage == "truncated":
        entry.write_bytes(data[: len(data) // 2])
    elif damage == "empty":
        entry.write_bytes(b"")
    elif damage == "garbage":
        entry.write_bytes(os.urandom(4096))
    elif damage == "compressed":
        with np.load(entry, allow_pickle=False) as npz:
            arrays = dict(npz)
        with open(entry, "wb") as fh:
            np.savez_compressed(fh, **arrays)
    else:
        entry.write_text(json.dumps({"omega_rad_s": [1.0, 2.0, 3.0]}))
    with pytest.warns(TruthCacheWarning, match=f"truth-{key}.npz"):
        got = compute_truth(load_beam(BEAMS / "tapered.json"), **ARGS, cache_dir=tmp_path)
    _assert_equal(got, _fresh())


def test_a_failed_write_leaves_the_previous_entry_and_no_temporary_file(tmp_path, monkeypatch):
    beam = load_beam(BEAMS / "tapered.json")
    first = compute_truth(beam, **ARGS, cache_dir=tmp_path)
    entry = _only_entry(tmp_path)
    before = entry.read_bytes()

    def crash(fh, **arrays):
        fh.write(b"PK\x03\x04 half an entry")
        raise KeyboardInterrupt

    monkeypatch.setattr(cache.np, "savez", crash)
    with pytest.raises(KeyboardInterrupt):
        cache.store_cached(tmp_path, entry.name[6:-4], first)
    assert entry.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == [entry.name]


def test_a_folder_that_cannot_take_the_entry_still_returns_the_truth(tmp_path):
    key = _key_of(tmp_path / "a")
    (tmp_path / "b").mkdir()
    (tmp_path / "b" / f"truth-{key}.npz").mkdir()  # a folder where the entry goes
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    for where in (tmp_path / "b", blocker, blocker / "below"):
        with pytest.warns(TruthCacheWarning, match="not cached"):
            got = compute_truth(load_beam(BEAMS / "tapered.json"), **ARGS, cache_dir=where)
        _assert_equal(got, _fresh())
    assert sorted(p.name for p in (tmp_path / "b").iterdir()) == [f"truth-{key}.npz"]


def test_the_code_digest_covers_the_modules_the_truth_imports():
    names = {p.relative_to(ROOT).as_posix() for p in truth_modules()}
    # the explicit list the digest covers is the import closure found in the source: a module
    # moved, added to or dropped from the truth's imports fails here until the list follows
    assert names == set(TRUTH_MODULES)
    assert {"prbdm_pin/member/geometry.py", "prbdm_pin/errors.py", "prbdm_pin/__init__.py",
            "prbdm_pin/truth/mesh.py", "prbdm_pin/truth/beam.py"} <= names
    # the truth never imports the fitting or simulation code
    assert not any(n.startswith("prbdm_pin/fitting/") for n in names)
    assert not any(n.startswith("prbdm_pin/simulation/") for n in names)


def _copy_package(tmp_path) -> Path:
    root = tmp_path / "copy"
    shutil.copytree(ROOT / "prbdm_pin", root / "prbdm_pin",
                    ignore=shutil.ignore_patterns("__pycache__"))
    return root


def test_editing_a_dependency_changes_the_digest(tmp_path):
    root = _copy_package(tmp_path)
    base = digest_of(root)
    assert base == digest_of(ROOT)
    fitting = root / "prbdm_pin" / "fitting" / "multistart.py"
    fitting.write_text(fitting.read_text() + "\n# edited\n")
    assert digest_of(root) == base
    geometry = root / "prbdm_pin" / "member" / "geometry.py"
    geometry.write_text(geometry.read_text() + "\n# edited\n")
    assert digest_of(root) != base


_RUN = textwrap.dedent("""
    import json, sys, warnings
    warnings.simplefilter("error")
    from prbdm_pin.files.beam_file import load_beam
    from prbdm_pin.truth import compute_truth
    beam = load_beam(sys.argv[1])
    out = {}
    if sys.argv[3] == "fresh":
        out["fresh"] = compute_truth(beam, model="beam", modes=3, static=False).omega_rad_s
    out["cached"] = compute_truth(beam, model="beam", modes=3, static=False,
                                  cache_dir=sys.argv[2]).omega_rad_s
    print(json.dumps({k: [float(x) for x in v] for k, v in out.items()}))
""")


def _omega(root: Path, cache_dir: Path, fresh: bool) -> dict:
    env = {**os.environ, "PYTHONPATH": str(root)}
    p = subprocess.run([sys.executable, "-c", _RUN, str(BEAMS / "tapered.json"),
                        str(cache_dir), "fresh" if fresh else "-"],
                       capture_output=True, text=True, env=env, timeout=120, cwd=root)
    assert p.returncode == 0, p.stderr[-2000:]
    return json.loads(p.stdout)


def test_a_truth_of_edited_geometry_code_is_not_served_from_the_cache(tmp_path):
    # the case: after editing geometry.half_width_at the cache served the old omega_1
    root = _copy_package(tmp_path)
    before = _omega(root, tmp_path / "cache", fresh=False)["cached"]
    geometry = root / "prbdm_pin" / "member" / "geometry.py"
    text = geometry.read_text()
    anchor = "    def half_width_at(self, x_m: np.ndarray | float, side: str = \"right\")"
    assert anchor in text
    # 5 cm wider everywhere (a milder taper): the edited code computes other frequencies
    text = text.replace(anchor, "    def half_width_at(self, *a, **k):\n"
                        "        return 0.05 + self._half_width_at(*a, **k)\n\n"
                        + anchor.replace("half_width_at", "_half_width_at"))
    geometry.write_text(text)
    after = _omega(root, tmp_path / "cache", fresh=True)
    assert not np.allclose(after["fresh"], before, rtol=1e-3)
    np.testing.assert_array_equal(after["cached"], after["fresh"])
