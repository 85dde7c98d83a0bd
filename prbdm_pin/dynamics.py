"""Dynamics and statics of a PRBDM chain: free functions in Pinocchio's style f(model, data, ...).

``pin_model`` is a ``pinocchio.Model`` of a serial chain of revolute joints about y (the model
builder's output); ``data`` is its workspace (``pin_model.createData()``), created once and reused;
stiffness is the diagonal of K in N m/rad. Frequencies solve the symmetric generalised problem
K phi = omega^2 M phi through the diagonal scaling K^(-1/2) M K^(-1/2) (exact, no inverse of M, and
the lowest frequencies come out of the largest eigenvalues, where the solver is most accurate).
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin
from scipy.linalg.lapack import dpotrf as _potrf
from scipy.linalg.lapack import dpotrs as _potrs
from scipy.linalg.lapack import dsyevd as _syevd

from .errors import BeamInputError, SolveError
from .statics_guard import check_load, load_ok_rows, off_saddle, require_finite

__all__ = [
    "mass_matrix",
    "mass_matrices",
    "planar_mass_matrices",
    "modes_from_mass",
    "natural_frequencies",
    "natural_frequencies_batch",
    "eig_scaled",
    "modes",
    "modal_damping",
    "tip_position",
    "tip_jacobian",
    "tip_kinematics",
    "planar_lengths",
    "planar_tip",
    "static_deflection",
    "static_deflection_planar",
    "planar_tips",
    "static_deflection_planar_batch",
]

_LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


def _all_finite(arr: np.ndarray) -> bool:
    # a ufunc and a reduction cost microseconds, as much as a kinematics pass of a short chain;
    # a Python loop over a short vector is cheaper
    if arr.size <= 32:
        return all(map(math.isfinite, arr.tolist()))
    return bool(np.isfinite(arr).all())


def _q(pin_model: pin.Model, q: np.ndarray | None) -> np.ndarray:
    n = pin_model.nq
    if q is None:
        return np.zeros(n)
    arr = np.asarray(q, dtype=float)
    if arr.shape != (n,):
        raise BeamInputError(f"q has shape {arr.shape}: must be ({n},) joint angles (rad)")
    if not _all_finite(arr):
        raise BeamInputError(f"q = {arr.tolist()}: must be finite (rad)")
    return arr


def mass_matrix(pin_model: pin.Model, data: pin.Data, q: np.ndarray | None = None) -> np.ndarray:
    """Joint-space mass matrix M(q) by CRBA, kg m^2, shape (n, n), symmetric.

    Pinocchio's C++ CRBA fills only the upper triangle; the Python binding returns the
    symmetrised matrix (tests check that it stays so).
    """
    return pin.crba(pin_model, data, _q(pin_model, q))


def mass_matrices(pin_model: pin.Model, data: pin.Data, Q: np.ndarray) -> np.ndarray:
    """Mass matrices at the poses in the rows of ``Q`` (rad), kg m^2, shape (m, n, n)."""
    Q = _poses(pin_model, Q)
    out = np.empty((Q.shape[0], pin_model.nv, pin_model.nv))
    crba = pin.crba
    for i in range(Q.shape[0]):
        out[i] = crba(pin_model, data, Q[i])
    return out


def planar_mass_matrices(
    lengths_m: np.ndarray,
    mass_kg: np.ndarray,
    com_offset_m: np.ndarray,
    inertia_yy_kg_m2: np.ndarray,
    Q: np.ndarray,
) -> np.ndarray:
    """Closed-form mass matrices of the planar chain at the poses in the rows of ``Q``.

    The fit's inner loop uses this instead of building a ``pinocchio.Model`` for every trial
    design (the model build cost ~10x the rest of an evaluation); the product, and every fit
    result, use Pinocchio's CRBA. Tests check it against ``pin.crba`` on ``build_model``'s model
    (relative 1e-12). No input checks: the caller passes valid arrays.

    Link i >= 1 (mass m_i, centre of mass d_i from its joint along its axis, inertia I_i about
    the centre of mass and the y axis) swings about joints 1..i, so
    ``M_jk = sum_(i >= max(j, k)) m_i r_ij . r_ik + I_i`` with ``r_ij`` the vector from joint j
    to the centre of mass of link i in the xz-plane (link 0 is clamped and adds nothing).

    Parameters
    ----------
    lengths_m : ndarray, shape (n+1,)
        Link lengths, m.
    mass_kg, com_offset_m, inertia_yy_kg_m2 : ndarray, shape (n+1,)
        Link masses (kg), centre-of-mass distances from the link's start along its axis (m),
        and inertias about the centre of mass around y (kg m^2); entry 0 (the clamped link) is
        not used.
    Q : ndarray, shape (m, n)
        Joint angles, rad.

    Returns
    -------
    ndarray, shape (m, n, n), kg m^2; (B, m, n, n) when the link arrays are stacks (B, n+1)
    of designs.
    """
    Q = np.asarray(Q, dtype=float)
    m, n = Q.shape
    L, mass, off, Iyy = (np.asarray(v, dtype=float).reshape(-1, n + 1)
                         for v in (lengths_m, mass_kg, com_offset_m, inertia_yy_kg_m2))
    B = L.shape[0]
    phi = np.zeros((m, n + 1))
    Q.cumsum(axis=1, out=phi[:, 1:])
    c, sn = np.cos(phi), np.sin(phi)  # link axes (the sign of z does not matter here)
    jx = (L[:, None, :-1] * c[:, :-1]).cumsum(axis=2)  # (B, m, n): joint j + 1
    jz = (L[:, None, :-1] * sn[:, :-1]).cumsum(axis=2)
    cx = jx + off[:, None, 1:] * c[:, 1:]  # (B, m, n): centre of mass of link i + 1
    cz = jz + off[:, None, 1:] * sn[:, 1:]
    # rows (i, x) of R hold sqrt(m_i) r_ij; link i moves with joint j only when j <= i
    w = (np.sqrt(mass[:, 1:])[:, :, None] * np.tri(n))[:, None]
    R = np.empty((B, m, 2 * n, n))
    np.multiply(cx[..., :, None] - jx[..., None, :], w, out=R[:, :, :n])
    np.multiply(cz[..., :, None] - jz[..., None, :], w, out=R[:, :, n:])
    M = R.swapaxes(-1, -2) @ R
    tail = Iyy[:, :0:-1].cumsum(axis=1)[:, ::-1]  # sum over links i >= j of I_i
    idx = np.arange(n)
    M += tail[:, None, np.maximum.outer(idx, idx)]
    if np.ndim(lengths_m) == 1:
        return M[0]
    return M


def modes_from_mass(
    M: np.ndarray, stiffness_Nm_per_rad: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Frequencies (rad/s, ascending) and mass-normalised mode shapes of stacked problems.

    ``M`` is (m, n, n) and ``stiffness_Nm_per_rad`` (n,) or (m, n) (no input checks); returns
    omega (m, n) and Phi (m, n, n) with Phi[i]^T M[i] Phi[i] = I, as :func:`modes` per pose.
    """
    s = np.broadcast_to(1.0 / np.sqrt(stiffness_Nm_per_rad), M.shape[:2])
    mu, V = np.linalg.eigh(M * s[:, :, None] * s[:, None, :])
    _check_conditioning(mu)
    with np.errstate(over="ignore", divide="ignore"):
        _check_finite(1.0 / mu)
    mu, V = mu[:, ::-1], V[:, :, ::-1]
    Phi = s[:, :, None] * V / np.sqrt(mu)[:, None, :]
    return np.sqrt(1.0 / mu), Phi


