"""Spectral form of a rank-one update ``M = M_free + b r`` of an already split phase.

The stuck (rigid or linear-spring) contact phase of the exact solver is the free flight
with the contact force fed back: ``M = M_free + b r`` (``b`` where the force enters, ``r``
the force row). With the free flight split as

    (s I - M_free)^-1 = S1V diag(1 / (s - lambda_i)) In1 + S0 sum_j N^j / s^(j+1) In0,

the matrix determinant lemma gives ``det(s I - M) = det(s I - M_free) g(s)`` with the
scalar secular function

    g(s) = 1 - r (s I - M_free)^-1 b = 1 - sum_i beta_i / (s - lambda_i)
                                         - sum_j gamma_j / s^(j+1),

``beta_i = (r S1V)_i (In1 b)_i``, ``gamma_j = (r S0) N^j (In0 b)``: the non-zero eigenvalues
of ``M`` are the zeros of ``g`` (in the solver, the zeros of ``H1 + H2``, paper eq. 5).
They are the ``m + q`` roots of the polynomial ``h(s) = s^q prod_i (s - lambda_i) g(s)``
(``q``: the order of the pole of ``g`` at 0), found by the Aberth-Ehrlich simultaneous
iteration (cubic convergence, O((m + q)^2) per sweep, compiled), polished by Newton steps
on ``g`` itself. Their eigenvectors follow in closed form,

    v(mu) = (mu I - M_free)^-1 b,   w(mu) = r (mu I - M_free)^-1,   w(mu) v(mu) = g'(mu),

and the generalised null space (eigenvalue 0: constants, common rigid-body motion) from
the spectral projector ``I - V W``. A free pole repeated ``p`` times (two equal bodies)
enters ``g`` once with the summed ``beta``; the update leaves ``p - 1`` copies of it in
place, with the combinations of their free eigenvectors that the force neither drives nor
sees (deflation). Cost O(n^2 m) against O(n^3) with a large constant
for the general Schur route; every result is checked (residuals of ``g``, conjugate
pairing, eigenvalue condition numbers, the projector's rank) and ``None`` is returned
whenever a check fails, so that the caller falls back to the general decomposition.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["rank_one_split"]

#: a term of g is absent when below this fraction of its rounding scale
_ZERO_RTOL = 1e-10
#: Aberth sweeps before giving up (the general route is then taken)
_MAX_SWEEPS = 200
#: a root is polished and accepted when |g(mu)| is below this fraction of sum |terms|
_RESIDUAL_RTOL = 1e-9


@njit(cache=True, inline="always", error_model="numpy")
def _inverse(x):  # pragma: no cover - compiled
    """``1/x`` for complex ``x`` by one real division (no scaling: |x| is far from the
    overflow and underflow limits here)."""
    den = 1.0 / (x.real * x.real + x.imag * x.imag)
    return complex(x.real * den, -x.imag * den)


@njit(cache=True, error_model="numpy")
def _secular(s, lam, beta, gamma):  # pragma: no cover - compiled
    """``(g(s), g'(s), sum_i 1/(s - lambda_i))`` of the secular function."""
    g, dg, poles = 1.0 + 0j, 0j, 0j
    for i in range(lam.size):
        d = _inverse(s - lam[i])
        t = beta[i] * d
        g -= t
        dg += t * d
        poles += d
    inv = _inverse(s)
    p = inv
    for j in range(gamma.size):
        t = gamma[j] * p
        g -= t
        dg += (j + 1) * t * inv
        p *= inv
    return g, dg, poles


@njit(cache=True, error_model="numpy")
def _residual(s, lam, beta, gamma):  # pragma: no cover - compiled
    """``|g(s)| / (1 + sum |terms|)``: zero to rounding at a root."""
    g, mag = 1.0 + 0j, 1.0
    for i in range(lam.size):
        t = beta[i] * _inverse(s - lam[i])
        g -= t
        mag += np.sqrt(t.real * t.real + t.imag * t.imag)
    inv = _inverse(s)
    p = inv
    for j in range(gamma.size):
        t = gamma[j] * p
        g -= t
        mag += np.sqrt(t.real * t.real + t.imag * t.imag)
        p *= inv
    return np.sqrt(g.real * g.real + g.imag * g.imag) / mag


@njit(cache=True, error_model="numpy")
def aberth(lam, beta, gamma, q, z, max_sweeps, rtol):  # pragma: no cover - compiled
    """Zeros of ``h(s) = s^q prod(s - lambda_i) g(s)`` by the Aberth-Ehrlich iteration.

    ``z`` (complex, ``m + q``): starting points, overwritten by the roots (Gauss-Seidel
    sweeps; a root whose last correction was below ``rtol |z|``, or where ``g`` is exactly
    0, is frozen). Returns the number of sweeps done, or -1 when ``max_sweeps`` did not
    suffice or a correction was not finite.
    """
    n = z.size
    done = np.zeros(n, np.bool_)
    for sweep in range(max_sweeps):
        moved = False
        for i in range(n):
            if done[i]:
                continue
            s = z[i]
            g, dg, poles = _secular(s, lam, beta, gamma)
            if g == 0:                  # a root hit exactly (rounding): converged
                done[i] = True
                continue
            ratio = q * _inverse(s) + poles + dg * _inverse(g)          # h'/h
            newton = _inverse(ratio)
            rep = 0j
            for k in range(n):
                if k != i:
                    rep += _inverse(s - z[k])
            step = newton * _inverse(1.0 - newton * rep)
            if not (np.isfinite(step.real) and np.isfinite(step.imag)):
                return -1
            z[i] = s - step
            if abs(step) <= rtol * abs(z[i]):
                done[i] = True
            else:
                moved = True
        if not moved:
            return sweep + 1
    return -1


@njit(cache=True, error_model="numpy")
def polish(z, lam, beta, gamma, steps):  # pragma: no cover - compiled
    """Newton steps on ``g`` at each root; returns ``|g(z)| / sum |terms|`` per root."""
    res = np.empty(z.size)
    for i in range(z.size):
        s = z[i]
        for _ in range(steps):
            g, dg, _ = _secular(s, lam, beta, gamma)
            if g == 0 or dg == 0:
                break
            s = s - g * _inverse(dg)
        z[i] = s
        res[i] = _residual(s, lam, beta, gamma)
    return res


def _starting_points(lam, beta, gamma, q):
    """``m + q`` distinct starting points for :func:`aberth`.

    Near a free pole, ``g(s) ~ 1 - beta_i / (s - lambda_i) - rest_i`` with ``rest_i`` the
    other terms at ``lambda_i``: the point ``lambda_i + beta_i / (1 - rest_i)``, its move
    bounded by half the distance to the nearest other pole. For the ``q`` new roots, the
    roots of the large-``s`` truncation of ``h``.
    """
    m = lam.size
    z = []
    if m:
        diff = lam[:, None] - lam[None, :]
        np.fill_diagonal(diff, 1.0)
        rest = (beta[None, :] / diff).sum(axis=1) - beta      # the diagonal's 1 removed
        for j in range(gamma.size):
            rest += gamma[j] / lam ** (j + 1)
        with np.errstate(divide="ignore", invalid="ignore"):
            shift = beta / (1.0 - rest)
        dist = np.abs(diff)
        np.fill_diagonal(dist, np.inf)
        room = 0.5 * np.min(dist, axis=1) if m > 1 else np.abs(lam)
        room = np.minimum(room, 0.5 * np.abs(lam))
        bad = ~np.isfinite(shift)
        shift[bad] = room[bad]
        far = np.abs(shift) > room
        shift[far] *= room[far] / np.abs(shift[far])
        z.append(lam + shift)
    if q:
        # s^q - c_1 s^(q-1) - ... - c_q, c_j = sum beta lambda^(j-1) + gamma_(j-1)
        c = [np.sum(beta * lam ** (j - 1)) + (gamma[j - 1] if j - 1 < gamma.size else 0.0)
             for j in range(1, q + 1)]
        extra = np.roots(np.concatenate([[1.0], -np.asarray(c, complex)]))
        if extra.size != q or not np.all(np.isfinite(extra)) or np.any(extra == 0):
            scale = max(float(np.max(np.abs(lam))) if m else 1.0, 1e-300)
            extra = 2.0 * scale * np.exp(2j * np.pi * (np.arange(q) + 0.25) / q)
        z.append(extra.astype(complex))
    z = np.concatenate(z)
    # break exact ties (Aberth needs distinct points) by a tiny rotation
    return z * np.exp(1e-7j * (np.arange(z.size) + 1) / (z.size + 1))


def _conjugate_pairs(z, tol):
    """``z`` made exactly closed under conjugation (real roots real), or None.

    Each root in the upper half-plane is paired with the nearest conjugate of one in the
    lower; the pairing must be one-to-one and within ``1e-9`` relative.
    """
    real = np.abs(z.imag) <= tol * np.maximum(np.abs(z), 1e-300)
    upper = z[~real & (z.imag > 0)]
    lower = np.conj(z[~real & (z.imag < 0)])
    if upper.size != lower.size:
        return None
    if upper.size:
        nearest = np.argmin(np.abs(upper[:, None] - lower[None, :]), axis=1)
        if np.unique(nearest).size != upper.size or np.max(
                np.abs(upper - lower[nearest]) / np.abs(upper)) > 1e-9:
            return None
        upper = 0.5 * (upper + lower[nearest])
    return np.concatenate([z[real].real.astype(complex), upper, np.conj(upper)])


def _repeated_poles(lam):
    """Index groups (arrays, size >= 2) of equal poles (to ``1e-12`` relative), or None
    when two poles are close (within ``1e-8``) but not equal."""
    if lam.size < 2:
        return []
    dist = np.abs(lam[:, None] - lam[None, :]) / np.maximum(np.abs(lam)[:, None], 1e-300)
    np.fill_diagonal(dist, 0.0)
    if np.any((dist <= 1e-8) & (dist > 1e-12)):
        return None
    label = np.argmax(dist <= 1e-12, axis=1)           # the first equal pole's index
    labels, inverse, counts = np.unique(label, return_inverse=True, return_counts=True)
    order = np.argsort(inverse, kind="stable")
    bounds = np.cumsum(counts)[:-1]
    return [g for g in np.split(order, bounds) if g.size >= 2]


def _kept_copies(free, lam, alpha, rho, groups):
    """``(lam, V, W)`` of the free poles the update leaves in place, or None.

    A pole ``lambda`` repeated ``p`` times keeps ``p - 1`` copies: right eigenvectors
    ``S1V c`` with ``rho . c = 0`` (the force row does not see them) and left ones ``d In1``
    with ``d . alpha = 0`` (the force does not drive them), normalised to ``W V = I``. For
    pairs (``p = 2``, two equal bodies), all at once: ``c = (rho_2, -rho_1)``,
    ``d = (alpha_2, -alpha_1)``, ``d . c = beta_1 + beta_2`` (not zero: checked by the
    caller); larger groups by SVD null spaces.
    """
    pairs = np.array([g for g in groups if g.size == 2], dtype=int).reshape(-1, 2)
    lams, vs, ws = [], [], []
    if pairs.size:
        i, j = pairs[:, 0], pairs[:, 1]
        vs.append(free.s1v[:, i] * rho[j] - free.s1v[:, j] * rho[i])
        gram = alpha[j] * rho[j] + alpha[i] * rho[i]
        ws.append((free.in1[i] * alpha[j][:, None] - free.in1[j] * alpha[i][:, None])
                  / gram[:, None])
        lams.append(lam[i])
    for idx in (g for g in groups if g.size > 2):
        right = np.linalg.svd(rho[idx][None, :])[2][1:].conj().T      # (p, p-1)
        left = np.linalg.svd(alpha[idx][:, None])[0][:, 1:].conj().T  # (p-1, p)
        gram = left @ right
        if np.linalg.cond(gram) > 1e8:
            return None
        vs.append(free.s1v[:, idx] @ right)
        ws.append(np.linalg.solve(gram, left @ free.in1[idx]))
        lams.append(np.full(idx.size - 1, lam[idx[0]]))
    return np.concatenate(lams), np.concatenate(vs, axis=1), np.concatenate(ws, axis=0)


def _complete(M, mu):
    """Are ``mu`` all the non-zero eigenvalues of ``M``, each once?

    Their first two power sums must be ``trace(M)`` and ``trace(M^2)`` (the eigenvalues at
    0 add nothing), to ``1e-8`` of the sums of magnitudes: a missing root, or one found
    twice, shows there. O(n^2).
    """
    prod = M * M.T
    one = abs(np.sum(mu) - np.trace(M))
    two = abs(np.sum(mu * mu) - np.sum(prod))
    return bool(one <= 1e-8 * (np.sum(np.abs(mu)) + np.sum(np.abs(np.diag(M))))
                and two <= 1e-8 * (np.sum(np.abs(mu) ** 2) + np.sum(np.abs(prod))))


def rank_one_split(M, free, b, r, *, tol, max_cond):
    """``(nil, lam, s0, s1v, in0, in1)`` of ``M = M_free + outer(b, r)``, or None.

    Parameters
    ----------
    M : ndarray, shape (n, n)
        The updated matrix itself (for its null-space block).
    free : SpectralPhase
        The split form of ``M_free`` (n x n).
    b, r : ndarray, shape (n,)
        The update's column and row.
    tol : float
        Eigenvalues with ``|lambda| <= tol`` (1/s) count as zero (as in the general route).
    max_cond : float
        Largest eigenvalue condition number accepted.

    Returns
    -------
    The general route's tuple (see ``.spectral._split``), or None when a check fails:
    a simple free pole that the update leaves in place (``beta_i`` zero to rounding),
    repeated poles whose copies cancel, or poles close but not equal; no convergence, a
    root at zero, a residual of ``g`` above rounding, unpaired conjugates, an
    ill-conditioned eigenvalue, or a null space of the wrong rank.
    """
    n = free.n
    lam_f, k_f = free.lam, free.k
    alpha = free.in1 @ b
    rho = r @ free.s1v
    beta = rho * alpha
    beta_scale = (np.abs(r) @ np.abs(free.s1v)) * (np.abs(free.in1) @ np.abs(b))
    if lam_f.size and np.any(np.abs(beta) <= _ZERO_RTOL * beta_scale):
        return None                       # an uncoupled mode: general route
    groups = _repeated_poles(lam_f)
    if groups is None:
        return None                       # poles close but not equal: ill-conditioned
    # a pole repeated p times (two equal bodies) enters g once, with the summed beta;
    # p - 1 of its copies are left in place by the update (deflated, see _kept_copies)
    first = np.ones(lam_f.size, bool)
    lam_u, beta_u = lam_f.copy(), beta.copy()
    for idx in groups:
        first[idx[1:]] = False
        beta_u[idx[0]] = beta[idx].sum()
        if abs(beta_u[idx[0]]) <= _ZERO_RTOL * float(beta_scale[idx].sum()):
            return None                   # the copies cancel: the pole stays p times
    lam_u, beta_u = lam_u[first], beta_u[first]
    gamma = np.zeros(k_f, complex)
    q = 0
    if k_f:
        u0, r0 = free.in0 @ b, r @ free.s0
        # rounding scales of the terms: from the magnitudes they are computed from
        vec, vec_abs = u0.copy(), np.abs(free.in0) @ np.abs(b)
        r0_abs = np.abs(r) @ np.abs(free.s0)
        for j in range(k_f):
            gamma[j] = r0 @ vec
            if abs(gamma[j]) > _ZERO_RTOL * float(r0_abs @ vec_abs):
                q = j + 1
            vec, vec_abs = free.nil @ vec, np.abs(free.nil) @ vec_abs
        gamma = gamma[:q]
    m = lam_f.size + q
    k = n - m
    if lam_u.size + q == 0:
        return None
    z = _starting_points(lam_u, beta_u, gamma, q)
    if aberth(lam_u, beta_u, gamma, q, z, _MAX_SWEEPS, 1e-13) < 0:
        return None
    res = polish(z, lam_u, beta_u, gamma, 1)
    if (not (np.all(np.isfinite(z)) and np.all(res <= _RESIDUAL_RTOL))
            or np.any(np.abs(z) <= tol)):
        return None
    mu = _conjugate_pairs(z, 1e-12)
    if mu is None:
        return None
    # right and left eigenvectors in closed form, through the free split
    C = alpha[:, None] / (mu[None, :] - lam_f[:, None])            # (m_f, m)
    Cw = rho[:, None] / (mu[None, :] - lam_f[:, None])
    dg = np.sum(beta[:, None] / (mu[None, :] - lam_f[:, None]) ** 2, axis=0)
    V = free.s1v @ C
    W = (Cw.T @ free.in1)
    if k_f:
        # (mu - N)^-1 = sum_j N^j / mu^(j+1)
        Z = np.zeros((k_f, mu.size), complex)
        Zw = np.zeros((mu.size, k_f), complex)
        ones = np.ones(mu.size)
        vec, row = np.outer(free.in0 @ b, ones), np.outer(ones, r @ free.s0)
        inv = 1.0 / mu
        p = inv.copy()
        for j in range(k_f):
            Z += vec * p[None, :]
            Zw += row * p[:, None]
            if j < gamma.size:
                dg += (j + 1) * gamma[j] * p * inv
            vec, row = free.nil @ vec, row @ free.nil
            p = p * inv
        V = V + free.s0 @ Z
        W = W + Zw @ free.in0
    W = W / dg[:, None]
    if groups:
        kept = _kept_copies(free, lam_f, alpha, rho, groups)
        if kept is None:
            return None
        mu = np.concatenate([mu, kept[0]])
        V = np.concatenate([V, kept[1]], axis=1)
        W = np.concatenate([W, kept[2]], axis=0)
    if not _complete(M, mu):
        return None
    cond = np.linalg.norm(V, axis=0) * np.linalg.norm(W, axis=1)
    if not np.all(cond <= max_cond):
        return None
    if k == 0:
        return np.zeros((0, 0)), mu, np.zeros((n, 0)), V, np.zeros((0, n)), W
    # the generalised null space: the range of the spectral projector P0 = I - V W,
    # spanned by its image of the free flight's null space (checked by the rank);
    # P0 is applied as I - V (W x), O(n m k), never formed
    if k_f < k:
        return None
    u, sv, _ = np.linalg.svd(free.s0 - (V @ (W @ free.s0)).real, full_matrices=False)
    if not (sv[k - 1] > 1e-8 * sv[0] and (sv.size == k or sv[k] <= 1e-10 * sv[0])):
        return None
    s0 = u[:, :k]
    in0 = s0.T - ((s0.T @ V) @ W).real
    nil = in0 @ M @ s0
    if np.any(np.abs(np.linalg.eigvals(nil)) > tol):
        return None                      # not nilpotent: the split is not trustworthy
    return nil, mu, s0, V, in0, W
