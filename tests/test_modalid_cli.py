"""The modalid command line: fit a measured FRF file, write the model and plots."""

from pathlib import Path

import numpy as np
import pytest

from data_synth import synthetic_frf
from modalid import ModalModel, SavedFit
from modalid.cli import main

CASE1 = str(Path(__file__).parent / "data" / "case1.mat")


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_fit_command_prints_the_modes_and_writes_the_model(tmp_path, capsys):
    status = main(["fit", CASE1, "--quantity", "accelerance", "--fmin", "20",
                   "--fmax", "400", "--weighting", "noise", "--not-driving-point",
                   "--out", str(tmp_path)])
    assert status == 0
    captured = capsys.readouterr()
    out = captured.out
    assert "212.08" in out
    # the reader's warning (coherence above 1 at 5 lines) is said as the fit's are, once
    assert captured.err.count("warning: Hf_coh_chan_2 of ") == 1
    assert "UserWarning" not in captured.err and "return _oriented" not in captured.err
    model = ModalModel.from_json(tmp_path / "case1_model.json")
    assert model.n_modes >= 4
    # the same file holds the fit's report: a prediction judges and continues it
    saved = SavedFit.from_json(tmp_path / "case1_model.json")
    assert saved.source == "case1.mat" and saved.report_["driving_point"] is False
    assert saved.report_["band_hz"] == (20.0, 400.0) and saved.report_["verdict"] == "ok"
    assert (tmp_path / "case1_fit.png").stat().st_size > 1000


def test_fit_command_says_how_a_uff_record_was_read(tmp_path, capsys):
    """An inch-pound UFF record along -Z for a force along +Z: converted and negated, and
    said so before the fit's report (the fit is a driving point's); its labels' warning
    said once (the record was read again to say how: it had been said twice, once as a
    raw Python warning)."""
    import pyuff

    f = np.linspace(1.0, 100.0, 400)
    frf = synthetic_frf(ModalModel.from_modes(2 * np.pi * np.array([20.0, 60.0]), [0.01, 0.01],
                                              [1.0, 2.0]), f, quantity="accelerance")
    inch, lbf = 1 / 0.0254, 1 / 4.4482216152605
    path = tmp_path / "in.uff"
    uff = pyuff.UFF(str(path))
    uff.write_sets(pyuff.prepare_164(units_code=7, units_description="IN", temp_mode=1,
                                     length=inch, force=lbf, temp=1.8, temp_offset=459.67),
                   mode="add")
    uff.write_sets(pyuff.prepare_58(binary=1, func_type=4, rsp_node=4, rsp_dir=-3, ref_node=4,
                                    ref_dir=3, abscissa_spacing=0, abscissa_spec_data_type=18,
                                    ordinate_spec_data_type=12, orddenom_spec_data_type=13,
                                    ordinate_axis_units_lab="g", orddenom_axis_units_lab="N",
                                    data=-frf.values * inch / lbf, x=f), mode="add")
    assert main(["fit", str(path)]) == 0
    captured = capsys.readouterr()
    out = captured.out
    # the labels contradict the units: said once, in the command line's words
    assert captured.err.count("its axis labels say 'g' over 'N'") == 1, captured.err
    assert "UserWarning" not in captured.err
    assert (f"{path}: UFF record 0: response 4-3, force 4+3, read negated (its directions "
            "differ in sign), values x 0.00571015 to SI (its units dataset)") in out
    assert "driving point: yes" in out