def _poses(pin_model: pin.Model, Q: np.ndarray) -> np.ndarray:
    Q = np.asarray(Q, dtype=float)
    n = pin_model.nq
    if Q.ndim != 2 or Q.shape[1] != n:
        raise BeamInputError(f"Q has shape {Q.shape}: must be (m, {n}) joint angles (rad)")
    if not np.all(np.isfinite(Q)):
        raise BeamInputError("Q: every joint angle must be finite (rad)")
    return Q


def _stiffness(k: np.ndarray, n: int, m: int | None = None) -> np.ndarray:
    k = np.asarray(k, dtype=float)
    ok_shapes = [(n,)] if m is None else [(n,), (m, n)]
    if k.shape not in ok_shapes:
        raise BeamInputError(
            f"stiffness has shape {k.shape}: must be one of {ok_shapes} (N m/rad)"
        )
    bad = ~(np.isfinite(k) & (k >= np.finfo(float).tiny))
    if np.any(bad):
        i = np.unravel_index(int(np.flatnonzero(bad)[0]), k.shape)
        raise BeamInputError(f"stiffness[{', '.join(map(str, i))}] = {k[i]}: must be finite, > 0 "
                             "and a normal double (>= 2.2e-308)")
    return k


def _eig_from_mass(M: np.ndarray, k: np.ndarray, squared: bool) -> np.ndarray:
    return eig_scaled(M, 1.0 / np.sqrt(k), squared)


