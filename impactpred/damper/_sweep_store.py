"""The store of a resumable :func:`~impactpred.damper.sweep.sweep`: one CSV row per finished run.

Format (a text file, UTF-8, readable with ``pandas.read_csv(path, comment="#")``):

* line 1, ``# impactpred sweep store v1 {json}``: what the rows belong to; the JSON holds
  ``axes`` (the swept axes, in grid order), ``n_cycles`` and ``damper_sha256`` (the
  SHA-256 of the base damper's ``repr`` printed with every digit of its arrays). A resume
  with another damper, ``n_cycles`` or set of axes is refused (``ValueError``): its rows
  would not be this study's;
* line 2: the column names, the axes then the result columns
  (:data:`~impactpred.damper.sweep.RESULT_COLUMNS`);
* one line per finished combination, in the order they finished: floats written with
  ``repr`` (shortest exact round trip: a resumed table is bit-identical), ``is_steady`` as
  ``True``/``False``, a missing ``steady_state_cycle`` as an empty field.

Rows are appended as each task's runs come back, flushed and synced to disk, one write
per task. A last line cut short by a kill (no final newline) is dropped on resume, and
its combinations run again; a combination present twice (never written so by
:func:`sweep`) keeps its first row. Combinations of the store not in the grid are kept in
the file and left out of the table (a grid can be widened and resumed).
One sweep at a time per store: two writers would interleave their lines.
"""

from __future__ import annotations

import hashlib
import json
import os
import sys
from pathlib import Path

import numpy as np

MAGIC = "# impactpred sweep store v1 "


def damper_digest(damper) -> str:
    """SHA-256 of ``repr(damper)`` with arrays printed in full, to 17 digits."""
    with np.printoptions(precision=17, threshold=sys.maxsize, floatmode="maxprec"):
        text = repr(damper)
    return hashlib.sha256(text.encode()).hexdigest()


def _cell(value) -> str:
    if value is None:
        return ""
    if isinstance(value, (bool, np.bool_)):
        return "True" if value else "False"
    if isinstance(value, (int, np.integer)):
        return str(int(value))
    return repr(float(value))


class SweepStore:
    """An open store at ``path`` for a sweep of ``axes`` (see the module's docstring)."""

    def __init__(self, path, *, axes, result_columns, n_cycles, damper):
        self.path = Path(os.fspath(path))
        self.axes = list(axes)
        self.columns = self.axes + list(result_columns)
        self.meta = {"axes": self.axes, "n_cycles": int(n_cycles),
                     "damper_sha256": damper_digest(damper)}

    def open(self) -> dict:
        """Create the store, or read it: ``{axis values (tuple of float): row (tuple)}``."""
        if self.path.is_dir():
            raise ValueError(f"store {self.path} is a directory, not a file")
        if not self.path.exists() or self.path.stat().st_size == 0:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            with open(self.path, "w", encoding="utf-8", newline="") as f:
                f.write(MAGIC + json.dumps(self.meta, sort_keys=True) + "\n")
                f.write(",".join(self.columns) + "\n")
                f.flush()
                os.fsync(f.fileno())
            return {}
        text = self.path.read_text(encoding="utf-8")
        if not text.endswith("\n"):          # a line cut short by a kill: drop it
            keep = text.rfind("\n") + 1
            with open(self.path, "r+", encoding="utf-8", newline="") as f:
                f.truncate(len(text[:keep].encode("utf-8")))
            text = text[:keep]
        lines = text.split("\n")[:-1]
        if not lines or not lines[0].startswith(MAGIC):
            raise ValueError(f"store {self.path} is not a sweep store (its first line does "
                             f"not start with {MAGIC.strip()!r}); give a new path")
        try:
            meta = json.loads(lines[0][len(MAGIC):])
        except json.JSONDecodeError as exc:
            raise ValueError(f"store {self.path}: unreadable first line ({exc})") from exc
        for key in ("axes", "n_cycles", "damper_sha256"):
            if meta.get(key) != self.meta[key]:
                what = {"damper_sha256": "another base damper"}.get(
                    key, f"{key}={meta.get(key)!r}")
                raise ValueError(f"store {self.path} holds a sweep with {what}, not this "
                                 f"one ({key}={self.meta[key]!r}); give a new path to start "
                                 "another study")
        if len(lines) < 2 or lines[1].split(",") != self.columns:
            raise ValueError(f"store {self.path}: its column line is not {self.columns}")
        done = {}
        n_axes = len(self.axes)
        for number, line in enumerate(lines[2:], start=3):
            fields = line.split(",")
            if len(fields) != len(self.columns):
                raise ValueError(f"store {self.path}, line {number}: {len(fields)} fields, "
                                 f"expected {len(self.columns)}")
            try:
                key = tuple(float(v) for v in fields[:n_axes])
                row = _row(fields[n_axes:])
            except ValueError as exc:
                raise ValueError(f"store {self.path}, line {number}: {exc}") from exc
            done.setdefault(key, row)
        return done

    def append(self, pairs) -> None:
        """Write ``[(combination dict, row tuple), ...]`` in one write, flushed and synced."""
        text = "".join(",".join([_cell(combination[a]) for a in self.axes]
                                + [_cell(v) for v in row]) + "\n"
                       for combination, row in pairs)
        if not text:
            return
        with open(self.path, "a", encoding="utf-8", newline="") as f:
            f.write(text)
            f.flush()
            os.fsync(f.fileno())


def _row(fields):
    """A stored row back as the tuple :func:`sweep` builds (floats, a bool, an int or None)."""
    amplitude, reduction, impacts, power, steady, cycle, without = fields
    if steady not in ("True", "False"):
        raise ValueError(f"is_steady must be True or False, got {steady!r}")
    return (float(amplitude), float(reduction), float(impacts), float(power),
            steady == "True", None if cycle == "" else int(cycle), float(without))
