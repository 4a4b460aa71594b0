"""The Cramer-Rao bound of a pole-residue fit: what the noise of an FRF allows any fit.

Run:  python benchmarks/bench_identification.py --bound-sweep   (the beam's bound over damping
      and line count)

``bench_identification.py`` prints, next to its measured errors, the errors an *efficient*
unbiased estimator (one that reaches the bound) would make on the same data. The data are
a receptance ``H(omega)`` on ``n_lines`` lines with proportional complex noise,
``H (1 + eta (n1 + i n2) / sqrt(2))``, ``n ~ N(0, 1)``: each line's real and imaginary
parts carry independent Gaussian noise of variance ``eta^2 |H|^2 / 2``.

The model is the one the benchmark's ``floor`` fit uses: the truth's first ``n_modes``
modes, each with natural frequency ``omega_n``, damping ratio ``zeta`` and complex residue
``r`` (``p = -zeta omega_n + i omega_n sqrt(1 - zeta^2)``, ``r/(s - p) + conj(r)/(s -
conj p)``), a constant flexibility and, for a free body, the rigid line ``u / s^2``. Its
Fisher information is ``F = 2 Re(J^H W J)`` with ``J`` the derivative of ``H`` with
respect to the *relative* parameters (``d omega_n / omega_n``, ``d zeta / zeta``, ``d r /
|r|`` in its real and imaginary parts, ``d u / u``, ``d flexibility / flexibility``) and
``W = 1 / (eta^2 |H|^2)``. The covariance of any unbiased estimator is at least ``F^-1``;
a maximum-likelihood fit reaches it to first order in the noise.

:func:`bound_draws` samples parameter errors from ``N(0, F^-1)`` and maps them to the
benchmark's metrics, linearised: per draw the worst relative frequency, damping and
residue errors over the band's modes, the rigid mass error and the FRF error against the
truth ``||J e|| / ||H||`` (the ``vs true`` column). A draw stands for one seed of an
efficient fit; the worst over ``n_seeds`` consecutive draws stands for one benchmark run.
Exact apart from the linearisation, which the benchmark checks by printing the floor fit's
own per-seed medians beside the bound's.
"""

from __future__ import annotations

import numpy as np

__all__ = ["bound_draws", "crb_covariance", "relative_jacobian", "runs_meeting",
           "worst_of"]


def relative_jacobian(truth, omega, n_modes):
    """``dH/dtheta`` of the floor's model at the truth, relative parameters.

    Parameters
    ----------
    truth : modalid.ModalModel
        The exact model; its first ``n_modes`` modes (by frequency), its flexibility and
        its rigid line are the parameters.
    omega : ndarray of float, shape (n_lines,)
        Angular frequencies of the lines (rad/s).
    n_modes : int
        Modes of the model: the band's and the pseudo-modes above it.

    Returns
    -------
    ndarray of complex, shape (n_lines, 4 n_modes + 1 [+ 1])
        Columns per mode: ``omega_n``, ``zeta``, ``Re r``, ``Im r`` (the last two scaled
        by ``|r|``), then the flexibility, then (free body) the inverse mass ``u``.
    """
    s = 1j * np.asarray(omega, float)
    modes = truth.modes.iloc[:n_modes]
    cols = []
    for wn, zeta, r in zip(modes["omega_n"], modes["damping_ratio"], modes["residue"]):
        root = np.sqrt(1.0 - zeta * zeta)
        p = wn * (-zeta + 1j * root)
        a, b = 1.0 / (s - p), 1.0 / (s - np.conj(p))
        for dp in (wn * (-zeta + 1j * root), zeta * wn * (-1.0 - 1j * zeta / root)):
            cols.append(r * a**2 * dp + np.conj(r) * b**2 * np.conj(dp))
        cols += [abs(r) * (a + b), 1j * abs(r) * (a - b)]
    cols.append(np.full(s.shape, abs(truth.flexibility) or 1.0, dtype=complex))
    if truth.inverse_mass > 0:
        cols.append(truth.inverse_mass / s**2)
    return np.array(cols).T


