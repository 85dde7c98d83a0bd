"""Every script of examples/ handles a bad ``--out`` as ``prbdm`` does: one line on stderr
naming ``--out``, exit code 2, before any computation, and nothing created; ``main(out=...)``
called from Python refuses it too, naming ``out``."""

from __future__ import annotations

import importlib.util
import os
import subprocess
import sys
import time
from pathlib import Path

import pytest
from paths import ROOT

from prbdm_pin.errors import BeamInputError

SCRIPTS = sorted(p.stem for p in (ROOT / "examples").glob("*.py"))


def test_every_example_is_covered():
    assert len(SCRIPTS) == 9 and "first_fit" in SCRIPTS and "spatial_panel" in SCRIPTS


def test_no_example_names_the_docs_folder():
    # an example writes under its --out only; the example pages' figures are written by
    # `scripts/docs_example_figures.py --write-docs` (a full run used to overwrite them)
    for script in SCRIPTS:
        assert "docs" not in (ROOT / "examples" / f"{script}.py").read_text(), script


def _bad_outs(tmp: Path) -> dict[str, tuple[str, str]]:
    a_file = tmp / "a_file"
    a_file.write_text("mine")
    return {"a file": (str(a_file), "is a file, not a folder"),
            "under a file": (str(a_file / "out"), "which is a file"),
            "in /proc": ("/proc/prbdm-example-out", "lies in /proc"),
            "empty": ("", "must be a path")}


@pytest.mark.parametrize("script", SCRIPTS)
def test_a_bad_out_is_one_line_and_exit_2_before_any_work(script, tmp_path):
    env = dict(os.environ, PYTHONPATH=str(ROOT), OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1")
    for what, (out, needle) in _bad_outs(tmp_path).items():
        before = sorted(tmp_path.rglob("*"))
        t0 = time.perf_counter()
        proc = subprocess.run([sys.executable, str(ROOT / "examples" / f"{script}.py"),
                               "--quick", "--out", out], capture_output=True, text=True,
                              cwd=tmp_path, env=env, timeout=120)
        elapsed = time.perf_counter() - t0
        err = proc.stderr
        assert proc.returncode == 2, (what, proc.returncode, err[-2000:])
        assert err.count("\n") == 1 and err.startswith(f"{script}.py: error: --out = "), \
            (what, err)
        assert needle in err, (what, err)
        assert sorted(tmp_path.rglob("*")) == before, what
        # refused before any computation: a quick run takes tens of seconds, imports a few
        assert elapsed < 30.0, (what, elapsed)
    assert not Path("/proc/prbdm-example-out").exists()


def _main(script: str):
    spec = importlib.util.spec_from_file_location(f"example_out_{script}",
                                                  ROOT / "examples" / f"{script}.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module.main


@pytest.mark.parametrize("script", SCRIPTS)
def test_main_refuses_a_bad_out_by_name(script, tmp_path):
    a_file = tmp_path / "a_file"
    a_file.write_text("mine")
    with pytest.raises(BeamInputError, match=r"^out = .*which is a file"):
        _main(script)(quick=True, out=a_file / "out")
    assert [p.name for p in tmp_path.iterdir()] == ["a_file"]
