"""Pole-residue form <-> real state-space matrices, on plain arrays.

The realisation behind :meth:`modalid.ModalModel.to_statespace` and
:class:`~modalid.MultiOutputModalModel`, and the one both of ``impactpred``'s exact
engine front ends build their bodies' phases from (``solve_impact``'s coupled system,
``ImpactDamper``'s primary): public so that they depend on ``modalid``'s interface, not
on its private modules.
"""

from __future__ import annotations

import contextlib
import warnings

import numpy as np
import scipy.linalg

__all__ = ["pole_residue_to_statespace", "pole_residue_from_statespace"]


def pole_residue_to_statespace(poles, residues, real_poles, real_residues, inverse_mass,
                               flexibility):
    """Real block-diagonal ``(A, b, c, d)`` realising the pole-residue receptance.

    ``c (sI - A)^-1 b + d = H(s)`` exactly (rounding only), for ``H(s) = sum_k r_k/(s -
    p_k) + conj(r_k)/(s - conj p_k) + sum_j q_j/(s - a_j) + inverse_mass/s^2 +
    flexibility``; block order: complex modes (a 2 x 2 rotation block each), real poles,
    rigid body (a double integrator).

    Parameters
    ----------
    poles : array_like of complex, shape (n_modes,)
        Poles with ``Im p > 0`` (rad/s).
    residues : array_like of complex, shape (n_modes,) or (n_outputs, n_modes)
        Their residues (m/N/s); 2-D: one output per row on the same states.
    real_poles : array_like of float, shape (n_real,)
        Real poles (rad/s).
    real_residues : array_like of float, shape (n_real,) or (n_outputs, n_real)
        Their residues.
    inverse_mass : float or array_like, shape (n_outputs,)
        Rigid-body term ``1/M`` (1/kg); 0: no rigid-body states.
    flexibility : float or array_like, shape (n_outputs,)
        Constant term (m/N).

    Returns
    -------
    a : ndarray, shape (n, n)
    b : ndarray, shape (n,)
    c : ndarray, shape (n,) or (n_outputs, n)
    d : float or ndarray, shape (n_outputs,)
        ``n = 2 n_modes + n_real (+ 2 with a rigid body)``.
    """
    multi = np.ndim(residues) == 2
    residues = np.atleast_2d(residues)
    real_residues = np.reshape(real_residues, (residues.shape[0], -1))
    inverse_mass = np.atleast_1d(np.asarray(inverse_mass, dtype=float))
    has_rigid = bool(np.any(inverse_mass != 0.0))
    n_c, n_r = len(poles), len(real_poles)
    n = 2 * n_c + n_r + (2 if has_rigid else 0)
    a = np.zeros((n, n))
    b = np.zeros(n)
    c = np.zeros((residues.shape[0], n))
    idx = 2 * np.arange(n_c)
    a[idx, idx] = a[idx + 1, idx + 1] = np.real(poles)
    a[idx, idx + 1] = -np.imag(poles)
    a[idx + 1, idx] = np.imag(poles)
    b[idx] = 1.0
    c[:, idx] = 2.0 * np.real(residues)
    c[:, idx + 1] = -2.0 * np.imag(residues)
    j = 2 * n_c + np.arange(n_r)
    a[j, j] = real_poles
    b[j] = 1.0
    c[:, j] = real_residues
    if has_rigid:
        k = 2 * n_c + n_r
        a[k, k + 1] = 1.0
        if multi:  # shared rigid states (displacement per unit 1/M, velocity); 1/M in c
            b[k + 1] = 1.0
            c[:, k] = inverse_mass
        else:      # states are the rigid displacement (m) and velocity (m/s)
            b[k + 1] = inverse_mass[0]
            c[:, k] = 1.0
    if multi:
        return a, b, c, np.asarray(flexibility, dtype=float).reshape(-1)
    return a, b, c[0], float(flexibility)


