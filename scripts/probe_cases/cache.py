"""Probe cases of the truth side: the truth cache, truth.json files and unbounded truth work."""

from __future__ import annotations

import contextlib
import io
import json
import os
import pickle
import shutil
import subprocess
import sys
import tempfile
import textwrap
import time
import warnings
import zipfile
from pathlib import Path

import numpy as np
from probe_cases._common import BEAMS, ROOT, expect_exit2

ARGS = {"model": "beam", "modes": 3, "static": False}


def run_cli(*args, timeout: float = 300, env=None) -> subprocess.CompletedProcess:
    """``python -m prbdm_pin ARGS`` (the package's entry point) in a subprocess."""
    return subprocess.run([sys.executable, "-m", "prbdm_pin", *map(str, args)],
                          capture_output=True, text=True, timeout=timeout, cwd=ROOT, env=env)
_FRESH: dict[str, object] = {}


def _scratch() -> Path:
    return Path(tempfile.mkdtemp(prefix="probe-cache-"))


def _beam(name="tapered.json"):
    from prbdm_pin.files.beam_file import load_beam

    return load_beam(BEAMS / name)


def _fresh(name="tapered.json"):
    from prbdm_pin.truth import compute_truth

    if name not in _FRESH:
        _FRESH[name] = compute_truth(_beam(name), **ARGS)
    return _FRESH[name]


def _same(a, b, what="result"):
    import dataclasses

    if dataclasses.is_dataclass(a):
        assert type(a) is type(b), f"{what}: {type(a).__name__} vs {type(b).__name__}"
        for f in dataclasses.fields(a):
            if f.name != "timings":
                _same(getattr(a, f.name), getattr(b, f.name), f"{what}.{f.name}")
    elif isinstance(a, np.ndarray):
        assert a.shape == b.shape and np.array_equal(a, b), f"{what} differs from a fresh truth"
    else:
        assert a == b, f"{what}: {a!r} vs fresh {b!r}"


def _served(d: Path, name="tapered.json", expect_warning=True):
    """compute_truth through cache ``d``: the result, checked against a fresh computation."""
    from prbdm_pin.truth import compute_truth
    from prbdm_pin.truth.cache import TruthCacheWarning

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        got = compute_truth(_beam(name), **ARGS, cache_dir=d)
    mine = [w for w in caught if issubclass(w.category, TruthCacheWarning)]
    if expect_warning:
        assert mine, "a refused entry gave no TruthCacheWarning"
    _same(got, _fresh(name))
    return got


def _entry(d: Path, name="tapered.json") -> Path:
    from prbdm_pin.truth import compute_truth

    compute_truth(_beam(name), **ARGS, cache_dir=d)
    found = list(d.glob("truth-*.npz"))
    assert len(found) == 1, f"{len(found)} entries in {d}"
    return found[0]


def _rewrite(entry: Path, arrays=None, meta=None, fix_checksum=False):
    from prbdm_pin.truth import cache

    with np.load(entry, allow_pickle=False) as npz:
        old = dict(npz)
    m = json.loads(old.pop("__meta__").tobytes())
    new = arrays(old) if arrays else old
    m = meta(m) if meta else m
    if fix_checksum:
        m["checksum"] = cache.entry_checksum(m, new)
    blob = np.frombuffer(json.dumps(m).encode(), dtype=np.uint8)
    with open(entry, "wb") as fh:
        np.savez(fh, __meta__=blob, **new)


class _Marker:
    def __init__(self, path):
        self.path = str(path)

    def __reduce__(self):
        return (Path.touch, (Path(self.path),))


# ---------------------------------------------------------------------------------------- 1 cache
def _pickle_case(where: str):
    def fn():
        d = _scratch()
        entry = _entry(d)
        marker = d / "executed"
        evil = pickle.dumps(_Marker(marker))
        if where == "pkl":
            entry.with_suffix(".pkl").write_bytes(evil)
            _served(d, expect_warning=False)
        elif where == "npz":
            entry.write_bytes(evil)
            _served(d)
        else:  # an object array inside a real NPZ
            with np.load(entry, allow_pickle=False) as npz:
                a = dict(npz)
            a["omega_rad_s"] = np.array([_Marker(marker)], dtype=object)
            with open(entry, "wb") as fh:
                np.savez(fh, **a)
            _served(d)
        assert not marker.exists(), "the pickle ran"
    return fn


