"""Where a run of the two-sided (impact-damper) engine stands, and its output rows.

State (real, shape (n,), ``n = n_p + 3``): the primary's block-diagonal modal states
(``ModalModel.to_statespace`` layout, ``n_p`` of them), the damper mass's displacement
``y_d`` (m) and velocity ``v_d`` (m/s), and a constant 1 (carries the clearance). The
phases themselves are built by the front end (:class:`impactpred.damper._engine.Engine`).
The rows every phase samples are indexed by ``OUT_*``.
"""

from __future__ import annotations

import numpy as np

__all__ = ["EngineState"]

#: outputs sampled (rows of every phase): y_p, v_p, y_d, v_d, lam, excitation
OUT_YP, OUT_VP, OUT_YD, OUT_VD, OUT_LAM, OUT_EXC, OUT_FEQ, OUT_BV = range(8)


class EngineState:
    """Where a run stopped: enough to continue it exactly (see ``DamperResult.final_state``)."""

    __slots__ = ("time", "state", "mode", "side", "open_impact")

    def __init__(self, time, state, mode, side, open_impact):
        self.time, self.mode, self.side, self.open_impact = time, mode, side, open_impact
        state = np.array(state, dtype=float)
        state.setflags(write=False)
        self.state = state
