"""The files other tools read: the licence, the citation, the changelog, the typing marker."""

from __future__ import annotations

import re
from pathlib import Path

import pytest
import yaml

import prbdm_pin
from prbdm_pin.version import __version__

ROOT = Path(__file__).resolve().parents[2]
tomllib = pytest.importorskip("tomllib")  # Python >= 3.11; pyproject is not read on 3.10


def test_license_is_the_one_pyproject_names():
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    text = (ROOT / "LICENSE").read_text()
    assert meta["license"] == {"text": "BSD-3-Clause"}
    assert text.startswith("BSD 3-Clause License")
    # the three clauses, the third being the non-endorsement one that distinguishes it from BSD-2
    assert len(re.findall(r"^\d\. ", text, flags=re.M)) == 3
    assert "endorse or promote products" in text


def test_citation_cff_names_the_package_version_and_the_paper():
    cff = yaml.safe_load((ROOT / "CITATION.cff").read_text())
    for key in ("cff-version", "message", "title", "authors", "version", "preferred-citation"):
        assert key in cff, key
    assert cff["version"] == __version__
    assert cff["license"] == "BSD-3-Clause"
    paper = cff["preferred-citation"]
    assert paper["doi"] == "10.1115/1.4045602"  # the DOI printed in the paper's abstract
    assert paper["title"].startswith("Pseudo-Rigid-Body Dynamic Models")


def test_changelog_has_a_section_for_the_version():
    text = (ROOT / "CHANGELOG.md").read_text()
    assert f"## [{__version__}]" in text and "## [Unreleased]" in text


def test_typing_marker_ships_with_the_package():
    pkg = Path(prbdm_pin.__file__).parent
    assert (pkg / "py.typed").is_file()
    data = tomllib.loads((ROOT / "pyproject.toml").read_text())["tool"]["setuptools"]
    assert "py.typed" in data["package-data"]["prbdm_pin"]