def _scaled(factor):
    def fn():
        d = _scratch()

        def edit(a):
            a["omega_rad_s"] = a["omega_rad_s"] * factor
            a["modal.omega_rad_s"] = a["modal.omega_rad_s"] * factor
            return a

        _rewrite(_entry(d), arrays=edit)
        _served(d)
    return fn


def _meta_edit(path, value):
    def fn():
        d = _scratch()

        def edit(m):
            node = m
            for k in path[:-1]:
                node = node[k]
            node[path[-1]] = value
            return m

        _rewrite(_entry(d), meta=edit)
        _served(d)
    return fn


def _forged(kind):
    def fn():
        d = _scratch()
        entry = _entry(d)
        if kind == "strings":
            _rewrite(entry, arrays=lambda a: {**a, "omega_rad_s": np.array(["1", "2", "3"])},
                     fix_checksum=True)
        elif kind == "negative":
            def neg(a):
                a["omega_rad_s"] = -a["omega_rad_s"]
                a["modal.omega_rad_s"] = -a["modal.omega_rad_s"]
                return a
            _rewrite(entry, arrays=neg, fix_checksum=True)
        elif kind == "shape":
            _rewrite(entry, arrays=lambda a: {**a, "mac_beam": a["mac_beam"][:1]},
                     fix_checksum=True)
        elif kind == "missing array":
            _rewrite(entry, arrays=lambda a: {k: v for k, v in a.items() if k != "omega_rad_s"},
                     fix_checksum=True)
        elif kind == "extra field":
            def extra(m):
                m["result"]["bogus"] = 1
                return m
            _rewrite(entry, meta=extra, fix_checksum=True)
        elif kind == "format":
            def fmt(m):
                m["format"] = "something else 9"
                return m
            _rewrite(entry, meta=fmt, fix_checksum=True)
        _served(d)
    return fn


def _other_beam(name, rekey):
    def fn():
        d = _scratch()
        other = _entry(d / "other", name)
        entry = _entry(d)
        key = entry.name[len("truth-"):-len(".npz")]
        shutil.copyfile(other, entry)
        if rekey:
            def k(m):
                m["key"] = key
                return m
            _rewrite(entry, meta=k, fix_checksum=True)
        _served(d)
    return fn


