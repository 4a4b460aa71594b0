"""The modalid command line: fit a measured FRF file, write the model and plots."""

from pathlib import Path

import numpy as np
import pytest

from modalid import ModalModel
from modalid.cli import main

CASE1 = str(Path(__file__).parent / "data" / "case1.mat")


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_fit_command_prints_the_modes_and_writes_the_model(tmp_path, capsys):
    status = main(["fit", CASE1, "--quantity", "accelerance", "--fmin", "20",
                   "--fmax", "400", "--weighting", "noise", "--not-driving-point",
                   "--out", str(tmp_path)])
    assert status == 0
    out = capsys.readouterr().out
    assert "212.08" in out
    model = ModalModel.from_json(tmp_path / "case1_model.json")
    assert model.n_modes >= 4
    assert (tmp_path / "case1_fit.png").stat().st_size > 1000


def test_fit_command_reports_bad_input(capsys):
    assert main(["fit", CASE1]) == 2
    assert "quantity" in capsys.readouterr().err
    assert main(["fit", "no_such_file.csv", "--quantity", "receptance"]) == 2


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_fit_command_models_an_exponential_window(windowed_free_rod_csv, tmp_path, capsys):
    """A free rod's mobility from an exponentially windowed hammer test, as a CSV: with
    --window-decay and --record-length the model written has the rod's mass (1 kg)."""
    path, options = windowed_free_rod_csv
    masses = {}
    window = ["--window-decay", str(options["window_decay_rate"]),
              "--record-length", str(options["record_length"])]
    # plain: the whole band, a passive fit without the window's model
    plain = ["--fmin", "0", "--driving-point", "yes"]
    for label, extra in (("window", window), ("plain", plain)):
        out = tmp_path / label
        assert main(["fit", str(path), "--out", str(out)] + extra) == 0
        masses[label] = 1.0 / ModalModel.from_json(out / "free_rod_model.json").inverse_mass
    assert masses["window"] == pytest.approx(1.0, rel=3e-3)
    assert abs(masses["plain"] - 1.0) > 0.05       # the windowed mass line read as 1/(M s^2)
    out = tmp_path / "dense"
    assert main(["fit", str(path), "--missed-modes", "dense", "--out", str(out)] + window) == 0
    dense = ModalModel.from_json(out / "free_rod_model.json")
    assert 1.0 / dense.inverse_mass == pytest.approx(1.0, rel=3e-3)
    capsys.readouterr()
    assert main(["fit", str(path), "--window-decay", "-1"]) == 2
    assert "--window-decay must be non-negative" in capsys.readouterr().err


def test_fit_command_on_a_bare_complex_lines_file(capsys):
    """pyuff's measured accelerance (one complex literal per line): without frequencies
    the message names the flags; with --df 1 the six peaks, 'not a driving point', the
    band and the verdict are printed, and nothing saved is said."""
    path = str(Path(__file__).parent / "data" / "meas_point_1.txt")
    assert main(["fit", path, "--quantity", "accelerance"]) == 2
    err = capsys.readouterr().err
    assert "--freq-start/--df" in err and "freq_hz=" not in err
    assert main(["fit", path, "--quantity", "accelerance", "--df", "1"]) == 0
    out = capsys.readouterr().out
    for peak in ("142.17", "278.67", "460.39", "687.1", "958.5"):
        assert peak in out
    assert "driving point: no" in out and "band 8-1000 Hz" in out and "verdict: ok" in out
    assert "nothing saved" in out
    assert main(["fit", path, "--quantity", "accelerance", "--df", "-1"]) == 2
    assert "--df must be a positive" in capsys.readouterr().err


def test_fit_command_on_a_file_with_no_usable_band(tmp_path, capsys):
    """Coherence near zero on every line: an error naming the file, exit 2."""
    freq = np.linspace(1.0, 100.0, 200)
    table = np.column_stack([freq, 1.0 / (1 + freq), 0 * freq, np.full(200, 0.01)])
    path = tmp_path / "noise.csv"
    np.savetxt(path, table, delimiter=",", header="freq_hz,real,imag,coherence")
    assert main(["fit", str(path), "--quantity", "receptance"]) == 2
    err = capsys.readouterr().err
    assert str(path) in err and "no usable band" in err
