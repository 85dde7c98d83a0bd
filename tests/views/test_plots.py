"""The figures: drawn without pyplot, and cropped as ``bbox_inches="tight"`` crops them."""

from __future__ import annotations

import subprocess
import sys

import numpy as np
from paths import ROOT

from prbdm_pin.views.plots import DPI, new_figure, save_figure

BEAM = ROOT / "examples" / "beams" / "tapered.json"


def _figure():
    # a legend outside the axes, as the planform's: the crop must take it in
    fig = new_figure((6, 4))
    ax = fig.subplots()
    x = np.linspace(0.0, 1.0, 50)
    ax.plot(x, np.sin(3 * x), "o-", label="a long legend entry")
    ax.annotate("J1", (0.5, 1.0), ha="center")
    ax.set_xlabel("x (m)")
    ax.set_title("title")
    ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0))
    ax.twinx().set_ylabel("right axis (%)")
    return fig


def test_save_figure_crops_as_savefig_tight_does(tmp_path):
    save_figure(_figure(), tmp_path / "once.png")
    _figure().savefig(tmp_path / "tight.png", format="png", dpi=DPI, bbox_inches="tight")
    assert (tmp_path / "once.png").read_bytes() == (tmp_path / "tight.png").read_bytes()


def test_the_figures_load_no_pyplot(tmp_path):
    code = (
        "import sys\n"
        "from prbdm_pin.files.beam_file import load_beam\n"
        "from prbdm_pin.views.plots import plot_planform\n"
        f"plot_planform(load_beam({str(BEAM)!r}), [0.3, 0.2, 0.1], sys.argv[1])\n"
        "assert 'matplotlib.pyplot' not in sys.modules\n"
    )
    p = subprocess.run([sys.executable, "-c", code, str(tmp_path / "p.png")],
                       capture_output=True, text=True, timeout=120)
    assert p.returncode == 0, p.stderr[-2000:]
    assert (tmp_path / "p.png").stat().st_size > 0
