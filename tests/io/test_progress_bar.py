"""Progress bars draw on a terminal and stay silent in a log file, a pipe, or with --quiet."""

from __future__ import annotations

import io
import os
import subprocess
import sys

from prbdm_pin.io.progress import progress_bar


class _Terminal(io.StringIO):
    def isatty(self) -> bool:
        return True


def _run(stream, enabled=True) -> str:
    bar = progress_bar(3, enabled=enabled, desc="work", unit="step", file=stream, mininterval=0)
    for _ in range(3):
        bar.update(1)
    bar.close()
    return stream.getvalue()


def test_bar_draws_on_a_terminal():
    text = _run(_Terminal())
    assert "work" in text and "3/3" in text


def test_bar_is_silent_off_a_terminal_and_when_disabled():
    assert _run(io.StringIO()) == ""          # a log file or a pipe
    assert _run(_Terminal(), enabled=False) == ""


def test_a_fit_from_the_command_line_writes_no_bar_into_its_log(tmp_path):
    # stderr is a file here, as under a job scheduler: no carriage-return redraws in it
    beam = os.path.join(os.path.dirname(__file__), "..", "..", "examples", "beams",
                        "uniform-narrow.json")
    log = tmp_path / "log.txt"
    with open(log, "w") as fh:
        rc = subprocess.run([sys.executable, "-m", "prbdm_pin", "fit", beam, "--joints", "2",
                             "--truth-model", "beam", "--objective", "eigen", "--stiffness",
                             "joint", "--starts", "2", "--out", str(tmp_path / "fit")],
                            stdout=subprocess.DEVNULL, stderr=fh, timeout=300).returncode
    assert rc == 0
    text = log.read_text()
    assert "\r" not in text and "fit starts" not in text