# Largest cond(K^-1/2 M K^-1/2) accepted. The highest omega^2 comes from the smallest eigenvalue
# mu_min of the scaled matrix, whose relative error is about eps * mu_max / mu_min (measured
# against 40-digit mpmath solves: up to 1.3 eps * cond). Beyond this limit the top frequency
# could be off by more than FREQUENCY_RTOL, so the solvers raise instead of answering.
FREQUENCY_RTOL = 1e-6
COND_LIMIT = FREQUENCY_RTOL / np.finfo(float).eps


def _check_conditioning(mu: np.ndarray) -> None:
    """Raise SolveError unless every row of ascending eigenvalues ``mu`` is positive and trusted."""
    lo, hi = mu[..., 0], mu[..., -1]
    # the common case in one pass (NaN fails every comparison): the full checks below only
    # run to find what is wrong
    if (lo > 0.0).all() and np.isfinite(mu).all() and (hi / lo).max() <= COND_LIMIT:
        return
    if not np.all(np.isfinite(mu)):
        raise SolveError("eigenvalues are not finite: the mass or stiffness values overflow "
                         "double precision")
    # an eigenvalue below zero by more than rounding: M itself is not positive definite
    if np.any(lo < -1e-12 * np.abs(hi)) or not np.all(hi > 0.0):
        raise SolveError("mass matrix is not positive definite: frequencies are undefined")
    with np.errstate(divide="ignore"):
        cond = np.where(lo > 0.0, hi / np.where(lo > 0.0, lo, 1.0), np.inf)
    worst = int(np.argmax(cond)) if cond.ndim else 0
    c = float(np.max(cond))
    if c > COND_LIMIT:
        where = f" (pose {worst})" if cond.ndim else ""
        raise SolveError(
            f"frequencies cannot be trusted{where}: cond(K^-1/2 M K^-1/2) = {c:.3g} exceeds "
            f"{COND_LIMIT:.3g}, so the highest frequency could be off by more than "
            f"{FREQUENCY_RTOL:g} relative in double precision; check the spread of the joint "
            "stiffness and of the link lengths"
        )


def _check_finite(w2: np.ndarray) -> np.ndarray:
    if not np.all(np.isfinite(w2)):
        raise SolveError("omega^2 overflows double precision: the stiffness is too large for "
                         "the mass (check the units)")
    return w2


def eig_scaled(M: np.ndarray, s: np.ndarray, squared: bool = False) -> np.ndarray:
    """Frequencies from mass matrices M (n, n) or (m, n, n) and s = K^(-1/2) (n,) or (m, n).

    The eigenvalues mu of S M S (S = diag(s)) are 1 / omega^2. No input checks: the callers
    validate once. Raises SolveError when mu_max / mu_min exceeds ``COND_LIMIT`` (the highest
    frequency would not be accurate to ``FREQUENCY_RTOL``).
    """
    # S normalised to max 1 keeps S M S as large as M: no underflow for stiff springs
    smax = s.max(axis=-1, keepdims=True)
    sn = s / smax
    A = M * sn[..., :, None] * sn[..., None, :]
    if A.ndim == 2:
        mu, _, info = _syevd(A, compute_v=0, lower=0)  # one small matrix: LAPACK directly
        if info != 0:
            raise SolveError(f"symmetric eigensolver failed (LAPACK info {info})")
    else:
        mu = np.linalg.eigvalsh(A)  # ascending, batched over the stack
    _check_conditioning(mu)
    with np.errstate(over="ignore"):
        w2 = _check_finite((1.0 / smax) ** 2 / mu[..., ::-1])
    return w2 if squared else np.sqrt(w2)


def natural_frequencies(
    pin_model: pin.Model,
    data: pin.Data,
    stiffness_Nm_per_rad: np.ndarray,
    q: np.ndarray | None = None,
    squared: bool = False,
) -> np.ndarray:
    """Natural frequencies at pose ``q`` (rad; default straight), rad/s ascending, shape (n,).

    ``squared=True`` returns omega^2 (rad^2/s^2), the quantity the paper's code compares.
    """
    k = _stiffness(stiffness_Nm_per_rad, pin_model.nv)
    return _eig_from_mass(mass_matrix(pin_model, data, q), k, squared)