def _damaged(kind):
    def fn():
        d = _scratch()
        entry = _entry(d)
        data = entry.read_bytes()
        if kind.startswith("truncated"):
            frac = float(kind.split()[1]) / 100
            entry.write_bytes(data[: int(len(data) * frac)])
        elif kind == "one byte short":
            entry.write_bytes(data[:-1])
        elif kind == "one byte flipped":
            b = bytearray(data)
            b[len(b) // 2] ^= 0x01
            entry.write_bytes(bytes(b))
        elif kind == "garbage":
            entry.write_bytes(os.urandom(len(data)))
        elif kind == "json text":
            entry.write_text(json.dumps({"omega_rad_s": [1.0, 2.0, 3.0]}))
        elif kind == "compressed":
            with np.load(entry, allow_pickle=False) as npz:
                a = dict(npz)
            with open(entry, "wb") as fh:
                np.savez_compressed(fh, **a)
        elif kind == "zip bomb":
            with zipfile.ZipFile(entry, "w", zipfile.ZIP_DEFLATED) as zf:
                zf.writestr("omega_rad_s.npy", b"\0" * 50_000_000)
        elif kind == "extra member":
            with zipfile.ZipFile(entry, "a", zipfile.ZIP_STORED) as zf:
                zf.writestr("run.py", b"print('hello')")
        elif kind == "metadata not json":
            with np.load(entry, allow_pickle=False) as npz:
                a = dict(npz)
            a["__meta__"] = np.frombuffer(b"\xff\xfe not json", dtype=np.uint8)
            with open(entry, "wb") as fh:
                np.savez(fh, **a)
        _served(d)
    return fn


def _symlink_case(target):
    def fn():
        d = _scratch()
        entry = _entry(d)
        entry.unlink()
        entry.symlink_to(target)
        t0 = time.perf_counter()
        from prbdm_pin.truth import compute_truth

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            got = compute_truth(_beam(), **ARGS, cache_dir=d)
        _same(got, _fresh())
        assert time.perf_counter() - t0 < 30, "took over 30 s"
    return fn


def _unwritable(kind):
    def fn():
        d = _scratch()
        if kind == "entry is a folder":
            entry = _entry(d)
            entry.unlink()
            entry.mkdir()
            where = d
        elif kind == "cache is a file":
            where = d / "file"
            where.write_text("x")
        else:
            (d / "file").write_text("x")
            where = d / "file" / "below"
        _served(where)
    return fn


_DIGEST_RUN = textwrap.dedent("""
    import json, sys, warnings
    warnings.simplefilter("error")
    from prbdm_pin.files.beam_file import load_beam
    from prbdm_pin.truth import compute_truth
    beam = load_beam(sys.argv[1])
    a = compute_truth(beam, model="beam", modes=3, static=False, cache_dir=sys.argv[2])
    b = compute_truth(beam, model="beam", modes=3, static=False)
    print(json.dumps([list(map(float, a.omega_rad_s)), list(map(float, b.omega_rad_s))]))
""")


def _edited_dependency():
    d = _scratch()
    root = d / "copy"
    shutil.copytree(ROOT / "prbdm_pin", root / "prbdm_pin",
                    ignore=shutil.ignore_patterns("__pycache__"))

    def run():
        p = subprocess.run([sys.executable, "-c", _DIGEST_RUN, str(BEAMS / "tapered.json"),
                            str(d / "cache")], capture_output=True, text=True, cwd=root,
                           env={**os.environ, "PYTHONPATH": str(root)}, timeout=120)
        assert p.returncode == 0, p.stderr[-300:]
        return json.loads(p.stdout)

    before = run()
    geo = root / "prbdm_pin" / "member" / "geometry.py"
    anchor = '    def half_width_at(self, x_m: np.ndarray | float, side: str = "right")'
    text = geo.read_text()
    assert anchor in text, "geometry.half_width_at not found"
    geo.write_text(text.replace(anchor, "    def half_width_at(self, *a, **k):\n"
                                "        return 0.05 + self._hw(*a, **k)\n\n"
                                + anchor.replace("half_width_at", "_hw")))
    cached, fresh = run()
    assert not np.allclose(fresh, before[1], rtol=1e-3), "the edit changed nothing"
    assert cached == fresh, f"cache served omega_1 = {cached[0]:.4g}, fresh {fresh[0]:.4g}"


def _location(where: str):
    """A CLI run with the cache at ``where``: entries are NPZ, a planted pickle never runs."""
    def fn():
        d = _scratch()
        env = {k: v for k, v in os.environ.items() if k != "PRBDM_CACHE"}
        fit = ["fit", BEAMS / "tapered.json", "--joints", "1", "--truth-model", "beam",
               "--starts", "1", "--seed", "0", "-q"]
        if where == "--cache-dir":
            cache, extra = d / "c", ["--cache-dir", d / "c"]
        elif where == "$PRBDM_CACHE":
            cache, extra = d / "c", []
            env["PRBDM_CACHE"] = str(cache)
        elif where == "~/.cache/prbdm_pin":
            cache, extra = d / "home" / ".cache" / "prbdm_pin", []
            env["HOME"] = str(d / "home")
        else:
            cache, extra = d / "b1" / "truth-cache", []
            fit = ["batch", "--beams", "1", "--joints", "1", "--truth-model", "beam",
                   "--starts", "1", "--workers", "1", "-q"]
        marker = d / "executed"
        for run in ("b1", "b2"):
            if where == "OUT/truth-cache":
                cache = d / run / "truth-cache"
                if run == "b2":  # the tampered cache of the first run, under the second OUT
                    shutil.copytree(d / "b1" / "truth-cache", cache)
            p = run_cli(*fit, *extra, "--out", d / run, env=env)
            assert p.returncode == 0, f"exit {p.returncode}: {p.stderr[-300:]}"
            entries = list(cache.glob("truth-*.npz"))
            assert entries and all(zipfile.is_zipfile(e) for e in entries), \
                f"entries {[e.name for e in entries]} are not NPZ files"
            if run == "b1":
                assert not list(cache.glob("*.pkl")), "a pickle entry was written"
                for e in entries:
                    e.write_bytes(pickle.dumps(_Marker(marker)))
                    e.with_suffix(".pkl").write_bytes(pickle.dumps(_Marker(marker)))
        assert not marker.exists(), "a pickle in the cache ran"
        if where != "OUT/truth-cache":
            a, b = (json.loads((d / r / "fit.json").read_text())["omega_truth_rad_s"]
                    for r in ("b1", "b2"))
            assert a == b, "the tampered cache changed the truth"
    return fn


# --------------------------------------------------------------------- 3 model and result files
_GOOD = {"omega_rad_s": [10.0, 60.0, 170.0], "tip_position_m": [0.9, 0.0, -0.3],
         "tip_displacement_m": [-0.1, 0.0, -0.3], "mac": [1.0, 0.99, 0.98]}


def _truth_files():
    def w(**ch):
        d = dict(_GOOD)
        for k, v in ch.items():
            if v is ...:
                d.pop(k)
            else:
                d[k] = v
        return json.dumps(d)

    cases = [
        ("top-level list", "[1, 2, 3]", "JSON object"),
        ("omega missing", w(omega_rad_s=...), "omega_rad_s"),
        ("omega empty", w(omega_rad_s=[]), "omega_rad_s"),
        ("omega descending", w(omega_rad_s=[60.0, 10.0, 170.0]), "omega_rad_s[1]"),
        ("omega NaN literal", '{"omega_rad_s": [10.0, NaN]}', "NaN"),
        ("omega Infinity", '{"omega_rad_s": [10.0, Infinity]}', "Infinity"),
        ("omega 1e999", '{"omega_rad_s": [10.0, 1e999]}', "omega_rad_s[1]"),
        ("truncated", '{"omega_rad_s": [10.0, 60', "not valid JSON"),
        ("not UTF-8", b'{"omega_rad_s": [10.0], "beam": "\xff"}', "UTF-8"),
        ("deep nesting", "[" * 100_000, "nested"),
        ("400-digit integer", '{"omega_rad_s": [1' + "0" * 400 + "]}", "digits"),
        ("unknown key (typo)", w(tip_positon_m=[1, 0, 0]), "tip_positon_m"),
        ("fingerprint not hex", w(beam_fingerprint="xyz"), "beam_fingerprint"),
        ("fingerprint number", w(beam_fingerprint=7), "beam_fingerprint"),
        ("mac above 1", w(mac=[1.0, 1.5, 1.0]), "mac[1]"),
        ("mac length", w(mac=[1.0]), "mac"),
        ("mode_index length", w(mode_index=[0]), "mode_index"),
        ("mode_index out of range", w(mode_index=[0, 1, 5], all_omega_rad_s=[10.0, 60.0, 170.0]),
         "mode_index[2]"),
        ("labels length", w(labels=["bending"]), "labels"),
        ("name with NUL", w(beam="a\u0000b"), "beam"),
        ("empty file", "", "not valid JSON"),
    ]
    bad_values = {"NaN-like string": "nan", "object": {"a": 1}, "nested list": [[1, 2, 3]],
                  "bool": True, "negative": -1.0}
    for field in ("omega_rad_s", "tip_position_m", "tip_displacement_m", "mac",
                  "static_theory_gap_pct", "mpf_z_fraction", "error_estimate_pct"):
        for label, v in bad_values.items():
            if field == "static_theory_gap_pct" and label == "negative":
                continue  # a negative gap is valid
            if field in ("tip_position_m", "tip_displacement_m", "error_estimate_pct") \
                    and label == "negative":
                continue
            cases.append((f"{field} {label}", w(**{field: v}), field))
    return cases


def _truth_file_case(text, needle):
    def fn():
        from prbdm_pin.cli import main

        d = _scratch()
        path = d / "truth.json"
        (path.write_bytes if isinstance(text, bytes) else path.write_text)(text)
        err = io.StringIO()
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
            rc = main(["fit", str(BEAMS / "uniform-narrow.json"), "--joints", "2", "--truth",
                       str(path), "--out", str(d / "fit"), "-q"])
        msg = err.getvalue().strip()
        assert rc == 2, f"exit {rc}: {msg[-300:]!r}"
        assert len(msg.splitlines()) == 1 and "Traceback" not in msg, msg[-300:]
        assert needle in msg, f"{needle!r} not named in {msg!r}"
        assert not (d / "fit" / "fit.json").exists()
    return fn


def _truth_json_round_trip():
    d = _scratch()
    p = run_cli("truth", BEAMS / "tapered.json", "--model", "beam", "--modes", "3",
                "--out", d / "t", "-q")
    assert p.returncode == 0, p.stderr[-300:]
    p = run_cli("fit", BEAMS / "tapered.json", "--joints", "2", "--truth", d / "t" / "truth.json",
                "--starts", "2", "--out", d / "f", "-q")
    assert p.returncode == 0, p.stderr[-300:]
    a = json.loads((d / "t" / "truth.json").read_text())["omega_rad_s"]
    b = json.loads((d / "f" / "fit.json").read_text())["omega_truth_rad_s"]
    assert b == a[: len(b)], "fit.json's truth differs from truth.json's"


# ------------------------------------------------------------------------------ 4 unbounded work
def _beam_file(d: Path, x, w, t=0.01, force=(0.0, 0.0, -100.0)) -> Path:
    path = d / "beam.json"
    path.write_text(json.dumps({"name": "probe", "x": list(x), "half_width": list(w),
                                "thickness": t, "tip_force": list(force)}))
    return path


_SHORT = ([0.0, 0.5, 0.5 + 1e-9, 1.0], [0.1, 0.1, 0.12, 0.1])


def _refused(model, x, w, t=0.01):
    def fn():
        d = _scratch()
        t0 = time.perf_counter()
        p = run_cli("truth", _beam_file(d, x, w, t), "--model", model, "--no-static",
                    "--out", d / "t", timeout=120)
        wall = time.perf_counter() - t0
        expect_exit2(p, "max_mesh_dofs")
        assert wall < 30, f"refused after {wall:.0f} s"
    return fn


def _implausible(model, x, w, t, field):
    """A size below the plausibility floor (1e-5 m) is refused by the beam, before any mesh."""
    def fn():
        d = _scratch()
        p = run_cli("truth", _beam_file(d, x, w, t), "--model", model, "--no-static",
                    "--out", d / "t", timeout=120)
        expect_exit2(p, field)
        assert "plausible range" in p.stderr, p.stderr[-300:]
    return fn


def _one_d(x, w, static, t=0.01):
    def fn():
        d = _scratch()
        args = [] if static else ["--no-static"]
        p = run_cli("truth", _beam_file(d, x, w, t), "--model", "beam", *args, "--out", d / "t",
                    "-q", timeout=120)
        err = p.stderr.strip()
        assert "Traceback" not in err and "LinAlgError" not in err, err[-300:]
        if p.returncode == 1:  # a SolveError, one line, saying why
            assert len(err.splitlines()) == 1 and ("near-step" in err or "near-hinge" in err), \
                err[-300:]
            return
        assert p.returncode == 0, f"exit {p.returncode}: {err[-300:]}"
        omega = json.loads((d / "t" / "truth.json").read_text())["omega_rad_s"]
        assert all(np.isfinite(omega)) and all(v > 0 for v in omega), omega
    return fn


def _one_d_limit():
    from prbdm_pin.member.geometry import Beam
    from prbdm_pin.truth import compute_truth

    step = Beam(np.array([0.0, 0.5, 0.5, 1.0]), np.array([0.1, 0.1, 0.12, 0.1]), 0.01)
    ref = compute_truth(step, **ARGS).omega_rad_s
    for dx in (1e-7, 1e-9, 1e-12):
        b = Beam(np.array([0.0, 0.5, 0.5 + dx, 1.0]), np.array([0.1, 0.1, 0.12, 0.1]), 0.01)
        got = compute_truth(b, **ARGS).omega_rad_s
        assert np.allclose(got, ref, rtol=1e-6), f"interval {dx}: {got} vs step {ref}"


def _many_vertices(n, static):
    def fn():
        from prbdm_pin.member.geometry import Beam
        from prbdm_pin.truth import compute_truth

        x = np.linspace(0.0, 1.0, n)
        beam = Beam(x, np.full(n, 0.05), 0.01, tip_force_N=np.array([0.0, 0.0, -100.0]))
        strip = Beam(np.array([0.0, 1.0]), np.full(2, 0.05), 0.01,
                     tip_force_N=np.array([0.0, 0.0, -100.0]))
        t0 = time.perf_counter()
        got = compute_truth(beam, model="beam", modes=5, static=static)
        wall = time.perf_counter() - t0
        ref = compute_truth(strip, model="beam", modes=5, static=static)
        assert np.allclose(got.omega_rad_s, ref.omega_rad_s, rtol=1e-5), "frequencies differ"
        if static:
            assert np.allclose(got.tip_position_m, ref.tip_position_m, rtol=1e-6)
        assert wall < 90, f"{wall:.0f} s"
    return fn


def cases():
    out = [("1 cache", f"pickle as {w}", _pickle_case(w)) for w in ("pkl", "npz", "object array")]
    out += [("1 cache", f"omega x {f}", _scaled(f)) for f in (1.37, 0.5, 1 + 1e-12)]
    for path, value in ((("result", "warnings"), ["fine"]), (("result", "modal", "dofs"), 7),
                        (("result", "static_theory_gap_pct"), 1.0),
                        (("result", "selection"), "shape"), (("result", "version"), "9"),
                        (("beam_fingerprint",), "0" * 64), (("key",), "0" * 64)):
        out.append(("1 cache", f"metadata {'.'.join(path)} edited", _meta_edit(path, value)))
    out += [("1 cache", f"forged ({k}, checksum recomputed)", _forged(k))
            for k in ("strings", "negative", "shape", "missing array", "extra field", "format")]
    for name in ("uniform-narrow.json", "tapered-linear.json", "square-plate.json",
                 "stepped-narrow.json"):
        out.append(("1 cache", f"{name} entry copied", _other_beam(name, False)))
        out.append(("1 cache", f"{name} entry copied, key rewritten", _other_beam(name, True)))
    out += [("1 cache", f"entry {k}", _damaged(k)) for k in (
        "truncated 0", "truncated 10", "truncated 50", "truncated 90", "truncated 99",
        "one byte short", "one byte flipped", "garbage", "json text", "compressed",
        "zip bomb", "extra member", "metadata not json")]
    out += [("1 cache", f"entry a symlink to {t}", _symlink_case(t)) for t in ("/dev/zero",
                                                                               "/nonexistent")]
    out += [("1 cache", k, _unwritable(k)) for k in ("entry is a folder", "cache is a file",
                                                    "cache under a file")]
    out.append(("1 cache", "edited geometry.half_width_at", _edited_dependency))
    out += [("1 cache", f"location {w}", _location(w)) for w in (
        "--cache-dir", "$PRBDM_CACHE", "~/.cache/prbdm_pin", "OUT/truth-cache")]
    out += [("3 model and result files", f"truth.json {n}", _truth_file_case(t, f))
            for n, t, f in _truth_files()]
    out.append(("3 model and result files", "truth.json of prbdm truth read back",
                _truth_json_round_trip))
    x, w = _SHORT
    out += [
        ("4 unbounded work", "plate, 1e-9 m interval", _refused("plate", x, w)),
        ("4 unbounded work", "plate, 1e-7 m interval", _refused("plate", [0.0, 0.5, 0.5 + 1e-7,
                                                                          1.0], w)),
        ("4 unbounded work", "plate-morley, 1e-9 m interval", _refused("plate-morley", x, w)),
        ("4 unbounded work", "plate, 1e-9 m half-width",
         _implausible("plate", [0.0, 0.5, 1.0], [0.1, 1e-9, 0.1], 0.01, "half_width[1]")),
        ("4 unbounded work", "plate, 1e-9 m tip",
         _implausible("plate", [0.0, 1.0], [0.1, 1e-9], 0.01, "half_width[1]")),
        ("4 unbounded work", "solid, 1e-6 m thickness",
         _implausible("solid", [0.0, 1.0], [0.1, 0.1], 1e-6, "thickness")),
        ("4 unbounded work", "1D beam, 1e-9 m interval, no static", _one_d(x, w, False)),
        ("4 unbounded work", "1D beam, 1e-9 m interval, static", _one_d(x, w, True)),
        ("4 unbounded work", "1D beam, 1e-9 m half-width",
         _implausible("beam", [0.0, 0.5, 1.0], [0.1, 1e-9, 0.1], 0.01, "half_width[1]")),
        ("4 unbounded work", "1D beam, 1e-9 m tip width",
         _implausible("beam", [0.0, 1.0], [0.1, 1e-9], 0.01, "half_width[1]")),
        ("4 unbounded work", "1D beam, vanishing interval = width step", _one_d_limit),
        ("4 unbounded work", "1D beam, 5k vertices with statics", _many_vertices(5_001, True)),
        ("4 unbounded work", "1D beam, 200k vertices", _many_vertices(200_001, False)),
    ]
    return out
