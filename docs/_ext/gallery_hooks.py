"""sphinx-gallery hooks of the docs build: each example runs in quick mode with its own
``--out`` under ``docs/_build/gallery_out/``, and its page shows the PNG figures the run
wrote there (the examples draw on ``matplotlib.figure.Figure``, not pyplot, so the default
matplotlib scraper finds none).

Named in ``sphinx_gallery_conf`` by their qualified names, so the configuration stays picklable.
"""

from __future__ import annotations

import logging
import shutil
from pathlib import Path

from sphinx_gallery.scrapers import figure_rst

OUT = Path(__file__).resolve().parents[1] / "_build" / "gallery_out"
# the examples' finite-element solves log every assembly at INFO: 260 lines of the build's log
logging.getLogger("skfem").setLevel(logging.WARNING)


def _out(src_file: str) -> Path:
    return OUT / Path(src_file).stem


def quick_argv(gallery_conf: dict, script_vars: dict) -> list[str]:
    """The arguments of every example in the build: quick mode, a fresh ``--out`` of its own."""
    out = _out(script_vars["src_file"])
    shutil.rmtree(out, ignore_errors=True)  # the page shows this run's figures, no stale ones
    return ["--quick", "--out", str(out)]


def png_scraper(block, block_vars: dict, gallery_conf: dict) -> str:
    """Copy the PNGs the example wrote under its ``--out`` into the gallery's image paths."""
    out = _out(block_vars["src_file"])
    pngs = sorted(out.rglob("*.png")) if out.is_dir() else []
    seen = block_vars.setdefault("prbdm_scraped", set())
    paths = []
    for png, image_path in zip((p for p in pngs if p not in seen),
                               block_vars["image_path_iterator"], strict=False):
        shutil.copyfile(png, image_path)
        seen.add(png)
        paths.append(image_path)
    return figure_rst(paths, gallery_conf["src_dir"])