def test_fit_command_reports_bad_input(capsys):
    assert main(["fit", CASE1]) == 2
    assert "quantity" in capsys.readouterr().err
    assert main(["fit", "no_such_file.csv", "--quantity", "receptance"]) == 2
    # an --fmin above the data's end: the top named is theirs (it said only "got (3000.0,
    # 500.0)")
    capsys.readouterr()
    assert main(["fit", CASE1, "--quantity", "accelerance", "--fmin", "3000"]) == 2
    assert ("--fmin/--fmax must have fmin < fmax, got (3000.0, 500.0) (the data span 0.3125-500 "
            "Hz)") in capsys.readouterr().err


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore::UserWarning")
def test_fit_command_models_an_exponential_window(windowed_free_rod_csv, tmp_path, capsys):
    """A free rod's mobility from an exponentially windowed hammer test, as a CSV: the
    file states the window and the record length, and the model written has the rod's
    mass (1 kg), as with --window-decay and --record-length; told none (0 and inf) the
    fit warns that the file states otherwise and misreads the mass line."""
    path, options = windowed_free_rod_csv
    masses = {}
    window = ["--window-decay", str(options["window_decay_rate"]),
              "--record-length", str(options["record_length"])]
    # plain: the whole band, a passive fit without the window's model
    plain = ["--fmin", "0", "--driving-point", "yes", "--window-decay", "0",
             "--record-length", "inf"]
    for label, extra in (("file", []), ("window", window), ("plain", plain)):
        out = tmp_path / label
        capsys.readouterr()
        assert main(["fit", str(path), "--out", str(out)] + extra) == 0
        masses[label] = 1.0 / ModalModel.from_json(out / "free_rod_model.json").inverse_mass
        said = capsys.readouterr()
        assert ("as the file states" in said.out) == (label == "file")
        assert ("but the data state" in said.err) == (label == "plain")
    assert masses["window"] == pytest.approx(1.0, rel=3e-3)
    assert masses["file"] == masses["window"]
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
    for peak in ("142.1", "278.6", "460.4", "687.1", "958.5"):
        assert peak in out
    assert "driving point: no" in out and "band 8-1000 Hz" in out and "verdict: ok" in out
    assert "nothing saved" in out
    assert main(["fit", path, "--quantity", "accelerance", "--df", "-1"]) == 2
    assert "--df must be a positive" in capsys.readouterr().err


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_several_files_are_one_common_pole_fit_with_shapes(tmp_path, capsys):
    """Three points of a cantilever (tip = driving point, mid-span, near the clamp), one
    CSV each: ``modalid fit`` of the three files is one common-pole fit, printing the
    modes and their shapes (1 at the driving row), with the poles of the same fit made in
    Python; the saved model is a body for ``impactpred predict``.
    Without --driving-row the message names the flag; --index is refused for a set."""
    from data_synth import CantileverBeam, synthetic_frf
    from impactpred.cli import main as impactpred_main
    from modalid import FRFSet, ModalFit, MultiOutputModalModel, write_frf

    beam = CantileverBeam(1.0, 1.0)
    xi = [0.0, 0.5, 0.8]
    truth = beam.multi_output_model(xi, 12, damping_ratio=0.01, residual=True)
    freq_hz = np.linspace(0.05, 60.0, 1200)
    frfs = [synthetic_frf(truth.row(i), freq_hz, noise=0.01, seed=i) for i in range(3)]
    paths = []
    for name, frf in zip(("tip", "mid", "clamp"), frfs):
        paths.append(str(tmp_path / f"{name}.csv"))
        write_frf(paths[-1], frf)
    assert main(["fit", *paths]) == 2
    err = capsys.readouterr().err
    assert "--driving-row" in err and "driving_point" not in err
    assert main(["fit", *paths, "--index", "1", "--driving-row", "0"]) == 2
    assert "--index picks one FRF" in capsys.readouterr().err
    out_dir = tmp_path / "out"
    assert main(["fit", *paths, "--driving-row", "tip", "--out", str(out_dir)]) == 0
    out = capsys.readouterr().out
    assert "3 FRFs (tip, mid, clamp)" in out and "driving point: yes" in out
    assert "mode shapes (real part, 1 at the driving point;" in out
    model = MultiOutputModalModel.from_json(out_dir / "tip_set_model.json")
    python = ModalFit().fit(FRFSet.from_frfs(frfs, driving_point=0,
                                             outputs=["tip", "mid", "clamp"])).model_
    assert np.allclose(np.sort(np.abs(model.poles)), np.sort(np.abs(python.poles)),
                       rtol=1e-9)
    # the first bending mode's shape (the columns are sorted by |p|: the one of the pole
    # nearest the exact first mode), against the exact one scaled to 1 at the tip
    exact = beam.mode_shapes(xi, 1)[:, 0]
    w1 = beam.natural_frequencies(1)[0]
    column = int(np.argmin(np.abs(np.sort(np.abs(model.poles)) - w1)))
    assert np.allclose(model.mode_shapes()[:, column].real, exact / exact[0], atol=0.02)
    # the printed table: the same shape, and the phase collinearity of a real mode
    table = out.split("real mode):")[1].splitlines()
    assert [line.split()[0] for line in table[2:6]] == ["tip", "mid", "clamp", "MPC"]
    assert float(table[3].split()[1]) == pytest.approx(exact[1] / exact[0], abs=0.02)
    assert float(table[5].split()[1]) > 0.99
    assert impactpred_main(["predict", "mass:0.1", str(out_dir / "tip_set_model.json"),
                            "--v1", "1", "--t-end", "2"]) == 0
    assert "restitution" in capsys.readouterr().out


