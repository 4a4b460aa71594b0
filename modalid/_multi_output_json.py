"""The JSON a :class:`modalid.MultiOutputModalModel` is written to and read from (its
:meth:`~modalid.MultiOutputModalModel.to_json` and ``from_json``): complex numbers as
``[re, im]`` pairs, SI units (rad/s, m/N). Reading never executes anything
(``json.loads``).
"""

from __future__ import annotations

import numpy as np

from ._model_json import _json_text, parse_json, require_a_field

__all__ = ["FORMAT", "multi_output_fields", "multi_output_payload", "read_multi_output_json"]

FORMAT = "modalid.MultiOutputModalModel"


def _pairs(z) -> list:
    return [[float(v.real), float(v.imag)] for v in np.ravel(z)]


def multi_output_payload(fields: dict) -> dict:
    """The JSON object of a model's constructor ``fields`` (validated arrays)."""
    return {
        "format": FORMAT, "version": 1, "units": {"s": "rad/s", "receptance": "m/N"},
        "outputs": list(fields["outputs"]), "driving_point": fields["driving_point"],
        "poles": _pairs(fields["poles"]),
        "residues": [_pairs(row) for row in fields["residues"]],
        "real_poles": np.asarray(fields["real_poles"]).tolist(),
        "real_residues": np.asarray(fields["real_residues"]).tolist(),
        "inverse_mass": np.asarray(fields["inverse_mass"]).tolist(),
        "flexibility": np.asarray(fields["flexibility"]).tolist(),
    }


def read_multi_output_json(source) -> dict:
    """The JSON object of ``source`` (a JSON text or a path), refused (``ValueError``)
    unless it is JSON whose ``format`` is :data:`FORMAT`."""
    text, _ = _json_text(source)          # a file read and refused as a model's is
    payload = parse_json(text, "not a MultiOutputModalModel JSON text")
    if not isinstance(payload, dict) or payload.get("format") != FORMAT:
        raise ValueError(f"not a MultiOutputModalModel JSON text: 'format' is not {FORMAT!r}")
    return payload


def multi_output_fields(payload: dict) -> dict:
    """The constructor's keyword arguments from a JSON object (``KeyError``,
    ``TypeError`` or ``ValueError`` where a field is missing or malformed)."""

    def complex_array(values):
        values = np.asarray(values, dtype=float)
        return values[..., 0] + 1j * values[..., 1]

    require_a_field(payload, ("poles", "real_poles", "inverse_mass", "flexibility"),
                    "it")
    n_out = len(payload["outputs"])
    poles = complex_array(np.reshape(payload.get("poles", []), (-1, 2)))
    residues = complex_array(np.reshape(payload["residues"], (n_out, poles.size, 2)))
    return dict(poles=poles, residues=residues, real_poles=payload.get("real_poles", []),
                real_residues=np.reshape(payload.get("real_residues", []), (n_out, -1)),
                inverse_mass=payload.get("inverse_mass", 0.0),
                flexibility=payload.get("flexibility", 0.0),
                driving_point=payload.get("driving_point", 0), outputs=payload["outputs"])
