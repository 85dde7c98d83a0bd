"""The docs' intersphinx mapping (docs/_ext/intersphinx_reach.py): a local inventory first, the
project's site when it answers, and a project neither can give left out with a note, so that a
build with -W on a closed network does not fail on Sphinx's unsuppressible fetch warning."""

from __future__ import annotations

import importlib.util

from paths import ROOT


def _module():
    spec = importlib.util.spec_from_file_location(
        "intersphinx_reach", ROOT / "docs" / "_ext" / "intersphinx_reach.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_local_inventory_then_site_then_left_out(tmp_path):
    reach = _module()
    (tmp_path / "numpy.inv").write_bytes(b"# Sphinx inventory version 2\n")
    asked = []

    def probe(url):
        asked.append(url)
        return url.startswith("https://docs.scipy.org/")

    mapping, notes = reach.intersphinx_mapping(
        {"numpy": "https://numpy.org/doc/stable/", "scipy": "https://docs.scipy.org/doc/scipy/",
         "pymoo": "https://pymoo.org/"}, local_dir=str(tmp_path), probe=probe)
    assert mapping == {"numpy": ("https://numpy.org/doc/stable/", str(tmp_path / "numpy.inv")),
                       "scipy": ("https://docs.scipy.org/doc/scipy/", None)}
    # the local copy is not fetched again; the others are probed at their objects.inv
    assert asked == ["https://docs.scipy.org/doc/scipy/objects.inv", "https://pymoo.org/objects.inv"]
    assert len(notes) == 1 and "pymoo" in notes[0] and "not linked" in notes[0]


def test_a_malformed_address_is_unreachable_not_an_error():
    assert _module().reachable("not a url") is False