@pytest.mark.filterwarnings("ignore::UserWarning")
@pytest.mark.filterwarnings("ignore::ResourceWarning")
def test_one_uff_of_several_points_is_a_set_with_its_driving_point_from_the_dofs(tmp_path,
                                                                                  capsys):
    """A UFF file of three records (response DOFs 1, 2, 3 against reference 1): without
    --index or --set the message names both flags; with --set the records are one
    common-pole fit whose driving row, record 0 (response DOF = reference DOF), comes
    from the file."""
    from data_synth import CantileverBeam, synthetic_frf
    from modalid import write_frf

    truth = CantileverBeam(1.0, 1.0).multi_output_model([0.0, 0.5, 0.8], 8,
                                                         damping_ratio=0.01, residual=True)
    freq_hz = np.linspace(0.05, 40.0, 800)
    text = ""
    for i in range(3):
        path = tmp_path / f"p{i}.uff"
        write_frf(path, synthetic_frf(truth.row(i), freq_hz, quantity="accelerance",
                                      noise=0.01, seed=i),
                  response=(i + 1, 3), reference=(1, 3))
        text += path.read_text()
    (tmp_path / "all.uff").write_text(text)
    assert main(["fit", str(tmp_path / "all.uff")]) == 2
    err = capsys.readouterr().err
    assert "--index" in err and "--set" in err and "read_frfs" not in err
    assert main(["fit", str(tmp_path / "all.uff"), "--set"]) == 0
    out = capsys.readouterr().out
    assert "all.uff: 3 FRFs (1+Z, 2+Z, 3+Z)" in out and "driving point: yes" in out
    shapes = out.split("real mode):")[1].splitlines()
    assert [line.split()[0] for line in shapes[2:5]] == ["1+Z", "2+Z", "3+Z"]
    first = CantileverBeam(1.0, 1.0).natural_frequencies(1)[0] / (2 * np.pi)
    assert shapes[1].split()[1] == "Hz"                        # the first bending mode
    assert float(shapes[1].split()[0]) == pytest.approx(first, rel=1e-3)
    # the errors printed are in the data's quantity (accelerance), as the Python fit's
    from modalid import ModalFit, read_frf_set

    python = ModalFit().fit(read_frf_set(tmp_path / "all.uff")).report_["frf_nrmse_data"]
    printed = out.split("FRF NRMSE ")[1].split(" (accelerance)")[0]
    assert printed == ", ".join(f"{label} {e:.4g}"
                                for label, e in zip(("1+Z", "2+Z", "3+Z"), python))
    assert main(["fit", str(tmp_path / "p0.uff"), "--set"]) == 2       # one FRF: no set
    assert "holds one FRF" in capsys.readouterr().err


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_a_set_named_by_numbers_and_one_with_no_driving_point(tmp_path, capsys):
    """Files named 1.csv, 2.csv, 3.csv: --driving-row 2 is the label "2" (the second
    file), not the index 2; an unknown row is named with the labels. pyuff's three points
    (transfer FRFs, no driving point): any row named, the fit says it is not one, the
    shapes are scaled to that row and the saved model is no impact body."""
    from data_synth import CantileverBeam, synthetic_frf
    from modalid import write_frf

    truth = CantileverBeam(1.0, 1.0).multi_output_model([0.5, 0.0, 0.8], 8,
                                                         damping_ratio=0.01, residual=True)
    freq_hz = np.linspace(0.05, 40.0, 800)
    paths = []
    for i in range(3):
        paths.append(str(tmp_path / f"{i + 1}.csv"))
        write_frf(paths[-1], synthetic_frf(truth.row(i), freq_hz, noise=0.01, seed=i))
    assert main(["fit", *paths, "--driving-row", "2"]) == 0
    out = capsys.readouterr().out
    assert "driving point: yes" in out and "1 at the driving point" in out
    assert main(["fit", *paths, "--driving-row", "7"]) == 2
    assert "neither an output label of the set (1, 2, 3)" in capsys.readouterr().err
    points = [str(Path(__file__).parent / "data" / f"meas_point_{i}.txt") for i in (1, 2, 3)]
    assert main(["fit", *points, "--quantity", "accelerance", "--df", "1",
                 "--driving-row", "meas_point_1", "--out", str(tmp_path / "out")]) == 0
    out = capsys.readouterr().out
    assert "driving point: no" in out and "1 at row meas_point_1, not a driving point" in out
    assert "not an impact body" in out


