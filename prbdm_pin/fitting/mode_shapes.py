"""Mode pairing by shape: the truth's and the chain's modes compared along the span (MAC).

A spatial fit matches the chain's modes about each axis to the truth's modes of the kinds that
axis represents, in frequency order (a smooth residual for the optimiser). Once fitted, the
pairing is checked by shape: each truth mode's deflection w(x) (bending-type modes, axis y) or
twist theta(x) (torsion modes, axis x) at stations along the span is compared with every mode
of the chain about that axis by the modal assurance criterion

    MAC(a, b) = (a . b)^2 / ((a . a) (b . b)),

and the pairs are those of the largest total of the clear MACs (at least ``MAC_WARN``; the
assignment problem, solved exactly by ``scipy.optimize.linear_sum_assignment``), the rank
breaking ties. A model mode that clearly looks like another truth mode than the one of its
rank is then reported against the truth mode it represents, never silently matched by order;
a truth mode that resembles no chain mode keeps its rank and its low MAC is named.

The truth's shapes come from its nodal z displacements: in each of ``STATIONS`` slices of the
span, uz = w + theta y + c (x - x_mean) by least squares over the slice's nodes (the slope c
takes the slice's own bending out of w; a slice whose nodes share one x has none). The
chain's, at the straight pose, from its joint coordinates: w(x) = -sum over joints at s_j < x
of (x - s_j) q_y,j (a rotation about +y turns x towards -z) and theta(x) = sum over joints at
s_j < x of q_x,j. In-plane modes (axis z) have no z displacement: they keep the order pairing
(the chain's in-plane block has no other kind).

A pair off its rank means the chain cannot have both: its modes about an axis ascend in
frequency, so when the truth's k-th mode of a kind looks like the chain's (k+1)-th, matching
the frequencies by rank matched the wrong shapes (on the reference panel's 5-joint ``xy`` fit,
the truth's third torsion mode is a twist local to the narrow tip, which the chain represents
as its fourth).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.optimize

from ..errors import BeamInputError
from ..options.validate import real_vector

__all__ = ["STATIONS", "ModeShapes", "truth_mode_shapes", "chain_shapes", "mac_matrix",
           "pair_by_mac", "pair_modes", "pairing_notes", "MAC_WARN"]

# slices of the span: enough to tell a mode's nodes apart up to the tenth mode of a kind
STATIONS = 24
# a pair whose shapes agree less than this is named in the result's warnings, and only a
# resemblance at least this clear moves a pair off its rank
MAC_WARN = 0.5
# the rank's weight in the pairing: breaks ties only (MACs that move pairs differ by more)
RANK_TIE = 1e-3


@dataclass(frozen=True, eq=False)
class ModeShapes:
    """The truth's mode shapes along the span, every computed mode (arbitrary scale).

    Attributes
    ----------
    stations_m : ndarray, shape (S,)
        Stations along the span, m from the root.
    deflection : ndarray, shape (K, S)
        Each mode's z deflection of the axis at the stations.
    twist : ndarray, shape (K, S)
        Each mode's twist (rotation of the section about x) at the stations.
    """

    stations_m: np.ndarray
    deflection: np.ndarray
    twist: np.ndarray

    def __post_init__(self) -> None:
        """Check sizes and finiteness (BeamInputError naming the field)."""
        x = real_vector("mode_shapes.stations_m", self.stations_m, "m")
        for name in ("deflection", "twist"):
            a = np.array(getattr(self, name), dtype=float)
            if a.ndim != 2 or a.shape[1] != x.size or not np.all(np.isfinite(a)):
                raise BeamInputError(f"mode_shapes.{name}: must be finite, one row per mode "
                                     f"and {x.size} stations")
            a.setflags(write=False)
            object.__setattr__(self, name, a)
        if self.deflection.shape != self.twist.shape:
            raise BeamInputError("mode_shapes: deflection and twist must have one row per mode")
        object.__setattr__(self, "stations_m", x)


def truth_mode_shapes(modal) -> ModeShapes | None:
    """Return the deflection and twist of every mode of a truth at ``STATIONS`` stations.

    ``modal`` is a truth's ``ModalSolution`` (``nodes_m``, ``node_uz``); the slices divide the
    nodes' span in x. None when it has no nodes or no width to twist over (the 1D beam).
    """
    nodes, uz = getattr(modal, "nodes_m", None), getattr(modal, "node_uz", None)
    if nodes is None or uz is None or np.ptp(nodes[:, 1]) <= 0.0:
        return None
    x, y = nodes[:, 0], nodes[:, 1]
    edges = np.linspace(float(x.min()), float(x.max()), STATIONS + 1)
    slot = np.clip(np.searchsorted(edges, x, side="right") - 1, 0, STATIONS - 1)
    xs, w, th = [], [], []
    for s in range(STATIONS):
        on = slot == s
        if not np.any(on):
            continue  # a slice between two lines of nodes
        xm = float(np.mean(x[on]))
        cols = [np.ones(int(on.sum())), y[on]] + ([x[on] - xm] if np.ptp(x[on]) > 0 else [])
        A = np.column_stack(cols)
        if np.linalg.matrix_rank(A) < A.shape[1]:
            continue  # a slice without width
        coef = np.linalg.lstsq(A, uz[:, on].T, rcond=None)[0]  # (3, K)
        xs.append(xm)
        w.append(coef[0])
        th.append(coef[1])
    if len(xs) < 3:
        return None
    return ModeShapes(np.asarray(xs), np.asarray(w).T, np.asarray(th).T)


def chain_shapes(lengths_m: np.ndarray, coords: np.ndarray, phi: np.ndarray,
                 stations_m: np.ndarray, axis: str) -> np.ndarray:
    """Return the chain's modes about one axis along the span at the straight pose, (S, k).

    ``coords`` are the coordinates of that axis, node by node (``model.axis_index``), ``phi``
    (nv, k) the modes; ``axis`` ``"y"`` gives the deflection (m per unit coordinate), ``"x"``
    the twist (rad per unit coordinate).
    """
    s_j = np.cumsum(np.asarray(lengths_m, dtype=float))[: coords.size]  # joint stations, m
    arm = np.asarray(stations_m, dtype=float)[:, None] - s_j[None, :]  # (S, n)
    inboard = arm > 0.0
    G = -np.where(inboard, arm, 0.0) if axis == "y" else inboard.astype(float)
    return G @ phi[coords]


def mac_matrix(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Return MAC(a_i, b_j) of the columns of a (S, p) and b (S, q), shape (p, q)."""
    num = (a.T @ b) ** 2
    den = np.outer(np.sum(a * a, axis=0), np.sum(b * b, axis=0))
    return np.divide(num, den, out=np.zeros_like(num), where=den > 0.0)


