"""Steps so small that a count of them overflows (a subnormal step: duration / dt = inf) or would
allocate gigabytes are refused by name before anything is allocated: found by the command-line
fuzz (`--output-dt 5e-324` raised OverflowError from deep inside)."""

from __future__ import annotations

import numpy as np
import pytest

import prbdm_pin as pp
from prbdm_pin.cli import main

BEAM = "examples/beams/uniform-narrow.json"


@pytest.mark.parametrize("kwargs, field", [
    (dict(output_dt_s=5e-324), "output_dt"),
    (dict(output_dt_s=1e-9), "output_dt"),
    (dict(dt_s=5e-324), "dt"),
    (dict(dt_s=5e-324, method="trapezoidal"), "dt"),
    (dict(dt_s=5e-324, method="gauss"), "dt"),
])
def test_simulate_refuses_step_counts_it_cannot_hold(kwargs, field):
    beam = pp.load_beam(BEAM)
    model = pp.build_model(beam, np.full(4, 0.25), np.array([5e3, 5e3, 5e3]))
    with pytest.raises(pp.BeamInputError) as exc:
        pp.simulate(model, 1.0, **kwargs)
    assert str(exc.value).startswith(f"{field} = ")


def test_pose_sweep_refuses_a_subnormal_step():
    with pytest.raises(pp.BeamInputError, match="eps = 5e-324"):
        pp.pose_sweep(3, 0.05, 5e-324)


@pytest.mark.parametrize("argv, option", [
    (["fit", BEAM, "--joints", "3", "--eps", "5e-324"], "--eps"),
    (["simulate", "FIT", "--duration", "1", "--output-dt", "5e-324"], "--output-dt"),
])
def test_cli_refuses_subnormal_steps_with_one_line(argv, option, tmp_path, capsys):
    argv = [str(tmp_path / "fit.json") if a == "FIT" else a for a in argv]
    (tmp_path / "fit.json").write_text("{}")
    rc = main([*argv, "--out", str(tmp_path / "out")])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 2 and len(err) == 1 and option in err[0], err
    assert not (tmp_path / "out").exists()
