"""ModalFit on random bands of the real files, with random options: nothing may break.

Run:  python benchmarks/random_bands.py [--seed 0] [--fits 40]

Per file of ``real_data.py`` (and pyuff's three points as a set), ``--fits`` fits of
``ModalFit`` on a random band (log-uniform width from three lines to the whole file, at
a random place; one in ten with no band: the automatic one) with, at random, another
weighting, ``missed_modes="dense"``, ``passive=False``, ``n_modes``, ``rigid_body`` or
``method``. A fit must return finite frequencies and damping ratios or refuse with a
documented ``ValueError`` (a band too narrow or empty, vector fitting asked of a set);
anything else (an exception from inside numpy or scipy, a non-finite parameter) is a
failure and is printed with its options, so that it can be replayed.

It asserts nothing and always exits 0. Three failures it found, each mended with a
test: a refinement through coinciding poles ("SVD did not converge"), the global
estimator's singular normal matrix on a narrow band ("Singular matrix") and vector
fitting on fewer lines than unknowns ("expected square matrix").
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

#: the refusals the documentation promises (ValueError messages)
DOCUMENTED = ("no usable band", "empty band", "does not fit an FRFSet")


def random_options(rng, freq_hz):
    """One random set of ``ModalFit`` options for data on ``freq_hz`` (Hz)."""
    df = freq_hz[1] - freq_hz[0]
    width = float(np.exp(rng.uniform(np.log(3 * df), np.log(freq_hz[-1] - freq_hz[1]))))
    lo = float(rng.uniform(freq_hz[0], max(freq_hz[-1] - width, freq_hz[0] + df)))
    options = {"freq_range": (lo, min(lo + width, float(freq_hz[-1])))}
    r = rng.uniform()
    if r < 0.1:
        options.pop("freq_range")
    elif r < 0.2:
        options["weighting"] = str(rng.choice(["relative", "noise", "mixed", "uniform"]))
    elif r < 0.3:
        options["missed_modes"] = "dense"
    elif r < 0.4:
        options["passive"] = False
    elif r < 0.5:
        options["n_modes"] = int(rng.integers(1, 6))
    elif r < 0.55:
        options["rigid_body"] = bool(rng.integers(0, 2))
    elif r < 0.6:
        options["method"] = str(rng.choice(["vf", "lscf"]))
    return options


def one_fit(data, options):
    """``None`` if the fit is sound or refused as documented, else what went wrong."""
    from modalid import ModalFit

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fit = ModalFit(**options).fit(data)
    except ValueError as exc:
        return None if any(d in str(exc) for d in DOCUMENTED) else f"ValueError: {exc}"
    except Exception as exc:                      # noqa: BLE001 - every other is a failure
        return f"{type(exc).__name__}: {exc}"
    modes = fit.report_["modes"][["frequency_hz", "damping_ratio"]].to_numpy(float)
    return None if np.all(np.isfinite(modes)) else "a non-finite frequency or damping"


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--fits", type=int, default=40, help="fits per file")
    args = parser.parse_args(argv)
    import real_data
    from modalid import FRFSet

    names = [n for n in real_data.FILES
             if not (n.startswith("pyfrf") and not real_data.SHARED.exists())]
    files = {n: real_data.load(n) for n in names}
    rows = [files[f"pyuff point {k}"] for k in (1, 2, 3)]
    files["pyuff set"] = FRFSet(rows[0].freq_hz, np.array([r.values for r in rows]),
                                quantity="accelerance", driving_point=0)
    rng = np.random.default_rng(args.seed)
    t0, failures, count = time.perf_counter(), 0, 0
    for name, data in files.items():
        for _ in range(args.fits):
            options = random_options(rng, data.freq_hz)
            problem = one_fit(data, options)
            count += 1
            if problem is not None:
                failures += 1
                print(f"FAILED {name} {options}: {problem[:200]}")
    print(f"{count} fits of {len(files)} files (seed {args.seed}): {failures} failures, "
          f"{time.perf_counter() - t0:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