def natural_frequencies_batch(
    pin_model: pin.Model,
    data: pin.Data,
    Q: np.ndarray,
    stiffness_Nm_per_rad: np.ndarray,
    squared: bool = False,
) -> np.ndarray:
    """Natural frequencies at many poses, rad/s ascending per row, shape (m, n).

    One CRBA per pose, then a single stacked symmetric eigensolve. ``stiffness_Nm_per_rad`` is
    (n,) for all poses or (m, n), one row per pose (e.g. one SCF per pose).
    """
    M = mass_matrices(pin_model, data, Q)
    k = _stiffness(stiffness_Nm_per_rad, pin_model.nv, M.shape[0])
    return _eig_from_mass(M, k, squared)


def modes(
    pin_model: pin.Model,
    data: pin.Data,
    stiffness_Nm_per_rad: np.ndarray,
    q: np.ndarray | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Natural frequencies (rad/s, ascending) and mass-normalised mode shapes (columns of Phi).

    Phi satisfies Phi^T M Phi = I and Phi^T K Phi = diag(omega^2).
    """
    k = _stiffness(stiffness_Nm_per_rad, pin_model.nv)
    M = mass_matrix(pin_model, data, q)
    s = 1.0 / np.sqrt(k)
    mu, V = np.linalg.eigh(M * s[:, None] * s[None, :])
    _check_conditioning(mu)
    with np.errstate(over="ignore", divide="ignore"):
        _check_finite(1.0 / mu)
    order = np.argsort(-mu)
    mu, V = mu[order], V[:, order]
    # K^(1/2) phi = V/sqrt(mu) makes phi^T M phi = v^T (S M S) v / mu = 1
    Phi = s[:, None] * V / np.sqrt(mu)[None, :]
    return np.sqrt(1.0 / mu), Phi


def modal_damping(M: np.ndarray, Phi: np.ndarray, omega_rad_s: np.ndarray, xi: np.ndarray | float):
    """Modal damping matrix C = M Phi diag(2 xi omega) Phi^T M, N m s/rad.

    With mass-normalised Phi each mode gets the damping ratio ``xi`` exactly.
    """
    d = 2.0 * np.broadcast_to(np.asarray(xi, dtype=float), omega_rad_s.shape) * omega_rad_s
    MP = M @ Phi
    return (MP * d[None, :]) @ MP.T


def tip_position(
    pin_model: pin.Model, data: pin.Data, q: np.ndarray, tip_frame_id: int
) -> np.ndarray:
    """World position of the tip frame, m, shape (3,) (joint kinematics plus one frame update)."""
    pin.forwardKinematics(pin_model, data, _q(pin_model, q))
    return pin.updateFramePlacement(pin_model, data, tip_frame_id).translation.copy()


def tip_jacobian(
    pin_model: pin.Model, data: pin.Data, q: np.ndarray, tip_frame_id: int
) -> np.ndarray:
    """World-aligned linear Jacobian of the tip point, m/rad, shape (3, n)."""
    J = pin.computeFrameJacobian(pin_model, data, _q(pin_model, q), tip_frame_id, _LWA)
    # the binding hands a one-column matrix back as a vector: keep (3, n) for n = 1 too
    return J[:3].reshape(3, pin_model.nv).copy()


def tip_kinematics(
    pin_model: pin.Model, data: pin.Data, q: np.ndarray, tip_frame_id: int
) -> tuple[np.ndarray, np.ndarray]:
    """Tip position (m, (3,)) and world-aligned linear Jacobian (m/rad, (3, n)) in one pass.

    What statics needs: the frame Jacobian's forward kinematics leaves the joint placements in
    ``data``, so the tip placement costs one frame update more (no second kinematics pass, one
    input check).
    """
    J = pin.computeFrameJacobian(pin_model, data, _q(pin_model, q), tip_frame_id, _LWA)
    p = pin.updateFramePlacement(pin_model, data, tip_frame_id).translation.copy()
    return p, J[:3].reshape(3, pin_model.nv).copy()


# --- statics ------------------------------------------------------------------------------------

def planar_lengths(pin_model: pin.Model, tip_frame_id: int) -> np.ndarray:
    """Link lengths (m) of a serial chain of y-revolute joints laid out along x, shape (n+1,).

    Raises BeamInputError when the model is not such a chain (the planar statics need it).
    """
    n = pin_model.njoints - 1
    out = np.empty(n + 1)
    for j in range(1, n + 1):
        if pin_model.parents[j] != j - 1 or pin_model.joints[j].shortname() != "JointModelRY":
            raise BeamInputError(f"joint {pin_model.names[j]!r}: must be a serial RY joint")
        out[j - 1] = _along_x(pin_model.jointPlacements[j], pin_model.names[j])
    frame = pin_model.frames[tip_frame_id]
    if frame.parentJoint != n:
        raise BeamInputError(f"frame {frame.name!r}: the tip frame must sit on the last joint")
    out[n] = _along_x(frame.placement, frame.name)
    return out


def _along_x(M: pin.SE3, name: str) -> float:
    p = M.translation
    if not (np.allclose(M.rotation, np.eye(3), atol=1e-12) and abs(p[1]) + abs(p[2]) <= 1e-12):
        raise BeamInputError(f"placement of {name!r} = {p.tolist()}: must be a pure x offset")
    return float(p[0])


def planar_tip(lengths_m: np.ndarray, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Closed-form tip position (3,) and linear Jacobian (3, n) of the planar chain.

    Link i >= 1 has world angle phi_i = q_1 + ... + q_i about +y, so its axis is
    (cos phi_i, 0, -sin phi_i) and p_tip = L_0 e_x + sum_i L_i (cos phi_i, 0, -sin phi_i).
    """
    L = np.asarray(lengths_m, dtype=float)
    phi = np.cumsum(q)
    lc, ls = L[1:] * np.cos(phi), L[1:] * np.sin(phi)
    p = np.array([L[0] + lc.sum(), 0.0, -ls.sum()])
    J = np.zeros((3, q.size))
    J[0] = -np.cumsum(ls[::-1])[::-1]
    J[2] = -np.cumsum(lc[::-1])[::-1]
    return p, J


class _Potential:
    """V(q) = 1/2 q^T K q - lam F . p_tip(q) of the planar chain, with exact gradient and Hessian.

    With T_m = sum_(i >= m) L_i (-Fx cos phi_i + Fz sin phi_i), d^2(F . p)/dq_j dq_k = T_max(j,k),
    so the Hessian is diag(K) - T[max(j, k)].
    """

    def __init__(self, lengths: np.ndarray, k: np.ndarray, force: np.ndarray) -> None:
        self.L0, self.L = float(lengths[0]), np.asarray(lengths[1:], dtype=float)
        self.k = k
        self.K = np.diag(k)
        self.fx, self.fz = float(force[0]), float(force[2])
        idx = np.arange(k.size)
        self.imax = np.maximum(idx[:, None], idx[None, :])

    def value(self, q: np.ndarray, lam: float) -> float:
        phi = np.cumsum(q)
        work = self.fx * (self.L0 + self.L @ np.cos(phi)) - self.fz * (self.L @ np.sin(phi))
        return 0.5 * float(q @ (self.k * q)) - lam * work

    def derivatives(self, q: np.ndarray, lam: float):
        phi = np.cumsum(q)
        lcs = np.array([np.cos(phi), np.sin(phi)]) * self.L
        rc, rs = np.cumsum(lcs[:, ::-1], axis=1)[:, ::-1]  # sum over i >= m of L c, L s
        # J^T F with J rows dp_x = -rcumsum(L s), dp_z = -rcumsum(L c)
        jtf = (-lam * self.fx) * rs - (lam * self.fz) * rc
        kq = self.k * q
        g = kq - jtf
        T = (-lam * self.fx) * rc + (lam * self.fz) * rs
        H = self.K - T[self.imax]
        scale = max(math.sqrt(kq @ kq), math.sqrt(jtf @ jtf), 1e-300)
        return g, H, scale


def _newton(pot: _Potential, q: np.ndarray, lam: float, rtol: float, max_iter: int,
            max_step: float) -> tuple[np.ndarray, bool]:
    """Damped Newton descent on V from ``q``; returns (q, converged)."""
    for _ in range(max_iter):
        g, H, scale = pot.derivatives(q, lam)
        gn = math.sqrt(g @ g)
        require_finite((pot.fx, 0.0, pot.fz), gn, scale)
        C, info = _potrf(H, lower=1)  # LAPACK Cholesky: thin wrapper, cheap for small n
        pd = info == 0
        if gn <= rtol * scale:
            if pd:
                return q, True
            # a stationary point that is not a minimum (e.g. the straight pose under a buckling
            # load): leave it along the direction of negative curvature
            w, V = np.linalg.eigh(H)
            d = V[:, 0] * min(max_step, 1e-2)
        elif pd:
            d = -_potrs(C, g, lower=1)[0]
        else:
            w, V = np.linalg.eigh(H)
            floor = 1e-8 * max(float(np.max(np.abs(w))), 1e-300)
            d = -V @ ((V.T @ g) / np.maximum(np.abs(w), floor))
        step = float(np.max(np.abs(d)))
        if step > max_step:
            d *= max_step / step
        # backtracking (Armijo) on the potential; near the solution V stops resolving the
        # decrease, so a step that shrinks the gradient is accepted as well
        v0, slope = pot.value(q, lam), float(g @ d)
        alpha = 1.0
        for _ in range(40):
            qn = q + alpha * d
            if pot.value(qn, lam) <= v0 + 1e-4 * alpha * min(slope, 0.0):
                break
            gnew = pot.derivatives(qn, lam)[0]
            if math.sqrt(gnew @ gnew) < 0.5 * gn:
                break
            alpha *= 0.5
        else:
            return q, False
        q = qn
    g, H, scale = pot.derivatives(q, lam)
    return q, bool(math.sqrt(g @ g) <= rtol * scale and _potrf(H, lower=1)[1] == 0)


def static_deflection_planar(
    lengths_m: np.ndarray,
    stiffness_Nm_per_rad: np.ndarray,
    tip_force_N: np.ndarray,
    q0: np.ndarray | None = None,
    rtol: float = 1e-10,
    max_iter: int = 60,
    max_step_rad: float = 0.5,
) -> np.ndarray:
    """Equilibrium joint angles (rad) of the planar chain under a dead tip force (N).

    Minimises V(q) = 1/2 q^T K q - F . p_tip(q) by damped Newton steps with the exact Hessian,
    starting from ``q0`` (default straight). If the full load does not converge, the load is
    applied in adaptive steps (continuation), each solved from the previous equilibrium.
    Converged means ||K q - J^T F|| <= rtol * max(||K q||, ||J^T F||) at a minimum of V.

    Raises
    ------
    SolveError
        If no equilibrium is found.
    """
    k = np.asarray(stiffness_Nm_per_rad, dtype=float)
    n = k.size
    F = np.asarray(tip_force_N, dtype=float)
    if F.shape != (3,) or not np.all(np.isfinite(F)):
        raise BeamInputError(f"tip_force = {F.tolist()}: must be 3 finite numbers (N)")
    q = np.zeros(n) if q0 is None else np.array(q0, dtype=float)
    if q.shape != (n,) or not np.all(np.isfinite(q)):
        raise BeamInputError(f"q0 = {q.tolist()}: must be {n} finite joint angles (rad)")
    if F[0] == 0.0 and F[2] == 0.0:
        return np.zeros(n)  # no in-plane load: V = 1/2 q^T K q has its only minimum at 0
    check_load(lengths_m, k, F, rtol)
    pot = _Potential(np.asarray(lengths_m, dtype=float), k, F)
    q1, ok = _newton(pot, q, 1.0, rtol, max_iter, max_step_rad)
    if ok:
        return q1
    # load stepping from the start pose
    lam, dlam = 0.0, 0.25
    while lam < 1.0:
        target = min(1.0, lam + dlam)
        qn, ok = _newton(pot, q, target, rtol, max(1, max_iter // 2), max_step_rad)
        if ok:
            q, lam = qn, target
            dlam *= 1.5
        else:
            dlam *= 0.5
            if dlam < 1e-5:
                # the path stalls at a bifurcation of the straight pose (a column under an
                # axial load), where the full-load descent had only run short of iterations
                qn, ok = _newton(pot, off_saddle(pot, q1), 1.0, rtol, 4 * max_iter,
                                 max_step_rad)
                if ok:
                    return qn
                raise SolveError(
                    f"static deflection: no equilibrium beyond {lam:.4g} of the load "
                    f"tip_force = {F.tolist()} N (load stepping stalled)"
                )
    return q


def planar_tips(lengths_m: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """Closed-form tip positions (m) of stacked planar chains, shape (B, 3).

    ``lengths_m`` (B, n+1) or (n+1,) for all rows, ``Q`` (B, n) joint angles (rad); the
    kinematics of :func:`planar_tip`, one row per chain.
    """
    Q = np.asarray(Q, dtype=float)
    L = np.broadcast_to(np.asarray(lengths_m, dtype=float), (Q.shape[0], Q.shape[1] + 1))
    phi = np.cumsum(Q, axis=1)
    out = np.zeros((Q.shape[0], 3))
    out[:, 0] = L[:, 0] + np.einsum("bi,bi->b", L[:, 1:], np.cos(phi))
    out[:, 2] = -np.einsum("bi,bi->b", L[:, 1:], np.sin(phi))
    return out


class _BatchPotential:
    """:class:`_Potential` of B chains at once: rows of lengths (B, n+1) and springs (B, n)."""

    def __init__(self, lengths: np.ndarray, k: np.ndarray, force: np.ndarray) -> None:
        self.L0, self.L = lengths[:, 0], lengths[:, 1:]
        self.k = k
        self.fx, self.fz = float(force[0]), float(force[2])
        idx = np.arange(k.shape[1])
        self.imax = np.maximum(idx[:, None], idx[None, :])
        self.diag = np.arange(k.shape[1])

    def value(self, q: np.ndarray, rows: np.ndarray) -> np.ndarray:
        phi = np.cumsum(q, axis=1)
        L = self.L[rows]
        work = (self.fx * (self.L0[rows] + np.einsum("bi,bi->b", L, np.cos(phi)))
                - self.fz * np.einsum("bi,bi->b", L, np.sin(phi)))
        return 0.5 * np.einsum("bi,bi->b", self.k[rows] * q, q) - work

    def derivatives(self, q: np.ndarray, rows: np.ndarray, hessian: bool = True):
        phi = np.cumsum(q, axis=1)
        L = self.L[rows]
        rc = np.cumsum((L * np.cos(phi))[:, ::-1], axis=1)[:, ::-1]
        rs = np.cumsum((L * np.sin(phi))[:, ::-1], axis=1)[:, ::-1]
        jtf = -self.fx * rs - self.fz * rc
        kq = self.k[rows] * q
        g = kq - jtf
        scale = np.maximum(np.maximum(np.linalg.norm(kq, axis=1), np.linalg.norm(jtf, axis=1)),
                           1e-300)
        if not hessian:
            return g, None, scale
        T = -self.fx * rc + self.fz * rs
        H = -T[:, self.imax]
        H[:, self.diag, self.diag] += self.k[rows]
        return g, H, scale


# Above this many rows the vectorised factorisation beats a LAPACK call per matrix (measured for
# n = 2...8: the two cross near 400 rows)
_ROWS_CHOLESKY_MIN = 400


def _cholesky_solve_batch(H: np.ndarray, g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Solve H d = g for a stack of small symmetric matrices; returns (d, positive definite per
    row). Rows that are not positive definite get d = 0."""
    if g.shape[0] >= _ROWS_CHOLESKY_MIN:
        return _cholesky_rows(H, g)
    try:
        # the common case, every row positive definite: LAPACK's loops
        np.linalg.cholesky(H)
        return np.linalg.solve(H, g[..., None])[..., 0], np.ones(g.shape[0], dtype=bool)
    except np.linalg.LinAlgError:
        return _cholesky_rows(H, g)


def _cholesky_rows(H: np.ndarray, g: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_cholesky_solve_batch` row by row in the factorisation, so that the rows that are
    not positive definite are found (n^2 vectorised steps for any batch size)."""
    B, n = g.shape
    C = np.zeros_like(H)
    pd = np.ones(B, dtype=bool)
    for j in range(n):
        dj = H[:, j, j] - np.einsum("bk,bk->b", C[:, j, :j], C[:, j, :j])
        pd &= dj > 0.0
        cjj = np.sqrt(np.where(dj > 0.0, dj, 1.0))
        C[:, j, j] = cjj
        if j + 1 < n:
            C[:, j + 1:, j] = (H[:, j + 1:, j]
                               - np.einsum("bik,bk->bi", C[:, j + 1:, :j], C[:, j, :j])) \
                / cjj[:, None]
    y = np.empty_like(g)
    for j in range(n):  # forward: C y = g
        y[:, j] = (g[:, j] - np.einsum("bk,bk->b", C[:, j, :j], y[:, :j])) / C[:, j, j]
    d = np.empty_like(g)
    for j in range(n - 1, -1, -1):  # back: C^T d = y
        d[:, j] = (y[:, j] - np.einsum("bk,bk->b", C[:, j + 1:, j], d[:, j + 1:])) / C[:, j, j]
    d[~pd] = 0.0
    return d, pd


def static_deflection_planar_batch(
    lengths_m: np.ndarray,
    stiffness_Nm_per_rad: np.ndarray,
    tip_force_N: np.ndarray,
    rtol: float = 1e-10,
    max_iter: int = 60,
    max_step_rad: float = 0.5,
) -> tuple[np.ndarray, np.ndarray]:
    """Equilibria of B planar chains under one dead tip force, solved together.

    The method of :func:`static_deflection_planar` (damped Newton with the exact Hessian on
    V = 1/2 q^T K q - F . p_tip, Armijo backtracking, the same convergence test), vectorised over
    the rows, so the fit's inner loop solves a whole population's (or every pose's) statics in
    one pass instead of one Python-level solve per row. Rows that Newton from the straight pose
    cannot finish (a non-convex start, say) are handed to :func:`static_deflection_planar` with
    its load stepping; rows that fail there too are reported, not raised.

    Parameters
    ----------
    lengths_m : ndarray, shape (B, n+1) or (n+1,)
        Link lengths of each chain, m.
    stiffness_Nm_per_rad : ndarray, shape (B, n)
        Joint springs of each chain, N m/rad.
    tip_force_N : ndarray, shape (3,)
        The dead tip force, N (world).

    Returns
    -------
    q : ndarray, shape (B, n)
        Joint angles, rad (NaN where no equilibrium was found).
    ok : ndarray of bool, shape (B,)
        Whether each row converged.
    """
    k = np.atleast_2d(np.asarray(stiffness_Nm_per_rad, dtype=float))
    B, n = k.shape
    L = np.broadcast_to(np.asarray(lengths_m, dtype=float), (B, n + 1))
    F = np.asarray(tip_force_N, dtype=float)
    if F.shape != (3,) or not np.all(np.isfinite(F)):
        raise BeamInputError(f"tip_force = {F.tolist()}: must be 3 finite numbers (N)")
    q = np.zeros((B, n))
    ok = np.zeros(B, dtype=bool)
    if F[0] == 0.0 and F[2] == 0.0:
        return q, ~ok  # no in-plane load: the straight pose is the only minimum
    pot = _BatchPotential(L, k, F)
    resolvable = load_ok_rows(L, k, F, rtol)
    active = np.flatnonzero(resolvable)
    for it in range(max_iter + 1):
        if active.size == 0:
            break
        qa = q[active]
        g, H, scale = pot.derivatives(qa, active)
        gn = np.linalg.norm(g, axis=1)
        d, pd = _cholesky_solve_batch(H, g)
        fin = np.isfinite(gn) & np.isfinite(scale)
        done = pd & fin & (gn <= rtol * scale)
        ok[active[done]] = True
        # not positive definite, not finite, or out of iterations: the scalar solver takes the
        # row over
        keep = pd & fin & ~done
        active, qa, g, gn, d = active[keep], qa[keep], g[keep], gn[keep], -d[keep]
        if it == max_iter or active.size == 0:
            break
        step = np.max(np.abs(d), axis=1)
        d *= np.minimum(1.0, max_step_rad / np.maximum(step, 1e-300))[:, None]
        v0 = pot.value(qa, active)
        slope = np.minimum(np.einsum("bi,bi->b", g, d), 0.0)
        alpha = np.ones(active.size)
        accepted = np.zeros(active.size, dtype=bool)
        for _ in range(40):
            todo = np.flatnonzero(~accepted)
            if todo.size == 0:
                break
            qn = qa[todo] + alpha[todo, None] * d[todo]
            good = pot.value(qn, active[todo]) <= v0[todo] + 1e-4 * alpha[todo] * slope[todo]
            bad = todo[~good]
            if bad.size:
                gnew = pot.derivatives(qa[bad] + alpha[bad, None] * d[bad], active[bad],
                                       hessian=False)[0]
                good[~good] = np.linalg.norm(gnew, axis=1) < 0.5 * gn[bad]
            accepted[todo[good]] = True
            alpha[todo[~good]] *= 0.5
        q[active[accepted]] = qa[accepted] + alpha[accepted, None] * d[accepted]
        active = active[accepted]  # rows whose line search failed go to the scalar solver
    q[~resolvable] = np.nan
    for r in np.flatnonzero(~ok & resolvable):
        try:
            q[r] = static_deflection_planar(L[r], k[r], F, rtol=rtol, max_iter=max_iter,
                                            max_step_rad=max_step_rad)
            ok[r] = True
        except SolveError:
            q[r] = np.nan
    return q, ok


def static_deflection(
    pin_model: pin.Model,
    data: pin.Data,
    stiffness_Nm_per_rad: np.ndarray,
    tip_frame_id: int,
    tip_force_N: np.ndarray,
    q0: np.ndarray | None = None,
    rtol: float = 1e-10,
) -> tuple[np.ndarray, np.ndarray]:
    """Large-deflection equilibrium K q = J(q)^T F under a dead tip force.

    Returns the joint angles q (rad) and the tip position (m, world). See
    :func:`static_deflection_planar` for the method.
    """
    k = _stiffness(stiffness_Nm_per_rad, pin_model.nv)
    lengths = planar_lengths(pin_model, tip_frame_id)
    q = static_deflection_planar(lengths, k, tip_force_N, q0=q0, rtol=rtol)
    return q, tip_position(pin_model, data, q, tip_frame_id)
