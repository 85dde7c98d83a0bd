"""The public API resolves, and `python -m prbdm_pin` is the `prbdm` command."""

import subprocess
import sys

import prbdm_pin


def test_every_public_name_resolves():
    for name in prbdm_pin.__all__:
        assert getattr(prbdm_pin, name) is not None, name


def test_module_entry_point_prints_help():
    out = subprocess.run([sys.executable, "-m", "prbdm_pin", "--help"], capture_output=True,
                         text=True, check=True).stdout
    for cmd in ("truth", "fit", "pareto", "simulate", "export", "batch", "batch-report"):
        assert cmd in out
