"""The response away from the contact point: a mass strikes the tip of a cantilever.

``Body(model, outputs=xi)`` asks for the motion of points at fractions ``xi`` of the
length from the struck end; on the exact beam the convolution solver gives them from
the exact transfer step responses.
"""
import matplotlib.pyplot as plt

from data_synth import CantileverBeam, LumpedMass
from impactpred import Body, solve_impact

beam = CantileverBeam(1.0, 1.0)                  # 1 kg, time scale 1 s
xi = [0.0, 0.5, 0.8]                             # tip, mid-span, near the clamp
res = solve_impact(Body(LumpedMass(0.1), velocity=1.0), Body(beam, outputs=xi), t_end=2.0)
points = res.points[1]
print(points.peaks().round(4))

fig, ax = plt.subplots()
for i, x in enumerate(xi):
    ax.plot(points.t, 1e3 * points.displacement[i], label=f"xi = {x}")
ax.set_xlabel("time (s)")
ax.set_ylabel("displacement (mm)")
ax.legend(loc="upper left")
fig.tight_layout()