def test_fit_command_on_a_file_with_no_usable_band(tmp_path, capsys):
    """Coherence near zero on every line: an error naming the file, exit 2."""
    freq = np.linspace(1.0, 100.0, 200)
    table = np.column_stack([freq, 1.0 / (1 + freq), 0 * freq, np.full(200, 0.01)])
    path = tmp_path / "noise.csv"
    np.savetxt(path, table, delimiter=",", header="freq_hz,real,imag,coherence")
    assert main(["fit", str(path), "--quantity", "receptance"]) == 2
    err = capsys.readouterr().err
    assert str(path) in err and "no usable band" in err


# ---------------------------------------------------------------- shared options
FIT_ARGS = ["--n-modes", "4", "--fmax", "50", "--rigid-body", "no", "--weighting", "noise",
            "--driving-point", "yes", "--missed-modes", "dense", "--window-decay", "2",
            "--record-length", "10"]
FIT_OPTIONS = {"method": "vf", "n_modes": 4, "freq_range": (None, 50.0), "rigid_body": False,
               "weighting": "noise", "passive": True, "missed_modes": "dense",
               "window_decay_rate": 2.0, "record_length": 10.0}


def test_fit_options_are_the_same_in_modalid_fit_and_impactpred_predict():
    """One definition: the same flags give the same ModalFit keywords in both commands
    (predict's --method is its solver's, so the fit's is --fit-method there)."""
    from impactpred.cli import build_parser as impactpred_parser
    from modalid._cli import fit_options
    from modalid.cli import build_parser

    fit = build_parser().parse_args(["fit", "x.csv", "--method", "vf"] + FIT_ARGS)
    pred = impactpred_parser().parse_args(["predict", "mass:1", "x.csv", "--t-end", "1",
                                           "--fit-method", "vf"] + FIT_ARGS)
    assert fit_options(fit) == FIT_OPTIONS
    assert fit_options(pred) == FIT_OPTIONS
    assert fit_options(build_parser().parse_args(["fit", "x.csv"])) == {}
    both = build_parser().parse_args(["fit", "x.csv", "--not-driving-point",
                                      "--driving-point", "yes"])
    with pytest.raises(ValueError, match="^--not-driving-point contradicts --driving-point "
                                         "yes: give one of them$"):
        fit_options(both)


@pytest.mark.parametrize("message, flags", [
    ("t_end=8.0 / dt=0.001 exceeds", "--t-end 8.0 / --dt 0.001 exceeds"),
    ("options: missed_modes='dense' for a band", "options: --missed-modes dense for a band"),
    ("window_decay_rate must be non-negative", "--window-decay must be non-negative"),
    ("pass quantity= one of [...]", "pass --quantity one of [...]"),
    ("read it with read_options={'conjugate': True}", "read it with --conjugate"),
    ("the grazing;\n use method='modal'", "the grazing; use --method modal"),
    ("passive=False allows it; check_passive=False", "--driving-point no allows it; "
                                                     "--no-passivity-check"),
    ("a quantity named in prose stays", "a quantity named in prose stays"),
    ("/data/record_length/t_end=1.csv: bad", "/data/record_length/t_end=1.csv: bad"),
    ("dt must be positive, got 0.0", "--dt must be positive, got 0.0"),
    ("velocity1 must be finite, got nan", "--v1 must be finite, got nan"),
    ("index must be below 1, got index=3", "--index must be below 1, got --index 3"),
    ("the fit's method mustered", "the fit's method mustered"),
    ("x.csv says '# quantity: velocity'; the quantity must be one of",
     "x.csv says '# quantity: velocity'; the quantity must be one of"),
    # what may fix a failed identification, and a saved fit refused for the band
    ("a band that holds whole resonances (freq_range=(fmin, fmax)), or identify the body "
     "yourself (modalid.ModalFit) and give the saved fit (modalid.SavedFit.to_json, or "
     "modalid fit --out)",
     "a band that holds whole resonances (--fmin/--fmax), or identify the body yourself "
     "(modalid fit FILE --out DIR, with the options it needs) and give the _model.json it "
     "writes"),
    ("which a saved fit does not hold; predict from its FRF file (or the fitted ModalFit) "
     "for the band", "which a saved fit does not hold; predict from its FRF file for the band"),
])
def test_in_flags_writes_python_arguments_as_flags(message, flags):
    from modalid._cli import in_flags

    assert in_flags(message) == flags


def test_the_remedies_of_a_failed_identification_name_flags_only():
    from impactpred.predict import _FIT_REMEDIES
    from modalid._cli import in_flags

    said = in_flags(_FIT_REMEDIES)
    assert "(--fmin/--fmax)" in said and said.endswith("the _model.json it writes")
    assert "modalid." not in said and "=" not in said


