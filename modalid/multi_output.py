"""``MultiOutputModalModel``: one input (the driving point), several outputs, shared poles.

    H_i(s) = inverse_mass_i / s**2 + flexibility_i
           + sum_k [ r_ik / (s - p_k) + conj(r_ik) / (s - conj(p_k)) ]
           + sum_j a_ij / (s - sigma_j)

for output ``i`` (m/N, ``s`` in rad/s): the receptances from a force at the driving point to
the displacements of several points. The poles belong to the structure and are shared; the
residue rows carry the mode shapes. One row is the driving point, the receptance the impact
solver uses; :meth:`row` gives any row as a :class:`~modalid.ModalModel`.
Every evaluation is a closed form: exact to rounding.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pandas as pd

from ._checks import as_choice, as_complex_array, as_real_array
from ._multi_output_json import (multi_output_fields, multi_output_payload,
                                 read_multi_output_json)
from .statespace import pole_residue_from_statespace, pole_residue_to_statespace
from .model import ModalModel, _frozen, _rebuild
from .quantities import QUANTITIES
from .receptance import modal_time_scales

__all__ = ["MultiOutputModalModel"]


def _per_output(name, value, n_outputs, *, dtype=float) -> np.ndarray:
    """A scalar broadcast to, or an array of, shape (n_outputs,)."""
    check = as_real_array if dtype is float else as_complex_array
    array = check(name, value)
    if array.ndim == 0:
        return np.full(n_outputs, array.item(), dtype=dtype)
    if array.shape != (n_outputs,):
        raise ValueError(f"{name} must be a scalar or have shape ({n_outputs},) (one value "
                         f"per output), got shape {array.shape}")
    return array


class MultiOutputModalModel:
    """Receptances (m/N) from the driving point to several outputs, with shared poles; immutable.

    Parameters
    ----------
    poles : array_like of complex, shape (n_modes,)
        One pole of each conjugate pair, ``Im p_k > 0`` (rad/s), shared by all outputs.
    residues : array_like of complex, shape (n_outputs, n_modes)
        Residue ``r_ik`` of pole ``k`` at output ``i`` (m/N * rad/s).
    real_poles : array_like of float, shape (n_real,), optional
        Real poles ``sigma_j < 0`` (rad/s).
    real_residues : array_like of float, shape (n_outputs, n_real), optional
        Their residues per output.
    inverse_mass : float or array_like, shape (n_outputs,), optional
        Rigid-body ``1/s**2`` coefficient of each output (1/kg); ``>= 0`` at the driving
        point, of any sign elsewhere (rigid rotation).
    flexibility : float or array_like, shape (n_outputs,), optional
        Constant term of each output (m/N): residual flexibility of the modes above the band.
    driving_point : int, optional
        Row of the driving point (default 0).
    outputs : sequence of str, optional
        A label per output (default ``"0"``, ``"1"``, ...); labels are unique.

    Notes
    -----
    Every output shares the states of :meth:`to_statespace`, so a force history at the
    driving point gives every output's response from one simulation.
    """

    __slots__ = ("_poles", "_residues", "_real_poles", "_real_residues", "_inverse_mass",
                 "_flexibility", "_driving_point", "_outputs")
    _poles: np.ndarray
    _residues: np.ndarray
    _real_poles: np.ndarray
    _real_residues: np.ndarray
    _inverse_mass: np.ndarray
    _flexibility: np.ndarray
    _driving_point: int
    _outputs: tuple

    def __init__(self, *, poles=(), residues=None, real_poles=(), real_residues=None,
                 inverse_mass=0.0, flexibility=0.0, driving_point=0, outputs=None):
        poles = as_complex_array("poles", poles, ndim=1)
        if residues is None:
            raise ValueError("residues is required: an array of shape (n_outputs, n_modes)")
        residues = as_complex_array("residues", residues)
        if residues.ndim != 2 or residues.shape[1] != poles.size:
            raise ValueError(f"residues must have shape (n_outputs, {poles.size}) for "
                             f"{poles.size} poles, got shape {residues.shape}")
        n_out = residues.shape[0]
        if n_out == 0:
            raise ValueError("a MultiOutputModalModel needs at least one output, got 0 rows")
        real_poles = as_real_array("real_poles", real_poles, ndim=1)
        if real_residues is None:
            real_residues = np.zeros((n_out, 0))
        real_residues = as_real_array("real_residues", real_residues)
        if real_residues.shape != (n_out, real_poles.size):
            raise ValueError(f"real_residues must have shape ({n_out}, {real_poles.size}), "
                             f"got shape {real_residues.shape}")
        inverse_mass = _per_output("inverse_mass", inverse_mass, n_out)
        flexibility = _per_output("flexibility", flexibility, n_out)
        if isinstance(driving_point, bool) or not isinstance(driving_point, (int, np.integer)):
            raise TypeError(f"driving_point must be an int row index, got {driving_point!r}")
        if not 0 <= driving_point < n_out:
            raise ValueError(f"driving_point must be a row index in [0, {n_out}), got "
                             f"{driving_point!r}")
        outputs = tuple(str(i) for i in range(n_out)) if outputs is None else outputs
        if isinstance(outputs, str) or len(outputs) != n_out:
            raise ValueError(f"outputs must be a sequence of {n_out} labels, got {outputs!r}")
        if not all(isinstance(label, str) for label in outputs):
            raise TypeError(f"outputs must be str labels, got {outputs!r}")
        if len(set(outputs)) != n_out:
            raise ValueError(f"outputs labels must be unique, got {outputs!r}")
        # The driving row is validated as a ModalModel (Im p > 0, sigma != 0); 1/M >= 0 below.
        ModalModel(poles=poles, residues=residues[driving_point], real_poles=real_poles,
                   real_residues=real_residues[driving_point],
                   inverse_mass=inverse_mass[driving_point],
                   flexibility=flexibility[driving_point])
        if inverse_mass[driving_point] < 0:
            raise ValueError(f"the driving point's inverse_mass must be >= 0 (1/M), got "
                             f"{inverse_mass[driving_point]!r}")
        for name, value in (("_poles", poles), ("_residues", residues),
                            ("_real_poles", real_poles), ("_real_residues", real_residues),
                            ("_inverse_mass", inverse_mass), ("_flexibility", flexibility)):
            object.__setattr__(self, name, _frozen(value))
        object.__setattr__(self, "_driving_point", int(driving_point))
        object.__setattr__(self, "_outputs", tuple(outputs))

    def __setattr__(self, name, value):
        raise AttributeError(f"MultiOutputModalModel is immutable: cannot set {name!r}")

    def __reduce__(self):
        """Pickle through the constructor (for process pools), never by setting attributes."""
        return (_rebuild, (type(self), self._fields()))

    def _fields(self) -> dict:
        return dict(poles=self._poles, residues=self._residues, real_poles=self._real_poles,
                    real_residues=self._real_residues, inverse_mass=self._inverse_mass,
                    flexibility=self._flexibility, driving_point=self._driving_point,
                    outputs=self._outputs)

    # ------------------------------------------------------------------ attributes
    poles = property(lambda self: self._poles, doc="Shared complex poles, Im > 0 (rad/s).")
    residues = property(lambda self: self._residues, doc="Residues, (n_outputs, n_modes).")
    real_poles = property(lambda self: self._real_poles, doc="Real poles (rad/s).")
    real_residues = property(lambda self: self._real_residues, doc="(n_outputs, n_real).")
    inverse_mass = property(lambda self: self._inverse_mass, doc="1/s^2 terms, (n_outputs,).")
    flexibility = property(lambda self: self._flexibility, doc="Constant terms, (n_outputs,).")
    driving_point = property(lambda self: self._driving_point, doc="Row of the driving point.")
    outputs = property(lambda self: self._outputs, doc="Output labels, one per row.")

    @property
    def n_outputs(self) -> int:
        """Number of outputs (rows)."""
        return int(self._residues.shape[0])

    @property
    def n_modes(self) -> int:
        """Number of complex-conjugate mode pairs."""
        return int(self._poles.size)

    # ------------------------------------------------------------------- rows
    def index(self, output) -> int:
        """Row index of ``output``: an int row index or an output label.

        Parameters
        ----------
        output : int or str
            Row index or output label.

        Returns
        -------
        int
        """
        if isinstance(output, str):
            if output not in self._outputs:
                raise ValueError(f"no output labelled {output!r}; outputs are {self._outputs}")
            return self._outputs.index(output)
        if isinstance(output, bool) or not isinstance(output, (int, np.integer)):
            raise TypeError(f"output must be a row index or a label, got {output!r}")
        if not -self.n_outputs <= output < self.n_outputs:
            raise ValueError(f"output index {output!r} is out of range for "
                             f"{self.n_outputs} outputs")
        return int(output) % self.n_outputs

    def row(self, output) -> ModalModel:
        """The receptance to one output (index or label) as a :class:`ModalModel`.

        Parameters
        ----------
        output : int or str
            Row index or output label.

        Returns
        -------
        ModalModel
        """
        i = self.index(output)
        return ModalModel(poles=self._poles, residues=self._residues[i],
                          real_poles=self._real_poles, real_residues=self._real_residues[i],
                          inverse_mass=self._inverse_mass[i], flexibility=self._flexibility[i])

    @property
    def driving(self) -> ModalModel:
        """The driving-point receptance: the model the impact solver uses."""
        return self.row(self._driving_point)

    # The receptance interface (modalid.receptance) through the driving-point row; its
    # inverse_mass and step_response are per output, so a body takes :attr:`driving`.
    is_rational = property(lambda self: True, doc="Always True: finitely many poles.")

    def elastic_flexibility(self) -> float:
        """The driving-point row's static flexibility (m/N).

        Returns
        -------
        float
        """
        return self.driving.static_flexibility()

    def time_scales(self) -> tuple:
        """The time scales of the (shared) poles (see ``ModalModel.time_scales``).

        Returns
        -------
        tuple of TimeScale
        """
        return modal_time_scales(self._poles, self._real_poles)

    def modal_form(self, n_modes=None) -> ModalModel:
        """The driving-point row (:attr:`driving`); ``n_modes`` is ignored.

        Parameters
        ----------
        n_modes : int, optional
            Ignored (the receptance interface's signature).

        Returns
        -------
        ModalModel
        """
        return self.driving

    @classmethod
    def from_rows(cls, rows, *, driving_point=0, outputs=None, rtol=1e-12):
        """Stack :class:`ModalModel` rows that share their poles (to ``rtol``).

        The rows' poles are matched to the first row's by nearest value, so their order may
        differ; a row whose poles differ raises ``ValueError`` naming it.

        Parameters
        ----------
        rows : sequence of ModalModel
            One receptance per output, with the same poles.
        driving_point : int, keyword-only
            Row of the driving point.
        outputs : sequence of str, optional, keyword-only
            Output labels.
        rtol : float, keyword-only
            Relative tolerance of the poles' match.

        Returns
        -------
        MultiOutputModalModel
        """
        rows = list(rows)
        if not rows or not all(isinstance(m, ModalModel) for m in rows):
            raise TypeError("rows must be a non-empty sequence of ModalModel")
        ref = rows[0]
        residues, real_residues = [], []
        for i, m in enumerate(rows):
            if m.n_modes != ref.n_modes or m.real_poles.size != ref.real_poles.size:
                raise ValueError(f"row {i} has {m.n_modes} modes and {m.real_poles.size} real "
                                 f"poles, row 0 has {ref.n_modes} and {ref.real_poles.size}")
            order = _match(ref.poles, m.poles, rtol, f"row {i}")
            real_order = _match(ref.real_poles, m.real_poles, rtol, f"row {i} (real poles)")
            residues.append(m.residues[order])
            real_residues.append(m.real_residues[real_order])
        return cls(poles=ref.poles, residues=np.array(residues).reshape(len(rows), -1),
                   real_poles=ref.real_poles,
                   real_residues=np.array(real_residues).reshape(len(rows), -1),
                   inverse_mass=[m.inverse_mass for m in rows],
                   flexibility=[m.flexibility for m in rows],
                   driving_point=driving_point, outputs=outputs)

    # ------------------------------------------------------------------ evaluation
    def receptance(self, s) -> np.ndarray:
        """Exact receptances (m/N) at complex ``s`` (rad/s): shape ``(n_outputs,) + s.shape``.

        A row with a rigid-body term is ``inf`` at ``s = 0``.

        Parameters
        ----------
        s : array_like of complex
            Laplace variable (rad/s), any shape.

        Returns
        -------
        numpy.ndarray of complex
            Shape ``(n_outputs,) + s.shape``.
        """
        s = as_complex_array("s", s)
        sk = s[..., None]
        out = np.zeros(s.shape + (self.n_outputs,), dtype=complex) + self._flexibility
        if self.n_modes:
            p = self._poles
            a, b = 1.0 / (sk - p), 1.0 / (sk - p.conj())
            out += a @ self._residues.T + b @ self._residues.conj().T
        if self._real_poles.size:
            out += (1.0 / (sk - self._real_poles)) @ self._real_residues.T
        out = np.moveaxis(out, -1, 0)
        if np.any(self._inverse_mass != 0):
            zero = s == 0
            with np.errstate(divide="ignore", invalid="ignore"):
                inv_s2 = 1.0 / np.where(zero, 1.0, s) ** 2
            for i in np.flatnonzero(self._inverse_mass):
                out[i] = np.where(zero, np.inf, out[i] + self._inverse_mass[i] * inv_s2)
        return out

    __call__ = receptance

    def frf(self, omega, *, quantity: str = "receptance") -> np.ndarray:
        """FRFs at ``omega`` (rad/s): shape ``(n_outputs,) + omega.shape``.

        ``quantity`` is receptance (m/N), mobility (m/(N s)) or accelerance (m/(N s^2));
        at ``omega = 0`` an accelerance row takes its finite limit ``inverse_mass_i``.

        Parameters
        ----------
        omega : array_like of float
            Angular frequencies (rad/s), any shape.
        quantity : {"receptance", "mobility", "accelerance"}, keyword-only
            What to return (m/N, m/(N s) or m/(N s^2)).

        Returns
        -------
        numpy.ndarray of complex
            Shape ``(n_outputs,) + omega.shape``.
        """
        as_choice("quantity", quantity, QUANTITIES)
        omega = as_real_array("omega", omega)
        return np.stack([self.row(i).frf(omega, quantity=quantity)
                         for i in range(self.n_outputs)])

    def impulse_response(self, t) -> np.ndarray:
        """Regular part of each output's impulse response (m/(N s)): ``(n_outputs,) + t.shape``.

        The ``flexibility_i * delta(t)`` terms are not in the samples (see
        :meth:`step_response`).

        Parameters
        ----------
        t : array_like of float
            Times (s), any shape.

        Returns
        -------
        numpy.ndarray of float
            Shape ``(n_outputs,) + t.shape``.
        """
        t = as_real_array("t", t)
        return np.stack([self.row(i).impulse_response(t) for i in range(self.n_outputs)])

    def step_response(self, t) -> np.ndarray:
        """Each output's step response (m/N): shape ``(n_outputs,) + t.shape``.

        Parameters
        ----------
        t : array_like of float
            Times (s), any shape.

        Returns
        -------
        numpy.ndarray of float
            Shape ``(n_outputs,) + t.shape``.
        """
        t = as_real_array("t", t)
        return np.stack([self.row(i).step_response(t) for i in range(self.n_outputs)])

    # ----------------------------------------------------------------- conversions
    def statespace_matrices(self):
        """Real state-space matrices ``(A, b, C, d)`` of all outputs.

        ``A`` (n, n), ``b`` (n,), ``C`` (n_outputs, n), ``d`` (n_outputs,): the same blocks
        as :meth:`ModalModel.to_statespace` (modes, real poles, rigid body), all outputs on
        the same states; the rigid block's states are the displacement and velocity per
        unit ``1/M`` (``b = [0, 1]``, ``C[i] = [inverse_mass_i, 0]``).

        Returns
        -------
        tuple of numpy.ndarray
            ``(A, b, C, d)``.
        """
        return pole_residue_to_statespace(self._poles, self._residues, self._real_poles,
                                          self._real_residues, self._inverse_mass,
                                          self._flexibility)

    def to_statespace(self):
        """One ``control.StateSpace`` with one input and ``n_outputs`` outputs (exact).

        Returns
        -------
        control.StateSpace
        """
        import control

        a, b, c, d = self.statespace_matrices()
        return control.ss(a, b[:, None], c, d[:, None], outputs=list(self._outputs),
                          inputs=["force"])

    @classmethod
    def from_control(cls, sys, *, driving_point=0, outputs=None):
        """Build from a continuous-time single-input ``control.StateSpace`` (any outputs).

        The same rules as :meth:`ModalModel.from_control` apply to every output; ``outputs``
        defaults to the system's output names.

        Parameters
        ----------
        sys : control.StateSpace
            Single input (force, N), any number of outputs (displacements, m).
        driving_point : int, keyword-only
            Row of the driving point.
        outputs : sequence of str, optional, keyword-only
            Output labels.

        Returns
        -------
        MultiOutputModalModel
        """
        import control

        if not isinstance(sys, control.StateSpace):
            raise TypeError(f"sys must be a control.StateSpace, got {type(sys).__name__}")
        if sys.ninputs != 1:
            raise ValueError(f"sys must have one input (the driving-point force), got "
                             f"{sys.ninputs}")
        if sys.dt not in (0, None):
            raise ValueError(f"sys must be continuous-time, got dt={sys.dt!r}")
        a, b, c, d = (np.asarray(m, dtype=float) for m in (sys.A, sys.B, sys.C, sys.D))
        if outputs is None:
            outputs = list(sys.output_labels)
        rows = [ModalModel(**pole_residue_from_statespace(a, b.ravel(), c[i],
                                                          float(d[i, 0]) if d.size else 0.0))
                for i in range(c.shape[0])]
        return cls._from_rows_loose(rows, driving_point=driving_point, outputs=outputs)

    @classmethod
    def _from_rows_loose(cls, rows, *, driving_point, outputs):
        """Rows from one realisation: poles equal up to the eigen-solver's rounding."""
        return cls.from_rows(rows, driving_point=driving_point, outputs=outputs, rtol=1e-8)

    # ------------------------------------------------------------------ mode shapes
    @property
    def modes(self) -> pd.DataFrame:
        """Shared modes sorted by ``omega_n``, with the driving point's modal mass.

        Columns as :attr:`ModalModel.modes` of :attr:`driving`.
        """
        return self.driving.modes

    def mode_shapes(self, *, scaling: str = "driving_point") -> np.ndarray:
        """Complex mode shapes, shape (n_outputs, n_modes), modes sorted by ``omega_n``.

        ``scaling="driving_point"``: residue rows divided by the driving point's residue
        (1 at the driving point). ``scaling="mass"``: unit modal mass,
        ``phi_d = sqrt(2 i w_d r_d)`` at the driving point and
        ``phi_i = 2 i w_d r_i / phi_d`` (real for real normal modes with ``phi_d > 0``).

        Parameters
        ----------
        scaling : {"driving_point", "mass"}, keyword-only
            The normalisation.

        Returns
        -------
        numpy.ndarray of complex, shape (n_outputs, n_modes)
        """
        as_choice("scaling", scaling, ("driving_point", "mass"))
        order = np.argsort(np.abs(self._poles), kind="stable")
        r = self._residues[:, order]
        rd = r[self._driving_point]
        if np.any(rd == 0):
            raise ValueError("a mode has a zero residue at the driving point: its shape "
                             "cannot be scaled by the driving point")
        if scaling == "driving_point":
            return r / rd
        two_i_wd = 2j * self._poles[order].imag
        phi_d = np.sqrt(two_i_wd * rd)
        return two_i_wd * r / phi_d

    # -------------------------------------------------------------------- persistence
    def to_json(self, path=None) -> str:
        """The model as a JSON text (also written to ``path`` when given); see ModalModel.

        Parameters
        ----------
        path : str or os.PathLike, optional
            A file to write the text to.

        Returns
        -------
        str
            The JSON text.
        """
        text = json.dumps(multi_output_payload(self._fields()), indent=1)
        if path is not None:
            Path(path).write_text(text)
        return text

    @classmethod
    def from_json(cls, source) -> MultiOutputModalModel:
        """Read a model written by :meth:`to_json` (a JSON text or a path); never executes it.

        Parameters
        ----------
        source : str or os.PathLike
            A JSON text, or the path of a file holding one.

        Returns
        -------
        MultiOutputModalModel
        """
        payload = read_multi_output_json(source)
        try:
            return cls(**multi_output_fields(payload))
        except (KeyError, TypeError, ValueError) as exc:
            raise ValueError(f"invalid MultiOutputModalModel JSON: {exc}") from exc

    # ------------------------------------------------------------------------ misc
    def replace(self, **changes) -> MultiOutputModalModel:
        """A copy with some constructor fields changed (validated like the constructor).

        Parameters
        ----------
        **changes
            Constructor fields (keyword arguments) and their new values.

        Returns
        -------
        MultiOutputModalModel
        """
        fields = self._fields()
        fields.update(changes)
        return MultiOutputModalModel(**fields)

    def __repr__(self) -> str:
        return (f"MultiOutputModalModel(n_outputs={self.n_outputs}, n_modes={self.n_modes}, "
                f"driving_point={self._outputs[self._driving_point]!r})")

    def __eq__(self, other) -> bool:
        if not isinstance(other, MultiOutputModalModel):
            return NotImplemented
        return (self._outputs == other._outputs
                and self._driving_point == other._driving_point
                and all(np.array_equal(getattr(self, k), getattr(other, k))
                        for k in ("_poles", "_residues", "_real_poles", "_real_residues",
                                  "_inverse_mass", "_flexibility")))

    __hash__ = None  # type: ignore[assignment]  # compared by value


def _match(reference, values, rtol, what) -> np.ndarray:
    """Indices ``order`` with ``values[order] ~ reference`` elementwise, or ValueError."""
    if reference.size == 0:
        return np.zeros(0, dtype=int)
    distance = np.abs(values[None, :] - reference[:, None])
    order = np.argmin(distance, axis=1)
    scale = np.maximum(np.abs(reference), 1e-300)
    worst = np.max(distance[np.arange(reference.size), order] / scale)
    if np.unique(order).size != order.size:
        twice = reference[np.bincount(order, minlength=values.size)[order] > 1][0]
        raise ValueError(f"{what} holds a repeated pole near {twice:.6g} rad/s that its poles "
                         "cannot be matched to one by one (two modes of one frequency, such "
                         "as two identical uncoupled oscillators): give the rows with each "
                         "pole once")
    if worst > rtol:
        raise ValueError(f"{what} does not share the poles of row 0 (relative difference "
                         f"{worst:.3g} > {rtol:g})")
    return order
