"""CI selects every test: each marker combination is run by the default step or a -m step."""

import itertools
import re
import shlex

import pytest
from _pytest.mark.expression import Expression
from paths import ROOT


def pytest_steps(script: str) -> list[str]:
    """The -m expression of each ``python -m pytest`` line of the CI script (addopts' when none)."""
    addopts = re.search(r"addopts\s*=\s*\"(.*)\"", (ROOT / "pyproject.toml").read_text())
    default = shlex.split(addopts.group(1))
    exprs = []
    for line in script.splitlines():
        if re.match(r"\s*python -m pytest\b", line):
            words = shlex.split(line.split("||")[0])
            argv = default + words[words.index("pytest") + 1:]
            last = len(argv) - 1 - argv[::-1].index("-m")  # the last -m wins, as in pytest
            exprs.append(argv[last + 1])
    return exprs


def test_ci_runs_every_marker_combination():
    exprs = pytest_steps((ROOT / ".ci" / "run").read_text())
    assert len(exprs) >= 2
    markers = ("slow", "stress")
    for k in range(len(markers) + 1):
        for combo in itertools.combinations(markers, k):
            chosen = [e for e in exprs if Expression.compile(e).evaluate(combo.__contains__)]
            # each test runs in exactly one step: none left out, none run twice
            assert len(chosen) == 1, (combo, exprs)


@pytest.mark.parametrize("path", sorted((ROOT / "tests").rglob("test_stress_*.py")))
def test_stress_modules_carry_the_stress_marker(path):
    assert "pytest.mark.stress" in path.read_text()


def test_every_test_module_has_its_own_basename():
    """The suite imports test modules by basename (rootdir mode, no packages): two files of one
    name in different folders stop the collection of the second on a fresh checkout."""
    names = [p.name for p in (ROOT / "tests").rglob("test_*.py")]
    twice = sorted({n for n in names if names.count(n) > 1})
    assert not twice, twice