def crb_covariance(jac, exact, noise):
    """``F^-1``: the smallest covariance of the relative parameters any unbiased fit has.

    Parameters
    ----------
    jac : ndarray of complex, shape (n_lines, n_par)
        :func:`relative_jacobian`.
    exact : ndarray of complex, shape (n_lines,)
        The noise-free receptance (sets the proportional noise's variance).
    noise : float
        ``eta > 0``.

    Returns
    -------
    ndarray of float, shape (n_par, n_par)
        The inverse Fisher information, in the relative units of ``jac``'s columns.
    """
    jw = jac / (noise * np.abs(exact))[:, None]
    fisher = 2.0 * np.real(jw.conj().T @ jw)
    scale = np.sqrt(np.diag(fisher))
    return np.linalg.inv(fisher / np.outer(scale, scale)) / np.outer(scale, scale)


def bound_draws(truth, omega, exact, noise, *, n_modes, n_band, draws, rng):
    """Per draw of an efficient fit's errors, the benchmark's metrics.

    Parameters
    ----------
    truth, omega, exact, noise
        As in :func:`relative_jacobian` and :func:`crb_covariance`.
    n_modes : int
        Modes in the model (the band's and the pseudo-modes above it).
    n_band : int
        The first ``n_band`` modes are scored.
    draws : int
        Number of simulated fits (seeds).
    rng : numpy.random.Generator
        Source of the draws (fixed seed for a reproducible table).

    Returns
    -------
    dict of ndarray, each of shape (draws,)
        ``df``, ``dz``, ``dr``: worst relative errors over the band's modes; ``dM``: the
        rigid mass's (0 without a rigid body); ``nrmse``: ``||J e|| / ||H||``.
    """
    jac = relative_jacobian(truth, omega, n_modes)
    cov = crb_covariance(jac, exact, noise)
    errors = rng.multivariate_normal(np.zeros(cov.shape[0]), cov, size=draws,
                                     method="eigh")
    k = 4 * np.arange(n_band)
    rigid = truth.inverse_mass > 0
    return {
        "df": np.abs(errors[:, k]).max(axis=1),
        "dz": np.abs(errors[:, k + 1]).max(axis=1),
        "dr": np.hypot(errors[:, k + 2], errors[:, k + 3]).max(axis=1),
        "dM": np.abs(errors[:, -1]) if rigid else np.zeros(draws),
        "nrmse": np.linalg.norm(errors @ jac.T, axis=1) / np.linalg.norm(exact),
    }


def worst_of(values, n_seeds):
    """The worst of each run of ``n_seeds`` consecutive draws: one benchmark run each.

    Parameters
    ----------
    values : array_like, shape (n,)
        One metric per draw.
    n_seeds : int
        Draws per run; a last incomplete run is dropped.

    Returns
    -------
    ndarray, shape (n // n_seeds,)
    """
    values = np.asarray(values)
    n_runs = values.size // n_seeds
    return values[:n_runs * n_seeds].reshape(n_runs, n_seeds).max(axis=1)


def runs_meeting(draws, targets, n_seeds):
    """How benchmark runs of ``n_seeds`` seeds fare against ``targets``.

    Parameters
    ----------
    draws : dict of ndarray
        :func:`bound_draws`.
    targets : dict of float
        Metric name -> the value its worst over a run must stay under.
    n_seeds : int
        Seeds (draws) per run.

    Returns
    -------
    per_metric : dict of (float, float)
        Per metric of ``targets``: the median over runs of its worst, and the share of runs
        under the target.
    all_met : float
        The share of runs under every target.
    """
    worst = {k: worst_of(draws[k], n_seeds) for k in targets}
    met = {k: worst[k] < targets[k] for k in targets}
    per_metric = {k: (np.median(worst[k]), np.mean(met[k])) for k in targets}
    return per_metric, np.mean(np.all([met[k] for k in targets], axis=0))
