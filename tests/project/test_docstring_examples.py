"""The ``Examples`` section of every public name runs as written and prints what it shows.

Each public name of ``prbdm_pin`` (its lazy map) is one case: its docstring's ``>>>`` lines are
collected by :class:`doctest.DocTestFinder` and run by :class:`doctest.DocTestRunner`, so a doc
example that drifts from the code fails here, not in a reader's terminal. The examples print
rounded numbers, shapes and booleans, and where a number has an independent value (the
Euler-Bernoulli frequency of a uniform cantilever, a round trip through a file, a field given
back) the example prints both.

A second check: the one-line summaries the API tables show (Sphinx's autosummary cuts at the
first ". ") are the whole first sentence, never stopped at an abbreviation such as "Eq." or "Sec.".
"""

from __future__ import annotations

import doctest
import inspect
import re
import tempfile

import pytest

import prbdm_pin as pp

# Public names whose docstring cannot carry a running example (each with the reason); every
# other public name must have an Examples section.
EXAMPLES_TO_DO: frozenset[str] = frozenset()

PUBLIC = tuple(name for name in pp._EXPORTS)
# examples that need a plate truth (seconds each on one core) run with the slow tests
SLOW = frozenset({
    "with_point_gains",  # a Kirchhoff plate truth, about 3 s
    "run_batch",  # starts a worker process, about 4 s
})


def _has_examples(obj) -> bool:
    doc = inspect.getdoc(obj) or ""
    return re.search(r"^Examples\n-{8}\s*$", doc, re.M) is not None


def _doctests(name: str) -> list[doctest.DocTest]:
    obj = getattr(pp, name)
    finder = doctest.DocTestFinder(recurse=False, exclude_empty=True)
    return [t for t in finder.find(obj, name, globs={}) if t.examples]


def _run(name: str) -> None:
    flags = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE
    runner = doctest.DocTestRunner(optionflags=flags)
    tests = _doctests(name)
    assert tests, f"{name}: an Examples section without a single >>> line"
    for test in tests:
        runner.run(test)
    summary = runner.summarize(verbose=False)
    assert summary.failed == 0, f"{name}: {summary.failed} of {summary.attempted} lines failed"


def test_every_public_name_has_examples_or_is_listed():
    missing = [n for n in PUBLIC if n not in EXAMPLES_TO_DO and not _has_examples(getattr(pp, n))]
    assert not missing, f"public names without an Examples section: {missing}"


def test_to_do_list_is_current():
    # a name in the list that is no longer public, or that has its section now, is dropped from it
    stale = sorted(n for n in EXAMPLES_TO_DO if n not in PUBLIC or _has_examples(getattr(pp, n)))
    assert not stale, f"EXAMPLES_TO_DO names that need no entry: {stale}"


@pytest.mark.parametrize(
    "name",
    [pytest.param(n, marks=pytest.mark.slow) if n in SLOW else n
     for n in PUBLIC if n not in EXAMPLES_TO_DO],
)
def test_examples_run(name, tmp_path, monkeypatch):
    # the examples write into tempfile.mkdtemp() folders: here, under the test's own folder
    monkeypatch.setattr(tempfile, "tempdir", str(tmp_path))
    _run(name)


def test_runner_sees_a_wrong_output():
    # the check is only as good as its runner: an example whose printed value is wrong must fail
    test = doctest.DocTestParser().get_doctest(">>> 1 + 1\n3\n", {}, "wrong", None, 0)
    runner = doctest.DocTestRunner()
    runner.run(test, out=lambda _text: None)
    assert runner.summarize(verbose=False).failed == 1


def _summary_problem(doc: str) -> str | None:
    """Why Sphinx's autosummary line of ``doc`` is not its whole first sentence, or None."""
    # Sphinx's own extractor against the first paragraph: what follows the summary must be
    # nothing, its closing period, or a new sentence, and it must not end on an abbreviation
    from docutils.frontend import get_default_settings
    from docutils.parsers.rst import Parser
    from sphinx.ext.autosummary import extract_summary

    summary = extract_summary(doc.splitlines(), get_default_settings(Parser)).rstrip(".")
    paragraph = " ".join(doc.split("\n\n")[0].split())
    if not paragraph.startswith(summary):
        return f"summary {summary!r} is not the paragraph's start"
    rest = paragraph[len(summary):]
    if not (rest in ("", ".") or re.match(r"\.?\s+[A-Z(`:]", rest)):
        return f"summary {summary!r} stops before {rest[:40]!r}"
    if re.search(r"\b(Eq|Eqs|Sec|Fig|approx|cf|resp)$", summary):
        return f"summary {summary!r} ends on an abbreviation"
    return None


@pytest.mark.parametrize("name", PUBLIC)
def test_summary_is_the_whole_first_sentence(name):
    problem = _summary_problem(inspect.getdoc(getattr(pp, name)) or "")
    assert problem is None, f"{name}: {problem}"


def test_summary_check_sees_a_cut_sentence():
    # the check is only as good as its parser: a summary Sphinx cuts at "Sec." must be caught
    assert _summary_problem("Draw a planform as in Sec. 2.1 of the paper.") is not None
    assert _summary_problem("Draw a planform as in section 2.1 of the paper.") is None
