"""From a measured FRF file to an impact: identification, continuation, prediction.

A free rod's accelerance is "measured" (30 modes of 0.5 % damping plus 1 % noise on 600
lines up to 6 Hz: five modes in the band) and written to a CSV file; ``predict``
identifies it with ``ModalFit``, checks the band against the force's spectrum,
continues the model above its band and solves the impact of a 0.5 kg mass at 1 m/s. The
exact (continuum, undamped) rod gives the reference.
"""
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from data_synth import LumpedMass, Rod, lightly_damped, synthetic_frf
from impactpred import Body, predict, solve_impact
from modalid import write_frf

truth = lightly_damped(Rod(1.0, 1.0, support="free"), 30, 0.005)   # 1 kg, T = 1 s
freq_hz = np.linspace(0.01, 6.0, 600)
frf = synthetic_frf(truth, freq_hz, quantity="accelerance", noise=0.01, seed=0)
path = Path(tempfile.mkdtemp()) / "rod_accelerance.csv"
write_frf(path, frf)

pred = predict("mass:0.5", path, velocity1=1.0, t_end=4.0)
exact = solve_impact(Body(LumpedMass(0.5), velocity=1.0), Body(Rod(1.0, 1.0, support="free")),
                     t_end=4.0)
print(pred.fits[1].report_["verdict"], pred.continuation[1])
for name in ("restitution", "contact_duration", "peak_force"):
    print(f"{name}: {pred.figures[name]:.4g} (exact rod {exact.summary()[name]:.4g})")

fig, ax = plt.subplots()
ax.plot(exact.t, exact.force, "k", lw=2, label="exact rod")
ax.plot(pred.result.t, pred.result.force, "C1", label="identified from the FRF file")
ax.set_xlabel("time (s)")
ax.set_ylabel("contact force (N)")
ax.set_xlim(0, 2.5)
ax.legend(loc="upper right")
fig.tight_layout()
