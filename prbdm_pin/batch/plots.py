"""The figures of a batch report.

Loss and link-fraction histograms, and SCF_mean against the geometry features.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from .report import FEATURES, BatchReport, column_values


def write_plots(records: list[dict[str, Any]], rep: BatchReport, out: Path) -> list[str]:
    """Plot the loss and link-fraction histograms and SCF_mean against the geometry features.

    Returns the PNG paths.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ok = [r for r in records if r.get("status") == "ok"]
    paths: list[str] = []
    if not ok:
        return paths

    def save(fig, name: str) -> None:
        from ..io.atomic import atomic_path

        path = out / name
        try:  # a killed report never leaves a half-written plot
            with atomic_path(path) as tmp:
                fig.savefig(tmp, format="png", dpi=110, bbox_inches="tight")
        finally:
            plt.close(fig)
        paths.append(str(path))

    if rep.losses:
        fig, ax = plt.subplots(figsize=(6, 4))
        for d in rep.losses:
            v = column_values(ok, d.name)
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
        y = column_values(ok, "scf_mean")
        for ax, f in zip(axes, FEATURES, strict=True):
            ax.scatter(column_values(ok, f), y, s=8, alpha=0.6)
            ax.set_xlabel(f)
        axes[0].set_ylabel("SCF_mean")
        save(fig, "scf_mean_vs_geometry.png")
    return paths
