"""Helpers shared by the probe case modules."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BEAMS = ROOT / "examples" / "beams"


def run_cli(*args: str, timeout: float = 300, **kw) -> subprocess.CompletedProcess:
    """``python -m prbdm_pin.cli ARGS`` in a subprocess, capturing text output."""
    return subprocess.run([sys.executable, "-m", "prbdm_pin.cli", *map(str, args)],
                          capture_output=True, text=True, timeout=timeout, cwd=kw.pop("cwd", ROOT),
                          **kw)


def expect_exit2(proc: subprocess.CompletedProcess, field: str | None = None) -> None:
    """Assert a one-line error, exit 2, no traceback, and (if given) ``field`` named."""
    err = proc.stderr.strip()
    assert proc.returncode == 2, f"exit {proc.returncode}, stderr: {err[-300:]!r}"
    assert "Traceback" not in err, f"traceback: {err[-300:]!r}"
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1, f"{len(lines)} lines on stderr: {err[-300:]!r}"
    if field is not None:
        assert field in err, f"{field!r} not named in {err!r}"