def test_fit_refuses_an_out_that_is_a_file_before_fitting(tmp_path, monkeypatch, capsys):
    from modalid import ModalFit

    def no_fit(*args, **kwargs):
        raise AssertionError("fitted before refusing --out")

    monkeypatch.setattr(ModalFit, "fit", no_fit)
    out = tmp_path / "result.txt"
    out.write_text("keep me")
    assert main(["fit", CASE1, "--quantity", "accelerance", "--out", str(out)]) == 2
    assert capsys.readouterr().err == (f"modalid: error: --out {out} is an existing file, not "
                                       "a folder: give a folder (created if missing)\n")
    assert out.read_text() == "keep me"


# ---------------------------------------------------------------- sign conventions
@pytest.fixture(scope="module")
def rod_accelerance():
    """A fixed rod's driving-point accelerance: 8 modes, 1 % noise."""
    from data_synth import Rod, lightly_damped, synthetic_frf

    truth = lightly_damped(Rod(1.0, 1.0, support="fixed"), 12, 0.01)
    top = truth.modes["omega_n"].to_numpy()[8] / (2 * np.pi)
    return synthetic_frf(truth, np.linspace(0.02, top, 1500), quantity="accelerance",
                         noise=0.01, seed=1)


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_fit_names_the_flag_for_a_conjugated_or_reversed_file(rod_accelerance, tmp_path,
                                                              capsys):
    from modalid import FRFData, write_frf

    for kind, values, flag in (("conj", rod_accelerance.values.conj(), "--conjugate"),
                               ("neg", -rod_accelerance.values, "--negate")):
        path = tmp_path / f"rod_{kind}.csv"
        write_frf(path, FRFData(rod_accelerance.freq_hz, values, quantity="accelerance"))
        status = main(["fit", str(path)])
        err = capsys.readouterr().err
        warning = next(line for line in err.splitlines() if line.startswith("warning: "))
        assert warning.startswith(f"warning: {path}: ")
        assert warning.endswith(f"read it with {flag}" + (
            "" if kind == "conj" else "; if its quantity is stated wrong (an accelerance read "
            "as a receptance looks reversed too), read it with --quantity ... (or correct the "
            "quantity the file states); if it is a transfer FRF, give the driving point's"))
        assert status == (3 if kind == "conj" else 0)   # a conjugated FRF cannot be fitted
        assert main(["fit", str(path), flag]) == 0
        out, err = capsys.readouterr()
        assert "driving point: yes" in out and "verdict: ok" in out and "warning" not in err


# ---------------------------------------------------------------- modalid hammer
@pytest.fixture(scope="module")
def hammer_test():
    """Three synthetic hits on a free rod (1 kg, T = 1 s), velocity response, 0.1 % noise:
    ``(test, decay)`` with the decay of a window ending at 1 %."""
    from data_synth import Rod, lightly_damped, synthetic_hammer_test

    truth = lightly_damped(Rod(1.0, 1.0), 15, 0.001)
    top, duration = 2.75, 100.0
    test = synthetic_hammer_test(truth, 5 * top, duration, n_hits=3, pulse_width=0.5 / top,
                                 response="velocity", anti_alias=True, noise=0.001, seed=2)
    return test, float(-np.log(0.01) / duration)


