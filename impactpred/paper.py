"""The seed paper's four benchmark cases (method.md, section 3), solved and tabulated.

All cases use non-dimensional units: the struck rod's mass ``m = 1`` kg, its transit time
``T = 1`` s, approach speeds of 1 m/s. Where the paper leaves parameters open the choice
is stated in the case's description.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import pandas as pd

from data_synth import CantileverBeam, LumpedMass, Rod

from modalid.validation import as_positive_scalar

from .api import _MAX_STEPS, solve_impact
from .body import Body

__all__ = ["PaperCase", "paper_cases", "run_paper_cases", "check_paper_dt"]

#: memory (bytes) a case takes per output sample at its peak: measured 98 for the closed
#: form, 176-354 for the convolution solver (case d at dt = 1e-4 s)
BYTES_PER_SAMPLE = 360


def _bytes(n: float) -> str:
    for unit, size in (("TiB", 2.0**40), ("GiB", 2.0**30), ("MiB", 2.0**20)):
        if n >= size:
            return f"{n / size:.3g} {unit}"
    return f"{n / 2**10:.3g} KiB"


def check_paper_dt(dt, *, t_end: float = 8.0) -> None:
    """Refuse a step the paper's cases cannot take, before any of them is solved.

    Parameters
    ----------
    dt : float or None
        The step (s) asked for; None (automatic) passes.
    t_end : float, keyword-only
        The cases' end (s).

    Raises
    ------
    ValueError
        ``dt`` not positive, or finer than ``t_end / 4,000,000`` (the solvers' limit on
        steps, about 1.3 GiB per case): the message gives the samples and the memory
        (:data:`BYTES_PER_SAMPLE` per sample) it would need.
    """
    if dt is None:
        return
    dt = as_positive_scalar("dt", dt)
    n = t_end / dt
    if n > _MAX_STEPS * (1 + 1e-9):
        finest = t_end / _MAX_STEPS
        raise ValueError(f"dt={dt:.4g} s is too fine for the paper's cases: {n:.3g} samples "
                         f"per case ({t_end:g} s each) would need about "
                         f"{_bytes(n * BYTES_PER_SAMPLE)} of memory; the finest step they "
                         f"take is {finest:.4g} s ({_MAX_STEPS:,} samples, about "
                         f"{_bytes(_MAX_STEPS * BYTES_PER_SAMPLE)})")


@dataclass(frozen=True)
class PaperCase:
    """One case: a label, a description and the two bodies.

    Parameters
    ----------
    key : str
        The case's label (``"a"``, ``"b_equal_mass"``, ...).
    description : str
        One line saying what it is.
    body1, body2 : Body
        The two bodies, with their velocities.
    t_end : float
        End of the simulation (s).
    """

    key: str
    description: str
    body1: Body
    body2: Body
    t_end: float = 8.0


def paper_cases() -> list[PaperCase]:
    """The paper's Fig. 4 cases; (b) in both readings of its unstated masses.

    Returns
    -------
    list of PaperCase
        Cases ``a``, ``b_equal_mass``, ``b_equal_material``, ``c`` and ``d``.
    """
    v0 = 1.0
    return [
        PaperCase("a", "two identical free rods (T1 = T2 = 1), speeds +v0 and -v0",
                  Body(Rod(1.0, 1.0, support="free"), velocity=v0),
                  Body(Rod(1.0, 1.0, support="free"), velocity=-v0)),
        PaperCase("b_equal_mass", "free rods T2 = 0.75 T1 with equal masses (the shorter rod "
                  "is stiffer): stepped force", Body(Rod(1.0, 1.0, support="free"), velocity=v0),
                  Body(Rod(1.0, 0.75, support="free"), velocity=-v0)),
        PaperCase("b_equal_material", "free rods T2 = 0.75 T1 of the same material and "
                  "section (m2 = 0.75 m1): a plain rectangular pulse 2 T2 wide",
                  Body(Rod(1.0, 1.0, support="free"), velocity=v0),
                  Body(Rod(0.75, 0.75, support="free"), velocity=-v0)),
        PaperCase("c", "a lumped mass M = m strikes a fixed-free rod at rest",
                  Body(LumpedMass(1.0), velocity=v0), Body(Rod(1.0, 1.0, support="fixed"))),
        PaperCase("d", "a free rod (m = 1, T = 1) strikes the tip of a cantilever at rest "
                  "(beam mass 10 kg, time scale 4 s: first period 7.1 T)",
                  Body(Rod(1.0, 1.0, support="free"), velocity=v0),
                  Body(CantileverBeam(10.0, 4.0)), t_end=8.0),
    ]


def run_paper_cases(out_dir=None, *, dt=None, plot=True) -> pd.DataFrame:
    """Solve every case; write ``fig4_<key>.png`` and ``paper_cases.csv`` into ``out_dir``.

    Returns the table: duration, peak force, impulse, restitution (first contact and after
    all contacts), vibration energy share, contacts, method and step, per case. A ``dt``
    (s) the cases cannot take is refused first (:func:`check_paper_dt`).

    Parameters
    ----------
    out_dir : str or Path, optional
        Folder for the figures and the table (created if missing); None writes nothing.
    dt : float, optional, keyword-only
        Time step (s) for every case; None chooses it per case.
    plot : bool, keyword-only
        Write the figures (with ``out_dir``).

    Returns
    -------
    pandas.DataFrame
        One row per case, indexed by its key.
    """
    cases = paper_cases()
    check_paper_dt(dt, t_end=max(case.t_end for case in cases))
    rows = []
    results = {}
    for case in cases:
        res = solve_impact(case.body1, case.body2, t_end=case.t_end, dt=dt, progress=False)
        results[case.key] = res
        s = res.summary()
        rows.append({"case": case.key, "description": case.description,
                     "contact_duration_s": s["contact_duration"], "peak_force_N": s["peak_force"],
                     "impulse_Ns": s["impulse"], "restitution_first": s["restitution_first"],
                     "restitution": s["restitution"],
                     "vibration_energy_fraction": s["vibration_energy_fraction"],
                     "n_contacts": s["n_contacts"], "method": s["method"], "dt_s": s["dt"]})
    table = pd.DataFrame(rows).set_index("case")
    if out_dir is not None:
        out = Path(out_dir)
        out.mkdir(parents=True, exist_ok=True)
        table.to_csv(out / "paper_cases.csv")
        if plot:
            import matplotlib

            matplotlib.use("Agg")
            import matplotlib.pyplot as plt

            for case in paper_cases():
                fig, ax = plt.subplots(figsize=(7, 4))
                results[case.key].plot(ax=ax)
                ax.set_title(f"Fig. 4 ({case.key}): {case.description}", fontsize=8)
                fig.tight_layout()
                fig.savefig(out / f"fig4_{case.key}.png", dpi=110)
                plt.close(fig)
    return table


