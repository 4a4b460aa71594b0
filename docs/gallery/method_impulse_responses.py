"""The exact impulse responses of the rods and the cantilever (m = 1 kg, T = 1 s)."""
import matplotlib.pyplot as plt
import numpy as np

from data_synth import CantileverBeam, Rod

t = np.linspace(1e-3, 8.0, 400)
fig, ax = plt.subplots()
ax.plot(t, Rod(1.0, 1.0, support="fixed").impulse_response(t), label="rod, fixed far end")
ax.plot(t, Rod(1.0, 1.0, support="free").impulse_response(t), label="rod, free far end")
ax.plot(t, CantileverBeam(1.0, 1.0).impulse_response(t), label="cantilever, at its tip")
ax.set_xlabel("time (s)")
ax.set_ylabel("impulse response h (m/(N s))")
ax.legend(loc="upper left")
fig.tight_layout()
