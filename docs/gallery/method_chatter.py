"""A mass on a fixed rod: the restitution of truncated modal models under rigid contact,
without and with the residual flexibility, against the exact rod."""
import matplotlib.pyplot as plt

from data_synth import LumpedMass, Rod
from impactpred import Body, solve_impact

rod = Rod(1.0, 1.0, support="fixed")
striker = Body(LumpedMass(1.0), velocity=1.0)
modes = [5, 10, 20, 40, 80]
fig, ax = plt.subplots()
for residual, label in [(False, "modes only"), (True, "modes + residual flexibility")]:
    runs = [solve_impact(striker, Body(rod.modal_model(n, residual=residual)), t_end=3.5)
            for n in modes]
    ax.plot(modes, [r.restitution for r in runs], "o-",
            label=f"{label} (contacts: {', '.join(str(len(r.contact_intervals)) for r in runs)})")
exact = solve_impact(striker, Body(rod), t_end=3.5)
ax.axhline(exact.restitution, color="k", lw=1, label=f"exact rod: e = {exact.restitution:.4f}")
ax.set_xscale("log")
ax.minorticks_off()
ax.set_xticks(modes, [str(n) for n in modes])
ax.set_xlabel("modes of the rod's model")
ax.set_ylabel("restitution after the first contact")
ax.legend(loc="lower right", fontsize=8)
fig.tight_layout()