def _refuse_split_repeated_pole(lam, v, res):
    """Raise for two poles within 1e-6 of each other whose eigenvectors are parallel.

    A repeated pole ``1/(s - p)^2`` (a Jordan block) reaches the eigen-decomposition split
    by rounding into two poles about ``1e-8 |p|`` apart, with parallel eigenvectors and
    huge opposite residues (``1/(s^2 + 100)^2``: ``+-4e4 i`` for a true ``1/s``
    coefficient of ``2.5e-4``), whenever the eigenvector matrix stays under
    ``defect_cond``. Two genuine close modes (a symmetric structure's pair) have
    independent eigenvectors and are kept.
    """
    if lam.size < 2:
        return
    unit = v / np.linalg.norm(v, axis=0)
    gap = np.abs(lam[:, None] - lam[None, :])
    close = np.triu(gap <= 1e-6 * np.abs(lam)[:, None], 1)
    for i, j in zip(*np.nonzero(close)):
        if abs(np.vdot(unit[:, i], unit[:, j])) > 1.0 - 1e-6:
            raise ValueError(f"the system has a repeated pole near s = {lam[i]:.6g} (a "
                             f"Jordan block: split by rounding into two poles "
                             f"{gap[i, j]:.2g} rad/s apart with parallel eigenvectors and "
                             f"residues {res[i]:.4g} and {res[j]:.4g}): its receptance is "
                             "not a sum of simple poles")


def pole_residue_from_statespace(a, b, c, d, *, zero_tol=1e-8, defect_cond=1e10):
    """Pole-residue parts of the SISO system ``c (sI - A)^-1 b + d``.

    The eigenvalues at 0 (``|lambda| <= zero_tol * ||A||``) are split off by an ordered
    real Schur form and a Sylvester solve; their block must be a pure double integrator
    (the rigid-body term). The rest is diagonalised; residues are
    ``(c v_k)(w_k b)``. Exact to rounding for a diagonalisable ``A``.

    Parameters
    ----------
    a : array_like, shape (n, n)
    b, c : array_like, shape (n,)
    d : float
        The system (a real state space of a receptance, m/N).
    zero_tol : float, keyword-only
        Eigenvalues within this share of ``||A||`` of 0 are the rigid body's.
    defect_cond : float, keyword-only
        An eigenvector matrix with a larger condition number is taken as defective.

    Returns
    -------
    dict
        Keyword arguments of :class:`~modalid.ModalModel`: ``poles``, ``residues``,
        ``real_poles``, ``real_residues``, ``inverse_mass``, ``flexibility``.

    Raises
    ------
    ValueError
        For a pole at 0 of order other than 2, an unstable pole, a defective
        (repeated, coupled) pole, or complex poles that do not pair.
    """
    a = np.atleast_2d(np.asarray(a, dtype=float))
    b = np.asarray(b, dtype=float).ravel()
    c = np.asarray(c, dtype=float).ravel()
    n = a.shape[0]
    out = dict(poles=np.zeros(0, complex), residues=np.zeros(0, complex),
               real_poles=np.zeros(0), real_residues=np.zeros(0), inverse_mass=0.0,
               flexibility=float(d))
    if n == 0:
        return out
    # Balancing (a diagonal similarity) tames companion forms from transfer functions.
    a, (scaling, _perm) = scipy.linalg.matrix_balance(a, permute=False, separate=True)
    b, c = b / scaling, c * scaling
    norm_a = np.linalg.norm(a, 1)
    tol = zero_tol * norm_a if norm_a > 0 else 1.0
    t, z, n_zero = scipy.linalg.schur(a, output="real",
                                      sort=lambda re, im: np.hypot(re, im) <= tol)
    bt, ct = z.T @ b, c @ z
    t11, t12, t22 = t[:n_zero, :n_zero], t[:n_zero, n_zero:], t[n_zero:, n_zero:]
    if n_zero and n_zero < n:
        x = scipy.linalg.solve_sylvester(t11, -t22, -t12)
        b1, b2 = bt[:n_zero] - x @ bt[n_zero:], bt[n_zero:]
        c1, c2 = ct[:n_zero], ct[:n_zero] @ x + ct[n_zero:]
    else:
        b1, b2, c1, c2 = bt[:n_zero], bt[n_zero:], ct[:n_zero], ct[n_zero:]

    lam, v = (np.linalg.eig(t22) if n_zero < n else (np.zeros(0, complex), np.zeros((0, 0))))
    if lam.size:
        if np.linalg.cond(v) > defect_cond:
            raise ValueError("the system has a defective (repeated, coupled) pole: its "
                             "receptance is not a sum of simple poles")
        res = (c2 @ v) * np.linalg.solve(v, b2.astype(complex))
        _refuse_split_repeated_pole(lam, v, res)
    else:
        res = np.zeros(0, complex)
    omega_ref = float(np.min(np.abs(lam))) if lam.size else 1.0

    if n_zero:
        k1 = float(c1 @ b1)              # 1/s coefficient
        k2 = float(c1 @ t11 @ b1)        # 1/s^2 coefficient
        scale = abs(k2) / omega_ref**2 + abs(float(d)) + float(np.sum(np.abs(res))) / omega_ref
        # 1/s^j coefficients c T^(j-1) b, j = 3 .. n_zero (the block is nilpotent): the
        # highest that is not rounding names the order (1/s^4: an accelerance's 1/s^2
        # divided by s^2 once too often), before a simple pole (1/s: a mobility's)
        power, highest = t11 @ t11, None
        for order in range(3, n_zero + 1):
            k_j = float(c1 @ power @ b1)
            if abs(k_j) / omega_ref**order > 1e-6 * scale:
                highest = (order, k_j)
            power = power @ t11
        if highest is not None:
            raise ValueError(f"the system has a pole of order {highest[0]} at s = 0 "
                             f"(coefficient {highest[1]:.6g} of 1/s^{highest[0]}): a "
                             "receptance has a rigid-body double pole or none")
        if abs(k1) / omega_ref > 1e-6 * scale:
            raise ValueError(f"the system has a simple pole at s = 0 (coefficient {k1:.6g} "
                             "of 1/s): a receptance has a rigid-body double pole or none (a "
                             "mass's mobility is 1/(m s), its receptance 1/(m s^2))")
        # Rounding-level values are zero; a negative one is a transfer term (rigid rotation).
        out["inverse_mass"] = k2 if abs(k2) > 1e-9 * scale * omega_ref**2 else 0.0

    stab_tol = 1e-9 * np.abs(lam)
    unstable = lam.real > stab_tol
    if np.any(unstable):
        raise ValueError(f"the system is unstable: pole {lam[unstable][0]:.6g} has a positive "
                         "real part")
    lam = np.where(lam.real > 0, 1j * lam.imag, lam)  # rounding of undamped poles
    is_real = np.abs(lam.imag) <= 1e-12 * np.abs(lam)
    upper = (~is_real) & (lam.imag > 0)
    if np.count_nonzero(upper) != np.count_nonzero((~is_real) & (lam.imag < 0)):
        raise ValueError("the complex poles do not come in conjugate pairs")
    out["poles"], out["residues"] = lam[upper], res[upper]
    out["real_poles"], out["real_residues"] = lam[is_real].real, res[is_real].real
    return out


