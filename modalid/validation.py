"""Input validation shared by ``modalid``, ``data_synth`` and ``impactpred`` (public).

Every helper raises ``TypeError`` for a value of the wrong kind and ``ValueError`` for a
value of the right kind but outside its domain, and always names the argument and the
offending value, so that a user reading the traceback knows what to fix:

* :func:`as_real_scalar`, :func:`as_positive_scalar`, :func:`as_nonnegative_scalar`:
  a finite Python float (> 0, >= 0);
* :func:`as_real_array`, :func:`as_complex_array`: a finite array (optionally of a given
  number of dimensions);
* :func:`as_choice`: one of a set of strings; :func:`as_count`: a whole number >= a
  minimum.

The other packages import these from here; ``modalid``'s own modules still use the
private ``modalid._checks`` that holds the code.
"""

from __future__ import annotations

from ._checks import (as_choice, as_complex_array, as_count, as_nonnegative_scalar,
                      as_positive_scalar, as_real_array, as_real_scalar)

__all__ = ["as_real_scalar", "as_positive_scalar", "as_nonnegative_scalar", "as_real_array",
           "as_complex_array", "as_choice", "as_count"]
