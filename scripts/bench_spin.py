"""Benchmark of the spinning hub: nR models of the uniform strip on a hub spinning at
Omega = omega_1 against the rotating Euler-Bernoulli cantilever.

The strip is examples/beams/uniform-narrow.json (L = 1 m, 50 mm x 10 mm steel; the chain bends
about y, EI = E b t^3 / 12). Each nR model (n = 3, 5, 8) is fitted with the package: ``prbdm fit
--truth-model beam --objective combined --stiffness joint`` (the eigen and tip-deflection
objective against the 1D beam truth, 2 starts; the layout follows the deflected shape). For
contrast, the 5R eigen-only fit (``--objective eigen``), whose layout matches the clamped
frequencies to 1e-7 but not the slope distribution the centrifugal stiffness acts on.

Each model sits on a hub at the root (radius 0, J_h = 1e3 kg m^2) held at the constant rate
Omega = omega_1 of the clamped strip (prescribed rotation, as the literature's rotating beam):
hub about z, the strip sweeps the xy-plane and bends out of it (flapping, Southwell coefficient
1.19); hub about y, it bends in its plane of rotation (lead-lag, 0.19). Per model and plane:

- the first three spinning frequencies from ``linearize(..., spin_rad_s=Omega)`` (the flexible
  block of K_e and M) against the chain's own closed form, K - Omega^2 / 2 d2M_hh/dq2 with the
  Hessian by second differences of CRBA (h = 1e-4 rad): the relative difference;
- the same frequencies against the rotating cantilever (tests/rotating_beam.py: 60 cubic
  Hermite elements with the centrifugal tension and, in plane, the -rho A Omega^2 softening;
  it reproduces Hodges & Rutkowski's table to its 5 digits): the error, %.

Second table: Epps & Chandra's rotating aluminium strip (the unswept case; dimensions and
measured frequencies from GXBeam.jl's test/examples/rotating.jl: 37.5 in from a 2.5 in hub
radius, 1 in x 0.063 in, E = 1.06e7 psi, rho = 2.51e-4 lbf s^2/in^4), flapping at 0, 500 and
750 rpm: 5R and 8R combined fits of it (the fit above, its tip load P L^2 / EI = 1) and the rotating
cantilever against the measurements.

Writes a Markdown table to results/bench_spin.md and docs/benchmarks/bench_spin.md (or the
path given with --out). BLAS is pinned to one thread before numpy is imported.

    python scripts/bench_spin.py [--out results/bench_spin.md]
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import argparse  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "scripts"))

from docs_tables import write_table  # noqa: E402
from rotating_beam import rotating_beam_frequencies  # noqa: E402

from prbdm_pin.cli import main as prbdm  # noqa: E402
from prbdm_pin.files.beam_file import load_beam  # noqa: E402
from prbdm_pin.files.fit_file import load_fit  # noqa: E402
from prbdm_pin.io.record_checks import LINK_FLOOR_FRACTION  # noqa: E402
from prbdm_pin.model.hub import Hub  # noqa: E402
from prbdm_pin.model.prbdm_model import build_model  # noqa: E402
from prbdm_pin.plant.linearize import linearize  # noqa: E402

BEAM_FILE = ROOT / "examples" / "beams" / "uniform-narrow.json"
EI = 205e9 * 0.05 * 0.01**3 / 12.0  # N m^2
RHO_A = 7850.0 * 0.05 * 0.01  # kg/m
PLANES = (("z", "out", "flapping (hub about z)"), ("y", "in", "lead-lag (hub about y)"))
H = 1e-4  # rad, the closed form's second-difference step


def fitted(n: int, objective: str, work: Path, beam_file: Path = BEAM_FILE):
    """Return the nR fit of a strip (``prbdm fit``, 2 starts, joint springs)."""
    out = work / f"{beam_file.stem}-{objective}-{n}"
    rc = prbdm(["fit", str(beam_file), "--joints", str(n), "--truth-model", "beam",
                "--objective", objective, "--stiffness", "joint", "--starts", "2",
                "--cache-dir", str(work / "cache"), "--out", str(out), "-q"])
    if rc != 0:
        raise SystemExit(f"prbdm fit failed for n = {n} ({objective})")
    return load_fit(out / "fit.json", beam=load_beam(beam_file))


def held_frequencies(K: np.ndarray, M: np.ndarray) -> np.ndarray:
    """Flexible frequencies with the hub held at its rate: the beam block of (K, M), rad/s."""
    import scipy.linalg as sla

    return np.sqrt(sla.eigh(K[1:, 1:], M[1:, 1:], eigvals_only=True))


def closed_form(model, spin: float) -> np.ndarray:
    """K - Omega^2 / 2 d2M_hh/dq2 at the straight pose, the Hessian by second differences."""
    nv = model.pin_model.nv
    E = np.eye(nv) * H
    Hs = np.zeros((nv, nv))
    for i in range(1, nv):
        for j in range(1, nv):
            m = [model.mass_matrix(s * E[i] + t * E[j])[0, 0]
                 for s, t in ((1, 1), (1, -1), (-1, 1), (-1, -1))]
            Hs[i, j] = (m[0] - m[1] - m[2] + m[3]) / (4 * H * H)
    return held_frequencies(model.stiffness_matrix() - 0.5 * spin**2 * Hs, model.mass_matrix())


def rows(fit, label: str, spin: float, refs: dict) -> list[str]:
    out = []
    for axis, plane, name in PLANES:
        beam = load_beam(BEAM_FILE)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a heavy hub: no LightHubWarning expected
            model = build_model(beam, fit.lengths_m, fit.stiffness_Nm_per_rad,
                                hub=Hub(1e3, 0.0, axis), min_fraction=LINK_FLOOR_FRACTION)
        lin = linearize(model, inputs=("hub_torque",), outputs=("hub_angle",),
                        spin_rad_s=spin, damping_ratio=0.0)
        w = held_frequencies(lin.stiffness_Nm_per_rad, lin.mass_kg_m2)[:3]
        w_rest = held_frequencies(model.stiffness_matrix(), model.mass_matrix())[:3]
        cf = closed_form(model, spin)[:3]
        self_diff = np.max(np.abs(w / cf - 1.0))
        err = 100.0 * (w / refs[plane] - 1.0)
        err0 = 100.0 * (w_rest / refs["rest"] - 1.0)
        out.append(f"| {label} | {name} | {' / '.join(f'{v:.2f}' for v in w)} | "
                   f"{self_diff:.1e} | {' / '.join(f'{v:+.2f}' for v in err)} | "
                   f"{' / '.join(f'{v:+.3f}' for v in err0)} |")
    return out


# Epps & Chandra's strip, SI units (inch, lbf)
INCH, LBF = 0.0254, 4.4482216152605
EC = {"E": 1.06e7 * LBF / INCH**2, "rho": 2.51e-4 * LBF / INCH**4, "L": 37.5 * INCH,
      "w": 1.0 * INCH, "h": 0.063 * INCH, "r": 2.5 * INCH}
EC_MEASURED_HZ = {0: (1.4, 10.3, 27.7), 500: (10.2, 25.2, 47.0), 750: (14.8, 36.1, 62.9)}


def epps_chandra(work: Path) -> list[str]:
    """5R and 8R fits of Epps & Chandra's strip and the rotating cantilever against the test."""
    from prbdm_pin.files.beam_file import beam_from_dict, save_beam

    L, w, h = EC["L"], EC["w"], EC["h"]
    EIs, rA = EC["E"] * w * h**3 / 12.0, EC["rho"] * w * h
    # the combined fit's tip load: P L^2 / (E I) = 1, as uniform-narrow.json has it
    beam = beam_from_dict({"name": "epps-chandra", "length": L, "x": [0.0, L],
                           "half_width": [w / 2, w / 2], "thickness": h,
                           "tip_force": [0.0, 0.0, -EIs / L**2],
                           "material": {"name": "aluminium", "E": EC["E"], "rho": EC["rho"],
                                        "nu": 0.325}})
    path = save_beam(beam, work / "epps-chandra.json")
    lines = ["", "## Epps & Chandra's rotating strip (unswept), flapping", "",
             "| model | rpm | measured 1/2/3 (Hz) | rotating beam (Hz) | model (Hz) | "
             "beam vs measured (%) | model vs measured (%) | model vs rotating beam (%) |",
             "|---|---|---|---|---|---|---|---|"]

    def fmt(v, d=2):
        return " / ".join(f"{x:.{d}f}" for x in v)

    for n in (5, 8):
        fit = fitted(n, "combined", work, path)
        model = build_model(beam, fit.lengths_m, fit.stiffness_Nm_per_rad,
                            hub=Hub(1e3, EC["r"], "z"), min_fraction=LINK_FLOOR_FRACTION)
        for rpm, f_exp in EC_MEASURED_HZ.items():
            spin = rpm * 2 * np.pi / 60
            lin = linearize(model, inputs=("hub_torque",), outputs=("hub_angle",),
                            spin_rad_s=spin, damping_ratio=0.0)
            f = held_frequencies(lin.stiffness_Nm_per_rad, lin.mass_kg_m2)[:3] / (2 * np.pi)
            ref = rotating_beam_frequencies(L, EIs, rA, spin, EC["r"], "out") / (2 * np.pi)
            lines.append(
                f"| {n}R combined fit | {rpm} | {fmt(f_exp, 1)} | {fmt(ref)} | {fmt(f)} | "
                f"{' / '.join(f'{x:+.1f}' for x in 100 * (ref / np.array(f_exp) - 1))} | "
                f"{' / '.join(f'{x:+.1f}' for x in 100 * (f / np.array(f_exp) - 1))} | "
                f"{' / '.join(f'{x:+.2f}' for x in 100 * (f / ref - 1))} |")
    return lines


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default=str(ROOT / "results" / "bench_spin.md"))
    args = ap.parse_args()
    rest = rotating_beam_frequencies(1.0, EI, RHO_A, 0.0)
    spin = float(rest[0])
    refs = {"rest": rest, "out": rotating_beam_frequencies(1.0, EI, RHO_A, spin, 0.0, "out"),
            "in": rotating_beam_frequencies(1.0, EI, RHO_A, spin, 0.0, "in")}
    lines = [
        "# Spinning hub: the uniform strip at Omega = omega_1",
        "",
        f"Omega = omega_1 = {spin:.4f} rad/s (the clamped strip's first frequency); the hub "
        "held at that rate, radius 0. Reference (rotating Euler-Bernoulli cantilever, 60 "
        "Hermite elements), rad/s: flapping "
        + " / ".join(f"{v:.2f}" for v in refs["out"]) + "; lead-lag "
        + " / ".join(f"{v:.2f}" for v in refs["in"]) + "; at rest "
        + " / ".join(f"{v:.2f}" for v in rest) + ".",
        "",
        "| model | plane | omega 1/2/3 (rad/s) | vs own closed form (max rel.) | "
        "error vs rotating beam 1/2/3 (%) | error at rest 1/2/3 (%) |",
        "|---|---|---|---|---|---|",
    ]
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for n in (3, 5, 8):
            lines += rows(fitted(n, "combined", work), f"{n}R combined fit", spin, refs)
        lines += rows(fitted(5, "eigen", work), "5R eigen-only fit", spin, refs)
        lines += epps_chandra(work)
    lines += ["", "Written by `python scripts/bench_spin.py`."]
    text = "\n".join(lines) + "\n"
    Path(args.out).parent.mkdir(parents=True, exist_ok=True)
    write_table(args.out, text, ap.get_default("out"), "bench_spin")
    print(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