def pair_by_mac(truth: np.ndarray, model: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pair each truth shape (S, p) with a distinct model shape (S, q >= p) by shape.

    Only a clear resemblance (MAC at least :data:`MAC_WARN`) moves a pair off its rank: the
    pairs maximise the total of those MACs, with the rank as the tie-break, so a truth mode
    that resembles no model mode keeps its rank (and its low MAC is reported) instead of
    being moved on noise. Returns the model column of each truth shape (p,) and its MAC (p,).
    """
    M = mac_matrix(truth, model)
    p = truth.shape[1]
    score = np.where(M >= MAC_WARN, M, 0.0)
    score[np.arange(p), np.arange(p)] += RANK_TIE
    rows, cols = scipy.optimize.linear_sum_assignment(score, maximize=True)
    out = np.empty(p, dtype=int)
    out[rows] = cols
    return out, M[np.arange(p), out]


def pair_modes(design, model, shapes: ModeShapes | None
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Pair a spatial fit's selected truth modes with the chain's modes by kind and MAC.

    ``design`` is the fit's ``SpatialDesign`` (its selection ``sel`` and ``axis_modes``).
    Returns, in the selection's order, the model frequency paired with each selected truth
    mode (rad/s), the pair's MAC (NaN where the pairing is by order: no truth shapes, or the
    in-plane axis) and whether the pair is off the rank the fit matched (bool).
    """
    sel = design.sel
    w = np.empty(sel.index.size)
    mac = np.full(sel.index.size, np.nan)
    moved = np.zeros(sel.index.size, dtype=bool)
    for a in design.order:
        rows = np.flatnonzero(sel.axis == a)
        omega, phi = design.axis_modes(model, a)
        cols = np.arange(rows.size)
        if shapes is not None and a in ("y", "x"):
            truth = (shapes.deflection if a == "y" else shapes.twist)[sel.index[rows]].T
            chain = chain_shapes(model.lengths_m, model.axis_index(a), phi, shapes.stations_m, a)
            cols, mac[rows] = pair_by_mac(truth, chain)
        w[rows] = omega[cols]
        moved[rows] = cols != np.arange(rows.size)
    return w, mac, moved


def pairing_notes(sel, omega_paired: np.ndarray, moved: np.ndarray, mac: np.ndarray
                  ) -> list[str]:
    """Return the result's warnings on the pairing: pairs off their rank, and poor shapes.

    ``omega_paired`` are the model frequencies paired by MAC (rad/s), ``moved`` the pairs off
    the rank within the kind the fit matched.
    """
    notes = []
    off = np.flatnonzero(moved)
    if off.size:
        pairs = "; ".join(f"truth mode {sel.index[k] + 1} ({sel.kind[k]}, "
                          f"{sel.omega_truth_rad_s[k]:.6g} rad/s) with the chain's mode at "
                          f"{omega_paired[k]:.6g} rad/s (MAC {mac[k]:.2f})" for k in off)
        notes.append("by shape the chain's modes pair with the truth's off their frequency "
                     "order, so the frequencies the fit matched by rank are not the pairs' "
                     f"({pairs}); modes lists the pairs by shape")
    poor = [k for k in np.flatnonzero(np.nan_to_num(mac, nan=1.0) < MAC_WARN) if not moved[k]]
    if poor:
        notes.append("the chain's mode paired with truth mode(s) "
                     + ", ".join(f"{sel.index[k] + 1} ({sel.kind[k]}, MAC {mac[k]:.2f})"
                                 for k in poor)
                     + " resembles it poorly along the span (a chain's highest modes of a kind "
                     "are its crudest): more joints represent it better")
    return notes