def save_rows(folder, test):
    """One .npy file per hit, rows t, force, response (as pyFRF's measurements)."""
    paths = []
    for i in range(test.force.shape[0]):
        paths.append(folder / f"hit{i}.npy")
        np.save(paths[-1], np.array([test.t, test.force[i], test.response[i]]))
    return [str(p) for p in paths]


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_hammer_command_writes_the_h1_and_the_flags_of_a_later_fit(hammer_test, tmp_path,
                                                                   capsys):
    """Three .npy files (rows t, force, velocity) -> the CSV holds frf_from_hammer's H1,
    coherence, window and record length exactly (a .uff keeps the window and record
    length too); the fit of that file with no flags gives the rod's mass."""
    from modalid import frf_from_hammer, read_frf

    test, decay = hammer_test
    out = tmp_path / "rod_frf.csv"
    rows = save_rows(tmp_path, test)
    assert main(["hammer", *rows, "--response-type", "velocity",
                 "--exponential-decay", repr(decay), "--out", str(out)]) == 0
    printed = capsys.readouterr().out
    assert printed.startswith("3 hits from 3 files (hit0.npy ... hit2.npy): 1375 samples at "
                              "13.75 Hz (100 s); channels: time 0, force 1, response 2\n")
    flags = f"--window-decay {decay:.9g} --record-length 100"
    assert (f"fit it with: modalid fit {out} (its automatic band keeps the lines above "
            "where the force spectrum the file keeps falls 20 dB, near ") in printed
    assert f"the file keeps the exponential window and the record length ({flags})" in printed
    expected = frf_from_hammer(test.force, test.response, test.fs, response_type="velocity",
                               exponential_decay=decay).frf
    written = read_frf(out)
    assert written.quantity == "mobility"
    np.testing.assert_array_equal(written.freq_hz, expected.freq_hz)
    np.testing.assert_array_equal(written.values, expected.values)
    np.testing.assert_array_equal(written.coherence, expected.coherence)
    assert (written.window_decay_rate, written.record_length) == (decay, 100.0)
    fitted = tmp_path / "fit"
    assert main(["fit", str(out), "--fmax", "2.75", "--out", str(fitted)]) == 0
    mass = 1.0 / ModalModel.from_json(fitted / "rod_frf_model.json").inverse_mass
    assert mass == pytest.approx(1.0, rel=3e-3)
    uff = tmp_path / "rod_frf.uff"
    assert main(["hammer", *rows, "--response-type", "velocity",
                 "--exponential-decay", repr(decay), "--out", str(uff)]) == 0
    said = capsys.readouterr()
    assert f"fit it with: modalid fit {uff} (and --fmax " in said.out
    # this rod's time scale is a second: its 0.18 s pulse is no hammer's, and is said;
    # 2.5 samples long, it holds force above fs / 2, which is said too (the records were
    # filtered: no aliasing, as the warning allows)
    assert said.err.startswith("warning: the force pulse lasts ")
    assert said.err.count("\n") == 2 and "near the Nyquist frequency" in said.err
    written = read_frf(uff)
    assert (written.window_decay_rate, written.record_length) == (decay, 100.0)


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_one_hit_writes_its_force_spectrum_and_the_fit_ends_its_band_there(hammer_test,
                                                                          tmp_path, capsys):
    """One hit (no coherence): the CSV keeps the force spectrum (``excitation``), the
    printed advice says the automatic band ends with it, and ``modalid fit`` on the file
    says it ended the band where the spectrum fell 20 dB (--max-freq: the lines to fs / 2,
    as by default)."""
    from modalid import frf_from_hammer, read_frf

    test, _ = hammer_test
    out = tmp_path / "one.csv"
    (path,) = save_rows(tmp_path, type(test)(**{**vars(test), "force": test.force[:1],
                                                "response": test.response[:1]}))
    top = repr(test.fs / 2)
    assert main(["hammer", path, "--response-type", "velocity", "--pretrigger", "keep",
                 "--max-freq", top, "--out", str(out)]) == 0
    assert "its automatic band ends where the force spectrum the file keeps falls 20 dB" in (
        capsys.readouterr().out)
    written = out.read_bytes()        # a second run does not overwrite it without a word
    assert main(["hammer", path, "--response-type", "velocity", "--pretrigger", "keep",
                 "--max-freq", top, "--out", str(out)]) == 2
    assert capsys.readouterr().err == (f"modalid: error: --out {out} exists: remove it "
                                       "first, or give another name\n")
    assert out.read_bytes() == written
    expected = frf_from_hammer(test.force[:1], test.response[:1], test.fs,
                               response_type="velocity", pretrigger="keep",
                               max_freq_hz=test.fs / 2)
    np.testing.assert_array_equal(read_frf(out).excitation, expected.force_spectrum)
    assert main(["fit", str(out), "--not-driving-point"]) == 0
    assert "the excitation's spectrum is 20 dB or more below its peak" in capsys.readouterr().out


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_a_labview_hammer_record_to_its_modes_from_the_command_line(tmp_path, capsys):
    """ladisk's one hit as LabVIEW wrote it (tests/data/acceleration.lvm.gz): modalid
    hammer reads it (the acceleration in g scaled to m/s^2) and writes the FRF with its
    force spectrum; modalid fit with no options ends the band where that spectrum falls
    20 dB and finds the tutorial's four modes within 0.1 %, verdict suspect for the sharp
    18 Hz resonance below them (the beam's suspension) that the model misses."""
    record = Path(__file__).parent / "data" / "acceleration.lvm.gz"
    out, fitted = tmp_path / "beam.csv", tmp_path / "fit"
    assert main(["hammer", str(record), "--out", str(out)]) == 0
    assert "response Acceleration (Trigger) (x 9.80665: g to SI)" in capsys.readouterr().out
    assert main(["fit", str(out), "--out", str(fitted)]) == 0
    printed = capsys.readouterr().out
    assert "20 dB or more below its peak" in printed and "verdict: suspect" in printed
    assert "the data's resonance at 17.9892 Hz is missed" in printed
    model = ModalModel.from_json(fitted / "beam_model.json")
    found = model.modes["frequency_hz"].to_numpy()
    for p in (695.0, 1897.6, 2777.3, 3671.2):
        assert np.min(np.abs(found / p - 1)) < 1e-3, (p, found)


