"""The common-pole route of ``modalid fit`` (several files, or ``--set``): reading the
files as one :class:`modalid.FRFSet` with its driving row, and printing the mode shapes."""

from __future__ import annotations

from ._cli import read_options

__all__ = ["read_set", "print_shapes"]


def read_set(args):
    """The FRFSet of ``modalid fit FILE... [--set] [--driving-row ROW]``: every FRF of the
    files, rows in the order given, read with the reading flags (one ``--quantity``,
    ``--format``, ``--freq-start``/``--df``, ``--conjugate``, ``--negate`` for all).

    ``--driving-row`` is an output label or, when no label equals it, a row index from 0;
    without it the UFF records' DOFs decide (:func:`modalid.read_frf_set`).

    Raises
    ------
    ValueError
        ``--index`` given, complex-lines files of different lengths, one FRF only, a
        ``--driving-row`` that is neither a label nor an index, or what
        :func:`modalid.read_frf_set` refuses.
    """
    from .frf_set import FRFSet
    from .io_set import read_frf_set

    if args.index is not None:
        raise ValueError("--index picks one FRF of a file; a common-pole fit (--set, or "
                         "several files) takes every FRF of its files")
    options: dict = {}
    for path in args.file:
        for key, value in read_options(args, path).items():
            if key == "freq_hz" and "freq_hz" in options and value.size != options[key].size:
                raise ValueError(f"the complex-lines files of a set must have as many lines "
                                 f"each: {args.file[0]} has {options[key].size}, {path} "
                                 f"{value.size}")
            options[key] = value
    source = args.file if len(args.file) > 1 else args.file[0]
    row = args.driving_row
    data = read_frf_set(source, driving_point="auto" if row is None else None, **options)
    if data.n_outputs < 2:
        raise ValueError(f"{args.file[0]} holds one FRF: a common-pole fit needs several "
                         "(fit it without --set)")
    if row is not None:
        labels = [str(label) for label in data.outputs]
        if row in labels:
            index = labels.index(row)
        elif row.isascii() and row.isdigit() and int(row) < len(labels):
            index = int(row)
        else:
            raise ValueError(f"--driving-row {row} is neither an output label of the set "
                             f"({', '.join(labels)}) nor a row index from 0 to "
                             f"{len(labels) - 1}")
        data = FRFSet(data.freq_hz, data.values, quantity=data.quantity,
                      coherence=data.coherence, outputs=data.outputs, driving_point=index)
    return data


def print_shapes(fit) -> None:
    """The physical modes' shapes of a common-pole fit (``fit.mode_shapes_``), real part,
    scaled to 1 at the driving row, one line per output, and each mode's phase
    collinearity (:func:`modalid.mpc`: 1 for a real mode)."""
    import pandas as pd

    from .shapes import mpc

    shapes = fit.mode_shapes_
    frequencies = fit.report_["modes"]["frequency_hz"].to_numpy(float)
    columns = [f"{f:.6g} Hz" for f in frequencies]
    outputs = [str(label) for label in fit.model_.outputs]
    table = pd.DataFrame(shapes.real, index=outputs, columns=columns)
    if shapes.shape[1]:
        table.loc["MPC"] = mpc(shapes)
    row = outputs[fit.model_.driving_point]
    at = ("the driving point" if fit.report_["driving_row_is_driving_point"]
          else f"row {row}, not a driving point")
    with pd.option_context("display.width", 140, "display.float_format", "{:.4g}".format):
        print(f"mode shapes (real part, 1 at {at}; MPC: phase collinearity, 1 for a real "
              "mode):")
        print(table.to_string())