@contextlib.contextmanager
def quiet_polynomial_trimming():
    """Silence scipy's BadCoefficients while converting between tf and ss.

    The conversions leave rounding-level leading coefficients that ``normalize`` trims
    with that warning; the round-trip tests bound the actual error.
    """
    from scipy.signal import BadCoefficients

    with warnings.catch_warnings():
        warnings.simplefilter("ignore", BadCoefficients)
        yield


def transfer_function_of(model):
    """``model``'s ``control.TransferFunction``, with a warning where it loses the model.

    Compared 1 % above the poles' moduli, between them (geometric means) and beyond them
    (rad/s): an error over ``1e-6`` of the sum of the terms' moduli anywhere raises a
    :class:`UserWarning` naming the worst point (polynomial coefficients lose high-order
    models to rounding).
    """
    import control

    with quiet_polynomial_trimming():
        tf = control.tf(model.to_statespace())
    rates = np.sort(np.abs(np.concatenate([model.poles, model.real_poles])))
    rates = rates[rates > 0]
    if not rates.size:
        return tf
    between = np.sqrt(rates[1:] * rates[:-1])
    w = np.concatenate([[0.5 * rates[0]], 1.01 * rates, between, [2.0 * rates[-1]]])
    s = 1j * w
    want = model.receptance(s)
    got = np.asarray(tf(s), dtype=complex).reshape(-1)
    # relative to the sum of the terms' moduli (|H| itself vanishes at an antiresonance)
    p, r = model.poles, model.residues
    size = (np.sum(np.abs(r) / np.abs(s[:, None] - p), axis=1)
            + np.sum(np.abs(r) / np.abs(s[:, None] - np.conj(p)), axis=1)
            + np.sum(np.abs(model.real_residues) / np.abs(s[:, None] - model.real_poles),
                     axis=1)
            + abs(model.flexibility) + abs(model.inverse_mass) / w**2)
    err = np.abs(got - want) / size
    err = np.where(np.isnan(err), np.inf, err)
    worst = int(np.argmax(err))
    if err[worst] > 1e-6:
        warnings.warn(f"to_transfer_function: the polynomials of this model's "
                      f"{np.asarray(tf.den[0][0]).size - 1} poles lose its receptance to "
                      f"rounding (relative error {err[worst]:.2g} at {w[worst]:.6g} rad/s); "
                      "to_statespace() is exact at any order", UserWarning, stacklevel=3)
    return tf
