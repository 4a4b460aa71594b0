"""``ModalModel``: the pole-residue driving-point receptance every stage exchanges.

    H(s) = inverse_mass / s**2 + flexibility
         + sum_k [ r_k / (s - p_k) + conj(r_k) / (s - conj(p_k)) ]   (Im p_k > 0)
         + sum_j a_j / (s - sigma_j)                                 (sigma_j < 0)

in m/N, with ``s`` in rad/s. Every evaluation below is a closed form: exact to rounding.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from ._checks import (as_choice, as_complex_array, as_count, as_real_array, as_real_scalar)
from .quantities import QUANTITIES, receptance_to
from .statespace import (pole_residue_from_statespace, pole_residue_to_statespace,
                         quiet_polynomial_trimming, transfer_function_of)
from .receptance import modal_time_scales
from ._model_json import _FORMAT, RECEPTANCE_UNITS, _of, read_model_json, require_a_field

__all__ = ["ModalModel", "read_model_json", "RECEPTANCE_UNITS"]

def _rebuild(cls, fields):
    """Unpickling: the class's constructor with its fields (validated again)."""
    return cls(**fields)


def _frozen(array: np.ndarray) -> np.ndarray:
    array = np.array(array, copy=True)
    array.setflags(write=False)
    return array


class ModalModel:
    """Receptance (m/N) in pole-residue form, driving-point or transfer; immutable.

    Parameters
    ----------
    poles : array_like of complex, shape (n_modes,)
        One pole of each complex-conjugate pair, ``Im p_k > 0`` (rad/s); the model adds
        the conjugates itself.
    residues : array_like of complex, shape (n_modes,)
        Residue ``r_k`` of each pole in ``poles`` (m/N * rad/s).
    real_poles : array_like of float, shape (n_real,), optional
        Real poles ``sigma_j < 0`` (rad/s), e.g. overdamped terms.
    real_residues : array_like of float, shape (n_real,), optional
        Their real residues ``a_j``.
    inverse_mass : float, optional
        Rigid-body term: coefficient of ``1/s**2`` (1/kg). At a driving point it is
        ``1/M >= 0`` of a free body (0 for a grounded one); a transfer receptance may have
        a negative one (rigid rotation), which :meth:`is_passive` flags.
    flexibility : float, optional
        Constant term (m/N): the residual flexibility of modes above the model's band.

    Notes
    -----
    The object is immutable: its arrays are read-only and every method returns a new
    object. Modes are stored in the order given; :meth:`truncate` and :attr:`modes`
    sort them by undamped natural frequency ``|p_k|``.
    """

    __slots__ = ("_poles", "_residues", "_real_poles", "_real_residues",
                 "_inverse_mass", "_flexibility")
    _poles: np.ndarray
    _residues: np.ndarray
    _real_poles: np.ndarray
    _real_residues: np.ndarray
    _inverse_mass: float
    _flexibility: float

    def __init__(self, *, poles=(), residues=(), real_poles=(), real_residues=(),
                 inverse_mass=0.0, flexibility=0.0):
        poles = as_complex_array("poles", poles, ndim=1)
        residues = as_complex_array("residues", residues, ndim=1)
        real_poles = as_real_array("real_poles", real_poles, ndim=1)
        real_residues = as_real_array("real_residues", real_residues, ndim=1)
        if poles.shape != residues.shape:
            raise ValueError(f"poles and residues must have the same shape, got "
                             f"{poles.shape} and {residues.shape}")
        if real_poles.shape != real_residues.shape:
            raise ValueError(f"real_poles and real_residues must have the same shape, got "
                             f"{real_poles.shape} and {real_residues.shape}")
        if np.any(poles.imag <= 0.0):
            bad = poles[poles.imag <= 0.0][0]
            raise ValueError(f"poles must have Im p > 0 (one of each conjugate pair; real "
                             f"poles go in real_poles), got {bad!r}")
        if np.any(real_poles == 0.0):
            raise ValueError("real_poles must be non-zero: a pole at s = 0 is the rigid-body "
                             "term, give it as inverse_mass")
        object.__setattr__(self, "_poles", _frozen(poles))
        object.__setattr__(self, "_residues", _frozen(residues))
        object.__setattr__(self, "_real_poles", _frozen(real_poles))
        object.__setattr__(self, "_real_residues", _frozen(real_residues))
        object.__setattr__(self, "_inverse_mass", as_real_scalar("inverse_mass", inverse_mass))
        object.__setattr__(self, "_flexibility", as_real_scalar("flexibility", flexibility))

    def __setattr__(self, name, value):
        raise AttributeError(f"ModalModel is immutable: cannot set {name!r}")

    def __reduce__(self):
        """Pickle through the constructor (for process pools), never by setting attributes."""
        return (_rebuild, (type(self), self._fields()))

    def _fields(self) -> dict:
        return dict(poles=self._poles, residues=self._residues, real_poles=self._real_poles,
                    real_residues=self._real_residues, inverse_mass=self._inverse_mass,
                    flexibility=self._flexibility)

    # ------------------------------------------------------------------ attributes
    poles = property(lambda self: self._poles, doc="Complex poles, Im > 0 (rad/s).")
    residues = property(lambda self: self._residues, doc="Residues of ``poles``.")
    real_poles = property(lambda self: self._real_poles, doc="Real poles (rad/s).")
    real_residues = property(lambda self: self._real_residues, doc="Residues of ``real_poles``.")
    inverse_mass = property(lambda self: self._inverse_mass,
                            doc="Rigid-body 1/s**2 coefficient (1/kg): 1/M at a driving point.")
    flexibility = property(lambda self: self._flexibility, doc="Constant term (m/N).")

    @property
    def n_modes(self) -> int:
        """Number of complex-conjugate mode pairs."""
        return int(self._poles.size)

    @property
    def order(self) -> int:
        """State dimension of :meth:`to_statespace`."""
        return 2 * self.n_modes + self._real_poles.size + (2 if self._inverse_mass else 0)

    # --------------------------------------------------------------- constructors
    @classmethod
    def from_modes(cls, omega_n, damping_ratio, modal_mass, *, inverse_mass=0.0,
                   flexibility=0.0) -> ModalModel:
        """Build from real normal modes: ``sum_k 1/(m_k (s^2 + 2 zeta_k w_k s + w_k^2))``.

        Parameters
        ----------
        omega_n : array_like of float, shape (n,)
            Undamped natural frequencies (rad/s), > 0.
        damping_ratio : float or array_like, shape (n,)
            Viscous damping ratios, 0 <= zeta < 1.
        modal_mass : float or array_like, shape (n,)
            Modal masses at the driving point (kg), > 0 for a passive driving point;
            a negative one is allowed here (transfer functions) and flagged by
            :meth:`is_passive`.
        inverse_mass, flexibility : float
            As in the constructor.

        Returns
        -------
        ModalModel
        """
        omega_n = as_real_array("omega_n", omega_n)
        if omega_n.ndim > 1:
            raise ValueError(f"omega_n must be 1-D, got shape {omega_n.shape}")
        omega_n = np.atleast_1d(omega_n)
        zeta = np.atleast_1d(as_real_array("damping_ratio", damping_ratio))
        mass = np.atleast_1d(as_real_array("modal_mass", modal_mass))
        try:
            omega_n, zeta, mass = np.broadcast_arrays(omega_n, zeta, mass)
        except ValueError as exc:
            raise ValueError(f"omega_n, damping_ratio and modal_mass must have matching "
                             f"shapes, got {omega_n.shape}, {zeta.shape}, {mass.shape}") from exc
        if np.any(omega_n <= 0):
            raise ValueError(f"omega_n must be positive (a rigid-body mode goes in "
                             f"inverse_mass), got {omega_n[omega_n <= 0][0]!r}")
        if np.any((zeta < 0) | (zeta >= 1)):
            raise ValueError(f"damping_ratio must be in [0, 1) for a complex mode pair, got "
                             f"{zeta[(zeta < 0) | (zeta >= 1)][0]!r}")
        if np.any(mass == 0):
            raise ValueError("modal_mass must be non-zero, got 0.0")
        omega_d = omega_n * np.sqrt(1.0 - zeta**2)
        poles = -zeta * omega_n + 1j * omega_d
        residues = -0.5j / (mass * omega_d)
        return cls(poles=poles, residues=residues, inverse_mass=inverse_mass,
                   flexibility=flexibility)

    @classmethod
    def from_control(cls, sys) -> ModalModel:
        """Build from a SISO python-control ``StateSpace`` or ``TransferFunction``.

        The system must be continuous-time, proper, and stable in Lyapunov's sense
        (poles with ``Re p <= 0``; a double pole at 0 is the rigid-body term). A simple
        pole at 0 or one of order 3 or more, a repeated pole that is a Jordan block (two
        uncoupled equal modes are kept), an improper or MIMO system, or non-finite entries
        raise ``ValueError``.

        Parameters
        ----------
        sys : control.StateSpace or control.TransferFunction
            A SISO system from force (N) to displacement (m).

        Returns
        -------
        ModalModel
        """
        import control

        if not isinstance(sys, (control.StateSpace, control.TransferFunction)):
            raise TypeError(f"sys must be a control.StateSpace or control.TransferFunction, "
                            f"got {type(sys).__name__}")
        if sys.ninputs != 1 or sys.noutputs != 1:
            raise ValueError(f"sys must be SISO, got {sys.noutputs} outputs and "
                             f"{sys.ninputs} inputs")
        if sys.dt not in (0, None):
            raise ValueError(f"sys must be continuous-time, got dt={sys.dt!r}")
        if isinstance(sys, control.TransferFunction):
            num = np.trim_zeros(np.atleast_1d(np.squeeze(sys.num[0][0])), "f")
            den = np.trim_zeros(np.atleast_1d(np.squeeze(sys.den[0][0])), "f")
            if num.size > den.size:
                raise ValueError(f"sys is improper: numerator degree {num.size - 1} exceeds "
                                 f"denominator degree {den.size - 1}")
            with quiet_polynomial_trimming():
                sys = control.ss(sys)
        a, b, c, d = (np.asarray(m, dtype=float) for m in (sys.A, sys.B, sys.C, sys.D))
        if not all(np.isfinite(m).all() for m in (a, b, c, d)):
            raise ValueError("sys has NaN or infinite entries in its A, B, C or D")
        parts = pole_residue_from_statespace(a, b.ravel(), c.ravel(), float(d.ravel()[0])
                                             if d.size else 0.0)
        return cls(**parts)

    # ----------------------------------------------------------------- evaluation
    def receptance(self, s) -> np.ndarray:
        """Exact receptance ``H(s)`` (m/N) at complex ``s`` (rad/s), any shape.

        ``H(0)`` of a free body is ``inf`` (its rigid-body term), never ``nan``.

        Parameters
        ----------
        s : array_like of complex
            Laplace variable (rad/s), any shape.

        Returns
        -------
        numpy.ndarray of complex
            Same shape as ``s``.
        """
        s = as_complex_array("s", s)
        out = np.full(s.shape, self._flexibility, dtype=complex)
        if self.n_modes:
            p, r = self._poles, self._residues
            sk = s[..., None]
            out += np.sum(r / (sk - p) + r.conj() / (sk - p.conj()), axis=-1)
        if self._real_poles.size:
            out += np.sum(self._real_residues / (s[..., None] - self._real_poles), axis=-1)
        if self._inverse_mass:
            zero = s == 0
            with np.errstate(divide="ignore", invalid="ignore"):
                rigid = self._inverse_mass / np.where(zero, 1.0, s) ** 2
            out = np.where(zero, np.inf, out + rigid)
        return out

    __call__ = receptance

    def frf(self, omega, *, quantity: str = "receptance") -> np.ndarray:
        """FRF at angular frequencies ``omega`` (rad/s) as receptance, mobility or accelerance.

        The accelerance of a free body at ``omega = 0`` is its finite limit ``inverse_mass``.

        Parameters
        ----------
        omega : array_like of float
            Angular frequencies (rad/s), any shape.
        quantity : {"receptance", "mobility", "accelerance"}, keyword-only
            What to return (m/N, m/(N s) or m/(N s^2)).

        Returns
        -------
        numpy.ndarray of complex
            Same shape as ``omega``.
        """
        as_choice("quantity", quantity, QUANTITIES)
        omega = as_real_array("omega", omega)
        if quantity == "accelerance" and self._inverse_mass:
            elastic = self.without_rigid_body().receptance(1j * omega)
            return receptance_to(quantity, elastic, omega) + self._inverse_mass
        return receptance_to(quantity, self.receptance(1j * omega), omega)

    def impulse_response(self, t) -> np.ndarray:
        """Regular part of the impulse response ``h(t)`` (m/(N s)) at times ``t`` (s).

        ``h = inverse_mass * t + sum 2 Re(r_k exp(p_k t)) + sum a_j exp(sigma_j t)`` for
        ``t >= 0`` and 0 for ``t < 0``. The flexibility term adds ``flexibility * delta(t)``,
        which is not in the returned samples (it is in :meth:`step_response`).

        Parameters
        ----------
        t : array_like of float
            Times (s), any shape.

        Returns
        -------
        numpy.ndarray of float
            Same shape as ``t``.
        """
        t = as_real_array("t", t)
        tk = t[..., None]
        out = self._inverse_mass * t
        if self.n_modes:
            out = out + 2.0 * np.sum((self._residues * np.exp(self._poles * tk)).real, axis=-1)
        if self._real_poles.size:
            out = out + np.sum(self._real_residues * np.exp(self._real_poles * tk), axis=-1)
        return np.where(t >= 0, out, 0.0)

    def step_response(self, t) -> np.ndarray:
        """Step response ``S(t) = flexibility + integral_0^t h`` (m/N) for ``t >= 0``, 0 before.

        Parameters
        ----------
        t : array_like of float
            Times (s), any shape.

        Returns
        -------
        numpy.ndarray of float
            Same shape as ``t``.
        """
        t = as_real_array("t", t)
        tk = t[..., None]
        out = self._flexibility + 0.5 * self._inverse_mass * t**2
        if self.n_modes:
            p, r = self._poles, self._residues
            out = out + 2.0 * np.sum((r / p * np.expm1(p * tk)).real, axis=-1)
        if self._real_poles.size:
            sig, a = self._real_poles, self._real_residues
            out = out + np.sum(a / sig * np.expm1(sig * tk), axis=-1)
        return np.where(t >= 0, out, 0.0)

    def static_flexibility(self) -> float:
        """Elastic flexibility at ``s = 0`` (m/N): ``H(0)`` less the rigid-body term.

        Returns
        -------
        float
        """
        value = self._flexibility - 2.0 * np.sum((self._residues / self._poles).real)
        return float(value - np.sum(self._real_residues / self._real_poles))

    # ------------------------------------------------- receptance interface (.receptance)
    is_rational = property(lambda self: True, doc="Always True: finitely many poles.")

    def elastic_flexibility(self) -> float:
        """:meth:`static_flexibility` (m/N), under the receptance interface's name.

        Returns
        -------
        float
        """
        return self.static_flexibility()

    def time_scales(self) -> tuple:
        """``(TimeScale(1/|p|max, "modal"),)`` of the fastest pole, ``()`` without poles.

        Returns
        -------
        tuple of TimeScale
        """
        return modal_time_scales(self._poles, self._real_poles)

    def modal_form(self, n_modes=None) -> ModalModel:
        """The model itself (it is its own pole-residue form; ``n_modes`` is ignored).

        Parameters
        ----------
        n_modes : int, optional
            Ignored (the receptance interface's signature).

        Returns
        -------
        ModalModel
            ``self``.
        """
        return self

    # ----------------------------------------------------------------- conversions
    def to_statespace(self):
        """Real block-diagonal ``control.StateSpace`` with the same receptance.

        Blocks, in order: one ``[[Re p, -Im p], [Im p, Re p]]`` per complex mode (state
        ``z = x1 + i x2`` with ``z' = p z + u`` and output ``2 Re(r z)``), one ``sigma_j``
        per real pole, then ``[[0, 1], [0, 0]]`` for the rigid body (states: rigid
        displacement in m and velocity in m/s, ``B = [0, inverse_mass]``).
        ``D = flexibility``.

        Returns
        -------
        control.StateSpace
        """
        import control

        a, b, c, d = pole_residue_to_statespace(
            self._poles, self._residues, self._real_poles, self._real_residues,
            self._inverse_mass, self._flexibility)
        return control.ss(a, b[:, None], c[None, :], [[d]])

    def to_transfer_function(self):
        """``control.TransferFunction`` (low orders only: polynomials lose poles at high order).

        Returns
        -------
        control.TransferFunction

        Warns
        -----
        UserWarning
            Where the polynomials lose the receptance (over ``1e-6`` relative: a fixed
            rod's 20 modes): :meth:`to_statespace` is exact at any order.
        """
        return transfer_function_of(self)

    # -------------------------------------------------------------------- persistence
    def to_json(self, path=None) -> str:
        """The model as a JSON text (also written to ``path`` when given).

        Complex numbers are stored as ``[re, im]`` pairs; units are SI with s in rad/s.

        Parameters
        ----------
        path : str or os.PathLike, optional
            A file to write the text to.

        Returns
        -------
        str
            The JSON text.
        """
        payload = {
            "format": _FORMAT, "version": 1,
            "units": {"s": "rad/s", "receptance": "m/N"},
            "poles": [[float(p.real), float(p.imag)] for p in self._poles],
            "residues": [[float(r.real), float(r.imag)] for r in self._residues],
            "real_poles": [float(x) for x in self._real_poles],
            "real_residues": [float(x) for x in self._real_residues],
            "inverse_mass": self._inverse_mass, "flexibility": self._flexibility,
        }
        text = json.dumps(payload, indent=1)
        if path is not None:
            Path(path).write_text(text)
        return text

    @classmethod
    def from_json(cls, source) -> ModalModel:
        """Read a model written by :meth:`to_json`: a JSON text or the path of a file.

        Parsing JSON never executes anything; every field is validated by the constructor.
        A ``units`` field other than SI is honoured where known (see
        :func:`read_model_json`) and refused otherwise; errors name the file.

        Parameters
        ----------
        source : str or os.PathLike
            A JSON text, or the path of a file holding one.

        Returns
        -------
        ModalModel
        """
        payload, label = read_model_json(source, formats=(_FORMAT,))
        return cls._from_payload(payload, label)

    @classmethod
    def _from_payload(cls, payload: dict, label: str) -> ModalModel:
        """The model of a :func:`read_model_json` payload (SI units) read from ``label``."""
        def pairs(name):
            values = np.asarray(payload.get(name, []), dtype=float).reshape(-1, 2)
            return values[:, 0] + 1j * values[:, 1]
        require_a_field(payload, ("poles", "residues", "real_poles", "real_residues",
                                  "inverse_mass", "flexibility"),
                        f"the ModalModel JSON{_of(label)}")
        try:
            return cls(poles=pairs("poles"), residues=pairs("residues"),
                       real_poles=payload.get("real_poles", []),
                       real_residues=payload.get("real_residues", []),
                       inverse_mass=payload.get("inverse_mass", 0.0),
                       flexibility=payload.get("flexibility", 0.0))
        except (TypeError, ValueError) as exc:
            raise ValueError(f"invalid ModalModel JSON{_of(label)}: {exc}") from exc

    # ------------------------------------------------------------------- modes etc.
    @property
    def modes(self) -> pd.DataFrame:
        """Table of complex modes sorted by ``omega_n``.

        Columns: ``frequency_hz``, ``omega_n`` (rad/s, ``|p|``), ``damping_ratio``
        (``-Re p/|p|``), ``residue``, ``modal_mass`` (kg, ``-1/(2 Im(p) Im(r))``: exact
        for real normal modes, the projection of a complex residue otherwise).
        """
        order = np.argsort(np.abs(self._poles), kind="stable")
        p, r = self._poles[order], self._residues[order]
        omega_n = np.abs(p)
        with np.errstate(divide="ignore"):
            modal_mass = -1.0 / (2.0 * p.imag * r.imag)
        return pd.DataFrame({"frequency_hz": omega_n / (2 * np.pi), "omega_n": omega_n,
                             "damping_ratio": 0.0 - p.real / omega_n, "residue": r,
                             "modal_mass": modal_mass})

    def truncate(self, n: int, *, residual: bool = False) -> ModalModel:
        """Keep the ``n`` lowest complex modes (by ``|p|``); real poles and rigid terms stay.

        With ``residual=True`` the dropped modes' static flexibility ``-2 Re(r/p)`` is added
        to ``flexibility``, so the static flexibility is unchanged.

        Parameters
        ----------
        n : int
            Complex modes to keep.
        residual : bool, keyword-only
            Add the dropped modes' static flexibility.

        Returns
        -------
        ModalModel
        """
        n = as_count("n", n)
        order = np.argsort(np.abs(self._poles), kind="stable")
        keep, drop = order[:n], order[n:]
        flexibility = self._flexibility
        if residual and drop.size:
            flexibility -= 2.0 * float(np.sum((self._residues[drop] / self._poles[drop]).real))
        return self.replace(poles=self._poles[keep], residues=self._residues[keep],
                             flexibility=flexibility)

    def without_rigid_body(self) -> ModalModel:
        """The same model with ``inverse_mass = 0``.

        Returns
        -------
        ModalModel
        """
        return self.replace(inverse_mass=0.0)

    def is_stable(self) -> bool:
        """True when no pole lies in the open right half-plane and real poles are negative.

        Undamped modes (``Re p = 0``) count as stable (Lyapunov), as the rigid-body
        double pole at 0 does for a free body.

        Returns
        -------
        bool
        """
        return bool(np.all(self._poles.real <= 0) and np.all(self._real_poles < 0))

    def is_passive(self) -> bool:
        """Driving-point passivity: positive modal masses and non-negative other terms.

        Checks every modal mass > 0, ``inverse_mass >= 0``, ``flexibility >= 0`` and real
        residues >= 0 (each real-pole term then has a positive-real mobility).

        Returns
        -------
        bool
        """
        modal_mass = self.modes["modal_mass"].to_numpy()
        return bool(self.is_stable() and np.all(modal_mass > 0) and self._flexibility >= 0
                    and self._inverse_mass >= 0 and np.all(self._real_residues >= 0))

    def replace(self, **changes) -> ModalModel:
        """A copy with some constructor fields changed (validated like the constructor).

        Parameters
        ----------
        **changes
            Constructor fields (keyword arguments) and their new values.

        Returns
        -------
        ModalModel
        """
        fields = self._fields()
        fields.update(changes)
        return ModalModel(**fields)

    def __repr__(self) -> str:
        return (f"ModalModel(n_modes={self.n_modes}, n_real={self._real_poles.size}, "
                f"inverse_mass={self._inverse_mass:.6g}, flexibility={self._flexibility:.6g})")

    def __eq__(self, other) -> bool:
        if not isinstance(other, ModalModel):
            return NotImplemented
        return (np.array_equal(self._poles, other._poles)
                and np.array_equal(self._residues, other._residues)
                and np.array_equal(self._real_poles, other._real_poles)
                and np.array_equal(self._real_residues, other._real_residues)
                and self._inverse_mass == other._inverse_mass
                and self._flexibility == other._flexibility)

    __hash__ = None  # type: ignore[assignment]  # mutable-free but compared by value
