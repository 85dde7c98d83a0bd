"""The docs build's sphinx-gallery hooks (docs/_ext/gallery_hooks.py): every example runs with
``--quick`` and a fresh ``--out`` of its own, and its page gets exactly the PNGs that run wrote
there, byte for byte."""

from __future__ import annotations

import importlib.util

import pytest
from paths import ROOT

pytest.importorskip("sphinx_gallery")  # the dev extra
from sphinx_gallery.scrapers import ImagePathIterator  # noqa: E402


def _hooks(monkeypatch, out):
    spec = importlib.util.spec_from_file_location("gallery_hooks",
                                                  ROOT / "docs" / "_ext" / "gallery_hooks.py")
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    monkeypatch.setattr(module, "OUT", out)
    return module


def test_each_example_gets_quick_mode_and_a_fresh_out(tmp_path, monkeypatch):
    hooks = _hooks(monkeypatch, tmp_path / "gallery_out")
    stale = tmp_path / "gallery_out" / "first_fit" / "old.png"
    stale.parent.mkdir(parents=True)
    stale.write_bytes(b"stale")
    argv = hooks.quick_argv({}, {"src_file": str(ROOT / "examples" / "first_fit.py")})
    assert argv == ["--quick", "--out", str(tmp_path / "gallery_out" / "first_fit")]
    assert not stale.parent.exists()  # the page shows this run's figures only


def test_the_page_gets_the_pngs_the_run_wrote(tmp_path, monkeypatch):
    hooks = _hooks(monkeypatch, tmp_path / "gallery_out")
    out = tmp_path / "gallery_out" / "pareto_run"
    (out / "sub").mkdir(parents=True)
    written = {out / "pareto_run.png": b"\x89PNG first", out / "sub" / "more.png": b"\x89PNG two"}
    for path, data in written.items():
        path.write_bytes(data)
    (out / "pareto.csv").write_text("not a figure")
    images = tmp_path / "images"
    images.mkdir()
    block_vars = {"src_file": str(ROOT / "examples" / "pareto_run.py"),
                  "image_path_iterator": ImagePathIterator(str(images / "sphx_{0:03}.png"))}
    rst = hooks.png_scraper(None, block_vars, {"src_dir": str(tmp_path)})
    copied = sorted(images.iterdir())
    assert [p.read_bytes() for p in copied] == [written[p] for p in sorted(written)]
    assert all(p.name in rst for p in copied)
    # a second block of the same script adds no figure twice
    assert hooks.png_scraper(None, block_vars, {"src_dir": str(tmp_path)}) == ""
    assert len(list(images.iterdir())) == 2
