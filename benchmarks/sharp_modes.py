"""Modes narrower than their frequency lines: found, and their standard deviations calibrated.

Run:  python benchmarks/sharp_modes.py [--seeds 20]

Three modes (100.13, 163.37 and 251.71 Hz, modal masses 1, 2 and 1.5 kg) of one damping
ratio, 2e-4, 1e-3 or 5e-3 (half-power widths of 0.08, 0.4 and 2 lines at 100 Hz), as
accelerance on 600 lines of 0.5 Hz, with noise proportional to the FRF
(``H (1 + eta (n1 + i n2) / sqrt(2))``, ``eta`` 1 % and 5 %, seeds 0 .. seeds-1), each
fitted by ``ModalFit()`` with no options. Per setting it prints how many of the modes
were found (within 1 Hz), and the rms over modes and seeds of the frequency error and of
the relative damping error, each over the standard deviation the fit reported for it: a
ratio near 1 means calibrated standard deviations, above 1 optimistic ones.

It asserts nothing and always exits 0; ``tests/test_modalid_fit.py::
test_modes_narrower_than_a_line_are_found_from_their_peaks`` asserts the finding.
"""

from __future__ import annotations

import sys
import time
import warnings

import numpy as np

from modalid import FRFData, ModalFit, ModalModel

FREQ_HZ = np.arange(1, 601) * 0.5
MODES_HZ = np.array([100.13, 163.37, 251.71])
MASSES = [1.0, 2.0, 1.5]


def one_setting(zeta, eta, seeds):
    """``(found, n, freq ratio, damping ratio, rms freq error Hz, median freq std Hz)``."""
    truth = ModalModel.from_modes(2 * np.pi * MODES_HZ, [zeta] * 3, MASSES)
    clean = truth.frf(2 * np.pi * FREQ_HZ, quantity="accelerance")
    df, dz = [], []
    std_f, found = [], 0
    for seed in range(seeds):
        rng = np.random.default_rng(seed)
        noise = rng.standard_normal(FREQ_HZ.size) + 1j * rng.standard_normal(FREQ_HZ.size)
        data = FRFData(FREQ_HZ, clean * (1 + eta * noise / np.sqrt(2)), quantity="accelerance")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            modes = ModalFit().fit(data).report_["modes"]
        f = modes["frequency_hz"].to_numpy()
        for target in MODES_HZ:
            if not f.size:
                continue
            k = int(np.argmin(np.abs(f - target)))
            if abs(f[k] - target) >= 1.0:
                continue
            found += 1
            row = modes.iloc[k]
            df.append((row["frequency_hz"] - target) / row["frequency_hz_std"])
            dz.append((row["damping_ratio"] / zeta - 1) / (row["damping_ratio_std"] / zeta))
            std_f.append(row["frequency_hz_std"])
    df, dz = np.array(df), np.array(dz)
    rms_hz = float(np.sqrt(np.mean((df * np.array(std_f)) ** 2))) if df.size else np.nan
    return (found, seeds * MODES_HZ.size, float(np.sqrt(np.mean(df**2))),
            float(np.sqrt(np.mean(dz**2))), rms_hz, float(np.median(std_f)))


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    seeds = int(argv[argv.index("--seeds") + 1]) if "--seeds" in argv else 20
    t0 = time.perf_counter()
    print(f"ModalFit() on three modes between 0.5 Hz lines, {seeds} seeds per setting")
    print("| zeta | half-power width at 100 Hz (lines) | noise | found | rms df / std "
          "| rms dzeta / std | rms df (Hz) | median std (Hz) |")
    print("|---|---|---|---|---|---|---|---|")
    for zeta in (2e-4, 1e-3, 5e-3):
        for eta in (0.01, 0.05):
            found, n, rf, rz, rms, med = one_setting(zeta, eta, seeds)
            print(f"| {zeta:g} | {2 * zeta * MODES_HZ[0] / 0.5:.2f} | {100 * eta:g} % | "
                  f"{found}/{n} | {rf:.2f} | {rz:.2f} | {rms:.3g} | {med:.3g} |")
    print(f"total {time.perf_counter() - t0:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