def test_hammer_command_reads_csv_and_npz_records(hammer_test, tmp_path, capsys):
    """A CSV with a header (time, force, velocity columns) and an .npz of hits x samples
    with --fs give the same FRF as the .npy rows; nothing saved without --out."""
    from modalid import read_frf

    test, _ = hammer_test
    paths = []
    for i in range(3):
        paths.append(tmp_path / f"hit{i}.csv")
        np.savetxt(paths[-1], np.column_stack([test.t, test.force[i], test.response[i]]),
                   delimiter=",", header="time_s,force_N,velocity", comments="")
    npz = tmp_path / "hits.npz"
    np.savez(npz, force=test.force, response=test.response)
    frfs = {}
    for label, args in (("csv", [str(p) for p in paths]), ("npz", [str(npz), "--fs", "13.75"]),
                        ("npy", save_rows(tmp_path, test))):
        frfs[label] = tmp_path / f"{label}.csv"
        assert main(["hammer", *args, "--response-type", "velocity", "--out",
                     str(frfs[label])]) == 0
    printed = capsys.readouterr().out
    assert "channels: time time_s, force force_N, response velocity" in printed
    assert "3 hits from 1 file (hits.npz): 1375 samples" in printed
    reference = read_frf(frfs["npy"])
    for label in ("csv", "npz"):
        np.testing.assert_allclose(read_frf(frfs[label]).values, reference.values,
                                   rtol=1e-12, atol=1e-12 * np.abs(reference.values).max())
    assert main(["hammer", str(npz), "--fs", "13.75", "--response-type", "velocity"]) == 0
    printed = capsys.readouterr().out
    assert printed.splitlines()[-1] == ("nothing saved (--out FILE writes the FRF with its "
                                        "coherence (.csv, .npz, .mat, .uff))")


def test_hammer_command_reads_what_the_channels_say(hammer_test, tmp_path, capsys):
    """A response channel in m/s is a velocity (it was written as an accelerance unless
    --response-type said otherwise), a flag that contradicts it is refused; a force in mV
    needs --force-scale; a time column rounded to 4 decimals (steps 0.0727 and 0.0728 s)
    is read with --fs, checked against it."""
    from modalid import read_frf

    test, _ = hammer_test
    paths = []
    for i in range(3):
        paths.append(tmp_path / f"hit{i}.csv")
        np.savetxt(paths[-1], np.column_stack([np.round(test.t, 4), test.force[i] / 0.02,
                                               test.response[i]]),
                   delimiter=",", header="Time [s],Force [mV],Response [m/s]", comments="")
    args = ["hammer", *map(str, paths)]
    assert main(args) == 2
    assert "'Force [mV]' is in 'mV', a unit not known here" in capsys.readouterr().err
    assert main(args + ["--force-scale", "-0.02"]) == 2
    assert "--force-scale must be positive, got -0.02" in capsys.readouterr().err
    assert main(args + ["--force-scale", "0.02"]) == 2
    assert "give the sample rate with --fs" in capsys.readouterr().err
    assert main(args + ["--force-scale", "0.02", "--fs", "13.8"]) == 2
    assert "--fs says 13.8 Hz" in capsys.readouterr().err
    out = tmp_path / "frf.csv"
    assert main(args + ["--force-scale", "0.02", "--fs", "13.75", "--out", str(out)]) == 0
    assert "H1 mobility" in capsys.readouterr().out
    assert read_frf(out).quantity == "mobility"
    assert main(args + ["--force-scale", "0.02", "--fs", "13.75",
                        "--response-type", "acceleration"]) == 2
    assert "but the response channel's unit or name says velocity" in capsys.readouterr().err


