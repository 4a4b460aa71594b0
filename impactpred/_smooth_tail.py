"""The passive minimax tail that continues a modal model above its band (``tail="smooth"``).

:func:`smooth_tail_design` solves, once per ``extend`` (a memoised pure function of its
arguments, ~1 s), the linear program behind :func:`impactpred.truncation.continue_above_band`'s
default tail: the impulse response ``G (1 - (2/pi) Si(omega_a t))`` of a continuum of
lightly damped modes above ``omega_a`` (the modes a finite band omits), fitted in the max
norm by positive terms only (a passive model), with ``h(0+) = G`` and the static
compliance ``2G/(pi omega_a)`` exact. Units: ``omega_a = G = 1``.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np
from scipy.optimize import linprog
from scipy.special import sici

__all__ = ["TailDesign", "smooth_tail_design"]


@dataclass(frozen=True)
class TailDesign:
    """A passive approximation of the omitted modes' continuum (units ``omega_a = G = 1``).

    The continuum of lightly damped modes above ``omega_a`` (modal mass ``m_k``, spacing
    ``dw``, conductance ``G = pi/(2 m_k dw)``) has the impulse response ``G (1 - (2/pi)
    Si(omega_a t))``; the design reproduces it with positive terms only. Frequencies and
    rates are in units of ``omega_a``; weights in units of ``G``.

    Attributes
    ----------
    extend : float
        Synthesized modes of the top modes' pattern run from ``omega_a`` to
        ``extend omega_a``.
    nodes, weights : tuple of float
        The synthesized modes' weight ``W(u)`` (linear between nodes ``u = omega/omega_a``;
        a mode at ``omega`` gets modal mass ``m_k / W``).
    modes : tuple of (u, zeta, c)
        Damped modes: frequency ``u omega_a``, damping ratio ``zeta``, modal mass
        ``1/(c omega_a G)``.
    poles : tuple of (s, c)
        Real poles ``c G/(p + s omega_a)`` (``p`` the Laplace variable).
    error : float
        ``max |h - G (1 - (2/pi) Si(x))| / G`` over the fitted ``0 <= x <= x_max``.
    x_max : float
        End of the fitted range of ``x = omega_a t``.
    """

    extend: float
    nodes: tuple
    weights: tuple
    modes: tuple
    poles: tuple
    error: float
    x_max: float

    def compliance(self) -> float:
        """Static compliance in units of ``G/omega_a`` (``2/pi`` by construction).

        Returns
        -------
        float
        """
        nodes, w = np.asarray(self.nodes), np.asarray(self.weights)
        return (float(np.dot(w, _hat_compliance(nodes))) if nodes.size else 0.0) + sum(
            c / u**2 for u, _, c in self.modes) + sum(c / s for s, c in self.poles)


#: damping ratios of the smooth tail's damped modes (0.05: lossless enough to ring on)
_TAIL_ZETAS = (0.05, 0.1, 0.2, 0.3, 0.5, 0.7)


def _hat_columns(x, nodes):
    """``(2/pi) int hat_i(u) sin(u x)/u du`` for the piecewise-linear basis on ``nodes``.

    Closed form per ramp: ``int_a^b (u - a) sin(ux)/u du = (cos ax - cos bx)/x
    - a (Si bx - Si ax)`` and ``int_b^c (c - u) sin(ux)/u du = c (Si cx - Si bx)
    - (cos bx - cos cx)/x``. Zero at ``x = 0``.
    """
    x = np.asarray(x, dtype=float)
    safe = np.where(x > 0, x, 1.0)
    si = {u: sici(u * x)[0] for u in nodes}
    co = {u: np.cos(u * x) for u in nodes}
    cols = []
    for i, b in enumerate(nodes):
        col = np.zeros_like(x)
        if i > 0:
            a = nodes[i - 1]
            col += ((co[a] - co[b]) / safe - a * (si[b] - si[a])) / (b - a)
        if i < len(nodes) - 1:
            c = nodes[i + 1]
            col += (c * (si[c] - si[b]) - (co[b] - co[c]) / safe) / (c - b)
        cols.append(np.where(x > 0, 2.0 / math.pi * col, 0.0))
    return np.array(cols).T


def _hat_compliance(nodes):
    """``(2/pi) int hat_i(u) / u^2 du`` for the piecewise-linear basis on ``nodes``."""
    out = np.zeros(len(nodes))
    for i, b in enumerate(nodes):
        if i > 0:
            a = nodes[i - 1]
            out[i] += (math.log(b / a) - 1.0 + a / b) / (b - a)
        if i < len(nodes) - 1:
            c = nodes[i + 1]
            out[i] += (c / b - 1.0 - math.log(c / b)) / (c - b)
    return 2.0 / math.pi * out


@functools.lru_cache(maxsize=16)
def smooth_tail_design(extend: float = 4.0, *, reach: float = 2.0, n_nodes: int = 16,
                       x_max: float = 150.0) -> TailDesign:
    """The minimax passive tail of :func:`continue_above_band` (``tail="smooth"``).

    Fits ``G (1 - (2/pi) Si(x))``, the impulse response of the modes omitted above
    ``omega_a`` (``x = omega_a t``), by a linear program in the max norm on
    ``0 <= x <= x_max`` with nonnegative weights (a passive model) over: the synthesized
    modes' weight ``W(u)`` on ``1 <= u <= extend`` (``n_nodes`` linear pieces, in the
    continuum limit), damped modes at 12 frequencies from ``extend`` to ``reach extend``
    with the damping ratios of ``_TAIL_ZETAS``, and 16 real poles from ``0.3 extend`` to
    ``4 reach extend`` (all in units of ``omega_a``). Constraints: ``h(0+) = G`` (the
    poles' residues sum to ``G``) and the static compliance ``2G/(pi omega_a)`` of the
    omitted modes. Cached per argument set (about 1 s each).

    Parameters
    ----------
    extend : float
        Top of the synthesized modes, in units of ``omega_a``; ``<= 1``: none.
    reach : float
        The damped modes and poles reach ``reach extend omega_a``, the poles 4 times
        further: the exact solver's cost grows with the highest rate used.
    n_nodes : int
        Pieces of ``W(u)``.
    x_max : float
        Fitted range of ``x = omega_a t`` (150: two transit times of a rod for up to 23
        modes; beyond, the target is below 0.5 % of ``G``).

    Returns
    -------
    TailDesign
    """
    if not (math.isfinite(extend) and extend > 0):
        raise ValueError(f"extend must be a positive finite number, got {extend!r}")
    if int(n_nodes) != n_nodes or n_nodes < 2:
        raise ValueError(f"n_nodes must be an integer >= 2, got {n_nodes!r}")
    extend = max(float(extend), 1.0)
    x = np.unique(np.concatenate([np.linspace(0.0, x_max, 2500),
                                  np.geomspace(1e-3, x_max, 800)]))
    target = 1.0 - 2.0 / math.pi * sici(x)[0]
    nodes = tuple(np.linspace(1.0, extend, n_nodes)) if extend > 1.0 + 1e-9 else ()
    cols = [_hat_columns(x, nodes)] if nodes else []
    comp = list(_hat_compliance(nodes)) if nodes else []
    at_zero = [0.0] * len(nodes)
    kinds = []
    for u in np.geomspace(extend, reach * extend, 12):
        for z in _TAIL_ZETAS:
            ud = u * math.sqrt(1.0 - z * z)
            cols.append((np.exp(-z * u * x) * np.sin(ud * x) / ud)[:, None])
            comp.append(1.0 / u**2)
            at_zero.append(0.0)
            kinds.append((float(u), z))
    rates = np.geomspace(0.3 * extend, 4.0 * reach * extend, 16)
    for r in rates:
        cols.append(np.exp(-r * x)[:, None])
        comp.append(1.0 / r)
        at_zero.append(1.0)
    A = np.hstack(cols)
    nv = A.shape[1]
    one = np.ones((x.size, 1))
    res = linprog(np.r_[np.zeros(nv), 1.0],
                  A_ub=np.vstack([np.hstack([A, -one]), np.hstack([-A, -one])]),
                  b_ub=np.r_[target, -target],
                  A_eq=np.array([at_zero + [0.0], comp + [0.0]]),
                  b_eq=np.array([1.0, 2.0 / math.pi]), bounds=[(0, None)] * (nv + 1),
                  method="highs")
    if res.status != 0:
        raise RuntimeError(f"smooth tail design failed: {res.message}")
    v = res.x
    nn, nm = len(nodes), len(kinds)
    modes = tuple((u, z, float(c)) for (u, z), c in zip(kinds, v[nn:nn + nm]) if c > 1e-9)
    poles = tuple((float(r), float(c)) for r, c in zip(rates, v[nn + nm:nv]) if c > 1e-9)
    # drop-outs below 1e-9 moved the sums slightly: renormalize h(0+) on the poles
    total = sum(c for _, c in poles)
    poles = tuple((r, c / total) for r, c in poles)
    return TailDesign(extend, tuple(float(u) for u in nodes),
                      tuple(float(w) for w in v[:nn]), modes, poles, float(v[-1]),
                      float(x_max))
