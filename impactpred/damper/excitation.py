"""Harmonic excitations of an impact damper's primary structure.

Both are ``Re(X e^{i Omega t})`` with ``Omega = 2 pi freq_hz`` (rad/s): a force on the
primary at its driving point, or (for a :class:`data_synth.SpringMass` primary only) a
prescribed displacement of its base.
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass, field

import numpy as np

from modalid.validation import as_nonnegative_scalar, as_positive_scalar, as_real_scalar

__all__ = ["HarmonicForce", "BaseExcitation"]


@dataclass(frozen=True)
class _Harmonic:
    """``amplitude * cos(2 pi freq_hz t + phase)``: the fields and helpers both share."""

    amplitude: float
    freq_hz: float
    phase: float = field(default=0.0, kw_only=True)

    def __post_init__(self):
        object.__setattr__(self, "amplitude", as_nonnegative_scalar("amplitude", self.amplitude))
        object.__setattr__(self, "freq_hz", as_positive_scalar("freq_hz", self.freq_hz))
        object.__setattr__(self, "phase", as_real_scalar("phase", self.phase))

    @property
    def omega(self) -> float:
        """Frequency ``Omega`` (rad/s)."""
        return 2.0 * math.pi * self.freq_hz

    @property
    def period(self) -> float:
        """Period (s)."""
        return 1.0 / self.freq_hz

    def with_frequency(self, freq_hz):
        """The same excitation at another frequency (Hz), validated."""
        return dataclasses.replace(self, freq_hz=freq_hz)


@dataclass(frozen=True)
class HarmonicForce(_Harmonic):
    """Force ``amplitude * cos(2 pi freq_hz t + phase)`` (N) on the primary's driving point,
    or, as ``Body(load=...)``, on a body at its contact point (along ``+y``; exact with
    ``solve_impact``'s Laplace method, sampled by the others: ``load(t)``).

    Parameters
    ----------
    amplitude : float
        Force amplitude ``F0`` (N), >= 0.
    freq_hz : float
        Forcing frequency (Hz), finite and > 0.
    phase : float, keyword-only, optional
        Phase at ``t = 0`` (rad).
    """

    def __call__(self, t):
        """The force (N) at times ``t`` (s), any shape."""
        return self.amplitude * np.cos(self.omega * np.asarray(t, dtype=float) + self.phase)


@dataclass(frozen=True)
class BaseExcitation(_Harmonic):
    """Base displacement ``amplitude * cos(2 pi freq_hz t + phase)`` (m).

    Exact for a :class:`data_synth.SpringMass` primary: its mass, in absolute coordinates,
    then feels the force ``k y_b + c y_b'`` (``c = 2 zeta sqrt(k m)``). A driving-point
    receptance alone does not contain the base transmissibility, so other primaries
    raise ``ValueError`` in :class:`~impactpred.damper.ImpactDamper`.

    Parameters
    ----------
    amplitude : float
        Base displacement amplitude (m), >= 0.
    freq_hz : float
        Frequency (Hz), finite and > 0.
    phase : float, keyword-only, optional
        Phase at ``t = 0`` (rad).
    """