def test_hammer_command_refuses_bad_records_on_one_line(hammer_test, tmp_path, capsys):
    test, _ = hammer_test
    pickled = tmp_path / "pickled.npy"
    np.save(pickled, np.array([{"force": 1}], dtype=object), allow_pickle=True)
    two = tmp_path / "two.npy"
    np.save(two, np.array([test.force[0], test.response[0]]))
    jitter = tmp_path / "jitter.npy"
    np.save(jitter, np.array([test.t * (1 + 0.01 * (np.arange(test.t.size) % 2)),
                              test.force[0], test.response[0]]))
    folder = tmp_path / "folder.csv"
    folder.mkdir()
    holed = tmp_path / "holed.npy"        # the error had not named the file
    response = test.response[0].copy()
    response[1000] = np.nan
    np.save(holed, np.array([test.t, test.force[0], response]))
    cases = [
        ([str(holed)], f"{holed}: its response channel holds nan (record 1 of 1, sample "
                       f"1001 of {test.t.size}; 1 value not finite)"),
        ([str(pickled)], f"cannot read {pickled} as .npy (pickled/object arrays are refused)"),
        ([str(two)], f"{two} has no time channel: give the sample rate with --fs"),
        ([str(jitter)], f"{jitter}: its time channel is not uniformly increasing"),
        ([str(two), "--fs", "13.75", "--exponential-decay", "-1"],
         "--exponential-decay must be non-negative, got -1.0"),
        ([str(two), "--fs", "13.75", "--out", str(folder)],
         f"--out {folder} is a folder: give the FRF file to write"),
        ([str(two), "--fs", "13.75", "--out", str(tmp_path / "frf.xyz")],
         "frf.xyz: its extension says the format; give .csv, .npz, .mat or .uff"),
        ([str(tmp_path / "missing.npy"), "--fs", "1"], "no such file: "),
    ]
    for args, message in cases:
        assert main(["hammer", *args]) == 2
        err = capsys.readouterr().err
        assert err.startswith("modalid: error: ") and err.count("\n") == 1
        assert message in err


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_a_time_column_with_a_rounded_step_gives_the_round_rate(hammer_test, tmp_path,
                                                                capsys):
    """pyFRF's time rows step 3.90625000080e-5 s for 25600 Hz: the rate read is 25600 Hz
    (10 significant digits), so the lines are whole multiples of their spacing and an
    ASCII UFF file holds them (the rate 25600.0000000002 made lines 1 - 2e-14 Hz apart,
    which it refused)."""
    from modalid import read_frf

    test, _ = hammer_test
    step = float(f"{1 / test.fs:.11e}") * (1 + 2e-11)         # the text's own rounding
    rows = type(test)(**{**vars(test), "t": np.arange(test.t.size) * step})
    paths = save_rows(tmp_path, rows)
    out = tmp_path / "h.uff"
    assert main(["hammer", *paths, "--response-type", "velocity", "--out", str(out)]) == 0
    assert f"samples at {test.fs:.9g} Hz" in capsys.readouterr().out
    f = read_frf(out).freq_hz
    np.testing.assert_allclose(f, np.arange(f.size) * (f[1] - f[0]), rtol=0, atol=1e-9)


def test_a_negative_exponent_number_is_attached_to_its_option_only():
    """``--gap -1e-3`` reads as ``--gap=-1e-3``; after ``--`` (the end of the options)
    the number stays a word of its own."""
    from modalid._cli import _attached_negative_numbers

    assert _attached_negative_numbers(["--gap", "-1e-3", "x"]) == ["--gap=-1e-3", "x"]
    assert _attached_negative_numbers(["--", "-1e-3"]) == ["--", "-1e-3"]
    assert _attached_negative_numbers(["--gap=1", "-2e3"]) == ["--gap=1", "-2e3"]


def test_hammer_command_cuts_the_pretrigger_where_the_file_can_hold_it(hammer_test, tmp_path,
                                                                     capsys):
    """Unwindowed records with the hits 0.87 s in: a CSV gets the cut records (the file's
    record length what is left, its lines on that length); an ASCII UFF file holds a round
    line spacing only, so --pretrigger auto keeps them whole there and says so; --pretrigger
    cut with a UFF file is refused in the interface's words."""
    from modalid import read_frf

    test, _ = hammer_test
    rows = save_rows(tmp_path, test)
    args = ["hammer", *rows, "--response-type", "velocity"]
    assert main(args + ["--out", str(tmp_path / "h.csv")]) == 0
    assert "pre-trigger cut: each hit's records from 0.8" in capsys.readouterr().out
    written = read_frf(tmp_path / "h.csv")
    assert 99 < written.record_length < 100
    assert main(args + ["--out", str(tmp_path / "h.uff")]) == 0
    assert "pre-trigger kept (--pretrigger auto with a .uff file" in capsys.readouterr().out
    assert read_frf(tmp_path / "h.uff").record_length == 100.0
    assert main(args + ["--pretrigger", "cut", "--out", str(tmp_path / "c.uff")]) == 2
    err = capsys.readouterr().err
    assert "--pretrigger keep" in err and "binary=True" not in err, err
    assert main(args + ["--out", str(tmp_path / "h.uf")]) == 0       # .uf is UFF too
    assert "pre-trigger kept" in capsys.readouterr().out
