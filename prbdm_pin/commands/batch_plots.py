"""The figures of ``prbdm batch-report``: loss and link-fraction histograms, SCF_mean against
the geometry features."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .batch_report import BatchReport


def write_plots(records: list[dict[str, Any]], rep: BatchReport, out: Path) -> list[str]:
    """Histograms of the losses and link fractions, SCF_mean against the geometry features;
    returns the PNG paths."""
    import matplotlib
    import numpy as np

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from .batch_report import FEATURES, _values

    ok = [r for r in records if r.get("status") == "ok"]
    paths: list[str] = []
    if not ok:
        return paths

    def save(fig, name: str) -> None:
        import os

        from ..atomic import mkstemp

        path = out / name
        fd, tmp = mkstemp(out, prefix=f".{name}.", suffix=".tmp")
        os.close(fd)
        try:  # a killed report never leaves a half-written plot
            fig.savefig(tmp, format="png", dpi=110, bbox_inches="tight")
            os.replace(tmp, path)
        finally:
            if os.path.exists(tmp):
                os.unlink(tmp)
            plt.close(fig)
        paths.append(str(path))

    if rep.losses:
        fig, ax = plt.subplots(figsize=(6, 4))
        for d in rep.losses:
            v = _values(ok, d.name)
            v = v[np.isfinite(v) & (v > 0)]
            if v.size:
                bins = np.logspace(np.log10(v.min()), np.log10(v.max()) + 1e-9, 30)
                ax.hist(v, bins=bins, histtype="step", label=d.name)
        ax.set_xscale("log")
        ax.set_xlabel("loss (%)")
        ax.set_ylabel("beams")
        ax.legend()
        save(fig, "losses.png")
    if rep.gammas:
        fig, ax = plt.subplots(figsize=(6, 4))
        data = [[r["gamma"][j] for r in ok
                 if len(r.get("gamma") or []) > j and r["gamma"][j] is not None]
                for j in range(len(rep.gammas))]
        ax.boxplot(data, tick_labels=[d.name for d in rep.gammas])
        ax.set_ylabel("link length / L")
        ax.set_title("link-length fractions")
        save(fig, "gammas.png")
        fig, ax = plt.subplots(figsize=(6, 4))
        ax.hist(data[0], bins=30)
        ax.set_xlabel("gamma_1 (first joint position / L)")
        ax.set_ylabel("beams")
        save(fig, "gamma_1.png")
    if rep.scf_mean is not None:
        fig, axes = plt.subplots(1, 2, figsize=(10, 4), sharey=True)
        y = _values(ok, "scf_mean")
        for ax, f in zip(axes, FEATURES, strict=True):
            ax.scatter(_values(ok, f), y, s=8, alpha=0.6)
            ax.set_xlabel(f)
        axes[0].set_ylabel("SCF_mean")
        save(fig, "scf_mean_vs_geometry.png")
    return paths
