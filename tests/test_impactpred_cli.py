"""The command line: help, the exact models, the paper's cases."""

import pandas as pd
import pytest

from impactpred.cli import main
from impactpred.paper import run_paper_cases


def test_help_lists_the_commands(capsys):
    with pytest.raises(SystemExit) as exit_info:
        main(["--help"])
    assert exit_info.value.code == 0
    out = capsys.readouterr().out
    assert "paper" in out and "models" in out


def test_models_command_prints_exact_frequencies(tmp_path, capsys):
    assert main(["models", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "0.2500" in out and "0.7500" in out          # fixed rod: (k - 1/2)/(2T) Hz
    assert "0.5596" in out                               # cantilever: eps_1^2/(2 pi T)
    assert (tmp_path / "exact_models_frf.png").stat().st_size > 1000


def test_paper_command_writes_figures_and_table(tmp_path, capsys):
    assert main(["paper", "--out", str(tmp_path)]) == 0
    table = pd.read_csv(tmp_path / "paper_cases.csv", index_col="case")
    assert table.loc["a", "restitution"] == pytest.approx(1.0, abs=1e-12)
    assert table.loc["a", "contact_duration_s"] == pytest.approx(2.0, abs=1e-12)
    assert table.loc["b_equal_material", "contact_duration_s"] == pytest.approx(1.5, abs=1e-9)
    assert table.loc["c", "restitution"] == pytest.approx(0.69888, abs=2e-4)
    assert table.loc["d", "n_contacts"] == 1
    for key in ("a", "b_equal_mass", "b_equal_material", "c", "d"):
        assert (tmp_path / f"fig4_{key}.png").stat().st_size > 1000


def test_paper_table_without_files():
    table = run_paper_cases(None, plot=False)
    assert 0 < table.loc["b_equal_mass", "restitution"] < 1
    assert (table.loc["b_equal_mass", "peak_force_N"]
            > table.loc["b_equal_material", "peak_force_N"])


def test_cli_reports_bad_input_without_a_traceback(capsys):
    assert main(["paper", "--dt", "-1", "--no-plot"]) == 2
    assert "dt must be positive" in capsys.readouterr().err


def test_benchmark_command_quick_writes_tables(tmp_path, capsys, monkeypatch):
    import impactpred.benchmark as benchmark

    tables = []
    real_run = benchmark.run_benchmark
    monkeypatch.setattr(benchmark, "run_benchmark",
                        lambda **kw: tables.append(real_run(**kw)) or tables[-1])
    assert main(["benchmark", "--quick", "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "mass-rod M/m=1" in out and "no prediction with e > 1" in out
    table = pd.read_csv(tmp_path / "synthetic_benchmark.csv")
    assert len(table) == 2 and (tmp_path / "synthetic_benchmark.md").exists()
    # a target missed is said, and the exit status says it too (4: written, not met)
    missed = tables[0].copy()
    missed.attrs["targets"] = tables[0].attrs["targets"].copy()
    missed.attrs["targets"].loc[0, "result"] = "MISS"
    monkeypatch.setattr(benchmark, "run_benchmark", lambda **kw: missed)
    assert main(["benchmark", "--quick"]) == 4
    n_targets = len(missed.attrs["targets"])
    assert f"1 of {n_targets} targets MISS; exit status 4" in capsys.readouterr().err


# ------------------------------------------------------------------ predict: files, flags
import json  # noqa: E402

import numpy as np  # noqa: E402

from modalid import FRFData, ModalModel, write_frf  # noqa: E402

TWO_MODES = ModalModel.from_modes([2 * np.pi * 10, 2 * np.pi * 25], [0.02, 0.02], [1.0, 0.5])
SPRING = ["--contact", "spring:stiffness=1e4"]


def one_line_error(capsys) -> str:
    """The command's stderr, checked to be one line, without its prefix."""
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith("impactpred: error: ")
    return err[len("impactpred: error: "):-1]


@pytest.fixture(scope="module")
def two_mode_accelerance():
    """The driving-point accelerance of a grounded two-mode body (10 and 25 Hz)."""
    freq = np.linspace(1.0, 40.0, 800)
    return FRFData(freq, TWO_MODES.frf(2 * np.pi * freq, quantity="accelerance"),
                   quantity="accelerance")


def test_predict_refuses_model_files_it_cannot_read_on_one_line(tmp_path, capsys):
    empty, prose, units = (tmp_path / f"{name}.json" for name in ("empty", "prose", "units"))
    empty.write_text("")
    prose.write_text("hello world\n")
    units.write_text(json.dumps(dict(json.loads(TWO_MODES.to_json()),
                                     units={"s": "rad/s", "receptance": "furlong/N"})))
    expected = {
        empty: f"{empty} is empty: not a model JSON file",
        prose: f"{prose} is not JSON: Expecting value: line 1 column 1 (char 0)",
        units: f"units.receptance 'furlong/N' ({units}) is not a known receptance unit: use "
               "one of m/N, mm/N, um/N, nm/N, m/kN, mm/kN, in/lbf (or convert the file to m/N)",
    }
    for path, message in expected.items():
        assert main(["predict", "mass:1", str(path), "--v1", "1", "--t-end", "1"]) == 2
        assert one_line_error(capsys) == message


def test_predict_reads_a_model_stated_in_mm_per_newton(tmp_path, capsys):
    """The same body saved in m/N and in mm/N (values x 1000, units say so) predicts the
    same impact; read as m/N it would be 1000 times softer."""
    payload = json.loads(TWO_MODES.to_json())
    scaled = dict(payload, units={"s": "rad/s", "receptance": "mm/N"},
                  residues=[[1e3 * re, 1e3 * im] for re, im in payload["residues"]])
    si, mm = tmp_path / "si.json", tmp_path / "mm.json"
    si.write_text(json.dumps(payload))
    mm.write_text(json.dumps(scaled))
    printed = {}
    for path in (si, mm):
        assert main(["predict", "mass:1", str(path), "--v1", "0.1", "--t-end", "0.3",
                     *SPRING]) == 0
        printed[path] = [line for line in capsys.readouterr().out.splitlines()
                         if line.strip().startswith(("peak_force_N", "restitution:"))]
    assert printed[si] == printed[mm] and len(printed[si]) == 2


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_predict_refuses_a_conjugated_or_reversed_frf_naming_the_flag(
        two_mode_accelerance, tmp_path, capsys):
    frf = two_mode_accelerance
    for flag, values, problem in (
            ("--conjugate", frf.values.conj(), "its resonances turn counter-clockwise"),
            ("--negate", -frf.values, "the real part of its mobility is negative")):
        path = tmp_path / f"body{flag}.csv"
        write_frf(path, FRFData(frf.freq_hz, values, quantity="accelerance"))
        args = ["predict", "mass:1", str(path), "--v1", "0.1", "--t-end", "0.3", *SPRING]
        assert main(args) == 2
        message = one_line_error(capsys)
        assert message.startswith(f"body 2: {path}: {problem}")
        assert f"read it with {flag}" in message and "read_options" not in message
        assert main(args + [flag]) == 0
        assert "verdict ok" in capsys.readouterr().out
        # the right file read with the flag: leave it out (not "read it with" it again)
        good = tmp_path / "good.csv"
        write_frf(good, FRFData(frf.freq_hz, frf.values, quantity="accelerance"))
        assert main(["predict", "mass:1", str(good), "--v1", "0.1", "--t-end", "0.3",
                     *SPRING, flag]) == 2
        message = one_line_error(capsys)
        assert message.startswith(f"body 2: {good}: read with {flag}, ")
        assert f"read it without {flag}" in message and "read it with " not in message


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_predict_says_how_a_uff_record_was_read(two_mode_accelerance, tmp_path, capsys):
    """A driving point stored as response 1-3 for a force at 1+3 (minus the FRF: write_frf
    stores it so) predicts the same impact as the FRF in a CSV file, and says it was read
    negated."""
    frf = two_mode_accelerance
    write_frf(tmp_path / "a.csv", frf)
    write_frf(tmp_path / "a.uff", frf, binary=True, response=(1, -3), reference=(1, 3))
    figures = {}
    for name in ("a.csv", "a.uff"):
        assert main(["predict", "mass:1", str(tmp_path / name), "--v1", "0.1", "--t-end",
                     "0.3", *SPRING]) == 0
        out = capsys.readouterr().out
        figures[name] = [line for line in out.splitlines()
                         if line.strip().startswith(("peak_force_N", "restitution:"))]
        said = ("  UFF record 0: response 1-3, force 1+3, read negated (its directions "
                "differ in sign)")
        assert (said in out.splitlines()) == (name == "a.uff")
    assert figures["a.csv"] == figures["a.uff"] and len(figures["a.csv"]) == 2


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_predict_reads_bare_complex_lines_and_takes_the_fit_flags(two_mode_accelerance,
                                                                  tmp_path, capsys):
    """A complex-lines file (no frequencies) needs --freq-start/--df, as for modalid fit;
    --fmax and --n-modes reach the identification; without --out nothing is saved."""
    frf = two_mode_accelerance
    path = tmp_path / "lines.txt"
    path.write_text("".join(f"{complex(v)!r}\n" for v in frf.values))
    args = ["predict", "mass:1", str(path), "--v1", "0.1", "--t-end", "0.3", "--contact",
            "spring:stiffness=1e3", "--quantity", "accelerance"]
    assert main(args) == 2
    assert "--freq-start/--df" in one_line_error(capsys)
    df = float(frf.freq_hz[1] - frf.freq_hz[0])
    lines = ["--freq-start", "1", "--df", repr(df)]
    assert main(args + lines) == 0
    out = capsys.readouterr().out
    assert f"body 2: identified from {path} (1-40 Hz," in out
    assert "continuation: body 2: off (auto: 0.03 % of the force's energy above the band)" \
        in out                                     # a soft contact: the force keeps to it
    assert out.splitlines()[-1] == ("nothing saved (--out DIR writes force_motion.csv, "
                                    "summary.csv, energy.csv and impact.png)")
    assert main(args + lines + ["--fmax", "18", "--n-modes", "1", "--fit-method", "vf"]) == 0
    out = capsys.readouterr().out
    assert f"body 2: identified from {path} (1-17.99 Hz," in out   # the last line below 18
    assert ("continuation: body 2: on, above 17.99 Hz (auto: 0.29 % of the force's energy "
            "lay above the band without it)") in out


def _fitted_and_saved(accelerance, tmp_path, capsys):
    """``(FRF file, the fit modalid fit --out saved of it, predict's arguments)``."""
    from modalid.cli import main as modalid_main

    path = tmp_path / "body.csv"
    write_frf(path, accelerance)
    assert modalid_main(["fit", str(path), "--out", str(tmp_path / "fit")]) == 0
    capsys.readouterr()
    args = ["--v1", "0.1", "--t-end", "0.3", "--contact", "spring:stiffness=1e3"]
    return path, tmp_path / "fit" / "body_model.json", args


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_the_model_modalid_fit_saves_predicts_as_its_frf_file(two_mode_accelerance,
                                                               tmp_path, capsys):
    """``modalid fit --out`` then ``impactpred predict`` on its JSON: the fit's band,
    verdict and continuation come with it, and every figure is the FRF file's."""
    path, saved, args = _fitted_and_saved(two_mode_accelerance, tmp_path, capsys)
    printed = {}
    for body in (path, saved):
        assert main(["predict", "mass:1", str(body), *args]) == 0
        printed[body] = capsys.readouterr().out.splitlines()
    assert printed[saved][0] == printed[path][0].replace(f"identified from {path}",
                                                         f"saved fit {saved}")
    assert printed[saved][1:] == printed[path][1:]


@pytest.mark.filterwarnings("ignore::UserWarning")
def test_identification_flags_no_body_uses_are_refused_or_said(two_mode_accelerance,
                                                                 tmp_path, capsys):
    """``--fmax`` and the reading flags apply to FRF files: with none among the bodies they
    are refused (before: a saved fit ignored them silently, ``--fmax 1000`` on a fit of
    4000 Hz printed "above 4000 Hz"); beside a saved fit they are said to reach the FRF
    file only."""
    path, saved, args = _fitted_and_saved(two_mode_accelerance, tmp_path, capsys)
    assert main(["predict", "mass:1", str(saved), *args, "--fmax", "20", "--negate"]) == 2
    assert one_line_error(capsys) == (
        "--fmax 20.0 --negate: these options say how an FRF file is read and identified, and "
        f"neither body is one: body 1 (mass:1) is an exact model; body 2 ({saved}) is a saved "
        "fit or model, identified already: fit its FRF file again with them and save it "
        "(modalid fit FILE --fmax 20.0 --negate --out DIR)")
    assert main(["predict", "mass:1", "mass:2", *args, "--quantity", "mobility"]) == 2
    assert one_line_error(capsys).startswith("--quantity mobility: this option says how")
    assert main(["predict", "mass:1", "mass:2", *args, "--index", "0"]) == 2   # 0 is given
    assert one_line_error(capsys).startswith("--index 0: this option says how")
    free = tmp_path / "free.csv"
    write_frf(free, FRFData(two_mode_accelerance.freq_hz, two_mode_accelerance.values
                            + 1.0, quantity="accelerance"))   # + a 1 kg mass line
    assert main(["predict", str(free), str(saved), *args, "--fmax", "30"]) == 0
    assert (f"warning: --fmax 30.0 applied to body 1 ({free}) only: body 2 ({saved}) is a "
            "saved fit or model, identified with the options it was fitted with"
            in capsys.readouterr().err)


def test_out_naming_a_file_is_refused_before_any_work(tmp_path, monkeypatch, capsys):
    import importlib

    def no_work(*args, **kwargs):
        raise AssertionError("worked before refusing --out")

    monkeypatch.setattr(importlib.import_module("impactpred.predict"), "predict", no_work)
    monkeypatch.setattr(importlib.import_module("impactpred.paper"), "run_paper_cases", no_work)
    out = tmp_path / "taken"
    out.write_text("keep me")
    for args in (["predict", "mass:1", "mass:1", "--t-end", "1"], ["paper"], ["models"],
                 ["benchmark", "--quick"]):
        assert main(args + ["--out", str(out)]) == 2
        assert one_line_error(capsys) == (f"--out {out} is an existing file, not a folder: "
                                          "give a folder (created if missing)")
    assert out.read_text() == "keep me"


@pytest.mark.parametrize("args, message", [
    (["--noise", "nan"], "argument --noise: a noise level in per cent, at least 0 and under "
                         "100, got nan"),
    (["--bands", "-3"], "argument --bands: a band covers at least 1 mode, got -3"),
])
def test_benchmark_flags_out_of_range_are_refused(args, message, capsys):
    """They said "cannot convert float NaN to integer" and "n must be >= 0"."""
    with pytest.raises(SystemExit):
        main(["benchmark", *args])
    assert message in capsys.readouterr().err


@pytest.mark.parametrize("args, message", [
    (["mass:1", "mass:1", "--contact", "spring:stiffness=-1"],
     "--contact spring:stiffness=-1: stiffness must be positive, got -1.0"),
    (["mass:1", "mass:1", "--contact", "hertz:stiffness=1e9,exponent=0"],
     "--contact hertz:stiffness=1e9,exponent=0: exponent must be positive"),
    (["mass:-1", "mass:1"], "body 1: mass spec 'mass:-1': mass must be positive, got -1.0"),
    (["mass:1", "beam:mass=2,time_scale=-0.02"],
     "body 2: beam spec 'beam:mass=2,time_scale=-0.02': time_scale must be positive"),
    (["mass:1", "mass:1", "--v1", "3e8"], "body 1: --v1 must be under the speed of light"),
    # a contact spec's missing fields, its fields refused or its kind unknown: the flag
    # (these said "contact 'hertz-sphere:...' lacks ...")
    (["mass:1", "mass:1", "--contact", "hertz-sphere:radius1=5e-3"],
     "--contact hertz-sphere:radius1=5e-3 lacks youngs_modulus1, poisson1, youngs_modulus2, "
     "poisson2"),
    (["mass:1", "mass:1", "--contact", "rigid:foo=1"],
     "--contact rigid:foo=1: rigid takes no fields"),
    (["mass:1", "mass:1", "--contact", "bogus"],
     "--contact bogus: use rigid, spring:..., hertz:... or hertz-sphere:..."),
])
def test_predict_refusals_of_specs_and_laws_name_the_flag_or_body(args, message, capsys):
    """A spec's or a law's own refusal ("stiffness must be positive") named neither the
    flag nor the body it came from; the speed limit said "velocity", not --v1."""
    assert main(["predict", *args[:2], "--v1", "1", "--t-end", "1", *args[2:]]) == 2
    assert one_line_error(capsys).startswith(message)


@pytest.mark.parametrize("args", [["--bands", "5"], ["--noise", "2"]])
def test_benchmark_quick_with_bands_or_noise_is_refused(args, capsys):
    """--quick ran 10 modes at 1 % whatever --bands and --noise said."""
    assert main(["benchmark", "--quick", *args]) == 2
    assert one_line_error(capsys) == ("--quick runs 10 modes at 1 % noise on two cases: drop "
                                      "--bands and --noise, or drop --quick")


def test_empty_out_and_absurd_mode_counts_are_refused(tmp_path, monkeypatch, capsys):
    """``--out ""`` wrote into the current folder; ``models --n-modes 100000000`` printed
    for minutes."""
    monkeypatch.chdir(tmp_path)
    for args in (["models"], ["paper", "--no-plot"]):
        assert main(args + ["--out", ""]) == 2
        assert one_line_error(capsys) == "--out is empty: give a folder (created if missing)"
    assert main(["models", "--n-modes", "100000000"]) == 2
    assert one_line_error(capsys) == ("--n-modes must lie in [1, 1000] (frequencies printed "
                                      "per model), got 100000000")
    assert not any(tmp_path.iterdir())


def test_models_command_says_nothing_is_saved(capsys):
    assert main(["models"]) == 0
    assert capsys.readouterr().out.splitlines()[-1] == "nothing saved (--out DIR writes the " \
                                                       "FRF plot)"


def test_paper_refuses_a_step_it_cannot_take_giving_the_memory(capsys):
    assert main(["paper", "--dt", "1e-9", "--no-plot"]) == 2
    assert one_line_error(capsys) == (
        "--dt 1e-09 s is too fine for the paper's cases: 8e+09 samples per case (8 s each) "
        "would need about 2.62 TiB of memory; the finest step they take is 2e-06 s "
        "(4,000,000 samples, about 1.34 GiB)")


def test_a_solver_that_cannot_go_on_is_one_line(monkeypatch, capsys):
    """A RuntimeError of the solver (the exact solver's grazing) exits 2 on one line that
    names the flag to use instead."""
    import importlib

    from impactpred.solvers.laplace import _grazing

    def grazing(*args, **kwargs):
        raise _grazing(0.25)

    monkeypatch.setattr(importlib.import_module("impactpred.predict"), "solve_impact", grazing)
    assert main(["predict", "mass:1", "mass:1", "--v1", "1", "--t-end", "1"]) == 2
    assert one_line_error(capsys) == (
        "the solver stopped: contact events repeat without time advancing at t = 0.25 s: the "
        "contact state cannot be decided (grazing); use --method modal")


def test_the_guardrails_names_are_exported():
    import impactpred
    from impactpred.predict import IdentificationWarning
    from impactpred.result import EnergyAudit, EnergyWarning

    assert impactpred.EnergyAudit is EnergyAudit and impactpred.EnergyWarning is EnergyWarning
    assert impactpred.IdentificationWarning is IdentificationWarning
    assert {"EnergyAudit", "EnergyWarning", "IdentificationWarning"} <= set(impactpred.__all__)


def test_two_rigid_masses_stick_and_the_unbounded_force_is_said(capsys):
    """1 kg at 1 m/s onto 2 kg at rest, rigid contact: the impulse passes at once (a Dirac
    of m1 m2 / (m1 + m2) v = 2/3 N s), the masses move on together (restitution 0 to
    round-off, which is no approach: no warning), and the printout says the peak force
    is unbounded where peak_force counts the regular force only (0)."""
    assert main(["predict", "mass:1", "mass:2", "--v1", "1", "--t-end", "0.01"]) == 0
    said = capsys.readouterr()
    assert "still approach" not in said.err and not said.err
    figures = dict(line.strip().split(": ", 1) for line in said.out.splitlines()
                   if ": " in line and line.startswith(" "))
    assert abs(float(figures["restitution"])) < 1e-12
    assert float(figures["impulse_Ns"]) == pytest.approx(2 / 3, rel=1e-12)
    assert float(figures["peak_force_N"]) == 0.0
    assert figures["dirac_impulses"].startswith("0.666667 N s at 0 s (momentum passed at "
                                                "once: neither body gives at the contact")


def test_negative_numbers_in_exponent_form_are_read(capsys):
    """argparse reads ``-1e-1`` as an option ("expected one argument"); the command line
    attaches it to its flag. 1 kg at 1 m/s onto 2 kg at -0.1 m/s: impulse 2/3 * 1.1."""
    assert main(["predict", "mass:1", "mass:2", "--v1", "1", "--v2", "-1e-1",
                 "--t-end", "0.01"]) == 0
    figures = dict(line.strip().split(": ", 1) for line in capsys.readouterr().out.splitlines()
                   if ": " in line and line.startswith(" "))
    assert float(figures["impulse_Ns"]) == pytest.approx(2 / 3 * 1.1, rel=1e-12)
    assert main(["predict", "mass:1", "mass:2", "--v1", "1", "--gap", "-1e-3",
                 "--t-end", "0.01"]) == 2
    assert "--gap must be >= 0" in capsys.readouterr().err


def _two_files(tmp_path):
    """A free rod's accelerance stored conjugated (another sign convention), headerless
    as to its quantity, and a cantilever's mobility in a UFF file, 1 % noise."""
    import numpy as np
    from data_synth import CantileverBeam, Rod, lightly_damped, synthetic_frf
    from modalid import FRFData, write_frf

    f = np.arange(2.0, 1201.0, 2.0)
    rod = synthetic_frf(lightly_damped(Rod(0.5, 5e-3, support="free"), 40, 0.01), f,
                        quantity="accelerance", noise=0.01, seed=1)
    beam = synthetic_frf(lightly_damped(CantileverBeam(2.0, 0.02), 12, 0.01), f,
                         quantity="mobility", noise=0.01, seed=2)
    conj = tmp_path / "rod.csv"
    pd.DataFrame({"freq_hz": f, "real": rod.values.real, "imag": -rod.values.imag}).to_csv(
        conj, index=False)
    write_frf(tmp_path / "beam.uff", beam)
    return conj, tmp_path / "beam.uff", FRFData(f, rod.values, quantity="accelerance")


def test_reading_flags_for_one_body(tmp_path, capsys):
    """Two files from different sources: a flag for both (--conjugate, --quantity) cannot
    read them; the message says so, and --conjugate1 --quantity1 accelerance reads body 1
    alone so: the restitution of the two files read right in Python."""
    from impactpred import predict

    rod, beam, rod_data = _two_files(tmp_path)
    args = ["predict", str(rod), str(beam), "--v1", "1", "--t-end", "0.05"]
    assert main(args + ["--quantity", "accelerance"]) == 2
    err = capsys.readouterr().err
    assert "body 1" in err and "add 1 or 2 for one alone (--conjugate1)" in err
    assert main(args + ["--conjugate1", "--quantity", "accelerance"]) == 2
    err = capsys.readouterr().err
    assert "body 2" in err and "add 1 or 2 for one alone (--quantity2)" in err
    # a flag given for one body is named so (it had said --quantity for --quantity2)
    assert main(args + ["--conjugate1", "--quantity1", "accelerance", "--quantity2",
                        "accelerance"]) == 2
    err = capsys.readouterr().err
    assert "body 2: " in err and "but --quantity2 accelerance was passed: drop the flag" in err
    assert main(args + ["--conjugate1", "--quantity1", "accelerance"]) == 0
    figures = dict(line.strip().split(": ", 1) for line in capsys.readouterr().out.splitlines()
                   if ": " in line and line.startswith(" "))
    expected = predict(rod_data, beam, velocity1=1.0, t_end=0.05).figures["restitution"]
    assert float(figures["restitution"]) == pytest.approx(expected, rel=1e-9)
    assert main(["predict", "mass:1", str(beam), "--v1", "1", "--t-end", "0.05",
                 "--conjugate1"]) == 2
    assert "body 1 (mass:1) is an exact model" in capsys.readouterr().err


def test_a_switch_off_for_one_body_and_errors_in_its_flags(tmp_path, capsys):
    """--conjugate --no-conjugate2 reads body 1 conjugated and body 2 as stored (the same
    restitution as --conjugate1); --driving-point2 yes stands over a common
    --not-driving-point for body 2 (it had raised "contradicts"); an error in a body's own
    flags names them as given and the body (--freq-start2 without --df: it had named
    --freq-start and no body)."""
    rod, beam, _ = _two_files(tmp_path)
    args = ["predict", str(rod), str(beam), "--v1", "1", "--t-end", "0.05",
            "--quantity1", "accelerance"]

    def restitution(extra):
        assert main(args + extra) == 0, capsys.readouterr().err
        out = capsys.readouterr().out
        return next(line.split(": ", 1)[1] for line in out.splitlines()
                    if line.strip().startswith("restitution:"))

    assert restitution(["--conjugate", "--no-conjugate2"]) == restitution(["--conjugate1"])
    assert main(args + ["--conjugate1", "--not-driving-point", "--driving-point2", "yes"]) != 0
    err = capsys.readouterr().err
    assert "contradicts" not in err and "body 1" in err
    assert main(args + ["--conjugate1", "--driving-point", "yes", "--not-driving-point2"]) != 0
    assert "contradicts" not in capsys.readouterr().err
    assert main(args + ["--conjugate1", "--freq-start2", "10"]) == 2
    err = capsys.readouterr().err
    assert "body 2: --df" in err and "--freq-start2" in err and "(--df2)" in err, err
